"""The closed loop in the library (issue 27, point 6): one orchestration for ``kitkb run``, the
API and the test methods, each input file parsed once, typed events drawn by the CLI."""

from __future__ import annotations

import io
import json
from collections import Counter
from pathlib import Path
from typing import Any

import pytest

import kb.io.loader as loader
from kb.cli import main
from kb.core.resources import scenario_dirs
from kb.execution import ClosedLoop, LoopOptions, run_plan, run_scenario
from kb.execution import events as ev

SMALL = next(d for d in scenario_dirs() if d.name == "small-kit")
INIT, GOAL = SMALL / "init.ttl", SMALL / "goal.ttl"


@pytest.fixture
def parses(monkeypatch: pytest.MonkeyPatch) -> Counter:
    """Every file parsed (its text through the parser), counted by file name."""
    counted: Counter = Counter()
    real = loader.parse_text

    def counting(text: str, fmt: str, path: Path, *args: Any, **kw: Any) -> Any:
        counted[Path(path).name] += 1
        return real(text, fmt, path, *args, **kw)

    monkeypatch.setattr(loader, "parse_text", counting)
    monkeypatch.setattr(loader, "_SHIPPED", {})  # as in a new process: the shipped model read once more
    return counted


def test_kitkb_run_parses_each_input_file_once(tmp_path: Path, parses: Counter) -> None:
    """One `kitkb run` of small-kit: init.ttl, goal.ttl and the domain file each parsed once
    (validation, the planner's facts, the geometry check, the world model, the executor's
    belief and the simulated cell all get what was read); was 9, 8 and 7 times."""
    assert main(["-q", "run", str(INIT), str(GOAL), "-o", str(tmp_path)]) == 0
    assert (parses["init.ttl"], parses["goal.ttl"], parses["kitting-domain.ttl"]) == (1, 1, 1)
    assert parses["kitting.ttl"] == parses["soap.ttl"] == 1  # the model each stage imports: once


def test_run_scenario_parses_each_state_file_once(parses: Counter) -> None:
    run = run_scenario(INIT, GOAL, notifier=lambda who, text: None)
    assert run.goal_holds
    assert (parses["init.ttl"], parses["goal.ttl"], parses["kitting-domain.ttl"]) == (1, 1, 1)


def test_the_loop_tells_its_stages_and_the_executors_events_in_order(tmp_path: Path) -> None:
    seen: list[ev.Event] = []
    notes: list[tuple[str, str]] = []
    options = LoopOptions(faults="missed-grasp@6", seed=1, out_dir=tmp_path, db=tmp_path / "w.sqlite",
                          notifier=lambda who, text: notes.append((who, text)))
    result = ClosedLoop(INIT, GOAL, options, on_event=seen.append).run()
    assert result.ok and result.report()["executed"] is True and "units" in result.report()
    stages = [(type(e).__name__, e.stage) for e in seen if isinstance(e, (ev.StageStarted, ev.StageEnded))]
    assert stages == [(kind, stage) for stage in ev.STAGES for kind in ("StageStarted", "StageEnded")]
    ended = {e.stage: e for e in seen if isinstance(e, ev.StageEnded)}
    assert ended["validate"].result.conforms and ended["geometry"].result.initial_agrees
    assert ended["world"].result.poses > 0 and ended["execute"].result is result.run
    assert (tmp_path / "plan.txt").read_text().splitlines() == list(result.plan.lines)
    # every action started and ended, in pairs; the stable states are the actions done
    actions = [e for e in seen if isinstance(e, (ev.ActionStarted, ev.ActionEnded))]
    assert [type(e) for e in actions] == [ev.ActionStarted, ev.ActionEnded] * (len(actions) // 2)
    assert [e.index for e in actions[::2]] == [e.index for e in actions[1::2]] == list(range(len(actions) // 2))
    done = [e.index for e in actions[1::2] if e.status == "done"]
    assert [e.index for e in seen if isinstance(e, ev.StableState)] == done
    assert [a.index for a in result.run.actions() if a.status == "done"] == done
    # the fault: a failed effect check, diagnosed, notified, retried; then the same action done
    checks = [e for e in seen if isinstance(e, ev.CheckMade)]
    assert len(checks) == len(result.run.record.checks) and [c for c in checks if not c.ok][0].index == 6
    failure = next(e for e in seen if isinstance(e, ev.FailureFound))
    assert (failure.index, failure.phase, failure.mode) == (6, "effect", "missed-grasp")
    after = seen[seen.index(failure):]
    assert isinstance(after[1], ev.Notified) and (after[1].recipient, after[1].message) == notes[0]
    assert any(isinstance(e, ev.Recovered) and e.kind == "retry" and e.index == 6 for e in after)
    assert failure.text() == ("  failure at action 6 ((take-part robot_1 part_a_1 part_a_tray part_gripper), effect): "
                              + ", ".join(failure.violated) + " -> missed-grasp")


def test_a_state_that_does_not_validate_ends_the_loop_at_validation(tmp_path: Path) -> None:
    bad = tmp_path / "init.ttl"
    bad.write_text(INIT.read_text().replace("hasPoint_X", "hasPoint_x", 1))
    seen: list[ev.Event] = []
    result = ClosedLoop(bad, GOAL, LoopOptions(out_dir=tmp_path / "out"), on_event=seen.append).run()
    assert (result.halted, result.executed, result.ok) == ("validate", False, False)
    assert result.report()["executed"] is False and result.report()["reason"].startswith("the state files do not validate")
    assert [e.stage for e in seen] == ["validate", "validate"] and seen[-1].ok is False
    assert not (tmp_path / "out").exists()


def test_run_plan_is_the_loops_execute_stage_with_the_plan_given() -> None:
    plan = run_scenario(INIT, GOAL, notifier=lambda who, text: None).record
    lines = [f"({a.action} {' '.join(x.rsplit('#', 1)[-1] for x in a.args)})" for a in plan.actions]
    seen: list[ev.Event] = []
    said: list[str] = []
    run = run_plan(lines, INIT, GOAL, on_event=seen.append, progress=said.append, notifier=lambda who, text: None)
    assert run.goal_holds
    assert [e.stage for e in seen if isinstance(e, ev.StageStarted)] == ["execute"]
    assert said == [t for e in seen if (t := e.text()) is not None and not isinstance(e, ev.Notified)]
    assert said[0] == f"    0 {lines[0]}  ok" and len(said) == len(lines)


class _Task:
    def __init__(self) -> None:
        self.advanced, self.totals = 0, []

    def advance(self, amount: float = 1) -> None:
        self.advanced += amount

    def update(self, *, completed: Any = None, total: Any = None, description: Any = None) -> None:
        self.totals.append(total)

    def __enter__(self) -> "_Task":
        return self

    def __exit__(self, *exc: object) -> None:
        return None


class _Display:
    enabled = True

    def __init__(self) -> None:
        self.tasks: list[tuple[str, Any, _Task]] = []

    def task(self, description: str, total: Any = None, unit: str = "") -> _Task:
        self.tasks.append((description, total, _Task()))
        return self.tasks[-1][2]


def test_the_cli_draws_the_events_it_is_given_and_parses_no_text(tmp_path: Path) -> None:
    """The run's progress comes from the events' types and fields: an action done advances
    the execution's task, a replan makes its total the actions done plus the new plan's
    (the lines' text plays no part)."""
    from kb.cli.pipeline import RunOptions, _Drawing, _Progress, _Show

    out, display = io.StringIO(), _Display()
    drawing = _Drawing("s", INIT, GOAL, tmp_path, _Progress(out, False, _Show(display=display)), RunOptions())
    drawing(ev.StageStarted("execute", "s", {"actions": 4}))
    for i in range(2):
        drawing(ev.ActionStarted(i, "a", (), "(a)"))
        drawing(ev.ActionEnded(i, "a", (), "(a)", "done"))
    drawing(ev.ActionEnded(2, "a", (), "(a)  ok", "failed"))  # the text is not looked at
    drawing(ev.Replanned(5))
    drawing.close()
    (description, total, task) = display.tasks[0]
    assert (description, total, task.advanced, task.totals) == ("s: executing the plan", 4, 2, [7])
    assert out.getvalue().splitlines() == ["  execute in the simulated cell:", "      0 (a)  ok", "      1 (a)  ok",
                                           "    replanned: 5 actions"]


def test_kitkb_run_format_json_prints_the_loops_report(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    assert main(["run", str(INIT), str(GOAL), "-o", str(tmp_path), "--format", "json",
                 "--faults", "missed-grasp@6", "--seed", "1"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["executed"] is True and data["scenario"] == "small-kit" and data["units"]["length"] == "meter"
    assert [f["mode"] for f in data["failures"]] == ["missed-grasp"]


def test_a_test_method_trial_runs_through_the_loop(monkeypatch: pytest.MonkeyPatch) -> None:
    from kb.testmethod import methods, trial

    runs: list[LoopOptions] = []
    real = ClosedLoop.run

    def run(self: ClosedLoop) -> Any:
        runs.append(self.options)
        return real(self)

    monkeypatch.setattr(ClosedLoop, "run", run)
    job = methods.jobs(methods.Options("basic", trials=1, parts=(4,), seed=5))[0]
    row = trial.run_trial(job)
    assert row["trial"]["error"] is None and row["executed"] is True
    assert [o.execute for o in runs][-1] is True and not any(o.validate or o.geometry for o in runs)
