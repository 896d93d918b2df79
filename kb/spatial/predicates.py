"""Predicates evaluated on a scene from their definitions (no predicate is written in Python).

A predicate's formula (:mod:`kb.model.definitions`) is evaluated for all its argument pairs at
once, as a Boolean array with one axis per term in scope: the reference candidates (objects of
its reference class), the target candidates, then one axis per enclosing quantifier. An array
has size 1 on an axis its value does not depend on, so numpy broadcasting does the joins:

* a relation atom reads the 30-bit RCC8/cardinal masks of its subject and object candidates
  (:class:`kb.spatial.relations.PairRelations`: one :func:`kb.spatial.rcc8.relate` call on the
  world boxes, for every pair at once in a small scene such as an action's neighbourhood, the
  pairs that meet there and whose object is turned decided again in the object's frame;
  docs/soap.md, "Orientation"), tested with the relation's ``owl:equivalentClass`` expression
  compiled to bit tests;
* ``Exists`` adds the variable's candidates (objects of its class that are placed or not,
  never the objects already bound on another axis) as a new axis and reduces it with ``any``;
  ``Count`` sums it and compares; ``And`` evaluates its operands left to right, each only on
  the candidates still alive (so ``robot-holds-part`` looks for a support below a part only
  for the parts that touch the gripper), ``Or`` and ``Not`` combine arrays;
* SKU, model and sensor atoms read the scene's facts (a kit's SKU is its tray's).

:class:`Evaluator` answers one atom (:meth:`~Evaluator.holds`), one predicate's table, every
true atom of the scene (:meth:`~Evaluator.facts`) and the functions' values.
"""

from __future__ import annotations

import operator
from dataclasses import dataclass
from typing import Iterable

import numpy as np

from kb.core.errors import InputError
from kb.core.namespaces import KTW
from kb.model.definitions import (
    REFERENCE,
    TARGET,
    And,
    Count,
    CountOf,
    Definitions,
    DesignCount,
    Exists,
    Formula,
    Model,
    Not,
    Or,
    PredicateLeaf,
    Relation,
    Sensor,
    Sku,
    Variable,
)
from kb.spatial.rcc8 import DEFAULT_TOLERANCE
from kb.spatial.relations import WHOLE_SCENE, PairRelations, compile_relation, compiled, object_frames

__all__ = ["Axis", "Evaluator", "compile_relation"]  # compile_relation: kb.spatial.relations', importable here too
from kb.spatial.scene import Scene

_OPS = {"<": operator.lt, "<=": operator.le, "=": operator.eq, ">=": operator.ge, ">": operator.gt}


@dataclass(frozen=True)
class Axis:
    """One term in scope and the scene indices of its candidates."""

    term: object
    cand: np.ndarray


class Evaluator:
    """Predicates and functions of ``defs`` on ``scene``."""

    def __init__(self, defs: Definitions, scene: Scene, tolerance: float = DEFAULT_TOLERANCE):
        self.defs, self.scene, self.tol = defs, scene, tolerance
        self._model: dict[str, np.ndarray] = {}
        self._pair_relations: PairRelations | None = None  # on the first relation atom

    # --- public ---------------------------------------------------------------------
    def candidates(self, cls: str | None) -> np.ndarray:
        """Scene indices of the objects of ``cls``."""
        return self.scene.of_class(cls) if cls is not None else np.zeros(0, np.int64)

    def table(self, name: str, reference: Iterable[str] | None = None,
              target: Iterable[str] | None = None) -> tuple[list[str], list[str], np.ndarray]:
        """(reference objects, target objects, truth array) of predicate ``name``; the argument
        lists default to every object of the predicate's classes."""
        p = self._predicate(name)
        axes = []
        names: list[list[str]] = []
        for key, cls, given in ((REFERENCE, p.reference_type, reference), (TARGET, p.target_type, target)):
            if cls is None:
                continue
            cand = self._indices(given) if given is not None else self.candidates(cls)
            axes.append(Axis(key, cand))
            names.append([self.scene.names[i] for i in cand])
        out = self._full(self.eval(p.formula, axes), axes)
        return (names[0] if names else [], names[1] if len(names) > 1 else [], out)

    def holds(self, name: str, *args: str) -> bool:
        """Whether ``name(args)`` is true in the scene."""
        p = self._predicate(name)
        if len(args) != p.arity:
            raise InputError(f"predicate {name} takes {p.arity} arguments, not {len(args)}")
        if p.reference_type is None and args:  # the table's reading of such a predicate
            return bool(self.table(name, [args[0]], None)[2].all())
        axes = [Axis(key, self._indices([arg])) for key, arg in zip((REFERENCE, TARGET), args)]
        return bool(np.asarray(self.eval(p.formula, axes)).all())  # one candidate per axis: no broadcast

    def witnesses(self, name: str, *args: str) -> list[str]:
        """The objects that decide a quantified atom ``name(args)``: for a predicate defined as
        ``∃x body``, ``¬∃x body`` or a count of ``x`` (its outermost node, under at most one
        negation), the candidates of ``x`` for which the body holds with the arguments bound
        (``worktable-empty(table)`` found false: what rests on the table); ``[]`` for any other
        definition, a predicate the domain does not have, or an argument not in the scene."""
        p = self.defs.predicates.get(name)
        if p is None:
            return []
        f = p.formula.operand if isinstance(p.formula, Not) else p.formula
        if isinstance(f, Exists):
            var, body = f.variable, f.body
        elif isinstance(f, Count):
            var, body = f.variable, f.condition
        else:
            return []
        if len(args) != p.arity or (p.reference_type is None and args) or any(a not in self.scene.index for a in args):
            return []
        axes = [Axis(key, self._indices([arg])) for key, arg in zip((REFERENCE, TARGET), args)]
        hits = np.asarray(self._over(var, body, axes)).reshape(-1)
        cand = self.candidates(var.cls)
        return [self.scene.names[cand[k]] for k in np.flatnonzero(hits[-len(cand):])] if len(cand) else []

    def holds_formula(self, formula: Formula, bindings: dict) -> bool:
        """Whether ``formula`` holds with its free terms (``"reference"``, ``"target"``, an
        action parameter's IRI) bound to the objects named in ``bindings`` (term -> IRI)."""
        axes = [Axis(term, self._indices([obj])) for term, obj in bindings.items()]
        return bool(np.asarray(self.eval(formula, axes)).all())

    def facts(self, names: Iterable[str] | None = None) -> list[tuple[str, tuple[str, ...]]]:
        """Every true atom ``(predicate, args)`` of the scene, sorted."""
        out = []
        for name in sorted(names if names is not None else self.defs.predicates):
            refs, tgts, truth = self.table(name)
            if truth.ndim == 0:
                if truth:
                    out.append((name, ()))
            elif truth.ndim == 1:
                out.extend((name, (refs[i],)) for i in np.flatnonzero(truth))
            else:
                out.extend((name, (refs[i], tgts[j])) for i, j in zip(*np.nonzero(truth)))
        return sorted(out)

    def function_values(self, name: str) -> dict[tuple[str, ...], int]:
        """``args -> value`` of function ``name`` for every argument tuple of its classes
        (``capacity-kit``: the kit's design counts, for the SKUs of its design only)."""
        f = self.defs.functions.get(name)
        if f is None:
            raise InputError(f"no function named {name!r} in the domain")
        if isinstance(f.definition, DesignCount):
            return self._design_counts()
        assert isinstance(f.definition, CountOf)
        axes = [Axis(k, self.candidates(c)) for k, c in ((REFERENCE, f.reference_type), (TARGET, f.target_type))
                if c is not None]
        counts = self._count(f.definition.variable, f.definition.condition, axes)
        counts = np.broadcast_to(counts, tuple(len(a.cand) for a in axes))
        names = self.scene.names
        return {tuple(names[a.cand[i]] for a, i in zip(axes, idx)): int(counts[idx]) for idx in np.ndindex(counts.shape)}

    # --- evaluation -----------------------------------------------------------------
    def eval(self, f: Formula, axes: list[Axis]) -> np.ndarray:
        """``f`` on the candidate grid of ``axes`` (size 1 on axes ``f`` does not depend on)."""
        if isinstance(f, And):
            return self._and(f, axes)
        if isinstance(f, Or):
            out = self.eval(f.operands[0], axes)
            for op in f.operands[1:]:
                out = out | self.eval(op, axes)
            return out
        if isinstance(f, Not):
            return ~self.eval(f.operand, axes)
        if isinstance(f, Exists):
            return self._exists(f, axes)
        if isinstance(f, Relation):
            out = self._relation(f, axes)
        elif isinstance(f, Sku):
            out = self._pairs(self._sku_matrix, f.subject, f.object, axes)
        elif isinstance(f, Model):
            out = self._pairs(lambda s, o: self._model_matrix(f.property, s, o), f.subject, f.object, axes)
        elif isinstance(f, Count):
            out = self._count_atom(f, axes)
        elif isinstance(f, Sensor):
            passed = self.scene.inspections.get(f.check, set())
            i = self._axis(f.subject, axes)
            vec = np.array([self.scene.names[x] in passed for x in axes[i].cand], bool)
            out = self._place([(i, vec)], len(axes))
        elif isinstance(f, PredicateLeaf):
            out = self._leaf(f, axes)
        else:  # pragma: no cover - the reader admits no other node
            raise TypeError(f"unknown formula node {f!r}")
        return ~out if f.negated else out

    def _and(self, f: And, axes: list[Axis]) -> np.ndarray:
        out = self.eval(f.operands[0], axes)
        for op in f.operands[1:]:
            if not out.any():
                return out
            live = [k for k in range(len(axes)) if out.shape[k] > 1]
            keep = {k: np.flatnonzero(out.any(axis=tuple(j for j in range(out.ndim) if j != k))) for k in live}
            if all(len(keep[k]) == out.shape[k] for k in live):
                out = out & self.eval(op, axes)
                continue
            sub = [Axis(a.term, a.cand[keep[k]]) if k in keep else a for k, a in enumerate(axes)]
            part = self.eval(op, sub)
            shape = tuple(len(axes[k].cand) if k in keep else part.shape[k] for k in range(len(axes)))
            back = np.zeros(shape, bool)
            index = np.ix_(*[keep[k] if k in keep else np.arange(shape[k]) for k in range(len(axes))])
            back[index] = part
            out = out & back
        return out

    def _bound_excluded(self, var: Variable, axes: list[Axis]) -> tuple[list[Axis], np.ndarray | None]:
        """The axes with ``var``'s candidates appended, and the mask that drops a candidate
        equal to an object already bound on another axis (None: no candidate is bound)."""
        cand = self.candidates(var.cls)
        inner = axes + [Axis(var, cand)]
        n = len(inner)
        keep = None
        names = set(cand.tolist())
        for k, a in enumerate(axes):
            if names.isdisjoint(a.cand.tolist()):
                continue
            shape = [1] * n
            shape[k], shape[-1] = len(a.cand), len(cand)
            apart = (a.cand[:, None] != cand[None, :]).reshape(shape)
            keep = apart if keep is None else keep & apart
        return inner, keep

    def _over(self, var: Variable, body: Formula, axes: list[Axis]) -> np.ndarray:
        """``body`` with ``var``'s candidates on a last axis of their number, the bound ones false."""
        inner, keep = self._bound_excluded(var, axes)
        out = self.eval(body, inner)
        if keep is not None:
            out = out & keep
        m = len(inner[-1].cand)
        return out if out.shape[-1] == m else np.broadcast_to(out, out.shape[:-1] + (m,))

    def _exists(self, f: Exists, axes: list[Axis]) -> np.ndarray:
        return self._over(f.variable, f.body, axes).any(axis=-1)

    def _count(self, var: Variable, cond: Formula, axes: list[Axis]) -> np.ndarray:
        return self._over(var, cond, axes).sum(axis=-1)

    def _count_atom(self, f: Count, axes: list[Axis]) -> np.ndarray:
        counts = self._count(f.variable, f.condition, axes)
        if f.limit is not None:
            return _OPS[f.operator](counts, f.limit)
        i = self._axis(f.limit_subject, axes)
        limits = []
        for x in axes[i].cand:
            v = self.scene.value(f.limit_property, self.scene.names[x])
            if v is None:
                raise InputError(f"{_local(self.scene.names[x])} has no {_local(f.limit_property)}, which "
                                 f"count atom {_local(f.node)} compares with", self.scene.path)
            limits.append(float(v))
        lim = self._place([(i, np.array(limits))], len(axes), fill=np.nan, dtype=float)
        return _OPS[f.operator](counts, lim)

    def _leaf(self, f: PredicateLeaf, axes: list[Axis]) -> np.ndarray:
        p = self._predicate_by_iri(f.predicate)
        sub, where = [], []
        for key, term in ((REFERENCE, f.reference), (TARGET, f.target)):
            if term is None:
                continue
            i = self._axis(term, axes)
            sub.append(Axis(key, axes[i].cand))
            where.append(i)
        truth = self._full(self.eval(p.formula, sub), sub)
        if len(where) == 2 and where[0] == where[1]:
            return self._place([(where[0], np.diagonal(truth).copy())], len(axes))
        if len(where) == 2:
            return self._place_matrix(truth, where[0], where[1], len(axes))
        return self._place([(where[0], truth)], len(axes)) if where else np.asarray(truth).reshape((1,) * len(axes))

    # --- atoms over pairs -------------------------------------------------------------
    def _relation(self, f: Relation, axes: list[Axis]) -> np.ndarray:
        rel = self._pair_relations
        if rel is None:
            rel = self._pair_relations = PairRelations(self.scene, self.tol, self._frames)
        test = compiled(self.defs.relation(f.relation))
        return self._pairs(lambda s, o: rel.truth(test, s, o), f.subject, f.object, axes,
                           lambda c: rel.diagonal(test, c))

    #: each object's frame yaw (docs/soap.md, "Orientation"); a subclass may decide otherwise
    _frames = staticmethod(object_frames)

    def _pairs(self, matrix, subject, obj, axes: list[Axis], diagonal=None) -> np.ndarray:  # noqa: ANN001
        """``matrix(s, o)`` (subjects x objects, Boolean) placed on the axes of ``subject`` and
        ``obj``; where both are one term, each candidate with itself (``diagonal(cand)``)."""
        i, j = self._axis(subject, axes), self._axis(obj, axes)
        if i == j:
            cand = axes[i].cand
            vec = diagonal(cand) if diagonal is not None else np.array([bool(matrix(cand[k:k + 1], cand[k:k + 1])[0, 0]) for k in range(len(cand))], bool)
            return self._place([(i, vec)], len(axes))
        return self._place_matrix(matrix(axes[i].cand, axes[j].cand), i, j, len(axes))

    def _related(self, prop: str, subjects: Iterable[str]) -> dict[str, list[str]]:
        """subject -> objects of ``prop``: the scene's index, or for a small scene (whose facts are
        a whole cell's) the pairs of ``subjects`` only, found in one pass."""
        sc = self.scene
        if len(sc.names) > WHOLE_SCENE:  # a whole cell's index, built once
            return sc.related(prop)
        wanted = set(subjects)
        out: dict[str, list[str]] = {}
        for a, b in sc.facts.get(prop, ()):
            if a in wanted:
                out.setdefault(a, []).append(b)
        return out

    def _model_matrix(self, prop: str, s: np.ndarray, o: np.ndarray) -> np.ndarray:
        pairs = self._related(prop, [self.scene.names[x] for x in s.tolist()])
        names, index = self.scene.names, self.scene.index
        pos = {x: k for k, x in enumerate(o.tolist())}
        out = np.zeros((len(s), len(o)), bool)
        for a, x in enumerate(s.tolist()):
            for y in pairs.get(names[x], ()):
                b = pos.get(index.get(y, -1))
                if b is not None:
                    out[a, b] = True
        return out

    def _sku_matrix(self, s: np.ndarray, o: np.ndarray) -> np.ndarray:
        """effector s is listed by the SKU of thing o (a kit: its tray's SKU)."""
        sc = self.scene
        things = [sc.names[y] for y in o.tolist()]
        tray_of = self._related(str(KTW.hasKit_KitTray), things)
        sku_of = self._related(str(KTW.hasSkuObject_Sku), things + [t for ts in tray_of.values() for t in ts])
        effectors = self._related(str(KTW.hasStockKeepingUnit_EndEffector), [k for ks in sku_of.values() for k in ks])
        pos = {x: k for k, x in enumerate(s.tolist())}
        out = np.zeros((len(s), len(o)), bool)
        for b, y in enumerate(o.tolist()):
            name = sc.names[y]
            skus = sku_of.get(name) or [k for t in tray_of.get(name, ()) for k in sku_of.get(t, ())]
            for sku in skus:
                for ee in effectors.get(sku, ()):
                    a = pos.get(sc.index.get(ee, -1))
                    if a is not None:
                        out[a, b] = True
        return out

    # --- helpers --------------------------------------------------------------------
    def _axis(self, term, axes: list[Axis]) -> int:  # noqa: ANN001
        for k in range(len(axes) - 1, -1, -1):
            if axes[k].term == term:
                return k
        raise InputError(f"term {term} is not bound where it is used")

    @staticmethod
    def _place(vectors: list[tuple[int, np.ndarray]], ndim: int, fill=False, dtype=bool) -> np.ndarray:  # noqa: ANN001
        (i, vec), = vectors
        shape = [1] * ndim
        shape[i] = len(vec)
        return np.asarray(vec, dtype).reshape(shape)

    @staticmethod
    def _place_matrix(m: np.ndarray, i: int, j: int, ndim: int) -> np.ndarray:
        if i > j:
            m, i, j = m.T, j, i
        shape = [1] * ndim
        shape[i], shape[j] = m.shape
        return m.reshape(shape)

    @staticmethod
    def _full(a: np.ndarray, axes: list[Axis]) -> np.ndarray:
        return np.broadcast_to(a, tuple(len(x.cand) for x in axes)).copy()

    def _indices(self, names: Iterable[str]) -> np.ndarray:
        out = []
        for n in names:
            if n not in self.scene.index:
                raise InputError(f"no object {_local(n)} in the scene", self.scene.path)
            out.append(self.scene.index[n])
        return np.array(out, np.int64)

    def _predicate(self, name: str):  # noqa: ANN202
        p = self.defs.predicates.get(name)
        if p is None:
            raise InputError(f"no predicate named {name!r} in the domain")
        return p

    def _predicate_by_iri(self, iri: str):  # noqa: ANN202
        for p in self.defs.predicates.values():
            if p.iri == iri:
                return p
        raise InputError(f"no predicate {_local(iri)} in the domain")

    def _design_counts(self) -> dict[tuple[str, ...], int]:
        sc = self.scene
        design_of = sc.related(str(KTW.hasKit_Design))
        prps = sc.related(str(KTW.hasKitDesign_PartRefAndPose))
        sku_of = sc.related(str(KTW.hasPartRefAndPose_Sku))
        out: dict[tuple[str, ...], int] = {}
        for k in self.candidates(str(KTW.Kit)):
            kit = sc.names[k]
            for design in design_of.get(kit, ()):
                for prp in prps.get(design, ()):
                    for sku in sku_of.get(prp, ()):
                        out[(kit, sku)] = out.get((kit, sku), 0) + 1
        return out


def _local(iri) -> str:  # noqa: ANN001
    return str(iri).rsplit("#", 1)[-1].rsplit("/", 1)[-1]
