"""Frames turned about z, for relations decided in the frame of their object (docs/soap.md,
"Orientation"): the world box of an oriented box (:func:`world_boxes`), the heading of a pose
(:func:`headings`), poses grouped into shared frames (:func:`heading_groups`) and boxes in a
frame turned by a yaw (:func:`frame_boxes`). :mod:`kb.spatial.rcc8` decides the relations on
these boxes and names all of them too.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["HEADING_MERGE", "frame_boxes", "heading_groups", "headings", "world_boxes"]

FloatArray = NDArray[np.float64]


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


# ---------------------------------------------------------------------------------------------
# Oriented boxes: headings and frames turned about z
# ---------------------------------------------------------------------------------------------
#
# A relation is decided in the frame of its object (the container, the support): the world
# frame turned about z by the object's heading. There the object's box is exact when the
# object is turned about z only (any rotation whose local axes are, up to a yaw, the world's),
# and the subject's box is the axis-aligned hull of its oriented box in that frame. Vertical
# stays vertical, so Z-Plus / Z-Minus ("on top", "under") keep their meaning whatever the
# object's rotation. Objects whose headings agree (within HEADING_MERGE) share a frame, so the
# kernel runs once per group of objects: one group (heading 0, the world boxes themselves) when
# everything is axis aligned, one more per differently turned tray and what it holds.

#: Headings (radians) closer than this share a frame (a 1 m box turned by it moves 10 um).
HEADING_MERGE = 1e-5
_QUARTER = np.pi / 2


def headings(poses: ArrayLike) -> FloatArray:
    """(K,) the heading of each pose, in [-pi/4, pi/4): the yaw of the frame, turned about the
    world's z axis, in which the pose's local box is axis aligned.

    Of the pose's three local axes, the one nearest to vertical is left out; the heading is the
    direction in the floor plane of the first of the other two, modulo a quarter turn (a box
    turned by a multiple of 90 degrees about any axis is still axis aligned). A pose turned
    about z by ``a`` (and then by any signed permutation of its axes) has heading ``a`` modulo
    90 degrees; an axis-aligned pose has heading 0. A tilted pose gets the heading of its most
    level axis (its box in that frame is then a hull, as a world box is). NaN where the pose is
    NaN.
    """
    g = np.asarray(poses, dtype=np.float64)
    k = g.shape[0]
    if k == 0:
        return np.zeros(0)
    rot = g[:, :3, :3]
    vertical = np.argmax(np.fmax(np.abs(rot[:, 2, :]), 0.0), axis=1)  # NaN counts as 0
    level = np.where(vertical == 0, 1, 0)
    axis = rot[np.arange(k), :, level]
    h = np.arctan2(axis[:, 1], axis[:, 0])
    return np.mod(h + np.pi / 4, _QUARTER) - np.pi / 4


def heading_groups(h: ArrayLike, merge: float = HEADING_MERGE) -> tuple[NDArray[np.intp], FloatArray]:
    """(labels (K,), yaws (G,)): objects of headings ``h`` grouped into frames.

    Label 0 is the world frame (yaw exactly 0): headings within ``merge`` of 0 and NaN (no
    pose). The others: the sorted headings cut where two neighbours are more than ``merge``
    apart, and a run wider than ``merge`` cut again every ``merge`` from its start; a group's
    yaw is the mean of its members' headings, so every member is within ``merge`` of it (a tray
    turned by any angle and the parts it holds, whose headings differ by rounding only, share
    one exact frame).
    """
    h = np.asarray(h, dtype=np.float64)
    labels = np.zeros(h.shape[0], dtype=np.intp)
    turned = np.flatnonzero(~(np.isnan(h) | (np.abs(h) <= merge)))
    if not turned.size:
        return labels, np.zeros(1)
    v = h[turned]
    if float(v.max()) - float(v.min()) <= merge / 2:  # one frame (a tray and what it holds): as below, fewer calls
        labels[turned] = 1
        return labels, np.array([0.0, sum(sorted(v.tolist())) / len(v)])
    order = turned[np.argsort(v, kind="stable")]
    v = h[order]
    run = np.concatenate([[0], np.cumsum(np.diff(v) > merge)])
    first = np.concatenate([[0], np.flatnonzero(np.diff(run)) + 1])
    cut = np.floor((v - v[first][run]) / merge).astype(np.intp)
    key = run * (int(cut.max()) + 1) + cut
    _, group = np.unique(key, return_inverse=True)
    labels[order] = group + 1
    yaws = np.zeros(int(group.max()) + 2)
    yaws[1:] = np.bincount(group, weights=v) / np.bincount(group)
    return labels, yaws


def frame_boxes(poses: ArrayLike, lo: ArrayLike, hi: ArrayLike, yaw: ArrayLike) -> tuple[FloatArray, FloatArray]:
    """(lo, hi) (K, 3): the boxes of oriented local boxes in the world frame turned by ``yaw``
    about z (a number, or one per pose): the axis-aligned hulls there, as :func:`world_boxes`
    gives them in the world frame (yaw 0 gives exactly the world boxes)."""
    g = np.asarray(poses, dtype=np.float64)
    yaw_a = np.broadcast_to(np.asarray(yaw, dtype=np.float64), (g.shape[0],))
    if not yaw_a.any():
        return world_boxes(g, lo, hi)
    lo_l, hi_l = np.asarray(lo, dtype=np.float64), np.asarray(hi, dtype=np.float64)
    c, s = np.cos(yaw_a)[:, None], np.sin(yaw_a)[:, None]
    rot = g[:, :3, :3]
    centre = g[:, :3, 3] + np.einsum("kij,kj->ki", rot, (lo_l + hi_l) * 0.5)
    half = (hi_l - lo_l) * 0.5
    rows = (c * rot[:, 0] + s * rot[:, 1], c * rot[:, 1] - s * rot[:, 0], rot[:, 2])  # Rz(-yaw) @ R
    extent = np.stack([np.einsum("kj,kj->k", np.abs(r), half) for r in rows], axis=1)
    middle = np.stack([c[:, 0] * centre[:, 0] + s[:, 0] * centre[:, 1], c[:, 0] * centre[:, 1] - s[:, 0] * centre[:, 0],
                       centre[:, 2]], axis=1)
    return middle - extent, middle + extent
