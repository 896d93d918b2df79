"""kitkb's changes to unified-planning's internals (checked on unified-planning 1.3.0).

- :data:`LEAN_IMPORT`: ``unified_planning.engines`` imports ConfigSpace at module level,
  which pulls in scipy.stats and costs seconds per process, only to annotate
  ``Engine.get_configuration_space``. kitkb never asks for configuration spaces, so
  :func:`environment` registers a stand-in module that imports the real ConfigSpace the
  first time anything in it is used. Stock: the plain import.
- :data:`LEAN_NETWORKX`: ``unified_planning.model.problem`` (and the plan classes) import
  networkx at module level (about 60 ms, 285 modules) for causal graphs and partial-order
  plans, which kitkb's paths do not make; :func:`environment` registers a stand-in module that
  imports the real networkx the first time anything in it is used (an attribute, a submodule
  import), and from then on holds the real module's names. ``nx.DiGraph`` in the library's
  annotations is a placeholder class whose instances are real ``DiGraph`` objects. Stock: the
  plain import.
- :data:`VALIDATOR`: :func:`validator_speedups` speeds up ``SequentialPlanValidator``
  without changing what it checks. The substituter re-promotes the same parameter -> object
  map for every precondition and effect of an action (about 20 times per plan step); the
  promoted map is memoised for the last map seen (compared by content). Ground literals and
  constants are substituted (:func:`substitute_fast`) and evaluated (:func:`evaluate_literal`)
  with the expression-manager calls the generic walkers make, without their stack machinery;
  other shapes use the walkers. ``UPState.MAX_ANCESTORS`` (the library's documented trade-off
  between state look-up and flattening the state history) goes from 20 to 200. Stock: the
  validator as it is (more than twice as slow on long plans).
- :data:`LEAN_PROBLEM`: :func:`problem_class` is a ``Problem`` whose ``initial_values`` are
  the explicitly set ones (unified-planning grounds every fluent over every object tuple to
  fill in defaults, tens of thousands of terms for a 640-part kit, only for the writer and
  the planners to skip the false ones again), whose ``kind`` is computed once by
  :func:`freeze`, and which finds objects by name in a dictionary instead of a linear scan.
  Stock: ``Problem``.
- :data:`EARLY_START`: :class:`StartedSolve` runs what ``PDDLPlanner._solve`` runs (the
  engine's own PDDL writer, command line, plan reader and exit-status reading), split in two:
  the planner's process is started at once and read when asked for, so the caller can work on
  the other core meanwhile (``kitkb run`` validates the state files while Fast Downward plans;
  a planner whose own ``_solve`` does more than ``PDDLPlanner``'s is not started ahead). Stock: nothing started ahead
  (:meth:`StartedSolve.start` returns None), the plan made when asked for.

Differential tests: ``tests/test_plan.py`` (fast paths give the walkers' results, broken
plans are rejected) and ``tests/test_patches.py`` (same PDDL and plans with the patches off).
"""

from __future__ import annotations

import contextlib
import importlib
import sys
import time
import types
from contextlib import contextmanager
from typing import Any, Iterator

from kb.patches.gate import Patch

LEAN_IMPORT = Patch("unified-planning", "1.3.0", "1.4", "ConfigSpace imported on first use only")
LEAN_NETWORKX = Patch("unified-planning", "1.3.0", "1.4", "networkx imported on first use only")
VALIDATOR = Patch("unified-planning", "1.3.0", "1.4", "plan-validator fast paths")
LEAN_PROBLEM = Patch("unified-planning", "1.3.0", "1.4", "Problem with explicit initial values, kind kept")
EARLY_START = Patch("unified-planning", "1.3.0", "1.4", "a PDDL planner's process started ahead, read later")
PATCHES = [LEAN_IMPORT, LEAN_NETWORKX, VALIDATOR, LEAN_PROBLEM, EARLY_START]


# --- lean import -----------------------------------------------------------------------------

class _LazyConfigSpace(types.ModuleType):
    """Stand-in for the ConfigSpace package: loads the real one on first real use."""

    def __getattr__(self, name: str) -> Any:
        if name.startswith("__"):
            raise AttributeError(name)
        return getattr(_real_configspace(), name)


def _real_configspace() -> types.ModuleType:
    if isinstance(sys.modules.get("ConfigSpace"), _LazyConfigSpace):
        del sys.modules["ConfigSpace"]
    return importlib.import_module("ConfigSpace")


class _ConfigurationSpace:
    """Placeholder class; instantiating it returns a real ``ConfigurationSpace``."""

    def __new__(cls, *args: Any, **kwargs: Any) -> Any:
        return _real_configspace().ConfigurationSpace(*args, **kwargs)


def _install_stand_in() -> None:
    if "ConfigSpace" in sys.modules or "unified_planning.engines" in sys.modules:
        return
    module = _LazyConfigSpace("ConfigSpace")
    module.ConfigurationSpace = _ConfigurationSpace  # type: ignore[attr-defined]
    sys.modules["ConfigSpace"] = module


class _LazyNetworkx(types.ModuleType):
    """Stand-in for the networkx package (:data:`LEAN_NETWORKX`): loads the real one on first
    use of any of its names or of its path (a submodule import; not of ``__file__``, which
    ``inspect.getmodule`` asks of every module), then holds the real names."""

    def __getattr__(self, name: str) -> Any:
        if name.startswith("__") and name not in ("__path__", "__version__", "__all__"):  # not __file__: inspect asks every module
            raise AttributeError(name)
        return getattr(_real_networkx(), name)


class _DiGraph:
    """Placeholder for ``networkx.DiGraph`` (named in unified-planning's annotations at import
    time); instantiating it returns a real ``DiGraph``."""

    def __new__(cls, *args: Any, **kwargs: Any) -> Any:
        return _real_networkx().DiGraph(*args, **kwargs)


def _real_networkx() -> types.ModuleType:
    stand_in = sys.modules.get("networkx")
    if isinstance(stand_in, _LazyNetworkx):
        del sys.modules["networkx"]
    real = importlib.import_module("networkx")
    if isinstance(stand_in, _LazyNetworkx):  # the modules that bound the stand-in see the real names from now on
        stand_in.__dict__.update(real.__dict__)
    return real


def _install_networkx_stand_in() -> None:
    if "networkx" in sys.modules or "unified_planning.model" in sys.modules:
        return
    module = _LazyNetworkx("networkx")
    module.DiGraph = _DiGraph  # type: ignore[attr-defined]
    sys.modules["networkx"] = module


def remove_stand_in() -> None:
    """Undo :func:`environment`'s stand-ins where nothing has used them yet."""
    if isinstance(sys.modules.get("ConfigSpace"), _LazyConfigSpace):
        del sys.modules["ConfigSpace"]
    if isinstance(sys.modules.get("networkx"), _LazyNetworkx):  # a used one is out of sys.modules already
        del sys.modules["networkx"]


def environment() -> Any:
    """unified-planning's global environment, credits silenced (imported cheaply when
    :data:`LEAN_IMPORT` and :data:`LEAN_NETWORKX` apply)."""
    if LEAN_IMPORT.active():
        _install_stand_in()
    if LEAN_NETWORKX.active():
        _install_networkx_stand_in()
    from unified_planning.environment import get_environment

    env = get_environment()
    env.credits_stream = None
    return env


# --- plan validator --------------------------------------------------------------------------

@contextmanager
def validator_speedups() -> Iterator[None]:
    """:data:`VALIDATOR`'s changes for the duration of the block (nothing when it does not apply)."""
    if not VALIDATOR.active():
        yield
        return
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
            last = (key, promote(self, substitutions))
            self.__dict__["_kitkb_last"] = last
        return substitute_fast(self, expression, last[1])

    def evaluate(self: Any, expression: Any, state: Any, _variable_assignments: Any = {}) -> Any:  # noqa: B006
        if not _variable_assignments:
            value = evaluate_literal(expression, state, self.manager)
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


def evaluate_literal(expression: Any, state: Any, manager: Any) -> Any:
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
        inner = evaluate_literal(expression.arg(0), state, manager)
        if inner is not None and inner.is_bool_constant():
            return manager.Bool(not inner.bool_constant_value())
    return None


def substitute_fast(substituter: Any, expression: Any, subs: dict) -> Any:
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
        return substituter.manager.Not(substitute_fast(substituter, expression.arg(0), subs))
    return substituter.walk(expression, subs=subs)


def promote(substituter: Any, substitutions: Any) -> dict:
    """What ``Substituter.substitute`` does with its map before walking (same checks)."""
    from unified_planning.exceptions import UPTypeError

    out = {}
    for k, v in substitutions.items():
        new_k, new_v = substituter.manager.auto_promote(k, v)
        if not new_k.type.is_compatible(new_v.type):
            raise UPTypeError(f"The expression type of {k} is not compatible with the given substitution {v}")
        out[new_k] = new_v
    return out


# --- problem class ---------------------------------------------------------------------------

_LEAN: list[type] = []


def problem_class() -> type:
    """The class kitkb builds problems with: :data:`LEAN_PROBLEM`'s when it applies, else ``Problem``."""
    from unified_planning.model import Problem

    if not LEAN_PROBLEM.active():
        return Problem
    if not _LEAN:
        class LeanProblem(Problem):
            _kitkb_kind = None

            @property
            def initial_values(self) -> dict:  # type: ignore[override]
                return dict(self.explicit_initial_values)

            @property
            def kind(self):  # type: ignore[override]  # noqa: ANN202
                # Problem.kind re-analyses the whole problem on every access (the factory,
                # the writer and the validator each ask); a frozen problem keeps its kind
                if self._kitkb_kind is not None:
                    return self._kitkb_kind
                return Problem.kind.fget(self)

            # Problem looks objects up by a linear scan; the validator asks once per plan
            # step (to name the grounded action), which is quadratic on a 640-part kit.
            def has_object(self, name: str) -> bool:
                index = self.__dict__.get("_kitkb_objects")
                return name in index if index is not None else Problem.has_object(self, name)

            def object(self, name: str):  # noqa: ANN201
                index = self.__dict__.get("_kitkb_objects")
                if index is not None and name in index:
                    return index[name]
                return Problem.object(self, name)

        _LEAN.append(LeanProblem)
    return _LEAN[0]


def freeze(problem: Any) -> None:
    """Mark a finished problem: a lean problem computes its kind and indexes its objects
    (a stock ``Problem`` is left as it is)."""
    if _LEAN and isinstance(problem, _LEAN[0]):
        problem._kitkb_kind = _stock_kind(problem)
        problem._kitkb_objects = {o.name: o for o in problem.all_objects}


def _stock_kind(problem: Any) -> Any:
    """The kind as the stock ``Problem`` computes it."""
    from unified_planning.model import Problem

    return Problem.kind.fget(problem)


# --- a PDDL planner started ahead ---------------------------------------------------------------

class StartedSolve:
    """A PDDL planner engine's process working on a problem in the background: what its
    ``_solve`` does (``unified_planning.engines.pddl_planner.PDDLPlanner._solve``, one-shot,
    no timeout, no output stream), with the waiting left to :meth:`result`. Its own temporary
    folder is the process's working folder (Fast Downward writes ``output.sas`` there)."""

    def __init__(self, engine: Any, problem: Any) -> None:
        import os
        import subprocess
        import tempfile

        from unified_planning.io import PDDLWriter

        self.engine, self.problem = engine, problem
        self.closed = False
        self._folder = tempfile.TemporaryDirectory(prefix="kitkb-plan-")
        try:
            work = self._folder.name
            self.writer = PDDLWriter(problem, engine._needs_requirements, engine._rewrite_bool_assignments)
            domain, task = os.path.join(work, "domain.pddl"), os.path.join(work, "problem.pddl")
            self.plan_file = os.path.join(work, "plan.txt")
            self.writer.write_domain(domain)
            self.writer.write_problem(task)
            cmd = engine._get_cmd(domain, task, self.plan_file)
            self._started = time.time()
            self.process = subprocess.Popen(cmd, cwd=work, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                            start_new_session=True)
        except BaseException:
            self._folder.cleanup()
            raise

    @classmethod
    def start(cls, engine: Any, problem: Any) -> "StartedSolve | None":
        """Start ``engine`` (made by unified-planning's factory in one-shot mode) on ``problem``,
        or None where :data:`EARLY_START` does not apply (another version, an engine that is
        not a PDDL planner or has its own ``_solve``)."""
        if not EARLY_START.active():
            return None
        from unified_planning.engines import OperationMode
        from unified_planning.engines.pddl_anytime_planner import PDDLAnytimePlanner
        from unified_planning.engines.pddl_planner import PDDLPlanner

        # PDDLAnytimePlanner._solve, one-shot, only sets the mode one-shot and calls PDDLPlanner's
        if not isinstance(engine, PDDLPlanner) \
                or type(engine)._solve not in (PDDLPlanner._solve, PDDLAnytimePlanner._solve) \
                or getattr(engine, "_mode_running", None) != OperationMode.ONESHOT_PLANNER:
            return None
        if not engine.skip_checks and not engine.supports(problem.kind):
            return None  # the engine's solve would warn or refuse: let it
        return cls(engine, problem)

    def result(self) -> Any:
        """Wait for the process; the ``PlanGenerationResult`` ``_solve`` would return."""
        import os

        from unified_planning.engines.results import LogLevel, LogMessage, PlanGenerationResult

        try:
            out, err = self.process.communicate()
            ended = time.time()
            logs = [LogMessage(LogLevel.INFO, out.decode()), LogMessage(LogLevel.ERROR, err.decode())]
            plan = None
            if os.path.isfile(self.plan_file):
                plan = self.engine._plan_from_file(self.problem, self.plan_file, self.writer.get_item_named)
            status = self.engine._result_status(self.problem, plan, self.process.returncode, logs)
            return PlanGenerationResult(status, plan, engine_name=self.engine.name, log_messages=logs,
                                        metrics={"engine_internal_time": str(ended - self._started)})
        finally:
            self.close()

    def cancel(self) -> None:
        """Stop the process (and what it started) if it still runs; remove its folder."""
        import os
        import signal
        import subprocess

        if self.closed:
            return
        if self.process.poll() is None:
            try:
                os.killpg(self.process.pid, signal.SIGTERM)
                self.process.wait(timeout=5)
            except ProcessLookupError:
                pass
            except subprocess.TimeoutExpired:
                with contextlib.suppress(ProcessLookupError):
                    os.killpg(self.process.pid, signal.SIGKILL)
            self.process.wait()
        self.close()

    def close(self) -> None:
        if self.closed:
            return
        self.closed = True
        for stream in (self.process.stdout, self.process.stderr):
            if stream is not None:
                stream.close()
        self._folder.cleanup()
        self.engine.destroy()
