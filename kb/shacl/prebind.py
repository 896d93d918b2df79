"""Pre-bound variables of SHACL-SPARQL queries (``$this``, ``$shapesGraph``, ``$currentShape``).

The SHACL specification (section 5.3.1 and appendix "Pre-binding of variables") defines
pre-binding as substitution: the query is evaluated as if each occurrence of a pre-bound
variable were replaced by its value, in every FILTER, BIND, UNION branch, inner group and
nested SELECT. It also forbids, in such queries, MINUS, VALUES, SERVICE, ``AS ?var`` for a
pre-bound variable, and nested SELECTs that do not return every pre-bound variable
(``SELECT *`` included). This module holds the three things the engine needs for that:

* :func:`forbidden`: the reason a query breaks those rules (None when it does not);
* :func:`groupable`: whether one evaluation with ``?this`` unbound, its rows grouped by
  ``?this``, gives the rows of pre-binding for every focus node (the fast path; true for the
  usual shape of a query: ``?this`` bound by a triple pattern before any expression uses it);
* :class:`Template`: the query text with the pre-bound variables cut out, filled with a
  focus node's term per evaluation (the path for every other query); a blank focus node,
  which no query text can name, is bound by pyoxigraph's ``substitutions`` instead
  (:func:`for_blank_nodes` mends ``bound($this)``, :func:`hands_on` finds the queries those
  substitutions do not reach).
"""

from __future__ import annotations

import re
import sys
from collections.abc import Collection, Iterable
from typing import Any

from rdflib import Variable
from rdflib.paths import AlternativePath, InvPath, MulPath, NegatedPath, Path, SequencePath

THIS = Variable("this")

#: The variables pre-bound in every sh:sparql constraint (SHACL 5.3.1).
CONSTRAINT_VARIABLES = frozenset({"this", "shapesGraph", "currentShape"})
#: Pre-bound variables a nested SELECT need not return (SHACL: "optional").
OPTIONAL_VARIABLES = frozenset({"shapesGraph", "currentShape"})


# --------------------------------------------------------------------------- forbidden forms


def _is_comp(node: Any) -> bool:
    """Is ``node`` a node of rdflib's SPARQL parse trees and algebra (``CompValue``)? There is
    none before rdflib's SPARQL parser is imported, and this imports nothing (the parser builds
    its grammar on import, 80 ms: a run whose query analyses are cached never needs it)."""
    module = sys.modules.get("rdflib.plugins.sparql.parserutils")
    return module is not None and isinstance(node, module.CompValue)


def _get(node: Any, key: str) -> Any:
    """``node[key]`` or None (rdflib's ``CompValue.get`` returns the key itself when missing)."""
    return dict.get(node, key) if isinstance(node, dict) else None


def forbidden(tree: Any, prebound: Collection[str] = CONSTRAINT_VARIABLES) -> str | None:
    """Why the parsed query ``tree`` (rdflib's ``parseQuery``) breaks SHACL's rules for queries
    with pre-bound variables, or None."""
    query = tree[1] if isinstance(tree, (list, tuple)) or hasattr(tree, "asList") else tree
    if _is_comp(query) and _get(query, "valuesClause") is not None:
        return "uses VALUES"
    return _forbidden_in(query, frozenset(prebound))


def _forbidden_in(node: Any, prebound: frozenset[str]) -> str | None:
    if _is_comp(node):
        name = node.name
        if name == "MinusGraphPattern":
            return "uses MINUS"
        if name in ("InlineData", "ValuesClause"):
            return "uses VALUES"
        if name == "ServiceGraphPattern":
            return "uses SERVICE (a federated query)"
        if name == "Bind" and str(_get(node, "var")) in prebound:
            var = _get(node, "var")
            return f"assigns the pre-bound variable ?{var} (BIND ... AS ?{var})"
        evar = _get(node, "evar")
        if isinstance(evar, Variable) and str(evar) in prebound:
            return f"assigns the pre-bound variable ?{evar} (... AS ?{evar})"
        if name == "SubSelect":
            projection = _get(node, "projection")
            if not projection:
                return "has a nested SELECT * (a nested SELECT must name the pre-bound variables it returns)"
            returned = {str(_get(v, "var")) for v in projection if _is_comp(v) and _get(v, "var") is not None}
            missing = sorted((prebound - OPTIONAL_VARIABLES) - returned)
            if missing:
                return f"has a nested SELECT that does not return the pre-bound variable ?{missing[0]}"
        for key, value in node.items():
            if key == "_vars":
                continue
            found = _forbidden_in(value, prebound)
            if found:
                return found
    elif isinstance(node, dict):
        for value in node.values():
            found = _forbidden_in(value, prebound)
            if found:
                return found
    elif isinstance(node, (list, tuple)) or hasattr(node, "asList"):
        for value in node:
            found = _forbidden_in(value, prebound)
            if found:
                return found
    return None


# --------------------------------------------------------------------------- grouped evaluation


def mentions(node: Any, var: Variable = THIS) -> bool:
    """Does the algebra (or expression) ``node`` use ``var`` anywhere?"""
    if isinstance(node, Variable):
        return node == var
    if _is_comp(node):
        return any(mentions(v, var) for k, v in node.items() if k != "_vars")
    if isinstance(node, dict):
        return any(mentions(v, var) for v in node.values())
    if isinstance(node, (list, tuple, set, frozenset)) or hasattr(node, "asList"):
        return any(mentions(v, var) for v in node)
    return False


def nullable(p: Any) -> bool:
    """Can the property path match zero steps (``p*``, ``p?``)?"""
    if isinstance(p, MulPath):
        return p.mod in ("*", "?")
    if isinstance(p, SequencePath):
        return all(nullable(a) for a in p.args)
    if isinstance(p, AlternativePath):
        return any(nullable(a) for a in p.args)
    if isinstance(p, InvPath):
        return nullable(p.arg)
    if isinstance(p, NegatedPath):
        return False
    return False


def groupable(algebra: Any) -> bool:
    """True when evaluating the SELECT query once with ``?this`` unbound and taking, for a
    focus node f, the rows with ``?this = f`` plus the rows without ``?this`` gives exactly
    the rows of the query with ``$this`` pre-bound to f.

    Holds when ``?this`` is projected and every part of the query that mentions ``?this``
    either binds it itself (a triple pattern) or only uses it where an enclosing join has
    bound it in every row (FILTER, BIND, OPTIONAL over it). Sub-queries, aggregates, LIMIT,
    GRAPH and anything unknown count as not groupable (they are evaluated per focus node).
    """
    query = _get(algebra, "p") if _is_comp(algebra) and algebra.name == "SelectQuery" else None
    if not _is_comp(query) or query.name != "Project":
        return False
    if THIS not in (_get(query, "PV") or []):
        return False
    ok, _ = _safe(query["p"])
    return ok


def _safe(p: Any) -> tuple[bool, bool]:
    """(safe, certain): ``p`` evaluated grouped equals ``p`` pre-bound (see :func:`groupable`);
    every row of ``p`` binds ``?this``."""
    if not _is_comp(p):
        return False, False
    name = p.name
    if name == "BGP":
        plain = zero = False
        for s, pred, o in _get(p, "triples") or ():
            if THIS in (s, pred, o):
                if isinstance(pred, Path) and nullable(pred):
                    zero = True
                else:
                    plain = True
        # a zero-length path binds ?this to any node of the graph but, pre-bound, also to a
        # focus node that is not in the graph: the same only where a plain triple binds it too
        return (plain or not zero), plain
    if name in ("Join", "Union"):
        ok1, c1 = _safe(p["p1"])
        ok2, c2 = _safe(p["p2"])
        return ok1 and ok2, (c1 or c2) if name == "Join" else (c1 and c2)
    if name == "LeftJoin":
        ok1, c1 = _safe(p["p1"])
        ok2, _ = _safe(p["p2"])
        if mentions(p["p2"]) or mentions(_get(p, "expr")):
            return ok1 and ok2 and c1, c1
        return ok1 and ok2, c1
    if name == "Filter":
        ok, certain = _safe(p["p"])
        return ok and (certain or not mentions(p["expr"])), certain
    if name == "Extend":
        ok, certain = _safe(p["p"])
        if _get(p, "var") == THIS:
            return False, certain
        return ok and (certain or not mentions(p["expr"])), certain
    if name in ("Distinct", "Reduced"):
        return _safe(p["p"])
    if name == "OrderBy":
        ok, certain = _safe(p["p"])
        return ok and (certain or not mentions(_get(p, "expr"))), certain
    # sub-queries (ToMultiSet), Group/AggregateJoin, Slice, Graph, Minus, values, SERVICE:
    # safe only when they do not touch ?this at all
    return (not mentions(p)), False


# --------------------------------------------------------------------------- substitution

_TOKEN = re.compile(
    r'''(?P<str>"""(?:[^"\\]|\\.|"(?!""))*"""|\'\'\'(?:[^'\\]|\\.|'(?!''))*\'\'\''''
    r'''|"(?:[^"\\\n]|\\.)*"|'(?:[^'\\\n]|\\.)*')'''
    r'''|(?P<iri><[^<>"{}|^`\\\x00-\x20]*>)'''
    r'''|(?P<comment>\#[^\n]*)'''
    r'''|(?P<var>[?$][A-Za-z0-9_\u00B7\u00C0-\uFFFF]+)'''
    r'''|(?P<word>[A-Za-z_][A-Za-z0-9_\-]*(?::[A-Za-z0-9_\-.%]*)?)'''
    r'''|(?P<space>\s+)'''
    r'''|(?P<other>.)''',
    re.S,
)
_ENDS_PROJECTION = {"WHERE", "FROM"}
_ENDS_MODIFIER = {"HAVING", "LIMIT", "OFFSET", "VALUES", "ORDER", "GROUP"}


class Template:
    """A query's text with its pre-bound variables cut out, filled per evaluation.

    Each occurrence becomes the variable's term (``<iri>``, a literal) except: in the
    projection of the outer SELECT it becomes ``(TERM AS ?var)`` (the row still names it), in
    a nested SELECT's projection ``(TERM AS ?fresh)``, after GROUP BY / ORDER BY ``(TERM)``,
    and ``bound(?var)`` becomes ``(true)``. Blank nodes cannot be written into a query: callers
    fill only IRIs and literals.
    """

    def __init__(self, text: str, variables: Iterable[str]) -> None:
        self.variables = frozenset(variables)
        self.parts: list[str | tuple[str, str, int]] = []
        self._cut(text)

    def _cut(self, text: str) -> None:
        tokens = [(m.lastgroup or "other", m.group()) for m in _TOKEN.finditer(text)]
        parts = self.parts
        braces = parens = 0
        mode: str | None = None  # "project" (top or nested) or "modifier"
        mode_parens = 0
        nested = False
        fresh = 0
        i = 0
        while i < len(tokens):
            kind, tok = tokens[i]
            upper = tok.upper() if kind == "word" else ""
            if kind == "word":
                if upper == "SELECT":
                    mode, mode_parens, nested = "project", parens, braces > 0
                elif mode == "project" and upper in _ENDS_PROJECTION:
                    mode = None
                elif upper == "BY" and _previous_word(tokens, i) in ("GROUP", "ORDER"):
                    mode, mode_parens = "modifier", parens
                elif mode == "modifier" and upper in _ENDS_MODIFIER:
                    mode = None
                elif upper == "BOUND":
                    end = _bound_call(tokens, i, self.variables)
                    if end is not None:
                        parts.append("(true)")
                        i = end + 1
                        continue
            elif tok == "{":
                braces += 1
                mode = None if mode == "project" else mode
            elif tok == "}":
                braces -= 1
                mode = None
            elif tok == "(":
                parens += 1
            elif tok == ")":
                parens -= 1
            elif kind == "var" and tok[1:] in self.variables:
                var = tok[1:]
                if mode == "project" and parens == mode_parens:
                    fresh += nested
                    parts.append(("project-nested", var, fresh) if nested else ("project", var, 0))
                elif mode == "modifier" and parens == mode_parens:
                    parts.append(("group", var, 0))
                else:
                    parts.append(("term", var, 0))
                i += 1
                continue
            parts.append(tok)
            i += 1

    @property
    def used(self) -> set[str]:
        """The pre-bound variables the query uses."""
        return {p[1] for p in self.parts if isinstance(p, tuple)}

    def fill(self, terms: dict[str, str]) -> str:
        """The query with each pre-bound variable replaced by ``terms[var]`` (SPARQL terms)."""
        out = []
        for p in self.parts:
            if isinstance(p, str):
                out.append(p)
                continue
            kind, var, n = p
            term = terms[var]
            if kind == "term":
                out.append(term)
            elif kind == "project":
                out.append(f"({term} AS ?{var})")
            elif kind == "project-nested":
                out.append(f"({term} AS ?kitkb_prebound_{var}_{n})")
            else:
                out.append(f"({term})")
        return "".join(out)


def for_blank_nodes(text: str, variables: Iterable[str] = ("this",)) -> str:
    """The query to run with pyoxigraph's ``substitutions`` binding a blank focus node (which
    cannot be written into the text): ``bound(?this)`` made ``(true)``, where pyoxigraph's
    substitution leaves the variable unbound. pyoxigraph substitutes the rest, in patterns,
    FILTERs, EXISTS and nested SELECTs, but not where an expression hands the value on
    (``BIND ($this AS ?x)``): :func:`hands_on` tells those queries apart."""
    names = frozenset(variables)
    tokens = [(m.lastgroup or "other", m.group()) for m in _TOKEN.finditer(text)]
    out: list[str] = []
    i = 0
    while i < len(tokens):
        kind, tok = tokens[i]
        if kind == "word" and tok.upper() == "BOUND":
            end = _bound_call(tokens, i, names)
            if end is not None:
                out.append("(true)")
                i = end + 1
                continue
        out.append(tok)
        i += 1
    return "".join(out)


def hands_on(algebra: Any, var: Variable = THIS) -> bool:
    """Does an expression of the query bind a new variable from ``var`` (BIND, a projected
    expression, an aggregate)? pyoxigraph's ``substitutions`` do not reach there."""
    if _is_comp(algebra):
        if algebra.name == "Extend" and mentions(_get(algebra, "expr"), var):
            return True
        if algebra.name.startswith("Aggregate") and mentions(algebra, var):
            return True
        return any(hands_on(v, var) for k, v in algebra.items() if k != "_vars")
    if isinstance(algebra, dict):
        return any(hands_on(v, var) for v in algebra.values())
    if isinstance(algebra, (list, tuple)):
        return any(hands_on(v, var) for v in algebra)
    return False


def _previous(tokens: list[tuple[str, str]], i: int) -> int:
    """Index of the token before ``i`` that is not white space or a comment (-1: none)."""
    j = i - 1
    while j >= 0 and tokens[j][0] in ("space", "comment"):
        j -= 1
    return j


def _previous_word(tokens: list[tuple[str, str]], i: int) -> str:
    j = _previous(tokens, i) if i >= 0 else -1
    return tokens[j][1].upper() if j >= 0 and tokens[j][0] == "word" else ""


def _bound_call(tokens: list[tuple[str, str]], i: int, variables: frozenset[str]) -> int | None:
    """Index of the ``)`` closing ``bound(?var)`` at ``tokens[i]`` for a pre-bound ``var``."""
    seq = [j for j in range(i + 1, min(len(tokens), i + 8)) if tokens[j][0] not in ("space", "comment")][:3]
    if len(seq) == 3 and tokens[seq[0]][1] == "(" and tokens[seq[1]][0] == "var" \
            and tokens[seq[1]][1][1:] in variables and tokens[seq[2]][1] == ")":
        return seq[2]
    return None
