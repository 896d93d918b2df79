"""Fault campaigns never crash: what long seeded campaigns found, kept as regressions
(benchmarks/bench_campaign.py runs the campaign itself)."""

from __future__ import annotations

import json
import sqlite3
from pathlib import Path

import numpy as np

from kb.cli import main
from kb.core.resources import ontology_path
from kb.execution import run_scenario
from kb.execution.store import RunStore

INIT, GOAL = ontology_path("scenarios/small-kit/init.ttl"), ontology_path("scenarios/small-kit/goal.ttl")
PART = "https://w3id.org/kitkb/scenario/small-kit#part_a_1"
#: part_a_1 shifts within its tray at take-part 6 (its new pose is queued for the next stable
#: state), the grasp misses, and at the retry (action 7) the part is gone: the belief makes its
#: pose NaN. Before the run store copied the poses it queued, that NaN reached the next stable
#: state: exit 2, "pose of part_a_1: a pose must be a finite 4x4 matrix", run lost.
FAULTS, SEED = "part-moved@6,missed-grasp@6,part-missing@7", 2


def test_a_part_that_moved_then_vanished_before_a_stable_state_does_not_crash_the_run(tmp_path: Path) -> None:
    db = tmp_path / "w.sqlite"
    run = run_scenario(INIT, GOAL, faults=FAULTS, seed=SEED, db=db, notifier=lambda *a: None)
    injected = {x["kind"]: x for x in run.record.injected}
    assert injected["part-moved"]["detail"].startswith("shifted within"), "the seed no longer makes this case"
    assert set(injected) == {"part-moved", "missed-grasp", "part-missing"}
    assert [(f.action_index, f.mode) for f in run.failures()] == [(6, "missed-grasp"), (7, "part-missing-from-tray")]
    assert run.goal_holds and run.stopped is None
    with sqlite3.connect(db) as c:  # a stable state per action done, every stored pose number finite
        stable = int(c.execute("SELECT value FROM kitkb_meta WHERE key = 'stable_state'").fetchone()[0])
        values = [v for row in c.execute("SELECT x, y, z FROM ktw_point UNION ALL SELECT i, j, k FROM ktw_vector")
                  for v in row]
    assert stable == sum(1 for a in run.record.actions if a.status == "done")
    assert values and all(v is not None and np.isfinite(float(v)) for v in values)


def test_the_run_store_keeps_the_poses_it_was_given_not_the_callers_arrays(tmp_path: Path) -> None:
    from kb.execution.store import prepare
    db = tmp_path / "w.sqlite"
    prepare(db, INIT, None)
    store = RunStore(db)
    try:
        belief = np.stack([np.eye(4)] * 2)
        belief[0, :3, 3] = (0.2, 0.9, 0.75)
        store.poses_changed({PART: belief[0]})
        belief[0] = np.nan  # the caller's belief changes afterwards (the part is gone)
        assert np.isfinite(store.pending[PART]).all()
        np.testing.assert_array_equal(store.pending[PART][:3, 3], (0.2, 0.9, 0.75))
    finally:
        store.close()


def test_kitkb_run_of_that_case_exits_0_with_a_report(tmp_path: Path) -> None:
    report = tmp_path / "r.json"
    code = main(["run", str(INIT), str(GOAL), "--faults", FAULTS, "--seed", str(SEED), "--report", str(report),
                 "-o", str(tmp_path / "out"), "-q"])
    assert code == 0
    assert json.loads(report.read_text())["goal_holds"] is True


def test_an_internal_error_during_execution_stops_the_run_for_the_operator(tmp_path: Path, monkeypatch) -> None:
    """A fault of kitkb's own in the middle of a run (here: computing a motion target fails at
    the fourth computation) is not reported as bad input nor as a crash: the run stops for the
    operator with the reason, kitkb run exits 1 and writes its report."""
    from kb.execution import targets

    real, calls = targets.Targets.compute, []

    def failing(self, expr, args):  # noqa: ANN001, ANN202
        calls.append(expr)
        if len(calls) == 4:
            raise ZeroDivisionError("a bug")
        return real(self, expr, args)

    monkeypatch.setattr(targets.Targets, "compute", failing)
    report = tmp_path / "r.json"
    assert main(["run", str(INIT), str(GOAL), "-o", str(tmp_path / "out"), "--report", str(report), "-q"]) == 1
    data = json.loads(report.read_text())
    assert data["executed"] and data["goal_holds"] is False
    assert data["stopped"].startswith("stopped for the operator: internal error at action ")
    assert "ZeroDivisionError: a bug" in data["stopped"]
