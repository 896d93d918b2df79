"""The main job: everything kitkb does, end to end, on the shipped scenarios.

The closed loop is the library's (:class:`kb.execution.loop.ClosedLoop`: each file read once,
every stage a library call); this module only draws its typed events (:mod:`kb.execution.events`,
no text parsed back) as one line per stage and per action, so that ``./main.sh`` shows a new
user what the project does:

1. validate the shipped model (closed world, SHACL);
2. for each shipped scenario: validate its initial and goal state files, generate the PDDL
   domain and problem, plan with a real planner (validated plan), check that the predicates
   decided from the objects' boxes equal the PDDL facts (and the goal holds in the goal's
   boxes), and load the initial state into the world-model database and read every object's
   global pose back.

Outputs go to ``out_dir`` (default ``out/``): ``<scenario>/domain.pddl``, ``problem.pddl``,
``plan.txt`` and ``world.sqlite``. On a terminal each stage also shows as progress on standard
error (the execution as actions done of the plan's); with ``--format json`` the stage lines are
left out and the report (what ``--report`` writes) is printed on standard output.
"""

from __future__ import annotations

import json
import sys
import time
from collections import Counter
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, TextIO

from kb.cli.output import Output
from kb.core.errors import InputError
from kb.core.files import write_atomic
from kb.core.namespaces import local_name
from kb.core.progress import SILENT, Progress
from kb.core.resources import ontologies_dir, scenario_dirs
from kb.execution import events as ev
from kb.execution.loop import ClosedLoop, LoopOptions
from kb.execution.scoring import delivered_kits
from kb.validation import validate


def run(files: list[str], output: str, faults: str | None, seed: int, db: str | None, report: str | None,
        cell: str | None, match_names: bool, out: Output, domain: list[str] | None = None,
        replace: bool = False, report_html: str | None = None, sensor_noise: str | None = None,
        partial_kits: str | None = None, resume: int | None = None, truth: str | None = None) -> int:
    """``kitkb run [INIT GOAL]``: the closed loop on the files, or the main job on every shipped
    scenario; a line per stage and action on standard output (with ``--quiet`` only the problems
    found; with ``--format json`` the report instead, the problems on standard error).
    ``--resume RUN_ID --db URL``: that stopped run gone on with (:mod:`kb.execution.resume`)."""
    if resume is not None:
        return _resume_command(resume, files, output, faults, seed, db, report, cell, out, truth, report_html,
                               domain=domain, replace=replace, sensor_noise=sensor_noise, partial_kits=partial_kits,
                               match_names=match_names)
    if files and len(files) != 2:
        raise InputError(f"kitkb run takes an initial and a goal state file, not {len(files)} file(s)")
    if db and not files:
        raise InputError("--db takes one scenario (kitkb run INIT GOAL --db URL); the main job writes "
                         "out/<scenario>/world.sqlite for each")
    if sensor_noise is not None:  # refused before any work
        from kb.cells.accuracy import SensorAccuracy
        try:
            SensorAccuracy.parse(sensor_noise)
        except ValueError as exc:
            raise InputError(f"--sensor-noise: {exc}") from None
    if cell is not None or faults:  # a URL, scheme, parameter or fault that cannot work is refused before any work
        _check_cell(cell, faults, seed, domain)
    options = RunOptions(faults, seed, db, cell, match_names, domain, replace, sensor_noise, partial_kits, truth)
    show = _Show(display=out.tracker, problems=_Current("stderr") if out.is_json else None,
                 on_report=(lambda data: print(json.dumps(data, indent=1), file=out.results, flush=True))
                 if out.is_json else None, html=report_html)
    stream: TextIO = _Discard() if out.is_json else out.stdout or _Current("stdout")  # type: ignore[assignment]
    if files:
        return run_files(stream, files[0], files[1], output, options, report, quiet=out.quiet, show=show)
    return run_main_job(stream, output, quiet=out.quiet, options=options, report_path=report, show=show)


def _resume_command(run_id: int, files: list[str], output: str, faults: str | None, seed: int, db: str | None,
                    report: str | None, cell: str | None, out: Output, truth: str | None, report_html: str | None,
                    **refused: Any) -> int:
    """``kitkb run --resume RUN_ID --db URL``: the run gone on with, drawn as a run is; 0 when
    the goal holds at the end and nothing stopped it."""
    if files:
        raise InputError("--resume takes no INIT GOAL: the run's own files are read again from --db")
    if not db:
        raise InputError("--resume RUN_ID needs the database the run was recorded in (--db URL)")
    given = [f"--{k.replace('_', '-')}" for k, v in refused.items() if v]
    if given:
        raise InputError(f"--resume goes on with the run's own {', '.join(given)} (as recorded): "
                         "give only --faults, --seed, --cell and --truth for the cell now")
    if cell is not None or faults:
        _check_cell(cell, faults, seed, None)
    from kb.execution.resume import Resume, ResumeOptions
    show = _Show(display=out.tracker, problems=_Current("stderr") if out.is_json else None,
                 on_report=(lambda data: print(json.dumps(data, indent=1), file=out.results, flush=True))
                 if out.is_json else None, html=report_html)
    stream: TextIO = _Discard() if out.is_json else out.stdout or _Current("stdout")  # type: ignore[assignment]
    progress = _Progress(stream, out.quiet, show)
    target = Path(output) / f"resume-{run_id}"
    options = RunOptions(faults, seed, db, cell, truth=truth)
    drawing = _Drawing(f"run {run_id}", Path(db), Path(db), target, progress, options)
    try:
        result = Resume(db, run_id, ResumeOptions(truth=truth, cell=cell, faults=faults, seed=seed or None,
                                                  out_dir=target, notifier=_quiet),
                        on_event=drawing, progress=progress.display).run()
    finally:
        drawing.close()
    _write_report(report, [result.report()], progress.show)
    return 0 if result.ok else 1


def _check_cell(cell: str | None, faults: str | None, seed: int, domain: list[str] | None) -> None:
    """``--cell`` and ``--faults`` as the cell's opener will read them (the kinds the faults name:
    the domain's, ``--domain`` included)."""
    from kb.cells import DEFAULT_URL, CellRequest, check_cell
    from kb.model.faults import domain_fault_kinds
    kinds = domain_fault_kinds(domain) if faults else None
    try:
        check_cell(cell or DEFAULT_URL, CellRequest(faults=faults or None, seed=seed or None, fault_kinds=kinds))
    except InputError as e:
        if cell is not None:
            raise
        raise InputError(f"--faults: {getattr(e, 'reason', e.message)}") from None


class _Current:
    """A standard stream as it is when written to (a progress display stands in for it while it
    is shown, to print lines above itself)."""

    def __init__(self, name: str) -> None:
        self.name = name

    def write(self, text: str) -> int:
        return getattr(sys, self.name).write(text)

    def flush(self) -> None:
        getattr(sys, self.name).flush()


class _Discard:
    """The stage lines with ``--format json``: nowhere."""

    def write(self, text: str) -> int:
        return len(text)

    def flush(self) -> None:
        pass


@dataclass
class _Show:
    """Where a run shows itself besides its lines: progress, the problems' stream (default: the
    lines' own), the report once made (``--format json``)."""

    display: Progress = SILENT
    problems: Any = None  # a stream
    on_report: Callable[[Any], None] | None = None
    html: str | None = None  # where the report goes as an HTML page (--report-html)


@dataclass
class RunOptions:
    """How scenarios are executed: injected faults and their seed, the database, the cell."""

    faults: str | None = None
    seed: int = 0
    db: str | None = None
    cell: str | None = None
    match_names: bool = False
    domain: list[str] | None = None  # domain files (failure modes, remediations) instead of the shipped one
    replace: bool = False  # --db may replace what the database holds
    sensor_noise: str | None = None  # the sensor's accuracy, over the state file's (--sensor-noise)
    partial_kits: str | None = None  # a kit the parts cannot finish: deliver | leave (--partial-kits)
    truth: str | None = None  # the state the simulated cell holds (--truth)


class _Progress:
    """The main job's lines: stages (unless quiet) and problems (always); ``display`` shows each
    stage's progress while it runs."""

    def __init__(self, out: TextIO, quiet: bool, show: _Show | None = None) -> None:
        self.out, self.quiet = out, quiet
        self.show = show or _Show()
        self.display = self.show.display

    def say(self, text: str) -> None:
        if not self.quiet:
            print(text, file=self.out)

    def stage(self, label: str, started: float) -> None:
        self.say(f"  {label} ({time.perf_counter() - started:.2f} s)")

    def problem(self, text: str) -> None:
        print(text, file=self.show.problems or self.out)


def run_main_job(out: TextIO, out_dir: str | Path = "out", quiet: bool = False, options: RunOptions | None = None,
                 report_path: str | None = None, show: _Show | None = None) -> int:
    """Run every stage on the shipped scenarios; 0 when all succeeded, 1 otherwise."""
    options = options or RunOptions()
    progress = _Progress(out, quiet, show)
    reports: list[dict] = []
    status = 0
    model = sorted(ontologies_dir().glob("*.ttl"))
    scenarios = scenario_dirs()
    progress.say(f"kitkb: main job on {len(scenarios)} shipped scenarios, outputs in {out_dir}/")
    t = time.perf_counter()
    with progress.display.task(f"validating the model ({len(model)} files)"):
        report = validate([str(p) for p in model])
    progress.stage(f"model: {len(model)} files, {report.summary()}", t)
    for diag in report.diagnostics:
        progress.problem("    " + diag.format())
    status |= 0 if report.conforms else 1
    with progress.display.task("shipped scenarios", total=len(scenarios), unit="scenarios") as task:
        for scenario in scenarios:
            progress.say(f"{scenario.name}:")
            status |= _scenario(scenario.name, scenario / "init.ttl", scenario / "goal.ttl",
                                Path(out_dir) / scenario.name, progress, options, reports)
            task.advance()
    _write_report(report_path, reports, progress.show)
    if status:
        progress.problem("kitkb: main job found problems")
    else:
        progress.say("kitkb: main job succeeded")
    return status


def run_files(out: TextIO, init: str | Path, goal: str | Path, out_dir: str | Path, options: RunOptions,
              report: str | None, quiet: bool = False, show: _Show | None = None) -> int:
    """The closed loop on one initial and goal state: 0 when the goal holds at the end."""
    progress = _Progress(out, quiet, show)
    reports: list[dict] = []
    # a state called init.ttl is named by its folder (run from inside it too: ./init.ttl)
    name = Path(init).resolve().parent.name if Path(init).stem == "init" else Path(init).stem
    status = _scenario(name, Path(init), Path(goal), Path(out_dir) / name, progress, options, reports, model_files=False)
    _write_report(report, reports, progress.show)
    return status


def _write_report(path: str | None, reports: list[dict], show: _Show | None = None) -> None:
    """The report to ``path`` (if given), as a page to ``show.html`` (``--report-html``) and to
    ``show.on_report`` (``--format json``)."""
    html = show.html if show is not None else None
    if path is None and html is None and (show is None or show.on_report is None):
        return
    data = _report_data(reports)
    if path is not None:
        write_atomic(Path(path), json.dumps(data, indent=1) + "\n")
    if html is not None:
        from kb.report import run_page  # plotly only when a page is asked for
        write_atomic(Path(html), run_page(json.loads(json.dumps(data))))
    if show is not None and show.on_report is not None:
        show.on_report(data)


def _report_data(reports: list[dict]) -> dict:
    if len(reports) == 1:
        data = reports[0]
    else:
        data = {"goal_holds": all(r["goal_holds"] for r in reports) if reports else False,
                "injected": [dict(x, scenario=r["scenario"]) for r in reports for x in r["injected"]],
                "failures": [dict(x, scenario=r["scenario"]) for r in reports for x in r["failures"]],
                "runs": reports}
    return data


def _scenario(name: str, init: Path, goal: Path, target: Path, progress: _Progress, options: RunOptions,
              reports: list[dict], model_files: bool = True) -> int:
    """One scenario's closed loop (:class:`kb.execution.loop.ClosedLoop`), drawn from its events;
    the loop holds its world model's writer lock from the start (a second run or a load of the
    same database is refused before any work, not after planning)."""
    db_file: str | Path = options.db or target / "world.sqlite"
    loop_options = LoopOptions(faults=options.faults, seed=options.seed, cell=options.cell,
                               match_names=options.match_names, domain_files=options.domain,
                               sensor_noise=options.sensor_noise, out_dir=target, db=db_file,
                               replace=options.replace or not options.db,  # the job's own output is replaced
                               notifier=_quiet, name=name, partial_kits=options.partial_kits, truth=options.truth)
    drawing = _Drawing(name, init, goal, target, progress, options)
    try:
        result = ClosedLoop(init, goal, loop_options, on_event=drawing, progress=progress.display).run()
    finally:
        drawing.close()
    reports.append(result.report())
    return 0 if result.ok else 1


def _quiet(recipient: str, message: str) -> None:
    """The run's notifier: its notifications are drawn from their events."""


class _Drawing:
    """The lines and progress of one scenario's closed loop, drawn from its events
    (:mod:`kb.execution.events`): a line per stage (its result, its time) and per executor
    event, the problems found, and on a terminal a progress task per stage (the execution as
    actions done of the plan's)."""

    _TASKS = {"pddl": "generating the PDDL domain and problem", "plan": "planning",
              "geometry": "deciding the predicates from geometry", "world": "loading the world model",
              "locate": "sensing the objects the state does not locate",
              "resume": "reading the stopped run and its stable state"}

    def __init__(self, name: str, init: Path, goal: Path, target: Path, progress: _Progress,
                 options: RunOptions) -> None:
        self.name, self.init, self.goal, self.target = name, init, goal, target
        self.progress, self.options = progress, options
        self.task: Any = None
        self._open: Any = None
        self.done = 0

    def __call__(self, event: ev.Event) -> None:
        if isinstance(event, ev.StageStarted):
            self._started(event)
        elif isinstance(event, ev.StageEnded):
            self.close()
            getattr(self, f"_{event.stage}")(event)
        else:
            self._executor(event)

    def close(self) -> None:
        """Close the progress task of the stage that is running (if any)."""
        if self._open is not None:
            opened, self._open, self.task = self._open, None, None
            opened.__exit__(None, None, None)

    def _started(self, event: ev.StageStarted) -> None:
        total, unit = None, ""
        if event.stage == "validate":
            what = f"validating {self.init.name} and {self.goal.name}"
        elif event.stage == "execute":
            what, total, unit = "executing the plan", event.detail.get("actions"), "actions"
            self.progress.say(f"  execute in {self._where()}:")
        else:
            what = self._TASKS[event.stage]
        self._open = self.progress.display.task(f"{self.name}: {what}", total=total, unit=unit)
        self.task = self._open.__enter__()
        self.done = 0

    def _where(self) -> str:
        o = self.options
        if o.cell:
            return f"the cell at {o.cell}"
        return "the simulated cell" + (f" (faults {o.faults}, seed {o.seed})" if o.faults else "") + (
            f" (sensor noise {o.sensor_noise})" if o.sensor_noise else "")

    def _line(self, label: str, event: ev.StageEnded) -> None:
        self.progress.say(f"  {label} ({event.seconds:.2f} s)")

    def _problem(self, text: str) -> None:
        self.progress.problem(f"    {self.name}: {text}")

    def _not_executed(self, event: ev.StageEnded) -> None:
        if not event.ok:
            self._problem(f"not executed: {event.reason}")

    # --- one method per stage, at its end ---------------------------------------------------
    def _validate(self, event: ev.StageEnded) -> None:
        report = event.result
        self._line(f"validate: {report.summary()}", event)
        for diag in report.diagnostics:
            self._problem(diag.format())
        self._not_executed(event)

    def _resume(self, event: ev.StageEnded) -> None:
        self._line(event.result.text(), event)

    def _locate(self, event: ev.StageEnded) -> None:
        self._line(event.result.text(), event)

    def _pddl(self, event: ev.StageEnded) -> None:
        self.model = event.result  # the planning model: which goal atoms an action's effects make true
        if event.result is None:  # too few parts for the whole goal: planned for the kits they allow
            self._line("pddl: not written (too few usable parts for every kit: planning for the kits they allow)", event)
            return
        self._line(f"pddl: {self.target / 'domain.pddl'}, {self.target / 'problem.pddl'}", event)

    def _plan(self, event: ev.StageEnded) -> None:
        if event.ok:
            result = event.result
            self._line(f"plan: {len(result.lines)} actions by {result.planner}, validated -> "
                       f"{self.target / 'plan.txt'}", event)
        self._not_executed(event)

    def _geometry(self, event: ev.StageEnded) -> None:
        geo = event.result
        verdict = ("equal to the PDDL init facts" if geo.initial_agrees else "DISAGREE with the PDDL init facts") + (
            "; every goal fact holds in the goal" if not geo.goal_not_holding else
            f"; {len(geo.goal_not_holding)} goal fact(s) do not hold in the goal file's own geometry")
        self._line(f"geometry: {geo.atoms} atoms hold in the initial state's boxes, {verdict}", event)
        for what, atoms in (("only in geometry", geo.only_geometry), ("only in PDDL", geo.only_symbolic)):
            for atom in atoms:
                self._problem(f"{what}: ({' '.join(atom)})")
        for atom in geo.goal_not_holding:  # the run is judged on the cell's geometry at its end
            self._problem(f"warning: goal file's geometry does not show ({' '.join(atom)})")
        if not geo.initial_agrees:
            for cause in geo.causes:
                self._problem(f"likely cause: {cause}")
        self._not_executed(event)

    def _world(self, event: ev.StageEnded) -> None:
        world = event.result
        self._line(f"world model: {world.individuals} individuals (workstation and domain), {world.poses} global "
                   f"poses -> {world.url}", event)

    def _execute(self, event: ev.StageEnded) -> None:
        rec = event.result.record
        data = event.result.report()
        modes = Counter(f.mode for f in rec.failures)
        recoveries = Counter(f.recovery for f in rec.failures if f.recovery)
        kits = sorted(set(_kits(rec, getattr(self, "model", None))))
        unmet = f" (unmet: {', '.join(rec.goal_unmet)})" if rec.goal_unmet else ""
        summary = (f"execute: goal {'holds' if rec.goal_holds else 'DOES NOT hold'} (from geometry){unmet}; kits "
                   f"{', '.join(kits) or '-'}; {data['actions']} actions, {data['checks']} checks; failures "
                   f"{', '.join(f'{m} {n}' for m, n in sorted(modes.items())) or 'none'}; recoveries "
                   f"{', '.join(f'{m} {n}' for m, n in sorted(recoveries.items())) or 'none'}; replans {rec.replans}")
        if rec.partial_kits:
            summary += "; partial kits " + ", ".join(
                f"{p['kit']} {p['outcome']} (lacks {', '.join(f'{sku} {n}' for sku, n in p['lacks'].items())})"
                for p in rec.partial_kits)
        if rec.injected:
            summary += "; injected " + ", ".join(f"{x['kind']}@{x['action_index']}" for x in rec.injected)
        contacts = data["metrics"]["contact_errors"]
        if contacts:
            summary += f"; contact errors {contacts}"
        self._line(summary, event)
        for kit in rec.kits:
            self.progress.say(f"  kit {local_name(kit.kit)}: {kit.score} of {kit.max_score} points" +
                              ("" if not kit.lost else "; lost: " + "; ".join(
                                  f"{x.points} for {x.reason} ({x.predicate})" for x in kit.lost)))
        if rec.stopped:
            self._problem(f"stopped: {rec.stopped}")

    # --- the executor's events --------------------------------------------------------------
    def _executor(self, event: ev.Event) -> None:
        text = event.text()
        if text is not None:
            self.progress.say("  " + text)
        if self.task is None:
            return
        if isinstance(event, ev.ActionEnded) and event.status == "done":
            self.done += 1
            self.task.advance()
        elif isinstance(event, ev.Replanned):
            self.task.update(total=self.done + event.actions)


def _kits(rec, model) -> list[str]:  # noqa: ANN001
    """The goal's kits the run delivered (:func:`kb.execution.scoring.delivered_kits`: an action
    done whose effects make a goal atom about the kit true), by the planning ``model``."""
    if model is None or getattr(model, "problem", None) is None:
        return []
    done = ((act.action, act.args) for act in rec.actions if act.status == "done")
    return delivered_kits(done, model.domain, model.problem)
