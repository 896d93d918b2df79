"""The executives' API: run a plan or a scenario, then ask what failed, why, and what was done.

    >>> from kb.execution import run_scenario
    >>> run = run_scenario("ontologies/scenarios/small-kit/init.ttl", "ontologies/scenarios/small-kit/goal.ttl",
    ...                    faults="missed-grasp@6", seed=1)
    >>> run.goal_holds, [f.mode for f in run.failures()]
    (True, ['missed-grasp'])
    >>> print(run.why(6))                                        # doctest: +ELLIPSIS
    action 6 (take-part robot_1 part_a_1 part_a_tray part_gripper) failed its effect check: ...

:func:`run_scenario` and :func:`run_plan` are the closed loop's (:mod:`kb.execution.loop`);
this module has what they return and share. A :class:`Run` holds the :class:`~kb.execution.records.RunRecord` (actions, checks, commands,
failures, recoveries) and answers queries on it; with a database (``db=``), the same records
are stored beside the world model and :func:`open_run` reads a run back from SQLite or
PostgreSQL (:mod:`kb.execution.store`).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Sequence

from kb.cells.accuracy import SensorAccuracy, assumed_accuracy
from kb.core.errors import InputError
from kb.crcl.cell import CellInterface, has, require
from kb.execution.belief import Belief
from kb.execution.events import Event
from kb.execution.executor import Executor, log_notifier
from kb.execution.inputs import PlanInputs
from kb.execution.records import ActionRecord, FailureRecord, RunRecord, local
from kb.execution.scoring import note_buildable
from kb.metrics.kits import KitScore
from kb.spatial.scene import Scene

__all__ = ["PlanInputs", "Run", "execute_plan", "note_ground_truth", "open_run", "sensor_accuracy"]


@dataclass
class Run:
    """One executed run and the queries executives ask of it."""

    record: RunRecord

    @property
    def goal_holds(self) -> bool:
        return bool(self.record.goal_holds)

    @property
    def stopped(self) -> str | None:
        return self.record.stopped

    @property
    def metrics(self) -> dict[str, Any]:
        """The execution metrics (the first paper's §IV-B): failures, failures per kit,
        recovered failure modes, plan time and replans, contact errors and other constraint
        violations (a simulated cell's ground truth), the static metrics of the CRCL sent."""
        return self.record.metrics()

    @property
    def kit_scores(self) -> list[KitScore]:
        """Each goal kit's score, with the predicate and objects behind every point lost."""
        return list(self.record.kits)

    def failures(self, *, kit: str | None = None, action: str | None = None, predicate: str | None = None,
                 mode: str | None = None, since: float | None = None, until: float | None = None) -> list[FailureRecord]:
        """Failures of the run, filtered: ``kit`` (local name or IRI) the failed action worked for
        (its argument, or the kit its part or kit tray was planned for), ``action`` name, a violated ``predicate``, failure ``mode`` name, and a time
        window in seconds since the run started."""
        out = []
        t0 = self.record.started
        for f in self.record.failures:
            if kit is not None and local(f.kit or "") != local(kit) and not any(local(a) == local(kit) for a in f.args):
                continue
            if action is not None and f.action != action:
                continue
            if predicate is not None and not any(a.predicate == predicate for a in f.violated):
                continue
            if mode is not None and f.mode != mode:
                continue
            if since is not None and f.time - t0 < since:
                continue
            if until is not None and f.time - t0 > until:
                continue
            out.append(f)
        return out

    def history(self) -> list[dict[str, Any]]:
        """Everything in order: actions (with their commands), checks, failures and recoveries."""
        t0 = self.record.started
        events: list[tuple[float, int, dict[str, Any]]] = []
        for a in self.record.actions:
            events.append((a.started - t0, 0, {"kind": "action", "index": a.index, "action": a.action,
                                               "args": [local(x) for x in a.args], "status": a.status,
                                               "commands": list(a.commands)}))
        for c in self.record.checks:
            events.append((c.time - t0, 1, {"kind": "check", "index": c.action_index, "phase": c.phase,
                                            "ok": c.ok, "violated": [a.text() for a in c.violated]}))
        for f in self.record.failures:
            events.append((f.time - t0, 2, {"kind": "failure", "index": f.action_index, "mode": f.mode,
                                            "recovery": f.recovery, "outcome": f.outcome}))
        events.sort(key=lambda e: (e[0], e[1]))
        return [dict(e[2], time=round(e[0], 6)) for e in events]

    def why(self, action_index: int) -> str:
        """Why action ``action_index`` failed: the violated predicates, the objects, where they
        were expected and where they were seen, the diagnosis and the recovery."""
        found = [f for f in self.record.failures if f.action_index == action_index]
        if not found:
            done = [a for a in self.record.actions if a.index == action_index]
            if not done:
                raise InputError(f"the run has no action {action_index}")
            return f"action {action_index} ({done[0].action}) did not fail: {done[0].status}"
        return "\n\n".join(f.why() for f in found)

    def actions(self) -> list[ActionRecord]:
        return list(self.record.actions)

    def report(self) -> dict[str, Any]:
        """The JSON report (``goal_holds``, ``injected``, ``failures``, counts)."""
        return self.record.report()


def execute_plan(plan: Sequence[str], cell: CellInterface, inputs: PlanInputs, record: RunRecord, *,
                 accuracy: SensorAccuracy | None = None, store: Any = None, paths: tuple[Any, Any] = (None, None),
                 notifier: Callable[[str, str], None] = log_notifier, progress: Callable[[str], None] | None = None,
                 planner: str | None = None, on_event: Callable[[Event], None] | None = None,
                 partial_kits: str | None = None) -> Run:
    """Carry out ``plan`` on ``cell`` from ``inputs`` (the second half of :func:`run_plan`,
    once its files are read): the executor's run into ``record``, then what a simulated cell
    knows that the executor does not (the faults it injected, its sensor's mistakes with a
    noisy ``accuracy``, the constraints the robot violated). ``store``: an open run store that
    gets the run (begun with ``paths``, the state files; ended when the run ends, interrupted
    too). ``on_event``: the executor's events (:mod:`kb.execution.events`); ``progress``: their
    lines. The closed loop (:mod:`kb.execution.loop`) makes ``inputs`` and ``cell`` and calls this."""
    executor = Executor(cell, inputs.domain, inputs.problem, inputs.definitions, inputs.failures,
                        Belief(inputs.scene), store=store, notifier=notifier, progress=progress, planner=planner,
                        record=record, accuracy=accuracy, on_event=on_event)
    executor.partial_kits = partial_kits  # None: the domain's policy (kb.execution.partial)
    require(cell, executor.needs(executor.parse_plan(list(plan))), "the plan")  # refused before the store hears of it
    if store is not None:
        store.begin_run(record, *paths)
    try:
        executor.run(list(plan))
    except KeyboardInterrupt:  # the database keeps its last stable state; the run says why it ended
        record.stopped = "interrupted"
        if store is not None:
            store.end_run(record)
        raise
    note_ground_truth(record, cell, accuracy)
    note_buildable(record, cell, inputs.scene, inputs.problem)  # the oracle of what was buildable
    if store is not None:
        store.end_run(record)
    return Run(record)


def note_ground_truth(record: RunRecord, cell: Any, accuracy: SensorAccuracy | None = None) -> None:
    """``record`` gets what a simulated ``cell`` did that the executor was not told: the faults
    it injected, what its sensor got wrong (with a noisy ``accuracy``), the constraints the
    robot violated. A cell without :class:`~kb.crcl.cell.GroundTruth` (a real one) leaves the
    record as it is."""
    if not has(cell, "ground-truth"):
        return
    record.injected = [{"kind": x.kind, "action_index": x.action_index, "objects": [local(o) for o in x.objects],
                        "detail": x.detail} for x in cell.injected]
    if accuracy is not None and not accuracy.zero:
        record.sensor_errors = [e.as_dict() for e in cell.sensor_errors]
    record.violations = [_as_data(v) for v in cell.violations]


def sensor_accuracy(scene: Scene, sensor_noise: SensorAccuracy | str | None) -> SensorAccuracy | None:
    """The sensor's accuracy: ``sensor_noise`` (a :class:`~kb.cells.accuracy.SensorAccuracy` or
    its text) over the sensor individual of the state of ``scene``; None when neither is given
    (:func:`kb.cells.accuracy.assumed_accuracy`)."""
    return assumed_accuracy(scene, sensor_noise)


def _as_data(record: Any) -> dict[str, Any]:
    """A cell's record of a violation as JSON data (object names by local name)."""
    data = dict(record) if isinstance(record, dict) else dataclasses.asdict(record)
    if "objects" in data:
        data["objects"] = [local(o) for o in data["objects"]]
    return data


def open_run(url: str | Path, run_id: int | None = None) -> Run:
    """A run recorded in a world-model database (the latest one by default), to query: its
    record equal, field for field, to the run's when it was recorded (each row holds its
    record's dict form, :mod:`kb.execution.codec`; a run of an older kitkb: what its columns
    kept). A database without runs, a run it does not hold, or a row that is not a record:
    :class:`~kb.core.errors.InputError` in one line."""
    from kb.execution.store import read_run
    return Run(read_run(url, run_id))
