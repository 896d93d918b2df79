"""Continuous contact: does a moving oriented box pass *through* a solid along a move?

A move carries a frame (the robot's tool tip) from one pose to the next through waypoints;
boxes fixed to the frame (the tool flange, the mounted end effector, the held object and what
rests in it) sweep a volume. :func:`sweep_contacts` finds the solids that volume enters, over
the whole path, not at sampled instants: a 5 mm part is found at any speed.

Contact
    Two boxes are in contact when their interiors overlap by more than the tolerance
    (:data:`kb.spatial.rcc8.DEFAULT_TOLERANCE`, 1 mm): the distance the one must be moved to
    leave the other (the minimum translation distance, the penetration depth) is more than
    ``tol``. Touching faces (RCC8 EC within the tolerance: a part on a floor, against a wall)
    are not in contact. For axis-aligned boxes this is "neither DC nor EC on any axis" of
    :mod:`kb.spatial.rcc8`.

Solids (:func:`solid_pieces`)
    A closed object (``open_top`` false: a part, a table, a station base) is its box. An open
    container (a tray, a large box, an effector holder) is its floor and its four walls, each a
    plate of no thickness on a face of its box: a part lying in a tray (the scenarios' parts
    stand on the tray's floor and stick out above its rim) is not in contact with the tray,
    a part lowered in from above is not either, a part moved sideways through the rim is. An
    open container recessed in a closed object (an effector holder in the changing station's
    base: the holder's box inside the base's, axes alike) is a hole in it: the base is its
    box less the column from the holder's floor up through the base's top, as up to five
    boxes per hole.

Swept volume, exactly (the separating axis test)
    Within a stretch of the path where the frame turns by a small angle, each moving box is
    taken at the stretch's middle orientation, inflated by the most any of its points moves
    when turned by half that angle (``2 r sin(angle / 4)``, ``r`` its farthest corner from the
    frame's origin), and swept along the stretch's translation ``d``: a box plus a segment plus
    a ball, which holds the real swept volume. The separating axis theorem decides the
    penetration depth of two convex polytopes on a finite set of axes: for a box (axes u) swept
    along d against a box (axes v) these are u, v, u x d, u x v and d x v (21 axes). The
    projection of a box swept along d on a unit axis L is the box's, widened by
    ``min(0, L.d)`` below and ``max(0, L.d)`` above (and by the inflation on both sides). The
    smallest depth over the axes is the penetration depth; any one axis's depth is at least
    that, so a nearly degenerate cross product is a safe axis. A move that does not turn is
    one stretch per leg; a turning one is cut into stretches that keep the inflation under
    ``max_inflation`` (default a quarter of the tolerance, so touching never reads as contact).

Vectorised with numpy: the pairs of (stretch, moving box) x (solid piece) whose axis-aligned
swept boxes meet are tested together, 21 axes per pair in a handful of array operations. The
pairs are found in two levels (a turning leg has hundreds of stretches): the pieces the box
around the whole path meets, then runs of consecutive swept boxes against those, then the
boxes of the runs that meet a piece (:func:`_overlapping`: the pairs of the dense test, no
fewer, in its order, so the results are those of the dense test to the last bit). Before a
turning leg's stretches are made, one box around all of them (:func:`_reach_box`, from how far
the boxes reach and how far the leg turns them) is tested against the pieces: a leg whose box
meets none has no contact, and :func:`clearance` asked for a rise above a height the caller
lifts to anyway answers without the stretches when the box shows there is none.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from kb.spatial.frames import world_boxes
from kb.spatial.rcc8 import DEFAULT_TOLERANCE

__all__ = ["Contact", "Pieces", "clearance", "recessed", "solid_pieces", "sweep_contacts"]

FloatArray = NDArray[np.float64]
#: Most stretches a turning leg is cut into (beyond, the inflation grows instead).
MAX_STRETCHES = 4096
#: Moving boxes per run in the first level of the pairs' test (:func:`_overlapping`).
CHUNK = 48
#: Stretches beyond which a path's swept boxes are first bounded by one box (:func:`_reach_box`).
FEW = 8


@dataclass(frozen=True)
class Pieces:
    """Solid pieces of objects, each an axis-aligned box in its object's frame: ``owner``
    (P,) the object's index, ``lo``, ``hi`` (P, 3) the corners (lo == hi on one axis: a plate)."""

    owner: NDArray[np.intp]
    lo: FloatArray
    hi: FloatArray

    def __len__(self) -> int:
        return len(self.owner)

    def select(self, keep: NDArray[np.bool_]) -> "Pieces":
        """The pieces where ``keep`` (P,) is true."""
        return Pieces(self.owner[keep], self.lo[keep], self.hi[keep])


@dataclass(frozen=True)
class Contact:
    """A moving box entered a solid: ``body`` (index of the moving box), ``owner`` (index of
    the object), ``leg`` (the first leg of the path where it did) and ``depth`` (m, the largest
    penetration depth found on that leg)."""

    body: int
    owner: int
    leg: int
    depth: float


# ---------------------------------------------------------------------------------------------
# Solids as pieces
# ---------------------------------------------------------------------------------------------

def _plates(lo: FloatArray, hi: FloatArray) -> tuple[FloatArray, FloatArray]:
    """(5 K, 3) lo, hi: the floor and four walls of open boxes (lo, hi: (K, 3))."""
    plo, phi = [], []
    floor_hi = hi.copy()
    floor_hi[:, 2] = lo[:, 2]
    plo.append(lo), phi.append(floor_hi)
    for axis in (0, 1):
        for side in (lo, hi):
            a, b = lo.copy(), hi.copy()
            a[:, axis] = b[:, axis] = side[:, axis]
            plo.append(a), phi.append(b)
    k = len(lo)
    return np.stack(plo, 1).reshape(5 * k, 3), np.stack(phi, 1).reshape(5 * k, 3)


def _carve(lo: FloatArray, hi: FloatArray, clo: FloatArray, chi: FloatArray) -> list[tuple[FloatArray, FloatArray]]:
    """Box [lo, hi] less box [clo, chi] (one frame) as up to six boxes."""
    if np.any(np.minimum(hi, chi) <= np.maximum(lo, clo)):
        return [(lo, hi)]
    out = []
    rest_lo, rest_hi = lo.copy(), hi.copy()
    for axis in range(3):
        if clo[axis] > rest_lo[axis]:
            a, b = rest_lo.copy(), rest_hi.copy()
            b[axis] = clo[axis]
            out.append((a, b))
        if chi[axis] < rest_hi[axis]:
            a, b = rest_lo.copy(), rest_hi.copy()
            a[axis] = chi[axis]
            out.append((a, b))
        rest_lo[axis], rest_hi[axis] = max(rest_lo[axis], clo[axis]), min(rest_hi[axis], chi[axis])
    return out


def recessed(poses: FloatArray, local_lo: FloatArray, local_hi: FloatArray, open_top: NDArray[np.bool_],
             candidates: NDArray[np.intp], tol: float = DEFAULT_TOLERANCE) -> dict[int, list[tuple[FloatArray, FloatArray]]]:
    """Closed objects with open containers recessed in them -> their pieces in their own frame.

    Among ``candidates`` (indices of placed objects), an open container j whose box lies inside
    a closed object i's box (within ``tol``; its axes along i's, up to a quarter turn about
    i's z) makes i its box less the column from j's floor up through i's top. Objects with
    no hole are not in the result."""
    cand = np.asarray(candidates, np.intp)
    holes = cand[open_top[cand]]
    closed = cand[~open_top[cand]]
    out: dict[int, list[tuple[FloatArray, FloatArray]]] = {}
    if not len(holes) or not len(closed):
        return out
    wlo, whi = world_boxes(poses[cand], local_lo[cand], local_hi[cand])
    where = {int(c): k for k, c in enumerate(cand.tolist())}
    hl, hh = wlo[[where[j] for j in holes.tolist()]], whi[[where[j] for j in holes.tolist()]]
    cl, ch = wlo[[where[i] for i in closed.tolist()]], whi[[where[i] for i in closed.tolist()]]
    inside = np.all((hl[None, :, :] >= cl[:, None, :] - tol) & (hh[None, :, :] <= ch[:, None, :] + tol), axis=2)
    for a, b in zip(*np.nonzero(inside)):
        out.setdefault(int(closed[a]), []).append(int(holes[b]))
    found, out = out, {}
    for i, inner in found.items():
        inv = np.linalg.inv(poses[i])
        ilo, ihi = local_lo[i], local_hi[i]
        pieces = [(ilo.copy(), ihi.copy())]
        for j in inner:
            rel = inv @ poses[j]
            r = rel[:3, :3]
            if not (np.allclose(np.abs(r), np.round(np.abs(r)), atol=1e-6) and abs(r[2, 2] - 1.0) < 1e-6):
                continue  # not axis aligned with i, or tilted: no hole
            corners = np.array([[x, y, z] for x in (local_lo[j, 0], local_hi[j, 0])
                                for y in (local_lo[j, 1], local_hi[j, 1]) for z in (local_lo[j, 2], local_hi[j, 2])])
            pts = corners @ r.T + rel[:3, 3]
            jlo, jhi = pts.min(axis=0), pts.max(axis=0)
            if not (np.all(jlo >= ilo - tol) and np.all(jhi <= ihi + tol)):
                continue
            chi = jhi.copy()
            chi[2] = ihi[2] + 1.0  # the column is open upwards, through the top
            pieces = [p for lo, hi in pieces for p in _carve(lo, hi, jlo, chi)]
        if len(pieces) != 1 or not (np.array_equal(pieces[0][0], ilo) and np.array_equal(pieces[0][1], ihi)):
            out[i] = pieces
    return out


def solid_pieces(local_lo: FloatArray, local_hi: FloatArray, open_top: NDArray[np.bool_],
                 objects: NDArray[np.intp], holes: dict[int, list[tuple[FloatArray, FloatArray]]] | None = None) -> Pieces:
    """The solid pieces of ``objects`` (indices), in their own frames: a closed object's box
    (or its pieces in ``holes``, from :func:`recessed`), an open container's floor and walls."""
    objs = np.asarray(objects, np.intp)
    holes = holes or {}
    shell = objs[open_top[objs]]
    plain = np.array([i for i in objs[~open_top[objs]].tolist() if i not in holes], np.intp)
    carved = [(i, lo, hi) for i in objs.tolist() if i in holes for lo, hi in holes[i]]
    slo, shi = _plates(local_lo[shell], local_hi[shell])
    owner = [plain, np.repeat(shell, 5), np.array([c[0] for c in carved], np.intp)]
    los = [local_lo[plain], slo, np.array([c[1] for c in carved]).reshape(-1, 3)]
    his = [local_hi[plain], shi, np.array([c[2] for c in carved]).reshape(-1, 3)]
    return Pieces(np.concatenate(owner).astype(np.intp), np.concatenate(los), np.concatenate(his))


# ---------------------------------------------------------------------------------------------
# The sweep
# ---------------------------------------------------------------------------------------------

def _axis_angle(r: FloatArray) -> tuple[FloatArray, float]:
    """(unit axis, angle in [0, pi]) of a rotation matrix."""
    c = min(max(float((r[0, 0] + r[1, 1] + r[2, 2] - 1.0) / 2.0), -1.0), 1.0)  # np.clip's value (NaN stays NaN), without its overhead
    angle = math.acos(c)
    if angle < 1e-12:
        return np.array([0.0, 0.0, 1.0]), 0.0
    w = np.array([r[2, 1] - r[1, 2], r[0, 2] - r[2, 0], r[1, 0] - r[0, 1]])
    if math.sin(angle) > 1e-6:
        return w / np.linalg.norm(w), angle
    sym = (r + np.eye(3)) / 2.0  # angle near pi: the axis is the column of (R + I) / 2 with most weight
    k = int(np.argmax(np.diag(sym)))
    axis = sym[:, k] / math.sqrt(max(sym[k, k], 1e-300))
    return axis / np.linalg.norm(axis), angle


def _turns(axis: FloatArray, angles: FloatArray) -> FloatArray:
    """(n, 3, 3) the rotations by each of ``angles`` about the unit ``axis`` (Rodrigues)."""
    k = np.array([[0.0, -axis[2], axis[1]], [axis[2], 0.0, -axis[0]], [-axis[1], axis[0], 0.0]])
    return (np.eye(3) + np.sin(angles)[:, None, None] * k
            + (1.0 - np.cos(angles))[:, None, None] * (k @ k))


def _stretches(path: FloatArray, reach: float, max_inflation: float) -> tuple[NDArray[np.intp], FloatArray,
                                                                               FloatArray, FloatArray, FloatArray]:
    """Each leg of ``path`` (P, 4, 4) cut into stretches: (leg of each, rotation (S, 3, 3) at its
    middle, frame origin (S, 3) at its start, its translation (S, 3), inflation (S,))."""
    legs = [_leg(path[k], path[k + 1], k, reach, max_inflation) for k in range(len(path) - 1)]
    if len(legs) == 1:
        return legs[0]
    return tuple(np.concatenate(part) for part in zip(*legs))  # type: ignore[return-value]


def _leg(a: FloatArray, b: FloatArray, k: int, reach: float, max_inflation: float) -> tuple:
    """The stretches of leg ``k`` from pose ``a`` to ``b`` (:func:`_stretches`)."""
    axis, angle = _axis_angle(a[:3, :3].T @ b[:3, :3])
    t0, t1 = a[:3, 3], b[:3, 3]
    if not angle > 0.0:  # one stretch: the arrays the general case makes for n = 1, made directly
        return (np.array([k], np.intp), a[None, :3, :3].copy(), (t0 + 0.0 * (t1 - t0))[None], ((t1 - t0) / 1)[None],
                np.array([2.0 * reach * math.sin(angle / 1 / 4.0)]))
    n = 1
    if reach > 0.0:
        step = 4.0 * math.asin(min(1.0, max_inflation / (2.0 * reach)))
        n = max(1, min(MAX_STRETCHES, math.ceil(angle / step)))
    first = np.arange(n) / n
    return (np.full(n, k, np.intp), a[:3, :3] @ _turns(axis, (first + 0.5 / n) * angle),
            t0 + first[:, None] * (t1 - t0), np.broadcast_to((t1 - t0) / n, (n, 3)).copy(),
            np.full(n, 2.0 * reach * math.sin(angle / n / 4.0)))


def _depths(ua: FloatArray, a: FloatArray, ca: FloatArray, d: FloatArray, grow: FloatArray,
            vb: FloatArray, b: FloatArray, cb: FloatArray) -> FloatArray:
    """(K,) penetration depth of box A (axes ``ua`` (K, 3, 3) as columns, half sizes ``a``,
    centre ``ca`` at the start) swept along ``d`` and inflated by ``grow``, into box B (``vb``,
    ``b``, ``cb``); at most 0 where they are apart."""
    k = len(a)
    u, v = np.swapaxes(ua, 1, 2), np.swapaxes(vb, 1, 2)  # (K, 3 axes, 3 components)
    norm = np.linalg.norm(d, axis=1, keepdims=True)
    dn = np.divide(d, norm, out=np.zeros_like(d), where=norm > 0)[:, None, :]
    axes = np.concatenate([u, v, np.cross(u, dn), np.cross(u[:, :, None, :], v[:, None, :, :]).reshape(k, 9, 3),
                           np.cross(dn, v)], axis=1)  # (K, 21, 3)
    length = np.linalg.norm(axes, axis=2)
    valid = length > 1e-9
    axes = axes / np.where(valid, length, 1.0)[:, :, None]
    ra = (np.abs(np.einsum("kla,kia->kli", axes, u)) * a[:, None, :]).sum(axis=2) + grow[:, None]
    rb = (np.abs(np.einsum("kla,kia->kli", axes, v)) * b[:, None, :]).sum(axis=2)
    c = np.einsum("kla,ka->kl", axes, cb - ca)
    dl = np.einsum("kla,ka->kl", axes, d)
    depth = np.minimum(ra + np.maximum(dl, 0.0) + rb - c, c + rb + ra - np.minimum(dl, 0.0))
    depth = np.where(valid, depth, np.inf)
    return depth.min(axis=1)


def _moving_boxes(path: FloatArray, rel: FloatArray, blo: FloatArray, bhi: FloatArray, tol: float,
                  max_inflation: float | None) -> tuple:
    """The moving boxes of each stretch of ``path``: (legs, axes (S, M, 3, 3), centres at the
    stretch's start (S, M, 3), half sizes (M, 3), translation (S, 3), inflation (S,), world
    boxes lo, hi (S, M, 3) of each box swept along its stretch)."""
    half_a, centre_a, reach = _in_frame(rel, blo, bhi)
    legs, rots, starts, moves, grow = _stretches(path, reach, tol / 4.0 if max_inflation is None else max_inflation)
    return (legs, *_swept_boxes(rots, starts, moves, grow, rel, centre_a, half_a))


def _in_frame(rel: FloatArray, blo: FloatArray, bhi: FloatArray) -> tuple[FloatArray, FloatArray, float]:
    """The moving boxes in the moving frame: (half sizes (M, 3), centres (M, 3), the farthest
    any of their points is from the frame's origin)."""
    half_a = (bhi - blo) / 2.0
    centre_a = np.einsum("mij,mj->mi", rel[:, :3, :3], (blo + bhi) / 2.0) + rel[:, :3, 3]
    reach = float((_norms(centre_a) + _norms(half_a)).max())
    return half_a, centre_a, reach


def _norms(x: FloatArray, axis: int = 1) -> FloatArray:
    """``np.linalg.norm(x, axis=axis)`` of a real array: the same sums and square roots,
    without its argument handling (called thousands of times on arrays of a few rows)."""
    return np.sqrt(np.add.reduce(x * x, axis=axis))


def _swept_boxes(rots: FloatArray, starts: FloatArray, moves: FloatArray, grow: FloatArray, rel: FloatArray,
                 centre_a: FloatArray, half_a: FloatArray) -> tuple:
    """(axes (S, M, 3, 3), centres at the stretch's start (S, M, 3), half sizes (M, 3),
    translation (S, 3), inflation (S,), world boxes lo, hi (S, M, 3) swept along each stretch)."""
    ua = np.einsum("sij,mjk->smik", rots, rel[:, :3, :3])
    ca = np.einsum("sij,mj->smi", rots, centre_a) + starts[:, None, :]
    ext_a = np.einsum("smij,mj->smi", np.abs(ua), half_a) + grow[:, None, None]
    lo_a = np.minimum(ca, ca + moves[:, None, :]) - ext_a
    hi_a = np.maximum(ca, ca + moves[:, None, :]) + ext_a
    return ua, ca, half_a, moves, grow, lo_a, hi_a


def _reach_box(rots: FloatArray, starts: FloatArray, moves: FloatArray, grow: FloatArray, rel: FloatArray,
               centre_a: FloatArray, half_a: FloatArray) -> tuple[FloatArray, FloatArray]:
    """(lo, hi) (3,): a box that holds every swept box of a path (rounding allowed for), made
    without them. In x and y, a moving box's point is within |its centre| + the lengths of its
    half axes of the frame's origin; in z, the z row of each stretch's rotation is within
    ``turn`` of the first stretch's (a move turning about the tool's axis, held upright, keeps
    its heights)."""
    size = _norms(centre_a) + (_norms(rel[:, :3, :3]) * half_a).sum(axis=1)
    end = starts + moves
    lo, hi = np.minimum(starts, end).min(axis=0), np.maximum(starts, end).max(axis=0)
    biggest = float(size.max())
    slack = 1e-9 * (1.0 + biggest + float(np.abs(lo).max()) + float(np.abs(hi).max()))
    grown = float(grow.max()) + slack
    xy = math.sqrt(float((rots[:, :2] ** 2).sum(axis=2).max())) * biggest * (1.0 + 1e-9) + grown
    z0 = rots[0, 2]
    turn = math.sqrt(float(((rots[:, 2] - z0) ** 2).sum(axis=1).max()))
    mid = centre_a @ z0
    half = (np.abs(z0 @ rel[:, :3, :3]) * half_a).sum(axis=1) + turn * size * (1.0 + 1e-9)
    return (np.array([lo[0] - xy, lo[1] - xy, lo[2] + float((mid - half).min()) - grown]),
            np.array([hi[0] + xy, hi[1] + xy, hi[2] + float((mid + half).max()) + grown]))


def _highest_top(box: tuple[FloatArray, FloatArray], blo: FloatArray, bhi: FloatArray, tol: float) -> float:
    """At least the largest (piece's top - swept box's bottom) :func:`clearance` can find, from
    a box around the swept boxes (:func:`_reach_box`): the top of the highest piece that box
    crosses in x and y, less its bottom; ``-inf`` when it crosses none."""
    lo, hi = box
    near = (np.minimum(hi[:2] - blo[:, :2], bhi[:, :2] - lo[:2]) > tol).all(axis=1)
    return float(bhi[near, 2].max()) - float(lo[2]) if near.any() else -math.inf


#: the last pieces placed in the world by :func:`_piece_boxes`: (pieces, their owners' poses' bytes, result)
_placed: list[tuple[Pieces, bytes, tuple]] = []


def _piece_boxes(poses: FloatArray, pieces: Pieces) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray, FloatArray]:
    """Pieces in the world: (axes (P, 3, 3), half sizes, centres, world box lo, hi). The last
    result is kept while the pieces are the same object and their owners' poses the same to the
    bit (a robot's moves sweep the same solids, which stand still, leg after leg); the arrays
    returned are not to be written to."""
    g = poses[pieces.owner]
    key = g.tobytes()
    if _placed and _placed[0][0] is pieces and _placed[0][1] == key:
        return _placed[0][2]
    found = _place(g, pieces)
    for array in found:
        array.flags.writeable = False
    _placed[:] = [(pieces, key, found)]
    return found


def _place(g: FloatArray, pieces: Pieces) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray, FloatArray]:
    vb = g[:, :3, :3]
    half_b = (pieces.hi - pieces.lo) / 2.0
    cb = np.einsum("pij,pj->pi", vb, (pieces.lo + pieces.hi) / 2.0) + g[:, :3, 3]
    ext_b = np.einsum("pij,pj->pi", np.abs(vb), half_b)
    return vb, half_b, cb, cb - ext_b, cb + ext_b


def clearance(path: ArrayLike, body_rel: ArrayLike, body_lo: ArrayLike, body_hi: ArrayLike, poses: ArrayLike,
              pieces: Pieces, tol: float = DEFAULT_TOLERANCE, above: float = -math.inf) -> float:
    """How high (m) the moving frame must be lifted so that the boxes it carries along ``path``
    pass above every solid piece whose world box their way crosses in x and y (more than
    ``tol`` deep): the largest (piece's top - box's bottom) over those, with the path as given;
    ``-inf`` when none is under the way. (Decided on world boxes: it may lift more than the
    oriented boxes need, never less.) ``above``: a height the frame will be lifted to anyway;
    when a bound made before the swept boxes shows the clearance is no more than that, the
    result is ``-inf`` (the swept boxes are not made)."""
    path = np.asarray(path, float)
    rel = np.asarray(body_rel, float)
    if len(path) < 2 or not len(rel) or not len(pieces):
        return -math.inf
    half_a, centre_a, reach = _in_frame(rel, np.asarray(body_lo, float), np.asarray(body_hi, float))
    legs, rots, starts, moves, grow = _stretches(path, reach, tol / 4.0)
    *_, blo, bhi = _piece_boxes(np.asarray(poses, float), pieces)
    if above > -math.inf and _highest_top(_reach_box(rots, starts, moves, grow, rel, centre_a, half_a), blo, bhi,
                                          tol) <= above:
        return -math.inf
    *_, lo_a, hi_a = _swept_boxes(rots, starts, moves, grow, rel, centre_a, half_a)
    lo_z = lo_a[..., 2].reshape(-1)
    lo_a, hi_a = lo_a[..., :2].reshape(-1, 2), hi_a[..., :2].reshape(-1, 2)
    # the pieces that the box around the whole way crosses (fmin, fmax: a NaN box, which
    # crosses nothing, does not hide the others), then the boxes that cross each
    whole_lo, whole_hi = np.fmin.reduce(lo_a, axis=0, keepdims=True), np.fmax.reduce(hi_a, axis=0, keepdims=True)
    near = np.flatnonzero(_deep(whole_lo, whole_hi, blo[:, :2], bhi[:, :2], tol)[0])
    q, p = _overlapping(lo_a, hi_a, blo[near, :2], bhi[near, :2], tol)
    if not len(q):
        return -math.inf
    return float(np.max(bhi[near[p], 2] - lo_z[q]))


def _overlapping(lo_a: FloatArray, hi_a: FloatArray, lo_b: FloatArray, hi_b: FloatArray, tol: float,
                 chunk: int = CHUNK) -> tuple[NDArray[np.intp], NDArray[np.intp]]:
    """(rows of A, rows of B) of the boxes A (``lo_a``, ``hi_a``: (Q, D)) and B ((P, D)) that
    overlap by more than ``tol`` on every axis, as ``np.nonzero`` of the dense (Q, P) test
    gives them (same pairs, same order). The dense test is made only within the runs of
    ``chunk`` consecutive rows of A whose bounding box meets a B that way: a box inside a
    run's bounding box overlaps B by no more than the run's box does (rounding is monotone),
    so no pair is lost."""
    q_n = len(lo_a)
    if q_n <= chunk:
        return np.nonzero(_deep(lo_a, hi_a, lo_b, hi_b, tol))
    starts = np.arange(0, q_n, chunk)
    # fmin / fmax: a NaN row (never overlapping) does not hide the other rows of its run
    c, p = np.nonzero(_deep(np.fmin.reduceat(lo_a, starts, axis=0), np.fmax.reduceat(hi_a, starts, axis=0),
                            lo_b, hi_b, tol))
    if not len(c):
        return c, p
    rows = c[:, None] * chunk + np.arange(chunk)  # (K, chunk): the rows of each run met
    inside = rows < q_n
    rows = np.where(inside, rows, q_n - 1)
    bl, bh = lo_b[p][:, None, :], hi_b[p][:, None, :]
    hit = np.all(np.minimum(hi_a[rows] - bl, bh - lo_a[rows]) > tol, axis=2) & inside
    k, j = np.nonzero(hit)
    q, p = rows[k, j], p[k]
    order = np.lexsort((p, q))
    return q[order], p[order]


def _deep(lo_a: FloatArray, hi_a: FloatArray, lo_b: FloatArray, hi_b: FloatArray, tol: float) -> NDArray[np.bool_]:
    """(Q, P): box a of A overlaps box b of B by more than ``tol`` on every axis."""
    return np.all(np.minimum(hi_a[:, None, :] - lo_b[None, :, :], hi_b[None, :, :] - lo_a[:, None, :]) > tol, axis=2)


def sweep_contacts(path: ArrayLike, body_rel: ArrayLike, body_lo: ArrayLike, body_hi: ArrayLike,
                   poses: ArrayLike, pieces: Pieces, tol: float = DEFAULT_TOLERANCE,
                   max_inflation: float | None = None) -> list[Contact]:
    """The solids the moving boxes enter along ``path``, one :class:`Contact` per (box, object).

    ``path`` (P, 4, 4): the moving frame's poses, start then each waypoint (straight legs,
    the orientation turning uniformly along each); ``body_rel`` (M, 4, 4): each moving box's
    pose in that frame, ``body_lo``, ``body_hi`` (M, 3) its local corners; ``poses`` the
    objects' global poses (indexed by ``pieces.owner``), ``pieces`` their solid pieces
    (:func:`solid_pieces`). Contact: penetration depth above ``tol`` (module docstring)."""
    path = np.asarray(path, float)
    rel = np.asarray(body_rel, float)
    if len(path) < 2 or not len(rel) or not len(pieces):
        return []
    half_a, centre_a, reach = _in_frame(rel, np.asarray(body_lo, float), np.asarray(body_hi, float))
    legs, rots, starts, moves, grow = _stretches(path, reach, tol / 4.0 if max_inflation is None else max_inflation)
    vb, half_b, cb, blo, bhi = _piece_boxes(np.asarray(poses, float), pieces)
    if len(legs) > FEW:  # a turning leg: first a box around the whole way, made without its stretches
        lo, hi = _reach_box(rots, starts, moves, grow, rel, centre_a, half_a)
        if not (np.minimum(hi - blo, bhi - lo) > tol).all(axis=1).any():
            return []
    ua, ca, half_a, moves, grow, lo_a, hi_a = _swept_boxes(rots, starts, moves, grow, rel, centre_a, half_a)
    s_n, m_n = lo_a.shape[:2]
    lo_a, hi_a = lo_a.reshape(-1, 3), hi_a.reshape(-1, 3)
    # broad phase: swept world boxes against piece world boxes, more than tol deep on every
    # axis (the distance to push one out of the other along the axis: a plate inside a box is
    # as deep as the box reaches on its thinner side)
    whole_lo, whole_hi = lo_a.min(axis=0), hi_a.max(axis=0)
    near = np.flatnonzero((np.minimum(whole_hi - blo, bhi - whole_lo) > tol).all(axis=1))
    if not len(near):
        return []
    q, p = _overlapping(lo_a, hi_a, blo[near], bhi[near], tol)
    if not len(q):
        return []
    pi = near[p]
    si, mi = q // m_n, q % m_n
    depth = _depths(ua[si, mi], half_a[mi], ca[si, mi], moves[si], grow[si], vb[pi], half_b[pi], cb[pi])
    hit = depth > tol
    found: dict[tuple[int, int], Contact] = {}
    for s, m, piece, dep in zip(si[hit].tolist(), mi[hit].tolist(), pi[hit].tolist(), depth[hit].tolist()):
        key = (m, int(pieces.owner[piece]))
        leg = int(legs[s])
        old = found.get(key)
        if old is None or leg < old.leg or (leg == old.leg and dep > old.depth):
            found[key] = Contact(m, key[1], leg, dep)
    return sorted(found.values(), key=lambda c: (c.leg, c.body, c.owner))
