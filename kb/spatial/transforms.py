"""Homogeneous 4x4 transforms of the kitting model's poses (numpy).

A ``PoseLocation`` gives a point and two axes (x and z) of an object's frame in the frame of
its reference object. As a matrix ``L`` (columns: x axis, y axis, z axis, point), the global
pose of an object is ``G = G_ref @ L``. Equation (1) of "A Simulated Sensor-based Approach"
updates ``L`` from a sensed global pose ``G'`` while keeping the reference object:
``L' = L @ inv(G) @ G'`` (which equals ``inv(G_ref) @ G'``).
"""

from __future__ import annotations

import math
from typing import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

Matrix = NDArray[np.float64]

#: Length below which an axis counts as zero.
_EPS = 1e-12


def identity() -> Matrix:
    """The 4x4 identity."""
    return np.eye(4)


def pose_matrix(point: Sequence[float], x_axis: Sequence[float], z_axis: Sequence[float]) -> Matrix:
    """The 4x4 transform of a point and an (x, z) axis pair; axes are normalized, x made orthogonal to z."""
    # Plain float arithmetic: numpy's overhead dominates on 3-vectors and this runs per object.
    zx, zy, zz = (float(v) for v in z_axis)
    xx, xy, xz = (float(v) for v in x_axis)
    nz = math.sqrt(zx * zx + zy * zy + zz * zz)
    if nz < _EPS or math.sqrt(xx * xx + xy * xy + xz * xz) < _EPS:
        raise ValueError("an axis of the pose has length zero")
    zx, zy, zz = zx / nz, zy / nz, zz / nz
    d = xx * zx + xy * zy + xz * zz
    xx, xy, xz = xx - d * zx, xy - d * zy, xz - d * zz
    nx = math.sqrt(xx * xx + xy * xy + xz * xz)
    if nx < _EPS:
        raise ValueError("the x and z axes of the pose are parallel")
    xx, xy, xz = xx / nx, xy / nx, xz / nx
    yx, yy, yz = zy * xz - zz * xy, zz * xx - zx * xz, zx * xy - zy * xx
    px, py, pz = (float(v) for v in point)
    return np.array([[xx, yx, zx, px], [xy, yy, zy, py], [xz, yz, zz, pz], [0.0, 0.0, 0.0, 1.0]])


def axes_of(m: ArrayLike) -> tuple[tuple[float, float, float], tuple[float, float, float], tuple[float, float, float]]:
    """(point, x axis, z axis) of a 4x4 transform, as plain floats."""
    a = check_matrix(m)
    return (tuple(float(v) for v in a[:3, 3]), tuple(float(v) for v in a[:3, 0]),  # type: ignore[return-value]
            tuple(float(v) for v in a[:3, 2]))


def check_matrix(m: ArrayLike) -> Matrix:
    """``m`` as a float 4x4 rigid transform; ValueError if it is not one."""
    a = np.asarray(m, dtype=float)
    if a.shape != (4, 4) or not np.all(np.isfinite(a)):
        raise ValueError("a pose must be a finite 4x4 matrix")
    if not np.allclose(a[3], [0, 0, 0, 1]) or not np.allclose(a[:3, :3].T @ a[:3, :3], np.eye(3), atol=1e-6):
        raise ValueError("a pose must be a rigid transform (orthonormal rotation, last row 0 0 0 1)")
    return a


def invert(m: ArrayLike) -> Matrix:
    """Inverse of a rigid transform (transpose of the rotation)."""
    a = np.asarray(m, dtype=float)
    r, t = a[:3, :3], a[:3, 3]
    out = np.eye(4)
    out[:3, :3] = r.T
    out[:3, 3] = -r.T @ t
    return out


def updated_relative(relative: ArrayLike, old_global: ArrayLike, new_global: ArrayLike) -> Matrix:
    """Equation (1): ``L' = L G^-1 G'``, the new relative pose keeping the same reference object."""
    return np.asarray(relative, dtype=float) @ invert(old_global) @ np.asarray(new_global, dtype=float)


def from_xyz_rpy(x: float, y: float, z: float, roll: float, pitch: float, yaw: float) -> Matrix:
    """A transform from a position and roll, pitch, yaw in radians (rotation Rz(yaw) Ry(pitch) Rx(roll))."""
    cr, sr, cp, sp, cy, sy = np.cos(roll), np.sin(roll), np.cos(pitch), np.sin(pitch), np.cos(yaw), np.sin(yaw)
    m = np.eye(4)
    m[:3, :3] = [[cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
                 [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
                 [-sp, cp * sr, cp * cr]]
    m[:3, 3] = [x, y, z]
    return m
