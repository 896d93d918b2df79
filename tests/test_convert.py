"""kitkb convert: output syntax by extension, round trips, atomic writes."""

from __future__ import annotations

from pathlib import Path

import pytest
from rdflib import URIRef
from rdflib import namespace as rns
from rdflib.compare import isomorphic

from kb.core import namespaces as ns
from kb.cli import main
from kb.io.convert import convert
from kb.core.errors import InputError
from kb.io.loader import load_file

from shared_data import NIST_DIR

NIST_INIT = NIST_DIR / "kittingInstancesInit1.owl"
DATA = Path(__file__).parent / "data" / "loader"


def round_trip(origin: Path, tmp_path: Path) -> tuple[Path, Path]:
    first, xml, back = tmp_path / "first.ttl", tmp_path / "mid.owl", tmp_path / "back.ttl"
    convert(origin, first)
    convert(first, xml)
    convert(xml, back)
    return first, back


@pytest.mark.parametrize("origin", [DATA / "small.ttl", NIST_INIT], ids=["small", "nist-init1"])
def test_turtle_rdfxml_turtle_round_trip_is_isomorphic(origin: Path, tmp_path: Path) -> None:
    if not origin.is_file():
        pytest.skip("NIST corpus not present")
    first, back = round_trip(origin, tmp_path)
    a, b = load_file(first), load_file(back)
    assert load_file(tmp_path / "mid.owl").format == "rdfxml"
    assert isomorphic(a.graph, b.graph)
    # the first conversion kept every statement of the origin, its imports pointed at the
    # shipped kitting model (NIST's file imports the NIST model by a dead file name)
    original, converted = load_file(origin).graph, a.graph
    assert set(converted.objects(None, rns.OWL.imports)) == {URIRef(ns.KITTING_ONTOLOGY)}
    if origin == NIST_INIT:
        for g in (original, converted):
            g.remove((None, rns.OWL.imports, None))
    assert len(converted) == len(original)
    assert isomorphic(converted, original)


def test_nist_conversion_keeps_every_statement(tmp_path: Path) -> None:
    if not NIST_INIT.is_file():
        pytest.skip("NIST corpus not present")
    out = tmp_path / "init.ttl"
    convert(NIST_INIT, out)
    original, converted = load_file(NIST_INIT).graph, load_file(out).graph
    onto = URIRef("http://www.nist.gov/el/ontologies/kittingInstancesInit1.owl")
    # the dead file: import of the NIST model becomes an import of our kitting model
    assert set(converted.objects(onto, rns.OWL.imports)) == {URIRef(ns.KITTING_ONTOLOGY)}
    original.remove((onto, rns.OWL.imports, None))
    converted.remove((onto, rns.OWL.imports, None))
    assert isomorphic(original, converted)
    text = out.read_text()
    assert "@prefix ktw: <https://w3id.org/kitkb/kitting#>" in text


def test_rdfxml_output_declares_the_ontology(tmp_path: Path) -> None:
    out = tmp_path / "small.rdf"
    convert(DATA / "small.ttl", out)
    text = out.read_text()
    assert text.startswith("<?xml")
    assert "owl#Ontology" in text and 'rdf:about="https://w3id.org/kitkb/scenario/small"' in text


def test_ntriples_output(tmp_path: Path) -> None:
    out = tmp_path / "small.nt"
    convert(DATA / "small.ttl", out)
    converted = load_file(out)
    assert converted.format == "ntriples"
    assert isomorphic(converted.graph, load_file(DATA / "small.ttl").graph)


def test_unknown_extension_is_an_input_error(tmp_path: Path) -> None:
    with pytest.raises(InputError, match="unknown output extension"):
        convert(DATA / "small.ttl", tmp_path / "out.json")
    assert not list(tmp_path.iterdir())


def test_failure_keeps_the_existing_output(tmp_path: Path) -> None:
    out = tmp_path / "out.ttl"
    out.write_text("precious\n")
    with pytest.raises(InputError):
        convert(DATA / "bad.ttl", out)
    assert out.read_text() == "precious\n"
    assert [p.name for p in tmp_path.iterdir()] == ["out.ttl"]


def test_cli_convert(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "small.owl"
    assert main(["convert", str(DATA / "small.ttl"), "-o", str(out)]) == 0
    assert load_file(out).format == "rdfxml"
    assert capsys.readouterr().err == f"kitkb: wrote {out} (RDF/XML, 18 statements)\n"
    assert main(["--quiet", "convert", str(DATA / "small.ttl"), "-o", str(out)]) == 0
    assert main(["convert", str(DATA / "small.ttl"), "-o", str(out), "-q"]) == 0
    assert capsys.readouterr() == ("", "")
    assert main(["convert", str(DATA / "bad.ttl"), "-o", str(tmp_path / "x.ttl")]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith(f"{DATA / 'bad.ttl'}:5: error: syntax error") and "\n" not in err
    assert main(["convert", str(DATA / "missing.ttl"), "-o", str(tmp_path / "x.ttl")]) == 2


def test_rdfxml_output_opens_in_an_owl_tool(tmp_path: Path) -> None:
    """py-horned-owl (an OWL API-like reader) reads the RDF/XML as the same ontology."""
    import pyhornedowl

    if not NIST_INIT.is_file():
        pytest.skip("NIST corpus not present")
    out = tmp_path / "init.owl"
    convert(NIST_INIT, out)
    converted = pyhornedowl.open_ontology_from_string(out.read_text(), "owl")
    original_text = "\n".join("" if line.startswith("//") else line for line in NIST_INIT.read_text().split("\n"))
    original = pyhornedowl.open_ontology_from_string(original_text, "ofn")
    assert str(converted.get_iri()) == str(original.get_iri())
    individuals = {str(i) for i in original.get_named_individuals()}
    assert len(individuals) == NIST_INIT.read_text().count("Declaration(NamedIndividual(")  # 138
    assert {str(i) for i in converted.get_named_individuals()} == individuals

    def axiom(text: str) -> str:
        """An axiom as written out, NIST's model namespace mapped to ours, xsd:string literals
        plain (the same literal in RDF 1.1)."""
        for old, new in ns.NAMESPACE_MAP.items():
            text = text.replace(old, new)
        return text.replace("^^<http://www.w3.org/2001/XMLSchema#string>", "")

    # the same axioms, but the dead import of the NIST model, which points at ours
    expected = {axiom(str(a)) for a in original.get_axioms() if not str(a).startswith("Import(")}
    expected.add(f"Import(<{ns.KITTING_ONTOLOGY}>)")
    assert {axiom(str(a)) for a in converted.get_axioms()} == expected
    assert len(converted.get_axioms()) == len(original.get_axioms())


def test_turtle_output_keeps_the_file_prefixes(tmp_path: Path) -> None:
    out = tmp_path / "small.ttl"
    convert(DATA / "small.ttl", out)
    text = out.read_text()
    assert "@prefix : <https://w3id.org/kitkb/scenario/small#> ." in text
    assert ":part_1 a ktw:Part" in text
