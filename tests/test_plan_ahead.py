"""The planner started ahead (issue 27, "Measure"): ``kitkb run`` makes the planning model and
starts Fast Downward before validating the state files, so that it plans on the other core;
the plan is the one planning afterwards makes, and a state that does not validate stops it."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest

import kb.validation
from kb.core.resources import scenario_dirs
from kb.execution import ClosedLoop, LoopOptions
from kb.execution.inputs import LoopInputs
from kb.planning import planners

SMALL = next(d for d in scenario_dirs() if d.name == "small-kit")
INIT, GOAL = SMALL / "init.ttl", SMALL / "goal.ttl"


@pytest.fixture
def started(monkeypatch: pytest.MonkeyPatch) -> list[Any]:
    """Every planner started ahead (None where none could be)."""
    made: list[Any] = []
    real = planners.start

    def spy(*args: Any, **kw: Any) -> Any:
        made.append(real(*args, **kw))
        return made[-1]

    monkeypatch.setattr(planners, "start", spy)
    return made


def test_the_plan_started_ahead_is_the_plan_made_after(tmp_path: Path, started: list[Any]) -> None:
    result = ClosedLoop(INIT, GOAL, LoopOptions(out_dir=tmp_path / "out", execute=False)).run()
    assert len(started) == 1 and started[0] is not None and started[0].name == "fast-downward"
    assert started[0]._solving.closed and started[0]._solving.process.returncode == 0
    model = LoopInputs.read(INIT, GOAL).model("strips")
    after = planners.run(model.up_problem, tmp_path / "plan.txt")
    assert result.plan.lines == after.lines and result.plan.status == "valid"
    assert (tmp_path / "out" / "plan.txt").read_text() == (tmp_path / "plan.txt").read_text()
    assert result.seconds["plan"] > 0 and result.seconds["pddl"] > 0


def test_a_state_that_does_not_validate_stops_the_planner_started_ahead(
        tmp_path: Path, started: list[Any], monkeypatch: pytest.MonkeyPatch) -> None:
    bad = tmp_path / "bad.ttl"
    bad.write_text(INIT.read_text().replace("hasPoint_X", "hasPoint_x", 1))
    refused = kb.validation.validate([str(bad), str(GOAL)])
    assert not refused.conforms
    monkeypatch.setattr(kb.validation, "validate", lambda *a, **k: refused)  # the good files, said invalid
    result = ClosedLoop(INIT, GOAL, LoopOptions(out_dir=tmp_path / "out")).run()
    assert result.halted == "validate" and result.plan is None and result.model is None
    assert len(started) == 1 and started[0] is not None
    solving = started[0]._solving
    assert solving.closed and solving.process.returncode is not None  # stopped (or done), waited for
    assert not Path(solving._folder.name).exists()
    assert not (tmp_path / "out").exists()  # nothing of the plan written


def test_a_problem_the_planner_refuses_is_not_started_ahead() -> None:
    model = LoopInputs.read(INIT, GOAL).model("strips")
    assert planners.start(model.up_problem, "no-such-planner") is None
    with pytest.raises(Exception, match="not installed"):
        planners.run(model.up_problem, None, "no-such-planner")


def test_not_started_ahead_without_the_patch(monkeypatch: pytest.MonkeyPatch, started: list[Any]) -> None:
    monkeypatch.setenv("KITKB_PATCHES", "0")
    result = ClosedLoop(INIT, GOAL, LoopOptions(execute=False)).run()
    assert started == [None] and result.plan is not None and result.plan.status == "valid"
