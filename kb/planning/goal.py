"""The goal of a planning problem: every fact of the goal state the domain can bring about.

The goal state's atoms are what holds there by the predicates' own definitions (the evaluation
``kitkb predicates`` makes, :class:`kb.spatial.predicates.Evaluator`, on the goal file's scene).
Which of them become goals is decided by one general rule, never by a predicate's name
(docs/pddl.md, "The goal"):

* **counted objects are not named.** A goal count ``f(args) = design(args)`` (``quantity-kit =
  capacity-kit``) fixes how many objects of a kind the goal wants, not which: every object the
  count could count — of the class its ``soap:CountExpression`` counts, satisfying the count
  condition's non-spatial atoms (model and SKU atoms) for the count's arguments, i.e. a part of
  a SKU the kit's design asks for — is interchangeable, and no goal atom names it or holds
  because of it (a quantified atom one of whose witnesses it is: ``partstray-not-empty``); the
  parts a plan picks may be others than those the goal file shows in the kit, and those left
  in the trays then differ too;
* **static atoms are not goals.** An atom of a predicate no action changes (in no action's add
  or delete effects: ``part-sku``, ``endeffector-type-part``) holds in the goal if and only if it
  holds initially; one that does not hold initially can never be brought about (below);
* **every other atom that holds in the goal state is a goal** (effectors in their holders, the
  robot with no effector, each kit in its box, an empty work table), true initially or not.

A goal atom no action can bring about — its predicate in no action's add effects, or not
reached by the delete-free relaxation of the domain from the initial state, and false
initially — is an :class:`~kb.core.errors.InputError` at the line of the goal file that makes it
hold, before anything is planned. :func:`unmet` lists the goal atoms and counts that do not hold
in a scene (what "goal holds" checks at the end of a run).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Iterable

import numpy as np
from rdflib import URIRef

from kb.core.errors import InputError
from kb.core.namespaces import KTW
from kb.model.definitions import REFERENCE, TARGET, And, Count, CountOf, Definitions, Exists, Model, Not, Sku
from kb.model.soap import DomainSpec
from kb.planning.state import pddl_name
from kb.spatial.predicates import Axis, Evaluator
from kb.spatial.scene import Scene

Atom = tuple[str, ...]

#: the most unreachable goal atoms one message names
SHOWN = 3


@dataclass
class GoalFacts:
    """What :func:`goal_facts` decided: ``atoms``, the goals (sorted); ``counted``, the objects
    left to the goal counts (PDDL names); ``static``, the goal state's atoms of predicates no
    action changes (implied by the initial state when they hold there)."""

    atoms: list[Atom]
    counted: set[str]
    static: list[Atom]


def goal_scene(goal: Any) -> Scene:
    """The scene of a goal state read as a :class:`kb.planning.state.World`: from the files it
    was loaded from (``kb.planning.problem.world_of`` keeps them), else its path."""
    sources = getattr(goal, "sources", None)
    return Scene.from_sources(sources) if sources else Scene.from_files([goal.path])


def state_atoms(defs: Definitions, scene: Scene) -> set[Atom]:
    """Every atom true in ``scene`` by the definitions, with PDDL object names."""
    return {(n, *map(pddl_name, a)) for n, a in Evaluator(defs, scene).facts()}


def changed_predicates(domain: DomainSpec) -> set[str]:
    """The predicates some action adds or deletes (the others are static)."""
    return {e.predicate for a in domain.actions for e in a.effects}


def added_predicates(domain: DomainSpec) -> set[str]:
    """The predicates some action makes true."""
    return {e.predicate for a in domain.actions for e in a.effects if not e.negated}


def counted_objects(defs: Definitions, scene: Scene, counts: Iterable[Atom]) -> set[str]:
    """The objects (PDDL names) the goal counts ``counts`` (function terms: ``(f, *args)``) could
    count: for each term whose function is a ``soap:CountExpression``, the objects of the class it
    counts that satisfy the count condition's non-spatial conjuncts with the term's arguments
    bound (every object of the class when the condition has none)."""
    ev = Evaluator(defs, scene)
    by_name = {pddl_name(n): i for i, n in enumerate(scene.names)}
    out: set[str] = set()
    for term in counts:
        fn = defs.functions.get(term[0])
        if fn is None or not isinstance(fn.definition, CountOf):
            continue
        var = fn.definition.variable
        cand = ev.candidates(var.cls)
        if not len(cand):
            continue
        keys = [k for k, t in ((REFERENCE, fn.reference_type), (TARGET, fn.target_type)) if t is not None]
        if any(a not in by_name for a in term[1:]) or len(keys) != len(term) - 1:
            continue
        axes = [Axis(k, np.array([by_name[a]], np.int64)) for k, a in zip(keys, term[1:])] + [Axis(var, cand)]
        ok = np.ones(len(cand), bool)
        for atom in _fixed_conjuncts(fn.definition.condition, {*keys, var}):
            ok &= np.broadcast_to(np.asarray(ev.eval(atom, axes)), (1,) * len(keys) + (len(cand),)).reshape(-1)
        out.update(pddl_name(scene.names[i]) for i in cand[ok])
    return out


def _fixed_conjuncts(condition: Any, terms: set) -> list[Any]:
    """The conjuncts of ``condition`` that no action changes: its model and SKU atoms over
    ``terms`` only (the spatial atoms are what a plan changes)."""
    parts = condition.operands if isinstance(condition, And) else (condition,)
    return [p for p in parts if isinstance(p, (Model, Sku)) and {p.subject, p.object} <= terms]


def decide(domain: DomainSpec, defs: Definitions, scene: Scene, counts: Iterable[Atom],
           objects: Iterable[str]) -> GoalFacts:
    """The goal facts of the goal state ``scene``: its atoms by ``defs``, less those about the
    objects the goal counts ``counts`` could count (naming one, or holding because of one),
    chosen by :func:`goal_facts` among the problem's ``objects``."""
    counted = counted_objects(defs, scene, counts)
    atoms = state_atoms(defs, scene)
    return goal_facts(domain, atoms - held_by(defs, scene, atoms, counted), counted, objects)


def held_by(defs: Definitions, scene: Scene, atoms: Iterable[Atom], counted: set[str]) -> set[Atom]:
    """The ``atoms`` that hold because of ``counted`` objects: those of a quantified definition
    (``∃x``, ``¬∃x``, a count of ``x``: :meth:`kb.spatial.predicates.Evaluator.witnesses`) one of
    whose witnesses is counted (``partstray-not-empty(tray)``: the parts in the tray, which
    the goal counts, not names)."""
    if not counted:
        return set()
    ev = Evaluator(defs, scene)
    iri = {pddl_name(n): n for n in scene.names}
    quantified = {name for name, p in defs.predicates.items()
                  if isinstance(p.formula.operand if isinstance(p.formula, Not) else p.formula, (Exists, Count))}
    out = set()
    for atom in atoms:
        if atom[0] in quantified and all(a in iri for a in atom[1:]):
            if counted.intersection(map(pddl_name, ev.witnesses(atom[0], *(iri[a] for a in atom[1:])))):
                out.add(atom)
    return out


def goal_facts(domain: DomainSpec, reached: Iterable[Atom], counted: set[str], objects: Iterable[str]) -> GoalFacts:
    """The goals among the goal state's atoms ``reached``: not naming a ``counted`` object, of a
    predicate some action changes, over ``objects`` (the problem's) only."""
    changed = changed_predicates(domain)
    known = set(objects)
    goals, static = [], []
    for atom in sorted(set(reached)):
        if atom[0] not in domain.predicates or not known.issuperset(atom[1:]) or counted.intersection(atom[1:]):
            continue
        (goals if atom[0] in changed else static).append(atom)
    return GoalFacts(goals, counted, static)


def unreachable(domain: DomainSpec, objects: dict[str, tuple[str, Any]], initial: set[Atom],
                goals: Iterable[Atom]) -> list[tuple[Atom, str]]:
    """The ``goals`` no action can bring about from ``initial``, each with the reason: its
    predicate is in no action's add effects, or the delete-free relaxation of the domain
    (negative and numeric conditions dropped) never reaches it."""
    wanted = [g for g in goals if g not in initial]
    if not wanted:
        return []
    adds = added_predicates(domain)
    out = [(g, f"no action makes {g[0]} true") for g in wanted if g[0] not in adds]
    rest = [g for g in wanted if g[0] in adds]
    if rest:
        reached = relaxed_closure(domain, objects, initial, rest)
        out += [(g, "no sequence of actions reaches it from the initial state (even with every delete "
                    "effect, negative and numeric condition ignored)") for g in rest if g not in reached]
    return sorted(out)


def relaxed_closure(domain: DomainSpec, objects: dict[str, tuple[str, Any]], initial: set[Atom],
                    stop_at: Iterable[Atom] = ()) -> set[Atom]:
    """The atoms the delete-free relaxation of ``domain`` reaches from ``initial``: each action's
    positive preconditions joined on the atoms reached so far, its add effects added, round by
    round until nothing is new or every atom of ``stop_at`` is reached. Semi-naive: a round
    joins only the bindings that use an atom new in the round before."""
    typed = _typed(domain, objects)
    reached: set[Atom] = set()
    delta = set(initial)
    targets = set(stop_at)
    first = True
    while delta:
        old, reached = _Index(reached), reached | delta
        if targets and targets <= reached:
            break
        every, fresh = _Index(reached), _Index(delta)
        new: set[Atom] = set()
        for action in domain.actions:
            adds = [e for e in action.effects if not e.negated]
            pres = [p for p in action.pre if not p.negated and p.predicate in domain.predicates]
            if not pres and not first:
                continue
            for j in range(len(pres)) if pres else [None]:
                sources = [old if k < j else fresh if k == j else every for k in range(len(pres))] if j is not None else []
                for binding in _bindings(action, pres, sources, typed):
                    for e in adds:
                        atom = (e.predicate, *(binding[a] for a in e.args))
                        if atom not in reached:
                            new.add(atom)
        delta, first = new, False
    return reached


class _Index:
    """Atoms by predicate, and by the values at some of their argument positions (made on
    first use of each position set)."""

    def __init__(self, atoms: Iterable[Atom]) -> None:
        self.by_pred: dict[str, list[Atom]] = {}
        for atom in atoms:
            self.by_pred.setdefault(atom[0], []).append(atom)
        self.maps: dict[tuple[str, tuple[int, ...]], dict[tuple[str, ...], list[Atom]]] = {}

    def count(self, pred: str) -> int:
        return len(self.by_pred.get(pred, ()))

    def get(self, pred: str, positions: tuple[int, ...], key: tuple[str, ...]) -> list[Atom]:
        if not positions:
            return self.by_pred.get(pred, [])
        m = self.maps.get((pred, positions))
        if m is None:
            m = self.maps[(pred, positions)] = {}
            for atom in self.by_pred.get(pred, ()):
                m.setdefault(tuple(atom[i + 1] for i in positions), []).append(atom)
        return m.get(key, [])


def _typed(domain: DomainSpec, objects: dict[str, tuple[str, Any]]) -> dict[str, set[str]]:
    """Type IRI -> the objects of it or of a subtype."""
    out: dict[str, set[str]] = {}
    for name, (cls, _iri) in objects.items():
        seen: set[str] = set()
        c: str | None = cls
        while c is not None and c not in seen:
            seen.add(c)
            out.setdefault(c, set()).add(name)
            c = domain.types.get(c)
    return out


def _bindings(action: Any, pres: list[Any], sources: list["_Index"], typed: dict[str, set[str]]) -> list[dict[str, str]]:
    """The parameter bindings under which ``action``'s positive preconditions ``pres`` all hold,
    each in the atoms of its index in ``sources`` (joined smallest first, then most bound);
    parameters no precondition binds range over their type's objects (only those an add
    effect uses)."""
    types = dict(action.params)
    todo = list(range(len(pres)))
    bindings: list[dict[str, str]] = [{}]
    bound: set[str] = set()
    while todo:
        k = max(todo, key=lambda k: (sum(a in bound for a in pres[k].args), -sources[k].count(pres[k].predicate)))
        todo.remove(k)
        pre = pres[k]
        positions = tuple(i for i, a in enumerate(pre.args) if a in bound)
        free = [(i, a) for i, a in enumerate(pre.args) if a not in bound]
        nxt = []
        for b in bindings:
            for fact in sources[k].get(pre.predicate, positions, tuple(b[pre.args[i]] for i in positions)):
                new = dict(b)
                if all(_bind(new, a, fact[i + 1], types, typed) for i, a in free):
                    nxt.append(new)
        bindings = nxt
        if not bindings:
            return []
        bound.update(pre.args)
    used = {a for e in action.effects if not e.negated for a in e.args}
    for p in sorted(used - bound):
        pool = sorted(typed.get(types.get(p, ""), ()))
        bindings = [dict(b, **{p: o}) for b in bindings for o in pool]
    return bindings


def _bind(binding: dict[str, str], param: str, value: str, types: dict[str, str], typed: dict[str, set[str]]) -> bool:
    """Bind ``param`` to ``value`` in ``binding`` if consistent with it and the parameter's type."""
    if param in binding:
        return binding[param] == value
    if param in types and value not in typed.get(types[param], ()):
        return False
    binding[param] = value
    return True


def atom_text(atom: Atom) -> str:
    """``pred(a, b)``, as ``kitkb predicates`` prints an atom."""
    return f"{atom[0]}({', '.join(atom[1:])})"


def where_it_holds(atom: Atom, scene: Scene, line_of: Any) -> int | None:
    """The line of the goal file that makes ``atom`` hold: where its first argument placed in the
    file is given its primary location (else where the argument is first stated)."""
    names = {pddl_name(n): n for n in scene.names}
    for arg in atom[1:]:
        iri = names.get(arg)
        if iri is None:
            continue
        node = URIRef(iri)
        line = line_of(node, KTW.hasSolidObject_PrimaryLocation) or line_of(node)
        if line:
            return line
    return None


def check_reachable(domain: DomainSpec, objects: dict[str, tuple[str, Any]], initial: set[Atom],
                    goals: GoalFacts, scene: Scene, path: str, line_of: Any) -> None:
    """Raise an InputError at the goal file's line when a goal atom (or a static atom of the
    goal state that is false initially) cannot be brought about."""
    bad = [(a, f"no action changes {a[0]}, and it does not hold initially") for a in goals.static if a not in initial]
    bad += unreachable(domain, objects, initial, goals.atoms)
    if not bad:
        return
    bad.sort(key=lambda b: (where_it_holds(b[0], scene, line_of) or 0, b[0]))
    atom, why = bad[0]
    more = ""
    if len(bad) > 1:
        shown = ", ".join(atom_text(a) for a, _ in bad[1:SHOWN + 1])
        more = f"; also {shown}" + (f" and {len(bad) - SHOWN - 1} more" if len(bad) > SHOWN + 1 else "")
    raise InputError(f"goal fact {atom_text(atom)} holds in the goal state, but no action can bring it about: "
                     f"{why}{more}", path, where_it_holds(atom, scene, line_of))


def unmet(goal: Iterable[Atom], goal_equal: Iterable[tuple[Atom, Atom]], ev: Evaluator) -> list[str]:
    """The goal atoms (``pred(a, b)``) and goal counts (``f(a, b) = g(a, b) (n, not m)``) that
    do not hold in ``ev``'s scene; empty when the goal holds."""
    goal = list(goal)
    true = {(n, *map(pddl_name, a)) for n, a in ev.facts({g[0] for g in goal})} if goal else set()
    out = [atom_text(g) for g in goal if tuple(g) not in true]
    values: dict[str, dict[Atom, int]] = {}
    for left, right in goal_equal:
        for term in (left, right):
            if term[0] not in values:
                values[term[0]] = {tuple(map(pddl_name, a)): v for a, v in ev.function_values(term[0]).items()}
        have, want = values[left[0]].get(tuple(left[1:]), 0), values[right[0]].get(tuple(right[1:]), 0)
        if have != want:
            out.append(f"{atom_text(left)} = {atom_text(right)} ({have}, not {want})")
    return out


__all__ = ["GoalFacts", "atom_text", "changed_predicates", "check_reachable", "counted_objects", "decide",
           "goal_facts", "goal_scene", "held_by", "relaxed_closure", "state_atoms", "unmet", "unreachable"]
