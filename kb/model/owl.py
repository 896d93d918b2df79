"""A typed view of an OWL model held in an rdflib graph: classes, properties, datatypes.

Generators read this instead of walking triples themselves. It understands the patterns the
kitkb and NIST models use: named classes with ``rdfs:subClassOf`` (named or restriction)
and ``owl:equivalentClass`` intersections of restrictions, property domains and ranges (named
or ``owl:unionOf``), functional / inverse-functional flags, ``owl:hasKey``, and datatypes
defined as ``owl:oneOf`` enumerations or facet restrictions of an XSD type.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Iterable

from rdflib import OWL, RDF, RDFS, XSD, BNode, Graph, Literal, URIRef
from rdflib.collection import Collection
from rdflib.term import Node

#: Namespaces of the W3C vocabularies (never "declared" by a model file).
W3C_NAMESPACES = (str(RDF), str(RDFS), str(OWL), str(XSD), "http://www.w3.org/ns/shacl#",
                  "http://www.w3.org/XML/1998/namespace")

UNBOUNDED = 10**9


def is_w3c(term: Node) -> bool:
    """True for IRIs of rdf:, rdfs:, owl:, xsd:, sh: (built-in vocabulary)."""
    return isinstance(term, URIRef) and str(term).startswith(W3C_NAMESPACES)


@dataclass
class Restriction:
    """One cardinality / value restriction a class puts on a property."""

    prop: URIRef
    min: int = 0
    max: int = UNBOUNDED
    on: Node | None = None          # qualifying class or data range (None: unqualified)
    all_values: Node | None = None  # owl:allValuesFrom filler
    via: URIRef = RDFS.subClassOf   # axiom stating it: rdfs:subClassOf or owl:equivalentClass


@dataclass
class ClassInfo:
    """A named class: its named superclasses and the restrictions it inherits by axiom."""

    iri: URIRef
    supers: set[URIRef] = field(default_factory=set)
    parents: set[URIRef] = field(default_factory=set)  # named rdfs:subClassOf objects only
    restrictions: list[Restriction] = field(default_factory=list)
    keys: list[list[URIRef]] = field(default_factory=list)
    disjoint: set[URIRef] = field(default_factory=set)


@dataclass
class PropertyInfo:
    """A declared object or datatype property."""

    iri: URIRef
    kind: str                       # "object" | "datatype"
    domains: list[URIRef] = field(default_factory=list)  # named classes (union members expanded)
    ranges: list[Node] = field(default_factory=list)     # named classes / datatypes
    functional: bool = False
    inverse_functional: bool = False
    inverse_of: URIRef | None = None


@dataclass
class DatatypeInfo:
    """A named datatype: an enumeration, or a base XSD type with facets."""

    iri: URIRef
    values: list[Literal] | None = None
    base: URIRef | None = None
    facets: dict[URIRef, Literal] = field(default_factory=dict)


class OwlModel:
    """The classes, properties and datatypes an rdflib graph declares."""

    def __init__(self, graph: Graph):
        self.graph = graph
        self.classes: dict[URIRef, ClassInfo] = {}
        self.properties: dict[URIRef, PropertyInfo] = {}
        self.annotation_properties: set[URIRef] = set()
        self.datatypes: dict[URIRef, DatatypeInfo] = {}
        #: Malformed axioms skipped while reading: (node, predicate, value, message).
        self.problems: list[tuple[Node, URIRef, Node, str]] = []
        self._ancestors: dict[URIRef, list[URIRef]] = {}
        self._descendants: dict[URIRef, list[URIRef]] | None = None
        self._by_domain: dict[URIRef, list[URIRef]] | None = None
        self._read()

    # --- reading ----------------------------------------------------------------------

    def _read(self) -> None:
        g = self.graph
        for c in _named(g.subjects(RDF.type, OWL.Class)) | _named(g.subjects(RDF.type, RDFS.Class)):
            if not is_w3c(c):
                self.classes[c] = ClassInfo(c)
        for kind, cls in (("object", OWL.ObjectProperty), ("datatype", OWL.DatatypeProperty)):
            for p in _named(g.subjects(RDF.type, cls)):
                self.properties.setdefault(p, PropertyInfo(p, kind))
        self.annotation_properties = {p for p in _named(g.subjects(RDF.type, OWL.AnnotationProperty))}
        defined = {d for d, e in g.subject_objects(OWL.equivalentClass)
                   if (e, RDF.type, RDFS.Datatype) in g or (e, OWL.onDatatype, None) in g
                   or any(isinstance(v, Literal) for v in _list(g, g.value(e, OWL.oneOf)))}
        for d in _named(g.subjects(RDF.type, RDFS.Datatype)) | _named(defined):
            if not is_w3c(d):
                self.datatypes[d] = self._datatype(d)
        for c, info in self.classes.items():
            self._read_class(c, info)
        for p, info in self.properties.items():
            self._read_property(p, info)

    def _read_class(self, c: URIRef, info: ClassInfo) -> None:
        g = self.graph
        for sup in g.objects(c, RDFS.subClassOf):
            self._class_expression(info, sup)
            if isinstance(sup, URIRef) and sup != OWL.Thing and sup != c:
                info.parents.add(sup)
        for eq in g.objects(c, OWL.equivalentClass):
            self._class_expression(info, eq, OWL.equivalentClass)
        for key in g.objects(c, OWL.hasKey):
            info.keys.append([k for k in Collection(g, key) if isinstance(k, URIRef)])
        for other in g.objects(c, OWL.disjointWith):
            if isinstance(other, URIRef):
                info.disjoint.add(other)
        for members in list(g.objects(c, OWL.disjointUnionOf)):
            self._disjoint_all(Collection(g, members))
        for node in g.subjects(RDF.type, OWL.AllDisjointClasses):
            for members in g.objects(node, OWL.members):
                self._disjoint_all(Collection(g, members))

    def _disjoint_all(self, members: Iterable[Node]) -> None:
        named = [m for m in members if isinstance(m, URIRef)]
        for a in named:
            if a in self.classes:
                self.classes[a].disjoint.update(b for b in named if b != a)

    def _class_expression(self, info: ClassInfo, expr: Node, via: URIRef = RDFS.subClassOf) -> None:
        """Fold a superclass expression (named, restriction, intersection) stated by ``via`` into ``info``."""
        g = self.graph
        if isinstance(expr, URIRef):
            if expr != OWL.Thing and expr != info.iri:
                info.supers.add(expr)
            return
        if (expr, RDF.type, OWL.Restriction) in g:
            r = self._restriction(expr)
            if r is not None:
                r.via = via
                info.restrictions.append(r)
            return
        for members in g.objects(expr, OWL.intersectionOf):
            for m in Collection(g, members):
                self._class_expression(info, m, via)

    def _restriction(self, node: Node) -> Restriction | None:
        g = self.graph
        prop = g.value(node, OWL.onProperty)
        if not isinstance(prop, URIRef):
            return None
        on = g.value(node, OWL.onClass) or g.value(node, OWL.onDataRange)
        r = Restriction(prop, on=on)
        for pred, lo, hi in ((OWL.cardinality, True, True), (OWL.qualifiedCardinality, True, True),
                             (OWL.minCardinality, True, False), (OWL.minQualifiedCardinality, True, False),
                             (OWL.maxCardinality, False, True), (OWL.maxQualifiedCardinality, False, True)):
            value = g.value(node, pred)
            if value is not None:
                n = _cardinality(value)
                if n is None:
                    self.problems.append((node, pred, value, f"cardinality {str(value)!r} of a restriction on "
                                          f"<{prop}> is not a whole number >= 0"))
                    continue
                r.min = n if lo else r.min
                r.max = n if hi else r.max
        some = g.value(node, OWL.someValuesFrom)
        if some is not None:
            r.min, r.on = max(r.min, 1), some
        r.all_values = g.value(node, OWL.allValuesFrom)
        return r

    def _read_property(self, p: URIRef, info: PropertyInfo) -> None:
        g = self.graph
        types = set(g.objects(p, RDF.type))
        info.functional = OWL.FunctionalProperty in types
        info.inverse_functional = OWL.InverseFunctionalProperty in types
        info.domains = sorted({d for e in g.objects(p, RDFS.domain) for d in self._union(e)})
        info.ranges = sorted({r for e in g.objects(p, RDFS.range) for r in self._union(e)})
        inv = g.value(p, OWL.inverseOf)
        info.inverse_of = inv if isinstance(inv, URIRef) else None

    def _union(self, expr: Node) -> list[URIRef]:
        if isinstance(expr, URIRef):
            return [expr]
        out: list[URIRef] = []
        for members in self.graph.objects(expr, OWL.unionOf):
            out += [m for m in Collection(self.graph, members) if isinstance(m, URIRef)]
        return out

    def datatype_info(self, d: Node) -> DatatypeInfo | None:
        """A named or anonymous datatype's enumeration / base and facets (None: neither)."""
        if isinstance(d, URIRef):
            return self.datatypes.get(d)
        info = self._datatype(d)  # type: ignore[arg-type]
        return info if info.values is not None or info.base is not None else None

    def _datatype(self, d: URIRef) -> DatatypeInfo:
        g = self.graph
        info = DatatypeInfo(d)
        for expr in [d, *g.objects(d, OWL.equivalentClass)]:
            one_of = g.value(expr, OWL.oneOf)
            if one_of is not None:
                info.values = [v for v in Collection(g, one_of) if isinstance(v, Literal)]
            base = g.value(expr, OWL.onDatatype)
            if isinstance(base, URIRef):
                info.base = base
                for facets in g.objects(expr, OWL.withRestrictions):
                    for f in Collection(g, facets):
                        for pred, value in g.predicate_objects(f):
                            if isinstance(value, Literal):
                                info.facets[pred] = value
        return info

    # --- queries ----------------------------------------------------------------------

    def ontologies(self) -> list[tuple[URIRef, str]]:
        """(IRI, owl:versionInfo or "") of every named ``owl:Ontology`` in the graph, sorted."""
        g = self.graph
        return sorted((o, str(g.value(o, OWL.versionInfo) or ""))
                      for o in _named(g.subjects(RDF.type, OWL.Ontology)))

    def comment(self, term: URIRef) -> str:
        """The ``rdfs:comment`` of ``term``, else its ``rdfs:label``, else ""."""
        g = self.graph
        return str(g.value(term, RDFS.comment) or g.value(term, RDFS.label) or "")

    def ancestors(self, c: URIRef) -> list[URIRef]:
        """Named superclasses of ``c`` (transitively, ``c`` excluded), sorted."""
        if c not in self._ancestors:
            seen: set[URIRef] = set()
            todo = [c]
            while todo:
                info = self.classes.get(todo.pop())
                for sup in info.supers if info else ():
                    if sup not in seen and sup != c:
                        seen.add(sup)
                        todo.append(sup)
            self._ancestors[c] = sorted(seen)
        return self._ancestors[c]

    def descendants(self, c: URIRef) -> list[URIRef]:
        """Named subclasses of ``c`` (transitively, ``c`` excluded), sorted."""
        if self._descendants is None:
            down: dict[URIRef, list[URIRef]] = {}
            for d in sorted(self.classes):
                for a in self.ancestors(d):
                    down.setdefault(a, []).append(d)
            self._descendants = down
        return self._descendants.get(c, [])

    def properties_of(self, c: URIRef) -> list[URIRef]:
        """Properties whose domain is ``c`` itself."""
        if self._by_domain is None:
            by: dict[URIRef, list[URIRef]] = {}
            for p, info in sorted(self.properties.items()):
                for d in info.domains:
                    by.setdefault(d, []).append(p)
            self._by_domain = by
        return self._by_domain.get(c, [])

    def global_properties(self) -> list[URIRef]:
        """Properties with no domain or domain owl:Thing: allowed on every individual."""
        return sorted(p for p, info in self.properties.items()
                      if not info.domains or OWL.Thing in info.domains)


def _named(nodes: Iterable[Node]) -> set[URIRef]:
    return {n for n in nodes if isinstance(n, URIRef)}


def _list(g: Graph, head: Node | None) -> list[Node]:
    return list(Collection(g, head)) if head is not None else []


def is_bnode(node: Node) -> bool:
    """True for a blank node."""
    return isinstance(node, BNode)


def _cardinality(value: Node) -> int | None:
    """The whole number >= 0 a cardinality literal states, or None if it states none."""
    try:
        n = int(str(value))
    except ValueError:
        return None
    return n if n >= 0 else None
