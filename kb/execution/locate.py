"""Sensing the objects a state does not locate, before planning (the closed loop's ``locate`` stage).

A state file may leave objects unlocated (:mod:`kb.spatial.unlocated`: no primary location,
or a relative one). Before it plans, the loop asks the cell's sensor for each such object's
class (:class:`kb.crcl.cell.Senses`, the one protocol every cell kind speaks: in process,
``kitkb://``, ``crcl://...?sensor=``), picks the answer that names the object, finds by
geometry the object that contains the sensed pose (the smallest placed object whose world box
holds its frame's origin: the parts tray it lies in; none: the workstation), and writes the
state with each object's primary location a pose in that container's frame
(:func:`kb.scenario.partial.with_locations`). An object the sensor does not report is a
one-line :class:`~kb.core.errors.InputError` (exit 2) at its line: a plan made without it
could not be trusted to build the kits.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Sequence

import numpy as np
from rdflib.namespace import RDF

from kb.core.errors import InputError
from kb.core.namespaces import KTW, local_name
from kb.core.units import SI, Units
from kb.crcl.cell import Observation, require
from kb.scenario.partial import Placement
from kb.spatial.scene import STAND_INS, Scene
from kb.spatial.transforms import from_xyz_rpy
from kb.spatial.unlocated import Unlocated

#: how far a sensed frame's origin may lie outside a container's box and still be in it
#: (a part's frame is on the tray's floor, on the face of its box)
TOLERANCE = 0.002
#: how many times the sensor is asked for an object it has not reported (then it is refused)
LOOKS = 3
_NOT_CONTAINERS = frozenset(STAND_INS) | {str(KTW.Robot)}


@dataclass
class Located:
    """The ``locate`` stage's result: ``asked`` the unlocated objects, ``placements`` where the
    sensor found them (container and pose), ``queries`` the classes asked for, ``units`` the
    state's (for the report), ``truth``: where the cell says they really were, when it tells
    (a simulated cell's ``hidden``: ground truth, for the report only)."""

    asked: list[Unlocated]
    placements: list[Placement] = field(default_factory=list)
    queries: list[str] = field(default_factory=list)
    units: Units = SI
    truth: list[Placement] = field(default_factory=list)

    def text(self) -> str:
        where = ", ".join(f"{local_name(p.name)} in {local_name(p.container)}" for p in self.placements)
        return (f"locate: {len(self.placements)} of {len(self.asked)} unlocated object(s) sensed by class "
                f"({', '.join(local_name(q) for q in self.queries)}): {where}")

    def as_dict(self) -> dict[str, Any]:
        """The report's ``located`` section."""
        return {"asked": [u.as_dict() for u in self.asked], "classes": [local_name(q) for q in self.queries],
                "sensed": [p.as_dict(self.units) for p in self.placements],
                "truth": [p.as_dict(self.units) for p in self.truth]}


def locate(cell: Any, scene: Scene, asked: Sequence[Unlocated], workstation: str | None = None) -> Located:
    """Sense ``asked`` (the unlocated objects of ``scene``'s state) on ``cell`` by class; each
    found placed in its container (:class:`Located`). ``workstation``: the world frame's object,
    the reference of an object found in no container. An object the sensor does not report is
    an InputError naming it at its line (after :data:`LOOKS` looks)."""
    require(cell, ["sense"], "sensing the objects the state does not locate")
    queries = sorted({u.cls for u in asked})
    seen: dict[str, Observation] = {}
    for _ in range(LOOKS):  # a sensor that misdetects may miss an object on one look
        for cls in sorted({u.cls for u in asked if local_name(u.name) not in seen}):
            for obs in cell.sense(local_name(cls), by="class"):
                seen.setdefault(local_name(obs.name), obs)
        if all(local_name(u.name) in seen for u in asked):
            break
    located = Located(list(asked), queries=queries, units=scene.units,
                      truth=list(getattr(cell, "hidden", None) or []))  # a simulated cell's ground truth
    for u in asked:
        obs = seen.get(local_name(u.name))
        if obs is None:
            raise InputError(f"{local_name(u.name)}'s location is unknown and the cell's sensor did not find it "
                             f"(asked {LOOKS} times for class {local_name(u.cls)}); the kits cannot be planned without it",
                             u.path, u.line)
        pose = from_xyz_rpy(*obs.location, *obs.orientation)
        c = container(scene, pose[:3, 3], exclude=u.name)
        if c is None:
            if workstation is None:
                raise InputError(f"{local_name(u.name)} was sensed in no container and the state has no "
                                 "workstation to place it in", u.path, u.line)
            located.placements.append(Placement(u.name, workstation, pose, pose))
        else:
            local = np.linalg.inv(scene.poses[c]) @ pose
            located.placements.append(Placement(u.name, scene.names[c], local, pose))
    return located


def container(scene: Scene, point: np.ndarray, exclude: str | None = None) -> int | None:
    """The index of the smallest placed object of ``scene`` whose world box holds ``point``
    (within :data:`TOLERANCE`), not counting objects that only lend another's box (kits,
    large boxes, changing stations) nor robots; None when none does."""
    if not len(scene):
        return None
    inside = scene.placed & np.all(scene.lo - TOLERANCE <= point, axis=1) & np.all(point <= scene.hi + TOLERANCE, axis=1)
    best, volume = None, np.inf
    for i in np.flatnonzero(inside):
        if scene.names[i] == exclude or scene.classes[i] & _NOT_CONTAINERS:
            continue
        v = float(np.prod(scene.hi[i] - scene.lo[i]))
        if 0 < v < volume:
            best, volume = int(i), v
    return best


def workstation_of(source: Any) -> str | None:
    """The kitting workstation a state file declares (the world frame), or None."""
    found = sorted(str(s) for s in source.view().subjects(RDF.type, KTW.KittingWorkstation))
    return found[0] if found else None
