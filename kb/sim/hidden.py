"""Where a simulated cell puts the objects its state does not locate (its ground truth).

:func:`place_unknown`: each unlocated object (:mod:`kb.spatial.unlocated`) put, seeded, in a free
spot of a container that suits it — the container the file names for it (a parts tray that
lists it, the reference of its relative location), else the first object whose
``hasPartsVessel_PartSku`` is its SKU — on the container's floor (its top when it is closed),
turned as the container, clear of what lies there already by :data:`MARGIN`. The same state
and seed, the same spots. The executor does not know them: it senses them
(:mod:`kb.execution.locate`).
"""

from __future__ import annotations

from typing import Sequence
from pathlib import Path

import numpy as np
from rdflib import Graph, URIRef

from kb.core.errors import InputError
from kb.core.namespaces import KTW, local_name
from kb.io.loader import Source
from kb.scenario.partial import Placement, copy_graph, graph_source, with_locations
from kb.spatial.scene import Scene
from kb.spatial.unlocated import Unlocated, unlocated

#: space kept between a placed object and its neighbours or the container's wall (metres)
MARGIN = 0.004


def place_unknown(source: Source, seed: int = 0, declared: Sequence[Source | str | Path] = (),
                  match_names: bool = False) -> tuple[Scene, list[Placement]]:
    """A ground truth of the partial state ``source``: its scene with every unlocated object
    (:func:`kb.spatial.unlocated.unlocated`) put in a free spot of a container that suits it,
    chosen with ``seed`` (the same seed, the same spots), and the placements. An object for
    which no container is found, or whose container has no room left, is an InputError naming
    it (a world file says where it is: ``sim:?world=FILE``)."""
    found = unlocated(source)
    graph = copy_graph(source)
    if not found:
        return Scene.from_sources([source], declared, match_names), []
    homes = {u.name: _home(graph, u) for u in found}
    # first every object at its container's origin: the scene gives each its box (in SI) and each container's
    provisional = [Placement(u.name, homes[u.name], np.eye(4), np.eye(4)) for u in found]
    scene = Scene.from_sources([graph_source(with_locations(copy_graph(source), provisional), source.path)],
                               declared, match_names)
    rng = np.random.default_rng(seed)
    taken: dict[str, list[tuple[np.ndarray, np.ndarray]]] = {}
    unknown = {u.name for u in found}
    placements = []
    for u in found:
        c = scene.index[homes[u.name]]
        if c not in taken:
            taken[c] = _occupied(scene, c, unknown)
        local = _free_spot(scene, c, scene.index[u.name], taken[c], rng)
        if local is None:
            raise InputError(f"the simulated cell has no free spot for {local_name(u.name)} in "
                             f"{local_name(homes[u.name])}; give it a world file that places it (sim:?world=FILE)",
                             u.path, u.line)
        g = scene.poses[c] @ local
        placements.append(Placement(u.name, homes[u.name], local, g))
    truth = with_locations(graph, placements, scene.units)
    return Scene.from_sources([graph_source(truth, source.path)], declared, match_names), placements


def _home(graph: Graph, u: Unlocated) -> str:
    """The container of an unlocated object: the one its file names, else the first (by name)
    object whose ``hasPartsVessel_PartSku`` is its SKU."""
    if u.container is not None:
        return u.container
    if u.sku is not None:
        vessels = sorted(str(v) for v in graph.subjects(KTW.hasPartsVessel_PartSku, URIRef(u.sku)))
        if vessels:
            return vessels[0]
    raise InputError(f"the simulated cell cannot place {local_name(u.name)}: its file names no container for it and "
                     "no parts vessel holds its SKU; give it a world file that places it (sim:?world=FILE)",
                     u.path, u.line)


def _corners(lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    return np.array([[x, y, z, 1.0] for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])])


def _footprint(m: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The xy rectangle (lo, hi) that a box (``lo``, ``hi`` in its own frame) posed by ``m`` covers."""
    pts = (m @ _corners(lo, hi).T).T[:, :2]
    return pts.min(axis=0), pts.max(axis=0)


def _occupied(scene: Scene, c: int, unknown: set[str]) -> list[tuple[np.ndarray, np.ndarray]]:
    """The xy rectangles, in container ``c``'s frame, of the placed objects resting in it."""
    inv = np.linalg.inv(scene.poses[c])
    out = []
    for i in np.flatnonzero(scene.parents == c):
        if scene.names[i] in unknown or np.isnan(scene.local_lo[i, 0]):
            continue
        out.append(_footprint(inv @ scene.poses[i], scene.local_lo[i], scene.local_hi[i]))
    return out


def _free_spot(scene: Scene, c: int, i: int, taken: list, rng: np.random.Generator) -> np.ndarray | None:
    """A pose in container ``c``'s frame for object ``i`` on the container's floor (its top
    when it is closed), clear of ``taken`` (which it joins), chosen by ``rng``; None: no room."""
    lo, hi = scene.local_lo[i], scene.local_hi[i]
    if np.isnan(lo[0]) or np.isnan(scene.local_lo[c, 0]):
        return None
    clo, chi = scene.local_lo[c], scene.local_hi[c]
    floor = clo[2] if scene.open_top[c] else chi[2]
    size = hi[:2] - lo[:2]
    step = size + MARGIN
    xs = np.arange(clo[0] + MARGIN - lo[0], chi[0] - MARGIN - hi[0] + 1e-9, step[0])
    ys = np.arange(clo[1] + MARGIN - lo[1], chi[1] - MARGIN - hi[1] + 1e-9, step[1])
    spots = [(x, y) for x in xs for y in ys]
    for k in rng.permutation(len(spots)):
        x, y = spots[k]
        rlo, rhi = np.array([x, y]) + lo[:2] - MARGIN / 2, np.array([x, y]) + hi[:2] + MARGIN / 2
        if all(np.any(rhi <= tlo) or np.any(rlo >= thi) for tlo, thi in taken):
            m = np.eye(4)
            m[:3, 3] = (x, y, floor - lo[2])
            taken.append((rlo, rhi))
            return m
    return None
