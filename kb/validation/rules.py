"""The validation rules that are not per-class SHACL shapes, as Python checks.

Model-file rules: every property used is declared and has a domain and a range; the
``has<Domain>_<Attribute>`` / ``hadBy<Attribute>_<Range>`` naming convention; every class
sits in a declared hierarchy; datatypes used as ranges exist.

Data-file rules: a data file declares no classes, properties or datatypes and adds no axioms
to them, save a domain file's classes of objects (:func:`domain_classes`: a class declared
``rdfs:subClassOf`` a class of the model, which then joins the model); every ``rdf:type`` names a declared class; every property is declared; every
reference names a declared individual, and every subject of a statement is typed somewhere
(a misspelt subject, NIST's ``:PartGipperPose``, is an ``unknown-individual``); no individual
is typed with an abstract class.

Each finding is reported at the line of the statement that carries the offending name or
value (the type statement, the property's statement, the reference), and a term of NIST's
2012 namespace is named as the file writes it (:class:`kb.validation.report.Namer`).

Each check yields :class:`kb.core.diagnostics.Diagnostic` objects through a
:class:`RuleContext`,
which knows how to name terms compactly and where a triple sits in its file.
"""

from __future__ import annotations

import functools
import re
from dataclasses import dataclass, field
from typing import Any, Callable, Iterator

from rdflib import OWL, RDF, RDFS, XSD, Graph, Literal, URIRef
from rdflib.term import Node

from kb.core.diagnostics import Diagnostic
from kb.core.namespaces import KITTING_DOMAIN_ONTOLOGY, KTW, SOAP, local_name
from kb.model.definitions import check_definitions
from kb.model.owl import OwlModel, is_w3c
from kb.validation.suggest import closest

#: Types that declare a vocabulary term (a file asserting them is defining the model).
DECLARING_TYPES = {OWL.Class, RDFS.Class, OWL.ObjectProperty, OWL.DatatypeProperty,
                   OWL.AnnotationProperty, RDFS.Datatype, RDF.Property}
#: Predicates that state axioms about vocabulary terms.
AXIOM_PREDICATES = {RDFS.subClassOf, RDFS.subPropertyOf, RDFS.domain, RDFS.range, OWL.equivalentClass,
                    OWL.equivalentProperty, OWL.inverseOf, OWL.disjointWith, OWL.disjointUnionOf,
                    OWL.hasKey, OWL.propertyChainAxiom}
#: rdf:type values that do not make a subject an individual of a model class.
META_TYPES = DECLARING_TYPES | {OWL.NamedIndividual, OWL.Ontology, OWL.Restriction, OWL.AllDifferent,
                                OWL.AllDisjointClasses, OWL.AllDisjointProperties, OWL.Axiom,
                                OWL.FunctionalProperty, OWL.InverseFunctionalProperty,
                                OWL.TransitiveProperty, OWL.SymmetricProperty, OWL.AsymmetricProperty,
                                OWL.ReflexiveProperty, OWL.IrreflexiveProperty, OWL.Thing}
ABSTRACT = KTW.abstractClass

_HAS = re.compile(r"^has([A-Z][A-Za-z0-9]*)_([A-Za-z0-9]+)$")
_HADBY = re.compile(r"^hadBy([A-Z][A-Za-z0-9]*)_([A-Za-z0-9]+)$")


def graph_of(src: Any) -> Any:
    """What the checks query for ``src``: its :class:`kb.io.views.TripleView` when the source
    offers one (cheap to build for big data files), else its rdflib graph."""
    view = getattr(src, "view", None)
    return view() if callable(view) else src.graph


def individual_types(graph: Graph) -> Iterator[tuple[URIRef, URIRef]]:
    """(individual, class) for every rdf:type triple naming a non-built-in class."""
    model_class: dict[Node, bool] = {}
    for s, o in graph.subject_objects(RDF.type):
        ok = model_class.get(o)
        if ok is None:
            ok = model_class[o] = isinstance(o, URIRef) and o not in META_TYPES and not is_w3c(o)
        if ok and isinstance(s, URIRef):
            yield s, o


def declared_terms(graph: Graph) -> dict[URIRef, URIRef]:
    """Vocabulary terms a graph declares: term -> declaring type."""
    out: dict[URIRef, URIRef] = {}
    for t in DECLARING_TYPES:
        for s in graph.subjects(RDF.type, t):
            if isinstance(s, URIRef) and not is_w3c(s):
                out.setdefault(s, t)
    return out


def is_data_graph(graph: Graph) -> bool:
    """A data file holds an individual of a class it does not declare itself."""
    declared = declared_terms(graph)
    return any(c not in declared for _, c in individual_types(graph))


def is_domain_graph(graph: Any) -> bool:
    """A domain file: a data file holding SOAP domain individuals (of a class of kitkb's SOAP
    namespace: ``soap:Action``, ``soap:Predicate``, ``soap:FaultKind`` ...), or one that
    imports the kitting domain (``kitting-domain.ttl``, a ``--domain`` extension)."""
    domain = KITTING_DOMAIN_ONTOLOGY.rstrip("#/")
    if any(str(o).rstrip("#/") == domain for o in graph.objects(None, OWL.imports)):
        return True
    soap = str(SOAP)
    return any(str(c).startswith(soap) for _, c in individual_types(graph))


#: what a domain file may say of a class of objects it declares, besides its declaration and
#: its named superclasses
CLASS_ANNOTATIONS = frozenset({RDFS.label, RDFS.comment, RDFS.seeAlso, RDFS.isDefinedBy})


@dataclass
class DomainClasses:
    """The classes of objects the domain files of one validation declare (a domain extension's
    ``xp:BufferBox a owl:Class ; rdfs:subClassOf ktw:LargeContainer``): ``accepted``, each
    under a class of the model, directly or through another accepted class, join the model for
    every file of the validation (``graph``: their declarations, superclasses and annotations,
    added to the model); ``refused`` (class -> why), the others. ``declared_in``: class -> the
    files declaring it."""

    accepted: dict[URIRef, frozenset[URIRef]] = field(default_factory=dict)
    refused: dict[URIRef, str] = field(default_factory=dict)
    declared_in: dict[URIRef, set[str]] = field(default_factory=dict)
    graph: Graph = field(default_factory=Graph)

    def __bool__(self) -> bool:
        return bool(self.accepted or self.refused)

    def declares(self, src: Any, term: Node) -> bool:
        """Whether ``src`` is a domain file declaring ``term`` as a class of objects."""
        return str(src.path) in self.declared_in.get(term, ())  # type: ignore[arg-type]


def domain_classes(sources: Any, model: OwlModel, namer: Callable[..., str]) -> DomainClasses:
    """The classes that the domain files among ``sources`` (:func:`is_domain_graph`) declare
    beyond ``model``, accepted or refused (:class:`DomainClasses`). A class is accepted when it
    has a named superclass and each is a class of the model or an accepted class; a class of
    the model declared again, or a property, is no class of objects here (the data-file rules
    refuse it). ``namer`` names terms in the refusals (``(term, source) -> name``)."""
    out = DomainClasses()
    supers: dict[URIRef, set[Node]] = {}
    where: dict[URIRef, Any] = {}
    for src in sources:
        g = graph_of(src)
        if not any(True for t in (OWL.Class, RDFS.Class) for _ in g.subjects(RDF.type, t)):
            continue  # the usual case (a state file, the shipped domain): nothing declared
        if not is_domain_graph(g):
            continue
        for term, kind in declared_terms(g).items():
            if kind not in (OWL.Class, RDFS.Class) or term in model.classes or term in model.properties \
                    or term in model.datatypes:
                continue
            out.declared_in.setdefault(term, set()).add(str(src.path))
            supers.setdefault(term, set()).update(g.objects(term, RDFS.subClassOf))
            where.setdefault(term, src)
    changed = True
    while changed:  # accepted from the model down, through the classes the files declare
        changed = False
        for c, ups in supers.items():
            named = {u for u in ups if isinstance(u, URIRef)}
            if c not in out.accepted and named and all(u in model.classes or u in out.accepted for u in named):
                out.accepted[c] = frozenset(named)
                changed = True
    for c in sorted(set(supers) - set(out.accepted)):
        src = where[c]
        named = sorted(u for u in supers[c] if isinstance(u, URIRef))
        if not named:
            why = "it has no named rdfs:subClassOf"
        else:
            unknown = [u for u in named if u not in model.classes and u not in out.accepted]
            parts = []
            for u in unknown:
                if u in supers:
                    parts.append(f"{namer(u, src)} is itself under no class of the model")
                else:
                    parts.append(f"{namer(u, src)} is neither a class of the model nor one a domain file declares")
            why = "rdfs:subClassOf " + ", ".join(namer(u, src) for u in named) + ": " + "; ".join(parts)
        out.refused[c] = why
    for c, ups in out.accepted.items():
        g = graph_of(where[c])
        for kind in (OWL.Class, RDFS.Class):
            if (c, RDF.type, kind) in g:
                out.graph.add((c, RDF.type, kind))
        for u in ups:
            out.graph.add((c, RDFS.subClassOf, u))
        for p in CLASS_ANNOTATIONS | model.annotation_properties:
            for o in g.objects(c, p):
                out.graph.add((c, p, o))
    return out


@dataclass
class RuleContext:
    """What the checks need: the model, the names known, and where things are."""

    model: OwlModel
    individuals: set[URIRef]
    name: Callable[..., str]            # (term, source, at=(s, p, o) written in) -> compact name
    locate: Callable[[Any, Node, Node | None, Node | None], int | None]  # (source, s, p, o) -> line
    out: list[Diagnostic] = field(default_factory=list)
    #: a warning's (file, rule, focus, message) -> the nodes (compact names) whose errors it
    #: follows from: left out of the report when one of them has an error
    follows: dict[tuple[str, str, str, str], frozenset[str]] = field(default_factory=dict)
    #: (file, rule, term): the classes and properties reported at each statement that uses
    #: them (``unknown-class``, ``unknown-property``, ``data-declares-term``); the loader's
    #: warning about NIST 2012 terms leaves them out (one defect, one report)
    reported_terms: set[tuple[str, str, URIRef]] = field(default_factory=set)
    #: subjects typed nowhere (``unknown-individual``) -> their properties; a class's missing
    #: property stated on a misspelt subject follows from it
    untyped: dict[URIRef, set[Node]] = field(default_factory=dict)
    #: objects whose location is unknown, to be sensed (kb.spatial.unlocated): a note each, and
    #: their missing primary location is no min-count error
    unlocated: set[URIRef] = field(default_factory=set)
    #: the classes of objects the validation's domain files declare (accepted ones are in
    #: ``model`` too); a domain file declaring one is not refused it, nor its superclasses
    domain: DomainClasses = field(default_factory=DomainClasses)

    def report(self, source: Any, line: int | None, severity: str, message: str, rule: str,
               focus: Node) -> None:
        """Add one diagnostic about ``focus`` in ``source``."""
        self.out.append(Diagnostic(str(source.path), line, severity, message, rule,  # type: ignore[arg-type]
                                   self.name(focus, source)))


# --- model files ------------------------------------------------------------------------

def check_model_source(ctx: RuleContext, src: Any) -> None:
    """Rules for a file that defines vocabulary."""
    g: Graph = src.graph
    declared = declared_terms(g)
    for p, kind in sorted(declared.items()):
        if kind in (OWL.ObjectProperty, OWL.DatatypeProperty):
            _check_property(ctx, src, p)
        elif kind in (OWL.Class, RDFS.Class):
            _check_class(ctx, src, p)
    _check_used_properties(ctx, src)
    for node, pred, value, message in ctx.model.problems:
        if (node, pred, value) in g:
            ctx.report(src, ctx.locate(src, node, pred, value), "error", message, "malformed-axiom", node)


def _check_property(ctx: RuleContext, src: Any, p: URIRef) -> None:
    info = ctx.model.properties.get(p)
    if info is None:
        return
    line = ctx.locate(src, p, RDF.type, None)
    n = ctx.name(p, src, at=(p, RDF.type, None))
    if not info.domains:
        ctx.report(src, line, "error", f"property {n} has no rdfs:domain", "property-domain", p)
    if not info.ranges:
        ctx.report(src, line, "error", f"property {n} has no rdfs:range", "property-range", p)
    for c in info.domains:
        if c not in ctx.model.classes and c != OWL.Thing:
            ctx.report(src, ctx.locate(src, p, RDFS.domain, c), "error",
                       f"domain of {n} is {ctx.name(c, src)}, which is not a declared class"
                       + _hint(ctx, c, ctx.model.classes, src), "undeclared-class", p)
    for r in info.ranges:
        _check_range(ctx, src, p, info.kind, r)
    _check_naming(ctx, src, p, line)


def _check_range(ctx: RuleContext, src: Any, p: URIRef, kind: str, r: Node) -> None:
    n = ctx.name(p, src, at=(p, RDF.type, None))
    if kind == "object" and r not in ctx.model.classes and r != OWL.Thing:
        ctx.report(src, ctx.locate(src, p, RDFS.range, r), "error",
                   f"range of {n} is {ctx.name(r, src)}, which is not a declared class"
                   + _hint(ctx, r, ctx.model.classes, src), "undeclared-class", p)
    if kind == "datatype" and isinstance(r, URIRef) and r not in ctx.model.datatypes \
            and not str(r).startswith((str(XSD), str(RDF), str(RDFS))):
        ctx.report(src, ctx.locate(src, p, RDFS.range, r), "error",
                   f"range of {n} is {ctx.name(r, src)}, which is not a declared datatype"
                   + _hint(ctx, r, ctx.model.datatypes, src), "undeclared-datatype", p)
    if kind == "datatype" and isinstance(r, URIRef) and str(r).startswith(str(XSD)) \
            and local_name(r) not in _XSD_TYPES:
        ctx.report(src, ctx.locate(src, p, RDFS.range, r), "error",
                   f"range of {n} is {ctx.name(r, src)}, which is not an XSD datatype"
                   + _did(local_name(r), _XSD_TYPES, "xsd:"), "undeclared-datatype", p)


_XSD_TYPES = ["string", "boolean", "decimal", "integer", "double", "float", "date", "time", "dateTime",
              "dateTimeStamp", "duration", "NMTOKEN", "token", "normalizedString", "Name", "NCName",
              "anyURI", "nonNegativeInteger", "positiveInteger", "negativeInteger", "nonPositiveInteger",
              "long", "int", "short", "byte", "unsignedLong", "unsignedInt", "unsignedShort",
              "unsignedByte", "hexBinary", "base64Binary", "language", "gYear", "gYearMonth"]


def _check_naming(ctx: RuleContext, src: Any, p: URIRef, line: int | None) -> None:
    """``hasD_A`` needs domain ``D``; ``hadByA_R`` needs range ``R`` and inverse ``hasR_A``."""
    info = ctx.model.properties[p]
    local, n = written_name(src, p), ctx.name(p, src, at=(p, RDF.type, None))
    m = _HAS.match(local)
    if m and info.domains and m.group(1) not in {local_name(d) for d in info.domains}:
        ctx.report(src, line, "error",
                   f"{n} is named for domain {m.group(1)} but its domain is "
                   f"{', '.join(ctx.name(d, src) for d in info.domains)}", "naming-convention", p)
    m = _HADBY.match(local)
    if not m:
        return
    attr, rng = m.group(1), m.group(2)
    if info.ranges and rng not in {local_name(r) for r in info.ranges}:
        ctx.report(src, line, "error",
                   f"{n} is named for range {rng} but its range is "
                   f"{', '.join(ctx.name(r, src) for r in info.ranges)}", "naming-convention", p)
    if info.inverse_of is not None and local_name(info.inverse_of) != f"has{rng}_{attr}":
        ctx.report(src, line, "error",
                   f"{n} should be the inverse of has{rng}_{attr}, "
                   f"but is the inverse of {ctx.name(info.inverse_of, src)}", "naming-convention", p)


def written_name(src: Any, term: URIRef) -> str:
    """The local name ``src`` writes ``term`` with: NIST 2012's where the file writes kitkb's
    term in that vocabulary under one other name (``hasPartsTray_SerialNumber`` for
    ``hasPartsVessel_SerialNumber``), else the term's own."""
    written = (getattr(src, "written_as", None) or {}).get(term, ())
    return local_name(written[0]) if len(written) == 1 else local_name(term)


def _check_class(ctx: RuleContext, src: Any, c: URIRef) -> None:
    info = ctx.model.classes.get(c)
    if info is None:
        return
    for sup in sorted(info.supers):
        if sup not in ctx.model.classes:
            ctx.report(src, ctx.locate(src, c, RDFS.subClassOf, sup), "error",
                       f"superclass {ctx.name(sup, src)} of {ctx.name(c, src)} is not a declared class"
                       + _hint(ctx, sup, ctx.model.classes, src), "class-hierarchy", c)
    if c in ctx.model.ancestors(c) or any(c in ctx.model.ancestors(s) for s in info.supers):
        ctx.report(src, ctx.locate(src, c, RDF.type, None), "error",
                   f"{ctx.name(c, src)} is its own superclass (a cycle in rdfs:subClassOf)",
                   "class-hierarchy", c)


def _check_used_properties(ctx: RuleContext, src: Any) -> None:
    """Properties named in axioms (restrictions, inverses, keys) must be declared."""
    g: Graph = src.graph
    known = set(ctx.model.properties) | ctx.model.annotation_properties
    used: list[tuple[Node, Node, URIRef]] = []
    for s, o in g.subject_objects(OWL.onProperty):
        used.append((s, OWL.onProperty, o))
    for pred in (OWL.inverseOf, RDFS.subPropertyOf, OWL.equivalentProperty):
        for s, o in g.subject_objects(pred):
            used.append((s, pred, o))
    for s, p, o in used:
        if isinstance(o, URIRef) and o not in known and not is_w3c(o):
            line = ctx.locate(src, s, p, o)
            owner = s if isinstance(s, URIRef) else _owner(g, s)
            ctx.report(src, line, "error",
                       f"property {ctx.name(o, src)} is used but not declared"
                       + _hint(ctx, o, known, src), "undeclared-property", owner or o)


def _owner(g: Graph, node: Node) -> Node | None:
    """The named class a blank restriction hangs off (for naming the focus)."""
    for _ in range(6):
        subjects = list(g.subjects(None, node))
        if not subjects:
            return None
        node = subjects[0]
        if isinstance(node, URIRef):
            return node
    return None


# --- data files -------------------------------------------------------------------------

def pairs_by_predicate(graph: Any, predicates: set[Node]) -> dict[Node, list[tuple[Node, Node]]]:
    """(subject, object) pairs of each of ``predicates``; one pass over a
    :class:`kb.io.views.TripleView` (no predicate index is built for a big data file)."""
    out: dict[Node, list[tuple[Node, Node]]] = {p: [] for p in predicates}
    spo = graph.by_subject() if hasattr(graph, "by_subject") else None
    if spo is None:
        for p in predicates:
            out[p].extend(graph.subject_objects(p))
        return out
    wanted = frozenset(predicates)
    for s, preds in spo.items():
        if wanted.isdisjoint(preds):
            continue
        for p in wanted.intersection(preds):
            pairs = out[p]
            for o in preds[p]:
                pairs.append((s, o))
    return out


def predicate_set(graph: Any) -> set[Node]:
    """The predicates ``graph`` uses."""
    spo = graph.by_subject() if hasattr(graph, "by_subject") else None
    if spo is None:
        return set(graph.predicates())
    return set().union(*spo.values())


def check_data_source(ctx: RuleContext, src: Any) -> None:
    """Rules for a file that holds individuals of an imported model."""
    g = graph_of(src)
    domain = ctx.domain
    for term, kind in sorted(declared_terms(g).items()):
        if domain.declares(src, term):
            if term in domain.refused:
                ctx.report(src, ctx.locate(src, term, RDF.type, kind), "error",
                           f"domain file declares {ctx.name(kind, src)} {ctx.name(term, src, at=(term, RDF.type, kind))} "
                           f"under no class of the model ({domain.refused[term]}): a domain file may declare only a "
                           "class of objects rdfs:subClassOf a class of the model, directly or through another "
                           "class it declares", "data-declares-term", term)
                ctx.reported_terms.add((str(src.path), "data-declares-term", term))
            continue
        ctx.report(src, ctx.locate(src, term, RDF.type, kind), "error",
                   f"data file declares {ctx.name(kind, src)} {ctx.name(term, src, at=(term, RDF.type, kind))}: "
                   "classes and properties belong in a model file", "data-declares-term", term)
        ctx.reported_terms.add((str(src.path), "data-declares-term", term))
    object_props = {p for p, info in ctx.model.properties.items() if info.kind == "object"}
    pairs = pairs_by_predicate(g, set(AXIOM_PREDICATES) | object_props)
    for pred in sorted(AXIOM_PREDICATES):
        for s, o in sorted(pairs[pred]):
            if pred == RDFS.subClassOf and isinstance(o, URIRef) and domain.declares(src, s):
                continue  # a domain class's superclass: accepted, or refused at its declaration
            if isinstance(s, URIRef) and domain.declares(src, s):
                ctx.report(src, ctx.locate(src, s, pred, o), "error",
                           f"domain file states {ctx.name(s, src)} {ctx.name(pred, src)} {_axiom_value(ctx, src, o)}: "
                           "a domain file's class of objects has only named superclasses (rdfs:subClassOf), "
                           "rdfs:label and rdfs:comment; other axioms belong in a model file",
                           "data-declares-term", s)
            elif isinstance(s, URIRef):
                what = "changes" if s in ctx.model.classes or s in ctx.model.properties else "states"
                ctx.report(src, ctx.locate(src, s, pred, o), "error",
                           f"data file {what} {ctx.name(s, src)} {ctx.name(pred, src)} {ctx.name(o, src)}: "
                           "axioms belong in a model file", "data-declares-term", s)
    _check_types(ctx, src)
    _check_predicates(ctx, src)
    _check_references(ctx, src, pairs)
    _check_subjects(ctx, src, g)
    _check_definitions(ctx, src, g)


def _axiom_value(ctx: RuleContext, src: Any, o: Node) -> str:
    """An axiom's value as a message names it: a blank node by what it is (a restriction)."""
    if isinstance(o, URIRef) or isinstance(o, Literal):
        return ctx.name(o, src)
    kind = graph_of(src).value(o, RDF.type)
    return f"an anonymous {ctx.name(kind, src)}" if kind is not None else "an anonymous class expression"


def _check_definitions(ctx: RuleContext, src: Any, g: Any) -> None:
    """A SOAP domain file: every predicate and function definition can be evaluated (the
    executor decides predicates from these formulas; see :mod:`kb.model.definitions`)."""
    if g.value(None, RDF.type, SOAP.Predicate) is None and g.value(None, RDF.type, SOAP.Function) is None:
        return
    union = Graph()
    for t in ctx.model.graph:
        union.add(t)
    for t in g.triples((None, None, None)):
        union.add(t)
    for problem in check_definitions(union, lambda node: (None, ctx.locate(src, node, None, None))):
        ctx.report(src, problem.line, "error", problem.message, "malformed-definition", SOAP.Predicate)


#: the longest name of an individual a world model holds (``kb.world.rows.MAX_IRI``; ``kitkb db
#: load`` refuses a longer one, so validate says so first: ``name-too-long``)
MAX_NAME = 760


def _check_types(ctx: RuleContext, src: Any) -> None:
    by_class: dict[URIRef, list[URIRef]] = {}
    long: dict[URIRef, None] = {}
    for s, c in individual_types(graph_of(src)):
        by_class.setdefault(c, []).append(s)
        if len(s) > MAX_NAME:
            long[s] = None
    for s in sorted(long):
        ctx.report(src, ctx.locate(src, s, RDF.type, None), "error",
                   f"name longer than {MAX_NAME} characters: {s[:40]}...", "name-too-long", s)
    _check_planning_names(ctx, src, by_class)
    true = Literal(True)
    offenders = [(s, c) for c, members in by_class.items()
                 if c not in ctx.model.classes or (c, ABSTRACT, true) in ctx.model.graph for s in members]
    for s, c in sorted(offenders):
        if c not in ctx.model.classes:
            ctx.report(src, ctx.locate(src, s, RDF.type, c), "error",
                       f"{ctx.name(s, src)} is typed {ctx.name(c, src)}, which is not a declared class"
                       + _hint(ctx, c, ctx.model.classes, src), "unknown-class", s)
            ctx.reported_terms.add((str(src.path), "unknown-class", c))
        elif (c, ABSTRACT, Literal(True)) in ctx.model.graph:
            ctx.report(src, ctx.locate(src, s, RDF.type, c), "warning",
                       f"{ctx.name(s, src)} is typed {ctx.name(c, src)}, an abstract class: "
                       "use one of its subclasses", "abstract-class", s)


_PDDL_UNSAFE = re.compile(r"[^A-Za-z0-9_-]")
_NAMED_IN_PLANS = (KTW.SolidObject, KTW.StockKeepingUnit)  # what the planning domain's types are under


def pddl_name(iri: object) -> str:
    """The object name ``kitkb plan`` gives an individual (``kb.planning.state.pddl_name``)."""
    local = str(iri).rsplit("#", 1)[-1].rsplit("/", 1)[-1]
    name = _PDDL_UNSAFE.sub("_", local)
    return name if name[:1].isalpha() else f"o_{name}"


def _check_planning_names(ctx: RuleContext, src: Any, by_class: dict[URIRef, list[URIRef]]) -> None:
    """``name-clash``: two individuals ``kitkb plan`` would give one object name (names are
    compared as PDDL does, case aside; ``part.a`` and ``Part_A`` are both ``part_a``): plan
    refuses the second, in IRI order, at its line. Only individuals of classes the planning
    domain types objects with count (the shipped domain's, read when two names meet)."""
    named: dict[str, list[URIRef]] = {}
    for c, members in by_class.items():
        if c in ctx.model.classes and any(t == c or t in ctx.model.ancestors(c) for t in _NAMED_IN_PLANS):
            for s in members:
                named.setdefault(pddl_name(s).lower(), []).append(s)
    clashes = [sorted(set(members), key=str) for members in named.values() if len(set(members)) > 1]
    if not clashes:
        return
    typed = _planning_types()
    classes: dict[URIRef, list[URIRef]] = {}
    for c, members in by_class.items():
        for s in members:
            classes.setdefault(s, []).append(c)
    for members in clashes:
        objects = [s for s in members if any(t == c or t in ctx.model.ancestors(c) for c in classes[s] for t in typed)]
        for s in objects[1:]:
            ctx.report(src, ctx.locate(src, s, None, None), "error", f"two individuals are both called {pddl_name(s)}",
                       "name-clash", s)


@functools.lru_cache(maxsize=1)
def _planning_types() -> frozenset[URIRef]:
    """The classes the shipped planning domain types objects with (``kb.planning.problem.used_types``)."""
    from kb.model.soap import load_domain  # the SOAP domain: only when two names meet
    domain, _ = load_domain()
    used = {t for a in domain.actions for _n, t in a.params}
    used |= {t for spec in domain.predicates.values() for t in spec.arg_types}
    used |= {t for spec in domain.functions.values() for t in spec.arg_types}
    return frozenset(URIRef(t) for t in used)


def _check_predicates(ctx: RuleContext, src: Any) -> None:
    g = graph_of(src)
    known = set(ctx.model.properties) | ctx.model.annotation_properties
    headers = set(g.subjects(RDF.type, OWL.Ontology))
    for p in sorted(predicate_set(g)):
        if is_w3c(p) or p in known:
            continue
        for s in sorted(set(g.subjects(p, None)) - headers):
            o = next(iter(g.objects(s, p)))
            ctx.report(src, ctx.locate(src, s, p, o), "error",
                       f"unknown property {ctx.name(p, src)} on {ctx.name(s, src)}"
                       + _hint(ctx, p, known, src), "unknown-property", s)
            ctx.reported_terms.add((str(src.path), "unknown-property", p))


def _check_references(ctx: RuleContext, src: Any, pairs: dict[Node, list[tuple[Node, Node]]]) -> None:
    for p, info in sorted(ctx.model.properties.items()):
        if info.kind != "object":
            continue
        unknown = [(s, o) for s, o in pairs[p]
                   if isinstance(o, URIRef) and o not in ctx.individuals and not _punned(ctx, o)]
        for s, o in sorted(unknown):
            ctx.report(src, ctx.locate(src, s, p, o), "error",
                       f"unknown individual {ctx.name(o, src)} (object of {ctx.name(p, src, at=(s, p, o))} on "
                       f"{ctx.name(s, src)})" + _hint(ctx, o, ctx.individuals, src),
                       "unknown-individual", s)
            if ctx.domain.declares(src, o):  # a class of the file refused at its declaration: one defect
                d = ctx.out[-1]
                key = (d.file, d.rule, d.focus, d.message)
                ctx.follows[key] = ctx.follows.get(key, frozenset()) | {ctx.name(o, src)}


def _check_subjects(ctx: RuleContext, src: Any, g: Any) -> None:
    """A named subject of statements that is typed nowhere (no ``rdf:type`` in any file
    loaded) is an unknown individual: closed world, it escapes every shape, and it is most
    often a misspelt name (NIST's ``ObjectPropertyAssertion(:hasPose_Rpy :PartGipperPose
    ...)``, whose pose ``:PartGripperPose`` then lacks its roll-pitch-yaw). Subjects with only
    annotations, the ontology header, model terms and the subjects of axioms (reported as
    ``data-declares-term``) are not individuals."""
    spo = g.by_subject() if hasattr(g, "by_subject") else None
    subjects = set(spo) if spo is not None else set(g.subjects())
    strangers = [s for s in subjects - ctx.individuals if isinstance(s, URIRef) and not is_w3c(s)]
    if not strangers:
        return
    headers = set(g.subjects(RDF.type, OWL.Ontology))
    annotations = ctx.model.annotation_properties
    typed = _typed_anywhere(ctx)
    for s in sorted(strangers):
        if s in headers or s in typed or _punned(ctx, s):
            continue
        preds = set(g.predicates(s, None))
        if preds & AXIOM_PREDICATES or RDF.type in preds:
            continue
        told = sorted(p for p in preds if p not in annotations and not is_w3c(p))
        if not told:
            continue
        ctx.untyped[s] = set(told)
        p = told[0]
        o = next(iter(g.objects(s, p)))
        ctx.report(src, ctx.locate(src, s, None, None), "error",
                   f"unknown individual {ctx.name(s, src)} (subject of {ctx.name(p, src, at=(s, p, o))}, typed "
                   "nowhere)" + _hint(ctx, s, ctx.individuals, src), "unknown-individual", s)


def _typed_anywhere(ctx: RuleContext) -> set[Node]:
    """Subjects with an ``rdf:type`` in the model (the data files' are ``ctx.individuals``)."""
    return set(ctx.model.graph.subjects(RDF.type, None))


def _punned(ctx: RuleContext, term: URIRef) -> bool:
    """A class, property or datatype IRI used as an individual (OWL 2 punning) is declared."""
    m = ctx.model
    return term in m.classes or term in m.properties or term in m.datatypes


# --- suggestions ------------------------------------------------------------------------

def _hint(ctx: RuleContext, wrong: Node, pool: Any, src: Any) -> str:
    """``, did you mean X?`` comparing compact names; same-namespace candidates first."""
    names = {ctx.name(t, src): t for t in pool if isinstance(t, URIRef)}
    want = ctx.name(wrong, src)
    ns = str(wrong)[: len(str(wrong)) - len(local_name(wrong))]
    same = [n for n, t in names.items() if str(t).startswith(ns)]
    best = closest(want, same) or closest(want, names)
    return f", did you mean {best}?" if best else ""


def _did(name: str, pool: list[str], prefix: str) -> str:
    best = closest(name, pool)
    return f", did you mean {prefix}{best}?" if best else ""


__all__ = ["RuleContext", "DomainClasses", "check_model_source", "check_data_source", "is_data_graph",
           "is_domain_graph", "domain_classes", "declared_terms", "individual_types"]
