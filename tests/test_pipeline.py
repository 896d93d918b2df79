"""The main job (``kitkb run``): every stage on every shipped scenario."""

from __future__ import annotations

import io
import json
import sqlite3
from pathlib import Path

import pytest

from kb.cli import main
from kb.core.resources import scenario_dirs


@pytest.mark.slow
def test_main_job_builds_every_shipped_scenario(tmp_path: Path) -> None:
    from rdflib.namespace import RDF

    from generators.pddl import PddlGenerator
    from kb.core.namespaces import SOAP
    from kb.core.resources import ontology_path
    from kb import planning, world
    from kb.io.loader import load_file

    report = tmp_path / "report.json"
    assert main(["run", "-o", str(tmp_path), "--report", str(report)]) == 0
    data = json.loads(report.read_text())
    assert data["goal_holds"] is True and data["failures"] == [] and data["injected"] == []
    assert sorted(r["scenario"] for r in data["runs"]) == sorted(s.name for s in scenario_dirs())
    for scenario in scenario_dirs():
        target = tmp_path / scenario.name
        init, goal = scenario / "init.ttl", scenario / "goal.ttl"
        # the PDDL kitkb generates, the plan the planner finds for it (validated), and the
        # initial state in the world-model database
        assert [(target / f).read_text() for f in ("domain.pddl", "problem.pddl")] == \
            list(PddlGenerator.from_files([init], [goal], "strips").texts())
        plan = (target / "plan.txt").read_text().splitlines()
        assert plan == planning.plan_files(init, goal, None, None, "strips").lines
        last_kit = max(i for i, line in enumerate(plan) if line.startswith("(put-kit "))
        # after the last kit is in its box, at most the effector goes back to its holder (goal facts)
        assert all(line.startswith("(remove-endeffector ") for line in plan[last_kit + 1:])
        # the world model: the initial state and the domain's SOAP individuals, then the run:
        # one stable state per action, the run's record with the goal reached
        held = world.read_graph(target / "world.sqlite")
        start = load_file(init).graph
        assert {s for s in start.subjects() if "_point" not in str(s) and "_axis" not in str(s)} <= set(held.subjects())
        modes = set(load_file(ontology_path("kitting-domain.ttl")).graph.subjects(RDF.type, SOAP.FailureMode))
        assert modes and modes == set(held.subjects(RDF.type, SOAP.FailureMode))
        with sqlite3.connect(target / "world.sqlite") as db:
            (goal_holds, stopped), = db.execute("SELECT goal_holds, stopped FROM kitkb_run").fetchall()
            stable = int(db.execute("SELECT value FROM kitkb_meta WHERE key = 'stable_state'").fetchone()[0])
        assert (goal_holds, stopped) == (1, None) and stable == len(plan)


def test_main_job_reports_a_broken_scenario(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """A scenario that does not validate stops at validation and the job exits 1."""
    import kb.cli.pipeline as pipeline

    bad = tmp_path / "scenarios" / "broken"
    bad.mkdir(parents=True)
    good = scenario_dirs()[0]
    (bad / "init.ttl").write_text((good / "init.ttl").read_text().replace("hasPoint_X", "hasPoint_x", 1))
    (bad / "goal.ttl").write_text((good / "goal.ttl").read_text())
    monkeypatch.setattr(pipeline, "scenario_dirs", lambda: [bad])
    out = io.StringIO()
    assert pipeline.run_main_job(out, tmp_path / "out") == 1
    text = out.getvalue()
    assert "did you mean ktw:hasPoint_X?" in text and "found problems" in text
    assert not (tmp_path / "out" / "broken" / "plan.txt").exists()


def test_a_run_started_inside_the_scenario_folder_is_named_by_it(tmp_path: Path,
                                                                   monkeypatch: pytest.MonkeyPatch) -> None:
    """`kitkb run init.ttl goal.ttl` from inside the folder: the scenario is the folder's name
    (its outputs in their own folder, the report's `scenario`), not an empty name."""
    small = next(d for d in scenario_dirs() if d.name == "small-kit")
    monkeypatch.chdir(small)
    report = tmp_path / "run.json"
    assert main(["-q", "run", "init.ttl", "goal.ttl", "-o", str(tmp_path / "out"), "--report", str(report)]) == 0
    assert json.loads(report.read_text())["scenario"] == "small-kit"
    assert (tmp_path / "out" / "small-kit" / "plan.txt").is_file()
