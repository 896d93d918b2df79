"""Relation atoms on a scene's pairs: a relation's expression compiled to bit tests, and which
pairs of a scene's objects it holds for, each pair decided in its object's frame.

A relation (``soap:Partially-In`` ...) is an ``owl:equivalentClass`` expression over the 30
primitives of :mod:`kb.spatial.rcc8`; :func:`compile_relation` makes it a test of uint32 masks.
:class:`PairRelations` gives the masks of subject x object candidate sets of one scene: one
:func:`kb.spatial.rcc8.relate` call on the world boxes, the pairs that meet there and whose
object is turned decided again in the object's frame (:func:`kb.spatial.rcc8.reframe`;
docs/soap.md, "Orientation"). A small scene (an action's neighbourhood: up to
:data:`WHOLE_SCENE` objects) has the masks of all its pairs computed in that one call on first
use and each relation's truth over them once, so the atoms of a check cost indexing only; a
larger scene computes the masks of each candidate pair of sets when an atom needs them.
"""

from __future__ import annotations

from typing import Callable

import numpy as np

from kb.model.definitions import RelationExpr
from kb.spatial.rcc8 import BIT, heading_groups, headings, reframe, relate
from kb.spatial.scene import Scene

Mask = Callable[[np.ndarray], np.ndarray]
#: A scene of at most this many objects has the masks of all its pairs computed at once.
WHOLE_SCENE = 160


def compile_relation(expr: RelationExpr) -> Mask:
    """A function of a uint32 relation-mask array -> Boolean array, from a relation expression."""
    if expr.op == "prim":
        bit = np.uint32(BIT[expr.name])
        return lambda m: (m & bit) != 0
    if expr.op == "true":
        return lambda m: np.ones(m.shape, bool)
    if expr.op == "not":
        inner = compile_relation(expr.args[0])
        return lambda m: ~inner(m)
    if expr.op == "any" and all(a.op == "prim" for a in expr.args):
        bits = np.uint32(sum(BIT[a.name] for a in expr.args))
        return lambda m: (m & bits) != 0
    parts = [compile_relation(a) for a in expr.args]
    if expr.op == "any":
        def any_of(m: np.ndarray) -> np.ndarray:
            out = parts[0](m)
            for p in parts[1:]:
                out |= p(m)
            return out
        return any_of

    def all_of(m: np.ndarray) -> np.ndarray:
        out = parts[0](m)
        for p in parts[1:]:
            out &= p(m)
        return out
    return all_of


#: id(expression) -> (expression, its compiled test): each relation compiled once per process
#: (by identity: hashing a frozen expression tree walks the whole tree every time)
_COMPILED: dict[int, tuple[RelationExpr, Mask]] = {}


def compiled(expr: RelationExpr) -> Mask:
    """:func:`compile_relation` of ``expr``, compiled once."""
    entry = _COMPILED.get(id(expr))
    if entry is None or entry[0] is not expr:
        if len(_COMPILED) > 4096:
            _COMPILED.clear()
        entry = _COMPILED[id(expr)] = (expr, compile_relation(expr))
    return entry[1]


def object_frames(scene: Scene) -> np.ndarray:
    """(K,) the yaw of each object's frame (:func:`kb.spatial.rcc8.heading_groups`; 0: the world's)."""
    k = len(scene.names)
    if scene.poses is None or scene.local_lo is None or not k:
        return np.zeros(k)
    h = headings(scene.poses)
    h[~scene.placed] = np.nan
    labels, yaws = heading_groups(h)
    return yaws[labels]


class PairRelations:
    """Relation masks and truths of a scene's pairs (``frames``: each object's frame yaw, as
    :func:`object_frames` gives them)."""

    def __init__(self, scene: Scene, tol: float, frames: Callable[[Scene], np.ndarray] = object_frames) -> None:
        self.scene, self.tol, self.frames = scene, tol, frames
        self.whole = len(scene.names) <= WHOLE_SCENE
        self._masks: dict[tuple, np.ndarray] = {}
        self._truth: dict[int, tuple[Mask, np.ndarray]] = {}  # id(test) -> test, (K, K) truth (whole scenes)
        self._all: np.ndarray | None = None  # (K, K) masks of every pair (whole scenes)
        # unplaced objects get a far-away box (DC from everything; masked out anyway), wide:
        # not thin, so that relate does not decide their pairs with each other again
        self._lo = np.where(np.isnan(scene.lo), 1e30, scene.lo)
        self._hi = np.where(np.isnan(scene.hi), 2e30, scene.hi)
        self._yaw: np.ndarray | None = None  # each object's frame, on first use

    def truth(self, test: Mask, s: np.ndarray, o: np.ndarray) -> np.ndarray:
        """(len s, len o) Boolean: ``test`` holds of subject s[i] and object o[j], both placed."""
        if self.whole:
            return self._truth_of(test)[s[:, None], o]
        placed = self.scene.placed
        return test(self.masks(s, o)) & placed[s][:, None] & placed[o][None, :]

    def diagonal(self, test: Mask, c: np.ndarray) -> np.ndarray:
        """(len c,) Boolean: ``test`` holds of each object c[k] with itself."""
        if self.whole:
            return self._truth_of(test)[c, c]
        return np.array([bool(self.truth(test, c[k:k + 1], c[k:k + 1])[0, 0]) for k in range(len(c))], bool)

    def _truth_of(self, test: Mask) -> np.ndarray:
        entry = self._truth.get(id(test))
        if entry is None or entry[0] is not test:
            if self._all is None:
                every = np.arange(len(self.scene.names))
                self._all = self.masks(every, every, keep=False)
            placed = self.scene.placed
            entry = self._truth[id(test)] = (test, test(self._all) & placed[:, None] & placed[None, :])
        return entry[1]

    def masks(self, s: np.ndarray, o: np.ndarray, keep: bool = True) -> np.ndarray:
        """Relation masks of subjects ``s`` x objects ``o``, each pair in its object's frame
        (:func:`kb.spatial.rcc8.reframe`; the world boxes alone when no object is turned);
        ``keep``: remembered for the same sets asked again."""
        key = (s.tobytes(), o.tobytes())
        m = self._masks.get(key) if keep else None
        if m is None:
            m = relate(self._lo[s], self._hi[s], self._lo[o], self._hi[o], self.tol)
            if self._yaw is None:
                self._yaw = self.frames(self.scene)
            yaw = self._yaw[o]
            if yaw.any():
                sc = self.scene
                boxes = (sc.poses, sc.local_lo, sc.local_hi)
                reframe(m, boxes, boxes, yaw, self.tol, s, o)
            if keep:
                if len(self._masks) > 64:
                    self._masks.clear()
                self._masks[key] = m
        return m
