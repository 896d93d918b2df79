"""Orientation: spatial relations, the simulator and the executor hold for objects turned about z.

Metamorphic: a workstation turned as a whole about the world's z axis, and each tray turned
alone about its own z axis (what it holds follows: their poses are relative to it), by yaws from
a seeded sample over the full circle, give the same predicates as unturned, and the kit is built
in the simulated cell. A tray is only turned by a yaw at which it stays clear of its neighbours
and inside what holds it (:func:`_fits`, plain corner geometry independent of kitkb's
predicates); a yaw that would make it collide is skipped, never counted as a pass.
docs/soap.md, "Orientation", has the design.
"""

from __future__ import annotations

import math
import random
import zlib
from pathlib import Path

import numpy as np
import pytest
from rdflib import Graph

from kb.core.namespaces import KTW
from kb.io import load_file
from kb.io.turtle import turtle
from kb.scenario import write_scenario
from kb.scenario.variants import turn
from kb.sim.robot import Robot
from kb.sim.world import World
from kb.spatial import true_predicates
from kb.spatial.rcc8 import (
    BIT,
    HEADING_MERGE,
    frame_boxes,
    heading_groups,
    headings,
    relate,
    relate_oriented,
    relate_rows,
    world_boxes,
)
from kb.spatial.scene import STAND_INS, Scene
from kb.spatial.transforms import from_xyz_rpy

ROOT = Path(__file__).resolve().parent.parent
SCENARIOS = ROOT / "ontologies" / "scenarios"
NIST = ROOT.parent / "shared" / "nist"
SHIPPED = sorted(p.name for p in SCENARIOS.iterdir() if (p / "init.ttl").exists())
TRAYS = (str(KTW.PartsTray), str(KTW.KitTray))
TOL = 1e-3


# --- helpers -------------------------------------------------------------------------------------

def turned(src: Path, out: Path, yaw: float, objects: list[str] | None = None) -> Path:
    """``src`` turned by ``yaw`` degrees (the workstation, or each of ``objects``), written to ``out``."""
    graph = Graph()
    graph += load_file(src).graph
    turn(graph, yaw, objects)
    out.write_text(turtle(graph))
    return out


def yaws(seed: int, n: int) -> list[float]:
    """``n`` yaws (degrees) over the full circle, none a multiple of 90 degrees."""
    rng = random.Random(seed)
    out = []
    while len(out) < n:
        y = round(rng.uniform(-180.0, 180.0), 3)
        if abs(y / 90.0 - round(y / 90.0)) > 0.02:
            out.append(y)
    return out


def _local(iri: str) -> str:
    return iri.rsplit("#", 1)[-1]


def turnable(scene: Scene) -> list[str]:
    """The trays of a scene as units to turn: a tray, or the kit it is the tray of when it is
    placed in that kit (NIST's goal places the kit's parts relative to the kit)."""
    out = []
    for i in np.flatnonzero(scene.placed):
        if not any(c in scene.classes[i] for c in TRAYS):
            continue
        p = int(scene.parents[i])
        unit = p if p >= 0 and str(KTW.Kit) in scene.classes[p] else int(i)
        out.append(_local(scene.names[unit]))
    return sorted(set(out))


def _footprints(scene: Scene, idx: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(corners (n, 4, 2) of the bottom faces, z intervals (n, 2)) of oriented boxes."""
    lo, hi = scene.local_lo[idx], scene.local_hi[idx]
    local = np.stack([np.stack([lo[:, 0], lo[:, 1]], 1), np.stack([hi[:, 0], lo[:, 1]], 1),
                      np.stack([hi[:, 0], hi[:, 1]], 1), np.stack([lo[:, 0], hi[:, 1]], 1)], 1)
    g = scene.poses[idx]
    corners = np.einsum("kij,kcj->kci", g[:, :2, :2], local) + g[:, None, :2, 3]
    wlo, whi = world_boxes(g, lo, hi)
    return corners, np.stack([wlo[:, 2], whi[:, 2]], 1)


def _overlap_2d(a: np.ndarray, b: np.ndarray) -> float:
    """Penetration depth of two convex quadrilaterals (separating axes; <= 0: apart or touching)."""
    depth = math.inf
    for poly in (a, b):
        for k in range(4):
            edge = poly[(k + 1) % 4] - poly[k]
            n = np.array([-edge[1], edge[0]]) / np.linalg.norm(edge)
            pa, pb = a @ n, b @ n
            depth = min(depth, min(pa.max(), pb.max()) - max(pa.min(), pb.min()))
    return depth


def _inside(a: np.ndarray, b: np.ndarray) -> bool:
    """Quadrilateral ``a`` inside quadrilateral ``b`` (within TOL)."""
    for k in range(4):
        edge = b[(k + 1) % 4] - b[k]
        n = np.array([-edge[1], edge[0]]) / np.linalg.norm(edge)
        side = np.sign((b[(k + 2) % 4] - b[k]) @ n)
        if ((a - b[k]) @ n * side < -TOL).any():
            return False
    return True


def _fits(scene: Scene, unit: str) -> bool:
    """The turned ``unit`` (with what moves with it) neither interpenetrates another solid
    (beyond TOL) nor sticks out of what holds it. Stand-ins (kits, large boxes, stations) and
    the objects they stand for are left out of the interpenetration test."""
    k = scene.index[next(n for n in scene.names if _local(n) == unit)]
    placed = [int(i) for i in np.flatnonzero(scene.placed)]
    moving = {k}
    while True:
        more = {i for i in placed if i not in moving and int(scene.parents[i]) in moving}
        if not more:
            break
        moving |= more
    up, p = [], int(scene.parents[k])
    while p >= 0:
        up.append(p)
        p = int(scene.parents[p])

    def same_box(i: int, j: int) -> bool:
        return bool(np.allclose(scene.poses[i], scene.poses[j]) and np.allclose(scene.local_lo[i], scene.local_lo[j])
                    and np.allclose(scene.local_hi[i], scene.local_hi[j]))
    solid = [i for i in placed if not any(c in scene.classes[i] for c in STAND_INS)]
    inner = np.array([i for i in solid if i in moving], np.int64)
    outer = np.array([i for i in solid if i not in moving and not any(same_box(i, j) for j in up + [k])], np.int64)
    ic, iz = _footprints(scene, inner)
    oc, oz = _footprints(scene, outer)
    for a in range(len(inner)):
        for b in range(len(outer)):
            if min(iz[a, 1], oz[b, 1]) - max(iz[a, 0], oz[b, 0]) > TOL and _overlap_2d(ic[a], oc[b]) > TOL:
                return False
    holder = next((h for h in up if scene.placed[h]), None)
    if holder is None:
        return True
    kc, _ = _footprints(scene, np.array([k]))
    hc, _ = _footprints(scene, np.array([holder]))
    return _inside(kc[0], hc[0])


def tray_turns(init: Path, seed: int, tries: int = 8) -> list[tuple[str, float]]:
    """(unit, yaw) for each tray of ``init``: the first yaw of a seeded sample at which the
    turned tray fits (:func:`_fits`, on the scene turned in memory: the unit's subtree turned
    about the unit's own z axis); trays with no such yaw are left out."""
    out = []
    scene = Scene.from_files([init])
    for unit in turnable(scene):
        for yaw in yaws(zlib.crc32(f"{seed}{unit}".encode()) % 10_000, tries):
            if _fits(_turned_scene(scene, unit, yaw), unit):
                out.append((unit, yaw))
                break
    return out


def _turned_scene(scene: Scene, unit: str, yaw: float) -> Scene:
    """A copy of ``scene`` with ``unit`` and what it holds turned by ``yaw`` degrees about its z."""
    k = scene.index[next(n for n in scene.names if _local(n) == unit)]
    g = scene.poses[k]
    delta = g @ from_xyz_rpy(0, 0, 0, 0, 0, math.radians(yaw)) @ np.linalg.inv(g)
    moving, todo = set(), [k]
    while todo:
        i = todo.pop()
        moving.add(i)
        todo.extend(int(j) for j in np.flatnonzero(scene.parents == i) if int(j) not in moving)
    poses = scene.poses.copy()
    for i in moving:
        poses[i] = delta @ poses[i]
    return Scene.from_parts(scene.names, scene.classes, poses, scene.local_lo, scene.local_hi,
                            parents=scene.parents, open_top=scene.open_top)


def generated(tmp: Path, seed: int, parts: int = 12, kits: int = 1) -> tuple[Path, Path]:
    return write_scenario(tmp / f"gen{seed}", parts=parts, kits=kits, seed=seed)


# --- the kernel: headings, groups, frames --------------------------------------------------------

def test_headings_modulo_a_quarter_turn():
    g = np.stack([from_xyz_rpy(0, 0, 0, r, p, y) for r, p, y in
                  [(0, 0, 0), (0, 0, math.pi / 2), (math.pi, 0, 0.3), (math.pi / 2, 0, 0.3), (0, 0, -2.0),
                   (0, math.pi / 2, 0.0)]])
    h = headings(g)
    assert np.allclose(h, [0.0, 0.0, 0.3, 0.3, -2.0 + math.pi / 2, 0.0], atol=1e-12)
    assert np.isnan(headings(np.full((1, 4, 4), np.nan))).all()


def test_groups_world_frame_first_and_members_within_merge():
    h = np.array([0.0, 1e-12, np.nan, 0.5, 0.5 + 1e-15, -0.7, 0.5 + 3e-6])
    labels, yaws_ = heading_groups(h)
    assert labels[0] == labels[1] == labels[2] == 0 and yaws_[0] == 0.0
    assert len(set(labels[[3, 4]])) == 1 and labels[3] != labels[5] != 0
    assert np.all(np.abs(yaws_[labels[3:]] - h[3:]) <= HEADING_MERGE)


def test_axis_aligned_scenes_are_one_group_with_todays_masks():
    """Axis-aligned poses (quarter turns about any axis included): one group, the masks of
    relate on the world boxes bit for bit."""
    rng = np.random.default_rng(3)
    n = 300
    quarter = [from_xyz_rpy(0, 0, 0, *(math.pi / 2 * rng.integers(0, 4, 3))) for _ in range(n)]
    poses = np.stack(quarter)
    poses[:, :3, 3] = np.round(rng.uniform(0, 1, (n, 3)) / 5e-4) * 5e-4
    lo = -np.round(rng.uniform(0.005, 0.1, (n, 3)) / 5e-4) * 5e-4
    hi = -lo
    labels, yaws_ = heading_groups(headings(poses))
    assert not labels.any() and len(yaws_) == 1
    wlo, whi = world_boxes(poses, lo, hi)
    assert (relate_oriented(poses, lo, hi, poses, lo, hi) == relate(wlo, whi, wlo, whi)).all()


@pytest.mark.parametrize("yaw", yaws(11, 4))
def test_relations_unchanged_when_everything_turns(yaw):
    """Boxes turned together by any yaw: the pairs that meet relate as they did, up to the
    quarter turns the frame leaves in (a box turned by 150 degrees is decided in the frame
    turned by -30: it is then the unturned box turned by 180 degrees, X-Plus and X-Minus
    swapped); the pairs that were apart are apart. Bounds on a 0.5 mm grid, tolerance a quarter
    of it, so no bound sits on a threshold and rounding cannot flip one."""
    rng = np.random.default_rng(5)
    n, grid, tol = 400, 5e-4, 1.25e-4
    poses = np.tile(np.eye(4), (n, 1, 1))
    poses[:, :3, 3] = np.round(rng.uniform(0, 0.5, (n, 3)) / grid) * grid
    lo = np.zeros((n, 3))
    hi = np.round(rng.uniform(0.01, 0.2, (n, 3)) / grid) * grid
    r = from_xyz_rpy(0.3, -0.2, 0.0, 0, 0, math.radians(yaw))
    quarters = round((yaw - math.degrees(headings(r[None])[0])) / 90.0) % 4
    q = np.eye(4)
    q[:2, :2] = np.linalg.matrix_power(np.array([[0.0, -1.0], [1.0, 0.0]]), quarters)  # exact
    before = relate(*world_boxes(q @ poses, lo, hi), *world_boxes(q @ poses, lo, hi), tol)
    after = relate_oriented(r @ poses, lo, hi, r @ poses, lo, hi, tol)
    dc = BIT["X-DC"] | BIT["Y-DC"] | BIT["Z-DC"]
    meet = (before & dc) == 0
    assert 100 < meet.sum() < meet.size
    assert (after[meet] == before[meet]).all()
    assert (after[~meet] & dc).all()
    world = relate(*world_boxes(r @ poses, lo, hi), *world_boxes(r @ poses, lo, hi), tol)
    assert ((world & dc) == 0).sum() > meet.sum()  # the world boxes of turned boxes meet more often


def test_a_part_in_a_turned_tray_is_in_it_and_clear_of_its_neighbour():
    """A 45-degree tray with two parts 5 mm apart: world boxes make them overlap, the tray's frame
    does not; the part is inside the tray."""
    tray = from_xyz_rpy(1.0, 1.0, 0.0, 0, 0, math.pi / 4)
    parts = [tray @ from_xyz_rpy(0.0, y, 0.0, 0, 0, 0) for y in (-0.0125, 0.0125)]
    poses = np.stack([tray] + parts)
    lo = np.array([[-0.15, -0.05, 0.0], [-0.1, -0.01, 0.0], [-0.1, -0.01, 0.0]])
    hi = np.array([[0.15, 0.05, 0.04], [0.1, 0.01, 0.05], [0.1, 0.01, 0.05]])
    m = relate_oriented(poses, lo, hi, poses, lo, hi)
    apart = BIT["X-DC"] | BIT["Y-DC"]  # the frame may be the tray's turned by a quarter
    assert m[1, 2] & apart and m[2, 1] & apart
    assert m[1, 0] & BIT["X-NTPP"] and m[1, 0] & BIT["Y-NTPP"]
    wlo, whi = world_boxes(poses, lo, hi)
    assert not relate(wlo, whi, wlo, whi)[1, 2] & (BIT["X-DC"] | BIT["Y-DC"] | BIT["Z-DC"])


def test_frame_boxes_of_yaw_zero_are_world_boxes():
    rng = np.random.default_rng(1)
    g = np.stack([from_xyz_rpy(*rng.uniform(-1, 1, 6)) for _ in range(20)])
    lo, hi = -rng.uniform(0, 1, (20, 3)), rng.uniform(0, 1, (20, 3))
    assert all((a == b).all() for a, b in zip(frame_boxes(g, lo, hi, 0.0), world_boxes(g, lo, hi)))


# --- predicates: turned workstations and turned trays -------------------------------------------

def _same_predicates(init: Path, out: Path, yaw: float, objects: list[str] | None = None,
                     goal: Path | None = None, match_names: bool = False) -> None:
    base = set(true_predicates([init], goal=goal, match_names=match_names))
    t = set(true_predicates([turned(init, out, yaw, objects)], goal=goal, match_names=match_names))
    assert t == base, (yaw, objects, sorted(base - t)[:5], sorted(t - base)[:5])


@pytest.mark.parametrize("scenario", SHIPPED)
@pytest.mark.parametrize("state", ["init", "goal"])
def test_turned_workstation_same_predicates(scenario, state, tmp_path):
    for yaw in yaws(zlib.crc32(scenario.encode()) % 1000, 2):
        _same_predicates(SCENARIOS / scenario / f"{state}.ttl", tmp_path / "t.ttl", yaw)


@pytest.mark.parametrize("scenario", [s if s == "small-kit" else pytest.param(s, marks=pytest.mark.slow)
                                      for s in SHIPPED])
def test_each_tray_turned_alone_same_predicates(scenario, tmp_path):
    for state in ("init", "goal"):
        path = SCENARIOS / scenario / f"{state}.ttl"
        turns = tray_turns(path, 0)
        assert len(turns) >= 2, turns
        for unit, yaw in turns:
            _same_predicates(path, tmp_path / "t.ttl", yaw, [unit])


@pytest.mark.parametrize("seed", [1, pytest.param(2, marks=pytest.mark.slow), pytest.param(3, marks=pytest.mark.slow)])
def test_generated_turned_same_predicates(seed, tmp_path):
    init, goal = generated(tmp_path, seed)
    for path in (init, goal):
        _same_predicates(path, tmp_path / "t.ttl", yaws(seed, 1)[0])
        for unit, yaw in tray_turns(path, seed):
            _same_predicates(path, tmp_path / "t.ttl", yaw, [unit])


@pytest.mark.skipif(not (NIST / "kittingInstancesInit1.owl").exists(), reason="NIST files not present")
def test_nist_turned_same_predicates(tmp_path):
    init, goal = NIST / "kittingInstancesInit1.owl", NIST / "kittingInstancesGoal1.owl"
    for yaw in yaws(7, 2):
        _same_predicates(init, tmp_path / "i.ttl", yaw, goal=goal, match_names=True)
        _same_predicates(goal, tmp_path / "g.ttl", yaw)
    for path, decl in ((init, goal), (goal, None)):
        turns = tray_turns(path, 7)
        assert len(turns) >= 3 and any(abs(y / 90 - round(y / 90)) * 90 >= 20 for _, y in turns), turns
        for unit, yaw in turns:
            _same_predicates(path, tmp_path / "t.ttl", yaw, [unit], goal=decl, match_names=decl is not None)


def _rotated(scene: Scene, yaw: float) -> Scene:
    """``scene`` with every placed object turned by ``yaw`` degrees about the world's z axis
    (in memory: the global poses)."""
    r = from_xyz_rpy(0, 0, 0, 0, 0, math.radians(yaw))
    return Scene(scene.names, scene.classes, *_world(r @ scene.poses, scene), scene.facts, scene.values,
                 scene.inspections, r @ scene.poses, scene.path, scene.parents, scene.local_lo, scene.local_hi,
                 scene.open_top, scene.slots)


def _world(poses: np.ndarray, scene: Scene) -> tuple[np.ndarray, np.ndarray]:
    from kb.spatial.scene import scene_boxes
    return scene_boxes(poses, scene.local_lo, scene.local_hi)


@pytest.mark.parametrize("files", [(SCENARIOS / s / f"{st}.ttl", None) for s in SHIPPED for st in ("init", "goal")]
                         + [(NIST / "kittingInstancesInit1.owl", NIST / "kittingInstancesGoal1.owl"),
                            (NIST / "kittingInstancesGoal1.owl", None)], ids=lambda f: f"{f[0].parent.name}/{f[0].name}")
def test_many_yaws_in_memory_same_predicates(files):
    """24 seeded yaws over the full circle per state, the scene turned in memory (no files)."""
    from kb.model.definitions import load_definitions
    from kb.spatial.predicates import Evaluator
    state, goal = files
    if not state.exists():
        pytest.skip("NIST files not present")
    defs = load_definitions()
    scene = Scene.from_files([state], declared=[goal] if goal else (), match_names=goal is not None)
    base = Evaluator(defs, scene).facts()
    assert base
    for yaw in yaws(zlib.crc32(str(state).encode()) % 1000, 24):
        assert Evaluator(defs, _rotated(scene, yaw)).facts() == base, yaw


def test_world_boxes_alone_would_be_wrong():
    """The in-memory yaw test has teeth: on kit-a2b3c3d1e1 turned by the same kind of yaws, the
    evaluator deciding everything on world boxes (one frame, as before) gets predicates wrong."""
    from kb.model.definitions import load_definitions
    from kb.spatial.predicates import Evaluator

    class WorldBoxes(Evaluator):
        @staticmethod
        def _frames(scene: Scene) -> np.ndarray:
            return np.zeros(len(scene.names))
    defs = load_definitions()
    scene = Scene.from_files([SCENARIOS / "kit-a2b3c3d1e1" / "init.ttl"])
    base = Evaluator(defs, scene).facts()
    wrong = [y for y in yaws(1, 24) if WorldBoxes(defs, _rotated(scene, y)).facts() != base]
    assert len(wrong) >= 3, wrong
    assert all(Evaluator(defs, _rotated(scene, y)).facts() == base for y in wrong)


# --- the simulated cell ---------------------------------------------------------------------------

def _tight_tray_world(yaw: float) -> World:
    """A tray turned by ``yaw`` on a table with two parts 5 mm apart, and a robot's flange far above."""
    table = from_xyz_rpy(0.0, 0.0, 0.0, 0, 0, 0)
    tray = from_xyz_rpy(0.5, 0.5, 0.1, 0, 0, yaw)
    parts = [tray @ from_xyz_rpy(0.0, y, 0.0, 0, 0, 0) for y in (0.0125, -0.0125)]
    names = ["urn:t#table", "urn:t#part_b", "urn:t#part_a", "urn:t#tray", "urn:t#robot"]
    classes = [{str(KTW.WorkTable)}, {str(KTW.Part)}, {str(KTW.Part)}, {str(KTW.PartsTray)}, {str(KTW.Robot)}]
    poses = np.stack([table, parts[0], parts[1], tray, from_xyz_rpy(0.0, 0.0, 2.0, 0, 0, 0)])
    lo = np.array([[-1.0, -1.0, 0.0], [-0.1, -0.01, 0.0], [-0.1, -0.01, 0.0], [-0.15, -0.05, 0.0],
                   [-0.05, -0.05, 0.0]])
    hi = np.array([[1.0, 1.0, 0.1], [0.1, 0.01, 0.05], [0.1, 0.01, 0.05], [0.15, 0.05, 0.04], [0.05, 0.05, 0.02]])
    scene = Scene.from_parts(names, [list(c) for c in classes], poses, lo, hi, parents=np.array([-1, 3, 3, 0, -1]),
                             open_top=np.array([False, False, False, True, False]))
    return World.from_scene(scene)


@pytest.mark.parametrize("yaw", [math.pi / 4, math.radians(-33.3)])
def test_sim_drop_lands_in_turned_tray_not_on_neighbour(yaw):
    w = _tight_tray_world(yaw)
    a, b, tray = w.index["urn:t#part_a"], w.index["urn:t#part_b"], w.index["urn:t#tray"]
    w.shift(a, 0.0, 0.0, 0.2)
    w.parent[a] = -1
    assert w.drop(a) == tray
    assert abs(w.poses[a, 2, 3] - w.poses[tray, 2, 3]) < 1e-9
    assert w.support_below(b, set())[1] == tray


@pytest.mark.parametrize("yaw", [math.pi / 4, math.radians(61.0)])
def test_sim_grasp_takes_the_part_under_the_tip(yaw):
    """The tip on part_a's top: part_b (listed first) has a world box over that point too."""
    w = _tight_tray_world(yaw)
    a, b = w.index["urn:t#part_a"], w.index["urn:t#part_b"]
    tip = w.poses[a] @ np.array([0.0, 0.0, 0.05, 1.0])
    lo, hi = w.box(b)
    assert (lo[:2] <= tip[:2]).all() and (tip[:2] <= hi[:2]).all()  # the world box would be ambiguous

    robot = Robot(w)
    robot._go(from_xyz_rpy(*tip[:3], 0, 0, 0))
    assert np.allclose(robot.tip()[:3, 3], tip[:3])
    assert robot._at_tip() == a


# --- kitkb run on turned workstations ------------------------------------------------------------

def _built(init: Path, goal: Path) -> None:
    from kb.execution import run_scenario
    run = run_scenario(init, goal)
    assert run.goal_holds and run.stopped is None, [(f.action, f.mode) for f in run.failures()]


def test_run_builds_kit_on_turned_workstation(tmp_path):
    src = SCENARIOS / "small-kit"
    yaw = yaws(21, 1)[0]
    _built(turned(src / "init.ttl", tmp_path / "i.ttl", yaw), turned(src / "goal.ttl", tmp_path / "g.ttl", yaw))


def test_run_builds_kit_with_turned_trays(tmp_path):
    src = SCENARIOS / "small-kit"
    turns = tray_turns(src / "init.ttl", 21)
    init, goal = src / "init.ttl", src / "goal.ttl"
    for k, (unit, yaw) in enumerate(turns):
        init = turned(init, tmp_path / f"i{k}.ttl", yaw, [unit])
    _built(init, goal)


@pytest.mark.slow
@pytest.mark.parametrize("scenario", SHIPPED)
def test_run_turned_shipped(scenario, tmp_path):
    src = SCENARIOS / scenario
    for yaw in yaws(zlib.crc32(scenario.encode()) % 1000 + 1, 2):
        _built(turned(src / "init.ttl", tmp_path / "i.ttl", yaw), turned(src / "goal.ttl", tmp_path / "g.ttl", yaw))
    init = src / "init.ttl"
    for k, (unit, yaw) in enumerate(tray_turns(init, 5)):
        init = turned(init, tmp_path / f"t{k}.ttl", yaw, [unit])
    _built(init, src / "goal.ttl")


@pytest.mark.slow
@pytest.mark.parametrize("seed", [1, 2, 3])
def test_run_turned_generated(seed, tmp_path):
    init, goal = generated(tmp_path, seed, parts=20, kits=2)
    yaw = yaws(seed + 100, 1)[0]
    _built(turned(init, tmp_path / "i.ttl", yaw), turned(goal, tmp_path / "g.ttl", yaw))
    for k, (unit, yaw) in enumerate(tray_turns(init, seed)):
        init = turned(init, tmp_path / f"t{k}.ttl", yaw, [unit])
    _built(init, goal)


@pytest.mark.slow
@pytest.mark.skipif(not (NIST / "kittingInstancesInit1.owl").exists(), reason="NIST files not present")
def test_run_turned_nist(tmp_path):
    from kb.execution import run_scenario
    init, goal = NIST / "kittingInstancesInit1.owl", NIST / "kittingInstancesGoal1.owl"
    for yaw in yaws(8, 2):
        run = run_scenario(turned(init, tmp_path / "i.ttl", yaw), turned(goal, tmp_path / "g.ttl", yaw),
                           match_names=True)
        assert run.goal_holds and run.stopped is None, (yaw, [(f.action, f.mode) for f in run.failures()])
    turned_init = init
    for k, (unit, yaw) in enumerate(tray_turns(init, 8)):
        turned_init = turned(turned_init, tmp_path / f"t{k}.ttl", yaw, [unit])
    run = run_scenario(turned_init, goal, match_names=True)
    assert run.goal_holds and run.stopped is None, [(f.action, f.mode) for f in run.failures()]


def test_relate_rows_is_relate_pair_by_pair():
    rng = np.random.default_rng(9)
    lo = np.round(rng.uniform(0, 0.3, (500, 3)) / 5e-4) * 5e-4
    hi = lo + np.round(rng.uniform(0.001, 0.2, (500, 3)) / 5e-4) * 5e-4
    a, b = rng.permutation(500), rng.permutation(500)
    full = relate(lo[a], hi[a], lo[b], hi[b])
    assert (relate_rows(lo[a], hi[a], lo[b], hi[b]) == np.diagonal(full)).all()
