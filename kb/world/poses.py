"""Poses of many objects at once (numpy): the transformation tree, global poses, eq. (1) in batches.

:class:`PoseTree` is the shape of the transformation tree as stored (which object is located
relative to which, and where its numbers are), read with one query and kept by
:class:`kb.world.worldmodel.WorldModel`: a pose then costs one query for the numbers of its
chain. :func:`matrices`, :func:`compose` and :func:`update_batch` do the arithmetic on
``(N, 4, 4)`` arrays, with the conventions of :mod:`kb.spatial.transforms` (a pose is a point
and unit x and z axes, ``y = z x x``; ``G = G_ref @ L``; eq. (1) ``L' = L G^-1 G' = G_ref^-1 G'``).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Sequence

import numpy as np
from numpy.typing import NDArray

from kb.core.errors import InputError

_EPS = 1e-12
#: Longest reference chain followed (longer ones are taken for cycles).
MAX_DEPTH = 1000

Matrices = NDArray[np.float64]  # (N, 4, 4)


class BadPose(ValueError):
    """Row ``row`` of the numbers is not a pose (``reason`` says why)."""

    def __init__(self, row: int, reason: str):
        super().__init__(f"row {row}: {reason}")
        self.row, self.reason = row, reason


@dataclass
class PoseTree:
    """The stored transformation tree of the solid objects (no numbers), index by index.

    ``ref[i]`` is the index of object ``i``'s reference object (-1 at the root), ``loc[i]``
    the id of its primary location, ``point[i]``/``x_axis[i]``/``z_axis[i]`` the ids of its
    pose rows (0 for a location without numbers). ``depth[i]`` is its distance from the root
    (-1 when its chain has a cycle or leaves the tree). ``posed[i]`` is False where the object,
    or one of its reference objects, is located relative to another by a location without
    numbers (a ``RelativeLocation``: "in the tray", no point): it has no pose to compute, as the
    scene builder says (:mod:`kb.spatial.scene`). A root without numbers (NIST's workstation,
    located relative to itself) is the world frame.
    """

    ids: list[int]
    names: list[str]
    iris: list[str]
    ref: NDArray[np.int64]
    loc: list[int]
    point: list[int]
    x_axis: list[int]
    z_axis: list[int]
    token: str | None = None
    index: dict[int, int] = field(default_factory=dict)
    by_name: dict[str, list[int]] = field(default_factory=dict)
    by_iri: dict[str, int] = field(default_factory=dict)
    depth: NDArray[np.int64] = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    levels: list[NDArray[np.int64]] = field(default_factory=list)
    posed: NDArray[np.bool_] = field(default_factory=lambda: np.zeros(0, dtype=bool))

    @classmethod
    def from_rows(cls, rows: Sequence[tuple[Any, ...]], token: str | None) -> "PoseTree":
        """From rows ``(id, name, iri, location id, reference id, point id, x axis id, z axis id)``."""
        rows = sorted(rows)
        ids = [r[0] for r in rows]
        index = {id_: i for i, id_ in enumerate(ids)}
        ref = np.array([-1 if r[4] is None or r[4] == r[0] else index.get(r[4], -2) for r in rows], dtype=np.int64)
        tree = cls(ids, [r[1] for r in rows], [r[2] for r in rows], ref, [r[3] for r in rows],
                   [r[5] or 0 for r in rows], [r[6] or 0 for r in rows], [r[7] or 0 for r in rows], token, index)
        for i, name in enumerate(tree.names):
            tree.by_name.setdefault(name, []).append(i)
        tree.by_iri = {iri: i for i, iri in enumerate(tree.iris)}
        tree.depth = _depths(ref)
        top = int(tree.depth.max(initial=-1))
        order = np.argsort(tree.depth, kind="stable")
        bounds = np.searchsorted(tree.depth[order], np.arange(top + 2))
        tree.levels = [order[bounds[d]:bounds[d + 1]] for d in range(top + 1)]
        tree.posed = (ref < 0) | (np.array(tree.point, dtype=np.int64) != 0)  # its own numbers, or the root
        for level in tree.levels[1:]:
            tree.posed[level] &= tree.posed[ref[level]]
        return tree

    def find(self, name: str) -> int:
        """The index of the solid object called ``name`` (local name or IRI)."""
        i = self.by_iri.get(name)
        if i is not None:
            return i
        found = self.by_name.get(name)
        if not found:
            raise InputError(f"no solid object named {name!r} in the world model")
        if len(found) > 1:
            raise InputError(f"the name {name!r} is ambiguous: " +
                             ", ".join(self.iris[i] for i in found[:3]) + " ...")
        return found[0]

    def chain(self, i: int) -> list[int]:
        """``i`` and its reference objects up to the root, nearest first."""
        if self.depth[i] < 0:
            raise InputError(f"{self.names[i]}: its reference objects form a cycle (or leave the tree)")
        out = [i]
        while self.ref[out[-1]] >= 0:
            out.append(int(self.ref[out[-1]]))
        if not self.posed[i]:
            j = next(j for j in reversed(out) if not self.posed[j])  # the first without numbers, from the root
            whose = "its location" if j == i else f"its reference object {self.names[j]}'s location"
            raise InputError(f"{self.names[i]} has no pose in the world model: {whose} has no point (a relative "
                             "location, such as 'in the tray', has no numbers to compose)")
        return out

    def closure(self, indexes: Sequence[int]) -> list[int]:
        """``indexes`` and all their reference objects, parents before children."""
        seen: set[int] = set()
        for i in indexes:
            for j in self.chain(i):
                if j in seen:
                    break
                seen.add(j)
        return sorted(seen, key=lambda j: (int(self.depth[j]), j))


def _depths(ref: NDArray[np.int64]) -> NDArray[np.int64]:
    """Distance of each object from its root; -1 where the chain has a cycle or leaves the tree."""
    n = len(ref)
    depth = np.full(n, -1, dtype=np.int64)
    depth[ref == -1] = 0
    for d in range(1, MAX_DEPTH + 1):
        mask = (depth == -1) & (ref >= 0)
        if not mask.any():
            break
        parents = ref[mask]
        ready = depth[parents] == d - 1
        if not ready.any():
            break
        idx = np.nonzero(mask)[0][ready]
        depth[idx] = d
    return depth


# --- arithmetic -----------------------------------------------------------------------------

def matrices(numbers: NDArray[np.float64]) -> Matrices:
    """``(N, 4, 4)`` poses of rows ``(px, py, pz, xi, xj, xk, zi, zj, zk)``: axes normalized, x made
    orthogonal to z (as :func:`kb.spatial.transforms.pose_matrix`). :class:`BadPose` names the first bad row."""
    numbers = np.asarray(numbers, dtype=float).reshape(-1, 9)
    p, x, z = numbers[:, 0:3], numbers[:, 3:6], numbers[:, 6:9]
    nz, nx0 = np.linalg.norm(z, axis=1), np.linalg.norm(x, axis=1)
    bad = (nz < _EPS) | (nx0 < _EPS)
    if bad.any():
        raise BadPose(int(np.argmax(bad)), "an axis of the pose has length zero")
    z = z / nz[:, None]
    x = x - np.einsum("ij,ij->i", x, z)[:, None] * z
    nx = np.linalg.norm(x, axis=1)
    if (nx < _EPS).any():
        raise BadPose(int(np.argmax(nx < _EPS)), "the x and z axes of the pose are parallel")
    x = x / nx[:, None]
    out = np.zeros((len(numbers), 4, 4))
    out[:, :3, 0], out[:, :3, 1], out[:, :3, 2], out[:, :3, 3] = x, np.cross(z, x), z, p
    out[:, 3, 3] = 1.0
    return out


def invert(m: Matrices) -> Matrices:
    """Inverses of rigid transforms (transposed rotations)."""
    out = np.zeros_like(m)
    rt = np.swapaxes(m[:, :3, :3], 1, 2)
    out[:, :3, :3] = rt
    out[:, :3, 3] = -np.einsum("nij,nj->ni", rt, m[:, :3, 3])
    out[:, 3, 3] = 1.0
    return out


def rigid(m: Any, names: Sequence[str]) -> Matrices:
    """``m`` as ``(N, 4, 4)`` finite rigid transforms; InputError naming the first that is not one."""
    a = np.asarray(m, dtype=float)
    if a.ndim == 2:
        a = a[None]
    if a.shape[1:] != (4, 4):
        raise InputError(f"pose of {names[0]}: a pose must be a finite 4x4 matrix")
    finite = np.isfinite(a).all(axis=(1, 2))
    last = np.array([0.0, 0.0, 0.0, 1.0])  # np.allclose's tolerances, as transforms.check_matrix
    rows = (np.abs(a[:, 3] - last) <= 1e-8 + 1e-5 * last).all(axis=1)
    r = a[:, :3, :3]
    ortho = (np.abs(np.swapaxes(r, 1, 2) @ r - np.eye(3)) <= 1e-6 + 1e-5 * np.eye(3)).all(axis=(1, 2))
    bad = ~(finite & rows & ortho)
    if bad.any():
        i = int(np.argmax(bad))
        what = "a finite 4x4 matrix" if not finite[i] else \
            "a rigid transform (orthonormal rotation, last row 0 0 0 1)"
        raise InputError(f"pose of {names[i]}: a pose must be {what}")
    return a


class Members:
    """Objects (``indexes``, tree indexes, parents first) with compact positions: row ``k`` of
    the arrays below is object ``indexes[k]``; ``parent[k]`` is the row of its reference object
    (-1 at the root, or when the reference object is not a member). Global poses need the
    members closed under "reference object of" (:meth:`PoseTree.closure`)."""

    def __init__(self, tree: PoseTree, indexes: Sequence[int]):
        self.indexes = list(indexes)
        self.row = {i: k for k, i in enumerate(self.indexes)}
        refs = tree.ref[self.indexes] if self.indexes else np.zeros(0, dtype=np.int64)
        self.parent = np.array([self.row.get(r, -1) for r in refs.tolist()], dtype=np.int64)
        depth = tree.depth[self.indexes] if self.indexes else np.zeros(0, dtype=np.int64)
        self.levels = [np.nonzero(depth == d)[0] for d in range(int(depth.max(initial=-1)) + 1)]


def compose(members: Members, local: Matrices) -> Matrices:
    """Global poses ``G = G_ref @ L`` of ``members`` from their relative poses ``local`` (rows
    as in ``members``)."""
    out = np.empty_like(local)
    for rows in members.levels:
        parents = members.parent[rows]
        root = parents < 0
        out[rows[root]] = local[rows[root]]
        child = rows[~root]
        if len(child):
            out[child] = out[parents[~root]] @ local[child]
    return out


def update_batch(members: Members, local: Matrices, relative: dict[int, Matrices],
                 targets: dict[int, Matrices]) -> Matrices:
    """New relative poses after a stable-state batch: ``relative`` poses set as given, then the
    sensed global ``targets`` reached with eq. (1), parents before children (a child's new ``L``
    is taken in its parent's new frame, so both reach their targets). ``local`` holds the
    current relative poses of ``members`` (the batch's objects and their reference objects,
    rows as in ``members``); ``relative`` and ``targets`` are keyed by row. Returns the new
    relative poses (same rows)."""
    new = local.copy()
    for k, m in relative.items():
        new[k] = m
    glob = np.empty_like(local)
    for rows in members.levels:
        parents = members.parent[rows]
        has = parents >= 0
        frame = np.empty((len(rows), 4, 4))
        frame[:] = np.eye(4)
        frame[has] = glob[parents[has]]
        sensed = [j for j, k in enumerate(rows.tolist()) if k in targets]
        if sensed:
            at = rows[sensed]
            new[at] = invert(frame[sensed]) @ np.stack([targets[int(k)] for k in at])
        glob[rows] = frame @ new[rows]
    return new


def axes(m: Matrices) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """(points, x axes, z axes) of ``(N, 4, 4)`` poses, each ``(N, 3)``."""
    return m[:, :3, 3], m[:, :3, 0], m[:, :3, 2]
