"""What the executor believes about the cell: the initial state's scene, kept up to date from
the sensor.

Objects, classes, local boxes and model facts come from the initial state file (and the goal
file's own individuals, such as kits that do not exist yet); global poses start as the file
says and are replaced by every observation (the sensor reports global poses: seed 004
§4.2). An object the sensor was asked for by name and did not report is believed gone. The
SKU the sensor recognises replaces the model's (``hasSkuObject_Sku``), so a part of the wrong
SKU shows in ``part-sku``. What a diagnosis learned about a part (missing, defective, of
another SKU, dropped) is kept (:attr:`Belief.unusable`). :meth:`Belief.scene` is the scene
predicates are evaluated on.
"""

from __future__ import annotations

import copy
import math
from typing import Any, Iterable

import numpy as np

from kb.core.namespaces import KTW
from kb.crcl.cell import Observation
from kb.spatial.scene import Scene, scene_boxes

SKU_OF, KIT_TRAY = str(KTW.hasSkuObject_Sku), str(KTW.hasKit_KitTray)
#: a look within this many sigmas of the belief is of the same pose (per coordinate, per angle)
GATE = 5.0
_LEVEL = 1e-9  # roll and pitch below this: level


class Belief:
    """The executor's model of the cell (global poses, boxes, facts, inspections)."""

    def __init__(self, scene: Scene):
        self.names = list(scene.names)
        self.index = dict(scene.index)
        self.classes = list(scene.classes)
        self.poses = np.array(scene.poses, float)
        self.local_lo = np.array(scene.local_lo, float)
        self.local_hi = np.array(scene.local_hi, float)
        self.open_top = np.array(scene.open_top, bool)
        self.facts = copy.deepcopy(scene.facts)
        self.values = scene.values
        self.slots = scene.slots
        self.inspections: dict[str, set[str]] = {"quality-inspection": set()}
        #: what diagnoses learned: part -> why it must not be used again ("missing", "defective",
        #: "wrong-sku", "dropped"); no later rebinding, replan or plan takes such a part
        self.unusable: dict[str, str] = {}
        self.initial = self.poses.copy()
        #: object -> local name of its SKU as believed (the model's, or what the sensor recognised)
        self._sku_local = {n: sku.rsplit("#", 1)[-1] for n, sku in self.facts.get(SKU_OF, ())}
        self._stand_in_boxes()
        self._scene: Scene | None = None
        self._boxes: tuple[np.ndarray, np.ndarray] | None = None
        self._stale: set[int] = set()  # objects whose world box changed since _boxes was made
        #: the sensor's accuracy the belief filters with (None: an exact sensor, every look taken as it is)
        self.noise: Any = None
        #: looks of each object averaged into its pose since it last moved (with noise)
        self.looks = np.zeros(len(self.names), np.int64)
        #: object -> the SKU (local name) a look reported instead of the believed one, to confirm
        self.claims: dict[str, str] = {}
        self.last_moved: list[str] = []  # the objects the last observe found moved (outside the gate)
        self._confirm = False

    def use_noise(self, noise: Any) -> None:
        """Filter the looks of a sensor of this accuracy (a :class:`~kb.sim.noise.SensorNoise`:
        ``position``, ``orientation``, ``bias`` sigmas; ``misclassification`` rate); None or
        an exact one: take every look as it is."""
        self.noise = noise if noise is not None and noise.poses else None
        self._confirm = bool(noise is not None and noise.misclassification)

    def _stand_in_boxes(self) -> None:
        """A kit not yet placed takes its tray's box (for when the sensor first reports it)."""
        for kit, tray in self.facts.get(KIT_TRAY, ()):
            k, t = self.index.get(kit), self.index.get(tray)
            if k is not None and t is not None and np.isnan(self.local_lo[k, 0]):
                self.local_lo[k], self.local_hi[k], self.open_top[k] = self.local_lo[t], self.local_hi[t], \
                    self.open_top[t]

    # --- updates --------------------------------------------------------------------
    def observe(self, observations: Iterable[Observation], asked: Iterable[str] = ()) -> list[str]:
        """Take the sensor's global poses; objects ``asked`` for by name and not reported are
        believed gone. Returns the names whose pose changed (with noise: moved or refined;
        :attr:`last_moved` has those that moved)."""
        if self.noise is not None:
            return self._filtered(list(observations), asked)
        changed = []
        seen = set()
        rows, locs, rpys = [], [], []
        for obs in observations:
            i = self.index.get(obs.name)
            if i is None:
                continue
            seen.add(obs.name)
            rows.append(i)
            locs.append(obs.location)
            rpys.append(obs.orientation)
            if obs.sku:
                self._recognised(obs.name, obs.sku)
        if rows:
            poses = _poses(np.asarray(locs, float), np.asarray(rpys, float))
            idx = np.asarray(rows)
            old = self.poses[idx]
            moved = ~np.all(np.abs(poses - old) <= 1e-9, axis=(1, 2))  # NaN (not placed before) counts as moved
            if moved.any():
                self.poses[idx[moved]] = poses[moved]
                changed.extend(self.names[i] for i in idx[moved])
        for name in asked:
            i = self.index.get(name)
            if name not in seen and i is not None and not np.isnan(self.poses[i, 0, 0]):
                self.poses[i] = np.nan
                changed.append(name)
        if changed:
            self._scene = None
            self._stale.update(self.index[n] for n in changed)
        self.last_moved = changed
        return changed

    def _filtered(self, observations: list[Observation], asked: Iterable[str]) -> list[str]:
        """:meth:`observe` with a noisy sensor: each look averaged into its object's belief or,
        outside the gate, taken as the object having moved (module docstring)."""
        changed: dict[str, None] = {}
        moved: dict[str, None] = {}
        seen = set()
        batches: list[list[tuple[int, Observation]]] = []  # an object's k-th look goes in batch k
        count: dict[int, int] = {}
        for obs in observations:
            i = self.index.get(obs.name)
            if i is None:
                continue
            seen.add(obs.name)
            k = count.get(i, 0)
            count[i] = k + 1
            if k == len(batches):
                batches.append([])
            batches[k].append((i, obs))
            if obs.sku:
                self._recognised(obs.name, obs.sku)
        for batch in batches:
            idx = np.array([i for i, _ in batch], np.int64)
            xyz = np.array([o.location for _, o in batch], float)
            rpy = np.array([o.orientation for _, o in batch], float)
            new, went = self._merge(idx, xyz, rpy)
            for j, i in enumerate(idx):
                if new[j]:
                    changed[self.names[i]] = None
                if went[j]:
                    moved[self.names[i]] = None
        for name in asked:
            i = self.index.get(name)
            if name not in seen and i is not None and not np.isnan(self.poses[i, 0, 0]):
                self.poses[i] = np.nan
                self.looks[i] = 0
                changed[name] = None
                moved[name] = None
        if changed:
            self._scene = None
            self._stale.update(self.index[n] for n in changed)
        self.last_moved = list(moved)
        return list(changed)

    def _merge(self, idx: np.ndarray, xyz: np.ndarray, rpy: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Take one look of each object ``idx`` (distinct): (pose changed, moved) per object."""
        nz = self.noise
        old = self.poses[idx]
        n = self.looks[idx]
        known = ~np.isnan(old[:, 0, 0]) & (n > 0)
        prior_level = np.isnan(old[:, 0, 0]) | ((np.abs(old[:, 2, 0]) < _LEVEL) & (np.abs(old[:, 2, 1]) < _LEVEL))
        spread = np.sqrt(1.0 + 1.0 / np.maximum(n, 1))
        tilt_gate = GATE * nz.orientation * spread + _LEVEL
        level = prior_level & (np.abs(rpy[:, 0]) <= tilt_gate) & (np.abs(rpy[:, 1]) <= tilt_gate)
        rpy = rpy.copy()
        rpy[level, :2] = 0.0
        old_xyz = old[:, :3, 3]
        old_rpy = _rpy(old)
        d_xyz = xyz - old_xyz
        d_rpy = _wrap(rpy - old_rpy)
        inside = known & np.all(np.abs(d_xyz) <= (GATE * nz.position * spread + _LEVEL)[:, None], axis=1) \
            & np.all(np.abs(d_rpy) <= (GATE * nz.orientation * spread + _LEVEL)[:, None], axis=1)
        w = np.where(inside, 1.0 / (n + 1.0), 1.0)[:, None]
        new_xyz = np.where(inside[:, None], old_xyz + d_xyz * w, xyz)
        new_rpy = np.where(inside[:, None], _wrap(old_rpy + d_rpy * w), rpy)
        poses = _poses(new_xyz, new_rpy)
        self.looks[idx] = np.where(inside, n + 1, 1)
        changed = ~np.all(np.abs(poses - np.nan_to_num(old, nan=np.inf)) <= 1e-12, axis=(1, 2))
        self.poses[idx[changed]] = poses[changed]
        return changed, ~inside

    def sigma(self, i: int) -> float:
        """The standard deviation (m) of object ``i``'s believed position, per coordinate, from
        its looks (the bias of a look does not average out); 0 with an exact sensor, or for an
        object not looked at yet (its pose is the state file's)."""
        nz = self.noise
        n = int(self.looks[i])
        if nz is None or n == 0:
            return 0.0
        s = math.hypot(nz.position / math.sqrt(n), nz.bias)
        if nz.orientation and not np.isnan(self.poses[i, 0, 0]) and not (
                abs(self.poses[i, 2, 0]) < _LEVEL and abs(self.poses[i, 2, 1]) < _LEVEL):
            s += nz.orientation / math.sqrt(n) * float(np.linalg.norm(self.local_hi[i] - self.local_lo[i]))
        return s

    def confirm_sku(self, name: str, sku_local: str | None) -> None:
        """Settle a SKU claim: ``sku_local`` is the SKU further looks agreed on (None: they did not)."""
        self.claims.pop(name, None)
        if sku_local is not None and self._sku_local.get(name) != sku_local:
            self._apply_sku(name, sku_local)

    def _recognised(self, name: str, sku_local: str) -> None:
        if self._sku_local.get(name) == sku_local:  # what the model says already (the usual case)
            self.claims.pop(name, None)
            return
        if self._confirm:  # a misclassification is possible: the executor confirms it first
            self.claims[name] = sku_local
            return
        self._apply_sku(name, sku_local)

    def _apply_sku(self, name: str, sku_local: str) -> None:
        pairs = self.facts.setdefault(SKU_OF, set())
        current = [s for n, s in pairs if n == name]
        match = [n for n in self.names if n.rsplit("#", 1)[-1] == sku_local]
        if match:
            for s in current:
                pairs.discard((name, s))
            pairs.add((name, match[0]))
            self._sku_local[name] = sku_local
            self._sku_shape(name, match[0])
            self._scene = None
            self._stale.add(self.index[name])

    def _sku_shape(self, name: str, sku: str) -> None:
        """An object recognised as of ``sku`` has that SKU's shape: the box of another object of
        it (a part of another SKU is grasped at its own top face, not the planned part's)."""
        i = self.index[name]
        for other, s in sorted(self.facts.get(SKU_OF, ())):
            j = self.index.get(other)
            if s == sku and other != name and j is not None and not np.isnan(self.local_lo[j, 0]):
                self.local_lo[i], self.local_hi[i] = self.local_lo[j], self.local_hi[j]
                return

    def passed_inspection(self, name: str, ok: bool) -> None:
        if ok:
            self.inspections["quality-inspection"].add(name)
        else:
            self.inspections["quality-inspection"].discard(name)
            self.learn(name, "defective")
        self._scene = None

    def learn(self, part: str, what: str) -> None:
        """A diagnosis found ``part`` unusable (``what``: missing, defective, wrong-sku, dropped);
        the first reason is kept."""
        self.unusable.setdefault(part, what)

    def usable(self, part: str) -> bool:
        return part not in self.unusable

    # --- reading --------------------------------------------------------------------
    def scene(self) -> Scene:
        if self._scene is None:  # classes are closed already: no Scene.from_parts closure per check
            lo, hi = self.world_boxes()
            self._scene = Scene(self.names, self.classes, lo, hi, self.facts, self.values, self.inspections,
                                self.poses, None, None, self.local_lo, self.local_hi, self.open_top, self.slots)
        return self._scene

    def world_boxes(self) -> tuple[np.ndarray, np.ndarray]:
        """(K, 3) lo, hi of every object's world box (NaN rows: not placed)."""
        if self._boxes is None:
            self._boxes = scene_boxes(self.poses, self.local_lo, self.local_hi)
            self._stale.clear()
        elif self._stale:  # new arrays (a scene made earlier keeps its own), the changed rows redone
            idx = np.array(sorted(self._stale), np.int64)
            self._stale.clear()
            lo, hi = self._boxes[0].copy(), self._boxes[1].copy()
            lo[idx], hi[idx] = scene_boxes(self.poses[idx], self.local_lo[idx], self.local_hi[idx])
            self._boxes = (lo, hi)
        return self._boxes

    def subscene(self, indices: np.ndarray) -> Scene:
        """The scene of the objects ``indices`` only (their facts, values and inspections as
        the whole one's): an action's neighbourhood (:mod:`kb.execution.focus`)."""
        idx = np.asarray(indices, np.int64)
        lo, hi = self.world_boxes()
        return Scene([self.names[i] for i in idx], [self.classes[i] for i in idx], lo[idx], hi[idx], self.facts,
                     self.values, self.inspections, self.poses[idx], None, None, self.local_lo[idx],
                     self.local_hi[idx], self.open_top[idx], self.slots)

    def pose(self, name: str) -> np.ndarray:
        return self.poses[self.index[name]]

    def box(self, name: str) -> tuple[np.ndarray, np.ndarray]:
        i = self.index[name]
        return self.local_lo[i], self.local_hi[i]

    def placed(self, name: str) -> bool:
        i = self.index.get(name)
        return i is not None and not np.isnan(self.poses[i, 0, 0]) and not np.isnan(self.local_lo[i, 0])

    def of_class(self, cls: str) -> list[str]:
        return [n for n, c in zip(self.names, self.classes) if cls in c]

    def related(self, prop: str, subject: str) -> list[str]:
        return sorted(o for s, o in self.facts.get(prop, ()) if s == subject)


def _rpy(m: np.ndarray) -> np.ndarray:
    """(K, 3) roll, pitch, yaw of K poses (inverse of :func:`_poses`; NaN rows stay NaN)."""
    r20 = np.clip(m[:, 2, 0], -1.0, 1.0)
    pitch = np.arcsin(-r20)
    regular = np.abs(r20) < 1 - 1e-9
    roll = np.where(regular, np.arctan2(m[:, 2, 1], m[:, 2, 2]), 0.0)
    yaw = np.where(regular, np.arctan2(m[:, 1, 0], m[:, 0, 0]), np.arctan2(-m[:, 0, 1], m[:, 1, 1]))
    return np.stack([roll, pitch, yaw], axis=1)


def _wrap(a: np.ndarray) -> np.ndarray:
    """Angles wrapped into [-pi, pi)."""
    return (a + np.pi) % (2 * np.pi) - np.pi


def _poses(xyz: np.ndarray, rpy: np.ndarray) -> np.ndarray:
    """(K, 4, 4) transforms of positions and roll, pitch, yaw (``Rz(yaw) Ry(pitch) Rx(roll)``,
    as :func:`kb.spatial.transforms.from_xyz_rpy`), for K observations at once."""
    cr, sr = np.cos(rpy[:, 0]), np.sin(rpy[:, 0])
    cp, sp = np.cos(rpy[:, 1]), np.sin(rpy[:, 1])
    cy, sy = np.cos(rpy[:, 2]), np.sin(rpy[:, 2])
    out = np.zeros((len(xyz), 4, 4))
    out[:, 0, 0], out[:, 0, 1], out[:, 0, 2] = cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr
    out[:, 1, 0], out[:, 1, 1], out[:, 1, 2] = sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr
    out[:, 2, 0], out[:, 2, 1], out[:, 2, 2] = -sp, cp * sr, cp * cr
    out[:, :3, 3] = xyz
    out[:, 3, 3] = 1.0
    return out
