"""The closed loop, once: validate -> plan -> geometry check -> world model -> execute.

:class:`ClosedLoop` is the one orchestration of kitkb's loop; ``kitkb run`` (:mod:`kb.cli.pipeline`),
the Python API (:func:`run_scenario`, :func:`run_plan`) and the test methods
(:mod:`kb.testmethod.trial`) all run it, each with the stages it wants (:class:`LoopOptions`):

1. ``validate``: the state files, closed world (:func:`kb.validation.validate`); errors end the loop;
   ``locate`` (only for an initial state that leaves objects unlocated, :mod:`kb.spatial.unlocated`):
   the cell is opened and its sensor finds them (:mod:`kb.execution.locate`); the loop goes on
   from the state with them placed (``init-sensed.ttl`` in ``out_dir``);
2. ``pddl``: the planning model (and ``domain.pddl``, ``problem.pddl`` with ``out_dir``);
3. ``plan``: a validated plan by a real planner (``plan.txt``); no plan ends the loop;
4. ``geometry``: the predicates decided from the initial state's boxes equal the PDDL facts
   (:func:`kb.planning.geometry.agreement`); a disagreement ends the loop;
5. ``world``: the initial state and the domain loaded into the world-model database ``db``,
   the global poses read back;
6. ``execute``: the plan carried out on the cell, every action checked from geometry
   (:func:`kb.execution.api.execute_plan`).

Each input file is parsed once (:class:`~kb.execution.inputs.LoopInputs`) and what is made of
it is handed to every stage. The loop tells ``on_event`` what happens as typed events
(:mod:`kb.execution.events`): each stage started and ended with its result, and inside the
``execute`` stage the executor's actions, checks, failures, recoveries, replans, stable states
and notifications. :class:`LoopResult` is what the loop made; :meth:`LoopResult.report` is the
scenario's report (``kitkb run --report``).
"""

from __future__ import annotations

import gc
import time
from collections import Counter
from contextlib import ExitStack
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Sequence

from kb.core.errors import NotSolvableError
from kb.core.namespaces import local_name
from kb.core.memory import gc_paused
from kb.core.progress import SILENT, Progress
from kb.crcl.cell import CellInterface
from kb.execution.api import Run, execute_plan, sensor_accuracy
from kb.execution.events import Event, Listener, Notified, StageEnded, StageStarted, WorldLoaded, ignore
from kb.execution.executor import log_notifier
from kb.execution.inputs import LoopInputs, PlanInputs
from kb.execution.records import RunRecord
from kb.model.faults import fault_kinds
from kb.spatial.scene import Scene


@dataclass
class LoopOptions:
    """Which stages run and how.

    ``validate``, ``geometry``, ``execute``: run those stages; ``out_dir``: where ``domain.pddl``,
    ``problem.pddl`` and ``plan.txt`` go (None: nowhere); ``db``: the world-model database
    (SQLite file or URL; the ``world`` stage runs only with one; a database that already
    holds a world model or run history only with ``replace``), or an open run ``store``.
    ``cell``: a :class:`~kb.crcl.cell.CellInterface`, a cell's address (``HOST:PORT``), or
    None: a simulated cell of the initial state (or of ``truth``: a state file or scene of the
    same objects placed otherwise) with ``faults`` and ``seed``; ``sensor_noise``: the
    sensor's accuracy (``kb.execution.api.sensor_accuracy``)."""

    faults: Any = None
    seed: int = 0
    cell: Any = None
    match_names: bool = False
    domain_files: Sequence[str | Path] | None = None
    sensor_noise: Any = None
    planner: str | None = None
    truth: str | Path | Scene | None = None
    validate: bool = True
    geometry: bool = True
    #: carry the plan out (False: the loop ends after the plan and the checks, the result has them)
    execute: bool = True
    out_dir: str | Path | None = None
    db: str | Path | None = None
    replace: bool = False
    store: Any = None
    notifier: Callable[[str, str], None] = log_notifier
    name: str | None = None
    #: the run's clock starts when planning starts (its timeline shows the planning time)
    clock_from_plan: bool = False
    #: what the executor does with a kit the usable parts cannot finish (``deliver`` | ``leave``;
    #: None: the domain's soap:hasExecutionPolicy_PartialKits; kb.execution.partial)
    partial_kits: str | None = None


@dataclass
class LoopResult:
    """What a closed loop made: each stage's result, and where and why it stopped short."""

    scenario: str
    validation: Any = None
    model: Any = None
    plan: Any = None  # a PlanResult (None when the plan was given)
    agreement: Any = None
    world: WorldLoaded | None = None
    run: Run | None = None
    units: Any = None  # the world model's units (with a database)
    #: the stage that ended the loop before execution, and why (the report's reason)
    halted: str | None = None
    reason: str | None = None
    located: Any = None  # the locate stage's kb.execution.locate.Located (None: every object was located)
    error: Exception | None = None  # what the planner raised when there is no plan
    seconds: dict[str, float] = field(default_factory=dict)

    @property
    def executed(self) -> bool:
        return self.run is not None

    @property
    def goal_holds(self) -> bool:
        return self.run is not None and self.run.goal_holds

    @property
    def ok(self) -> bool:
        """The plan was carried out, the goal holds and nothing stopped the run."""
        return self.goal_holds and self.run is not None and self.run.stopped is None

    def report(self) -> dict[str, Any]:
        """The scenario's report: the run's (``executed`` True, the world model's ``units``
        with a database), or why it was not executed."""
        if self.run is None:
            data = {"scenario": self.scenario, "executed": False, "reason": self.reason, "goal_holds": False,
                    "stopped": None, "injected": [], "failures": []}
        else:
            data = {"executed": True, **self.run.report()}
        if self.units is not None and self.run is not None:
            data["units"] = self.units.as_dict()
        if self.located is not None:
            data["located"] = self.located.as_dict()
        return data


class ClosedLoop:
    """One closed loop from ``init`` to ``goal``; :meth:`run` it.

    ``inputs``: the files already read (else read here, once); ``plan``: PDDL action lines to
    carry out instead of planning (the ``pddl`` and ``plan`` stages are skipped);
    ``plan_inputs``: what the executor needs, made beforehand (a test method's design);
    ``on_event``: each :mod:`~kb.execution.events` event; ``progress``: where long stages
    report their steps (:mod:`kb.core.progress`)."""

    def __init__(self, init: str | Path, goal: str | Path, options: LoopOptions | None = None, *,
                 inputs: LoopInputs | None = None, plan: Sequence[str] | None = None,
                 plan_inputs: PlanInputs | None = None, plan_time: float | None = None,
                 on_event: Listener = ignore, progress: Progress = SILENT) -> None:
        self.init, self.goal = Path(init), Path(goal)
        self.given = (self.init, self.goal)  # as given: what a resume reads again (the locate stage replaces init)
        self.options = options or LoopOptions()
        self.inputs = inputs
        self.given_plan = list(plan) if plan is not None else None
        self.plan_inputs = plan_inputs
        self.plan_time = plan_time
        self.on_event = on_event
        self.progress = progress
        o = self.options
        self.name = o.name or (self.init.resolve().parent.name if self.init.stem == "init" else self.init.stem)
        self.result = LoopResult(self.name)
        self._clock: float | None = None
        self._cpu = 0.0
        self._frozen = False
        self._model: tuple[Any, float] | None = None  # the planning model made ahead, and its seconds
        self._started: Any = None  # the planner started ahead (kb.planning.planners.Started)
        self._opened: tuple[Any, bool] | None = None  # the cell opened by the locate stage, kept for execute
        self._tmp: Any = None  # the folder of the sensed state when there is no out_dir
        self._chosen: Any = None  # the kits the parts allow, when the first plan was made for them

    # --- the loop ---------------------------------------------------------------------------
    def run(self) -> LoopResult:
        """Run the stages; the result says how far they went. Input errors are raised
        (:class:`~kb.core.errors.InputError`, as each stage raises them)."""
        o = self.options
        with ExitStack() as stack:
            stack.callback(self._thaw)
            stack.callback(self._cancel_planner)
            stack.callback(self._close_cell)
            if o.db is not None and o.store is None:  # the writer lock from the start: a second run is
                from kb.world.database import normalize_url  # refused before any work, not after planning
                from kb.world.lock import hold
                stack.enter_context(hold(normalize_url(o.db), "a run"))
            self._stages()
        return self.result

    def _stages(self) -> None:
        o = self.options
        if self.inputs is None and self.plan_inputs is None:
            with gc_paused():  # what is read lives to the loop's end: frozen next, never walked
                self.inputs = LoopInputs.read(self.init, self.goal, domain_files=o.domain_files,
                                              match_names=o.match_names, imports=o.validate)
        unknown = self._unlocated()
        self._freeze()
        if o.validate and self.given_plan is None and not unknown:
            self._start_planner()
        if o.validate:
            # what validation keeps (the shapes graphs, their compiled programs) frozen before the
            # collector's first pass after it would walk all of it (0.15 s of a 160-part run)
            with gc_paused():
                valid = self._validate()
                self._freeze()
            if not valid:
                return
        if unknown:
            self._locate(unknown)
        plan = self.given_plan
        if plan is None:
            plan = self._plan()
            if plan is None:
                if o.geometry and self.inputs is not None:  # no plan: a stated placement geometry
                    self._geometry()  # does not bear out says why (its reason replaces "no plan")
                return
        if o.geometry and not self._geometry():
            return
        self._freeze()  # the scenes and the planning model too
        if not o.execute:
            return
        store = o.store
        own_store = None
        if store is None and o.db is not None:
            self._world()
            from kb.execution.store import RunStore, recorded_inputs
            store = own_store = RunStore(o.db)
            store.inputs = recorded_inputs(*self.given, o)  # what kitkb run --resume reads (kb.execution.resume)
            self.result.units = store.units
        try:
            self._execute(plan, store)
        finally:
            if own_store is not None:
                own_store.close()

    def _freeze(self) -> None:
        """Keep what was read and made so far out of the garbage collector's passes for the rest
        of the loop (they live to its end: a planner's or the executor's collections would
        walk them again and again); only when nobody else froze objects (:func:`gc.freeze`)."""
        if self._frozen or gc.get_freeze_count() == 0:
            gc.freeze()
            self._frozen = True

    def _thaw(self) -> None:
        if self._frozen:
            gc.unfreeze()
            self._frozen = False

    def _stage(self, stage: str, **detail: Any) -> float:
        self.on_event(StageStarted(stage, self.name, detail))
        self._cpu = time.process_time()
        return time.perf_counter()

    def _ended(self, stage: str, started: float, result: Any, ok: bool = True, reason: str | None = None) -> bool:
        seconds = time.perf_counter() - started
        self.result.seconds[stage] = seconds
        if not ok:
            self.result.halted, self.result.reason = stage, reason
        self.on_event(StageEnded(stage, self.name, seconds, result, ok, reason, time.process_time() - self._cpu))
        return ok

    # --- the stages -------------------------------------------------------------------------
    def _validate(self) -> bool:
        from kb.validation import validate
        assert self.inputs is not None
        t = self._stage("validate", files=[str(self.init), str(self.goal)])
        extensions = self.inputs.knowledge.domain_files or ()
        if extensions:  # a broken extension is bad input (refused at its line, exit 2), before any finding
            self.inputs.knowledge.domain  # noqa: B018 - read now
        # the extensions validated with the states: their classes of objects known to them
        report = validate([str(self.init), str(self.goal)], loaded=self.inputs.states,
                          domain=extensions)
        self.result.validation = report
        return self._ended("validate", t, report, report.conforms,
                           None if report.conforms else invalid_reason(report.errors))

    def _plan(self) -> list[str] | None:
        from kb import planning
        from kb.core.generators import get_generator
        o, inputs = self.options, self.inputs
        assert inputs is not None
        out = Path(o.out_dir) if o.out_dir is not None else None
        t = self._stage("pddl", out_dir=str(out) if out is not None else None)
        try:
            model, ahead = self._model if self._model is not None else (inputs.model("strips"), 0.0)
        except NotSolvableError:  # too few parts for the goal's kits: the kits they allow, if a policy says
            result = self._within_parts()
            if result is None:
                raise
            self._ended("pddl", t, None)  # nothing written: the whole goal has no problem to write
            t = self._stage("plan")
            self._clock = t
            if out is not None:
                out.mkdir(parents=True, exist_ok=True)
                (out / "plan.txt").write_text("\n".join(result.lines) + "\n")
            self.plan_time = time.perf_counter() - t
            self._ended("plan", t, result)
            return list(result.lines)
        if out is not None:
            get_generator("pddl")(model).write_outputs(out)
        self.result.model = model
        self._ended("pddl", t - ahead, model)  # the model made ahead counts as this stage's time
        started, self._started = self._started, None
        t = self._stage("plan")
        self._clock = t
        if started is not None:
            t -= started.seconds
        try:
            result = planning.run(model.up_problem, out / "plan.txt" if out is not None else None, o.planner,
                                  progress=self.progress, started=started)
        except NotSolvableError as e:
            result = self._within_parts()
            if result is None:
                self.result.error = e
                self._ended("plan", t, None, False, f"no plan: {e}")
                return None
            if out is not None:
                (out / "plan.txt").write_text("\n".join(result.lines) + "\n")
        self.plan_time = time.perf_counter() - t
        self.result.plan = result
        self._ended("plan", t, result)
        return list(result.lines)

    def _within_parts(self) -> Any:
        """A state short of parts before the run: when a partial-kit policy is given (the run's or
        the domain's) and the usable parts cannot fill every kit, the plan to the kits they allow
        (:func:`kb.planning.achievable.replan_achievable`, as a replan makes it), its choice kept for
        the run's record; else None (the run stops with "no plan", as before)."""
        from kb.planning.achievable import check_policy, replan_achievable
        from kb.planning.replan import restated
        pin = self.plan_inputs or self.inputs.plan_inputs()  # type: ignore[union-attr]
        o = self.options
        delivers = pin.failures.delivers_partial_kits
        policy = check_policy(o.partial_kits) if o.partial_kits is not None else \
            (None if delivers is None else ("deliver" if delivers else "leave"))
        spec = pin.problem
        if policy is None or not restated(spec, spec.facts, dict(spec.values), (), pin.domain).shortage:
            return None
        try:
            result, self._chosen = replan_achievable(pin.domain, spec, spec.facts, dict(spec.values), (), policy,
                                                     o.planner)
        except NotSolvableError:
            return None
        self.result.plan = result
        return result

    def _start_planner(self) -> None:
        """Make the planning model and start the planner before validation, so that it plans on
        the other core while the state files are validated (:func:`kb.planning.planners.start`);
        the pddl and plan stages then use them. Anything that goes wrong here is left for those
        stages to meet again and say, after validation, as without; a state that does not
        validate stops the planner (nothing of it is written)."""
        from kb.planning import planners
        assert self.inputs is not None
        t = time.perf_counter()
        try:
            model = self.inputs.model("strips")
        except Exception:  # noqa: BLE001 - said by the pddl stage, after validation
            return
        self._model = (model, time.perf_counter() - t)
        self._started = planners.start(model.up_problem, self.options.planner)

    def _cancel_planner(self) -> None:
        if self._started is not None:
            self._started.cancel()
            self._started = None

    def _unlocated(self) -> list[Any]:
        """The initial state's objects whose location is unknown (one look at its types; none
        for a state with every object placed, or when the executor's inputs were given)."""
        if self.inputs is None:
            return []
        from kb.spatial.unlocated import unlocated
        return unlocated(self.inputs.init)

    def _locate(self, unknown: list[Any]) -> None:
        """The ``locate`` stage: open the cell (kept for the execute stage), sense the unlocated
        objects (:func:`kb.execution.locate.locate`), write the state with them placed
        (``init-sensed.ttl`` in ``out_dir``, else a temporary folder kept to the loop's end)
        and read it as the loop's initial state."""
        import tempfile
        from kb.execution.locate import locate, workstation_of
        from kb.scenario.partial import copy_graph, with_locations, write_state
        o, inputs = self.options, self.inputs
        assert inputs is not None
        t = self._stage("locate", objects=len(unknown))
        scene = inputs.scene
        accuracy = sensor_accuracy(scene, o.sensor_noise)
        self._opened = self._cell(scene, accuracy)
        located = locate(self._opened[0], scene, unknown, workstation_of(inputs.init))
        if o.out_dir is not None:
            folder = Path(o.out_dir)
            folder.mkdir(parents=True, exist_ok=True)
        else:
            self._tmp = tempfile.TemporaryDirectory(prefix="kitkb-sensed-")
            folder = Path(self._tmp.name)
        path = write_state(with_locations(copy_graph(inputs.init), located.placements, scene.units),
                           folder / "init-sensed.ttl")
        self.init = path
        self.inputs = LoopInputs.read(path, self.goal, match_names=o.match_names, imports=False,
                                      knowledge=inputs.knowledge)
        self.result.located = located
        self._ended("locate", t, located)

    def _close_cell(self) -> None:
        opened, self._opened = self._opened, None
        if opened is not None and opened[1]:
            from kb.cells import close_cell
            close_cell(opened[0])
        if self._tmp is not None:
            self._tmp.cleanup()
            self._tmp = None

    def _geometry(self) -> bool:
        from kb.planning.geometry import agreement
        inputs = self.inputs
        assert inputs is not None
        t = self._stage("geometry")
        geo = agreement(inputs.problem, inputs.definitions, inputs.scene, inputs.goal_scene)
        self.result.agreement = geo
        return self._ended("geometry", t, geo, geo.initial_agrees, geo.reason() or None)

    def _world(self) -> None:
        from kb.execution.store import prepare
        from kb.world import WorldModel
        from kb.world.database import safe_url
        o, inputs = self.options, self.inputs
        t = self._stage("world", db=str(o.db))
        loaded = prepare(o.db, self.init, o.domain_files, replace=o.replace,
                         loaded=inputs.loaded() if inputs is not None else None)
        with WorldModel(o.db) as world:
            poses = world.global_poses()
        self.result.world = WorldLoaded(safe_url(str(o.db)), loaded.individuals, len(poses))
        self._ended("world", t, self.result.world)

    def _execute(self, plan: list[str], store: Any) -> None:
        o = self.options
        pin = self.plan_inputs or self.inputs.plan_inputs()  # type: ignore[union-attr]
        t = self._stage("execute", actions=len(plan))
        accuracy = sensor_accuracy(pin.scene, o.sensor_noise)
        if self._opened is not None:  # opened by the locate stage (on the state as the cell holds it)
            (cell, own), self._opened = self._opened, None
        else:
            cell, own = self._cell(pin.scene, accuracy)
        if own:  # a simulated cell's own noise (its URL's noise= included) is what is verified with
            from kb.cells import cell_accuracy
            found = cell_accuracy(cell, accuracy)
            if accuracy is not None or (found is not None and not found.zero):  # an exact sensor stays None
                accuracy = found
        # the run's clock from its planning on, set before the run is stored (its rows equal the record)
        clock = self._clock if o.clock_from_plan and self._clock is not None else 0.0
        record = RunRecord(self.name, o.seed, plan_time=self.plan_time, started=clock)
        if self._chosen is not None:  # planned for the kits the parts allow from the start
            from kb.execution.events import KitsChosen
            record.partial_kits = self._chosen.as_list()
            self.on_event(KitsChosen([local_name(k) for k in self._chosen.finished],
                                     [(local_name(p["kit"]), p["outcome"], tuple(p["lacks"].items()))
                                      for p in record.partial_kits]))

        def notify(recipient: str, message: str) -> None:
            self.on_event(Notified(recipient, message))
            o.notifier(recipient, message)

        try:
            # without the cyclic collector's passes: the executor's objects are nearly all freed by
            # their reference counts (a 160-part run holds 3 MB more at its peak, 0.14 s less)
            with gc_paused():
                run = execute_plan(plan, cell, pin, record, accuracy=accuracy, store=store,
                                   paths=(self.init, self.goal), notifier=notify, planner=o.planner,
                                   on_event=self.on_event, partial_kits=o.partial_kits)
        finally:
            if own:
                from kb.cells import close_cell
                close_cell(cell)
        self.result.run = run
        self._ended("execute", t, run)

    def _cell(self, scene: Scene, accuracy: Any) -> tuple[Any, bool]:
        """The cell to execute on (a cell object as given, else opened from its URL by the
        registry of :mod:`kb.cells`: default the in-process simulator of the initial state, or
        of ``truth``), and whether the loop opened it (and closes it)."""
        o = self.options
        if o.cell is not None and not isinstance(o.cell, str):
            return o.cell, False
        from kb.cells import CellRequest, open_cell
        if isinstance(o.truth, Scene):
            truth = o.truth
        elif o.truth is not None:
            goal = self.inputs.goal if self.inputs is not None else self.goal  # not parsed again
            truth = Scene.from_files([o.truth], declared=[goal], match_names=o.match_names)
        else:
            truth = scene  # the belief and the cell each copy it
        kinds = fault_kinds(self.inputs.knowledge.kb) if self.inputs is not None else None
        request = CellRequest(scene=truth, faults=o.faults or None, fault_kinds=kinds, seed=o.seed or None,
                              accuracy=accuracy, state=self.init, goal=self.goal, match_names=o.match_names)
        return open_cell(o.cell, request), True


def invalid_reason(errors: list[Any]) -> str:
    """Why state files that do not validate are not executed: how many errors of which rules,
    and the first (a kit design whose slots do not fit its tray says so)."""
    rules = Counter(d.rule or "error" for d in errors)
    counts = ", ".join(f"{rule} {n}" if n > 1 else rule for rule, n in sorted(rules.items(), key=lambda kv: -kv[1]))
    return f"the state files do not validate ({len(errors)} error(s): {counts}); first: {errors[0].format()}"


# --- the executives' entry points -----------------------------------------------------------------

def run_plan(plan: Sequence[str], init: str | Path, goal: str | Path, *, cell: CellInterface | str | None = None,
             faults: Any = None, seed: int = 0, match_names: bool = False, db: str | Path | None = None,
             replace: bool = False, store: Any = None,
             progress: Callable[[str], None] | None = None, notifier: Callable[[str, str], None] = log_notifier,
             planner: str | None = None, domain_files: Sequence[str | Path] | None = None,
             name: str | None = None, truth: str | Path | None = None, plan_time: float | None = None,
             sensor_noise: Any = None, on_event: Listener | None = None, partial_kits: str | None = None) -> Run:
    """Carry out ``plan`` (PDDL action lines) from the state ``init`` towards ``goal``: the
    closed loop's ``world`` (with ``db``) and ``execute`` stages (:class:`ClosedLoop`).

    ``cell``: any :class:`~kb.crcl.cell.CellInterface` (a real cell, :class:`kb.crcl.RemoteCell`)
    or a cell's address; default: a simulated cell of ``init`` with ``faults`` (a
    :class:`kb.sim.FaultSpec` or its text, ``"missed-grasp=0.2,part-missing@3"``) and ``seed``.
    ``db``: a database (SQLite file or URL) that gets the initial state and the domain (a
    database that already holds a world model or run history only with ``replace``), then the
    stable states and the run's records (:mod:`kb.execution.store`); or pass an open ``store``.
    ``truth``: a state file the simulated cell holds instead of ``init`` (the same objects
    placed and turned otherwise: the first paper's "the actual location of the kit tray and
    parts supplies will not be known before runtime"); the executor starts from ``init``, the
    nominal layout, and finds the objects by sensing. ``plan_time``: the seconds the plan took
    to make (a metric of the run). ``sensor_noise``: the sensor's accuracy (a
    :class:`kb.sim.noise.SensorNoise` or its text, ``"position=1mm,orientation=0.5deg,misdetection=0.01"``),
    over the sensor individual of ``init``: the simulated cell's sensor has it, and the
    executor verifies with it (docs/execution.md, "Sensing with noise"); with another
    ``cell``, what the executor assumes of its sensor. ``on_event``: each event of the loop
    (:mod:`kb.execution.events`); ``progress``: each event's line. ``partial_kits``: what is done
    with a kit the usable parts cannot finish (``deliver`` | ``leave``; default: the domain's
    policy, :mod:`kb.execution.partial`).
    """
    options = LoopOptions(faults=faults, seed=seed, cell=cell, match_names=match_names, domain_files=domain_files,
                          sensor_noise=sensor_noise, planner=planner, truth=truth, validate=False, geometry=False,
                          db=db, replace=replace, store=store, notifier=notifier,
                          name=name or Path(init).resolve().parent.name, partial_kits=partial_kits)
    loop = ClosedLoop(init, goal, options, plan=plan, plan_time=plan_time, on_event=_listener(on_event, progress))
    return _ran(loop.run())


def run_scenario(init: str | Path, goal: str | Path, *, validate: bool = False, geometry: bool = False,
                 on_event: Listener | None = None, progress: Callable[[str], None] | None = None, **kw: Any) -> Run:
    """Plan from ``init`` to ``goal`` with a real planner, then carry the plan out as
    :func:`run_plan` does: the closed loop, by default without its ``validate`` and
    ``geometry`` stages (``validate=True``, ``geometry=True`` add them; a stage that ends the
    loop is an :class:`~kb.core.errors.InputError` or :class:`~kb.core.errors.NotSolvableError`
    saying why)."""
    name, plan_time = kw.pop("name", None), kw.pop("plan_time", None)
    options = LoopOptions(validate=validate, geometry=geometry, clock_from_plan=True,
                          name=name or Path(init).resolve().parent.name, **kw)
    loop = ClosedLoop(init, goal, options, plan_time=plan_time, on_event=_listener(on_event, progress))
    return _ran(loop.run())


def _listener(on_event: Listener | None, progress: Callable[[str], None] | None) -> Listener:
    if progress is None:
        return on_event or ignore

    def listen(event: Event) -> None:
        if on_event is not None:
            on_event(event)
        text = event.text()
        if text is not None and not isinstance(event, Notified):  # notifications go to the notifier
            progress(text)
    return listen


def _ran(result: LoopResult) -> Run:
    """The run of a loop; a loop that stopped before executing is an error saying why."""
    if result.run is not None:
        return result.run
    from kb.core.errors import InputError
    if result.error is not None:
        raise result.error
    raise InputError(f"not executed: {result.reason}")
