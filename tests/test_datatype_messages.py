"""Values of a model's own datatypes (issue 26, point 7).

NIST's xml2owl printer wrote lengths as ``"0.800000"^^:positiveDecimal``, a literal typed with
the model's ``DatatypeDefinition(:positiveDecimal DatatypeRestriction(xsd:decimal
xsd:minExclusive "0"^^xsd:decimal))``. kitkb used to report such a value twice, once as a
``value-range`` "expected minExclusive 0" although 7 > 0: the range check compared a literal of
an unknown datatype with the decimal bound, which rdflib orders by the datatype's IRI (a model in
``http://www.nist.gov/...`` sorts before XSD's namespace, ``https://w3id.org/...`` after it).

Now a literal of a named datatype definition whose base is an XSD type is read as that type
(``kitkbsh:readAs``): inside its bounds it conforms, on an exclusive bound or outside it is one
``value-range`` naming the datatype and its bounds, ill-formed it is one ``datatype``. The same
model and data are written in OWL functional syntax, Turtle and RDF/XML, with decimal, integer,
double and float bases, and checked on both engines.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from rdflib import Graph, Literal, URIRef, XSD

from kb.shacl import validate_graph
from kb.shacl.compiler import READ_AS
from kb.validation import validate
from kb.validation.plain import validate_files
from shared_data import NIST_DIR

KIT = "http://example.org/kit#"

MODEL_OFN = """Prefix(:=<http://example.org/kit#>)
Prefix(owl:=<http://www.w3.org/2002/07/owl#>)
Prefix(rdf:=<http://www.w3.org/1999/02/22-rdf-syntax-ns#>)
Prefix(xsd:=<http://www.w3.org/2001/XMLSchema#>)
Prefix(rdfs:=<http://www.w3.org/2000/01/rdf-schema#>)

Ontology(<http://example.org/kit>
Declaration(Class(:Box))
Declaration(DataProperty(:hasBox_Length))
Declaration(DataProperty(:hasBox_Fill))
Declaration(DataProperty(:hasBox_Count))
Declaration(DataProperty(:hasBox_Ratio))
Declaration(DataProperty(:hasBox_Scale))
Declaration(Datatype(:positiveDecimal))
Declaration(Datatype(:fraction))
Declaration(Datatype(:smallCount))
Declaration(Datatype(:unitDouble))
Declaration(Datatype(:positiveFloat))
DatatypeDefinition(:positiveDecimal
  DatatypeRestriction(xsd:decimal xsd:minExclusive "0"^^xsd:decimal))
DatatypeDefinition(:fraction
  DatatypeRestriction(xsd:decimal xsd:minInclusive "0"^^xsd:decimal xsd:maxInclusive "1"^^xsd:decimal))
DatatypeDefinition(:smallCount
  DatatypeRestriction(xsd:integer xsd:minInclusive "1"^^xsd:integer xsd:maxInclusive "10"^^xsd:integer))
DatatypeDefinition(:unitDouble
  DatatypeRestriction(xsd:double xsd:minInclusive "0.0"^^xsd:double xsd:maxExclusive "1.0"^^xsd:double))
DatatypeDefinition(:positiveFloat
  DatatypeRestriction(xsd:float xsd:minExclusive "0.0"^^xsd:float))
DataPropertyDomain(:hasBox_Length :Box)
DataPropertyRange(:hasBox_Length :positiveDecimal)
DataPropertyDomain(:hasBox_Fill :Box)
DataPropertyRange(:hasBox_Fill :fraction)
DataPropertyDomain(:hasBox_Count :Box)
DataPropertyRange(:hasBox_Count :smallCount)
DataPropertyDomain(:hasBox_Ratio :Box)
DataPropertyRange(:hasBox_Ratio :unitDouble)
DataPropertyDomain(:hasBox_Scale :Box)
DataPropertyRange(:hasBox_Scale :positiveFloat)
)
"""

MODEL_TTL = """@prefix : <http://example.org/kit#> .
@prefix owl: <http://www.w3.org/2002/07/owl#> .
@prefix rdfs: <http://www.w3.org/2000/01/rdf-schema#> .
@prefix xsd: <http://www.w3.org/2001/XMLSchema#> .

<http://example.org/kit> a owl:Ontology .
:Box a owl:Class .
:positiveDecimal a rdfs:Datatype ; owl:equivalentClass [ a rdfs:Datatype ;
    owl:onDatatype xsd:decimal ; owl:withRestrictions ( [ xsd:minExclusive "0"^^xsd:decimal ] ) ] .
:fraction a rdfs:Datatype ; owl:equivalentClass [ a rdfs:Datatype ; owl:onDatatype xsd:decimal ;
    owl:withRestrictions ( [ xsd:minInclusive "0"^^xsd:decimal ] [ xsd:maxInclusive "1"^^xsd:decimal ] ) ] .
:smallCount a rdfs:Datatype ; owl:equivalentClass [ a rdfs:Datatype ; owl:onDatatype xsd:integer ;
    owl:withRestrictions ( [ xsd:minInclusive "1"^^xsd:integer ] [ xsd:maxInclusive "10"^^xsd:integer ] ) ] .
:unitDouble a rdfs:Datatype ; owl:equivalentClass [ a rdfs:Datatype ; owl:onDatatype xsd:double ;
    owl:withRestrictions ( [ xsd:minInclusive "0.0"^^xsd:double ] [ xsd:maxExclusive "1.0"^^xsd:double ] ) ] .
:positiveFloat a rdfs:Datatype ; owl:equivalentClass [ a rdfs:Datatype ; owl:onDatatype xsd:float ;
    owl:withRestrictions ( [ xsd:minExclusive "0.0"^^xsd:float ] ) ] .
:hasBox_Length a owl:DatatypeProperty ; rdfs:domain :Box ; rdfs:range :positiveDecimal .
:hasBox_Fill a owl:DatatypeProperty ; rdfs:domain :Box ; rdfs:range :fraction .
:hasBox_Count a owl:DatatypeProperty ; rdfs:domain :Box ; rdfs:range :smallCount .
:hasBox_Ratio a owl:DatatypeProperty ; rdfs:domain :Box ; rdfs:range :unitDouble .
:hasBox_Scale a owl:DatatypeProperty ; rdfs:domain :Box ; rdfs:range :positiveFloat .
"""

#: (individual, property, value in Turtle/functional syntax): what each individual holds.
VALUES = [
    # inside, or on an inclusive bound, typed with the model's datatype: conforms
    ("b1", "Length", '"7.000000"^^kit:positiveDecimal'), ("b1", "Fill", '"1"^^kit:fraction'),
    ("b1", "Count", '"10"^^kit:smallCount'), ("b1", "Ratio", '"0.0"^^kit:unitDouble'),
    ("b1", "Scale", '"2.5"^^kit:positiveFloat'),
    # on an exclusive bound or outside: one value-range each
    ("b2", "Length", '"0"^^kit:positiveDecimal'), ("b2", "Fill", '"1.5"^^kit:fraction'),
    ("b2", "Count", '"11"^^kit:smallCount'), ("b2", "Ratio", '"1.0"^^kit:unitDouble'),
    ("b2", "Scale", '"-1"^^kit:positiveFloat'),
    # typed with the base type, inside: conforms
    ("b3", "Length", '"7"^^xsd:decimal'), ("b3", "Fill", '"0.5"^^xsd:decimal'),
    ("b3", "Count", '"3"^^xsd:integer'), ("b3", "Ratio", '"0.5"^^xsd:double'),
    ("b3", "Scale", '"1.5"^^xsd:float'),
    # typed with the base type, outside: one value-range each
    ("b4", "Length", '"-1"^^xsd:decimal'), ("b4", "Count", '"0"^^xsd:integer'),
    ("b4", "Ratio", '"1.5"^^xsd:double'),
    # not a value of the datatype at all: one datatype each, never also a value-range
    ("b5", "Length", '"abc"^^kit:positiveDecimal'), ("b5", "Count", '"1.5"^^kit:smallCount'),
    ("b5", "Fill", '"x"^^kit:fraction'),
    ("b6", "Length", '"7"^^xsd:double'), ("b6", "Scale", '"7"^^xsd:string'),
    # another datatype of the model, read as its base: the decimal 7 is > 0, so it conforms
    ("b7", "Length", '"7"^^kit:smallCount'),
]

EXPECTED = {
    (":b2", "value-range", 'kit:hasBox_Length of :b2 is "0"^^kit:positiveDecimal, out of range: '
                           "expected kit:positiveDecimal, an xsd:decimal > 0"),
    (":b2", "value-range", 'kit:hasBox_Fill of :b2 is "1.5"^^kit:fraction, out of range: '
                           "expected kit:fraction, an xsd:decimal >= 0, <= 1"),
    (":b2", "value-range", 'kit:hasBox_Count of :b2 is "11"^^kit:smallCount, out of range: '
                           "expected kit:smallCount, an xsd:integer >= 1, <= 10"),
    (":b2", "value-range", 'kit:hasBox_Ratio of :b2 is "1.0"^^kit:unitDouble, out of range: '
                           "expected kit:unitDouble, an xsd:double >= 0.0, < 1.0"),
    (":b2", "value-range", 'kit:hasBox_Scale of :b2 is "-1"^^kit:positiveFloat, out of range: '
                           "expected kit:positiveFloat, an xsd:float > 0.0"),
    (":b4", "value-range", "kit:hasBox_Length of :b4 is -1, out of range: expected kit:positiveDecimal, "
                           "an xsd:decimal > 0"),
    (":b4", "value-range", "kit:hasBox_Count of :b4 is 0, out of range: expected kit:smallCount, "
                           "an xsd:integer >= 1, <= 10"),
    (":b4", "value-range", "kit:hasBox_Ratio of :b4 is 1.5, out of range: expected kit:unitDouble, "
                           "an xsd:double >= 0.0, < 1.0"),
    (":b5", "datatype", 'kit:hasBox_Length of :b5 is "abc"^^kit:positiveDecimal, expected '
                        "kit:positiveDecimal, an xsd:decimal > 0"),
    (":b5", "datatype", 'kit:hasBox_Count of :b5 is "1.5"^^kit:smallCount, expected kit:smallCount, '
                        "an xsd:integer >= 1, <= 10"),
    (":b5", "datatype", 'kit:hasBox_Fill of :b5 is "x"^^kit:fraction, expected kit:fraction, '
                        "an xsd:decimal >= 0, <= 1"),
    (":b6", "datatype", 'kit:hasBox_Length of :b6 is "7.0"^^xsd:double, expected kit:positiveDecimal, '
                        "an xsd:decimal > 0"),
    (":b6", "datatype", 'kit:hasBox_Scale of :b6 is "7", expected kit:positiveFloat, an xsd:float > 0.0'),
}


def _data_ofn() -> str:
    lines = ["Prefix(:=<http://example.org/data#>)", "Prefix(kit:=<http://example.org/kit#>)",
             "Prefix(xsd:=<http://www.w3.org/2001/XMLSchema#>)", "Ontology(<http://example.org/data>",
             "Import(<http://example.org/kit>)"]
    for b in sorted({b for b, _, _ in VALUES}):
        lines += [f"Declaration(NamedIndividual(:{b}))", f"ClassAssertion(kit:Box :{b})"]
        lines += [f"DataPropertyAssertion(kit:hasBox_{p} :{b} {v})" for bb, p, v in VALUES if bb == b]
    return "\n".join(lines + [")"]) + "\n"


def _data_ttl() -> str:
    lines = ["@prefix : <http://example.org/data#> .", "@prefix kit: <http://example.org/kit#> .",
             "@prefix owl: <http://www.w3.org/2002/07/owl#> .",
             "@prefix xsd: <http://www.w3.org/2001/XMLSchema#> .",
             "<http://example.org/data> a owl:Ontology ; owl:imports <http://example.org/kit> ."]
    for b in sorted({b for b, _, _ in VALUES}):
        lines.append(f":{b} a kit:Box .")
        lines += [f":{b} kit:hasBox_{p} {v} ." for bb, p, v in VALUES if bb == b]
    return "\n".join(lines) + "\n"


def _rdfxml(turtle_text: str) -> str:
    g = Graph().parse(data=turtle_text, format="turtle")
    return g.serialize(format="xml")


def _write(tmp_path: Path, syntax: str) -> list[str]:
    if syntax == "ofn":
        files = {"kit.owl": MODEL_OFN, "data.owl": _data_ofn()}
    elif syntax == "turtle":
        files = {"kit.ttl": MODEL_TTL, "data.ttl": _data_ttl()}
    else:
        files = {"kit.rdf": _rdfxml(MODEL_TTL), "data.rdf": _rdfxml(_data_ttl())}
    for name, text in files.items():
        (tmp_path / name).write_text(text, encoding="utf-8")
    return [str(tmp_path / name) for name in files]


def _found(paths: list[str]) -> set[tuple[str, str, str]]:
    diags = validate(paths).diagnostics
    # RDF/XML as rdflib writes it declares no prefix for the data's namespace: names in full
    full = re.compile(r"<http://example\.org/data#(\w+)>")
    return {(full.sub(r":\1", d.focus), d.rule, full.sub(r":\1", d.message)) for d in diags}


@pytest.mark.parametrize("syntax", ["ofn", "turtle", "rdfxml"])
def test_each_value_once_with_a_true_message(tmp_path: Path, syntax: str) -> None:
    found = _found(_write(tmp_path, syntax))
    assert found == EXPECTED, f"extra: {found - EXPECTED}\nmissing: {EXPECTED - found}"


def test_lines_point_at_the_value(tmp_path: Path) -> None:
    paths = _write(tmp_path, "ofn")
    text = Path(paths[1]).read_text().splitlines()
    for d in validate(paths).diagnostics:
        assert d.line is not None and d.focus.lstrip(":") in text[d.line - 1], d


def test_pyshacl_engine_reads_them_the_same(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    paths = _write(tmp_path, "turtle")
    monkeypatch.setenv("KITKB_SHACL_ENGINE", "pyshacl")
    assert _found(paths) == EXPECTED


def _nist_init(tmp_path: Path, old: str, new: str) -> str:
    text = (NIST_DIR / "kittingInstancesInit1.owl").read_text(encoding="utf-8")
    assert old in text
    out = tmp_path / "kittingInstancesInit1.owl"
    out.write_text(text.replace(old, new, 1), encoding="utf-8")
    return str(out)


def test_nist_positive_decimal_literal_conforms(tmp_path: Path) -> None:
    """The issue's case: NIST's model, a length written "7.000000"^^ktw:positiveDecimal."""
    original = {(d.rule, d.message) for d in validate([str(NIST_DIR / "kittingInstancesInit1.owl")]).diagnostics}
    path = _nist_init(tmp_path, '"7.000000"^^xsd:decimal)', '"7.000000"^^ktw:positiveDecimal)')
    assert {(d.rule, d.message) for d in validate([path]).diagnostics} == original


def test_nist_positive_decimal_out_of_range_once(tmp_path: Path) -> None:
    path = _nist_init(tmp_path, '"0.420000"^^xsd:decimal)', '"0"^^ktw:positiveDecimal)')
    found = [d for d in validate([path]).diagnostics if d.severity == "error"]
    assert [(d.rule, d.message) for d in found] == [
        ("value-range", 'ktw:hasBoxyShape_Length of :shape_changing_station_base is "0"^^ktw:positiveDecimal, '
                        "out of range: expected ktw:positiveDecimal, an xsd:decimal > 0")]


def test_shipped_shapes_declare_the_reading() -> None:
    shapes = Graph().parse(Path(__file__).resolve().parent.parent / "shapes" / "kitting-shapes.ttl")
    ktw = "https://w3id.org/kitkb/kitting#"
    assert set(shapes.subject_objects(READ_AS)) == {(URIRef(ktw + "positiveDecimal"), XSD.decimal)}


PRE = """@prefix sh: <http://www.w3.org/ns/shacl#> .
@prefix xsd: <http://www.w3.org/2001/XMLSchema#> .
@prefix ex: <http://example.org/t#> .
@prefix kitkbsh: <https://w3id.org/kitkb/shapes#> .
"""


def _results(shapes: str, data: str) -> set[tuple[str, object]]:
    results = validate_graph(Graph().parse(data=PRE + data, format="turtle"),
                             Graph().parse(data=PRE + shapes, format="turtle"))
    return {(str(r.component).rsplit("#", 1)[1], r.value) for r in results}


def test_unknown_datatype_is_never_within_a_bound_whatever_its_iri() -> None:
    """SPARQL's < on a literal of an unknown datatype is an error: outside the bound, whether
    the datatype's IRI sorts before XSD's namespace or after it (rdflib's order decided)."""
    shapes = "ex:S sh:targetNode ex:a ; sh:property [ sh:path ex:p ; sh:minExclusive 0 ] ."
    data = 'ex:a ex:p "7"^^<http://a.example/dt> , "7"^^<https://z.example/dt> , 7 .'
    assert _results(shapes, data) == {("MinExclusiveConstraintComponent", Literal("7", datatype=URIRef(d)))
                                      for d in ("http://a.example/dt", "https://z.example/dt")}


def test_read_as_in_plain_shapes() -> None:
    """``kitkbsh:readAs`` in a user's shapes graph: the engine reads the datatype's literals as
    the base type (lexical form and value), and nothing else changes."""
    shapes = ("ex:pd kitkbsh:readAs xsd:decimal .\n"
              "ex:S sh:targetNode ex:a ; sh:property [ sh:path ex:p ; sh:datatype ex:pd ; sh:minExclusive 0 ] .")
    data = 'ex:a ex:p "7"^^ex:pd , "0"^^ex:pd , "abc"^^ex:pd , "7"^^ex:other .'
    pd = URIRef("http://example.org/t#pd")
    assert _results(shapes, data) == {
        ("MinExclusiveConstraintComponent", Literal("0", datatype=pd)),
        ("DatatypeConstraintComponent", Literal("abc", datatype=pd)),
        ("MinExclusiveConstraintComponent", Literal("abc", datatype=pd)),  # SHACL reports both
        ("DatatypeConstraintComponent", Literal("7", datatype=URIRef("http://example.org/t#other"))),
        ("MinExclusiveConstraintComponent", Literal("7", datatype=URIRef("http://example.org/t#other"))),
    }


def test_double_shown_with_its_type_in_a_datatype_message(tmp_path: Path) -> None:
    f = tmp_path / "d.ttl"
    f.write_text(_data_ttl().replace('"7"^^xsd:decimal', '"1e3"^^xsd:double'), encoding="utf-8")
    (tmp_path / "kit.ttl").write_text(MODEL_TTL, encoding="utf-8")
    found = _found([str(tmp_path / "kit.ttl"), str(f)])
    assert (":b3", "datatype", 'kit:hasBox_Length of :b3 is "1000.0"^^xsd:double, expected '
                               "kit:positiveDecimal, an xsd:decimal > 0") in found


def test_plain_shacl_command_reads_nothing_new(tmp_path: Path) -> None:
    """Without a readAs declaration, sh:datatype is SHACL's: the datatype IRI alone."""
    (tmp_path / "s.ttl").write_text(PRE + "ex:S sh:targetNode ex:a ; sh:property [ sh:path ex:p ; "
                                    "sh:datatype ex:pd ] .", encoding="utf-8")
    (tmp_path / "d.ttl").write_text(PRE + 'ex:a ex:p "abc"^^ex:pd .', encoding="utf-8")
    assert validate_files([tmp_path / "d.ttl"], [tmp_path / "s.ttl"]).conforms
