"""Does the geometry of a state agree with what its file states, and does the goal's geometry
give the goal?

The initial facts the planner is given are decided by the predicates' definitions on the
initial state's geometry (:mod:`kb.planning.facts`), as the executor decides them. What the
file states besides its boxes is where each object is placed: its pose's reference object (a
part's tray, a tray's table). :func:`agreement` checks that geometry bears every stated
placement out: an object and its reference object must make at least one spatial atom of the
domain true between them (an atom of a two-argument predicate of the planning problem whose
definition has a relation atom and whose argument classes admit the pair, in either order);
one that makes none (a part posed 0.5 m above the tray it says it is in) is a disagreement,
told as those atoms (``only_symbolic``: stated, not in geometry). A pair for which the domain
has no such predicate is not checked. And every PDDL goal fact (and goal count) must hold in
the goal's geometry.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from pathlib import Path
from typing import Sequence

import numpy as np

from kb.core.namespaces import local_name
from kb.core.units import LENGTH
from kb.model.definitions import Definitions, PredicateLeaf, Relation, load_definitions
from kb.planning.model import read_specs
from kb.planning.problem import ProblemSpec
from kb.planning.state import pddl_name
from kb.spatial import Evaluator, Scene
from kb.spatial.plausibility import check, describe


@dataclass
class Agreement:
    """Differences between geometry and the generated facts (all empty: they agree)."""

    atoms: int = 0  # atoms true in the initial geometry
    only_geometry: list[tuple[str, ...]] = field(default_factory=list)
    only_symbolic: list[tuple[str, ...]] = field(default_factory=list)
    goal_not_holding: list[tuple[str, ...]] = field(default_factory=list)

    #: what probably makes the initial geometry disagree (implausible poses, a unit)
    causes: list[str] = field(default_factory=list)

    @property
    def agrees(self) -> bool:
        return not (self.only_geometry or self.only_symbolic or self.goal_not_holding)

    @property
    def initial_agrees(self) -> bool:
        """The initial state's geometry gives exactly its facts: execution can start (a goal
        file whose own geometry misses a goal fact is only a warning: a run is judged on the
        cell's geometry at its end)."""
        return not (self.only_geometry or self.only_symbolic)

    def reason(self) -> str:
        """One line: why the initial state cannot be executed (empty when it can)."""
        if self.initial_agrees:
            return ""
        atoms = [f"only in geometry ({' '.join(a)})" for a in self.only_geometry] + \
                [f"only in the facts ({' '.join(a)})" for a in self.only_symbolic]
        shown = "; ".join(atoms[:6]) + (f"; and {len(atoms) - 6} more" if len(atoms) > 6 else "")
        why = ("; likely cause: " + "; ".join(self.causes)) if self.causes else ""
        return f"the initial state's geometry disagrees with its facts: {shown}{why}"


def check_geometry(init: Sequence[str | Path], goal: Sequence[str | Path], match_names: bool = False,
                   domain_files: Sequence[str | Path] | None = None) -> Agreement:
    """Compare the geometry of ``init`` and ``goal`` with the generated PDDL facts and goal."""
    _domain, spec = read_specs(init, goal, encoding="numeric", domain_files=domain_files, match_names=match_names)
    return agreement(spec, load_definitions(domain_files),
                     Scene.from_files(list(init), declared=list(goal), match_names=match_names),
                     Scene.from_files(list(goal)))


def agreement(spec: ProblemSpec, defs: Definitions, initial: Scene, goal: Scene) -> Agreement:
    """:func:`check_geometry` of inputs already read: the numeric problem ``spec``, the
    domain's definitions, the initial state's scene (the goal's individuals declared) and the
    goal state's."""
    used = set(spec.predicates) or {f[0] for f in spec.facts} | {g[0] for g in spec.goal}
    start = Evaluator(defs, initial)
    end = Evaluator(defs, goal)
    true = start.facts(sorted(n for n in used if n in defs.predicates))
    seen = {(n, *map(pddl_name, a)) for n, a in true}
    unconfirmed = stated_not_in_geometry(defs, start, set(used), {(n, *a) for n, a in true})
    reached = {(n, *map(pddl_name, a)) for n, a in end.facts()}
    counts = {fn: {tuple(map(pddl_name, a)): v for a, v in end.function_values(fn).items()}
              for fn in {t[0] for pair in spec.goal_equal for t in pair}}
    missing = [tuple(g) for g in spec.goal if tuple(g) not in reached]
    for left, right in spec.goal_equal:
        if counts[left[0]].get(tuple(left[1:]), 0) != counts[right[0]].get(tuple(right[1:]), 0):
            missing.append(("=", *left, *right))
    out = Agreement(len(seen), sorted(seen - spec.facts), sorted((spec.facts - seen) | unconfirmed), missing)
    if not out.initial_agrees:
        out.causes = likely_causes(start.scene, out.only_geometry + out.only_symbolic)
    return out


def stated_not_in_geometry(defs: Definitions, ev: Evaluator, predicates: set[str],
                           true: set[tuple[str, ...]]) -> set[tuple[str, ...]]:
    """The atoms (PDDL names) of the stated placements geometry does not bear out: for each
    placed object and its pose's reference object, the spatial two-argument predicates of
    ``predicates`` whose classes admit the pair (either order), when none of their atoms is in
    ``true`` (IRIs)."""
    sc = ev.scene
    spatial = [p for name, p in sorted(defs.predicates.items())
               if name in predicates and p.reference_type is not None and p.target_type is not None
               and _is_spatial(p.formula, defs)]
    out: set[tuple[str, ...]] = set()
    for child in np.flatnonzero(sc.parents >= 0).tolist():
        parent = int(sc.parents[child])
        a, b = sc.names[child], sc.names[parent]
        atoms = [(p.name, x, y) for p in spatial for x, y in ((a, b), (b, a))
                 if p.reference_type in sc.classes[sc.index[x]] and p.target_type in sc.classes[sc.index[y]]]
        if atoms and not any(atom in true for atom in atoms):
            out.update((n, pddl_name(x), pddl_name(y)) for n, x, y in atoms)
    return out


def _is_spatial(node: object, defs: Definitions, seen: frozenset[str] = frozenset()) -> bool:
    """Whether a formula has a relation atom (through the predicates it names, too)."""
    if isinstance(node, Relation):
        return True
    if isinstance(node, PredicateLeaf):
        p = next((q for q in defs.predicates.values() if q.iri == node.predicate), None)
        return p is not None and p.iri not in seen and _is_spatial(p.formula, defs, seen | {p.iri})
    if isinstance(node, (tuple, list)):
        return any(_is_spatial(x, defs, seen) for x in node)
    if dataclasses.is_dataclass(node):
        return any(_is_spatial(getattr(node, f.name), defs, seen) for f in dataclasses.fields(node))
    return False


def likely_causes(scene: Scene, atoms: Sequence[tuple[str, ...]]) -> list[str]:
    """Why a state's geometry may disagree with its facts: the implausible poses
    (:mod:`kb.spatial.plausibility`) of objects the disagreeing atoms name, and lengths that do
    not look like the unit the workstation declares."""
    named = {a for atom in atoms for a in atom[1:]}
    causes = [describe(f, local_name, scene.units) for f in check(scene)
              if {pddl_name(f.obj), pddl_name(f.other or f.obj)} & named]
    unit = unit_suspicion(scene)
    return causes + ([unit] if unit else [])


def unit_suspicion(scene: Scene) -> str | None:
    """A sentence when the objects' sizes, read in the declared length unit, are not those of
    a kitting cell (a part of 0.05 mm, a table 25 m long): the file's numbers are probably in
    another unit."""
    ok = scene.placed & ~np.isnan(scene.local_lo[:, 0]) if scene.local_lo is not None else scene.placed
    if not ok.any():
        return None
    size = float(np.max(scene.local_hi[ok] - scene.local_lo[ok]))  # the largest object, in metres
    if 0.05 <= size <= 10.0:
        return None
    declared = scene.units.length
    fits = [u for u, m in LENGTH.items() if u != declared and 0.05 <= size / scene.units.metres * m <= 10.0]
    return (f"the largest object is {size:g} m long when read in {declared}s"
            + (f"; the numbers look like {' or '.join(u + 's' for u in fits)}" if fits else ""))
