"""Property-based tests of the simulated cell: random CRCL programs and fault mixes never make a
pose non-finite or a rigid body lose its shape.

Hypothesis drives a :class:`kb.sim.SimulatedCell` step by step (``st.data()``: each step is
drawn from where things are now, so grasps, tool changes and releases really happen): moves to
random points and to the top faces of objects, waypoints, grippers, the tool changer, speeds,
dwells, units, plan actions announced with sensible or nonsense arguments under a random fault
mix, and wild values (points kilometres away, tiny speeds, endless dwells). After every step:

* every pose is either not placed (all NaN) or a finite rigid transform (orthonormal rotation
  with determinant 1, last row 0 0 0 1), and so is every sensor observation; the clock is
  finite and never runs backwards;
* local boxes are what the state file gave, except a part a ``wrong-sku`` fault replaced (the
  box of a part of its new SKU) and a kit once created (its tray's);
* what did not move keeps its global pose, and every object whose support did not change keeps
  its pose relative to that support (children rigid with their parents): only the robot's
  subtree, objects that changed support (grasped, released, mounted, fallen) with what rests on
  them, and the objects a fault names move;
* the supports form a tree (no cycle), and a placed object rests on a placed one or on the world;
* a fault changes only what it concerns: a part the robot does not hold, a kit.

The default profile is fast (tens of examples on the small kit); ``-m slow`` runs many more,
longer programs, on a generated 40-part kit as well.
"""

from __future__ import annotations

from functools import lru_cache
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from kb import crcl
from kb.core.resources import ontology_path
from kb.model.faults import shipped_fault_kinds
from kb.sim import FaultSpec, SimulatedCell
from kb.sim.world import KIT_TRAY, World
from kb.spatial.scene import Scene

SMALL_KIT = ontology_path("scenarios/small-kit/init.ttl")
ATOL = 1e-9
DOWN = (0.0, 0.0, -1.0)


@lru_cache(maxsize=None)
def scene_of(which: str) -> Scene:
    if which == "small-kit":
        return Scene.from_files([SMALL_KIT], [ontology_path("scenarios/small-kit/goal.ttl")])
    from tempfile import mkdtemp

    from kb.scenario import write_scenario
    init, goal = write_scenario(Path(mkdtemp()), parts=40, kits=2, seed=3)
    return Scene.from_files([init], [goal])


# --- strategies -----------------------------------------------------------------------------

KINDS = shipped_fault_kinds()
FAULT_KINDS = KINDS.names


def fault_specs() -> st.SearchStrategy[FaultSpec]:
    """Rates for every kind (those of one action adding up to at most 1) and a seed."""
    def spec(weights: list[float], scale: float, seed: int) -> FaultSpec:
        rates = {}
        for action in KINDS.actions:
            kinds = [k.name for k in KINDS.eligible(action)]
            total = sum(weights[FAULT_KINDS.index(k)] for k in kinds) or 1.0
            for k in kinds:  # a kind striking several actions (defective-part): its least share
                rates[k] = min(rates.get(k, 1.0), scale * weights[FAULT_KINDS.index(k)] / total)
        return FaultSpec(rates, seed=seed)
    return st.builds(spec, st.lists(st.floats(0, 1), min_size=len(FAULT_KINDS), max_size=len(FAULT_KINDS)),
                     st.floats(0, 1), st.integers(0, 2**32 - 1))


def _unit(data: st.DataObject, label: str) -> tuple[float, float, float]:
    v = np.array(data.draw(st.tuples(*[st.floats(-1, 1)] * 3), label=label))
    return tuple(v) if np.linalg.norm(v) > 0.1 else DOWN  # type: ignore[return-value]


def _orientation(data: st.DataObject) -> tuple[tuple[float, float, float], tuple[float, float, float]]:
    """(x axis, z axis): tool down at a random yaw, or any orientation."""
    if data.draw(st.booleans(), label="tool down"):
        a = data.draw(st.floats(-np.pi, np.pi), label="yaw")
        return (float(np.cos(a)), float(np.sin(a)), 0.0), DOWN
    z = _unit(data, "z axis")
    x = np.cross(z, _unit(data, "x hint"))
    if np.linalg.norm(x) < 1e-3:
        x = np.cross(z, (1.0, 0.0, 0.0)) if abs(z[0]) < 0.9 else np.cross(z, (0.0, 1.0, 0.0))
    return tuple(x), z  # type: ignore[return-value]


def _point(data: st.DataObject, cell: SimulatedCell) -> tuple[float, float, float]:
    """Near the cell (its objects' extent and a metre around), or at an object's top face."""
    w = cell.world
    placed = [i for i in w.solids()]
    if placed and data.draw(st.booleans(), label="at an object"):
        i = data.draw(st.sampled_from(placed), label="object")
        lo, hi = w.box(i)
        fx, fy = data.draw(st.floats(0, 1), label="fx"), data.draw(st.floats(0, 1), label="fy")
        dz = data.draw(st.sampled_from([0.0, 0.0, 0.001, -0.001, 0.05, 0.3]), label="dz")
        return float(lo[0] + fx * (hi[0] - lo[0])), float(lo[1] + fy * (hi[1] - lo[1])), float(hi[2] + dz)
    lo, hi = _extent(w)
    return tuple(float(data.draw(st.floats(float(lo[a]) - 1, float(hi[a]) + 1), label="xyz"[a]))
                 for a in range(3))  # type: ignore[return-value]


def _extent(w: World) -> tuple[np.ndarray, np.ndarray]:
    boxes = [w.box(i) for i in w.solids()]
    return np.min([b[0] for b in boxes], axis=0), np.max([b[1] for b in boxes], axis=0)


def _pose(data: st.DataObject, cell: SimulatedCell) -> crcl.Pose:
    """A target near the cell, or (one in twenty) a wild one: a point kilometres to 1e300 m
    away, or axes whose norm overflows."""
    if data.draw(st.integers(0, 19), label="wild?") == 0:
        huge = st.tuples(*[st.floats(-1e300, 1e300)] * 3)
        if data.draw(st.booleans(), label="wild point"):
            return crcl.Pose(data.draw(huge, label="point"), *_orientation(data))
        z, x = data.draw(huge, label="z axis"), data.draw(huge, label="x axis")
        if not (any(z) and any(x)):
            z, x = DOWN, (1.0, 0.0, 0.0)
        return crcl.Pose(_point(data, cell), x, z)
    return crcl.Pose(_point(data, cell), *_orientation(data))


def _mount_pose(data: st.DataObject, cell: SimulatedCell) -> crcl.Pose | None:
    """The tool tip at a free end effector's mount face, oriented as it is."""
    w = cell.world
    free = [j for j in w.solids(set(w.subtree(cell.robot.index))) if w.is_a(j, "EndEffector")]
    if not free:
        return None
    j = data.draw(st.sampled_from(free), label="effector")
    return crcl.Pose.from_matrix(w.poses[j])


def _names(cell: SimulatedCell, cls: str) -> list[str]:
    w = cell.world
    return [w.names[i] for i in range(len(w)) if w.is_a(i, cls)]


def _action(data: st.DataObject, cell: SimulatedCell) -> tuple[str, tuple[str, ...]]:
    """A plan action with sensible arguments (as a plan has them), or any objects at all."""
    w = cell.world
    action = data.draw(st.sampled_from(["take-part", "take-part", "put-part", "create-kit", "attach-endeffector",
                                        "look-for-part"]), label="action")
    if data.draw(st.integers(0, 4), label="nonsense?") == 0:
        return action, tuple(data.draw(st.lists(st.sampled_from(w.names), max_size=5), label="any args"))
    robot = w.names[cell.robot.index]
    part = data.draw(st.sampled_from(_names(cell, "Part")), label="part")
    i = w.index[part]
    tray = w.names[int(w.parent[i])] if w.parent[i] >= 0 else part
    kits = _names(cell, "Kit") or [part]
    kit = data.draw(st.sampled_from(kits), label="kit")
    if action == "put-part":
        return action, (robot, part, kit, "work_table", w.sku(i) or "")
    if action == "create-kit":
        trays = w.objects(KIT_TRAY, kit) or _names(cell, "KitTray") or [part]
        return action, (kit, trays[0], "work_table")
    return action, (robot, part, tray, "gripper")


def _step(data: st.DataObject, cell: SimulatedCell, index: int) -> str:
    """Draw one step and carry it out; its description (for the failure message)."""
    kind = data.draw(st.sampled_from(
        ["move", "move", "move", "through", "straight", "grasp", "grasp", "release", "mount", "unmount",
         "action", "action", "speed", "dwell", "units", "canon", "sense", "inspect"]), label="step")
    command: crcl.Command | None = None
    if kind in ("move", "straight"):
        pose = _pose(data, cell)
        command = crcl.MoveTo(pose) if kind == "move" else crcl.MoveStraightTo(pose)
    elif kind == "through":
        command = crcl.MoveThroughTo(tuple(_pose(data, cell) for _ in range(data.draw(st.integers(1, 4)))))
    elif kind == "grasp":
        x, y, z = _point(data, cell)
        cell.execute(crcl.MoveTo(crcl.Pose((x, y, z), _orientation(data)[0], DOWN)))
        command = crcl.CloseGripper()
    elif kind == "release":
        command = crcl.OpenGripper()
    elif kind == "mount":
        pose = _mount_pose(data, cell)
        if pose is not None:
            cell.execute(crcl.MoveTo(pose))
        command = crcl.CloseToolChanger()
    elif kind == "unmount":
        command = crcl.OpenToolChanger()
    elif kind == "speed":
        command = crcl.SetAbsoluteSpeed(data.draw(st.one_of(st.floats(1e-3, 10), st.floats(1e-320, 1e-300),
                                                            st.floats(-1, 0)), label="speed"))
    elif kind == "dwell":
        command = crcl.Dwell(data.draw(st.one_of(st.floats(0, 10), st.floats(1e300, 1e308), st.floats(-1, 0)),
                                       label="seconds"))
    elif kind == "units":
        command = data.draw(st.sampled_from([crcl.SetLengthUnits("meter"), crcl.SetLengthUnits("millimeter"),
                                             crcl.SetAngleUnits("radian"), crcl.SetAngleUnits("degree")]))
    elif kind == "canon":
        command = data.draw(st.sampled_from([crcl.InitCanon(), crcl.EndCanon(), crcl.Message("hello")]))
    elif kind == "action":
        action, args = _action(data, cell)
        cell.begin_action(index, action, args)
        return f"begin_action({index}, {action}, {args})"
    elif kind == "sense":
        for obs in cell.sense("SolidObject"):
            assert np.all(np.isfinite(obs.location)) and np.all(np.isfinite(obs.orientation)), obs
        return "sense"
    else:
        parts = _names(cell, "Part")
        cell.inspect(data.draw(st.sampled_from(parts), label="inspected"))
        return "inspect"
    status = cell.execute(command)
    assert status is not None
    return repr(command)


# --- invariants -------------------------------------------------------------------------------

class Snapshot:
    def __init__(self, cell: SimulatedCell):
        w = cell.world
        self.poses, self.parent = w.poses.copy(), w.parent.copy()
        self.lo, self.hi = w.local_lo.copy(), w.local_hi.copy()
        self.time, self.injected = cell.time, len(cell.injected)
        self.robot_tree = set(w.subtree(cell.robot.index))


def _placed(poses: np.ndarray) -> np.ndarray:
    return ~np.isnan(poses).all(axis=(1, 2))


def check_poses(w: World, what: str) -> None:
    p = w.poses
    placed = _placed(p)
    finite = np.isfinite(p).all(axis=(1, 2))
    bad = placed & ~finite
    assert not bad.any(), f"{what}: pose of {w.names[int(np.argmax(bad))]} is not finite: {p[bad][0]}"
    r = p[placed, :3, :3]
    ortho = np.abs(np.swapaxes(r, 1, 2) @ r - np.eye(3)).max(axis=(1, 2)) if len(r) else np.zeros(0)
    names = [n for n, k in zip(w.names, placed) if k]
    assert np.all(ortho <= ATOL), f"{what}: rotation of {names[int(np.argmax(ortho))]} is not orthonormal"
    assert np.allclose(np.linalg.det(r), 1.0) if len(r) else True, f"{what}: a rotation is a reflection"
    assert np.array_equal(p[placed, 3], np.tile([0.0, 0.0, 0.0, 1.0], (int(placed.sum()), 1))), what


def check_tree(w: World, what: str) -> None:
    n = len(w)
    placed = _placed(w.poses)
    for i in range(n):
        seen, j = {i}, int(w.parent[i])
        while j >= 0:
            assert j < n and j not in seen, f"{what}: the supports of {w.names[i]} form a cycle"
            seen.add(j)
            j = int(w.parent[j])
        p = int(w.parent[i])
        assert not placed[i] or p < 0 or placed[p], f"{what}: {w.names[i]} rests on {w.names[p]}, not placed"


def check_boxes(cell: SimulatedCell, first: Snapshot, what: str) -> None:
    w = cell.world
    replaced = {o[0] for o in (x.objects for x in cell.injected if x.kind == "wrong-sku")}
    for i in range(len(first.lo)):
        same = np.array_equal(w.local_lo[i], first.lo[i], equal_nan=True) and \
            np.array_equal(w.local_hi[i], first.hi[i], equal_nan=True)
        if same:
            continue
        name = w.names[i]
        if name in replaced:  # the box of a part of its new SKU
            sku = w.sku(i)
            sizes = [(first.lo[j], first.hi[j]) for j in range(len(first.lo)) if w.sku(j) == sku and j != i]
            assert any(np.array_equal(w.local_lo[i], lo) and np.array_equal(w.local_hi[i], hi)
                       for lo, hi in sizes) or not sizes, f"{what}: {name} has no box of {sku}"
        elif w.is_a(i, "Kit") and np.isnan(first.lo[i]).all():  # created: its tray's box
            trays = [w.index[t] for t in w.objects(KIT_TRAY, name) if t in w.index]
            assert any(np.array_equal(w.local_lo[i], first.lo[t]) for t in trays), f"{what}: box of {name}"
        else:
            pytest.fail(f"{what}: the local box of {name} changed")


def _subtrees(parent: np.ndarray, roots: set[int]) -> set[int]:
    out, todo = set(), list(roots)
    while todo:
        j = todo.pop()
        if j in out:
            continue
        out.add(j)
        todo.extend(int(k) for k in np.flatnonzero(parent == j))
    return out


def _relative(poses: np.ndarray, child: int, parent: int) -> np.ndarray:
    g = poses[parent]
    inv = np.eye(4)
    inv[:3, :3] = g[:3, :3].T
    inv[:3, 3] = -g[:3, :3].T @ g[:3, 3]
    return inv @ poses[child]


def check_rigid(cell: SimulatedCell, before: Snapshot, what: str) -> None:
    """What did not move kept its pose; children kept theirs relative to an unchanged support."""
    w = cell.world
    new_faults = cell.injected[before.injected:]
    named = {w.index[o] for x in new_faults for o in x.objects if o in w.index}
    changed = {int(i) for i in np.flatnonzero(before.parent != w.parent[:len(before.parent)])}
    roots = {cell.robot.index} | changed | named
    movers = _subtrees(before.parent, roots) | _subtrees(w.parent, roots) | before.robot_tree
    placed_before, placed_now = _placed(before.poses), _placed(w.poses[:len(before.poses)])
    for i in range(len(before.poses)):
        if not (placed_before[i] and placed_now[i]):
            continue
        if i not in movers:
            assert np.allclose(w.poses[i], before.poses[i], atol=ATOL), f"{what}: {w.names[i]} moved"
        p = int(w.parent[i])
        if i in roots or p < 0 or p != before.parent[i] or not (placed_before[p] and placed_now[p]):
            continue
        assert np.allclose(_relative(w.poses, i, p), _relative(before.poses, i, p), atol=1e-7), \
            f"{what}: {w.names[i]} did not move rigidly with {w.names[p]}"


def check_faults(cell: SimulatedCell, before: Snapshot, what: str) -> None:
    """A fault changes what its action concerns: a part free in the cell, or a kit not held."""
    w = cell.world
    for x in cell.injected[before.injected:]:
        i = w.index[x.objects[0]]
        assert w.is_a(i, "Kit" if x.kind == "kit-tray-moved" else "Part"), f"{what}: {x}"
        assert i not in before.robot_tree or x.kind in ("missed-grasp", "dropped-part"), f"{what}: {x}"


def check_all(cell: SimulatedCell, first: Snapshot, before: Snapshot, what: str) -> None:
    w = cell.world
    check_faults(cell, before, what)
    check_poses(w, what)
    check_tree(w, what)
    check_boxes(cell, first, what)
    check_rigid(cell, before, what)
    assert np.isfinite(cell.time) and cell.time >= before.time, f"{what}: clock {before.time} -> {cell.time}"


def drive(data: st.DataObject, which: str, steps: int) -> None:
    cell = SimulatedCell(scene_of(which), faults=data.draw(fault_specs(), label="faults"))
    first = Snapshot(cell)
    check_poses(cell.world, "initial state")
    history: list[str] = []
    for index in range(data.draw(st.integers(1, steps), label="steps")):
        before = Snapshot(cell)
        history.append(_step(data, cell, index))
        check_all(cell, first, before, " / ".join(history[-4:]))


FAST = settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow,
                                                                        HealthCheck.data_too_large])
SLOW = settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow,
                                                                         HealthCheck.data_too_large])


@FAST
@given(st.data())
def test_random_programs_and_faults_keep_poses_finite_and_bodies_rigid(data: st.DataObject) -> None:
    drive(data, "small-kit", 40)


@pytest.mark.slow
@settings(SLOW, max_examples=50)
@given(st.data())
def test_long_random_programs_and_faults_on_the_small_kit(data: st.DataObject) -> None:
    drive(data, "small-kit", 150)


@pytest.mark.slow
@settings(SLOW, max_examples=30)  # each example three times the small kit's time
@given(st.data())
def test_long_random_programs_and_faults_on_a_generated_kit(data: st.DataObject) -> None:
    drive(data, "generated", 150)
