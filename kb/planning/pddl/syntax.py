"""A PDDL domain and problem read into their sections, each part with its line.

Only the structure is read here (which section holds what, typed lists, the keyword
arguments of an action); the meaning of conditions and effects is :mod:`.rewrite`'s. A
section kitkb cannot plan with is refused at its line, naming it (:data:`REFUSED`).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

from kb.core.errors import InputError
from kb.planning.pddl.sexp import Expr, Node, Sym, show

#: Every requirement flag of PDDL 1.2 to 3.1 (and the IPC's :action-costs).
REQUIREMENTS = frozenset("""
:strips :typing :negative-preconditions :disjunctive-preconditions :equality
:existential-preconditions :universal-preconditions :quantified-preconditions
:conditional-effects :fluents :numeric-fluents :object-fluents :adl :durative-actions
:duration-inequalities :continuous-effects :derived-predicates :timed-initial-literals
:timed-initial-effects :preferences :constraints :action-costs :domain-axioms
:safety-constraints :expression-evaluation :open-world :true-negation :ucpop :time
:contingent :hierarchy :method-preconditions
""".split())
#: Requirement flags that make another kind of problem, refused where they are declared.
REFUSED_REQUIREMENTS = {
    ":contingent": "contingent planning (:contingent): no installed planner plans contingent problems",
    ":hierarchy": "HTN planning (:hierarchy, HDDL): no installed planner plans hierarchical problems",
    ":method-preconditions": "HTN planning (:method-preconditions, HDDL): no installed planner plans "
                             "hierarchical problems",
}
#: The requirement flags unified-planning's reader takes (others are left out of its input;
#: a requirement declares, it does not change what the reader makes of the domain).
UP_REQUIREMENTS = frozenset("""
:strips :typing :negative-preconditions :disjunctive-preconditions :equality
:existential-preconditions :universal-preconditions :quantified-preconditions
:conditional-effects :fluents :numeric-fluents :adl :durative-actions :duration-inequalities
:timed-initial-literals :timed-initial-effects :action-costs :constraints :preferences :time
:continuous-effects
""".split())  # also its :hierarchy and :contingent, which kitkb refuses
#: Sections kitkb refuses, and why (the feature named in the one-line error).
REFUSED = {
    ":task": "HTN tasks (HDDL): no installed planner plans hierarchical problems",
    ":method": "HTN methods (HDDL): no installed planner plans hierarchical problems",
    ":htn": "an HTN task network (HDDL): no installed planner plans hierarchical problems",
    ":axiom": "PDDL 1.2 axioms (:axiom): write them as :derived predicates",
    ":timeless": "PDDL 1.2 :timeless facts: put them in the problem's :init",
    ":domain-variables": "PDDL 1.2 :domain-variables",
    ":extends": "PDDL 1.2 domain extension (:extends)",
    ":situation": "PDDL 1.2 situations (:situation)",
    ":safety": "PDDL 1.2 safety constraints (:safety)",
}


@dataclass
class Typed:
    """One name of a typed list and its type: a symbol, ``(either t ...)``, or None (object)."""

    name: Sym
    type: Node | None

    @property
    def type_names(self) -> tuple[Sym, ...]:
        """The type's alternatives (one, or those of ``either``; ``object`` when untyped)."""
        if self.type is None:
            return (Sym("object", self.name.line),)
        if isinstance(self.type, Sym):
            return (self.type,)
        return tuple(self.type[1:])  # type: ignore[arg-type]


@dataclass
class Signature:
    """A predicate, function or derived predicate head: name, parameters, value type."""

    name: Sym
    params: list[Typed]
    line: int
    value: Node | None = None  # a function's type (number, object, ...)


@dataclass
class Operator:
    """An action (``:action``, ``:durative-action``), process or event, its parts by keyword."""

    kind: str
    name: Sym
    params: list[Typed]
    parts: dict[str, Node]
    line: int


@dataclass
class Derived:
    """One ``(:derived (p ?x ...) condition)`` rule."""

    head: Signature
    body: Node
    line: int


@dataclass
class Domain:
    """A domain file's sections."""

    path: Path
    name: Sym
    requirements: list[Sym] = field(default_factory=list)
    requirements_line: int = 0
    types: list[Typed] = field(default_factory=list)
    constants: list[Typed] = field(default_factory=list)
    predicates: list[Signature] = field(default_factory=list)
    functions: list[Signature] = field(default_factory=list)
    operators: list[Operator] = field(default_factory=list)
    derived: list[Derived] = field(default_factory=list)
    sections: dict[str, int] = field(default_factory=dict)  # first line of each section


@dataclass
class Problem:
    """A problem file's sections."""

    path: Path
    name: Sym
    domain: Sym | None = None
    requirements: list[Sym] = field(default_factory=list)
    objects: list[Typed] = field(default_factory=list)
    init: list[Node] = field(default_factory=list)
    goal: Node | None = None
    constraints: list[Node] = field(default_factory=list)
    metric: tuple[Sym, Node] | None = None
    metric_line: int = 0
    sections: dict[str, int] = field(default_factory=dict)


class Reader:
    """Reads sections of one file; errors name the file and line."""

    def __init__(self, path: Path, warn: Callable[[str], None]) -> None:
        self.path = path
        self.warn = warn

    def error(self, message: str, where: Node | int | None) -> InputError:
        """An InputError at ``where`` (a node, a line, or None)."""
        line = where if isinstance(where, int) or where is None else where.line
        return InputError(message, self.path, line or None)

    def header(self, top: Expr, kind: str) -> tuple[Sym, list[Node]]:
        """``(define (KIND NAME) rest...)`` -> (NAME, rest)."""
        if top.head != "define":
            raise self.error(f"expected '(define ({kind} NAME) ...)', found {show(top)}", top)
        if len(top) < 2 or not isinstance(top[1], Expr) or len(top[1]) != 2 or top[1].head != kind \
                or not isinstance(top[1][1], Sym):
            other = "problem" if kind == "domain" else "domain"
            if len(top) > 1 and isinstance(top[1], Expr) and top[1].head == other:
                raise self.error(f"this is a {other} file, where a {kind} file was expected "
                                 "(kitkb plan DOMAIN PROBLEM)", top[1])
            raise self.error(f"expected '({kind} NAME)' after 'define'", top[1] if len(top) > 1 else top)
        return top[1][1], top[2:]

    def sections(self, rest: list[Node]) -> list[tuple[Sym, Expr]]:
        """Each ``(:keyword ...)`` of a file body; anything else is an error at its line."""
        out = []
        for node in rest:
            if not isinstance(node, Expr) or not node.head.startswith(":"):
                raise self.error(f"expected a section such as '(:init ...)', found {show(node)}", node)
            if node.head in REFUSED:
                raise self.error(f"{node.head}: not supported: {REFUSED[node.head]}", node)
            out.append((node[0], node))
        return out

    def typed_list(self, items: list[Node], what: str) -> list[Typed]:
        """``a b - t c - (either u v) d`` -> Typed entries (``d`` untyped)."""
        items = split_dashes(items)
        out: list[Typed] = []
        pending: list[Sym] = []
        i = 0
        while i < len(items):
            item = items[i]
            if isinstance(item, Expr):
                raise self.error(f"expected a name in {what}, found {show(item)}", item)
            if item == "-":
                if i + 1 >= len(items):
                    raise self.error(f"'-' without a type at the end of {what}", item)
                kind = items[i + 1]
                if isinstance(kind, Expr) and (kind.head != "either" or len(kind) < 2
                                               or not all(isinstance(k, Sym) for k in kind[1:])):
                    raise self.error(f"expected a type or '(either TYPE ...)' after '-' in {what}, "
                                     f"found {show(kind)}", kind)
                if not pending:
                    raise self.error(f"'-' with no names before it in {what}", item)
                out.extend(Typed(name, kind) for name in pending)
                pending = []
                i += 2
                continue
            pending.append(item)
            i += 1
        out.extend(Typed(name, None) for name in pending)
        return out

    def keywords(self, node: Expr, start: int, allowed: tuple[str, ...], what: str) -> dict[str, Node]:
        """``:key value`` pairs of ``node`` from ``start`` on; each key once and known."""
        parts: dict[str, Node] = {}
        i = start
        while i < len(node):
            key = node[i]
            if not isinstance(key, Sym) or not key.startswith(":"):
                raise self.error(f"expected a keyword such as {allowed[0]} in {what}, found {show(key)}", key)
            if key not in allowed:
                raise self.error(f"{key.written} is not a part of {what} (expected one of "
                                 f"{', '.join(allowed)})", key)
            if key in parts:
                raise self.error(f"{key.written} given twice in {what}", key)
            if i + 1 >= len(node):
                raise self.error(f"{key.written} without a value in {what}", key)
            parts[key] = node[i + 1]
            i += 2
        return parts

    def requirements(self, node: Expr) -> list[Sym]:
        """The flags of ``(:requirements ...)``; an unknown flag is an error at its line."""
        flags = []
        for flag in node[1:]:
            if not isinstance(flag, Sym) or flag not in REQUIREMENTS:
                raise self.error(f"unknown requirement {show(flag)}", flag)
            if flag in REFUSED_REQUIREMENTS:
                raise self.error(f"{flag}: not supported: {REFUSED_REQUIREMENTS[flag]}", flag)
            flags.append(flag)
        return flags

    def once(self, seen: dict[str, int], key: Sym, node: Expr, repeatable: tuple[str, ...] = ()) -> None:
        """Note ``key``'s first line; a section given twice is an error."""
        if key in seen and key not in repeatable:
            raise self.error(f"section {key.written} given twice (first at line {seen[key]})", node)
        seen.setdefault(key, node.line)


DOMAIN_OPERATORS = {
    ":action": (":parameters", ":precondition", ":effect"),
    ":durative-action": (":parameters", ":duration", ":condition", ":effect"),
    ":process": (":parameters", ":precondition", ":effect"),
    ":event": (":parameters", ":precondition", ":effect"),
}


def read_domain(top: Expr, path: Path, warn: Callable[[str], None]) -> Domain:
    """The sections of a domain file's tree."""
    r = Reader(path, warn)
    name, rest = r.header(top, "domain")
    d = Domain(path, name)
    for key, node in r.sections(rest):
        r.once(d.sections, key, node, repeatable=(*DOMAIN_OPERATORS, ":derived"))
        if key == ":requirements":
            d.requirements, d.requirements_line = r.requirements(node), node.line
        elif key == ":types":
            d.types = r.typed_list(node[1:], "(:types ...)")
        elif key == ":constants":
            d.constants = r.typed_list(node[1:], "(:constants ...)")
        elif key == ":predicates":
            d.predicates = [_signature(r, p, "predicate") for p in node[1:]]
        elif key == ":functions":
            d.functions = _functions(r, node)
        elif key in DOMAIN_OPERATORS:
            d.operators.append(_operator(r, key, node))
        elif key == ":derived":
            d.derived.append(_derived(r, node))
        elif key == ":constraints":
            raise r.error("domain :constraints (PDDL 3): not supported: unified-planning reads "
                          "trajectory constraints only in a problem", node)
        else:
            raise r.error(f"unknown domain section {key.written}", node)
    return d


def read_problem(top: Expr, path: Path, warn: Callable[[str], None]) -> Problem:
    """The sections of a problem file's tree."""
    r = Reader(path, warn)
    name, rest = r.header(top, "problem")
    p = Problem(path, name)
    for key, node in r.sections(rest):
        r.once(p.sections, key, node)
        if key == ":domain":
            if len(node) != 2 or not isinstance(node[1], Sym):
                raise r.error("expected '(:domain NAME)'", node)
            p.domain = node[1]
        elif key == ":requirements":
            p.requirements = r.requirements(node)
        elif key == ":objects":
            p.objects = r.typed_list(node[1:], "(:objects ...)")
        elif key == ":init":
            p.init = list(node[1:])
        elif key == ":goal":
            if len(node) != 2:
                raise r.error("expected one condition in (:goal ...)", node)
            p.goal = node[1]
        elif key == ":constraints":
            p.constraints = list(node[1:])
        elif key == ":metric":
            if len(node) != 3 or node[1] not in ("minimize", "maximize"):
                raise r.error("expected '(:metric minimize|maximize EXPRESSION)'", node)
            p.metric, p.metric_line = (node[1], node[2]), node.line  # type: ignore[assignment]
        elif key == ":length":
            warn(f"{path}:{node.line}: warning: (:length ...) (PDDL 1.2) ignored")
        else:
            raise r.error(f"unknown problem section {key.written}", node)
    if p.goal is None:
        raise r.error("the problem has no (:goal ...)", top)
    return p


def _signature(r: Reader, node: Node, what: str) -> Signature:
    if not isinstance(node, Expr) or not node or not isinstance(node[0], Sym):
        raise r.error(f"expected a {what} such as '(name ?x - type)', found {show(node)}", node)
    params = r.typed_list(node[1:], f"the {what} {node[0].written}")
    for p in params:
        if not p.name.startswith("?"):
            raise r.error(f"expected a variable (?name) in the {what} {node[0].written}, found "
                          f"{p.name.written}", p.name)
    return Signature(node[0], params, node.line)


def split_dashes(items: list[Node]) -> list[Node]:
    """``?t -person`` read as ``?t - person`` (no name starts with '-'; unified-planning's
    reader takes the glued form, so files written for it have it)."""
    out: list[Node] = []
    for item in items:
        if isinstance(item, Sym) and len(item) > 1 and item.startswith("-"):
            out += [Sym("-", item.line), Sym(item.written[1:], item.line)]
        else:
            out.append(item)
    return out


def _functions(r: Reader, node: Expr) -> list[Signature]:
    """``(f ?x) (g) - number (h) - object``: a type after '-' applies to every function before it."""
    out: list[Signature] = []
    pending: list[Signature] = []
    items = split_dashes(node[1:])
    i = 0
    while i < len(items):
        if items[i] == "-":
            if i + 1 >= len(items) or not pending:
                raise r.error("'-' without a type, or with no function before it, in (:functions ...)",
                              items[i])
            for sig in pending:
                sig.value = items[i + 1]
            pending = []
            i += 2
            continue
        sig = _signature(r, items[i], "function")
        out.append(sig)
        pending.append(sig)
        i += 1
    return out


def _operator(r: Reader, key: Sym, node: Expr) -> Operator:
    what = f"({key.written} ...)"
    if len(node) < 2 or not isinstance(node[1], Sym):
        raise r.error(f"expected a name after {key.written}", node)
    what = f"{key.written[1:]} {node[1].written}"
    parts = r.keywords(node, 2, DOMAIN_OPERATORS[key], what)
    params_node = parts.pop(":parameters", Expr(line=node.line))
    if not isinstance(params_node, Expr):
        raise r.error(f"expected a list after :parameters in {what}", params_node)
    params = r.typed_list(list(params_node), f"the parameters of {what}")
    for p in params:
        if not p.name.startswith("?"):
            raise r.error(f"expected a variable (?name) in the parameters of {what}, found "
                          f"{p.name.written}", p.name)
    return Operator(key, node[1], params, parts, node.line)


def _derived(r: Reader, node: Expr) -> Derived:
    if len(node) != 3:
        raise r.error("expected '(:derived (PREDICATE ?x ...) CONDITION)'", node)
    head = _signature(r, node[1], "derived predicate")
    return Derived(head, node[2], node.line)
