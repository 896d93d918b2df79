"""The MuJoCo cell (kb.physics): its scene, its robot's grasps and releases, faults caused by
physics, the cell by URL and the closed loop on it. Fast: a few seconds in all."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import mujoco
import numpy as np
import pytest

from kb.cells import CellRequest, open_cell
from kb.core.errors import InputError
from kb.crcl import CloseGripper, CloseToolChanger, MoveTo, OpenGripper, Pose
from kb.physics import MujocoCell, build, cylinders
from kb.physics import params as P
from kb.physics.robot import profile
from kb.sim import FaultSpec
from kb.sim.world import World
from kb.spatial.scene import Scene

ROOT = Path(__file__).resolve().parent.parent
SMALL = ROOT / "ontologies" / "scenarios" / "small-kit"
INIT, GOAL = SMALL / "init.ttl", SMALL / "goal.ttl"
DOWN = dict(x_axis=(1.0, 0.0, 0.0), z_axis=(0.0, 0.0, -1.0))


def _index(world: World, local: str) -> int:
    return next(i for i, n in enumerate(world.names) if n.endswith("#" + local))


def _tip(x: float, y: float, z: float) -> MoveTo:
    return MoveTo(end_position=Pose(point=(x, y, z), **DOWN))


@pytest.fixture(scope="module")
def small_scene() -> Scene:
    return Scene.from_files([INIT], [GOAL])


def test_scene_bodies_from_the_state(small_scene: Scene) -> None:
    """Parts and trays free, tables/boxes/holders fixed, effectors and the flange mocap;
    an open container is a floor plate and four walls; the XML loads in MuJoCo."""
    world = World.from_scene(small_scene)
    scene = build(world, cylinders(small_scene))
    model = mujoco.MjModel.from_xml_string(scene.xml)
    kinds = {world.names[i].rsplit("#", 1)[1]: b.kind for i, b in scene.bodies.items()}
    assert kinds["part_a_1"] == kinds["part_a_tray"] == kinds["kit_tray_1"] == "free"
    assert kinds["work_table_1"] == kinds["parts_table_1"] == kinds["empty_kit_tray_box"] == "static"
    assert kinds["part_gripper"] == kinds["tray_gripper"] == kinds["robot_1"] == "mocap"
    assert "changing_station_1" not in kinds and "kit_1" not in kinds  # stand-ins have no body of their own
    tray = next(b for b in scene.bodies.values() if b.name == "part_a_tray")
    assert len(tray.geoms) == 5
    body = model.body("part_a_tray")
    assert model.body_jntnum[body.id] == 1 and model.jnt_type[model.body_jntadr[body.id]] == mujoco.mjtJoint.mjJNT_FREE
    assert model.body_mocapid[model.body("part_gripper").id] >= 0
    assert model.neq == sum(1 for b in scene.bodies.values() if b.kind == "free")  # one grip weld each
    # the floor plate lies under the box's bottom face: what the state puts in the tray rests on it
    floor = model.geom("part_a_tray__0")
    assert floor.pos[2] + floor.size[2] == pytest.approx(0.0)


def test_masses_from_sku_weights(tmp_path: Path) -> None:
    """A generated state gives SKU weights: each part's body weighs its SKU's."""
    out = tmp_path / "g"
    subprocess.run([sys.executable, "-m", "kb.cli", "scenario", "generate", "--parts", "4", "--kits", "1",
                    "--seed", "2", "-o", str(out), "--quiet"], check=True, cwd=ROOT)
    cell = MujocoCell(out / "init.ttl", declared=[out / "goal.ttl"])
    w = cell.world
    parts = [i for i in range(len(w)) if w.is_a(i, "Part") and w.placed(i)]
    assert parts
    for i in parts:
        weight = w.values["https://w3id.org/kitkb/kitting#hasStockKeepingUnit_Weight"][w.sku(i)]
        assert cell.physics.mass(i) == pytest.approx(float(weight), rel=1e-4)


def test_initial_state_at_rest_where_the_file_puts_it() -> None:
    """Settling the initial state moves nothing more than the contacts' softness (< 0.1 mm)."""
    from kb.sim import SimulatedCell
    phys, kin = MujocoCell(INIT), SimulatedCell(INIT)
    d = np.nan_to_num(np.abs(phys.world.poses - kin.world.poses))
    assert d.max() < 1e-4
    assert (phys.world.parent == kin.world.parent).all()


def _mounted() -> MujocoCell:
    """small-kit's MuJoCo cell with the part gripper mounted."""
    cell = MujocoCell(INIT)
    w = cell.world
    g = w.poses[_index(w, "part_gripper")][:3, 3]
    assert cell.execute(_tip(*g)).done
    assert "mounted" in cell.execute(CloseToolChanger()).message
    return cell


def test_grasp_by_geometry_and_a_release_that_falls() -> None:
    """A grasp far off the centre misses; one within the fingers' reach holds the part off its
    centre; let go over the floor, it falls and comes to rest there (its fate: the floor)."""
    cell = _mounted()
    w = cell.world
    part = _index(w, "part_a_1")
    x, y, _ = w.poses[part][:3, 3]
    top = float(w.box(part)[1][2])
    half = float(w.local_hi[part, 0])
    cell.execute(_tip(x + half * 0.95, y, top))
    assert "nothing grasped" in cell.execute(CloseGripper()).message
    assert cell.robot.held is None
    cell.execute(_tip(x + 0.02, y, top))
    assert "grasped" in cell.execute(CloseGripper()).message and cell.robot.held == part
    cell.execute(_tip(0.2, -0.5, 1.0))
    held_at = w.poses[part][:3, 3] - cell.robot.tip()[:3, 3]
    assert held_at[0] == pytest.approx(-0.02, abs=2e-3)  # held where it was taken: 2 cm off the centre
    assert cell.execute(OpenGripper()).done
    assert w.box(part)[0][2] == pytest.approx(0.0, abs=2e-3)  # on the floor
    assert int(w.parent[part]) == -1
    fate = next(f for f in cell.part_fates() if f.name == w.names[part])
    assert fate.place == "floor"
    assert cell.physics.at_rest()


def test_vacuum_seal_by_cover() -> None:
    """A cup sealing on too little of the face holds nothing."""
    from kb.physics.robot import _covered
    half = np.array([0.05, 0.04])
    assert _covered(np.zeros(2), half, 0.02) == 1.0
    assert _covered(np.array([0.05, 0.0]), half, 0.02) == pytest.approx(0.5, abs=0.05)
    assert _covered(np.array([0.2, 0.0]), half, 0.02) == 0.0


def test_speed_profile() -> None:
    """A leg takes its length at the speed plus the ramps; a short one is triangular."""
    total, s = profile(1.0, 1.0, P.ACCELERATION)
    assert total == pytest.approx(1.0 + 1.0 / P.ACCELERATION)
    assert s(total) == pytest.approx(1.0) and s(total / 2) == pytest.approx(0.5)
    total, s = profile(0.01, 1.0, 2.0)
    assert total == pytest.approx(2 * np.sqrt(0.01 / 2.0)) and s(total) == pytest.approx(0.01)


def test_weak_grip_lets_go_and_physics_decides_where() -> None:
    """dropped-part (ReleaseInTransit) lets go at a seeded moment of the first sideways leg: the
    part lands where it falls, on what is below, recorded as it came to rest."""
    cell = _mounted()
    cell.faults = type(cell.faults)(FaultSpec.parse("dropped-part@0", seed=4), cell.world, cell.robot,
                                    cell.physics, cell.injected.append)
    w = cell.world
    part = _index(w, "part_b_1")
    cell.begin_action(0, "take-part", (w.names[_index(w, "robot_1")], w.names[part]))
    x, y, _ = w.poses[part][:3, 3]
    cell.execute(_tip(x, y, float(w.box(part)[1][2])))
    cell.execute(CloseGripper())
    cell.execute(_tip(1.4, 0.0, 1.1))  # across to the work table
    assert cell.robot.held is None
    (fault,) = cell.injected
    assert fault.kind == "dropped-part" and "came to rest" in fault.detail
    assert cell.physics.at_rest()
    z = float(w.box(part)[0][2])
    support = int(w.parent[part])
    assert z == pytest.approx(float(w.box(support)[1][2]) if support >= 0 else 0.0, abs=3e-3) or support >= 0


def test_push_moves_the_part_by_physics() -> None:
    """part-moved (DisplaceObject) is a seeded push: the part ends at rest elsewhere, the record
    says where MuJoCo left it."""
    cell = MujocoCell(INIT, faults=FaultSpec.parse("part-moved@0", seed=3))
    w = cell.world
    part = _index(w, "part_a_2")
    before = w.poses[part][:3, 3].copy()
    cell.begin_action(0, "take-part", (w.names[_index(w, "robot_1")], w.names[part],
                                       w.names[_index(w, "part_a_tray")], w.names[_index(w, "part_gripper")]))
    (fault,) = cell.injected
    assert fault.kind == "part-moved" and "came to rest" in fault.detail
    assert np.linalg.norm(w.poses[part][:3, 3] - before) > 1e-3
    assert cell.physics.at_rest()


def test_open_by_url_and_refusals() -> None:
    """mujoco: opens the physics cell with sim:'s parameters; a bad one is one line, exit 2."""
    scene = Scene.from_files([INIT], [GOAL])
    cell = open_cell("mujoco:?faults=missed-grasp@3&seed=2", CellRequest(scene=scene))
    assert isinstance(cell, MujocoCell) and cell.url.startswith("mujoco:")
    assert "part-fates" in cell.capabilities and "ground-truth" in cell.capabilities
    with pytest.raises(InputError):
        open_cell("mujoco:?nonsense=1", CellRequest(scene=scene))
    with pytest.raises(InputError):
        open_cell("mujoco:?faults=no-such-kind@1", CellRequest(scene=scene))


def test_closed_loop_builds_small_kit_on_physics() -> None:
    """The executor, metrics and report run unchanged: small-kit's kit is built on MuJoCo, with
    the same final predicates as on the kinematic cell."""
    from kb.execution.loop import run_scenario
    from kb.model.definitions import load_definitions
    from kb.sim import SimulatedCell
    from kb.spatial import DEFAULT_TOLERANCE, Evaluator
    facts = {}
    for kind in (MujocoCell, SimulatedCell):
        cell = kind(INIT, declared=[GOAL])
        run = run_scenario(INIT, GOAL, cell=cell)
        assert run.report()["goal_holds"] is True
        ev = Evaluator(load_definitions(None), cell.scene(), DEFAULT_TOLERANCE)
        facts[kind] = set(ev.facts())
    assert facts[MujocoCell] == facts[SimulatedCell]


def test_export_mjcf_command(tmp_path: Path) -> None:
    """kitkb sim export-mjcf writes a file MuJoCo loads; a missing state is exit 2, one line."""
    from kb.cli import main
    out = tmp_path / "scene.xml"
    assert main(["sim", "export-mjcf", str(INIT), "-o", str(out), "--quiet"]) == 0
    model = mujoco.MjModel.from_xml_path(str(out))
    assert model.body("part_a_1").id > 0
    assert main(["sim", "export-mjcf", str(tmp_path / "none.ttl"), "-o", str(out), "--quiet"]) == 2


def test_sim_serve_engine_builds_the_physics_cell() -> None:
    """kitkb sim serve --engine mujoco serves a MujocoCell (the same server and ports)."""
    from kb.cli.sim import _cell
    from kb.sim import SimulatedCell
    assert isinstance(_cell(str(INIT), str(GOAL), None, 0, None, engine="mujoco"), MujocoCell)
    plain = _cell(str(INIT), str(GOAL), None, 0, None)
    assert isinstance(plain, SimulatedCell) and not isinstance(plain, MujocoCell)


@pytest.mark.slow
def test_a_crcl_client_drives_the_physics_cell_over_the_server() -> None:
    """The MuJoCo cell behind kb.sim.CellServer: kitkb run --cell HOST:PORT builds small-kit."""
    from kb.execution.loop import run_scenario
    from kb.sim import CellServer
    cell = MujocoCell(INIT, declared=[GOAL])
    with CellServer(cell, sensor_port=0, command_port=0) as server:
        run = run_scenario(INIT, GOAL, cell=f"kitkb://{server.host}:{server.sensor_port}?command={server.command_port}")
    assert run.goal_holds
    assert cell.physics.steps > 0
