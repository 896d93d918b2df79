"""Continuous contact (kb.spatial.sweep) and the constraint violations the simulated robot
notices: the swept boxes against dense sampling, plates and holes, the 5 mm part at speed,
MoveTo's transfer height, overweight and wrong-effector grasps, moves out of the work volume."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from kb import crcl
from kb.core.resources import ontology_path
from kb.sim import SimulatedCell
from kb.spatial.sweep import _depths, clearance, recessed, solid_pieces, sweep_contacts
from kb.spatial.transforms import from_xyz_rpy

INIT = ontology_path("scenarios/small-kit/init.ttl")
NS = "https://w3id.org/kitkb/scenario/small-kit#"
TOL = 0.001
EYE = np.eye(4)


def pose(x: float, y: float, z: float, yaw: float = 0.0) -> np.ndarray:
    return from_xyz_rpy(x, y, z, 0.0, 0.0, yaw)


def cube(size: float, at: tuple[float, float, float], open_top: bool = False):  # noqa: ANN201
    """One object: a cube of ``size`` standing at ``at`` (poses, its pieces)."""
    poses = np.array([pose(*at)])
    h = size / 2
    return poses, solid_pieces(np.array([[-h, -h, 0.0]]), np.array([[h, h, size]]), np.array([open_top]), np.array([0]))


def carried(path: list[np.ndarray], size=(0.1, 0.08, 0.06), poses=None, pieces=None):  # noqa: ANN001, ANN201
    """Contacts of a part of ``size`` hanging below the tip (its top face at the tip) along ``path``."""
    lx, ly, lz = size
    rel = np.array([np.diag([1.0, 1.0, 1.0, 1.0])])
    lo, hi = np.array([[-lx / 2, -ly / 2, -lz]]), np.array([[lx / 2, ly / 2, 0.0]])
    return sweep_contacts(np.array(path), rel, lo, hi, poses, pieces, tol=TOL)


# --- kb.spatial.sweep -------------------------------------------------------------------------

def test_a_5_mm_part_is_found_at_any_speed_though_both_end_poses_are_free() -> None:
    poses, pieces = cube(0.005, (0.5, 0.0, 0.0))
    low = 0.06 + 0.003  # the carried part's bottom 3 mm up: 2 mm into the 5 mm cube
    path = [pose(0.0, 0.0, low), pose(1.0, 0.0, low)]  # one metre in one command
    found = carried(path, poses=poses, pieces=pieces)
    assert [(c.body, c.owner) for c in found] == [(0, 0)] and found[0].depth == pytest.approx(0.002)
    for end in path:  # no contact at either end pose
        assert carried([end, end], poses=poses, pieces=pieces) == []
    # 1 mm deep is touching (the tolerance), 5 mm above is clear
    assert carried([pose(0.0, 0.0, 0.066 - 0.0001), pose(1.0, 0.0, 0.066 - 0.0001)], poses=poses, pieces=pieces) == []
    assert carried([pose(0.0, 0.0, 0.07), pose(1.0, 0.0, 0.07)], poses=poses, pieces=pieces) == []


def test_an_open_container_is_its_floor_and_walls() -> None:
    """A part lowered into a tray, resting on its floor, lifted out: no contact; moved out
    sideways through a wall: contact."""
    poses, pieces = cube(0.2, (0.0, 0.0, 0.0), open_top=True)
    inside = 0.06  # tip at the part's top when it stands on the floor
    assert carried([pose(0.0, 0.0, 0.5), pose(0.0, 0.0, inside)], poses=poses, pieces=pieces) == []
    assert carried([pose(0.0, 0.0, inside), pose(0.04, 0.0, inside)], poses=poses, pieces=pieces) == []
    through = carried([pose(0.0, 0.0, inside), pose(0.5, 0.0, inside)], poses=poses, pieces=pieces)
    assert [(c.body, c.owner) for c in through] == [(0, 0)]
    assert carried([pose(0.0, 0.0, 0.3), pose(0.5, 0.0, 0.3)], poses=poses, pieces=pieces) == []  # above the rim
    # the same tray closed is a solid: the part inside it is in contact
    poses, solid = cube(0.2, (0.0, 0.0, 0.0))
    assert carried([pose(0.0, 0.0, inside), pose(0.04, 0.0, inside)], poses=poses, pieces=solid)


def test_a_holder_recessed_in_a_base_is_a_hole() -> None:
    """An effector holder sunk into a station's base (the scenarios' layout): an effector
    leaves it straight up without touching the base; sideways it goes through the base."""
    poses = np.array([pose(0.0, 0.0, 0.0), pose(0.15, 0.0, 0.7)])
    llo, lhi = np.array([[-0.3, -0.15, 0.0], [-0.06, -0.06, 0.0]]), np.array([[0.3, 0.15, 0.8], [0.06, 0.06, 0.1]])
    top = np.array([False, True])
    holes = recessed(poses, llo, lhi, top, np.array([0, 1]))
    assert set(holes) == {0} and len(holes[0]) == 5  # the base less the holder's column
    pieces = solid_pieces(llo, lhi, top, np.array([0, 1]), holes)
    effector = (0.08, 0.06, 0.08)
    assert carried([pose(0.15, 0.0, 0.8), pose(0.15, 0.0, 1.0)], effector, poses, pieces) == []
    assert [c.owner for c in carried([pose(0.15, 0.0, 0.8), pose(-0.15, 0.0, 0.8)], effector, poses, pieces)] == [0, 1]


def test_clearance_lifts_what_is_carried_over_the_walls_on_its_way() -> None:
    poses, pieces = cube(0.15, (0.0, 0.0, 0.0), open_top=True)  # a large box, walls 0.15 high
    rel, lo, hi = np.array([EYE]), np.array([[-0.05, -0.05, 0.0]]), np.array([[0.05, 0.05, 0.09]])  # an effector
    way = np.array([pose(0.0, 0.0, 0.0), pose(1.0, 0.0, 0.0)])
    assert clearance(way, rel, lo, hi, poses, pieces) == pytest.approx(0.15)
    away = np.array([pose(0.5, 0.0, 0.0), pose(1.0, 0.0, 0.0)])  # nothing under this way
    assert clearance(away, rel, lo, hi, poses, pieces) == -np.inf


def _sampled_depth(path: np.ndarray, lo: np.ndarray, hi: np.ndarray, poses: np.ndarray, pieces, samples: int) -> float:  # noqa: ANN001
    """The deepest instant of a moving box along a straight, turning leg, sampled."""
    a, b = path
    from kb.spatial.sweep import _axis_angle, _turns
    axis, angle = _axis_angle(a[:3, :3].T @ b[:3, :3])
    s = np.linspace(0.0, 1.0, samples)
    rots = a[:3, :3] @ _turns(axis, s * angle) if angle > 0 else np.broadcast_to(a[:3, :3], (samples, 3, 3))
    centres = rots @ ((lo + hi) / 2) + (a[:3, 3] + s[:, None] * (b[:3, 3] - a[:3, 3]))
    g = poses[pieces.owner]
    best = -np.inf
    for p in range(len(pieces)):
        vb = np.broadcast_to(g[p, :3, :3], (samples, 3, 3))
        cb = g[p, :3, :3] @ ((pieces.lo[p] + pieces.hi[p]) / 2) + g[p, :3, 3]
        d = _depths(rots, np.broadcast_to((hi - lo) / 2, (samples, 3)), centres, np.zeros((samples, 3)),
                    np.zeros(samples), vb, np.broadcast_to((pieces.hi[p] - pieces.lo[p]) / 2, (samples, 3)),
                    np.broadcast_to(cb, (samples, 3)))
        best = max(best, float(d.max()))
    return best


@settings(max_examples=60, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(st.floats(-0.3, 0.3), min_size=6, max_size=6), st.floats(-1.5, 1.5), st.floats(-0.4, 0.4),
       st.booleans())
def test_the_sweep_agrees_with_dense_sampling(xyz: list[float], turn: float, obstacle_yaw: float, open_top: bool) -> None:
    """Never a miss: an instant deeper than the tolerance (with a sampling margin) is a
    contact; and a contact has an instant where the boxes meet."""
    poses = np.array([pose(0.0, 0.0, 0.0, obstacle_yaw)])
    pieces = solid_pieces(np.array([[-0.1, -0.05, 0.0]]), np.array([[0.1, 0.05, 0.08]]), np.array([open_top]),
                          np.array([0]))
    path = np.array([pose(xyz[0], xyz[1], 0.04 + xyz[2] / 3), pose(xyz[3], xyz[4], 0.04 + xyz[5] / 3, turn)])
    lo, hi = np.array([-0.04, -0.02, -0.03]), np.array([0.04, 0.02, 0.0])
    found = sweep_contacts(path, np.array([EYE]), lo[None], hi[None], poses, pieces, tol=TOL)
    samples = 2001
    step = np.linalg.norm(path[1, :3, 3] - path[0, :3, 3]) / (samples - 1) + 0.05 * abs(turn) / (samples - 1)
    deepest = _sampled_depth(path, lo, hi, poses, pieces, samples)
    if deepest > TOL + step:
        assert found, f"missed: an instant {deepest * 1000:.2f} mm deep"
    if found:
        assert deepest > -step - TOL / 4, f"a contact where the boxes never meet ({deepest * 1000:.2f} mm apart)"


# --- the simulated robot ----------------------------------------------------------------------

def move(x: float, y: float, z: float) -> crcl.MoveTo:
    return crcl.MoveTo(crcl.Pose((x, y, z), (1, 0, 0), (0, 0, -1)))


def straight(x: float, y: float, z: float) -> crcl.MoveStraightTo:
    return crcl.MoveStraightTo(crcl.Pose((x, y, z), (1, 0, 0), (0, 0, -1)))


def mount(cell: SimulatedCell, x: float, y: float = 0.0, z: float = 0.8) -> None:
    for c in (crcl.InitCanon(), move(x, y, z + 0.2), move(x, y, z), crcl.CloseToolChanger(), move(x, y, z + 0.2)):
        assert cell.execute(c).done


def in_grams(tmp_path: Path, **limits: float) -> Path:
    """small-kit written in grams, with some limits changed (name -> grams)."""
    text = INIT.read_text().replace('hasKittingWorkstation_WeightUnit "kilogram"', 'hasKittingWorkstation_WeightUnit "gram"')
    text = re.sub(r"(_Weight|_MaximumLoadWeight) ([0-9.]+)", lambda m: f"{m.group(1)} {float(m.group(2)) * 1000:g}", text)
    for name, grams in limits.items():
        text = re.sub(rf"(:{name} a .*?MaximumLoadWeight )[0-9.]+", rf"\g<1>{grams:g}", text, flags=re.S)
    path = tmp_path / "init.ttl"
    path.write_text(text)
    return path


def test_the_executors_moves_make_no_violation_and_a_clear_move_is_not_a_contact() -> None:
    cell = SimulatedCell(INIT)
    mount(cell, 2.85)
    for c in (move(0.165, 0.945, 0.81), crcl.CloseGripper(), move(0.165, -1.045, 0.06), crcl.OpenGripper(),
              move(1.4, 0.0, 1.0)):
        assert cell.execute(c).done
    assert cell.violations == []  # MoveTo went up over the tray's walls, across, and down into the box


def test_overweight_grasps_lift_nothing_in_the_files_units(tmp_path: Path) -> None:
    """small-kit in grams, the tray gripper's load 900 g: part_a_tray with its four parts
    (300 + 4 x 180 g) is too heavy; the kit tray (250 g) is not."""
    cell = SimulatedCell(in_grams(tmp_path, tray_gripper=900))
    mount(cell, 2.55)
    assert cell.execute(move(0.305, 0.995, 0.79)).done
    status = cell.execute(crcl.CloseGripper())
    assert not status.done and "weighs 1.02 kg, more than tray_gripper's maximum load 0.9 kg" in status.message
    assert cell.robot.held is None
    [v] = cell.violations
    assert (v.kind, v.command, v.objects) == ("overweight", 6, (NS + "part_a_tray", NS + "tray_gripper"))
    assert cell.execute(move(0.235, -0.995, 0.04)).done and cell.execute(crcl.CloseGripper()).done
    assert cell.robot.held == cell.world.index[NS + "kit_tray_1"] and len(cell.violations) == 1


def test_the_robots_load_counts_the_effector(tmp_path: Path) -> None:
    cell = SimulatedCell(in_grams(tmp_path, robot_1=600))  # tray gripper 400 g + kit tray 250 g
    mount(cell, 2.55)
    assert cell.execute(move(0.235, -0.995, 0.04)).done
    assert not cell.execute(crcl.CloseGripper()).done
    [v] = cell.violations
    assert v.kind == "overweight" and "robot_1's maximum load 0.6 kg (with tray_gripper: 0.65 kg)" in v.detail


def test_a_state_without_weights_or_volume_is_not_checked(tmp_path: Path) -> None:
    text = re.sub(r"ktw:has\w*(Weight|WorkVolume) ", "rdfs:comment ", INIT.read_text())  # no weight, no volume
    path = tmp_path / "init.ttl"
    path.write_text(text)
    cell = SimulatedCell(path)
    assert cell.world.work_volumes == {} and cell.world.weight(cell.world.index[NS + "part_a_1"]) is None
    mount(cell, 2.85)
    for c in (move(0.165, 0.945, 0.81), crcl.CloseGripper(), move(0.165, 0.945, 3.0)):
        assert cell.execute(c).done
    assert cell.violations == [] and cell.robot.held is not None


def test_work_volume_and_wrong_effector_are_counted_and_what_the_robot_does() -> None:
    cell = SimulatedCell(INIT)
    mount(cell, 2.85)  # the part gripper
    cell.begin_action(3, "take-kittray", ())
    assert cell.execute(move(0.235, -0.995, 0.04)).done
    status = cell.execute(crcl.CloseGripper())
    assert status.done and "does not suit" in status.message and cell.robot.held is None
    status = cell.execute(move(0.235, -0.995, 2.6))  # 2.5 m is the top of small-kit's work volume
    assert status.done and "outside the work volume" in status.message
    assert cell.robot.tip()[2, 3] == pytest.approx(2.6)  # the move was made
    kinds = [(v.kind, v.command, v.action) for v in cell.violations]
    assert kinds == [("wrong-effector", 6, 3), ("work-volume", 7, 3)]
    assert cell.violations[0].objects == (NS + "part_gripper", NS + "kit_tray_1")


def test_a_part_carried_through_a_tray_wall_and_other_parts() -> None:
    cell = SimulatedCell(INIT)
    mount(cell, 2.85)
    for c in (move(0.675, 0.945, 0.81), crcl.CloseGripper(), straight(0.675, 0.945, 0.86),
              straight(1.2, 0.945, 0.86)):  # 1 cm too low over part_b_2 and part_b_3
        assert cell.execute(c).done
    got = sorted((v.objects, v.command) for v in cell.violations)
    assert got == [((NS + "part_b_1", NS + "part_b_2"), 8), ((NS + "part_b_1", NS + "part_b_3"), 8)]
    for c in (move(0.305, 1.045, 0.82), straight(0.305, 1.40, 0.82)):  # into part_a_tray's free cell, out
        assert cell.execute(c).done  # through its back wall (the table below is 1 cm lower)
    assert [(v.objects, v.command) for v in cell.violations[2:]] == [((NS + "part_b_1", NS + "part_a_tray"), 10)]
