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
from typing import Any, Iterable

import numpy as np

from kb.cells.accuracy import SensorAccuracy
from kb.core.namespaces import KTW
from kb.crcl.cell import Observation
from kb.spatial.scene import Scene, scene_boxes

SKU_OF, KIT_TRAY = str(KTW.hasSkuObject_Sku), str(KTW.hasKit_KitTray)
#: a look within this many sigmas of the belief is of the same pose (per coordinate, per angle)
GATE = 5.0
#: the pose of an object is rewritten when the mean of its looks has moved more than this many
#: sigmas of a look from it, so a still object's belief settles and its checks are not decided
#: anew for nothing (:meth:`Belief.settle` writes the mean itself, for a motion target)
STEADY = 0.25
_LEVEL = 1e-9  # roll and pitch this near a quarter turn: level (z up or down: a tool points down)
_QUARTER = np.pi / 2


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
        #: the unusable objects an inspection that passes them makes usable again
        self.reinspect: set[str] = set()
        self.initial = self.poses.copy()
        #: object -> local name of its SKU as believed (the model's, or what the sensor recognised)
        self._sku_local = {n: sku.rsplit("#", 1)[-1] for n, sku in self.facts.get(SKU_OF, ())}
        self._stand_in_boxes()
        self._scene: Scene | None = None
        self._boxes: tuple[np.ndarray, np.ndarray] | None = None
        self._stale: set[int] = set()  # objects whose world box changed since _boxes was made
        #: the sensor's accuracy the belief filters with (None: an exact sensor, every look taken as it is)
        self.noise: SensorAccuracy | None = None
        #: looks of each object averaged into its pose since it last moved (with noise)
        self.looks = np.zeros(len(self.names), np.int64)
        #: object -> the SKU (local name) a look reported instead of the believed one, to confirm
        self.claims: dict[str, str] = {}
        self.last_moved: list[str] = []  # the objects the last observe found moved (outside the gate)
        self._confirm = False

    def use_noise(self, noise: SensorAccuracy | None) -> None:
        """Filter the looks of a sensor of this accuracy (a :class:`~kb.cells.accuracy.SensorAccuracy`:
        ``position``, ``orientation``, ``bias`` sigmas; ``misclassification`` rate); None or
        an exact one: take every look as it is."""
        self.noise = noise if noise is not None and noise.poses else None
        self._confirm = bool(noise is not None and noise.misclassification)
        if self.noise is not None:  # each object's mean look (x, y, z, roll, pitch, yaw), the one
            # its pose was written from, and whether it is believed level
            self._mean = np.concatenate([self.poses[:, :3, 3], _rpy(self.poses)], axis=1)
            self._written = self._mean.copy()
            self._level = np.isnan(self.poses[:, 0, 0]) | _square(self._mean[:, 3:5])
            nz = self.noise
            self._sigma6 = np.array([nz.position] * 3 + [nz.orientation] * 3)  # the gate per coordinate
            self._steady = STEADY * self._sigma6

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
        """:meth:`observe` with a noisy sensor: each object's looks (several when it was asked
        for several times in one query: simultaneous frames) averaged into its belief or, outside
        the gate, taken as the object having moved (module docstring)."""
        index, names = self.index, self.names
        rows: dict[int, list[int]] = {}  # object -> its observations' positions
        looks = []
        for obs in observations:
            i = index.get(obs.name)
            if i is None:
                continue
            rows.setdefault(i, []).append(len(looks))
            looks.append(obs.location + obs.orientation)
            if obs.sku and self._sku_local.get(obs.name) != obs.sku:
                self._recognised(obs.name, obs.sku)
        changed: list[str] = []
        moved: list[str] = []
        if rows:
            idx = np.fromiter(rows, np.int64, len(rows))
            look = np.array(looks, float)
            if len(looks) == len(rows):  # one look each (the usual case)
                m = np.ones(len(idx))
            else:  # the mean of each object's looks (angles about its first look's)
                groups = list(rows.values())
                m = np.array([len(ks) for ks in groups], float)
                first = look[[ks[0] for ks in groups]]
                look = np.array([np.concatenate([look[ks, :3].mean(axis=0),
                                                 first[j, 3:] + _wrap(look[ks, 3:] - first[j, 3:]).mean(axis=0)])
                                 for j, ks in enumerate(groups)])
            new, went = self._merge(idx, look, m)
            changed = [names[i] for i in idx[new]]
            moved = [names[i] for i in idx[went]]
        for name in asked:
            i = index.get(name)
            if i is not None and i not in rows and not np.isnan(self.poses[i, 0, 0]):
                self.poses[i] = np.nan
                self._mean[i] = self._written[i] = np.nan
                self._level[i] = True  # an object seen again after it was gone: level if it looks it
                self.looks[i] = 0
                changed.append(name)
                moved.append(name)
        if changed:
            self._scene = None
            self._stale.update(index[n] for n in changed)
        self.last_moved = moved
        return changed

    def _merge(self, idx: np.ndarray, look: np.ndarray, m: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Take the mean ``look`` (x, y, z, roll, pitch, yaw) of ``m`` looks of each object
        ``idx`` (distinct): (pose changed, moved) per object. A roll or pitch within the gate of
        a quarter turn is that quarter turn (the levelling prior). The mean of all the looks is
        kept exactly; the pose is rewritten when it moves away from the written one by more than
        :data:`STEADY` sigmas (a still object's belief settles)."""
        n = self.looks[idx]
        known = n > 0
        gate = np.outer(GATE * np.sqrt(1.0 / m + 1.0 / np.maximum(n, 1)), self._sigma6) + _LEVEL
        rp = look[:, 3:5]  # a view: levelled in place
        square = np.round(rp / _QUARTER) * _QUARTER
        np.copyto(rp, square, where=np.abs(rp - square) <= gate[:, 3:5])
        mean = self._mean[idx]
        if not known.all():
            mean[~known] = look[~known]
        d = look - mean
        d[:, 3:] = (d[:, 3:] + np.pi) % (2 * np.pi) - np.pi
        inside = known & (np.abs(d) <= gate).all(axis=1)
        new = mean + d * np.where(inside, m / (n + m), 1.0)[:, None]
        new[:, 3:] = (new[:, 3:] + np.pi) % (2 * np.pi) - np.pi
        self._mean[idx] = new
        self.looks[idx] = np.where(inside, n + m, m)
        take = ~inside | (np.abs(new - self._written[idx]) > self._steady).any(axis=1)
        rows = idx[take]
        if len(rows):
            self.poses[rows] = _poses(new[take, :3], new[take, 3:])
            self._written[rows] = new[take]
            self._level[rows] = _square(new[take, 3:5])
        return take, ~inside

    def settle(self, names: Iterable[str]) -> list[str]:
        """Write the mean of each named object's looks as its pose (what a motion target is
        computed from: the mean itself, not the pose it settled at); the names whose pose changed."""
        if self.noise is None:
            return []
        idx = np.array([self.index[n] for n in names if self.placed(n)], np.int64)
        if not len(idx):
            return []
        idx = idx[(self._mean[idx] != self._written[idx]).any(axis=1)]
        if len(idx):
            self.poses[idx] = _poses(self._mean[idx, :3], self._mean[idx, 3:])
            self._written[idx] = self._mean[idx]
            self._scene = None
            self._stale.update(idx.tolist())
        return [self.names[i] for i in idx]

    def sigma(self, i: int, looks: int | None = None) -> float:
        """The standard deviation (m) of object ``i``'s believed position, per coordinate, from
        its looks (the bias of a look does not average out), with that of its corners from its
        orientation's (yaw turns a long object's ends: its error times half the diagonal; a
        level object's tilt is 0), the two independent; 0 with an exact sensor, or for an object
        not looked at yet (its pose is the state file's). ``looks``: after that many looks."""
        n = int(self.looks[i]) if looks is None else looks
        return float(self._sigmas(np.array([i]), np.array([n]))[0])

    def sigmas(self, indices: np.ndarray) -> np.ndarray:
        """:meth:`sigma` of the objects ``indices`` (NaN rows for objects not placed)."""
        idx = np.asarray(indices, np.int64)
        return self._sigmas(idx, self.looks[idx])

    def _sigmas(self, idx: np.ndarray, n: np.ndarray) -> np.ndarray:
        nz = self.noise
        if nz is None:
            return np.zeros(len(idx))
        size = self.local_hi[idx] - self.local_lo[idx]
        reach = np.where(self._level[idx], np.hypot(size[:, 0], size[:, 1]), np.linalg.norm(size, axis=1)) / 2
        looks = np.maximum(n, 1)
        reach = np.where(np.isnan(reach), 0.0, reach)  # np.nan_to_num's 0 for an unplaced box (sizes are finite)
        out = np.sqrt(nz.position ** 2 / looks + nz.bias ** 2 + (nz.orientation * reach) ** 2 / looks)
        return np.where(n > 0, out, 0.0)

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
            if name in self.reinspect:  # kept out until an inspection passed it: usable again
                self.reinspect.discard(name)
                self.unusable.pop(name, None)
        else:
            self.reinspect.discard(name)
            self.inspections["quality-inspection"].discard(name)
            self.learn(name, "defective")
        self._scene = None

    def learn(self, part: str, what: str, until_inspected: bool = False) -> None:
        """A diagnosis found ``part`` unusable (``what``: the reason its failure mode gives, e.g.
        missing, defective, wrong-sku, dropped); the first reason is kept. ``until_inspected``:
        an inspection that passes it makes it usable again (unless it was unusable already)."""
        if until_inspected and part not in self.unusable:
            self.reinspect.add(part)
        elif not until_inspected:
            self.reinspect.discard(part)
        self.unusable.setdefault(part, what)

    def awaits_inspection(self, part: str) -> bool:
        """Unusable until an inspection passes it."""
        return part in self.reinspect

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

    def placed_positions(self, cls: str, but: str | None = None) -> np.ndarray:
        """(K, 3) global positions of the placed objects of class ``cls`` but ``but`` (each
        ``name`` of :meth:`of_class` for which :meth:`placed` holds: ``pose(name)[:3, 3]``)."""
        index = self.index
        idx = np.fromiter((index[n] for n, c in zip(self.names, self.classes) if cls in c and n != but),
                          np.int64)
        idx = idx[~np.isnan(self.poses[idx, 0, 0]) & ~np.isnan(self.local_lo[idx, 0])]
        return self.poses[idx, :3, 3].reshape(-1, 3)

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


def _square(rp: np.ndarray) -> np.ndarray:
    """(K,) whether each roll, pitch pair is axis-aligned (a multiple of a quarter turn each)."""
    return np.abs(rp - np.round(rp / _QUARTER) * _QUARTER).max(axis=1) < _LEVEL


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
