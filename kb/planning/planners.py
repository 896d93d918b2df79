"""Planners: choose one for a problem, run it, validate its plan, write the plan file.

The planner is chosen by unified-planning's factory: the first engine of its preference list
(Fast Downward first) that is installed, plans in one shot and declares support for the
problem's kind, so a classical STRIPS problem goes to Fast Downward and a numeric one to
ENHSP. ``name`` overrides the choice.

A plan is written only after unified-planning's sequential plan validator accepted it,
one action per line as in the seeds: ``(take-part robot_1 part_e1 ptr_e part_gripper)``.
"""

from __future__ import annotations

import contextlib
import subprocess
import sys
import tempfile
import time
from importlib.resources import as_file, files
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Protocol

from kb.core.errors import ConfigurationError, InputError, KitkbError, NotSolvableError
from kb.core.files import write_atomic
from kb.core.progress import SILENT, Progress
from kb.patches.unified_planning import environment, validator_speedups

#: Which PyPI package provides a unified-planning engine.
PACKAGES = {
    "fast-downward": "up-fast-downward", "fast-downward-opt": "up-fast-downward",
    "enhsp": "up-enhsp", "enhsp-opt": "up-enhsp", "enhsp-any": "up-enhsp",
    "pyperplan": "up-pyperplan", "pyperplan-opt": "up-pyperplan",
    "tamer": "up-tamer", "lpg": "up-lpg", "aries": "up-aries", "symk": "up-symk",
}
#: Engine parameters kitkb passes. Fast Downward: lazy greedy best-first search with one FF
#: heuristic, also used for preferred operators (plans at or near the minimum length here, without
#: LAMA's landmark generation, which costs seconds on large kits); the translator skips
#: invariant synthesis and causal-graph variable reordering, which cost more than they
#: save on this domain (see docs/benchmarks.md).
PARAMS: dict[str, dict[str, Any]] = {
    # ENHSP: greedy search with the MRP heuristic and helpful actions; its default
    # configuration needs minutes on kitkb's numeric encoding of a two-kit scenario.
    "enhsp": {"params": "-planner sat-hmrphj"},
    "fast-downward": {
        # ``let`` shares one FF heuristic between the open list and the preferred operators
        # (``[ff()], preferred=[ff()]`` builds two and evaluates every state twice).
        "fast_downward_search_config": "let(h,ff(),lazy_greedy([h],preferred=[h]))",
        "fast_downward_translate_options": [
            "--invariant-generation-max-candidates", "0", "--skip-variable-reordering"],
    },
}


@dataclass
class PlanResult:
    """What a planning run produced: the plan's lines, its cost under the problem's metric
    (None without one), and where the time went."""

    planner: str
    lines: list[str]
    status: str
    times: dict[str, float] = field(default_factory=dict)
    cost: float | int | None = None


class Source(Protocol):
    """What a problem read from files can say about itself (:class:`kb.planning.pddl.PddlTask`):
    names, where features are used, and (``planner_texts``) the PDDL a planner that reads
    axioms plans with, when unified-planning's problem cannot carry them."""

    planner_texts: tuple[str, str] | None

    def original(self, name: str) -> str:
        """The name in the files of an object or action of the problem."""

    def explain(self, kind_flags: list[str] | set[str]) -> tuple[str, tuple[Path, int] | None]:
        """The file features behind unified-planning kind flags, and where the first is used."""


def choose_planner(problem: Any, name: str | None = None, source: Source | None = None) -> str:
    """The engine to use for ``problem``: ``name`` if given (installed and able), else the
    first engine unified-planning's factory finds applicable to the problem's kind
    (``source``: where a feature no engine takes is used, for the error)."""
    from unified_planning.engines import OperationMode

    factory = environment().factory
    applicable = factory.get_all_applicable_engines(problem.kind, OperationMode.ONESHOT_PLANNER)
    if name is not None:
        if name not in factory.engines:
            raise _not_installed(name)
        if name not in applicable:
            missing = _missing(factory.engine(name), problem.kind)
            raise _refusal(f"planner {name} does not support this problem", missing, source,
                           "it does not plan in one shot")
        return name
    if not applicable:
        planners = [n for n in factory.preference_list if n in PACKAGES and n in factory.engines]
        missing = set.intersection(*(_missing(factory.engine(n), problem.kind) for n in planners)) \
            if planners else set(problem.kind.features)
        if not missing and planners:  # each lacks something, no one flag all of them lack
            missing = _missing(factory.engine(planners[0]), problem.kind)
        hint = "" if planners else "; install up-fast-downward (classical) or up-enhsp (numeric)"
        raise _refusal("no installed planner supports this problem", missing or set(problem.kind.features),
                       source, "", hint=hint)
    return applicable[0]


def _missing(engine: Any, kind: Any) -> set[str]:
    return set(kind.features) - set(engine.supported_kind().features)


def _refusal(what: str, missing: set[str], source: Source | None, empty: str, hint: str = "") -> KitkbError:
    """The error of a problem an engine does not take: its features named, at the line of the
    first where the problem came from files."""
    if source is not None and missing:
        features, where = source.explain(missing)
        message = f"{what}: {features}{hint}"
        return InputError(message, *where) if where else ConfigurationError(message)
    if not missing:
        return ConfigurationError(f"{what} ({empty})")
    return ConfigurationError(f"{what} ({', '.join(sorted(missing))}){hint}")


def _not_installed(name: str) -> ConfigurationError:
    package = PACKAGES.get(name)
    hint = f"pip install {package}" if package else "see unified-planning's list of engines"
    return ConfigurationError(f"planner {name} is not installed ({hint})")


def solve(problem: Any, planner: str, timeout: float | None = None, engine_defaults: bool = False) -> Any:
    """Run ``planner`` on ``problem``; the plan, or NotSolvableError with the planner's status.

    kitkb's :data:`PARAMS` are passed to the engine unless ``engine_defaults``.
    """
    factory = environment().factory
    try:
        engine_cm = factory.OneshotPlanner(name=planner, params=None if engine_defaults else PARAMS.get(planner))
    except Exception as exc:  # an engine that cannot start (missing binary, Java, ...)
        raise ConfigurationError(f"planner {planner} cannot start: {exc} "
                                 f"(package {PACKAGES.get(planner, '?')})") from None
    # in a folder of its own: Fast Downward's driver writes its output.sas in the current
    # folder, so two plans made at once from one folder would overwrite each other's file
    with engine_cm as engine, tempfile.TemporaryDirectory(prefix="kitkb-plan-") as work, contextlib.chdir(work):
        try:
            result = engine.solve(problem, timeout=timeout)
        except FileNotFoundError as exc:
            raise ConfigurationError(f"planner {planner} cannot run: {exc} (is Java installed for ENHSP?)") from None
    return _plan_of(result, planner)


def _plan_of(result: Any, planner: str) -> Any:
    """The plan of an engine's ``PlanGenerationResult``, or the error its status means."""
    from unified_planning.engines import PlanGenerationResultStatus as Status

    ok = (Status.SOLVED_SATISFICING, Status.SOLVED_OPTIMALLY)
    if result.status in (Status.UNSUPPORTED_PROBLEM, Status.INTERNAL_ERROR):  # not "no plan exists"
        raise ConfigurationError(f"planner {planner} cannot plan this problem: it says {result.status.name}"
                                 f"{_last_log(result, failure=True)}")
    if result.status not in ok or result.plan is None:
        detail = _last_log(result)
        raise NotSolvableError(f"no plan: {planner} says {result.status.name}{detail}")
    return result.plan


#: Planners that read PDDL axioms (derived predicates), with the search kitkb runs; the opt
#: one is A* without a heuristic (LM-cut, unified-planning's choice, does not take axioms).
AXIOM_SEARCH = {"fast-downward": PARAMS["fast-downward"]["fast_downward_search_config"],
                "fast-downward-opt": "astar(blind())"}
#: Fast Downward driver exit codes (driver/returncodes.py) that mean no plan, and what they say.
_FD_NO_PLAN = {10: "UNSOLVABLE_PROVEN", 11: "UNSOLVABLE_PROVEN", 12: "UNSOLVABLE_INCOMPLETELY",
               13: "UNSOLVABLE_INCOMPLETELY", 20: "MEMOUT", 21: "TIMEOUT", 22: "MEMOUT", 23: "TIMEOUT",
               24: "MEMOUT"}


def solve_axioms(problem: Any, texts: tuple[str, str], planner: str | None, timeout: float | None = None,
                 engine_defaults: bool = False, source: Source | None = None) -> Any:
    """Plan with Fast Downward on PDDL ``texts`` that hold axioms (derived predicates), which
    unified-planning's problem cannot carry; the plan as actions of ``problem`` (same names)."""
    name = planner or "fast-downward"
    if name not in AXIOM_SEARCH:
        raise _refusal(f"planner {name} does not support this problem", {"RECURSIVE_DERIVED_PREDICATES"}, source,
                       "", hint=f" (planners that do: {', '.join(AXIOM_SEARCH)})")
    try:
        driver_resource = files("up_fast_downward").joinpath("downward/fast-downward.py")
    except ModuleNotFoundError:
        raise _not_installed(name) from None
    limit = ["--overall-time-limit", f"{max(1, int(timeout))}s"] if timeout else []
    with as_file(driver_resource) as driver, tempfile.TemporaryDirectory(prefix="kitkb-plan-") as work:
        folder = Path(work)
        (folder / "domain.pddl").write_text(texts[0])
        (folder / "problem.pddl").write_text(texts[1])
        cmd = [sys.executable, str(driver), *limit, "--plan-file", "plan"]
        if engine_defaults and name == "fast-downward":  # what unified-planning's engine runs by default
            cmd += ["--alias", "lama-first", "domain.pddl", "problem.pddl"]
        else:
            cmd += ["domain.pddl", "problem.pddl", "--translate-options",
                    *PARAMS["fast-downward"]["fast_downward_translate_options"],
                    "--search-options", "--search", AXIOM_SEARCH[name]]
        proc = subprocess.run(cmd, cwd=folder, capture_output=True, text=True)
        if proc.returncode in _FD_NO_PLAN:
            raise NotSolvableError(f"no plan: {name} says {_FD_NO_PLAN[proc.returncode]}")
        plan_file = folder / "plan"
        if proc.returncode not in (0, 1, 2, 3) or not plan_file.exists():
            lines = [line.strip() for line in (proc.stdout + proc.stderr).splitlines() if line.strip()]
            said = [line for line in lines if line.lower().startswith(("error", "unsupported", "critical"))] \
                or [line for line in lines if not line.startswith("INFO") and "exit code" not in line] or ["?"]
            raise ConfigurationError(f"planner {name} failed (exit code {proc.returncode}): {said[-1][:200]}")
        text = plan_file.read_text()
    environment()
    from unified_planning.io import PDDLReader

    return PDDLReader().parse_plan_string(problem, text)


def _last_log(result: Any, failure: bool = False) -> str:
    """The planner's own words about the outcome, if its log has them (``failure``: the last
    line before it gave up)."""
    lines = [line.strip() for m in (getattr(result, "log_messages", None) or [])
             for line in m.message.splitlines() if line.strip()]
    telling = [line for line in lines if "solution" in line.lower() or "unsolvable" in line.lower()]
    if failure:
        telling = [line for line in lines if not line.startswith("INFO") and "exit code" not in line
                   and "aborting" not in line.lower()]
    return f" ({telling[-1][:200]})" if telling else ""


def check_validatable(problem: Any, source: Source | None = None) -> None:
    """Raise unless unified-planning's plan validator can check plans of ``problem`` (asked
    before planning: a plan that cannot be checked is not written, so it is not made)."""
    from unified_planning.engines.plan_validator import SequentialPlanValidator

    missing = set(problem.kind.features) - set(SequentialPlanValidator.supported_kind().features)
    if missing:
        raise _refusal("unified-planning's plan validator cannot check plans of this problem", missing,
                       source, "", hint="; no plan written")


def validate(problem: Any, plan: Any, source: Source | None = None) -> None:
    """Raise unless unified-planning's plan validator accepts ``plan`` for ``problem``."""
    from unified_planning.engines import ValidationResultStatus
    from unified_planning.engines.plan_validator import SequentialPlanValidator
    from unified_planning.exceptions import UPUsageError

    check_validatable(problem, source)
    try:
        with validator_speedups():
            result = SequentialPlanValidator().validate(problem, plan)
    except UPUsageError as exc:
        raise KitkbError(f"unified-planning's plan validator cannot check this problem: {exc}") from None
    if result.status != ValidationResultStatus.VALID:
        reason = getattr(result, "reason", None) or getattr(result, "inapplicable_action", None) or ""
        raise KitkbError(f"the planner's plan does not validate: {result.status.name} {reason}".strip())


def plan_lines(plan: Any, source: Source | None = None) -> list[str]:
    """One ``(action arg ...)`` line per action of a sequential plan (named as in the files
    the problem came from, with ``source``)."""
    name = source.original if source is not None else (lambda n: n)
    lines = []
    for ai in plan.actions:
        args = " ".join(name(str(p.object())) if p.is_object_exp() else str(p) for p in ai.actual_parameters)
        lines.append(f"({name(ai.action.name)}{' ' + args if args else ''})")
    return lines


def plan_cost(problem: Any, plan: Any) -> float | int | None:
    """The cost of ``plan`` under the problem's action-cost or plan-length metric (None
    without one); action costs are read from the initial state (they are static)."""
    from unified_planning.model.walkers import FreeVarsExtractor

    metrics = problem.quality_metrics
    if not metrics:
        return None
    metric = metrics[0]
    if metric.is_minimize_sequential_plan_length():
        return len(plan.actions)
    if not metric.is_minimize_action_costs():
        return None
    fluents = FreeVarsExtractor()
    total = 0
    for ai in plan.actions:
        cost = metric.get_action_cost(ai.action)
        if cost is None:
            continue
        cost = cost.substitute(dict(zip(ai.action.parameters, ai.actual_parameters)))
        cost = cost.substitute({f: problem.initial_value(f) for f in fluents.get(cost)}).simplify()
        total += cost.constant_value()
    return int(total) if float(total).is_integer() else float(total)


def write_plan(lines: list[str], path: str | Path) -> Path:
    """Write the plan lines to ``path`` (atomically)."""
    return write_atomic(path, "".join(line + "\n" for line in lines))


class Started:
    """A planner already at work on a problem (:func:`start`): :func:`run` reads its plan
    (``started=``); :meth:`cancel` stops it when the plan is not wanted after all."""

    def __init__(self, problem: Any, planner: str | None, name: str, solving: Any) -> None:
        self.problem, self.planner, self.name, self._solving = problem, planner, name, solving
        self.seconds = 0.0  # spent here starting it (the caller's time, the planner's part)

    def plan(self) -> Any:
        """Wait for the planner; its plan (or the error ``solve`` would raise)."""
        return _plan_of(self._solving.result(), self.name)

    def cancel(self) -> None:
        self._solving.cancel()


def start(problem: Any, planner: str | None = None, source: Source | None = None) -> Started | None:
    """Start the planner :func:`run` would choose for ``problem`` (kitkb's parameters, no time
    limit) as a process of its own and return at once, so that other work runs on another core
    while it plans; None where it cannot be started ahead (a problem with axioms, a planner not
    run as a PDDL process, a refusal: :func:`run` then plans, or says why, as without)."""
    from kb.patches.unified_planning import StartedSolve

    t = time.perf_counter()
    if source is not None and source.planner_texts:
        return None
    engine = None
    try:
        name = choose_planner(problem, planner, source)
        check_validatable(problem, source)
        engine = environment().factory.OneshotPlanner(name=name, params=PARAMS.get(name))
        solving = StartedSolve.start(engine, problem)
    except Exception:  # noqa: BLE001 - whatever refuses here is said by run(), at its place
        solving = None
    if solving is None:
        if engine is not None:
            engine.destroy()
        return None
    started = Started(problem, planner, name, solving)
    started.seconds = time.perf_counter() - t
    return started


def run(problem: Any, out: str | Path | None, planner: str | None = None,
        timeout: float | None = None, engine_defaults: bool = False, progress: Progress = SILENT,
        source: Source | None = None, started: Started | None = None) -> PlanResult:
    """Choose a planner, solve, validate, and write the plan to ``out`` (if given);
    ``progress``: where solving and validating report (:mod:`kb.core.progress`); ``source``:
    the files the problem came from (names in the plan, where a refused feature is used);
    ``started``: the same problem's planner already at work (:func:`start`; only without a
    ``timeout`` or ``engine_defaults``), whose plan is read instead of solving again."""
    if started is not None and (started.problem is not problem or started.planner != planner or timeout
                                or engine_defaults):
        started.cancel()
        started = None
    times: dict[str, float] = {}
    t0 = time.perf_counter()
    axioms = source.planner_texts if source is not None else None
    if axioms:  # Fast Downward, called on the text with the axioms; it must take the rest too
        name = planner or "fast-downward"
        choose_planner(problem, "fast-downward", source)
    else:
        name = choose_planner(problem, planner, source)
    check_validatable(problem, source)
    if started is not None and started.name != name:
        started.cancel()
        started = None
    with progress.task(f"solving with {name}" + (f" (time limit {timeout:g} s)" if timeout else "")):
        if started is not None and started.name == name:
            plan = started.plan()
        elif axioms:
            plan = solve_axioms(problem, axioms, name, timeout, engine_defaults, source)
        else:
            plan = solve(problem, name, timeout, engine_defaults)
    times["solve"] = time.perf_counter() - t0
    t1 = time.perf_counter()
    with progress.task("validating the plan (unified-planning)"):
        validate(problem, plan, source)
    times["validate"] = time.perf_counter() - t1
    lines = plan_lines(plan, source)
    if out is not None:
        write_plan(lines, out)
    return PlanResult(name, lines, "valid", times, plan_cost(problem, plan))
