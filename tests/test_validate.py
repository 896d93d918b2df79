"""Tests of ``kitkb validate``: rules, report format, exit codes, shipped and NIST files."""

from __future__ import annotations

import io
import json
import os
import re
from pathlib import Path

import pytest
from rdflib import Graph

from kb import cli
from kb.core.errors import InputError
from kb.validation.suggest import closest, did_you_mean
from kb.cli.output import Output
from kb.cli.validation import validate as validate_command
from kb.validation import default_files, validate
from kb.validation.rules import is_data_graph

from shared_data import NIST_DIR

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "tests" / "data" / "validate"
ONTOLOGIES = ROOT / "ontologies"
SCENARIO = ONTOLOGIES / "scenarios" / "small-kit" / "init.ttl"
NIST = NIST_DIR

needs_nist = pytest.mark.skipif(not (NIST / "kittingInstancesInit1.owl").exists(), reason="NIST files not present")


def _found(paths: list[Path]) -> set[tuple[str, str]]:
    return {(d.rule, d.focus) for d in validate([str(p) for p in paths]).diagnostics}


# --- did you mean -------------------------------------------------------------------------

def test_suggestions() -> None:
    assert closest("hasPoint_x", ["hasPoint_X", "hasPoint_Y", "hasVector_I"]) == "hasPoint_X"
    assert closest(":part_a_l", [":part_a_1", ":part_a_4", ":part_b_1"]) == ":part_a_1"
    assert closest("ktw:Pont", ["ktw:Point", "ktw:Part", "ktw:Robot"]) == "ktw:Point"
    assert closest("zzzz", ["ktw:Point"]) is None
    assert did_you_mean("Pont", ["Point"]) == ", did you mean Point?"
    assert did_you_mean("Pont", []) == ""


# --- model files ----------------------------------------------------------------------------

def test_model_rules_on_a_broken_model() -> None:
    report = validate([str(DATA / "bad-model.ttl")])
    assert {(d.rule, d.focus, d.line) for d in report.diagnostics} == {
        ("class-hierarchy", ":Gadget", 12),            # superclass :Widgte is not declared
        ("undeclared-property", ":Sprocket", 15),      # restriction on :hasSprocket_Teth (typo)
        ("property-range", ":hasWidget_Colour", 22),   # no rdfs:range
        ("naming-convention", ":hasGadget_Size", 25),  # hasGadget_ but domain :Widget
        ("undeclared-datatype", ":hasGadget_Weight", 31),  # xsd:decmal
        ("naming-convention", ":hadByPart_Gadget", 37),    # range and inverse do not fit the name
    }
    messages = "\n".join(d.message for d in report.diagnostics)
    assert "did you mean :Widget?" in messages
    assert "did you mean :hasSprocket_Teeth?" in messages
    assert "did you mean xsd:decimal?" in messages
    assert "should be the inverse of hasGadget_Part" in messages


def test_files_are_told_apart() -> None:
    assert not is_data_graph(Graph().parse(ONTOLOGIES / "kitting.ttl"))
    assert is_data_graph(Graph().parse(SCENARIO))
    assert not is_data_graph(Graph().parse(DATA / "bad-model.ttl"))


# --- shipped files --------------------------------------------------------------------------

@pytest.mark.parametrize("path", default_files(), ids=lambda p: f"{Path(p).parent.name}/{Path(p).name}")
def test_shipped_file_validates_clean(path: str) -> None:
    report = validate([path])
    assert report.diagnostics == [], "\n".join(d.format() for d in report.diagnostics)


def test_default_files_cover_model_and_scenarios() -> None:
    files = [Path(p).relative_to(ONTOLOGIES).as_posix() for p in default_files()]
    assert files == ["kitting-domain.ttl", "kitting.ttl", "soap.ttl"] + [
        f"scenarios/{name}/{state}.ttl" for name in ("kit-a2b3c3d1e1", "small-kit", "two-designs")
        for state in ("goal", "init")]


# --- NIST files -----------------------------------------------------------------------------

@needs_nist
@pytest.mark.parametrize("names", [
    ["kittingWorkstationClasses.owl"],
    ["kittingInstancesInit1.owl"],
    ["kittingInstancesGoal1.owl"],
    ["kittingInstancesInit1.owl", "kittingInstancesGoal1.owl"],
    ["soapClasses.owl"],
])
def test_nist_file_has_no_violations(names: list[str]) -> None:
    report = validate([str(NIST / n) for n in names])
    assert report.conforms, "\n".join(d.format() for d in report.errors)
    # the only warning: the `//` comment lines, which functional syntax does not allow (one
    # warning per file that has them, at the first of them)
    expected = []
    for n in names:
        lines = (NIST / n).read_text(encoding="utf-8").split("\n")
        comments = [i for i, line in enumerate(lines, 1) if line.lstrip().startswith("//")]
        if comments:
            expected.append(("ofn-comment", str(NIST / n), comments[0], "warning"))
    assert sorted((d.rule, d.file, d.line, d.severity) for d in report.diagnostics) == sorted(expected)


@needs_nist
def test_nist_soap_instances_report_only_real_defects() -> None:
    """soapInstances.owl against soapClasses.owl (shapes generated from NIST's SOAP model)."""
    report = validate([str(NIST / "soapInstances.owl")])
    assert {(d.rule, d.focus) for d in report.errors} == {
        # the group element for "kit on work table" points at an OnTopWithContact relation,
        # while soapClasses gives hasG1_WorkTableHasKit_StateRelation the range UnderWithContact
        ("class", ":G1_workTable-has-objectOnTable-kit"),
        # hasEffectPlaceKitTray_KitTrayHasRefObjectWorkTable: range KitHasRefObjectWorkTable (kit),
        # value a KTrayHasRefObjectWTable (kit tray) -- the range was copied from the kit property
        ("class", ":effect-PlaceKitTray"),
        # hasPreconditionCreateKit_KitTrayHasRefObjectWorkTable: the same kit/kit-tray range mix-up
        ("class", ":precondition-CreateKit"),
        # hasEffectCreateKit_NotWorkTableHasObjectOnTableKitTray: range NotWorkTableHasKit,
        # value a NotWorkTableHasKitTray
        ("class", ":effect-CreateKit"),
        # hasIncreasePlacePart_Function: range QuantityOfPartsInKit, value a
        # CurrentQuantityOfPartsInKit, which soapClasses makes a Function but not a QuantityOfPartsInKit
        ("class", ":increase-PlacePart"),
        # the holders are placed with no shape, which stops `kitkb predicates` (issue 26, point 5)
        ("no-shape", ":part_gripper_holder"), ("no-shape", ":tray_gripper_holder"),
        # the kit designs' slots put their parts outside the 0.5 x 0.3 m kit tray, by 3.5 to
        # 39 cm (a2b1c1's first slot at y = 0.3, a2b2c1's at y = +-0.145 to +-0.215)
        *(("slot-outside-tray", f":part_ref_and_pose_kit_{slot}") for slot in (
            "a2b1c1_a_1", "a2b1c1_a_2", "a2b1c1_b_1", "a2b1c1_c_1",
            "a2b2c1_a_1", "a2b2c1_a_2", "a2b2c1_b_1", "a2b2c1_b_2")),
    }
    lines = {d.focus: d.line for d in report.errors}
    assert lines[":G1_workTable-has-objectOnTable-kit"] == 4951
    assert all(d.file == str(NIST / "soapInstances.owl") for d in report.errors)


# --- report and command ----------------------------------------------------------------------

def _mutated(tmp_path: Path) -> Path:
    text = SCENARIO.read_text(encoding="utf-8").replace("ktw:hasPoint_X", "ktw:hasPoint_x", 1)
    target = tmp_path / "init.ttl"
    target.write_text(text, encoding="utf-8")
    return target


def test_text_report_lines_sorted(tmp_path: Path) -> None:
    """Every point misspelt: one line per point, in file order, then the summary."""
    text = SCENARIO.read_text(encoding="utf-8").replace("ktw:hasPoint_X", "ktw:hasPoint_x")
    target = tmp_path / "init.ttl"
    target.write_text(text, encoding="utf-8")
    where = [n for n, ln in enumerate(text.splitlines(), 1) if "ktw:hasPoint_x" in ln]
    subjects = sorted(set(re.findall(r"^(:\w+) a owl:NamedIndividual, ktw:Point\b", text, re.M)))
    assert len(where) == len(subjects) == 29  # the points of small-kit/init.ttl
    out = io.StringIO()
    assert validate_command([str(target)], "text", Output(stdout=out)) == 1
    lines = out.getvalue().splitlines()
    assert lines[-1] == f"1 file(s): {len(where)} errors"
    body = lines[:-1]
    assert [int(ln.split(":")[1]) for ln in body] == where  # sorted: file order
    assert sorted(re.sub(r"^\S+:\d+: ", "", ln) for ln in body) == sorted(
        f"error: unknown property ktw:hasPoint_x on {s}, did you mean ktw:hasPoint_X? [unknown-property]"
        for s in subjects)
    assert all(ln.startswith(f"{target}:") for ln in body)


def test_json_report(tmp_path: Path) -> None:
    out = io.StringIO()
    target = _mutated(tmp_path)
    assert validate_command([str(target)], "json", Output(stdout=out)) == 1
    report = json.loads(out.getvalue())
    assert set(report) == {"conforms", "files", "counts", "diagnostics"}
    assert report["conforms"] is False and report["files"] == [str(target)]
    line = next(n for n, ln in enumerate(target.read_text(encoding="utf-8").splitlines(), 1) if "hasPoint_x" in ln)
    assert report["counts"] == {"error": 1, "warning": 0, "info": 0}
    assert report["diagnostics"] == [{
        "file": str(target), "line": line, "severity": "error", "rule": "unknown-property",
        "focus": ":kitting_workstation_1_point",
        "message": "unknown property ktw:hasPoint_x on :kitting_workstation_1_point, did you mean ktw:hasPoint_X?"}]


def test_json_report_of_conforming_files() -> None:
    out = io.StringIO()
    assert validate_command([str(SCENARIO)], "json", Output(stdout=out)) == 0
    report = json.loads(out.getvalue())
    assert report == {"conforms": True, "files": [str(SCENARIO)],
                      "counts": {"error": 0, "warning": 0, "info": 0}, "diagnostics": []}


def test_exit_codes(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert cli.main(["validate", str(SCENARIO)]) == 0
    assert cli.main(["validate", str(_mutated(tmp_path))]) == 1
    assert cli.main(["validate", str(tmp_path / "missing.ttl")]) == 2
    broken = tmp_path / "broken.ttl"
    broken.write_text("@prefix : <https://example.org/x#> .\n:a :b .\n", encoding="utf-8")
    assert cli.main(["validate", str(broken)]) == 2
    err = capsys.readouterr().err
    assert "Traceback" not in err and str(broken) in err


def test_empty_shapes_graph_is_refused() -> None:
    with pytest.raises(InputError, match="no SHACL shapes"):
        validate([str(SCENARIO)], shapes_files=[str(DATA / "bad-prefix-shapes.ttl")])


def test_report_summary(tmp_path: Path) -> None:
    assert validate([str(SCENARIO)]).summary() == "conforms"
    assert validate([str(_mutated(tmp_path))]).summary() == "1 error"  # the typo only, no follow-on


@pytest.mark.slow
def test_fast_engine_agrees_with_pyshacl(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """The fast engine's failure mode is silence: compare it with pySHACL on real files."""
    files = [_mutated(tmp_path)] + ([NIST / "soapInstances.owl"] if (NIST / "soapInstances.owl").exists() else [])
    for f in files:
        monkeypatch.setenv("KITKB_SHACL_ENGINE", "pyshacl")
        slow = {(d.rule, d.focus, d.line, d.message) for d in validate([str(f)]).diagnostics}
        monkeypatch.setenv("KITKB_SHACL_ENGINE", "fast")
        fast = {(d.rule, d.focus, d.line, d.message) for d in validate([str(f)]).diagnostics}
        assert slow == fast
    assert os.environ.get("KITKB_SHACL_ENGINE") == "fast"


def _scenario_with(tmp_path: Path, extra: str) -> Path:
    target = tmp_path / "init.ttl"
    target.write_text(SCENARIO.read_text(encoding="utf-8") + extra, encoding="utf-8")
    return target


def test_abstract_class_is_a_warning(tmp_path: Path) -> None:
    report = validate([str(_scenario_with(tmp_path, "\n:odd_thing a ktw:SkuObject ;\n"
                                          "    ktw:hasSkuObject_Sku :sku_part_a ;\n"
                                          "    ktw:hasSolidObject_PrimaryLocation :odd_pose .\n"))])
    warnings = [(d.rule, d.focus) for d in report.diagnostics if d.severity == "warning"]
    assert warnings == [("abstract-class", ":odd_thing")]


def test_data_file_may_not_add_axioms(tmp_path: Path) -> None:
    target = _scenario_with(tmp_path, "\nktw:Part rdfs:subClassOf ktw:KitTray .\n")
    report = validate([str(target)])
    n = len(target.read_text(encoding="utf-8").splitlines())
    declared = [(d.rule, d.focus, d.line, d.severity) for d in report.diagnostics if d.rule == "data-declares-term"]
    assert declared == [("data-declares-term", "ktw:Part", n, "error")]


def test_data_without_a_model_is_unusable(tmp_path: Path) -> None:
    f = tmp_path / "lonely.ttl"
    f.write_text("@prefix : <https://example.org/x#> .\n@prefix ktw: <https://w3id.org/kitkb/kitting#> .\n"
                 ":p a ktw:Point ; ktw:hasPoint_X 1.0 .\n", encoding="utf-8")
    with pytest.raises(InputError, match="no model"):
        validate([str(f)])


def test_data_file_importing_another_data_file(tmp_path: Path) -> None:
    """A partial state importing a full one: references into the imported file resolve."""
    init = tmp_path / "base.ttl"
    init.write_text(SCENARIO.read_text(encoding="utf-8").replace(
        "<https://w3id.org/kitkb/scenario/small-kit/init> a owl:Ontology",
        "<https://example.org/base> a owl:Ontology"), encoding="utf-8")
    extra = tmp_path / "extra.ttl"
    extra.write_text(
        "@prefix : <https://w3id.org/kitkb/scenario/small-kit#> .\n"
        "@prefix ktw: <https://w3id.org/kitkb/kitting#> .\n@prefix owl: <http://www.w3.org/2002/07/owl#> .\n"
        "<https://example.org/extra> a owl:Ontology ; owl:imports <https://example.org/base> .\n"
        ":extra_location a owl:NamedIndividual, ktw:RelativeLocationIn ;\n"
        "    ktw:hasPhysicalLocation_RefObject :kitting_workstation_1 ;\n"
        "    ktw:hasRelativeLocation_Description \"beside the workstation\" .\n"
        ":extra_location ktw:hasPhysicalLocation_RefObject :kiting_workstation_1 .\n", encoding="utf-8")
    report = validate([str(extra), str(init)])
    found = {(d.rule, d.focus, d.line) for d in report.diagnostics}
    # the second RefObject (a misspelt reference, line 8) is both unknown and one value too many
    assert found == {("unknown-individual", ":extra_location", 8), ("max-count", ":extra_location", 8)}, found


def test_malformed_cardinality_is_reported_at_its_line(tmp_path: Path) -> None:
    model = tmp_path / "model.ttl"
    model.write_text(
        "@prefix owl: <http://www.w3.org/2002/07/owl#> .\n"
        "@prefix rdfs: <http://www.w3.org/2000/01/rdf-schema#> .\n"
        "@prefix xsd: <http://www.w3.org/2001/XMLSchema#> .\n"
        "@prefix ex: <urn:ex#> .\n"
        "<urn:ex> a owl:Ontology .\n"
        "ex:Thing a owl:Class .\n"
        "ex:Foo a owl:Class ; rdfs:subClassOf ex:Thing ,\n"
        "    [ a owl:Restriction ; owl:onProperty ex:hasFoo_Bar ; owl:cardinality \"one\" ] .\n"
        "ex:hasFoo_Bar a owl:DatatypeProperty ; rdfs:domain ex:Foo ; rdfs:range xsd:string .\n"
    )
    (diag,) = [d for d in validate([model]).diagnostics if d.rule == "malformed-axiom"]
    # a blank node is located through the statement that refers to it (Source.line_of; the
    # Turtle line index records nothing under a blank subject): ex:Foo rdfs:subClassOf, line 7,
    # not the line the restriction's brackets open on (8)
    assert diag.line == 7 and "'one'" in diag.message and diag.severity == "error"
