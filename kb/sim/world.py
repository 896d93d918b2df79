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

:meth:`World.to_scene` is the ground truth as a scene, with ``inspections`` =
``{"quality-inspection": parts inspected so far that passed}``.
"""

from __future__ import annotations

import copy
from dataclasses import dataclass, field

import numpy as np

from kb.core.namespaces import KTW
from kb.spatial.rcc8 import DEFAULT_TOLERANCE, world_boxes
from kb.spatial.scene import STAND_INS, Scene
from kb.spatial.transforms import invert

QUALITY = "quality-inspection"
SKU = str(KTW.hasSkuObject_Sku)
SKU_EFFECTOR = str(KTW.hasStockKeepingUnit_EndEffector)
KIT_TRAY = str(KTW.hasKit_KitTray)
#: How far (metres) a face may be from where it should be and still count as there.
TOLERANCE = DEFAULT_TOLERANCE


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
                    set(scene.inspections.get(QUALITY, ())))
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
        return [int(j) for j in np.flatnonzero(self.parent == i)]

    def subtree(self, i: int) -> list[int]:
        """``i`` and everything that moves with it."""
        out, todo = [], [i]
        while todo:
            j = todo.pop()
            out.append(j)
            todo.extend(self.children(j))
        return out

    def box(self, i: int) -> tuple[np.ndarray, np.ndarray]:
        """World box (lo, hi) of object ``i``."""
        lo, hi = world_boxes(self.poses[i:i + 1], self.local_lo[i:i + 1], self.local_hi[i:i + 1])
        return lo[0], hi[0]

    def solids(self, exclude: set[int] | frozenset[int] = frozenset()) -> list[int]:
        """Placed objects that are not stand-ins, minus ``exclude``."""
        return [i for i in range(len(self)) if i not in exclude and self.placed(i) and not self.stand_in(i)]

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
        On equal heights a container wins over the object it stands on.
        """
        lo, hi = self.box(i)
        best = (0.0, 0, -1)
        skip = set(self.subtree(i)) | exclude
        for j in self.solids(skip):
            jlo, jhi = self.box(j)
            overlap = all(min(hi[a], jhi[a]) - max(lo[a], jlo[a]) > TOLERANCE for a in (0, 1))
            inside = all(lo[a] >= jlo[a] - TOLERANCE and hi[a] <= jhi[a] + TOLERANCE for a in (0, 1))
            if self.open_top[j] and inside and jlo[2] <= lo[2] + TOLERANCE:
                cand = (float(jlo[2]), 1, j)
            elif overlap and jhi[2] <= lo[2] + TOLERANCE:
                cand = (float(jhi[2]), 0, j)
            else:
                continue
            if cand[:2] > best[:2]:
                best = cand
        return best[0], best[2]

    def drop(self, i: int, exclude: set[int] | frozenset[int] = frozenset()) -> int:
        """Let ``i`` fall straight down onto what is below it; it then rests on that (returned; -1: floor)."""
        height, support = self.support_below(i, exclude)
        lo, _ = self.box(i)
        self.shift(i, 0.0, 0.0, height - float(lo[2]))
        self.parent[i] = support
        return support

    def holder_around(self, i: int) -> int | None:
        """The end effector holder ``i`` sits in (footprint inside it, heights overlapping), if any."""
        lo, hi = self.box(i)
        for j in self.solids(set(self.subtree(i))):
            if not self.is_a(j, "EndEffectorHolder"):
                continue
            jlo, jhi = self.box(j)
            inside = all(lo[a] >= jlo[a] - TOLERANCE and hi[a] <= jhi[a] + TOLERANCE for a in (0, 1))
            if inside and lo[2] < jhi[2] + TOLERANCE and hi[2] > jlo[2] - TOLERANCE:
                return j
        return None

    # --- output -------------------------------------------------------------------------
    def to_scene(self) -> Scene:
        """The ground truth as a :class:`Scene` (a snapshot: later changes do not show in it)."""
        return Scene.from_parts(list(self.names), list(self.classes), self.poses.copy(), self.local_lo.copy(),
                                self.local_hi.copy(), copy.deepcopy(self.facts), copy.deepcopy(self.values),
                                {QUALITY: set(self.passed)}, self.parent.copy(), self.open_top.copy())
