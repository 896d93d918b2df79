"""Turn a :class:`DomainSpec` (and a :class:`ProblemSpec`) into a unified-planning problem.

unified-planning is imported when a problem is built, not when this module is: ``kitkb plan``
imports it in parallel with reading the state files (:func:`kb.planning.model.kitting_model`).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from kb.core.namespaces import local_name
from kb.model.soap import DomainSpec, FTerm
from kb.patches.unified_planning import environment, freeze, problem_class
from kb.planning.problem import ProblemSpec

if TYPE_CHECKING:  # pragma: no cover
    from unified_planning.model import Problem

PROBLEM_NAME = "kitting"


class _Builder:
    def __init__(self, domain: DomainSpec):
        env = environment()
        import unified_planning.model as m

        self.m = m
        self.em = env.expression_manager
        self.tm = env.type_manager
        BoolType, IntType = self.tm.BoolType, self.tm.IntType  # noqa: N806
        self.domain = domain
        self.problem = problem_class()(PROBLEM_NAME)
        self.types: dict[str, Any] = {}
        for cls in domain.types:
            self.user_type(cls)
        self.fluents: dict[str, Any] = {}
        for sig in domain.predicates.values():
            self.fluents[sig.name] = self.fluent(sig.name, BoolType(), sig.arg_types, False)
        for fn in domain.functions.values():
            self.fluents[fn.name] = self.fluent(fn.name, IntType(), fn.arg_types, 0)
        for spec in domain.actions:
            self.problem.add_action(self.action(spec))

    def user_type(self, cls: str) -> Any:
        if cls not in self.types:
            parent = self.domain.types.get(cls)
            father = self.user_type(parent) if parent else None
            self.types[cls] = self.tm.UserType(local_name(cls), father)
        return self.types[cls]

    def fluent(self, name: str, kind: Any, arg_types: tuple[str, ...], default: Any) -> Any:
        params: dict[str, Any] = {}
        for t in arg_types:
            base = local_name(t).lower()
            key = base if base not in params else f"{base}{len(params) + 1}"
            params[key] = self.user_type(t)
        fluent = self.m.Fluent(name, kind, **params)
        self.problem.add_fluent(fluent, default_initial_value=default)
        return fluent

    # --- actions --------------------------------------------------------------------
    def action(self, spec) -> Any:  # noqa: ANN001
        em = self.em
        Not, LT, LE, GT, GE, Equals = em.Not, em.LT, em.LE, em.GT, em.GE, em.Equals  # noqa: N806
        params = {name: self.user_type(cls) for name, cls in spec.params}
        act = self.m.InstantaneousAction(spec.name, **params)
        p = {name: act.parameter(name) for name, _ in spec.params}
        for atom in spec.pre:
            expr = self.fluents[atom.predicate](*(p[a] for a in atom.args))
            act.add_precondition(Not(expr) if atom.negated else expr)
        ops = {"<": LT, "<=": LE, ">": GT, ">=": GE, "=": Equals}
        for cmp in spec.comparisons:
            right = self.term(cmp.right, p) if isinstance(cmp.right, FTerm) else _number(cmp.right)
            act.add_precondition(ops[cmp.op](self.term(cmp.left, p), right))
        for atom in sorted(spec.effects, key=lambda a: not a.negated):  # deletes first
            act.add_effect(self.fluents[atom.predicate](*(p[a] for a in atom.args)), not atom.negated)
        for eff in spec.numeric:
            amount = self.term(eff.amount, p) if isinstance(eff.amount, FTerm) else _number(eff.amount)
            target = self.term(eff.term, p)
            {"increase": act.add_increase_effect, "decrease": act.add_decrease_effect,
             "assign": act.add_effect}[eff.kind](target, amount)
        return act

    def term(self, term: FTerm, p: dict) -> Any:
        return self.fluents[term.function](*(p[a] for a in term.args))

    # --- problem --------------------------------------------------------------------
    def add_problem(self, spec: ProblemSpec) -> None:
        Equals = self.em.Equals  # noqa: N806
        made = [self.m.Object(name, self.user_type(cls)) for name, (cls, _iri) in spec.objects.items()]
        self.problem.add_objects(made)
        # object expressions made once (fluent applications would promote them every time)
        objects = {o.name: self.em.ObjectExp(o) for o in made}
        for fact in sorted(spec.facts):
            self.problem.set_initial_value(self.fluents[fact[0]](*(objects[a] for a in fact[1:])), True)
        for key, value in sorted(spec.values.items()):
            self.problem.set_initial_value(self.fluents[key[0]](*(objects[a] for a in key[1:])), _number(value))
        goals = [self.fluents[g[0]](*(objects[a] for a in g[1:])) for g in spec.goal]
        for left, right in spec.goal_equal:
            goals.append(Equals(self.fluents[left[0]](*(objects[a] for a in left[1:])),
                                self.fluents[right[0]](*(objects[a] for a in right[1:]))))
        for goal in goals:
            self.problem.add_goal(goal)


def _number(value: float) -> int | float:
    return int(value) if float(value).is_integer() else value


def build_problem(domain: DomainSpec, problem: ProblemSpec | None = None) -> "Problem":
    """The unified-planning problem of ``domain`` (with ``problem``'s objects, init and goal)."""
    builder = _Builder(domain)
    if problem is not None:
        builder.add_problem(problem)
    freeze(builder.problem)
    return builder.problem
