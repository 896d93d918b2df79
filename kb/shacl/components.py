"""SPARQL-based constraint components (SHACL 6), evaluated by kitkb's engine.

A constraint component is a SHACL instance of ``sh:ConstraintComponent``: its ``rdf:type`` is
``sh:ConstraintComponent`` or a class that reaches it by ``rdfs:subClassOf`` steps, any number
of them (pySHACL 0.40 follows one step and ignores the rest, so such a component used to pass
for "conforms"). It declares parameters (``sh:parameter [ sh:path ex:p ; sh:optional ... ]``)
and validators. A shape that has a value for every mandatory parameter of a component has a
constraint of it for each combination of its parameters' values; the validator is chosen by
the shape's kind (SHACL 6.2.3): ``sh:nodeValidator`` for node shapes, ``sh:propertyValidator``
for property shapes, else ``sh:validator``. A SELECT validator runs as a SPARQL constraint
(:class:`kb.shacl.sparql.SparqlC`) and an ASK validator once per value node
(:class:`kb.shacl.sparql.AskC`), with the parameters' values written in for the pre-bound
variables named after the parameters' local names.

What kitkb cannot evaluate is refused (:class:`kb.shacl.shape.ShapeError`), never skipped: a
component without a validator for the shape's kind, a validator that is neither SELECT nor
ASK (SHACL-JS), a parameter without an IRI ``sh:path`` or whose local name is not a SPARQL
variable name, and a shape that uses the parameter of a node declaring parameters and
validators that is no SHACL instance of ``sh:ConstraintComponent``. A shape that gives a
component's optional parameters without its mandatory ones has, by the specification, no
constraint of it: that is said as a warning on the ``kb.shacl`` logger.
"""

from __future__ import annotations

import itertools
import logging
import re
from dataclasses import dataclass, field

from rdflib import RDF, RDFS, BNode, Graph, Literal, URIRef
from rdflib.term import Node

from kb.core.namespaces import SH
from kb.shacl.shape import Constraint, Shape, ShapeError
from kb.shacl.sparql import AskC, SparqlC, check_validators, sparql_constraint
from kb.shacl.terms import key_of

log = logging.getLogger("kb.shacl")

#: The longest NCName at the end of an IRI (SHACL's "local name"), and SPARQL's VARNAME.
_LOCAL_NAME = re.compile(r"[A-Za-z_\u00C0-\uFFFF][A-Za-z0-9_.\-\u00B7\u00C0-\uFFFF]*$")
_VARNAME = re.compile(r"[A-Za-z0-9_\u00C0-\uFFFF][A-Za-z0-9_\u00B7\u00C0-\uFFFF]*")
#: Names a parameter may not have (SHACL 6.2.1).
_RESERVED = {"this", "shapesGraph", "currentShape", "focusNode", "predicate", "path", "value"}
_VALIDATORS = (SH.validator, SH.nodeValidator, SH.propertyValidator)


def subclasses(g: Graph, cls: Node) -> set[Node]:
    """``cls`` and every class that reaches it by ``rdfs:subClassOf`` steps in ``g``."""
    found = {cls}
    todo = [cls]
    while todo:
        for sub in g.subjects(RDFS.subClassOf, todo.pop()):
            if sub not in found:
                found.add(sub)
                todo.append(sub)
    return found


def instances(g: Graph, cls: Node) -> set[Node]:
    """The SHACL instances of ``cls`` in ``g``: nodes with ``rdf:type/rdfs:subClassOf*`` ``cls``."""
    return {n for c in subclasses(g, cls) for n in g.subjects(RDF.type, c)}


def local_name(iri: Node) -> str | None:
    """SHACL's local name of an IRI (the longest NCName at its end), or None."""
    m = _LOCAL_NAME.search(str(iri))
    return m.group() if m else None


@dataclass
class Parameter:
    path: URIRef
    name: str
    optional: bool


@dataclass
class Component:
    """A constraint component: its parameters and validators."""

    node: Node
    parameters: list[Parameter] = field(default_factory=list)

    def mandatory(self) -> list[Parameter]:
        return [p for p in self.parameters if not p.optional]


def spell(g: Graph, node: Node) -> str:
    """``node`` for a message: an IRI with the shapes graph's prefixes, a blank node as ``[]``."""
    if isinstance(node, URIRef):
        try:
            return node.n3(g.namespace_manager)
        except Exception:  # a prefix rdflib will not use: the IRI in full
            return node.n3()
    return node.n3() if isinstance(node, Literal) else "[]"


def components(g: Graph) -> dict[Node, Component]:
    """The constraint components of ``g`` (SHACL instances of ``sh:ConstraintComponent``);
    :class:`ShapeError` for one with a parameter that no shape could give (no IRI
    ``sh:path``), which would be skipped wherever it is meant."""
    found: dict[Node, Component] = {}
    for node in sorted(instances(g, SH.ConstraintComponent), key=str):
        comp = found[node] = Component(node)
        for p in g.objects(node, SH.parameter):
            paths = list(g.objects(p, SH.path))
            if len(paths) != 1 or not isinstance(paths[0], URIRef):
                raise ShapeError(node, f"constraint component {spell(g, node)} has a parameter without exactly "
                                       "one IRI sh:path (SHACL 6.2.1): no shape can give it", node)
            opt = next(iter(g.objects(p, SH.optional)), None)
            optional = isinstance(opt, Literal) and opt.value is True
            comp.parameters.append(Parameter(paths[0], local_name(paths[0]) or "", optional))
    return found


def pretenders(g: Graph, known: dict[Node, Component]) -> dict[Node, Node]:
    """Parameter path -> a node that declares it with validators but is not a SHACL instance of
    ``sh:ConstraintComponent`` (a misspelt type, a broken ``rdfs:subClassOf`` chain)."""
    found: dict[Node, Node] = {}
    for node in set(g.subjects(SH.parameter, None)):
        if node in known or not any((node, v, None) in g for v in _VALIDATORS):
            continue
        for p in g.objects(node, SH.parameter):
            for path in g.objects(p, SH.path):
                found.setdefault(path, node)
    return found


def parameter_index(comps: dict[Node, Component]) -> dict[Node, list[Component]]:
    """Parameter path -> the components declaring it."""
    out: dict[Node, list[Component]] = {}
    for comp in comps.values():
        for p in comp.parameters:
            out.setdefault(p.path, []).append(comp)
    return out


def constraints(g: Graph, prefixes: dict[str, str], s: Shape, comp: Component,
                rdf11: bool) -> tuple[list[Constraint], str | None]:
    """The constraints of component ``comp`` on shape ``s`` (none when the shape lacks a
    mandatory parameter), or a problem that sends the shape to pySHACL; :class:`ShapeError`
    for what no engine may or kitkb cannot evaluate."""
    for p in comp.parameters:
        if not _VARNAME.fullmatch(p.name) or p.name in _RESERVED:
            raise ShapeError(s.node, f"parameter {spell(g, p.path)} of constraint component {spell(g, comp.node)}: "
                                     f"its local name {p.name!r} cannot name a SPARQL variable (SHACL 6.2.1)",
                             comp.node)
    given = {p.name: sorted(g.objects(s.node, p.path), key=str) for p in comp.parameters}
    missing = [p for p in comp.mandatory() if not given[p.name]]
    if missing and any(given[p.name] for p in comp.mandatory()):
        raise ShapeError(s.node, f"it gives {', '.join(spell(g, p.path) for p in comp.mandatory() if given[p.name])} "
                                 f"of constraint component {spell(g, comp.node)} without its mandatory "
                                 f"{', '.join(spell(g, p.path) for p in missing)}: the component does not apply "
                                 "(SHACL 6.2.3), so it would check nothing", s.node)
    if missing:
        if any(given.values()):
            log.warning("shape %s gives %s of constraint component %s without its mandatory %s: "
                        "by SHACL 6.2.3 the component does not apply", spell(g, s.node),
                        ", ".join(spell(g, p.path) for p in comp.parameters if given[p.name]), spell(g, comp.node),
                        ", ".join(spell(g, p.path) for p in missing))
        return [], None
    validator = _validator(g, s, comp)
    check_validators(g, prefixes, s.node, comp.node)
    names = [p.name for p in comp.parameters if given[p.name]]
    out: list[Constraint] = []
    for combo in itertools.product(*(given[n] for n in names)):
        values = dict(zip(names, combo))
        if any(isinstance(v, BNode) for v in values.values()):
            return [], (f"a blank-node value of a parameter of constraint component {comp.node} "
                        "(kitkb writes parameter values into the query)")
        c, problem = _one(g, prefixes, s, comp, validator, values, rdf11)
        if problem:
            return [], problem
        out.append(c)  # type: ignore[arg-type]
    return out, None


def _validator(g: Graph, s: Shape, comp: Component) -> Node:
    """The validator the specification picks for the kind of ``s`` (SHACL 6.2.3)."""
    kind = "property" if s.path is not None else "node"
    own = SH.propertyValidator if kind == "property" else SH.nodeValidator
    for pred in (own, SH.validator):
        found = sorted(g.objects(comp.node, pred), key=str)
        if found:
            return found[0]
    raise ShapeError(s.node, f"constraint component {spell(g, comp.node)} has no validator for a {kind} shape "
                             f"(sh:{kind}Validator or sh:validator): kitkb cannot evaluate it", comp.node)


def _one(g: Graph, prefixes: dict[str, str], s: Shape, comp: Component, validator: Node,
         values: dict[str, Node], rdf11: bool) -> tuple[SparqlC | None, str | None]:
    selects, asks = list(g.objects(validator, SH.select)), list(g.objects(validator, SH.ask))
    if len(selects) + len(asks) != 1:
        raise ShapeError(s.node, f"the validator of constraint component {spell(g, comp.node)} has "
                                 f"{len(selects)} sh:select and {len(asks)} sh:ask: kitkb evaluates a SPARQL "
                                 "validator with exactly one of them", validator)
    terms = {name: key_of(v, rdf11_strings=rdf11) for name, v in values.items()}
    messages = [_fill(str(m), values) for m in sorted(g.objects(validator, SH.message), key=str)]
    if selects:
        c, problem = sparql_constraint(g, prefixes, s, validator, str(selects[0]), messages, SparqlC, terms)
    else:
        c, problem = sparql_constraint(g, prefixes, s, validator, str(asks[0]), messages, AskC, terms)
    if c is not None:
        c.component = comp.node  # type: ignore[assignment]
    return c, problem


def _fill(message: str, values: dict[str, Node]) -> str:
    """A validator's message with its parameters' ``{$name}`` / ``{?name}`` filled in."""
    for name, v in values.items():
        message = re.sub(r"\{[$?]" + re.escape(name) + r"\}", str(v), message)
    return message
