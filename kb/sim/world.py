"""Ground truth of the simulated cell: every object of a state, where it really is.

Built from a :class:`~kb.spatial.scene.Scene` (usually ``Scene.from_files([init])``): names,
classes, global poses, local boxes, parents (what an object rests in or on, or is attached
to), ``open_top``, and the model facts and values of the file. Children move with their parent
(:meth:`World.set_pose` moves a whole subtree rigidly): parts in a kit tray move with the tray,
a held object with the end effector, a mounted end effector with the robot's tool flange.

Objects whose box the scene lends from another object (a kit takes its kit tray's, a large box
with kits its container's, a changing station its base's: :data:`kb.spatial.scene.STAND_INS`)
are *stand-ins*: they are never a support or a grasp target themselves, and move as the parent
of the object that lends them its box.

Support, holders and grasps compare footprints in the frame of the support / holder / grasped
object (the world turned about z by its heading, :meth:`World.boxes_in_frames`), so a turned
tray holds what lies in it, not what lies in its world box (docs/soap.md, "Orientation").

:meth:`World.to_scene` is the ground truth as a scene, with ``inspections`` =
``{"quality-inspection": parts inspected so far that passed}``.

Limits of the robot (the checks of :mod:`kb.sim.robot`), in SI whatever the file's units
(:mod:`kb.spatial.scene` converts the model's quantities when it reads them): weights from
the model's values (:meth:`World.weight` of an object and what moves with it, from its SKU's
``hasStockKeepingUnit_Weight``; :meth:`World.number` of ``hasRobot_MaximumLoadWeight``,
``hasEndEffector_MaximumLoadWeight``, ``hasEndEffector_Weight``), and each robot's work
volume (``hasRobot_WorkVolume``, a ``BoxVolume`` whose minimum and maximum points are in the
workstation's frame), which the scene does not keep (points are geometry, not objects): it is
read from the scene's state file (:func:`work_volumes`). What a file does not state is None:
that check is not made.
"""

from __future__ import annotations

import copy
import math
import os
from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np
from rdflib import Literal, URIRef

from kb.core.errors import InputError
from kb.core.namespaces import KTW, local_name
from kb.core.units import Units
from kb.spatial.rcc8 import DEFAULT_TOLERANCE, HEADING_MERGE, depth_tolerance, frame_boxes, headings, world_boxes
from kb.spatial.scene import STAND_INS, Scene
from kb.spatial.transforms import invert

QUALITY = "quality-inspection"
SKU = str(KTW.hasSkuObject_Sku)
SKU_EFFECTOR = str(KTW.hasStockKeepingUnit_EndEffector)
KIT_TRAY = str(KTW.hasKit_KitTray)
SKU_WEIGHT = str(KTW.hasStockKeepingUnit_Weight)
ROBOT_LOAD = str(KTW.hasRobot_MaximumLoadWeight)
EFFECTOR_LOAD = str(KTW.hasEndEffector_MaximumLoadWeight)
EFFECTOR_WEIGHT = str(KTW.hasEndEffector_Weight)
HOLDER_EFFECTOR = str(KTW.hasEndEffectorHolder_EndEffector)
#: How far (metres) a face may be from where it should be and still count as there.
TOLERANCE = DEFAULT_TOLERANCE


def _snapped(yaw: np.ndarray) -> np.ndarray:
    """Headings within :data:`~kb.spatial.rcc8.HEADING_MERGE` of 0 as exactly 0 (the world
    frame: the world boxes, bit for bit), NaN as 0."""
    return np.where(np.isnan(yaw) | (np.abs(yaw) <= HEADING_MERGE), 0.0, yaw)


def translate(x: float, y: float, z: float) -> np.ndarray:
    """The 4x4 translation by (x, y, z)."""
    m = np.eye(4)
    m[:3, 3] = (x, y, z)
    return m


@dataclass
class World:
    """Mutable ground truth: one row per object of the state (placed or not)."""

    names: list[str]
    classes: list[frozenset[str]]
    poses: np.ndarray  # (K, 4, 4) global poses; NaN where not placed (or removed)
    local_lo: np.ndarray  # (K, 3) local box corners; NaN where no shape
    local_hi: np.ndarray
    parent: np.ndarray  # (K,) index of what the object rests in / on / is attached to; -1: the world
    open_top: np.ndarray  # (K,) bool
    facts: dict[str, set[tuple[str, str]]]
    values: dict[str, dict[str, object]]
    passed: set[str] = field(default_factory=set)  # parts that passed a quality inspection
    defective: set[str] = field(default_factory=set)  # parts a quality inspection rejects
    #: robot IRI -> (lo, hi) of each of its work volumes in the workstation's frame (m)
    work_volumes: dict[str, list[tuple[np.ndarray, np.ndarray]]] = field(default_factory=dict)

    def __post_init__(self) -> None:
        self.index = {n: i for i, n in enumerate(self.names)}

    @classmethod
    def from_scene(cls, scene: Scene) -> "World":
        """The ground truth of a scene (copied: the scene is not changed)."""
        k = len(scene.names)
        poses = np.array(scene.poses, float) if scene.poses is not None else np.full((k, 4, 4), np.nan)
        llo = np.array(scene.local_lo, float) if scene.local_lo is not None else np.full((k, 3), np.nan)
        lhi = np.array(scene.local_hi, float) if scene.local_hi is not None else np.full((k, 3), np.nan)
        world = cls(list(scene.names), list(scene.classes), poses, llo, lhi, np.array(scene.parents, np.int64),
                    np.array(scene.open_top, bool), copy.deepcopy(scene.facts), copy.deepcopy(scene.values),
                    set(scene.inspections.get(QUALITY, ())), work_volumes=work_volumes(scene))
        for i in range(k):  # an unplaced reference (e.g. the workstation) is the world
            p = int(world.parent[i])
            if p >= 0 and not world.placed(p):
                world.parent[i] = -1
        return world

    # --- queries ----------------------------------------------------------------------
    def __len__(self) -> int:
        return len(self.names)

    def placed(self, i: int) -> bool:
        """True when object ``i`` is in the cell with a pose and a box."""
        return not (np.isnan(self.poses[i, 0, 0]) or np.isnan(self.local_lo[i, 0]))

    def is_a(self, i: int, cls: str) -> bool:
        """True when object ``i`` is of class ``cls`` (a ``ktw`` local name or an IRI)."""
        return (cls if ":" in cls else str(KTW) + cls) in self.classes[i]

    def stand_in(self, i: int) -> bool:
        """True for an object whose box is lent by another one (a kit, a large box, a station)."""
        return any(c in self.classes[i] for c in STAND_INS)

    def objects(self, prop: str, subject: str) -> list[str]:
        """Objects of the model property ``prop`` (IRI) for ``subject``."""
        return sorted(o for s, o in self.facts.get(prop, ()) if s == subject)

    def subjects(self, prop: str, obj: str) -> list[str]:
        """Subjects of the model property ``prop`` (IRI) with object ``obj``."""
        return sorted(s for s, o in self.facts.get(prop, ()) if o == obj)

    def children(self, i: int) -> list[int]:
        """Objects resting in / on or attached to ``i``."""
        return list(self._children().get(int(i), ()))

    def subtree(self, i: int) -> list[int]:
        """``i`` and everything that moves with it."""
        parent = self.parent  # each node's children in index order (the parents change between calls:
        out, todo = [], [i]  # one comparison per node costs less than a table made again)
        while todo:
            j = todo.pop()
            out.append(j)
            todo.extend(np.flatnonzero(parent == j).tolist())
        return out

    def _children(self) -> dict[int, list[int]]:
        """Parent index -> its children, in index order (kept while ``parent`` holds the same
        values: it is changed in place)."""
        key = self.parent.tobytes()
        kept = getattr(self, "_children_of", None)
        if kept is None or kept[0] != key:
            kids: dict[int, list[int]] = {}
            for j, p in enumerate(self.parent.tolist()):
                kids.setdefault(p, []).append(j)
            kept = self._children_of = (key, kids)
        return kept[1]

    def box(self, i: int) -> tuple[np.ndarray, np.ndarray]:
        """World box (lo, hi) of object ``i``."""
        lo, hi = world_boxes(self.poses[i:i + 1], self.local_lo[i:i + 1], self.local_hi[i:i + 1])
        return lo[0], hi[0]

    def solids(self, exclude: set[int] | frozenset[int] = frozenset()) -> list[int]:
        """Placed objects that are not stand-ins, minus ``exclude``."""
        mask = self.solid_mask()
        if exclude:
            mask[np.fromiter(exclude, np.intp, len(exclude))] = False
        return np.flatnonzero(mask).tolist()

    def solid_mask(self) -> np.ndarray:
        """(K,) bool: placed and not a stand-in (:meth:`solids`, as an array)."""
        placed = ~(np.isnan(self.poses[:, 0, 0]) | np.isnan(self.local_lo[:, 0]))
        return placed & ~self._stand_ins()

    def _stand_ins(self) -> np.ndarray:
        """(K,) bool: :meth:`stand_in` of every object (kept while no object is added)."""
        kept = getattr(self, "_stand_in_mask", None)
        if kept is None or len(kept) != len(self.classes):
            kept = self._stand_in_mask = np.array([self.stand_in(i) for i in range(len(self.classes))], bool)
        return kept.copy()

    def sku(self, i: int) -> str | None:
        """The SKU of ``i``; for a kit, its kit tray's."""
        skus = self.objects(SKU, self.names[i])
        if not skus and self.is_a(i, "Kit"):
            trays = self.objects(KIT_TRAY, self.names[i])
            skus = self.objects(SKU, trays[0]) if trays else []
        return skus[0] if skus else None

    def effectors_for(self, i: int) -> list[str]:
        """The end effectors the SKU of ``i`` lists (``hasStockKeepingUnit_EndEffector``)."""
        sku = self.sku(i)
        return self.objects(SKU_EFFECTOR, sku) if sku else []

    def number(self, prop: str, name: str | None) -> float | None:
        """The value (SI) of the data property ``prop`` (IRI) of ``name``, if it is a number."""
        v = self.values.get(prop, {}).get(name) if name is not None else None
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(float(v)):
            return None
        return float(v)

    def weight(self, i: int) -> float | None:
        """The weight (kg) of ``i`` and what moves with it (a kit: its tray and parts; a tray:
        its parts), each object's its SKU's; None when none of them has one. Stand-ins (a kit)
        weigh nothing of their own."""
        found = [self.number(SKU_WEIGHT, s) for j in self.subtree(i) if not self.stand_in(j)
                 for s in self.objects(SKU, self.names[j])[:1]]
        known = [w for w in found if w is not None]
        return math.fsum(known) if known else None

    def kit_of_tray(self, i: int) -> int | None:
        """The kit whose kit tray ``i`` is, if any."""
        kits = [k for k in self.subjects(KIT_TRAY, self.names[i]) if k in self.index and self.placed(self.index[k])]
        return self.index[kits[0]] if kits else None  # a kit declared by the goal exists once it is created

    # --- changes ----------------------------------------------------------------------
    def set_pose(self, i: int, pose: np.ndarray) -> None:
        """Move ``i`` to the global ``pose``; everything that rests on or in it moves along.

        ``i`` gets ``pose`` itself, not ``delta @ old``: ``invert`` transposes the rotation, so
        any rounding in the old pose would be squared on every move (the robot's flange moves
        hundreds of times in a run, and the error doubled per move until poses overflowed)."""
        pose = np.asarray(pose, float)
        delta = pose @ invert(self.poses[i])
        for j in self.subtree(i):
            self.poses[j] = pose if j == i else delta @ self.poses[j]

    def shift(self, i: int, dx: float, dy: float, dz: float) -> None:
        """Translate ``i`` (and what moves with it) in the world frame."""
        self.set_pose(i, translate(dx, dy, dz) @ self.poses[i])

    def remove(self, i: int) -> None:
        """Take ``i`` (and what rests on it) out of the cell: no pose, no parent."""
        for j in self.subtree(i):
            self.poses[j] = np.nan
        self.parent[i] = -1

    def add(self, name: str, classes: frozenset[str]) -> int:
        """A new, unplaced object (e.g. a kit that first appears when it is created)."""
        self.names.append(name)
        self.classes.append(classes)
        self.index[name] = len(self.names) - 1
        self.poses = np.concatenate([self.poses, np.full((1, 4, 4), np.nan)])
        self.local_lo = np.concatenate([self.local_lo, np.full((1, 3), np.nan)])
        self.local_hi = np.concatenate([self.local_hi, np.full((1, 3), np.nan)])
        self.parent = np.append(self.parent, -1)
        self.open_top = np.append(self.open_top, False)
        return len(self.names) - 1

    # --- gravity ------------------------------------------------------------------------
    def support_below(self, i: int, exclude: set[int] | frozenset[int]) -> tuple[float, int]:
        """(height, support) where ``i`` comes to rest when it falls straight down.

        The highest of: the floor (z = 0, support -1); the top face of an object below whose
        footprint overlaps ``i``'s; the floor (bottom face) of an open-top container whose
        footprint contains ``i``'s (objects already inside it are supports by their top face).
        On equal heights (within the tolerance: a turned tray's floor and the table top under
        it differ by rounding) a container wins over the object it stands on. Footprints are compared
        in each candidate support's frame (:meth:`boxes_in_frames`): a turned tray holds what
        lies inside it, not what lies inside its world box.

        Thin and narrow objects (docs/soap.md, "Tolerance"): footprints overlap when they do by
        more than :func:`kb.spatial.rcc8.depth_tolerance` (the tolerance, or half the narrower
        footprint: a 0.5 mm shaft lying on a table rests on it), and two heights are equal
        within the tolerance or half the height of a support thinner than twice it (a part let
        go over a 0.3 mm washer lying in a tray rests on the washer, not inside it on the floor).
        """
        skip = set(self.subtree(i)) | exclude
        js = np.array(self.solids(skip), np.int64)
        best = (0.0, 0, -1, TOLERANCE)  # (height, container first, support, tolerance of its height)
        if not len(js):
            return best[0], best[2]
        (lo, hi), (jlo, jhi) = self.boxes_in_frames(i, js)
        t = TOLERANCE
        deep = depth_tolerance(t, hi[:, :2] - lo[:, :2], jhi[:, :2] - jlo[:, :2])
        overlap = ((np.minimum(hi[:, :2], jhi[:, :2]) - np.maximum(lo[:, :2], jlo[:, :2])) > deep).all(axis=1)
        inside = ((lo[:, :2] >= jlo[:, :2] - t) & (hi[:, :2] <= jhi[:, :2] + t)).all(axis=1)
        contained = self.open_top[js] & inside & (jlo[:, 2] <= lo[:, 2] + t)
        below = ~contained & overlap & (jhi[:, 2] <= lo[:, 2] + t)
        level = depth_tolerance(t, jhi[:, 2] - jlo[:, 2])
        for k in np.flatnonzero(contained | below):
            top = float(jlo[k, 2]) if contained[k] else float(jhi[k, 2])
            cand = (top, int(contained[k]), int(js[k]), float(level[k]))
            same = min(cand[3], best[3])
            if cand[0] > best[0] + same or (cand[0] >= best[0] - same and cand[1] > best[1]):
                best = cand
        return best[0], best[2]

    def boxes_in_frames(self, i: int, js: np.ndarray, pose: np.ndarray | None = None) -> tuple[
            tuple[np.ndarray, np.ndarray], tuple[np.ndarray, np.ndarray]]:
        """((lo, hi) of ``i``, (lo, hi) of each of ``js``), each (len(js), 3): both boxes in the
        frame of object j, the world turned about z by j's heading (:func:`kb.spatial.rcc8.headings`;
        exactly the world frame for an axis-aligned j). There j's box is exact when j is turned
        about z only, and i's is the hull of its oriented box (at ``pose``, default where i is)."""
        yaw = _snapped(headings(self.poses[js]))
        j_boxes = frame_boxes(self.poses[js], self.local_lo[js], self.local_hi[js], yaw)
        n = len(js)
        at = self.poses[i] if pose is None else pose
        i_boxes = frame_boxes(np.broadcast_to(at, (n, 4, 4)), np.broadcast_to(self.local_lo[i], (n, 3)),
                              np.broadcast_to(self.local_hi[i], (n, 3)), yaw)
        return i_boxes, j_boxes

    def point_in_frames(self, p: np.ndarray, js: np.ndarray) -> tuple[np.ndarray, tuple[np.ndarray, np.ndarray]]:
        """(point ``p`` in each frame of ``js`` (len(js), 3), (lo, hi) of each of ``js`` there)."""
        yaw = _snapped(headings(self.poses[js]))
        c, s = np.cos(yaw), np.sin(yaw)
        q = np.stack([c * p[0] + s * p[1], c * p[1] - s * p[0], np.full(len(js), float(p[2]))], axis=1)
        return q, frame_boxes(self.poses[js], self.local_lo[js], self.local_hi[js], yaw)

    def drop(self, i: int, exclude: set[int] | frozenset[int] = frozenset()) -> int:
        """Let ``i`` fall straight down onto what is below it; it then rests on that (returned; -1: floor)."""
        height, support = self.support_below(i, exclude)
        lo, _ = self.box(i)
        self.shift(i, 0.0, 0.0, height - float(lo[2]))
        self.parent[i] = support
        return support

    def holder_around(self, i: int, pose: np.ndarray | None = None) -> int | None:
        """The end effector holder ``i`` sits in (footprint inside it, heights overlapping), if
        any; compared in the holder's frame. ``pose``: where i would be (default: where it is)."""
        js = np.array([j for j in self.solids(set(self.subtree(i))) if self.is_a(j, "EndEffectorHolder")], np.int64)
        if not len(js):
            return None
        (lo, hi), (jlo, jhi) = self.boxes_in_frames(i, js, pose)
        t = TOLERANCE
        inside = ((lo[:, :2] >= jlo[:, :2] - t) & (hi[:, :2] <= jhi[:, :2] + t)).all(axis=1)
        hits = np.flatnonzero(inside & (lo[:, 2] < jhi[:, 2] + t) & (hi[:, 2] > jlo[:, 2] - t))
        return int(js[hits[0]]) if len(hits) else None

    # --- output -------------------------------------------------------------------------
    def to_scene(self) -> Scene:
        """The ground truth as a :class:`Scene` (a snapshot: later changes do not show in it)."""
        return Scene.from_parts(list(self.names), list(self.classes), self.poses.copy(), self.local_lo.copy(),
                                self.local_hi.copy(), copy.deepcopy(self.facts), copy.deepcopy(self.values),
                                {QUALITY: set(self.passed)}, self.parent.copy(), self.open_top.copy())


# --- work volumes -----------------------------------------------------------------------------

def work_volumes(scene: Scene) -> dict[str, list[tuple[np.ndarray, np.ndarray]]]:
    """Robot IRI -> (lo, hi) of each of its ``hasRobot_WorkVolume`` boxes in metres (the model
    allows several: the robot reaches their union), read from the scene's state file
    (``scene.path``, in the file's length unit ``scene.units``); empty for a scene not read
    from a file. A work volume whose points are missing or not numbers is an
    :class:`~kb.core.errors.InputError` naming it."""
    if scene.path is None or not os.path.isfile(scene.path):
        return {}
    robots = tuple(n for n, c in zip(scene.names, scene.classes) if str(KTW.Robot) in c)
    source = getattr(scene, "source", None)
    if source is not None and str(source.path) == scene.path:  # the file as the scene read it: not parsed again
        return _read_volumes(source, scene.units, robots)
    st = os.stat(scene.path)
    found = _volumes(scene.path, st.st_mtime_ns, st.st_size, scene.units, robots)
    return {r: [(lo.copy(), hi.copy()) for lo, hi in boxes] for r, boxes in found.items()}


@lru_cache(maxsize=8)
def _volumes(path: str, mtime: int, size: int, units: Units,
             robots: tuple[str, ...]) -> dict[str, list[tuple[np.ndarray, np.ndarray]]]:
    from kb.io import load_file  # the state file again: its points are not in the scene
    return _read_volumes(load_file(path), units, robots)


def _read_volumes(source, units: Units, robots: tuple[str, ...]) -> dict[str, list[tuple[np.ndarray, np.ndarray]]]:  # noqa: ANN001
    view = source.view()
    factor = units.factor("length")
    out: dict[str, list[tuple[np.ndarray, np.ndarray]]] = {}
    for robot in robots:
        for volume in sorted(view.objects(URIRef(robot), KTW.hasRobot_WorkVolume), key=str):
            corners = [_point(view, volume, prop, robot, source) * factor
                       for prop in (KTW.hasBoxVolume_MinimumPoint, KTW.hasBoxVolume_MaximumPoint)]
            out.setdefault(robot, []).append((np.minimum(*corners), np.maximum(*corners)))
    return out


def _point(view, volume, prop, robot: str, source) -> np.ndarray:  # noqa: ANN001
    """The (x, y, z) of a work volume's corner ``prop``; InputError when it is not three numbers."""
    point = view.value(volume, prop)
    xyz = [view.value(point, q) if point is not None else None for q in (KTW.hasPoint_X, KTW.hasPoint_Y, KTW.hasPoint_Z)]
    try:
        out = np.array([float(v.toPython()) for v in xyz if isinstance(v, Literal)], float)
    except (TypeError, ValueError, OverflowError):
        out = np.zeros(0)
    if out.shape != (3,) or not np.isfinite(out).all():
        raise InputError(f"work volume {local_name(volume)} of {local_name(robot)}: its "
                         f"{local_name(prop).rsplit('_', 1)[-1]} is not a point of three numbers",
                         source.path, source.line_of(volume))
    return out
