"""The CRCL ``Pose``: a point and the Z and X axes of a coordinate system.

As in CRCL.xsd's ``PoseType`` (``Point``, ``ZAxis``, ``XAxis``) and the text form of the first
paper (``{{x, y, z}, {i, j, k}, {i, j, k}}``: point, Z axis, X axis), in the units and the
coordinate frame currently set on the robot.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Iterable

import numpy as np

Vector = tuple[float, float, float]


def _triple(name: str, values: Iterable[Any]) -> Vector:
    """``values`` as three finite floats; ValueError naming ``name`` otherwise."""
    try:
        xyz = tuple(float(v) for v in values)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be three numbers, not {values!r}") from None
    except OverflowError:  # an integer of hundreds of digits
        raise ValueError(f"{name} must be three finite numbers (one is too large for a float)") from None
    if len(xyz) != 3 or not all(math.isfinite(v) for v in xyz):
        raise ValueError(f"{name} must be three finite numbers, not {xyz!r}")
    return xyz  # type: ignore[return-value]


@dataclass(frozen=True)
class Pose:
    """Where the controlled point is and how it is turned: ``point`` (x, y, z), ``x_axis`` and
    ``z_axis`` (i, j, k components of the controlled frame's X and Z axes).

    Any sequences of three numbers are accepted and kept as tuples of finite floats.
    """

    point: Vector
    x_axis: Vector
    z_axis: Vector

    def __post_init__(self) -> None:
        for name in ("point", "x_axis", "z_axis"):
            object.__setattr__(self, name, _triple(name, getattr(self, name)))

    @classmethod
    def from_matrix(cls, m: Any) -> Pose:
        """The pose of a 4x4 homogeneous transform: its translation, first and third columns."""
        a = np.asarray(m, dtype=float)
        if a.shape != (4, 4):
            raise ValueError(f"a pose matrix is 4x4, not {a.shape}")
        return cls(point=a[:3, 3], x_axis=a[:3, 0], z_axis=a[:3, 2])

    def matrix(self) -> np.ndarray:
        """The 4x4 homogeneous transform of this pose.

        The Z axis is normalised, the X axis made perpendicular to it (Gram-Schmidt) and
        normalised, and Y = Z x X, so the rotation part is a proper rotation. A zero axis, or
        an X axis parallel to Z, is a ValueError.
        """
        z = np.array(self.z_axis)
        x = np.array(self.x_axis)
        length = np.linalg.norm(z)
        if not length:
            raise ValueError("the Z axis of a pose cannot be zero")
        z = z / length
        x = x - np.dot(x, z) * z
        length = np.linalg.norm(x)
        if length < 1e-12:
            raise ValueError("the X axis of a pose must not be zero or parallel to its Z axis")
        x = x / length
        (z0, z1, z2), (x0, x1, x2) = z.tolist(), x.tolist()
        m = np.eye(4)
        # Y = Z x X as np.cross computes it (each component one product less another), without
        # its overhead on 3-vectors
        y = (z1 * x2 - z2 * x1, z2 * x0 - z0 * x2, z0 * x1 - z1 * x0)
        m[:3, 0], m[:3, 1], m[:3, 2], m[:3, 3] = x, y, z, self.point
        return m
