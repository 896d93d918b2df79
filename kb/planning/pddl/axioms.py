"""Recursive derived predicates made exact for unified-planning's plan validator.

A recursive derived predicate holds in a state where the least fixpoint of its rules makes
it hold. On finitely many objects that fixpoint is reached after at most as many rounds as
the predicates of one recursive group have ground atoms: round 0 makes every atom false,
round k applies every rule once to round k-1's atoms. kitkb builds each round's atoms as
ground unified-planning expressions over the problem's fluents (static facts folded to
true or false, each expression made once and shared: unified-planning keeps one node per
distinct expression and its evaluator visits each once), and puts the last round in place
of every atom of a recursive predicate in preconditions, conditions of effects and goals.
The validator then checks a plan against the derived predicates' PDDL meaning, whatever
planner made it. Past :data:`MAX_NODES` expressions the problem is refused at the line of
the predicate's first rule.
"""

from __future__ import annotations

from itertools import product
from typing import Any

from kb.core.errors import InputError
from kb.planning.pddl.derived import Expander
from kb.planning.pddl.sexp import Expr, Node, Sym

#: Expressions the rounds may create before kitkb refuses the problem.
MAX_NODES = 400_000


class Grounding:
    """The rounds of the recursive derived predicates of one problem."""

    def __init__(self, problem: Any, expander: Expander) -> None:
        self.problem = problem
        self.ex = expander
        env = problem.environment
        self.em = env.expression_manager
        self.static = problem.get_static_fluents()
        self.values = problem.explicit_initial_values  # booleans default to false in PDDL
        self.final: dict[tuple[str, tuple[str, ...]], Any] = {}  # atom -> its fixpoint expression
        self.made = 0

    # --- rounds ----------------------------------------------------------------------------

    def build(self) -> None:
        """The fixpoint expression of every ground atom of every recursive predicate."""
        names = self.ex.rw.names.predicates
        for component in self.ex.components:
            if not any(p in self.ex.recursive for p in component):
                continue
            preds = {names[p]: p for p in component}
            atoms = {(names[p], args) for p in component for args in self._tuples(p)}
            previous = {atom: self.em.FALSE() for atom in atoms}
            for _ in range(len(atoms)):
                current = {atom: self._atom(preds[atom[0]], atom[1], previous) for atom in atoms}
                if current == previous:
                    break
                previous = current
            self.final.update(previous)

    def _tuples(self, pred: Sym) -> list[tuple[str, ...]]:
        sig = self.ex.rw.s.predicates[pred]
        kinds = [tuple(str(k) for k in p.type_names) for p in sig.params]
        objects = [[self.ex.rw.names.objects[o] for o in self.ex.rw.s.members(k)] for k in kinds]
        return list(product(*objects))

    def _atom(self, pred: Sym, args: tuple[str, ...], previous: dict) -> Any:
        s = self.ex.rw.s
        disjuncts = []
        for rule, t in zip(s.derived[pred], self.ex.templates[pred]):
            kinds_ok = all(s.covered(s.object_types(self._source_object(a)), kinds)
                           for a, (_, kinds) in zip(args, t.head))
            if kinds_ok:
                binding = {"?" + var: a for (var, _), a in zip(t.head, args)}
                disjuncts.append(self._ground(t.body, binding, previous, rule.line))
        return self._or(disjuncts)

    def _source_object(self, emitted: str) -> str:
        rw = self.ex.rw
        if not hasattr(self, "_sources"):
            self._sources = {v: k for k, v in rw.names.objects.items()}
        return self._sources[emitted]

    # --- one rule body, ground -------------------------------------------------------------

    def _ground(self, n: Node, binding: dict[str, str], previous: dict, line: int) -> Any:
        self._count(line)
        if isinstance(n, Sym) or not n:
            return self.em.TRUE()
        h = n.head
        if h == "and":
            return self._and([self._ground(c, binding, previous, line) for c in n[1:]])
        if h == "or":
            return self._or([self._ground(c, binding, previous, line) for c in n[1:]])
        if h == "not":
            inner = self._ground(n[1], binding, previous, line)
            return self.em.Bool(not inner.bool_constant_value()) if inner.is_bool_constant() else self.em.Not(inner)
        if h == "imply":
            inner = self._ground(n[1], binding, previous, line)
            negated = self.em.Bool(not inner.bool_constant_value()) if inner.is_bool_constant() else self.em.Not(inner)
            return self._or([negated, self._ground(n[2], binding, previous, line)])
        if h in ("exists", "forall"):
            variables = _typed_variables(n[1])
            domains = [self._objects(kind) for _, kind in variables]
            parts = [self._ground(n[2], {**binding, **dict(zip((v for v, _ in variables), objects))}, previous, line)
                     for objects in product(*domains)]
            return self._or(parts) if h == "exists" else self._and(parts)
        if h == "=" and all(isinstance(a, Sym) for a in n[1:]):
            left, right = (binding.get(a, a) for a in n[1:])
            return self.em.Bool(left == right)
        if h in ("=", "<", ">", "<=", ">="):
            raise InputError("a numeric condition in a recursive derived predicate's rule: not supported",
                             self.ex.rw.s.domain.path, line)
        args = tuple(binding.get(a, a) for a in n[1:])  # type: ignore[arg-type]
        key = (str(h), args)
        if key in previous:
            return previous[key]
        if key in self.final:
            return self.final[key]
        if any(key[0] == name for name in self._recursive_names()):
            return self.em.FALSE()  # an atom outside the predicate's head types
        fluent = self.problem.fluent(str(h))
        exp = self.em.FluentExp(fluent, [self.problem.object(a) for a in args])
        if fluent in self.static:
            value = self.values.get(exp)
            return value if value is not None else self.em.FALSE()
        return exp

    def _recursive_names(self) -> set[str]:
        if not hasattr(self, "_names"):
            self._names = {self.ex.rw.names.predicates[p] for p in self.ex.recursive}
        return self._names

    def _objects(self, kind: str) -> list[str]:
        if kind == "object" and not self.problem.has_type(kind):
            return [o.name for o in self.problem.all_objects]
        return [o.name for o in self.problem.objects(self.problem.user_type(kind))]

    def _and(self, parts: list[Any]) -> Any:
        if any(p.is_bool_constant() and not p.bool_constant_value() for p in parts):
            return self.em.FALSE()
        rest = [p for p in parts if not p.is_bool_constant()]
        return self.em.TRUE() if not rest else rest[0] if len(rest) == 1 else self.em.And(*rest)

    def _or(self, parts: list[Any]) -> Any:
        if any(p.is_bool_constant() and p.bool_constant_value() for p in parts):
            return self.em.TRUE()
        rest = [p for p in parts if not p.is_bool_constant()]
        return self.em.FALSE() if not rest else rest[0] if len(rest) == 1 else self.em.Or(*rest)

    def _count(self, line: int) -> None:
        self.made += 1
        if self.made > MAX_NODES:
            raise InputError(f"recursive derived predicates: checking plans against their definition takes more "
                             f"than {MAX_NODES:,} ground expressions on this problem's objects: not supported",
                             self.ex.rw.s.domain.path, line)

    # --- in the problem --------------------------------------------------------------------

    def lifted(self, exp: Any) -> Any:
        """An atom of a recursive predicate with parameters or variables as arguments: the
        disjunction over the ground atoms it can be, each with its fixpoint expression."""
        name = exp.fluent().name
        options = []
        for (pred, objects), value in self.final.items():
            if pred != name or (value.is_bool_constant() and not value.bool_constant_value()):
                continue
            tests = []
            for arg, obj in zip(exp.args, objects):
                if arg.is_object_exp():
                    if arg.object().name != obj:
                        break
                else:
                    tests.append(self.em.Equals(arg, self.problem.object(obj)))
            else:
                options.append(self._and([*tests, value]))
        return self._or(options)

    def replace(self, condition: Any) -> Any:
        """``condition`` with every atom of a recursive predicate replaced by its meaning."""
        atoms = _atoms(condition, self._recursive_names())
        if not atoms:
            return condition
        # by hand: unified-planning's substitute leaves alone what a quantifier's variable is in
        return _rebuild(condition, {a: self.lifted(a) for a in atoms}, self.em, {})


def install(problem: Any, expander: Expander) -> None:
    """Give ``problem``'s preconditions, conditions of effects and goals the exact meaning of
    its recursive derived predicates (nothing when it has none)."""
    if not expander.recursive:
        return
    from unified_planning.model import InstantaneousAction

    g = Grounding(problem, expander)
    g.build()
    for action in problem.actions:
        if not isinstance(action, InstantaneousAction):
            raise InputError("recursive derived predicates with durative actions: not supported",
                             expander.rw.s.domain.path, None)
        preconditions = [g.replace(c) for c in action.preconditions]
        effects = list(action.effects)
        action.clear_preconditions()
        for c in preconditions:
            action.add_precondition(c)
        action.clear_effects()
        for e in effects:
            condition = g.replace(e.condition)
            add = action.add_increase_effect if e.is_increase() else \
                action.add_decrease_effect if e.is_decrease() else action.add_effect
            add(e.fluent, e.value, condition, e.forall)
    goals = [g.replace(goal) for goal in problem.goals]
    problem.clear_goals()
    for goal in goals:
        problem.add_goal(goal)


def _atoms(condition: Any, names: set[str]) -> list[Any]:
    """The fluent expressions of predicates ``names`` in ``condition`` (also under quantifiers)."""
    found: list[Any] = []
    seen: set[int] = set()
    stack = [condition]
    while stack:
        node = stack.pop()
        if id(node) in seen:
            continue
        seen.add(id(node))
        if node.is_fluent_exp() and node.fluent().name in names:
            found.append(node)
        stack.extend(node.args)
    return found


def _rebuild(node: Any, mapping: dict, em: Any, memo: dict) -> Any:
    """``node`` with the atoms in ``mapping`` replaced. An atom of a predicate stands only under
    connectives and quantifiers, so only those are rebuilt (unified-planning's public
    constructors); every other node is kept as it is."""
    if node in mapping:
        return mapping[node]
    if node in memo:
        return memo[node]
    new = node
    if node.is_and() or node.is_or() or node.is_not() or node.is_implies() or node.is_iff() \
            or node.is_exists() or node.is_forall():
        args = [_rebuild(a, mapping, em, memo) for a in node.args]
        if any(a is not b for a, b in zip(args, node.args)):
            if node.is_exists() or node.is_forall():
                make = em.Exists if node.is_exists() else em.Forall
                new = make(args[0], *node.variables())
            else:
                make = {"and": em.And, "or": em.Or, "not": em.Not, "implies": em.Implies, "iff": em.Iff}
                kind = next(k for k in make if getattr(node, f"is_{k}")())
                new = make[kind](*args)
    memo[node] = new
    return new


def _typed_variables(node: Node) -> list[tuple[str, str]]:
    """``(?a ?b - t ?c)`` of the rewritten text -> [(?a, t), (?b, t), (?c, object)]."""
    out: list[tuple[str, str]] = []
    pending: list[str] = []
    items = list(node) if isinstance(node, Expr) else []
    i = 0
    while i < len(items):
        if items[i] == "-":
            out += [(v, str(items[i + 1])) for v in pending]
            pending = []
            i += 2
            continue
        pending.append(str(items[i]))
        i += 1
    return out + [(v, "object") for v in pending]
