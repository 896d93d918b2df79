"""Target poses of the tool tip, bound late: computed when the command is sent, from where the
objects are believed to be at that moment (seed 004 §4.2).

An action program (``soap:ActionProgram``) names a target as ``function(arg, ...)``: the
arguments are the action's parameter names or numbers (metres). The functions are the
geometry of kit building, not per-action code:

===============================  ===============================================================
``grasp(x)``                     the tip on the top of x as it lies, above the middle of its
                                 footprint (tool z down, x along x's level axis: :func:`top_of`,
                                 :func:`level_axis`)
``above(x, d)``                  ``grasp(x)`` raised by d
``place(x, where)``              the tip where the top of x will be once x lies at its place in
                                 ``where`` (:meth:`Targets.placed_pose`): a kit (a free slot of
                                 x's SKU in the kit's design), a work table (its top), a large box
                                 (a free spot on its floor)
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

Parts as they lie (docs/execution.md, "Grasp and place targets"). A part's frame is where its
file puts it: NIST's GearBox shafts are CylindricalShapes framed at the centre of one end cap,
z along the shaft, and lie in their tray with that z axis level. So the top of a part is taken
in the world, not along its own z axis: the point above the centre of its box at the height of
its highest corner (the top face of its hull in the frame of its heading, where the simulated
gripper looks for it too), whatever its orientation. The tool's x axis follows the part's
level axis (of its three axes the first that is not the most vertical, projected on the
floor: its x axis when it stands upright, as before), so the part turns with the tool's yaw.
At a place the part takes the slot's orientation when a turn about the vertical gets it
there (it rests on the face the slot wants); else it keeps the face it lies on, turned as
near the slot's orientation as the vertical allows, its frame over the slot's point and its
lowest point where the slot's part's would be (a warning says so once per part and slot).
"""

from __future__ import annotations

import logging
import math
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
log = logging.getLogger("kitkb.execution")
#: A part whose orientation, turned about the vertical, is this near its slot's (largest
#: difference of the rotation matrices' entries) takes the slot's orientation exactly: what is
#: left is rounding (an upright part in an upright slot gives the targets it always gave).
SAME_ORIENTATION = 1e-6
#: cos 45 degrees: a part whose up direction (in its own frame) is nearer than this to the
#: slot's rests on the face the slot wants; farther, it rests on another face.
SAME_FACE = math.cos(math.pi / 4)


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


def top_of(pose: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """The top of the box (lo, hi) at ``pose`` as it lies: the point above its centre at the
    height of its highest corner (world up; for a box standing on its bottom face, the centre
    of its top face). Computed in the box's frame, so an upright box framed at the middle of
    its bottom (every shape kitkb reads) gets its top face's centre to the bit."""
    up = pose[2, :3]  # the world's up direction in the box's frame
    half = (np.asarray(hi, float) - np.asarray(lo, float)) / 2
    local = (np.asarray(lo, float) + np.asarray(hi, float)) / 2 + up * float(np.abs(up) @ half)
    return (pose @ np.append(local, 1.0))[:3]


def height_of(pose: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> float:
    """The height of the box (lo, hi) at ``pose``: from its lowest corner to its highest."""
    return float(np.abs(pose[2, :3]) @ (np.asarray(hi, float) - np.asarray(lo, float)))


def level_axis(pose: np.ndarray) -> np.ndarray:
    """The axis of ``pose`` the tool's x axis follows: of its three axes the first that is not
    the most vertical (its x axis, or its y axis when x is the most vertical), as
    :func:`kb.spatial.rcc8.headings` chooses. It is never nearer vertical than 45 degrees, and
    a turn about the vertical turns it alike."""
    vertical = int(np.argmax(np.abs(pose[2, :3])))
    return pose[:3, 1 if vertical == 0 else 0]


def turned_to(current: np.ndarray, wanted: np.ndarray) -> np.ndarray:
    """The rotation (3x3) of ``current`` turned about the vertical as near ``wanted`` as such a
    turn gets (the yaw that maximises the trace of ``wanted^T Rz(yaw) current``, which is
    ``cos(yaw) (m00 + m11) + sin(yaw) (m01 - m10) + m22`` with ``m = current wanted^T``)."""
    m = current @ wanted.T
    yaw = math.atan2(m[0, 1] - m[1, 0], m[0, 0] + m[1, 1])
    c, s = math.cos(yaw), math.sin(yaw)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]) @ current


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
        self._warned: set[tuple] = set()  # (part, slot, point) said to go in on another face
        self._slot_name: str | None = None  # the design slot the last destination was

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
        """(point, x axis) of the tool on x: the top of x as it lies (:func:`top_of`) and x's
        level axis (:func:`level_axis`)."""
        g = self._seen(x)
        lo, hi = self.b.box(x)
        return top_of(g, lo, hi), level_axis(g)

    def grasp(self, x: str) -> np.ndarray:
        point, xaxis = self.top(x)
        return tool_down(point, xaxis)

    def above(self, x: str, d: float) -> np.ndarray:
        return raised(self.grasp(x), d)

    def place(self, x: str, where: str, dest: np.ndarray | None = None) -> np.ndarray:
        return self._on_top(x, self.placed_pose(x, self.destination(x, where) if dest is None else dest))

    def _on_top(self, x: str, at: np.ndarray) -> np.ndarray:
        """The tip on the top of x lying at ``at``, its x axis along x's level axis."""
        lo, hi = self.b.box(x)
        return tool_down(top_of(at, lo, hi), level_axis(at))

    def placed_pose(self, x: str, dest: np.ndarray) -> np.ndarray:
        """Where x will lie when put at ``dest`` (the frame its slot or place gives it): ``dest``
        itself when x, turned about the vertical (all a tool pointing down can do), gets its
        orientation; else x as it is held, turned as near ``dest``'s orientation as the vertical
        allows, its frame over ``dest``'s point and its lowest point at the height where x's
        would be at ``dest`` (a part lying on its side in a slot that stands it up: it goes in
        lying, its frame where the slot says). x not seen (held out of the sensor's view):
        ``dest``."""
        if not self.b.placed(x):
            return dest
        now = self.b.pose(x)
        if np.array_equal(now[2, :3], dest[2, :3]):  # up is the same direction in both: they differ by a yaw
            return dest
        rot = turned_to(now[:3, :3], dest[:3, :3])
        if np.abs(rot - dest[:3, :3]).max() <= SAME_ORIENTATION:
            return dest
        lo, hi = self.b.box(x)
        at = np.eye(4)
        at[:3, :3] = rot
        at[:3, 3] = dest[:3, 3]
        at[2, 3] += _bottom(dest, lo, hi) - _bottom(at, lo, hi)
        if float(now[2, :3] @ dest[2, :3]) < SAME_FACE:
            self._another_face(x, dest)
        return at

    def _another_face(self, x: str, dest: np.ndarray) -> None:
        """Say once per part and place that x goes in on another face than its place wants."""
        key = (x, self._slot_name, tuple(np.round(dest[:3, 3], 6)))
        if key in self._warned:
            return
        self._warned.add(key)
        place = f"slot {_local(self._slot_name)}" if self._slot_name else "its place"
        log.warning("%s lies on another face than %s wants: a tool pointing down turns a part about the vertical "
                    "only, so it goes in as it lies, its frame at %s point", _local(x), place,
                    "the slot's" if self._slot_name else "the place's")

    def above_place(self, x: str, where: str, d: float) -> np.ndarray:
        """``place`` raised until x's bottom is d above everything at its place (a box's walls,
        the parts already in a kit), at least d. Footprints are compared in the frame of x at its
        place (the world turned by its heading: a turned kit's neighbours are not in the way)."""
        at = self.placed_pose(x, self.destination(x, where))
        tip = self._on_top(x, at)
        lo, hi = self.b.box(x)
        bottom = float(tip[2, 3]) - height_of(at, lo, hi)  # x's bottom when placed
        yaw = _heading(at)
        flo, fhi = frame_boxes(at[None], lo[None], hi[None], yaw)
        scene = self.b.scene()
        slo, shi = self._frame(scene, yaw)
        near = scene.placed.copy()  # every object at once (was one at a time: O(objects) Python per target)
        near[self.b.index[x]] = False
        with np.errstate(invalid="ignore"):
            near &= slo[:, 2] <= bottom + self.tolerance  # at the place (a box, a table, a kit and its parts)
            near &= (slo[:, :2] < fhi[0, :2]).all(axis=1) & (shi[:, :2] > flo[0, :2]).all(axis=1)
        tops = shi[near, 2]
        rise = max(d, float(np.max(tops + d - bottom))) if tops.size else d
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
        near = scene.placed.copy()  # every object at once
        near[i] = False
        with np.errstate(invalid="ignore"):
            near &= slo[:, 2] <= lo[2] + tol  # under x or around it (a tray, a box, a holder)
            near &= (slo[:, :2] <= hi[:2] + tol).all(axis=1) & (shi[:, :2] >= lo[:2] - tol).all(axis=1)
            near &= ~((slo[:, :2] >= lo[:2] - tol).all(axis=1) & (shi[:, :2] <= hi[:2] + tol).all(axis=1))
        below = shi[near, 2]
        rise = max(d, (float(np.max(below)) + d - float(lo[2])) if below.size else d)
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
        self._slot_name = None
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
        taken = self.b.placed_positions(str(KTW.Part), but=part)
        skus: dict[str, list[str]] = {}  # each slot's SKUs (as related() says them), in one pass
        for s, o in self.b.facts.get(str(KTW.hasPartRefAndPose_Sku), ()):
            skus.setdefault(s, []).append(o)
        for design in self.b.related(str(KTW.hasKit_Design), kit):
            for prp in self.b.related(str(KTW.hasKitDesign_PartRefAndPose), design):
                if sorted(skus.get(prp, ())) != sku:
                    continue
                frame = g @ self._prp_pose(prp)
                off = taken[:, :2] - frame[:2, 3]  # every part at once: none within 1 cm across and 5 cm up
                if np.all((np.sqrt(np.einsum("ij,ij->i", off, off)) > 0.01) | (np.abs(frame[2, 3] - taken[:, 2]) > 0.05)):
                    self._slot_name = prp
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


def _bottom(pose: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> float:
    """The height of the lowest corner of the box (lo, hi) at ``pose``."""
    return float(top_of(pose, lo, hi)[2]) - height_of(pose, lo, hi)


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
