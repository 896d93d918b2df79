"""The simulated robot behind the time metrics: its limits, and the time of a move with a
trapezoidal velocity profile (accelerate at the acceleration in force, cruise at the speed in
force, decelerate to a stop at the end point)."""

from __future__ import annotations

import math
from dataclasses import dataclass

#: NIST's kittingViewer defaults (``ROBOTDEFAULTMAXSPEED`` 1000 mm/s, ``ROBOTDEFAULTMAXACCEL``
#: 10000 mm/s²), in SI.
DEFAULT_MAX_SPEED = 1.0
DEFAULT_MAX_ACCELERATION = 10.0
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

    def __post_init__(self) -> None:
        if self.length_unit not in (None, "meter", "millimeter", "inch"):
            raise ValueError(f"length_unit must be meter, millimeter or inch, not {self.length_unit!r}")
        if self.angle_unit not in (None, "degree", "radian"):
            raise ValueError(f"angle_unit must be degree or radian, not {self.angle_unit!r}")
        for name in ("max_speed", "max_acceleration"):
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
                raise ValueError(f"{name} must be a positive number, not {value!r}")
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

