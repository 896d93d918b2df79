"""Derived predicates (PDDL 2.2 ``:derived``), expanded where they are used.

unified-planning 1.3 has no derived predicates (its reader rejects ``:derived``, its model
has no axioms: unified-planning issues #496, #683). A derived predicate that does not depend
on itself, directly or through others, means exactly its definition: ``(p ?a)`` holds iff the
body of one of p's rules holds with the rule's head variables bound to the arguments (and
the arguments of the head's types). kitkb substitutes that definition for every use, in
preconditions, conditions of effects, goals and other definitions, so the problem is one
unified-planning, every planner and the plan validator take as it is, with the same plans.

A recursive definition (the least fixpoint of rules that use their own head, as in PSR's
``fed``) has no finite substitution; it is refused at its line, naming the cycle.
"""

from __future__ import annotations

from kb.core.errors import InputError
from kb.planning.pddl.rewrite import Rewriter, Scope
from kb.planning.pddl.sexp import Expr, Node, Sym, expr
from kb.planning.pddl.syntax import Derived

DERIVED = "derived predicates (:derived)"
#: Symbols an expanded definition may have before kitkb refuses it (the expansion of rules
#: that each use another twice doubles per level).
MAX_SIZE = 200_000


class Template:
    """One rule, rewritten: its head variables (output names, types) and its body."""

    def __init__(self, head: list[tuple[str, tuple[str, ...]]], body: Node) -> None:
        self.head = head
        self.body = body


class Expander:
    """Builds each derived predicate's rules once (in dependency order) and expands atoms."""

    def __init__(self, rw: Rewriter) -> None:
        self.rw = rw
        self.templates: dict[str, list[Template]] = {}
        self.building: list[Sym] = []
        rw.expand = self.expand

    def expand(self, name: Sym, args: list[Sym], arg_kinds: list[tuple[str, ...] | None]) -> Node:
        """The definition of ``(name args...)``: one disjunct per rule."""
        self.rw.note(DERIVED, name)
        disjuncts = [self._instance(t, args, arg_kinds, name) for t in self._templates(name)]
        if len(disjuncts) == 1:
            return disjuncts[0]
        return expr(["or", *disjuncts], name)

    def _templates(self, name: Sym) -> list[Template]:
        if name in self.templates:
            return self.templates[name]
        if name in self.building:
            cycle = self.building[self.building.index(name):] + [name]
            first = self.rw.s.derived[cycle[0]][0]
            raise InputError(f"derived predicate {cycle[0].written} is recursive "
                             f"({' -> '.join(c.written for c in cycle)}): not supported (kitkb "
                             "expands derived predicates where they are used, and unified-planning, "
                             "whose validator checks every plan, has no derived predicates)",
                             self.rw.s.domain.path, first.line)
        self.building.append(name)
        try:
            self.templates[name] = [self._template(rule) for rule in self.rw.s.derived[name]]
        finally:
            self.building.pop()
        return self.templates[name]

    def _template(self, rule: Derived) -> Template:
        rw = self.rw
        saved = rw.path, rw.in_problem, rw.fresh_names
        rw.path, rw.in_problem, rw.fresh_names = rw.s.domain.path, False, True
        try:
            params, scope, guards = rw.params(rule.head.params, Scope(),
                                              f"the derived predicate {rule.head.name.written}")
            body = rw.condition(rule.body, scope)
        finally:
            rw.path, rw.in_problem, rw.fresh_names = saved
        if guards:
            body = expr(["and", *guards, body], rule.body)
        size = _size(body)
        if size > MAX_SIZE:
            raise InputError(f"derived predicate {rule.head.name.written}: its definition expands to "
                             f"{size:,} symbols (more than {MAX_SIZE:,}): not supported", rw.s.domain.path,
                             rule.line)
        head = [(v.name, v.kinds) for v in (scope.vars[p.name[1:]] for p in rule.head.params)]
        return Template(head, body)

    def _instance(self, t: Template, args: list[Sym], arg_kinds: list[tuple[str, ...] | None],
                  where: Sym) -> Node:
        mapping = {"?" + var: arg for (var, _), arg in zip(t.head, args)}
        body = _substitute(t.body, mapping)
        guards: list[Node] = []
        for (var, kinds), arg, have in zip(t.head, args, arg_kinds):
            if have is None or not self.rw.s.covered(have, kinds):
                guards.append(expr([self.rw.membership(kinds, where), arg], where))
        return expr(["and", *guards, body], where) if guards else body

    def check_all(self) -> None:
        """Build every rule, so that a recursive or malformed one is refused even where
        nothing uses it."""
        for name in self.rw.s.derived:
            self._templates(name)


def _substitute(node: Node, mapping: dict[str, Sym]) -> Node:
    """``node`` with head variables replaced by arguments (every variable a template binds
    has a name used nowhere else, so nothing is captured)."""
    if isinstance(node, Sym):
        return mapping.get(node, node)
    return Expr((_substitute(c, mapping) for c in node), node.line)


def _size(node: Node) -> int:
    if isinstance(node, Sym):
        return 1
    return 1 + sum(_size(c) for c in node)
