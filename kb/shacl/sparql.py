"""SHACL-SPARQL constraints, evaluated once over the whole graph with pyoxigraph.

pySHACL runs a constraint's SELECT once per focus node with ``$this`` pre-bound (and parses
the query text each time). Here the query runs once with ``$this`` unbound and the rows are
grouped by ``?this``, for the query forms where that gives the same rows (basic graph
patterns, FILTER, BIND, UNION, DISTINCT; ``?this`` projected). Other forms (sub-SELECT,
aggregates, OPTIONAL, MINUS, EXISTS, VALUES, LIMIT) run once per focus node with ``?this``
bound by a VALUES block. Simple groups get a cheap join order first (:mod:`kb.shacl.reorder`).
The pyoxigraph store holds only the triples whose predicates the queries mention (all
triples when one uses a variable predicate, a negated path, or a ``*``/``?`` path between
two variables).

Difference from pySHACL (rdflib's evaluator): the SPARQL semantics are Oxigraph's. They agree
on the arithmetic, comparisons and errors the generated shapes use, including xsd:decimal zeros
(the equivalence tests check that). pyoxigraph stores typed literals in canonical form, so a
literal bound to ``?value`` is reported in canonical spelling (``"1"^^xsd:decimal`` for
``"1.0"``).
"""

from __future__ import annotations

import re
import threading
from collections.abc import Iterator
from typing import Any

import pyoxigraph as ox
from rdflib import Graph, Literal, URIRef, Variable
from rdflib.paths import AlternativePath, InvPath, MulPath, SequencePath
from rdflib.plugins.sparql import prepareQuery
from rdflib.plugins.sparql.parserutils import CompValue
from rdflib.term import Node

from kb.core.namespaces import SH
from kb.shacl.reorder import predicates_in, reorder
from kb.shacl.shape import Constraint, Context, Hit, Pairs, Shape
from kb.shacl.terms import key_of, to_node

_PATH_VAR = re.compile(r"([\s{}()])[$?]PATH")
_UNSAFE = {
    "Minus", "LeftJoin", "Group", "AggregateJoin", "Builtin_EXISTS", "Builtin_NOTEXISTS",
    "ToMultiSet", "values", "Slice", "ServiceGraphPattern", "Graph",
}


class SparqlC(Constraint):
    """One sh:sparql constraint (sh:select) of a shape."""

    component = SH.SPARQLConstraintComponent

    def __init__(self, shape: Shape, node: Node, text: str, messages: list[str]) -> None:
        super().__init__(shape)
        self.node = node
        self.text = text
        self.messages = messages
        self.predicates: set[str] | None = set()
        self.projected: set[str] = set()
        self.once = True

    def check(self, ctx: Context, pairs: Pairs, out: list[Hit]) -> None:
        for focus, _ in pairs:
            rows = ctx.sparql.rows(self, focus)
            if rows:
                out.extend(self._hits(focus, rows))

    def _hits(self, focus: str, rows: list[dict[str, str]]) -> Iterator[Hit]:
        node_shape = self.shape.path is None
        default_value = focus if node_shape else None
        seen: list[tuple[Any, ...]] = []
        failed = False
        for row in rows:
            if "failure" in row:
                if failed:
                    continue
                failed = True
                yield self.hit(focus, default_value, message=self._message(row))
                continue
            path, value, this = row.get("path"), row.get("value"), row.get("this")
            if path is None and value is None and this is None:
                continue
            rest = {k: v for k, v in row.items() if k not in ("path", "value", "this")}
            sig = (this, path, value, sorted(rest.items()))
            if sig in seen:
                continue
            seen.append(sig)
            yield self.hit(
                this or focus,
                value if value is not None else default_value,
                path=to_node(path) if path is not None else None,
                message=self._message(row),
            )

    def _message(self, row: dict[str, str]) -> str | None:
        if not self.messages:
            return None
        text = self.messages[0]
        for var, key in row.items():
            text = re.sub(r"\{[$?]" + re.escape(var) + r"\}", str(to_node(key)), text)
        return text

    def generic(self, value: str | None) -> str:
        return f"SPARQL constraint {self.node} reported a violation"


def _walk(node: Any, names: list[str], triples: list[tuple[Any, Any, Any]], extends: list[Any]) -> None:
    if isinstance(node, CompValue):
        names.append(node.name)
        if node.name == "Extend":
            extends.append(node.get("var"))
        for key, value in node.items():
            if key == "triples" and isinstance(value, list):
                triples.extend(tuple(t) for t in value if isinstance(t, (tuple, list)) and len(t) == 3)
            _walk(value, names, triples, extends)
    elif isinstance(node, dict):
        for value in node.values():
            _walk(value, names, triples, extends)
    elif isinstance(node, (list, tuple)):
        for value in node:
            _walk(value, names, triples, extends)


def _path_predicates(p: Any, out: set[str]) -> bool:
    """Collect the IRIs of a predicate or path; False when it can match any predicate."""
    if isinstance(p, URIRef):
        out.add(key_of(p))
        return True
    if isinstance(p, InvPath):
        return _path_predicates(p.arg, out)
    if isinstance(p, (SequencePath, AlternativePath)):
        return all(_path_predicates(a, out) for a in p.args)
    if isinstance(p, MulPath):
        return _path_predicates(p.path, out)
    return False


def _nullable(p: Any) -> bool:
    """Can the path match zero steps (``p*``, ``p?``)?"""
    if isinstance(p, MulPath):
        return p.mod in ("*", "?")
    if isinstance(p, SequencePath):
        return all(_nullable(a) for a in p.args)
    if isinstance(p, AlternativePath):
        return any(_nullable(a) for a in p.args)
    if isinstance(p, InvPath):
        return _nullable(p.arg)
    return False


def _analyse(c: SparqlC) -> None:
    query = prepareQuery(c.text)
    names: list[str] = []
    triples: list[tuple[Any, Any, Any]] = []
    extends: list[Any] = []
    _walk(query.algebra, names, triples, extends)
    preds: set[str] = set()
    every = False
    for subj, p, obj in triples:
        if not _path_predicates(p, preds):
            every = True
        elif _nullable(p) and isinstance(subj, Variable) and isinstance(obj, Variable):
            every = True  # a zero-length match binds every node of the graph
    c.predicates = None if every else preds
    pv = query.algebra.get("PV") or []
    c.projected = {str(v) for v in pv}
    c.once = (
        "this" in c.projected
        and names.count("Project") == 1
        and not any(n in _UNSAFE or n.startswith("Aggregate") for n in names)
        and Variable("this") not in extends
    )


def _prefix_block(g: Graph, prefixes: dict[str, str], cnode: Node, body: str) -> str:
    """PREFIX declarations for ``body``: the shapes graph's prefixes and the constraint's
    sh:prefixes, those ``body`` can use (``name:`` occurs in it; an unused declaration
    means nothing, and parsing dozens of them was most of the time of compiling a query)."""
    found = dict(prefixes)
    for pnode in g.objects(cnode, SH.prefixes):
        for decl in g.objects(pnode, SH.declare):
            pre = next(iter(g.objects(decl, SH.prefix)), None)
            ns = next(iter(g.objects(decl, SH.namespace)), None)
            if pre is not None and ns is not None:
                found[str(pre)] = str(ns)
    return "".join(f"PREFIX {p}: <{ns}>\n" for p, ns in found.items() if f"{p}:" in body)


def _path_text(path: Node | None) -> str | None:
    if isinstance(path, URIRef):
        return f"<{path}>"
    return None


def compile_sparql(g: Graph, prefixes: dict[str, str], s: Shape, cnode: Node) -> tuple[SparqlC | None, str | None]:
    """Compile one sh:sparql node of shapes graph ``g`` (``prefixes``: those of the shapes
    graph); returns (constraint, problem); deactivated -> (None, None)."""
    deact = next(iter(g.objects(cnode, SH.deactivated)), None)
    if isinstance(deact, Literal) and deact.value is True:
        return None, None
    selects = list(g.objects(cnode, SH.select))
    if len(selects) != 1:
        return None, f"SPARQL constraint {cnode} needs exactly one sh:select (sh:ask is not supported)"
    body = str(selects[0])
    if re.search(r"[$?](shapesGraph|currentShape)\b", body):
        return None, f"SPARQL constraint {cnode} uses $shapesGraph or $currentShape"
    if _PATH_VAR.search(body):
        if s.path is None or s.path[0] != "pred" or s.path_node is None:
            return None, f"SPARQL constraint {cnode} uses $PATH without a predicate path"
        body = _PATH_VAR.sub(r"\g<1>" + str(_path_text(s.path_node)), body)
    messages = sorted(str(m) for m in g.objects(cnode, SH.message))
    c = SparqlC(s, cnode, _prefix_block(g, prefixes, cnode, body) + body, messages)
    try:
        _analyse(c)
    except Exception as exc:  # a query rdflib cannot parse: let pySHACL report on it
        return None, f"SPARQL constraint {cnode} does not parse: {exc}"
    return c, None


def ox_key(term: Any) -> str:
    """Key of a pyoxigraph term (its N-Triples spelling)."""
    return str(term)


def _inject_values(text: str, focus: str) -> str:
    """Bind ``?this`` by a VALUES block at the start of the WHERE group (pre-binding, also
    inside FILTER NOT EXISTS, which pyoxigraph's ``substitutions`` do not reach)."""
    brace = text.index("{")  # the PREFIX block before it has no braces
    return f"{text[: brace + 1]} VALUES ?this {{ {focus} }} {text[brace + 1 :]}"


class SparqlRunner:
    """Evaluates SPARQL constraints; keeps each constraint's rows grouped by ``?this``.

    ``engine`` is ``"oxigraph"`` (default, fast) or ``"rdflib"`` (rdflib's evaluator, the one
    pySHACL uses, still run once over the graph; slow on large graphs).
    """

    def __init__(self, ctx: Context, constraints: list[SparqlC], engine: str = "oxigraph") -> None:
        if engine not in ("oxigraph", "rdflib"):
            raise ValueError(f"unknown SPARQL engine {engine!r}")
        self.engine = engine
        self.ctx = ctx
        self.constraints = constraints
        self._graph: Any = None
        self._prepared: dict[int, Any] = {}
        self._store: ox.Store | None = None
        self._stats: dict[str, tuple[int, int, int]] | None = None
        self._texts: dict[tuple[int, frozenset[str]], str] = {}
        self._grouped: dict[int, tuple[dict[str, list[dict[str, str]]], list[dict[str, str]]]] = {}
        self._bnodes: dict[str, ox.BlankNode] = {}
        self._pending: Any = None  # the background thread of prefetch(), until joined

    def prefetch(self) -> None:
        """Load the pyoxigraph store in a background thread (the queries run later, here).

        pyoxigraph releases the GIL while it loads, so this overlaps with the Python
        constraints. :meth:`rows` joins the thread before using the store; results are the
        same as without prefetching (a failed load is done again, and raises, on first use).
        Running the queries in the thread too was slower: turning their rows into Python
        objects takes turns with the caller for the GIL.
        """
        if self.engine != "oxigraph" or self._pending is not None or not self.constraints:
            return
        # the Python part (spelling the triples) runs here: in the thread it would only
        # take turns with the caller for the GIL
        try:
            store, plain, quads = ox.Store(), *self._triples(self._predicates())
        except Exception:  # raised again, in the caller's thread, by the first use
            return

        def load() -> None:
            try:
                self._fill(store, plain, quads)
                self._store = store
            except Exception:  # idem: store() loads again, and raises
                pass

        self._pending = threading.Thread(target=load, name="kitkb-sparql", daemon=True)
        self._pending.start()

    def join(self) -> None:
        """Wait for :meth:`prefetch` to finish (no-op when none is running)."""
        pending = self._pending
        if pending is not None:
            pending.join()
            self._pending = None

    def store(self) -> ox.Store:
        if self._store is None:
            store = ox.Store()
            self._load(store, self._predicates())
            self._store = store  # only once complete (a failed load is retried, and raises)
        return self._store

    def _load(self, store: ox.Store, preds: set[str] | None) -> None:
        self._fill(store, *self._triples(preds))

    def _triples(self, preds: set[str] | None) -> tuple[bytes, list[ox.Quad]]:
        """N-Triples of the triples without blank nodes, and quads of those with them."""
        plain, with_bnodes = self.ctx.index.ntriples_split(preds)
        # the N-Triples parser renames blank nodes: build those quads ourselves to keep labels
        quads = [ox.Quad(self.ox_term(s), self.ox_term(p), self.ox_term(o)) for s, p, o in with_bnodes]
        return plain.encode(), quads

    @staticmethod
    def _fill(store: ox.Store, plain: bytes, quads: list[ox.Quad]) -> None:
        store.load(input=plain, format=ox.RdfFormat.N_TRIPLES)
        if quads:
            store.extend(quads)

    def ox_term(self, key: str) -> Any:
        if key[0] == "<":
            return ox.NamedNode(key[1:-1])
        if key[0] == "_":
            b = self._bnodes.get(key)
            if b is None:
                b = self._bnodes[key] = ox.BlankNode(key[2:])
            return b
        lit = to_node(key)
        assert isinstance(lit, Literal)
        if lit.language:
            return ox.Literal(str(lit), language=lit.language)
        if lit.datatype is not None:
            return ox.Literal(str(lit), datatype=ox.NamedNode(str(lit.datatype)))
        return ox.Literal(str(lit))

    def _predicates(self) -> set[str] | None:
        preds: set[str] | None = set()
        for c in self.constraints:
            if c.predicates is None or preds is None:
                preds = None
            else:
                preds |= c.predicates
        return preds

    def graph(self) -> Any:
        """rdflib graph of the triples the SPARQL constraints can match (rdflib engine)."""
        if self._graph is None:
            from rdflib import Graph

            g = Graph()
            wanted = self._predicates()
            for subj, preds in self.ctx.index.spo.items():
                s_node = to_node(subj)
                for p, objs in preds.items():
                    if wanted is None or p in wanted:
                        p_node = to_node(p)
                        for o in objs:
                            g.add((s_node, p_node, to_node(o)))
            self._graph = g
        return self._graph

    def _rdflib_solutions(self, c: SparqlC, focus: str | None) -> list[dict[str, str]]:
        q = self._prepared.get(id(c))
        if q is None:
            q = self._prepared[id(c)] = prepareQuery(c.text)
        binds = {"this": to_node(focus)} if focus is not None else None
        rows = []
        for r in self.graph().query(q, initBindings=binds):
            row = {str(k): key_of(v, rdf11_strings=self.ctx.rdf11_strings) for k, v in r.asdict().items()}
            if focus is not None and "this" in row:
                row["this"] = focus
            rows.append(row)
        return rows

    def _solutions(self, c: SparqlC, focus: str | None = None) -> list[dict[str, str]]:
        if self.engine == "rdflib":
            return self._rdflib_solutions(c, focus)
        if focus is None:
            res = self.store().query(self._query_text(c, frozenset()))
        elif focus[0] == "_":
            res = self.store().query(c.text, substitutions={ox.Variable("this"): self.ox_term(focus)})
        else:
            res = self.store().query(_inject_values(self._query_text(c, frozenset({"this"})), focus))
        names = [v.value for v in res.variables]
        rows = []
        for sol in res:
            row = {}
            for name in names:
                t = sol[name]
                if t is not None:
                    row[name] = ox_key(t)
            rows.append(row)
        return rows

    def _query_text(self, c: SparqlC, bound: frozenset[str]) -> str:
        """The query as pyoxigraph runs it: triple patterns in a cheap join order."""
        key = (id(c), bound)
        text = self._texts.get(key)
        if text is None:
            if self._stats is None:
                preds: set[str] = set()
                for other in self.constraints:
                    preds |= predicates_in(other.text)
                self._stats = self.ctx.index.predicate_stats(preds)
            text = self._texts[key] = reorder(c.text, self._stats.get, bound)
        return text

    def _group(self, c: SparqlC) -> tuple[dict[str, list[dict[str, str]]], list[dict[str, str]]]:
        by_this: dict[str, list[dict[str, str]]] = {}
        anywhere: list[dict[str, str]] = []
        for row in self._solutions(c):
            this = row.get("this")
            if this is None:
                anywhere.append(row)
            else:
                by_this.setdefault(this, []).append(row)
        grouped = self._grouped[id(c)] = (by_this, anywhere)
        return grouped

    def rows(self, c: SparqlC, focus: str) -> list[dict[str, str]]:
        if self._pending is not None:
            self.join()
        if not c.once:
            return self._solutions(c, focus)
        grouped = self._grouped.get(id(c))
        if grouped is None:
            grouped = self._group(c)
        by_this, anywhere = grouped
        mine = by_this.get(focus)
        if not anywhere:
            return mine or []
        return (mine or []) + [dict(r, this=focus) for r in anywhere]
