"""Trays placed and turned on their tables, a seeded layout per run of a test method.

The first paper's basic kit test method (seed 000 §III-B): "the actual location of the kit tray
and parts supplies will not be known before runtime. The location and orientation (yaw) of the
kit and parts supplies will be varied during consecutive runs". :func:`place_trays` takes a
laid-out scenario (its nominal layout) and a seed and gives the same workstation with every
parts tray on the parts table, and every kit tray that starts on the work table, somewhere else
on its table and turned by a yaw drawn over the full circle:

* each tray is drawn anywhere its turned footprint lies wholly on its table (so within the
  robot's work volume, which holds the tables), :data:`MARGIN` in from the edges, and drawn
  again while it comes nearer than :data:`GAP` to a tray already placed;
* a table too crowded for that after :data:`TRIES` draws a tray gets each of its trays in its
  own cell of the nominal grid (which a spec's ``room`` sizes for a tray at any yaw) at a drawn
  yaw and offset.

Kit trays in the storage box and everything else stay where the nominal layout has them. The
same scenario and seed give the same placement (``random.Random(seed)``, numbers rounded as the
files write them).
"""

from __future__ import annotations

import dataclasses
import math
import random
from dataclasses import dataclass

from kb.scenario.layout import TABLE_H, Pose, Scenario, pose, yaw_axes

#: no two trays nearer than this (m)
GAP = 0.02
#: a tray's footprint stays this far in from its table's edges (m)
MARGIN = 0.01
#: draws of one tray before a table falls back to its grid
TRIES = 200


@dataclass(frozen=True)
class Placement:
    """Where a tray stands: ``x``, ``y`` in its table's frame (m), turned ``yaw`` degrees."""

    obj: str
    table: str
    x: float
    y: float
    yaw: float

    def as_dict(self) -> dict[str, object]:
        return {"object": self.obj, "on": self.table, "x": self.x, "y": self.y, "yaw_deg": self.yaw}


def placements(sc: Scenario) -> list[Placement]:
    """The placed trays of ``sc`` as its layout has them (parts trays, then kit trays on the
    work table)."""
    out = [Placement(t.name, "parts_table_1", t.pose[0], t.pose[1], _yaw(t.pose)) for t in sc.trays]
    out += [Placement(k.tray, "work_table_1", k.tray_pose[0], k.tray_pose[1], _yaw(k.tray_pose))
            for k in sc.kits if k.on_table]
    return out


def place_trays(sc: Scenario, seed: int) -> tuple[Scenario, list[Placement]]:
    """``sc`` with its placed trays (:func:`placements`) moved and turned as drawn from ``seed``,
    and the new placements."""
    rng = random.Random(seed)
    nominal = placements(sc)
    dims = {t.name: sc.skus["sku_parts_tray"].dims[:2] for t in sc.trays}
    dims.update({k.tray: sc.skus["sku_kit_tray"].dims[:2] for k in sc.kits if k.on_table})
    drawn: dict[str, Placement] = {}
    for table in dict.fromkeys(p.table for p in nominal):
        on = [p for p in nominal if p.table == table]
        size = sc.floor[table][1][:2]
        drawn.update({p.obj: p for p in _on_table(rng, on, dims, size, sc.spec.room)})
    _check_reach(sc, drawn.values())
    trays = [dataclasses.replace(t, pose=pose_of(drawn[t.name])) for t in sc.trays]
    kits = [dataclasses.replace(k, tray_pose=pose_of(drawn[k.tray])) if k.on_table else k for k in sc.kits]
    return dataclasses.replace(sc, trays=trays, kits=kits), [drawn[p.obj] for p in nominal]


def _on_table(rng: random.Random, trays: list[Placement], dims: dict, size: tuple[float, float],
              room: float) -> list[Placement]:
    """The trays of one table, drawn anywhere on it; each in its own grid cell if it is crowded."""
    placed: list[Placement] = []
    for t in trays:
        for _ in range(TRIES):
            p = _draw(rng, t, dims[t.obj], size)
            if p is not None and not any(_meet(p, dims[p.obj], q, dims[q.obj]) for q in placed):
                placed.append(p)
                break
        else:
            return [_in_cell(rng, t, dims[t.obj], room) for t in trays]
    return placed


def _draw(rng: random.Random, t: Placement, dims: tuple[float, float], size: tuple[float, float]) -> Placement | None:
    yaw = round(rng.uniform(0.0, 360.0), 3) % 360.0
    ex, ey = _extents(dims, yaw)
    sx, sy = size[0] / 2 - MARGIN - ex, size[1] / 2 - MARGIN - ey
    if sx < 0 or sy < 0:
        return None
    return Placement(t.obj, t.table, round(rng.uniform(-sx, sx), 6), round(rng.uniform(-sy, sy), 6), yaw)


def _in_cell(rng: random.Random, t: Placement, dims: tuple[float, float], room: float) -> Placement:
    """Around the nominal place, by up to the cell's spare room (none when the spec has none)."""
    yaw = round(rng.uniform(0.0, 360.0), 3) % 360.0 if room > 0 else t.yaw
    slack = max(0.0, room - GAP / 2)
    return Placement(t.obj, t.table, round(t.x + rng.uniform(-slack, slack), 6),
                     round(t.y + rng.uniform(-slack, slack), 6), yaw)


def _extents(dims: tuple[float, float], yaw: float) -> tuple[float, float]:
    """Half the sides of the axis-aligned box around a ``dims`` footprint turned by ``yaw``."""
    c, s = abs(math.cos(math.radians(yaw))), abs(math.sin(math.radians(yaw)))
    return (dims[0] * c + dims[1] * s) / 2, (dims[0] * s + dims[1] * c) / 2


def _corners(p: Placement, dims: tuple[float, float], grow: float) -> list[tuple[float, float]]:
    a = math.radians(p.yaw)
    c, s = math.cos(a), math.sin(a)
    hx, hy = dims[0] / 2 + grow, dims[1] / 2 + grow
    return [(p.x + c * u - s * v, p.y + s * u + c * v) for u, v in ((hx, hy), (-hx, hy), (-hx, -hy), (hx, -hy))]


def _meet(p: Placement, pd: tuple[float, float], q: Placement, qd: tuple[float, float]) -> bool:
    """True when the footprints of p and q, each grown by half of :data:`GAP`, overlap
    (separating axes of two rectangles)."""
    a, b = _corners(p, pd, GAP / 2), _corners(q, qd, GAP / 2)
    for poly in (a, b):
        for i in range(2):
            (x0, y0), (x1, y1) = poly[i], poly[i + 1]
            axis = (y0 - y1, x1 - x0)
            pa = [axis[0] * x + axis[1] * y for x, y in a]
            pb = [axis[0] * x + axis[1] * y for x, y in b]
            if max(pa) < min(pb) or max(pb) < min(pa):
                return False
    return True


def _check_reach(sc: Scenario, drawn) -> None:  # noqa: ANN001
    """Every placed tray's footprint within the robot's work volume (true by construction: the
    volume holds the tables; checked so that a change of layout cannot break it unseen)."""
    (x0, y0, _), (x1, y1, _) = sc.work_volume
    for p in drawn:
        table = sc.floor[p.table][0]
        dims = sc.skus["sku_parts_tray" if p.table == "parts_table_1" else "sku_kit_tray"].dims[:2]
        for x, y in _corners(p, dims, 0.0):
            gx, gy = table[0] + x, table[1] + y
            if not (x0 <= gx <= x1 and y0 <= gy <= y1):
                raise ValueError(f"{p.obj} placed outside the robot's work volume")


def pose_of(p: Placement) -> Pose:
    """The pose of a placed tray on its table (the table's frame)."""
    return pose(p.x, p.y, TABLE_H, yaw_axes(p.yaw))


def _yaw(p: tuple) -> float:
    return round(math.degrees(math.atan2(p[4], p[3])) % 360.0, 3)
