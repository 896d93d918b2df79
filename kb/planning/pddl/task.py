"""A PDDL domain and problem file -> unified-planning problem, through kitkb's rewriting.

The files are read (:mod:`.sexp`, :mod:`.syntax`), their declarations checked
(:mod:`.symbols`), named as unified-planning can take them (:mod:`.names`), rewritten
(:mod:`.rewrite`, :mod:`.derived`, :mod:`.costs`) and written as the PDDL unified-planning's
reader takes: its section order, its requirement flags, one name space. That text is read
by unified-planning's own reader; an error it still finds is reported at the line of the
original file the text came from (:class:`~.sexp.Rendered`).
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable

from kb.core.errors import InputError
from kb.core.files import note_input
from kb.core.limits import check_file_size, deep_calls
from kb.io.parsing import decode
from kb.patches.unified_planning import environment
from kb.planning.pddl import axioms, sexp
from kb.planning.pddl.costs import Costs
from kb.planning.pddl.derived import Expander
from kb.planning.pddl.features import UNDEFINED as F_UNDEFINED, Features
from kb.planning.pddl.names import Names, safe
from kb.planning.pddl.rewrite import Rewriter, Scope, Var
from kb.planning.pddl.sexp import Expr, Node, Rendered, Sym, expr, sym
from kb.planning.pddl.symbols import OBJECT, build
from kb.planning.pddl.syntax import UP_REQUIREMENTS, Domain, Operator, Problem, Typed, read_domain, read_problem


@dataclass
class PddlTask:
    """A PDDL domain and problem as unified-planning's problem, and how to speak of it."""

    problem: Any
    domain_path: Path
    problem_path: Path
    features: Features
    back: dict[str, str] = field(default_factory=dict)  # renamed object/action -> name in the file
    texts: tuple[str, str] = ("", "")  # the domain and problem text unified-planning read
    #: the same with the rules of recursive derived predicates, for a planner that reads axioms
    #: (Fast Downward); None when there are none
    planner_texts: tuple[str, str] | None = None

    def original(self, name: str) -> str:
        """The name in the file of an object or action named ``name`` in :attr:`problem`."""
        return self.back.get(name, name)

    def explain(self, kind_flags: list[str] | set[str]) -> tuple[str, tuple[Path, int | None]]:
        """The PDDL features behind unified-planning kind flags, and where the first is used
        (the domain file, without a line, if none is found in the files)."""
        features, where = self.features.explain(kind_flags)
        return features, where if where is not None else (self.domain_path, None)


def read_task(domain_path: str | Path, problem_path: str | Path, warn: Callable[[str], None]) -> PddlTask:
    """Read, check and rewrite a domain and problem; the unified-planning problem of them."""
    dpath, ppath = Path(domain_path), Path(problem_path)
    dtext, ptext = _read(dpath), _read(ppath)
    with deep_calls():
        domain = read_domain(sexp.parse(dtext, dpath), dpath, warn)
        problem = read_problem(sexp.parse(ptext, ppath), ppath, warn)
        _check_headers(domain, problem, warn)
        s = build(domain, problem)
        names = Names(s)
        features = Features()
        if ":functions" in domain.sections:  # unified-planning's validator needs every value given
            features.note(F_UNDEFINED, dpath, domain.sections[":functions"])
        rw = Rewriter(s, names, features, _variables(domain, problem))
        costs = Costs(rw)
        expander = Expander(rw)
        expander.check_all()
        rw.path, rw.in_problem = ppath, True
        body = _problem_body(rw, costs, problem)  # first: the cost values it gives guard the actions
        rw.path, rw.in_problem = dpath, False
        guards = costs.plan_guards()
        operators = [op for op in (_operator(rw, costs, op, warn) for op in domain.operators) if op is not None]
        rw.recursive = expander.recursive
        domain_text = _domain_text(rw, costs, domain, operators, guards)
        problem_text = _problem_text(rw, costs, problem, body)
        planner_texts = None
        if expander.recursive:  # Fast Downward plans with the rules; the validator gets their meaning
            planner_texts = (_domain_text(rw, costs, domain, operators, guards, expander.axioms()).text(),
                             problem_text.text())
    up_problem = _up_read(domain_text, problem_text, dpath, ppath)
    costs.install(up_problem, {f: name for f, name, _ in guards})
    axioms.install(up_problem, expander)
    return PddlTask(up_problem, dpath, ppath, features, dict(names.back),
                    (domain_text.text(), problem_text.text()), planner_texts)


def _read(path: Path) -> str:
    note_input(path)
    check_file_size(path)
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise InputError(f"cannot read: {exc.strerror or exc}", path) from None
    return decode(data, path).replace("\r\n", "\n").replace("\r", "\n")


def _check_headers(domain: Domain, problem: Problem, warn: Callable[[str], None]) -> None:
    if problem.domain is not None and problem.domain != domain.name:
        warn(f"{problem.path}:{problem.domain.line}: warning: the problem is for domain "
             f"{problem.domain.written}, the domain file is {domain.name.written}")
    if Sym(":derived-predicates") in domain.requirements and not domain.derived:
        warn(f"{domain.path}:{domain.requirements_line}: warning: requirement :derived-predicates is "
             "declared but never used; ignored")


def _variables(domain: Domain, problem: Problem) -> set[str]:
    """Every variable name (without ``?``) the files use."""
    found: set[str] = set()
    roots: list[Node] = [*[n for op in domain.operators for n in op.parts.values()],
                         *[r.body for r in domain.derived], *([problem.goal] if problem.goal else []),
                         *problem.constraints]
    for typed in ([p for op in domain.operators for p in op.params]
                  + [p for r in domain.derived for p in r.head.params]):
        found.add(typed.name[1:])
    stack = list(roots)
    while stack:
        n = stack.pop()
        if isinstance(n, Sym):
            if n.startswith("?"):
                found.add(n[1:])
        else:
            stack.extend(n)
    return found


# --- operators -------------------------------------------------------------------------------

def _operator(rw: Rewriter, costs: Costs, op: Operator, warn: Callable[[str], None]) -> Expr | None:
    """The operator as unified-planning reads it; None for an action that changes nothing
    (Fast Downward's reader wants an effect, and such an action is never of use in a plan)."""
    what = f"{op.kind[1:]} {op.name.written}"
    params, scope, guards = rw.params(op.params, Scope(), what)
    costs.current = op.name
    kind = op.kind
    parts: list[Node] = [sym(kind, op.line), sym(rw.names.operators[op.name], op.name),
                         sym(":parameters", op.line), params]
    if kind == ":durative-action":
        rw.note("durative actions (:durative-action)", op.line)
        duration_scope = scope.bind({"duration": _duration_var()})
        if ":duration" in op.parts:
            parts += [_key(op, ":duration"), rw.condition(op.parts[":duration"], duration_scope)]
        condition = rw.condition(op.parts[":condition"], duration_scope) if ":condition" in op.parts else None
        condition = _conjoin([expr(["at", "start", g], g) for g in guards], condition)
        if condition is not None:
            parts += [_key(op, ":condition"), condition]
        effect = rw.effect(op.parts[":effect"], duration_scope) if ":effect" in op.parts else None
        parts += [_key(op, ":effect"), effect if effect is not None else expr(["and"], op.line)]
    else:
        rw.note({":process": "processes (:process)", ":event": "events (:event)"}.get(kind, ""), op.line)
        effect = rw.effect(op.parts[":effect"], scope) if ":effect" in op.parts else None
        pre = rw.condition(op.parts[":precondition"], scope) if ":precondition" in op.parts else None
        pre = _conjoin(guards + costs.precondition_guards(op.name), pre)
        if pre is not None:
            parts += [_key(op, ":precondition"), pre]
        if effect is None and kind == ":action":
            warn(f"{rw.s.domain.path}:{op.line}: warning: action {op.name.written} changes nothing; left out")
            costs.current = None
            return None
        if effect is not None:
            parts += [_key(op, ":effect"), effect]
    costs.current = None
    return Expr(parts, op.line)


def _key(op: Operator, key: str) -> Sym:
    """The keyword ``key`` placed at the line of its value in the file."""
    value = op.parts.get(key)
    return sym(key, value.line if value is not None and value.line else op.line)


def _duration_var() -> Var:
    return Var("duration", (OBJECT,))


def _conjoin(guards: list[Node], condition: Node | None) -> Node | None:
    if not guards:
        return condition
    if condition is None or (isinstance(condition, Expr) and not condition):
        return guards[0] if len(guards) == 1 else expr(["and", *guards], guards[0])
    line = condition.line
    return expr(["and", *guards, condition], line)


# --- the problem -----------------------------------------------------------------------------

@dataclass
class _Body:
    init: list[Node]
    goal: Node
    constraints: list[Node]
    metric: tuple[Sym, Node] | None


def _problem_body(rw: Rewriter, costs: Costs, problem: Problem) -> _Body:
    init = [f for f in (rw.fact(n) for n in problem.init) if f is not None]
    assert problem.goal is not None
    goal = rw.condition(problem.goal, Scope())
    constraints = [rw.constraint(c, Scope()) for c in problem.constraints]
    metric = None
    if problem.metric is not None and costs.mode != "metric":
        rw.note("a metric (:metric)", problem.metric_line)
        direction, expression = problem.metric
        metric = (direction, rw.numeric(expression, Scope()))
    return _Body(init, goal, constraints, metric)


# --- the text unified-planning reads -----------------------------------------------------------

def _domain_text(rw: Rewriter, costs: Costs, domain: Domain, operators: list[Expr],
                 guards: list[tuple[str, str, list[Node]]], axioms: list[Expr] | None = None) -> Rendered:
    s, names = rw.s, rw.names
    out: list[Node] = [sym("define", 1), expr(["domain", _label(domain.name)], 1)]
    flags = [f for f in domain.requirements if f in UP_REQUIREMENTS]
    if axioms:
        flags.append(sym(":derived-predicates"))
    if flags:
        out.append(Expr([sym(":requirements", domain.requirements_line), *flags], domain.requirements_line))
    if s.parents:
        items: list[Node] = [sym(":types", domain.sections.get(":types", 0))]
        for name, parent in s.parents.items():  # each with its parent: a typed list
            line = s.type_line[name][1]
            items += [sym(names.types[name], line), sym("-", line), sym(names.types[parent], line)]
        out.append(Expr(items, items[0].line))
    constants = [t for t in domain.constants]
    if constants:
        out.append(Expr([sym(":constants", domain.sections[":constants"]), *_typed_objects(rw, constants)],
                        domain.sections[":constants"]))
    predicates = _predicates(rw, guards)
    if predicates:
        out.append(Expr([sym(":predicates", domain.sections.get(":predicates", 0)), *predicates],
                        domain.sections.get(":predicates", 0)))
    functions = _functions(rw, costs)
    if functions:
        out.append(Expr([sym(":functions", domain.sections[":functions"]), *functions], domain.sections[":functions"]))
    out += axioms or []
    kinds = {":action": 0, ":durative-action": 0, ":process": 1, ":event": 2}
    out += sorted(operators, key=lambda op: kinds[op[0]])
    return Rendered().write([Expr(out, 1)])


def _label(name: str) -> str:
    """A domain's or problem's name as unified-planning's reader takes it."""
    return name if safe(name) else "k-" + re.sub(r"[^a-z0-9_-]", "_", name)


def _typed_objects(rw: Rewriter, typed: list[Typed]) -> list[Node]:
    """Objects with their types, the untyped ones last (a typed list gives a name without a
    type the type of the next name that has one)."""
    out: list[Node] = []
    ordered = sorted(typed, key=lambda t: t.type_names[0] == OBJECT)
    for i, t in enumerate(ordered):
        out.append(sym(rw.names.objects[t.name], t.name))
        kind = str(t.type_names[0])
        following = str(ordered[i + 1].type_names[0]) if i + 1 < len(ordered) else None
        if kind != OBJECT and following != kind:  # names of one type share their '- type'
            out += [sym("-", t.name), sym(rw.names.types[kind], t.name)]
    return out


def _declaration(rw: Rewriter, name: str, params: list[Typed], line: int) -> Expr:
    """``(name ?a - t ...)``: repeated parameter names made distinct, ``either`` as the
    common type (a declaration only says which atoms exist)."""
    items: list[Node] = [sym(name, line)]
    used: set[str] = set()
    kinds = [rw.s.common_type(tuple(str(k) for k in p.type_names)) for p in params]
    for i, (p, kind) in enumerate(zip(params, kinds)):
        var = rw.names.variable(p.name[1:], used)
        used.add(var)
        items.append(sym("?" + var, line))
        if kind != OBJECT or any(k != OBJECT for k in kinds[i + 1:]):
            items += [sym("-", line), sym(rw.names.types[kind], line)]
    return Expr(items, line)


def _predicates(rw: Rewriter, guards: list[tuple[str, str, list[Node]]]) -> list[Node]:
    s = rw.s
    out: list[Node] = [_declaration(rw, rw.names.predicates[name], sig.params, sig.line)
                       for name, sig in s.predicates.items() if name not in s.derived or name in rw.recursive]
    for kinds, (name, common) in rw.memberships.items():
        out.append(expr([name, "?x", *(["-", rw.names.types[common]] if common != OBJECT else [])]))
    for _, name, params in guards:
        out.append(Expr([sym(name), *params]))
    return out


def _functions(rw: Rewriter, costs: Costs) -> list[Node]:
    dropped = costs.declared_functions()
    out: list[Node] = []
    for name, sig in rw.s.functions.items():
        if name in dropped:
            continue
        out += [_declaration(rw, rw.names.functions[name], sig.params, sig.line), sym("-", sig.line),
                sym("number", sig.line)]
    return out


def _problem_text(rw: Rewriter, costs: Costs, problem: Problem, body: _Body) -> Rendered:
    names, s = rw.names, rw.s
    out: list[Node] = [sym("define", 1), expr(["problem", _label(problem.name)], 1),
                       expr([":domain", _label(s.domain.name)], 1)]
    objects = [t for name, t in s.objects.items() if name not in s.constants]
    if objects:
        out.append(Expr([sym(":objects", problem.sections[":objects"]), *_typed_objects(rw, objects)],
                        problem.sections[":objects"]))
    init = list(body.init)
    for kinds, (name, _) in rw.memberships.items():
        init += [expr([name, names.objects[o]]) for o in s.members(tuple(kinds))]
    init += costs.guard_facts() + costs.extra_init()
    out.append(Expr([sym(":init", problem.sections.get(":init", 0)), *init], problem.sections.get(":init", 0)))
    out.append(Expr([sym(":goal", problem.sections[":goal"]), body.goal], problem.sections[":goal"]))
    if body.constraints:
        out.append(Expr([sym(":constraints", problem.sections[":constraints"]), *body.constraints],
                        problem.sections[":constraints"]))
    if body.metric is not None:
        out.append(Expr([sym(":metric", problem.metric_line), *body.metric], problem.metric_line))
    return Rendered().write([Expr(out, 1)])


# --- unified-planning's reader ---------------------------------------------------------------

def _up_read(domain: Rendered, problem: Rendered, dpath: Path, ppath: Path) -> Any:
    environment()
    from unified_planning.io import PDDLReader

    dtext, ptext = domain.text(), problem.text()
    _parse(lambda: PDDLReader().parse_problem_string(dtext, None), dpath, domain)
    return _parse(lambda: PDDLReader().parse_problem_string(dtext, ptext), ppath, problem)


def _parse(call: Callable[[], Any], path: Path, rendered: Rendered) -> Any:
    try:
        return call()
    except KeyError as exc:  # an undeclared type or object
        name = str(exc.args[0]) if exc.args else "?"
        raise InputError(f"unknown type or object {name!r}", path) from None
    except Exception as exc:  # noqa: BLE001 - pyparsing / UP errors, reported as one line
        text = str(exc)
        msg = text.splitlines()[0] if text else type(exc).__name__
        line = getattr(exc, "lineno", None)
        found = re.search(r"line:? (\d+)", text)
        if line is None and found:
            line = int(found.group(1))
        msg = re.sub(r"\s*(?:from line|Line|line):?\s*\d+.*$", "", msg).rstrip(" .,") or type(exc).__name__
        raise InputError(f"not valid PDDL: {msg}", path, rendered.line_of(line) if line else None) from None
