"""Conditions, effects and terms rewritten into the PDDL unified-planning's reader takes.

One walk over every condition and effect does what the reader cannot: names are replaced by
:class:`~.names.Names` (clashes, unreadable names); a variable of an ``(either a b)`` type
becomes a variable of the types' common ancestor guarded by a static membership predicate
(:meth:`Rewriter.membership`); a derived predicate is replaced by its definition
(:mod:`.derived`); action-cost effects are taken out when :mod:`.costs` builds the metric
itself. On the way every predicate, function, constant and variable is checked (declared,
right number of arguments, in scope), with the error at its line, and each PDDL feature's
first use is noted (:mod:`.features`).
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

from kb.core.errors import InputError
from kb.planning.pddl import features as F
from kb.planning.pddl.names import Names, safe
from kb.planning.pddl.sexp import Expr, Node, Sym, expr, show, sym
from kb.planning.pddl.symbols import OBJECT, Symbols
from kb.planning.pddl.syntax import Reader, Typed

CONNECTIVES = ("and", "or", "not", "imply", "exists", "forall")
COMPARISONS = ("<", ">", "<=", ">=", "=")
ARITHMETIC = ("+", "-", "*", "/")
ASSIGNMENTS = ("assign", "increase", "decrease", "scale-up", "scale-down")
TRAJECTORY = ("always", "sometime", "at-most-once", "sometime-before", "sometime-after")


@dataclass
class Var:
    """A variable in scope: its name in the output (without ``?``) and its types."""

    name: str
    kinds: tuple[str, ...]


@dataclass
class Scope:
    """Variables by their name in the file (without ``?``)."""

    vars: dict[str, Var] = field(default_factory=dict)

    def bind(self, extra: dict[str, Var]) -> "Scope":
        """This scope with ``extra`` added (shadowing)."""
        return Scope({**self.vars, **extra})


class Rewriter:
    """Rewrites the nodes of one domain and problem (see the module docstring)."""

    def __init__(self, s: Symbols, names: Names, features: F.Features, all_vars: set[str]) -> None:
        self.s = s
        self.names = names
        self.features = features
        self.used_vars = set(all_vars)  # every variable name in the files or made here
        self.memberships: dict[frozenset[str], tuple[str, str]] = {}  # types -> (predicate, its type)
        self.path: Path = s.domain.path
        self.in_problem = False
        self.fresh_names = False  # every bound variable gets a new name (derived definitions)
        self.recursive: set[str] = set()  # derived predicates kept as predicates (:mod:`.derived`)
        #: derived predicate -> the function that expands an atom of it (set by :mod:`.derived`)
        self.expand: Callable[[Sym, list[Sym], list[tuple[str, ...] | None]], Node] | None = None
        #: hooks of :mod:`.costs`: an assignment to drop (and keep as a cost), a fact to drop
        self.cost_effect: Callable[[Expr, Node, Scope], bool] = lambda node, value, scope: False
        self.cost_fact: Callable[[Expr], bool] = lambda node: False

    # --- errors and places ---------------------------------------------------------------

    def error(self, message: str, where: Node | int | None) -> InputError:
        line = where if isinstance(where, int) or where is None else where.line
        return InputError(message, self.path, line or None)

    def note(self, feature: str, where: Node | int) -> None:
        self.features.note(feature, self.path, where)

    # --- variables and types ---------------------------------------------------------------

    def fresh_var(self, base: str) -> str:
        """A variable name no file uses and kitkb did not make before."""
        name = self.names.variable(base, self.used_vars)
        self.used_vars.add(name)
        return name

    def params(self, params: list[Typed], scope: Scope, what: str,
               fresh: bool = False) -> tuple[Expr, Scope, list[Node]]:
        """A typed list of variables for the output, the scope inside it, and the guards
        its ``either`` types need (``fresh``: every variable renamed to a new name)."""
        out: list[Node] = []
        new: dict[str, Var] = {}
        guards: list[Node] = []
        line = params[0].name.line if params else 0
        typed_after = [any(q.type is not None and q.type != OBJECT for q in params[i + 1:])
                       for i in range(len(params))]
        for p, later in zip(params, typed_after):
            raw = p.name[1:]
            if raw in new:
                raise self.error(f"variable {p.name.written} is declared twice in {what}", p.name)
            keep = not (fresh or self.fresh_names) and raw not in scope.vars and safe(raw)
            name = raw if keep else self.fresh_var(raw)
            kinds = tuple(str(k) for k in p.type_names)
            new[raw] = Var(name, kinds)
            out.append(sym("?" + name, p.name))
            emitted, guard = self.var_type(kinds, "?" + name, p.name)
            if emitted != OBJECT or later:  # a name without a type takes the next one's
                out += [sym("-", p.name), sym(emitted, p.name)]
            if guard is not None:
                guards.append(guard)
        return Expr(out, line), scope.bind(new), guards

    def var_type(self, kinds: tuple[str, ...], var: str, where: Node) -> tuple[str, Node | None]:
        """The output type of a variable of ``kinds`` and its membership guard (or None)."""
        if len(kinds) == 1:
            return self.names.types[kinds[0]], None
        self.note("either types", where)
        common = self.s.common_type(kinds)
        if self.s.covered((common,), kinds):
            return self.names.types[common], None
        return self.names.types[common], expr([self.membership(kinds, where), sym(var, where)], where)

    def membership(self, kinds: tuple[str, ...], where: Node | int = 0) -> str:
        """The static predicate true of exactly the objects of one of ``kinds``."""
        key = frozenset(kinds)
        if key not in self.memberships:
            name = self.names.fresh("is-" + "-or-".join(sorted(key)))
            self.memberships[key] = (name, self.s.common_type(kinds))
        return self.memberships[key][0]

    # --- conditions ----------------------------------------------------------------------

    def condition(self, n: Node, scope: Scope) -> Node:
        """A goal description (precondition, goal, derived body)."""
        if isinstance(n, Sym):
            raise self.error(f"expected a condition in parentheses, found {n.written!r}", n)
        if not n:
            return n
        h = n.head
        if h in ("and", "or"):
            if h == "or":
                self.note(F.DISJUNCTION, n)
            return Expr([n[0], *(self.condition(c, scope) for c in n[1:])], n.line)
        if h == "not":
            self._arity(n, 1, "(not CONDITION)")
            self.note(F.NEGATION, n)
            return Expr([n[0], self.condition(n[1], scope)], n.line)
        if h == "imply":
            self._arity(n, 2, "(imply CONDITION CONDITION)")
            self.note(F.DISJUNCTION, n)
            return Expr([n[0], self.condition(n[1], scope), self.condition(n[2], scope)], n.line)
        if h in ("exists", "forall"):
            return self._quantified(n, scope)
        if h in COMPARISONS:
            return self._comparison(n, scope)
        if h == "preference":
            raise self.error("preferences (PDDL 3 :preferences) are not supported", n)
        if h in ("at", "over") and len(n) == 3 and n[1] in ("start", "end", "all"):
            return Expr([n[0], n[1], self.condition(n[2], scope)], n.line)
        return self.atom(n, scope, effect=False)

    def _arity(self, n: Expr, k: int, form: str) -> None:
        if len(n) != k + 1:
            raise self.error(f"expected {form}, found {show(n)}", n)

    def _quantified(self, n: Expr, scope: Scope) -> Node:
        self._arity(n, 2, f"({n.head} (?x - type ...) CONDITION)")
        if not isinstance(n[1], Expr):
            raise self.error(f"expected a list of variables after {n.head}", n[1])
        self.note(F.EXISTS if n.head == "exists" else F.FORALL, n)
        typed = self._typed_vars(n[1], n.head)
        if not typed:  # no variables: the condition itself
            return self.condition(n[2], scope)
        params, inner, guards = self.params(typed, scope, f"({n.head} ...)")
        body = self.condition(n[2], inner)
        if guards:
            guard = guards[0] if len(guards) == 1 else expr(["and", *guards], n)
            body = expr(["and" if n.head == "exists" else "imply", guard, body], n)
        return Expr([n[0], params, body], n.line)

    def _typed_vars(self, node: Expr, what: str) -> list[Typed]:
        typed = Reader(self.path, lambda m: None).typed_list(list(node), f"({what} ...)")
        for t in typed:
            if not t.name.startswith("?"):
                raise self.error(f"expected a variable (?name) in ({what} ...), found {t.name.written}", t.name)
            for kind in t.type_names:
                if kind != OBJECT and kind not in self.s.parents:
                    raise self.error(f"unknown type {kind.written}", kind)
        return typed

    def _comparison(self, n: Expr, scope: Scope) -> Node:
        self._arity(n, 2, f"({n.head} A B)")
        if n.head == "=" and all(isinstance(a, Sym) and not is_number(a) and not self._is_function(a)
                                 for a in n[1:]):
            self.note(F.EQUALITY, n)
            return Expr([n[0], self.term(n[1], scope), self.term(n[2], scope)], n.line)
        self.note(F.NUMERIC, n)
        return Expr([n[0], self.numeric(n[1], scope), self.numeric(n[2], scope)], n.line)

    def _is_function(self, a: Sym) -> bool:
        return a in self.s.functions

    def atom(self, n: Expr, scope: Scope, effect: bool) -> Node:
        """``(predicate term ...)``: checked, renamed; a derived one expanded."""
        name = n[0]
        if not isinstance(name, Sym):
            raise self.error(f"expected a predicate name, found {show(name)}", n)
        sig = self.s.predicates.get(name)
        if sig is None:
            if name in self.s.functions:
                raise self.error(f"{name.written} is a function, used here as a predicate", n)
            raise self.error(f"unknown predicate {name.written}", n)
        if len(n) - 1 != len(sig.params):
            raise self.error(f"{name.written} takes {len(sig.params)} argument(s), given {len(n) - 1}: {show(n)}", n)
        args = [self.term(a, scope) for a in n[1:]]
        if name in self.s.derived:
            if effect:
                raise self.error(f"derived predicate {name.written} is changed by an effect (a derived "
                                 "predicate is only defined by its :derived rules)", n)
            assert self.expand is not None
            return self.expand(name, args, [self._kinds_of(a, scope) for a in n[1:]])
        return Expr([sym(self.names.predicates[name], name), *args], n.line)

    def _kinds_of(self, a: Node, scope: Scope) -> tuple[str, ...] | None:
        if isinstance(a, Sym) and a.startswith("?") and a[1:] in scope.vars:
            return scope.vars[a[1:]].kinds
        if isinstance(a, Sym) and a in self.s.objects:
            return self.s.object_types(a)
        return None

    def term(self, a: Node, scope: Scope) -> Sym:
        """A variable in scope or a declared constant (in a problem: any object)."""
        if isinstance(a, Expr):
            raise self.error(f"a function term as an argument ({show(a)}): object-valued functions "
                             "(:object-fluents) are not supported", a)
        if a.startswith("?"):
            var = scope.vars.get(a[1:])
            if var is None:
                raise self.error(f"unknown variable {a.written} (not a parameter, nor bound by a "
                                 "quantifier around it)", a)
            return sym("?" + var.name, a)
        if a in self.s.objects and (self.in_problem or a in self.s.constants):
            return sym(self.names.objects[a], a)
        if a in self.s.objects:
            raise self.error(f"{a.written} is an object of the problem, not a constant of the domain "
                             "(declare it in the domain's :constants)", a)
        raise self.error(f"unknown {'object' if self.in_problem else 'constant'} {a.written}", a)

    def number(self, a: Sym) -> Sym:
        """``a``, a number of at most :data:`MAX_DIGITS` characters."""
        if len(a) > MAX_DIGITS:
            raise self.error(f"a number of {len(a):,} characters (more than {MAX_DIGITS})", a)
        return a

    def numeric(self, n: Node, scope: Scope) -> Node:
        """A numeric expression: numbers, function terms, arithmetic, ``?duration``, ``#t``."""
        if isinstance(n, Sym):
            if is_number(n):
                return self.number(n)
            if n in ("#t", "?duration", "total-time"):
                if n == "#t":
                    self.note(F.CONTINUOUS, n)
                return n
            if n in self.s.functions:
                return self.function_term(Expr([n], n.line), scope)
            return self.term(n, scope)
        if not n:
            raise self.error("expected a numeric expression, found ()", n)
        if len(n) == 1 and n.head == "total-time":
            return n
        if n.head in ARITHMETIC:
            if len(n) < 2 or (n.head in ("*", "/") and len(n) < 3):
                raise self.error(f"expected ({n.head} A B), found {show(n)}", n)
            return Expr([n[0], *(self.numeric(a, scope) for a in n[1:])], n.line)
        return self.function_term(n, scope)

    def function_term(self, n: Expr, scope: Scope) -> Node:
        """``(function term ...)``: checked and renamed."""
        name = n[0]
        sig = self.s.functions.get(name) if isinstance(name, Sym) else None
        if sig is None:
            shown = name.written if isinstance(name, Sym) else show(n)
            if isinstance(name, Sym) and name in self.s.predicates:
                raise self.error(f"{shown} is a predicate, used here as a number", n)
            raise self.error(f"unknown function {shown}", n)
        if len(n) - 1 != len(sig.params):
            raise self.error(f"{name.written} takes {len(sig.params)} argument(s), given {len(n) - 1}: {show(n)}", n)
        self.note(F.NUMERIC, n)
        return Expr([sym(self.names.functions[name], name), *(self.term(a, scope) for a in n[1:])], n.line)

    # --- effects -------------------------------------------------------------------------

    def effect(self, n: Node, scope: Scope) -> Node | None:
        """An effect; None where nothing is left (an action-cost increase taken out)."""
        if isinstance(n, Sym):
            raise self.error(f"expected an effect in parentheses, found {n.written!r}", n)
        if not n:
            return None
        h = n.head
        if h == "and":
            parts = [e for e in (self.effect(c, scope) for c in n[1:]) if e is not None]
            return Expr([n[0], *parts], n.line) if parts else None
        if h == "not":
            self._arity(n, 1, "(not ATOM)")
            if not isinstance(n[1], Expr):
                raise self.error(f"expected (not (predicate ...)), found {show(n)}", n)
            return Expr([n[0], self.atom(n[1], scope, effect=True)], n.line)
        if h == "forall":
            return self._forall_effect(n, scope)
        if h == "when":
            self._arity(n, 2, "(when CONDITION EFFECT)")
            self.note(F.CONDITIONAL, n)
            inner = self.effect(n[2], scope)
            return None if inner is None else Expr([n[0], self.condition(n[1], scope), inner], n.line)
        if h in ASSIGNMENTS:
            self._arity(n, 2, f"({h} (function ...) VALUE)")
            target = n[1] if isinstance(n[1], Expr) else Expr([n[1]], n[1].line)
            value = self.numeric(n[2], scope)
            if self.cost_effect(target, value, scope):
                return None
            self.note(F.NUMERIC, n)
            return Expr([n[0], self.function_term(target, scope), value], n.line)
        if h == "at" and len(n) == 3 and n[1] in ("start", "end"):
            inner = self.effect(n[2], scope)
            return None if inner is None else Expr([n[0], n[1], inner], n.line)
        if h in CONNECTIVES or h in ("exists", "imply", "or"):
            raise self.error(f"({h} ...) is not an effect", n)
        return self.atom(n, scope, effect=True)

    def _forall_effect(self, n: Expr, scope: Scope) -> Node | None:
        self._arity(n, 2, "(forall (?x - type ...) EFFECT)")
        if not isinstance(n[1], Expr):
            raise self.error("expected a list of variables after forall", n[1])
        typed = self._typed_vars(n[1], "forall")
        if not typed:  # no variables: the effect itself
            return self.effect(n[2], scope)
        self.note(F.FORALL_EFFECT, n)
        params, inner, guards = self.params(typed, scope, "(forall ...)")
        body = self.effect(n[2], inner)
        if body is None:
            return None
        if guards:
            body = guarded(expr(["and", *guards], n) if len(guards) > 1 else guards[0], body)
        return Expr([n[0], params, body], n.line)

    # --- problem parts -------------------------------------------------------------------

    def fact(self, n: Node) -> Node | None:
        """One element of :init: an atom, ``(not atom)``, ``(= (f ...) v)``, ``(at N fact)``."""
        if not isinstance(n, Expr) or not n:
            raise self.error(f"expected a fact such as (predicate object ...) in :init, found {show(n)}", n)
        if n.head == "at" and len(n) == 3 and isinstance(n[1], Sym) and is_number(n[1]):
            self.number(n[1])
            self.note(F.TIMED_LITERALS, n)
            inner = self.fact(n[2])
            return None if inner is None else Expr([n[0], n[1], inner], n.line)
        if n.head == "not":
            self._arity(n, 1, "(not (predicate ...))")
            return Expr([n[0], self._init_atom(n[1])], n.line)
        if n.head == "=" and len(n) == 3 and (isinstance(n[1], Expr) or n[1] in self.s.functions):
            target = n[1] if isinstance(n[1], Expr) else Expr([n[1]], n[1].line)
            if self.cost_fact(Expr([n[0], target, n[2]], n.line)):
                return None
            value = n[2]
            if isinstance(value, Expr) or not is_number(value):
                raise self.error(f"expected a number as the value of {show(target)}, found {show(value)}", value)
            return Expr([n[0], self.function_term(target, Scope()), self.number(value)], n.line)
        return self._init_atom(n)

    def _init_atom(self, n: Node) -> Node:
        if not isinstance(n, Expr) or not n:
            raise self.error(f"expected a fact such as (predicate object ...), found {show(n)}", n)
        if isinstance(n[0], Sym) and n[0] in self.s.derived:
            raise self.error(f"derived predicate {n[0].written} given in :init (a derived predicate "
                             "holds by its :derived rules only)", n)
        return self.atom(n, Scope(), effect=False)

    def constraint(self, n: Node, scope: Scope) -> Node:
        """A PDDL 3 trajectory constraint of the kinds unified-planning reads."""
        if not isinstance(n, Expr) or not n:
            raise self.error(f"expected a constraint such as (always CONDITION), found {show(n)}", n)
        self.note(F.CONSTRAINTS, n)
        if n.head == "and":
            return Expr([n[0], *(self.constraint(c, scope) for c in n[1:])], n.line)
        if n.head == "forall":
            self._arity(n, 2, "(forall (?x - type ...) CONSTRAINT)")
            if not isinstance(n[1], Expr):
                raise self.error("expected a list of variables after forall", n[1])
            typed = self._typed_vars(n[1], "forall")
            if not typed:
                return self.constraint(n[2], scope)
            params, inner, guards = self.params(typed, scope, "(forall ...)")
            if guards:
                raise self.error("(either ...) types in a forall of :constraints are not supported", n)
            return Expr([n[0], params, self.constraint(n[2], inner)], n.line)
        if n.head in TRAJECTORY:
            return Expr([n[0], *(self.condition(c, scope) for c in n[1:])], n.line)
        raise self.error(f"constraint {show(n[0])} is not supported (supported: {', '.join(TRAJECTORY)})", n)


def guarded(guard: Node, effect: Node) -> Node:
    """``effect`` happening only where ``guard`` holds (one ``when``, never nested)."""
    if isinstance(effect, Expr) and effect.head == "and":
        return Expr([effect[0], *(guarded(guard, e) for e in effect[1:])], effect.line)
    if isinstance(effect, Expr) and effect.head == "when":
        return Expr([effect[0], expr(["and", guard, effect[1]], effect), effect[2]], effect.line)
    if isinstance(effect, Expr) and effect.head == "forall":
        return Expr([effect[0], effect[1], guarded(guard, effect[2])], effect.line)
    return expr(["when", guard, effect], effect)


_NUMBER = re.compile(r"[-+]?(?:\d+(?:\.\d*)?|\.\d+)(?:e[-+]?\d+)?\Z")
#: Characters a number may have (unified-planning reads numbers exactly, as fractions).
MAX_DIGITS = 100


def is_number(a: Sym) -> bool:
    """A decimal number (with an exponent, which unified-planning's reader also takes)."""
    return bool(_NUMBER.match(a))
