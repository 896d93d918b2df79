"""3-D RCC8 and cardinal direction relations between axis-aligned world boxes (seed 004, 4.3).

The SOAP predicates are decided from the relations of two solid objects (subject, object): the
eight RCC8 relations applied per axis to the projections of the two objects' world-frame
axis-aligned boxes on x, y and z (24 relations), plus six cardinal directions. These are the
classes of ``ontologies/soap.ttl`` section 4 (``soap:X-DC`` ... ``soap:Z-Minus``).

Relations and masks
    :data:`RELATIONS` names the 30 relations; bit ``i`` of a mask is ``RELATIONS[i]``
    (``X-DC X-EC X-PO X-EQ X-TPP X-NTPP X-TPPi X-NTPPi``, the same eight for ``Y-`` and ``Z-``,
    then ``X-Plus X-Minus Y-Plus Y-Minus Z-Plus Z-Minus``); :data:`BIT` maps a name to its bit
    value. :func:`relate` gives the uint32 masks of N subjects x M objects, :func:`relate_pair`
    the set of names of one pair, :func:`world_boxes` the world boxes of oriented local boxes.

Decision per axis, subject interval ``[a0, a1]``, object interval ``[b0, b1]``, tolerance
``t >= 0``; the first rule that applies gives the axis's one RCC8 relation (so the eight are
jointly exhaustive and pairwise disjoint):

    ====  ======================================================  ===================
    rule  condition                                               relation
    ====  ======================================================  ===================
    1     ``a1 < b0 - t`` or ``b1 < a0 - t``                      DC
    2     ``|a0 - b0| <= t`` and ``|a1 - b1| <= t``               EQ
    3     ``|a1 - b0| <= t`` or ``|b1 - a0| <= t``                EC
    4     ``a0 >= b0 - t`` and ``a1 <= b1 + t`` (subject inside)  TPP if ``|a0 - b0| <= t``
                                                                  or ``|a1 - b1| <= t``,
                                                                  else NTPP
    5     ``b0 >= a0 - t`` and ``b1 <= a1 + t`` (object inside)   TPPi if ``|a0 - b0| <= t``
                                                                  or ``|a1 - b1| <= t``,
                                                                  else NTPPi
    6     otherwise                                               PO
    ====  ======================================================  ===================

Cardinal directions, on each axis independently of the RCC8 relation: ``A-Plus`` iff
``a0 >= b0 - t`` (the subject does not reach below the object along A), ``A-Minus`` iff
``a1 <= b1 + t`` (it does not reach beyond it). With DC or EC they mean "entirely on the +
(-) side" for intervals longer than ``2 t``.

Floating point: every test compares one subject bound with one object bound shifted by the
tolerance, ``b - t`` or ``b + t`` (``|x - b| <= t`` is read as ``b - t <= x <= b + t``,
``b1 < a0 - t`` as ``a0 > b1 + t``; equal in exact arithmetic). :func:`relate` and
:func:`relate_pair` both evaluate exactly these comparisons in float64, so they agree bit for
bit, ties included.

Tolerance
    ``tol`` (default :data:`DEFAULT_TOLERANCE` = 0.001) is in the unit of length of the boxes
    (the state files are in metres: 1 mm). Two bounds closer than ``tol`` count as equal: a gap
    of 0.5 mm between a part and a table is EC, a gap of 2 mm is DC. Intervals shorter than
    ``2 tol`` are at the resolution of the tolerance, and their relations follow the table
    literally (a point on the end of an interval is EC, rule 3 before rule 4).

Kernel
    For each axis the decision depends only on the ternary comparisons (below / within
    tolerance / above) of the four bound pairs (a0, b0), (a1, b1), (a1, b0), (a0, b1): an index
    0..80 into a 81-entry uint32 table holding that axis's RCC8 bit and its two cardinal bits;
    the three axes' entries are ORed. :func:`relate` runs it over blocks of subjects that fit
    in the cache, in uint8, into preallocated buffers.
"""

from __future__ import annotations

from typing import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["BIT", "DEFAULT_TOLERANCE", "RELATIONS", "relate", "relate_pair", "world_boxes"]

#: The eight RCC8 relations of one axis, in mask order.
RCC8: tuple[str, ...] = ("DC", "EC", "PO", "EQ", "TPP", "NTPP", "TPPi", "NTPPi")
AXES: tuple[str, ...] = ("X", "Y", "Z")

#: The 30 relation names; bit ``i`` of a mask is ``RELATIONS[i]``.
RELATIONS: tuple[str, ...] = (
    tuple(f"{axis}-{rel}" for axis in AXES for rel in RCC8)
    + tuple(f"{axis}-{side}" for axis in AXES for side in ("Plus", "Minus"))
)

#: Relation name -> its bit value (``1 << i``).
BIT: dict[str, int] = {name: 1 << i for i, name in enumerate(RELATIONS)}

#: Tolerance in the boxes' unit of length (metres in the state files: 1 mm).
DEFAULT_TOLERANCE: float = 0.001

#: Subjects per block of :func:`relate` (about ``_BLOCK_PAIRS`` pairs per block).
_BLOCK_PAIRS = 1 << 15

FloatArray = NDArray[np.float64]


# ---------------------------------------------------------------------------------------------
# Reference: one pair in plain Python
# ---------------------------------------------------------------------------------------------

def _axis_rcc8(a0: float, a1: float, b0: float, b1: float, t: float) -> str:
    """The RCC8 relation of subject interval [a0, a1] to object interval [b0, b1] (rules 1-6)."""
    def near(x: float, b: float) -> bool:  # |x - b| <= t
        return b - t <= x <= b + t

    if a1 < b0 - t or a0 > b1 + t:
        return "DC"
    if near(a0, b0) and near(a1, b1):
        return "EQ"
    if near(a1, b0) or near(a0, b1):
        return "EC"
    tangential = near(a0, b0) or near(a1, b1)
    if a0 >= b0 - t and a1 <= b1 + t:
        return "TPP" if tangential else "NTPP"
    if a0 <= b0 + t and a1 >= b1 - t:  # b0 >= a0 - t and b1 <= a1 + t
        return "TPPi" if tangential else "NTPPi"
    return "PO"


def relate_pair(a_lo: Sequence[float], a_hi: Sequence[float], b_lo: Sequence[float],
                b_hi: Sequence[float], tol: float = DEFAULT_TOLERANCE) -> frozenset[str]:
    """The relations (names of :data:`RELATIONS`) of subject box a to object box b.

    Plain Python, straight from the decision table of the module docstring; the reference for
    :func:`relate`. Each argument is a 3-sequence (x, y, z) of one box corner.
    """
    t = _check_tolerance(tol)
    names = []
    for k, axis in enumerate(AXES):
        a0, a1, b0, b1 = float(a_lo[k]), float(a_hi[k]), float(b_lo[k]), float(b_hi[k])
        names.append(f"{axis}-{_axis_rcc8(a0, a1, b0, b1, t)}")
        if a0 >= b0 - t:
            names.append(f"{axis}-Plus")
        if a1 <= b1 + t:
            names.append(f"{axis}-Minus")
    return frozenset(names)


def _check_tolerance(tol: float) -> float:
    """``tol`` as a float; finite and >= 0, else ValueError."""
    t = float(tol)
    if not (t >= 0.0 and np.isfinite(t)):
        raise ValueError(f"tolerance must be a finite number >= 0, not {tol!r}")
    return t


# ---------------------------------------------------------------------------------------------
# Lookup tables: ternary comparisons -> bits
# ---------------------------------------------------------------------------------------------

def _axis_table(axis: int) -> NDArray[np.uint32]:
    """81 entries: index ``c00 + 3 c11 + 9 c10 + 27 c01`` -> the axis's RCC8 and cardinal bits.

    ``cXY`` is the ternary comparison of subject bound X with object bound Y (0 below,
    1 within tolerance, 2 above), 0 = lower bound, 1 = upper bound. Each entry is decided by
    :func:`_axis_rcc8` on representative intervals (bounds 0, 1, 2 against shifted ones), so
    the table is the reference decision itself; index combinations no pair of intervals can
    produce get the same treatment and are never looked up.
    """
    table = np.zeros(81, dtype=np.uint32)
    name = AXES[axis]
    for idx in range(81):
        c00, c11, c10, c01 = idx % 3, idx // 3 % 3, idx // 9 % 3, idx // 27
        rel = _rcc8_of_codes(c00, c11, c10, c01)
        bits = BIT[f"{name}-{rel}"]
        if c00 >= 1:
            bits |= BIT[f"{name}-Plus"]
        if c11 <= 1:
            bits |= BIT[f"{name}-Minus"]
        table[idx] = bits
    return table


def _rcc8_of_codes(c00: int, c11: int, c10: int, c01: int) -> str:
    """Rules 1-6 on ternary codes (0 below, 1 within tolerance, 2 above)."""
    if c10 == 0 or c01 == 2:
        return "DC"
    if c00 == 1 and c11 == 1:
        return "EQ"
    if c10 == 1 or c01 == 1:
        return "EC"
    tangential = c00 == 1 or c11 == 1
    if c00 >= 1 and c11 <= 1:
        return "TPP" if tangential else "NTPP"
    if c00 <= 1 and c11 >= 1:
        return "TPPi" if tangential else "NTPPi"
    return "PO"


_TABLES: tuple[NDArray[np.uint32], ...] = tuple(_axis_table(k) for k in range(3))


# ---------------------------------------------------------------------------------------------
# Vectorised kernel
# ---------------------------------------------------------------------------------------------

def _boxes(lo: ArrayLike, hi: ArrayLike, what: str) -> tuple[FloatArray, FloatArray]:
    """``lo``, ``hi`` as float64 (n, 3) arrays; finite, ``lo <= hi``, else ValueError."""
    lo_a = np.ascontiguousarray(lo, dtype=np.float64)
    hi_a = np.ascontiguousarray(hi, dtype=np.float64)
    if lo_a.ndim != 2 or lo_a.shape[1] != 3 or lo_a.shape != hi_a.shape:
        raise ValueError(f"{what} boxes: lo and hi must both have shape (n, 3), not {lo_a.shape} and {hi_a.shape}")
    if not (np.isfinite(lo_a).all() and np.isfinite(hi_a).all()):
        raise ValueError(f"{what} boxes: bounds must be finite")
    if (lo_a > hi_a).any():
        raise ValueError(f"{what} boxes: lo must be <= hi on every axis")
    return lo_a, hi_a


def relate(a_lo: ArrayLike, a_hi: ArrayLike, b_lo: ArrayLike, b_hi: ArrayLike,
           tol: float = DEFAULT_TOLERANCE) -> NDArray[np.uint32]:
    """uint32 (N, M): the mask of the 30 relations of subject box i to object box j.

    ``a_lo``, ``a_hi`` (N, 3) and ``b_lo``, ``b_hi`` (M, 3) are the corners of world-frame
    axis-aligned boxes (finite, lo <= hi). Bit ``k`` of a mask is ``RELATIONS[k]``; the
    decision is the module docstring's table, exactly that of :func:`relate_pair`.
    """
    t = _check_tolerance(tol)
    a0s, a1s = _boxes(a_lo, a_hi, "subject")
    b0s, b1s = _boxes(b_lo, b_hi, "object")
    n, m = a0s.shape[0], b0s.shape[0]
    out = np.empty((n, m), dtype=np.uint32)
    if n == 0 or m == 0:
        return out
    block = max(1, min(n, _BLOCK_PAIRS // m))
    kernel = _Kernel(block, m)
    for axis in range(3):
        kernel.set_objects(axis, b0s[:, axis], b1s[:, axis], t)
    for start in range(0, n, block):
        stop = min(n, start + block)
        kernel.run(a0s[start:stop], a1s[start:stop], out[start:stop])
    return out


class _Kernel:
    """Preallocated buffers of one block of subjects x all objects."""

    def __init__(self, block: int, m: int) -> None:
        self.m = m
        self.shifted: list[tuple[FloatArray, ...]] = [(), (), ()]  # per axis: b0-t, b0+t, b1-t, b1+t
        self.cmp = np.empty((block, m), dtype=np.bool_)
        self.code = np.empty((block, m), dtype=np.uint8)
        self.bits = np.empty((block, m), dtype=np.uint32)

    def set_objects(self, axis: int, b0: FloatArray, b1: FloatArray, t: float) -> None:
        """Shift the objects' bounds of one axis by the tolerance, once per call."""
        self.shifted[axis] = (b0 - t, b0 + t, b1 - t, b1 + t)

    def _ternary(self, x: FloatArray, lo: FloatArray, hi: FloatArray, weight: int, code: NDArray[np.uint8]) -> None:
        """code += weight * ((x >= lo) + (x > hi)), x a column of subject bounds."""
        cmp = self.cmp[: code.shape[0]]
        for op, thr in ((np.greater_equal, lo), (np.greater, hi)):
            op(x[:, None], thr[None, :], out=cmp)
            view = cmp.view(np.uint8)
            if weight == 1:
                code += view
            else:
                code += view * np.uint8(weight)

    def run(self, a0s: FloatArray, a1s: FloatArray, out: NDArray[np.uint32]) -> None:
        """Masks of one block of subjects into ``out`` (rows x m)."""
        rows = a0s.shape[0]
        code, bits = self.code[:rows], self.bits[:rows]
        for axis in range(3):
            b0lo, b0hi, b1lo, b1hi = self.shifted[axis]
            a0, a1 = a0s[:, axis], a1s[:, axis]
            code.fill(0)
            self._ternary(a0, b0lo, b0hi, 1, code)
            self._ternary(a1, b1lo, b1hi, 3, code)
            self._ternary(a1, b0lo, b0hi, 9, code)
            self._ternary(a0, b1lo, b1hi, 27, code)
            if axis == 0:
                np.take(_TABLES[axis], code, out=out)
            else:
                np.take(_TABLES[axis], code, out=bits)
                out |= bits


# ---------------------------------------------------------------------------------------------
# World boxes of oriented local boxes
# ---------------------------------------------------------------------------------------------

def world_boxes(poses: ArrayLike, lo: ArrayLike, hi: ArrayLike) -> tuple[FloatArray, FloatArray]:
    """Axis-aligned world boxes (lo_w, hi_w), each (K, 3), of oriented local boxes.

    ``poses`` (K, 4, 4) are the objects' global transforms, ``lo``, ``hi`` (K, 3) the corners
    of each object's box in its own frame. The world box is the smallest axis-aligned box
    holding the 8 transformed corners: center ``R @ c + t``, half extent ``|R| @ h``, computed
    here as ``t + R+ @ lo + R- @ hi`` and ``t + R+ @ hi + R- @ lo`` (R+ and R- the positive and
    negative entries of R), which is the same box and exact for axis-aligned poses.
    """
    g = np.asarray(poses, dtype=np.float64)
    lo_l = np.asarray(lo, dtype=np.float64)
    hi_l = np.asarray(hi, dtype=np.float64)
    if g.ndim != 3 or g.shape[1:] != (4, 4) or lo_l.shape != (g.shape[0], 3) or hi_l.shape != lo_l.shape:
        raise ValueError(f"world_boxes: poses (K, 4, 4), lo and hi (K, 3) expected, not {g.shape}, {lo_l.shape}, {hi_l.shape}")
    rot, trans = g[:, :3, :3], g[:, :3, 3]
    pos, neg = np.maximum(rot, 0.0), np.minimum(rot, 0.0)
    lo_w = trans + np.einsum("kij,kj->ki", pos, lo_l) + np.einsum("kij,kj->ki", neg, hi_l)
    hi_w = trans + np.einsum("kij,kj->ki", pos, hi_l) + np.einsum("kij,kj->ki", neg, lo_l)
    return lo_w, hi_w
