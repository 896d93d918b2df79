"""The main job (``kitkb run``): every stage on every shipped scenario."""

from __future__ import annotations

import io
from pathlib import Path

import pytest

from kb.cli import main
from kb.core.resources import scenario_dirs


@pytest.mark.slow
def test_main_job_builds_every_shipped_scenario(tmp_path: Path) -> None:
    from rdflib.compare import isomorphic

    from generators.pddl import PddlGenerator
    from kb import planning, world
    from kb.io.loader import load_file

    assert main(["run", "-o", str(tmp_path)]) == 0
    for scenario in scenario_dirs():
        target = tmp_path / scenario.name
        init, goal = scenario / "init.ttl", scenario / "goal.ttl"
        # the PDDL kitkb generates, the plan the planner finds for it (validated), and the
        # initial state in the world-model database
        assert [(target / f).read_text() for f in ("domain.pddl", "problem.pddl")] == \
            list(PddlGenerator.from_files([init], [goal], "strips").texts())
        plan = (target / "plan.txt").read_text().splitlines()
        assert plan == planning.plan_files(init, goal, None, None, "strips").lines
        assert plan[-1].startswith("(put-kit ")
        assert isomorphic(world.read_graph(target / "world.sqlite"), load_file(init).graph)


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
