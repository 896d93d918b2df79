"""Turn a :class:`DomainSpec` (and a :class:`ProblemSpec`) into a unified-planning problem.

unified-planning is imported here, inside the functions, so that importing kitkb stays cheap.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from generators.pddl.soap_reader import local_name
from generators.pddl.spec import DomainSpec, FTerm, ProblemSpec
from generators.pddl.up_env import environment

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
        self.problem = _lean_problem_class()(PROBLEM_NAME)
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


_LEAN: list = []


def _lean_problem_class() -> type:
    """A ``Problem`` whose ``initial_values`` are the explicitly set ones.

    Its ``kind`` is computed once, by :meth:`freeze` at the end of :func:`build_problem`.

    unified-planning's ``Problem.initial_values`` grounds every fluent over every object
    tuple to fill in defaults (tens of thousands of terms for a 640-part kit), only for the
    PDDL writer and pyperplan to skip the false ones again. Every fact kitkb needs is set
    explicitly, so the explicit values say the same thing; the simulator and the plan
    validator already work from the explicit values and the defaults.
    """
    if not _LEAN:
        from unified_planning.model import Problem

        class LeanProblem(Problem):
            _kitkb_kind = None

            @property
            def initial_values(self) -> dict:  # type: ignore[override]
                return dict(self.explicit_initial_values)

            @property
            def kind(self):  # type: ignore[override]  # noqa: ANN202
                # Problem.kind re-analyses the whole problem on every access (the factory,
                # the writer and the validator each ask); a finished kitkb problem is not
                # changed any more, so the kind is computed once (see freeze()).
                if self._kitkb_kind is not None:
                    return self._kitkb_kind
                return Problem.kind.fget(self)

            def freeze(self) -> None:
                """Compute the kind and index the objects; call when the problem is complete."""
                self._kitkb_kind = Problem.kind.fget(self)
                self._kitkb_objects = {o.name: o for o in self.all_objects}

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


def _number(value: float) -> int | float:
    return int(value) if float(value).is_integer() else value


def build_problem(domain: DomainSpec, problem: ProblemSpec | None = None) -> "Problem":
    """The unified-planning problem of ``domain`` (with ``problem``'s objects, init and goal)."""
    builder = _Builder(domain)
    if problem is not None:
        builder.add_problem(problem)
    builder.problem.freeze()
    return builder.problem
