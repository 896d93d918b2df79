"""``kitkb shacl DATA... -s SHAPES...``: plain SHACL, SHACL's report, pySHACL's exit codes.

0 when the data conforms (no result of any severity), 1 when not, 2 for unusable input: a
missing or broken file (at its line), shapes files without shapes, a shape SHACL forbids.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from rdflib import Graph, Literal
from rdflib.namespace import RDF, XSD

from kb.cli import main
from kb.core.namespaces import SH
from kb.validation.plain import validate_files

PRE = """@prefix sh: <http://www.w3.org/ns/shacl#> .
@prefix xsd: <http://www.w3.org/2001/XMLSchema#> .
@prefix ex: <http://example.org/ex#> .
"""
SHAPES = PRE + """
ex:Person a sh:NodeShape ;
    sh:targetClass ex:Person ;
    sh:property [ sh:path ex:age ; sh:datatype xsd:integer ; sh:maxCount 1 ] ;
    sh:property [ sh:path ( ex:knows ex:name ) ; sh:minCount 1 ; sh:severity sh:Warning ] .
"""
DATA = PRE + """
ex:ann a ex:Person ;
    ex:age 31 ;
    ex:knows ex:bob .
ex:bob a ex:Person ;
    ex:name "Bob" ;
    ex:age "forty" ;
    ex:knows ex:ann .
"""


@pytest.fixture
def files(tmp_path: Path) -> tuple[Path, Path]:
    (tmp_path / "data.ttl").write_text(DATA)
    (tmp_path / "shapes.ttl").write_text(SHAPES)
    return tmp_path / "data.ttl", tmp_path / "shapes.ttl"


def test_text_report(files: tuple[Path, Path], capsys: pytest.CaptureFixture[str]) -> None:
    data, shapes = files
    assert main(["shacl", str(data), "-s", str(shapes)]) == 1
    out = capsys.readouterr().out.splitlines()
    # the warning: ann knows bob, who has a name; bob knows ann, who has none
    assert out == [
        f"{data}:8: warning: ex:bob ex:knows/ex:name: Less than 1 values on "
        f"(<http://example.org/ex#knows>/<http://example.org/ex#name>) [MinCount]",
        f'{data}:10: error: ex:bob ex:age = "forty": Value is not Literal with datatype '
        f"http://www.w3.org/2001/XMLSchema#integer [Datatype]",
        "1 data file(s), 1 shapes file(s): does not conform: 2 results (1 violation, 1 warning)",
    ]


def test_turtle_report_is_shacl_s(files: tuple[Path, Path], capsys: pytest.CaptureFixture[str]) -> None:
    data, shapes = files
    assert main(["shacl", str(data), "-s", str(shapes), "--format", "turtle"]) == 1
    report = Graph().parse(data=capsys.readouterr().out, format="turtle")
    (node,) = report.subjects(RDF.type, SH.ValidationReport)
    assert report.value(node, SH.conforms) == Literal(False)
    results = list(report.objects(node, SH.result))
    assert {report.value(r, SH.resultSeverity) for r in results} == {SH.Violation, SH.Warning}
    path = next(report.value(r, SH.resultPath) for r in results if report.value(r, SH.resultSeverity) == SH.Warning)
    assert [str(t) for t in report.items(path)] == ["http://example.org/ex#knows", "http://example.org/ex#name"]


def test_json_and_output_file(files: tuple[Path, Path], tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    data, shapes = files
    assert main(["shacl", str(data), "-s", str(shapes), "--format", "json"]) == 1
    got = json.loads(capsys.readouterr().out)
    assert got["command"] == "shacl" and got["conforms"] is False
    assert got["counts"] == {"violation": 1, "warning": 1, "info": 0}
    assert {(r["line"], r["severity"], r["value"]) for r in got["results"]} == {
        (8, "warning", None), (10, "violation", '"forty"')}
    out = tmp_path / "report.ttl"
    assert main(["shacl", str(data), "-s", str(shapes), "--format", "turtle", "-o", str(out)]) == 1
    assert "wrote" in capsys.readouterr().err
    assert (None, SH.conforms, Literal(False)) in Graph().parse(out)
    assert main(["shacl", str(data), "-s", str(shapes), "-o", str(data)]) == 2  # never over an input
    assert "refusing to write over" in capsys.readouterr().err and data.read_text() == DATA


def test_conforming_data_exits_0(files: tuple[Path, Path], tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    data, shapes = files
    fixed = tmp_path / "fixed.ttl"
    fixed.write_text(DATA.replace('"forty"', "40") + "ex:ann ex:name \"Ann\" .\n")
    assert main(["shacl", str(fixed), "-s", str(shapes)]) == 0
    assert capsys.readouterr().out.strip() == "1 data file(s), 1 shapes file(s): conforms"
    report = validate_files([fixed], [shapes])
    assert report.conforms and report.results == []


def test_a_warning_alone_does_not_conform(files: tuple[Path, Path], tmp_path: Path) -> None:
    data, shapes = files
    fixed = tmp_path / "fixed.ttl"
    fixed.write_text(DATA.replace('"forty"', "40"))
    report = validate_files([fixed], [shapes])
    assert not report.conforms and report.counts() == {"violation": 0, "warning": 1, "info": 0}
    assert main(["shacl", str(fixed), "-s", str(shapes)]) == 1


@pytest.mark.parametrize("case, message", [
    ("missing data", "no such file"),
    ("broken data", "data.ttl:5: error: syntax error"),
    ("no shapes", "no SHACL shapes found"),
    ("forbidden", "shapes.ttl:5: error: shape ex:S: its SPARQL query uses VALUES"),
])
def test_unusable_input_exits_2(files: tuple[Path, Path], capsys: pytest.CaptureFixture[str], case: str,
                                message: str) -> None:
    data, shapes = files
    if case == "missing data":
        data = data.with_name("none.ttl")
    elif case == "broken data":
        data.write_text(PRE + "ex:ann a ex:Person ;\n")
    elif case == "no shapes":
        shapes.write_text(PRE.replace("shacl#", "shacl/") + "ex:S a sh:NodeShape ; sh:targetClass ex:Person .\n")
    else:
        shapes.write_text(PRE + 'ex:S a sh:NodeShape ; sh:targetClass ex:Person ;\n'
                                '  sh:sparql [ sh:select "SELECT $this WHERE { VALUES ?x { 1 } }" ] .\n')
    assert main(["shacl", str(data), "-s", str(shapes)]) == 2
    err = capsys.readouterr().err
    assert message in err and "Traceback" not in err and len(err.splitlines()) == 1
    assert XSD  # the namespace import keeps the prefixes above honest
