"""The fast paths of ``kitkb validate``: targeted line lookup in big Turtle files, the
dictionary-indexed triple view, and the shapes the fast engine runs without pySHACL."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from rdflib import BNode, Graph, Literal, URIRef
from rdflib.namespace import RDF

from kb.io import loader
from kb.io.loader import load_file
from kb.core.namespaces import KTW
from kb.core.resources import ontology_path, scenario_dirs, shapes_path
from kb.scenario import write_scenario
from kb.scenario.spec import random_spec
from kb.io.views import TripleView, UnionView
from kb.validation.validator import validate


@pytest.fixture(scope="module")
def broken(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A generated workstation in Turtle with a few mistakes appended and edited in."""
    out = tmp_path_factory.mktemp("fast")
    init, _ = write_scenario(out / "scenario", parts=40, kits=1, seed=3)
    text = init.read_text()
    parts = sorted(set(re.findall(r"^(:part_[a-z]+_\d+) a ", text, re.M)))
    spec = random_spec(40, 1, 3)
    assert len(parts) == 40 + spec.spare * len(spec.part_types)  # the kit's and the spares
    text = text.replace("ktw:hasKittingWorkstation_LengthUnit \"meter\"",
                        "ktw:hasKittingWorkstation_LengthUnit \"furlong\"")
    text += "\n# mistakes\n"
    text += f'{parts[0]} ktw:hasPart_Colour "red" .\n'
    text += f'{parts[1]} ktw:hasPart_SerialNumber "dup_1"^^xsd:NMTOKEN .\n'
    text += f"{parts[2]} ktw:hasSkuObject_Sku :no_such_sku .\n"
    text += f"<{_iri(text, parts[3])}> a ktw:NoSuchClass .\n"
    path = out / "broken.ttl"
    path.write_text(text)
    return path


def _iri(text: str, pname: str) -> str:
    base = re.search(r"@prefix : <([^>]*)>", text).group(1)  # type: ignore[union-attr]
    return base + pname[1:]


def _files() -> list[Path]:
    return [p for d in scenario_dirs() for p in sorted(d.glob("*.ttl"))]


@pytest.mark.parametrize("path", _files()[:4], ids=lambda p: f"{p.parent.name}/{p.name}")
def test_targeted_lines_equal_full_index_on_shipped_files(path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    full = load_file(path)
    monkeypatch.setattr(loader.Source, "TARGETED_BYTES", 0)
    targeted = load_file(path)
    subjects = {s for s in full.view().subjects() if isinstance(s, URIRef)}
    targeted.prepare_lines(subjects)
    assert targeted._mode == "targeted"
    checked = 0
    for s, p, o in full.view():
        assert targeted.line_of(s, p, o) == full.line_of(s, p, o), (s, p, o)
        assert targeted.line_of(s) == full.line_of(s)
        checked += 1
    assert checked == len(Graph().parse(path, format="turtle"))  # every statement of the file


def test_targeted_lines_one_subject_at_a_time(broken: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    full = load_file(broken)
    monkeypatch.setattr(loader.Source, "TARGETED_BYTES", 0)
    targeted = load_file(broken)
    for s, p, o in list(full.view())[::7]:
        assert targeted.line_of(s, p, o) == full.line_of(s, p, o), (s, p, o)
    assert targeted.line_of(URIRef("https://example.org/nowhere")) is None


def test_report_is_the_same_with_targeted_lines(broken: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    full = validate([broken])
    monkeypatch.setattr(loader.Source, "TARGETED_BYTES", 0)
    targeted = validate([broken])
    assert [d.format() for d in targeted.diagnostics] == [d.format() for d in full.diagnostics]
    # each mistake of the fixture, at its line (the four appended ones are the last lines)
    text = broken.read_text().splitlines()
    n = len(text)
    furlong = next(i for i, line in enumerate(text, 1) if '"furlong"' in line)
    tray = next(i for i, line in enumerate(text, 1) if line.startswith(":part_a_tray "))
    # the vessel-part-sku finding is at the statement that lists the part (its value)
    listed = next(i for i, line in enumerate(text[tray - 1:], tray) if "part_a_3" in line)
    assert [(d.rule, d.focus, d.line) for d in full.diagnostics] == [
        ("enumeration", ":kitting_workstation_1", furlong),
        ("vessel-part-sku", ":part_a_tray", listed),  # it lists part_a_3, whose SKU is now unknown
        ("unknown-property", ":part_a_1", n - 3),
        ("max-count", ":part_a_2", n - 2),  # a second serial number
        ("max-count", ":part_a_3", n - 1),  # a second SKU
        ("unknown-individual", ":part_a_3", n - 1),
        ("unknown-class", ":part_a_4", n),
    ]


def test_targeted_scan_needs_statement_starts(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    path = tmp_path / "t.ttl"
    path.write_text('@prefix ex: <http://e/> .\n'
                    'ex:a ex:p """text\nex:b ex:p ex:c ."""  .\n'
                    '# ex:b ex:p ex:d .\n'
                    'ex:b ex:q ex:a ;\n'
                    '   ex:r ex:b .\n')
    full = load_file(path)
    monkeypatch.setattr(loader.Source, "TARGETED_BYTES", 0)
    targeted = load_file(path)
    b = URIRef("http://e/b")
    assert targeted.line_of(b) == full.line_of(b) == 5
    assert targeted.line_of(b, URIRef("http://e/r")) == full.line_of(b, URIRef("http://e/r")) == 6


def test_base_directive_falls_back_to_full_index(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    path = tmp_path / "b.ttl"
    path.write_text("@base <http://e/> .\n<a> <p> <b> .\n")
    monkeypatch.setattr(loader.Source, "TARGETED_BYTES", 0)
    src = load_file(path)
    assert src.line_of(URIRef("http://e/a")) == 2
    assert src._mode == "full"


def test_triple_view_answers_like_rdflib() -> None:
    src = load_file(ontology_path("scenarios") / scenario_dirs()[0].name / "init.ttl")
    g, v = src.graph, src.view()
    assert len(v) == len(g) and set(v) == set(g)
    some = list(g)[:40]
    for s, p, o in some:
        assert (s, p, o) in v and (s, None, None) in v and (None, None, o) in v
        assert set(v.objects(s, p)) == set(g.objects(s, p))
        assert set(v.subjects(p, o)) == set(g.subjects(p, o))
        assert set(v.predicates(s, None)) == set(g.predicates(s, None))
        assert set(v.subject_predicates(o)) == set(g.subject_predicates(o))
        assert set(v.predicate_objects(s)) == set(g.predicate_objects(s))
        assert set(v.subject_objects(p)) == set(g.subject_objects(p))
        assert set(v.triples((None, p, None))) == set(g.triples((None, p, None)))
    assert set(v.predicates()) == set(g.predicates())
    assert (URIRef("http://nowhere/x"), None, None) not in v
    u = UnionView([v, Graph()])
    assert set(u.objects(some[0][0], some[0][1])) == set(g.objects(some[0][0], some[0][1]))


def test_triple_view_drops_duplicates() -> None:
    a, p, b = URIRef("http://e/a"), URIRef("http://e/p"), BNode()
    v = TripleView([(a, p, b), (a, p, b), (a, RDF.type, KTW.Part), (a, p, Literal(1))])
    assert len(v) == 3 and len(list(v)) == 3


def test_shipped_shapes_need_no_pyshacl_fallback() -> None:
    from kb.shacl import unsupported_shapes

    shapes = Graph()
    for name in ("kitting-shapes.ttl", "kitting-rules.ttl"):
        shapes.parse(shapes_path(name), format="turtle")
    assert unsupported_shapes(shapes) == {}


def test_pyshacl_results_are_top_level_only() -> None:
    """sh:node violations carry nested sh:detail results, which are not report lines."""
    from kb.shacl import _pyshacl as _run_pyshacl

    shapes = Graph().parse(data="""
        @prefix sh: <http://www.w3.org/ns/shacl#> . @prefix ex: <http://e/> .
        ex:S a sh:NodeShape ; sh:targetClass ex:C ;
            sh:property [ sh:path ex:p ; sh:node ex:T ] .
        ex:T a sh:NodeShape ; sh:property [ sh:path ex:q ; sh:minCount 1 ] .
    """, format="turtle")
    data = Graph().parse(data="""
        @prefix ex: <http://e/> . ex:a a ex:C ; ex:p ex:b . ex:b ex:r 1 .
    """, format="turtle")
    results = _run_pyshacl(data, shapes)
    assert [str(r.focus) for r in results] == ["http://e/a"]
    assert str(results[0].component).endswith("NodeConstraintComponent")


def test_targeted_lines_follow_prefix_changes(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    path = tmp_path / "p.ttl"
    path.write_text("PREFIX ex: <http://e/>\n"
                    "ex:a ex:p ex:b .\n"
                    "@prefix ex: <http://f/> .\n"
                    "ex:a ex:p ex:b .\n"
                    "<http://e/b> ex:q \"x\" . <http://e/a> ex:q 1 .\n"
                    "<http://e/a> ex:q 2 .\n")
    full = load_file(path)
    monkeypatch.setattr(loader.Source, "TARGETED_BYTES", 0)
    targeted = load_file(path)
    for s, p, o in full.view():
        assert targeted.line_of(s, p, o) == full.line_of(s, p, o), (s, p, o)
    assert targeted.line_of(URIRef("http://f/a")) == 4
