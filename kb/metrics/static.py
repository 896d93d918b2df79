"""The static metrics of a CRCL program (the first paper's §IV-A, NIST's kittingViewer):
evaluated at the end of each command with cumulative values, by executing the program on a
simulated robot (:class:`~kb.metrics.motion.Robot`). docs/metrics.md defines each metric and
says where kitkb had to choose; in short:

* a command is *executed* when it is in sequence and sets no value out of range; an executed
  move, dwell or gripper / tool changer command is an *action* command (ACE), any other
  executed command an *other* command (OCE); a refused command has no effect and is not
  counted as executed (as in the kittingViewer);
* each value out of range is one range error (RE): ``SetRelativeAcceleration(-110)`` is
  negative and more than 100 %, two errors;
* an unreadable line is one parse error (PE) and nothing else;
* InitCanon not the first (readable) command, EndCanon not the last, and any other command
  while the robot is not initialised (before InitCanon, after EndCanon) are sequence errors
  (CSE); TE = RE + PE + CSE;
* an executed command that changes nothing — the gripper or tool changer already in that
  state (both start closed), a unit, frame, speed, acceleration or tolerance set to what it
  is, a move to where the robot is, ``Dwell(0)``, a StopMotion with nothing moving — is
  useless (UCE);
* TDM is the tool tip's path (straight lines between the points, from where it stands), TET
  the sum of the action commands' times (CCE), a move's time from a trapezoidal velocity
  profile over its path with the speed and acceleration in force.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Callable, Iterable, Sequence

from kb.metrics.motion import INITIAL_PERCENT, Robot, timed_move, transfer_points
from kb.metrics.steps import Step

#: The metrics in the paper's order, and their names.
METRICS = ("ACE", "OCE", "TCE", "TDM", "CCE", "TET", "RE", "PE", "CSE", "TE", "UCE")
NAMES = {
    "ACE": "Action Commands Executed", "OCE": "Other Commands Executed", "TCE": "Total Commands Executed",
    "TDM": "Total Distance Moved", "CCE": "Current Command Execution Time", "TET": "Total Execution Time",
    "RE": "Range Errors", "PE": "Parse Errors", "CSE": "Command Sequence Errors", "TE": "Total Errors",
    "UCE": "Useless Commands Executed",
}
#: The unit of each metric that has one (the others are counts).
UNITS = {"TDM": "m", "CCE": "s", "TET": "s"}

_LENGTH = {"meter": 1.0, "millimeter": 0.001, "inch": 0.0254}
_SHORT = {"meter": "m", "millimeter": "mm", "inch": "in"}
_ANGLE = {"degree": math.pi / 180.0, "radian": 1.0}
#: The units InitCanon sets in the first paper's forms (kb.crcl.PAPER_UNITS).
_PAPER_UNITS = ("millimeter", "degree")
#: How far from 1 an axis' length, and from 0 the Z and X axes' dot product, may be.
AXIS_TOLERANCE = 1e-4
_DOWN = (0.0, 0.0, -1.0, 1.0, 0.0, 0.0)
#: What executing a command did: an action command?, its seconds, its distance, why it was useless.
_Done = tuple[bool, float, float, "str | None"]


@dataclass(slots=True)
class Row:
    """The metrics after one command: ``values`` in :data:`METRICS` order (cumulative, CCE the
    command's own time), ``notes`` what happened (errors, why it was useless), ``settings``
    the robot's settings after it, in the units in force (the kittingViewer's Metrics &
    Settings window)."""

    index: int
    line: int | None
    command: str
    values: tuple[float, ...]
    notes: tuple[str, ...] = ()
    settings: dict[str, Any] | None = field(default=None, compare=False)
    #: a move's path: the points the tool tip passed through to its end (m), in order; () else
    path: tuple[tuple[float, float, float], ...] = field(default=(), compare=False)

    def as_dict(self) -> dict[str, Any]:
        """The row as JSON data."""
        return {"index": self.index, "line": self.line, "command": self.command,
                **dict(zip(METRICS, self.values)), "notes": list(self.notes), "settings": self.settings}


@dataclass(frozen=True)
class StaticMetrics:
    """The static metrics of a program: ``totals`` after its last command (CCE: the last
    command's time), ``rows`` one per command when asked for, the ``robot`` they assume."""

    source: str | None
    commands: int
    robot: Robot
    totals: dict[str, float]
    rows: list[Row] | None = field(default=None, compare=False)

    def as_dict(self) -> dict[str, Any]:
        """The metrics as JSON data."""
        data: dict[str, Any] = {
            "program": self.source, "commands": self.commands,
            "robot": {"max_speed": self.robot.max_speed, "max_acceleration": self.robot.max_acceleration,
                      "effector_seconds": self.robot.effector_seconds, "start": list(self.robot.start)},
            "metrics": dict(self.totals), "names": dict(NAMES), "units": dict(UNITS)}
        if self.rows is not None:
            data["rows"] = [r.as_dict() for r in self.rows]
        return data


def static_metrics(steps: Iterable[Step], robot: Robot | None = None, *, rows: bool = False,
                   source: str | None = None) -> StaticMetrics:
    """The static metrics of a program's steps (:func:`kb.metrics.read_steps`,
    :func:`kb.metrics.steps_of`) on ``robot`` (default :class:`Robot()`); ``rows``: keep the
    metrics after every command too."""
    units = getattr(steps, "units", None)
    steps = list(steps)
    robot = robot or Robot()
    run = _Run(robot, units)
    readable = [i for i, s in enumerate(steps) if s[0] != "Unreadable"]
    first, last = (readable[0], readable[-1]) if readable else (-1, -1)
    kept: list[Row] | None = [] if rows else None
    for index, step in enumerate(steps):
        notes = run.step(step, index == first, index == last)
        if kept is not None:
            kept.append(Row(index, step[1], describe(step), run.values(), tuple(notes), run.settings()))
    return StaticMetrics(source, len(steps), robot, dict(zip(METRICS, run.values())), kept)


def session_metrics(programs: Iterable[Iterable[Step]], robot: Robot | None = None, *,
                    source: str | None = None, units: tuple[str, str] | None = None,
                    rows: bool = False) -> StaticMetrics:
    """The static metrics of programs sent one after another to one robot — a run's CRCL, one
    program per action: each program's InitCanon and EndCanon are judged by their place in
    that program, the robot's state (where it stands, gripper, settings) carries over, and the
    counts add up. ``units``: those of the programs' form (default the paper's) where
    ``robot`` names none. ``rows``: keep the metrics after every command too, numbered across
    the session, each with the tool tip's path (:attr:`Row.path`: the points it passed, m)."""
    robot = robot or Robot()
    run = _Run(robot, units)
    count = 0
    kept: list[Row] | None = [] if rows else None
    for program in programs:
        steps = list(program)
        readable = [i for i, s in enumerate(steps) if s[0] != "Unreadable"]
        first, last = (readable[0], readable[-1]) if readable else (-1, -1)
        for index, step in enumerate(steps):
            run.legs = []
            notes = run.step(step, index == first, index == last)
            if kept is not None:
                kept.append(Row(count + index, step[1], describe(step), run.values(), tuple(notes), run.settings(),
                                tuple(run.legs)))
        count += len(steps)
    return StaticMetrics(source, count, robot, dict(zip(METRICS, run.values())), kept)


class _Run:
    """The robot's state and the counters while a program runs."""

    def __init__(self, robot: Robot, units: tuple[str, str] | None = None) -> None:
        self.robot = robot
        self.form_units = units or _PAPER_UNITS
        self.stating_units = False  # in the unit commands right after an InitCanon
        self.ace = self.oce = self.re = self.pe = self.cse = self.uce = 0
        self.tdm = self.tet = self.cce = 0.0
        self.ready = False
        self.ended = False
        self.point = tuple(float(v) for v in robot.start)
        self.axes = _DOWN
        self.gripper_open = False
        self.changer_open = False
        self.scanning: set[str] = set()
        self.frame = "Workstation"
        self.legs: list[tuple[float, float, float]] = []  # the last move's points (m)
        # the robot's start (the kittingViewer's: 10 % of the maxima), tolerances 0
        self.speed = robot.start_speed or INITIAL_PERCENT / 100.0 * robot.max_speed
        self.acceleration = robot.start_acceleration or INITIAL_PERCENT / 100.0 * robot.max_acceleration
        self.tolerances = dict.fromkeys(
            ("end angle tolerance (rad)", "end point tolerance (m)", "intermediate point tolerance (m)"), 0.0)
        self._defaults()
        self._axes_checked: dict[tuple[float, ...], list[str]] = {}
        self._execute: dict[str, Callable[[Any], _Done]] = {
            name[1:]: getattr(self, name) for name in dir(self) if name[1:2].isupper() and name[0] == "_"}
        self._checks: dict[str, Callable[[str, Any], list[str]]] = {
            **dict.fromkeys(("SetRelativeSpeed", "SetRelativeAcceleration"), self._check_percent),
            **dict.fromkeys(("SetAbsoluteSpeed", "SetAbsoluteAcceleration"), self._check_absolute),
            **dict.fromkeys(("Dwell", "SetEndAngleTolerance", "SetEndPointTolerance",
                             "SetIntermediatePointTolerance", "EndCanon"), self._check_signed),
            **dict.fromkeys(("MoveTo", "MoveStraightTo", "MoveThroughTo"), self._check_move)}

    def _defaults(self) -> None:
        """The units InitCanon sets: the robot's, else those of the program's form (the paper:
        millimetres and degrees; CRCL 1.x: metres and radians)."""
        self.length_unit = self.robot.length_unit or self.form_units[0]
        self.angle_unit = self.robot.angle_unit or self.form_units[1]

    def values(self) -> tuple[float, ...]:
        """The metrics now, in :data:`METRICS` order."""
        te = self.re + self.pe + self.cse
        return (self.ace, self.oce, self.ace + self.oce, self.tdm, self.cce, self.tet,
                self.re, self.pe, self.cse, te, self.uce)

    def settings(self) -> dict[str, Any]:
        """The settings now, in the units in force (speeds per second, tolerances, the
        controlled point's position), as the kittingViewer showed them."""
        length, angle = _LENGTH[self.length_unit], _ANGLE[self.angle_unit]
        tolerance = self.tolerances
        return {
            "length_unit": self.length_unit, "angle_unit": self.angle_unit,
            "speed": self.speed / length, "relative_speed": 100.0 * self.speed / self.robot.max_speed,
            "acceleration": self.acceleration / length,
            "relative_acceleration": 100.0 * self.acceleration / self.robot.max_acceleration,
            "end_angle_tolerance": tolerance["end angle tolerance (rad)"] / angle,
            "end_point_tolerance": tolerance["end point tolerance (m)"] / length,
            "intermediate_point_tolerance": tolerance["intermediate point tolerance (m)"] / length,
            "gripper": "open" if self.gripper_open else "closed",
            "tool_changer": "open" if self.changer_open else "closed",
            "position": [v / length for v in self.point], "coordinate_frame": self.frame,
        }

    def step(self, step: Step, first: bool, last: bool) -> Sequence[str]:
        """Execute one step; the notes of what happened."""
        kind, _, value = step
        self.cce = 0.0
        if kind == "Unreadable":
            self.pe += 1
            return [f"parse error: {value[1]}" if value[1] else "parse error"]
        notes: list[str] = []
        if kind == "InitCanon":
            if not first:
                self.cse += 1
                notes.append("sequence error: InitCanon is not the first command")
        elif kind == "EndCanon":
            if not last:
                self.cse += 1
                notes.append("sequence error: EndCanon is not the last command")
        elif not self.ready:
            self.cse += 1
            return [f"sequence error: {'after EndCanon' if self.ended else 'before InitCanon'}, not executed"]
        check = self._checks.get(kind)
        if check is not None:
            errors = check(kind, value)
            if errors:
                self.re += len(errors)
                return notes + [f"range error: {e}" for e in errors] + ["not executed"]
        action, seconds, distance, useless = self._execute.get(kind, self._other)(value)
        if kind in ("SetLengthUnits", "SetAngleUnits") and self.stating_units:
            useless = None  # units said right after InitCanon, as every program should (issue 27)
        self.stating_units = kind in ("InitCanon", "SetLengthUnits", "SetAngleUnits")
        if action:
            self.ace += 1
            self.cce = seconds
            self.tet += seconds
            self.tdm += distance
        else:
            self.oce += 1
        if useless:
            self.uce += 1
            notes.append(f"useless: {useless}")
        return notes

    # --- range checks -------------------------------------------------------------------------

    def _check_percent(self, kind: str, value: float) -> list[str]:
        return _signed(value, "percent") + ([f"{value:g} % is more than 100 %"] if abs(value) > 100 else [])

    def _check_absolute(self, kind: str, value: float) -> list[str]:
        speed = kind == "SetAbsoluteSpeed"
        most = self.robot.max_speed if speed else self.robot.max_acceleration
        unit = f"{_SHORT[self.length_unit]}/s" + ("" if speed else "²")
        over = abs(value) * _LENGTH[self.length_unit] > most * (1 + 1e-12)
        return _signed(value, "speed" if speed else "acceleration") + (
            [f"{abs(value):g} {unit} is more than the robot's maximum "
             f"{most / _LENGTH[self.length_unit]:g} {unit}"] if over else [])

    def _check_signed(self, kind: str, value: float) -> list[str]:
        return _signed(value, {"Dwell": "dwell time", "EndCanon": "reason"}.get(kind, "tolerance"))

    def _check_move(self, kind: str, poses: tuple[tuple[float, ...], ...]) -> list[str]:
        errors: list[str] = []
        checked = self._axes_checked
        for n, p in enumerate(poses, 1):
            axes = p[3:9]
            found = checked.get(axes)
            if found is None:
                found = checked[axes] = _axis_errors(axes)
            if found:
                errors.extend(f"{e} of pose {n}" if len(poses) > 1 else e for e in found)
        if not errors and (self.speed <= 0 or self.acceleration <= 0) and self._path(poses)[0] > 0:
            errors.append(f"a move with {'speed' if self.speed <= 0 else 'acceleration'} 0 never ends")
        return errors

    # --- execution: (action?, seconds, distance, why useless) ----------------------------------

    def _path(self, poses: tuple[tuple[float, ...], ...], transfer: bool = False
              ) -> tuple[float, tuple[float, ...], bool]:
        """Length (m) of the straight lines from the tool tip through the poses' points (with
        ``transfer``, a MoveTo's up, across and down: :func:`~kb.metrics.motion.transfer_points`),
        the last point (m), and whether any pose turns the tool."""
        scale = _LENGTH[self.length_unit]
        here, total, axes, turned = self.point, 0.0, self.axes, False
        for p in poses:
            there = (p[0] * scale, p[1] * scale, p[2] * scale)
            for corner in transfer_points(here, there) if transfer else (there,):
                total += math.dist(here, corner)
                here = corner
                self.legs.append(corner)
            here = there
            turned = turned or p[3:9] != axes
        return total, here, turned

    def _move(self, poses: tuple[tuple[float, ...], ...], transfer: bool = False) -> _Done:
        self.legs = []
        distance, self.point, turned = self._path(poses, transfer)
        self.axes = poses[-1][3:9]
        useless = None if distance > 0 or turned else "the robot is already there"
        return True, timed_move(distance, self.speed, self.acceleration, self.robot.accelerates), distance, useless

    _MoveStraightTo = _MoveThroughTo = _move

    def _MoveTo(self, poses: tuple[tuple[float, ...], ...]) -> _Done:
        return self._move(poses, self.robot.move_to == "transfer")

    def _InitCanon(self, _: Any) -> _Done:
        self.ready, self.ended = True, False
        self._defaults()
        return False, 0.0, 0.0, None

    def _EndCanon(self, _: Any) -> _Done:
        self.ready, self.ended = False, True
        return False, 0.0, 0.0, None

    def _Message(self, _: Any) -> _Done:
        return False, 0.0, 0.0, None

    def _Dwell(self, seconds: float) -> _Done:
        return True, seconds, 0.0, None if seconds > 0 else "a dwell of 0 s"

    def _effector(self, attribute: str, opened: bool, what: str) -> _Done:
        useless = getattr(self, attribute) == opened
        setattr(self, attribute, opened)
        return True, self.robot.effector_seconds, 0.0, (
            f"the {what} is already {'open' if opened else 'closed'}" if useless else None)

    def _OpenGripper(self, _: Any) -> _Done:
        return self._effector("gripper_open", True, "gripper")

    def _CloseGripper(self, _: Any) -> _Done:
        return self._effector("gripper_open", False, "gripper")

    def _OpenToolChanger(self, _: Any) -> _Done:
        return self._effector("changer_open", True, "tool changer")

    def _CloseToolChanger(self, _: Any) -> _Done:
        return self._effector("changer_open", False, "tool changer")

    def _setting(self, attribute: str, new: Any, what: str) -> _Done:
        old = getattr(self, attribute)
        same = old == new if isinstance(new, str) else math.isclose(old, new, rel_tol=1e-9)
        setattr(self, attribute, new)
        return False, 0.0, 0.0, f"the {what} is already {_show(new)}" if same else None

    def _SetLengthUnits(self, unit: str) -> _Done:
        return self._setting("length_unit", unit, "length unit")

    def _SetAngleUnits(self, unit: str) -> _Done:
        return self._setting("angle_unit", unit, "angle unit")

    def _SetCoordinateFrame(self, frame: str) -> _Done:
        return self._setting("frame", frame, "coordinate frame")

    def _SetAbsoluteSpeed(self, speed: float) -> _Done:
        return self._setting("speed", speed * _LENGTH[self.length_unit], "speed (m/s)")

    def _SetRelativeSpeed(self, percent: float) -> _Done:
        return self._setting("speed", percent / 100.0 * self.robot.max_speed, "speed (m/s)")

    def _SetAbsoluteAcceleration(self, acceleration: float) -> _Done:
        return self._setting("acceleration", acceleration * _LENGTH[self.length_unit], "acceleration (m/s²)")

    def _SetRelativeAcceleration(self, percent: float) -> _Done:
        return self._setting("acceleration", percent / 100.0 * self.robot.max_acceleration, "acceleration (m/s²)")

    def _tolerance(self, name: str, value: float) -> _Done:
        same = math.isclose(self.tolerances[name], value, rel_tol=1e-9)
        self.tolerances[name] = value
        return False, 0.0, 0.0, f"the {name} is already {_show(value)}" if same else None

    def _SetEndAngleTolerance(self, tolerance: float) -> _Done:
        return self._tolerance("end angle tolerance (rad)", tolerance * _ANGLE[self.angle_unit])

    def _SetEndPointTolerance(self, tolerance: float) -> _Done:
        return self._tolerance("end point tolerance (m)", tolerance * _LENGTH[self.length_unit])

    def _SetIntermediatePointTolerance(self, tolerance: float) -> _Done:
        return self._tolerance("intermediate point tolerance (m)", tolerance * _LENGTH[self.length_unit])

    def _StartObjectScan(self, name: str) -> _Done:
        useless = name in self.scanning
        self.scanning.add(name)
        return False, 0.0, 0.0, f"{name} is already searched for" if useless else None

    def _StopObjectScan(self, _: Any) -> _Done:
        useless = not self.scanning
        self.scanning.clear()
        return False, 0.0, 0.0, "the object sensor is not active" if useless else None

    def _SetEndEffector(self, setting: float) -> _Done:
        return self._effector("gripper_open", setting > 0, "gripper")

    def _other(self, _: Any) -> _Done:
        """A CRCL 1.x command the paper's language lacks: executed, changes nothing measured."""
        return False, 0.0, 0.0, None

    def _StopMotion(self, _: Any) -> _Done:
        return False, 0.0, 0.0, "nothing is moving (every move stops at its end)"


def _axis_errors(axes: tuple[float, ...]) -> list[str]:
    """What is wrong with a pose's Z and X axes (not unit vectors, not perpendicular)."""
    z, x = axes[:3], axes[3:]
    errors = [f"the {name} axis is not a unit vector" for name, axis in (("Z", z), ("X", x))
              if abs(math.sqrt(sum(c * c for c in axis)) - 1.0) > AXIS_TOLERANCE]
    if abs(sum(a * b for a, b in zip(z, x))) > AXIS_TOLERANCE:
        errors.append("the Z and X axes are not perpendicular")
    return errors


def _signed(value: float, what: str) -> list[str]:
    return [f"negative {what} {value:g}"] if value < 0 else []


def _show(value: Any) -> str:
    return f"{value:g}" if isinstance(value, float) else str(value)


def describe(step: Step) -> str:
    """A short text of a step for the per-command rows: ``SetRelativeSpeed(50)``,
    ``MoveTo(9, 8, 2)`` (the end point), the unreadable text as it stands."""
    kind, _, value = step
    if kind == "Unreadable":
        return value[0].split("\n", 1)[0]
    if value is None:
        return f"{kind}()"
    if kind in ("MoveTo", "MoveStraightTo", "MoveThroughTo"):
        more = f"{len(value)} poses to " if len(value) > 1 else ""
        return f"{kind}({more}{', '.join(f'{v:g}' for v in value[-1][:3])})"
    if isinstance(value, str):
        return f'{kind}("{value}")'
    return f"{kind}({value:g})"
