"""Replanning from a stable state decided from geometry, with the original goal.

The executor knows the current state as the predicates and counts that hold in its belief of
the cell (``kb.spatial.predicates``), which equal the facts the generator would read from a
state file (tests/test_predicates.py). :func:`restated` turns them into the numeric problem
of the original objects and goal; :func:`replan` compiles it to STRIPS (quota tokens: the
parts now lying in parts trays, then the other parts in no kit and no gripper, minus those the
executor's diagnoses found unusable, which are not in any tray for the planner) and plans.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Iterable

from kb.model.soap import DomainSpec
from kb.planning.build import build_problem
from kb.planning.goal import unreachable
from kb.planning.planners import PlanResult, run
from kb.planning.problem import ProblemSpec, movable
from kb.planning.strips import compile_domain, compile_problem

Atom = tuple[str, ...]


def restated(spec: ProblemSpec, facts: Iterable[Atom], values: dict[Atom, float],
             excluded: Iterable[str] = (), domain: DomainSpec | None = None) -> ProblemSpec:
    """``spec`` (numeric) with a new initial state; objects and goal unchanged.

    ``facts`` and ``values`` use PDDL object names; atoms over names the problem does not
    know are dropped; functions the problem knows but ``values`` lacks are 0.
    """
    known = set(spec.objects)
    bad = set(excluded)
    # an excluded part (found missing, defective, of another SKU, dropped) is not in a parts
    # tray for the planner: no plan takes it, whatever the geometry says
    new_facts = {a for a in facts if all(x in known for x in a[1:])
                 and not (a[0] == "part-location-partstray" and a[1] in bad)}
    new_values = {k: 0.0 for k in spec.values}
    new_values.update({k: float(v) for k, v in values.items() if all(x in known for x in k[1:])})
    out = replace(spec, facts=new_facts, values=new_values, quota={}, shortage=[])
    sku_of = {a[1]: a[2] for a in new_facts if a[0] == "part-sku"}
    in_trays: dict[str, list[str]] = {}
    for a in sorted(new_facts):
        if a[0] == "part-location-partstray" and a[1] not in bad:
            in_trays.setdefault(sku_of.get(a[1], ""), []).append(a[1])
    others = _other_parts(out, sku_of, in_trays, bad, movable(new_facts, domain) if domain is not None else set())
    used: set[str] = set()
    for left, right in spec.goal_equal:
        kit_sku = left[1:]
        need = int(new_values.get(right, 0) - new_values.get(left, 0))
        # a part lying out of place (dropped, knocked out of its tray) first: taken from where it
        # lies, it clears that place (the work table a kit tray must go on) and spares a tray's part
        tokens = [p for p in others.get(kit_sku[-1], []) + in_trays.get(kit_sku[-1], []) if p not in used][:max(need, 0)]
        used.update(tokens)
        out.quota[left] = tokens
        if len(tokens) < need:
            out.shortage.append(f"kit {kit_sku[0]} needs {need} more part(s) of {kit_sku[-1]}; only "
                                f"{len(tokens)} usable one(s) lie in parts trays")
    return out


def _other_parts(spec: ProblemSpec, sku_of: dict[str, str], in_trays: dict[str, list[str]],
                 bad: set[str], movable: set[str]) -> dict[str, list[str]]:
    """SKU -> the usable parts of the SKU that lie in no parts tray, no kit and no robot's
    gripper (no fact relates them to a kit or a robot) and that an action can take from where
    they lie (``movable``: :func:`kb.planning.problem.movable`), in name order: after the parts
    in trays, those a domain extension's action takes from elsewhere (a bin, a table)."""
    kinds = ("Robot", "Kit")
    holders = {n for n, (kind, _iri) in spec.objects.items() if kind.rsplit("#", 1)[-1].rsplit("/", 1)[-1] in kinds}
    taken = {x for a in spec.facts if holders & set(a[1:]) for x in a[1:]}
    trays = {p for parts in in_trays.values() for p in parts}
    out: dict[str, list[str]] = {}
    for part, sku in sorted(sku_of.items()):
        if part not in trays and part not in bad and part not in taken and part in movable:
            out.setdefault(sku, []).append(part)
    return out


def replan(domain: DomainSpec, spec: ProblemSpec, facts: Iterable[Atom], values: dict[Atom, float],
           excluded: Iterable[str] = (), planner: str | None = None, timeout: float | None = None) -> PlanResult:
    """A validated plan from the state ``facts``/``values`` to ``spec``'s goal (STRIPS encoding);
    NotSolvableError when no plan exists (e.g. no usable part of a SKU is left).

    A goal atom no action can bring about from this state any more (:func:`kb.planning.goal.unreachable`:
    a part left on the work table, which no action takes from there, keeps ``worktable-empty``
    false) is left out of this plan's goal, so that the rest of the goal (the kits) is still
    reached; the run's end says it does not hold (``goal_unmet``)."""
    strips_domain, quotas = compile_domain(domain)
    state = restated(spec, facts, values, excluded, domain)
    lost = {atom for atom, _why in unreachable(domain, state.objects, state.facts, state.goal)}
    if lost:
        state = replace(state, goal=[g for g in state.goal if g not in lost])
    problem = compile_problem(state, quotas)
    return run(build_problem(strips_domain, problem), None, planner, timeout)
