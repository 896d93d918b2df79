"""The simulated robot behind the time metrics: its limits, its settings before a program sets
any, and the time of a move — with a trapezoidal velocity profile (accelerate at the
acceleration in force, cruise at the speed in force, decelerate to a stop at the end point), or
at the speed in force throughout (a robot that :attr:`Robot.accelerates` not: kitkb's kinematic
cell).

Two robots matter: NIST's kittingViewer's (:class:`Robot`'s defaults: 10 % of 1 m/s and of
10 m/s² at the start, 0.2 s per gripper command, a MoveTo in a straight line), for a program
judged on its own (``kitkb metrics FILE``); and the robot of kitkb's cells (:func:`cell_robot`:
1 m/s from the start, no acceleration phases, gripper commands at once, a MoveTo up, across and
down), for a run — so that a run's TET, its replay and the cell's clock are one clock
(docs/metrics.md, "One clock"). Either way the speeds a program commands (``SetTransSpeed``,
``SetAbsoluteSpeed``, ``SetRelativeSpeed``) are in force from the command on."""

from __future__ import annotations

import math
from dataclasses import dataclass

#: NIST's kittingViewer defaults (``ROBOTDEFAULTMAXSPEED`` 1000 mm/s, ``ROBOTDEFAULTMAXACCEL``
#: 10000 mm/s²), in SI.
DEFAULT_MAX_SPEED = 1.0
DEFAULT_MAX_ACCELERATION = 10.0
#: Speed and acceleration before a program sets them, in % of the robot's maxima (the
#: kittingViewer's ``robotRelSpeed`` and ``robotRelAccel`` at the start).
INITIAL_PERCENT = 10.0
#: The paths a MoveTo may take (:attr:`Robot.move_to`).
MOVE_TO_PATHS = ("straight", "transfer")
#: Time the kittingViewer gives an OpenGripper, CloseGripper, OpenToolChanger or CloseToolChanger.
DEFAULT_EFFECTOR_SECONDS = 0.2


@dataclass(frozen=True)
class Robot:
    """The robot a program's metrics are computed for, in SI: ``max_speed`` (m/s) and
    ``max_acceleration`` (m/s²) of the controlled point, ``effector_seconds`` the time of a
    gripper or tool changer command, ``start`` where the controlled point is at first (m), with
    its Z axis down and X axis along the workstation's X; ``length_unit`` and ``angle_unit``
    the units InitCanon sets (None: those of the program's form, docs/crcl.md: the paper's
    millimetre and degree for text and 2014 XML, CRCL 1.x's metre and radian; kitkb's own cell
    and executor speak metres and radians)."""

    max_speed: float = DEFAULT_MAX_SPEED
    max_acceleration: float = DEFAULT_MAX_ACCELERATION
    effector_seconds: float = DEFAULT_EFFECTOR_SECONDS
    start: tuple[float, float, float] = (0.0, 0.0, 0.0)
    length_unit: str | None = None
    angle_unit: str | None = None
    #: the speed (m/s) and acceleration (m/s²) in force before a program sets one; None:
    #: :data:`INITIAL_PERCENT` of the maximum (the kittingViewer's ``robotRelSpeed`` at the start)
    start_speed: float | None = None
    start_acceleration: float | None = None
    #: False: a move runs at the speed in force from its start to its end (no acceleration
    #: phases, as kitkb's kinematic cell times it: path length / speed)
    accelerates: bool = True
    #: a MoveTo's path ("any convenient trajectory", CRCL): ``straight`` from where the tip
    #: stands to the target (the kittingViewer's), or ``transfer``: straight up to the higher
    #: end's height, across, straight down (a pick-and-place robot's, kitkb's cells')
    move_to: str = "straight"

    def __post_init__(self) -> None:
        if self.length_unit not in (None, "meter", "millimeter", "inch"):
            raise ValueError(f"length_unit must be meter, millimeter or inch, not {self.length_unit!r}")
        if self.angle_unit not in (None, "degree", "radian"):
            raise ValueError(f"angle_unit must be degree or radian, not {self.angle_unit!r}")
        for name in ("max_speed", "max_acceleration"):
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
                raise ValueError(f"{name} must be a positive number, not {value!r}")
        for name in ("start_speed", "start_acceleration"):
            value = getattr(self, name)
            if value is not None and not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
                raise ValueError(f"{name} must be a positive number or None, not {value!r}")
        if self.move_to not in MOVE_TO_PATHS:
            raise ValueError(f"move_to must be one of {', '.join(MOVE_TO_PATHS)}, not {self.move_to!r}")
        if not (math.isfinite(self.effector_seconds) and self.effector_seconds >= 0):
            raise ValueError(f"effector_seconds must be a number >= 0, not {self.effector_seconds!r}")
        if len(self.start) != 3 or not all(math.isfinite(v) for v in self.start):
            raise ValueError(f"start must be three finite numbers, not {self.start!r}")


def move_time(distance: float, speed: float, acceleration: float) -> float:
    """Seconds to travel ``distance`` from rest to rest at most at ``speed`` with
    ``acceleration`` (and the same deceleration), both positive: a trapezoid when the
    distance lets the robot reach ``speed`` (``distance >= speed² / acceleration``), else a
    triangle."""
    if distance <= 0.0:
        return 0.0
    if distance * acceleration >= speed * speed:
        return distance / speed + speed / acceleration
    return 2.0 * math.sqrt(distance / acceleration)



def cell_robot(start: tuple[float, float, float] | None = None) -> Robot:
    """The robot of kitkb's cells (:mod:`kb.sim.robot`: the simulated cell in process and behind
    ``kitkb sim serve``), as a run's metrics and its replay time it: 1 m/s from the start until a
    program commands another speed, each move at the speed in force throughout (path length /
    speed), a MoveTo up, across at the higher end's height and down, gripper and tool changer
    commands at once, CRCL 1.x's metre and radian after InitCanon; ``start``: where the tool tip
    stands (m)."""
    return Robot(max_speed=DEFAULT_MAX_SPEED, start_speed=DEFAULT_MAX_SPEED, accelerates=False,
                 effector_seconds=0.0, move_to="transfer", start=start or (0.0, 0.0, 0.0),
                 length_unit="meter", angle_unit="radian")


def timed_move(distance: float, speed: float, acceleration: float, accelerates: bool = True) -> float:
    """Seconds of a move of ``distance`` at ``speed``: :func:`move_time` (trapezoid or
    triangle), or ``distance / speed`` for a robot that does not accelerate."""
    if accelerates:
        return move_time(distance, speed, acceleration)
    return max(0.0, distance) / speed


def transfer_points(start: tuple[float, ...], end: tuple[float, ...]) -> list[tuple[float, float, float]]:
    """The corners of a MoveTo's transfer path from ``start`` to ``end`` (points, m): up to the
    higher end's height, across, down; legs of no length left out, ``end`` always last."""
    top = max(start[2], end[2])
    corners = [(start[0], start[1], top), (end[0], end[1], top), (end[0], end[1], end[2])]
    out: list[tuple[float, float, float]] = []
    here = tuple(start[:3])
    for c in corners:
        if c != here:
            out.append(c)
            here = c
    return out or [tuple(end[:3])]  # type: ignore[list-item]
