"""Execution metrics and kit scores of runs (issue 18 parts 4 and 5): in the report, the
executives' API and the database, the same from a recorded run, and why each point was lost."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from kb import planning
from kb.cli import main
from kb.execution import open_run, run_plan
from kb.execution.records import ActionRecord, FailureRecord
from kb.metrics import Robot
from kb.metrics.execution import execution_metrics, recovered
from kb.metrics.static import session_metrics, static_metrics
from kb.metrics.steps import text_steps
from kb.scenario import write_spec
from kb.scenario.spec import DesignSpec, PartType, ScenarioSpec

ROOT = Path(__file__).resolve().parents[1]
SMALL = ROOT / "ontologies" / "scenarios" / "small-kit"


@pytest.fixture(scope="module")
def tight(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path, list[str]]:
    """A kit of one part A and one part B with no spare part: a B that is lost cannot be replaced."""
    spec = ScenarioSpec("tight", "no spare parts", (PartType("a", 0.1, 0.08, 0.06, 0.2),
                                                    PartType("b", 0.12, 0.08, 0.06, 0.2)),
                        (DesignSpec("kit_design_1", (("a", 1), ("b", 1))),), (0,), spare=0)
    init, goal = write_spec(spec, tmp_path_factory.mktemp("tight"))
    model = planning.kitting_model([init], [goal], "strips")
    return init, goal, planning.run(model.up_problem, None).lines


@pytest.fixture(scope="module")
def small_plan() -> list[str]:
    model = planning.kitting_model([SMALL / "init.ttl"], [SMALL / "goal.ttl"], "strips")
    return planning.run(model.up_problem, None).lines


def _take(plan: list[str], part_type: str) -> int:
    return next(i for i, line in enumerate(plan) if line.startswith("(take-part") and f"part_{part_type}_" in line)


def test_a_built_kit_scores_full_marks_and_the_report_says_so(small_plan: list[str]) -> None:
    run = run_plan(small_plan, SMALL / "init.ttl", SMALL / "goal.ttl", plan_time=0.5)
    assert run.goal_holds
    [kit] = run.kit_scores
    assert kit.kit.endswith("#kit_1") and kit.design.endswith("#kit_design_a2b1")
    assert (kit.score, kit.max_score, kit.lost) == (6, 6, ())  # tray + 3 slots + no extras + delivered
    m = run.metrics
    assert m["failures"] == 0 and m["replans"] == 0 and m["plan_time_s"] == 0.5
    static = m["static"]
    # every action's program begins with InitCanon and ends with EndCanon: in sequence, no errors
    assert static["CSE"] == 0 and static["TE"] == 0 and static["PE"] == 0
    assert static["ACE"] > len(small_plan) and static["TDM"] > 1.0
    data = json.loads(json.dumps(run.report()))
    assert data["kits"] == [{"kit": "kit_1", "design": "kit_design_a2b1", "score": 6, "max_score": 6, "lost": []}]
    assert data["metrics"]["static"] == static
    # what a report page draws: the objects, the tip's path, the timeline
    names = {o["name"]: o for o in data["scene"]["objects"]}
    assert names["kit_tray_1"]["class"] == "KitTray" and names["part_a_1"]["class"] == "Part"
    assert names["part_a_1"]["initial"] != names["part_a_1"]["final"]
    assert [p["index"] for p in data["path"]] == sorted(p["index"] for p in data["path"]) and data["path"]
    assert [e["kind"] for e in data["timeline"]].count("action") == len(small_plan)


def test_an_unrecovered_wrong_sku_loses_the_slot_point_with_its_predicate(tight: tuple[Path, Path, list[str]],
                                                                         tmp_path: Path, capsys) -> None:
    init, goal, plan = tight
    at = _take(plan, "b")
    db = tmp_path / "world.sqlite"
    run = run_plan(plan, init, goal, faults=f"wrong-sku@{at}", seed=3, db=db)
    assert not run.goal_holds
    assert [f.mode for f in run.failures()][0] == "wrong-sku"
    # no B left: by the domain's partial-kit policy (deliver) the kit goes to its box without it
    [partial] = run.record.partial_kits
    assert partial["outcome"] == "delivered partial" and set(partial["lacks"]) == {"sku_part_b"}, partial
    [kit] = run.kit_scores
    slot_b = [x for x in kit.lost if x.predicate == "part-location-kit" and "_b_" in x.objects[-1]]
    assert len(slot_b) == 1 and slot_b[0].points == 1 and "empty" in slot_b[0].reason
    assert not any(x.predicate == "part-location-kit" and "_a_" in x.objects[-1] for x in kit.lost)  # A is in
    assert kit.score == kit.max_score - sum(x.points for x in kit.lost) < kit.max_score
    m = run.metrics
    # the failure was handled (the part rejected, a plan to the kits the parts allow): recovered,
    # though the kit lacks its B
    assert m["failures"] >= 1 and m["unrecovered"] == 0 and m["failures_per_kit"] == {"kit_1": m["failures"]}
    # the same from the database, without re-running
    back = open_run(db)
    assert back.metrics == m and back.kit_scores == run.kit_scores
    lost = run.report()["kits"][0]["lost"]
    assert {"points": 1, "predicate": "part-location-kit"}.items() <= next(
        x for x in lost if x["predicate"] == "part-location-kit").items()
    # kitkb metrics --run: the same, from the database
    capsys.readouterr()
    assert main(["metrics", "--run", str(run.record.run_id), "--db", str(db), "--format", "json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["metrics"] == json.loads(json.dumps(m)) and data["kits"] == run.report()["kits"]
    assert main(["metrics", "--run", str(run.record.run_id), "--db", str(db)]) == 0
    text = capsys.readouterr().out
    assert f"kit kit_1: {kit.score} of {kit.max_score} points" in text and "(part-location-kit(kit_1, " in text
    for bad in (["--run", "99", "--db", str(db)], ["--run", "1", "--db", str(tmp_path / "none.sqlite")],
                ["--run", "1"], [str(tmp_path / "p.crcl"), "--run", "1", "--db", str(db)]):
        assert main(["metrics", *bad]) == 2
        assert capsys.readouterr().err.count("\n") == 1
    assert not (tmp_path / "none.sqlite").exists()


def test_failures_count_for_their_kit_across_retries_and_replans() -> None:
    def f(i: int, mode: str, recovery: str, outcome: str, kit: str | None = "urn:x#kit_1") -> FailureRecord:
        return FailureRecord(i, "take-part", ("r", "p"), "effect", [], [], mode, recovery=recovery,
                             outcome=outcome, kit=kit)
    actions = [ActionRecord(0, "take-part", ("r", "p"), "failed"), ActionRecord(1, "take-part", ("r", "p"), "done"),
               ActionRecord(2, "take-part", ("r", "q"), "failed"), ActionRecord(3, "take-part", ("r", "q"), "failed")]
    failures = [f(0, "missed-grasp", "retry", "retry 1 of 2"),                  # then done: recovered
                f(2, "missed-grasp", "retry", "retry 1 of 2"),                  # never done: not recovered
                f(3, "dropped-part", "replan", "recovered: new plan of 9 actions"),
                f(3, "wrong-sku", "replan", "stopped: no plan", kit="urn:x#kit_2"),
                f(3, "effector-missing", "replan", "recovered: new plan", kit=None)]
    assert [recovered(x, actions) for x in failures] == [True, False, True, False, True]
    m = execution_metrics(failures, actions, replans=2, replan_time=0.25)
    assert m["failures_per_kit"] == {"-": 1, "kit_1": 3, "kit_2": 1}
    assert (m["recovered"], m["unrecovered"]) == (3, 2)
    assert m["recovered_by_mode"] == {"dropped-part": 1, "effector-missing": 1, "missed-grasp": 1}
    assert m["contact_errors"] is None  # a cell that reports no ground truth
    m = execution_metrics([], [], replans=0, violations=[{"kind": "contact"}, {"kind": "contact"},
                                                         {"kind": "overweight"}])
    assert m["contact_errors"] == 2 and m["violations"] == {"contact": 2, "overweight": 1}


def test_a_run_s_programs_are_judged_one_by_one_with_the_robot_s_state_carried_over() -> None:
    first = ["InitCanon()", "MoveTo({{1, 0, 0}, {0, 0, -1}, {1, 0, 0}})", "CloseGripper()", "EndCanon()"]
    second = ["InitCanon()", "MoveTo({{1, 0, 0}, {0, 0, -1}, {1, 0, 0}})", "OpenGripper()", "EndCanon()"]
    robot = Robot(length_unit="meter")
    m = session_metrics([list(text_steps(first)), list(text_steps(second))], robot).totals
    # one program of the two would have two sequence errors; the move of the second goes nowhere,
    # the first CloseGripper finds the gripper closed: useless
    assert m["CSE"] == 0 and m["UCE"] == 2 and m["TDM"] == pytest.approx(1.0) and m["ACE"] == 4
    joined = static_metrics(list(text_steps(first + second)), robot).totals
    assert joined["CSE"] == 2
    # InitCanon sets the robot's unit: millimetres by the paper, metres for kitkb's cell
    assert session_metrics([list(text_steps(first))]).totals["TDM"] == pytest.approx(0.001)


def test_kitkb_run_writes_the_report_as_a_page(tmp_path: Path) -> None:
    page, report = tmp_path / "run.html", tmp_path / "run.json"
    assert main(["run", str(SMALL / "init.ttl"), str(SMALL / "goal.ttl"), "-o", str(tmp_path / "out"), "-q",
                 "--faults", "missed-grasp@6", "--seed", "1", "--report", str(report), "--report-html", str(page)]) == 0
    html = page.read_text(encoding="utf-8")
    data = json.loads(report.read_text())
    assert html.lstrip().lower().startswith("<!doctype html") and "plotly" in html.lower()
    assert "kit_1" in html and "missed-grasp" in html and data["kits"][0]["score"] == data["kits"][0]["max_score"]
    assert main(["run", str(SMALL / "init.ttl"), str(SMALL / "goal.ttl"), "-o", str(tmp_path / "out"), "-q",
                 "--report-html", str(SMALL / "init.ttl")]) == 2  # never over an input
