"""The parts of kb.model.owl the SQL mapping relies on: told parents, axiom of a restriction."""

from __future__ import annotations

from rdflib import OWL, RDFS, Graph

from kb.model.owl import OwlModel
from generators.sql_model import build_schema

TTL = """
@prefix ktw: <https://w3id.org/kitkb/kitting#> .
@prefix owl: <http://www.w3.org/2002/07/owl#> .
@prefix rdfs: <http://www.w3.org/2000/01/rdf-schema#> .
@prefix xsd: <http://www.w3.org/2001/XMLSchema#> .
<https://w3id.org/kitkb/kitting> a owl:Ontology ; owl:versionInfo "9.9" .
ktw:Alpha a owl:Class ; rdfs:label "Alpha   class" .
ktw:Beta a owl:Class ; rdfs:comment "The  beta\\n class." .
ktw:Gamma a owl:Class ; rdfs:subClassOf ktw:Beta ,
        [ a owl:Restriction ; owl:onProperty ktw:hasGamma_Size ; owl:cardinality 1 ] ;
    owl:equivalentClass [ owl:intersectionOf ( ktw:Alpha
        [ a owl:Restriction ; owl:onProperty ktw:hasGamma_Tag ; owl:maxCardinality 1 ] ) ] .
ktw:hasGamma_Size a owl:DatatypeProperty ; rdfs:domain ktw:Gamma ; rdfs:range ktw:small .
ktw:hasGamma_Tag a owl:DatatypeProperty ; rdfs:domain ktw:Gamma ; rdfs:range xsd:string .
ktw:small a rdfs:Datatype ; owl:equivalentClass [ a rdfs:Datatype ; owl:onDatatype xsd:integer ;
    owl:withRestrictions ( [ xsd:minInclusive 1 ] [ xsd:maxExclusive 10 ] ) ] .
"""


def _graph() -> Graph:
    return Graph().parse(data=TTL, format="turtle")


def test_parents_are_told_superclasses_and_restrictions_know_their_axiom():
    m = OwlModel(_graph())
    ktw = "https://w3id.org/kitkb/kitting#"
    gamma = m.classes[next(c for c in m.classes if str(c) == ktw + "Gamma")]
    assert {str(p) for p in gamma.parents} == {ktw + "Beta"}
    assert {str(s) for s in gamma.supers} == {ktw + "Alpha", ktw + "Beta"}
    via = {str(r.prop).split("#")[1]: r.via for r in gamma.restrictions}
    assert via == {"hasGamma_Size": RDFS.subClassOf, "hasGamma_Tag": OWL.equivalentClass}
    assert [(str(o), v) for o, v in m.ontologies()] == [("https://w3id.org/kitkb/kitting", "9.9")]


def test_schema_uses_told_parent_and_subclass_restrictions_only():
    s = build_schema(_graph())
    gamma = s.table("ktw_gamma")
    assert gamma.parent == "ktw_beta"
    assert [c.name for c in gamma.columns] == ["size"]
    size = gamma.columns[0]
    assert not size.nullable and size.value.kind == "integer"
    assert size.value.checks == (("ge", "1"), ("lt", "10"))
    assert [l.property_iri.split("#")[1] for l in s.links] == ["hasGamma_Tag"]
    assert s.table("ktw_beta").comment == "The beta class."
    assert s.table("ktw_alpha").comment == "Alpha class"
    assert s.ontologies == (("https://w3id.org/kitkb/kitting", "9.9"),)
