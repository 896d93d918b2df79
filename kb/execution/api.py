"""The executives' API: run a plan or a scenario, then ask what failed, why, and what was done.

    >>> from kb.execution import run_scenario
    >>> run = run_scenario("ontologies/scenarios/small-kit/init.ttl", "ontologies/scenarios/small-kit/goal.ttl",
    ...                    faults="missed-grasp@6", seed=1)
    >>> run.goal_holds, [f.mode for f in run.failures()]
    (True, ['missed-grasp'])
    >>> print(run.why(6))                                        # doctest: +ELLIPSIS
    action 6 (take-part robot_1 part_a_1 part_a_tray part_gripper) failed its effect check: ...

A :class:`Run` holds the :class:`~kb.execution.records.RunRecord` (actions, checks, commands,
failures, recoveries) and answers queries on it; with a database (``db=``), the same records
are stored beside the world model and :func:`open_run` reads a run back from SQLite or
PostgreSQL (:mod:`kb.execution.store`).
"""

from __future__ import annotations

import dataclasses
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Sequence

from kb.core.errors import InputError
from kb.crcl.cell import CellInterface
from kb.execution.belief import Belief
from kb.execution.executor import Executor, log_notifier
from kb.execution.records import ActionRecord, FailureRecord, RunRecord, local
from kb.metrics.kits import KitScore
from kb.model.definitions import Definitions, load_definitions
from kb.model.failures import FailureModel, load_failure_model
from kb.model.soap import DomainSpec
from kb.planning.problem import ProblemSpec
from kb.spatial.scene import Scene

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


def run_plan(plan: Sequence[str], init: str | Path, goal: str | Path, *, cell: CellInterface | None = None,
             faults: Any = None, seed: int = 0, match_names: bool = False, db: str | Path | None = None,
             replace: bool = False, store: Any = None,
             progress: Callable[[str], None] | None = None, notifier: Callable[[str, str], None] = log_notifier,
             planner: str | None = None, domain_files: Sequence[str | Path] | None = None,
             name: str | None = None, truth: str | Path | None = None, plan_time: float | None = None,
             sensor_noise: Any = None) -> Run:
    """Carry out ``plan`` (PDDL action lines) from the state ``init`` towards ``goal``.

    ``cell``: any :class:`~kb.crcl.cell.CellInterface` (a real cell, :class:`kb.crcl.RemoteCell`);
    default: a simulated cell of ``init`` with ``faults`` (a :class:`kb.sim.FaultSpec` or its
    text, ``"missed-grasp=0.2,part-missing@3"``) and ``seed``. ``db``: a database (SQLite file
    or URL) that gets the initial state and the domain (a database that already holds a world
    model or run history only with ``replace``), then the stable states and the run's records
    (:mod:`kb.execution.store`); or pass an open ``store``. ``truth``: a state file the simulated
    cell holds instead of ``init`` (the same objects placed and turned otherwise: the first
    paper's "the actual location of the kit tray and parts supplies will not be known before
    runtime"); the executor starts from ``init``, the nominal layout, and finds the objects by
    sensing. ``plan_time``: the seconds the plan took to make (a metric of the run).
    ``sensor_noise``: the sensor's accuracy (a :class:`kb.sim.noise.SensorNoise` or its text,
    ``"position=1mm,orientation=0.5deg,misdetection=0.01"``), over the sensor individual of
    ``init`` (:meth:`SensorNoise.from_scene <kb.sim.noise.SensorNoise.from_scene>`): the
    simulated cell's sensor has it, and the executor verifies with it (docs/execution.md,
    "Sensing with noise"); with another ``cell``, what the executor assumes of its sensor.

    It is :func:`read_inputs`, the cell made, then :func:`execute_plan`.
    """
    inputs = read_inputs(init, goal, domain_files=domain_files, match_names=match_names)
    accuracy = sensor_accuracy(inputs.scene, sensor_noise)
    if cell is None:
        from kb.sim import FaultSpec, SimulatedCell  # imported only when no cell is given
        spec_f = FaultSpec.parse(faults, seed=seed) if isinstance(faults, str) else faults
        cell = SimulatedCell(Scene.from_files([truth or init], declared=[goal], match_names=match_names),
                             faults=spec_f, seed=seed, **({"noise": accuracy} if accuracy is not None else {}))
    own_store = None
    if db is not None and store is None:
        from kb.execution.store import RunStore, prepare
        prepare(db, init, domain_files, replace=replace)
        store = own_store = RunStore(db)
    record = RunRecord(name or Path(init).resolve().parent.name, seed, plan_time=plan_time)
    try:
        return execute_plan(plan, cell, inputs, record, accuracy=accuracy, store=store, paths=(init, goal),
                            notifier=notifier, progress=progress, planner=planner)
    finally:  # interrupted too: the store ended the run at its last stable state
        if own_store is not None:
            own_store.close()


@dataclass(frozen=True)
class PlanInputs:
    """What :func:`run_plan` reads from its files before it runs a plan: the domain and the
    problem (numeric encoding), the initial state's scene (the executor's first belief), the
    predicate definitions and the failure modes. A caller that runs many plans of one design
    (``kb.testmethod``) reads them once and passes them to :func:`execute_plan`."""

    domain: DomainSpec
    problem: ProblemSpec
    scene: Scene
    definitions: Definitions
    failures: FailureModel


def read_inputs(init: str | Path, goal: str | Path, *, domain_files: Sequence[str | Path] | None = None,
                match_names: bool = False) -> PlanInputs:
    """The :class:`PlanInputs` of the state files ``init`` and ``goal``."""
    from kb.planning.model import read_specs
    domain, problem = read_specs([init], [goal], encoding="numeric", domain_files=domain_files,
                                 match_names=match_names)
    scene = Scene.from_files([init], declared=[goal], match_names=match_names)
    return PlanInputs(domain, problem, scene, load_definitions(domain_files), load_failure_model(domain_files))


def execute_plan(plan: Sequence[str], cell: CellInterface, inputs: PlanInputs, record: RunRecord, *,
                 accuracy: Any = None, store: Any = None, paths: tuple[Any, Any] = (None, None),
                 notifier: Callable[[str, str], None] = log_notifier, progress: Callable[[str], None] | None = None,
                 planner: str | None = None) -> Run:
    """Carry out ``plan`` on ``cell`` from ``inputs`` (the second half of :func:`run_plan`,
    once its files are read): the executor's run into ``record``, then what a simulated cell
    knows that the executor does not (the faults it injected, its sensor's mistakes with a
    noisy ``accuracy``, the constraints the robot violated). ``store``: an open run store that
    gets the run (begun with ``paths``, the state files; ended when the run ends, interrupted
    too)."""
    executor = Executor(cell, inputs.domain, inputs.problem, inputs.definitions, inputs.failures,
                        Belief(inputs.scene), store=store, notifier=notifier, progress=progress, planner=planner,
                        record=record, accuracy=accuracy)
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
    if store is not None:
        store.end_run(record)
    return Run(record)


def note_ground_truth(record: RunRecord, cell: Any, accuracy: Any = None) -> None:
    """``record`` gets what a simulated ``cell`` did that the executor was not told: the faults
    it injected, what its sensor got wrong (with a noisy ``accuracy``), the constraints the
    robot violated. A cell without them (a real one) leaves the record as it is."""
    injected = getattr(cell, "injected", None)
    if injected is not None:
        record.injected = [{"kind": x.kind, "action_index": x.action_index, "objects": [local(o) for o in x.objects],
                            "detail": x.detail} for x in injected]
    errors = getattr(getattr(cell, "sensor", None), "errors", None)
    if accuracy is not None and not accuracy.zero and isinstance(errors, list):
        record.sensor_errors = [e.as_dict() for e in errors]
    violations = getattr(cell, "violations", None)
    if violations is not None:
        record.violations = [_as_data(v) for v in violations]


def sensor_accuracy(scene: Scene, sensor_noise: Any) -> Any:
    """The sensor's accuracy: ``sensor_noise`` (a SensorNoise or its text) over the sensor
    individual of the state of ``scene``; None when neither is given (kb.sim imported only then)."""
    from kb.sim.noise import SENSOR_OF, SensorNoise
    if sensor_noise is None and SENSOR_OF not in scene.facts and not any(
            "PoseSensor" in str(c) for cs in scene.classes for c in cs):
        return None
    try:
        base = SensorNoise.from_scene(scene)
    except ValueError as exc:
        raise InputError(str(exc), scene.path) from None
    if isinstance(sensor_noise, str):
        try:
            return SensorNoise.parse(sensor_noise, base)
        except ValueError as exc:
            raise InputError(f"sensor noise: {exc}") from None
    return sensor_noise if sensor_noise is not None else base


def _as_data(record: Any) -> dict[str, Any]:
    """A cell's record of a violation as JSON data (object names by local name)."""
    data = dict(record) if isinstance(record, dict) else dataclasses.asdict(record)
    if "objects" in data:
        data["objects"] = [local(o) for o in data["objects"]]
    return data


def open_run(url: str | Path, run_id: int | None = None) -> Run:
    """A run recorded in a world-model database (the latest one by default), to query."""
    from kb.execution.store import read_run
    return Run(read_run(url, run_id))


def run_scenario(init: str | Path, goal: str | Path, **kw: Any) -> Run:
    """Plan from ``init`` to ``goal`` with a real planner, then :func:`run_plan` it."""
    from kb import planning
    t = time.perf_counter()
    model = planning.kitting_model([init], [goal], "strips", match_names=kw.get("match_names", False),
                                   domain_files=kw.get("domain_files"))
    plan = planning.run(model.up_problem, None, kw.get("planner")).lines
    kw.setdefault("plan_time", time.perf_counter() - t)
    run = run_plan(plan, init, goal, **kw)
    run.record.started = min(run.record.started, t)
    return run
