"""One trial of a test method, as a worker runs it: :func:`run_trial` takes a
:class:`~kb.testmethod.methods.Job` and gives its row (the run's report and the trial's facts).

The system under test is kitkb's executor given the kit design and the *nominal* layout (the
job's workstation as laid out); the simulated cell holds the trial's *real* placement (the same
workstation with its trays placed and turned by :func:`kb.scenario.placement.place_trays`): the
executor finds the trays by sensing and binds its motions late, as
``run_plan(..., truth=FILE)`` does. Both halves are the closed loop's
(:class:`kb.execution.loop.ClosedLoop`): what depends only on the design — the nominal files
read once, the plan (it names objects, never poses; the loop's ``pddl`` and ``plan`` stages),
the problem, the nominal scene — is made once per design in each worker process
(:func:`prepared`) and kept, the domain's definitions and failure modes once per process
(:func:`knowledge`); per trial only the real placement's scene and the loop's ``execute``
stage are run, with the plan and inputs given.

``new-variety`` trials are the exception: their design is new, so it is written as Turtle files
("delivered"), and from their receipt the system reads them, plans and starts; the time from
receipt to the first CRCL command the cell gets is the trial's ``receipt_to_first_command_s``
(one closed loop from reading the files to the end of the run).
"""

from __future__ import annotations

import dataclasses
import itertools
import tempfile
import time
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path
from typing import Any, Literal, Sequence

import numpy as np

from kb.core.errors import KitkbError
from kb.cells.accuracy import SensorAccuracy
from kb.cells.registry import CellRequest, close_cell, open_cell
from kb.crcl.cell import Observation, Status, capabilities, execute_program, sense_names
from kb.crcl.commands import Command
from kb.execution import Run
from kb.execution.api import sensor_accuracy
from kb.execution.events import Listener, ignore
from kb.execution.inputs import DomainInputs, LoopInputs, PlanInputs
from kb.execution.loop import ClosedLoop, LoopOptions
from kb.execution.scoring import delivered_kits
from kb.io.loader import Source
from kb.model.definitions import Definitions
from kb.model.failures import FailureModel
from kb.model.faults import fault_kinds
from kb.model.soap import DomainSpec
from kb.planning.problem import ProblemSpec
from kb.scenario import layout, write_spec
from kb.scenario.blocks import state_graph
from kb.scenario.layout import Scenario
from kb.scenario.placement import Placement, place_trays, placements, pose_of
from kb.scenario.spec import ScenarioSpec
from kb.spatial.scene import Scene, scene_boxes
from kb.spatial.transforms import pose_matrix
from kb.testmethod.methods import Job, not_executed

#: designs whose preparation a worker keeps (a campaign has one, multi a few orders of them)
KEEP = 32


@dataclass
class Prepared:
    """What the system under test knows of a design before a trial: the nominal files, layout
    and scene, the plan, and the problem it plans and checks against."""

    scenario: Scenario
    init: Path
    goal: Path
    plan: list[str]
    plan_time: float
    domain: DomainSpec
    problem: ProblemSpec
    scene: Scene
    extensions: tuple[str, ...] = ()  # the domain's extension files (Job.domain)


@lru_cache(maxsize=4)
def domain_inputs(extensions: tuple[str, ...] = ()) -> DomainInputs:
    """The domain (the shipped one and the extension files ``extensions``, the campaign's
    ``--domain``): its files read once per process, its planning domain, predicate definitions
    and failure modes made once."""
    return DomainInputs(list(extensions) or None)


def shipped_domain() -> DomainInputs:
    """The shipped domain alone (:func:`domain_inputs` with no extension)."""
    return domain_inputs(())


def knowledge(extensions: tuple[str, ...] = ()) -> tuple[Definitions, FailureModel]:
    """The domain's predicate definitions and failure modes (made once per process)."""
    return domain_inputs(extensions).definitions, domain_inputs(extensions).failures


#: this process's folder for the nominal state files it writes (removed when the process ends)
_FOLDER: list[tempfile.TemporaryDirectory] = []
_DESIGNS = itertools.count(1)


@lru_cache(maxsize=KEEP)
def prepared(spec: ScenarioSpec, extensions: tuple[str, ...] = ()) -> Prepared:
    """:func:`prepare` once per design, domain and process."""
    if not _FOLDER:
        _FOLDER.append(tempfile.TemporaryDirectory(prefix="kitkb-testmethod-"))
    return prepare(spec, Path(_FOLDER[0].name) / f"design-{next(_DESIGNS)}", extensions)


def prepare(spec: ScenarioSpec, folder: Path, extensions: tuple[str, ...] = ()) -> Prepared:
    """Lay out ``spec`` nominally, write its files into ``folder``, plan, and read the problem."""
    sc = layout(spec)
    init, goal = write_spec(sc, folder)
    return receive(sc, init, goal, extensions)


def receive(sc: Scenario, init: Path, goal: Path, extensions: tuple[str, ...] = ()) -> Prepared:
    """What the system does with a design's files: read them (once), plan: the closed loop up
    to its plan (:class:`~kb.execution.loop.ClosedLoop`, no validation, geometry or execution)."""
    t = time.perf_counter()
    inputs = LoopInputs.read(init, goal, imports=False, knowledge=domain_inputs(extensions))
    result = ClosedLoop(init, goal, _options(execute=False), inputs=inputs).run()
    plan = list(result.plan.lines)
    return Prepared(sc, init, goal, plan, time.perf_counter() - t, inputs.domain, inputs.problem, inputs.scene,
                    extensions)


def _options(**kw: Any) -> LoopOptions:
    """A trial's loop: no validation or geometry check (the design is kitkb's own), no notices."""
    return LoopOptions(validate=False, geometry=False, notifier=_quiet, **kw)


def file_scene(sc: Scenario, goal: Path) -> Scene:
    """The scene of ``sc``'s initial state as its file would be read (built in memory)."""
    source = Source(Path(f"{sc.name}-init.ttl"), "turtle", graph=state_graph(sc, "init"))
    return Scene.from_sources([source], declared=[goal])


def placed_scene(nominal: Scene, namespace: str, placed: Sequence[Placement]) -> Scene:
    """``nominal`` (a scene of the scenario of ``namespace``) with each placed tray at its new pose on its table and everything it holds
    carried along: the scene :func:`file_scene` reads from the placed layout's file (the
    objects, facts and boxes are the same; only poses differ), made in a millisecond."""
    poses = nominal.poses.copy()
    index, parents = nominal.index, nominal.parents
    moved: dict[int, np.ndarray] = {}
    for p in placed:
        i, table = index[namespace + p.obj], index[namespace + p.table]
        pose = pose_of(p)
        local = pose_matrix(pose[:3], pose[3:6], pose[6:])
        moved[i] = poses[table] @ local @ np.linalg.inv(nominal.poses[i])
    for j in range(len(poses)):
        k = j
        while k >= 0 and k not in moved:
            k = int(parents[k])
        if k >= 0:
            poses[j] = moved[k] @ nominal.poses[j]
    lo, hi = scene_boxes(poses, nominal.local_lo, nominal.local_hi)
    return dataclasses.replace(nominal, poses=poses, lo=lo, hi=hi)


class WatchedCell:
    """A cell that notes when it got its first CRCL command (``first_command``, perf_counter
    seconds; None before). It has the capabilities of the cell it watches, declared
    (:func:`kb.crcl.cell.capabilities`), and forwards each of them."""

    def __init__(self, cell: Any) -> None:
        self.cell = cell
        self.first_command: float | None = None
        own = capabilities(cell)  # it moves by programs and senses by names where the cell moves and senses
        self.capabilities = own | ({"move-program"} if "move" in own else set()) | (
            {"sense-names"} if "sense" in own else set())
        self.url = getattr(cell, "url", None)

    def execute(self, command: Command) -> Status:
        self._note()
        return self.cell.execute(command)

    def execute_program(self, commands: Sequence[Command]) -> list[Status]:
        self._note()
        return execute_program(self.cell, commands)

    def sense(self, query: str, *, by: Literal["class", "name"] = "class") -> list[Observation]:
        return self.cell.sense(query, by=by)

    def sense_names(self, names: Sequence[str]) -> list[Observation]:
        return sense_names(self.cell, names)

    def inspect(self, name: str) -> bool:
        return self.cell.inspect(name)

    def begin_action(self, index: int, action: str, args: tuple[str, ...]) -> None:
        self.cell.begin_action(index, action, args)

    @property
    def injected(self) -> Sequence[Any]:
        return self.cell.injected

    @property
    def violations(self) -> Sequence[Any]:
        return self.cell.violations

    @property
    def sensor_errors(self) -> Sequence[Any]:
        return self.cell.sensor_errors

    def part_fates(self) -> list[Any]:
        return self.cell.part_fates()

    def close(self) -> None:
        close_cell(self.cell)

    def _note(self) -> None:
        if self.first_command is None:
            self.first_command = time.perf_counter()


def execute(prep: Prepared, cell: WatchedCell, name: str, seed: int, accuracy: SensorAccuracy | None = None,
            on_event: Listener = ignore, partial_kits: str | None = None) -> Run:
    """Carry out the design's plan on ``cell`` from the nominal belief, verifying with the
    sensor ``accuracy``: the closed loop's ``execute`` stage, the plan and inputs given."""
    defs, failures = knowledge(prep.extensions)
    inputs = PlanInputs(prep.domain, prep.problem, prep.scene, defs, failures)
    loop = ClosedLoop(prep.init, prep.goal, _options(cell=cell, seed=seed, sensor_noise=accuracy, name=name,
                                                     partial_kits=partial_kits),
                      plan=prep.plan, plan_inputs=inputs, plan_time=prep.plan_time, on_event=on_event)
    run = loop.run().run
    assert run is not None  # nothing before the execute stage can end a loop with a given plan
    return run


def _quiet(recipient: str, message: str) -> None:
    """A campaign's notifier: the failures are in the report."""


def run_trial(job: Job) -> dict[str, Any]:
    """The row of one trial: the run's report plus ``trial`` (index, seed, method, design,
    layout, time_s, error; the sensor noise and sweep level when it has them). An input or
    planning error of kitkb's is the row's ``error``."""
    t = time.perf_counter()
    facts = job.facts()
    try:
        report = _run(job, facts)
    except KitkbError as e:
        report = not_executed(job, str(e))
        facts["error"] = str(e)
    facts.setdefault("error", None)
    facts["time_s"] = round(time.perf_counter() - t, 3)
    return {**report, "trial": facts}


def _run(job: Job, facts: dict[str, Any]) -> dict[str, Any]:
    if job.deliver:
        with tempfile.TemporaryDirectory(prefix="kitkb-new-variety-") as folder:
            return _delivered(job, Path(folder), facts)
    prep = prepared(job.spec, job.domain)
    cell, accuracy = _cell(job, prep.scenario, prep.scene, facts)
    try:
        return _report(execute(prep, cell, job.spec.name, job.seed, accuracy, partial_kits=job.partial_kits), facts,
                       prep.domain, prep.problem)
    finally:
        cell.close()


def _cell(job: Job, nominal: Scenario, scene: Scene, facts: dict[str, Any]) -> tuple[WatchedCell, SensorAccuracy | None]:
    """The trial's cell, its layout in ``facts``; and the sensor's accuracy (``job.noise`` over
    the nominal state's sensor, as ``run_plan`` reads it; None: an exact sensor). By default
    the simulated cell (``sim:``, :func:`kb.cells.open_cell`) of the trial's real placement,
    faults and sensor noise; with ``job.cell`` the one cell at that URL, whose placement is its
    own (``layout.placed`` None)."""
    accuracy = sensor_accuracy(scene, job.noise)
    nominal_layout = [p.as_dict() for p in placements(nominal)]
    if job.cell is not None:
        facts["layout"] = {"nominal": nominal_layout, "placed": None, "cell": job.cell}
        return WatchedCell(open_cell(job.cell, CellRequest(accuracy=accuracy, seed=job.seed))), accuracy
    _real, placed = place_trays(nominal, job.seed)
    facts["layout"] = {"nominal": nominal_layout, "placed": [p.as_dict() for p in placed]}
    if job.faults:
        facts["faults"] = job.faults
    request = CellRequest(scene=placed_scene(scene, nominal.namespace, placed), faults=job.faults or None,
                          fault_kinds=fault_kinds(domain_inputs(job.domain).kb) if job.faults else None, seed=job.seed,
                          accuracy=accuracy)
    return WatchedCell(open_cell("sim:", request)), accuracy


def _delivered(job: Job, folder: Path, facts: dict[str, Any]) -> dict[str, Any]:
    """new-variety: the design's files written (delivered), the cell set up, then the clock
    runs from their receipt: read, plan, execute until the first CRCL command."""
    sc = layout(job.spec)
    init, goal = write_spec(sc, folder)
    cell, accuracy = _cell(job, sc, Scene.from_files([init], declared=[goal]), facts)
    received = time.perf_counter()
    try:
        inputs = LoopInputs.read(init, goal, imports=False, knowledge=domain_inputs(job.domain))
        result = ClosedLoop(init, goal, _options(cell=cell, seed=job.seed, sensor_noise=accuracy, name=job.spec.name,
                                                 partial_kits=job.partial_kits),
                            inputs=inputs).run()
    finally:
        cell.close()
    if result.run is None:  # no plan: the planner's error, the row's
        raise result.error or KitkbError(f"not executed: {result.reason}")
    run = result.run
    facts["receipt_to_first_command_s"] = (round(cell.first_command - received, 4)
                                           if cell.first_command is not None else None)
    return _report(run, facts, inputs.domain, inputs.problem)


def _report(run: Run, facts: dict[str, Any], domain: DomainSpec, problem: ProblemSpec) -> dict[str, Any]:
    """The run's report; ``facts`` gets ``built``: the designs of the kits in the order they
    were delivered where the goal wants them (:func:`kb.execution.scoring.delivered_kits`)."""
    report = {"executed": True, **run.report()}
    design = {k.get("kit"): k.get("design") for k in report.get("kits") or []}
    done = ((e["action"], e["args"]) for e in report.get("timeline") or []
            if e.get("kind") == "action" and e.get("status") == "done")
    facts["built"] = [design.get(kit, kit) for kit in delivered_kits(done, domain, problem)]
    return report
