"""The first paper's §IV-B execution metrics kitkb lacked (issue 31 point 4): transporting
components, manipulation robustness by stage with operator interventions, failures classed
precondition / action / unattributable, and the distinct failure modes recovered from —
computed from the commands, the scene and the cell's ground truth, alike for every system."""

from __future__ import annotations

import json
from pathlib import Path
from types import SimpleNamespace as F
from typing import Any

import pytest

from kb.execution.loop import run_scenario
from kb.metrics.clock import timed_commands
from kb.metrics.handling import fault_mechanisms
from kb.metrics.robustness import failure_classes, modes_recovery, paper_metrics
from kb.report import run_page
from kb.sim import FaultSpec
from kb.sim.cell import SimulatedCell

ROOT = Path(__file__).resolve().parent.parent
SMALL = ROOT / "ontologies" / "scenarios" / "small-kit"


def _run(faults: str | None) -> dict[str, Any]:
    spec = FaultSpec.parse(faults, seed=1) if faults else None
    cell = SimulatedCell(SMALL / "init.ttl", faults=spec, seed=1)
    run = run_scenario(SMALL / "init.ttl", SMALL / "goal.ttl", cell=cell, seed=1, notifier=lambda *a: None)
    return json.loads(json.dumps(run.record.report()))


@pytest.fixture(scope="module")
def clean() -> dict[str, Any]:
    return _run(None)


@pytest.fixture(scope="module")
def faulty() -> dict[str, Any]:
    return _run("dropped-part@6,part-moved@10")


def test_a_fault_free_run_transports_every_part_into_its_kit(clean: dict[str, Any]) -> None:
    m = clean["metrics"]
    parts = sum(1 for o in clean["scene"]["objects"] if o["class"] == "Part" and o["final"][2][3] < 0.5)
    assert parts == 3  # small-kit's kit takes three parts (into the finished kit box, on the floor)
    assert m["transporting"] == {"parts_transported": 3, "parts_delivered": 3, "dropped": 0, "rate": 1.0}
    r = m["robustness"]
    rows = clean["commands"]["rows"]
    assert r["approach"]["attempts"] == sum(1 for row in rows if row[1].startswith("Move")) > 0
    assert r["manipulation"]["attempts"] == sum(1 for row in rows if "Gripper" in row[1] or "ToolChanger" in row[1])
    assert r["detection"]["attempts"] == clean["checks"]
    assert all(r[s]["failures"] == 0 and r[s]["per_attempt"] == 0.0 for s in ("detection", "approach", "manipulation"))
    assert r["operator_interventions"] == 0
    assert m["failure_classes"] == {"precondition": 0, "action": 0, "unattributable": 0}
    assert (m["failure_modes"], m["failure_modes_recovered"], m["modes_not_recovered"]) == (0, 0, [])


def test_a_drop_and_a_part_moved_by_an_agent(faulty: dict[str, Any]) -> None:
    m = faulty["metrics"]
    assert {x["kind"] for x in faulty["injected"]} == {"dropped-part", "part-moved"}
    # part_a_1 fell in transit: transported, not delivered; three others went into the kit
    assert m["transporting"] == {"parts_transported": 4, "parts_delivered": 3, "dropped": 1, "rate": 0.75}
    manipulation = m["robustness"]["manipulation"]
    assert manipulation["failures"] == 1
    assert manipulation["per_attempt"] == pytest.approx(1 / manipulation["attempts"], abs=1e-6)
    # the drop is the robot's action failing (found by the next action's preconditions); the part
    # knocked off its tray is an external agent's doing
    modes = {f["mode"]: f["phase"] for f in faulty["failures"]}
    assert modes == {"dropped-part-in-transit": "precondition", "part-missing-from-tray": "precondition"}
    assert m["failure_classes"] == {"precondition": 0, "action": 1, "unattributable": 1}
    assert (m["failure_modes"], m["failure_modes_recovered"]) == (2, 2) and m["recovered"] == 2


def test_failure_classes_and_modes_from_records() -> None:
    injected = [{"kind": "missed-grasp", "action_index": 3, "objects": ["p1"]},
                {"kind": "kit-tray-moved", "action_index": 5, "objects": ["tray"]},
                {"kind": "wrong-sku", "action_index": 8, "objects": ["p4"]}]
    mech = fault_mechanisms(["missed-grasp", "kit-tray-moved", "wrong-sku", "no-such-kind"])
    assert mech == {"missed-grasp": "GraspNothing", "kit-tray-moved": "ShiftInPlane", "wrong-sku": "SwapSku"}
    failures = [F(objects=["urn:x#p1"], action_index=3, phase="effect", mode="missed-grasp"),
                F(objects=["tray", "kit"], action_index=7, phase="precondition", mode="kit-not-on-worktable"),
                F(objects=["tray"], action_index=4, phase="precondition", mode="kit-not-on-worktable"),  # before the push
                F(objects=["p4"], action_index=8, phase="effect", mode="wrong-sku"),
                F(objects=["p9"], action_index=9, phase="effect", mode="missed-grasp")]
    assert failure_classes(failures, injected, mech, True) == {"precondition": 1, "action": 2, "unattributable": 2}
    # a real cell: no ground truth, so nothing is known to be an agent's
    assert failure_classes(failures, [], {}, False) == {"precondition": 2, "action": 3, "unattributable": None}
    # six of six built, one failure not recovered: one mode, recovered from
    again = modes_recovery(failures[:1] + failures[4:], [True, False])
    assert again == {"failure_modes": 1, "failure_modes_recovered": 1, "modes_not_recovered": []}
    assert modes_recovery(failures, [False, True, True, False, False])["modes_not_recovered"] == ["missed-grasp",
                                                                                                 "wrong-sku"]


def test_ground_truth_stages_and_operator_interventions() -> None:
    actions = [F(index=0, programs=[["InitCanon()", "MoveTo({{1, 0, 0}, {0, 0, -1}, {1, 0, 0}})", "CloseGripper()",
                                     "MoveTo({{1, 1, 0}, {0, 0, -1}, {1, 0, 0}})", "OpenGripper()", "EndCanon()"]])]
    commands = timed_commands(actions)
    m = paper_metrics([], [], commands, violations=[{"kind": "contact"}, {"kind": "overweight"}, {"kind": "contact"}],
                      sensor_errors=[{"kind": "misdetection"}], checks=4, resumes=1, stopped="gave up")
    r = m["robustness"]
    assert r["approach"] == {"attempts": 2, "failures": 2, "per_attempt": 1.0}
    assert r["manipulation"] == {"attempts": 2, "failures": 1, "per_attempt": 0.5}
    assert r["detection"] == {"attempts": 4, "failures": 1, "per_attempt": 0.25}
    assert r["operator_interventions"] == 2
    assert m["transporting"]["rate"] is None  # no scene
    real = paper_metrics([], [], commands)  # a real cell: no ground truth
    assert real["robustness"]["approach"]["failures"] is None and real["failure_classes"]["unattributable"] is None


def test_the_run_page_shows_them(faulty: dict[str, Any]) -> None:
    html = run_page(faulty)
    for text in ("Transporting components", "Manipulation robustness", "unattributable", "operator interventions",
                 "failure modes recovered"):
        assert text in html, text


def test_a_campaign_pools_them(clean: dict[str, Any], faulty: dict[str, Any]) -> None:
    from kb.testmethod.summary import figures, paper_metrics as pooled
    p = pooled([clean, faulty])
    assert p["transporting"] == {"parts_delivered": 6, "parts_transported": 7, "dropped": 1, "rate": round(6 / 7, 6)}
    assert p["failure_classes"] == {"precondition": 0, "action": 1, "unattributable": 1}
    man = p["robustness"]["manipulation"]
    assert man["failures"] == 1 and man["attempts"] == (clean["metrics"]["robustness"]["manipulation"]["attempts"]
                                                        + faulty["metrics"]["robustness"]["manipulation"]["attempts"])
    assert (p["failure_modes"], p["failure_modes_recovered"]) == (2, 2)
    row = dict(faulty, executed=True)
    assert figures(row)["metrics.transporting.rate"] == 0.75
    assert figures(row)["metrics.robustness.manipulation.failures"] == 1.0
