"""Derived predicates (PDDL 2.2 ``:derived``): expanded where they are used, or kept as
axioms where they are recursive.

unified-planning 1.3 has no derived predicates (its reader rejects ``:derived``, its model
has no axioms: unified-planning issues #496, #683). A derived predicate that does not depend
on itself, directly or through others, means exactly its definition: ``(p ?a)`` holds iff the
body of one of p's rules holds with the rule's head variables bound to the arguments (and
the arguments of the head's types). kitkb substitutes that definition for every use, in
preconditions, conditions of effects, goals and other definitions, so the problem is one
unified-planning, every planner and the plan validator take as it is, with the same plans.

A recursive definition (the least fixpoint of rules that use their own head, as PSR's
``fed`` or a transitive closure) has no finite substitution. Its predicates stay predicates
in the text unified-planning reads, their rules are kept (:meth:`Expander.axioms`) for Fast
Downward, which plans with axioms, and :mod:`.axioms` gives the plan validator their exact
meaning on the problem's objects.
"""

from __future__ import annotations

from kb.core.errors import InputError
from kb.planning.pddl.features import RECURSIVE
from kb.planning.pddl.rewrite import Rewriter, Scope
from kb.planning.pddl.sexp import Expr, Node, Sym, expr, sym
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
    """Builds each derived predicate's rules once and expands atoms of the non-recursive ones."""

    def __init__(self, rw: Rewriter) -> None:
        self.rw = rw
        self.templates: dict[str, list[Template]] = {}
        self.building: list[Sym] = []
        self.components = _components(rw)  # strongly connected, dependencies first
        self.recursive = {p for c in self.components for p in c
                          if len(c) > 1 or p in _dependencies(rw, p)}
        rw.expand = self.expand

    def expand(self, name: Sym, args: list[Sym], arg_kinds: list[tuple[str, ...] | None]) -> Node:
        """The definition of ``(name args...)`` (one disjunct per rule); an atom of a
        recursive one stays an atom."""
        self.rw.note(DERIVED, name)
        if name in self.recursive:
            return Expr([sym(self.rw.names.predicates[name], name), *args], name.line)
        disjuncts = [self._instance(t, args, arg_kinds, name) for t in self._templates(name)]
        if len(disjuncts) == 1:
            return disjuncts[0]
        return expr(["or", *disjuncts], name)

    def _templates(self, name: Sym) -> list[Template]:
        if name in self.templates:
            return self.templates[name]
        assert name not in self.building, name  # a cycle is recursive, never expanded
        self.building.append(name)
        try:
            self.templates[name] = [self._template(rule) for rule in self.rw.s.derived[name]]
        finally:
            self.building.pop()
        return self.templates[name]

    def axioms(self) -> list[Expr]:
        """The rules of the recursive derived predicates, as ``(:derived (p ?x - t) body)``."""
        out = []
        for name in self.rw.s.derived:
            if name not in self.recursive:
                continue
            for rule, t in zip(self.rw.s.derived[name], self._templates(name)):
                head: list[Node] = [sym(self.rw.names.predicates[name], rule.line)]
                for var, kinds in t.head:
                    kind = self.rw.s.common_type(kinds)
                    head += [sym("?" + var, rule.line), sym("-", rule.line), sym(self.rw.names.types[kind], rule.line)]
                out.append(Expr([sym(":derived", rule.line), Expr(head, rule.line), t.body], rule.line))
        return out

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
            if name in self.recursive:
                self.rw.note(RECURSIVE, self.rw.s.derived[name][0].line)


def _dependencies(rw: Rewriter, name: Sym) -> set[Sym]:
    """The derived predicates the rules of ``name`` use."""
    found: set[Sym] = set()
    stack: list[Node] = [rule.body for rule in rw.s.derived[name]]
    while stack:
        n = stack.pop()
        if isinstance(n, Expr):
            if n and isinstance(n[0], Sym) and n[0] in rw.s.derived:
                found.add(n[0])
            stack.extend(n)
    return found


def _components(rw: Rewriter) -> list[list[Sym]]:
    """Tarjan's strongly connected components of the derived predicates' dependencies,
    each after those it depends on."""
    index: dict[Sym, int] = {}
    low: dict[Sym, int] = {}
    stack: list[Sym] = []
    out: list[list[Sym]] = []
    edges = {p: sorted(_dependencies(rw, p)) for p in rw.s.derived}

    def visit(p: Sym) -> None:
        index[p] = low[p] = len(index)
        stack.append(p)
        for q in edges[p]:
            if q not in index:
                visit(q)
                low[p] = min(low[p], low[q])
            elif q in stack:
                low[p] = min(low[p], index[q])
        if low[p] == index[p]:
            component = []
            while True:
                q = stack.pop()
                component.append(q)
                if q == p:
                    break
            out.append(component)

    for p in rw.s.derived:
        if p not in index:
            visit(p)
    return out


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
