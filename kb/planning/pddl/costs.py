"""Action costs as the IPC writes them (``:action-costs``), for planners that take them.

The convention (IPC 2008): ``(total-cost)`` is a 0-ary function that actions only
``increase`` by a number or a static function term, at the top of their effect; it starts
at 0 whether or not the problem says ``(= (total-cost) 0)``; and ``(:metric minimize
(total-cost))`` asks for a cheap plan (without it, costs do not matter, as Fast Downward
reads it). Cost functions are often given for the pairs that matter only (road lengths).

unified-planning's reader makes such a domain a numeric problem when the problem does not
initialise ``total-cost``, and reads cost functions as real-valued with undefined values,
which Fast Downward's engine does not take and the plan validator cannot check (the plan
was found, then refused). kitkb takes the costs out of the text and builds the metric
itself: cost functions become integer fluents (real where a value is not whole) with a
static ``defined-...`` precondition where some values are missing, so an action whose cost
is undefined is not applicable, as in Fast Downward and VAL. Anything else that mentions
``total-cost`` stays the numeric problem it is (with ``(= (total-cost) 0)`` added if the
problem omits it).
"""

from __future__ import annotations

from fractions import Fraction
from math import prod
from typing import Any

from kb.planning.pddl import features as F
from kb.planning.pddl.rewrite import ASSIGNMENTS, Rewriter, Scope, is_number
from kb.planning.pddl.sexp import Expr, Node, Sym, expr

TOTAL = "total-cost"


class Costs:
    """The cost reading of one domain and problem (``mode``) and what it took out."""

    def __init__(self, rw: Rewriter) -> None:
        self.rw = rw
        s = rw.s
        self.mode = "none"  # none | metric | ignored | numeric
        self.current: str | None = None  # the operator being rewritten
        self.action_costs: dict[str, list[Node]] = {}
        self.values: dict[str, dict[tuple[str, ...], Fraction]] = {}
        self.guards: dict[str, str] = {}  # cost-only function -> its defined-... predicate
        self.initialised = False
        self.cost_only: set[str] = set()
        rw.cost_effect = self._effect
        rw.cost_fact = self._fact
        declared = s.functions.get(TOTAL)
        if declared is None or declared.params:
            return
        static = _static_functions(rw)
        simple, uses = _cost_uses(rw, static)
        metric = rw.s.problem.metric
        is_min_cost = metric is not None and metric[0] == "minimize" and _is_total(metric[1])
        if simple and (metric is None or is_min_cost):
            self.mode = "metric" if is_min_cost else "ignored"
        else:
            self.mode = "numeric"
        self.cost_only = {f for f, n in uses.items() if n == 0 and f != TOTAL} if self.mode != "numeric" else set()
        rw.note(F.COSTS, declared.line)

    # --- rewriter hooks ------------------------------------------------------------------

    def _effect(self, target: Expr, value: Node, scope: Scope) -> bool:
        if self.mode in ("none", "numeric") or not _is_total(target):
            return False
        if self.mode == "metric" and self.current is not None:
            self.action_costs.setdefault(self.current, []).append(value)
        return True

    def _fact(self, node: Expr) -> bool:
        target = node[1]
        assert isinstance(target, Expr)
        if _is_total(target):
            self.initialised = True
            return self.mode in ("metric", "ignored")
        name = target[0]
        if self.mode in ("metric", "ignored") and name in self.cost_only:
            args = tuple(self.rw.term(a, Scope()) for a in target[1:])
            value = node[2]
            if isinstance(value, Expr) or not is_number(value):
                raise self.rw.error(f"expected a number as the value of {name}, found {value}", node)
            self.values.setdefault(str(name), {})[tuple(map(str, args))] = Fraction(str(self.rw.number(value)))
            return True
        return False

    # --- what the text gets --------------------------------------------------------------

    def declared_functions(self) -> set[str]:
        """Functions (names in the file) left out of the text unified-planning reads."""
        if self.mode in ("metric", "ignored"):
            return {TOTAL, *self.cost_only}
        return set()

    def extra_init(self) -> list[Node]:
        """``(= (total-cost) 0)`` where a numeric reading needs it and the problem omits it."""
        if self.mode == "numeric" and not self.initialised:
            name = self.rw.names.functions[Sym(TOTAL)]
            return [expr(["=", expr([name]), "0"])]
        return []

    def precondition_guards(self, operator: str) -> list[Node]:
        """``(defined-f args)`` for each partially defined cost function the operator's cost uses."""
        out: list[Node] = []
        for value in self.action_costs.get(operator, []):
            for term in _function_terms(value):
                guard = self.guards.get(str(term[0]))
                if guard is not None:
                    out.append(expr([guard, *term[1:]], term))
        return out

    def plan_guards(self) -> list[tuple[str, str, list[Node]]]:
        """The ``defined-...`` predicates to declare: (function, predicate, output params)."""
        out = []
        for f in sorted(self.cost_only):
            sig = self.rw.s.functions[Sym(f)]
            params, _, _ = self.rw.params(sig.params, Scope(), f"the function {f}", fresh=True)
            total = prod(len(self.rw.s.members(tuple(str(k) for k in p.type_names))) for p in sig.params)
            name = self.rw.names.fresh(f"defined-{self.rw.names.functions[Sym(f)]}")
            if len(self.values.get(f, {})) < total:
                self.guards[self.rw.names.functions[Sym(f)]] = name
            out.append((f, name, list(params)))
        return out

    def guard_facts(self) -> list[Node]:
        """The facts of the ``defined-...`` predicates."""
        facts: list[Node] = []
        for f in sorted(self.cost_only):
            emitted = self.rw.names.functions[Sym(f)]
            if emitted in self.guards:
                facts += [expr([self.guards[emitted], *args]) for args in self.values.get(f, {})]
        return facts

    # --- after unified-planning read the text --------------------------------------------

    def install(self, problem: Any, guard_names: dict[str, str]) -> None:
        """Add the cost functions and the metric to unified-planning's ``problem``."""
        if self.mode != "metric":
            return
        from unified_planning.model import Fluent
        from unified_planning.model.metrics import MinimizeActionCosts, MinimizeSequentialPlanLength

        env = problem.environment
        em, tm = env.expression_manager, env.type_manager
        fluents = {}
        for f in sorted(self.cost_only):
            values = self.values.get(f, {})
            whole = all(v.denominator == 1 for v in values.values())
            kind = tm.IntType() if whole else tm.RealType()
            signature = problem.fluent(guard_names[f]).signature
            fluent = Fluent(self.rw.names.functions[Sym(f)], kind, signature, env)
            problem.add_fluent(fluent, default_initial_value=em.Int(0) if whole else em.Real(Fraction(0)))
            for args, value in values.items():
                number = em.Int(value.numerator) if whole else em.Real(value)
                problem.set_initial_value(fluent(*(problem.object(a) for a in args)), number)
            fluents[fluent.name] = fluent
        costs = {}
        for action in problem.actions:  # an action without a cost increase costs the default, 0
            source = self._source_name(action.name)
            parts = [self._up(v, action, problem, fluents, em) for v in self.action_costs.get(source, [])]
            if parts:
                costs[action] = parts[0] if len(parts) == 1 else em.Plus(*parts)
        if len(costs) == len(problem.actions) and all(c.is_int_constant() and c.constant_value() == 1
                                                      for c in costs.values()):
            problem.add_quality_metric(MinimizeSequentialPlanLength(environment=env))
        else:
            problem.add_quality_metric(MinimizeActionCosts(costs, em.Int(0), environment=env))

    def _source_name(self, emitted: str) -> str:
        for source, name in self.rw.names.operators.items():
            if name == emitted:
                return source
        return emitted

    def _up(self, node: Node, action: Any, problem: Any, fluents: dict, em: Any) -> Any:
        if isinstance(node, Sym):
            if node.startswith("?"):
                return em.ParameterExp(action.parameter(node[1:]))
            number = Fraction(str(node))
            return em.Int(number.numerator) if number.denominator == 1 else em.Real(number)
        if node.head in ("+", "-", "*", "/"):
            args = [self._up(a, action, problem, fluents, em) for a in node[1:]]
            op = {"+": em.Plus, "-": em.Minus, "*": em.Times, "/": em.Div}[node.head]
            return op(*args) if node.head != "-" or len(args) > 1 else em.Times(-1, args[0])
        fluent = fluents.get(node[0]) or problem.fluent(node[0])
        args = [em.ParameterExp(action.parameter(a[1:])) if a.startswith("?") else em.ObjectExp(problem.object(a))
                for a in node[1:]]
        return em.FluentExp(fluent, args)


def _is_total(node: Node) -> bool:
    return (isinstance(node, Expr) and len(node) == 1 and node[0] == TOTAL) or node == TOTAL


def _function_terms(node: Node) -> list[Expr]:
    if isinstance(node, Sym):
        return []
    if node.head in ("+", "-", "*", "/"):
        return [t for a in node[1:] for t in _function_terms(a)]
    return [node]


def _static_functions(rw: Rewriter) -> set[str]:
    assigned: set[str] = set()
    for op in rw.s.domain.operators:
        for n in _walk(op.parts.get(":effect")):
            if isinstance(n, Expr) and n.head in ASSIGNMENTS and len(n) == 3:
                target = n[1]
                assigned.add(str(target[0] if isinstance(target, Expr) and target else target))
    return set(rw.s.functions) - assigned


def _cost_uses(rw: Rewriter, static: set[str]) -> tuple[bool, dict[str, int]]:
    """Whether every use of total-cost is an IPC cost increase (and a ``minimize (total-cost)``
    metric), and how often each function is named outside those."""
    uses = dict.fromkeys(map(str, rw.s.functions), 0)
    skip: set[int] = set()  # the cost increases
    parts: list[Node | None] = []
    for op in rw.s.domain.operators:
        if op.kind == ":action":
            skip.update(id(n) for n in _top_effects(op.parts.get(":effect"))
                        if isinstance(n, Expr) and n.head == "increase" and len(n) == 3 and _is_total(n[1])
                        and _cost_value(n[2], static))
        parts += op.parts.values()
    p = rw.s.problem
    parts += [rule.body for rule in rw.s.domain.derived] + [p.goal, *p.constraints]
    if p.metric is not None and not (p.metric[0] == "minimize" and _is_total(p.metric[1])):
        parts.append(p.metric[1])
    for part in parts:
        for n in _walk(part, skip):
            if isinstance(n, Sym) and n in uses:
                uses[n] += 1
    return uses.get(TOTAL, 0) == 0, uses


def _cost_value(node: Node, static: set[str]) -> bool:
    if isinstance(node, Sym):
        return is_number(node)
    return bool(node) and isinstance(node[0], Sym) and node[0] in static and node[0] != TOTAL \
        and all(isinstance(a, Sym) for a in node[1:])


def _top_effects(effect: Node | None):  # noqa: ANN202 - a generator of nodes
    if isinstance(effect, Expr) and effect.head == "and":
        for e in effect[1:]:
            yield from _top_effects(e)
    elif effect is not None:
        yield effect


def _walk(node: Node | None, skip: set[int] | None = None):  # noqa: ANN202 - a generator of nodes
    stack = [node] if node is not None else []
    while stack:
        n = stack.pop()
        if skip and id(n) in skip:
            continue
        yield n
        if isinstance(n, Expr):
            stack.extend(n)
