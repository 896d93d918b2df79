"""Compile a SHACL shapes graph into Shape objects the engine evaluates in bulk.

A shape the engine cannot evaluate exactly like pySHACL (an unknown SHACL parameter, a
malformed property path, a custom constraint component, ``$shapesGraph``/``$currentShape`` in
a SPARQL query) is recorded in :attr:`Program.unsupported` with the reason; the engine hands
every top-level shape that reaches such a shape to pySHACL instead. A shape that no engine
may evaluate (SPARQL the specification forbids, a query that does not parse, in a constraint
or in the validator of a custom component it uses) raises :class:`kb.shacl.shape.ShapeError`.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field

from rdflib import RDF, RDFS, BNode, Graph, Literal, URIRef
from rdflib.collection import Collection
from rdflib.term import Node

from kb.core.namespaces import SH
from kb.shacl import constraints as C
from kb.shacl import paths
from kb.shacl.shape import Constraint, Shape
from kb.shacl.sparql import SparqlC, check_validators, compile_sparql
from kb.shacl.terms import XSD_NS, key_of

TARGET_PREDICATES = (SH.targetClass, SH.targetNode, SH.targetSubjectsOf, SH.targetObjectsOf)

#: SHACL predicates that may appear on a shape and that the engine understands.
KNOWN = {
    RDF.type, SH.path, SH.deactivated, SH.severity, SH.message, SH.name, SH.description,
    SH.order, SH.group, SH.defaultValue, SH.prefixes, SH.ignoredProperties, SH.flags,
    SH.property, SH.node, SH["not"], SH["and"], SH["or"], SH.xone, SH["class"], SH.datatype,
    SH.nodeKind, SH.minCount, SH.maxCount, SH.minExclusive, SH.minInclusive, SH.maxExclusive,
    SH.maxInclusive, SH.minLength, SH.maxLength, SH.pattern, SH["in"], SH.hasValue, SH.closed,
    SH.sparql, *TARGET_PREDICATES,
}


#: ``D kitkbsh:readAs B`` in a shapes graph: a literal typed ``D`` (an OWL datatype definition,
#: which OWL 2 gives no lexical space, though NIST's tools wrote ``"0.8"^^:positiveDecimal``) is
#: read as the literal of the XSD datatype ``B`` with the same lexical form: sh:datatype D wants
#: that form in B's lexical space, and comparisons (sh:minExclusive ...) use B's value.
READ_AS = URIRef("https://w3id.org/kitkb/shapes#readAs")


def read_as(g: Graph) -> dict[str, str]:
    """The ``kitkbsh:readAs`` declarations of ``g``: datatype IRI -> XSD datatype IRI."""
    return {str(d): str(b) for d, b in g.subject_objects(READ_AS)
            if isinstance(d, URIRef) and isinstance(b, URIRef) and str(b).startswith(XSD_NS)}


@dataclass
class Program:
    """Compiled shapes: the target-bearing shapes and what the engine cannot do itself."""

    shapes: dict[Node, Shape]
    top: list[tuple[Shape, dict[URIRef, list[str]]]]
    unsupported: dict[Node, str]

    def sparql_constraints(self) -> list[Constraint]:
        return [c for s in self.shapes.values() for c in s.constraints if isinstance(c, SparqlC)]


def _list(g: Graph, head: Node) -> list[Node]:
    try:
        return list(Collection(g, head))
    except Exception:  # malformed list: nothing to compare against
        return []


def _custom_parameters(g: Graph) -> dict[Node, list[Node]]:
    """Parameter (its sh:path) -> the custom constraint components declaring it; a component
    is typed sh:ConstraintComponent or a subclass of it (rdfs:subClassOf*, in ``g``)."""
    kinds = {SH.ConstraintComponent}
    todo = [SH.ConstraintComponent]
    while todo:
        for sub in g.subjects(RDFS.subClassOf, todo.pop()):
            if sub not in kinds:
                kinds.add(sub)
                todo.append(sub)
    params: dict[Node, list[Node]] = {}
    for kind in kinds:
        for comp in g.subjects(RDF.type, kind):
            for p in g.objects(comp, SH.parameter):
                for path in g.objects(p, SH.path):
                    params.setdefault(path, []).append(comp)
    return params


class Compiler:
    """Turns shape nodes of one shapes graph into :class:`Shape` objects (memoised)."""

    def __init__(self, g: Graph, *, rdf11_strings: bool, prefixes: dict[str, str]) -> None:
        self.g = g
        self.rdf11 = rdf11_strings
        self.prefixes = prefixes
        self.shapes: dict[Node, Shape] = {}
        self.custom = _custom_parameters(g)
        self.read_as = read_as(g)

    def key(self, term: Node) -> str:
        return key_of(term, rdf11_strings=self.rdf11)

    def shape(self, node: Node) -> Shape:
        found = self.shapes.get(node)
        if found is not None:
            return found
        s = self.shapes[node] = Shape(node)
        self._fill(s)
        return s

    def _one(self, node: Node, pred: URIRef) -> Node | None:
        vals = list(self.g.objects(node, pred))
        return vals[0] if vals else None

    def _fill(self, s: Shape) -> None:
        g, n = self.g, s.node
        for p in set(g.predicates(n)):
            if p in self.custom:
                for comp in self.custom[p]:
                    check_validators(g, self.prefixes, n, comp)
                s.problems.append(f"custom constraint component parameter {p}")
            elif str(p).startswith(str(SH)) and p not in KNOWN:
                s.problems.append(f"unsupported SHACL parameter {p}")
        deact = self._one(n, SH.deactivated)
        s.deactivated = isinstance(deact, Literal) and deact.value is True
        sev = self._one(n, SH.severity)
        if isinstance(sev, URIRef):
            s.severity = sev
        msgs = sorted(str(m) for m in g.objects(n, SH.message))
        s.message = msgs[0] if msgs else None
        path = self._one(n, SH.path)
        if path is not None:
            s.path_node = path
            found = paths.read(g, path, self.key)
            if found is None:
                s.problems.append(f"sh:path {path} is not a well-formed SHACL property path")
                s.path = ("pred", "<urn:kitkb:unsupported-path>")
            elif found[0] == "pred" or (found[0] == "inv" and found[1][0] == "pred"):
                s.path = (found[0], found[1] if found[0] == "pred" else found[1][1])
            else:
                s.path = ("path", found)
        self._constraints(s)

    def _constraints(self, s: Shape) -> None:
        g, n, add = self.g, s.node, s.constraints.append
        for cls in g.objects(n, SH["class"]):
            add(C.ClassC(s, self.key(cls)))
        for dt in g.objects(n, SH.datatype):
            add(C.DatatypeC(s, self.key(dt), self.read_as))
        for kind in g.objects(n, SH.nodeKind):
            add(C.NodeKindC(s, kind))
        for which in ("min", "max"):
            for v in g.objects(n, SH[which + "Count"]):
                limit = C.literal_int(v)
                if limit is None:
                    s.problems.append(f"sh:{which}Count {v} is not an integer")
                else:
                    add(C.CountC(s, which, limit))
            for v in g.objects(n, SH[which + "Length"]):
                limit = C.literal_int(v)
                if limit is None:
                    s.problems.append(f"sh:{which}Length {v} is not an integer")
                else:
                    add(C.LengthC(s, which, limit))
        for which in ("minExclusive", "minInclusive", "maxExclusive", "maxInclusive"):
            for v in g.objects(n, SH[which]):
                add(C.RangeC(s, which, v, self.read_as))
        flags = self._one(n, SH.flags)
        for pat in g.objects(n, SH.pattern):
            add(C.PatternC(s, str(pat), str(flags) if flags is not None else None))
        for head in g.objects(n, SH["in"]):
            add(C.InC(s, [self.key(m) for m in _list(g, head)]))
        for hv in g.objects(n, SH.hasValue):
            add(C.HasValueC(s, self.key(hv)))
        for other in g.objects(n, SH.node):
            add(C.NodeC(s, self._ref(s, other)))
        for other in g.objects(n, SH["not"]):
            add(C.NotC(s, self._ref(s, other)))
        for which in ("and", "or", "xone"):
            for head in g.objects(n, SH[which]):
                add(C.ListC(s, which, [self._ref(s, m) for m in _list(g, head)]))
        props = list(g.objects(n, SH.property))
        closed = self._one(n, SH.closed)
        if isinstance(closed, Literal) and closed.value is True:
            allowed = {self.key(p) for p in (self._one(ps, SH.path) for ps in props) if isinstance(p, URIRef)}
            for head in g.objects(n, SH.ignoredProperties):
                allowed.update(self.key(m) for m in _list(g, head))
            add(C.ClosedC(s, allowed))
        for ps in props:
            add(C.PropertyC(s, self._ref(s, ps)))
        if (n, SH.sparql, None) in g:
            for cnode in g.objects(n, SH.sparql):
                c, problem = compile_sparql(g, self.prefixes, s, cnode)
                if problem:
                    s.problems.append(problem)
                elif c is not None:
                    add(c)

    def _ref(self, s: Shape, other: Node) -> Shape:
        ref = self.shape(other)
        s.refs.append(ref)
        return ref


def _reachable_problems(s: Shape) -> list[str]:
    """Problems of ``s`` and of the shapes it reaches; a reference cycle is one too."""
    found: list[str] = []
    done: set[int] = set()
    on_path: set[int] = set()

    def visit(cur: Shape) -> None:
        if id(cur) in on_path:
            found.append(f"{cur.node}: recursive shape reference (pySHACL's recursion rule applies)")
            return
        if id(cur) in done:
            return
        on_path.add(id(cur))
        found.extend(f"{cur.node}: {p}" for p in cur.problems)
        for ref in cur.refs:
            visit(ref)
        on_path.discard(id(cur))
        done.add(id(cur))

    visit(s)
    return found


def _implicit_class_target(g: Graph, n: Node) -> bool:
    if not ((n, RDF.type, SH.NodeShape) in g or (n, RDF.type, SH.PropertyShape) in g):
        return False
    classes = set(g.subjects(RDFS.subClassOf, RDFS.Class)) | {RDFS.Class}
    return any(t in classes for t in g.objects(n, RDF.type))


def targeted_shapes(g: Graph) -> set[Node]:
    """The shapes of ``g`` with a target: sh:targetClass, sh:targetNode, sh:targetSubjectsOf,
    sh:targetObjectsOf, or a shape that is also a class (an implicit class target)."""
    heads: set[Node] = set()
    for p in TARGET_PREDICATES:
        heads.update(g.subjects(p, None))
    for n in set(g.subjects(RDF.type, None)):
        if _implicit_class_target(g, n):
            heads.add(n)
    return heads


def compile_program(g: Graph, *, rdf11_strings: bool, prefixes: dict[str, str]) -> Program:
    """Compile every shape of ``g`` that has a target (and the shapes they reach)."""
    comp = Compiler(g, rdf11_strings=rdf11_strings, prefixes=prefixes)
    heads = targeted_shapes(g)
    top: list[tuple[Shape, dict[URIRef, list[str]]]] = []
    unsupported: dict[Node, str] = {}
    for head in sorted(heads, key=lambda h: (isinstance(h, BNode), str(h))):
        s = comp.shape(head)
        problems = _reachable_problems(s)
        if problems:
            unsupported[head] = "; ".join(problems)
            continue
        targets = {p: [comp.key(o) for o in g.objects(head, p)] for p in TARGET_PREDICATES}
        if _implicit_class_target(g, head):
            targets[SH.targetClass].append(comp.key(head))
        top.append((s, targets))
    return Program(comp.shapes, top, unsupported)
