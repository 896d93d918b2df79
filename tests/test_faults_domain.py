"""Fault kinds declared once, in Turtle (soap:FaultKind, kb.model.faults): the shipped kinds read
from kitting-domain.ttl; a kind declared only in an extension (``--domain``) is injected by the
simulator through its mechanism and scored by its data; an extension adds a diagnosing mode to
a shipped kind; an unknown kind, a malformed kind and a mechanism the simulator lacks are
refused with one line (exit 2)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from kb import crcl
from kb.cli import main
from kb.core.errors import InputError
from kb.core.resources import ontology_path
from kb.execution import run_scenario
from kb.execution.quality import score, score_detection
from kb.model.faults import domain_fault_kinds, shipped_fault_kinds
from kb.sim import FaultSpec, SimulatedCell
from kb.testmethod.methods import Options, default_faults

DATA = Path(__file__).parent / "data" / "faults"
NEW_KINDS, MORE_DIAGNOSES = DATA / "new-kinds.ttl", DATA / "more-diagnoses.ttl"
BAD_KIND, NO_MECHANISM = DATA / "bad-kind.ttl", DATA / "no-mechanism.ttl"
SMALL = ontology_path("scenarios/small-kit")
INIT, GOAL = str(SMALL / "init.ttl"), str(SMALL / "goal.ttl")
NS = "https://w3id.org/kitkb/scenario/small-kit#"
ROBOT, PART, TRAY, GRIPPER = NS + "robot_1", NS + "part_a_1", NS + "part_a_tray", NS + "part_gripper"
TAKE = (ROBOT, PART, TRAY, GRIPPER)


def _quiet(who: str, text: str) -> None:
    pass


# --- the records -------------------------------------------------------------------------------

def test_the_shipped_kinds_are_read_from_the_domain_in_their_order() -> None:
    kinds = shipped_fault_kinds()
    assert len(kinds) == 7 and [k.position for k in kinds] == list(range(1, 8))
    assert kinds.actions == ("take-part", "take-part-from-worktable", "put-part")  # defective-part strikes a part taken from a table too
    by_mechanism = {k.mechanism.name: k for k in kinds}
    assert set(by_mechanism) == {"GraspNothing", "ReleaseInTransit", "RemoveObject", "MarkDefective", "SwapSku",
                                 "DisplaceObject", "ShiftInPlane"}
    # a mechanism acting on an object names the argument it acts on and that argument's type
    shift = by_mechanism["ShiftInPlane"]
    assert shift.strike("put-part").argument == 2 and shift.strike("put-part").type.endswith("#Kit")
    assert (shift.mechanism.min_shift, shift.mechanism.max_shift) == (0.02, 0.06)
    assert by_mechanism["GraspNothing"].strike("take-part").argument is None
    assert kinds.rejecting_modes() == {m for k in kinds if k.rejecting for m in k.diagnosed_by}
    assert all(k.diagnosed_by for k in kinds)
    # the errors method's default mix is the kinds' test-method rates, the most frequent first
    assert default_faults() == kinds.default_mix()
    assert Options("errors").faults == kinds.default_mix()
    assert sorted(FaultSpec.parse(kinds.default_mix()).rates.items()) == sorted(
        (k.name, k.test_rate) for k in kinds if k.test_rate)


def test_an_extension_adds_kinds_after_the_shipped_ones() -> None:
    kinds = domain_fault_kinds([NEW_KINDS])
    assert kinds.names[:7] == shipped_fault_kinds().names
    assert kinds.names[7:] == ("part-stolen", "partstray-nudged")
    nudged = kinds.check("partstray-nudged")
    assert nudged.strike("take-part").argument == 2 and nudged.strike("take-part").type.endswith("#PartsTray")
    assert "part-stolen=0.02" in kinds.default_mix()
    assert default_faults((str(NEW_KINDS),)) == kinds.default_mix()
    # the test methods check a fault mix against the campaign's domain
    assert Options("errors", faults="part-stolen=0.1", domain=(str(NEW_KINDS),)).faults == "part-stolen=0.1"
    with pytest.raises(InputError, match="--faults: unknown fault kind 'part-stolen'"):
        Options("errors", faults="part-stolen=0.1")


# --- the simulator -----------------------------------------------------------------------------

def test_a_kind_declared_in_an_extension_is_injected_by_its_mechanism() -> None:
    kinds = domain_fault_kinds([NEW_KINDS])
    with pytest.raises(ValueError, match="unknown fault kind 'part-stolen'; known: missed-grasp"):
        FaultSpec.parse("part-stolen@0")  # the shipped domain alone does not know it
    cell = SimulatedCell(INIT, faults=FaultSpec.parse("part-stolen@0,partstray-nudged@0", seed=3, kinds=kinds))
    before = cell.scene()
    lo = before.lo[before.index[TRAY]].copy()
    cell.begin_action(0, "take-part", TAKE)
    assert [(i.kind, i.action_index, i.objects) for i in cell.injected] == [
        ("part-stolen", 0, (PART,)), ("partstray-nudged", 0, (TRAY,))]
    after = cell.scene()
    assert not cell.world.placed(cell.world.index[PART])
    moved = after.lo[after.index[TRAY]] - lo
    assert moved[2] == 0 and 0.02 - 1e-9 <= float((moved[:2] ** 2).sum() ** 0.5) <= 0.06 + 1e-9
    # a kind on an action it does not strike waits for one it does
    cell = SimulatedCell(INIT, faults=FaultSpec.parse("part-stolen@0", kinds=kinds))
    cell.begin_action(0, "put-part", (ROBOT, PART, NS + "kit_1", NS + "work_table_1", NS + "sku_a"))
    assert cell.injected == []
    cell.begin_action(1, "take-part", TAKE)
    assert [i.kind for i in cell.injected] == ["part-stolen"]


def test_the_robot_reports_its_armed_primitive_and_the_kind_is_mapped_back() -> None:
    cell = SimulatedCell(INIT, faults=FaultSpec.parse("missed-grasp@1"))
    cell.execute(crcl.InitCanon())
    cell.begin_action(1, "take-part", TAKE)
    assert cell.robot.miss_grasp
    cell.robot.on_fault("miss_grasp", (PART,), "closed on nothing")
    assert [(i.kind, i.action_index) for i in cell.injected] == [("missed-grasp", 1)]


def test_a_mechanism_the_simulator_lacks_is_refused() -> None:
    kinds = domain_fault_kinds([NO_MECHANISM])
    with pytest.raises(ValueError, match="no mechanism Teleport"):
        FaultSpec.parse("part-teleported@2", kinds=kinds)


# --- scoring -----------------------------------------------------------------------------------

def test_a_kind_from_an_extension_runs_end_to_end_and_is_scored_by_its_data() -> None:
    run = run_scenario(INIT, GOAL, faults="part-stolen@0", seed=1, domain_files=[str(NEW_KINDS)], notifier=_quiet)
    report = run.report()
    assert [(x["kind"], x["objects"]) for x in report["injected"]] == [("part-stolen", ["part_a_1"])]
    assert report["failures"] and report["failures"][0]["mode"] in {"part-missing-from-tray", "parts-tray-empty"}
    quality = score_detection([report], domain_fault_kinds([NEW_KINDS]))
    assert quality.kinds["part-stolen"].as_dict()["diagnosed_right"] == 1
    assert quality.rates()["detection"] == 1.0
    with pytest.raises(InputError, match="fault kind 'part-stolen', which the domain does not declare"):
        score_detection([report])


def test_an_extension_adds_a_diagnosing_mode_to_a_shipped_kind() -> None:
    kinds = domain_fault_kinds([MORE_DIAGNOSES])
    assert kinds.check("missed-grasp").diagnosed_by == {"missed-grasp", "dropped-part"}
    assert shipped_fault_kinds().check("missed-grasp").diagnosed_by == {"missed-grasp"}
    report = {"injected": [{"kind": "missed-grasp", "action_index": 4, "objects": ["part_a_1"], "detail": ""}],
              "failures": [{"mode": "dropped-part", "action_index": 4, "objects": ["part_a_1", "part_a_tray"]}],
              "attempts": 10}
    assert score(report)["verdicts"] == ["wrong"]
    assert score(report, kinds)["verdicts"] == ["correct"]
    assert score_detection([report], kinds).kinds["missed-grasp"].right == 1


# --- the command line ----------------------------------------------------------------------------

def test_kitkb_faults_lists_the_domains_kinds(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["faults"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert [line.split(":", 1)[0] for line in lines] == list(shipped_fault_kinds().names)
    assert main(["faults", "--domain", str(NEW_KINDS), "--domain", str(MORE_DIAGNOSES), "--format", "json"]) == 0
    data = json.loads(capsys.readouterr().out)
    by_name = {k["name"]: k for k in data["kinds"]}
    assert by_name["part-stolen"]["mechanism"] == "RemoveObject"
    assert by_name["missed-grasp"]["diagnosed_by"] == ["dropped-part", "missed-grasp"]
    assert data["default_mix"] == domain_fault_kinds([NEW_KINDS]).default_mix()


def test_an_unknown_kind_is_exit_2_before_any_work(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["run", INIT, GOAL, "--faults", "part-stolen@3", "-o", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [f"error: --faults: unknown fault kind 'part-stolen'; known: {', '.join(shipped_fault_kinds().names)}"]
    assert not (tmp_path / "out").exists()  # refused before validation and planning
    assert main(["testmethod", "errors", "--faults", "lost=0.1", "--out", str(tmp_path / "c")]) == 2
    assert "--faults: unknown fault kind 'lost'" in capsys.readouterr().err
    assert main(["sim", "serve", INIT, "--faults", "lost@1"]) == 2
    assert "unknown fault kind 'lost'" in capsys.readouterr().err


def test_a_malformed_kind_or_a_missing_mechanism_is_exit_2_at_its_line(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["faults", "--domain", str(BAD_KIND)]) == 2
    line = next(i for i, text in enumerate(BAD_KIND.read_text().splitlines(), 1) if "x:fault_kit-vanishes a" in text)
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith(f"{BAD_KIND}:{line}: ") and "hasFaultKind_Target" in err[0]
    assert main(["run", INIT, GOAL, "--domain", str(NO_MECHANISM), "--faults", "part-teleported@1"]) == 2
    assert "no mechanism Teleport" in capsys.readouterr().err


def test_a_diagnosing_mode_the_domain_lacks_is_a_warning_not_an_error(tmp_path: Path,
                                                                   capsys: pytest.CaptureFixture[str]) -> None:
    ext = tmp_path / "ext.ttl"
    ext.write_text("@prefix kd: <https://w3id.org/kitkb/kitting-domain#> .\n"
                   "@prefix soap: <https://w3id.org/kitkb/soap#> .\n"
                   "kd:fault_missed-grasp soap:hasFaultKind_DiagnosedBy <https://example.org/u#not-a-mode> .\n")
    kind = domain_fault_kinds([ext]).check("missed-grasp")
    assert kind.diagnosed_by == {"missed-grasp"} and kind.undeclared_modes == ("https://example.org/u#not-a-mode",)
    assert main(["faults", "--domain", str(ext)]) == 0
    assert "not-a-mode (hasFaultKind_DiagnosedBy) is no failure mode of the domain" in capsys.readouterr().err
