"""Planners: choose one for a problem, run it, validate its plan, write the plan file.

The planner is chosen from the problem's kind, the way unified-planning does it: the first
engine of :data:`PREFERENCE` (then of unified-planning's own preference list) that is
installed and whose declared ``supported_kind`` covers the problem. A classical STRIPS
problem goes to Fast Downward, a numeric one to ENHSP. ``name`` overrides the choice.

A plan is written only after unified-planning's sequential plan validator accepted it,
one action per line as in the seeds: ``(take-part robot_1 part_e1 ptr_e part_gripper)``.
"""

from __future__ import annotations

import time
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Iterator

from generators.pddl.up_env import environment
from kb.errors import ConfigurationError, KitkbError, NotSolvableError

#: Which PyPI package provides a unified-planning engine.
PACKAGES = {
    "fast-downward": "up-fast-downward", "fast-downward-opt": "up-fast-downward",
    "enhsp": "up-enhsp", "enhsp-opt": "up-enhsp", "enhsp-any": "up-enhsp",
    "pyperplan": "up-pyperplan", "pyperplan-opt": "up-pyperplan",
    "tamer": "up-tamer", "lpg": "up-lpg", "aries": "up-aries", "symk": "up-symk",
}
#: Engines tried first, in this order (then unified-planning's own preference list).
PREFERENCE = ["fast-downward", "enhsp", "pyperplan"]
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
    """What a planning run produced: the plan's lines and where the time went."""

    planner: str
    lines: list[str]
    status: str
    times: dict[str, float] = field(default_factory=dict)


def choose_planner(problem: Any, name: str | None = None) -> str:
    """The engine to use for ``problem``: ``name`` if given (and installed), else by kind."""
    factory = environment().factory
    if name is not None:
        if name not in factory.engines:
            raise _not_installed(name)
        engine = factory.engine(name)
        if not engine.supports(problem.kind):
            raise ConfigurationError(f"planner {name} does not support this problem "
                                     f"({_missing_features(engine, problem.kind)})")
        return name
    candidates = PREFERENCE + [n for n in factory.preference_list if n not in PREFERENCE]
    for candidate in candidates:
        if candidate in factory.engines:
            engine = factory.engine(candidate)
            if _is_oneshot(engine) and engine.supports(problem.kind):
                return candidate
    features = ", ".join(sorted(problem.kind.features))
    raise ConfigurationError(f"no installed planner supports this problem ({features}); "
                             "install up-fast-downward (classical) or up-enhsp (numeric)")


def _is_oneshot(engine: Any) -> bool:
    from unified_planning.engines.mixins.oneshot_planner import OneshotPlannerMixin

    return isinstance(engine, type) and issubclass(engine, OneshotPlannerMixin)


def _missing_features(engine: Any, kind: Any) -> str:
    missing = sorted(set(kind.features) - set(engine.supported_kind().features))
    return "it lacks " + ", ".join(missing) if missing else "unsupported problem kind"


def _not_installed(name: str) -> ConfigurationError:
    package = PACKAGES.get(name)
    hint = f"pip install {package}" if package else "see unified-planning's list of engines"
    return ConfigurationError(f"planner {name} is not installed ({hint})")


def solve(problem: Any, planner: str, timeout: float | None = None, engine_defaults: bool = False) -> Any:
    """Run ``planner`` on ``problem``; the plan, or NotSolvableError with the planner's status.

    kitkb's :data:`PARAMS` are passed to the engine unless ``engine_defaults``.
    """
    from unified_planning.engines import PlanGenerationResultStatus as Status
    from unified_planning.shortcuts import OneshotPlanner

    try:
        engine_cm = OneshotPlanner(name=planner, params=None if engine_defaults else PARAMS.get(planner))
    except Exception as exc:  # an engine that cannot start (missing binary, Java, ...)
        raise ConfigurationError(f"planner {planner} cannot start: {exc} "
                                 f"(package {PACKAGES.get(planner, '?')})") from None
    with engine_cm as engine:
        try:
            result = engine.solve(problem, timeout=timeout)
        except FileNotFoundError as exc:
            raise ConfigurationError(f"planner {planner} cannot run: {exc} (is Java installed for ENHSP?)") from None
    ok = (Status.SOLVED_SATISFICING, Status.SOLVED_OPTIMALLY)
    if result.status not in ok or result.plan is None:
        detail = _last_log(result)
        raise NotSolvableError(f"no plan: {planner} says {result.status.name}{detail}")
    return result.plan


def _last_log(result: Any) -> str:
    """The planner's own words about the failure, if its log has them."""
    lines = [line.strip() for m in (getattr(result, "log_messages", None) or [])
             for line in m.message.splitlines()]
    telling = [line for line in lines if "solution" in line.lower() or "unsolvable" in line.lower()]
    return f" ({telling[-1][:200]})" if telling else ""


def validate(problem: Any, plan: Any) -> None:
    """Raise unless unified-planning's plan validator accepts ``plan`` for ``problem``."""
    from unified_planning.engines import ValidationResultStatus
    from unified_planning.engines.plan_validator import SequentialPlanValidator

    from unified_planning.exceptions import UPUsageError

    missing = sorted(set(problem.kind.features) - set(SequentialPlanValidator.supported_kind().features))
    if missing:
        raise KitkbError("unified-planning's plan validator cannot check this problem "
                         f"({', '.join(missing)}); no plan written")
    try:
        with _lean_validation():
            result = SequentialPlanValidator().validate(problem, plan)
    except UPUsageError as exc:
        raise KitkbError(f"unified-planning's plan validator cannot check this problem: {exc}") from None
    if result.status != ValidationResultStatus.VALID:
        reason = getattr(result, "reason", None) or getattr(result, "inapplicable_action", None) or ""
        raise KitkbError(f"the planner's plan does not validate: {result.status.name} {reason}".strip())


@contextmanager
def _lean_validation() -> Iterator[None]:
    """Speed settings for unified-planning's validator, restored afterwards.

    The validator grounds every action instance of the plan. unified-planning's substituter
    re-promotes the same parameter -> object map for every precondition and effect of an
    action (about 20 times per plan step here); the promoted map is memoised for the
    last map seen (compared by content, so callers that reuse a dict stay correct).
    Ground literals and constants are substituted (:func:`_substitute_fast`) and evaluated
    in a state (:func:`_evaluate_literal`) with the expression-manager calls the generic
    walkers make, without the walkers' stack machinery; other shapes use the walkers.
    ``UPState.MAX_ANCESTORS`` (unified-planning's documented trade-off between state
    look-up time and flattening the state history) is raised from 20 to 200: a 640-part
    plan then flattens its 5,000-fact state 6 times instead of 64. The validation logic
    itself is untouched; together this cuts the validation time of long plans by more than half.
    """
    from unified_planning.model.state import UPState
    from unified_planning.model.walkers.state_evaluator import StateEvaluator
    from unified_planning.model.walkers.substituter import Substituter

    original, ancestors = Substituter.substitute, UPState.MAX_ANCESTORS
    original_evaluate = StateEvaluator.evaluate

    def substitute(self: Any, expression: Any, substitutions: Any = {}) -> Any:  # noqa: B006
        if not substitutions:
            return expression
        key = tuple(substitutions.items())
        last = self.__dict__.get("_kitkb_last")
        if last is None or last[0] != key:
            last = (key, _promote(self, substitutions))
            self.__dict__["_kitkb_last"] = last
        return _substitute_fast(self, expression, last[1])

    def evaluate(self: Any, expression: Any, state: Any, _variable_assignments: Any = {}) -> Any:  # noqa: B006
        if not _variable_assignments:
            value = _evaluate_literal(expression, state, self.manager)
            if value is not None:
                return value
        return original_evaluate(self, expression, state, _variable_assignments)

    Substituter.substitute = substitute
    StateEvaluator.evaluate = evaluate
    UPState.MAX_ANCESTORS = 200
    try:
        yield
    finally:
        Substituter.substitute = original
        StateEvaluator.evaluate = original_evaluate
        UPState.MAX_ANCESTORS = ancestors


def _evaluate_literal(expression: Any, state: Any, manager: Any) -> Any:
    """``StateEvaluator.evaluate`` for a ground literal or constant; None for other shapes.

    What the evaluator's walk computes for these shapes: a constant is itself, a ground
    fluent expression is ``state.get_value`` of the (hash-consed, hence identical) node,
    ``not x`` is the negated boolean constant.
    """
    if expression.is_constant():
        return expression
    if expression.is_fluent_exp():
        if all(arg.is_constant() for arg in expression.args):
            return state.get_value(expression)
        return None
    if expression.is_not():
        inner = _evaluate_literal(expression.arg(0), state, manager)
        if inner is not None and inner.is_bool_constant():
            return manager.Bool(not inner.bool_constant_value())
    return None


def _substitute_fast(substituter: Any, expression: Any, subs: dict) -> Any:
    """``Substituter.walk(expression, subs=subs)`` for the shapes a STRIPS action has.

    Literals over parameters and constants (``f(?a, ?b)``, ``not f(?a)``, constants) are
    rebuilt with the same expression-manager calls the walker would make (``FluentExp``,
    ``Not``; hash-consed, so the result is the identical node, type checks included),
    without the generic DAG walk; any other shape goes through the walker itself.
    """
    found = subs.get(expression)
    if found is not None:
        return found
    if expression.is_parameter_exp() or expression.is_constant():
        return expression
    if expression.is_fluent_exp():
        args = []
        for arg in expression.args:
            new = subs.get(arg)
            if new is None:
                if not (arg.is_parameter_exp() or arg.is_constant()):
                    return substituter.walk(expression, subs=subs)
                new = arg
            args.append(new)
        return substituter.manager.FluentExp(expression.fluent(), tuple(args))
    if expression.is_not():
        return substituter.manager.Not(_substitute_fast(substituter, expression.arg(0), subs))
    return substituter.walk(expression, subs=subs)


def _promote(substituter: Any, substitutions: Any) -> dict:
    """What ``Substituter.substitute`` does with its map before walking (same checks)."""
    from unified_planning.exceptions import UPTypeError

    out = {}
    for k, v in substitutions.items():
        new_k, new_v = substituter.manager.auto_promote(k, v)
        if not new_k.type.is_compatible(new_v.type):
            raise UPTypeError(f"The expression type of {k} is not compatible with the given substitution {v}")
        out[new_k] = new_v
    return out


def plan_lines(plan: Any) -> list[str]:
    """One ``(action arg ...)`` line per action of a sequential plan."""
    lines = []
    for ai in plan.actions:
        args = " ".join(str(p.object()) if p.is_object_exp() else str(p) for p in ai.actual_parameters)
        lines.append(f"({ai.action.name}{' ' + args if args else ''})")
    return lines


def write_plan(lines: list[str], path: str | Path) -> Path:
    """Write the plan lines to ``path`` (atomically)."""
    from generators.base import write_text_atomic

    return write_text_atomic(Path(path), "".join(line + "\n" for line in lines))


def run(problem: Any, out: str | Path | None, planner: str | None = None,
        timeout: float | None = None, engine_defaults: bool = False) -> PlanResult:
    """Choose a planner, solve, validate, and write the plan to ``out`` (if given)."""
    times: dict[str, float] = {}
    t0 = time.perf_counter()
    name = choose_planner(problem, planner)
    plan = solve(problem, name, timeout, engine_defaults)
    times["solve"] = time.perf_counter() - t0
    t1 = time.perf_counter()
    validate(problem, plan)
    times["validate"] = time.perf_counter() - t1
    lines = plan_lines(plan)
    if out is not None:
        write_plan(lines, out)
    return PlanResult(name, lines, "valid", times)


# --- existing PDDL files ----------------------------------------------------------------

def read_pddl(domain_path: str | Path, problem_path: str | Path, warn: Any = None) -> Any:
    """Parse a PDDL domain and problem with unified-planning's reader.

    A ``:derived-predicates`` requirement that the domain never uses (NIST's domain declares
    it) is removed with a warning, since unified-planning's reader rejects it. Errors become
    :class:`~kb.errors.InputError` naming the file and line.
    """
    import re
    import sys

    from kb.errors import InputError

    warn = warn or (lambda msg: print(msg, file=sys.stderr))
    texts = {}
    for path in (domain_path, problem_path):
        try:
            texts[path] = Path(path).read_text(encoding="utf-8")
        except OSError as exc:
            raise InputError(f"cannot read: {exc.strerror or exc}", path) from None
    domain = texts[domain_path]
    if ":derived-predicates" in domain.lower() and "(:derived" not in domain.lower():
        line = domain.lower()[:domain.lower().index(":derived-predicates")].count("\n") + 1
        warn(f"{domain_path}:{line}: warning: requirement :derived-predicates is declared but "
             "never used; ignored")
        domain = re.sub(r":derived-predicates", "", domain, flags=re.IGNORECASE)
    environment()
    from unified_planning.io import PDDLReader

    _parse(lambda: PDDLReader().parse_problem_string(domain, None), domain_path, domain)
    return _parse(lambda: PDDLReader().parse_problem_string(domain, texts[problem_path]),
                  problem_path, texts[problem_path])


def _parse(call: Any, path: str | Path, text: str) -> Any:
    import re

    from kb.errors import InputError

    try:
        return call()
    except KeyError as exc:  # an undeclared type or object
        name = str(exc.args[0]) if exc.args else "?"
        raise InputError(f"unknown type or object {name!r}", path, _line_of_word(text, name)) from None
    except Exception as exc:  # noqa: BLE001 - pyparsing / UP errors, reported as one line
        msg = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        line = getattr(exc, "lineno", None)
        found = re.search(r"line:? (\d+)", msg)
        if line is None and found:
            line = int(found.group(1))
        raise InputError(f"not valid PDDL: {msg}", path, line) from None


def _line_of_word(text: str, word: str) -> int | None:
    import re

    pattern = re.compile(rf"(?<![\w-]){re.escape(word)}(?![\w-])", re.IGNORECASE)
    for number, line in enumerate(text.splitlines(), 1):
        if pattern.search(line.split(";", 1)[0]):
            return number
    return None


def plan_files(init: str | Path, goal: str | Path, out: str | Path | None = None, planner: str | None = None,
               encoding: str = "strips", timeout: float | None = None) -> PlanResult:
    """From an initial and a goal state file to a validated plan (written to ``out`` if given)."""
    from generators.pddl.model import kitting_model

    return run(kitting_model([init], [goal], encoding).up_problem, out, planner, timeout)
