"""SHACL-SPARQL constraints, evaluated with pyoxigraph: once over the whole graph where that
gives the rows of pre-binding, else once per focus node with ``$this`` substituted.

pySHACL runs a constraint's SELECT once per focus node with ``$this`` pre-bound (and parses
the query text each time). Here a query whose ``?this`` is bound by a triple pattern before
anything else uses it runs once with ``$this`` unbound and its rows are grouped by ``?this``
(:func:`kb.shacl.prebind.groupable` says when that is exact). Every other query runs once
per focus node with the focus node's term written in place of ``$this`` (pre-binding as the
specification defines it: substitution into the whole query, :class:`kb.shacl.prebind.Template`);
a blank focus node, which cannot be written into a query, is bound by pyoxigraph's
``substitutions`` (:func:`kb.shacl.prebind.for_blank_nodes`), or where the query does not
project ``$this`` or hands it on in an expression, by rdflib's evaluator (``initBindings``,
as pySHACL does, with its departures: see tests/test_shacl_prebind.py). Queries the
specification forbids (MINUS, VALUES, SERVICE, ``AS $this``, nested SELECTs not returning
``$this``) and queries that do not parse are refused with a :class:`kb.shacl.shape.ShapeError`.
Simple groups get a cheap join order first (:mod:`kb.shacl.reorder`). The pyoxigraph store holds only the triples whose
predicates the queries mention (all triples when one uses a variable predicate, a negated
path, or a ``*``/``?`` path between two variables).

Difference from pySHACL (rdflib's evaluator): the SPARQL semantics are Oxigraph's. They agree
on the arithmetic, comparisons and errors the generated shapes use, including xsd:decimal zeros
(the equivalence tests check that). pyoxigraph stores typed literals in canonical form, so a
literal bound to ``?value`` is reported in canonical spelling (``"1"^^xsd:decimal`` for
``"1.0"``).
"""

from __future__ import annotations

import re
import threading
from collections.abc import Collection, Iterator
from importlib.metadata import version
from pathlib import Path
from typing import Any

import pyoxigraph as ox
import rdflib
from rdflib import Graph, Literal, URIRef, Variable
from rdflib.paths import AlternativePath, InvPath, MulPath, SequencePath
from rdflib.term import Node

from kb.core.cache import JsonCache, digest
from kb.core.namespaces import SH
from kb.shacl import paths, prebind
from kb.shacl.prebind import (CONSTRAINT_VARIABLES, Template, _is_comp, for_blank_nodes, forbidden, groupable,
                               hands_on, mentions, nullable)
from kb.shacl.reorder import predicates_in, reorder
from kb.shacl.shape import Constraint, Context, Hit, Pairs, Shape, ShapeError
from kb.shacl.terms import key_of, to_node

_PATH_VAR = re.compile(r"([\s{}()])[$?]PATH")
_SHAPES_VARS = re.compile(r"[$?](shapesGraph|currentShape)\b")
#: The name of the shapes graph in the SPARQL store (what ``$shapesGraph`` is bound to).
SHAPES_GRAPH = "<urn:kitkb:shapes-graph>"
_CHECK_TERM = "<urn:kitkb:prebound>"


class SparqlC(Constraint):
    """One sh:sparql constraint (sh:select) of a shape, or the SELECT validator of a
    constraint component with its parameters written in (``component`` is then the
    component's IRI)."""

    component = SH.SPARQLConstraintComponent
    #: The variables pre-bound per evaluation (written into the query text where they can be).
    VARIABLES: tuple[str, ...] = ("this",)

    def __init__(self, shape: Shape, node: Node, text: str, messages: list[str]) -> None:
        super().__init__(shape)
        self.node = node
        self.text = text
        self.messages = messages
        self.predicates: set[str] | None = set()
        self.projected: set[str] = set()
        self.once = True
        #: Can ``$this`` be written into the query text (:class:`kb.shacl.prebind.Template`)?
        self.substitutable = True
        #: Can pyoxigraph's ``substitutions`` pre-bind a blank focus node (``$this`` projected,
        #: not handed on by an expression; :func:`kb.shacl.prebind.hands_on`)?
        self.blank_bindable = True
        #: ``$shapesGraph`` and ``$currentShape``, where the query uses them: their terms.
        self.fixed: dict[str, str] = {}
        #: The shapes graph, loaded into the store as :data:`SHAPES_GRAPH` when used.
        self.shapes_graph: Graph | None = None

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


class AskC(SparqlC):
    """The ASK validator of a constraint component (SHACL 6.3.2.2): one ASK per value node,
    with ``$this`` and ``$value`` pre-bound (and the parameters written in); a value node for
    which it is false is a result."""

    VARIABLES = ("this", "value")

    def check(self, ctx: Context, pairs: Pairs, out: list[Hit]) -> None:
        for focus, values in pairs:
            for v in values:
                if not ctx.sparql.ask(self, focus, v):  # type: ignore[attr-defined]
                    out.append(self.hit(focus, v, message=self._message({"this": focus, "value": v})))

    def generic(self, value: str | None) -> str:
        return f"Value does not conform to the ASK validator {self.node} of {self.component}"


def _walk(node: Any, triples: list[tuple[Any, Any, Any]]) -> None:
    if _is_comp(node):
        for key, value in node.items():
            if key == "triples" and isinstance(value, list):
                triples.extend(tuple(t) for t in value if isinstance(t, (tuple, list)) and len(t) == 3)
            _walk(value, triples)
    elif isinstance(node, dict):
        for value in node.values():
            _walk(value, triples)
    elif isinstance(node, (list, tuple)):
        for value in node:
            _walk(value, triples)


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


#: what an analysis found, kept between runs (:mod:`kb.core.cache`), keyed by the source of the
#: code that decides it and the parser's versions: rdflib's SPARQL grammar (pyparsing) takes
#: about 25 ms per query, most of compiling the shipped shapes, and 80 ms to import (so it is
#: imported only to parse a query, or to run one on rdflib's engine)
_ANALYSES = JsonCache("sparql-analysis", [Path(__file__).read_bytes(), Path(prebind.__file__).read_bytes(),
                                          rdflib.__version__, version("pyparsing")])


def _analyse(c: SparqlC) -> None:
    """Check the query (it parses, the specification allows it) and decide how it runs; the
    decisions are kept for the same query with the same pre-bound variables (a query that does
    not pass is not kept: it is checked again, and refused again, every time).

    Raises :class:`ShapeError` for a query that does not parse or that SHACL forbids."""
    key = digest([c.text, *c.VARIABLES, "\1", *c.fixed, "\1", *sorted(CONSTRAINT_VARIABLES)])
    found = _ANALYSES.get(key)
    if not (isinstance(found, list) and len(found) == 5):
        found = _analysis(c)
        _ANALYSES.put(key, found)
    predicates, projected, c.once, c.substitutable, c.blank_bindable = found
    c.predicates = None if predicates is None else set(predicates)
    c.projected = set(projected)


def _analysis(c: SparqlC) -> list:
    """:func:`_analyse`'s decisions, as JSON: [predicates or None, projected, once, substitutable,
    blank_bindable]."""
    query = checked_query(c.text, c.shape.node, c.node, CONSTRAINT_VARIABLES | set(c.VARIABLES))
    triples: list[tuple[Any, Any, Any]] = []
    _walk(query.algebra, triples)
    preds: set[str] = set()
    every = False
    for subj, p, obj in triples:
        if not _path_predicates(p, preds):
            every = True
        elif nullable(p) and isinstance(subj, Variable) and isinstance(obj, Variable):
            every = True  # a zero-length match binds every node of the graph
    pv = dict.get(query.algebra, "PV") or []
    projected = sorted({str(v) for v in pv})
    once = bool(c.VARIABLES == ("this",) and groupable(query.algebra) and not c.fixed)
    substitutable = bool(once or _substitutes(c.text, (*c.VARIABLES, *c.fixed)))
    blank_bindable = bool("this" in projected and not c.fixed and not hands_on(query.algebra))
    return [None if every else sorted(preds), projected, once, substitutable, blank_bindable]


def checked_query(text: str, shape: Node, node: Node, prebound: Collection[str] = CONSTRAINT_VARIABLES,
                  what: str = "SPARQL query") -> Any:
    """The query ``text`` of constraint (or validator) ``node`` of ``shape``, parsed and
    translated to rdflib's algebra; :class:`ShapeError` when it does not parse or breaks
    SHACL's rules for the pre-bound variables ``prebound``."""
    from rdflib.plugins.sparql.algebra import translateQuery
    from rdflib.plugins.sparql.parser import parseQuery

    where = f"the {what} of {node.n3()}" if isinstance(node, URIRef) else f"its {what}"
    try:
        tree = parseQuery(text)
    except Exception as exc:  # pyparsing's ParseException, with the position in the text
        raise ShapeError(shape, f"{where} does not parse: {exc}", node) from None
    reason = forbidden(tree, prebound)
    if reason:
        raise ShapeError(shape, f"{where} {reason}, which SHACL forbids where variables are pre-bound "
                                "(SHACL 5.3.1)", node)
    try:
        return translateQuery(tree)
    except Exception as exc:
        raise ShapeError(shape, f"{where} is not valid SPARQL: {exc}", node) from None


def _substitutes(text: str, variables: tuple[str, ...]) -> bool:
    """Does writing terms in place of the pre-bound ``variables`` leave a query that no longer
    uses them (but to name them in the outer projection)? Checked once per query, on a
    stand-in term."""
    from rdflib.plugins.sparql.parser import parseQuery

    try:
        filled = parseQuery(Template(text, variables).fill(dict.fromkeys(variables, _CHECK_TERM)))
    except Exception:
        return False
    tree = _without_projected_names(filled)
    return not any(mentions(tree, Variable(v)) for v in variables)


def _prepared(text: str) -> Any:
    """``text`` prepared for rdflib's engine (its SPARQL parser imported now)."""
    from rdflib.plugins.sparql import prepareQuery

    return prepareQuery(text)


def _without_projected_names(node: Any) -> Any:
    """The parse tree without the ``AS ?var`` names of projections (``(TERM AS ?this)``)."""
    if _is_comp(node):
        return {k: _without_projected_names(v) for k, v in node.items() if k != "evar"}
    if isinstance(node, dict):
        return {k: _without_projected_names(v) for k, v in node.items()}
    if isinstance(node, (list, tuple)) or hasattr(node, "asList"):
        return [_without_projected_names(v) for v in node]
    return node


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


def compile_sparql(g: Graph, prefixes: dict[str, str], s: Shape, cnode: Node) -> tuple[SparqlC | None, str | None]:
    """Compile one sh:sparql node of shapes graph ``g`` (``prefixes``: those of the shapes
    graph); returns (constraint, problem); deactivated -> (None, None). A constraint without
    exactly one sh:select is refused (:class:`ShapeError`): SHACL-SPARQL constraints are
    SELECT queries (ASK queries are for the validators of constraint components)."""
    deact = next(iter(g.objects(cnode, SH.deactivated)), None)
    if isinstance(deact, Literal) and deact.value is True:
        return None, None
    selects = list(g.objects(cnode, SH.select))
    if len(selects) != 1:
        found = f"{len(selects)} sh:select" + (" and an sh:ask" if (cnode, SH.ask, None) in g else "")
        raise ShapeError(s.node, f"its SPARQL constraint has {found}: a SPARQL-based constraint needs "
                                 "exactly one sh:select (SHACL 5.1)", cnode)
    return sparql_constraint(g, prefixes, s, cnode, str(selects[0]))


def sparql_constraint(g: Graph, prefixes: dict[str, str], s: Shape, cnode: Node, body: str,
                      messages: list[str] | None = None, kind: type[SparqlC] | None = None,
                      params: dict[str, str] | None = None) -> tuple[SparqlC | None, str | None]:
    """A SPARQL constraint of shape ``s`` from the query ``body`` of node ``cnode`` (a
    sh:sparql constraint, or a validator of a constraint component with its parameters'
    values ``params``, variable name -> SPARQL term, written in); returns (constraint,
    problem): a problem sends the shape to pySHACL."""
    uses = set(_SHAPES_VARS.findall(body))
    if "currentShape" in uses and not isinstance(s.node, URIRef):
        return None, f"SPARQL constraint {cnode} uses $currentShape in a blank-node shape"
    if _PATH_VAR.search(body):
        if s.path is None:
            raise ShapeError(s.node, f"the SPARQL query of {_spelt(cnode)} uses $PATH, which only a property "
                                     "shape has", cnode)
        kind_, arg = s.path
        text = arg if kind_ == "pred" else f"^{arg}" if kind_ == "inv" else paths.sparql(arg)
        body = _PATH_VAR.sub(lambda m: m.group(1) + text, body)
    if params:
        body = Template(body, params).fill(params)
    if messages is None:
        messages = sorted(str(m) for m in g.objects(cnode, SH.message))
    c = (kind or SparqlC)(s, cnode, _prefix_block(g, prefixes, cnode, body) + body, messages)
    if uses:
        c.shapes_graph = g
        c.fixed = {v: SHAPES_GRAPH if v == "shapesGraph" else key_of(s.node) for v in uses}
    _analyse(c)
    return c, None


def _spelt(node: Node) -> str:
    return node.n3() if isinstance(node, URIRef) else "its constraint"


def check_validators(g: Graph, prefixes: dict[str, str], shape: Node, component: Node) -> None:
    """Refuse (:class:`ShapeError`) a custom constraint component used by ``shape`` whose
    validator queries do not parse or break SHACL's rules for pre-bound variables: those of a
    constraint, the component's parameters (by local name) and, in ASK validators, ``$value``."""
    params = {str(path).replace("#", "/").rsplit("/", 1)[-1]
              for p in g.objects(component, SH.parameter) for path in g.objects(p, SH.path)}
    for pred in (SH.validator, SH.nodeValidator, SH.propertyValidator):
        for v in g.objects(component, pred):
            for key, extra in ((SH.select, set()), (SH.ask, {"value"})):
                for body in g.objects(v, key):
                    text = _PATH_VAR.sub(r"\g<1><urn:kitkb:path>", str(body))
                    checked_query(_prefix_block(g, prefixes, v, text) + text, shape, v,
                                  CONSTRAINT_VARIABLES | params | extra, "validator")


def ox_key(term: Any) -> str:
    """Key of a pyoxigraph term (its N-Triples spelling)."""
    return str(term)


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
        self._templates: dict[int, Template] = {}
        self._blank_texts: dict[int, str] = {}
        self._grouped: dict[int, tuple[dict[str, list[dict[str, str]]], list[dict[str, str]]]] = {}
        self._bnodes: dict[str, ox.BlankNode] = {}
        self._pending: Any = None  # the background thread of prefetch(), until joined
        self._ask_templates: dict[int, Template] = {}
        self._answers: dict[tuple[str, str, int], bool] = {}

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
        shapes = {id(c.shapes_graph): c.shapes_graph for c in self.constraints if c.shapes_graph is not None}
        if shapes:  # for $shapesGraph: the shapes graph as a named graph beside the data
            name = self.ox_term(SHAPES_GRAPH)
            for g in shapes.values():
                quads += [ox.Quad(*(self.ox_term(key_of(t)) for t in triple), name) for triple in g]
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
            q = self._prepared[id(c)] = _prepared(c.text)
        binds = {"this": to_node(focus)} if focus is not None else None
        rows = []
        for r in self.graph().query(q, initBindings=binds):
            row = {str(k): key_of(v, rdf11_strings=self.ctx.rdf11_strings) for k, v in r.asdict().items()}
            if focus is not None and "this" in row:
                row["this"] = focus
            rows.append(row)
        return rows

    def _solutions(self, c: SparqlC, focus: str | None = None) -> list[dict[str, str]]:
        """The query's rows: all of them (``focus`` None), or with ``$this`` pre-bound to
        ``focus`` (written into the query; rdflib's pre-binding for a blank node)."""
        blank = focus is not None and focus[0] == "_"
        if self.engine == "rdflib" or (focus is not None and not c.substitutable) or (blank and not c.blank_bindable):
            if c.fixed:
                raise ShapeError(c.shape.node, "kitkb pre-binds $shapesGraph and $currentShape only with "
                                               "pyoxigraph, for focus nodes that are IRIs or literals", c.node)
            return self._rdflib_solutions(c, focus)
        if focus is None:
            res = self.store().query(self._query_text(c, frozenset()))
        elif blank:  # no query text can name a blank node: pyoxigraph binds it
            text = self._blank_texts.get(id(c))
            if text is None:
                text = self._blank_texts[id(c)] = for_blank_nodes(c.text)
            res = self.store().query(text, substitutions={ox.Variable("this"): self.ox_term(focus)})
        else:
            res = self.store().query(self._template(c).fill({"this": focus, **c.fixed}))
        names = [v.value for v in res.variables]
        rows = []
        for sol in res:
            row = {}
            for name in names:
                t = sol[name]
                if t is not None:
                    row[name] = ox_key(t)
            if focus is not None:
                row["this"] = focus
            rows.append(row)
        return rows

    def ask(self, c: SparqlC, focus: str, value: str) -> bool:
        """The ASK query of ``c`` with ``$this`` = ``focus`` and ``$value`` = ``value``
        (remembered per value where the query does not use ``$this``)."""
        if self._pending is not None:
            self.join()
        template = self._ask_templates.get(id(c))
        if template is None:
            template = self._ask_templates[id(c)] = Template(c.text, (*c.VARIABLES, *c.fixed))
        key = (focus if "this" in template.used else "", value, id(c))
        known = self._answers.get(key)
        if known is None:
            blank = focus[0] == "_" or value[0] == "_"
            if self.engine == "rdflib" or blank or not c.substitutable:
                if c.fixed:
                    raise ShapeError(c.shape.node, "kitkb pre-binds $shapesGraph and $currentShape only with "
                                                   "pyoxigraph, for nodes that are IRIs or literals", c.node)
                q = self._prepared.get(id(c))
                if q is None:
                    q = self._prepared[id(c)] = _prepared(c.text)
                known = bool(self.graph().query(q, initBindings={"this": to_node(focus),
                                                                  "value": to_node(value)}).askAnswer)
            else:
                known = bool(self.store().query(template.fill({"this": focus, "value": value, **c.fixed})))
            self._answers[key] = known
        return known

    def _template(self, c: SparqlC) -> Template:
        """The query, triple patterns in a cheap join order for a bound ``?this``, ready to
        take a focus node's term in place of ``$this``."""
        found = self._templates.get(id(c))
        if found is None:
            text = self._query_text(c, frozenset({"this"}))
            found = self._templates[id(c)] = Template(text, ("this", *c.fixed))
        return found

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
