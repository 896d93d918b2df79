"""Does the geometry of a state agree with the facts the planner is given?

The PDDL generator reads predicates off a state file's explicit facts (primary locations,
SKUs, designs: :mod:`kb.planning.facts`); the executor decides them from the objects' boxes
(:mod:`kb.spatial.predicates`). :func:`check_geometry` compares the two on an initial and a
goal state: the atoms true in the initial geometry against the PDDL init facts, and every
PDDL goal fact (and goal count) against the goal's geometry.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Sequence

from kb.model.definitions import load_definitions
from kb.planning.model import read_specs
from kb.planning.state import pddl_name
from kb.spatial import Evaluator, Scene


@dataclass
class Agreement:
    """Differences between geometry and the generated facts (all empty: they agree)."""

    atoms: int = 0  # atoms true in the initial geometry
    only_geometry: list[tuple[str, ...]] = field(default_factory=list)
    only_symbolic: list[tuple[str, ...]] = field(default_factory=list)
    goal_not_holding: list[tuple[str, ...]] = field(default_factory=list)

    @property
    def agrees(self) -> bool:
        return not (self.only_geometry or self.only_symbolic or self.goal_not_holding)


def check_geometry(init: Sequence[str | Path], goal: Sequence[str | Path], match_names: bool = False,
                   domain_files: Sequence[str | Path] | None = None) -> Agreement:
    """Compare the geometry of ``init`` and ``goal`` with the generated PDDL facts and goal."""
    _domain, spec = read_specs(init, goal, encoding="numeric", domain_files=domain_files, match_names=match_names)
    defs = load_definitions(domain_files)
    start = Evaluator(defs, Scene.from_files(list(init), declared=list(goal), match_names=match_names))
    end = Evaluator(defs, Scene.from_files(list(goal)))
    seen = {(n, *map(pddl_name, a)) for n, a in start.facts()}
    reached = {(n, *map(pddl_name, a)) for n, a in end.facts()}
    counts = {fn: {tuple(map(pddl_name, a)): v for a, v in end.function_values(fn).items()}
              for fn in {t[0] for pair in spec.goal_equal for t in pair}}
    missing = [tuple(g) for g in spec.goal if tuple(g) not in reached]
    for left, right in spec.goal_equal:
        if counts[left[0]].get(tuple(left[1:]), 0) != counts[right[0]].get(tuple(right[1:]), 0):
            missing.append(("=", *left, *right))
    return Agreement(len(seen), sorted(seen - spec.facts), sorted(spec.facts - seen), missing)
