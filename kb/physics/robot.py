"""The robot of the MuJoCo cell: kitkb's CRCL robot (:class:`kb.sim.robot.Robot`) whose tool
moves a mocap body through MuJoCo, whose grips are welds and whose releases fall by physics.

What it keeps of the kinematic robot: every command's meaning (units, speeds, tolerances, the
tool changer, MoveTo's up-across-down path, constraint checks: overweight, work volume, wrong
effector, and the swept-box contacts, kept as ``swept`` for comparison). What physics decides
instead:

* **motion**: each straight leg is driven at the commanded speed with a trapezoidal profile of
  :data:`~kb.physics.params.ACCELERATION` (orientation turned in proportion), the flange's
  mocap body (and the mounted effector's) set every step of MuJoCo; the clock is the
  simulated time. A held object follows through its weld, lagging and swinging with its
  inertia;
* **grasps by geometry and effector kind**: CloseGripper finds what is at the tip as the
  kinematic robot does (its top face at the tip, the effector its SKU lists), then a parallel
  gripper holds it only if the tip is within :data:`~kb.physics.params.FINGER_REACH` of its
  half-length from its centre along both axes (the fingers bracket it), a vacuum cup only if
  at least :data:`~kb.physics.params.SEAL` of its disc lies on the top face, with a strength in
  proportion; a grasp that holds welds the object to the flange where it is (off the centre:
  held off the centre; a vacuum weld turns under the load's torque: held crooked). A grip
  whose weld force exceeds its strength lets go, wherever the robot is;
* **release**: OpenGripper switches the weld off; the cell steps until everything is at rest
  (at most :data:`~kb.physics.params.SETTLE` s): the object falls, bounces and comes to rest
  wherever it does; its support is what it presses on (MuJoCo's contacts);
* **contacts**: MuJoCo contacts deeper than :data:`~kb.physics.params.CONTACT_DEPTH` between
  what moves with the robot (flange, effector, held object) and any other object during a
  move are contact violations (the object at the tip at the leg's start or end, what it
  carries and effector holders excepted, as in the kinematic robot); the swept-box contacts
  of the kinematic robot on the same moves are kept in ``swept``.
* **weak grip** (the armed ``drop_in_transit`` of the fault mechanism ReleaseInTransit): in the
  first leg that carries a held part :data:`~kb.physics.params.WEAK_GRIP_AFTER` sideways, the
  grip lets go at a seeded moment of the leg (:data:`~kb.physics.params.WEAK_GRIP_MOMENT`);
  where the part comes to rest is physics'.
"""

from __future__ import annotations

from typing import Callable

import numpy as np

from kb.crcl.cell import Status
from kb.physics import params as P
from kb.physics.engine import Physics
from kb.physics.mjcf import quaternion
from kb.sim.robot import Robot, _turn
from kb.sim.world import EFFECTOR_LOAD, World, translate

#: objects, detail -> None: a MuJoCo contact of the robot, reported as a contact violation
ContactHook = Callable[[tuple[str, ...], str], None]
G = 9.81


def profile(length: float, speed: float, accel: float = P.ACCELERATION) -> tuple[float, Callable[[float], float]]:
    """(duration, s(t)): the trapezoidal (or triangular, for a short leg) speed profile covering
    ``length`` at top ``speed`` with ``accel``; s(t) is the distance covered at time t."""
    if length <= 0:
        return 0.0, lambda t: 0.0
    ta = speed / accel
    if accel * ta * ta >= length:  # triangular: never reaches the speed
        ta = float(np.sqrt(length / accel))
        total = 2 * ta

        def s(t: float) -> float:
            t = min(max(t, 0.0), total)
            return 0.5 * accel * t * t if t <= ta else length - 0.5 * accel * (total - t) ** 2
        return total, s
    cruise = (length - accel * ta * ta) / speed
    total = 2 * ta + cruise

    def s2(t: float) -> float:
        t = min(max(t, 0.0), total)
        if t <= ta:
            return 0.5 * accel * t * t
        if t <= ta + cruise:
            return 0.5 * accel * ta * ta + speed * (t - ta)
        return length - 0.5 * accel * (total - t) ** 2
    return total, s2


class PhysicsRobot(Robot):
    """:class:`kb.sim.robot.Robot` driving a :class:`~kb.physics.engine.Physics` scene."""

    def __init__(self, world: World, physics: Physics, rng: np.random.Generator,
                 on_violation: Callable[[str, tuple[str, ...], str], None] | None = None,
                 on_contact: ContactHook | None = None, on_rest: Callable[[], None] | None = None) -> None:
        super().__init__(world, on_violation=on_violation)
        self.physics = physics
        self.rng = rng
        self.on_contact = on_contact or (lambda objects, detail: None)
        self.on_rest = on_rest or (lambda: None)
        self.strength: float | None = None  # the grip's strength (N), None: nothing held by physics
        self.swept: list[tuple[tuple[str, ...], str]] = []  # the kinematic robot's contacts, for comparison
        self.let_go: list[tuple[str, str]] = []  # (object, why) a grip let go on its own
        self._contacts_now: dict[tuple[str, str], str] = {}
        self.physics.set_flange(self.flange)
        self._place_mocaps()

    # --- motion ---------------------------------------------------------------------------
    def _segment(self, target: np.ndarray) -> None:
        start = self.tip()
        step = target[:3, 3] - start[:3, 3]
        length = float(np.linalg.norm(step))
        duration, s = profile(length, self.speed)
        if self.rot_speed is not None:
            duration = max(duration, _turn(start, target) / self.rot_speed)
        if duration <= 0:
            duration = P.TIMESTEP
        weak = None
        if (self.drop_in_transit and self.held is not None and self.world.is_a(self.held, "Part")
                and np.linalg.norm(step[:2]) >= P.WEAK_GRIP_AFTER):
            weak = float(self.rng.uniform(*P.WEAK_GRIP_MOMENT)) * duration
        self._drive(start, target, duration, s, length, weak)
        self._go(target)
        self.time += duration

    def _drive(self, start: np.ndarray, target: np.ndarray, duration: float, s: Callable[[float], float],
               length: float, weak: float | None) -> None:
        """Step MuJoCo through one leg, the flange's mocap body (and the mounted effector's) along
        it; when nothing is held and every body is asleep nothing can move, so the leg only
        looks for the robot's contacts at :data:`~kb.physics.params.CONTACT_EVERY` steps and
        the clock advances (:meth:`_quiet_leg`)."""
        ph = self.physics
        n = max(1, int(np.ceil(duration / P.TIMESTEP)))
        t = np.minimum(np.arange(1, n + 1) * P.TIMESTEP, duration)
        f = np.array([s(x) for x in t]) / length if length > 0 else t / duration
        flange_pos, flange_quat, eff_pos, eff_quat = self._trajectory(start, target, f)
        self._contacts_now = {}
        moving = self._moving()
        if self.held is None and weak is None and ph.quiet():
            self._quiet_leg(flange_pos, flange_quat, eff_pos, eff_quat, duration, moving)
            self._report_contacts(start, target)
            return
        dropped = None
        d, fm = ph.data, ph.flange_mocap
        em = ph.mocap.get(self.effector) if self.effector is not None else None
        for k in range(n):
            d.mocap_pos[fm] = flange_pos[k]
            d.mocap_quat[fm] = flange_quat[k]
            if em is not None:
                d.mocap_pos[em] = eff_pos[k]
                d.mocap_quat[em] = eff_quat[k]
            ph.step()
            if weak is not None and t[k] >= weak and self.held is not None:
                dropped = self.held
                self._let_go()
                weak = None
            elif self.strength is not None and k % P.CONTACT_EVERY == 0 and ph.grip_force() > self.strength:
                name = self.world.names[self.held] if self.held is not None else "?"
                self.let_go.append((name, f"the grip's force passed its strength {self.strength:.2f} N"))
                self._let_go()
            if k % P.CONTACT_EVERY == 0 or k == n - 1:
                self._note_contacts(moving)
        self.time += ph.catch_up()
        self._report_contacts(start, target)
        if dropped is not None:
            self.drop_in_transit = False
            self._rest()
            w = self.world
            sup = int(w.parent[dropped])
            where = w.names[sup] if sup >= 0 else "the floor"
            self.on_fault("drop_in_transit", (w.names[dropped],),
                          f"the grip let go in transit; came to rest at {_xyz(w.poses[dropped][:3, 3])} on {where}")

    def _trajectory(self, start: np.ndarray, target: np.ndarray, f: np.ndarray) -> tuple[
            np.ndarray, np.ndarray, np.ndarray | None, np.ndarray | None]:
        """Positions (n, 3) and quaternions (n, 4) of the flange, and of the mounted effector
        (None without one), at the fractions ``f`` of the leg (the orientation turned by the
        same fraction, about one axis)."""
        length = self.tool_length()
        r0 = start[:3, :3]
        axis, angle = _axis_angle(r0.T @ target[:3, :3])
        half = 0.5 * angle * np.minimum(np.maximum(f, 0.0), 1.0)
        turn = np.column_stack([np.cos(half), np.outer(np.sin(half), axis)])  # in the start's frame
        q0 = quaternion(r0)
        flange_quat = _qmul(q0, turn)
        tips = start[:3, 3] + np.outer(f, target[:3, 3] - start[:3, 3])
        z = _rotate(flange_quat, np.array([0.0, 0.0, 1.0]))
        flange_pos = tips - length * z
        if self.effector is None:
            return flange_pos, flange_quat, None, None
        mounted = np.linalg.inv(self.flange) @ self.world.poses[self.effector]
        eff_pos = flange_pos + _rotate(flange_quat, mounted[:3, 3])
        eff_quat = _qmul(flange_quat, quaternion(mounted[:3, :3]))
        return flange_pos, flange_quat, eff_pos, eff_quat

    def _quiet_leg(self, flange_pos: np.ndarray, flange_quat: np.ndarray, eff_pos: np.ndarray | None,
                   eff_quat: np.ndarray | None, duration: float, moving: set[int]) -> None:
        """A leg in a world at rest with nothing held: the robot's geoms placed every
        :data:`~kb.physics.params.CONTACT_EVERY` steps and MuJoCo's collision detection run
        there (its contacts noted), no integration; MuJoCo's clock advanced by the leg."""
        ph = self.physics
        d, fm = ph.data, ph.flange_mocap
        em = ph.mocap.get(self.effector) if self.effector is not None else None
        n = len(flange_pos)
        for k in list(range(P.CONTACT_EVERY - 1, n, P.CONTACT_EVERY)) + [n - 1]:
            d.mocap_pos[fm] = flange_pos[k]
            d.mocap_quat[fm] = flange_quat[k]
            if em is not None:
                d.mocap_pos[em] = eff_pos[k]  # type: ignore[index]
                d.mocap_quat[em] = eff_quat[k]  # type: ignore[index]
            ph.collide()
            self._note_contacts(moving)
        ph.advance(duration)

    def _go(self, tip: np.ndarray) -> None:
        """The kinematic robot's end of a leg (its swept-box contacts, the flange and what it
        carries set at the target), then the free bodies where MuJoCo has them."""
        held = self.held
        super()._go(tip)
        self.physics.set_flange(self.flange)
        self._place_mocaps()
        self._sync(moved_only=True, skip={held} if held is not None else set())

    def _moving(self) -> set[int]:
        """Objects that move with the flange: the robot, its effector, what it holds (objects)."""
        return set(self.world.subtree(self.index))

    def _note_contacts(self, moving: set[int]) -> None:
        for a, b, dist in self.physics.touching(P.CONTACT_DEPTH):
            if (a in moving) == (b in moving):
                continue
            mover, other = (a, b) if a in moving else (b, a)
            if other < 0 or mover < 0:
                continue
            key = (self.world.names[mover], self.world.names[other])
            if key not in self._contacts_now:
                self._contacts_now[key] = f"{-dist * 1000:.1f} mm deep"

    def _report_contacts(self, start: np.ndarray, end: np.ndarray) -> None:
        w = self.world
        skip: set[int] = set()
        for point in (start[:3, 3], end[:3, 3]):
            at = self._at_point(point)
            if at is not None:
                skip.update(w.subtree(at))
        for (mover, other), detail in sorted(self._contacts_now.items()):
            o = w.index[other]
            if o in skip or w.is_a(o, "EndEffectorHolder"):
                continue
            self.on_contact((mover, other), f"{_local(mover)} touches {_local(other)} in MuJoCo ({detail}) on the "
                                            f"way from {_xyz(start[:3, 3])} to {_xyz(end[:3, 3])}")
        self._contacts_now = {}

    # --- grasping --------------------------------------------------------------------------
    def close_gripper(self) -> Status:
        """The kinematic robot's grasp (what is at the tip, the effector it needs, its weight),
        then physics' test of the geometry by effector kind; a grasp that holds welds it."""
        before = self.world.parent.copy()
        status = super().close_gripper()
        if self.held is None:
            return status
        i = self.held
        body = self._body(i)
        why, weld, strength = self._geometry(body)
        if why is not None or body is None:
            self.held = None
            self.world.parent[:] = before
            return Status.ok(f"nothing grasped: {why or 'no body to hold'}")
        self.physics.grip(body, weld.timeconst, weld.damping, weld.torquescale)
        self.strength = strength
        return status

    def _body(self, i: int) -> int | None:
        """The free body standing for object ``i`` (a kit: its kit tray)."""
        if i in self.physics.qadr:
            return i
        for j in self.world.children(i):
            if j in self.physics.qadr:
                return j
        return None

    def _geometry(self, body: int | None) -> tuple[str | None, P.Weld, float]:
        """(why the grasp does not hold, or None; the weld; the grip's strength in N)."""
        if body is None:
            return "no body", P.GRIPPER, 0.0
        w = self.world
        tip = self.tip()[:3, 3]
        pose = w.poses[body]
        q = np.linalg.inv(pose) @ np.append(tip, 1.0)
        lo, hi = w.local_lo[body], w.local_hi[body]
        centre, half = (lo + hi)[:2] / 2, (hi - lo)[:2] / 2
        off = q[:2] - centre
        load = self._load(body)
        limit = w.number(EFFECTOR_LOAD, w.names[self.effector]) if self.effector is not None else None
        nominal = max(limit * G if limit is not None else 0.0, P.GRIP_MARGIN * load * G)
        if self.effector is not None and w.is_a(self.effector, "VacuumEffector"):
            r = float(max(w.local_hi[self.effector, 0] - w.local_lo[self.effector, 0],
                          w.local_hi[self.effector, 1] - w.local_lo[self.effector, 1])) / 2
            covered = _covered(off, half, r)
            if covered < P.SEAL:
                return f"the cup covers {covered:.0%} of its disc on the top face (seals from {P.SEAL:.0%})", P.VACUUM, 0.0
            return None, P.VACUUM, nominal * covered
        reach = P.FINGER_REACH * half
        if np.any(np.abs(off) > reach):
            return (f"the fingers close {np.abs(off).max() * 1000:.1f} mm off the centre, beyond their reach "
                    f"({P.FINGER_REACH:.0%} of the half-length)"), P.GRIPPER, 0.0
        return None, P.GRIPPER, nominal

    def _load(self, body: int) -> float:
        """What a grip on ``body`` lifts (kg): its body and what rests in it."""
        return sum(self.physics.mass(j) for j in self.world.subtree(body))

    def _release(self) -> int:
        """Let go of the held object: the weld off, MuJoCo stepped until everything is at rest;
        its support (what it rests on, -1: the floor)."""
        i = self.held
        assert i is not None
        self._let_go()
        self._rest()
        return int(self.world.parent[i])

    def _let_go(self) -> None:
        i, self.held = self.held, None
        self.physics.release()
        self.strength = None
        if i is not None:
            self.world.parent[i] = -1

    def _rest(self) -> None:
        """Step until everything is at rest, then read the poses and supports back."""
        self.time += self.physics.settle()
        self._sync(moved_only=False, skip=set())
        self.on_rest()

    def dwell(self, seconds: float) -> Status:
        status = super().dwell(seconds)
        if status.done and seconds > 0:
            self.physics.step(max(1, int(round(min(seconds, P.SETTLE) / P.TIMESTEP))))
            self._sync(moved_only=True, skip=set())
        return status

    def close_tool_changer(self) -> Status:
        status = super().close_tool_changer()
        self._place_mocaps()
        return status

    def open_tool_changer(self) -> Status:
        status = super().open_tool_changer()
        self._place_mocaps()
        return status

    # --- the world from MuJoCo ------------------------------------------------------------------
    def _place_mocaps(self) -> None:
        """Every effector's mocap body where the world has it (a stowed one where it was left)."""
        for i in self.physics.mocap:
            if self.world.placed(i):
                self.physics.set_mocap(i, self.world.poses[i])

    def _sync(self, moved_only: bool, skip: set[int]) -> None:
        """Free bodies' poses into the world (stand-ins with their lender); supports of the
        bodies that moved from MuJoCo's contacts (held ones keep their effector)."""
        w, ph = self.world, self.physics
        poses = ph.free_poses()
        moved = []
        for i, pose in poses.items():
            old = w.poses[i]
            if np.isnan(old[0, 0]):
                continue
            if np.abs(pose - old).max() > 1e-4:
                moved.append(i)
            w.poses[i] = pose
        for s in range(len(w)):
            if w.stand_in(s) and w.placed(s):
                lender = next((j for j in w.children(s) if j in poses and
                               np.array_equal(w.local_lo[j], w.local_lo[s])), None)
                if lender is not None:
                    w.poses[s] = w.poses[lender]
        if moved_only and not moved:
            return
        carried = self._moving()
        supports = ph.supports()
        for i in (moved if moved_only else list(poses)):
            if i in carried or i in skip:
                continue
            if i not in supports:
                continue
            sup = supports[i]
            node = i
            p = int(w.parent[i])
            if p >= 0 and w.stand_in(p):
                node = p  # a kit's tray: the kit rests where the tray does
            if sup >= 0 and w.stand_in(sup):
                sup = next((j for j in w.children(sup) if j in poses), sup)
            if sup in w.subtree(node):
                continue
            w.parent[node] = sup


def _axis_angle(rel: np.ndarray) -> tuple[np.ndarray, float]:
    """(unit axis, angle) of a rotation matrix (any axis for no turn)."""
    angle = float(np.arccos(np.clip((np.trace(rel) - 1) / 2, -1, 1)))
    axis = np.array([rel[2, 1] - rel[1, 2], rel[0, 2] - rel[2, 0], rel[1, 0] - rel[0, 1]])
    n = np.linalg.norm(axis)
    if angle < 1e-12:
        return np.array([0.0, 0.0, 1.0]), 0.0
    if n < 1e-9:  # a half turn: the eigenvector of eigenvalue 1
        w, v = np.linalg.eigh((rel + rel.T) / 2)
        return v[:, int(np.argmax(w))], angle
    return axis / n, angle


def _qmul(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Quaternion products a b (w, x, y, z), either of shape (4,) or (n, 4)."""
    a, b = np.atleast_2d(a), np.atleast_2d(b)
    w1, x1, y1, z1 = a.T
    w2, x2, y2, z2 = b.T
    return np.column_stack([w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2, w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
                            w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2, w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2])


def _rotate(q: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Vector ``v`` (3,) turned by each quaternion of ``q`` (n, 4): (n, 3)."""
    w, u = q[:, :1], q[:, 1:]
    t = 2.0 * np.cross(u, v)
    return v + w * t + np.cross(u, t)


def _covered(off: np.ndarray, half: np.ndarray, r: float, n: int = 40) -> float:
    """The fraction of a disc of radius ``r`` centred ``off`` from a face's centre that lies on
    the face (half-lengths ``half``): sampled at the centres of an n x n grid of cells."""
    if r <= 0:
        return 1.0 if np.all(np.abs(off) <= half) else 0.0
    g = ((np.arange(n) + 0.5) / n * 2.0 - 1.0) * r
    x, y = np.meshgrid(g, g)
    disc = x * x + y * y <= r * r
    on = (np.abs(off[0] + x) <= half[0]) & (np.abs(off[1] + y) <= half[1])
    return float((disc & on).sum() / disc.sum())


def _local(name: str) -> str:
    return name.rsplit("#", 1)[-1].rsplit("/", 1)[-1]


def _xyz(p: np.ndarray) -> str:
    return "(" + ", ".join(f"{float(v):.3f}" for v in p) + ")"


__all__ = ["PhysicsRobot", "profile"]
