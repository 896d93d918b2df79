"""3-D RCC8 and cardinal direction relations between axis-aligned boxes (seed 004, 4.3), and
between oriented boxes, each pair in its object's frame.

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
``t >= 0``. Each of the four bound pairs (a0, b0), (a1, b1), (a1, b0), (a0, b1) is compared
with a tolerance of its own, ``t`` or 0 (see "Thin boxes" below: 0 where the two bounds are not
each other's nearest, so that a box thinner than ``2 t`` is never taken for a point); ``|x - b|
<= t`` below means "within that pair's tolerance". The first rule that applies gives the
axis's one RCC8 relation (so the eight are jointly exhaustive and pairwise disjoint):

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

Thin boxes
    A comparison of bounds (a_i, b_j) has the tolerance ``t`` only when they are each other's
    nearest: ``|a_i - b_j|`` is no larger than the distance from b_j to the subject's other
    bound, nor than the distance from a_i to the object's other bound; else its tolerance is 0
    (the comparison is exact). So a bound stands in for one face of a box, never for both: a
    washer 0.343 mm thick lying on its tray's floor has its bottom at the floor and its top
    0.343 mm above it: the floor's nearest washer bound is the bottom, so the top is compared
    with the floor exactly and the washer is TPP of the tray on z, not EC ("under the floor")
    as it was with one tolerance for all four pairs.
    A box thinner than ``2 t`` is decided by the side of the other box's face its middle lies
    on, and keeps the whole tolerance for gaps (a washer 0.5 mm above a table still rests on
    it). Nothing changes where both boxes are wider than ``2 t`` on the axis (two bounds of a
    box cannot then both be within ``t`` of one bound), nor for a point (its two bounds are
    equally near: a point at the end of an interval is EC to it). docs/soap.md, "Thin and
    narrow parts", has the reasoning. :func:`depth_tolerance` is the same rule for a depth
    measured along an axis — how far one box enters another, or how far two footprints
    overlap: the simulated cell's support test, and ``kitkb validate``'s plausibility checks
    (:mod:`kb.spatial.plausibility`: each separating-axis depth, each face of an open
    container, the ground), which like the predicates keep the whole tolerance for a gap.

Floating point: every test compares one subject bound with one object bound shifted by the
pair's tolerance, ``b - t`` or ``b + t`` (``|x - b| <= t`` is read as ``b - t <= x <= b + t``,
``b1 < a0 - t`` as ``a0 > b1 + t``; equal in exact arithmetic); which pairs keep ``t`` is
decided on the float64 distances ``|a_i - b_j|``. :func:`relate` and :func:`relate_pair` both
evaluate exactly these comparisons in float64, so they agree bit for bit, ties included.

Oriented boxes
    :func:`relate_oriented` relates boxes given by poses: each pair in the frame of its object,
    the world turned about z by the object's heading (:func:`headings`, :func:`heading_groups`,
    :func:`frame_boxes`); the pairs whose world boxes meet and whose object is turned are
    decided again there by :func:`reframe` (one row per pair, :func:`relate_rows`). The design
    is in docs/soap.md, "Orientation"; the frames' geometry (world boxes, headings, frame
    boxes) is in :mod:`kb.spatial.frames`, its names importable from here too.

Tolerance
    ``tol`` (default :data:`DEFAULT_TOLERANCE` = 0.001) is one setting, in the unit of length
    of the boxes: the state files are in metres, so 1 mm (boxes in millimetres would need
    ``tol=1.0``). Two bounds no farther apart than ``tol`` count as equal: a gap of 0.5 mm
    between a part and a table is EC, a gap of 2 mm is DC. Intervals shorter than ``2 tol``
    keep their extent ("Thin boxes" above); a point at the end of an interval is EC to it
    (rule 3 before rule 4).

Kernel
    Per axis the decision depends only on the ternary comparisons (below / within tolerance /
    above) of the bound pairs (a0, b0), (a1, b1), (a1, b0), (a0, b1): an index 0..80 into an
    81-entry uint32 table of that axis's RCC8 bit and two cardinal bits; the axes' entries are
    ORed (x and y through one 6561-entry table). For many subjects :func:`relate` gets the
    index without float work per pair: a subject bound's comparisons with all the thresholds
    of a chunk of objects follow from its rank among those thresholds, so two small tables
    indexed by rank give each row of indexes by a row gather and an add, in uint8/uint16,
    block by block in cache (see the comment "Vectorised kernel" below; figures in
    ``docs/benchmarks.md``). Few subjects use broadcast comparisons instead. The kernels give
    every pair the tolerance ``t``; then the pairs with a box thinner than ``2 t`` (and
    rounding) on an axis where they are not DC are decided again with the bound pairs' own
    tolerances (:func:`_masks_exact`): only those can differ (on an axis where two intervals
    are apart, no bound pair is within the tolerance).
"""

from __future__ import annotations

import threading
from typing import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from kb.spatial.frames import HEADING_MERGE, frame_boxes, heading_groups, headings, world_boxes

__all__ = ["BIT", "DEFAULT_TOLERANCE", "HEADING_MERGE", "RELATIONS", "depth_tolerance", "frame_boxes", "heading_groups",
           "headings", "reframe", "relate", "relate_oriented", "relate_pair", "relate_rows", "world_boxes"]

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

#: The three DC bits: a pair with one of them is apart in every frame.
_DC_ANY = np.uint32(BIT["X-DC"] | BIT["Y-DC"] | BIT["Z-DC"])

FloatArray = NDArray[np.float64]


# ---------------------------------------------------------------------------------------------
# Reference: one pair in plain Python
# ---------------------------------------------------------------------------------------------

def _pair_tolerances(a0: float, a1: float, b0: float, b1: float, t: float) -> tuple[float, float, float, float]:
    """The tolerances of the bound pairs (a0, b0), (a1, b1), (a1, b0), (a0, b1): ``t`` where
    the two bounds are each other's nearest, else 0 (module docstring, "Thin boxes")."""
    d00, d11, d10, d01 = abs(a0 - b0), abs(a1 - b1), abs(a1 - b0), abs(a0 - b1)
    return (t if d00 <= min(d10, d01) else 0.0, t if d11 <= min(d01, d10) else 0.0,
            t if d10 <= min(d00, d11) else 0.0, t if d01 <= min(d00, d11) else 0.0)


def _code(x: float, b: float, t: float) -> int:
    """0 when ``x`` is below ``b`` beyond ``t``, 1 within ``t`` of it, 2 above beyond ``t``."""
    return 0 if x < b - t else (2 if x > b + t else 1)


def _axis_codes(a0: float, a1: float, b0: float, b1: float, t: float) -> tuple[int, int, int, int]:
    """The ternary codes (c00, c11, c10, c01) of subject interval [a0, a1] against object
    interval [b0, b1], each bound pair with its own tolerance."""
    t00, t11, t10, t01 = _pair_tolerances(a0, a1, b0, b1, t)
    return _code(a0, b0, t00), _code(a1, b1, t11), _code(a1, b0, t10), _code(a0, b1, t01)


def relate_pair(a_lo: Sequence[float], a_hi: Sequence[float], b_lo: Sequence[float],
                b_hi: Sequence[float], tol: float = DEFAULT_TOLERANCE) -> frozenset[str]:
    """The relations (names of :data:`RELATIONS`) of subject box a to object box b.

    Plain Python, straight from the decision table of the module docstring (rules 1-6 on each
    axis's codes, :func:`_rcc8_of_codes`); the reference for :func:`relate`. Each argument is
    a 3-sequence (x, y, z) of one box corner.
    """
    t = _check_tolerance(tol)
    names = []
    for k, axis in enumerate(AXES):
        c00, c11, c10, c01 = _axis_codes(float(a_lo[k]), float(a_hi[k]), float(b_lo[k]), float(b_hi[k]), t)
        names.append(f"{axis}-{_rcc8_of_codes(c00, c11, c10, c01)}")
        if c00 >= 1:  # a0 >= b0 - t
            names.append(f"{axis}-Plus")
        if c11 <= 1:  # a1 <= b1 + t
            names.append(f"{axis}-Minus")
    return frozenset(names)


def depth_tolerance(tol: float, *extents: ArrayLike) -> NDArray[np.float64]:
    """The tolerance a depth measured along an axis (how far one box overlaps or enters
    another, a gap) is compared with, for boxes of the given ``extents`` along that axis (numbers
    or arrays that broadcast together): ``tol``, or half the smallest positive extent where
    that is less.

    The RCC8 decision's rule for thin boxes (module docstring, "Thin boxes") for checks that
    measure a depth rather than compare bounds: a box thinner than ``2 tol`` counts as
    entering another (or as resting on it, for an overlap of footprints) once its middle has,
    not only beyond ``tol``, which it can never reach. A zero extent (a point, a plate of no
    thickness) does not lower it. With every extent at least ``2 tol``, it is ``tol``.
    """
    t = _check_tolerance(tol)
    arrays = [np.asarray(e, dtype=np.float64) for e in extents]
    out = np.full(np.broadcast_shapes(*(a.shape for a in arrays)), t)
    for a in arrays:
        np.minimum(out, np.where(a > 0.0, a * 0.5, t), out=out)
    return out


def _check_tolerance(tol: float) -> float:
    """``tol`` as a float; finite and >= 0, else ValueError."""
    t = float(tol)
    if not (t >= 0.0 and np.isfinite(t)):
        raise ValueError(f"tolerance must be a finite number >= 0, not {tol!r}")
    return t


# ---------------------------------------------------------------------------------------------
# Lookup tables: ternary comparisons -> bits
# ---------------------------------------------------------------------------------------------

def _rcc8_of_codes(c00: int, c11: int, c10: int, c01: int) -> str:
    """Rules 1-6 on ternary codes ``cXY`` of subject bound X against object bound Y.

    0 = lower bound, 1 = upper bound; a code is 0 below (``a < b - t``), 1 within tolerance,
    2 above (``a > b + t``), ``t`` the bound pair's own tolerance (:func:`_pair_tolerances`).
    """
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


def _axis_table(axis: int) -> NDArray[np.uint32]:
    """81 entries: index ``c00 + 3 c11 + 9 c10 + 27 c01`` -> the axis's RCC8 and cardinal bits.

    Index combinations no two intervals can produce are filled by the same rules and never
    looked up.
    """
    table = np.zeros(81, dtype=np.uint32)
    name = AXES[axis]
    for idx in range(81):
        c00, c11, c10, c01 = idx % 3, idx // 3 % 3, idx // 9 % 3, idx // 27
        bits = BIT[f"{name}-{_rcc8_of_codes(c00, c11, c10, c01)}"]
        if c00 >= 1:
            bits |= BIT[f"{name}-Plus"]
        if c11 <= 1:
            bits |= BIT[f"{name}-Minus"]
        table[idx] = bits
    return table


#: Per axis: 81-entry table of the axis's bits.
_TABLES: tuple[NDArray[np.uint32], ...] = tuple(_axis_table(k) for k in range(3))
#: The three axes' tables one after the other (axis k's entry i at 81 k + i).
_TABLES_FLAT: NDArray[np.uint32] = np.concatenate(_TABLES)
#: Where each axis's table starts in _TABLES_FLAT, shaped for (3, P) and (3, N, M) indexes.
_AXIS_OFFSET = {2: np.arange(0, 243, 81, dtype=np.uint16)[:, None], 3: np.arange(0, 243, 81, dtype=np.uint16)[:, None, None]}
#: x and y together: index ``ix + 81 iy`` -> the bits of both axes (6561 entries, 26 KB).
_TABLE_XY: NDArray[np.uint32] = (_TABLES[0][None, :] | _TABLES[1][:, None]).reshape(-1)
#: Weight of each axis's code in the table index (x, y share the 6561-entry table).
_AXIS_WEIGHT = (1, 81, 1)
_AXIS_DTYPE = (np.uint16, np.uint16, np.uint8)


# ---------------------------------------------------------------------------------------------
# Vectorised kernel
# ---------------------------------------------------------------------------------------------
#
# Every comparison is ``x >= v``: ``x < b - t`` is ``not x >= b - t`` and ``x > b + t`` is
# ``x >= nextafter(b + t, +inf)`` (exact for finite floats). Per axis an object has four
# thresholds: b0 - t, b0 + t (next float up), b1 - t, b1 + t (next float up); the ternary code
# of a subject bound x against b0 is ``(x >= b0 - t) + (x >= next(b0 + t))``.
#
# Two kernels, the same answer:
# - compare (few subjects): broadcast comparisons, per block of subjects, codes in uint8.
# - rank (many subjects; the fast one): all thresholds U of a chunk of objects, sorted. A
#   subject bound x is ``x >= v`` exactly when rank(x) >= rank of v, where rank(x) = number of
#   thresholds <= x. So per axis two small tables indexed by rank, P0[r, j] (the code part of
#   a0: c00 + 27 c01) and P1[r, j] (of a1: 3 c11 + 9 c10), give the per-pair index by two row
#   gathers and an add, in uint8/uint16: no float work per pair. x and y share one 6561-entry
#   table, z has its own.

#: The rank kernel is used from this many subjects on (below, its tables and ranks cost more
#: than the comparisons they save; measured on a 2-core Xeon).
_RANK_MIN_SUBJECTS = 512
#: Objects per chunk of the rank kernel: about subjects / 16, within these bounds (its tables
#: are (4 C + 1) x C per axis, built once per chunk; 256 keeps them in L2).
_RANK_CHUNK = (64, 256)
#: Up to this many pairs, all three axes in one broadcast (:func:`_masks_all_axes`): few numpy calls.
_FEW_PAIRS = 4096
#: Pairs per chunk of the compare kernel (subjects x objects; its buffers stay in L2).
_COMPARE_PAIRS = 1 << 16
#: Subjects per block of the kernels.
_BLOCK = 512
#: Bucket ranking gives up (falls back to a binary search) above this many thresholds per bucket.
_MAX_LEVELS = 4


def _boxes(lo: ArrayLike, hi: ArrayLike, what: str) -> tuple[FloatArray, FloatArray]:
    """``lo``, ``hi`` (n, 3) as float64 (3, n) arrays (one row per axis); finite, lo <= hi."""
    lo_a = np.asarray(lo, dtype=np.float64)
    hi_a = np.asarray(hi, dtype=np.float64)
    if lo_a.ndim != 2 or lo_a.shape[1] != 3 or lo_a.shape != hi_a.shape:
        raise ValueError(f"{what} boxes: lo and hi must both have shape (n, 3), not {lo_a.shape} and {hi_a.shape}")
    if not (np.isfinite(lo_a).all() and np.isfinite(hi_a).all()):
        raise ValueError(f"{what} boxes: bounds must be finite")
    if (lo_a > hi_a).any():
        raise ValueError(f"{what} boxes: lo must be <= hi on every axis")
    return np.ascontiguousarray(lo_a.T), np.ascontiguousarray(hi_a.T)


def relate(a_lo: ArrayLike, a_hi: ArrayLike, b_lo: ArrayLike, b_hi: ArrayLike,
           tol: float = DEFAULT_TOLERANCE) -> NDArray[np.uint32]:
    """uint32 (N, M): the mask of the 30 relations of subject box i to object box j.

    ``a_lo``, ``a_hi`` (N, 3) and ``b_lo``, ``b_hi`` (M, 3) are the corners of world-frame
    axis-aligned boxes (finite, lo <= hi, else ValueError). Bit ``k`` of a mask is
    ``RELATIONS[k]``; the decision is the module docstring's table, exactly that of
    :func:`relate_pair`.
    """
    t = _check_tolerance(tol)
    a0s, a1s = _boxes(a_lo, a_hi, "subject")
    b0s, b1s = _boxes(b_lo, b_hi, "object")
    n, m = a0s.shape[1], b0s.shape[1]
    if n < _RANK_MIN_SUBJECTS and n * m <= min(_FEW_PAIRS, _COMPARE_PAIRS):  # (the kernels' own tests shrink these)
        out = _masks_all_axes(a0s[:, :, None], a1s[:, :, None], b0s[:, None, :], b1s[:, None, :], t)
    else:
        out = np.empty((n, m), dtype=np.uint32)
        kernel, chunk = _plan(n)
        for start in range(0, m, chunk):
            cols = slice(start, min(m, start + chunk))
            _run_blocks(kernel(_Thresholds(b0s[:, cols], b1s[:, cols], t), a0s, a1s), out, cols)
    _thin_again(out, a0s, a1s, b0s, b1s, t)
    return out


#: Boxes per block of :func:`_thin`, and its scratch arrays (one pair per thread): fresh
#: temporaries the size of the objects' bounds cost more than the test itself (page faults).
_THIN_BLOCK = 8192
_THIN_SMALL = 1024
_SCRATCH = threading.local()
#: :func:`_thin`'s allowance for rounding: ``_THIN_REL |lo| + 2 t (1 + 1e-12) (1 + 2e-12)``.
_THIN_REL = 2e-12 * (1.0 + 2e-12)


def _thin(lo: FloatArray, hi: FloatArray, t: float) -> NDArray[np.bool_]:
    """(3, n) for boxes given as (3, n) bounds: at most ``2 t`` across on that axis, rounding
    allowed for. Only there can a bound pair whose tolerance is 0 change a code: two bounds
    of the box within ``t`` of one bound b of the other box are at most ``2 t`` apart, plus a
    few roundings of numbers no larger than ``|lo| + 4 t`` (b is within ``t`` of the box). The
    allowance, ``2e-12 |lo| + 1e-12 t`` (and a relative 2e-12 more), is a thousand times that.
    relate calls it on every call: for many boxes block by block in scratch arrays."""
    n = lo.shape[1]
    base = (2.0 + 1e-12) * t * (1.0 + 2e-12)
    if n <= _THIN_SMALL:  # small temporaries cost less than the blocks' bookkeeping
        thr = np.abs(lo)
        thr *= _THIN_REL
        thr += base
        return (hi - lo) <= thr
    out = np.empty((3, n), dtype=np.bool_)
    scratch = getattr(_SCRATCH, "thin", None)
    if scratch is None:
        scratch = _SCRATCH.thin = np.empty((2, 3, _THIN_BLOCK))
    for start in range(0, n, _THIN_BLOCK):
        stop = min(n, start + _THIN_BLOCK)
        ext, thr = scratch[0, :, : stop - start], scratch[1, :, : stop - start]
        np.subtract(hi[:, start:stop], lo[:, start:stop], out=ext)
        np.abs(lo[:, start:stop], out=thr)
        thr *= _THIN_REL
        thr += base
        np.less_equal(ext, thr, out=out[:, start:stop])
    return out


#: The DC bit of each axis, shaped to weigh a (3, n) Boolean array.
_DC_AXIS = np.array([BIT["X-DC"], BIT["Y-DC"], BIT["Z-DC"]], dtype=np.uint32)[:, None]


def _thin_again(masks: NDArray[np.uint32], a0s: FloatArray, a1s: FloatArray, b0s: FloatArray, b1s: FloatArray,
                t: float) -> None:
    """Decide again, in place, with each bound pair's own tolerance (:func:`_masks_exact`), the
    pairs of ``masks`` (decided with ``t`` for every bound pair) that have a box thin on some
    axis (:func:`_thin`) and are not DC on that axis: the only ones whose bits can differ (on an
    axis where two intervals are apart no bound pair is within the tolerance)."""
    thin_a, thin_b = _thin(a0s, a1s, t), _thin(b0s, b1s, t)
    rows, cols = np.flatnonzero(thin_a.any(axis=0)), np.flatnonzero(thin_b.any(axis=0))
    if not (rows.size or cols.size):
        return
    i_parts, j_parts = [], []
    if rows.size:  # a row's pairs that are not DC on one of its thin axes
        dc = (thin_a[:, rows] * _DC_AXIS).sum(axis=0, dtype=np.uint32)[:, None]
        i, j = np.nonzero((masks[rows] & dc) != dc)
        i_parts.append(rows[i]), j_parts.append(j)
    if cols.size:
        dc = (thin_b[:, cols] * _DC_AXIS).sum(axis=0, dtype=np.uint32)[None, :]
        i, j = np.nonzero((masks[:, cols] & dc) != dc)
        i_parts.append(i), j_parts.append(cols[j])
    i, j = np.concatenate(i_parts), np.concatenate(j_parts)  # a pair found twice gets the same mask twice
    if i.size:
        masks[i, j] = _masks_exact(a0s[:, i], a1s[:, i], b0s[:, j], b1s[:, j], t)


def _masks_all_axes(a0s: FloatArray, a1s: FloatArray, b0s: FloatArray, b1s: FloatArray, t: float) -> NDArray[np.uint32]:
    """The masks of subject bounds ``a0s``, ``a1s`` against object bounds ``b0s``, ``b1s``, all
    three axes in one broadcast (axis first: (3, ...) arrays broadcasting against each other):
    the comparisons of the kernels, a handful of numpy calls whatever the shape (for few pairs)."""
    lo0, hi0 = b0s - t, np.nextafter(b0s + t, np.inf)
    lo1, hi1 = b1s - t, np.nextafter(b1s + t, np.inf)
    index = None  # c00 + 3 c11 + 9 c10 + 27 c01, Horner form from c01 down, in uint8
    for x, lo, hi in ((a0s, lo1, hi1), (a1s, lo0, hi0), (a1s, lo1, hi1), (a0s, lo0, hi0)):
        code = (x >= lo).view(np.uint8)
        code += (x >= hi).view(np.uint8)
        if index is None:
            index = code
        else:
            index *= np.uint8(3)
            index += code
    bits = _TABLES_FLAT[index + _AXIS_OFFSET[index.ndim]]
    return bits[0] | bits[1] | bits[2]


def _masks_exact(a0s: FloatArray, a1s: FloatArray, b0s: FloatArray, b1s: FloatArray, t: float) -> NDArray[np.uint32]:
    """:func:`_masks_all_axes` with each bound pair's own tolerance (module docstring, "Thin
    boxes": ``t`` where the two bounds are each other's nearest, else 0), as
    :func:`relate_pair` decides: for the few pairs that need it (one row per pair, or a small
    broadcast)."""
    d00, d11 = np.abs(a0s - b0s), np.abs(a1s - b1s)
    d10, d01 = np.abs(a1s - b0s), np.abs(a0s - b1s)
    keep = (d01 <= np.minimum(d00, d11), d10 <= np.minimum(d00, d11),  # (a0, b1), (a1, b0),
            d11 <= np.minimum(d01, d10), d00 <= np.minimum(d10, d01))  # (a1, b1), (a0, b0)
    index = None  # c00 + 3 c11 + 9 c10 + 27 c01, Horner form from c01 down, in uint8
    for x, b, k in zip((a0s, a1s, a1s, a0s), (b1s, b0s, b1s, b0s), keep):
        tt = np.where(k, t, 0.0)
        code = (x >= b - tt).view(np.uint8)
        code += (x >= np.nextafter(b + tt, np.inf)).view(np.uint8)
        if index is None:
            index = code
        else:
            index *= np.uint8(3)
            index += code
    bits = _TABLES_FLAT[index + _AXIS_OFFSET[index.ndim]]
    return bits[0] | bits[1] | bits[2]


def _plan(n: int) -> tuple[type[_CompareKernel] | type[_RankKernel], int]:
    """The kernel for ``n`` subjects and its chunk of objects (see the constants)."""
    if n >= _RANK_MIN_SUBJECTS:
        low, high = _RANK_CHUNK
        return _RankKernel, min(high, max(low, n // 16))
    return _CompareKernel, max(64, _COMPARE_PAIRS // max(n, 1))


class _Thresholds:
    """The four thresholds of each object of a chunk, per axis: each (3, m)."""

    def __init__(self, b0s: FloatArray, b1s: FloatArray, t: float) -> None:
        self.m = b0s.shape[1]
        self.lo0, self.hi0 = b0s - t, np.nextafter(b0s + t, np.inf)
        self.lo1, self.hi1 = b1s - t, np.nextafter(b1s + t, np.inf)


def _run_blocks(kernel: _CompareKernel | _RankKernel, out: NDArray[np.uint32], cols: slice) -> None:
    """Fill ``out[:, cols]`` block of subjects by block (through a buffer if not contiguous)."""
    n = out.shape[0]
    whole = cols.start == 0 and cols.stop == out.shape[1]
    buffer = None if whole else np.empty((min(n, _BLOCK), cols.stop - cols.start), dtype=np.uint32)
    for start in range(0, n, _BLOCK):
        rows = slice(start, min(n, start + _BLOCK))
        if buffer is None:
            kernel.run(rows, out[rows])
        else:
            dest = buffer[: rows.stop - rows.start]
            kernel.run(rows, dest)
            out[rows, cols] = dest


class _CompareKernel:
    """Broadcast comparisons per block of subjects, codes in uint8 (for few subjects)."""

    def __init__(self, objects: _Thresholds, a0s: FloatArray, a1s: FloatArray) -> None:
        self.obj, self.a0s, self.a1s = objects, a0s, a1s
        shape = (min(a0s.shape[1], _BLOCK), objects.m)
        self.cmp = np.empty(shape, dtype=np.bool_)
        self.code = np.empty(shape, dtype=np.uint8)
        self.bits = np.empty(shape, dtype=np.uint32)

    def _add_ternary(self, code: NDArray[np.uint8], x: FloatArray, lo: FloatArray, hi: FloatArray) -> None:
        """code = 3 code + ternary(x vs the threshold pair lo, hi) (Horner form of the index)."""
        cmp = self.cmp[: code.shape[0]]
        code *= np.uint8(3)
        for thr in (lo, hi):
            np.greater_equal(x[:, None], thr[None, :], out=cmp)
            code += cmp.view(np.uint8)

    def run(self, rows: slice, out: NDArray[np.uint32]) -> None:
        """Masks of subjects ``rows`` into ``out`` (C-contiguous, rows x m)."""
        o = self.obj
        code, bits = self.code[: out.shape[0]], self.bits[: out.shape[0]]
        for axis in range(3):
            a0, a1 = self.a0s[axis, rows], self.a1s[axis, rows]
            code.fill(0)  # index = c00 + 3 c11 + 9 c10 + 27 c01, built from c01 down
            self._add_ternary(code, a0, o.lo1[axis], o.hi1[axis])
            self._add_ternary(code, a1, o.lo0[axis], o.hi0[axis])
            self._add_ternary(code, a1, o.lo1[axis], o.hi1[axis])
            self._add_ternary(code, a0, o.lo0[axis], o.hi0[axis])
            np.take(_TABLES[axis], code, out=out if axis == 0 else bits, mode="clip")
            if axis:
                out |= bits


class _RankKernel:
    """Rank tables per axis for a chunk of objects; per pair two row gathers and an add."""

    def __init__(self, objects: _Thresholds, a0s: FloatArray, a1s: FloatArray) -> None:
        self.p0: list[NDArray] = []
        self.p1: list[NDArray] = []
        self.r0: list[NDArray[np.intp]] = []
        self.r1: list[NDArray[np.intp]] = []
        for axis in range(3):
            thresholds = [v[axis] for v in (objects.lo0, objects.hi0, objects.lo1, objects.hi1)]
            u = np.unique(np.concatenate(thresholds))
            p0, p1 = _rank_tables(u, thresholds, _AXIS_WEIGHT[axis], _AXIS_DTYPE[axis])
            self.p0.append(p0)
            self.p1.append(p1)
            self.r0.append(_ranks(u, a0s[axis]))
            self.r1.append(_ranks(u, a1s[axis]))
        shape = (min(a0s.shape[1], _BLOCK), objects.m)
        self.ixy, self.tmp16 = np.empty(shape, np.uint16), np.empty(shape, np.uint16)
        self.iz, self.tmp8 = np.empty(shape, np.uint8), np.empty(shape, np.uint8)
        self.bits = np.empty(shape, np.uint32)

    def _index(self, axes: range, rows: slice, index: NDArray, tmp: NDArray) -> None:
        """index = sum over ``axes`` of P0[r0] + P1[r1] for subjects ``rows``."""
        first = True
        for axis in axes:
            for table, ranks in ((self.p0[axis], self.r0[axis]), (self.p1[axis], self.r1[axis])):
                np.take(table, ranks[rows], axis=0, out=index if first else tmp, mode="clip")
                if not first:
                    index += tmp
                first = False

    def run(self, rows: slice, out: NDArray[np.uint32]) -> None:
        """Masks of subjects ``rows`` into ``out`` (C-contiguous, rows x m)."""
        k = out.shape[0]
        ixy, iz, bits = self.ixy[:k], self.iz[:k], self.bits[:k]
        self._index(range(2), rows, ixy, self.tmp16[:k])
        np.take(_TABLE_XY, ixy, out=out, mode="clip")
        self._index(range(2, 3), rows, iz, self.tmp8[:k])
        np.take(_TABLES[2], iz, out=bits, mode="clip")
        out |= bits


def _rank_tables(u: FloatArray, thresholds: list[FloatArray], weight: int, dtype: type) -> tuple[NDArray, NDArray]:
    """P0, P1 ((len(u) + 1) x m): the index parts of a0 and a1 for a bound of each rank.

    ``thresholds`` are lo0, hi0, lo1, hi1 of the objects; a bound x of rank r (r thresholds
    <= x) is >= v exactly when r >= searchsorted(u, v, 'right'). Each threshold adds its
    weight from its rank on (a cumulative sum down the rows): in P0, c00 + 27 c01 (a0 against
    b0 and b1), in P1, 3 c11 + 9 c10 (a1 against b1 and b0), times the axis's weight.
    """
    m = thresholds[0].shape[0]
    cols = np.arange(m)
    p0 = np.zeros((u.shape[0] + 1, m), dtype=dtype)
    p1 = np.zeros((u.shape[0] + 1, m), dtype=dtype)
    for v, w0, w1 in zip(thresholds, (1, 1, 27, 27), (9, 9, 3, 3)):
        start = np.searchsorted(u, v, "right")
        p0[start, cols] += dtype(w0 * weight)
        p1[start, cols] += dtype(w1 * weight)
    np.cumsum(p0, axis=0, out=p0)
    np.cumsum(p1, axis=0, out=p1)
    return p0, p1


def _ranks(u: FloatArray, x: FloatArray) -> NDArray[np.intp]:
    """For each x, the number of values of ``u`` (sorted, unique) that are <= x.

    ``np.searchsorted(u, x, 'right')``, computed through buckets: bucket(v) = floor((clip(v) -
    u[0]) * B / width) is monotone in v (each float operation is), so the values of u in lower
    buckets are all < x and those in higher buckets all > x; x is compared only with the few
    values of its own bucket. Exact; 10x faster than the binary search on random x. Falls back
    to the binary search when a bucket holds more than _MAX_LEVELS values.
    """
    k = u.shape[0]
    nb = max(64, 1 << int(8 * k).bit_length())
    width = float(u[-1]) - float(u[0])  # Python floats: inf on overflow, no warning
    scale = nb / width if width > 0.0 else 0.0
    if not np.isfinite(scale) or scale == 0.0:
        return np.searchsorted(u, x, "right")

    def bucket(v: FloatArray) -> NDArray[np.intp]:
        w = np.clip(v, u[0], u[-1])
        w -= u[0]
        w *= scale
        b = w.astype(np.intp)
        return np.minimum(b, nb - 1, out=b)

    bu = bucket(u)
    below = np.searchsorted(bu, np.arange(nb), "left")  # values of u in buckets < b
    level = np.arange(k) - below[bu]
    if level.max() >= _MAX_LEVELS:
        return np.searchsorted(u, x, "right")
    levels = np.full((int(level.max()) + 1, nb), np.inf)
    levels[level, bu] = u
    bx = bucket(x)
    rank = below[bx]
    for row in levels:
        rank += row[bx] <= x
    return rank


def relate_oriented(a_poses: ArrayLike, a_lo: ArrayLike, a_hi: ArrayLike, b_poses: ArrayLike, b_lo: ArrayLike,
                    b_hi: ArrayLike, tol: float = DEFAULT_TOLERANCE) -> NDArray[np.uint32]:
    """uint32 (N, M): the masks of oriented subject boxes to oriented object boxes, each pair
    decided in its object's frame (the world turned about z by the object's heading group's
    yaw: the object's box exact, the subject's its hull there).

    ``a_poses`` (N, 4, 4) and ``b_poses`` (M, 4, 4) are global poses, ``a_lo``, ``a_hi``,
    ``b_lo``, ``b_hi`` the local box corners. One :func:`relate` call on the world boxes, then
    :func:`reframe`: with every object axis aligned, exactly the masks of :func:`relate` on the
    world boxes.
    """
    a = tuple(np.asarray(x, dtype=np.float64) for x in (a_poses, a_lo, a_hi))
    b = tuple(np.asarray(x, dtype=np.float64) for x in (b_poses, b_lo, b_hi))
    masks = relate(*world_boxes(*a), *world_boxes(*b), tol)
    labels, yaws = heading_groups(headings(b[0]))
    reframe(masks, a, b, yaws[labels], tol)
    return masks


def reframe(masks: NDArray[np.uint32], a: tuple, b: tuple, b_yaw: FloatArray, tol: float = DEFAULT_TOLERANCE,
            a_rows: NDArray[np.intp] | None = None, b_rows: NDArray[np.intp] | None = None) -> None:
    """Decide again, in place, the pairs of world-box ``masks`` whose object is turned
    (``b_yaw`` of its frame not 0) and whose world boxes meet (DC on no axis), in the object's
    frame: subject hull and object box turned by ``-b_yaw`` (:func:`frame_boxes`), one row per
    pair (:func:`relate_rows`).

    ``a``, ``b``: (poses, local lo, local hi) of the subjects and objects, indexed through
    ``a_rows`` / ``b_rows`` (mask row / column -> array row; identity when None). ``b_yaw``:
    per mask column. Pairs whose world boxes are apart stay as they are: world boxes hold the
    objects, so such a pair is apart in every frame (and its object's frame could only make its
    subject's hull larger).
    """
    cols = np.flatnonzero(b_yaw)
    if not cols.size:
        return
    sub = masks[:, cols] if cols.size < masks.shape[1] else masks
    i, k = np.nonzero((sub & _DC_ANY) == 0)
    if not i.size:
        return
    j = cols[k]
    yaw = b_yaw[j]
    ai = a_rows[i] if a_rows is not None else i
    bj = b_rows[j] if b_rows is not None else j
    if a is b:  # subjects and objects from the same arrays: their boxes in one call
        rows, p = np.concatenate([ai, bj]), len(ai)
        lo, hi = frame_boxes(a[0][rows], a[1][rows], a[2][rows], np.concatenate([yaw, yaw]))
        alo, ahi, blo, bhi = lo[:p], hi[:p], lo[p:], hi[p:]
    else:
        alo, ahi = frame_boxes(a[0][ai], a[1][ai], a[2][ai], yaw)
        blo, bhi = frame_boxes(b[0][bj], b[1][bj], b[2][bj], yaw)
    # relate_rows without its checks: these are hulls of placed boxes, finite, lo <= hi
    masks[i, j] = _masks_exact(alo.T, ahi.T, blo.T, bhi.T, _check_tolerance(tol))


def relate_rows(a_lo: ArrayLike, a_hi: ArrayLike, b_lo: ArrayLike, b_hi: ArrayLike,
                tol: float = DEFAULT_TOLERANCE) -> NDArray[np.uint32]:
    """uint32 (P,): the mask of subject box p to object box p, row by row (P pairs): the same
    comparisons and tables as :func:`relate`."""
    t = _check_tolerance(tol)
    a0s, a1s = _boxes(a_lo, a_hi, "subject")
    b0s, b1s = _boxes(b_lo, b_hi, "object")
    return _masks_exact(a0s, a1s, b0s, b1s, t)
