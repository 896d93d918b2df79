"""The simulated sensor: focus-of-attention queries on ground truth, and USARTruth's text form.

Seed 004 §3.2: a query names a class or an object (:func:`observe`), or both
(:func:`observe_where`; :func:`truth_class` reads a USARTruth client's Unreal class names);
the answer is one key-value line per matching object::

    {Name part_a_1} {Class Part} {Time 12.5} {Location 1.0,2.0,0.3} {Rotation 0.0,0.0,1.57}

(Name, Class: the most specific class, Time: simulated seconds, Location: global x,y,z,
Rotation: global roll,pitch,yaw). :func:`observe` answers a query from a
:class:`~kb.sim.world.World`, with the SKU it recognises (``{Sku sku_part_a}``: the local name
of the object's ``hasSkuObject_Sku``, a kit's tray's), so a part of the wrong SKU shows; a
:class:`Sensor` adds the errors of a :class:`~kb.sim.noise.SensorNoise` (Gaussian position and
orientation noise from the cell's seeded generator, a per-object bias, objects not reported,
objects reported with another SKU) and keeps a :class:`SensorError` for each object it did not
report or misclassified, as the faults keep an ``Injected``: ground truth, for scoring. The
ground truth itself never changes.
:func:`truth_line` / :func:`parse_truth_line`, the text form (numbers written with ``repr``, so
a line reads back to the same floats), are the cell contract's (:mod:`kb.crcl.cell`).
"""

from __future__ import annotations

import math
import zlib
from dataclasses import dataclass
from functools import lru_cache
from typing import Any, Callable, Iterable, Literal, Sequence

import numpy as np

from kb.core.namespaces import KTW, local_name
from kb.crcl.cell import Observation, parse_truth_line, truth_line
from kb.sim.noise import SensorNoise
from kb.sim.world import SKU, World
from kb.spatial.scene import class_ancestors

__all__ = ["Sensor", "SensorError", "matches", "most_specific", "observe", "observe_where", "parse_truth_line", "rpy",
           "truth_class", "truth_line"]

#: what a sensor can do wrong besides the pose noise, as its errors are recorded
SENSOR_ERROR_KINDS: tuple[str, ...] = ("misdetection", "misclassification")


@lru_cache(maxsize=None)
def most_specific(classes: frozenset[str]) -> str:
    """Local name of the most specific class among ``classes`` (the one with most ancestors):
    a kitting class, or a class a domain extension declares under one."""
    anc = class_ancestors()
    known = [c for c in classes if c in anc]
    if not known:
        return ""
    best = max(known, key=lambda c: (len(anc[c]), c))
    return best.rsplit("#", 1)[-1].rsplit("/", 1)[-1]


def rpy(m: np.ndarray) -> tuple[float, float, float]:
    """(roll, pitch, yaw) of a rotation ``Rz(yaw) Ry(pitch) Rx(roll)`` (inverse of ``from_xyz_rpy``)."""
    r = m[:3, :3]
    pitch = math.asin(max(-1.0, min(1.0, -float(r[2, 0]))))
    if abs(float(r[2, 0])) < 1 - 1e-9:
        roll = math.atan2(float(r[2, 1]), float(r[2, 2]))
        yaw = math.atan2(float(r[1, 0]), float(r[0, 0]))
    else:  # gimbal lock: yaw absorbs roll
        roll, yaw = 0.0, math.atan2(-float(r[0, 1]), float(r[1, 1]))
    return roll, pitch, yaw


def matches(world: World, i: int, query: str, by: Literal["class", "name"]) -> bool:
    """True when object ``i`` answers ``query``: a class (local name or IRI) or a name (local or IRI)."""
    if by == "class":
        return world.is_a(i, query)
    if by == "name":
        name = world.names[i]
        return query == name or query == name.rsplit("#", 1)[-1].rsplit("/", 1)[-1]
    raise ValueError(f"by must be 'class' or 'name', not {by!r}")


#: Unreal's classes a USARTruth client may ask for, and the kitting class each stands for
#: ("": every object). USARSim's USARTruth answered an empty class with its Pawns (robots);
#: kitkb answers every object, as NIST's client means by ``{class Engine.Actor}``.
UNREAL_CLASSES = {"actor": "", "wcobject": str(KTW.SolidObject), "pawn": str(KTW.Robot)}


def truth_class(text: str, known: Iterable[str]) -> str | None:
    """The class IRI a USARTruth query's ``{class text}`` asks for, among the ``known`` class
    IRIs: "" for every object (an empty value, Unreal's ``Actor``); an IRI as it is; a local
    name of a kitting class in any case (Unreal's class names are), after Unreal's package
    prefix is dropped (``USARPhysObj.Part`` is ``Part``, ``Engine.Actor`` is ``Actor``,
    :data:`UNREAL_CLASSES`); None for a class the cell does not know (nothing answers it)."""
    text = text.strip()
    if not text:
        return ""
    if ":" in text:
        return text
    local = text.rsplit(".", 1)[-1]
    if local.lower() in UNREAL_CLASSES:
        return UNREAL_CLASSES[local.lower()]
    ktw = str(KTW)
    if ktw + local in known:
        return ktw + local
    folded = {c[len(ktw):].lower(): c for c in known if c.startswith(ktw)}
    if local.lower() in folded:
        return folded[local.lower()]
    # a class a domain extension declares (xp:BufferBox), by its local name
    others = {c.rsplit("#", 1)[-1].rsplit("/", 1)[-1].lower(): c for c in known if not c.startswith(ktw)}
    return others.get(local.lower())


def observe(world: World, query: str, by: Literal["class", "name"], time: float,
            noise: "tuple[float, float] | SensorNoise" = (0.0, 0.0), rng: np.random.Generator | None = None,
            sensor: "Sensor | None" = None) -> list[Observation]:
    """Observations of the placed objects answering ``query``, in name order.

    ``noise``: (position sigma in metres, orientation sigma in radians) of Gaussian noise added
    to each coordinate, drawn from ``rng``; none is drawn when both are 0. A ``sensor`` brings
    its own noise and generators instead (:meth:`Sensor.report`).
    """
    if by not in ("class", "name"):
        raise ValueError(f"by must be 'class' or 'name', not {by!r}")
    return observe_where(world, time, cls=query if by == "class" else None, name=query if by == "name" else None,
                         noise=noise, rng=rng, sensor=sensor)


def observe_where(world: World, time: float, cls: str | None = None, name: str | None = None,
                  noise: "tuple[float, float] | SensorNoise" = (0.0, 0.0), rng: np.random.Generator | None = None,
                  sensor: "Sensor | None" = None) -> list[Observation]:
    """Observations of the placed objects of class ``cls`` and name ``name`` (None: any; as
    :func:`matches` reads them), in name order, as :func:`observe` makes them."""
    skus: dict[str, str] = {}  # name -> its SKU, as World.sku gives it (one pass, not one per object)
    for s, o in world.facts.get(SKU, ()):
        if s not in skus or o < skus[s]:
            skus[s] = o
    placed = ~(np.isnan(world.poses[:, 0, 0]) | np.isnan(world.local_lo[:, 0]))
    chosen = [i for i in sorted(range(len(world)), key=lambda k: world.names[k])
              if placed[i] and (cls is None or matches(world, i, cls, "class"))
              and (name is None or matches(world, i, name, "name"))]
    if not chosen:
        return []
    if sensor is None:
        sensor = Sensor(SensorNoise.of(noise), rng=rng)
    return sensor.report(world, chosen, time, lambda i: skus.get(world.names[i]) or
                         (world.sku(i) if world.is_a(i, "Kit") else None))


@dataclass(frozen=True)
class SensorError:
    """What the sensor got wrong in one look (ground truth, like :class:`~kb.sim.faults.Injected`):
    ``kind`` (misdetection: the object was not reported; misclassification: it was reported
    with another SKU), ``action_index`` (the plan action announced last, None before any),
    ``objects`` (its IRI), ``detail`` and the cell's ``time``."""

    kind: str
    action_index: int | None
    objects: tuple[str, ...]
    detail: str
    time: float

    def as_dict(self) -> dict[str, Any]:
        """The error as JSON data (objects by local name)."""
        return {"kind": self.kind, "action_index": self.action_index,
                "objects": [local_name(o) for o in self.objects], "detail": self.detail, "time": self.time}


class Sensor:
    """The simulated pose sensor: a :class:`~kb.sim.noise.SensorNoise` and its seeded
    generators. ``rng`` draws the position and orientation noise per look (the cell's
    generator, seeded by the cell's seed); the misdetections and misclassifications come from a
    generator of their own (seed, 1), and each object's bias from one seeded by the seed and its
    name, drawn once: changing one rate leaves the other draws as they were. ``errors`` lists
    what it did wrong; ``action`` is the plan action its errors are recorded under."""

    def __init__(self, noise: SensorNoise | None = None, seed: int = 0, rng: np.random.Generator | None = None) -> None:
        self.noise = noise or SensorNoise()
        self.seed = seed
        self.rng = rng if rng is not None else np.random.default_rng(seed)
        self._detect = np.random.default_rng([seed, 1])
        self._bias: dict[str, np.ndarray] = {}
        self.errors: list[SensorError] = []
        self.action: int | None = None
        self._kinds: tuple[World | None, int, dict[str, list[int]]] = (None, 0, {})  # world, its size, kinds

    def report(self, world: World, chosen: Sequence[int], time: float,
               sku_of: Callable[[int], str | None]) -> list[Observation]:
        """The observations of objects ``chosen`` (indices, placed), in that order, with the
        sensor's errors: pose noise drawn for every object (locations, then orientations), then
        each object missed or misclassified at its rate."""
        n = self.noise
        rows = list(chosen)
        locs = world.poses[rows, :3, 3].astype(float)
        oris = _rpy_many(world.poses[rows])
        if n.position:
            locs += self.rng.normal(0.0, n.position, locs.shape)
        if n.orientation:
            oris += self.rng.normal(0.0, n.orientation, oris.shape)
        if n.bias:
            locs += np.array([self.bias(world.names[i]) for i in rows])
        missed = self._detect.random(len(rows)) < n.misdetection if n.misdetection else np.zeros(len(rows), bool)
        wrong = self._detect.random(len(rows)) < n.misclassification if n.misclassification \
            else np.zeros(len(rows), bool)
        out = []
        for k, i in enumerate(rows):
            name = world.names[i]
            if missed[k]:
                self.errors.append(SensorError("misdetection", self.action, (name,),
                                               f"{local_name(name)} was not reported", float(time)))
                continue
            sku = sku_of(i)
            if wrong[k] and sku:
                other = self._other_sku(world, i, sku, sku_of)
                if other is not None:
                    self.errors.append(SensorError("misclassification", self.action, (name,),
                                                   f"{local_name(name)} reported as {local_name(other)}, not "
                                                   f"{local_name(sku)}", float(time)))
                    sku = other
            out.append(Observation(name, most_specific(world.classes[i]), float(time),
                                   tuple(locs[k].tolist()), tuple(oris[k].tolist()),  # type: ignore[arg-type]
                                   local_name(sku) if sku else None))
        return out

    def bias(self, name: str) -> np.ndarray:
        """The object's location offset (m), drawn once from its own seeded generator."""
        b = self._bias.get(name)
        if b is None:
            rng = np.random.default_rng([self.seed, 2, zlib.crc32(name.encode("utf-8"))])
            b = self._bias[name] = rng.normal(0.0, self.noise.bias, 3)
        return b

    def _other_sku(self, world: World, i: int, sku: str, sku_of: Callable[[int], str | None]) -> str | None:
        """Another SKU of the cell's objects of ``i``'s kind (its most specific class), drawn
        uniformly; None when there is none (kits are never misclassified: a kit's SKU is its tray's)."""
        cls = most_specific(world.classes[i])
        if cls == "Kit":
            return None
        others = sorted({s for j in self._kind(world, cls) for s in (sku_of(j),) if s and s != sku})
        if not others:
            return None
        return others[int(self._detect.integers(len(others)))]


    def _kind(self, world: World, cls: str) -> list[int]:
        """The objects of ``world`` whose most specific class is ``cls`` (an object's classes never
        change; kept while the world has the same objects)."""
        kept_world, size, kinds = self._kinds
        if kept_world is not world or size != len(world):
            kinds = {}
            for j in range(len(world)):
                kinds.setdefault(most_specific(world.classes[j]), []).append(j)
            self._kinds = (world, len(world), kinds)
        return kinds.get(cls, [])


def _rpy_many(m: np.ndarray) -> np.ndarray:
    """(K, 3) roll, pitch, yaw of K rotations, as :func:`rpy` gives them one by one."""
    r20 = m[:, 2, 0]
    pitch = np.arcsin(np.clip(-r20, -1.0, 1.0))
    regular = np.abs(r20) < 1 - 1e-9
    roll = np.where(regular, np.arctan2(m[:, 2, 1], m[:, 2, 2]), 0.0)
    yaw = np.where(regular, np.arctan2(m[:, 1, 0], m[:, 0, 0]), np.arctan2(-m[:, 0, 1], m[:, 1, 1]))
    return np.stack([roll, pitch, yaw], axis=1)
