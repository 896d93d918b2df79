"""A simulated robot executing CRCL commands on the ground truth (:class:`~kb.sim.world.World`).

Conventions (those of the state files):

* the robot's pose is its tool flange, z along the tool (down when the tool points down); its
  box is the flange (0.1 x 0.1 x 0.02 in kitkb's scenarios, a point in NIST's), extending from
  its origin along +z. An end effector's frame is its mount face, its box extends along +z too;
  a mounted effector's frame is ``flange @ translate(0, 0, flange height)``;
* a CRCL pose (``MoveTo``, ``MoveStraightTo``, ``MoveThroughTo``) is the pose of the tool tip:
  the far face of the mounted effector (``effector @ translate(0, 0, effector length)``), or
  the flange's far face with no effector. So ``flange = tip @ translate(0, 0, -(effector
  length + flange height))``;
* moves are instantaneous: the end pose is reached (through the waypoints); the clock advances
  by the tip's path length / speed (``SetAbsoluteSpeed``, default 1 m/s, in the length unit in force); ``Dwell`` adds its time;
* the path: ``MoveStraightTo`` a straight line, ``MoveThroughTo`` straight legs through its
  waypoints, ``MoveTo`` (CRCL: "any convenient trajectory") up, across and down
  (:meth:`Robot.transfer`): straight up to the transfer height, across at that height,
  straight down — a pick-and-place robot's way. The transfer height is the higher of the
  start's and the target's, or higher where what the robot carries would not clear a solid
  below its way across (a box's walls around the start, a table on the way): the
  controller chooses a MoveTo's path, so it goes over what it can see; a program that chooses
  its path (MoveStraightTo, MoveThroughTo) can run into things, and so can a MoveTo's legs
  straight up and down. The orientation turns uniformly along a leg (about one axis; for
  MoveTo, across);
* ``CloseGripper`` grasps the object whose top face is at the tip (within :data:`GRASP_TOLERANCE`
  = 2 x :data:`kb.spatial.rcc8.DEFAULT_TOLERANCE` = 2 mm) and whose footprint contains the
  tip's x, y (its own footprint, in its frame: a part of a turned tray, not its world box) —
  if the mounted effector suits it (listed by its SKU, ``hasStockKeepingUnit_EndEffector``; a
  kit by its kit tray's SKU: touching a kit's tray grasps the kit). Otherwise it grasps
  nothing, which is not an error (the executor's checks find it).
  The held object then moves rigidly with the tip; ``OpenGripper`` lets it fall straight down
  (:meth:`World.drop`) onto what is below, its new parent;
* ``CloseToolChanger`` mounts the free end effector whose mount face is at the flange's far face
  (within :data:`GRASP_TOLERANCE`); the effector keeps its orientation (its z axis is taken to
  be along the flange's, as in a holder that presents it tool-down). ``OpenToolChanger``
  leaves it where it is: in the holder it sits in, else it falls;
* units: ``InitCanon`` sets the length and angle units back to the defaults of the form the
  robot is driven in (``length_unit``, ``angle_unit``: CRCL 1.x's metre and radian in process
  and on the CRCL 1.x wire; a paper-form program played by :mod:`kb.sim.playback`,
  millimetre and degree; docs/crcl.md) until a ``SetLengthUnits`` (meter, millimeter, inch)
  or ``SetAngleUnits`` (degree, radian) says otherwise: the positions, speeds and point
  tolerances of the commands after it are in that length unit, rotational speeds
  (``SetRotSpeed``: a move takes at least its turn / that speed) and angle tolerances in that
  angle unit (the ground truth stays in metres and radians); another unit, a coordinate frame
  other than ``Workstation``, ``ActuateJoints`` (the robot has no joint model), ``RunProgram``
  and an ``Unreadable`` line are error statuses. ``SetEndEffector`` opens the gripper for
  a setting above 0 and closes it at 0 (a two-state gripper, as Reference.md says). Other
  commands are accepted;
* a move whose waypoint is no rigid pose (axes so large their norm overflows) or lies farther
  than :data:`REACH` (1 km) from the origin on an axis, a move or dwell that would overflow the
  clock, and a speed that is not a positive number are error statuses: the robot does not move,
  so every pose stays a finite rigid transform (``tests/test_sim_properties.py``).

Constraint violations (the first paper, §VI: "It will also be necessary to decide what the
simulation should do in these cases"), each reported through ``on_violation(kind, objects,
detail)`` (:class:`kb.sim.SimulatedCell` keeps them as ``violations``); a check the state file
gives no numbers for (no weight, no load, no work volume) is not made:

* ``overweight`` — ``CloseGripper`` on an object heavier than the mounted effector's
  ``hasEndEffector_MaximumLoadWeight``, or than the robot's ``hasRobot_MaximumLoadWeight``
  with the effector's own ``hasEndEffector_Weight`` (the load hangs on the flange). An
  object's weight is its SKU's ``hasStockKeepingUnit_Weight`` plus that of everything that
  moves with it (a kit: its tray and its parts). The robot lifts nothing and the command is an
  error status (the arm cannot lift it; what a program does next is its own);
* ``work-volume`` — a move with a tip point (its target, a waypoint, the corners of MoveTo's
  path) outside every ``hasRobot_WorkVolume`` box of the robot (workstation frame, within the
  tolerance; a box holds the straight legs between its points). The move is carried out and
  counted, its status says so: the box is all kitkb knows of the arm's reach, and refusing
  would stop a run on a file whose box does not hold its own objects (NIST's
  kittingInstancesInit1: a 2 m box at the origin, trays at x 1.5 to 8.75 m);
* ``wrong-effector`` — ``CloseGripper`` on an object whose SKU lists end effectors
  (``hasStockKeepingUnit_EndEffector``), not the mounted one. It grasps nothing, as before
  (status done, "nothing grasped"). An object whose SKU lists none is not checked;
* ``contact`` — along every move, the flange, the mounted effector or the held object (with
  what rests in it) passing through another solid (:mod:`kb.spatial.sweep`: continuous, the
  whole path, so no part is too small or too fast to be missed; touching within the
  tolerance is not contact). Not counted: what moves together, what the tip starts or ends
  on (the object grasped or just released and what is in it — a vacuum cup over a kit's
  parts —, the effector being mounted), and the holder of the mounted effector or of the
  one at the tip (the holder listing it, ``hasEndEffectorHolder_EndEffector``, or the one it
  sits in at the start or the end of the move: NIST's effectors hang through their holders,
  thin solid plates). One violation per (moving object, solid) per
  command; the move goes on (a simulation does not stop at a collision; the count is the
  metric).
"""

from __future__ import annotations

from typing import Any, Callable

import re

import numpy as np

from kb import crcl
from kb.core.namespaces import local_name
from kb.core.units import ANGLE, LENGTH
from kb.crcl.cell import Status
from kb.sim.world import EFFECTOR_LOAD, EFFECTOR_WEIGHT, HOLDER_EFFECTOR, ROBOT_LOAD, TOLERANCE, World, translate
from kb.spatial.sweep import Pieces, clearance, recessed, solid_pieces, sweep_contacts

GRASP_TOLERANCE = 2 * TOLERANCE
#: A held part armed to drop falls in the first move that carries its tip this far sideways (m).
TRANSIT = 0.05
#: How far (m) from the workstation's origin a target may be on any axis: far beyond any cell,
#: near enough that poses composed there stay rigid to well under a micrometre.
REACH = 1000.0
_EYE3 = np.eye(3)
_RIGID = 1e-9 + 1e-5 * _EYE3  # np.allclose's bound for (R^T R, I): atol + rtol |I|

#: primitive, objects, detail -> None: how the robot reports an armed fault taking effect, by the
#: name of the attribute that armed it (``miss_grasp``, ``drop_in_transit``; kb.sim.faults maps it back).
FaultHook = Callable[[str, tuple[str, ...], str], None]
#: The constraint violations the robot notices (module docstring), in the order it checks them.
VIOLATION_KINDS: tuple[str, ...] = ("overweight", "work-volume", "wrong-effector", "contact")
#: violation kind, objects, detail -> None: how the robot reports a constraint violation.
ViolationHook = Callable[[str, tuple[str, ...], str], None]


class Robot:
    """The robot of a :class:`World`: its flange, mounted effector, held object and the clock."""

    def __init__(self, world: World, on_fault: FaultHook | None = None,
                 on_violation: ViolationHook | None = None) -> None:
        self.world = world
        robots = [i for i in range(len(world)) if world.is_a(i, "Robot") and world.placed(i)]
        if not robots:
            raise ValueError("the state has no placed robot")
        self.index = robots[0]
        self.time = 0.0
        self.speed = 1.0  # m/s
        self.metres = 1.0  # metres per length unit of the commands (CRCL SetLengthUnits; metre by default)
        self.radians = 1.0  # radians per angle unit of the commands (CRCL SetAngleUnits)
        # the units InitCanon sets (CRCL: "units ... back to their defaults"): the form driven in
        self.length_unit, self.angle_unit = crcl.CRCL1_UNITS
        self.rot_speed: float | None = None  # rad/s (SetRotSpeed); None: turns take no longer than moves
        self.tolerances: dict[str, float] = {}  # end / intermediate point (m) and angle (rad) tolerances
        self.on_fault = on_fault or (lambda kind, objects, detail: None)
        self.on_violation = on_violation or (lambda kind, objects, detail: None)
        self._holes: dict | None = None  # open containers recessed in closed objects (on the first move)
        self._piece_key: tuple | None = None
        self._all_pieces: Pieces | None = None
        self._split_key: tuple | None = None  # what _split was made for, and its result
        self._split_of: tuple = ((), None, None)
        self._contacts: dict[tuple[str, str], str] | None = None  # contacts of the move under way
        self.miss_grasp = False  # armed faults (kb.sim.faults)
        self.drop_in_transit = False
        mounted = [j for j in world.children(self.index) if world.is_a(j, "EndEffector")]
        self.effector: int | None = mounted[0] if mounted else None
        held = world.children(self.effector) if self.effector is not None else []
        self.held: int | None = held[0] if held else None
        self.disabled: set[int] = set()  # effectors disabled by DisableGripper (no SetEndEffector until enabled)
        self.parameter_status: set[str] = set()  # robot parameters a client asked to be reported (none are)

    # --- geometry ---------------------------------------------------------------------
    @property
    def flange(self) -> np.ndarray:
        """The flange pose."""
        return self.world.poses[self.index]

    def _length(self, i: int) -> float:
        return float(self.world.local_hi[i, 2])

    def tool_length(self) -> float:
        """Flange height plus the mounted effector's length: flange origin to tool tip."""
        eff = self._length(self.effector) if self.effector is not None else 0.0
        return self._length(self.index) + eff

    def tip(self) -> np.ndarray:
        """The tool tip pose (what CRCL poses give)."""
        return self.flange @ translate(0.0, 0.0, self.tool_length())

    # --- commands ---------------------------------------------------------------------
    def execute(self, command: crcl.Command) -> Status:
        """Carry out one CRCL command."""
        handler = _HANDLERS.get(type(command))
        if handler is not None:
            return handler(self, command)
        if isinstance(command, crcl.Unreadable):
            return Status.error(f"unreadable command: {command.text!r}")
        return Status.ok()

    def move(self, waypoints: tuple[crcl.Pose, ...], straight: bool = True) -> Status:
        """Move the tip through ``waypoints`` to the last one, in straight legs, or (``straight``
        false: MoveTo's "any convenient trajectory") up, across and down (:func:`transfer`); a
        waypoint that is no rigid pose, or out of :data:`REACH`, or a path the clock cannot time,
        or a waypoint out of the work volume, is an error status and the robot does not move."""
        targets = []
        for pose in waypoints:
            try:
                targets.append(_target(pose, self.metres))
            except ValueError as e:
                return Status.error(f"bad pose: {e}")
        if not straight:
            targets = self.transfer(self.tip(), targets[-1])
        points = np.array([self.tip()[:3, 3]] + [t[:3, 3] for t in targets])
        seconds = float(np.linalg.norm(np.diff(points, axis=0), axis=1).sum()) / self.speed
        if not np.isfinite(self.time + seconds):
            return Status.error(f"a path of {seconds} s at {self.speed} m/s: the clock would overflow")
        outside = self._outside_work_volume(points[1:])
        self._contacts = {}
        try:
            for target in targets:
                self._segment(target)
        finally:
            found, self._contacts = self._contacts, None
        for (body, obstacle), detail in found.items():
            self.on_violation("contact", (body, obstacle), detail)
        return Status.ok(outside or "")

    def _outside_work_volume(self, points: np.ndarray) -> str | None:
        """Why a move with these tip points leaves the robot's work volume (the union of its
        boxes: a straight leg between points of one box stays in it), reported as a violation;
        None when every point is inside one (within the tolerance) or the state gives none."""
        volumes = self.world.work_volumes.get(self.world.names[self.index])
        if not volumes:
            return None
        inside = np.zeros(len(points), bool)
        for lo, hi in volumes:
            inside |= np.all((points >= lo - TOLERANCE) & (points <= hi + TOLERANCE), axis=1)
        if inside.all():
            return None
        p = points[int(np.argmin(inside))]
        boxes = ", ".join(f"{_xyz(lo)} .. {_xyz(hi)}" for lo, hi in volumes)
        detail = f"tip target {_xyz(p)} is outside the work volume {boxes}"
        self.on_violation("work-volume", (self.world.names[self.index],), detail)
        return detail

    def _segment(self, target: np.ndarray) -> None:
        start = self.tip()
        step = target[:3, 3] - start[:3, 3]
        if (self.drop_in_transit and self.held is not None and self.world.is_a(self.held, "Part")
                and np.linalg.norm(step[:2]) >= TRANSIT):
            mid = target.copy()
            mid[:3, 3] = start[:3, 3] + step / 2
            self._go(mid)
            name = self.world.names[self.held]
            support = self._release()
            self.drop_in_transit = False
            where = self.world.names[support] if support >= 0 else "the floor"
            self.on_fault("drop_in_transit", (name,), f"fell at {_xyz(mid[:3, 3])} onto {where}")
        self._go(target)
        seconds = float(np.linalg.norm(step)) / self.speed
        if self.rot_speed is not None:
            seconds = max(seconds, _turn(start, target) / self.rot_speed)
        self.time += seconds

    def _go(self, tip: np.ndarray) -> None:
        if self._contacts is not None:
            self._sweep(self.tip(), tip)
        self.world.set_pose(self.index, tip @ translate(0.0, 0.0, -self.tool_length()))

    def transfer(self, start: np.ndarray, end: np.ndarray) -> list[np.ndarray]:
        """The legs of a MoveTo from tip pose ``start`` to ``end`` (its "convenient trajectory"):
        straight up to the transfer height, across at that height (turning to the end
        orientation), straight down; legs of no length left out. The transfer height is the
        higher end point's, or higher where what the robot carries would not clear a solid
        below its way across (kb.spatial.sweep.clearance)."""
        up, over = start.copy(), end.copy()
        up[2, 3] = over[2, 3] = 0.0
        bodies, pieces = self._split()
        rise, high = -np.inf, max(float(start[2, 3]), float(end[2, 3]))
        if bodies and len(pieces):
            w = self.world
            rel = np.linalg.inv(start) @ w.poses[bodies]
            rise = clearance(np.array([up, over]), rel, w.local_lo[bodies], w.local_hi[bodies], w.poses, pieces,
                             above=high)  # a rise no higher than the end points' is not needed
        up[2, 3] = over[2, 3] = max(high, rise)
        legs, last = [], start
        for pose in (up, over, end):
            if not (np.array_equal(pose[:3, 3], last[:3, 3]) and np.array_equal(pose[:3, :3], last[:3, :3])):
                legs.append(pose)
                last = pose
        return legs or [end]

    def _split(self) -> tuple[list[int], Pieces]:
        """(the boxes that move with the flange: itself, the mounted effector, the held object
        and what rests in it (not stand-ins: a held kit is its tray); the solid pieces of
        everything else), kept while what rests on what, what is placed and the solid pieces
        are the same (every move asks, few moves change them)."""
        w = self.world
        pieces, mask = self._pieces(), w.solid_mask()
        key = (w.parent.tobytes(), mask.tobytes(), self.index)
        if self._split_key != key or self._split_of[1] is not pieces:
            subtree = w.subtree(self.index)
            moving = [j for j in subtree if mask[j]]
            mask[subtree] = False
            self._split_key, self._split_of = key, (moving, pieces, pieces.select(mask[pieces.owner]))
        return list(self._split_of[0]), self._split_of[2]

    def _sweep(self, start: np.ndarray, end: np.ndarray) -> None:
        """Contacts of the straight leg from tip pose ``start`` to ``end`` (kb.spatial.sweep):
        the flange, the mounted effector and the held object (with what rests in it) against
        every other solid, except what the tip starts or ends on (the object grasped or just
        released, a kit with its parts, the effector being mounted)."""
        w = self.world
        bodies, pieces = self._split()
        if not bodies or not len(pieces):
            return
        rel = np.linalg.inv(start) @ w.poses[bodies]
        found = sweep_contacts(np.array([start, end]), rel, w.local_lo[bodies], w.local_hi[bodies], w.poses, pieces)
        if not found:
            return
        skip: set[int] = set()
        effectors = [self.effector] if self.effector is not None else []
        for point in (start[:3, 3], end[:3, 3]):
            at = self._at_point(point)
            if at is not None:
                skip.update(w.subtree(at))
                effectors += [j for j in w.subtree(at) if w.is_a(j, "EndEffector")]
        to_end = end @ np.linalg.inv(start)
        for e in effectors:  # an effector's holder, which it is mounted from and stowed into
            skip.update(w.index[h] for h in w.subjects(HOLDER_EFFECTOR, w.names[e]) if h in w.index)
            for pose in (None, to_end @ w.poses[e] if e in bodies else None):
                holder = w.holder_around(e, pose)
                if holder is not None:
                    skip.add(holder)
        for c in found:
            key = (w.names[bodies[c.body]], w.names[c.owner])
            if c.owner in skip or self._contacts is None or key in self._contacts:
                continue
            self._contacts[key] = (f"{_local(key[0])} passes through {_local(key[1])} ({c.depth * 1000:.1f} mm "
                                   f"deep) on the way from {_xyz(start[:3, 3])} to {_xyz(end[:3, 3])}")

    def _pieces(self) -> Pieces:
        """The solid pieces of every object (:func:`kb.spatial.sweep.solid_pieces`), kept while
        the objects' boxes are the same (a fault giving a part another SKU changes its box, a kit
        takes its tray's); holes (holders recessed in a station's base) found once, on the first move."""
        w = self.world
        key = (w.local_lo.tobytes(), w.local_hi.tobytes(), w.open_top.tobytes())
        if self._piece_key != key:
            every = np.flatnonzero(~np.isnan(w.local_lo[:, 0]))
            if self._holes is None:
                self._holes = recessed(w.poses, w.local_lo, w.local_hi, w.open_top, np.array(w.solids(), np.intp))
            self._piece_key, self._all_pieces = key, solid_pieces(w.local_lo, w.local_hi, w.open_top, every, self._holes)
        return self._all_pieces

    def close_gripper(self) -> Status:
        """Grasp what is at the tip, if the mounted effector suits it."""
        if self.effector is None or self.held is not None:
            return Status.ok("nothing grasped" if self.held is None else "already holding")
        target = self._at_tip()
        if target is None:
            return Status.ok("nothing grasped: no top face at the tip")
        name, eff = self.world.names[target], self.world.names[self.effector]
        suits = self.world.effectors_for(target)
        if eff not in suits:
            if suits:  # its SKU lists others: a wrong effector (a SKU listing none: nothing to check)
                self.on_violation("wrong-effector", (eff, name), f"{_local(eff)} is not an end effector the SKU of "
                                  f"{_local(name)} lists ({', '.join(_local(e) for e in suits)})")
            return Status.ok(f"nothing grasped: {eff} does not suit {name}")
        heavy = self._overweight(target)
        if heavy is not None:
            self.on_violation("overweight", (name, eff), heavy)
            return Status.error(f"nothing grasped: {heavy}")
        if self.miss_grasp:
            self.miss_grasp = False
            self.on_fault("miss_grasp", (name,), f"the gripper closed on nothing above {name}")
            return Status.ok("nothing grasped")
        self.held = target
        self.world.parent[target] = self.effector
        return Status.ok(f"grasped {name}")

    def _overweight(self, target: int) -> str | None:
        """Why ``target`` (and what moves with it) is too heavy to lift with the mounted
        effector: more than the effector's maximum load, or with the effector's own weight
        more than the robot's; None when it is not, or the state gives no weight or no limit."""
        w = self.world
        load = w.weight(target)
        if load is None or self.effector is None:
            return None
        eff, robot = w.names[self.effector], w.names[self.index]
        why = []
        limit = w.number(EFFECTOR_LOAD, eff)
        if limit is not None and load > limit * (1 + 1e-9):
            why.append(f"{_local(eff)}'s maximum load {limit:g} kg")
        limit = w.number(ROBOT_LOAD, robot)
        total = load + (w.number(EFFECTOR_WEIGHT, eff) or 0.0)
        if limit is not None and total > limit * (1 + 1e-9):
            why.append(f"{_local(robot)}'s maximum load {limit:g} kg (with {_local(eff)}: {total:g} kg)")
        return f"{_local(w.names[target])} weighs {load:g} kg, more than {' and '.join(why)}" if why else None

    def _at_tip(self) -> int | None:
        """The object whose top face is at the tip and whose footprint contains it (a kit for its
        tray); the footprint is the object's own, in its frame (a turned part in a turned tray)."""
        return self._at_point(self.tip()[:3, 3])

    def _at_point(self, p: np.ndarray) -> int | None:
        """:meth:`_at_tip` for the tip at point ``p``."""
        js = np.array(self.world.solids(set(self.world.subtree(self.index))), np.int64)
        if not len(js):
            return None
        q, (lo, hi) = self.world.point_in_frames(p, js)
        gap = np.abs(hi[:, 2] - q[:, 2])
        inside = ((lo[:, :2] - TOLERANCE <= q[:, :2]) & (q[:, :2] <= hi[:, :2] + TOLERANCE)).all(axis=1)
        hits = np.flatnonzero(inside & (gap <= GRASP_TOLERANCE))
        if not len(hits):
            return None
        best = int(js[hits[np.argmin(gap[hits])]])  # the nearest top face; the first of equals
        kit = self.world.kit_of_tray(best)
        return kit if kit is not None else best

    def open_gripper(self) -> Status:
        """Release the held object where it is: it falls onto what is below."""
        if self.held is not None:
            self._release()
        return Status.ok()

    def _release(self) -> int:
        i, self.held = self.held, None
        assert i is not None
        self.world.parent[i] = -1
        return self.world.drop(i, set(self.world.subtree(self.index)))

    def close_tool_changer(self) -> Status:
        """Mount the free end effector whose mount face is at the flange's far face."""
        if self.effector is not None:
            return Status.ok("already mounted")
        face = (self.flange @ translate(0.0, 0.0, self._length(self.index)))[:3, 3]
        w = self.world
        for j in range(len(w)):
            if not (w.is_a(j, "EndEffector") and w.placed(j)) or j in w.subtree(self.index):
                continue
            if np.linalg.norm(w.poses[j, :3, 3] - face) <= GRASP_TOLERANCE:
                pose = w.poses[j].copy()
                pose[:3, 3] = face
                w.set_pose(j, pose)
                w.parent[j] = self.index
                self.effector = j
                return Status.ok(f"mounted {w.names[j]}")
        return Status.ok("nothing mounted")

    def open_tool_changer(self) -> Status:
        """Dismount the effector where it is: it stays in a holder, else falls."""
        j, self.effector = self.effector, None
        if j is None:
            return Status.ok()
        if self.held is not None and self.world.parent[self.held] == j:
            self.held = None  # it stays in the effector's grip
        holder = self.world.holder_around(j)
        if holder is not None:
            self.world.parent[j] = holder
        else:
            self.world.parent[j] = -1
            self.world.drop(j, set(self.world.subtree(self.index)))
        return Status.ok()

    def gripper_name(self, index: int | None = None) -> str:
        """The CRCL ``GripperName`` of the effector ``index`` (the mounted one by default): its
        local name as an XML name token (characters outside one as ``_``)."""
        j = self.effector if index is None else index
        return "" if j is None else re.sub(r"[^\w.:-]", "_", local_name(self.world.names[j])) or "effector"

    def enable_gripper(self, name: str, enable: bool) -> Status:
        """EnableGripper / DisableGripper ``name``: the mounted effector (by its GripperName, local
        name or IRI); a disabled gripper takes no SetEndEffector until enabled again."""
        verb = "EnableGripper" if enable else "DisableGripper"
        j = self.effector
        if j is None:
            return Status.error(f"{verb} {name}: no gripper is mounted")
        if name not in (self.gripper_name(), local_name(self.world.names[j]), self.world.names[j]):
            return Status.error(f"{verb} {name}: no gripper {name} on this controller "
                                f"(the mounted gripper is {self.gripper_name()})")
        (self.disabled.discard if enable else self.disabled.add)(j)
        return Status.ok(f"gripper {self.gripper_name()} {'enabled' if enable else 'disabled'}")

    def end_effector(self, c: crcl.Command) -> Status:
        """OpenGripper, CloseGripper, SetEndEffector (above 0: open); CRCL_Error when the mounted
        gripper is disabled (DisableGripper)."""
        if self.effector is not None and self.effector in self.disabled:
            return Status.error(f"{type(c).__name__}: gripper {self.gripper_name()} is disabled "
                                f"(DisableGripper): EnableGripper {self.gripper_name()} first")
        if isinstance(c, crcl.CloseGripper) or (isinstance(c, crcl.SetEndEffector) and c.setting <= 0):
            return self.close_gripper()
        return self.open_gripper()

    def parameter_report(self, c: crcl.EnableRobotParameterStatus | crcl.DisableRobotParameterStatus) -> Status:
        """Enable/DisableRobotParameterStatus: recorded; the simulated robot has no parameters to report."""
        if isinstance(c, crcl.EnableRobotParameterStatus):
            self.parameter_status.add(c.name)
            return Status.ok(f"robot parameter {c.name}: recorded; the simulated robot has no parameters, "
                             "nothing is reported")
        self.parameter_status.discard(c.name)
        return Status.ok(f"robot parameter {c.name}: not reported")

    def dwell(self, seconds: float) -> Status:
        """Wait: the clock advances."""
        if not seconds >= 0:
            return Status.error(f"negative dwell time {seconds}")
        if not np.isfinite(self.time + seconds):
            return Status.error(f"a dwell of {seconds} s: the clock would overflow")
        self.time += seconds
        return Status.ok()

    def set_speed(self, speed: float) -> Status:
        """Set the tip speed (length units of the commands per second): positive and finite."""
        if not (speed > 0 and np.isfinite(speed * self.metres)):
            return Status.error(f"speed must be a positive number, not {speed}")
        self.speed = speed * self.metres
        return Status.ok()

    def set_length_units(self, unit: str) -> Status:
        """Lengths of the following commands are in ``unit`` (meter, millimeter, inch)."""
        metres = LENGTH.get(str(unit))
        if metres is None:
            return Status.error(f"SetLengthUnits {unit}: not one of {', '.join(LENGTH)}")
        self.metres = metres
        return Status.ok()

    def set_angle_units(self, unit: str) -> Status:
        """Angles of the following commands are in ``unit`` (degree, radian)."""
        radians = ANGLE.get(str(unit))
        if radians is None:
            return Status.error(f"SetAngleUnits {unit}: not one of {', '.join(ANGLE)}")
        self.radians = radians
        return Status.ok()

    def init_canon(self) -> Status:
        """InitCanon: the length and angle units back to the defaults (``length_unit``, ``angle_unit``)."""
        status = self.set_length_units(self.length_unit)
        return status if not status.done else self.set_angle_units(self.angle_unit)

    def set_rot_speed(self, c: crcl.RotSetting) -> Status:
        """SetRotSpeed: an absolute setting in angle units per second (positive); a relative one
        is a fraction of a maximum the simulated robot does not have, so turns stay untimed."""
        if isinstance(c, crcl.SetRotAccel):
            return Status.ok()  # moves are timed without acceleration
        if c.relative:
            self.rot_speed = None
            return Status.ok("a relative rotational speed: the simulated robot has no maximum; turns untimed")
        if not (c.setting > 0 and np.isfinite(c.setting * self.radians)):
            return Status.error(f"rotational speed must be a positive number, not {c.setting}")
        self.rot_speed = c.setting * self.radians
        return Status.ok()

    def set_tolerance(self, c: crcl.Command) -> Status:
        """The end and intermediate tolerances, kept in metres and radians."""
        t: Any = c
        if isinstance(c, crcl.SetEndAngleTolerance):
            self.tolerances["end angle"] = t.tolerance * self.radians
        elif isinstance(c, crcl.SetEndPointTolerance):
            self.tolerances["end point"] = t.tolerance * self.metres
        elif isinstance(c, crcl.SetIntermediatePointTolerance):
            self.tolerances["intermediate point"] = t.tolerance * self.metres
        else:
            where = "end" if isinstance(c, crcl.SetEndPoseTolerance) else "intermediate"
            for attr, scale in (("x_point", self.metres), ("y_point", self.metres), ("z_point", self.metres),
                                ("x_axis", self.radians), ("z_axis", self.radians)):
                value = getattr(t.tolerance, attr)
                if value is not None:
                    self.tolerances[f"{where} {attr.replace('_', ' ')}"] = value * scale
        return Status.ok()


def _target(pose: crcl.Pose, metres: float = 1.0) -> np.ndarray:
    """The 4x4 tip pose of a CRCL pose: a finite rigid transform within :data:`REACH` of the
    workstation's origin, else ValueError (an axis of 1e300 overflows its norm, and a point
    kilometres away is out of any workcell, where composing poses would lose their rigidity)."""
    with np.errstate(over="ignore", invalid="ignore"):
        m = pose.matrix()
    r = m[:3, :3]
    if not (np.isfinite(m).all() and (np.abs(r.T @ r - _EYE3) <= _RIGID).all()):  # np.allclose(r.T @ r, I, atol=1e-9)
        raise ValueError(f"axes {pose.z_axis} (Z), {pose.x_axis} (X) give no rotation")
    m[:3, 3] *= metres
    if np.abs(m[:3, 3]).max() > REACH:
        raise ValueError(f"point {pose.point} is out of reach (more than {REACH:g} m from the origin)")
    return m


def _turn(start: np.ndarray, end: np.ndarray) -> float:
    """The angle (radians) of the rotation from ``start``'s orientation to ``end``'s."""
    cos = (float(np.trace(start[:3, :3].T @ end[:3, :3])) - 1.0) / 2.0
    return float(np.arccos(min(1.0, max(-1.0, cos))))


def _refuse(why: str) -> Callable[[Robot, crcl.Command], Status]:
    return lambda r, c: Status.error(f"{type(c).__name__}: {why}")


def _unit(expected: str) -> Callable[[Robot, crcl.Command], Status]:
    def check(robot: Robot, c: crcl.Command) -> Status:
        value = getattr(c, "unit_name", None) or getattr(c, "coord_system", None)
        return Status.ok() if value == expected else Status.error(f"{type(c).__name__} {value}: only "
                                                                  f"{expected} is supported")
    return check


def _local(name: str) -> str:
    return name.rsplit("#", 1)[-1].rsplit("/", 1)[-1]


def _xyz(p: np.ndarray) -> str:
    return "(" + ", ".join(f"{float(v):.3f}" for v in p) + ")"


_HANDLERS: dict[type, Callable[[Robot, crcl.Command], Status]] = {
    crcl.InitCanon: lambda r, c: r.init_canon(),
    crcl.MoveTo: lambda r, c: r.move((c.end_position,), straight=False),  # type: ignore[attr-defined]
    crcl.MoveStraightTo: lambda r, c: r.move((c.end_position,)),  # type: ignore[attr-defined]
    crcl.MoveThroughTo: lambda r, c: r.move(tuple(c.waypoints)),  # type: ignore[attr-defined]
    crcl.CloseGripper: lambda r, c: r.end_effector(c),
    crcl.OpenGripper: lambda r, c: r.end_effector(c),
    crcl.CloseToolChanger: lambda r, c: r.close_tool_changer(),
    crcl.OpenToolChanger: lambda r, c: r.open_tool_changer(),
    crcl.Dwell: lambda r, c: r.dwell(c.dwell_time),  # type: ignore[attr-defined]
    crcl.SetAbsoluteSpeed: lambda r, c: r.set_speed(c.speed),  # type: ignore[attr-defined]
    crcl.SetLengthUnits: lambda r, c: r.set_length_units(c.unit_name),  # type: ignore[attr-defined]
    crcl.SetAngleUnits: lambda r, c: r.set_angle_units(c.unit_name),  # type: ignore[attr-defined]
    crcl.SetCoordinateFrame: _unit("Workstation"),
    crcl.SetEndEffector: lambda r, c: r.end_effector(c),
    crcl.SetRotSpeed: lambda r, c: r.set_rot_speed(c),  # type: ignore[arg-type]
    crcl.SetRotAccel: lambda r, c: r.set_rot_speed(c),  # type: ignore[arg-type]
    **dict.fromkeys((crcl.SetEndAngleTolerance, crcl.SetEndPointTolerance, crcl.SetIntermediatePointTolerance,
                     crcl.SetEndPoseTolerance, crcl.SetIntermediatePoseTolerance), lambda r, c: r.set_tolerance(c)),
    crcl.ActuateJoints: _refuse("the simulated robot has no joint model (its joint positions would be in the "
                                "angle or length units in force)"),
    crcl.RunProgram: _refuse("the simulated robot has no program language of its own"),
    crcl.EnableGripper: lambda r, c: r.enable_gripper(c.name, True),  # type: ignore[attr-defined]
    crcl.DisableGripper: lambda r, c: r.enable_gripper(c.name, False),  # type: ignore[attr-defined]
    crcl.EnableRobotParameterStatus: lambda r, c: r.parameter_report(c),  # type: ignore[arg-type]
    crcl.DisableRobotParameterStatus: lambda r, c: r.parameter_report(c),  # type: ignore[arg-type]
    crcl.ConfigureStatusReport: lambda r, c: Status.ok("this cell sends no status documents: nothing to configure"),
    **dict.fromkeys((crcl.EnableSensor, crcl.DisableSensor), lambda r, c: Status.error(
        f"{type(c).__name__}: no sensor {c.sensor_id} on this controller (the cell's sensor "  # type: ignore[attr-defined]
        "answers on its own port)")),
    crcl.SetDefaultJointPositionsTolerances: _refuse("the simulated robot has no joint model, so no joint "
                                                     "tolerances to honour"),
    crcl.Guarded: lambda r, c: Status.error(
        f"{type(c.command).__name__} guarded by {', '.join(sorted({g.sensor_id for g in c.guards}))}: "  # type: ignore[attr-defined]
        f"no sensor {', '.join(sorted({g.sensor_id for g in c.guards}))} on this controller to watch, "  # type: ignore[attr-defined]
        "so it is not executed"),
    crcl.MoveScrew: _refuse("the simulated robot does not screw (no screwing motion is modelled)"),
    **dict.fromkeys((crcl.LoopBlockStart, crcl.LoopBlockEnd), _refuse(
        "this controller executes no loops: send the block's commands unrolled")),
}
