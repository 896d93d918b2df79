"""Every part's and kit tray's fate in the simulated cell: where it truly is, what it truly is,
whether the robot could take it from there (:class:`kb.crcl.cell.Fate`), for the oracle of
what was buildable (:mod:`kb.metrics.oracle`). Ground truth, never told to the executor.

Where an object is, read from what it rests on (:attr:`World.parent <kb.sim.world.World.parent>`):

* ``held``: it moves with the robot (in its gripper, or what the gripper holds);
* ``kit``: a kit is among what it rests in (a part in a kit's tray; a kit tray is in its kit);
* ``parts-tray``: it rests in a parts tray;
* ``on``: it rests on or in another object (a work table, a box, an end effector holder);
* ``floor``: it rests on nothing: fallen to the floor (z = 0, where :meth:`World.drop
  <kb.sim.world.World.drop>` lets it land), or an object of the state placed with no support
  whose bottom is at floor height;
* ``gone``: it has no pose (taken out of the cell).

Reachable: held, or placed, not on the floor, and its grasp point (the top of its box, at the
box's centre) inside one of the robot's work volumes (within the world's tolerance); a state
without work volumes leaves that test out.
"""

from __future__ import annotations

import numpy as np

from kb.crcl.cell import Fate
from kb.sim.world import TOLERANCE, World


def fates(world: World, robot: int) -> list[Fate]:
    """The fate of every part and kit tray of ``world`` (its robot at index ``robot``), in the
    world's order."""
    held = set(world.subtree(robot))
    volumes = [box for boxes in world.work_volumes.values() for box in boxes]
    out = []
    for i, name in enumerate(world.names):
        kind = "part" if world.is_a(i, "Part") else "kit-tray" if world.is_a(i, "KitTray") else None
        if kind is None:
            continue
        place, holder = _place(world, i, held)
        out.append(Fate(name, kind, world.sku(i), name in world.defective, place, holder, _kit(world, i),
                        _reachable(world, i, place, volumes)))
    return out


def _place(world: World, i: int, held: set[int]) -> tuple[str, str | None]:
    if not world.placed(i):
        return "gone", None
    p = int(world.parent[i])
    holder = world.names[p] if p >= 0 else None
    if i in held:
        return "held", holder
    if p < 0:
        return ("floor" if float(world.box(i)[0][2]) <= TOLERANCE else "on"), None
    if _kit(world, i) is not None:
        return "kit", holder
    return ("parts-tray" if world.is_a(p, "PartsTray") else "on"), holder


def _kit(world: World, i: int) -> str | None:
    """The kit among what ``i`` rests in (a kit tray's own kit), walking up its supports."""
    j, seen = int(world.parent[i]), set()
    while j >= 0 and j not in seen:
        if world.is_a(j, "Kit"):
            return world.names[j]
        seen.add(j)
        j = int(world.parent[j])
    return None


def _reachable(world: World, i: int, place: str, volumes: list[tuple[np.ndarray, np.ndarray]]) -> bool:
    if place == "held":
        return True
    if place in ("gone", "floor"):
        return False
    if not volumes:
        return True
    lo, hi = world.box(i)
    point = np.array([(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, hi[2]])
    return any(bool(np.all((point >= vlo - TOLERANCE) & (point <= vhi + TOLERANCE))) for vlo, vhi in volumes)
