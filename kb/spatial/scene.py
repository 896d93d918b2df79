"""A scene: the objects of one workstation state, their classes, model facts and world boxes.

What the predicates are evaluated on. Built from a state file (:meth:`Scene.from_files`) or
by a simulator from its ground truth (:meth:`Scene.from_parts`).

Geometry, as the kitting model states it:

* every placed object has a ``PoseLocation`` (point, x axis, z axis) in the frame of its
  reference object; its global pose is the chain of these poses down the transformation tree
  (``G = G_ref @ L``, :mod:`kb.spatial.transforms`). The object whose location refers to itself
  (the kitting workstation), or a kitting workstation with no location, is the world frame: it
  is not a solid in the scene. Any other reference object must be an object the state places:
  one that is not (a name no file of the state declares, a SKU, a solid with no location or with
  a relative location, which has no point) is an :class:`~kb.core.errors.InputError` at the
  location's statement of it (:func:`unknown_reference` says why), never the world frame;
* a shape is the ``InternalShape`` of the object's SKU, else its own
  (``hasNoSkuObject_InternalShape``): a ``BoxyShape`` (length along x, width along y, height
  along z, frame in the middle of the bottom) or a ``CylindricalShape`` (by its bounding box).
  Where the model has no shape: a vacuum effector is a cylinder of its cup diameter and length;
  a robot is its tool point (the pose of a ``Robot`` is its tool flange, as in NIST's files);
  a kit is where its kit tray is and has its tray's box; a large box with kits or with empty
  kit trays has the box of its large container, a changing station the box of its base. Any other placed object with no shape is an
  :class:`~kb.core.errors.InputError` naming it;
* an object's box in the world is the axis-aligned box of its oriented local box
  (:func:`kb.spatial.rcc8.world_boxes`).

Units: a scene is always in SI (metres, radians, kilograms), whatever the units the
workstation declares (``hasKittingWorkstation_LengthUnit`` etc.): every value of a data
property the kitting model annotates with a ``ktw:quantityKind`` (points, vectors' lengths are
unitless, shapes, cup diameters, weights) is converted when the file is read, and
:attr:`Scene.units` keeps the file's units for what goes back to it (database poses, reports).
A unit kitkb cannot convert is an :class:`~kb.core.errors.InputError` at its line.

Objects with no pose (declared in another state file only, such as NIST's kits, which first
appear in the goal; or individuals that are not solids: SKUs, designs) are in the scene for
the non-spatial atoms and have no box (``placed`` is False): spatial atoms are false for them.
"""

from __future__ import annotations

from collections import defaultdict
from dataclasses import dataclass, field
from decimal import Decimal
from functools import lru_cache
from pathlib import Path
from typing import Iterable, Sequence

import numpy as np
from rdflib import Literal, URIRef
from rdflib.namespace import OWL, RDF, RDFS

from kb.core.errors import InputError
from kb.core.namespaces import KTW
from kb.core.resources import ontology_path
from kb.core.units import SI, Units
from kb.io import load, load_file
from kb.io.loader import Source, extension_classes
from kb.io.views import TripleView
from kb.model.units import quantity_kinds, read_units
from kb.spatial.rcc8 import world_boxes
from kb.spatial.transforms import pose_matrix

_KTW = str(KTW)
SOLID = str(KTW.SolidObject)
_POSE_PROPS = (KTW.hasPoseLocation_Point, KTW.hasPoseLocation_XAxis, KTW.hasPoseLocation_ZAxis)
_XYZ = (KTW.hasPoint_X, KTW.hasPoint_Y, KTW.hasPoint_Z)
_IJK = (KTW.hasVector_I, KTW.hasVector_J, KTW.hasVector_K)
_PRIMARY, _REF = KTW.hasSolidObject_PrimaryLocation, KTW.hasPhysicalLocation_RefObject
#: classes of the geometry vocabulary (points, vectors, locations, shapes): not objects of the scene
_GEOMETRY = tuple(str(c) for c in (KTW.Point, KTW.Vector, KTW.PhysicalLocation, KTW.ShapeDesign, KTW.BoxVolume))
#: object class -> the property whose value lends it its box (when it has no shape of its own)
STAND_INS = {
    str(KTW.Kit): KTW.hasKit_KitTray,
    str(KTW.LargeBoxWithKits): KTW.hasLargeBoxWithKits_LargeContainer,
    str(KTW.LargeBoxWithEmptyKitTrays): KTW.hasLargeBoxWithEmptyKitTrays_LargeContainer,
    str(KTW.EndEffectorChangingStation): KTW.hasEndEffectorChangingStation_Base,
}


def class_ancestors() -> dict[str, frozenset[str]]:
    """Each class of the shipped kitting model, and each class of objects the loaded domain
    declares under one (:func:`kb.io.loader.extension_classes`) -> itself and its named
    ancestors."""
    extra = extension_classes()
    return _ancestors(tuple(sorted(extra.items())) if extra else ())


@lru_cache(maxsize=4)
def _ancestors(extra: tuple[tuple[str, frozenset[str]], ...]) -> dict[str, frozenset[str]]:
    view = load_file(ontology_path("kitting.ttl")).view()
    parents: dict[str, set[str]] = defaultdict(set)
    classes = {str(c) for c in view.subjects(RDF.type, OWL.Class) if isinstance(c, URIRef)}
    for c, p in view.subject_objects(RDFS.subClassOf):
        if isinstance(c, URIRef) and isinstance(p, URIRef):
            parents[str(c)].add(str(p))
    for c, ps in extra:  # an extension's class counts where it descends from a class of the model
        parents[c].update(ps)
    out: dict[str, frozenset[str]] = {}

    def up(c: str) -> frozenset[str]:
        if c not in out:
            out[c] = frozenset({c})  # cycle guard
            out[c] = frozenset({c}).union(*(up(p) for p in parents.get(c, ())))
        return out[c]
    for c in classes:
        up(c)
    model = dict(out)
    for c, _ps in extra:
        if up(c) & classes:
            model[c] = out[c]
    return model


@dataclass
class Scene:
    """Objects (IRIs), their classes, model facts, and world boxes of the placed ones."""

    names: list[str]
    classes: list[frozenset[str]]
    lo: np.ndarray  # (K, 3) world box minima; NaN where not placed
    hi: np.ndarray
    facts: dict[str, set[tuple[str, str]]]  # property IRI -> (subject IRI, object IRI) pairs
    values: dict[str, dict[str, object]] = field(default_factory=dict)  # data property -> subject -> value
    inspections: dict[str, set[str]] = field(default_factory=dict)  # check name -> objects that passed
    poses: np.ndarray | None = None  # (K, 4, 4) global poses (NaN where not placed)
    path: str | None = None
    #: (K,) index of each object's reference object (-1: the world frame or not placed)
    parents: np.ndarray | None = None
    #: (K, 3) local box corners in each object's own frame (NaN where it has no shape)
    local_lo: np.ndarray | None = None
    local_hi: np.ndarray | None = None
    #: (K,) True for an open container (a shape with ``HasTop`` false: trays, large boxes)
    open_top: np.ndarray | None = None
    #: a kit design's slot (``PartRefAndPose`` IRI) -> its pose in the kit tray's frame
    slots: dict[str, np.ndarray] = field(default_factory=dict)
    #: the units of the file the scene was read from (its numbers are SI: metres, radians, kg)
    units: Units = SI

    def __post_init__(self) -> None:
        k = len(self.names)
        if self.parents is None:
            self.parents = np.full(k, -1, np.int64)
        if self.open_top is None:
            self.open_top = np.zeros(k, bool)
        self.index = {n: i for i, n in enumerate(self.names)}
        self.placed = ~np.isnan(self.lo[:, 0]) if len(self.names) else np.zeros(0, bool)
        self._of: dict[str, np.ndarray] = {}
        self._pairs: dict[str, dict[str, list[str]]] = {}
        #: the loaded file ``path`` was read from (:meth:`from_sources`), for what else is read
        #: of it without parsing it again (a robot's work volumes); None otherwise
        self.source: Source | None = None

    def __len__(self) -> int:
        return len(self.names)

    def of_class(self, cls: str) -> np.ndarray:
        """Indices of the objects of class ``cls`` (directly or by a subclass), in name order."""
        if cls not in self._of:
            self._of[cls] = np.array([i for i, c in enumerate(self.classes) if cls in c], dtype=np.int64)
        return self._of[cls]

    def related(self, prop: str) -> dict[str, list[str]]:
        """subject -> objects of the model property ``prop``."""
        if prop not in self._pairs:
            out: dict[str, list[str]] = defaultdict(list)
            for s, o in self.facts.get(prop, ()):
                out[s].append(o)
            self._pairs[prop] = dict(out)
        return self._pairs[prop]

    def value(self, prop: str, subject: str) -> object | None:
        """The data property value of ``subject`` (None when absent)."""
        return self.values.get(prop, {}).get(subject)

    # --- construction -------------------------------------------------------------
    @classmethod
    def from_files(cls, paths: Sequence[str | Path], declared: Sequence[str | Path | Source] = (),
                   match_names: bool = False) -> "Scene":
        """The scene of a state given as one or more files; ``declared`` files (e.g. the goal
        state for an initial state) add the individuals they alone state, with their model
        facts but no geometry (as the PDDL generator reads objects that first appear in the
        goal). ``match_names``: an individual of a declared file is the state's individual of
        the same local name (NIST names its initial and goal states in two namespaces)."""
        return cls.from_sources(load(list(paths), resolve_imports=False).sources, declared, match_names)

    @classmethod
    def from_sources(cls, sources: Sequence[Source], declared: Sequence[str | Path | Source] = (),
                     match_names: bool = False) -> "Scene":
        """:meth:`from_files` of files already loaded (:class:`kb.io.loader.Source`: e.g. the
        validator's, so a file is not parsed twice)."""
        views = [s.view() for s in sources]
        extra = [(p if isinstance(p, Source) else load_file(p)).view() for p in declared]
        if match_names and extra:
            extra = [_renamed(v, views) for v in extra]
        path = str(sources[0].path)
        locate = sources[0].line_of if len(sources) == 1 else (lambda *a: None)
        scene = _Builder(views, extra, path, locate).build()
        scene.source = sources[0] if len(sources) == 1 else None
        return scene

    @classmethod
    def from_parts(cls, names: list[str], classes: list[Iterable[str]], poses: np.ndarray, local_lo: np.ndarray,
                   local_hi: np.ndarray, facts: dict[str, set[tuple[str, str]]] | None = None,
                   values: dict[str, dict[str, object]] | None = None,
                   inspections: dict[str, set[str]] | None = None, parents: np.ndarray | None = None,
                   open_top: np.ndarray | None = None) -> "Scene":
        """A scene from global poses (K, 4, 4) and local boxes (K, 3) — NaN rows for objects
        with no geometry — e.g. a simulator's ground truth. ``classes`` are asserted classes;
        their ancestors are added from the kitting model."""
        anc = class_ancestors()
        closed = [frozenset().union(*(anc.get(c, frozenset({c})) for c in cs)) for cs in classes]
        poses, local_lo, local_hi = (np.asarray(a, float) for a in (poses, local_lo, local_hi))
        lo, hi = _boxes(poses, local_lo, local_hi)
        return cls(list(names), closed, lo, hi, facts or {}, values or {}, inspections or {}, poses, None,
                   parents, local_lo, local_hi, open_top)


def _renamed(view, like: list) -> TripleView:  # noqa: ANN001
    """``view``'s triples with individuals renamed to those of ``like`` with the same local name."""
    known = {_local(s): s for v in like for s in v.subjects(RDF.type) if isinstance(s, URIRef)}
    alias = {}
    for s in view.subjects(RDF.type):
        if isinstance(s, URIRef) and _local(s) in known and known[_local(s)] != s:
            alias[s] = known[_local(s)]
    if not alias:
        return view
    return TripleView((alias.get(s, s), p, alias.get(o, o)) for s, p, o in view.triples((None, None, None)))


def scene_boxes(poses: np.ndarray, llo: np.ndarray, lhi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """World boxes (K, 3) lo, hi of objects with global poses (K, 4, 4) and local boxes; NaN
    rows where either is missing."""
    return _boxes(poses, llo, lhi)


def _boxes(poses: np.ndarray, llo: np.ndarray, lhi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    k = len(poses)
    lo, hi = np.full((k, 3), np.nan), np.full((k, 3), np.nan)
    ok = ~(np.isnan(llo).any(axis=1) | np.isnan(poses.reshape(k, -1)).any(axis=1)) if k else np.zeros(0, bool)
    if ok.any():
        lo[ok], hi[ok] = world_boxes(poses[ok], llo[ok], lhi[ok])
    return lo, hi


class _Builder:
    """Reads a state file's triples into a :class:`Scene`."""

    def __init__(self, views: list, extra: list, path: str, locate) -> None:  # noqa: ANN001
        self.views, self.extra, self.path, self.locate = views, extra, path, locate
        self.units = read_units(views, path, locate)
        kinds = quantity_kinds()
        #: data property -> SI per file unit, for the properties that hold a quantity
        self.scale = {p: self.units.factor(k) for p, k in kinds.items()}

    def value(self, s, p, everywhere: bool = False):  # noqa: ANN001, ANN201
        """The value of (s, p) in the state's files (with ``everywhere``, also the declared ones)."""
        for v in (self.views + self.extra) if everywhere else self.views:
            x = v.value(s, p)
            if x is not None:
                return x
        return None

    def build(self) -> Scene:
        anc = class_ancestors()
        asserted: dict[URIRef, set[str]] = defaultdict(set)
        own: set[URIRef] = set()
        for i, view in enumerate(self.views + self.extra):
            for s, c in view.subject_objects(RDF.type):
                cs = str(c)
                if isinstance(s, URIRef) and cs in anc:
                    if i < len(self.views):
                        own.add(s)
                    elif s in own:
                        continue
                    asserted[s].add(cs)
        geometry = set(_GEOMETRY)
        names = sorted((n for n in asserted if not any(anc[c] & geometry for c in asserted[n])), key=str)
        classes = [frozenset().union(*(anc[c] for c in asserted[n])) for n in names]
        facts, values = self.facts(set(names))
        k = len(names)
        poses = np.full((k, 4, 4), np.nan)
        llo, lhi = np.full((k, 3), np.nan), np.full((k, 3), np.nan)
        index = {n: i for i, n in enumerate(names)}
        parents = np.full(k, -1, np.int64)
        open_top = np.zeros(k, bool)
        self.place(names, classes, own, index, poses, parents, asserted)
        self.shape(names, classes, index, poses, llo, lhi, open_top)
        lo, hi = _boxes(poses, llo, lhi)
        return Scene([str(n) for n in names], classes, lo, hi, facts, values, {}, poses, self.path, parents,
                     llo, lhi, open_top, self.slots(asserted), self.units)

    def slots(self, asserted: dict) -> dict[str, np.ndarray]:
        """Kit design slots: PartRefAndPose -> its pose (point, x and z axes) in the kit tray's frame."""
        prp = str(KTW.PartRefAndPose)
        out = {}

        def num(node, prop) -> float:  # noqa: ANN001
            v = self.value(node, prop, everywhere=True)
            if not isinstance(v, Literal):
                return 0.0
            try:
                return float(v.toPython()) * self.scale.get(str(prop), 1.0)
            except (TypeError, ValueError, OverflowError):  # not a number, or hundreds of digits
                raise InputError(f"{_local(node)}: {_local(prop)} is not a usable number", self.path,
                                 self.locate(node)) from None
        for n, cs in asserted.items():
            point = self.value(n, KTW.hasPartRefAndPose_Point, everywhere=True) if prp in cs else None
            if point is None:
                continue
            xa = self.value(n, KTW.hasPartRefAndPose_XAxis, everywhere=True)
            za = self.value(n, KTW.hasPartRefAndPose_ZAxis, everywhere=True)
            x = [num(xa, q) for q in _IJK] if xa is not None else [1.0, 0.0, 0.0]
            z = [num(za, q) for q in _IJK] if za is not None else [0.0, 0.0, 1.0]
            try:
                out[str(n)] = pose_matrix([num(point, q) for q in _XYZ], x, z)
            except ValueError as e:
                raise InputError(f"slot {_local(n)}: {e}", self.path, self.locate(n)) from None
        return out

    def facts(self, individuals: set) -> tuple[dict, dict]:
        facts: dict[str, set] = defaultdict(set)
        values: dict[str, dict] = defaultdict(dict)
        skip = {RDF.type}
        for view in self.views + self.extra:
            for s, p, o in view.triples((None, None, None)):
                if s not in individuals or p in skip:
                    continue
                if o in individuals:
                    facts[str(p)].add((str(s), str(o)))
                elif isinstance(o, Literal):
                    values[str(p)].setdefault(str(s), self.quantity(str(p), o.toPython()))
        return dict(facts), dict(values)

    def quantity(self, prop: str, v: object) -> object:
        """A literal's value, in SI where ``prop`` holds a quantity."""
        factor = self.scale.get(prop)
        if factor is None or factor == 1.0 or isinstance(v, bool) or not isinstance(v, (int, float, Decimal)):
            return v
        return float(v) * factor

    # --- poses ----------------------------------------------------------------------
    def local(self, loc) -> np.ndarray | None:  # noqa: ANN001
        point, xa, za = (self.value(loc, p) for p in _POSE_PROPS)
        if point is None:
            return None
        p = [self.number(point, q) for q in _XYZ]
        x = [self.number(xa, q) for q in _IJK] if xa else [1, 0, 0]
        z = [self.number(za, q) for q in _IJK] if za else [0, 0, 1]
        try:
            return pose_matrix(p, x, z)
        except ValueError as e:
            raise InputError(f"pose {_local(loc)}: {e}", self.path, self.locate(loc)) from None

    def number(self, node, prop) -> float:  # noqa: ANN001
        v = self.value(node, prop)
        if v is None:
            raise InputError(f"{_local(node)} has no {_local(prop)}", self.path, self.locate(node))
        try:
            return float(v.toPython() if isinstance(v, Literal) else v) * self.scale.get(str(prop), 1.0)
        except (TypeError, ValueError):
            raise InputError(f"{_local(node)}: {_local(prop)} is not a number: {v}", self.path,
                             self.locate(node)) from None
        except OverflowError:  # an xsd:integer of hundreds of digits
            raise InputError(f"{_local(node)}: {_local(prop)} is too large ({len(str(v))} digits)", self.path,
                             self.locate(node)) from None

    @np.errstate(over="ignore", invalid="ignore")  # NaN / infinite coordinates: no RuntimeWarning lines
    def place(self, names, classes, own, index, poses, parents, asserted) -> None:  # noqa: ANN001
        """Global poses of the placed objects of the state file, level by level down the tree.
        A reference object that is not an object the state places (nor the world frame) is an
        InputError at the location's statement of it (:func:`unknown_reference`)."""
        rel: dict[int, tuple[int | None, np.ndarray]] = {}
        refs: dict[int, tuple] = {}
        for i, n in enumerate(names):
            if n not in own or SOLID not in classes[i]:
                continue
            loc = self.value(n, _PRIMARY)
            if loc is None:
                continue
            ref = self.value(loc, _REF)
            if ref == n:  # the world frame
                continue
            m = self.local(loc)
            if m is None:
                continue
            rel[i] = (index.get(ref) if ref is not None else None, m)
            if ref is not None:
                refs[i] = (loc, ref)
        for i, (loc, ref) in refs.items():  # each reference: an object the state places, or the world frame
            j = index.get(ref)
            if j is not None and j in rel:
                continue
            ref_loc = self.value(ref, _PRIMARY)
            why = unknown_reference(ref in own, asserted.get(ref, ()) if ref in own else (), False,
                                    _local(ref_loc) if ref_loc is not None else None, self.refers_to_itself(ref))
            if why:
                raise InputError(f"{_local(loc)}: its reference object {_local(ref)} {why}", self.path,
                                 self.locate(loc, _REF, ref))
        done: dict[int, np.ndarray | None] = {}

        def glob(i: int, trail: tuple) -> np.ndarray | None:
            if i in done:
                return done[i]
            if i not in rel:
                return np.eye(4)  # the world frame (its location refers to itself, or a workstation with none)
            ref, m = rel[i]
            if ref is None:
                g = m
            elif ref in trail:
                raise InputError(f"{_local(names[i])}: its location refers back to itself through "
                                 f"{_local(names[ref])}", self.path, self.locate(names[i]))
            else:
                parent = glob(ref, trail + (i,))
                g = parent @ m if parent is not None else None
            done[i] = g
            return g
        for i in rel:
            g = glob(i, ())
            if g is not None:
                poses[i] = g
                parents[i] = rel[i][0] if rel[i][0] is not None and rel[i][0] in rel else -1

    def refers_to_itself(self, n) -> bool:  # noqa: ANN001
        """Whether ``n``'s location refers to ``n`` itself (the world frame)."""
        loc = self.value(n, _PRIMARY)
        return loc is not None and self.value(loc, _REF) == n

    # --- shapes ---------------------------------------------------------------------
    def shape(self, names, classes, index, poses, llo, lhi, open_top) -> None:  # noqa: ANN001
        lend: list[tuple[int, int]] = []
        for i, n in enumerate(names):
            if np.isnan(poses[i, 0, 0]):
                continue
            box = self.own_shape(n, classes[i])
            if box is not None:
                llo[i], lhi[i], open_top[i] = box
                continue
            stand = next((STAND_INS[c] for c in STAND_INS if c in classes[i]), None)
            other = self.value(n, stand) if stand is not None else None
            if other is not None and other in index:
                lend.append((i, index[other]))
                continue
            kinds = sorted(c[len(_KTW):] for c in classes[i] if c.startswith(_KTW))
            sku = self.value(n, KTW.hasSkuObject_Sku)  # an ExternalShape is named (validate: the same words)
            external = (self.value(sku, KTW.hasStockKeepingUnit_ExternalShape) if sku is not None else None) \
                or self.value(n, KTW.hasNoSkuObject_ExternalShape)
            raise InputError(f"{_local(n)} is placed but has no shape: no InternalShape on its SKU or itself"
                             f"{' (an ExternalShape is a model file kitkb does not read)' if external else ''}, "
                             f"and no rule gives one to a {' / '.join(kinds[:3])}", self.path, self.locate(n))
        for i, j in lend:  # a kit is where its tray is; a large box has its container's box
            if np.isnan(llo[j, 0]):
                raise InputError(f"{_local(names[i])} takes the box of {_local(names[j])}, which has none",
                                 self.path, self.locate(names[i]))
            poses[i], llo[i], lhi[i], open_top[i] = poses[j], llo[j], lhi[j], open_top[j]

    def own_shape(self, n, classes) -> tuple[np.ndarray, np.ndarray, bool] | None:  # noqa: ANN001
        """(local lo, local hi, open on top) of ``n``'s own shape, or None."""
        sku = self.value(n, KTW.hasSkuObject_Sku)
        shape = self.value(sku, KTW.hasStockKeepingUnit_InternalShape) if sku is not None else None
        if shape is None:
            shape = self.value(n, KTW.hasNoSkuObject_InternalShape)
        if shape is not None:
            top = self.value(shape, KTW.hasBoxyShape_HasTop)
            if top is None:
                top = self.value(shape, KTW.hasCylindricalShape_HasTop)
            is_open = top is not None and str(top).lower() in ("false", "0")
            if self.value(shape, KTW.hasBoxyShape_Length) is not None:
                length, width, height = (self.number(shape, p) for p in (
                    KTW.hasBoxyShape_Length, KTW.hasBoxyShape_Width, KTW.hasBoxyShape_Height))
                return np.array([-length / 2, -width / 2, 0.0]), np.array([length / 2, width / 2, height]), is_open
            if self.value(shape, KTW.hasCylindricalShape_Diameter) is not None:
                d, h = (self.number(shape, p) for p in (KTW.hasCylindricalShape_Diameter,
                                                        KTW.hasCylindricalShape_Height))
                return np.array([-d / 2, -d / 2, 0.0]), np.array([d / 2, d / 2, h]), is_open
            raise InputError(f"shape {_local(shape)} of {_local(n)} is neither a BoxyShape nor a CylindricalShape "
                             "with dimensions", self.path, self.locate(shape))
        if str(KTW.VacuumEffector) in classes and self.value(n, KTW.hasVacuumEffector_CupDiameter) is not None:
            d = self.number(n, KTW.hasVacuumEffector_CupDiameter)
            h = self.number(n, KTW.hasVacuumEffector_Length)
            return np.array([-d / 2, -d / 2, 0.0]), np.array([d / 2, d / 2, h]), False
        if str(KTW.Robot) in classes:
            return np.zeros(3), np.zeros(3), False
        return None


#: the classes whose object is the world frame when it is not placed (it has no location)
_WORLD = str(KTW.KittingWorkstation)


def unknown_reference(declared: bool, classes: Iterable[str], placed: bool, location: str | None,
                      itself: bool) -> str:
    """Why a location's reference object cannot be its frame, or ``""`` when it can: it is an
    object the state places (``placed``: a solid object with a location that has a point), or
    the world frame — an object whose location refers to itself (``itself``), or a kitting
    workstation with no location (``location``: the name of its primary location, None when it
    has none). ``declared``: the reference is typed with a class of the kitting model in the
    state's files; ``classes``: those classes, as asserted. The words of
    :mod:`kb.spatial.survey`'s ``unknown-reference`` defect too (docs/validation.md, "Geometry of
    state files")."""
    if placed or itself:
        return ""
    anc = class_ancestors()
    closed = frozenset().union(*(anc.get(c, frozenset()) for c in classes))
    if not declared or not closed:
        return ("is not an object of the state: none of its files declares it with a class of the kitting model "
                "(a misspelt name, or an individual of another file)")
    if SOLID not in closed:
        kinds = sorted(c[len(_KTW):] for c in classes if c.startswith(_KTW))
        return f"is not a solid object: it is a {' / '.join(kinds[:3])}"
    if _WORLD in closed and location is None:
        return ""
    return "is not placed by the state: " + (f"its location {location} has no point" if location else "it has no location")


def _local(node) -> str:  # noqa: ANN001
    return str(node).rsplit("#", 1)[-1].rsplit("/", 1)[-1]
