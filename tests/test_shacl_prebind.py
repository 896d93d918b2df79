"""Pre-bound variables of SHACL-SPARQL (kb.shacl.prebind) and the engine's SPARQL paths.

The specification defines pre-binding as substitution into the whole query; the engine runs
a query once, grouped by ``?this``, only where that gives the same rows, and refuses what the
specification forbids. These tests pin each piece, and hold the engine to rdflib's pre-binding
(pySHACL's) on queries where grouping would be wrong.
"""

from __future__ import annotations

import logging

import pytest
from rdflib import BNode, Graph, Literal, Namespace, URIRef
from rdflib.namespace import XSD
from rdflib.plugins.sparql import prepareQuery
from rdflib.plugins.sparql.parser import parseQuery

from kb.core.namespaces import SH
from kb.core.resources import shapes_path
from kb.shacl import ShapeError, validate_graph
from kb.shacl.compiler import compile_program
from kb.shacl.engine import prefixes_of
from kb.shacl.fallback import pyshacl_results
from kb.shacl.prebind import Template, forbidden, groupable

T = Namespace("http://example.org/t#")
PRE = """@prefix rdf: <http://www.w3.org/1999/02/22-rdf-syntax-ns#> .
@prefix rdfs: <http://www.w3.org/2000/01/rdf-schema#> .
@prefix xsd: <http://www.w3.org/2001/XMLSchema#> .
@prefix sh: <http://www.w3.org/ns/shacl#> .
@prefix t: <http://example.org/t#> .
"""


def ttl(text: str) -> Graph:
    return Graph().parse(data=PRE + text, format="turtle")


def sparql_shape(query: str, target: str = "sh:targetClass t:C") -> Graph:
    return ttl(f"""t:S a sh:NodeShape ; {target} ;
        sh:sparql [ sh:select \"\"\"PREFIX t: <http://example.org/t#>
        {query}\"\"\" ] .""")


def foci(results) -> set:
    return {r.focus for r in results}


# --------------------------------------------------------------- which queries run grouped


@pytest.mark.parametrize("query, expected", [
    ("SELECT $this ?v WHERE { $this t:p ?v . FILTER (?v > 1) }", True),
    ("SELECT $this WHERE { { $this t:p ?v } UNION { $this t:q ?v } }", True),
    ("SELECT $this WHERE { $this t:p ?v . OPTIONAL { $this t:q ?w } }", True),
    ("SELECT $this WHERE { $this t:p ?v . BIND ($this AS ?that) }", True),
    ("SELECT $this WHERE { FILTER ($this = t:x) }", False),  # only in a FILTER
    ("SELECT $this WHERE { { FILTER (false) } UNION { FILTER ($this = t:x) } }", False),
    ("SELECT $this WHERE { BIND ($this AS ?that) . FILTER (?that = t:x) }", False),
    ("SELECT $this WHERE { { FILTER (bound($this)) } $this t:p ?v }", False),  # inner group
    ("SELECT $this WHERE { { SELECT $this WHERE { $this t:p ?v } } }", False),  # a sub-query
    ("SELECT $this ?v WHERE { $this t:p ?v } GROUP BY $this ?v", False),  # aggregates
    ("SELECT $this WHERE { $this t:p* ?v }", False),  # zero-length: a focus outside the graph
    ("SELECT $this WHERE { $this t:p* ?v . $this t:q ?w }", True),
    ("SELECT ?v WHERE { $this t:p ?v }", False),  # $this not projected
])
def test_groupable(query: str, expected: bool) -> None:
    assert groupable(prepareQuery(query, initNs={"t": str(T)}).algebra) is expected


def test_the_shipped_rules_still_run_grouped() -> None:
    g = Graph().parse(shapes_path("kitting-shapes.ttl"))
    g.parse(shapes_path("kitting-rules.ttl"))
    program = compile_program(g, rdf11_strings=False, prefixes=prefixes_of(g))
    once = {str(c.shape.node).rpartition("#")[2]: c.once for c in program.sparql_constraints()}
    assert once.pop("VesselPartQuantity") is False  # GROUP BY: per focus node, substituted
    assert once and all(once.values()), once


# --------------------------------------------------------------- forbidden forms


@pytest.mark.parametrize("query, reason", [
    ("SELECT $this WHERE { $this ?p ?o MINUS { $this ?p 1 } }", "MINUS"),
    ("SELECT $this WHERE { VALUES ?x { 1 } }", "VALUES"),
    ("SELECT $this WHERE { $this ?p ?o } VALUES ?o { 1 }", "VALUES"),
    ("SELECT $this WHERE { SERVICE <http://example.org/> { ?a ?b ?c } }", "SERVICE"),
    ("SELECT $this WHERE { BIND (1 AS $this) }", "?this"),
    ("SELECT (1 AS ?this) WHERE { }", "?this"),
    ("SELECT $this WHERE { { SELECT * WHERE { ?a ?b ?c } } }", "SELECT *"),
    ("SELECT $this WHERE { { SELECT ?a WHERE { ?a ?b ?c } } }", "?this"),
])
def test_forbidden(query: str, reason: str) -> None:
    found = forbidden(parseQuery(query))
    assert found and reason in found


def test_allowed() -> None:
    assert forbidden(parseQuery("SELECT $this ?v WHERE { { SELECT $this ?v WHERE { $this ?p ?v } } }")) is None
    assert forbidden(parseQuery("SELECT $this (?o AS ?value) WHERE { $this ?p ?o }")) is None


def test_a_forbidden_query_is_a_shape_error_naming_the_shape() -> None:
    shapes = sparql_shape("SELECT $this WHERE { $this t:p ?v MINUS { $this t:q ?v } }")
    with pytest.raises(ShapeError) as caught:
        validate_graph(ttl("t:x a t:C ; t:p 1 ."), shapes)
    assert caught.value.shape == T.S and "MINUS" in caught.value.what


def test_a_query_that_does_not_parse_is_a_shape_error() -> None:
    with pytest.raises(ShapeError, match="does not parse"):
        validate_graph(ttl("t:x a t:C ."), sparql_shape("SELECT $this WHERE { $this t:p }"))


# --------------------------------------------------------------- substitution


def test_template_fills_every_place() -> None:
    text = ("SELECT DISTINCT $this ?v WHERE { $this t:p ?v . FILTER (bound($this) && ?v != $this) "
            "{ SELECT $this WHERE { ?this t:q ?w } } } GROUP BY $this ?v ORDER BY ?this")
    filled = Template(text, ("this",)).fill({"this": "<urn:x>"})
    assert filled == ("SELECT DISTINCT (<urn:x> AS ?this) ?v WHERE { <urn:x> t:p ?v . FILTER ((true) && ?v != <urn:x>) "
                      "{ SELECT (<urn:x> AS ?kitkb_prebound_this_1) WHERE { <urn:x> t:q ?w } } } "
                      "GROUP BY (<urn:x>) ?v ORDER BY (<urn:x>)")


def test_template_leaves_strings_iris_and_comments_alone() -> None:
    text = 'SELECT $this WHERE { $this t:p "$this ?this" . # ?this\n FILTER (?x < <urn:a?this>) }'
    assert Template(text, ("this",)).fill({"this": '"lit"@en'}) == \
        'SELECT ("lit"@en AS ?this) WHERE { "lit"@en t:p "$this ?this" . # ?this\n FILTER (?x < <urn:a?this>) }'


B = "[]"  # the blank node of the data below, as the expected sets name it


@pytest.mark.parametrize("query, expected, rdflib_agrees", [
    ("SELECT $this WHERE { FILTER ($this = t:x) }", {"x"}, True),
    ("SELECT $this WHERE { { FILTER (false) } UNION { FILTER ($this = t:x) } }", {"x"}, False),
    ("SELECT $this WHERE { { { FILTER ($this = t:x) } FILTER bound($this) } FILTER (true) }", {"x"}, True),
    ("SELECT $this WHERE { BIND ($this AS ?that) . FILTER (?that = t:x) }", {"x"}, True),
    ("SELECT $this WHERE { { FILTER (bound($this)) } $this t:p ?v . FILTER (bound($this)) }", {"x", "y", B}, True),
    ("SELECT $this WHERE { { SELECT $this WHERE { FILTER ($this = t:x) } } }", {"x"}, True),
    ("SELECT $this WHERE { FILTER NOT EXISTS { $this t:q ?w } }", {"x", B}, True),
    ("SELECT $this ?v WHERE { $this t:p ?v . OPTIONAL { $this t:q ?w } FILTER (!bound(?w)) }", {"x", B}, True),
    ("SELECT $this WHERE { { SELECT $this WHERE { $this t:p ?v FILTER (?v > 3) } } }", {B}, True),
    ("SELECT $this WHERE { { FILTER (isBlank($this)) } }", {B}, True),
    ("SELECT $this WHERE { BIND ($this AS ?that) FILTER (isBlank(?that)) }", {B}, True),
])
def test_pre_binding_is_substitution(query: str, expected: set[str], rdflib_agrees: bool) -> None:
    """The focus nodes with rows when $this is replaced by each (IRIs and a blank node); rdflib's
    pre-binding (pySHACL's, and kitkb's ``sparql="rdflib"``) departs from it on a UNION of
    FILTER-only groups, where it keeps the binding of a group whose FILTER fails."""
    data = ttl("t:x a t:C ; t:p 1 . t:y a t:C ; t:p 2 ; t:q 3 . [] a t:C ; t:p 4 .")
    shapes = sparql_shape(query)

    def names(results) -> set[str]:
        return {B if isinstance(f, BNode) else str(f).rpartition("#")[2] for f in foci(results)}

    assert names(validate_graph(data, shapes)) == expected
    assert (names(validate_graph(data, shapes, sparql="rdflib")) == expected) is rdflib_agrees


def test_a_literal_focus_node_is_substituted() -> None:
    shapes = sparql_shape('SELECT $this WHERE { FILTER (isLiteral($this) && STRLEN($this) > 3) }',
                          target='sh:targetNode "long", "abc"')
    assert foci(validate_graph(ttl("t:x t:p 1 ."), shapes)) == {Literal("long")}


def test_shapes_graph_and_current_shape() -> None:
    shapes = sparql_shape("SELECT $this WHERE { GRAPH $shapesGraph { $currentShape t:flag true } }",
                          target="sh:targetNode t:x ; t:flag true")
    assert foci(validate_graph(ttl("t:x t:p 1 ."), shapes)) == {T.x}
    unflagged = sparql_shape("SELECT $this WHERE { GRAPH $shapesGraph { $currentShape t:flag true } }",
                             target="sh:targetNode t:x")
    assert foci(validate_graph(ttl("t:x t:p 1 ."), unflagged)) == set()


# --------------------------------------------------------------- around SPARQL


def test_an_ill_typed_boolean_stays_ill_typed_on_rdflib_graphs() -> None:
    """rdflib reads "none"^^xsd:boolean as "false" (marked ill-typed): still not an xsd:boolean."""
    logging.getLogger("rdflib.term").setLevel(logging.CRITICAL)
    with pytest.warns(UserWarning):
        data = ttl('t:x t:p "none"^^xsd:boolean . t:y t:p "false"^^xsd:boolean .')
    shapes = ttl("t:S a sh:NodeShape ; sh:targetSubjectsOf t:p ; sh:property [ sh:path t:p ; sh:datatype xsd:boolean ] .")
    results = validate_graph(data, shapes)
    assert foci(results) == {T.x}
    assert results[0].value == Literal("false", datatype=XSD.boolean)  # as rdflib spells the value


def test_complex_paths_run_natively() -> None:
    shapes = ttl("""t:S a sh:NodeShape ; sh:targetNode t:a ;
        sh:property [ sh:path ( t:p [ sh:zeroOrMorePath t:q ] [ sh:inversePath t:r ] ) ; sh:minCount 2 ] ;
        sh:property [ sh:path [ sh:alternativePath ( t:p [ sh:oneOrMorePath t:q ] ) ] ; sh:class t:C ] .""")
    data = ttl("t:a t:p t:b . t:b t:q t:c . t:z t:r t:c . t:b a t:C .")
    compiled = compile_program(shapes, rdf11_strings=False, prefixes=prefixes_of(shapes))
    assert compiled.unsupported == {}
    rows = {(r.component.rpartition("#")[2], r.value) for r in validate_graph(data, shapes)}
    assert rows == {("MinCountConstraintComponent", None)}  # only t:z: t:b has no t:r from anything
    data.add((T.y, T.r, T.b))
    assert validate_graph(data, shapes) == []


def test_pyshacl_refusing_a_shape_is_a_shape_error() -> None:
    """$currentShape in a blank-node shape goes to pySHACL, which cannot pre-bind it."""
    shapes = ttl("""[] a sh:NodeShape ; sh:targetNode t:x ;
        sh:sparql [ sh:select "SELECT $this WHERE { GRAPH $shapesGraph { $currentShape ?p ?o } }" ] .""")
    only = [s for s in shapes.subjects(SH.targetNode, None)]
    with pytest.raises(ShapeError, match="pySHACL"):
        pyshacl_results(ttl("t:x t:p 1 ."), shapes, None, only, advanced=False)
    with pytest.raises(ShapeError, match="pySHACL"):
        validate_graph(ttl("t:x t:p 1 ."), shapes)


def test_custom_component_typed_with_a_subclass_goes_to_pyshacl() -> None:
    shapes = ttl("""t:Component rdfs:subClassOf sh:ConstraintComponent .
        t:Starts a t:Component ; sh:parameter [ sh:path t:prefix ] ;
            sh:validator [ a sh:SPARQLAskValidator ; sh:ask "ASK { FILTER (STRSTARTS(STR($value), $prefix)) }" ] .
        t:S a sh:NodeShape ; sh:targetNode "ab", "xy" ; t:prefix "a" .""")
    results = validate_graph(ttl("t:x t:p 1 ."), shapes)
    assert {(r.focus, r.component) for r in results} == {(Literal("xy"), T.Starts)}


def test_a_forbidden_validator_of_a_custom_component_is_refused() -> None:
    shapes = ttl("""t:Lang a sh:ConstraintComponent ; sh:parameter [ sh:path t:lang ] ;
            sh:validator [ a sh:SPARQLAskValidator ; sh:ask "ASK { BIND (true AS ?value) }" ] .
        t:S a sh:NodeShape ; sh:targetNode t:x ; t:lang "en" .""")
    with pytest.raises(ShapeError, match=r"\?value"):
        validate_graph(ttl("t:x t:p 1 ."), shapes)


def test_blank_focus_nodes_of_a_substituted_query() -> None:
    data = ttl("[] a t:C ; t:p 5 . [] a t:C ; t:p 1 .")
    shapes = sparql_shape("SELECT $this WHERE { { SELECT $this WHERE { $this t:p ?v FILTER (?v > 3) } } }")
    results = validate_graph(data, shapes)
    assert len(results) == 1 and isinstance(results[0].focus, BNode)
    assert {o for o in data.objects(results[0].focus, T.p)} == {Literal(5)}
    assert URIRef  # noqa: the namespace import stays used by readers of this file
