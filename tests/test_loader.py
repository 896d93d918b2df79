"""Loader: formats, NIST files, imports, namespace mapping, line numbers, XML safety, errors."""

from __future__ import annotations

import random
import re
from collections import Counter
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from rdflib import BNode, Graph, Literal, URIRef
from rdflib import namespace as rns
from rdflib.collection import Collection

from kb.core import namespaces as ns
from kb.core.errors import InputError
from kb.io.loader import catalog, load, load_file, resolve_import
from kb.core.resources import ontology_path

from shared_data import NIST_DIR

NIST = NIST_DIR
DATA = Path(__file__).parent / "data" / "loader"
NIST_FILES = ["kittingWorkstationClasses.owl", "kittingInstancesInit1.owl", "kittingInstancesGoal1.owl",
              "soapClasses.owl", "soapInstances.owl"]
INIT = "http://www.nist.gov/el/ontologies/kittingInstancesInit1.owl#"
KTW = ns.KTW
OWL, RDF = rns.OWL, rns.RDF

needs_nist = pytest.mark.skipif(not NIST.is_dir(), reason="NIST corpus not present")


def line_containing(path: Path, needle: str, start: int = 1) -> int:
    """1-based number of the first line at or after ``start`` containing ``needle``."""
    for number, line in enumerate(path.read_text(encoding="utf-8").split("\n"), 1):
        if number >= start and needle in line:
            return number
    raise AssertionError(f"{needle!r} not in {path}")


def needs_kitting() -> None:
    if not ontology_path("kitting.ttl").is_file():
        pytest.skip("ontologies/kitting.ttl not written yet")


# --- NIST files --------------------------------------------------------------------------

@needs_nist
@pytest.mark.parametrize("name", NIST_FILES)
def test_nist_files_load_as_functional_syntax(name: str) -> None:
    source = load_file(NIST / name)
    assert source.format == "ofn"
    assert source.ontology_iri == "http://www.nist.gov/el/ontologies/" + name
    # the same triples as rdflib reads from py-horned-owl's RDF/XML of the file (its `//` lines
    # blanked, the NIST model namespace mapped onto ours): nothing lost, added or misnamed
    expected = _rdflib_reading_of_ofn(NIST / name)
    assert len(source.graph) == len(expected)
    assert _triple_shapes(source.graph) == _triple_shapes(expected)
    text_lines = (NIST / name).read_text(encoding="utf-8").split("\n")
    comments = [i + 1 for i, line in enumerate(text_lines) if line.lstrip().startswith("//")]
    if comments:
        assert len(source.warnings) == 1
        warning = source.warnings[0]
        assert warning.severity == "warning" and warning.line == comments[0]
        assert f"{len(comments)} `//` comment lines" in warning.message
    else:
        assert source.warnings == []


def _rdflib_reading_of_ofn(path: Path) -> Graph:
    import pyhornedowl

    text = "\n".join("" if line.lstrip().startswith("//") else line
                     for line in path.read_text(encoding="utf-8").split("\n"))
    xml = pyhornedowl.open_ontology_from_string(text, "ofn").save_to_string("rdf")

    def mapped(term):  # noqa: ANN001, ANN202
        if isinstance(term, URIRef):
            for old, new in ns.NAMESPACE_MAP.items():
                if str(term).startswith(old):
                    return URIRef(new + str(term)[len(old):])
        if isinstance(term, Literal) and term.datatype == rns.XSD.string:
            return Literal(str(term))  # the same literal in RDF 1.1; the loader writes it plain
        return term

    out = Graph()
    for triple in Graph().parse(data=xml, format="xml"):
        out.add(tuple(mapped(t) for t in triple))  # type: ignore[arg-type]
    return out


def _triple_shapes(graph: Graph) -> Counter:
    """The triples with every blank node written ``_`` (an isomorphism check is minutes on
    soapClasses.owl; this one catches a lost, added or changed statement all the same, short
    of a rewiring between blank nodes)."""
    return Counter(tuple("_" if isinstance(t, BNode) else t for t in triple) for triple in graph)


@needs_nist
def test_nist_case_count() -> None:
    assert len(list(NIST.glob("*.owl"))) == len(NIST_FILES)


@needs_nist
def test_nist_namespace_is_mapped_onto_ktw() -> None:
    graph = load_file(NIST / "kittingInstancesInit1.owl").graph
    assert (URIRef(INIT + "kitting_workstation_1"), RDF.type, KTW.KittingWorkstation) in graph
    assert not any(ns.NIST_KTW in str(term) for triple in graph for term in triple)
    point = URIRef(INIT + "part_a_1_point")
    # DataPropertyAssertion(ktw:hasPoint_X :part_a_1_point "0.159000"^^xsd:decimal)
    assert list(graph.objects(point, KTW.hasPoint_X)) == [Literal("0.159000", datatype=rns.XSD.decimal)]


@needs_nist
def test_nist_imports_resolve_to_catalog() -> None:
    needs_kitting()
    kb = load([NIST / "kittingInstancesInit1.owl"])
    assert [s.path.name for s in kb.sources] == ["kittingInstancesInit1.owl", "kitting.ttl"]
    assert kb.sources[0].imports == ["file:/home/chris/Documents/ipmas/Ontology/Kitting/kittingWorkstationClasses.owl"]
    assert not [w for w in kb.warnings if w.rule == "unresolved-import"]
    assert (KTW.Part, RDF.type, OWL.Class) in kb.graph
    # the union of both files, the imported model whole
    assert len(kb.sources[1].graph) == len(Graph().parse(ontology_path("kitting.ttl"), format="turtle"))
    assert set(kb.graph) == set(kb.sources[0].graph) | set(kb.sources[1].graph)


@needs_nist
def test_soap_instances_import_soap_classes_from_the_same_folder() -> None:
    needs_kitting()
    kb = load([NIST / "soapInstances.owl"])
    names = [s.path.name for s in kb.sources]
    assert names == ["soapInstances.owl", "soapClasses.owl", "kitting.ttl"]


@needs_nist
def test_named_file_wins_over_same_folder(tmp_path: Path) -> None:
    copy = tmp_path / "soapClasses.owl"
    copy.write_bytes((NIST / "soapClasses.owl").read_bytes())
    kb = load([NIST / "soapInstances.owl", copy], resolve_imports=True)
    assert [s.path for s in kb.sources][:2] == [NIST / "soapInstances.owl", copy]
    assert sum(1 for s in kb.sources if s.path.name == "soapClasses.owl") == 1


def test_unresolved_imports_warn_with_line() -> None:
    kb = load([DATA / "soapish.ofn"])
    warnings = [w for w in kb.warnings if w.rule == "unresolved-import"]
    path = DATA / "soapish.ofn"
    assert [w.line for w in warnings] == [line_containing(path, "soapClasses.owl"),
                                          line_containing(path, "not-in-the-catalog")]
    assert len(kb.sources) == 1


def test_import_never_reaches_arbitrary_files(tmp_path: Path) -> None:
    elsewhere = tmp_path / "other"
    elsewhere.mkdir()
    (elsewhere / "secret.ttl").write_text("<http://a/s> <http://a/p> <http://a/o> .\n")
    data = tmp_path / "data.ttl"
    data.write_text(f"<http://a/d> a <http://www.w3.org/2002/07/owl#Ontology> ;\n"
                    f"  <http://www.w3.org/2002/07/owl#imports> <{(elsewhere / 'secret.ttl').as_uri()}> .\n")
    kb = load([data])
    assert len(kb.sources) == 1
    assert (URIRef("http://a/s"), None, None) not in kb.graph
    assert [w.line for w in kb.warnings] == [2]


def test_catalog_lists_shipped_ontologies() -> None:
    table = catalog()
    assert table[ns.KITTING_ONTOLOGY] == ontology_path("kitting.ttl")
    assert table[ns.NIST_ONTOLOGY] == ontology_path("kitting.ttl")
    assert table[ns.SOAP_ONTOLOGY].name == "soap.ttl"


def test_nist_model_alias_by_file_name() -> None:
    importer = load_file(DATA / "small.ttl")
    target = resolve_import("file:/x/y/kittingWorkstationClasses.owl", importer, [importer])
    assert target == ontology_path("kitting.ttl")
    assert resolve_import("http://example.org/unknown.owl", importer, [importer]) is None


# --- line numbers ------------------------------------------------------------------------

@needs_nist
def test_line_of_functional_syntax_statements() -> None:
    path = NIST / "kittingInstancesInit1.owl"
    source = load_file(path)
    ws = URIRef(INIT + "kitting_workstation_1")
    assert source.line_of(ws, RDF.type, KTW.KittingWorkstation) == \
        line_containing(path, "ClassAssertion(ktw:KittingWorkstation :kitting_workstation_1)")
    assert source.line_of(ws) == line_containing(path, "Declaration(NamedIndividual(:kitting_workstation_1))")
    rel = URIRef(INIT + "relative_location_in_1")
    assert source.line_of(rel, KTW.hasRelativeLocation_Description) == \
        line_containing(path, "DataPropertyAssertion(ktw:hasRelativeLocation_Description :relative_location_in_1")
    # an object property assertion whose arguments continue on the next line
    start = line_containing(path, "ObjectPropertyAssertion(ktw:hasPhysicalLocation_RefObject")
    assert source.line_of(rel, KTW.hasPhysicalLocation_RefObject, ws) == start
    unit = Literal("degree", datatype=rns.XSD.NMTOKEN)
    assert source.line_of(ws, KTW.hasKittingWorkstation_AngleUnit, unit) == \
        line_containing(path, "DataPropertyAssertion(ktw:hasKittingWorkstation_AngleUnit :kitting_workstation_1")


@needs_nist
@pytest.mark.parametrize("name", NIST_FILES)
def test_every_nist_statement_has_a_line(name: str) -> None:
    source = load_file(NIST / name)
    text = (NIST / name).read_text(encoding="utf-8").split("\n")
    onto = URIRef(source.ontology_iri)

    def local(term: URIRef) -> str:
        return str(term).rsplit("#", 1)[-1].rsplit("/", 1)[-1]

    for s, p, o in source.graph:
        line = source.line_of(s, p, o)
        assert line is not None and 1 <= line <= len(text), (s, p, o)
        if isinstance(s, BNode):
            continue  # located through the axiom of the named node above it
        # the axiom that starts on that line names the statement's subject, property and
        # object (the ontology header's annotations and imports do not repeat its IRI)
        axiom = _axiom_at(text, line)
        if p == OWL.imports:
            names = [str(o)]
        else:
            names = [local(t) for t in ((p, o) if s == onto else (s, p, o))
                     if isinstance(t, URIRef) and not str(t).startswith("http://www.w3.org/")]
        assert all(n in axiom for n in names), (s, p, o, line, axiom)


def _axiom_at(lines: list[str], number: int) -> str:
    """The functional-syntax text from line ``number`` to where its parentheses close."""
    i, text = number - 1, lines[number - 1]
    while text.count("(") > text.count(")") and i + 1 < len(lines):
        i += 1
        text += " " + lines[i]
    return text


@needs_nist
def test_blank_node_of_an_nary_axiom_is_located() -> None:
    path = NIST / "kittingInstancesInit1.owl"
    source = load_file(path)
    text = path.read_text(encoding="utf-8").split("\n")
    # DifferentIndividuals axioms of more than two individuals: their members and their line
    # (one of two individuals becomes an owl:differentFrom statement, no blank node)
    axioms = {}
    for number, line in enumerate(text, 1):
        if line.startswith("DifferentIndividuals("):
            members = frozenset(re.findall(r":(\w+)", _axiom_at(text, number)))
            if len(members) > 2:
                axioms[members] = number
    found = {}
    for node in source.graph.subjects(RDF.type, OWL.AllDifferent):
        members = frozenset(str(m).rsplit("#", 1)[1] for m in Collection(source.graph, source.graph.value(node, OWL.members)))
        found[members] = source.line_of(node)
    assert len(axioms) == 9
    assert found == axioms  # one owl:AllDifferent node per axiom, each at its own axiom's line


@needs_nist
def test_line_of_model_axioms() -> None:
    path = NIST / "kittingWorkstationClasses.owl"
    source = load_file(path)
    assert source.line_of(KTW.BoxVolume, RDF.type, OWL.Class) == line_containing(path, "Declaration(Class(ktw:BoxVolume))")
    assert source.line_of(URIRef(ns.NIST_ONTOLOGY), RDF.type, OWL.Ontology) == line_containing(path, "Ontology(<")


def test_line_of_turtle() -> None:
    path = DATA / "small.ttl"
    source = load_file(path)
    s = URIRef("https://w3id.org/kitkb/scenario/small#")
    part, sku_b = URIRef(s + "part_1"), URIRef(s + "sku_b")
    assert source.line_of(part) == line_containing(path, ":part_1 a ktw:Part")
    assert source.line_of(part, KTW.hasSkuObject_Sku, sku_b) == line_containing(path, ":sku_b .")
    assert source.line_of(part, KTW.hasPart_SerialNumber, Literal("1")) == line_containing(path, "hasPart_SerialNumber")
    point = URIRef(s + "point_1")
    assert source.line_of(point, KTW.hasPoint_Z, Literal("-3", datatype=rns.XSD.integer)) == line_containing(path, "hasPoint_Z")
    assert source.line_of(point, KTW.hasPoint_Y, Literal("2.0", datatype=rns.XSD.decimal)) == line_containing(path, ":point_1 a")
    sku_a = URIRef(s + "sku_a")
    desc = Literal('a part\nthat spans "two" lines', lang="en")
    assert source.line_of(sku_a, KTW.hasSku_Description, desc) == line_containing(path, "hasSku_Description")
    assert source.line_of(sku_a, KTW.hasSku_Weight) == line_containing(path, "hasSku_Weight")
    pose = next(source.graph.objects(URIRef(s + "tray_1"), KTW.hasSolidObject_PrimaryLocation))
    assert isinstance(pose, BNode)
    assert source.line_of(pose, RDF.type, KTW.PoseLocationIn) == line_containing(path, "a ktw:PoseLocationIn")
    assert source.line_of(URIRef(s + "nothing")) is None


def test_line_of_rdfxml_and_owlxml() -> None:
    rdf = load_file(DATA / "small.rdf")
    assert rdf.format == "rdfxml"
    part = URIRef("http://example.org/rdf#part_1")
    assert rdf.line_of(part, RDF.type, KTW.Part) == line_containing(DATA / "small.rdf", '<ktw:Part rdf:about="#part_1">')
    assert rdf.line_of(URIRef("http://example.org/rdf#sku_a"), KTW.hasSku_Weight,
                       Literal("0.2", datatype=rns.XSD.decimal)) == line_containing(DATA / "small.rdf", "<ktw:hasSku_Weight")
    owx = load_file(DATA / "small.owx")
    assert owx.format == "owlxml"
    part = URIRef("http://example.org/owx#part_1")
    assert (part, RDF.type, KTW.Part) in owx.graph
    assert owx.line_of(part, RDF.type, KTW.Part) == line_containing(DATA / "small.owx", "<ClassAssertion>")
    assert owx.line_of(part, RDF.type, OWL.NamedIndividual) == line_containing(DATA / "small.owx", "<Declaration>")
    assert owx.line_of(part, KTW.hasPart_SerialNumber) == line_containing(DATA / "small.owx", "<DataPropertyAssertion>")


def test_source_of_prefers_named_files() -> None:
    needs_kitting()
    kb = load([DATA / "small.ttl"])
    part = URIRef("https://w3id.org/kitkb/scenario/small#part_1")
    source, line = kb.source_of(part, RDF.type, KTW.Part)
    assert source.path == DATA / "small.ttl" and line == line_containing(DATA / "small.ttl", ":part_1 a")
    source, _ = kb.source_of(KTW.Part)
    assert source.path.name == "kitting.ttl"
    assert kb.source_of(URIRef("http://example.org/none")) is None


# --- formats, errors, safety -------------------------------------------------------------

def test_format_detected_by_content(tmp_path: Path) -> None:
    cases = {"a.owl": (DATA / "small.rdf", "rdfxml"), "b.owl": (DATA / "small.owx", "owlxml"),
             "c.owl": (DATA / "soapish.ofn", "ofn"), "d.txt": (DATA / "small.ttl", "turtle")}
    for name, (origin, fmt) in cases.items():
        copy = tmp_path / name
        copy.write_bytes(origin.read_bytes())
        assert load_file(copy).format == fmt
    nt = tmp_path / "e.nt"
    nt.write_text('<http://a/s> <http://a/p> "x" .\n')
    assert load_file(nt).format == "ntriples"


@pytest.mark.parametrize("name, declaration, message", [
    ("xxe.rdf", "<!ENTITY x SYSTEM", "external XML entity 'x' is not allowed (nothing is fetched)"),
    ("xxe.owx", "<!ENTITY x SYSTEM", "external XML entity 'x' is not allowed (nothing is fetched)"),
    ("laughs.rdf", "<!ENTITY g ", "XML entity 'g' expands to 41,000,000 characters: over the limit on a "
                                  "literal's length (10,000,000 characters; set KITKB_MAX_LITERAL to raise it)"),
])
def test_xml_entities_are_refused(name: str, declaration: str, message: str) -> None:
    """Refused at the declaration of the first entity that is not allowed."""
    with pytest.raises(InputError) as info:
        load_file(DATA / name)
    assert info.value.line == line_containing(DATA / name, declaration)
    assert str(info.value) == f"{DATA / name}:{info.value.line}: error: {message}"


def test_quadratic_entity_expansion_is_refused(tmp_path: Path) -> None:
    path = tmp_path / "quadratic.rdf"
    path.write_text('<?xml version="1.0"?>\n<!DOCTYPE r [<!ENTITY a "' + "x" * 9000 + '">]>\n'
                    '<rdf:RDF xmlns:rdf="http://www.w3.org/1999/02/22-rdf-syntax-ns#" xmlns:ex="http://example.org/">'
                    '<rdf:Description rdf:about="http://example.org/a"><ex:p>' + "&a;" * 100_000 +
                    "</ex:p></rdf:Description></rdf:RDF>")
    with pytest.raises(InputError, match="amplification"):
        load_file(path)


def test_internal_entities_still_work() -> None:
    graph = load_file(DATA / "small.rdf").graph
    assert (URIRef("http://example.org/rdf#part_1"), RDF.type, KTW.Part) in graph
    assert "root:" not in graph.serialize(format="nt")


@pytest.mark.parametrize("name, needle", [("bad.ttl", "ex:r ex:c ex:d"), ("bad.ofn", ":A :y :z")])
def test_syntax_errors_name_the_line(name: str, needle: str) -> None:
    with pytest.raises(InputError) as info:
        load_file(DATA / name)
    assert info.value.file == str(DATA / name)
    assert info.value.line == line_containing(DATA / name, needle)
    assert str(info.value).startswith(f"{DATA / name}:{info.value.line}: error: syntax error")


def test_missing_and_unreadable_files(tmp_path: Path) -> None:
    with pytest.raises(InputError, match="no such file"):
        load_file(tmp_path / "missing.ttl")
    with pytest.raises(InputError, match="folder"):
        load_file(tmp_path)
    binary = tmp_path / "b.ttl"
    binary.write_bytes(b"<http://a/s> <http://a/p> \"\xff\xfe\" .\n")
    with pytest.raises(InputError, match="UTF-8") as info:
        load_file(binary)
    assert info.value.line == 1


def _check_loads_or_input_error(path: Path) -> None:
    try:
        load_file(path)
    except InputError as exc:
        assert "\n" not in str(exc)


@settings(max_examples=120, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(data=st.binary(max_size=400), suffix=st.sampled_from([".ttl", ".owl", ".nt", ".rdf", ".owx"]))
def test_fuzz_random_bytes(tmp_path: Path, data: bytes, suffix: str) -> None:
    path = tmp_path / f"fuzz{suffix}"
    path.write_bytes(data)
    _check_loads_or_input_error(path)


_SEEDS = [DATA / "small.ttl", DATA / "small.rdf", DATA / "small.owx", DATA / "soapish.ofn"]


@settings(max_examples=80, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(seed=st.integers(0, 2**32 - 1), which=st.integers(0, len(_SEEDS) - 1), edits=st.integers(1, 6))
def test_fuzz_mutated_files(tmp_path: Path, seed: int, which: int, edits: int) -> None:
    rng = random.Random(seed)
    data = bytearray(_SEEDS[which].read_bytes())
    for _ in range(edits):
        pos = rng.randrange(len(data))
        action = rng.randrange(3)
        if action == 0:
            data[pos] = rng.randrange(256)
        elif action == 1:
            del data[pos: pos + rng.randrange(1, 20)]
        else:
            data[pos:pos] = rng.choice([b"(", b")", b"<", b">", b'"', b"&x;", b"[", b".", b";", b"\n", b"//"])
    path = tmp_path / _SEEDS[which].name
    path.write_bytes(bytes(data))
    _check_loads_or_input_error(path)
