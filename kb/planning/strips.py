"""Compile the numeric domain into classical STRIPS: counts become token objects.

The only numeric pattern of the kitting domain is a quota: an action may run while a
count is below a capacity, and then increases the count by one
(``(< (quantity-kit ?kit ?sku) (capacity-kit ?kit ?sku))`` with
``(increase (quantity-kit ?kit ?sku) 1)``), and the goal asks for ``count = capacity``.
When the count is a ``soap:CountExpression`` over a class C and the action has exactly one
parameter of class C, each unit of capacity is represented by the object that will fill it
(parts of one SKU are interchangeable, so the problem generator names them up front):

* the comparison becomes ``(<count>-pending ?args... ?token)``,
* the increase becomes ``(not (<count>-pending ...))`` and ``(<count>-counted ...)``,
* the goal ``count = capacity`` becomes one ``(<count>-counted args token)`` per token.

A numeric effect on a function no precondition or goal compares (``quantity-partstray``)
does not constrain plans and is left out. Anything else cannot be compiled and is an error
that names the comparison (use the numeric encoding then).

The grounded size stays linear in the number of parts: ``put-part`` is grounded only for
the (kit, SKU, part) tokens of the initial state, never for part x slot pairs.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

from kb.core.errors import InputError, NotSolvableError
from kb.core.namespaces import local_name
from kb.model.soap import ActionSpec, Atom, Comparison, DomainSpec, FTerm, NumericEffect, Signature
from kb.planning.problem import ProblemSpec


@dataclass(frozen=True)
class Quota:
    """A count compiled into tokens: ``pending``/``counted`` predicates over args + token."""

    count: str
    capacity: str
    pending: str
    counted: str


def compile_domain(domain: DomainSpec) -> tuple[DomainSpec, dict[str, Quota]]:
    """The STRIPS version of ``domain`` and the quotas it introduced (by count function)."""
    compared = {c.left.function for a in domain.actions for c in a.comparisons}
    compared |= {c.right.function for a in domain.actions for c in a.comparisons if isinstance(c.right, FTerm)}
    quotas: dict[str, Quota] = {}
    predicates = dict(domain.predicates)
    actions = []
    for action in domain.actions:
        new = replace(action, pre=list(action.pre), effects=list(action.effects), comparisons=[], numeric=[])
        handled: set[FTerm] = set()  # count terms this action increases under a quota test
        for cmp in action.comparisons:
            quota, token = _quota(domain, action, cmp)
            fn = domain.functions[quota.count]
            for name in (quota.pending, quota.counted):
                predicates.setdefault(name, Signature(name, (*fn.arg_types, fn.counted), cmp.source))
            args = (*cmp.left.args, token)
            new.pre.append(Atom(quota.pending, args, False, cmp.source))
            new.effects += [Atom(quota.pending, args, True, cmp.source), Atom(quota.counted, args, False, cmp.source)]
            quotas[quota.count] = quota
            handled.add(cmp.left)
        for eff in action.numeric:
            if eff.term in handled and _is_unit_increase(eff, quotas[eff.term.function]):
                continue
            if eff.term.function not in compared:
                continue  # never tested: does not constrain plans
            raise InputError(f"action {action.name}: numeric effect {local_name(eff.source)} cannot be "
                             "compiled to STRIPS; use --encoding numeric")
        actions.append(new)
    types = dict(domain.types)
    return DomainSpec(domain.name, domain.source, types, predicates, {}, actions), quotas


def _quota(domain: DomainSpec, action: ActionSpec, cmp: Comparison) -> tuple[Quota, str]:
    bad = InputError(f"action {action.name}: comparison {local_name(cmp.source)} is not a quota "
                     "(count < capacity, count increased by 1); use --encoding numeric")
    if cmp.op != "<" or not isinstance(cmp.right, FTerm) or cmp.left.args != cmp.right.args:
        raise bad
    count = domain.functions[cmp.left.function]
    if count.kind != "CountExpression" or not count.counted:
        raise bad
    if any(e.term.function == cmp.right.function for a in domain.actions for e in a.numeric):
        raise bad  # the capacity must not change
    quota = Quota(count.name, cmp.right.function, f"{count.name}-pending", f"{count.name}-counted")
    if not any(e.term == cmp.left and _is_unit_increase(e, quota) for e in action.numeric):
        raise bad
    tokens = [n for n, t in action.params if t == count.counted and n not in cmp.left.args]
    if len(tokens) != 1:
        raise bad
    return quota, tokens[0]


def _is_unit_increase(eff: NumericEffect, quota: Quota) -> bool:
    return eff.kind == "increase" and eff.term.function == quota.count and eff.amount == 1.0


def compile_problem(problem: ProblemSpec, quotas: dict[str, Quota]) -> ProblemSpec:
    """The STRIPS version of a numeric problem: token facts and goals instead of counts."""
    if problem.shortage:
        raise NotSolvableError("no plan: " + "; ".join(problem.shortage))
    out = replace(problem, facts=set(problem.facts), values={}, goal=list(problem.goal), goal_equal=[])
    for left, right in problem.goal_equal:
        quota = quotas.get(left[0])
        if quota is None or right[0] != quota.capacity:
            raise InputError(f"goal ({' '.join(left)}) = ({' '.join(right)}) cannot be compiled to STRIPS")
        for token in problem.quota.get(left, []):
            out.facts.add((quota.pending, *left[1:], token))
            out.goal.append((quota.counted, *left[1:], token))
    return out
