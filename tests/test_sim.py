"""kb.sim: the simulated workcell — ground truth, CRCL robot checked against the predicate
definitions, the seven fault kinds, seeded repeatability, sensor noise and USARTruth lines."""

from __future__ import annotations

from functools import lru_cache

import numpy as np
import pytest

from kb import crcl
from kb.core.resources import ontology_path
from kb.model.definitions import Definitions, read_definitions
from kb.model.soap import load_domain
from kb.model.faults import shipped_fault_kinds
from kb.sim import (CellInterface, FaultSpec, Injected, Observation, SimulatedCell, Status,
                    parse_truth_line, truth_line)
from kb.spatial.predicates import Evaluator, compile_relation
from kb.spatial.rcc8 import relate
from kb.spatial.scene import Scene

INIT = ontology_path("scenarios/small-kit/init.ttl")
NS = "https://w3id.org/kitkb/scenario/small-kit#"
ROBOT, PART, TRAY, TABLE = NS + "robot_1", NS + "part_a_1", NS + "part_a_tray", NS + "parts_table_1"
GRIPPER, HOLDER = NS + "part_gripper", NS + "part_gripper_holder"
TAKE = (ROBOT, PART, TRAY, GRIPPER)  # take-part(robot, part, partstray, endeffector)
# where things are in small-kit's initial state (tool tip poses, tool pointing down)
GRIPPER_MOUNT = (2.85, 0.0, 0.8)  # part gripper's mount face in its holder
TRAY_GRIPPER_MOUNT = (2.55, 0.0, 0.8)
PART_TOP = (0.165, 0.945, 0.81)  # top face of part_a_1 in part_a_tray
KIT_TRAY_TOP = (0.235, -0.995, 0.04)  # kit_tray_1 in the large box of empty kit trays


@lru_cache(maxsize=1)
def definitions() -> Definitions:
    _, g = load_domain()
    return read_definitions(g)


def holds(cell: SimulatedCell, predicate: str, *args: str) -> bool:
    return Evaluator(definitions(), cell.scene()).holds(predicate, *args)


def related(cell: SimulatedCell, relation: str, a: str, b: str) -> bool:
    """The intermediate state relation ``relation`` (local name) between objects a and b."""
    iri = next(i for i in definitions().relations if i.endswith("#" + relation) or i.endswith("/" + relation))
    s = cell.scene()
    ia, ib = s.index[a], s.index[b]
    mask = relate(s.lo[[ia]], s.hi[[ia]], s.lo[[ib]], s.hi[[ib]])
    return bool(compile_relation(definitions().relation(iri))(mask)[0, 0])


def move(x: float, y: float, z: float) -> crcl.MoveTo:
    return crcl.MoveTo(crcl.Pose((x, y, z), (1, 0, 0), (0, 0, -1)))


def run(cell: SimulatedCell, *commands: crcl.Command) -> list[Status]:
    statuses = [cell.execute(c) for c in commands]
    assert all(s.done for s in statuses), statuses
    return statuses


def mount(cell: SimulatedCell, at: tuple[float, float, float] = GRIPPER_MOUNT) -> None:
    x, y, z = at
    run(cell, crcl.InitCanon(), move(x, y, z + 0.2), move(x, y, z), crcl.CloseToolChanger(), move(x, y, z + 0.2))


def pick(cell: SimulatedCell, top: tuple[float, float, float] = PART_TOP) -> None:
    x, y, z = top
    run(cell, move(x, y, 1.0), move(x, y, z), crcl.CloseGripper(), move(x, y, 1.0))


def box(cell: SimulatedCell, name: str) -> tuple[np.ndarray, np.ndarray]:
    s = cell.scene()
    return s.lo[s.index[name]], s.hi[s.index[name]]


# --- ground truth ----------------------------------------------------------------------

def test_ground_truth_reproduces_the_state_files_scene() -> None:
    file_scene = Scene.from_files([INIT])
    truth = SimulatedCell(INIT).scene()
    assert truth.names == file_scene.names
    assert truth.classes == file_scene.classes
    np.testing.assert_array_equal(truth.lo, file_scene.lo)
    np.testing.assert_array_equal(truth.hi, file_scene.hi)
    np.testing.assert_array_equal(truth.parents, file_scene.parents)
    np.testing.assert_array_equal(truth.open_top, file_scene.open_top)
    assert truth.facts == file_scene.facts and truth.values == file_scene.values
    assert truth.inspections == {"quality-inspection": set()}
    assert truth.names[truth.parents[truth.index[PART]]] == TRAY


def test_the_cell_implements_the_interface() -> None:
    assert isinstance(SimulatedCell(INIT), CellInterface)


# --- the robot, checked against the predicate definitions --------------------------------

def test_attach_grasp_lift_release_detach() -> None:
    cell = SimulatedCell(INIT)
    assert holds(cell, "robot-with-no-endeffector", ROBOT)
    mount(cell)
    assert holds(cell, "endeffector-location-robot", GRIPPER, ROBOT)
    assert holds(cell, "robot-with-endeffector", ROBOT, GRIPPER)
    assert holds(cell, "robot-empty", ROBOT)
    assert not holds(cell, "endeffector-location-endeffectorholder", GRIPPER, HOLDER)
    pick(cell)
    assert holds(cell, "robot-holds-part", ROBOT, PART)
    assert holds(cell, "part-location-robot", PART, ROBOT)
    assert not holds(cell, "part-location-partstray", PART, TRAY)
    assert not holds(cell, "robot-empty", ROBOT)
    lo, hi = box(cell, PART)  # the part hangs under the tip: its top face at the tip
    assert hi[2] == pytest.approx(1.0) and lo[2] == pytest.approx(0.94)
    # released in the air above the work table: falls onto it
    run(cell, move(1.4, 0.1, 1.2), crcl.OpenGripper())
    assert holds(cell, "robot-empty", ROBOT)
    assert not holds(cell, "robot-holds-part", ROBOT, PART)
    assert not holds(cell, "part-location-robot", PART, ROBOT)
    assert related(cell, "On-Top-With-Contact", PART, NS + "work_table_1")
    lo, hi = box(cell, PART)
    np.testing.assert_allclose((lo + hi)[:2] / 2, (1.4, 0.1))
    assert lo[2] == pytest.approx(0.75)
    assert cell.scene().names[cell.scene().parents[cell.scene().index[PART]]] == NS + "work_table_1"
    # taken again and released high above its tray: falls back into it
    pick(cell, (1.4, 0.1, 0.81))
    run(cell, move(PART_TOP[0], PART_TOP[1], 1.3), crcl.OpenGripper())
    assert holds(cell, "part-location-partstray", PART, TRAY)
    assert box(cell, PART)[0][2] == pytest.approx(0.75)
    # back to the holder and detached: the gripper stays in it
    x, y, z = GRIPPER_MOUNT
    run(cell, move(x, y, z + 0.2), move(x, y, z - 0.08), crcl.OpenToolChanger(), move(x, y, z + 0.3))
    assert holds(cell, "endeffector-location-endeffectorholder", GRIPPER, HOLDER)
    assert holds(cell, "robot-with-no-endeffector", ROBOT)
    assert not holds(cell, "endeffector-location-robot", GRIPPER, ROBOT)
    np.testing.assert_allclose(box(cell, GRIPPER)[0], Scene.from_files([INIT]).lo[cell.scene().index[GRIPPER]])


def test_many_moves_keep_the_robot_and_its_load_rigid() -> None:
    """A run moves the flange hundreds of times; rounding must not build up (it once doubled
    per move until the poses overflowed)."""
    cell = SimulatedCell(INIT)
    mount(cell)
    pick(cell)
    size = np.subtract(*box(cell, PART)[::-1])
    for k in range(400):
        a = 0.3 + 0.001 * k
        run(cell, crcl.MoveTo(crcl.Pose((1.0 + 0.2 * (k % 2), 0.5, 1.2), (np.cos(a), np.sin(a), 0), (0, 0, -1))))
    w = cell.world
    for name in (ROBOT, GRIPPER, PART):
        r = w.poses[w.index[name], :3, :3]
        np.testing.assert_allclose(r.T @ r, np.eye(3), atol=1e-9)
    lo, hi = box(cell, PART)  # a yawed box of the part's size, not a blown-up one
    assert np.all(hi[:2] - lo[:2] <= np.hypot(*size[:2]) + 1e-9) and hi[2] - lo[2] == pytest.approx(size[2])


def test_a_grasp_with_the_wrong_effector_grasps_nothing() -> None:
    cell = SimulatedCell(INIT)
    mount(cell, TRAY_GRIPPER_MOUNT)
    assert holds(cell, "robot-with-endeffector", ROBOT, NS + "tray_gripper")
    x, y, z = PART_TOP  # the tray gripper's tip at the part's top face
    status = run(cell, move(x, y, 1.0), move(x, y, z), crcl.CloseGripper(), move(x, y, 1.0))[2]
    assert "does not suit" in status.message
    assert holds(cell, "part-location-partstray", PART, TRAY)
    assert not holds(cell, "robot-holds-part", ROBOT, PART)
    assert holds(cell, "robot-empty", ROBOT)
    # the tray gripper does suit a kit tray
    pick(cell, KIT_TRAY_TOP)
    assert holds(cell, "robot-holds-kittray", ROBOT, NS + "kit_tray_1")
    assert not holds(cell, "kittray-location-lbwekt", NS + "kit_tray_1", NS + "empty_kit_tray_supply")


def test_no_effector_grasps_nothing_and_time_follows_distance_and_speed() -> None:
    cell = SimulatedCell(INIT)
    run(cell, crcl.SetAbsoluteSpeed(0.5), move(0.2, 0.0, 1.18))
    # with no effector the tip is the flange's far face, 0.02 below the flange at z 1.2: no move
    assert cell.time == pytest.approx(0.0)
    run(cell, move(0.2, 0.0, 0.68), crcl.Dwell(1.5))
    assert cell.time == pytest.approx(0.5 / 0.5 + 1.5)
    assert run(cell, crcl.CloseGripper())[0].message.startswith("nothing grasped")


def test_units_and_unreadable_lines() -> None:
    cell = SimulatedCell(INIT)
    assert cell.execute(crcl.SetLengthUnits("meter")).done
    assert cell.execute(crcl.SetAngleUnits("radian")).done
    assert cell.execute(crcl.SetLengthUnits("millimeter")).done and cell.robot.metres == 0.001
    assert cell.execute(crcl.SetAngleUnits("degree")).done
    assert cell.execute(crcl.SetCoordinateFrame("RobotBase")).state == "error"
    assert cell.execute(crcl.Unreadable("MoveTo(")).state == "error"
    for c in (crcl.Message("hi"), crcl.StartObjectScan("part_a_1"), crcl.StopObjectScan(), crcl.StopMotion(0),
              crcl.EndCanon()):
        assert cell.execute(c).done


def test_create_kit_makes_the_kit_where_its_tray_is_and_carries_it() -> None:
    cell = build_kit()
    kit = NS + "kit_1"
    assert holds(cell, "kit-location-worktable", kit, NS + "work_table_1")
    assert holds(cell, "kit-kittray", kit, NS + "kit_tray_1")
    np.testing.assert_array_equal(box(cell, kit)[0], box(cell, NS + "kit_tray_1")[0])


def build_kit() -> SimulatedCell:
    """small-kit with kit_tray_1 put on the work table and kit_1 created on it; tray gripper mounted."""
    cell = SimulatedCell(INIT, faults=FaultSpec(at={5: "kit-tray-moved"}, seed=3))
    mount(cell, TRAY_GRIPPER_MOUNT)
    pick(cell, KIT_TRAY_TOP)
    run(cell, move(1.4, 0.0, 0.9), crcl.OpenGripper(), move(1.4, 0.0, 1.2))
    cell.begin_action(4, "create-kit", (NS + "kit_1", NS + "kit_tray_1", NS + "work_table_1"))
    assert NS + "kit_1" not in cell.scene().index  # the kit comes into being as the action ends
    run(cell, crcl.InitCanon(), crcl.Message("kit kit_1 starts on kit_tray_1"), crcl.EndCanon())
    return cell


# --- faults -------------------------------------------------------------------------------

def test_missed_grasp_leaves_the_part_in_its_tray() -> None:
    cell = SimulatedCell(INIT, faults=FaultSpec(at={1: "missed-grasp"}, seed=1))
    mount(cell)
    cell.begin_action(1, "take-part", TAKE)
    pick(cell)
    assert holds(cell, "part-location-partstray", PART, TRAY)
    assert not holds(cell, "robot-holds-part", ROBOT, PART)
    assert [(i.kind, i.action_index, i.objects) for i in cell.injected] == [("missed-grasp", 1, (PART,))]
    cell.begin_action(2, "take-part", TAKE)  # armed for action 1 only
    pick(cell)
    assert holds(cell, "robot-holds-part", ROBOT, PART)
    assert len(cell.injected) == 1


def test_dropped_part_falls_in_transit() -> None:
    cell = SimulatedCell(INIT, faults=FaultSpec(at={3: "dropped-part"}, seed=1))
    mount(cell)
    cell.begin_action(3, "take-part", TAKE)
    pick(cell)
    assert holds(cell, "robot-holds-part", ROBOT, PART)  # the short lift is no transit
    cell.begin_action(4, "put-part", (ROBOT, PART, NS + "kit_1", NS + "work_table_1", TRAY))
    run(cell, move(1.4, 0.0, 1.0))
    assert not holds(cell, "robot-holds-part", ROBOT, PART)
    assert holds(cell, "robot-empty", ROBOT)
    lo, hi = box(cell, PART)  # half way from above the tray to above the work table: the floor
    np.testing.assert_allclose((lo + hi)[:2] / 2, ((0.165 + 1.4) / 2, 0.945 / 2))
    assert lo[2] == 0.0
    [inj] = cell.injected
    assert (inj.kind, inj.action_index, inj.objects) == ("dropped-part", 3, (PART,))
    assert "the floor" in inj.detail


def test_dropped_part_never_drops_what_is_not_a_part() -> None:
    """A client may announce take-part and then grasp a kit tray: the armed fault waits for a part."""
    cell = SimulatedCell(INIT, faults=FaultSpec(at={3: "dropped-part"}, seed=1))
    mount(cell, TRAY_GRIPPER_MOUNT)
    cell.begin_action(3, "take-part", TAKE)
    pick(cell, KIT_TRAY_TOP)
    run(cell, move(1.4, 0.0, 1.2))
    assert cell.injected == []
    lo, hi = box(cell, NS + "kit_tray_1")
    np.testing.assert_allclose((lo + hi)[:2] / 2, (1.4, 0.0), atol=0.05)  # carried, not fallen
    assert lo[2] > 0.5


def test_part_missing_takes_the_part_out_of_the_cell() -> None:
    cell = SimulatedCell(INIT, faults=FaultSpec.parse("part-missing@0", seed=1))
    cell.begin_action(0, "take-part", TAKE)
    scene = cell.scene()
    assert not scene.placed[scene.index[PART]]
    assert not holds(cell, "part-location-partstray", PART, TRAY)
    assert holds(cell, "part-location-partstray", NS + "part_a_2", TRAY)
    assert cell.sense("part_a_1", by="name") == []
    assert not cell.inspect(PART)
    assert cell.injected == [Injected("part-missing", 0, (PART,), "taken out of the cell from " + TRAY)]


def test_part_moved_within_its_tray_or_out_of_it() -> None:
    original = Scene.from_files([INIT])
    outcomes = set()
    for seed in range(8):
        cell = SimulatedCell(INIT, faults=FaultSpec(at={0: "part-moved"}, seed=seed))
        cell.begin_action(0, "take-part", TAKE)
        [inj] = cell.injected
        lo, hi = box(cell, PART)
        old_lo, old_hi = original.lo[original.index[PART]], original.hi[original.index[PART]]
        assert np.linalg.norm((lo + hi - old_lo - old_hi)[:2] / 2) >= 0.01
        assert hi - lo == pytest.approx(old_hi - old_lo)
        how = inj.detail.split()[0]
        outcomes.add(how)
        assert holds(cell, "part-location-partstray", PART, TRAY) == (how == "shifted")
        if how == "shifted":
            assert lo[2] == pytest.approx(0.75)
        else:  # small-kit's parts table has no room beside its trays: the part is knocked off
            assert how == "knocked" and lo[2] == 0.0 and "beside parts_table_1" in inj.detail
            assert not related(cell, "In-Contact-With", PART, TABLE)
        for other in ("part_a_2", "part_a_3", "part_a_4", "part_b_1"):  # no overlap with its neighbours
            olo, ohi = box(cell, NS + other)
            assert np.any(hi[:2] <= olo[:2] + 1e-9) or np.any(lo[:2] >= ohi[:2] - 1e-9)
    assert outcomes == {"shifted", "knocked"}


def test_defective_part_only_inspection_reveals_it() -> None:
    cell = SimulatedCell(INIT, faults=FaultSpec(at={0: "defective-part"}, seed=1))
    before = cell.scene()
    cell.begin_action(0, "take-part", TAKE)
    after = cell.scene()
    np.testing.assert_array_equal(after.lo, before.lo)
    np.testing.assert_array_equal(after.hi, before.hi)
    assert after.facts == before.facts
    assert not cell.inspect(PART)
    assert cell.inspect(NS + "part_a_2")
    assert not holds(cell, "part-quality-ok", PART)
    assert holds(cell, "part-quality-ok", NS + "part_a_2")
    assert cell.scene().inspections == {"quality-inspection": {NS + "part_a_2"}}
    assert cell.injected == [Injected("defective-part", 0, (PART,), "flagged defective")]


def test_wrong_sku_changes_the_parts_sku_and_shape() -> None:
    cell = SimulatedCell(INIT, faults=FaultSpec(at={0: "wrong-sku"}, seed=1))
    assert holds(cell, "part-sku", PART, NS + "sku_part_a")
    lo0, hi0 = box(cell, PART)
    cell.begin_action(0, "take-part", TAKE)
    assert holds(cell, "part-sku", PART, NS + "sku_part_b")
    assert not holds(cell, "part-sku", PART, NS + "sku_part_a")
    lo, hi = box(cell, PART)
    np.testing.assert_allclose(hi - lo, (0.12, 0.08, 0.06))  # part B's box
    np.testing.assert_allclose((lo + hi)[:2] / 2, (lo0 + hi0)[:2] / 2)
    assert lo[2] == lo0[2]
    assert cell.injected[0].objects == (PART, NS + "sku_part_b")


def test_kit_tray_moved_shifts_the_kit_on_the_work_table() -> None:
    cell = build_kit()
    kit, tray = NS + "kit_1", NS + "kit_tray_1"
    lo0, hi0 = box(cell, tray)
    cell.begin_action(5, "put-part", (ROBOT, PART, kit, NS + "work_table_1", TRAY))
    lo, hi = box(cell, tray)
    shift = lo - lo0
    assert shift[2] == 0.0 and 0.02 <= np.linalg.norm(shift[:2]) <= 0.06
    np.testing.assert_allclose(box(cell, kit)[0], lo)
    assert holds(cell, "kit-location-worktable", kit, NS + "work_table_1")
    [inj] = cell.injected
    assert (inj.kind, inj.action_index, inj.objects) == ("kit-tray-moved", 5, (kit, tray))


def test_a_fault_named_for_an_ineligible_action_waits_for_an_eligible_one() -> None:
    cell = SimulatedCell(INIT, faults=FaultSpec(at={0: "part-missing"}, seed=1))
    cell.begin_action(0, "attach-endeffector", (ROBOT, GRIPPER, HOLDER, NS + "changing_station_1"))
    assert cell.injected == []
    cell.begin_action(1, "take-part", TAKE)
    assert [(i.kind, i.action_index) for i in cell.injected] == [("part-missing", 1)]


def test_fault_spec_parsing_and_checks() -> None:
    spec = FaultSpec.parse("missed-grasp=0.2, part-missing=0.1, dropped-part@3", seed=7)
    assert spec == FaultSpec({"missed-grasp": 0.2, "part-missing": 0.1}, {3: ("dropped-part",)}, 7)
    assert set(shipped_fault_kinds().names) == {"missed-grasp", "dropped-part", "part-moved", "part-missing", "kit-tray-moved",
                                "defective-part", "wrong-sku"}
    with pytest.raises(ValueError, match="unknown fault kind 'lost-part'"):
        FaultSpec.parse("lost-part=0.1")
    with pytest.raises(ValueError, match="add up to"):
        FaultSpec.parse("missed-grasp=0.7,wrong-sku=0.6")
    with pytest.raises(ValueError, match="in \\[0, 1\\]"):
        FaultSpec({"wrong-sku": 1.5})


def play(spec: FaultSpec) -> SimulatedCell:
    """A stream of take-part / put-part actions with their CRCL on small-kit."""
    cell = SimulatedCell(INIT, faults=spec)
    mount(cell)
    index = 1
    for n, (px, py) in enumerate([(0.165, 0.945), (0.305, 0.945), (0.445, 0.945), (0.165, 1.045)]):
        part = NS + f"part_a_{n + 1}"
        cell.begin_action(index, "take-part", (ROBOT, part, TRAY, GRIPPER))
        pick(cell, (px, py, 0.81))
        cell.begin_action(index + 1, "put-part", (ROBOT, part, NS + "kit_1", NS + "work_table_1", TRAY))
        run(cell, move(1.2 + 0.15 * n, 0.0, 1.0), crcl.OpenGripper())
        index += 2
    return cell


def test_same_seed_same_run() -> None:
    spec = FaultSpec.parse("missed-grasp=0.25,dropped-part=0.25,part-moved=0.25,wrong-sku=0.25", seed=7)
    a, b = play(spec), play(spec)
    assert a.injected == b.injected
    assert [(i.kind, i.action_index, i.objects[0]) for i in a.injected] == [
        ("part-moved", 1, PART), ("part-moved", 3, NS + "part_a_2"), ("wrong-sku", 5, NS + "part_a_3"),
        ("dropped-part", 7, NS + "part_a_4")]
    sa, sb = a.scene(), b.scene()
    np.testing.assert_array_equal(sa.poses, sb.poses)
    np.testing.assert_array_equal(sa.lo, sb.lo)
    assert sa.facts == sb.facts and a.time == b.time
    c = play(FaultSpec.parse("missed-grasp=0.25,dropped-part=0.25,part-moved=0.25,wrong-sku=0.25", seed=8))
    assert c.injected != a.injected


# --- sensor ---------------------------------------------------------------------------------

def test_sense_by_class_and_name_without_noise_is_ground_truth() -> None:
    cell = SimulatedCell(INIT)
    parts = cell.sense("Part")
    assert [o.name for o in parts] == [NS + f"part_a_{i}" for i in range(1, 5)] + [NS + f"part_b_{i}"
                                                                                 for i in range(1, 4)]
    assert cell.sense("https://w3id.org/kitkb/kitting#Part") == parts
    [o] = cell.sense("part_a_1", by="name")
    assert (o.name, o.cls, o.time, o.orientation) == (PART, "Part", 0.0, (0.0, 0.0, 0.0))
    assert o.location == pytest.approx((0.165, 0.945, 0.75), abs=1e-12)
    [g] = cell.sense(GRIPPER, by="name")
    assert g.cls == "GripperEffector" and g.orientation == pytest.approx((np.pi, 0.0, 0.0))
    assert [o.cls for o in cell.sense("EndEffector")] == ["GripperEffector", "VacuumEffectorSingleCup"]


def test_sensor_noise_has_its_sigma() -> None:
    cell = SimulatedCell(INIT, noise=(0.01, 0.02), seed=5)
    truth = SimulatedCell(INIT).sense("Part")
    loc, ori = [], []
    for _ in range(300):
        for o, t in zip(cell.sense("Part"), truth):
            loc.append(np.subtract(o.location, t.location))
            ori.append(np.subtract(o.orientation, t.orientation))
    loc_err, ori_err = np.array(loc), np.array(ori)  # 2100 samples per coordinate
    assert np.all(np.abs(loc_err.std(axis=0) - 0.01) < 0.001)
    assert np.all(np.abs(ori_err.std(axis=0) - 0.02) < 0.002)
    assert np.all(np.abs(loc_err.mean(axis=0)) < 0.001)
    same = [SimulatedCell(INIT, noise=(0.01, 0.02), seed=5).sense("Part") for _ in range(2)]
    assert same[0] == same[1] != SimulatedCell(INIT, noise=(0.01, 0.02), seed=6).sense("Part")


def test_truth_line_round_trip() -> None:
    obs = Observation(PART, "Part", 12.5, (1.0, 2.0, 0.3), (0.0, 0.1, 1.5707963267948966))
    line = truth_line(obs)
    assert line == (f"{{Name {PART}}} {{Class Part}} {{Time 12.5}} {{Location 1.0,2.0,0.3}} "
                    "{Rotation 0.0,0.1,1.5707963267948966}")
    assert parse_truth_line(line) == obs
    noisy = SimulatedCell(INIT, noise=(0.003, 0.01), seed=2).sense("Part")
    assert [parse_truth_line(truth_line(o)) for o in noisy] == noisy
    seed_line = "{Name P3AT_0} {Class P3AT} {Time 29.97} {Location 0.67,2.30,1.86} {Rotation 0.00,0.46,0.00}"
    assert parse_truth_line(seed_line) == Observation("P3AT_0", "P3AT", 29.97, (0.67, 2.3, 1.86), (0.0, 0.46, 0.0))
    with pytest.raises(ValueError, match="without Rotation"):
        parse_truth_line("{Name a} {Class Part} {Time 1} {Location 1,2,3}")


def test_a_kit_is_carried_with_its_tray_and_parts() -> None:
    cell = build_kit()
    kit = NS + "kit_1"
    x, y, z = TRAY_GRIPPER_MOUNT
    run(cell, move(x, y, z + 0.2), move(x, y, z - 0.09), crcl.OpenToolChanger(), move(x, y, z + 0.3))
    mount(cell)
    pick(cell)
    run(cell, move(1.33, -0.05, 1.0), move(1.33, -0.05, 0.81), crcl.OpenGripper(), move(1.33, -0.05, 1.0))
    assert holds(cell, "part-location-kit", PART, kit)
    run(cell, move(*GRIPPER_MOUNT[:2], 1.0), move(*GRIPPER_MOUNT[:2], 0.72), crcl.OpenToolChanger(),
        move(*GRIPPER_MOUNT[:2], 1.1))
    mount(cell, TRAY_GRIPPER_MOUNT)
    pick(cell, (1.52, 0.08, 0.79))  # the tray's rim beside the part: the kit is grasped
    assert holds(cell, "robot-holds-kit", ROBOT, kit)
    assert not holds(cell, "kit-location-worktable", kit, NS + "work_table_1")
    assert holds(cell, "part-location-kit", PART, kit)
    assert box(cell, PART)[0][2] == pytest.approx(0.75 + 0.21)
