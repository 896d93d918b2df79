"""Target poses of the tool tip, bound late: computed when the command is sent, from where the
objects are believed to be at that moment (seed 004 §4.2).

An action program (``soap:ActionProgram``) names a target as ``function(arg, ...)``: the
arguments are the action's parameter names or numbers (metres). The functions are the
geometry of kit building, not per-action code:

===============================  ===============================================================
``grasp(x)``                     the tip on the centre of x's top face (tool z down, x along x's)
``above(x, d)``                  ``grasp(x)`` raised by d
``place(x, where)``              the tip where x's top face will be once x stands at its place in
                                 ``where``: a kit (a free slot of x's SKU in the kit's design), a
                                 work table (its top), a large box (a free spot on its floor)
``above_place(x, where, d)``     ``place`` raised by d
``mount(e)``                     the bare tool flange on effector e's mount face
``above_mount(e, d)``            ``mount(e)`` raised by d
``stow(e, h)``                   effector e (mounted) back at its place in holder h (its pose
                                 relative to h in the initial state)
``above_stow(e, h, d)``          ``stow`` raised by d
``lift(d)``                      straight up by d from where the tip is
``clear(x, d)``                  straight up until the held x is d above everything under it
===============================  ===============================================================

The tool tip is the far end of the mounted effector (the flange's far face with none): the
effector's box extends from its frame along its z axis (the tool direction).
"""

from __future__ import annotations

import re
from typing import Callable

import numpy as np

from kb.core.errors import KitkbError
from kb.core.namespaces import KTW
from kb.execution.belief import SKU_OF, Belief
from kb.spatial.rcc8 import HEADING_MERGE, frame_boxes, headings, world_boxes
from kb.spatial.scene import Scene

_CALL = re.compile(r"^\s*([a-z_]+)\s*\((.*)\)\s*$")
UP = np.array([0.0, 0.0, 1.0])


class TargetError(KitkbError):
    """A target cannot be computed (no free slot, an object not seen ...)."""

    exit_code = 1


def parse(expr: str) -> tuple[str, list[str]]:
    """``"above(part, 0.1)"`` -> ``("above", ["part", "0.1"])``."""
    m = _CALL.match(expr)
    if m is None or m.group(1) not in FUNCTIONS:
        raise ValueError(f"target {expr!r}: expected one of {', '.join(sorted(FUNCTIONS))}(...)")
    args = [a.strip() for a in m.group(2).split(",")] if m.group(2).strip() else []
    return m.group(1), args


def tool_down(point: np.ndarray, x_axis: np.ndarray) -> np.ndarray:
    """A tip pose at ``point``, z pointing down, x along ``x_axis`` projected on the floor."""
    x = np.array(x_axis, float)
    x[2] = 0.0
    if np.linalg.norm(x) < 1e-9:
        x = np.array([1.0, 0.0, 0.0])
    x /= np.linalg.norm(x)
    z = -UP
    y = np.cross(z, x)
    m = np.eye(4)
    m[:3, 0], m[:3, 1], m[:3, 2], m[:3, 3] = x, y, z, point
    return m


def raised(pose: np.ndarray, d: float) -> np.ndarray:
    out = pose.copy()
    out[:3, 3] += UP * d
    return out


class Targets:
    """Computes tip poses on a belief; ``tip`` is the last commanded tip pose, ``mounted`` the
    effector on the flange (None: bare flange)."""

    def __init__(self, belief: Belief, robot: str):
        self.b = belief
        self.robot = robot
        self.mounted: str | None = None
        #: how far (m) an object's bottom may lie above another's and still count as level with it
        #: (what stands at a place, what is around a held object); wider with a noisy sensor
        self.tolerance = 1e-3
        flange = belief.pose(robot)
        lo, hi = belief.box(robot)
        self.tip = flange @ _along_z(float(hi[2]))
        self._stowed = self._holder_places()

    def _holder_places(self) -> dict[str, np.ndarray]:
        """Effector -> its pose relative to its holder in the initial state."""
        out = {}
        for holder in self.b.of_class(str(KTW.EndEffectorHolder)):
            for ee in self.b.related(str(KTW.hasEndEffectorHolder_EndEffector), holder):
                h, e = self.b.index[holder], self.b.index[ee]
                if not (np.isnan(self.b.initial[h, 0, 0]) or np.isnan(self.b.initial[e, 0, 0])):
                    out[ee] = np.linalg.inv(self.b.initial[h]) @ self.b.initial[e]
        return out

    def compute(self, expr: str, args: dict[str, str]) -> np.ndarray:
        """The tip pose of ``expr`` with the action's parameters bound to ``args`` (name -> IRI)."""
        name, raw = parse(expr)
        self._args = args
        values: list = []
        for a in raw:
            try:
                values.append(float(a))
            except ValueError:
                if a not in args:
                    raise TargetError(f"target {expr}: {a} is not a parameter of the action") from None
                values.append(args[a])
        return FUNCTIONS[name](self, *values)

    # --- geometry -------------------------------------------------------------------
    def _seen(self, x: str) -> np.ndarray:
        if not self.b.placed(x):
            raise TargetError(f"{_local(x)} is not where the sensor can see it")
        return self.b.pose(x)

    def top(self, x: str) -> tuple[np.ndarray, np.ndarray]:
        """(point, x axis) of the centre of x's top face."""
        g = self._seen(x)
        lo, hi = self.b.box(x)
        c = g @ np.array([(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, hi[2], 1.0])
        return c[:3], g[:3, 0]

    def grasp(self, x: str) -> np.ndarray:
        point, xaxis = self.top(x)
        return tool_down(point, xaxis)

    def above(self, x: str, d: float) -> np.ndarray:
        return raised(self.grasp(x), d)

    def place(self, x: str, where: str, dest: np.ndarray | None = None) -> np.ndarray:
        dest = self.destination(x, where) if dest is None else dest
        lo, hi = self.b.box(x)
        point = dest @ np.array([(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, hi[2], 1.0])
        return tool_down(point[:3], dest[:3, 0])

    def above_place(self, x: str, where: str, d: float) -> np.ndarray:
        """``place`` raised until x's bottom is d above everything at its place (a box's walls,
        the parts already in a kit), at least d. Footprints are compared in the frame of x at its
        place (the world turned by its heading: a turned kit's neighbours are not in the way)."""
        dest = self.destination(x, where)
        tip = self.place(x, where, dest)
        lo, hi = self.b.box(x)
        bottom = float(tip[2, 3]) - float(hi[2] - lo[2])  # x's bottom when placed
        yaw = _heading(dest)
        flo, fhi = frame_boxes(dest[None], lo[None], hi[None], yaw)
        scene = self.b.scene()
        slo, shi = self._frame(scene, yaw)
        tops = [float(shi[j, 2]) for j in range(len(scene)) if self.b.names[j] != x and scene.placed[j]
                and slo[j, 2] <= bottom + self.tolerance  # at the place (a box, a table, a kit and its parts)
                and np.all(slo[j, :2] < fhi[0, :2]) and np.all(shi[j, :2] > flo[0, :2])]
        rise = max([d] + [t + d - bottom for t in tops])
        return raised(tip, rise)

    def mount(self, e: str) -> np.ndarray:
        g = self._seen(e)
        return g.copy()

    def above_mount(self, e: str, d: float) -> np.ndarray:
        return raised(self.mount(e), d)

    def stow(self, e: str, h: str) -> np.ndarray:
        # where e sat in its holder at the start; an effector that started on the robot goes
        # the way the other effectors sit in theirs
        rel = self._stowed.get(e)
        if rel is None:
            rel = next(iter(self._stowed.values()), None)
        if rel is None:
            raise TargetError(f"no place known for {_local(e)} in {_local(h)}")
        frame = self._seen(h) @ rel
        return frame @ _along_z(float(self.b.box(e)[1][2]))

    def above_stow(self, e: str, h: str, d: float) -> np.ndarray:
        return raised(self.stow(e, h), d)

    def lift(self, d: float) -> np.ndarray:
        return raised(self.tip, d)

    def clear(self, x: str, d: float) -> np.ndarray:
        """Straight up until x (held) is d above the top of everything under, around or beside
        it (a container's walls, a holder, the station base a holder hangs on), at least d.
        Compared in x's frame (the world turned by its heading)."""
        scene = self.b.scene()
        i = self.b.index[x]
        if not scene.placed[i]:
            return self.lift(d)
        slo, shi = self._frame(scene, _heading(scene.poses[i]))
        lo, hi = slo[i], shi[i]
        tol = self.tolerance
        below = [float(shi[j, 2]) for j in range(len(scene)) if j != i and scene.placed[j]
                 and slo[j, 2] <= lo[2] + tol  # under x or around it (a tray, a box, a holder)
                 and np.all(slo[j, :2] <= hi[:2] + tol) and np.all(shi[j, :2] >= lo[:2] - tol)
                 and not (np.all(slo[j, :2] >= lo[:2] - tol) and np.all(shi[j, :2] <= hi[:2] + tol))]
        rise = max(d, (max(below) + d - float(lo[2])) if below else d)
        return self.lift(rise)

    @staticmethod
    def _frame(scene: Scene, yaw: float) -> tuple[np.ndarray, np.ndarray]:
        """Every object's box (K, 3) in the world turned by ``yaw`` about z (NaN where not
        placed); the world boxes themselves for yaw 0."""
        if yaw == 0.0:
            return scene.lo, scene.hi
        return frame_boxes(scene.poses, scene.local_lo, scene.local_hi, yaw)

    # --- destinations ---------------------------------------------------------------
    def destination(self, x: str, where: str) -> np.ndarray:
        """The global frame x's origin (middle of its bottom) goes to."""
        classes = self.b.classes[self.b.index[where]]
        if str(KTW.Kit) in classes:
            return self._slot(x, where)
        if str(KTW.WorkTable) in classes:
            g = self._seen(where)
            lo, hi = self.b.box(where)
            return g @ _at((lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, hi[2])
        container = self.b.related(str(KTW.hasLargeBoxWithKits_LargeContainer), where) or \
            self.b.related(str(KTW.hasLargeBoxWithEmptyKitTrays_LargeContainer), where)
        return self._free_spot(x, container[0] if container else where, where)

    def _slot(self, part: str, kit: str) -> np.ndarray:
        """A free slot of the part's SKU in the kit's design (kit frame = its tray's)."""
        g = self._seen(kit)
        planned = getattr(self, "_args", {}).get("sku")  # the SKU the plan puts in this slot
        sku = [planned] if planned else self.b.related(SKU_OF, part)
        taken = [self.b.pose(p)[:3, 3] for p in self.b.of_class(str(KTW.Part))
                 if p != part and self.b.placed(p)]
        for design in self.b.related(str(KTW.hasKit_Design), kit):
            for prp in self.b.related(str(KTW.hasKitDesign_PartRefAndPose), design):
                if self.b.related(str(KTW.hasPartRefAndPose_Sku), prp) != sku:
                    continue
                frame = g @ self._prp_pose(prp)
                if all(np.linalg.norm(frame[:2, 3] - t[:2]) > 0.01 or abs(frame[2, 3] - t[2]) > 0.05 for t in taken):
                    return frame
        raise TargetError(f"no free slot for {_local(part)} ({', '.join(map(_local, sku))}) in {_local(kit)}")

    def _prp_pose(self, prp: str) -> np.ndarray:
        pose = self.b.slots.get(prp)
        if pose is None:
            raise TargetError(f"slot {_local(prp)} of the kit design has no pose")
        return pose

    def _free_spot(self, x: str, container: str, where: str) -> np.ndarray:
        """A spot on the container's floor where x's footprint meets nothing placed in it."""
        g = self._seen(container)
        clo, chi = self.b.box(container)
        xlo, xhi = self.b.box(x)
        w, h = xhi[0] - xlo[0], xhi[1] - xlo[1]
        scene = self.b.scene()
        top = float(scene.hi[self.b.index[container], 2])
        inv = np.linalg.inv(g)
        boxes = []
        near = [i for i, n in enumerate(self.b.names) if n not in (x, container, where) and scene.placed[i]
                and scene.lo[i, 2] < top - 1e-6]  # not the box, its stand-in, nor what is above it (the load)
        if near:  # each oriented box's hull in the container's frame (exact for one turned alike)
            llo, lhi = world_boxes(inv @ scene.poses[near], scene.local_lo[near], scene.local_hi[near])
            boxes = list(zip(llo, lhi))
        step = 0.02
        y = clo[1] + h / 2 + 0.01
        while y + h / 2 <= chi[1] - 0.01 + 1e-9:
            xx = clo[0] + w / 2 + 0.01
            while xx + w / 2 <= chi[0] - 0.01 + 1e-9:
                lo = np.array([xx - w / 2, y - h / 2, clo[2]])
                hi = np.array([xx + w / 2, y + h / 2, chi[2]])
                if all(np.any(hi <= blo + 1e-9) or np.any(lo >= bhi - 1e-9) for blo, bhi in boxes):
                    return g @ _at(xx, y, clo[2])
                xx += step
            y += step
        raise TargetError(f"no free room for {_local(x)} in {_local(container)}")


FUNCTIONS: dict[str, Callable] = {
    "grasp": Targets.grasp, "above": Targets.above, "place": Targets.place, "above_place": Targets.above_place,
    "mount": Targets.mount, "above_mount": Targets.above_mount, "stow": Targets.stow,
    "above_stow": Targets.above_stow, "lift": Targets.lift, "clear": Targets.clear,
}


def _heading(pose: np.ndarray) -> float:
    """The heading of ``pose`` (:func:`kb.spatial.rcc8.headings`), 0 within HEADING_MERGE of it."""
    h = float(headings(pose[None])[0])
    return 0.0 if not abs(h) > HEADING_MERGE else h


def _along_z(d: float) -> np.ndarray:
    m = np.eye(4)
    m[2, 3] = d
    return m


def _at(x: float, y: float, z: float) -> np.ndarray:
    m = np.eye(4)
    m[:3, 3] = [x, y, z]
    return m


def _local(iri: str) -> str:
    return str(iri).rsplit("#", 1)[-1]
