"""``kitkb validate --shapes FILE...``: users' shapes beside the shipped ones.

Their results are reported at ``file:line`` like the rest (the shape's sh:message, the rule
named by ``kitkbsh:rule`` or after the component); a shapes file that is broken, holds no
shapes, has no targets or holds a shape SHACL forbids is an input error (exit 2) naming the
file and line, before any data is checked.
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

from kb import cli
from kb.core.errors import InputError
from kb.core.resources import scenario_dirs
from kb.validation import validate

SCENARIO = {d.name: d for d in scenario_dirs()}["small-kit"] / "init.ttl"
HEAD = """@prefix sh: <http://www.w3.org/ns/shacl#> .
@prefix ktw: <https://w3id.org/kitkb/kitting#> .
@prefix kitkbsh: <https://w3id.org/kitkb/shapes#> .
@prefix plant: <https://example.org/plant#> .
"""
PLANT = HEAD + """
plant:SerialNumbers a sh:NodeShape ;
    sh:targetClass ktw:Part ;
    sh:property [
        sh:path ktw:hasPart_SerialNumber ;
        sh:pattern "^[ab]_[1-3]$" ;
        sh:message "serial numbers of this plant are a_1 to b_3" ;
    ] .

plant:TraysOfThree a sh:NodeShape ;
    sh:targetClass ktw:PartsTray ;
    sh:property [
        sh:path ktw:hasPartsVessel_Part ;
        sh:maxCount 3 ;
        kitkbsh:rule "plant-tray-size" ;  # the rule's name in reports (else the component's: max-count)
        sh:severity sh:Warning ;          # a severity is the shape's own: it is not inherited
    ] .
"""


def _write(tmp_path: Path, text: str, name: str = "plant.ttl") -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


def _lines(scenario: Path, pattern: str) -> list[int]:
    return [i for i, line in enumerate(scenario.read_text().splitlines(), 1) if re.search(pattern, line)]


@pytest.fixture(scope="module")
def plant(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return _write(tmp_path_factory.mktemp("plant"), PLANT)


def test_user_shapes_report_at_file_line(plant: Path) -> None:
    report = validate([str(SCENARIO)], extra_shapes=[str(plant)])
    serial = [d for d in report.diagnostics if d.rule == "pattern"]
    # part a_4 is the only serial number outside a_1 .. b_3 in the small kit
    assert [(d.line, d.focus, d.severity) for d in serial] == [
        (line, ":part_a_4", "error") for line in _lines(SCENARIO, r'hasPart_SerialNumber "a_4"')]
    assert serial[0].message == ":part_a_4: serial numbers of this plant are a_1 to b_3"
    trays = [d for d in report.diagnostics if d.rule == "plant-tray-size"]
    assert [(d.focus, d.severity) for d in trays] == [(":part_a_tray", "warning")]
    assert trays[0].line in _lines(SCENARIO, r"hasPartsVessel_Part")
    assert "ktw:hasPartsVessel_Part" in trays[0].message
    assert len(report.diagnostics) == 2  # the shipped shapes find nothing: the file conforms to them


def test_the_command_line(plant: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert cli.main(["validate", str(SCENARIO), "--shapes", str(plant)]) == 1
    out = capsys.readouterr().out.splitlines()
    assert any(re.match(rf"{re.escape(str(SCENARIO))}:\d+: error: :part_a_4: serial numbers", line) for line in out)
    assert out[-1] == "1 file(s): 1 error, 1 warning"
    assert cli.main(["validate", "--format", "json", str(SCENARIO), "--shapes", str(plant), "--ignore", "pattern"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert [d["rule"] for d in data["diagnostics"]] == ["plant-tray-size"]


@pytest.mark.parametrize("text, where, message", [
    (HEAD + "plant:S a sh:NodeShape ;\n  sh:targetClass ktw:Part\n  sh:property [ .\n", 7, "cannot read shapes"),
    (HEAD.replace("shacl#", "shacl") + "plant:S a sh:NodeShape ; sh:targetClass ktw:Part .\n", None, "no SHACL shapes"),
    (HEAD + "plant:S a sh:NodeShape ; sh:property [ sh:path ktw:hasPart_SerialNumber ; sh:minCount 1 ] .\n",
     None, "has a target"),  # it would check nothing
    (HEAD + 'plant:S a sh:NodeShape ; sh:targetClass ktw:Part ;\n  sh:sparql [\n    sh:select """SELECT $this WHERE {'
     ' $this ?p ?o MINUS { $this ?p 1 } }""" ] .\n', 6, "shape plant:S: its SPARQL query uses MINUS"),
])
def test_unusable_shapes_files(tmp_path: Path, capsys: pytest.CaptureFixture[str], text: str,
                               where: int | None, message: str) -> None:
    shapes = _write(tmp_path, text)
    with pytest.raises(InputError, match=message) as caught:
        validate([str(SCENARIO)], extra_shapes=[str(shapes)])
    assert caught.value.file == str(shapes) and caught.value.line == where
    assert cli.main(["validate", str(SCENARIO), "--shapes", str(shapes)]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"{shapes}:{where}: error:" if where else f"{shapes}: error:") and "Traceback" not in err


def test_a_missing_shapes_file(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert cli.main(["validate", str(SCENARIO), "--shapes", str(tmp_path / "none.ttl")]) == 2
    assert "none.ttl: error: cannot read shapes: no such file" in capsys.readouterr().err


def test_user_shapes_are_checked_without_data_files(tmp_path: Path) -> None:
    """A model file alone gets no SHACL run; a broken shapes file is refused all the same."""
    model = {d.name: d for d in scenario_dirs()}["small-kit"].parents[1] / "kitting.ttl"
    with pytest.raises(InputError, match="MINUS"):
        validate([str(model)], extra_shapes=[str(_write(tmp_path, HEAD + (
            'plant:S a sh:NodeShape ; sh:targetClass ktw:Part ; sh:sparql [ sh:select '
            '"SELECT $this WHERE { $this ?p ?o MINUS { $this ?p 1 } }" ] .\n')))])
