"""What a domain and problem declare: types and their tree, objects, predicates, functions,
derived predicates, actions; each declaration checked once, errors at its line.

Types follow PDDL: ``object`` is every object's type; a type named only as another's
parent is declared by that (unified-planning's reading); ``(either a b)`` is the union of its
types, allowed where a variable is typed, not for an object or in ``(:types ...)``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from kb.core.errors import InputError
from kb.planning.pddl.sexp import Sym
from kb.planning.pddl.syntax import Derived, Domain, Operator, Problem, Signature, Typed

OBJECT = "object"
#: Function value types read as numbers.
NUMERIC = ("number", "int", "integer", "float", "real")


@dataclass
class Symbols:
    """The declarations of one domain and problem, and the type tree."""

    domain: Domain
    problem: Problem
    parents: dict[str, str] = field(default_factory=dict)  # type -> parent ('object' at the top)
    type_line: dict[str, tuple[Path, int]] = field(default_factory=dict)
    objects: dict[str, Typed] = field(default_factory=dict)  # constants and objects
    constants: set[str] = field(default_factory=set)
    object_file: dict[str, Path] = field(default_factory=dict)
    predicates: dict[str, Signature] = field(default_factory=dict)
    functions: dict[str, Signature] = field(default_factory=dict)
    derived: dict[str, list[Derived]] = field(default_factory=dict)
    operators: dict[str, Operator] = field(default_factory=dict)

    # --- types ---------------------------------------------------------------------------

    def ancestors(self, name: str) -> list[str]:
        """``name``, its parent, ... up to ``object``."""
        out = [name]
        while out[-1] != OBJECT:
            out.append(self.parents.get(out[-1], OBJECT))
        return out

    def is_subtype(self, name: str, of: str) -> bool:
        """True if every object of type ``name`` is of type ``of``."""
        return of == OBJECT or of in self.ancestors(name)

    def covered(self, kinds: tuple[str, ...] | frozenset[str], by: tuple[str, ...] | frozenset[str]) -> bool:
        """True if every object of one of ``kinds`` is of one of ``by``."""
        return all(any(self.is_subtype(k, b) for b in by) for k in kinds)

    def common_type(self, kinds: tuple[str, ...] | frozenset[str]) -> str:
        """The most specific type every one of ``kinds`` is a subtype of."""
        first, *rest = kinds
        for candidate in self.ancestors(first):
            if all(self.is_subtype(k, candidate) for k in rest):
                return candidate
        return OBJECT

    def members(self, kinds: tuple[str, ...] | frozenset[str]) -> list[str]:
        """The objects (constants first, in declaration order) of one of ``kinds``."""
        return [name for name, t in self.objects.items() if self.covered(_kinds(t), tuple(kinds))]

    def object_types(self, name: str) -> tuple[str, ...]:
        """The type of an object or constant (as a one-type tuple)."""
        return _kinds(self.objects[name])

    @property
    def typed(self) -> bool:
        """True if the domain declares types."""
        return bool(self.parents)


def _kinds(t: Typed) -> tuple[str, ...]:
    return tuple(str(k) for k in t.type_names)


def build(domain: Domain, problem: Problem) -> Symbols:
    """The symbol tables of ``domain`` and ``problem``; InputError at the line of a name
    declared twice, an unknown type, a type cycle, or an object of an ``either`` type."""
    s = Symbols(domain, problem)
    _types(s, domain)
    for typed, path, constant in ([(t, domain.path, True) for t in domain.constants]
                                  + [(t, problem.path, False) for t in problem.objects]):
        _object(s, typed, path, constant)
    for sig in domain.predicates:
        _declare(s, s.predicates, sig, "predicate", domain.path)
    for sig in domain.functions:
        _function(s, sig, domain.path)
    for rule in domain.derived:
        _derived(s, rule, domain.path)
    for op in domain.operators:
        if op.name in s.operators:
            raise InputError(f"{op.kind[1:]} {op.name.written} is declared twice (first at line "
                             f"{s.operators[op.name].line})", domain.path, op.line)
        _check_params(s, op.params, f"{op.kind[1:]} {op.name.written}", domain.path)
        s.operators[op.name] = op
    return s


def _types(s: Symbols, d: Domain) -> None:
    for t in d.types:
        if isinstance(t.type, list):
            raise InputError(f"type {t.name.written} is declared with (either ...): not supported "
                             "(a type has one parent type; use either where a variable is typed)",
                             d.path, t.name.line)
        parent = str(t.type) if t.type is not None else OBJECT
        if t.name == OBJECT:
            continue
        if t.name in s.parents and s.parents[t.name] != parent:
            raise InputError(f"type {t.name.written} is declared twice, under "
                             f"{s.parents[t.name]} and {parent} (a type has one parent type)",
                             d.path, t.name.line)
        s.parents[t.name] = parent
        s.type_line.setdefault(t.name, (d.path, t.name.line))
    for t in d.types:
        if t.type is not None and t.type != OBJECT and t.type not in s.parents:
            s.parents[str(t.type)] = OBJECT  # named only as a parent: a type under object
            s.type_line.setdefault(str(t.type), (d.path, t.type.line))
    for name in s.parents:
        seen = [name]
        while seen[-1] != OBJECT:
            up = s.parents[seen[-1]] if seen[-1] in s.parents else OBJECT
            if up in seen:
                path, line = s.type_line[name]
                raise InputError(f"type {name} is its own ancestor ({' - '.join(seen + [up])})", path, line)
            seen.append(up)


def known_type(s: Symbols, kind: Sym, path: Path) -> None:
    """InputError unless ``kind`` is a declared type (or ``object``)."""
    if kind != OBJECT and kind not in s.parents:
        hint = "" if s.typed else " (the domain declares no :types)"
        raise InputError(f"unknown type {kind.written}{hint}", path, kind.line)


def _object(s: Symbols, t: Typed, path: Path, constant: bool) -> None:
    if isinstance(t.type, list):
        raise InputError(f"object {t.name.written} is of type (either ...): not supported (an "
                         "object has one type)", path, t.name.line)
    if t.type is not None:
        known_type(s, t.type, path)  # type: ignore[arg-type]
    if t.name in s.objects:
        first = s.objects[t.name]
        where = "" if s.object_file[t.name] == path else f"{s.object_file[t.name]}:"
        raise InputError(f"object {t.name.written} is declared twice (first at {where}line "
                         f"{first.name.line})", path, t.name.line)
    s.objects[t.name] = t
    s.object_file[t.name] = path
    if constant:
        s.constants.add(t.name)


def _check_params(s: Symbols, params: list[Typed], what: str, path: Path) -> None:
    seen: dict[str, Sym] = {}
    for p in params:
        for kind in p.type_names:
            known_type(s, kind, path)
        if p.name in seen:
            raise InputError(f"parameter {p.name.written} is declared twice in {what} (first at "
                             f"line {seen[p.name].line}): which one the body means is ambiguous",
                             path, p.name.line)
        seen[p.name] = p.name


def _declare(s: Symbols, table: dict[str, Signature], sig: Signature, what: str, path: Path) -> None:
    if sig.name in s.predicates or sig.name in s.functions:
        first = s.predicates.get(sig.name) or s.functions[sig.name]
        raise InputError(f"{sig.name.written} is declared twice (first at line {first.line})", path, sig.line)
    for p in sig.params:
        for kind in p.type_names:
            known_type(s, kind, path)
    table[sig.name] = sig


def _function(s: Symbols, sig: Signature, path: Path) -> None:
    value = sig.value
    if value is not None and (not isinstance(value, Sym) or value not in NUMERIC):
        shown = value.written if isinstance(value, Sym) else "(either ...)"
        raise InputError(f"function {sig.name.written} has values of type {shown}: object-valued "
                         "functions (:object-fluents) are not supported", path, sig.line)
    _declare(s, s.functions, sig, "function", path)


def _derived(s: Symbols, rule: Derived, path: Path) -> None:
    head = rule.head
    _check_params(s, head.params, f"the derived predicate {head.name.written}", path)
    if head.name in s.functions:
        raise InputError(f"derived predicate {head.name.written} is declared as a function", path, rule.line)
    declared = s.predicates.get(head.name)
    if declared is None:
        s.predicates[head.name] = Signature(head.name, head.params, rule.line)
    elif len(declared.params) != len(head.params):
        raise InputError(f"derived predicate {head.name.written} has {len(head.params)} parameters; "
                         f"it is declared with {len(declared.params)} (line {declared.line})", path, rule.line)
    s.derived.setdefault(head.name, []).append(rule)
