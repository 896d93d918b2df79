"""Resuming a run that stopped for the operator (``kitkb run --resume RUN_ID --db URL``).

A run that stops (its report's ``stopped``: a remediation asking for an operator, no usable
part left, no plan) leaves in its world-model database its last stable state (the poses of
every object after the last action whose effects held, :mod:`kb.execution.store`), its records
(actions, failures, the objects as sensed at its end) and what it was started from (its state
and domain files with their SHA-256, its options: :func:`recorded_inputs`, written when the run
began). :class:`Resume` goes on from there, as the third paper's future work asks (replan from
the stable state stored in the database):

1. the run is read back (:func:`kb.execution.store.read_run`); a run that finished, an unknown
   run id, a database with no run, a run that is not the database's last, or a state or domain
   file that is gone or changed since is refused in one line (exit 2);
2. the **stable state** becomes a state file (``resume-<id>-stable.ttl``): the run's initial
   state with each object that moved placed at its stable pose, in the frame of what holds it
   now, decided by geometry (:func:`placements`: an end effector at a robot's flange is mounted
   on it, an object whose top face is at a mounted effector's tip is held by it, anything else
   lies in the smallest object whose box holds its origin, :func:`kb.execution.locate.container`);
   the executor's belief starts from it;
3. the cell: a given one (``cell``), or the in-process simulator holding the cell as the run
   left it — the objects as sensed at the run's end (``resume-<id>-stopped.ttl``, placed the
   same way; what was not seen then is not in the cell) — or, with ``truth``, the state file
   the operator's cell holds (an object it does not locate is not in the cell);
4. the executor senses the whole cell again; what the run's diagnoses learned about an object
   (condemned, to be inspected, moved: the failure modes' object consequences, re-applied from
   the recorded failures) holds again, except for an object the run's end did not see and the
   cell shows now (the operator brought it back: nothing learned of it before holds);
5. it replans against the same goal from the sensed state (:mod:`kb.planning.replan`, through
   the executor's replanning: the run's partial-kit policy, the unusable objects left out) and
   carries the plan out as the **same run**: the same run id and rows, actions appended with
   continuing indices, the stable-state counter continuing, the record's ``resumes`` (the
   report's timeline shows the stop and the resume).

Times: the record's times are the clock of the process that made them; a resumed run's old
times are moved to end where the resume begins, so its timeline goes on (the operator's pause is
not in it; each resume says when it happened, ``resumed_at``).
"""

from __future__ import annotations

import dataclasses
import datetime as dt
import hashlib
import tempfile
import time
from collections import deque
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable

import numpy as np

from kb.core.errors import InputError
from kb.core.namespaces import KTW, local_name
from kb.core.progress import SILENT, Progress
from kb.execution.api import Run, note_ground_truth, sensor_accuracy
from kb.execution.belief import Belief
from kb.execution.events import Listener, StageEnded, StageStarted, ignore
from kb.execution.executor import Executor, log_notifier
from kb.execution.inputs import LoopInputs
from kb.execution.locate import container, workstation_of
from kb.execution.loop import LoopResult
from kb.execution.records import RunRecord
from kb.execution.recovery import CONSEQUENCES
from kb.execution.steps import Stop
from kb.execution.store import RunStore, latest_run, read_run, run_inputs
from kb.cells import CellRequest, close_cell, open_cell
from kb.model.faults import fault_kinds
from kb.scenario.partial import Placement, copy_graph, unlocate, with_locations, write_state
from kb.spatial.scene import Scene, scene_boxes
from kb.spatial.unlocated import unlocated
from kb.world.database import normalize_url, safe_url

#: how far (m) an effector's origin may be from a robot's flange face, or an object's top face
#: from a mounted effector's tip, and still be mounted on it or held by it
ATTACHED = 0.002
_ROBOT, _EFFECTOR = str(KTW.Robot), str(KTW.EndEffector)


# --- what a run is started from ---------------------------------------------------------------

def _checked(entry: Any, what: str, run_id: int) -> Path:
    """The recorded file ``entry``, as it was when the run began (else an InputError)."""
    if not isinstance(entry, dict) or not isinstance(entry.get("path"), str):
        raise InputError(f"run {run_id}: its recorded {what} is not a file entry ({entry!r})")
    path = Path(entry["path"])
    if not path.is_file():
        raise InputError(f"run {run_id} was started from {what} {path}, which is gone: it cannot be resumed")
    if hashlib.sha256(path.read_bytes()).hexdigest() != entry.get("sha256"):
        raise InputError(f"run {run_id} was started from {what} {path}, which has changed since: "
                         "it cannot be resumed")
    return path


# --- the stable state as a state file ----------------------------------------------------------

def placements(scene: Scene, poses: dict[str, np.ndarray], workstation: str | None) -> list[Placement]:
    """Where each object of ``scene`` whose global pose in ``poses`` (local name -> 4x4, SI)
    differs from the scene's is, in the frame of what holds it now (decided by geometry on the
    scene with those poses): a robot keeps its reference; an end effector whose origin is at a
    robot's flange face is mounted on it; an object whose top face is at a mounted effector's
    tip is held by it; anything else lies in the smallest object whose box holds its origin
    (:func:`~kb.execution.locate.container`), else in the workstation."""
    now = np.array(scene.poses, float)
    by_local = {local_name(n): i for i, n in enumerate(scene.names)}
    moved = []
    for name, m in poses.items():
        i = by_local.get(name)
        if i is not None and not np.allclose(now[i], m, atol=1e-9, equal_nan=False):
            now[i] = m
            moved.append(i)
    lo, hi = scene_boxes(now, scene.local_lo, scene.local_hi)
    keep = np.isnan(lo[:, 0]) & ~np.isnan(scene.lo[:, 0])  # boxes lent by another object: as they were
    lo[keep], hi[keep] = scene.lo[keep], scene.hi[keep]
    stable = dataclasses.replace(scene, lo=lo, hi=hi, poses=now)
    robots = [i for i in stable.of_class(_ROBOT).tolist() if stable.placed[i]]
    mounted = {int(e): r for e in stable.of_class(_EFFECTOR).tolist() for r in robots
               if np.linalg.norm(now[e][:3, 3] - _face(now[r], scene.local_hi[r])) < ATTACHED}
    out = []
    for i in sorted(moved, key=lambda i: scene.names[i]):
        ref = _reference(stable, i, robots, mounted)
        if ref is None:
            if workstation is None:
                continue  # nowhere to place it: its location is left as the file has it
            ref_name, frame = workstation, _pose_of(stable, workstation)
        else:
            ref_name, frame = stable.names[ref], now[ref]
        out.append(Placement(scene.names[i], ref_name, np.linalg.inv(frame) @ now[i], now[i]))
    return out


def _reference(stable: Scene, i: int, robots: list[int], mounted: dict[int, int]) -> int | None:
    now = stable.poses
    assert now is not None and stable.parents is not None
    if i in robots:
        p = int(stable.parents[i])
        return p if p >= 0 else None
    if i in mounted:
        return mounted[i]
    top = np.array([(stable.lo[i, 0] + stable.hi[i, 0]) / 2, (stable.lo[i, 1] + stable.hi[i, 1]) / 2, stable.hi[i, 2]])
    for e in mounted:
        if e != i and np.linalg.norm(top - _face(now[e], stable.local_hi[e])) < ATTACHED:  # type: ignore[index]
            return e
    return container(stable, now[i][:3, 3], exclude=stable.names[i])


def _face(pose: np.ndarray, local_hi: np.ndarray) -> np.ndarray:
    """The centre of an object's far face along its z axis (a flange's, an effector's tip)."""
    return (pose @ np.array([0.0, 0.0, float(local_hi[2]), 1.0]))[:3]


def _pose_of(scene: Scene, name: str) -> np.ndarray:
    i = scene.index.get(name)
    if i is None or scene.poses is None or np.isnan(scene.poses[i][0, 0]):
        return np.eye(4)
    return scene.poses[i]


def state_file(inputs: LoopInputs, poses: dict[str, np.ndarray], path: Path, gone: set[str] = frozenset()) -> Path:
    """The initial state of ``inputs`` with the objects at ``poses`` (local name -> 4x4, SI),
    those of ``gone`` (local names) without a location (not in the cell), written to ``path``."""
    graph = copy_graph(inputs.init)
    found = placements(inputs.scene, poses, workstation_of(inputs.init))
    graph = with_locations(graph, found, inputs.scene.units)
    placed = [n for n, p in zip(inputs.scene.names, inputs.scene.placed) if p and local_name(n) in gone]
    if placed:  # (an object of the goal only, a kit, has no location to take away)
        unlocate(graph, placed)
    return write_state(graph, path)


def without(scene: Scene, names: set[str]) -> Scene:
    """``scene`` with the objects of ``names`` (local names) out of the cell (no pose, no box),
    as a scene of no file (a simulator does not place what it does not locate)."""
    gone = np.array([local_name(n) in names for n in scene.names], bool)
    poses = np.array(scene.poses, float)
    lo, hi = np.array(scene.lo, float), np.array(scene.hi, float)
    poses[gone], lo[gone], hi[gone] = np.nan, np.nan, np.nan
    return dataclasses.replace(scene, poses=poses, lo=lo, hi=hi)


# --- the resume --------------------------------------------------------------------------------

@dataclass
class ResumeOptions:
    """How a run is resumed: ``truth`` (a state file the simulated cell holds: the cell as the
    operator left it; default: as the run left it), ``cell`` (a cell object or URL; default the
    run's own: a URL it was given, else the in-process simulator), ``faults`` / ``seed`` of a
    simulated cell (default: none; the run's seed), ``out_dir`` (where the stable and stopped
    state files go; default a temporary folder), ``notifier``."""

    truth: str | Path | None = None
    cell: Any = None
    faults: Any = None
    seed: int | None = None
    out_dir: str | Path | None = None
    notifier: Callable[[str, str], None] = log_notifier


@dataclass
class Resumed:
    """The ``resume`` stage's result: the run, where it stopped, the stable state it went on
    from, the state files written, the objects the operator brought back."""

    run_id: int
    after: int
    stopped: str
    stable_state: int
    state: Path
    stopped_state: Path | None
    truth: str | None
    brought_back: list[str]

    def text(self) -> str:
        back = f"; back in the cell: {', '.join(self.brought_back)}" if self.brought_back else ""
        cell = f"the cell of {self.truth}" if self.truth else "the cell as the run left it"
        return (f"resume: run {self.run_id} after action {self.after} from stable state {self.stable_state} "
                f"({self.state}), {cell}{back}")


class Resume:
    """Resume run ``run_id`` recorded in the database ``db``; :meth:`run` it (module docstring)."""

    def __init__(self, db: str | Path, run_id: int, options: ResumeOptions | None = None, *,
                 on_event: Listener = ignore, progress: Progress = SILENT) -> None:
        self.url = normalize_url(db)
        self.run_id = run_id
        self.options = options or ResumeOptions()
        self.on_event = on_event
        self.progress = progress

    def run(self) -> LoopResult:
        record = read_run(self.url, self.run_id)  # a database or run that is not there: one line
        last = latest_run(self.url)
        where = safe_url(self.url)
        if last != self.run_id:
            raise InputError(f"run {self.run_id} is not the last run in {where} (run {last} is): its world model "
                             "holds the last run's stable state; only the last run can be resumed")
        if record.stopped is None:
            how = "its goal holds" if record.goal_holds else "its goal does not hold"
            raise InputError(f"run {self.run_id} in {where} finished ({how}); only a run that stopped "
                             "(its report's stopped) can be resumed")
        given = run_inputs(self.url, self.run_id)
        init = _checked(given.get("init"), "the initial state", self.run_id)
        goal = _checked(given.get("goal"), "the goal state", self.run_id)
        domain = [_checked(d, "the domain extension", self.run_id) for d in given.get("domain") or []]
        truth = self.options.truth
        if truth is not None and not Path(truth).is_file():
            raise InputError(f"--truth {truth}: no such file")
        store = RunStore(self.url)  # the writer lock from here to the end
        tmp = None
        try:
            out = Path(self.options.out_dir) if self.options.out_dir is not None else None
            if out is None:
                tmp = tempfile.TemporaryDirectory(prefix="kitkb-resume-")
                out = Path(tmp.name)
            out.mkdir(parents=True, exist_ok=True)
            return self._resume(store, record, given, init, goal, domain, out)
        finally:
            store.close()
            if tmp is not None:
                tmp.cleanup()

    def _resume(self, store: Any, record: RunRecord, given: dict[str, Any], init: Path, goal: Path,
                domain: list[Path], out: Path) -> LoopResult:
        o = self.options
        name = given.get("name") or record.scenario
        result = LoopResult(name)
        result.units = store.units
        t = time.perf_counter()
        self.on_event(StageStarted("resume", name, {"run": self.run_id}))
        first = LoopInputs.read(init, goal, domain_files=domain or None, match_names=bool(given.get("match_names")),
                                imports=False)
        metres = store.metres
        stable = {n: _si(m, metres) for n, m in store.world.global_poses().items()}
        counter = store.world.stable_state()
        path = state_file(first, stable, out / f"resume-{self.run_id}-stable.ttl")
        inputs = LoopInputs.read(path, goal, match_names=bool(given.get("match_names")), imports=False,
                                 knowledge=first.knowledge)
        pin = inputs.plan_inputs()
        seen_at_stop = _seen(record)
        truth, stopped_path = self._truth(first, record, seen_at_stop, goal, given, out)
        accuracy = sensor_accuracy(pin.scene, given.get("sensor_noise"))
        cell, own = self._cell(truth, accuracy, inputs, given, path, goal)
        if own and seen_at_stop is not None:
            remake_kits(cell, first.scene, seen_at_stop)
        try:
            return self._execute(store, record, given, pin, cell, accuracy, seen_at_stop, counter, path,
                                 stopped_path, result, t)
        finally:
            if own:
                close_cell(cell)

    def _truth(self, first: LoopInputs, record: RunRecord, seen: dict[str, np.ndarray] | None, goal: Path,
               given: dict[str, Any], out: Path) -> tuple[Scene, Path | None]:
        """The scene the simulated cell holds, and the state file of the cell as the run left it."""
        match = bool(given.get("match_names"))
        stopped_path = None
        if seen is not None:  # the cell as sensed at the run's end; what was not seen then is not located
            stopped_path = state_file(first, seen, out / f"resume-{self.run_id}-stopped.ttl", _named(record) - set(seen))
        held = self.options.truth if self.options.truth is not None else stopped_path
        if held is None:  # a run of no recorded scene: the stable state
            return first.scene, None
        scene = Scene.from_files([held], declared=[goal], match_names=match)
        assert scene.source is not None
        return without(scene, {local_name(u.name) for u in unlocated(scene.source)}), stopped_path

    def _cell(self, truth: Scene, accuracy: Any, inputs: LoopInputs, given: dict[str, Any], state: Path,
              goal: Path) -> tuple[Any, bool]:
        o = self.options
        cell = o.cell if o.cell is not None else given.get("cell")
        if cell is not None and not isinstance(cell, str):
            return cell, False
        seed = o.seed if o.seed is not None else given.get("seed")
        request = CellRequest(scene=truth, faults=o.faults or None, fault_kinds=fault_kinds(inputs.knowledge.kb),
                              seed=seed or None, accuracy=accuracy, state=state, goal=goal,
                              match_names=bool(given.get("match_names")))
        return open_cell(cell, request), True

    def _execute(self, store: Any, record: RunRecord, given: dict[str, Any], pin: Any, cell: Any, accuracy: Any,
                 seen_at_stop: dict[str, np.ndarray] | None, counter: int, path: Path, stopped_path: Path | None,
                 result: LoopResult, t: float) -> LoopResult:
        o = self.options
        after = max((a.index for a in record.actions), default=-1)
        stopped = record.stopped or ""
        _continue_clock(record)
        kept = {"tip_start": record.tip_start, "injected": list(record.injected),
                "violations": record.violations, "sensor_errors": record.sensor_errors}
        record.stopped, record.goal_holds, record.goal_unmet, record.kits = None, None, [], []
        record.partial_kits = []
        executor = Executor(cell, pin.domain, pin.problem, pin.definitions, pin.failures, Belief(pin.scene),
                            store=store, notifier=o.notifier, planner=given.get("planner"), record=record,
                            accuracy=accuracy, on_event=self.on_event)
        executor.partial_kits = given.get("partial_kits")
        executor.index = after + 1
        record.tip_start = kept["tip_start"]
        store.continue_run(record)
        executor._sense_all()  # the cell sensed again
        back = relearn(executor, record, seen_at_stop)
        entry = {"after": after, "stopped": stopped, "stopped_t": round(record.ended - record.started, 6),
                 "resumed_t": round(time.perf_counter() - record.started, 6),
                 "resumed_at": dt.datetime.now(dt.timezone.utc).isoformat(timespec="seconds"),
                 "truth": None if o.truth is None else str(Path(o.truth).resolve()),
                 "stable_state": counter, "brought_back": back}
        record.resumes = [*record.resumes, entry]
        resumed = Resumed(self.run_id, after, stopped, counter, path, stopped_path, entry["truth"], back)
        seconds = time.perf_counter() - t
        result.seconds["resume"] = seconds
        self.on_event(StageEnded("resume", result.scenario, seconds, resumed, True, None, 0.0))
        t = time.perf_counter()
        queue: deque = deque()
        try:
            executor._replan(queue, None)  # from the sensed state, the same goal
        except Stop as stop:
            record.stopped = str(stop)
        lines = [s.line() for s in queue]
        self.on_event(StageStarted("execute", result.scenario, {"actions": len(lines)}))
        try:
            executor.run(lines)
        except KeyboardInterrupt:
            record.stopped = "interrupted"
            store.end_run(record)
            raise
        note_ground_truth(record, cell, accuracy)
        record.injected = kept["injected"] + list(record.injected)
        if kept["violations"] is not None or record.violations is not None:
            record.violations = list(kept["violations"] or []) + list(record.violations or [])
        if kept["sensor_errors"] is not None or record.sensor_errors is not None:
            record.sensor_errors = list(kept["sensor_errors"] or []) + list(record.sensor_errors or [])
        store.end_run(record)
        result.run = Run(record)
        seconds = time.perf_counter() - t
        result.seconds["execute"] = seconds
        self.on_event(StageEnded("execute", result.scenario, seconds, result.run, True, None, 0.0))
        return result


def remake_kits(cell: Any, scene: Scene, seen: dict[str, np.ndarray]) -> list[str]:
    """The kits the run had made (seen at its end with their kit tray) made again in a simulated
    ``cell`` that makes kits (``create_kit``: a kit is an object of the cell's model, not of the
    state file, made on its tray when the action starting it ends); the kits made (local names)."""
    make = getattr(cell, "create_kit", None)
    if make is None:
        return []
    made = []
    for kit, tray in sorted(scene.facts.get(str(KTW.hasKit_KitTray), ())):
        if local_name(kit) in seen and local_name(tray) in seen:
            make(kit, tray)
            made.append(local_name(kit))
    return made


def relearn(executor: Executor, record: RunRecord, seen_at_stop: dict[str, np.ndarray] | None) -> list[str]:
    """What the run's diagnoses learned about objects, in the resumed executor's belief again
    (each recorded failure's mode's object consequences, by the executor's own handlers), but
    for the objects the run's end did not see and the cell, sensed again, shows (the operator
    brought them back: nothing learned of them before holds). Returns those (local names)."""
    belief = executor.belief
    drawn = _named(record)
    back = sorted(local_name(n) for n in belief.names
                  if seen_at_stop is not None and local_name(n) in drawn and local_name(n) not in seen_at_stop
                  and belief.placed(n))
    params = {a.name: [p for p, _t in a.params] for a in executor.domain.actions}
    for f in record.failures:
        mode = executor.failures.modes.get(f.mode)
        if mode is None or f.action not in params:
            continue
        args = dict(zip(params[f.action], f.args))
        for c in mode.consequences:
            obj = args.get(c.parameter)
            handler = CONSEQUENCES.get(c.kind)
            if obj is None or handler is None or local_name(obj) in back:
                continue
            getattr(executor, handler)(obj, c.reason)
    return back


def _named(record: RunRecord) -> set[str]:
    """The objects (local names) the run's end drew (its record's scene)."""
    return {o["name"] for o in (record.scene or {}).get("objects", []) if isinstance(o, dict)}


def _seen(record: RunRecord) -> dict[str, np.ndarray] | None:
    """The objects as sensed at the run's end (local name -> 4x4, SI), from its record's scene;
    None when the record has none."""
    if not record.scene or not isinstance(record.scene.get("objects"), list):
        return None
    return {o["name"]: np.array(o["final"], float) for o in record.scene["objects"]
            if isinstance(o, dict) and o.get("final") is not None}


def _si(pose: np.ndarray, metres: float) -> np.ndarray:
    out = np.array(pose, float)
    out[:3, 3] *= metres
    return out


def _continue_clock(record: RunRecord) -> None:
    """Move every time of ``record`` (another process's clock) so that it ends now."""
    shift = time.perf_counter() - record.ended
    record.started += shift
    record.ended += shift
    for a in record.actions:
        a.started += shift
        a.ended += shift
    for c in record.checks:
        c.time += shift
    for f in record.failures:
        f.time += shift


def resume_run(db: str | Path, run_id: int, *, truth: str | Path | None = None, cell: Any = None,
               faults: Any = None, seed: int | None = None, out_dir: str | Path | None = None,
               notifier: Callable[[str, str], None] = log_notifier, on_event: Listener | None = None) -> Run:
    """Resume run ``run_id`` of the database ``db`` (:class:`Resume`): the same run, gone on
    from its last stable state; its :class:`~kb.execution.api.Run`."""
    options = ResumeOptions(truth=truth, cell=cell, faults=faults, seed=seed, out_dir=out_dir, notifier=notifier)
    result = Resume(db, run_id, options, on_event=on_event or ignore).run()
    assert result.run is not None
    return result.run
