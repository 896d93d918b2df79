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
    expected = {"str": str, "Pose": Pose}[kind]
    if not isinstance(value, expected):
        raise ValueError(f"{cls_name}.{name} must be a {kind}, not {value!r}")
    return value


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
            if f.name != "line" and isinstance(f.type, str) and f.type in ("float", "int", "str", "Pose"):
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
    """Move near every waypoint but the last, and stop at the last (at least one waypoint).

    ``num_positions`` (the XSD's ``NumPositions``, the paper's ``numPoses``) is derived.
    """

    waypoints: tuple[Pose, ...]

    def __post_init__(self) -> None:
        object.__setattr__(self, "waypoints", tuple(self.waypoints))
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


@dataclass(frozen=True)
class Program:
    """A CRCL program: its commands in order, and the file it was read from (not compared)."""

    commands: tuple[Command, ...]
    source: str | None = field(default=None, compare=False)

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
