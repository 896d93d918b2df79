"""What the robot handled during a run, from its commands and its scene, as the cell decides it:
the grasps and releases behind the run page's replay (:mod:`kb.report.replay`) and the first
paper's *transporting components* (:mod:`kb.metrics.robustness`), the same for every system —
only the CRCL it sent (timed, :mod:`kb.metrics.clock`), the objects' boxes with their initial and
final poses (the report's ``scene``) and the cell's ground truth of the faults it injected.

* A ``CloseGripper`` takes the object whose top face is at the tool tip (within
  :data:`GRASP_TOLERANCE`) and whose footprint holds it, with what rests in it (a kit tray's
  parts), as :mod:`kb.sim.robot` does; a ``CloseToolChanger`` mounts the end effector there (it
  then hangs below the tip: its far face is the tip). A held object moves with the tip, keeping
  its orientation, until the gripper (tool changer) opens; it then rests where it was let go.
* The ground truth: a grasp a fault made miss (mechanism ``GraspNothing``) takes nothing; a part
  a weak grip dropped (``ReleaseInTransit``) leaves the tip half way through the first move that
  carries it sideways (5 cm or more); an object an external agent moved (``DisplaceObject``,
  ``ShiftInPlane`` with what rests in it, ``RemoveObject``) leaves its place when the action it
  struck starts. Where such an object lies is not in the commands: it is found where the robot
  next grasps it (its top at the tip), else at its final pose.
* At the end every object is at its final pose: those the commands did not bring there (a kit
  that came into being, a turn of a held object) are listed as ``put_right``.

Each object's motion is a list of segments ``[t, kind, corners]``: from time ``t`` on it rests
with its box's 8 world corners (``"rest"``), is held with its corners relative to the tool tip
(``"held"``), or is not there (``"gone"``, no corners).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Sequence

import numpy as np

#: How far (m) an object's top may be from the tip for a grasp to take it (the cell: 2 mm; a
#: report rounds poses to the micrometre, and a released object may have settled a little).
GRASP_TOLERANCE = 0.005
#: How far above a held object's top what rests in it may reach (m).
CONTENT_REACH = 0.05
#: A dropped part falls in the first move carrying it this far sideways (m; kb.sim.robot.TRANSIT).
TRANSIT = 0.05
#: Classes the robot never moves (furniture, the robot, effector holders).
FIXED = frozenset({"WorkTable", "LargeContainer", "LargeBoxWithKits", "LargeBoxWithEmptyKitTrays",
                   "EndEffectorChangingStation", "MechanicalComponent", "Robot", "EndEffectorHolder"})
#: Fault mechanisms (soap:FaultMechanism) by who causes them: the robot's grasp or an external agent.
GRASP_MISSED, DROPPED = "GraspNothing", "ReleaseInTransit"
EXTERNAL = frozenset({"DisplaceObject", "ShiftInPlane", "RemoveObject", "SwapSku", "MarkDefective"})
MOVED_BY_AGENT = frozenset({"DisplaceObject", "ShiftInPlane", "RemoveObject"})
_CLOSE = {"CloseGripper()": "gripper", "CloseToolChanger()": "changer"}
_OPEN = {"OpenGripper()": "gripper", "OpenToolChanger()": "changer"}
_UNIT = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]], float)


def box_corners(lo: Sequence[float], hi: Sequence[float], pose: Any) -> np.ndarray:
    """The 8 world corners (8 x 3) of the box ``lo``..``hi`` in the frame of the 4x4 ``pose``."""
    lo_a, hi_a = np.asarray(lo, float), np.asarray(hi, float)
    m = np.asarray(pose, float)
    return (lo_a + _UNIT * (hi_a - lo_a)) @ m[:3, :3].T + m[:3, 3]


def _numbers(value: Any, n: int) -> bool:
    return (isinstance(value, list) and len(value) == n
            and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in value))


def placed(obj: Any, state: str) -> bool:
    """Whether a scene object has a box and a 4x4 pose in ``state`` (initial, final), all numbers."""
    if not isinstance(obj, dict) or not (_numbers(obj.get("lo"), 3) and _numbers(obj.get("hi"), 3)):
        return False
    pose = obj.get(state)
    return isinstance(pose, list) and len(pose) == 4 and all(_numbers(row, 4) for row in pose)


@dataclass
class Transport:
    """One grasp of an object until its release: when, where from and to (box centres, m), and
    whether it was dropped on the way (ground truth) or let go where the robot put it."""

    name: str
    cls: str
    grasped: float
    released: float | None = None
    start: list[float] = field(default_factory=list)
    end: list[float] | None = None
    dropped: bool = False

    @property
    def carried(self) -> float:
        """How far (m) the object's centre went, 0 while it is unknown."""
        if self.end is None or not self.start:
            return 0.0
        return float(np.linalg.norm(np.asarray(self.end) - np.asarray(self.start)))


@dataclass
class Handling:
    """The objects' motion through a run (module docstring)."""

    names: list[str]
    classes: list[str]
    segments: list[list[list[Any]]]
    transports: list[Transport]
    put_right: list[str]
    t_end: float


class _Boxes(list):
    """The objects' corners now (None: held, lost or gone), with their world boxes kept as arrays
    (lo, hi; NaN for None) so that a grasp's search is one numpy expression."""

    def __init__(self, items: list[np.ndarray | None]) -> None:
        super().__init__(items)
        self.lo = np.full((len(items), 3), np.nan)
        self.hi = np.full((len(items), 3), np.nan)
        for n, c in enumerate(items):
            self._bound(n, c)

    def _bound(self, n: int, c: np.ndarray | None) -> None:
        if c is None:
            self.lo[n] = self.hi[n] = np.nan
        else:
            self.lo[n], self.hi[n] = c.min(axis=0), c.max(axis=0)

    def __setitem__(self, n: int, c: np.ndarray | None) -> None:  # type: ignore[override]
        super().__setitem__(n, c)
        self._bound(n, c)


class _State:
    def __init__(self, scene: dict[str, Any]) -> None:
        objs = [o for o in scene.get("objects") or [] if str(o.get("class")) not in FIXED
                and (placed(o, "initial") or placed(o, "final"))]
        self.names = [str(o.get("name", "")) for o in objs]
        self.classes = [str(o.get("class") or "object") for o in objs]
        self.index = {n: k for k, n in enumerate(self.names)}
        self.effector = np.array([c == "EndEffector" for c in self.classes], bool)
        self.now = _Boxes([box_corners(o["lo"], o["hi"], o["initial"]) if placed(o, "initial") else None
                           for o in objs])
        self.final: list[np.ndarray | None] = [box_corners(o["lo"], o["hi"], o["final"]) if placed(o, "final")
                                               else None for o in objs]
        self.shape = [(c if c is not None else f) for c, f in zip(self.now, self.final)]
        self.segments: list[list[list[Any]]] = [[[0.0, "rest", _r(c)]] if c is not None else [[0.0, "gone"]]
                                                for c in self.now]
        self.lost: dict[int, list[Any]] = {}  # object -> its rest segment whose corners are not known yet
        self.held: dict[int, np.ndarray] = {}  # object -> corners relative to the tip
        self.by: dict[str, list[int]] = {"gripper": [], "changer": []}
        self.open: dict[int, Transport] = {}
        self.transports: list[Transport] = []

    def bounds(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Every object's world box now (lo, hi: n x 3; NaN where it is held, lost or gone) and
        which are placed."""
        return self.now.lo, self.now.hi, ~np.isnan(self.now.lo[:, 0])

    def at_tip(self, tip: np.ndarray, effector: bool) -> int | None:
        """The object whose top is at ``tip`` and whose footprint holds it (an end effector for
        the tool changer, anything else for the gripper): the nearest top, then the smallest."""
        lo, hi, here = self.bounds()
        with np.errstate(invalid="ignore"):
            gap = np.abs(hi[:, 2] - tip[2])
            ok = (here & (gap <= GRASP_TOLERANCE) & (self.effector == effector)
                  & np.all(lo[:, :2] - 1e-3 <= tip[:2], axis=1) & np.all(hi[:, :2] + 1e-3 >= tip[:2], axis=1))
        found = np.flatnonzero(ok)
        if not len(found):
            return None
        size = np.prod(hi[found] - lo[found], axis=1)
        return int(min(zip(np.round(gap[found], 4), size, found))[2])

    def found_lost(self, tip: np.ndarray, effector: bool) -> int | None:
        """An object whose place is not known, grasped at ``tip``: the nearest (by where it was)."""
        lost = [n for n in self.lost if (self.classes[n] == "EndEffector") == effector and self.shape[n] is not None]
        if not lost:
            return None
        n = min(lost, key=lambda m: float(np.linalg.norm(self.shape[m].mean(axis=0)[:2] - tip[:2])))  # type: ignore[union-attr]
        shape = self.shape[n]
        assert shape is not None
        top = np.array([shape[:, 0].mean(), shape[:, 1].mean(), shape[:, 2].max()])
        self.place(n, shape + (tip - top))
        return n

    def place(self, n: int, corners: np.ndarray) -> None:
        """Where lost object ``n`` was, now known."""
        self.now[n] = corners
        self.shape[n] = corners
        self.lost.pop(n)[2] = _r(corners)

    def contents(self, n: int) -> list[int]:
        """The objects resting in object ``n`` (their centre over its footprint, between its
        bottom and a little above its top), end effectors apart."""
        c = self.now[n]
        assert c is not None
        lo, hi = c.min(axis=0), c.max(axis=0)
        olo, ohi, here = self.bounds()
        centre = (olo + ohi) / 2
        with np.errstate(invalid="ignore"):
            ok = (here & ~self.effector & np.all(centre[:, :2] >= lo[:2], axis=1) & np.all(centre[:, :2] <= hi[:2], axis=1)
                  & (centre[:, 2] >= lo[2]) & (centre[:, 2] <= hi[2] + CONTENT_REACH))
        ok[n] = False
        return [int(m) for m in np.flatnonzero(ok)]

    def lose(self, n: int, t: float, gone: bool = False) -> None:
        """Object ``n`` leaves the robot's knowledge at ``t`` (moved by an agent, dropped)."""
        if gone:
            self.segments[n].append([t, "gone"])
            self.now[n] = None
            return
        segment: list[Any] = [t, "rest", None]
        self.segments[n].append(segment)
        if self.now[n] is not None:
            self.shape[n] = self.now[n]
        self.now[n] = None
        self.lost[n] = segment

    def grasp(self, what: str, tip: np.ndarray, t: float) -> None:
        n = self.at_tip(tip, effector=what == "changer")
        if n is None:
            n = self.found_lost(tip, effector=what == "changer")
        if n is None:
            return
        taken = [n] if what == "changer" else [n, *self.contents(n)]
        lift = np.zeros(3)
        if what == "changer":
            c = self.now[n]
            assert c is not None
            lift[2] = float(c[:, 2].max() - c[:, 2].min())
        for m in taken:
            c = self.now[m]
            assert c is not None
            self.held[m] = c - tip + lift
            self.now[m] = None
            self.segments[m].append([t, "held", _r(self.held[m])])
        self.by[what] = taken
        self.open[n] = Transport(self.names[n], self.classes[n], t, start=_r((self.held[n] + tip).mean(axis=0)))
        self.transports.append(self.open[n])

    def release(self, what: str, tip: np.ndarray, t: float, dropped: bool = False) -> None:
        for m in self.by[what]:
            self.now[m] = self.held.pop(m) + tip
            if dropped:
                self.lose(m, t)
            else:
                self.segments[m].append([t, "rest", _r(self.now[m])])
            move = self.open.pop(m, None)
            if move is not None:
                move.released, move.dropped = t, dropped
                move.end = None if dropped else _r(self.now[m].mean(axis=0))  # type: ignore[union-attr]
        self.by[what] = []


def _r(a: np.ndarray) -> list[Any]:
    return np.round(a, 5).tolist()


def _faults(injected: Sequence[dict[str, Any]] | None, mechanisms: dict[str, str]) -> dict[str, dict[int, set[str]]]:
    """Mechanism -> action index -> the objects it struck there."""
    out: dict[str, dict[int, set[str]]] = {}
    for x in injected or []:
        mech = mechanisms.get(str(x.get("kind")))
        index = x.get("action_index")
        if mech is None or not isinstance(index, int):
            continue
        out.setdefault(mech, {}).setdefault(index, set()).update(str(o) for o in x.get("objects") or [])
    return out


def handled(commands: dict[str, Any], scene: dict[str, Any], injected: Sequence[dict[str, Any]] | None = None,
            mechanisms: dict[str, str] | None = None) -> Handling:
    """The objects' motion through a run: its timed ``commands`` (:func:`kb.metrics.clock.timed_commands`,
    rows assumed well-formed), its ``scene``, the ``injected`` faults (kind, action_index, objects)
    with each kind's mechanism (``mechanisms``: kind name -> mechanism name)."""
    rows = commands.get("rows") or []
    state = _State(scene)
    faults = _faults(injected, mechanisms or {})
    missed, drops = faults.get(GRASP_MISSED, {}), faults.get(DROPPED, {})
    agents = {m: faults.get(m, {}) for m in MOVED_BY_AGENT}
    tip = np.asarray(commands.get("start") or [0.0, 0.0, 0.0], float)
    armed: set[int] = set()  # held objects a weak grip will drop
    # an agent's move, when the action it struck starts (or, if that action sent nothing, the next that did)
    pending = sorted((k, mech, name) for mech, by_action in agents.items() for k, names in by_action.items()
                     for name in sorted(names))
    for row in rows:
        action, text, t0, t1 = row[0], str(row[1]), float(row[2]), float(row[3])
        while pending and pending[0][0] <= action:
            _, mech, name = pending.pop(0)
            _agent_moves(state, name, mech, t0)
        before = tip
        tip = np.asarray(row[4], float)
        if armed and row[5] and float(np.linalg.norm(tip[:2] - before[:2])) >= TRANSIT:
            mid = (before + tip) / 2
            state.release("gripper", mid, (t0 + t1) / 2, dropped=True)
            armed.clear()
        if text in _CLOSE and not state.by[_CLOSE[text]]:
            if _CLOSE[text] == "gripper" and _misses(state, tip, missed.get(action, set())):
                continue
            state.grasp(_CLOSE[text], tip, t1)
            if _CLOSE[text] == "gripper" and any(state.names[n] in drops.get(action, ()) for n in state.by["gripper"]):
                armed.add(state.by["gripper"][0])
        elif text in _OPEN and state.by[_OPEN[text]]:
            state.release(_OPEN[text], tip, t1)
            armed.clear()
    t_end = float(rows[-1][3]) if rows else 0.0
    for what in ("gripper", "changer"):
        if state.by[what]:
            state.release(what, tip, t_end)
    return Handling(state.names, state.classes, state.segments, state.transports, _finish(state, t_end), t_end)


def _misses(state: _State, tip: np.ndarray, names: set[str]) -> bool:
    """A grasp a fault made miss: the object at the tip is one it struck."""
    n = state.at_tip(tip, effector=False)
    return n is not None and state.names[n] in names


def _agent_moves(state: _State, name: str, mechanism: str, t: float) -> None:
    n = state.index.get(name)
    if n is None or n in state.held or state.now[n] is None:
        return
    moved = [n] + (state.contents(n) if mechanism == "ShiftInPlane" else [])
    for m in moved:
        state.lose(m, t, gone=mechanism == "RemoveObject")


def _finish(state: _State, t_end: float) -> list[str]:
    """Lost objects where they ended; then every object to its final pose at ``t_end``: the names
    of those the commands did not bring there (more than a millimetre off)."""
    for n in list(state.lost):
        final = state.final[n]
        if final is not None:
            state.place(n, final)
        else:
            segment = state.lost.pop(n)
            segment[1:] = ["gone"]
    out = []
    for n, (now, final) in enumerate(zip(state.now, state.final)):
        if final is None:
            if now is not None:
                state.segments[n].append([t_end, "gone"])
                out.append(state.names[n])
            continue
        if now is None or float(np.abs(now - final).max()) > 1e-3:
            state.segments[n].append([t_end, "rest", _r(final)])
            out.append(state.names[n])
    return out


def fault_mechanisms(kinds: Sequence[str]) -> dict[str, str]:
    """The mechanism of each fault kind named (the shipped domain's; a kind it lacks is left out)."""
    if not kinds:
        return {}
    from kb.model.faults import shipped_fault_kinds  # the domain is read only for a run with faults
    catalogue = shipped_fault_kinds()
    return {k: catalogue.get(k).mechanism.name for k in kinds if catalogue.get(k) is not None}  # type: ignore[union-attr]
