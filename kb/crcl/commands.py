"""CRCL commands as typed values: one frozen dataclass per command of the first paper's
§V-C, named as CRCL.xsd names its elements (fields: the XSD's child elements in snake case,
or the paper's argument where the XSD has none).

Every command carries ``line``, the line of its source (``None`` when made in code); it is
keyword-only and not compared, so two commands are equal when they command the same thing.
A line of a text file that cannot be parsed is an :class:`Unreadable` (the paper's
``UnreadableMsg``), which keeps the text so the metrics can count it and writers can give it
back.
"""

from __future__ import annotations

import math
import numbers
import operator
from dataclasses import dataclass, field, fields
from typing import ClassVar, Iterator

from kb.crcl.pose import Pose

#: Length units of CRCL.xsd's ``LengthUnitType`` (the paper's text form writes ``"mm"``).
LENGTH_UNITS = ("meter", "millimeter", "inch")
#: Angle units of CRCL.xsd's ``AngleUnitType``.
ANGLE_UNITS = ("degree", "radian")
#: Coordinate systems of the paper's ``SetCoordinateFrame``.
COORDINATE_FRAMES = ("Workstation", "RobotBase", "ToolTip")
#: Force units of CRCL 1.x's ``ForceUnitEnumType``.
FORCE_UNITS = ("newton", "pound", "ounce")
#: Torque units of CRCL 1.x's ``TorqueUnitEnumType``.
TORQUE_UNITS = ("newtonMeter", "footPound")


def _checked(cls_name: str, name: str, kind: str, value: object) -> object:
    """``value`` as the field type ``kind`` (float, int, str, Pose); ValueError otherwise."""
    if kind == "float":
        if isinstance(value, bool) or not isinstance(value, numbers.Real) or not math.isfinite(value):
            raise ValueError(f"{cls_name}.{name} must be a finite number, not {value!r}")
        return float(value)
    if kind == "int":
        if isinstance(value, bool):
            raise ValueError(f"{cls_name}.{name} must be an integer, not {value!r}")
        try:
            return operator.index(value)  # type: ignore[arg-type]
        except TypeError:
            raise ValueError(f"{cls_name}.{name} must be an integer, not {value!r}") from None
    if kind == "bool":
        if not isinstance(value, bool):
            raise ValueError(f"{cls_name}.{name} must be true or false, not {value!r}")
        return value
    if kind == "float | None":
        return None if value is None else _checked(cls_name, name, "float", value)
    if kind == "fraction":
        number = _checked(cls_name, name, "float", value)
        if not 0.0 <= number <= 1.0:  # type: ignore[operator]
            raise ValueError(f"{cls_name}.{name} must be a fraction from 0 to 1, not {value!r}")
        return number
    expected = {"str": str, "Pose": Pose}[kind]
    if not isinstance(value, expected):
        raise ValueError(f"{cls_name}.{name} must be a {kind}, not {value!r}")
    return value


_KINDS = frozenset({"float", "int", "str", "Pose", "bool", "float | None", "fraction"})


@dataclass(frozen=True)
class Command:
    """Base of the CRCL commands; ``line`` is where the command was read (not compared).

    Field values are checked when a command is made: numbers finite (ints kept as floats
    where the field is a float), names from the allowed lists; a bad value is a ValueError.
    """

    line: int | None = field(default=None, compare=False, kw_only=True)

    #: Allowed values of a command's one name field (units, frames), if it has one.
    choices: ClassVar[tuple[str, ...]] = ()

    def __post_init__(self) -> None:
        name = type(self).__name__
        for f in fields(self):
            if f.name != "line" and isinstance(f.type, str) and f.type in _KINDS:
                object.__setattr__(self, f.name, _checked(name, f.name, f.type, getattr(self, f.name)))
        for f in fields(self):
            if self.choices and f.type == "str" and getattr(self, f.name) not in self.choices:
                raise ValueError(f"{name}.{f.name} must be one of {', '.join(self.choices)}, "
                                 f"not {getattr(self, f.name)!r}")


# --- first and last ---------------------------------------------------------------------------

@dataclass(frozen=True)
class InitCanon(Command):
    """Get ready to move; units and coordinate frame back to their defaults."""


@dataclass(frozen=True)
class EndCanon(Command):
    """Stop executing commands (only InitCanon may follow); ``reason`` 0: the plan completed,
    positive: it did not. CRCL.xsd's ``EndCanon`` has no reason (only 0 can be written as XML)."""

    reason: int = 0


# --- messages and waiting ---------------------------------------------------------------------

@dataclass(frozen=True)
class Message(Command):
    """Display ``message`` on the operator console."""

    message: str


@dataclass(frozen=True)
class Dwell(Command):
    """Stay motionless for ``dwell_time`` seconds."""

    dwell_time: float


# --- motion -----------------------------------------------------------------------------------

@dataclass(frozen=True)
class MoveTo(Command):
    """Move the controlled point along any convenient trajectory to ``end_position``."""

    end_position: Pose


@dataclass(frozen=True)
class MoveStraightTo(Command):
    """Move the controlled point in a straight line to ``end_position``."""

    end_position: Pose


@dataclass(frozen=True)
class MoveThroughTo(Command):
    """Move near every waypoint but the last, and stop at the last (at least one waypoint);
    ``straight`` (CRCL 1.x's ``MoveStraight``): in straight lines between them, which the
    paper's form and CRCL.xsd cannot say (only ``straight=False`` is written there).

    ``num_positions`` (the XSD's ``NumPositions``, the paper's ``numPoses``) is derived.
    """

    waypoints: tuple[Pose, ...]
    straight: bool = False

    def __post_init__(self) -> None:
        object.__setattr__(self, "waypoints", tuple(self.waypoints))
        if not isinstance(self.straight, bool):
            raise ValueError(f"MoveThroughTo.straight must be true or false, not {self.straight!r}")
        if not self.waypoints or not all(isinstance(p, Pose) for p in self.waypoints):
            raise ValueError(f"MoveThroughTo.waypoints must be one or more Poses, not {self.waypoints!r}")

    @property
    def num_positions(self) -> int:
        """The number of waypoints."""
        return len(self.waypoints)


@dataclass(frozen=True)
class StopMotion(Command):
    """Stop the robot; ``is_emergency`` non-zero: as soon as possible, 0: gracefully."""

    is_emergency: int


# --- end effector -----------------------------------------------------------------------------

@dataclass(frozen=True)
class OpenGripper(Command):
    """Open the gripper (release what it holds)."""


@dataclass(frozen=True)
class CloseGripper(Command):
    """Close the gripper (grasp what is between its fingers)."""


@dataclass(frozen=True)
class OpenToolChanger(Command):
    """Open the tool changer: release the end effector."""


@dataclass(frozen=True)
class CloseToolChanger(Command):
    """Close the tool changer: attach the end effector it is positioned at."""


# --- settings ---------------------------------------------------------------------------------

@dataclass(frozen=True)
class SetLengthUnits(Command):
    """Length units of later commands: ``meter``, ``millimeter`` or ``inch``."""

    unit_name: str
    choices: ClassVar[tuple[str, ...]] = LENGTH_UNITS


@dataclass(frozen=True)
class SetAngleUnits(Command):
    """Angle units of later commands: ``degree`` or ``radian``."""

    unit_name: str
    choices: ClassVar[tuple[str, ...]] = ANGLE_UNITS


@dataclass(frozen=True)
class SetCoordinateFrame(Command):
    """Operating coordinate system: ``Workstation``, ``RobotBase`` or ``ToolTip`` (not in CRCL.xsd)."""

    coord_system: str
    choices: ClassVar[tuple[str, ...]] = COORDINATE_FRAMES


@dataclass(frozen=True)
class SetAbsoluteSpeed(Command):
    """Speed of the controlled point in length units per second."""

    speed: float


@dataclass(frozen=True)
class SetRelativeSpeed(Command):
    """Speed as a percentage of the robot's maximum (a range is not checked here)."""

    percent: float


@dataclass(frozen=True)
class SetAbsoluteAcceleration(Command):
    """Acceleration of the controlled point in length units per second per second."""

    acceleration: float


@dataclass(frozen=True)
class SetRelativeAcceleration(Command):
    """Acceleration as a percentage of the robot's maximum (a range is not checked here)."""

    percent: float


@dataclass(frozen=True)
class SetEndAngleTolerance(Command):
    """Tolerance of the final orientation, in angle units."""

    tolerance: float


@dataclass(frozen=True)
class SetEndPointTolerance(Command):
    """Tolerance of the final position, in length units."""

    tolerance: float


@dataclass(frozen=True)
class SetIntermediatePointTolerance(Command):
    """Tolerance of smooth motion near intermediate waypoints, in length units."""

    tolerance: float


# --- sensing ----------------------------------------------------------------------------------

@dataclass(frozen=True)
class StartObjectScan(Command):
    """Activate the object sensor and add ``name`` to the parts searched for (not in CRCL.xsd)."""

    name: str


@dataclass(frozen=True)
class StopObjectScan(Command):
    """Deactivate the object sensor (not in CRCL.xsd)."""


# --- CRCL 1.x (NIST's CRCLCommands.xsd, doc/Reference.md) ---------------------------------------

@dataclass(frozen=True)
class GetStatus(Command):
    """Report status immediately (CRCL 1.x)."""


@dataclass(frozen=True)
class SetEndEffector(Command):
    """Set the end effector's effectivity, a fraction from 0 to 1 (CRCL 1.x): of a gripper
    0 closed, 1 open. Settings 1 and 0 are :class:`OpenGripper` and :class:`CloseGripper`
    when read; this class holds the settings between."""

    setting: float

    def __post_init__(self) -> None:
        super().__post_init__()
        object.__setattr__(self, "setting", _checked("SetEndEffector", "setting", "fraction", self.setting))


@dataclass(frozen=True)
class SetForceUnits(Command):
    """Force units of later commands: ``newton``, ``pound`` or ``ounce`` (CRCL 1.x)."""

    unit_name: str
    choices: ClassVar[tuple[str, ...]] = FORCE_UNITS


@dataclass(frozen=True)
class SetTorqueUnits(Command):
    """Torque units of later commands: ``newtonMeter`` or ``footPound`` (CRCL 1.x)."""

    unit_name: str
    choices: ClassVar[tuple[str, ...]] = TORQUE_UNITS


@dataclass(frozen=True)
class SetMotionCoordination(Command):
    """Whether rotation and translation must finish together (CRCL 1.x)."""

    coordinated: bool


@dataclass(frozen=True)
class RotSetting(Command):
    """Base of :class:`SetRotSpeed` and :class:`SetRotAccel`: an absolute ``setting`` or, with
    ``relative``, a fraction (0 to 1) of the maximum."""

    setting: float
    relative: bool = False

    def __post_init__(self) -> None:
        super().__post_init__()
        if self.relative and not 0.0 <= self.setting <= 1.0:
            raise ValueError(f"{type(self).__name__}: a relative setting is a fraction from 0 to 1, "
                             f"not {self.setting!r}")


@dataclass(frozen=True)
class SetRotSpeed(RotSetting):
    """Rotational speed (CRCL 1.x): ``setting`` in angle units per second, or with
    ``relative`` a fraction (0 to 1) of the maximum."""


@dataclass(frozen=True)
class SetRotAccel(RotSetting):
    """Rotational acceleration (CRCL 1.x): ``setting`` in angle units per second per second,
    or with ``relative`` a fraction (0 to 1) of the maximum."""


@dataclass(frozen=True)
class PoseTolerance:
    """CRCL 1.x's ``PoseToleranceType``: each optional; point tolerances in length units, axis
    tolerances in angle units."""

    x_point: float | None = None
    y_point: float | None = None
    z_point: float | None = None
    x_axis: float | None = None
    z_axis: float | None = None

    def __post_init__(self) -> None:
        for f in fields(self):
            object.__setattr__(self, f.name, _checked("PoseTolerance", f.name, "float | None", getattr(self, f.name)))


@dataclass(frozen=True)
class SetEndPoseTolerance(Command):
    """Tolerance of the final pose (CRCL 1.x); the paper's SetEndPointTolerance and
    SetEndAngleTolerance are the two halves of it."""

    tolerance: PoseTolerance


@dataclass(frozen=True)
class SetIntermediatePoseTolerance(Command):
    """Tolerance near intermediate waypoints (CRCL 1.x)."""

    tolerance: PoseTolerance


@dataclass(frozen=True)
class Parameter:
    """A name and a value, as CRCL 1.x's ``ParameterSettingType`` (both tokens)."""

    name: str
    value: str


@dataclass(frozen=True)
class SetEndEffectorParameters(Command):
    """Parameters of the end effector, meaning not CRCL's (CRCL 1.x)."""

    settings: tuple[Parameter, ...]

    def __post_init__(self) -> None:
        object.__setattr__(self, "settings", tuple(self.settings))
        if not self.settings or not all(isinstance(p, Parameter) for p in self.settings):
            raise ValueError(f"{type(self).__name__}.settings must be one or more Parameters, not {self.settings!r}")


@dataclass(frozen=True)
class SetRobotParameters(SetEndEffectorParameters):
    """Parameters of the robot, meaning not CRCL's (CRCL 1.x)."""


@dataclass(frozen=True)
class JointActuation:
    """One joint of an :class:`ActuateJoints`: its number (from 1), target position (length or
    angle units) and either speed and acceleration or (``force_control``) force or torque and
    its rate of change, each optional."""

    number: int
    position: float
    speed: float | None = None
    accel: float | None = None
    force_control: bool = False
    force: float | None = None
    change_rate: float | None = None


@dataclass(frozen=True)
class ActuateJoints(Command):
    """Move the given joints to their positions (CRCL 1.x)."""

    joints: tuple[JointActuation, ...]

    def __post_init__(self) -> None:
        object.__setattr__(self, "joints", tuple(self.joints))
        if not self.joints or not all(isinstance(j, JointActuation) for j in self.joints):
            raise ValueError(f"ActuateJoints.joints must be one or more JointActuations, not {self.joints!r}")


@dataclass(frozen=True)
class JointReport:
    """What to report of one joint (CRCL 1.x's ``ConfigureJointReportType``)."""

    number: int
    position: bool
    torque_or_force: bool
    velocity: bool


@dataclass(frozen=True)
class ConfigureJointReports(Command):
    """Which joint statuses to report (CRCL 1.x); ``reset_all``: none but these."""

    reset_all: bool
    reports: tuple[JointReport, ...] = ()

    def __post_init__(self) -> None:
        super().__post_init__()
        object.__setattr__(self, "reports", tuple(self.reports))


@dataclass(frozen=True)
class RunProgram(Command):
    """Run a program in the controller's own language (CRCL 1.x)."""

    program_text: str


# --- CRCL 1.x housekeeping and the rest of CRCLCommands.xsd -----------------------------------------

@dataclass(frozen=True)
class ConfigureStatusReport(Command):
    """Which parts the controller's status documents carry from now on (CRCL 1.x): joint
    statuses, the pose, the gripper, settings, sensors and guards, each true or false."""

    joints: bool
    pose: bool
    gripper: bool
    settings: bool
    sensors: bool
    guards: bool


@dataclass(frozen=True)
class EnableGripper(Command):
    """Enable the gripper named ``name`` (an XML name token), with ``options`` whose meaning
    is the controller's (CRCL 1.x)."""

    name: str
    options: tuple[Parameter, ...] = ()

    def __post_init__(self) -> None:
        super().__post_init__()
        _options(self, "options")


@dataclass(frozen=True)
class DisableGripper(Command):
    """Disable the gripper named ``name``: it takes no SetEndEffector until enabled (CRCL 1.x)."""

    name: str


@dataclass(frozen=True)
class EnableSensor(Command):
    """Enable the sensor ``sensor_id``, with ``options`` whose meaning is the sensor's (CRCL 1.x)."""

    sensor_id: str
    options: tuple[Parameter, ...] = ()

    def __post_init__(self) -> None:
        super().__post_init__()
        _options(self, "options")


@dataclass(frozen=True)
class DisableSensor(Command):
    """Disable the sensor ``sensor_id`` (CRCL 1.x)."""

    sensor_id: str


@dataclass(frozen=True)
class EnableRobotParameterStatus(Command):
    """Report the robot parameter ``name`` in the status's settings (CRCL 1.x)."""

    name: str


@dataclass(frozen=True)
class DisableRobotParameterStatus(Command):
    """Stop reporting the robot parameter ``name`` (CRCL 1.x)."""

    name: str


@dataclass(frozen=True)
class JointTolerance:
    """One joint's position tolerance (CRCL 1.x's ``JointPositionToleranceSettingType``): its
    number and the tolerance in length or angle units."""

    number: int
    tolerance: float


@dataclass(frozen=True)
class SetDefaultJointPositionsTolerances(Command):
    """Default position tolerances of the given joints (CRCL 1.x's
    ``SetDefaultJointPositonsTolerances``, spelt so in CRCLCommands.xsd)."""

    tolerances: tuple[JointTolerance, ...]

    def __post_init__(self) -> None:
        object.__setattr__(self, "tolerances", tuple(self.tolerances))
        if not self.tolerances or not all(isinstance(t, JointTolerance) for t in self.tolerances):
            raise ValueError("SetDefaultJointPositionsTolerances.tolerances must be one or more JointTolerances, "
                             f"not {self.tolerances!r}")


@dataclass(frozen=True)
class MoveScrew(Command):
    """A screwing motion (CRCL 1.x): from ``start_position`` (optional) turn ``turn`` (angle
    units) about the axis through ``axis_point`` (optional), moving ``axial_distance_free``
    (optional) and then ``axial_distance_screw`` along it (length units)."""

    axial_distance_screw: float
    turn: float
    start_position: Pose | None = None
    axis_point: tuple[float, float, float] | None = None
    axial_distance_free: float | None = None

    def __post_init__(self) -> None:
        super().__post_init__()
        if self.start_position is not None and not isinstance(self.start_position, Pose):
            raise ValueError(f"MoveScrew.start_position must be a Pose, not {self.start_position!r}")
        if self.axis_point is not None:
            point = tuple(_checked("MoveScrew", "axis_point", "float", v) for v in self.axis_point)
            if len(point) != 3:
                raise ValueError(f"MoveScrew.axis_point must be three numbers, not {self.axis_point!r}")
            object.__setattr__(self, "axis_point", point)


@dataclass(frozen=True)
class LoopBlockStart(Command):
    """Start of a block repeated until its :class:`LoopBlockEnd` of the same ``name`` (CRCL 1.x)."""

    name: str


@dataclass(frozen=True)
class LoopBlockEnd(Command):
    """End of the block ``name``: back to its start, at most ``max_count`` times (CRCL 1.x)."""

    name: str
    max_count: int


#: CRCL 1.x's ``GuardLimitEnumType``.
GUARD_LIMITS = ("OVER_MAX", "UNDER_MIN", "INCREASE_OVER_LIMIT", "DECREASE_BEYOND_LIMIT")


@dataclass(frozen=True)
class Guard:
    """A condition on a sensor's value that stops the command it guards (CRCL 1.x's
    ``GuardType``): ``sensor_id`` (and its ``sub_field``), ``limit_type`` (one of
    :data:`GUARD_LIMITS`) and ``limit_value``; the rest optional as in the schema."""

    sensor_id: str
    limit_type: str
    limit_value: float
    sub_field: str | None = None
    recheck_us: int | None = None
    check_count: int | None = None
    last_check_time: int | None = None
    last_check_value: float | None = None
    require_trigger: bool | None = None
    error_on_trigger: bool | None = None
    name: str | None = None

    def __post_init__(self) -> None:
        if self.limit_type not in GUARD_LIMITS:
            raise ValueError(f"Guard.limit_type must be one of {', '.join(GUARD_LIMITS)}, not {self.limit_type!r}")
        object.__setattr__(self, "limit_value", _checked("Guard", "limit_value", "float", self.limit_value))
        for attr in ("recheck_us", "check_count", "last_check_time"):
            if getattr(self, attr) is not None:
                object.__setattr__(self, attr, _checked("Guard", attr, "int", getattr(self, attr)))
        for attr in ("require_trigger", "error_on_trigger"):
            if getattr(self, attr) is not None:
                _checked("Guard", attr, "bool", getattr(self, attr))
        object.__setattr__(self, "last_check_value",
                           _checked("Guard", "last_check_value", "float | None", self.last_check_value))


@dataclass(frozen=True)
class Guarded(Command):
    """``command`` with ``guards`` (one or more): it stops when a guard's sensor value passes
    its limit (CRCL 1.x, any command may carry guards). Its line is the command's."""

    command: Command
    guards: tuple[Guard, ...]

    def __post_init__(self) -> None:
        object.__setattr__(self, "guards", tuple(self.guards))
        if not isinstance(self.command, Command) or isinstance(self.command, Guarded):
            raise ValueError(f"Guarded.command must be a command without guards, not {self.command!r}")
        if not self.guards or not all(isinstance(g, Guard) for g in self.guards):
            raise ValueError(f"Guarded.guards must be one or more Guards, not {self.guards!r}")


def unguarded(command: Command) -> Command:
    """The command a :class:`Guarded` guards; any other command itself."""
    return command.command if isinstance(command, Guarded) else command


def _options(command: Command, attr: str) -> None:
    value = tuple(getattr(command, attr))
    if not all(isinstance(p, Parameter) for p in value):
        raise ValueError(f"{type(command).__name__}.{attr} must be Parameters, not {value!r}")
    object.__setattr__(command, attr, value)


# --- what could not be read -------------------------------------------------------------------

@dataclass(frozen=True)
class Unreadable(Command):
    """A text line (or a command spread over lines) that does not parse: ``text`` as it
    stands in the file, ``reason`` what is wrong (not compared). Executing one counts a
    parse error (the first paper's ``UnreadableMsg``)."""

    text: str
    reason: str = field(default="", compare=False)


#: Every command class, by name (the text form's and CRCL.xsd's names).
COMMANDS: dict[str, type[Command]] = {
    cls.__name__: cls for cls in (
        InitCanon, EndCanon, Message, Dwell, MoveTo, MoveStraightTo, MoveThroughTo, StopMotion,
        OpenGripper, CloseGripper, OpenToolChanger, CloseToolChanger,
        SetLengthUnits, SetAngleUnits, SetCoordinateFrame, SetAbsoluteSpeed, SetRelativeSpeed,
        SetAbsoluteAcceleration, SetRelativeAcceleration, SetEndAngleTolerance,
        SetEndPointTolerance, SetIntermediatePointTolerance, StartObjectScan, StopObjectScan)
}
#: The commands of CRCL 1.x that the first paper's language lacks (read and written only as CRCL 1.x
#: XML; :mod:`kb.crcl.instance`).
CRCL1_COMMANDS: dict[str, type[Command]] = {
    cls.__name__: cls for cls in (
        GetStatus, SetEndEffector, SetForceUnits, SetTorqueUnits, SetMotionCoordination, SetRotSpeed,
        SetRotAccel, SetEndPoseTolerance, SetIntermediatePoseTolerance, SetEndEffectorParameters,
        SetRobotParameters, ActuateJoints, ConfigureJointReports, RunProgram, ConfigureStatusReport,
        EnableGripper, DisableGripper, EnableSensor, DisableSensor, EnableRobotParameterStatus,
        DisableRobotParameterStatus, SetDefaultJointPositionsTolerances, MoveScrew, LoopBlockStart, LoopBlockEnd,
        Guarded)
}


#: (length unit, angle unit) a controller resets to at InitCanon, by form: the first paper's
#: (its text forms and NIST's 2014 CRCL.xsd XML) and CRCL 1.x's (doc/Reference.md). docs/crcl.md.
PAPER_UNITS = ("millimeter", "degree")
CRCL1_UNITS = ("meter", "radian")


@dataclass(frozen=True)
class Program:
    """A CRCL program: its commands in order, the file it was read from, and ``units``: the
    (length, angle) units of its form's InitCanon (:data:`PAPER_UNITS`, :data:`CRCL1_UNITS`;
    None: not known, as made in code). Neither is compared."""

    commands: tuple[Command, ...]
    source: str | None = field(default=None, compare=False)
    units: tuple[str, str] | None = field(default=None, compare=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "commands", tuple(self.commands))

    def __iter__(self) -> Iterator[Command]:
        return iter(self.commands)

    def __len__(self) -> int:
        return len(self.commands)

    def __getitem__(self, index: int) -> Command:
        return self.commands[index]

    @property
    def unreadable(self) -> tuple[Unreadable, ...]:
        """The lines that did not parse (the first paper's parse errors)."""
        return tuple(c for c in self.commands if isinstance(c, Unreadable))
