"""Parts lying on their side are grasped and placed (issue 26, point 1, in the executor).

NIST's GearBox shafts are CylindricalShapes whose frame is the centre of one end cap with z
along the shaft: lying in their tray, their z axis is level. The grasp target is the top of
a part as it lies (world up), above the centre of its footprint, and the place target puts
its frame on the slot's with the slot's orientation (docs/execution.md, "Grasp and place
targets"); before, both took the top face along the part's own z axis (a shaft's end cap),
and a kit with a lying shaft gave ``missed-grasp`` at every try.

The workstation is the GearBox-like one of tests/test_thin_parts.py (washers 0.343 mm thick,
shafts 4.966 mm across, millimetres) with a kit design of two washers, a shaft lying across
the kit (its axis along the kit's x: the tool turns it a quarter turn on the way) and a
gear-like short cylinder lying on its rim (20 mm across, 6 mm thick). :func:`lying_graphs`
builds it; tests/data/thin/shaft-kit-init.ttl and shaft-kit-goal.ttl are its files.
"""

from __future__ import annotations

import json
import logging
import math
from pathlib import Path

import numpy as np
import pytest
from rdflib import Graph, Literal, URIRef
from rdflib.namespace import RDF

from kb.cli import main
from kb.core.namespaces import KTW
from kb.execution.belief import Belief
from kb.execution.targets import Targets, tool_down
from kb.io.turtle import turtle
from kb.scenario.blocks import state_graph
from kb.scenario.layout import layout
from kb.scenario.spec import DesignSpec, PartType, ScenarioSpec
from kb.scenario.variants import number, rescale, turn
from kb.sim.robot import Robot
from kb.sim.world import World
from kb.spatial import Scene
from kb.spatial.frames import world_boxes

DATA = Path(__file__).parent / "data" / "thin"
MM = 0.001
WASHER = (10.16 * MM, 0.343 * MM)  # diameter, height (NIST's GearBox)
SHAFT = (4.966 * MM, 34.239 * MM)  # diameter, length
GEAR = (20.0 * MM, 6.0 * MM)       # diameter, thickness: a short cylinder lying on its rim
NS = "https://w3id.org/kitkb/scenario/gearbox-lying#"

#: (x axis, z axis) of each part type as it lies in its parts tray and in the kit (the goal;
#: its design slot's frame too, unless "slot" gives another)
LYING = {
    "shaft": {"tray": ((1, 0, 0), (0, 1, 0)), "kit": ((0, 1, 0), (-1, 0, 0))},  # along y, then along the kit's x
    "gear": {"tray": ((0, 0, 1), (1, 0, 0)), "kit": ((0, 0, 1), (0, 1, 0))},    # axis along x, then along y
}
#: NIST's GearBox design: the shaft lies in the kit as in its tray (the goal file), but its
#: slot's frame stands it up (z axis (0, 0, 1)) at the point where the lying shaft's frame is
NIST_SLOT = {"shaft": {"tray": ((1, 0, 0), (0, 1, 0)), "kit": ((1, 0, 0), (0, 1, 0)), "slot": ((1, 0, 0), (0, 0, 1))},
             "gear": LYING["gear"]}


# --- the workstation ----------------------------------------------------------------------------

def lying_graphs(unit: str = "millimeter", orientations: dict | None = None) -> dict[str, Graph]:
    """The initial and goal states (``{"init": g, "goal": g}``), lengths written in ``unit``:
    six washers, three shafts and three gears in their trays, lying as ``orientations`` (default
    :data:`LYING`) says; the goal puts two washers, a shaft and a gear in kit_1, lying as the
    design's slots say (or, with a ``"slot"`` entry, the slot's frame otherwise turned about
    the point where the part's frame is)."""
    orientations = orientations or LYING
    spec = ScenarioSpec(
        name="gearbox-lying",
        description="GearBox-like workstation: a shaft and a gear lying on their side go in the kit.",
        part_types=(PartType("washer", WASHER[0], WASHER[0], WASHER[1], 0.001),
                    PartType("shaft", SHAFT[1], SHAFT[1], SHAFT[0], 0.005),
                    PartType("gear", GEAR[0], GEAR[0], GEAR[0], 0.01)),
        designs=(DesignSpec("kit_design_gearbox", (("washer", 2), ("shaft", 1), ("gear", 1))),), kits=(0,),
        spare=2, tray_grid=(3, 2))
    sc = layout(spec)
    out = {}
    for state in ("init", "goal"):
        g = state_graph(sc, state)
        g.bind("", NS)
        g.bind("ktw", str(KTW))
        _cylinder(g, "washer", *WASHER)
        _cylinder(g, "shaft", *SHAFT)
        _cylinder(g, "gear", *GEAR)
        for key, (diameter, height) in (("shaft", SHAFT), ("gear", GEAR)):
            sku = URIRef(NS + f"sku_part_{key}")
            for part in g.subjects(KTW.hasSkuObject_Sku, sku):
                loc = g.value(part, KTW.hasSolidObject_PrimaryLocation)
                in_kit = str(g.value(loc, KTW.hasPhysicalLocation_RefObject)).endswith("kit_tray_1")
                axes = orientations[key]["kit" if in_kit else "tray"]
                _lying(g, loc, KTW.hasPoseLocation_Point, KTW.hasPoseLocation_XAxis, KTW.hasPoseLocation_ZAxis,
                       axes, axes, diameter, height)
            for prp in g.subjects(KTW.hasPartRefAndPose_Sku, sku):
                kit = orientations[key]["kit"]
                _lying(g, prp, KTW.hasPartRefAndPose_Point, KTW.hasPartRefAndPose_XAxis, KTW.hasPartRefAndPose_ZAxis,
                       kit, orientations[key].get("slot", kit), diameter, height)
        if unit != "meter":
            rescale(g, "length", unit)
        out[state] = g
    return out


def _cylinder(g: Graph, key: str, diameter: float, height: float) -> None:
    """The SKU shape of part type ``key`` made a CylindricalShape (NIST's GearBox parts: the
    frame at the centre of one end, z along the axis)."""
    shape = URIRef(f"{NS}shape_part_{key}")
    for p in (KTW.hasBoxyShape_Length, KTW.hasBoxyShape_Width, KTW.hasBoxyShape_Height, KTW.hasBoxyShape_HasTop):
        g.remove((shape, p, None))
    g.remove((shape, RDF.type, KTW.BoxyShape))
    g.add((shape, RDF.type, KTW.CylindricalShape))
    g.add((shape, KTW.hasCylindricalShape_Diameter, number(diameter)))
    g.add((shape, KTW.hasCylindricalShape_Height, number(height)))
    g.add((shape, KTW.hasCylindricalShape_HasTop, Literal(True)))


def _lying(g: Graph, node: URIRef, point_p: URIRef, x_p: URIRef, z_p: URIRef, axes: tuple, frame: tuple,
           diameter: float, height: float) -> None:
    """A location (or a slot) of a cylinder lying on its rim with ``axes`` (x, z), its middle
    where the layout put the middle of its footprint, its rim on the floor; written with the
    axes ``frame`` (``axes`` but for NIST's slot)."""
    z_axis = np.array(axes[1], float)
    point = g.value(node, point_p)
    middle = np.array([float(g.value(point, p).toPython()) for p in (KTW.hasPoint_X, KTW.hasPoint_Y)])
    origin = middle - z_axis[:2] * height / 2  # the end cap's centre, half the length back along the axis
    for p, v in zip((KTW.hasPoint_X, KTW.hasPoint_Y, KTW.hasPoint_Z), (*origin, diameter / 2)):
        g.set((point, p, number(v)))
    for prop, axis in zip((x_p, z_p), frame):
        vector = g.value(node, prop)
        for p, v in zip((KTW.hasVector_I, KTW.hasVector_J, KTW.hasVector_K), axis):
            g.set((vector, p, number(v)))


def write_states(folder: Path, prefix: str = "", **kw) -> tuple[Path, Path]:  # noqa: ANN003
    """:func:`lying_graphs` written to ``folder``/``prefix``init.ttl and goal.ttl."""
    folder.mkdir(parents=True, exist_ok=True)
    paths = []
    for state, g in lying_graphs(**kw).items():
        path = folder / f"{prefix}{state}.ttl"
        path.write_text(_header(state) + turtle(g), encoding="utf-8")
        paths.append(path)
    return paths[0], paths[1]


def _header(state: str) -> str:
    return (f"# A GearBox-like workstation ({state} state), in millimetres: a shaft and a gear-like short\n"
            "# cylinder lying on their side go into the kit, turned a quarter turn (issue 26, point 1).\n"
            "# Written by tests/test_lying_parts.py (lying_graphs); do not edit by hand.\n\n")


def local(name: str) -> str:
    return name.rsplit("#", 1)[-1]


def rz(a: float) -> np.ndarray:
    """The 4x4 turn by ``a`` radians about z."""
    m = np.eye(4)
    m[:2, :2] = [[math.cos(a), -math.sin(a)], [math.sin(a), math.cos(a)]]
    return m


def rx(a: float) -> np.ndarray:
    """The 4x4 turn by ``a`` radians about x."""
    m = np.eye(4)
    m[1:3, 1:3] = [[math.cos(a), -math.sin(a)], [math.sin(a), math.cos(a)]]
    return m


def frame(x_axis, z_axis, point=(0.0, 0.0, 0.0)) -> np.ndarray:  # noqa: ANN001
    """The 4x4 pose of a frame given as a state file gives it (x axis, z axis, point)."""
    x, z = np.array(x_axis, float), np.array(z_axis, float)
    m = np.eye(4)
    m[:3, 0], m[:3, 1], m[:3, 2], m[:3, 3] = x, np.cross(z, x), z, point
    return m


def targets_on(scene: Scene) -> Targets:
    """Targets on an exact belief of ``scene`` (the executor's, before it senses)."""
    belief = Belief(scene)
    return Targets(belief, belief.of_class(str(KTW.Robot))[0])


def put(t: Targets, part: str, pose: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``part`` believed at ``pose``, grasped and carried rigidly to its slot in kit_1: (grasp
    tip, place tip, where the part ends: the place tip times the part in the gripper)."""
    t.b.poses[t.b.index[NS + part]] = pose
    grasp = t.grasp(NS + part)
    place = t.place(NS + part, NS + "kit_1")
    return grasp, place, place @ np.linalg.inv(grasp) @ pose


def box_of(t: Targets, part: str, pose: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The world box of ``part`` at ``pose``."""
    i = t.b.index[NS + part]
    lo, hi = world_boxes(pose[None], t.b.local_lo[i][None], t.b.local_hi[i][None])
    return lo[0], hi[0]


def gripped(t: Targets, tip: np.ndarray) -> str | None:
    """What the simulated gripper closing at ``tip`` takes, the cell being as ``t`` believes it
    (its own test: a top face within the grasp tolerance, the tip over the footprint)."""
    world = World.from_scene(t.b.scene())
    found = Robot(world)._at_point(tip[:3, 3])  # noqa: SLF001
    return None if found is None else world.names[found]


def slot_frame(t: Targets, key: str) -> np.ndarray:
    """The world frame of kit_1's slot ``kit_design_gearbox_prp_<key>``."""
    return t.b.pose(NS + "kit_1") @ t.b.slots[NS + f"kit_design_gearbox_prp_{key}"]


@pytest.fixture(scope="module")
def scenes() -> dict[str, Scene]:
    return {state: Scene.from_files([DATA / f"shaft-kit-{state}.ttl"]) for state in ("init", "goal")}


@pytest.fixture
def goal_targets(scenes: dict[str, Scene]) -> Targets:
    return targets_on(scenes["goal"])


# --- the files ----------------------------------------------------------------------------------

def test_data_files_are_the_builder_s(tmp_path: Path) -> None:
    init, goal = write_states(tmp_path, prefix="shaft-kit-")
    assert init.read_text() == (DATA / "shaft-kit-init.ttl").read_text()
    assert goal.read_text() == (DATA / "shaft-kit-goal.ttl").read_text()


def test_the_parts_lie_on_their_side() -> None:
    """NIST's GearBox shape: the frame at an end cap's centre, z along the axis, level."""
    scene = Scene.from_files([DATA / "shaft-kit-init.ttl"])
    assert scene.units.length == "millimeter"
    for name, extent in (("part_shaft_1", (SHAFT[0], SHAFT[1], SHAFT[0])), ("part_gear_1", (GEAR[1], GEAR[0], GEAR[0]))):
        i = scene.index[NS + name]
        np.testing.assert_allclose(scene.hi[i] - scene.lo[i], extent, rtol=1e-9)
        assert abs(scene.poses[i][2, 2]) < 1e-12  # its z axis level
        tray = scene.index[NS + name.rsplit("_", 1)[0] + "_tray"]
        assert scene.lo[i, 2] == pytest.approx(scene.lo[tray, 2], abs=1e-9)  # on its tray's floor
    goal = Scene.from_files([DATA / "shaft-kit-goal.ttl"])
    shaft = goal.index[NS + "part_shaft_1"]
    np.testing.assert_allclose(goal.hi[shaft] - goal.lo[shaft], (SHAFT[1], SHAFT[0], SHAFT[0]), rtol=1e-9)  # across


# --- the targets --------------------------------------------------------------------------------

POSES = {  # (x axis, z axis) of a part lying, standing, upside down, on a side
    "shaft along y": ((1, 0, 0), (0, 1, 0)), "shaft along x": ((0, 0, 1), (1, 0, 0)),
    "shaft upright": ((1, 0, 0), (0, 0, 1)), "shaft upside down": ((1, 0, 0), (0, 0, -1)),
    "gear on its rim": ((0, 0, 1), (1, 0, 0)), "gear flat": ((0, 1, 0), (0, 0, 1)),
}


@pytest.mark.parametrize("part", ["part_shaft_1", "part_gear_1", "part_washer_1"])
@pytest.mark.parametrize("axes", list(POSES.values()), ids=list(POSES))
@pytest.mark.parametrize("yaw", [0.0, 0.3, -2.1, math.pi / 2])
def test_the_grasp_is_on_the_top_of_the_part_as_it_lies(goal_targets: Targets, part: str, axes, yaw: float) -> None:  # noqa: ANN001
    """The tip on the top of the part's box as it lies, over its middle, tool down, its x axis
    level; and the simulated gripper there grasps that part (its top face within the grasp
    tolerance, the tip over its footprint in its own frame)."""
    pose = rz(yaw) @ frame(*axes, (0.5, 0.4, 2.0))
    tip = put(goal_targets, part, pose)[0]
    lo, hi = box_of(goal_targets, part, pose)
    np.testing.assert_allclose(tip[:3, 3], [(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, hi[2]], atol=1e-12)
    np.testing.assert_allclose(tip[:3, 2], [0, 0, -1], atol=1e-12)
    assert abs(tip[2, 0]) < 1e-12 and np.linalg.norm(tip[:3, 0]) == pytest.approx(1.0)
    assert gripped(goal_targets, tip) == NS + part


@pytest.mark.parametrize("part,key", [("part_shaft_1", "shaft_1"), ("part_gear_1", "gear_1"),
                                      ("part_washer_1", "washer_1")])
@pytest.mark.parametrize("yaw", [0.0, 0.7, -1.9, math.pi, 3 * math.pi / 2])
def test_a_part_carried_from_its_tray_ends_in_its_slot(goal_targets: Targets, scenes: dict[str, Scene], part: str,
                                                      key: str, yaw: float) -> None:
    """Grasped where it lies in its tray (the tray turned by ``yaw``) and carried rigidly to its
    place, the part's frame is its slot's, orientation included: the tool turns it a quarter
    turn and more about the vertical; the approach above the slot turns it alike."""
    t = goal_targets
    init = scenes["init"]
    start = rz(yaw) @ init.poses[init.index[NS + part]]
    grasp, place, end = put(t, part, start)
    np.testing.assert_allclose(end, slot_frame(t, key), atol=1e-9)
    above = t.above_place(NS + part, NS + "kit_1", 0.1)
    np.testing.assert_allclose(above[:3, :3], place[:3, :3], atol=1e-12)
    np.testing.assert_allclose(above[:2, 3], place[:2, 3], atol=1e-12)
    assert above[2, 3] >= place[2, 3] + 0.1 - 1e-12


def old_targets(pose: np.ndarray, dest: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The grasp and place tips as kitkb computed them before parts could lie (the top face
    along the part's own z axis): the reference for upright parts."""
    centre = [(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, hi[2], 1.0]
    return tool_down((pose @ centre)[:3], pose[:3, 0]), tool_down((dest @ centre)[:3], dest[:3, 0])


def test_upright_parts_get_the_targets_they_always_got(goal_targets: Targets) -> None:
    """An upright part (any yaw, any box with its frame at the middle of its bottom, as every
    shape kitkb reads) gets bit for bit the grasp and place tips of before."""
    t = goal_targets
    i = t.b.index[NS + "part_washer_1"]
    saved = t.b.local_lo[i].copy(), t.b.local_hi[i].copy()
    rng = np.random.default_rng(26)
    try:
        for _ in range(200):
            w, l, h = rng.uniform(0.0001, 0.3, 3)
            off = rng.uniform(-0.05, 0.05, 2) * rng.integers(0, 2)
            t.b.local_lo[i], t.b.local_hi[i] = (-w / 2 + off[0], -l / 2 + off[1], 0.0), (w / 2 + off[0], l / 2 + off[1], h)
            pose = rz(rng.uniform(-4, 4)) @ frame((1, 0, 0), (0, 0, 1), rng.uniform(-3, 3, 3))
            grasp, place, _ = put(t, "part_washer_1", pose)
            dest = t.destination(NS + "part_washer_1", NS + "kit_1")
            want = old_targets(pose, dest, t.b.local_lo[i], t.b.local_hi[i])
            assert np.array_equal(grasp, want[0]) and np.array_equal(place, want[1])
    finally:
        t.b.local_lo[i], t.b.local_hi[i] = saved


@pytest.mark.parametrize("part,key", [("part_washer_1", "washer_1"), ("part_shaft_1", "shaft_1")])
@pytest.mark.parametrize("tilt", [0.2, -0.35])
def test_a_tilted_part_goes_in_as_tilted_as_it_is_held(goal_targets: Targets, part: str, key: str, tilt: float) -> None:
    """A part held tilted (leaning in its tray: the same face down as its slot wants) keeps its
    tilt, a tool pointing down only turns it about the vertical: its frame over the slot's
    point, its lowest corner on the slot's floor, turned as near the slot's orientation as can be."""
    t = goal_targets
    slot = slot_frame(t, key)
    start = rz(1.1) @ frame(slot[:3, 0], slot[:3, 2], (0.5, 0.4, 2.0)) @ rx(tilt)
    grasp, _place, end = put(t, part, start)
    assert gripped(t, grasp) == NS + part
    np.testing.assert_allclose(end[:2, 3], slot[:2, 3], atol=1e-9)
    assert box_of(t, part, end)[0][2] == pytest.approx(box_of(t, part, slot)[0][2], abs=1e-9)
    np.testing.assert_allclose(end[2, :3], start[2, :3], atol=1e-12)  # the same tilt: only a yaw changed it
    best = max(np.trace(slot[:3, :3].T @ (rz(a) @ start)[:3, :3]) for a in np.linspace(-math.pi, math.pi, 3601))
    assert np.trace(slot[:3, :3].T @ end[:3, :3]) >= best - 1e-6


def test_a_part_lying_on_another_face_than_its_slot_goes_in_as_it_lies(tmp_path: Path, caplog) -> None:  # noqa: ANN001
    """NIST's GearBox design stands its shaft slots up (z axis (0, 0, 1)) at the point of a
    lying shaft's frame; a tool pointing down cannot stand a lying shaft up: it goes in lying,
    its frame at the slot's point, its lowest point where the slot's shaft's would be, and a
    warning says so once."""
    _init, goal = write_states(tmp_path, orientations=NIST_SLOT)
    t = targets_on(Scene.from_files([goal]))
    slot = slot_frame(t, "shaft_1")
    np.testing.assert_allclose(slot[:3, 2], [0, 0, 1], atol=1e-12)
    start = rz(0.4) @ frame((1, 0, 0), (0, 1, 0), (0.5, 0.4, 2.0))
    with caplog.at_level(logging.WARNING, logger="kitkb.execution"):
        _grasp, _place, end = put(t, "part_shaft_1", start)
        t.above_place(NS + "part_shaft_1", NS + "kit_1", 0.1)
    np.testing.assert_allclose(end[:2, 3], slot[:2, 3], atol=1e-9)
    assert box_of(t, "part_shaft_1", end)[0][2] == pytest.approx(box_of(t, "part_shaft_1", slot)[0][2], abs=1e-9)
    np.testing.assert_allclose(end[:3, :3], frame((1, 0, 0), (0, 1, 0))[:3, :3], atol=1e-9)  # lying, turned square
    said = [r.getMessage() for r in caplog.records if "another face" in r.getMessage()]
    assert len(said) == 1 and "part_shaft_1" in said[0] and "kit_design_gearbox_prp_shaft_1" in said[0]


# --- end to end ---------------------------------------------------------------------------------

def run(tmp_path: Path, init: Path, goal: Path, *args: str) -> dict:
    """``kitkb run`` on the files: its exit code and report."""
    report = tmp_path / "run.json"
    code = main(["run", str(init), str(goal), "-o", str(tmp_path / "out"), "--report", str(report), "--quiet", *args])
    data = json.loads(report.read_text())
    data["code"] = code
    return data


def assert_built(data: dict, init: Path) -> None:
    """The run built kit_1 with no constraint violation, every part's frame at its slot's."""
    assert data["code"] == 0 and data["goal_holds"] is True, data.get("stopped")
    assert data["violations"] == []
    assert data["kits"] == [{"kit": "kit_1", "design": "kit_design_gearbox", "score": 7, "max_score": 7, "lost": []}]
    final = {o["name"]: np.array(o["final"]) for o in data["scene"]["objects"] if o["final"] is not None}
    kit = final["kit_tray_1"]
    slots = {local(k): kit @ v for k, v in Scene.from_files([init]).slots.items()}
    for key in ("shaft", "gear"):
        (part,) = [n for n, p in final.items() if n.startswith(f"part_{key}_")
                   and np.linalg.norm(p[:2, 3] - slots[f"kit_design_gearbox_prp_{key}_1"][:2, 3]) < 0.002]
        np.testing.assert_allclose(final[part], slots[f"kit_design_gearbox_prp_{key}_1"], atol=2e-5)


@pytest.mark.slow
def test_run_builds_a_kit_of_lying_parts_in_millimetres(tmp_path: Path) -> None:
    data = run(tmp_path, DATA / "shaft-kit-init.ttl", DATA / "shaft-kit-goal.ttl")
    assert data["failures"] == [] and data["units"]["length"] == "millimeter"
    assert_built(data, DATA / "shaft-kit-init.ttl")


@pytest.mark.slow
@pytest.mark.parametrize("yaw", [30.0, -63.0])
def test_run_builds_it_in_metres_from_turned_trays(tmp_path: Path, yaw: float) -> None:
    """The same kit in a metre file, its parts trays turned: the tool turns each part from its
    tray's heading to its slot's."""
    graphs = lying_graphs(unit="meter")
    turn(graphs["init"], yaw, ["part_shaft_tray", "part_gear_tray", "part_washer_tray"])
    paths = {}
    for state, g in graphs.items():
        paths[state] = tmp_path / f"{state}.ttl"
        paths[state].write_text(turtle(g), encoding="utf-8")
    data = run(tmp_path, paths["init"], paths["goal"])
    assert data["failures"] == [] and data["units"]["length"] == "meter"
    assert_built(data, paths["init"])


EXPECTED = {"missed-grasp": "missed-grasp", "part-missing": "part-missing-from-tray",
            "dropped-part": "dropped-part-in-transit", "wrong-sku": "wrong-sku", "defective-part": "defective-part"}


@pytest.mark.slow
@pytest.mark.parametrize(("faults", "seed"), [("missed-grasp@6,part-missing@8,dropped-part@10", 1),
                                              ("wrong-sku=0.2,defective-part=0.2", 3),
                                              ("missed-grasp=0.3,part-missing=0.1", 5)])
def test_run_diagnoses_faults_on_lying_parts(tmp_path: Path, faults: str, seed: int) -> None:
    """Faults on the lying shaft and gear are diagnosed from their geometry as the failure
    model says, one failure per injected fault, and recovered: the kit is built."""
    data = run(tmp_path, DATA / "shaft-kit-init.ttl", DATA / "shaft-kit-goal.ttl", "--faults", faults, "--seed",
               str(seed))
    assert data["injected"]
    assert sorted(f["mode"] for f in data["failures"]) == sorted(EXPECTED[f["kind"]] for f in data["injected"])
    assert_built(data, DATA / "shaft-kit-init.ttl")


@pytest.mark.slow
def test_run_puts_a_lying_shaft_in_a_slot_that_stands_it_up(tmp_path: Path, caplog) -> None:  # noqa: ANN001
    """NIST's GearBox design (a shaft slot standing up at the lying shaft's frame): the shaft
    goes in lying as the goal file has it, the kit scores full, a warning names the slot."""
    init, goal = write_states(tmp_path, orientations=NIST_SLOT)
    with caplog.at_level(logging.WARNING, logger="kitkb.execution"):
        data = run(tmp_path, init, goal)
    assert data["code"] == 0 and data["goal_holds"] is True and data["violations"] == []
    assert data["kits"][0]["score"] == data["kits"][0]["max_score"] == 7
    final = {o["name"]: np.array(o["final"]) for o in data["scene"]["objects"]}
    want = Scene.from_files([goal])
    shaft = want.index[NS + "part_shaft_1"]
    kit_tray = want.index[NS + "kit_tray_1"]
    np.testing.assert_allclose(np.linalg.inv(final["kit_tray_1"]) @ final["part_shaft_1"],
                               np.linalg.inv(want.poses[kit_tray]) @ want.poses[shaft], atol=2e-5)
    assert any("another face" in r.getMessage() and "prp_shaft_1" in r.getMessage() for r in caplog.records)
