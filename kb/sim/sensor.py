"""The simulated sensor: focus-of-attention queries on ground truth, and USARTruth's text form.

Seed 004 §3.2: a query names a class or an object; the answer is one key-value line per
matching object::

    {Name part_a_1} {Class Part} {Time 12.5} {Location 1.0,2.0,0.3} {Rotation 0.0,0.0,1.57}

(Name, Class: the most specific class, Time: simulated seconds, Location: global x,y,z,
Rotation: global roll,pitch,yaw). :func:`observe` answers a query from a
:class:`~kb.sim.world.World`, with optional Gaussian noise drawn from the cell's seeded
generator, and the SKU it recognises (``{Sku sku_part_a}``: the local name of the object's
``hasSkuObject_Sku``, a kit's tray's), so a part of the wrong SKU shows.
:func:`truth_line` / :func:`parse_truth_line`, the text form (numbers written with ``repr``, so
a line reads back to the same floats), are the cell contract's (:mod:`kb.crcl.cell`).
"""

from __future__ import annotations

import math
from functools import lru_cache
from typing import Literal

import numpy as np

from kb.core.namespaces import KTW, local_name
from kb.crcl.cell import Observation, parse_truth_line, truth_line
from kb.sim.world import SKU, World
from kb.spatial.scene import class_ancestors

__all__ = ["matches", "most_specific", "observe", "parse_truth_line", "rpy", "truth_line"]


@lru_cache(maxsize=None)
def most_specific(classes: frozenset[str]) -> str:
    """Local name of the most specific kitting class among ``classes`` (the one with most ancestors)."""
    anc = class_ancestors()
    ktw = [c for c in classes if c.startswith(str(KTW))]
    if not ktw:
        return ""
    best = max(ktw, key=lambda c: (len(anc.get(c, ())), c))
    return best[len(str(KTW)):]


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


def observe(world: World, query: str, by: Literal["class", "name"], time: float,
            noise: tuple[float, float] = (0.0, 0.0), rng: np.random.Generator | None = None) -> list[Observation]:
    """Observations of the placed objects answering ``query``, in name order.

    ``noise``: (position sigma in metres, orientation sigma in radians) of Gaussian noise added
    to each coordinate, drawn from ``rng``; none is drawn when both are 0.
    """
    out = []
    sp, so = noise
    skus: dict[str, str] = {}  # name -> its SKU, as World.sku gives it (one pass, not one per object)
    for s, o in world.facts.get(SKU, ()):
        if s not in skus or o < skus[s]:
            skus[s] = o
    placed = ~(np.isnan(world.poses[:, 0, 0]) | np.isnan(world.local_lo[:, 0]))
    chosen = [i for i in sorted(range(len(world)), key=lambda k: world.names[k])
              if placed[i] and matches(world, i, query, by)]
    if not chosen:
        return out
    locs = world.poses[chosen, :3, 3].astype(float)
    oris = _rpy_many(world.poses[chosen])
    for k, i in enumerate(chosen):
        loc, ori = locs[k], oris[k]
        if (sp or so) and rng is not None:
            loc = loc + rng.normal(0.0, sp, 3) if sp else loc
            ori = ori + rng.normal(0.0, so, 3) if so else ori
        sku = skus.get(world.names[i]) or (world.sku(i) if world.is_a(i, "Kit") else None)
        out.append(Observation(world.names[i], most_specific(world.classes[i]), float(time),
                               tuple(loc.tolist()), tuple(ori.tolist()),  # type: ignore[arg-type]
                               local_name(sku) if sku else None))
    return out


def _rpy_many(m: np.ndarray) -> np.ndarray:
    """(K, 3) roll, pitch, yaw of K rotations, as :func:`rpy` gives them one by one."""
    r20 = m[:, 2, 0]
    pitch = np.arcsin(np.clip(-r20, -1.0, 1.0))
    regular = np.abs(r20) < 1 - 1e-9
    roll = np.where(regular, np.arctan2(m[:, 2, 1], m[:, 2, 2]), 0.0)
    yaw = np.where(regular, np.arctan2(m[:, 1, 0], m[:, 0, 0]), np.arctan2(-m[:, 0, 1], m[:, 1, 1]))
    return np.stack([roll, pitch, yaw], axis=1)
