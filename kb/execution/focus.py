"""Focus of attention: the objects an action's checks depend on, its neighbourhood.

An action's predicates quantify over classes (``robot-empty``: is a solid object in contact
with an end effector in contact with the robot?). Where a definition ties every quantified
variable, by a relation atom in its body's conjunction, to a term already bound — an argument
or an outer variable — and that relation holds only between boxes that touch (within the
tolerance), only the objects touching the bound ones can make the atom true or false. In the
kitting domain every quantifier is tied so (``In-Contact-With``, ``In-Or-Against``,
``On-Top-With-Contact``, ``Partially-In``); whether a relation implies contact is not assumed
but tested once: its compiled expression on the masks of every arrangement of two boxes apart
along some axis (:func:`contact_only`).

An action whose atoms are all tied is *local*: its neighbourhood is its arguments and, atom by
atom, each variable's candidates — objects of its class whose world box touches a candidate of
the term it is tied to (world boxes hold an object however it is turned, so the test is
conservative). The executor senses the neighbourhood by name (:func:`kb.crcl.cell.sense_names`)
where the belief had it, then again where it is seen now, with whatever touched an object that
moved (what it carries: the effector on the robot, the part in the gripper, a moved kit's
tray and parts), until nothing new comes in; and decides the checks on a scene of those
objects only (:meth:`kb.execution.belief.Belief.subscene`), which gives the same truth as the
whole belief: what lies outside cannot satisfy a tied variable. An action with an untied
variable (a ``soap:`` definition added in Turtle may have one) is sensed and decided on the
whole cell, as before.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from itertools import combinations_with_replacement

import numpy as np

from kb.model.definitions import (REFERENCE, TARGET, And, Count, Definitions, Exists, Formula, Not, Or,
                                  PredicateLeaf, Relation, Variable)
from kb.model.soap import ActionSpec
from kb.spatial.predicates import compile_relation
from kb.spatial.rcc8 import AXES, BIT, relate

#: interval end points (against the interval [0, 1]) giving every per-axis arrangement
_POINTS = (-2.0, -0.5, 0.0, 0.5, 1.0, 1.5, 3.0)
_TOL = 0.01


@lru_cache(maxsize=None)
def _apart_masks() -> np.ndarray:
    """The relation masks of a box to the unit box for every arrangement where the two are apart
    (beyond the tolerance) along at least one axis. A mask is the union of its axes' bits, each
    axis's decided by that axis's spans alone: one kernel call per axis, then every combination."""
    spans = np.array(list(combinations_with_replacement(_POINTS, 2)))  # (S, 2): lo, hi along one axis
    apart = (spans[:, 1] < -_TOL) | (spans[:, 0] > 1 + _TOL)
    per_axis = []
    for k, axis in enumerate(AXES):
        lo, hi = np.zeros((len(spans), 3)), np.ones((len(spans), 3))
        lo[:, k], hi[:, k] = spans[:, 0], spans[:, 1]
        bits = np.uint32(sum(v for name, v in BIT.items() if name.startswith(axis + "-")))
        per_axis.append(relate(lo, hi, np.zeros((1, 3)), np.ones((1, 3)), _TOL)[:, 0] & bits)
    x, y, z = np.meshgrid(*(np.arange(len(spans)),) * 3, indexing="ij")
    x, y, z = x.ravel(), y.ravel(), z.ravel()
    keep = apart[x] | apart[y] | apart[z]
    return per_axis[0][x[keep]] | per_axis[1][y[keep]] | per_axis[2][z[keep]]


def contact_only(defs: Definitions, relation: str) -> bool:
    """True when ``relation`` (IRI) never holds between boxes apart along some axis."""
    return not compile_relation(defs.relation(relation))(_apart_masks()).any()


@dataclass(frozen=True)
class Tie:
    """Variable ``var``'s candidates: objects of its class touching a candidate of ``to``."""

    var: Variable
    to: object  # REFERENCE, TARGET or an outer Variable


class Focus:
    """Which actions are local, and their neighbourhoods in a belief's world boxes."""

    def __init__(self, defs: Definitions, actions: dict[str, ActionSpec], classes: list[frozenset[str]],
                 tolerance: float) -> None:
        self.defs, self.actions = defs, actions
        self.classes = classes
        self.margin = 2 * tolerance
        self._contact: dict[str, bool] = {}
        self._ties: dict[str, list[Tie] | None] = {}
        self._plans: dict[str, list[tuple[tuple[str, ...], list[Tie]]] | None] = {}
        self._paths: dict[str, list[tuple[str, tuple[str, ...]]]] = {}
        self._of: dict[str, np.ndarray] = {}
        self._last: tuple[np.ndarray, np.ndarray, _Touching] | None = None

    # --- the definitions ------------------------------------------------------------
    def plan(self, action: str) -> list[tuple[tuple[str, ...], list[Tie]]] | None:
        """Per atom of the action: its parameters and its variables' ties; None: not local."""
        if action not in self._plans:
            spec = self.actions[action]
            out: list[tuple[tuple[str, ...], list[Tie]]] | None = []
            for atom in spec.pre + spec.effects:
                ties = self.ties(atom.predicate)
                if ties is None:
                    out = None
                    break
                out.append((tuple(atom.args), ties))
            self._plans[action] = out
        return self._plans[action]

    def ties(self, predicate: str) -> list[Tie] | None:
        """The ties of a predicate's variables, outer first; None when one is not tied (or the
        predicate is not defined: nothing is known of what it searches)."""
        if predicate not in self._ties:
            p = self.defs.predicates.get(predicate)
            out: list[Tie] | None = None
            if p is not None:
                out = []
                if not self._tie(p.formula, (REFERENCE, TARGET), out):
                    out = None
            self._ties[predicate] = out
        return self._ties[predicate]

    def _tie(self, f: Formula, scope: tuple, out: list[Tie]) -> bool:
        if isinstance(f, (Exists, Count)):
            body = f.body if isinstance(f, Exists) else f.condition
            to = self._anchor(f.variable, body, scope)
            if to is None:
                return False
            out.append(Tie(f.variable, to))
            return self._tie(body, scope + (f.variable,), out)
        if isinstance(f, PredicateLeaf):
            return False  # a predicate inside another: not analysed, so not local
        if isinstance(f, (And, Or)):
            return all(self._tie(op, scope, out) for op in f.operands)
        if isinstance(f, Not):
            return self._tie(f.operand, scope, out)
        return True  # atoms bind nothing

    def _anchor(self, var: Variable, body: Formula, scope: tuple) -> object | None:
        """A term in ``scope`` that ``var`` must touch for ``body`` to hold, or None."""
        conj = body.operands if isinstance(body, And) else (body,)
        for f in conj:
            if not isinstance(f, Relation) or f.negated or not self._touching(f.relation):
                continue
            for a, b in ((f.subject, f.object), (f.object, f.subject)):
                if a == var and b in scope:
                    return b
        return None

    def _touching(self, relation: str) -> bool:
        if relation not in self._contact:
            self._contact[relation] = contact_only(self.defs, relation)
        return self._contact[relation]

    # --- neighbourhoods -------------------------------------------------------------
    def paths(self, action: str) -> list[tuple[str, tuple[str, ...]]]:
        """The action's tied variables as paths, each once: the parameter a chain of ties starts
        at and the classes along it (``robot-empty``'s held: robot, (EndEffector, SolidObject))."""
        if action not in self._paths:
            out: dict[tuple[str, tuple[str, ...]], None] = {}
            for params, ties in self.plan(action) or ():
                chain: dict[object, tuple[str, tuple[str, ...]]] = {
                    key: (param, ()) for key, param in zip((REFERENCE, TARGET), params)}
                for tie in ties:
                    param, classes = chain[tie.to]
                    chain[tie.var] = (param, classes + (tie.var.cls,))
                    out[chain[tie.var]] = None
            self._paths[action] = list(out)
        return self._paths[action]

    def neighbourhood(self, action: str, args: dict[str, int], lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
        """Indices of the objects the checks of ``action`` (local) depend on: ``args``
        (parameter -> object index; placed or not) and each tied variable's candidates, in the
        world boxes ``lo``, ``hi`` (NaN: not placed)."""
        touching = self._touching_in(lo, hi)
        keep = np.zeros(len(lo), bool)
        keep[np.array(sorted(set(args.values())), np.int64)] = True
        found: dict[tuple[str, tuple[str, ...]], np.ndarray] = {}
        for param, classes in self.paths(action):  # prefixes come first: (p, (A,)) before (p, (A, B))
            base = found[(param, classes[:-1])] if len(classes) > 1 else np.array([args[param]], np.int64)
            near = touching(base) & self._of_class(classes[-1])
            found[(param, classes)] = np.flatnonzero(near)
            keep |= near
        return np.flatnonzero(keep)

    def touching(self, objects: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
        """Indices of the placed objects whose boxes in ``lo``, ``hi`` touch one of ``objects``'."""
        return np.flatnonzero(self._touching_in(lo, hi)(np.asarray(objects, np.int64)))

    def _touching_in(self, lo: np.ndarray, hi: np.ndarray) -> "_Touching":
        """One :class:`_Touching` per set of boxes (a belief's boxes while nothing moves)."""
        if self._last is None or self._last[0] is not lo or self._last[1] is not hi:
            self._last = (lo, hi, _Touching(lo, hi, self.margin))
        return self._last[2]

    def _of_class(self, cls: str) -> np.ndarray:
        if cls not in self._of:
            self._of[cls] = np.array([cls in c for c in self.classes], bool)
        return self._of[cls]


class _Touching:
    """The placed objects whose world boxes touch (within ``margin``) one of a set's; answers
    kept for the sets asked again (atoms share their ties)."""

    def __init__(self, lo: np.ndarray, hi: np.ndarray, margin: float) -> None:
        self.placed = ~np.isnan(lo[:, 0])
        self.idx = np.flatnonzero(self.placed)
        self.lo, self.hi = lo[self.idx], hi[self.idx]
        self.all_lo, self.all_hi = lo, hi
        self.margin = margin
        self.n = len(lo)
        self._seen: dict[bytes, np.ndarray] = {}

    def __call__(self, base: np.ndarray) -> np.ndarray:
        key = base.tobytes()
        out = self._seen.get(key)
        if out is None:
            out = self._seen[key] = self._compute(base)
        return out

    def _compute(self, base: np.ndarray) -> np.ndarray:
        out = np.zeros(self.n, bool)
        base = base[self.placed[base]] if len(base) else base
        if not len(base):
            return out
        blo, bhi = self.all_lo[base] - self.margin, self.all_hi[base] + self.margin
        for k in range(0, len(base), 64):  # bounded memory: (objects x 64 x 3)
            b0, b1 = blo[k:k + 64], bhi[k:k + 64]
            hit = ((self.lo[:, None, :] <= b1[None]) & (self.hi[:, None, :] >= b0[None])).all(axis=2).any(axis=1)
            out[self.idx[hit]] = True
        return out
