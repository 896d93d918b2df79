"""A state file's geometry read in bulk for validation: its scene, its kit designs' slots, and
every defect that keeps kitkb from building the scene, each at its node.

:meth:`kb.spatial.scene.Scene.from_sources` is what the commands read a state with
(``predicates``, the geometry check of ``plan`` and ``run``, the executor): object by object,
stopping at the first defect with an :class:`~kb.core.errors.InputError`. ``kitkb validate``
must report the same defects (the same message at the same line; "one verdict per defect",
docs/validation.md), every one of them, and read a file of 10,000 parts in a fraction of the
time the check may take. :func:`survey` reads one file's triples the way the scene builder does
— the same rules for poses down the transformation tree, shapes, stand-ins, units and slots —
but in one pass over the file's subject index, with the numbers converted and the poses
composed as arrays, and it lists each defect instead of stopping. When there is none, its
:class:`Survey` holds the scene the builder would build (the geometry and the model facts of
the stand-ins, which is what :func:`kb.spatial.plausibility.check` reads; tests compare it with
the builder's) and the slots of the file's kit designs with the boxes of their parts and trays
(:func:`kb.spatial.plausibility.slot_misfits`).
"""

from __future__ import annotations

from collections import defaultdict
from dataclasses import dataclass, field
from typing import Any, Callable

import numpy as np
from rdflib import Literal, URIRef
from rdflib.namespace import RDF

from kb.core.namespaces import KTW
from kb.core.units import KINDS, Units, unit_factor
from kb.model.units import UNIT_PROPS, quantity_kinds
from kb.spatial.scene import STAND_INS, Scene, class_ancestors, scene_boxes, unknown_reference

#: the rules of the defects (docs/validation.md, "One verdict per defect")
NO_SHAPE = "no-shape"                  # a placed object with no box
REFERENCE_CYCLE = "reference-cycle"    # locations that refer back to themselves
MISSING_VALUE = "missing-value"        # a coordinate, axis component or dimension left out
BAD_NUMBER = "unusable-number"         # a coordinate or dimension that is no usable number
DEGENERATE_POSE = "degenerate-pose"    # an axis of length zero, or x and z axes parallel
UNIT = "unit"                          # a unit kitkb cannot convert, or two units of one kind
UNKNOWN_REFERENCE = "unknown-reference"  # a location's reference object that the state does not place
RULES = (NO_SHAPE, REFERENCE_CYCLE, MISSING_VALUE, BAD_NUMBER, DEGENERATE_POSE, UNIT, UNKNOWN_REFERENCE)

_KTW = str(KTW)
_SOLID, _PRP = str(KTW.SolidObject), str(KTW.PartRefAndPose)
_VACUUM, _ROBOT = str(KTW.VacuumEffector), str(KTW.Robot)
_GEOMETRY = frozenset(str(c) for c in (KTW.Point, KTW.Vector, KTW.PhysicalLocation, KTW.ShapeDesign, KTW.BoxVolume))
_XYZ = (KTW.hasPoint_X, KTW.hasPoint_Y, KTW.hasPoint_Z)
_IJK = (KTW.hasVector_I, KTW.hasVector_J, KTW.hasVector_K)
_BOXY = (KTW.hasBoxyShape_Length, KTW.hasBoxyShape_Width, KTW.hasBoxyShape_Height)
_CYLINDER = (KTW.hasCylindricalShape_Diameter, KTW.hasCylindricalShape_Height)
_CUP = (KTW.hasVacuumEffector_CupDiameter, KTW.hasVacuumEffector_Length)
_SKU, _PRP_SKU, _TRAY_SKU = KTW.hasSkuObject_Sku, KTW.hasPartRefAndPose_Sku, KTW.hasKitDesign_KitTraySku
_SKU_SHAPE, _OWN_SHAPE = KTW.hasStockKeepingUnit_InternalShape, KTW.hasNoSkuObject_InternalShape
_SKU_EXTERNAL, _OWN_EXTERNAL = KTW.hasStockKeepingUnit_ExternalShape, KTW.hasNoSkuObject_ExternalShape
_TOPS = (KTW.hasBoxyShape_HasTop, KTW.hasCylindricalShape_HasTop)
#: every term the reader looks up (looked up as the file's own objects: see _Reader.terms)
_TERMS = (RDF.type, KTW.hasSolidObject_PrimaryLocation, KTW.hasPhysicalLocation_RefObject,
          KTW.hasPoseLocation_Point, KTW.hasPoseLocation_XAxis, KTW.hasPoseLocation_ZAxis,
          KTW.hasPartRefAndPose_Point, KTW.hasPartRefAndPose_XAxis, KTW.hasPartRefAndPose_ZAxis,
          _PRP_SKU, KTW.hasKitDesign_PartRefAndPose, _TRAY_SKU,
          _SKU, _SKU_SHAPE, _OWN_SHAPE, _SKU_EXTERNAL, _OWN_EXTERNAL, *_TOPS,
          *_XYZ, *_IJK, *_BOXY, *_CYLINDER, *_CUP, *STAND_INS.values(), *UNIT_PROPS.values())
#: subjects whose predicates are looked at to find the file's own term objects
_TERM_SEARCH = 3_000
_EPS = 1e-12  # as kb.spatial.transforms


@dataclass(frozen=True)
class Defect:
    """One defect: ``rule``; ``message`` (the builder's, word for word); ``node``, what it is
    about; ``at``, the ``(subject, predicate, object)`` whose line the builder reports;
    ``nodes``, what it is read from: a node, or ``(node, word)`` for a node of which only an
    error whose message has ``word`` in it says why (another error there is another defect)."""

    rule: str
    message: str
    node: Any
    at: tuple
    nodes: tuple = ()


@dataclass
class Slots:
    """The slots (``PartRefAndPose``) of the file's kit designs whose part SKU and tray SKU
    both have a box: for slot ``n``, ``names[n]``, its ``design[n]``, ``part_sku[n]``,
    ``tray_sku[n]``; its pose in the tray's frame ``pose[n]`` (4, 4), the part's box ``part_lo``,
    ``part_hi`` and the tray's ``tray_lo``, ``tray_hi`` (each (N, 3), metres, in their own frames);
    ``nodes[n]``: what the slot is read from."""

    names: list[str] = field(default_factory=list)
    design: list[str] = field(default_factory=list)
    part_sku: list[str] = field(default_factory=list)
    tray_sku: list[str] = field(default_factory=list)
    pose: np.ndarray = field(default_factory=lambda: np.zeros((0, 4, 4)))
    part_lo: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    part_hi: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    tray_lo: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    tray_hi: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    nodes: list[tuple] = field(default_factory=list)


@dataclass
class Survey:
    """What :func:`survey` read: ``scene`` (None when a defect keeps it from being built),
    ``defects`` (each once; the builder's InputError is one of them), ``slots``,
    ``locations`` (object IRI -> its pose location's IRI) and ``units``."""

    scene: Scene | None
    defects: list[Defect]
    slots: Slots
    locations: dict[str, str]
    units: Units


def survey(src: Any) -> Survey:
    """Read the geometry of one loaded file ``src`` (:class:`kb.io.loader.Source`)."""
    return _Reader(src).read()


def no_shape_message(name: str, kinds: list[str], external: bool) -> str:
    """The words of the scene builder's "placed but has no shape" error."""
    why = "no InternalShape on its SKU or itself" + (
        " (an ExternalShape is a model file kitkb does not read)" if external else "")
    return f"{name} is placed but has no shape: {why}, and no rule gives one to a {' / '.join(kinds[:3])}"


def _local(node: Any) -> str:
    return str(node).rsplit("#", 1)[-1].rsplit("/", 1)[-1]


def _first(objs: Any) -> Any:
    """The first of a subject index's objects (a dict), or None."""
    if objs:
        for o in objs:
            return o
    return None


class _Failed(Exception):
    """A defect met while reading one value (the reader records it and goes on)."""

    def __init__(self, defect: Defect) -> None:
        super().__init__(defect.message)
        self.defect = defect


class _Reader:
    """One file's subject index read as :class:`kb.spatial.scene._Builder` reads its triples.

    Values are looked up in the file's subject -> predicate -> objects index with the file's
    own term objects as keys (an equal rdflib term that is another object costs a Python-level
    comparison on every look-up); the numbers of a point, a vector or a shape are converted
    together, and only when one of them fails is each read again to say which and why."""

    def __init__(self, src: Any) -> None:
        self.src = src
        self.spo: dict = src.view().by_subject()
        self.path = str(src.path)
        self.defects: list[Defect] = []
        self.design_of: dict[Any, Any] = {}  # slot -> its kit design
        self.converted: dict[int, float] = {}  # id of a literal of the file -> its number
        self.t = self.terms()

    def terms(self) -> dict[Any, Any]:
        """Each of :data:`_TERMS` -> the object the file itself uses for it (itself if absent)."""
        out = {t: t for t in _TERMS}
        missing = set(_TERMS)
        for n, preds in enumerate(self.spo.values()):
            if n >= _TERM_SEARCH or not missing:
                break
            for p in preds:
                if p in missing:
                    out[p] = p
                    missing.discard(p)
        return out

    # --- values -------------------------------------------------------------------------
    def value(self, s: Any, p: Any) -> Any:
        preds = self.spo.get(s)
        return _first(preds.get(self.t.get(p, p))) if preds else None

    def number(self, node: Any, prop: Any) -> float:
        """The builder's ``number``: a missing value, or one that is no number, is a defect."""
        v = self.value(node, prop)
        if v is None:
            raise _Failed(Defect(MISSING_VALUE, f"{_local(node)} has no {_local(prop)}", node, (node,), (node,)))
        try:
            return float(v.toPython() if isinstance(v, Literal) else v) * self.scale.get(str(prop), 1.0)
        except (TypeError, ValueError):
            raise _Failed(Defect(BAD_NUMBER, f"{_local(node)}: {_local(prop)} is not a number: {v}",
                                 node, (node,), (node,))) from None
        except OverflowError:
            raise _Failed(Defect(BAD_NUMBER, f"{_local(node)}: {_local(prop)} is too large ({len(str(v))} digits)",
                                 node, (node,), (node,))) from None

    def reading(self, props: tuple) -> Callable[[Any], list[float]]:
        """A function: node -> :meth:`number` of each of the three ``props``. Each literal is
        converted once per file (a parsed file holds one object per distinct literal); on a
        failure each value is read again to say which and why."""
        get, done = self.spo.get, self.converted
        (k0, k1, k2), (s0, s1, s2) = (self.t[p] for p in props), (self.scales[p] for p in props)

        def read(node: Any) -> list[float]:
            try:
                preds = get(node)
                v0, v1, v2 = next(iter(preds[k0])), next(iter(preds[k1])), next(iter(preds[k2]))  # type: ignore[index]
                x0, x1, x2 = done.get(id(v0)), done.get(id(v1)), done.get(id(v2))
                if x0 is None:
                    x0 = done[id(v0)] = float(v0.toPython())
                if x1 is None:
                    x1 = done[id(v1)] = float(v1.toPython())
                if x2 is None:
                    x2 = done[id(v2)] = float(v2.toPython())
                return [x0 * s0, x1 * s1, x2 * s2]
            except Exception:  # noqa: BLE001 - said precisely below
                return [self.number(node, p) for p in props]
        return read

    # --- the pass -----------------------------------------------------------------------
    def read(self) -> Survey:
        anc = class_ancestors()
        typed, primary, units = self.scan(anc)
        self.units = self.read_units(units)
        kinds = quantity_kinds()
        self.scale = {p: self.units.factor(k) for p, k in kinds.items()}
        self.scales = {p: self.scale.get(str(p), 1.0) for p in _TERMS}
        spelled = sorted((str(n), n) for n in typed)  # (IRI as text, term): name order, each spelled once
        names = [n for _, n in spelled]
        classes = [typed[n][0] for n in names]
        k = len(names)
        index = {n: i for i, n in enumerate(names)}
        poses = np.full((k, 4, 4), np.nan)
        parents = np.full(k, -1, np.int64)
        llo, lhi = np.full((k, 3), np.nan), np.full((k, 3), np.nan)
        open_top = np.zeros(k, bool)
        unplaced = self.place(names, classes, index, primary, poses, parents)
        boxes = self.shape(names, classes, index, poses, llo, lhi, open_top, unplaced)
        slot_poses, slots = self.slots(typed, boxes)
        locations = {spelled[index[n]][0]: str(loc) for n, loc in primary.items() if isinstance(loc, URIRef)}
        scene = None
        if not self.defects:
            lo, hi = scene_boxes(poses, llo, lhi)
            scene = Scene([text for text, _ in spelled], classes, lo, hi, self.stand_in_facts(names, classes, index),
                          {}, {}, poses, self.path, parents, llo, lhi, open_top, slot_poses, self.units)
        return Survey(scene, self.defects, slots, locations, self.units)

    def scan(self, anc: dict[str, frozenset[str]]) -> tuple[dict, dict, dict]:
        """One pass over the subjects: individuals typed with kitting classes (their classes
        closed upwards, and whether they are geometry: points, vectors, locations, shapes),
        primary locations, the workstation's units, and each slot's kit design."""
        t = self.t
        a, primary_p, design_p = t[RDF.type], t[KTW.hasSolidObject_PrimaryLocation], t[KTW.hasKitDesign_PartRefAndPose]
        unit_props = tuple((kind, t[p]) for kind, p in UNIT_PROPS.items())
        kinds: dict[tuple, tuple | None] = {}
        typed: dict[URIRef, tuple[frozenset[str], bool]] = {}  # individuals that are no geometry
        primary: dict[URIRef, Any] = {}
        units: dict[str, list[tuple]] = {kind: [] for kind in UNIT_PROPS}
        design_of = self.design_of
        rare = frozenset([design_p, *(p for _, p in unit_props)])
        for s, preds in self.spo.items():
            types = preds.get(a)
            if types is not None and isinstance(s, URIRef):
                key = tuple(types)
                kind = kinds.get(key, False)
                if kind is False:
                    own = [str(c) for c in key if str(c) in anc]
                    kind = kinds[key] = (frozenset().union(*(anc[c] for c in own)),
                                         any(anc[c] & _GEOMETRY for c in own)) if own else None
                if kind is not None and not kind[1]:  # (points, vectors, locations, shapes: not objects)
                    typed[s] = kind
                    loc = preds.get(primary_p)
                    if loc:
                        primary[s] = _first(loc)
            if rare.isdisjoint(preds):  # (one test instead of four for nearly every subject)
                continue
            for kind_name, prop in unit_props:
                named = preds.get(prop)
                if named:
                    units[kind_name].extend((s, o) for o in named)
            slots = preds.get(design_p)
            if slots:
                for prp in slots:
                    design_of.setdefault(prp, s)
        return typed, primary, units

    def read_units(self, found: dict[str, list[tuple]]) -> Units:
        """:func:`kb.model.units.read_units` of the file: each unit kitkb cannot convert, and a
        second unit of one kind, is a defect at the workstation's statement of it."""
        chosen: dict[str, str] = {}
        for kind, pairs in found.items():
            prop = UNIT_PROPS[kind]
            for ws, name in _grouped_by_object(pairs):
                text = str(name).strip().lower()
                at = (ws, prop, name)
                if unit_factor(kind, text) is None:
                    known = ", ".join(KINDS[kind])
                    self.defects.append(Defect(UNIT, f"{_local(ws)}: {kind} unit {str(name)!r} cannot be converted "
                                                     f"(kitkb knows {known})", ws, at, ((ws, "unit"),)))
                elif chosen.setdefault(kind, text) != text:
                    self.defects.append(Defect(UNIT, f"{_local(ws)}: {kind} unit {text!r} differs from "
                                                     f"{chosen[kind]!r} declared by another workstation of the same "
                                                     "state", ws, at, ((ws, "unit"),)))
        return Units(**{k: chosen.get(k, getattr(Units(), k)) for k in UNIT_PROPS})

    # --- poses ----------------------------------------------------------------------------
    def place(self, names: list, classes: list, index: dict, primary: dict, poses: np.ndarray,
              parents: np.ndarray) -> dict[int, Any]:
        """Global poses down the tree (the builder's ``place``). Returns object index -> its
        location for the objects a defect left unplaced (whose shapes are still read)."""
        get, t = self.spo.get, self.t
        ref_p, point_p, x_p, z_p = (t[p] for p in (KTW.hasPhysicalLocation_RefObject, KTW.hasPoseLocation_Point,
                                                  KTW.hasPoseLocation_XAxis, KTW.hasPoseLocation_ZAxis))
        rel_ref: dict[int, int | None] = {}
        rows: list[int] = []
        numbers: list[list[float]] = []
        located: dict[int, Any] = {}
        refs: list[tuple[int, Any, Any]] = []
        xyz, ijk = self.reading(_XYZ), self.reading(_IJK)
        for i, n in enumerate(names):
            loc = primary.get(n)
            if loc is None or _SOLID not in classes[i]:
                continue
            lp = get(loc) or {}
            ref = _first(lp.get(ref_p))
            if ref is n or (type(ref) is type(n) and str.__eq__(ref, n)):  # the world frame
                continue
            point = _first(lp.get(point_p))
            if point is None:
                continue
            located[i] = loc
            if ref is not None:
                refs.append((i, loc, ref))
            xa, za = _first(lp.get(x_p)), _first(lp.get(z_p))
            try:
                row = xyz(point)
                row += ijk(xa) if xa is not None else [1.0, 0.0, 0.0]
                row += ijk(za) if za is not None else [0.0, 0.0, 1.0]
            except _Failed as exc:
                self.defects.append(exc.defect)
                continue
            rel_ref[i] = index.get(ref) if ref is not None else None
            rows.append(i)
            numbers.append(row)
        for i in self.references(refs, index, located, primary):  # a reference the state does not place
            rel_ref.pop(i, None)
        m, zero, parallel = _frames(numbers)
        local: dict[int, np.ndarray] = {}
        bad = (zero | parallel).tolist()
        for n, i in enumerate(rows):
            if bad[n]:
                loc = located[i]
                self.defects.append(Defect(DEGENERATE_POSE, f"pose {_local(loc)}: {_degenerate(zero[n])}", loc, (loc,),
                                           (loc, _first(get(loc, {}).get(x_p)), _first(get(loc, {}).get(z_p)))))
            else:
                local[i] = m[n]
        placed = self.compose(names, {i: r for i, r in rel_ref.items() if i in local}, local, poses, parents)
        return {i: loc for i, loc in located.items() if i not in placed}

    def references(self, refs: list[tuple[int, Any, Any]], index: dict, located: dict, primary: dict) -> list[int]:
        """The objects (of ``refs``: object, its location, the location's reference object)
        whose reference object is neither an object the state places (one with a location
        that has a point, even one with a defect of its own) nor the world frame: an
        ``unknown-reference`` defect each, at the location's statement of it, in the builder's
        words (:func:`kb.spatial.scene.unknown_reference`)."""
        get, t = self.spo.get, self.t
        anc = class_ancestors()
        a, primary_p, ref_p = t[RDF.type], t[KTW.hasSolidObject_PrimaryLocation], t[KTW.hasPhysicalLocation_RefObject]
        out = []
        for i, loc, ref in refs:
            if index.get(ref) in located:
                continue
            preds = get(ref) or {}
            classes = [str(c) for c in preds.get(a, ()) if str(c) in anc]
            ref_loc = primary.get(ref)
            itself = ref_loc is not None and _first((get(ref_loc) or {}).get(ref_p)) == ref
            why = unknown_reference(bool(classes), classes, False, _local(ref_loc) if ref_loc is not None else None,
                                    itself)
            if not why:
                continue
            message = f"{_local(loc)}: its reference object {_local(ref)} {why}"
            self.defects.append(Defect(UNKNOWN_REFERENCE, message, loc, (loc, KTW.hasPhysicalLocation_RefObject, ref),
                                       ((loc, "refobject"), (ref, "primarylocation"), (ref_loc, "point"))))
            out.append(i)
        return out

    @np.errstate(over="ignore", invalid="ignore")  # NaN / infinite coordinates: no RuntimeWarning lines
    def compose(self, names: list, rel: dict, local: dict, poses: np.ndarray, parents: np.ndarray) -> set[int]:
        """``G = G_ref @ L`` down the tree, a level at a time; the objects placed. A reference
        cycle is found as the builder's recursion finds it (objects in name order)."""
        depth: dict[int, int] = {}
        failed: set[int] = set()
        for i in rel:
            path: list[int] = []
            j: int | None = i
            while j is not None and j in rel and j not in depth and j not in failed:
                ref = rel[j]
                if ref is not None and ref in path:
                    self.defects.append(Defect(
                        REFERENCE_CYCLE, f"{_local(names[j])}: its location refers back to itself through "
                                         f"{_local(names[ref])}", names[j], (names[j],)))
                    failed.update(path + [j])
                    break
                path.append(j)
                j = ref
            else:
                if j is not None and j in failed:
                    failed.update(path)
                    continue
                base = depth[j] if j is not None and j in depth else -1
                for q in reversed(path):
                    base += 1
                    depth[q] = base
        levels: dict[int, list[int]] = defaultdict(list)
        for i, d in depth.items():
            levels[d].append(i)
        for d in sorted(levels):
            members = levels[d]
            m = np.stack([local[i] for i in members])
            refs = [rel[i] for i in members]
            if d == 0:
                # no reference object: the location is global; a reference object that is not
                # placed stands at the origin (the builder multiplies by the identity)
                g = m.copy()
                has_ref = np.array([r is not None for r in refs])
                if has_ref.any():
                    g[has_ref] = np.matmul(np.eye(4), m[has_ref])
            else:
                g = np.matmul(poses[refs], m)
            poses[members] = g
            parents[members] = [r if r is not None and r in rel else -1 for r in refs]
        return set(depth)

    # --- shapes ---------------------------------------------------------------------------
    def shape(self, names: list, classes: list, index: dict, poses: np.ndarray, llo: np.ndarray, lhi: np.ndarray,
              open_top: np.ndarray, unplaced: dict) -> dict[Any, tuple | None]:
        """Local boxes (the builder's ``shape``) of the placed objects, and whether those a
        defect left unplaced have one; returns shape node -> its box (None: a defect)."""
        boxes: dict[Any, tuple | None] = {}
        lend: list[tuple[int, int]] = []
        nan = np.isnan(poses[:, 0, 0]).tolist()
        failed = set(unplaced)  # objects with a defect of their own (pose or shape)
        for i, n in enumerate(names):
            if nan[i] and i not in unplaced:
                continue
            box, broken = self.own_shape(n, classes[i], boxes)
            if box is not None:
                if not nan[i]:
                    llo[i], lhi[i], open_top[i] = box
                continue
            if broken:  # a shape with a defect: reported once, at the shape
                failed.add(i)
                continue
            stand = next((STAND_INS[c] for c in STAND_INS if c in classes[i]), None)
            other = self.value(n, stand) if stand is not None else None
            if other is not None and other in index:
                lend.append((i, index[other]))
                continue
            kinds = sorted(c[len(_KTW):] for c in classes[i] if c.startswith(_KTW))
            sku = self.value(n, _SKU)
            external = self.value(sku, _SKU_EXTERNAL) if sku is not None else None
            if external is None:
                external = self.value(n, _OWN_EXTERNAL)
            self.defects.append(Defect(NO_SHAPE, no_shape_message(_local(n), kinds, external is not None), n, (n,),
                                       ((n, "sku"), (n, "shape"), (sku, "shape"))))
            failed.add(i)
        for i, j in lend:  # a kit is where its tray is; a large box has its container's box
            if np.isnan(llo[j, 0]):
                if j not in failed:
                    self.defects.append(Defect(NO_SHAPE, f"{_local(names[i])} takes the box of {_local(names[j])}, "
                                                         "which has none", names[i], (names[i],), (names[j],)))
            elif not nan[i]:
                poses[i], llo[i], lhi[i], open_top[i] = poses[j], llo[j], lhi[j], open_top[j]
        return boxes

    def own_shape(self, n: Any, classes: frozenset[str], boxes: dict) -> tuple[tuple | None, bool]:
        """(``n``'s own box or None, whether its shape has a defect); each shape read once."""
        sku = self.value(n, _SKU)
        shape = self.value(sku, _SKU_SHAPE) if sku is not None else None
        if shape is None:
            shape = self.value(n, _OWN_SHAPE)
        if shape is not None:
            if shape not in boxes:
                boxes[shape] = self.shape_box(shape, n, sku if sku is not None and _first(
                    (self.spo.get(sku) or {}).get(self.t[_SKU_SHAPE])) is not None else n)
            return boxes[shape], boxes[shape] is None
        if _VACUUM in classes and self.value(n, _CUP[0]) is not None:
            try:
                d, h = self.number(n, _CUP[0]), self.number(n, _CUP[1])
            except _Failed as exc:
                self.defects.append(exc.defect)
                return None, True
            return (np.array([-d / 2, -d / 2, 0.0]), np.array([d / 2, d / 2, h]), False), False
        if _ROBOT in classes:
            return (np.zeros(3), np.zeros(3), False), False
        return None, False

    def shape_box(self, shape: Any, owner: Any, holder: Any = None) -> tuple | None:
        """(local lo, local hi, open on top) of a shape node of ``owner`` (``holder``: the SKU
        or object that names it); None after recording its defect."""
        top = self.value(shape, _TOPS[0])
        if top is None:
            top = self.value(shape, _TOPS[1])
        is_open = top is not None and str(top).lower() in ("false", "0")
        try:
            if self.value(shape, _BOXY[0]) is not None:
                length, width, height = (self.number(shape, p) for p in _BOXY)
                return np.array([-length / 2, -width / 2, 0.0]), np.array([length / 2, width / 2, height]), is_open
            if self.value(shape, _CYLINDER[0]) is not None:
                d, h = (self.number(shape, p) for p in _CYLINDER)
                return np.array([-d / 2, -d / 2, 0.0]), np.array([d / 2, d / 2, h]), is_open
        except _Failed as exc:
            self.defects.append(exc.defect)
            return None
        self.defects.append(Defect(NO_SHAPE, f"shape {_local(shape)} of {_local(owner)} is neither a BoxyShape nor a "
                                             "CylindricalShape with dimensions", shape, (shape,),
                                   (shape, (holder, "shape"))))
        return None

    def stand_in_facts(self, names: list, classes: list, index: dict) -> dict[str, set[tuple[str, str]]]:
        """The model facts :func:`kb.spatial.plausibility.check` reads: who lends a stand-in its box."""
        facts: dict[str, set[tuple[str, str]]] = {}
        for cls, prop in STAND_INS.items():
            key = self.t[prop]
            pairs = {(str(names[i]), str(o)) for i, cs in enumerate(classes) if cls in cs
                     for o in (self.spo.get(names[i]) or {}).get(key, ()) if o in index}
            if pairs:
                facts[str(prop)] = pairs
        return facts

    # --- kit designs --------------------------------------------------------------------------
    def slots(self, typed: dict, boxes: dict) -> tuple[dict[str, np.ndarray], Slots]:
        """Every slot's pose in its tray's frame (the builder's ``slots``: a number that is not
        a literal counts as 0, an axis left out as the default), and the slots of the kit
        designs whose part and tray have boxes."""
        get, t = self.spo.get, self.t
        point_p, x_p, z_p = (t[p] for p in (KTW.hasPartRefAndPose_Point, KTW.hasPartRefAndPose_XAxis,
                                            KTW.hasPartRefAndPose_ZAxis))
        names, numbers, axes = [], [], []
        xyz, ijk = self.slot_reading(_XYZ), self.slot_reading(_IJK)
        for n, (classes, _) in typed.items():
            if _PRP not in classes:
                continue
            preds = get(n) or {}
            point = _first(preds.get(point_p))
            if point is None:
                continue
            xa, za = _first(preds.get(x_p)), _first(preds.get(z_p))
            try:
                x = ijk(xa) if xa is not None else [1.0, 0.0, 0.0]
                z = ijk(za) if za is not None else [0.0, 0.0, 1.0]
                numbers.append(xyz(point) + x + z)
            except _Failed as exc:
                self.defects.append(exc.defect)
                continue
            names.append(n)
            axes.append((xa, za))
        m, zero, parallel = _frames(numbers)
        poses: dict[str, np.ndarray] = {}
        good = []
        bad = (zero | parallel).tolist()
        for k, n in enumerate(names):
            if bad[k]:
                self.defects.append(Defect(DEGENERATE_POSE, f"slot {_local(n)}: {_degenerate(zero[k])}", n, (n,),
                                           (n, *axes[k])))
            else:
                poses[str(n)] = m[k]
                good.append(n)
        return poses, self.design_slots(good, poses, boxes)

    def slot_reading(self, props: tuple) -> Callable[[Any], list[float]]:
        """:meth:`reading` as the builder reads a slot: a value that is not a literal is 0, one
        that is no usable number a defect."""
        get, done, t, scales = self.spo.get, self.converted, self.t, self.scales
        (k0, k1, k2), (s0, s1, s2) = (t[p] for p in props), (scales[p] for p in props)

        def read(node: Any) -> list[float]:
            try:  # three literals that are numbers, each converted once per file
                preds = get(node)
                v0, v1, v2 = next(iter(preds[k0])), next(iter(preds[k1])), next(iter(preds[k2]))  # type: ignore[index]
                if isinstance(v0, Literal) and isinstance(v1, Literal) and isinstance(v2, Literal):
                    x0, x1, x2 = done.get(id(v0)), done.get(id(v1)), done.get(id(v2))
                    if x0 is None:
                        x0 = done[id(v0)] = float(v0.toPython())
                    if x1 is None:
                        x1 = done[id(v1)] = float(v1.toPython())
                    if x2 is None:
                        x2 = done[id(v2)] = float(v2.toPython())
                    return [x0 * s0, x1 * s1, x2 * s2]
            except Exception:  # noqa: BLE001 - said precisely below
                pass
            return careful(node)

        def careful(node: Any) -> list[float]:
            preds = get(node) or {}
            out = []
            for p in props:
                v = _first(preds.get(t[p]))
                if not isinstance(v, Literal):
                    out.append(0.0)
                    continue
                x = done.get(id(v))
                if x is None:
                    try:
                        x = done[id(v)] = float(v.toPython())
                    except (TypeError, ValueError, OverflowError):  # not a number, or hundreds of digits
                        raise _Failed(Defect(BAD_NUMBER, f"{_local(node)}: {_local(p)} is not a usable number", node,
                                             (node,), (node,))) from None
                out.append(x * scales[p])
            return out
        return read

    def design_slots(self, names: list, poses: dict, boxes: dict) -> Slots:
        """The slots of the file's kit designs whose part SKU and tray SKU have a shape."""
        out = Slots()
        rows = []
        get, t = self.spo.get, self.t
        sku_p, tray_p = t[_PRP_SKU], t[_TRAY_SKU]
        sku_boxes: dict[Any, tuple | None] = {}
        for n in names:
            design = self.design_of.get(n)
            part_sku = _first((get(n) or {}).get(sku_p))
            tray_sku = _first((get(design) or {}).get(tray_p)) if design is not None else None
            for sku in (part_sku, tray_sku):
                if sku not in sku_boxes:
                    sku_boxes[sku] = self.sku_box(sku, boxes)
            part, tray = sku_boxes[part_sku], sku_boxes[tray_sku]
            if part is None or tray is None:
                continue
            out.names.append(str(n))
            out.design.append(str(design))
            out.part_sku.append(str(part_sku))
            out.tray_sku.append(str(tray_sku))
            rows.append((poses[str(n)], part, tray))
            out.nodes.append((n, design, part_sku, tray_sku, part[3], tray[3]))
        if rows:
            out.pose = np.stack([r[0] for r in rows])
            out.part_lo, out.part_hi = np.stack([r[1][0] for r in rows]), np.stack([r[1][1] for r in rows])
            out.tray_lo, out.tray_hi = np.stack([r[2][0] for r in rows]), np.stack([r[2][1] for r in rows])
        return out

    def sku_box(self, sku: Any, boxes: dict) -> tuple | None:
        """(lo, hi, open, shape) of a SKU's internal shape; None when it has none (or a defect)."""
        shape = self.value(sku, _SKU_SHAPE) if sku is not None else None
        if shape is None:
            return None
        if shape not in boxes:
            before = len(self.defects)
            boxes[shape] = self.shape_box(shape, sku)
            del self.defects[before:]  # a shape no placed object has: SHACL says what is wrong with it
        box = boxes[shape]
        return (*box, shape) if box is not None else None


def _grouped_by_object(pairs: list[tuple]) -> list[tuple]:
    """(subject, object) pairs grouped by object in the order objects first appear (the order
    a :class:`kb.io.views.TripleView` lists ``subject_objects``)."""
    by: dict[Any, list] = {}
    for s, o in pairs:
        by.setdefault(o, []).append(s)
    return [(s, o) for o, subjects in by.items() for s in subjects]


def _degenerate(zero: bool) -> str:
    """The words of :func:`kb.spatial.transforms.pose_matrix`'s ValueError."""
    return "an axis of the pose has length zero" if zero else "the x and z axes of the pose are parallel"


@np.errstate(over="ignore", invalid="ignore", divide="ignore")
def _frames(rows: list[list[float]]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`kb.spatial.transforms.pose_matrix` of each row (point, x axis, z axis) at once,
    with the same arithmetic: (N, 4, 4) matrices, and where an axis has length zero or the
    axes are parallel (those matrices are not to be used)."""
    if not rows:
        return np.zeros((0, 4, 4)), np.zeros(0, bool), np.zeros(0, bool)
    a = np.array(rows, dtype=float)
    p, x, z = a[:, 0:3], a[:, 3:6], a[:, 6:9]
    nz = np.sqrt(z[:, 0] * z[:, 0] + z[:, 1] * z[:, 1] + z[:, 2] * z[:, 2])
    nx0 = np.sqrt(x[:, 0] * x[:, 0] + x[:, 1] * x[:, 1] + x[:, 2] * x[:, 2])
    zero = (nz < _EPS) | (nx0 < _EPS)
    z = z / nz[:, None]
    d = x[:, 0] * z[:, 0] + x[:, 1] * z[:, 1] + x[:, 2] * z[:, 2]
    x = x - d[:, None] * z
    nx = np.sqrt(x[:, 0] * x[:, 0] + x[:, 1] * x[:, 1] + x[:, 2] * x[:, 2])
    parallel = ~zero & (nx < _EPS)
    x = x / nx[:, None]
    y = np.stack([z[:, 1] * x[:, 2] - z[:, 2] * x[:, 1], z[:, 2] * x[:, 0] - z[:, 0] * x[:, 2],
                  z[:, 0] * x[:, 1] - z[:, 1] * x[:, 0]], axis=1)
    m = np.zeros((len(rows), 4, 4))
    m[:, :3, 0], m[:, :3, 1], m[:, :3, 2], m[:, :3, 3], m[:, 3, 3] = x, y, z, p, 1.0
    return m, zero, parallel


__all__ = ["Defect", "RULES", "Slots", "Survey", "no_shape_message", "survey"]
