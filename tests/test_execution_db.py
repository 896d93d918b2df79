"""A run in the world-model database: stable states, records, and what an interrupted run leaves."""

from __future__ import annotations

import os
import signal
import sqlite3
import subprocess
import sys
import time
from pathlib import Path

import pytest

from kb.core.resources import ontology_path
from kb.execution import open_run, run_scenario
from kb.execution.records import without_timings
from kb.world import WorldModel

SCENARIO = Path(ontology_path("kitting-domain.ttl")).parent / "scenarios" / "two-designs"
INIT, GOAL = SCENARIO / "init.ttl", SCENARIO / "goal.ttl"
KITKB = [sys.executable, "-m", "kb.cli"]


def _stable(db: Path) -> int:
    with sqlite3.connect(db) as c:
        return int(c.execute("SELECT value FROM kitkb_meta WHERE key = 'stable_state'").fetchone()[0])


def test_a_run_commits_one_stable_state_per_action_and_records_failures_by_key(tmp_path: Path) -> None:
    db = tmp_path / "w.sqlite"
    run = run_scenario(INIT, GOAL, faults="part-missing@6", seed=2, db=db, notifier=lambda *a: None)
    assert run.goal_holds
    assert _stable(db) == sum(1 for a in run.record.actions if a.status == "done")
    with sqlite3.connect(db) as c:
        rows = c.execute("SELECT m.name, p.name, a.name FROM soap_action_failure f "
                         "JOIN kitkb_thing m ON m.id = f.failure_mode_id JOIN kitkb_thing p ON p.id = f.phase_id "
                         "JOIN kitkb_thing a ON a.id = f.action_id").fetchall()
        atoms = c.execute("SELECT t.name FROM soap_has_action_failure_violated_atom v "
                          "JOIN kitkb_thing t ON t.id = v.value_id").fetchall()
    assert rows == [("part-missing-from-tray", "PreconditionCheck", "take-part")]
    assert atoms == [("take-part_pre_part-location-partstray",)]
    back = open_run(db)
    assert [(f.action_index, f.mode, f.recovery, f.outcome) for f in back.failures()] == \
        [(f.action_index, f.mode, f.recovery, f.outcome) for f in run.failures()]
    assert back.goal_holds and back.why(6) == run.why(6)
    # the database's poses are the last stable state: where the sensor saw things at the end
    placed = [a.args[1] for a in run.record.actions if a.action == "put-part" and a.status == "done"]
    with WorldModel(db) as world:
        start = {p: float(world.global_pose(p.rsplit("#", 1)[-1])[2, 3]) for p in placed}
    assert run.record.actions[-1].action == "remove-endeffector"  # the tray gripper back: a goal fact
    assert all(z < 0.5 for z in start.values())  # on the parts table (0.75 m) at first, now in a box on the floor


def test_a_database_holding_a_world_is_not_replaced_without_asking(tmp_path: Path) -> None:
    from kb.core.errors import InputError
    db = tmp_path / "w.sqlite"
    run_scenario(INIT, GOAL, db=db, notifier=lambda *a: None)
    before = _stable(db)
    with pytest.raises(InputError, match="already holds the world model"):
        run_scenario(INIT, GOAL, db=db, notifier=lambda *a: None)
    assert _stable(db) == before and open_run(db).goal_holds
    run_scenario(INIT, GOAL, db=db, replace=True, notifier=lambda *a: None)
    with sqlite3.connect(db) as c:
        assert c.execute("SELECT count(*) FROM kitkb_run").fetchone() == (1,)


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGKILL])
def test_an_interrupted_run_leaves_the_last_stable_state(tmp_path: Path, sig: int) -> None:
    """Killed while it runs, the database holds a committed stable state and a readable world."""
    db = tmp_path / "w.sqlite"
    proc = subprocess.Popen(KITKB + ["run", str(INIT), str(GOAL), "--db", str(db), "-o", str(tmp_path / "out"),
                                     "--faults", "missed-grasp=0.3", "--seed", "5"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            env={**os.environ, "PYTHONUNBUFFERED": "1"})  # each action's line as it is done
    seen = ""
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline:  # wait until some actions were carried out
        line = proc.stdout.readline()
        seen += line
        if line.strip().startswith("10 ") or not line:
            break
    if proc.poll() is not None:  # a loaded machine: the run wrote ahead into the pipe and ended before we read
        pytest.skip("the run ended before the signal could be sent (the reader fell behind the pipe)")
    os.kill(proc.pid, sig)
    out, err = proc.communicate(timeout=60)
    assert "10 (" in seen, seen + out + err
    assert proc.returncode == (130 if sig == signal.SIGINT else -signal.SIGKILL)
    with sqlite3.connect(db) as c:
        assert c.execute("PRAGMA integrity_check").fetchone() == ("ok",)
        runs = c.execute("SELECT stopped FROM kitkb_run").fetchall()
    assert runs == ([("interrupted",)] if sig == signal.SIGINT else [(None,)])
    stable = _stable(db)
    assert stable >= 10
    with WorldModel(db) as world:
        assert len(world.global_poses()) > 20  # every pose still reads


@pytest.mark.postgres
def test_a_run_on_postgresql_records_the_same_as_on_sqlite(tmp_path: Path) -> None:
    url = os.environ.get("KITKB_PG_URL")
    if not url:
        pytest.skip("KITKB_PG_URL is not set")
    from kb import world
    world.drop_all(url)
    try:
        pg = run_scenario(INIT, GOAL, faults="missed-grasp@6,part-missing@9", seed=1, db=url, notifier=lambda *a: None)
        lite = run_scenario(INIT, GOAL, faults="missed-grasp@6,part-missing@9", seed=1, db=tmp_path / "w.sqlite",
                            notifier=lambda *a: None)
        back = open_run(url)
        assert back.goal_holds and [(f.action_index, f.mode, f.recovery) for f in back.failures()] == \
            [(f.action_index, f.mode, f.recovery) for f in lite.failures()] == \
            [(f.action_index, f.mode, f.recovery) for f in pg.failures()]
        with WorldModel(url) as wm:
            assert wm.stable_state() == sum(1 for a in pg.record.actions if a.status == "done")
        # the metrics and kit scores read back equal the run's, and SQLite's
        assert back.kit_scores == pg.kit_scores and [k.score - k.max_score for k in pg.kit_scores] == [0, 0]
        assert without_timings(back.report())["metrics"] == without_timings(pg.report())["metrics"] == \
            without_timings(lite.report())["metrics"]
    finally:
        world.drop_all(url)
