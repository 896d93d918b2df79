"""Sensor noise (issue 21): the noise model and its option, the simulated sensor that applies it
and never the ground truth, the executor's verification under noise, detection quality.

Fast: small-kit and a generated 10-part kit, a few seeds each (the campaign figures are
benchmarks/bench_noise.py's)."""

from __future__ import annotations

import copy
import math
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from kb import planning
from kb.cli import main
from kb.core.errors import InputError
from kb.crcl.cell import Observation
from kb.execution import run_plan
from kb.execution.belief import Belief
from kb.execution.quality import score_detection
from kb.execution.records import without_timings
from kb.sim import SimulatedCell
from kb.sim.noise import SensorNoise
from kb.spatial.scene import Scene

ROOT = Path(__file__).resolve().parents[1]
SMALL = ROOT / "ontologies" / "scenarios" / "small-kit"
INIT, GOAL = str(SMALL / "init.ttl"), str(SMALL / "goal.ttl")
DOCUMENTED = "position=1mm,orientation=0.5deg,misdetection=1%,misclass=0.5%"
SENSOR = """
:kitting_workstation_1 ktw:hasKittingWorkstation_Sensor :camera_1 .
:camera_1 a owl:NamedIndividual, ktw:PoseSensor ;
    ktw:hasPoseSensor_PositionAccuracy {position} ;
    ktw:hasPoseSensor_OrientationAccuracy {orientation} ;
    ktw:hasPoseSensor_MisdetectionRate {misdetection} .
"""


def quiet(*_a: object) -> None:
    return None


@pytest.fixture(scope="module")
def small_plan() -> list[str]:
    model = planning.kitting_model([INIT], [GOAL], "strips")
    return list(planning.run(model.up_problem, None).lines)


@pytest.fixture(scope="module")
def generated(tmp_path_factory: pytest.TempPathFactory) -> tuple[str, str, list[str]]:
    from kb.scenario import write_scenario
    init, goal = write_scenario(tmp_path_factory.mktemp("p10"), parts=10, kits=1, seed=0)
    model = planning.kitting_model([init], [goal], "strips")
    return str(init), str(goal), list(planning.run(model.up_problem, None).lines)


def with_sensor(tmp_path: Path, **values: str) -> str:
    """small-kit's initial state with a pose sensor individual (values in the file's units)."""
    text = Path(INIT).read_text() + SENSOR.format(**values)
    out = tmp_path / "init.ttl"
    out.write_text(text)
    return str(out)


# --- the noise model and its option ---------------------------------------------------------------

def test_parse_values_with_their_units() -> None:
    n = SensorNoise.parse("position=1mm,orientation=0.5deg,misdetection=0.01,misclass=0.5%,bias=0.05cm")
    assert (n.position, n.misdetection, n.misclassification) == pytest.approx((0.001, 0.01, 0.005))
    assert n.orientation == pytest.approx(math.radians(0.5)) and n.bias == pytest.approx(0.0005)
    assert SensorNoise.parse("position=0.04in,orientation=0.01rad").position == pytest.approx(0.001016)
    again = SensorNoise.parse(n.text())
    assert np.allclose(list(again.as_dict().values()), list(n.as_dict().values()))
    assert SensorNoise().zero and SensorNoise().text() == "none"


def test_the_option_overrides_the_files_sensor_key_by_key() -> None:
    base = SensorNoise(position=0.002, orientation=0.01, misdetection=0.05)
    n = SensorNoise.parse("position=1mm", base)
    assert (n.position, n.orientation, n.misdetection) == (0.001, 0.01, 0.05)


def test_a_sweep_of_one_key() -> None:
    base = SensorNoise.parse("orientation=0.5deg,misdetection=1%")
    levels = SensorNoise.sweep("position=0mm:5mm:6", base)
    assert [round(n.position * 1000, 9) for n in levels] == [0, 1, 2, 3, 4, 5]
    assert all(n.orientation == base.orientation and n.misdetection == 0.01 for n in levels)
    for bad in ("position=0mm:5mm", "position=0:5mm:6", "position=0mm:5mm:1", "position=0mm:5mm:x"):
        with pytest.raises(ValueError):
            SensorNoise.sweep(bad)


@pytest.mark.parametrize("text,words", [
    ("position=1", ["bare length", "item 1"]),
    ("position=1mm,orientation=0.5", ["bare angle", "item 2", "deg"]),
    ("position=1ft", ["unknown length unit 'ft'"]),
    ("speed=1mm", ["KEY=VALUE", "item 1"]),
    ("position=1mm,,bias=1mm", ["empty item", "item 2"]),
    ("misdetection=1.5", ["below 1"]),
    ("misclass=3mm", ["a rate is a number"]),
    ("position=-1mm", [">= 0"]),
    ("orientation=fast", ["not a number with a unit"]),
])
def test_parse_errors_name_their_place(text: str, words: list[str]) -> None:
    with pytest.raises(ValueError) as e:
        SensorNoise.parse(text)
    assert all(w in str(e.value) for w in words), str(e.value)


def test_cli_refuses_a_bare_number_and_the_old_option(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    assert main(["run", INIT, GOAL, "-o", str(tmp_path), "--sensor-noise", "position=1"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--sensor-noise" in err[0] and "bare length" in err[0]
    assert main(["sim", "serve", INIT, "--noise", "0.001,0.01"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--sensor-noise position=1mm" in err[0]


def test_the_sensor_is_data_in_the_state_file_in_its_units(tmp_path: Path) -> None:
    init = with_sensor(tmp_path, position="0.002", orientation="0.5", misdetection="0.01")  # metres, degrees
    n = SensorNoise.from_scene(Scene.from_files([init], declared=[GOAL]))
    assert n == SensorNoise(position=0.002, orientation=math.radians(0.5), misdetection=0.01)
    assert SensorNoise.from_scene(Scene.from_files([INIT], declared=[GOAL])) is None
    bad = with_sensor(tmp_path, position="-1.0", orientation="0.5", misdetection="0.01")
    with pytest.raises(InputError, match="camera_1"):
        run_plan([], bad, GOAL, notifier=quiet)


# --- the simulated sensor: noise in what it reports, never in the ground truth ----------------------

SCENE = Scene.from_files([INIT], declared=[GOAL])


@settings(max_examples=25, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow])
@given(position=st.floats(0.0, 0.01), orientation=st.floats(0.0, 0.05), bias=st.floats(0.0, 0.005),
       misdetection=st.floats(0.0, 0.6), misclass=st.floats(0.0, 0.6), seed=st.integers(0, 2**31))
def test_noise_never_moves_the_ground_truth(position: float, orientation: float, bias: float, misdetection: float,
                                            misclass: float, seed: int) -> None:
    noise = SensorNoise(position, orientation, misdetection, misclass, bias)
    cell = SimulatedCell(SCENE, noise=noise, seed=seed)
    w = cell.world
    before = (w.poses.copy(), w.local_lo.copy(), w.local_hi.copy(), w.parent.copy(), copy.deepcopy(w.facts))
    placed = [n for i, n in enumerate(w.names) if w.placed(i)]
    first = cell.sense("SolidObject")
    seen = first + cell.sense_names(placed + placed) + cell.sense("Part")
    assert np.array_equal(w.poses, before[0], equal_nan=True) and np.array_equal(w.parent, before[3])
    assert np.array_equal(w.local_lo, before[1], equal_nan=True) and np.array_equal(w.local_hi, before[2], equal_nan=True)
    assert w.facts == before[4]
    errors = cell.sensor.errors
    exact = SimulatedCell(SCENE)
    asked = len(exact.sense("SolidObject")) + 2 * len(placed) + len(exact.sense("Part"))
    assert len(seen) == asked - sum(e.kind == "misdetection" for e in errors)
    true_sku = {o.name: o.sku for o in exact.sense_names(placed)}
    wrong = [o for o in seen if o.sku != true_sku[o.name]]
    assert len(wrong) == sum(e.kind == "misclassification" for e in errors)
    if noise.zero:
        assert first == exact.sense("SolidObject") and not errors


def test_the_same_seed_gives_the_same_looks_and_errors() -> None:
    noise = SensorNoise.parse("position=2mm,orientation=1deg,bias=1mm,misdetection=20%,misclass=20%")
    a, b = (SimulatedCell(SCENE, noise=noise, seed=7) for _ in range(2))
    assert a.sense("SolidObject") == b.sense("SolidObject") and a.sensor.errors == b.sensor.errors
    assert a.sense("SolidObject") != SimulatedCell(SCENE, noise=noise, seed=8).sense("SolidObject")


# --- the belief: a small filter --------------------------------------------------------------------

def _look(name: str, xyz: tuple[float, float, float], rpy: tuple[float, float, float] = (0.0, 0.0, 0.0)) -> Observation:
    return Observation(name, "Part", 0.0, xyz, rpy)


def test_belief_averages_looks_within_the_gate_and_moves_outside_it() -> None:
    b = Belief(SCENE)
    b.use_noise(SensorNoise(position=0.001, orientation=0.01))
    part = next(n for n in b.names if n.endswith("#part_a_1"))
    x, y, z = (float(v) for v in b.pose(part)[:3, 3])
    b.observe([_look(part, (x + 0.001, y, z))])
    b.observe([_look(part, (x - 0.001, y, z), (0.003, -0.002, 0.01))])  # tilted within the gate: levelled
    assert b.looks[b.index[part]] == 2 and b.last_moved == []
    assert b.pose(part)[:3, 3] == pytest.approx([x, y, z], abs=1e-9)
    assert b.pose(part)[2, :3] == pytest.approx([0.0, 0.0, 1.0])  # level still; yaw averaged
    b.observe([_look(part, (x + 0.05, y, z))])  # 5 cm: it moved
    assert b.last_moved == [part] and b.looks[b.index[part]] == 1
    assert b.pose(part)[0, 3] == pytest.approx(x + 0.05)
    b.observe([_look(part, (x + 0.05, y, z))] * 4)  # four simultaneous frames count as four looks
    assert b.looks[b.index[part]] == 5


def test_exact_sensor_belief_takes_every_look_as_it_is() -> None:
    b = Belief(SCENE)
    b.use_noise(SensorNoise())
    part = next(n for n in b.names if n.endswith("#part_a_1"))
    x, y, z = (float(v) for v in b.pose(part)[:3, 3])
    assert b.observe([_look(part, (x + 0.0005, y, z))]) == [part]
    assert b.pose(part)[0, 3] == x + 0.0005 and b.noise is None


# --- runs --------------------------------------------------------------------------------------------

EXPECTED_FAILURES = [  # today's run of small-kit with these faults (before sensor noise existed)
    ("missed-grasp", 6, "retry", "retry 1 of 3"),
    ("part-missing-from-tray", 9, "rebind", "recovered: bound part_a_3 from part_a_tray"),
]
FAULTS = "missed-grasp@6,part-missing@9"


def test_zero_noise_gives_todays_run(small_plan: list[str], tmp_path: Path) -> None:
    runs = [run_plan(small_plan, INIT, GOAL, faults=FAULTS, seed=1, notifier=quiet, **kw) for kw in (
        {}, {"sensor_noise": "position=0mm,orientation=0deg,misdetection=0,misclass=0"})]
    zero_file = with_sensor(tmp_path, position="0.0", orientation="0.0", misdetection="0.0")
    runs.append(run_plan(small_plan, zero_file, GOAL, faults=FAULTS, seed=1, notifier=quiet, name="small-kit"))
    reports = [without_timings(r.report()) for r in runs]
    assert all(rep == reports[0] for rep in reports[1:])
    assert "sensor" not in reports[0] and "sensor_errors" not in reports[0]
    assert [(f["mode"], f["action_index"], f["recovery"], f["outcome"]) for f in reports[0]["failures"]] == EXPECTED_FAILURES
    assert reports[0]["actions"] == len(small_plan) and reports[0]["goal_holds"] is True
    assert reports[0]["checks"] > len(small_plan)  # each action's preconditions and effects, the retried one twice


@pytest.mark.parametrize("seed", [0, 1])
def test_a_noisy_run_without_faults_raises_no_failure(small_plan: list[str], seed: int) -> None:
    run = run_plan(small_plan, INIT, GOAL, seed=seed, notifier=quiet, sensor_noise=DOCUMENTED)
    rep = run.report()
    assert rep["failures"] == [] and run.goal_holds and run.stopped is None
    assert rep["sensor"]["accuracy"]["position"] == 0.001 and rep["sensor"]["queries"] > 0
    assert rep["sensor_errors"] is not None  # what the sensor did wrong, listed like the faults


def test_a_noisy_run_of_a_generated_kit_raises_no_failure(generated: tuple[str, str, list[str]]) -> None:
    init, goal, plan = generated
    run = run_plan(plan, init, goal, seed=3, notifier=quiet, sensor_noise=DOCUMENTED)
    assert run.report()["failures"] == [] and run.goal_holds


def test_misdetections_are_looked_for_again_not_diagnosed_missing(small_plan: list[str]) -> None:
    run = run_plan(small_plan, INIT, GOAL, seed=2, notifier=quiet, sensor_noise="misdetection=25%")
    rep = run.report()
    assert sum(e["kind"] == "misdetection" for e in rep["sensor_errors"]) >= 10
    assert rep["failures"] == [] and run.goal_holds


def test_misclassifications_are_not_diagnosed_wrong_sku(small_plan: list[str]) -> None:
    run = run_plan(small_plan, INIT, GOAL, seed=4, notifier=quiet, sensor_noise="position=1mm,misclass=10%")
    rep = run.report()
    assert sum(e["kind"] == "misclassification" for e in rep["sensor_errors"]) >= 3
    assert rep["failures"] == [] and run.goal_holds


def test_faults_are_still_diagnosed_under_noise_and_say_how_sure(small_plan: list[str]) -> None:
    run = run_plan(small_plan, INIT, GOAL, faults=FAULTS + ",wrong-sku@12", seed=1, notifier=quiet,
                   sensor_noise=DOCUMENTED)
    rep = run.report()
    assert [f["mode"] for f in rep["failures"]] == ["missed-grasp", "part-missing-from-tray", "wrong-sku"]
    assert {f["certainty"] for f in rep["failures"]} <= {"certain", "uncertain"}
    assert "certain" in run.why(6)
    q = score_detection([rep])
    assert (q.total.right, q.false_alarm_count) == (3, 0)


# --- detection quality -------------------------------------------------------------------------------

def test_score_detection_counts_per_kind_and_false_alarms() -> None:
    def failure(mode: str, i: int, *objects: str) -> dict:
        return {"mode": mode, "action_index": i, "objects": list(objects)}
    reports = [
        {"injected": [{"kind": "missed-grasp", "action_index": 3, "objects": ["p1"]},
                      {"kind": "part-missing", "action_index": 5, "objects": ["p2"]},
                      {"kind": "part-moved", "action_index": 7, "objects": ["p3"]}],
         "failures": [failure("missed-grasp", 3, "p1", "tray"), failure("dropped-part", 9, "p9")],
         "attempts": 20},
        {"injected": [{"kind": "wrong-sku", "action_index": 2, "objects": ["p4", "sku_b"]}],
         "failures": [failure("missed-grasp", 2, "p4")], "actions": 10,
         "sensor": {"accuracy": SensorNoise(position=0.001).as_dict(), "undecidable": 2}},
    ]
    q = score_detection(reports)
    assert (q.runs, q.actions, q.undecidable) == (2, 30, 2)
    assert q.kinds["missed-grasp"].right == 1 and q.kinds["part-missing"].missed == 1
    assert q.kinds["part-moved"].absorbed == 1 and q.kinds["wrong-sku"].wrong == 1
    assert dict(q.false_alarms) == {"dropped-part": 1}
    assert q.rates()["detection"] == pytest.approx(2 / 3)
