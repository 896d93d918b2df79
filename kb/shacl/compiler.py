"""Compile a SHACL shapes graph into Shape objects the engine evaluates in bulk.

A shape the engine cannot evaluate exactly like pySHACL (a core component it leaves to
pySHACL, a blank-node parameter value of a constraint component, ``$currentShape`` in a
blank-node shape, a recursive shape) is recorded in :attr:`Program.unsupported` with the
reason; the engine hands every top-level shape that reaches such a shape to pySHACL instead
(with the SHACL instances it needs spelt out, :mod:`kb.shacl.fallback`). SPARQL-based
constraint components are evaluated here (:mod:`kb.shacl.components`).

A shape that no engine may evaluate, or whose constraint would be skipped, raises
:class:`kb.shacl.shape.ShapeError`, never a silent "conforms": SPARQL the specification
forbids or that does not parse, a term of the ``sh:`` namespace that is no SHACL term or that
neither engine evaluates (:mod:`kb.shacl.vocabulary`; checked on every node of the shapes
graph, so a misspelt ``sh:targetClas`` is caught too), a malformed RDF list or property path,
a count that is not an integer, a pattern that is not a regular expression, an unknown node
kind, an ``sh:property`` value without ``sh:path``, a constraint component kitkb cannot
evaluate (:mod:`kb.shacl.components`).
"""

from __future__ import annotations

import re
from collections.abc import Iterable
from dataclasses import dataclass

from rdflib import RDF, RDFS, BNode, Graph, Literal, URIRef
from rdflib.term import Node

from kb.core.namespaces import SH
from kb.shacl import components as CC
from kb.shacl import constraints as C
from kb.shacl import paths
from kb.shacl import vocabulary as V
from kb.shacl.shape import Constraint, Shape, ShapeError
from kb.shacl.sparql import SparqlC, compile_sparql
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


def _list(g: Graph, head: Node, s: Shape, pred: URIRef) -> list[Node]:
    """The members of the RDF list ``head`` (the value of ``pred`` on shape ``s``);
    :class:`ShapeError` when it is not a well-formed list (it would constrain nothing)."""
    members: list[Node] = []
    seen: set[Node] = set()
    node = head
    while node != RDF.nil:
        firsts, rests = list(g.objects(node, RDF.first)), list(g.objects(node, RDF.rest))
        if len(firsts) != 1 or len(rests) != 1 or node in seen:
            raise ShapeError(s.node, f"the value of sh:{_local(pred)} is not a well-formed RDF list", s.node)
        seen.add(node)
        members.append(firsts[0])
        node = rests[0]
    return members


#: Core components whose parameters a shape gives only in part: (given, wanted, refused?).
#: Without a mandatory parameter a component does not apply (SHACL 2.2) and the rest of the
#: shape still counts (the W3C suite's core/node/qualified-001 has counts without
#: sh:qualifiedValueShape and expects the other results): warned of, on the kb.shacl logger.
_PARTIAL = (
    ((SH.qualifiedMinCount, SH.qualifiedMaxCount), SH.qualifiedValueShape, False),
    ((SH.qualifiedValueShape,), None, False),
    ((SH.flags,), SH.pattern, False),
    ((SH.ignoredProperties,), SH.closed, False),
    ((SH.qualifiedValueShapesDisjoint,), SH.qualifiedValueShape, False),
)


def _partial_core(g: Graph, n: Node, preds: set[Node]) -> None:
    for given, wanted, refused in _PARTIAL:
        found = [p for p in given if p in preds]
        if not found:
            continue
        if wanted is None:  # sh:qualifiedValueShape wants a count
            if SH.qualifiedMinCount in preds or SH.qualifiedMaxCount in preds:
                continue
            what = "sh:qualifiedValueShape without sh:qualifiedMinCount or sh:qualifiedMaxCount"
        elif wanted in preds:
            continue
        else:
            what = f"sh:{_local(found[0])} without sh:{_local(wanted)}"
        if refused:
            raise ShapeError(n, f"{what}: the constraint does not apply (SHACL 2.2), so it would check nothing", n)
        CC.log.warning("shape %s has %s: by SHACL that constraint does not apply, it checks nothing",
                       CC.spell(g, n), what)


def _inert(p: Node, preds: set[Node]) -> bool:
    """Is the qualified-count parameter ``p`` without the rest of its component (so that
    nothing needs pySHACL for it)?"""
    counts = SH.qualifiedMinCount in preds or SH.qualifiedMaxCount in preds
    if p == SH.qualifiedValueShape:
        return not counts
    if p in (SH.qualifiedMinCount, SH.qualifiedMaxCount, SH.qualifiedValueShapesDisjoint):
        return SH.qualifiedValueShape not in preds
    return False


def _one_typo(a: str, b: str) -> bool:
    """Are ``a`` and ``b`` (different, 4 letters or more) one letter apart: one left out, added
    or changed, or two neighbours swapped?"""
    if a == b or min(len(a), len(b)) < 4 or abs(len(a) - len(b)) > 1:
        return False
    if len(a) == len(b):
        diff = [i for i in range(len(a)) if a[i] != b[i]]
        return len(diff) == 1 or (len(diff) == 2 and diff[1] == diff[0] + 1
                                  and a[diff[0]] == b[diff[1]] and a[diff[1]] == b[diff[0]])
    short, long_ = (a, b) if len(a) < len(b) else (b, a)
    return any(long_[:i] + long_[i + 1:] == short for i in range(len(long_)))


def _namespace(iri: Node) -> str:
    text = str(iri)
    cut = max(text.rfind("#"), text.rfind("/"))
    return text[: cut + 1]


def _local(term: Node) -> str:
    return str(term).rpartition("#")[2]


class Compiler:
    """Turns shape nodes of one shapes graph into :class:`Shape` objects (memoised)."""

    def __init__(self, g: Graph, *, rdf11_strings: bool, prefixes: dict[str, str]) -> None:
        self.g = g
        self.rdf11 = rdf11_strings
        self.prefixes = prefixes
        self.shapes: dict[Node, Shape] = {}
        self.components = CC.components(g)
        self.params = CC.parameter_index(self.components)
        self.pretenders = CC.pretenders(g, self.components)
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
        used: list[CC.Component] = []
        preds = set(g.predicates(n))
        _partial_core(g, n, preds)
        for p in sorted(preds, key=str):
            if p in self.params:
                used += [c for c in self.params[p] if c not in used]
            elif p in self.pretenders:
                raise ShapeError(n, f"{CC.spell(g, p)} is a parameter of {CC.spell(g, self.pretenders[p])}, which is no SHACL "
                                    "instance of sh:ConstraintComponent (its rdf:type does not lead there by "
                                    "rdfs:subClassOf), so its validators would never run", n)
            elif str(p).startswith(str(SH)):
                _check_term(g, n, p)
                if p in V.PYSHACL and not _inert(p, preds):
                    s.problems.append(f"{CC.spell(g, p)}, a SHACL core constraint kitkb's engine leaves to pySHACL")
            elif self.params and isinstance(p, URIRef):
                near = self._misspelt_parameter(p)
                if near is not None:
                    raise ShapeError(n, f"{CC.spell(g, p)} is no parameter of a constraint component here, did "
                                        f"you mean {CC.spell(g, near)}? (it would check nothing)", n)
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
                raise ShapeError(n, f"sh:path {CC.spell(g, path)} is not a well-formed SHACL property path", n)
            if found[0] == "pred" or (found[0] == "inv" and found[1][0] == "pred"):
                s.path = (found[0], found[1] if found[0] == "pred" else found[1][1])
            else:
                s.path = ("path", found)
        self._constraints(s)
        for comp in used:
            found_c, problem = CC.constraints(g, self.prefixes, s, comp, self.rdf11)
            if problem:
                s.problems.append(problem)
            s.constraints.extend(found_c)

    def _constraints(self, s: Shape) -> None:
        g, n, add = self.g, s.node, s.constraints.append
        for cls in g.objects(n, SH["class"]):
            add(C.ClassC(s, self.key(cls)))
        for dt in g.objects(n, SH.datatype):
            add(C.DatatypeC(s, self.key(dt), self.read_as))
        for kind in g.objects(n, SH.nodeKind):
            if kind not in V.NODE_KINDS:
                raise ShapeError(n, f"sh:nodeKind {CC.spell(g, kind)} is none of SHACL's six node kinds", n)
            add(C.NodeKindC(s, kind))
        for which in ("min", "max"):
            for v in g.objects(n, SH[which + "Count"]):
                add(C.CountC(s, which, self._integer(s, which + "Count", v)))
            for v in g.objects(n, SH[which + "Length"]):
                add(C.LengthC(s, which, self._integer(s, which + "Length", v)))
        for which in ("minExclusive", "minInclusive", "maxExclusive", "maxInclusive"):
            for v in g.objects(n, SH[which]):
                add(C.RangeC(s, which, v, self.read_as))
        flags = self._one(n, SH.flags)
        for pat in g.objects(n, SH.pattern):
            try:
                add(C.PatternC(s, str(pat), str(flags) if flags is not None else None))
            except re.error as exc:
                raise ShapeError(n, f"sh:pattern {str(pat)!r} is not a regular expression kitkb reads: {exc}",
                                 n) from None
        for head in g.objects(n, SH["in"]):
            add(C.InC(s, [self.key(m) for m in _list(g, head, s, SH["in"])]))
        for hv in g.objects(n, SH.hasValue):
            add(C.HasValueC(s, self.key(hv)))
        for other in g.objects(n, SH.node):
            add(C.NodeC(s, self._ref(s, other)))
        for other in g.objects(n, SH["not"]):
            add(C.NotC(s, self._ref(s, other)))
        for which in ("and", "or", "xone"):
            for head in g.objects(n, SH[which]):
                add(C.ListC(s, which, [self._ref(s, m) for m in _list(g, head, s, SH[which])]))
        props = list(g.objects(n, SH.property))
        for ps in props:
            if self._one(ps, SH.path) is None:
                raise ShapeError(n, f"the value {CC.spell(g, ps)} of its "
                                    "sh:property has no sh:path (a property shape needs one)", ps)
        closed = self._one(n, SH.closed)
        if isinstance(closed, Literal) and closed.value is True:
            allowed = {self.key(p) for p in (self._one(ps, SH.path) for ps in props) if isinstance(p, URIRef)}
            for head in g.objects(n, SH.ignoredProperties):
                allowed.update(self.key(m) for m in _list(g, head, s, SH.ignoredProperties))
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

    def _misspelt_parameter(self, p: URIRef) -> Node | None:
        """The parameter of a component of this shapes graph that ``p`` (no parameter) misspells
        by one letter (left out, added, changed, or two swapped), in the same namespace
        (``ex:maxLenght`` for ``ex:maxLength``), else None."""
        ns = _namespace(p)
        local = str(p)[len(ns):]
        for q in sorted(self.params, key=str):
            if isinstance(q, URIRef) and _namespace(q) == ns and _one_typo(local, str(q)[len(ns):]):
                return q
        return None

    @staticmethod
    def _integer(s: Shape, param: str, v: Node) -> int:
        limit = C.literal_int(v)
        if limit is None:
            raise ShapeError(s.node, f"sh:{param} {v.n3()} is not an integer", s.node)
        return limit

    def _ref(self, s: Shape, other: Node) -> Shape:
        ref = self.shape(other)
        s.refs.append(ref)
        return ref


def _reachable_problems(s: Shape) -> list[str]:
    """Problems of ``s`` and of the shapes it reaches; a reference cycle is one too (pySHACL
    evaluates recursive shapes, and kitkb refuses its answer where it stopped short:
    :mod:`kb.shacl.fallback`)."""
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


@dataclass
class _Kinds:
    """The SHACL classes a shapes graph's own rdfs:subClassOf reaches: its classes (SHACL
    instances of rdfs:Class) and its shape types (of sh:NodeShape, sh:PropertyShape)."""

    classes: set[Node]
    shapes: set[Node]

    @classmethod
    def of(cls, g: Graph) -> "_Kinds":
        return cls(CC.subclasses(g, RDFS.Class),
                   CC.subclasses(g, SH.NodeShape) | CC.subclasses(g, SH.PropertyShape))

    def implicit_target(self, g: Graph, n: Node) -> bool:
        """A shape that is also a class has an implicit class target (SHACL 2.1.3.3)."""
        types = set(g.objects(n, RDF.type))
        return bool(types & self.shapes) and bool(types & self.classes)


def targeted_shapes(g: Graph) -> set[Node]:
    """The shapes of ``g`` with a target: sh:targetClass, sh:targetNode, sh:targetSubjectsOf,
    sh:targetObjectsOf, or a shape that is also a class (an implicit class target; both by
    rdf:type/rdfs:subClassOf*)."""
    heads: set[Node] = set()
    for p in TARGET_PREDICATES:
        heads.update(g.subjects(p, None))
    kinds = _Kinds.of(g)
    for n in set(g.subjects(RDF.type, None)):
        if kinds.implicit_target(g, n):
            heads.add(n)
    return heads


#: Predicates that make their subject a shape (SHACL 2.1: a target, a constraint parameter).
_SHAPE_PARAMETERS = (KNOWN | V.PYSHACL) - {RDF.type, SH.deactivated, SH.severity, SH.message, SH.name,
                                            SH.description, SH.order, SH.group, SH.defaultValue, SH.prefixes,
                                            SH.flags, SH.ignoredProperties}
#: Predicates whose values are shapes (a node used so has no other role through them).
_SHAPE_VALUES = {SH.property, SH.node, SH["not"], SH.qualifiedValueShape}


def _check_term(g: Graph, n: Node, p: URIRef) -> None:
    """:class:`ShapeError` when shape ``n``'s predicate ``p`` (of the ``sh:`` namespace) would
    be skipped: no SHACL term, an advanced feature, or a term that belongs elsewhere (unless
    ``n`` plays that other role too, as a shape that is its own sh:sparql constraint)."""
    why = V.on_shape(p, KNOWN)  # type: ignore[arg-type]
    if why and p in V.PROPERTIES and p not in V.ADVANCED and _other_role(g, n):
        return
    if why:
        raise ShapeError(n, why, n)


def _other_role(g: Graph, n: Node) -> bool:
    """Is ``n`` the value of an ``sh:`` predicate that does not take a shape (sh:sparql, a
    validator, sh:path ...)?"""
    sh = str(SH)
    return any(str(p).startswith(sh) and p not in _SHAPE_VALUES for p in g.predicates(None, n))


def _shape_like(g: Graph) -> set[Node]:
    """Nodes SHACL takes for shapes: SHACL instances of sh:NodeShape or sh:PropertyShape,
    subjects of a target or of a constraint parameter."""
    kinds = _Kinds.of(g)
    found = {n for t in kinds.shapes for n in g.subjects(RDF.type, t)}
    for p in (*TARGET_PREDICATES, *_SHAPE_PARAMETERS):
        found.update(g.subjects(p, None))
    return found


def check_vocabulary(g: Graph, checked: Iterable[Node] = ()) -> None:
    """:class:`ShapeError` for a shape with a predicate of the ``sh:`` namespace that would be
    skipped (:func:`_check_term`), reached from a target or not (a misspelt ``sh:targetClas``
    leaves its shape without one), and for an sh:targetClass, sh:targetSubjectsOf or
    sh:targetObjectsOf that is a literal (it would select nothing). ``checked``: shapes
    whose predicates were checked already (compiled)."""
    sh = str(SH)
    for n in sorted(_shape_like(g) - set(checked), key=str):
        for p in sorted(set(g.predicates(n)), key=str):
            if str(p).startswith(sh):
                _check_term(g, n, p)  # type: ignore[arg-type]
    for p in (SH.targetClass, SH.targetSubjectsOf, SH.targetObjectsOf):
        for node, value in g.subject_objects(p):
            if isinstance(value, Literal):
                raise ShapeError(node, f"sh:{_local(p)} {value.n3()} is a literal: it selects no focus node", node)


def compile_program(g: Graph, *, rdf11_strings: bool, prefixes: dict[str, str]) -> Program:
    """Compile every shape of ``g`` that has a target (and the shapes they reach)."""
    comp = Compiler(g, rdf11_strings=rdf11_strings, prefixes=prefixes)
    heads = targeted_shapes(g)
    kinds = _Kinds.of(g)
    top: list[tuple[Shape, dict[URIRef, list[str]]]] = []
    unsupported: dict[Node, str] = {}
    for head in sorted(heads, key=lambda h: (isinstance(h, BNode), str(h))):
        s = comp.shape(head)
        problems = _reachable_problems(s)
        if problems:
            unsupported[head] = "; ".join(problems)
            continue
        targets = {p: [comp.key(o) for o in g.objects(head, p)] for p in TARGET_PREDICATES}
        if kinds.implicit_target(g, head):
            targets[SH.targetClass].append(comp.key(head))
        top.append((s, targets))
    check_vocabulary(g, comp.shapes)  # the shapes no target reaches (a misspelt sh:targetClass)
    return Program(comp.shapes, top, unsupported)
