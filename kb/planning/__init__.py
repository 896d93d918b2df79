"""Planning: from an initial and a goal state file to a validated plan, with a real planner.

Pipeline (each step one module): the SOAP domain (:mod:`kb.model.soap`) and the state files
(:mod:`.state`: the symbolic view of a workstation; :mod:`.facts`: how each predicate and
function is read off it; :mod:`.problem`: objects, initial state, goal) -> STRIPS compilation
of counts (:mod:`.strips`) -> a unified-planning problem (:mod:`.build`; :mod:`.model` runs
the chain) -> a planner chosen by unified-planning's factory, its plan validated and written
(:mod:`.planners`). :mod:`.pddl_files` reads existing PDDL instead. The PDDL text of a
problem is an emitted file (the ``pddl`` generator).
"""

from __future__ import annotations

from pathlib import Path

from kb.planning.model import ENCODINGS, KittingModel, domain_model, kitting_model
from kb.planning.pddl_files import is_pddl, read_pddl
from kb.planning.planners import PlanResult, choose_planner, plan_lines, run, solve, validate, write_plan

__all__ = ["ENCODINGS", "KittingModel", "PlanResult", "choose_planner", "domain_model", "is_pddl",
           "kitting_model", "plan_files", "plan_lines", "read_pddl", "run", "solve", "validate",
           "write_plan"]


def plan_files(init: str | Path, goal: str | Path, out: str | Path | None = None, planner: str | None = None,
               encoding: str = "strips", timeout: float | None = None, match_names: bool = False) -> PlanResult:
    """From an initial and a goal state file to a validated plan (written to ``out`` if given)."""
    model = kitting_model([init], [goal], encoding, match_names=match_names)
    return run(model.up_problem, out, planner, timeout)
