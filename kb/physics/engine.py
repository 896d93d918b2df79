"""MuJoCo behind the cell: the compiled scene, its bodies by object, stepping, rest, grips, contacts.

:class:`Physics` holds one ``MjModel``/``MjData`` built from a :class:`kb.sim.world.World`
(:mod:`kb.physics.mjcf`) and maps between the world's objects (by index) and MuJoCo's bodies,
geoms, mocap bodies and grip welds. It knows nothing of CRCL: the robot (:mod:`kb.physics.robot`)
moves the mocap bodies and grips; the cell (:mod:`kb.physics.cell`) reads poses back into the
world and MuJoCo's contacts into its ground truth.

Time: ``time`` is MuJoCo's simulated time (s); ``wall`` the seconds spent stepping it.
MuJoCo's island sleeping is on: bodies at rest cost nothing until something touches them.
"""

from __future__ import annotations

import time as _time

import mujoco
import numpy as np

from kb.physics import params as P
from kb.physics.mjcf import FLANGE, ROBOT, Mjcf, build, quaternion
from kb.sim.world import World

_EQ = int(mujoco.mjtConstraint.mjCNSTR_EQUALITY)
ROBOT_BIT = ROBOT[0]


class Physics:
    """A MuJoCo model and data of a world's objects."""

    def __init__(self, world: World, cylinders: set[str] | frozenset[str] = frozenset()) -> None:
        self.mjcf: Mjcf = build(world, cylinders)
        try:
            self.model = mujoco.MjModel.from_xml_string(self.mjcf.xml)
        except ValueError as exc:  # a degenerate shape MuJoCo refuses
            raise ValueError(f"MuJoCo refused the scene: {exc}") from None
        self.data = mujoco.MjData(self.model)
        m = self.model
        self.body: dict[int, int] = {}  # world index -> body id
        self.object_of_geom = np.full(m.ngeom, -1, np.int64)
        self.object_of_body = np.full(m.nbody, -1, np.int64)
        self.mocap: dict[int, int] = {}  # world index -> mocap id
        self.weld: dict[int, int] = {}  # world index (free body) -> equality id
        self.qadr: dict[int, int] = {}
        self.vadr: dict[int, int] = {}
        for i, b in self.mjcf.bodies.items():
            bid = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, b.name)
            self.body[i] = bid
            self.object_of_body[bid] = i
            for g in b.geoms:
                self.object_of_geom[mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_GEOM, g)] = i
            if b.kind == "mocap":
                self.mocap[i] = int(m.body_mocapid[bid])
            elif b.kind == "free":
                j = int(m.body_jntadr[bid])
                self.qadr[i], self.vadr[i] = int(m.jnt_qposadr[j]), int(m.jnt_dofadr[j])
                self.weld[i] = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_EQUALITY, f"grip__{b.name}")
        self.flange_mocap = int(m.body_mocapid[mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, FLANGE)])
        self.free = sorted(self.qadr)
        #: open containers with a body -> their footprint's area (m^2)
        self.containers = {i: float(np.prod(world.local_hi[i, :2] - world.local_lo[i, :2]))
                           for i in self.body if world.open_top[i]}
        self.gone: set[int] = set()
        self.gripped: int | None = None  # the world index welded to the flange
        self.steps = 0
        self.wall = 0.0
        self.skipped = 0.0  # simulated seconds of quiet legs, not integrated
        mujoco.mj_forward(m, self.data)

    @property
    def time(self) -> float:
        """Simulated seconds stepped so far."""
        return float(self.data.time)

    # --- stepping -----------------------------------------------------------------------
    def step(self, n: int = 1) -> None:
        """``n`` steps of :data:`~kb.physics.params.TIMESTEP`."""
        t0 = _time.perf_counter()
        mujoco.mj_step(self.model, self.data, nstep=n)
        self.steps += n
        self.wall += _time.perf_counter() - t0

    def settle(self, limit: float = P.SETTLE) -> float:
        """Step until every free body is at rest (under :data:`~kb.physics.params.REST_SPEED` for
        :data:`~kb.physics.params.REST_TIME`), at most ``limit`` s; the seconds stepped."""
        chunk = max(1, int(round(P.REST_TIME / P.TIMESTEP)))
        start = self.time
        while self.time - start < limit:
            self.step(chunk)
            if self.at_rest():
                break
        return self.time - start

    def quiet(self) -> bool:
        """Every body asleep (MuJoCo's island sleeping) and nothing held: stepping would move nothing."""
        return self.gripped is None and int(self.data.ntree_awake) == 0

    def collide(self) -> None:
        """MuJoCo's collision detection where the bodies and mocap bodies are now (no integration)."""
        t0 = _time.perf_counter()
        mujoco.mj_kinematics(self.model, self.data)
        mujoco.mj_collision(self.model, self.data)
        self.wall += _time.perf_counter() - t0

    def advance(self, seconds: float) -> None:
        """MuJoCo's clock moved on by ``seconds`` with nothing integrated (a world at rest)."""
        self.data.time += seconds
        self.skipped += seconds

    def catch_up(self, limit: float = P.CATCH_UP) -> float:
        """Step until the held body moves slower than :data:`~kb.physics.params.REST_SPEED`
        (it has caught up with the still tool), at most ``limit`` s; the seconds stepped."""
        if self.gripped is None:
            return 0.0
        v = self.vadr[self.gripped]
        start = self.time
        while self.time - start < limit:
            self.step(5)
            if np.abs(self.data.qvel[v:v + 6]).max() < P.REST_SPEED:
                break
        return self.time - start

    def at_rest(self) -> bool:
        """Every free body moves slower than :data:`~kb.physics.params.REST_SPEED` (a held one
        moves with the flange and is left out)."""
        qvel = self.data.qvel
        if not len(qvel):
            return True
        if self.gripped is None:
            return bool(np.abs(qvel).max() < P.REST_SPEED)
        v = self.vadr.get(self.gripped)
        mask = np.ones(len(qvel), bool)
        if v is not None:
            mask[v:v + 6] = False
        return bool(not mask.any() or np.abs(qvel[mask]).max() < P.REST_SPEED)

    # --- poses ---------------------------------------------------------------------------
    def pose(self, i: int) -> np.ndarray:
        """The 4x4 world pose of object ``i``'s body."""
        b = self.body[i]
        out = np.eye(4)
        out[:3, :3] = self.data.xmat[b].reshape(3, 3)
        out[:3, 3] = self.data.xpos[b]
        return out

    def free_poses(self) -> dict[int, np.ndarray]:
        """Each free body still in the cell: its pose now (from its joint's position)."""
        out = {}
        q = self.data.qpos
        for i in self.free:
            if i in self.gone:
                continue
            a = self.qadr[i]
            m = np.eye(4)
            r = np.zeros(9)
            mujoco.mju_quat2Mat(r, q[a + 3:a + 7])
            m[:3, :3] = r.reshape(3, 3)
            m[:3, 3] = q[a:a + 3]
            out[i] = m
        return out

    def set_mocap(self, i: int, pose: np.ndarray) -> None:
        """Put mocap body ``i`` (the flange, an effector) at ``pose``."""
        k = self.mocap.get(i)
        if k is None:
            return
        self.data.mocap_pos[k] = pose[:3, 3]
        self.data.mocap_quat[k] = quaternion(pose[:3, :3])

    def set_flange(self, pose: np.ndarray) -> None:
        """Put the flange's mocap body at ``pose`` (also when the robot has no geometry)."""
        self.data.mocap_pos[self.flange_mocap] = pose[:3, 3]
        self.data.mocap_quat[self.flange_mocap] = quaternion(pose[:3, :3])

    def place(self, i: int, pose: np.ndarray) -> None:
        """Teleport free body ``i`` to ``pose``, at rest."""
        a, v = self.qadr[i], self.vadr[i]
        self.data.qpos[a:a + 3] = pose[:3, 3]
        self.data.qpos[a + 3:a + 7] = quaternion(pose[:3, :3])
        self.data.qvel[v:v + 6] = 0.0
        mujoco.mj_forward(self.model, self.data)

    # --- grips ---------------------------------------------------------------------------
    def grip(self, i: int, timeconst: float, damping: float, torquescale: float) -> None:
        """Weld free body ``i`` to the flange where it is now (its pose relative to the flange
        kept: a grasp off the centre holds it off the centre)."""
        e = self.weld[i]
        mujoco.mj_forward(self.model, self.data)
        fl = mujoco.mj_name2id(self.model, mujoco.mjtObj.mjOBJ_BODY, FLANGE)
        r1 = self.data.xmat[fl].reshape(3, 3)
        b = self.body[i]
        rel = r1.T @ (self.data.xpos[b] - self.data.xpos[fl])
        q1, q2 = self.data.xquat[fl], self.data.xquat[b]
        inv, rq = np.zeros(4), np.zeros(4)
        mujoco.mju_negQuat(inv, q1)
        mujoco.mju_mulQuat(rq, inv, q2)
        self.model.eq_data[e, 0:3] = 0.0
        self.model.eq_data[e, 3:6] = rel
        self.model.eq_data[e, 6:10] = rq
        self.model.eq_data[e, 10] = torquescale
        self.model.eq_solref[e] = (max(timeconst, 2 * P.TIMESTEP), damping)
        self.model.eq_solimp[e] = P.WELD_SOLIMP
        self.data.eq_active[e] = 1
        self._affinity(i, held=True)
        self.gripped = i

    def release(self) -> int | None:
        """Let go of what the flange holds (its weld off); the world index let go, if any."""
        i, self.gripped = self.gripped, None
        if i is not None:
            self.data.eq_active[self.weld[i]] = 0
            self._affinity(i, held=False)
        return i

    def grip_force(self) -> float:
        """The force (N) the grip's weld carries now (0 when nothing is held)."""
        if self.gripped is None:
            return 0.0
        d = self.data
        n = d.nefc
        rows = (d.efc_type[:n] == _EQ) & (d.efc_id[:n] == self.weld[self.gripped])
        f = d.efc_force[:n][rows][:3]
        return float(np.linalg.norm(f))

    def mass(self, i: int) -> float:
        """The mass (kg) of object ``i``'s body (0 without one)."""
        b = self.body.get(i)
        return float(self.model.body_mass[b]) if b is not None else 0.0

    def _affinity(self, i: int, held: bool) -> None:
        """The conaffinity of ``i``'s geoms: held, the scene's without the robot's bit (the
        gripper does not push what it holds); else the scene's."""
        for g in np.flatnonzero(self.object_of_geom == i):
            self.model.geom_conaffinity[g] = self._affinity0(g) & ~ROBOT_BIT if held else self._affinity0(g)

    def _affinity0(self, g: int) -> int:
        kept = getattr(self, "_aff0", None)
        if kept is None:
            kept = self._aff0 = self.model.geom_conaffinity.copy()
        return int(kept[g])

    # --- interventions (faults) ----------------------------------------------------------
    def kick(self, i: int, velocity: np.ndarray, spin: np.ndarray | None = None) -> None:
        """Give free body ``i`` a linear ``velocity`` (m/s, world frame) and ``spin`` (rad/s)."""
        v = self.vadr[i]
        self.data.qvel[v:v + 3] = velocity
        if spin is not None:
            self.data.qvel[v + 3:v + 6] = spin

    def remove(self, i: int) -> None:
        """Take free body ``i`` out of the scene: no contacts, no gravity, parked far below."""
        if i not in self.qadr:
            return
        self._aff0 = getattr(self, "_aff0", None) if getattr(self, "_aff0", None) is not None \
            else self.model.geom_conaffinity.copy()
        for g in np.flatnonzero(self.object_of_geom == i):
            self.model.geom_contype[g] = 0
            self.model.geom_conaffinity[g] = 0
            self._aff0[g] = 0
        self.model.body_gravcomp[self.body[i]] = 1.0
        pose = np.eye(4)
        pose[:3, 3] = (0.0, 0.0, -100.0 - i)
        self.place(i, pose)
        self.gone.add(i)

    def resize(self, i: int, lo: np.ndarray, hi: np.ndarray) -> None:
        """Give object ``i`` the box ``lo``..``hi`` (a part swapped for one of another SKU): its
        one geom resized (a container's plates are not)."""
        geoms = np.flatnonzero(self.object_of_geom == i)
        if len(geoms) != 1:
            return
        g = int(geoms[0])
        size, centre = (hi - lo) / 2, (hi + lo) / 2
        m = self.model
        if m.geom_type[g] == mujoco.mjtGeom.mjGEOM_CYLINDER:
            m.geom_size[g] = (min(size[0], size[1]), size[2], 0.0)
        else:
            m.geom_size[g] = size
        m.geom_pos[g] = centre
        m.geom_rbound[g] = float(np.linalg.norm(size))
        m.geom_aabb[g] = np.concatenate([np.zeros(3), size])
        mujoco.mj_forward(m, self.data)

    # --- contacts -------------------------------------------------------------------------
    def touching(self, depth: float = 0.0) -> list[tuple[int, int, float]]:
        """(object a, object b, distance) of every contact now deeper than ``depth`` (m of
        penetration; -1 for the floor)."""
        d = self.data
        n = d.ncon
        if not n:
            return []
        geoms = d.contact.geom[:n]
        dist = d.contact.dist[:n]
        keep = dist < -depth
        a = self.object_of_geom[geoms[keep, 0]]
        b = self.object_of_geom[geoms[keep, 1]]
        return list(zip(a.tolist(), b.tolist(), dist[keep].tolist()))

    def collide_all(self) -> None:
        """MuJoCo's contacts and their forces for every body, those asleep too (sleeping
        islands are left out of collision detection): one ``mj_forward`` with sleep off."""
        m = self.model
        flags = m.opt.enableflags
        m.opt.enableflags = flags & ~int(mujoco.mjtEnableBit.mjENBL_SLEEP)
        try:
            mujoco.mj_forward(m, self.data)
        finally:
            m.opt.enableflags = flags

    def supports(self) -> dict[int, int]:
        """Each free body's support now: the open container it rests in (the smallest of those
        it touches: a kit tray, not the box the tray stands in), else the object it presses on
        hardest from above (by the contact's normal force; contacts whose normal is
        within 60 degrees of vertical), -1 for the floor; bodies touching nothing from above
        are left out. (What lies in a tray on a table touches both: the tray's floor plate is
        under the tray's bottom face.)"""
        d, m = self.data, self.model
        self.collide_all()
        best: dict[int, tuple[tuple[bool, float, float], int]] = {}
        containers = self.containers
        f6 = np.zeros(6)
        for k in range(d.ncon):
            c = d.contact[k]
            normal = c.frame[:3]  # from geom1 to geom2
            if abs(normal[2]) < 0.5:
                continue
            mujoco.mj_contactForce(m, d, k, f6)
            a, b = int(self.object_of_geom[c.geom1]), int(self.object_of_geom[c.geom2])
            upper, lower = (a, b) if normal[2] < 0 else (b, a)  # the normal points from geom1 into geom2
            if upper < 0 or upper not in self.qadr:
                continue
            # an open container before what it stands on (a tray's floor plate lies under its bottom
            # face, so what lies in it touches the table or box floor under it too), the smallest first
            score = (lower in containers, -containers.get(lower, 0.0), float(f6[0]))
            if upper not in best or score > best[upper][0]:
                best[upper] = (score, lower)
        return {i: s for i, (f, s) in best.items()}
