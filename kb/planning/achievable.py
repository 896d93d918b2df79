"""The achievable goal when not every kit can be finished: which kits get the scarce parts.

When the usable parts left (:func:`kb.planning.replan.restated`: those in parts trays and those
an action can take from where they lie, minus the unusable) cannot fill every kit, the replanner
is given the goal the parts allow instead of none:

* :func:`choose_kits` picks the kits to finish: as many as the parts allow (exactly, by trying
  the sets of kits from the largest down; a kit is one whole kit, never two halves), ties broken
  by the parts already in the kits of a set (more first), then by the kits' names;
* each other kit follows the partial-kit policy (``soap:hasDomain_PartialKitPolicy`` in the
  domain's Turtle, or ``kitkb run --partial-kits``): ``deliver`` gets what parts are left after
  the finished kits (in kit name order) and is delivered as the goal says, partial (ARIAC's rule
  for insufficient parts); ``leave`` gets no more parts and is not delivered: the goal atoms
  naming it are dropped, and so are those about the place where it stands (a kit left on the work
  table keeps the table occupied, so with ``leave`` a kit standing there that cannot be finished
  lets no other kit be built after it: :func:`choose_kits` counts that);
* :func:`achievable` returns the restated problem with that goal (quota tokens per kit) and, per
  kit not finished, what it lacks (SKU -> count).

The executor's goal check still uses the whole goal: a run with a partial or left kit does not
reach its goal (``goal_holds`` false, the report's ``partial_kits``).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from itertools import combinations
from typing import Iterable, Mapping

from kb.core.errors import InputError
from kb.model.soap import DomainSpec
from kb.planning.build import build_problem
from kb.planning.goal import unreachable
from kb.planning.planners import NotSolvableError, PlanResult, run
from kb.planning.problem import ProblemSpec, movable
from kb.planning.replan import restated
from kb.planning.strips import compile_domain, compile_problem

Atom = tuple[str, ...]

#: the partial-kit policies (``soap:PartialKitPolicy`` individuals' ``soap:hasPartialKitPolicy_Name``)
POLICIES = ("deliver", "leave")
#: kits from which :func:`choose_kits` tries every set; beyond, kits needing fewest parts first
EXACT_KITS = 16
#: a capacity no kit needs: asks :func:`restated` for every usable part of a SKU
_ALL = 1e9


@dataclass
class KitChoice:
    """Which kits are finished and what each other kit lacks (kit -> SKU -> count) under ``policy``."""

    policy: str
    finished: list[str] = field(default_factory=list)
    lacking: dict[str, dict[str, int]] = field(default_factory=dict)

    def as_list(self) -> list[dict]:
        """The report's ``partial_kits``: each kit not finished, how it ends and what it lacks."""
        how = "delivered partial" if self.policy == "deliver" else "left"
        return [{"kit": kit, "outcome": how, "lacks": dict(sorted(lacks.items()))}
                for kit, lacks in sorted(self.lacking.items())]


def check_policy(policy: str) -> str:
    if policy not in POLICIES:
        raise InputError(f"partial-kit policy {policy!r} is not one of: {', '.join(POLICIES)}")
    return policy


def choose_kits(needs: Mapping[str, Mapping[str, int]], pool: Mapping[str, int],
                placed: Mapping[str, int] | None = None, standing: Iterable[str] = (),
                policy: str = "deliver") -> list[str]:
    """The kits to finish: the largest set whose remaining needs (kit -> SKU -> parts still to
    put in) the ``pool`` (SKU -> usable parts) covers; ties: more parts already ``placed`` in
    the set's kits, then the kit names in order. With ``leave``, a kit ``standing`` where kits
    are built (on the work table) that the set leaves out blocks every kit not yet finished."""
    placed = placed or {}
    kits = sorted(needs)
    standing = set(standing)
    done = [k for k in kits if not any(n > 0 for n in needs[k].values())]
    open_ = [k for k in kits if k not in done]

    def fits(chosen: Iterable[str]) -> bool:
        used: dict[str, int] = {}
        for k in chosen:
            for sku, n in needs[k].items():
                used[sku] = used.get(sku, 0) + max(n, 0)
        return all(pool.get(sku, 0) >= n for sku, n in used.items())

    def allowed(chosen: tuple[str, ...]) -> bool:
        if policy != "leave":
            return True
        blocked = (standing & set(open_)) - set(chosen)
        return not blocked or not chosen

    def key(chosen: tuple[str, ...]) -> tuple:
        return (-sum(placed.get(k, 0) for k in chosen), chosen)

    if len(open_) <= EXACT_KITS:
        for size in range(len(open_), 0, -1):
            found = [c for c in combinations(open_, size) if allowed(c) and fits(c)]
            if found:
                return sorted(done + list(min(found, key=key)))
        return done
    chosen: list[str] = []  # many kits: the cheapest first
    for k in sorted(open_, key=lambda k: (sum(needs[k].values()), -placed.get(k, 0), k)):
        if fits(chosen + [k]) and allowed(tuple(chosen + [k])):
            chosen.append(k)
    return sorted(done + chosen)


def achievable(domain: DomainSpec, spec: ProblemSpec, facts: Iterable[Atom], values: dict[Atom, float],
               excluded: Iterable[str] = (), policy: str = "deliver",
               within: Iterable[str] | None = None) -> tuple[ProblemSpec, KitChoice]:
    """:func:`restated` with the goal the usable parts allow (module doc): its quota tokens
    given to the kits :func:`choose_kits` finishes, then (``deliver``) to the others; no shortage
    left. The :class:`KitChoice` says what each kit not finished lacks."""
    check_policy(policy)
    facts = set(facts)
    excluded = set(excluded)
    state = restated(spec, facts, values, excluded, domain)
    pool = _pool(domain, spec, facts, values, excluded)
    quantity = {left: state.values.get(left, 0.0) for left, _right in spec.goal_equal}
    needs: dict[str, dict[str, int]] = {}
    placed: dict[str, int] = {}
    for left, right in spec.goal_equal:
        kit, sku = left[1], left[-1]
        needs.setdefault(kit, {})[sku] = max(int(state.values.get(right, 0.0) - quantity[left]), 0)
        placed[kit] = placed.get(kit, 0) + int(quantity[left])
    # a kit whose goal facts all hold already (delivered to its box) takes no more parts: what it
    # lacks stays lacking, whatever the policy
    closed = {k for k in delivered(state.goal, state.facts, needs) if any(n > 0 for n in needs[k].values())}
    shut = {k: needs[k] for k in closed}
    needs = {k: v for k, v in needs.items() if k not in closed}
    standing = movable(state.facts, domain) & set(needs)
    finished = choose_kits(needs, {s: len(p) for s, p in pool.items()}, placed, standing, policy)
    if within is not None:  # a choice the planner could not reach: only kits of ``within`` (and kits done)
        keep = set(within)
        finished = [k for k in finished if k in keep or not any(n > 0 for n in needs[k].values())]
    choice = KitChoice(policy, finished)
    free = {s: list(p) for s, p in pool.items()}
    quota: dict[Atom, list[str]] = {}
    order = finished + [k for k in sorted(needs) if k not in finished]
    for kit, lacks in shut.items():
        for left, _right in spec.goal_equal:
            if left[1] == kit:
                quota[left] = []
        lacking = {sku: n for sku, n in lacks.items() if n > 0}
        if lacking:
            choice.lacking[kit] = lacking
    for kit in order:
        for left, _right in spec.goal_equal:
            if left[1] != kit:
                continue
            sku, need = left[-1], needs[kit][left[-1]]
            take = need if kit in finished or policy == "deliver" else 0
            quota[left] = free.get(sku, [])[:take]
            del free.get(sku, [])[:take]
            if len(quota[left]) < need:
                choice.lacking.setdefault(kit, {})[sku] = need - len(quota[left])
    left_kits = set(choice.lacking) if policy == "leave" else set()
    # where a left kit stands: the other objects of the changing facts about it (kit-location-worktable(kit, table))
    places = {x for a in state.facts if len(a) > 1 and a[1] in left_kits and a[0] not in _static(domain)
              for x in a[2:] if x not in left_kits}
    goal = [g for g in state.goal if not (left_kits | places) & set(g[1:])]
    return replace(state, quota=quota, shortage=[], goal=goal), choice


def replan_achievable(domain: DomainSpec, spec: ProblemSpec, facts: Iterable[Atom], values: dict[Atom, float],
                      excluded: Iterable[str] = (), policy: str = "deliver", planner: str | None = None,
                      timeout: float | None = None) -> tuple[PlanResult, KitChoice]:
    """:func:`kb.planning.replan.replan` to the :func:`achievable` goal: a validated plan and
    the choice of kits; NotSolvableError when none exists.

    The kits chosen are those the usable parts cover (:func:`choose_kits`); when the planner
    proves that goal unreachable (a kit tray it cannot get, a part it cannot reach), one kit
    fewer is finished, the kit that needs the most parts first, down to none finished: the
    policy still applies to every kit, and the error is the planner's only when even that fails."""
    strips_domain, quotas = compile_domain(domain)
    within: list[str] | None = None
    while True:
        state, choice = achievable(domain, spec, facts, values, excluded, policy, within)
        lost = {atom for atom, _why in unreachable(domain, state.objects, state.facts, state.goal)}
        if lost:
            state = replace(state, goal=[g for g in state.goal if g not in lost])
        problem = compile_problem(state, quotas)
        try:
            return run(build_problem(strips_domain, problem), None, planner, timeout), choice
        except NotSolvableError:
            need = _needs(spec, state)
            open_ = sorted((k for k in choice.finished if need.get(k, 0) > 0), key=lambda k: (need[k], k))
            if not open_:
                raise
            within = open_[:-1]  # the kit that needs the most parts is given up first


def delivered(goal: Iterable[Atom], facts: set[Atom], kits: Iterable[str]) -> set[str]:
    """The kits whose goal facts (kit-location-lbwk(kit, box)) all hold now: delivered, they take
    no more parts (no action of the domain opens a kit in its box again)."""
    about: dict[str, list[Atom]] = {}
    for g in goal:
        for k in g[1:]:
            about.setdefault(k, []).append(g)
    return {k for k in kits if about.get(k) and all(g in facts for g in about[k])}


def _needs(spec: ProblemSpec, state: ProblemSpec) -> dict[str, int]:
    """Kit -> parts still to put in, over its SKUs."""
    out: dict[str, int] = {}
    for left, right in spec.goal_equal:
        out[left[1]] = out.get(left[1], 0) + max(int(state.values.get(right, 0.0) - state.values.get(left, 0.0)), 0)
    return out


def _pool(domain: DomainSpec, spec: ProblemSpec, facts: set[Atom], values: dict[Atom, float],
          excluded: set[str]) -> dict[str, list[str]]:
    """SKU -> every usable part of it, as :func:`restated` finds them (its own order: parts
    trays first): asked of it with one kit needing them all."""
    first: dict[str, tuple[Atom, Atom]] = {}
    for left, right in spec.goal_equal:
        first.setdefault(left[-1], (left, right))
    ask = replace(spec, goal_equal=list(first.values()))
    wide = dict(values)
    for left, right in first.values():
        wide[left] = 0.0
        wide[right] = _ALL
    state = restated(ask, facts, wide, excluded, domain)
    return {left[-1]: list(state.quota.get(left, [])) for left, _right in first.values()}


def _static(domain: DomainSpec) -> set[str]:
    """Predicates no action changes (a kit's tray, what grips it): not where a kit stands."""
    changed = {e.predicate for a in domain.actions for e in a.effects}
    return {p for p in domain.predicates if p not in changed}
