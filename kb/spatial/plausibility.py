"""Physical plausibility of a scene: solids that interpenetrate, and solids that float.

What ``kitkb validate`` reports as the warnings ``interpenetration`` and ``floating-object``
(docs/validation.md), and the kit design slots whose part would not lie in their tray
(:func:`slot_misfits`, the error ``slot-outside-tray``). Pure functions of a
:class:`kb.spatial.scene.Scene` or of arrays (geometry in metres); :func:`check` returns
:class:`Finding` objects, the validator words them.

Geometry: each placed object is its oriented box (its local box under its global pose, any
rotation). Two boxes interpenetrate when the separating-axis test finds no separating axis
among the 15 candidates (the 3 + 3 face normals and the 9 edge cross products) along which
they overlap by at most the tolerance; the depth is the smallest overlap along those axes (how
far one must move for them to part). Pairs are found on world boxes first
(:func:`overlapping_pairs`: a sweep along x in bands along y, the few large objects in the
cells of a grid in plan), so only neighbours are tested, all at once with numpy.

Tolerance: ``tol``, as the predicates use it; for a box thinner than ``2 tol`` on some axis
(:func:`thin_boxes`: NIST's 0.343 mm washers, narrow shafts), a depth measured along an axis is
compared with half the boxes' extents along it where that is less
(:func:`kb.spatial.rcc8.depth_tolerance`, the predicates' rule: a thin box is through a face
once its middle is): along a separating axis the two boxes' projections on it
(:func:`sat_excess`), for a face of an open container the inner object's extent across it, for
the ground its height. Gaps keep the whole tolerance (a washer 0.5 mm above a table rests on
it). Boxes at least ``2 tol`` across get exactly ``tol``, as before.

What is not a pair, or not an interpenetration:

* an object and the stand-in that shares its box (a kit and its kit tray, a large box and its
  large container, a changing station and its base): the stand-in is left out, and what
  refers to it refers to the object lending the box (the lender placed in its stand-in, as
  NIST's kit tray in its kit, refers to what the stand-in refers to);
* an object inside an open container (``open_top``: trays, large boxes, open holders) that lies
  within the container's walls and not below its floor (in the container's frame, beyond the
  tolerance); an object partly through a wall or the floor goes through each face it reaches
  beyond (``Finding.faces``: the face, how far beyond it, how far on the cavity's side);
* in the robot's assembly (everything whose chain of reference objects reaches the robot), an
  object and what it holds (the flange and its effector, the effector and its load; not the
  effector and the parts of a kit it holds); an effector and the holder it hangs in; anything
  mounted on a changing station (holders, the effectors in them) and the station.

An object floats when the highest support under its footprint is more than the tolerance
below its bottom: a support is the top of an object under it, or the floor of an open
container whose walls it is within, or the ground (z = 0 of the workstation). Objects that
legitimately hang are not checked: the robot and everything whose chain reaches it, effectors
touching the holder they are in, and holders touching the changing station they are on (in it,
or against it). An object below the ground interpenetrates the workstation.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable, Mapping

import numpy as np

from kb.core.namespaces import KTW
from kb.core.units import SI, Units
from kb.spatial.rcc8 import DEFAULT_TOLERANCE, depth_tolerance
from kb.spatial.scene import STAND_INS, Scene

INTERPENETRATION = "interpenetration"
FLOATING = "floating-object"
RULES = (INTERPENETRATION, FLOATING)

_ROBOT, _EFFECTOR = str(KTW.Robot), str(KTW.EndEffector)
_HOLDER, _STATION = str(KTW.EndEffectorHolder), str(KTW.EndEffectorChangingStation)
_PAIR_BLOCK = 1 << 20  # candidate pairs per block of the sweep


@dataclass(frozen=True)
class Finding:
    """One implausible pose.

    ``rule``: :data:`INTERPENETRATION` or :data:`FLOATING`; ``obj``: the object whose pose is
    wrong (the one inside, the smaller, or the floating one); ``other``: the object it
    interpenetrates or floats above (None: the ground); ``depth``: metres; ``how``: ``"overlap"``,
    ``"floor"`` or ``"wall"`` (through an open container's floor or wall), ``"ground"``
    (below z = 0), ``"top"`` / ``"floor"`` / ``"ground"`` for what a floating object is above;
    ``pose``: the IRI of ``obj``'s pose location (from ``locations``), for its line;
    ``faces``: for ``"floor"`` / ``"wall"``, each face of the container ``obj`` goes through,
    the furthest first: (``"floor"`` or the wall's side ``"-x"``, ``"+x"``, ``"-y"``, ``"+y"``
    in the container's frame, how far ``obj`` reaches beyond it, how far it reaches on the
    cavity's side of it), metres; ``depth`` is the first's reach beyond it.
    """

    rule: str
    obj: str
    other: str | None
    depth: float
    how: str
    pose: str | None = None
    faces: tuple[tuple[str, float, float], ...] = ()


@dataclass
class Boxes:
    """Oriented boxes: centres (K, 3), axes (K, 3, 3) (columns: local x, y, z in the world),
    half sizes (K, 3), the pose origins (K, 3) and local boxes (K, 3) they come from."""

    centre: np.ndarray
    axes: np.ndarray
    half: np.ndarray
    origin: np.ndarray
    lo: np.ndarray
    hi: np.ndarray

    @classmethod
    def of(cls, poses: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> "Boxes":
        """The boxes ``lo``, ``hi`` (K, 3) (swapped where given the wrong way round, as a
        negative length makes them) under the global poses (K, 4, 4)."""
        lo, hi = np.minimum(lo, hi), np.maximum(lo, hi)
        axes = poses[:, :3, :3]
        origin = poses[:, :3, 3]
        centre = origin + np.einsum("kij,kj->ki", axes, (lo + hi) / 2)
        return cls(centre, axes, (hi - lo) / 2, origin, lo, hi)

    def take(self, idx: np.ndarray) -> "Boxes":
        return Boxes(*(a[idx] for a in (self.centre, self.axes, self.half, self.origin, self.lo, self.hi)))


# --- separating axes ----------------------------------------------------------------------

def sat_depth(a: Boxes, b: Boxes) -> np.ndarray:
    """(P,) for P pairs of oriented boxes: the smallest overlap along the 15 candidate
    separating axes (positive: they interpenetrate by that much; zero or less: separated or
    touching, minus the gap along the best axis).

    Computed in ``a``'s frame from ``R = A^T B`` (the axes are orthonormal, as every pose
    is): along ``a``'s axis i the radii are ``a.half[i]`` and ``sum_j b.half[j] |R_ij|``;
    along ``b``'s axis j, ``sum_i a.half[i] |R_ij|`` and ``b.half[j]``; along ``a_i x b_j``
    (of length ``sqrt(R_ij1^2 + R_ij2^2)``, j1, j2 the other two of j; none when the edges are
    parallel) ``a.half[i1] |R_i2j| + a.half[i2] |R_i1j|`` and ``b.half[j1] |R_ij2| +
    b.half[j2] |R_ij1|``, the centres ``|t_i2 R_i1j - t_i1 R_i2j|`` apart (``t``: the
    centres' offset in ``a``'s frame)."""
    p = a.centre.shape[0]
    if p == 0:
        return np.zeros(0)
    r = np.matmul(np.swapaxes(a.axes, 1, 2), b.axes)  # (P, 3, 3): a_i . b_j
    ar = np.abs(r)
    t = np.einsum("pji,pj->pi", a.axes, b.centre - a.centre)  # the offset in a's frame
    ea, eb = a.half, b.half
    face_a = ea + np.einsum("pij,pj->pi", ar, eb) - np.abs(t)
    face_b = np.einsum("pij,pi->pj", ar, ea) + eb - np.abs(np.einsum("pij,pi->pj", r, t))
    n1, n2 = _NEXT, _AFTER
    ra = ea[:, n1, None] * ar[:, n2, :] + ea[:, n2, None] * ar[:, n1, :]
    rb = eb[:, None, n1] * ar[:, :, n2] + eb[:, None, n2] * ar[:, :, n1]
    dist = np.abs(t[:, n2, None] * r[:, n1, :] - t[:, n1, None] * r[:, n2, :])
    length = np.sqrt(r[:, :, n1] ** 2 + r[:, :, n2] ** 2)
    valid = length > 1e-6  # parallel edges give no axis
    edge = np.where(valid, (ra + rb - dist) / np.where(valid, length, 1.0), np.inf)
    return np.minimum(np.minimum(face_a.min(axis=1), face_b.min(axis=1)), edge.reshape(p, 9).min(axis=1))


#: for each of the three axes, the next one and the one after (cyclic)
_NEXT, _AFTER = np.array([1, 2, 0]), np.array([2, 0, 1])


def sat_excess(a: Boxes, b: Boxes, tol: float, thin: np.ndarray | None = None,
               a_radii: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """(depth, excess), each (P,): :func:`sat_depth` and by how much the two boxes overlap
    beyond the tolerance: the smallest, over the 15 candidate axes, of the overlap along the
    axis less the tolerance along it (positive: they interpenetrate).

    The tolerance along an axis is ``tol``, or half the smaller positive extent of the two
    boxes along that axis (their projections on it) where that is less
    (:func:`kb.spatial.rcc8.depth_tolerance`): a washer 0.343 mm thick overlaps a floor once its
    middle is through it, as the predicates decide. It is computed only for the pairs flagged
    ``thin`` (P,) (a box with an extent under ``2 tol``); the others, and every pair when
    ``thin`` is None, get ``tol`` on every axis (``excess = depth - tol``, exactly as before).
    ``a_radii`` (P, 3): the half sizes of ``a`` its extents are taken from, if not ``a.half``
    (a floating object's column: the object's own height, not the column's)."""
    depth = sat_depth(a, b)
    excess = depth - tol
    rows = np.flatnonzero(thin) if thin is not None else np.zeros(0, np.intp)
    if rows.size:
        sub_a, sub_b = a.take(rows), b.take(rows)
        overlap, ra, rb = _sat_axes(sub_a, sub_b, a_radii[rows] if a_radii is not None else None)
        allowed = np.minimum(np.minimum(tol, np.where(ra > 0.0, ra, tol)), np.where(rb > 0.0, rb, tol))
        excess[rows] = (overlap - allowed).min(axis=1)
    return depth, excess


def _sat_axes(a: Boxes, b: Boxes, a_radii: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(overlap, ra, rb), each (P, 15): along each of the 15 candidate axes (``a``'s three,
    ``b``'s three, the nine edge cross products, normalised; ``inf`` overlap where two edges are
    parallel), the overlap of the boxes' projections and their radii (half extents) along it.
    ``a_radii`` (P, 3): the half sizes of ``a`` for its radii (default ``a.half``)."""
    p = a.centre.shape[0]
    r = np.matmul(np.swapaxes(a.axes, 1, 2), b.axes)  # (P, 3, 3): a_i . b_j
    ar = np.abs(r)
    t = np.einsum("pji,pj->pi", a.axes, b.centre - a.centre)
    ea, eb = a.half, b.half
    ha = a_radii if a_radii is not None else ea
    n1, n2 = _NEXT, _AFTER

    def radii(e_a: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        face_a = e_a
        face_b = np.einsum("pij,pi->pj", ar, e_a)
        edge = e_a[:, n1, None] * ar[:, n2, :] + e_a[:, n2, None] * ar[:, n1, :]
        return face_a, face_b, edge
    fa_a, fb_a, ed_a = radii(ea)
    fa_b = np.einsum("pij,pj->pi", ar, eb)
    fb_b = eb
    ed_b = eb[:, None, n1] * ar[:, :, n2] + eb[:, None, n2] * ar[:, :, n1]
    dist_a, dist_b = np.abs(t), np.abs(np.einsum("pij,pi->pj", r, t))
    dist_e = np.abs(t[:, n2, None] * r[:, n1, :] - t[:, n1, None] * r[:, n2, :])
    length = np.sqrt(r[:, :, n1] ** 2 + r[:, :, n2] ** 2)
    valid = length > 1e-6  # parallel edges give no axis
    norm = np.where(valid, length, 1.0)
    overlap = np.concatenate([fa_a + fa_b - dist_a, fb_a + fb_b - dist_b,
                              np.where(valid, (ed_a + ed_b - dist_e) / norm, np.inf).reshape(p, 9)], axis=1)
    ta, tb, te = radii(ha) if a_radii is not None else (fa_a, fb_a, ed_a)
    ra = np.concatenate([ta, tb, (te / norm).reshape(p, 9)], axis=1)
    rb = np.concatenate([fa_b, fb_b, (ed_b / norm).reshape(p, 9)], axis=1)
    return overlap, ra, rb


def in_frame_of(a: Boxes, b: Boxes) -> tuple[np.ndarray, np.ndarray]:
    """(lo, hi) (P, 3): the hull of each box ``a`` in the local frame of box ``b`` (where
    ``b``'s own box is ``b.lo``, ``b.hi``)."""
    turn = np.swapaxes(b.axes, 1, 2)
    rel = turn @ a.axes  # a's axes in b's frame (columns)
    centre = (turn @ (a.centre - b.origin)[:, :, None])[:, :, 0]
    half = (np.abs(rel) @ a.half[:, :, None])[:, :, 0]
    return centre - half, centre + half


# --- candidate pairs ----------------------------------------------------------------------

def overlapping_pairs(lo: np.ndarray, hi: np.ndarray, margin: float) -> tuple[np.ndarray, np.ndarray]:
    """(i, j), i < j, of the boxes (K, 3) whose world boxes overlap or are less than ``margin``
    apart on every axis.

    Boxes up to four times the median size in plan (parts, most things) are swept along x in
    bands along y of that width, so a box meets only its neighbours; the larger ones (tables,
    trays, large boxes: few) are put in the cells of a grid in plan of that width that they
    reach, and meet what is in those cells (a box reaching more than :data:`_MAX_CELLS` cells,
    or one that is not finite, is swept against all along x)."""
    k = lo.shape[0]
    if k < 2:
        return np.zeros(0, np.intp), np.zeros(0, np.intp)
    size = (hi - lo)[:, :2].max(axis=1)
    band = max(4.0 * float(np.median(size)), 4.0 * margin, 1e-9)
    large = ~(size <= band)
    c0, c1, cells = _cell_span(lo, hi, margin, band)
    spread = ~(cells <= np.where(large, _MAX_CELLS, 9))  # past the grid (or not finite)
    small = np.flatnonzero(~large & ~spread)
    found = [_banded(lo, hi, margin, small, band)]
    gridded = np.flatnonzero(large & ~spread)
    if gridded.size:
        found.append(_gridded(lo, hi, margin, gridded, small, c0, c1, cells))
    others = np.flatnonzero(spread)
    if others.size:
        everything = np.arange(k)
        found.append(_against(lo, hi, margin, others, everything, np.inf))
    i, j = (np.concatenate(x) for x in zip(*found))
    i, j = np.minimum(i, j), np.maximum(i, j)
    keep = i != j
    key = np.unique(i[keep].astype(np.int64) * k + j[keep])
    return (key // k).astype(np.intp), (key % k).astype(np.intp)


#: the most grid cells a large box is put in (a larger one is swept along x against all)
_MAX_CELLS = 4096
_FAR = float(1 << 30)  # cell coordinates are kept within +-_FAR (past it: the last cell)


@np.errstate(invalid="ignore", over="ignore")
def _cell_span(lo: np.ndarray, hi: np.ndarray, margin: float, cell: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The first and last grid cell (K, 2) in plan each box reaches (with ``margin``), and how
    many cells that is (K,) (NaN or infinite where a box is not finite)."""
    c0 = np.floor((lo[:, :2] - margin) / cell)
    c1 = np.floor((hi[:, :2] + margin) / cell)
    cells = (c1 - c0 + 1).prod(axis=1)
    return np.clip(c0, -_FAR, _FAR), np.clip(c1, -_FAR, _FAR), cells


def _in_cells(ids: np.ndarray, c0: np.ndarray, c1: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(cell key, box) for every cell each box of ``ids`` reaches, sorted by cell."""
    first = c0[ids].astype(np.int64)
    n = (c1[ids] - c0[ids]).astype(np.int64) + 1
    count = n[:, 0] * n[:, 1]
    who = np.repeat(ids, count)
    step = np.arange(count.sum()) - np.repeat(np.cumsum(count) - count, count)
    nx = np.repeat(n[:, 0], count)
    cx = np.repeat(first[:, 0], count) + step % nx
    cy = np.repeat(first[:, 1], count) + step // nx
    key = cx * (1 << 32) + cy
    order = np.argsort(key, kind="stable")
    return key[order], who[order]


def _gridded(lo: np.ndarray, hi: np.ndarray, margin: float, large: np.ndarray, small: np.ndarray, c0: np.ndarray,
             c1: np.ndarray, cells: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Pairs of the ``large`` boxes with the ``small`` ones and with each other: each against
    what shares a grid cell with it (two boxes near each other share a cell)."""
    big_key, big = _in_cells(large, c0, c1)
    small_key, small_who = _in_cells(small, c0, c1)
    first = np.searchsorted(small_key, big_key, side="left")
    last = np.searchsorted(small_key, big_key, side="right")
    with_small = _pairs_in_runs(lo, hi, margin, big, first, last, small_who)
    last = np.searchsorted(big_key, big_key, side="right")
    first = np.arange(big_key.size) + 1
    with_large = _pairs_in_runs(lo, hi, margin, big, first, np.maximum(last, first), big)
    return tuple(np.concatenate(x) for x in zip(with_small, with_large))  # type: ignore[return-value]


def _near(lo: np.ndarray, hi: np.ndarray, margin: float, i: np.ndarray, j: np.ndarray) -> np.ndarray:
    return np.all((lo[i] <= hi[j] + margin) & (lo[j] <= hi[i] + margin), axis=1)


def _banded(lo: np.ndarray, hi: np.ndarray, margin: float, ids: np.ndarray, band: float
            ) -> tuple[np.ndarray, np.ndarray]:
    """Pairs among ``ids`` (each at most ``band`` wide along y): each box in every band of y
    it reaches, then a sweep along x within each band."""
    if ids.size < 2:
        return np.zeros(0, np.intp), np.zeros(0, np.intp)
    b0 = np.floor((lo[ids, 1] - margin) / band).astype(np.int64)
    b1 = np.floor((hi[ids, 1] + margin) / band).astype(np.int64)
    reach = b1 - b0 + 1
    who = np.repeat(ids, reach)
    bands = np.repeat(b0, reach) + (np.arange(reach.sum()) - np.repeat(np.cumsum(reach) - reach, reach))
    x0 = lo[:, 0].min()
    width = float(hi[:, 0].max() - x0) + 2 * margin + 1.0
    start = (bands - bands.min()) * width + (lo[who, 0] - x0)
    order = np.argsort(start, kind="stable")
    start, who, bands = start[order], who[order], bands[order]
    stop = (bands - bands.min()) * width + (hi[who, 0] - x0) + margin
    return _sweep(lo, hi, margin, who, start, stop, who)


def _against(lo: np.ndarray, hi: np.ndarray, margin: float, these: np.ndarray, those: np.ndarray,
             widest: float) -> tuple[np.ndarray, np.ndarray]:
    """Pairs of ``these`` with ``those`` (each of ``those`` at most ``widest`` long along x):
    ``those`` sorted along x, each of ``these`` against the run that can reach it."""
    if not these.size or not those.size:
        return np.zeros(0, np.intp), np.zeros(0, np.intp)
    order = those[np.argsort(lo[those, 0], kind="stable")]
    start = lo[order, 0]
    reach = widest if np.isfinite(widest) else float((hi[those, 0] - lo[those, 0]).max())
    if not np.isfinite(reach):  # a box that is not finite: each of these against all of those
        reach = np.inf
    first = np.searchsorted(start, lo[these, 0] - reach - margin, side="left")
    last = np.searchsorted(start, hi[these, 0] + margin, side="right")
    return _pairs_in_runs(lo, hi, margin, these, first, last, order)


def _sweep(lo: np.ndarray, hi: np.ndarray, margin: float, who: np.ndarray, start: np.ndarray,
           stop: np.ndarray, order: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Each sorted entry against the entries after it that start before it stops."""
    last = np.searchsorted(start, stop, side="right")
    first = np.arange(start.size) + 1
    return _pairs_in_runs(lo, hi, margin, who, first, np.maximum(last, first), order)


def _pairs_in_runs(lo: np.ndarray, hi: np.ndarray, margin: float, who: np.ndarray, first: np.ndarray,
                   last: np.ndarray, order: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``who[n]`` against ``order[first[n]:last[n]]`` for every n, kept where the boxes are
    near on every axis; in blocks of at most :data:`_PAIR_BLOCK` candidates."""
    counts = np.maximum(last - first, 0)
    out_i, out_j = [np.zeros(0, np.intp)], [np.zeros(0, np.intp)]
    total = np.cumsum(counts)
    n0 = 0
    while n0 < counts.size:
        n1 = int(np.searchsorted(total, (total[n0 - 1] if n0 else 0) + _PAIR_BLOCK, side="right"))
        n1 = max(n1, n0 + 1)
        c = counts[n0:n1]
        pos = np.repeat(np.arange(n0, n1), c)
        step = np.arange(c.sum()) - np.repeat(np.cumsum(c) - c, c)
        i, j = who[pos], order[first[pos] + step]
        near = _near(lo, hi, margin, i, j)
        out_i.append(i[near])
        out_j.append(j[near])
        n0 = n1
    return np.concatenate(out_i), np.concatenate(out_j)


# --- the scene's structure ----------------------------------------------------------------

@dataclass
class _Structure:
    """Which objects take part, what they refer to, and who hangs from what."""

    active: np.ndarray   # (K,) bool: placed, finite, not a stand-in
    alias: np.ndarray    # (K,) the object whose box each one has (itself unless a stand-in)
    chain: np.ndarray    # (K, D) reference objects up the tree (aliased), -1 padded
    robot: np.ndarray    # (K,) the robot of its chain (itself included), -1
    station: np.ndarray  # (K,) the changing station (its box's object) it hangs from, -1
    effector: np.ndarray  # (K,) bool
    holder: np.ndarray   # (K,) bool
    holder_of: np.ndarray  # (K,) the nearest holder up its chain, -1


def _structure(scene: Scene) -> _Structure:
    k = len(scene)
    finite = np.isfinite(scene.poses.reshape(k, -1)).all(axis=1) & np.isfinite(scene.local_lo).all(axis=1) \
        & np.isfinite(scene.local_hi).all(axis=1) if k else np.zeros(0, bool)
    active = finite & scene.placed
    alias = np.arange(k)
    for cls, prop in STAND_INS.items():
        lender = scene.related(str(prop))
        for i in scene.of_class(cls):
            j = scene.index.get((lender.get(scene.names[i]) or [None])[0])
            if j is not None and active[i] and active[j] and _same_box(scene, i, j):
                alias[i], active[i] = j, False
    parent = scene.parents.copy()
    for _ in range(4):  # a lender placed in its stand-in (NIST's kit tray in its kit): the stand-in's reference
        own = (parent >= 0) & (alias[np.maximum(parent, 0)] == np.arange(k))
        if not own.any():
            break
        parent[own] = scene.parents[parent[own]]
    parent = np.where(parent >= 0, alias[np.maximum(parent, 0)], -1)
    links = [parent]
    while (links[-1] >= 0).any() and len(links) < 64:
        up = links[-1]
        links.append(np.where(up >= 0, parent[np.maximum(up, 0)], -1))
    chain = np.stack(links[:-1] if len(links) > 1 else links, axis=1)
    is_of = {c: np.isin(np.arange(k), scene.of_class(c)) for c in (_ROBOT, _EFFECTOR, _HOLDER, _STATION)}
    robot = np.where(is_of[_ROBOT], np.arange(k), -1)
    station_box = np.where(is_of[_STATION], alias, -1)
    hang_station, holder_of = np.full(k, -1), np.full(k, -1)
    stations = station_box[station_box >= 0]
    for up in chain.T:  # up the tree: the nearest robot / station / holder wins
        robot = np.where((robot < 0) & (up >= 0) & is_of[_ROBOT][np.maximum(up, 0)], up, robot)
        hang_station = np.where((hang_station < 0) & (up >= 0) & np.isin(up, stations), up, hang_station)
        holder_of = np.where((holder_of < 0) & (up >= 0) & is_of[_HOLDER][np.maximum(up, 0)], up, holder_of)
    return _Structure(active, alias, chain, robot, hang_station, is_of[_EFFECTOR], is_of[_HOLDER], holder_of)


def _same_box(scene: Scene, i: int, j: int) -> bool:
    return bool(np.allclose(scene.poses[i], scene.poses[j]) and np.allclose(scene.local_lo[i], scene.local_lo[j])
                and np.allclose(scene.local_hi[i], scene.local_hi[j]))


def _exempt(st: _Structure, i: np.ndarray, j: np.ndarray) -> np.ndarray:
    """Pairs that may overlap: in one robot's assembly, an object and what it holds (the
    robot's flange and its effector, an effector and the object it holds); a station and what
    hangs from it; an effector and the holder above it in its chain."""
    attached = (st.chain[i, 0] == j) | (st.chain[j, 0] == i)
    held_by_robot = attached & (st.robot[i] >= 0) & (st.robot[i] == st.robot[j])
    mounted = (st.station[i] == j) | (st.station[j] == i)
    anc_ij = (st.chain[i] == j[:, None]).any(axis=1)
    anc_ji = (st.chain[j] == i[:, None]).any(axis=1)
    in_holder = (st.effector[i] & st.holder[j] & anc_ij) | (st.effector[j] & st.holder[i] & anc_ji)
    return held_by_robot | mounted | in_holder


# --- the check ------------------------------------------------------------------------------

@np.errstate(over="ignore", invalid="ignore")  # NaN / infinite coordinates: no RuntimeWarning lines
def check(scene: Scene, tol: float = DEFAULT_TOLERANCE, locations: Mapping[str, str] | None = None,
          rules: tuple[str, ...] = RULES) -> list[Finding]:
    """The implausible poses of ``scene`` (metres) beyond ``tol`` metres: interpenetrating and
    floating objects (``rules`` chooses), ordered by object and rule. ``locations``: object
    IRI -> the IRI of its pose location, copied into each finding."""
    if scene.poses is None or scene.local_lo is None or not len(scene):
        return []
    st = _structure(scene)
    idx = np.flatnonzero(st.active)
    if idx.size == 0:
        return []
    boxes = Boxes.of(scene.poses[idx], scene.local_lo[idx], scene.local_hi[idx])
    lo, hi = scene.lo[idx], scene.hi[idx]
    reach = lo.copy()
    reach[:, 2] = np.minimum(reach[:, 2], 0.0)  # down to the ground: what may hold it up
    a, b = overlapping_pairs(reach, hi, tol)
    thin = thin_boxes(boxes.half, tol)
    pairs = _Pairs(scene, st, idx, boxes, a, b, tol, thin)
    found: list[Finding] = []
    if INTERPENETRATION in rules:
        found += pairs.interpenetrations()
        allowed = np.where(thin, depth_tolerance(tol, hi[:, 2] - lo[:, 2]), tol)  # a washer: by its middle
        below = np.flatnonzero(lo[:, 2] < -allowed)
        found += [Finding(INTERPENETRATION, scene.names[idx[n]], None, float(-lo[n, 2]), "ground") for n in below]
    if FLOATING in rules:
        found += pairs.floating(_hanging(st, idx, boxes, tol))
    locations = locations or {}
    found = [Finding(f.rule, f.obj, f.other, f.depth, f.how, locations.get(f.obj), f.faces) for f in found]
    return sorted(found, key=lambda f: (f.obj, f.rule, f.other or ""))


def thin_boxes(half: np.ndarray, tol: float) -> np.ndarray:
    """(K,) bool: the boxes of half sizes ``half`` (K, 3) with an extent under ``2 tol`` (a
    zero extent, a point or a plate, does not count): the only ones whose depths are compared
    with less than ``tol`` (:func:`kb.spatial.rcc8.depth_tolerance`)."""
    return ((half > 0.0) & (half < tol)).any(axis=1)


def _hanging(st: _Structure, idx: np.ndarray, boxes: Boxes, tol: float) -> np.ndarray:
    """(len(idx),) bool: objects that hang rather than rest: the robot's assembly; effectors
    touching the holder they are in, holders touching the changing station they are on."""
    out = st.robot[idx] >= 0
    pos = {int(n): m for m, n in enumerate(idx)}
    for kind, on in ((st.effector, st.holder_of), (st.holder, st.station)):
        these = np.flatnonzero(kind[idx] & (on[idx] >= 0))
        those = np.array([pos.get(int(on[idx[m]]), -1) for m in these], dtype=np.intp)
        ok = those >= 0
        if ok.any():
            touch = sat_depth(boxes.take(these[ok]), boxes.take(those[ok])) >= -tol
            out[these[ok][touch]] = True
    return out


class _Pairs:
    """The candidate pairs (indices into the active objects) and what each needs."""

    def __init__(self, scene: Scene, st: _Structure, idx: np.ndarray, boxes: Boxes, a: np.ndarray,
                 b: np.ndarray, tol: float, thin: np.ndarray) -> None:
        self.scene, self.st, self.idx, self.boxes, self.tol = scene, st, idx, boxes, tol
        self.a, self.b = a, b
        self.thin = thin  # (len(idx),): a box with an extent under 2 tol
        self.exempt = _exempt(st, idx[a], idx[b])  # may overlap (still hold each other up)
        self.open = scene.open_top[idx]
        self.ba, self.bb = boxes.take(a), boxes.take(b)  # each pair's boxes
        self.inside_ab = _Cavity(self.ba, self.bb, tol, thin[a])  # a in b's cavity
        self.inside_ba = _Cavity(self.bb, self.ba, tol, thin[b])

    def interpenetrations(self) -> list[Finding]:
        a, b, tol = self.a, self.b, self.tol
        depth, excess = sat_excess(self.ba, self.bb, tol, self.thin[a] | self.thin[b])
        hit = (excess > 0.0) & ~self.exempt
        if not hit.any():
            return []
        open_b, open_a = self.open[b], self.open[a]
        contained = (open_b & self.inside_ab.within) | (open_a & self.inside_ba.within)
        return [self._one(n, float(depth[n])) for n in np.flatnonzero(hit & ~contained)]

    def _one(self, n: int, depth: float) -> Finding:
        """The finding of pair ``n``. With an open container and a smaller object: through the
        faces of the container (its floor, its walls) it reaches beyond by more than the
        tolerance, each by how far; otherwise an overlap by the separating-axis depth, reported
        at the object referring to the other, else the smaller."""
        names, a, b = self.scene.names, int(self.idx[self.a[n]]), int(self.idx[self.b[n]])
        options = []
        if self.open[self.b[n]] and self._volume(a) < self._volume(b):
            options.append((self.inside_ab, a, b))
        if self.open[self.a[n]] and self._volume(b) < self._volume(a):
            options.append((self.inside_ba, b, a))
        if options:
            cavity, inner, outer = options[0]
            faces = cavity.faces(n)
            if faces:
                how = "floor" if faces[0][0] == "floor" else "wall"
                return Finding(INTERPENETRATION, names[inner], names[outer], faces[0][1], how, faces=faces)
        first, second = self._reported(a, b)
        return Finding(INTERPENETRATION, names[first], names[second], depth, "overlap")

    def _volume(self, i: int) -> float:
        return float(np.prod(self.scene.local_hi[i] - self.scene.local_lo[i]))

    def _reported(self, a: int, b: int) -> tuple[int, int]:
        """(the object whose pose is reported, the other): the one referring to the other
        (down the tree), else the smaller, else the first by name."""
        chain = self.st.chain
        if (chain[b] == a).any():
            return b, a
        if (chain[a] == b).any():
            return a, b
        va, vb = self._volume(a), self._volume(b)
        if not np.isclose(va, vb):
            return (a, b) if va < vb else (b, a)
        return (a, b) if self.scene.names[a] <= self.scene.names[b] else (b, a)

    def floating(self, hanging: np.ndarray) -> list[Finding]:
        """Objects whose highest support under the footprint is more than ``tol`` below them."""
        bottom = self.scene.lo[self.idx, 2]
        ups, downs, heights, floors = [], [], [], []
        for up, down, cavity, up_boxes, down_boxes in ((self.a, self.b, self.inside_ab, self.ba, self.bb),
                                                       (self.b, self.a, self.inside_ba, self.bb, self.ba)):
            # only what reaches below the bottom by more than its tolerance along z can be under
            # it (the column's depth along z bounds its separating-axis depth; 1 nm for the
            # rounding); that tolerance is tol but for thin boxes (half their heights, if less)
            thin = self.thin[up] | self.thin[down]
            allowed = np.full(up.size, self.tol)
            if thin.any():
                tall = [self.scene.hi[self.idx[x[thin]], 2] - self.scene.lo[self.idx[x[thin]], 2] for x in (up, down)]
                allowed[thin] = depth_tolerance(self.tol, *tall)
            maybe = np.flatnonzero(self.scene.lo[self.idx[down], 2] < bottom[up] - allowed + 1e-9)
            under = np.zeros(up.size, bool)
            if maybe.size:
                shadow, radii = _shadow(up_boxes.take(maybe), bottom[up[maybe]], self.tol)
                under[maybe] = sat_excess(shadow, down_boxes.take(maybe), self.tol, thin[maybe], radii)[1] > 0.0
            in_cavity = self.open[down] & cavity.walls & cavity.rises  # on (or through) its floor
            height = np.where(in_cavity, self.scene.lo[self.idx[down], 2], self.scene.hi[self.idx[down], 2])
            ok = ((under & ~(self.open[down] & cavity.walls)) | in_cavity) & (height > -self.tol)
            ups.append(up[ok]), downs.append(down[ok]), heights.append(height[ok]), floors.append(in_cavity[ok])
        u, d, h, f = (np.concatenate(x) for x in (ups, downs, heights, floors))
        order = np.lexsort((f, h, u))  # per object: the highest support last (a floor before a top)
        last = order[np.r_[u[order][1:] != u[order][:-1], True]] if order.size else order
        best = np.zeros(len(self.idx))  # the ground
        by = np.full(len(self.idx), -1)
        how = np.full(len(self.idx), "ground", dtype=object)
        high = last[h[last] >= 0]
        best[u[high]], by[u[high]] = h[high], d[high]
        how[u[high]] = np.where(f[high], "floor", "top")
        gap = bottom - best
        out = []
        for m in np.flatnonzero((gap > self.tol) & ~hanging):
            other = self.scene.names[self.idx[by[m]]] if by[m] >= 0 else None
            out.append(Finding(FLOATING, self.scene.names[self.idx[m]], other, float(gap[m]), str(how[m])))
        return out


#: the faces of an open container (:meth:`_Cavity.faces`), in the order of ``_Cavity.beyond``
FACES = ("-x", "+x", "-y", "+y", "floor")


class _Cavity:
    """Box ``a`` against the cavity of box ``b`` (as if ``b`` were an open container: walls and
    a floor of no thickness), in ``b``'s frame: how far ``a`` reaches beyond each face of
    :data:`FACES` (``beyond`` (P, 5), metres) and on the cavity's side of it (``inside``), the
    tolerance of each (``allowed``: ``tol``, or for a ``thin`` box (P,) half its extent across
    the face where that is less, as the predicates decide: a washer is in once its middle is);
    within its walls in plan (``walls``), also above its floor (``within``), not all under the
    floor (``rises``)."""

    def __init__(self, a: Boxes, b: Boxes, tol: float, thin: np.ndarray) -> None:
        lo, hi = in_frame_of(a, b)
        self.beyond = np.stack([b.lo[:, 0] - lo[:, 0], hi[:, 0] - b.hi[:, 0], b.lo[:, 1] - lo[:, 1],
                                hi[:, 1] - b.hi[:, 1], b.lo[:, 2] - lo[:, 2]], axis=1)
        self.inside = np.stack([hi[:, 0] - b.lo[:, 0], b.hi[:, 0] - lo[:, 0], hi[:, 1] - b.lo[:, 1],
                                b.hi[:, 1] - lo[:, 1], hi[:, 2] - b.lo[:, 2]], axis=1)
        allowed = np.full((len(lo), 3), tol)
        rows = np.flatnonzero(thin)
        if rows.size:
            allowed[rows] = depth_tolerance(tol, hi[rows] - lo[rows])
        self.allowed = allowed[:, [0, 0, 1, 1, 2]]
        out = ~(self.beyond <= self.allowed)  # (a NaN, of coordinates past float's range, is out)
        self.walls = ~out[:, :4].any(axis=1)
        self.within = self.walls & ~out[:, 4]
        self.rises = hi[:, 2] > b.lo[:, 2] + allowed[:, 2]  # not all under the floor

    def faces(self, n: int) -> tuple[tuple[str, float, float], ...]:
        """Pair ``n``'s faces that box ``a`` reaches beyond by more than their tolerance: (face,
        how far beyond, how far on the cavity's side), the furthest first."""
        out = [(FACES[k], float(self.beyond[n, k]), float(self.inside[n, k])) for k in range(5)
               if self.beyond[n, k] > self.allowed[n, k]]
        return tuple(sorted(out, key=lambda f: -f[1]))


def _shadow(a: Boxes, bottom: np.ndarray, tol: float) -> tuple[Boxes, np.ndarray]:
    """The column under each box ``a``: its footprint, from just below the ground to its
    bottom (what reaches more than ``tol`` into it is under ``a``; what rests on the same floor
    is not). Along a local axis that is vertical (up or down) the box is stretched; a tilted
    box's column is the axis-aligned one under its world box. Returns the columns and their
    half sizes with the box's own height for the column's (P, 3): what a thin box's tolerance
    is taken from (:func:`sat_excess`)."""
    p = a.centre.shape[0]
    top, ground = bottom, np.full(p, -tol)
    vertical = np.abs(a.axes[:, 2, :]) > 1 - 1e-9  # (P, 3): which local axis is vertical
    upright = vertical.any(axis=1)
    axes = np.where(upright[:, None, None], a.axes, np.eye(3))
    lo, hi = a.lo.copy(), a.hi.copy()
    origin = a.origin.copy()
    k = np.argmax(vertical, axis=1)
    rows = np.flatnonzero(upright)
    sign = a.axes[rows, 2, k[rows]]
    z0 = origin[rows, 2]
    lo[rows, k[rows]] = np.minimum((ground[rows] - z0) * sign, (top[rows] - z0) * sign)
    hi[rows, k[rows]] = np.maximum((ground[rows] - z0) * sign, (top[rows] - z0) * sign)
    radii = a.half.copy()  # upright: the box's own half sizes along the column's axes
    tilted = np.flatnonzero(~upright)
    if tilted.size:
        corners = _world_hull(a.take(tilted))
        origin[tilted] = 0.0
        lo[tilted], hi[tilted] = corners[0], corners[1]
        radii[tilted] = (corners[1] - corners[0]) / 2
        lo[tilted, 2], hi[tilted, 2] = ground[tilted], top[tilted]
    poses = np.zeros((p, 4, 4))
    poses[:, :3, :3], poses[:, :3, 3], poses[:, 3, 3] = axes, origin, 1.0
    return Boxes.of(poses, lo, hi), radii


def _world_hull(a: Boxes) -> tuple[np.ndarray, np.ndarray]:
    half = np.einsum("pij,pj->pi", np.abs(a.axes), a.half)
    return a.centre - half, a.centre + half


# --- kit designs -------------------------------------------------------------------------------

#: the rule of a kit design's slot whose part would not lie in (or on) the design's kit tray
SLOT_OUTSIDE = "slot-outside-tray"
#: where a slot's part leaves its tray (:func:`slot_misfits`' ``side``)
SIDES = ("-x", "+x", "-y", "+y", "below", "above")


@np.errstate(over="ignore", invalid="ignore")
def slot_misfits(pose: np.ndarray, part_lo: np.ndarray, part_hi: np.ndarray, tray_lo: np.ndarray,
                 tray_hi: np.ndarray, tol: float = DEFAULT_TOLERANCE) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Which of N kit design slots would put their part outside the kit tray.

    ``pose`` (N, 4, 4): each slot's pose in its tray's frame (as a kit design gives it: the
    part's frame, the middle of its bottom, goes there); ``part_lo``, ``part_hi``,
    ``tray_lo``, ``tray_hi`` (N, 3): the part's and the tray's boxes in their own frames, in
    metres. A part lies in (or on) its tray when its box, turned by the slot's pose, is within
    the tray's walls in plan and neither below the tray's floor nor above its top (a part may
    stick out of an open tray's top, as NIST's, exactly as tall as their tray, do), each by at
    most the tolerance: ``tol``, or half the part's extent along that axis where that is less
    (:func:`kb.spatial.rcc8.depth_tolerance`: a washer 0.343 mm thick is out once half of it
    is). Returns (misfit (N,) bool, by how much (N,) metres, side (N,) index into
    :data:`SIDES`: the side it is furthest out of, beyond its tolerance)."""
    n = pose.shape[0]
    if n == 0:
        return np.zeros(0, bool), np.zeros(0), np.zeros(0, np.intp)
    box = Boxes.of(pose, part_lo, part_hi)
    lo, hi = _world_hull(box)  # in the tray's frame
    out = np.stack([tray_lo[:, 0] - lo[:, 0], hi[:, 0] - tray_hi[:, 0], tray_lo[:, 1] - lo[:, 1],
                    hi[:, 1] - tray_hi[:, 1], tray_lo[:, 2] - lo[:, 2], lo[:, 2] - tray_hi[:, 2]], axis=1)
    out = np.where(np.isnan(out), np.inf, out)  # a number that is not one fits nowhere
    allowed = np.repeat(depth_tolerance(tol, hi - lo), 2, axis=1)  # (N, 6): per side, by the part's extent
    side = np.argmax(out - allowed, axis=1)
    rows = np.arange(n)
    return out[rows, side] > allowed[rows, side], out[rows, side], side


def describe_misfit(slot: str, design: str, part: str, tray: str, by: float, side: int, part_size: np.ndarray,
                    tray_size: np.ndarray, units: Units = SI) -> str:
    """One sentence for a slot :func:`slot_misfits` found (names as the file spells them,
    lengths in its unit): ``slot :s of :d puts its part (:sku_b, 0.12 x 0.06 m) 0.12 m beyond
    the +x side of its kit tray (:sku_kit_tray, 0.5 x 0.4 m)``."""
    def size(s: np.ndarray) -> str:
        if not np.all(np.isfinite(s[:2])):
            return "of no usable size"
        length, width = (length_text(float(v), units) for v in s[:2])
        return f"{length.rsplit(' ', 1)[0]} x {width}"
    where = {"below": "below the floor", "above": "above the top"}.get(SIDES[side], f"beyond the {SIDES[side]} side")
    amount = length_text(by, units) if math.isfinite(by) else "an unknown distance"
    return (f"slot {slot} of {design} puts its part ({part}, {size(part_size)}) {amount} {where} of its kit tray "
            f"({tray}, {size(tray_size)})")


__all__ = ["FACES", "FLOATING", "INTERPENETRATION", "RULES", "SIDES", "SLOT_OUTSIDE", "Boxes", "Finding", "check",
           "describe", "describe_misfit", "in_frame_of", "overlapping_pairs", "sat_depth", "sat_excess", "slot_misfits",
           "thin_boxes"]


def describe(f: Finding, name: Callable[[str], str], units: Units = SI) -> str:
    """One sentence for finding ``f``: objects spelled by ``name`` (IRI -> text), lengths in the
    file's length unit with four significant digits (``"20 mm"``, ``"0.7874 in"``). Through an
    open container, each face with how far the object reaches beyond it, which a reader checks
    against the object's box in the container's frame (``:GearBox_top_1 goes through the -y wall
    of :GearBox_top_tray, 91.5 mm beyond it, and through its floor, 47.8 mm below it``)."""
    obj = name(f.obj)
    other = name(f.other) if f.other else None
    depth = length_text(f.depth, units)
    if f.rule == FLOATING:
        below = {"floor": f"the floor of {other}", "top": str(other)}.get(f.how, "the ground (z = 0)")
        return f"{obj} floats {depth} above {below}"
    if f.how == "ground":
        return f"{obj} is {depth} below the ground (z = 0 of the workstation)"
    if f.how in ("floor", "wall"):
        if not f.faces:
            return f"{obj} goes {depth} through {'the floor' if f.how == 'floor' else 'a wall'} of {other}"
        parts = [_through(face, beyond, inside, units) for face, beyond, inside in f.faces]
        face, where = parts[0]
        text = f"{obj} goes through {face} of {other}, {where}"
        for face, where in parts[1:]:
            text += f", and through {face.replace('the ', 'its ', 1)}, {where}"
        return text
    return f"{obj} and {other} interpenetrate by {depth}"


def _through(face: str, beyond: float, inside: float, units: Units) -> tuple[str, str]:
    """(the face's name, where the object reaches) for one face of a container an object goes
    through: ``("the -y wall", "91.5 mm beyond it")``, ``("the floor", "0.3 mm below it and
    0.043 mm above")``: how far beyond the face and, when that is the larger part of it, how
    far on the cavity's side (a part beside a tray, its edge in the wall)."""
    floor = face == "floor"
    name = "the floor" if floor else f"the {face} wall"
    where = f"{length_text(beyond, units)} {'below' if floor else 'beyond'} it"
    if beyond > inside:
        where += f" and {length_text(max(inside, 0.0), units)} {'above' if floor else 'inside'}"
    return name, where


def length_text(metres: float, units: Units = SI) -> str:
    """``metres`` in the file's length unit with four significant digits."""
    value = abs(units.from_si("length", metres))
    digits = max(0, 3 - math.floor(math.log10(value))) if value > 0 else 0
    return units.length_text(metres, digits)
