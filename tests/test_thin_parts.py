"""Thin and narrow parts keep their predicates (issue 26, point 1): a bound of a box stands for
one of its faces only (kb.spatial.rcc8, "Thin boxes"; docs/soap.md, "Tolerance").

The workstation is shaped like NIST's GearBox (el-robotics-core kittingInstancesInitGearBox.owl,
a millimetre file): washers 0.343 mm thick (CylindricalShape, 10.16 mm across) lying on the
floor of their parts tray, shafts 4.966 mm across (CylindricalShape, 34.239 mm long) lying
across theirs (cylinder axis level, along the tray's y), a kit design of four washers. It is
built by :func:`gearbox_graphs` from a kitkb scenario layout and written in millimetres to
tests/data/thin/ (``test_data_files_are_the_builder_s`` keeps them the builder's).
"""

from __future__ import annotations

import itertools
import json
import math
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from rdflib import Graph, Literal, URIRef
from rdflib.namespace import RDF

from kb.cli import main
from kb.core.namespaces import KTW
from kb.io.turtle import turtle
from kb.planning.geometry import check_geometry
from kb.scenario.blocks import state_graph
from kb.scenario.layout import layout
from kb.scenario.spec import DesignSpec, PartType, ScenarioSpec
from kb.scenario.variants import number, rescale, turn
from kb.sim.world import World
from kb.spatial import Scene, true_predicates
from kb.spatial import rcc8
from kb.spatial.rcc8 import BIT, DEFAULT_TOLERANCE, RELATIONS, depth_tolerance, relate, relate_pair, relate_rows
from kb.spatial.sweep import solid_pieces, sweep_contacts
from kb.spatial.transforms import from_xyz_rpy

DATA = Path(__file__).parent / "data" / "thin"
MM = 0.001
WASHER = (10.16 * MM, 0.343 * MM)  # diameter, height (NIST's GearBox)
SHAFT = (4.966 * MM, 34.239 * MM)  # diameter, length
NS = "https://w3id.org/kitkb/scenario/gearbox-thin#"
RCC8 = ("DC", "EC", "PO", "EQ", "TPP", "NTPP", "TPPi", "NTPPi")


# --- the workstation ----------------------------------------------------------------------------

def gearbox_graphs(washer_height: float = WASHER[1], shaft_diameter: float = SHAFT[0],
                   unit: str = "millimeter") -> dict[str, Graph]:
    """The initial and goal states (``{"init": g, "goal": g}``) of the GearBox-like workstation,
    lengths written in ``unit``; sizes in metres. Six washers lie on the floor of
    part_washer_tray and two shafts across part_shaft_tray; the goal puts four washers in kit_1."""
    spec = ScenarioSpec(
        name="gearbox-thin",
        description="GearBox-like workstation: thin washers, narrow shafts lying in their trays.",
        part_types=(PartType("washer", WASHER[0], WASHER[0], WASHER[1], 0.001),
                    PartType("shaft", SHAFT[1], SHAFT[1], SHAFT[0], 0.005)),
        designs=(DesignSpec("kit_design_washers", (("washer", 4),)),), kits=(0,), spare=2, tray_grid=(3, 2))
    sc = layout(spec)
    out = {}
    for state in ("init", "goal"):
        g = state_graph(sc, state)
        g.bind("", NS)
        g.bind("ktw", str(KTW))
        _cylinder(g, "washer", WASHER[0], washer_height)
        _cylinder(g, "shaft", shaft_diameter, SHAFT[1])
        for part in g.subjects(KTW.hasSkuObject_Sku, URIRef(NS + "sku_part_shaft")):
            _lying(g, g.value(part, KTW.hasSolidObject_PrimaryLocation), shaft_diameter)
        if unit != "meter":
            rescale(g, "length", unit)
        out[state] = g
    return out


def _cylinder(g: Graph, key: str, diameter: float, height: float) -> None:
    """The SKU shape of part type ``key`` made a CylindricalShape (NIST's GearBox parts)."""
    shape = URIRef(f"{NS}shape_part_{key}")
    for p in (KTW.hasBoxyShape_Length, KTW.hasBoxyShape_Width, KTW.hasBoxyShape_Height, KTW.hasBoxyShape_HasTop):
        g.remove((shape, p, None))
    g.remove((shape, RDF.type, KTW.BoxyShape))
    g.add((shape, RDF.type, KTW.CylindricalShape))
    g.add((shape, KTW.hasCylindricalShape_Diameter, number(diameter)))
    g.add((shape, KTW.hasCylindricalShape_Height, number(height)))
    g.add((shape, KTW.hasCylindricalShape_HasTop, Literal(True)))


def _lying(g: Graph, loc: URIRef, diameter: float) -> None:
    """A shaft's location turned to lie on the tray floor, its axis along y (NIST: z axis (0, 1,
    0), its point at the axis's height), centred where the layout put it."""
    point, z_axis = g.value(loc, KTW.hasPoseLocation_Point), g.value(loc, KTW.hasPoseLocation_ZAxis)
    for p, v in ((KTW.hasVector_I, 0.0), (KTW.hasVector_J, 1.0), (KTW.hasVector_K, 0.0)):
        g.set((z_axis, p, number(v)))
    y = float(g.value(point, KTW.hasPoint_Y).toPython())
    g.set((point, KTW.hasPoint_Y, number(y - SHAFT[1] / 2)))
    g.set((point, KTW.hasPoint_Z, number(diameter / 2)))


def write_states(folder: Path, **kw) -> tuple[Path, Path]:  # noqa: ANN003
    """:func:`gearbox_graphs` written to ``folder``/init.ttl and goal.ttl."""
    folder.mkdir(parents=True, exist_ok=True)
    paths = []
    for state, g in gearbox_graphs(**kw).items():
        path = folder / f"{state}.ttl"
        path.write_text(_header(state) + turtle(g), encoding="utf-8")
        paths.append(path)
    return paths[0], paths[1]


def _header(state: str) -> str:
    return (f"# A GearBox-like workstation ({state} state), in millimetres: washers 0.343 mm thick lying on\n"
            "# the floor of their tray, shafts 4.966 mm across lying across theirs (issue 26, point 1).\n"
            "# Written by tests/test_thin_parts.py (gearbox_graphs); do not edit by hand.\n\n")


def local(atoms) -> set[tuple[str, ...]]:  # noqa: ANN001
    """Atoms with local names."""
    return {(p, *(a.rsplit("#", 1)[-1] for a in args)) for p, args in atoms}


@pytest.fixture(scope="module")
def reference() -> dict[str, set[tuple[str, ...]]]:
    """The predicates of the shipped files: the initial and goal states."""
    return {state: local(true_predicates([DATA / f"{state}.ttl"])) for state in ("init", "goal")}


# --- the files ----------------------------------------------------------------------------------

def test_data_files_are_the_builder_s(tmp_path: Path) -> None:
    init, goal = write_states(tmp_path)
    assert init.read_text() == (DATA / "init.ttl").read_text()
    assert goal.read_text() == (DATA / "goal.ttl").read_text()


def test_the_files_are_shaped_like_nist_s_gearbox() -> None:
    scene = Scene.from_files([DATA / "init.ttl"])
    assert scene.units.length == "millimeter"
    ext = {n.rsplit("#", 1)[-1]: scene.hi[i] - scene.lo[i] for i, n in enumerate(scene.names) if scene.placed[i]}
    washers = [n for n in ext if n.startswith("part_washer_") and n[-1].isdigit()]
    shafts = [n for n in ext if n.startswith("part_shaft_") and n[-1].isdigit()]
    assert len(washers) == 6 and len(shafts) == 2
    for w in washers:
        np.testing.assert_allclose(ext[w], [10.16 * MM, 10.16 * MM, 0.343 * MM], rtol=1e-9)
    for s in shafts:  # lying: long along y, narrow across and up
        np.testing.assert_allclose(ext[s], [4.966 * MM, 34.239 * MM, 4.966 * MM], rtol=1e-9)
    i, tray = scene.index[NS + "part_washer_1"], scene.index[NS + "part_washer_tray"]
    assert scene.lo[i, 2] == pytest.approx(scene.lo[tray, 2], abs=1e-12)  # on the tray's floor


# --- the predicates of the files -----------------------------------------------------------------

def test_washers_and_shafts_are_in_their_trays(reference) -> None:  # noqa: ANN001
    init = reference["init"]
    for k in range(1, 7):
        assert ("part-location-partstray", f"part_washer_{k}", "part_washer_tray") in init
    for k in (1, 2):
        assert ("part-location-partstray", f"part_shaft_{k}", "part_shaft_tray") in init
    goal = reference["goal"]
    for k in range(1, 5):
        assert ("part-location-kit", f"part_washer_{k}", "kit_1") in goal


def test_geometry_agrees_with_the_facts_in_millimetres_and_metres(tmp_path: Path) -> None:
    """What ``kitkb run`` checks before it executes: the initial geometry gives exactly the PDDL
    facts, and every goal fact holds in the goal's geometry."""
    got = check_geometry([DATA / "init.ttl"], [DATA / "goal.ttl"])
    assert got.agrees and got.atoms > 30, got.reason()
    init, goal = write_states(tmp_path, unit="meter")
    assert check_geometry([init], [goal]).agrees


# --- metamorphic: thinner and narrower parts keep their predicates -----------------------------

THIN = [0.343, 0.3, 0.2, 0.15, 0.1]           # washer height, mm
NARROW = [4.966, 3.0, 1.5, 1.0, 0.5, 0.1]     # shaft diameter, mm


@pytest.mark.parametrize("unit", ["millimeter", "meter"])
@pytest.mark.parametrize(("height", "diameter"), list(zip(THIN, NARROW)) + [(0.1, 4.966), (0.343, 0.1)])
def test_thinner_and_narrower_parts_keep_their_predicates(tmp_path: Path, reference, height: float,  # noqa: ANN001
                                                          diameter: float, unit: str) -> None:
    init, goal = write_states(tmp_path, washer_height=height * MM, shaft_diameter=diameter * MM, unit=unit)
    assert local(true_predicates([init])) == reference["init"]
    assert local(true_predicates([goal])) == reference["goal"]


@settings(max_examples=5, deadline=None)
@given(st.floats(0.1, 0.343), st.floats(0.1, 4.966), st.sampled_from(["millimeter", "meter", "inch"]))
def test_any_thickness_down_to_a_tenth_of_a_millimetre(tmp_path_factory, reference, height: float,  # noqa: ANN001
                                                       diameter: float, unit: str) -> None:
    folder = tmp_path_factory.mktemp("thin")
    init, _ = write_states(folder, washer_height=height * MM, shaft_diameter=diameter * MM, unit=unit)
    assert local(true_predicates([init])) == reference["init"]


@pytest.mark.parametrize("yaw", [30.0, -63.0, 180.0])
def test_turned_trays_keep_the_thin_parts_predicates(tmp_path: Path, reference, yaw: float) -> None:  # noqa: ANN001
    """Relations decided in a turned tray's frame (kb.spatial.rcc8.reframe) follow the same rule."""
    for height, diameter in ((0.343, 4.966), (0.1, 0.1)):
        g = gearbox_graphs(washer_height=height * MM, shaft_diameter=diameter * MM)["init"]
        turn(g, yaw, ["part_washer_tray", "part_shaft_tray"])
        path = tmp_path / f"turned-{height}.ttl"
        path.write_text(turtle(g), encoding="utf-8")
        assert local(true_predicates([path])) == reference["init"]


# --- the decision on boxes ------------------------------------------------------------------------

def names(mask: int) -> frozenset[str]:
    return frozenset(n for n in RELATIONS if int(mask) & BIT[n])


def on_z(a: tuple[float, float], b: tuple[float, float], tol: float = DEFAULT_TOLERANCE) -> frozenset[str]:
    """The Z relations of intervals a, b (x and y: a well inside b), by relate_pair, checked
    equal to relate and relate_rows."""
    a_lo, a_hi, b_lo, b_hi = (0.4, 0.4, a[0]), (0.6, 0.6, a[1]), (0.0, 0.0, b[0]), (1.0, 1.0, b[1])
    ref = relate_pair(a_lo, a_hi, b_lo, b_hi, tol)
    assert names(relate(np.array([a_lo]), np.array([a_hi]), np.array([b_lo]), np.array([b_hi]), tol)[0, 0]) == ref
    assert names(relate_rows(np.array([a_lo]), np.array([a_hi]), np.array([b_lo]), np.array([b_hi]), tol)[0]) == ref
    return frozenset(n for n in ref if n.startswith("Z-"))


WASHER_H = 0.343 * MM
FLOOR = 0.75  # a tray's floor on a table
TRAY = (FLOOR, FLOOR + 0.02)


def test_a_washer_on_the_floor_of_its_tray_is_in_it() -> None:
    assert on_z((FLOOR, FLOOR + WASHER_H), TRAY) == {"Z-TPP", "Z-Plus", "Z-Minus"}
    # noise of less than half its thickness: still in (resting on the floor, or just above it)
    assert on_z((FLOOR - 0.1 * MM, FLOOR - 0.1 * MM + WASHER_H), TRAY) == {"Z-TPP", "Z-Plus", "Z-Minus"}
    assert on_z((FLOOR + 0.8 * MM, FLOOR + 0.8 * MM + WASHER_H), TRAY) == {"Z-TPP", "Z-Plus", "Z-Minus"}
    # and the tray seen from the washer: it holds the washer on its floor
    a_lo, a_hi = (0.0, 0.0, TRAY[0]), (1.0, 1.0, TRAY[1])
    assert {"Z-TPPi"} <= relate_pair(a_lo, a_hi, (0.4, 0.4, FLOOR), (0.6, 0.6, FLOOR + WASHER_H))


def test_a_washer_under_the_floor_touches_it_from_below() -> None:
    assert on_z((FLOOR - WASHER_H, FLOOR), TRAY) == {"Z-EC", "Z-Minus"}
    # its middle below the floor: not in the tray (it reaches below it)
    assert "Z-Plus" not in on_z((FLOOR - 0.25 * MM, FLOOR - 0.25 * MM + WASHER_H), TRAY)


def test_a_thin_part_keeps_the_whole_tolerance_for_gaps() -> None:
    table = (0.0, FLOOR)
    for gap in (0.0, 0.5 * MM, 0.9 * MM):  # resting on the table, sensed a little above it
        assert on_z((FLOOR + gap, FLOOR + gap + WASHER_H), table) == {"Z-EC", "Z-Plus"}
    assert on_z((FLOOR + 1.5 * MM, FLOOR + 1.5 * MM + WASHER_H), table) == {"Z-DC", "Z-Plus"}


def test_stacked_and_equal_thin_parts() -> None:
    lower = (FLOOR, FLOOR + WASHER_H)
    upper = (FLOOR + WASHER_H, FLOOR + 2 * WASHER_H)
    assert on_z(upper, lower) == {"Z-EC", "Z-Plus"}     # on top, not EQ as one tolerance found
    assert on_z(lower, upper) == {"Z-EC", "Z-Minus"}
    assert on_z(lower, lower) == {"Z-EQ", "Z-Plus", "Z-Minus"}


def test_a_point_is_decided_as_before() -> None:
    """A point (NIST's robot flange) has no extent to lose: both its bounds are the nearest."""
    assert on_z((FLOOR + 0.5 * MM, FLOOR + 0.5 * MM), TRAY) == {"Z-EC", "Z-Plus", "Z-Minus"}
    assert on_z((FLOOR + 5 * MM, FLOOR + 5 * MM), TRAY) == {"Z-NTPP", "Z-Plus", "Z-Minus"}
    # a point on the top face of a 1 mm plate (NIST's effector holders): on it, not EQ to it
    assert on_z((FLOOR + MM, FLOOR + MM), (FLOOR, FLOOR + MM)) == {"Z-EC", "Z-Plus", "Z-Minus"}


def old_rules(a0: float, a1: float, b0: float, b1: float, t: float) -> set[str]:
    """The decision before this change (one tolerance for every bound pair), on one axis."""
    def near(x: float, b: float) -> bool:
        return b - t <= x <= b + t

    if a1 < b0 - t or a0 > b1 + t:
        rel = "DC"
    elif near(a0, b0) and near(a1, b1):
        rel = "EQ"
    elif near(a1, b0) or near(a0, b1):
        rel = "EC"
    elif a0 >= b0 - t and a1 <= b1 + t:
        rel = "TPP" if near(a0, b0) or near(a1, b1) else "NTPP"
    elif a0 <= b0 + t and a1 >= b1 - t:
        rel = "TPPi" if near(a0, b0) or near(a1, b1) else "NTPPi"
    else:
        rel = "PO"
    return {rel} | ({"Plus"} if a0 >= b0 - t else set()) | ({"Minus"} if a1 <= b1 + t else set())


extent = st.floats(0.0021, 0.3)  # wider than twice the tolerance
corner = st.floats(-1.0, 1.0)


@settings(max_examples=150, deadline=None)
@given(st.lists(st.tuples(corner, extent), min_size=6, max_size=6), st.integers(0, 5))
def test_boxes_wider_than_twice_the_tolerance_decide_as_before(bounds, snap) -> None:  # noqa: ANN001
    """Exact compatibility: with every extent over 2 t the rule is the old one; bounds snapped
    onto each other within the tolerance make the ties frequent."""
    a = [(lo, lo + w) for lo, w in bounds[:3]]
    b = [(lo, lo + w) for lo, w in bounds[3:]]
    k = snap % 3
    a[k] = (b[k][snap % 2] + (snap - 2) * 0.0004, b[k][snap % 2] + (snap - 2) * 0.0004 + (a[k][1] - a[k][0]))
    got = relate_pair(*zip(*a), *zip(*b))
    want = {f"{axis}-{r}" for axis, (x, y) in zip("XYZ", zip(a, b)) for r in old_rules(*x, *y, DEFAULT_TOLERANCE)}
    assert got == want


def grid(rng: np.random.Generator, n: int, step: float) -> tuple[np.ndarray, np.ndarray]:
    """Boxes on a grid of ``step``, many thinner than twice the tolerance (points included)."""
    lo = rng.integers(0, 8, (n, 3)) * step
    hi = lo + rng.choice([0, 0, 1, 1, 2, 3, 9], (n, 3)) * step
    return lo.astype(float), hi.astype(float)


@pytest.mark.parametrize("kernel", ["default", "rank", "compare"])
@pytest.mark.parametrize(("step", "tol"), [(0.00025, 0.001), (0.25, 1.0), (0.0001, 0.001), (1.0, 1.0)])
def test_relate_equals_relate_pair_with_thin_boxes(kernel: str, step: float, tol: float) -> None:
    """The kernels' second pass decides the thin boxes' pairs as relate_pair does (metres and
    millimetres: the same boxes in both units)."""
    settings_ = {"default": {}, "rank": {"_RANK_MIN_SUBJECTS": 0, "_RANK_CHUNK": (3, 5), "_BLOCK": 7},
                 "compare": {"_RANK_MIN_SUBJECTS": 10**9, "_COMPARE_PAIRS": 16, "_BLOCK": 5}}[kernel]
    saved = {key: getattr(rcc8, key) for key in settings_}
    rng = np.random.default_rng(26)
    a_lo, a_hi = grid(rng, 60, step)
    b_lo, b_hi = grid(rng, 40, step)
    try:
        for key, value in settings_.items():
            setattr(rcc8, key, value)
        masks = relate(a_lo, a_hi, b_lo, b_hi, tol)
    finally:
        for key, value in saved.items():
            setattr(rcc8, key, value)
    for i, j in itertools.product(range(60), range(40)):
        assert names(masks[i, j]) == relate_pair(a_lo[i], a_hi[i], b_lo[j], b_hi[j], tol), (i, j)


def test_relate_with_many_thin_boxes() -> None:
    """Thousands of boxes, many thin: the check for thin boxes in blocks (kb.spatial.rcc8._thin,
    across its block boundary), as subjects and as objects."""
    rng = np.random.default_rng(9)
    lo, hi = grid(rng, 9000, 0.00025)
    few_lo, few_hi = grid(rng, 12, 0.00025)
    as_objects, as_subjects = relate(few_lo, few_hi, lo, hi), relate(lo, hi, few_lo, few_hi)
    for k in list(rng.integers(0, 9000, 150)) + [8191, 8192]:
        for j in range(12):
            assert names(as_objects[j, k]) == relate_pair(few_lo[j], few_hi[j], lo[k], hi[k])
            assert names(as_subjects[k, j]) == relate_pair(lo[k], hi[k], few_lo[j], few_hi[j])


CONVERSE = {"DC": "DC", "EC": "EC", "PO": "PO", "EQ": "EQ", "TPP": "TPPi", "NTPP": "NTPPi", "TPPi": "TPP",
            "NTPPi": "NTPP"}
dyadic = st.integers(0, 24).map(lambda k: k / 64)  # exact in binary: no rounding in the tests


@settings(max_examples=300, deadline=None)
@given(st.lists(st.tuples(dyadic, st.integers(0, 4).map(lambda k: k / 64)), min_size=6, max_size=6))
def test_the_rule_is_the_same_from_either_side(bounds) -> None:  # noqa: ANN001
    """Subject and object swapped give the converse relation on every axis (the bound pairs'
    tolerances do not depend on which box is the subject)."""
    a_lo = [lo for lo, _ in bounds[:3]]
    a_hi = [lo + w for lo, w in bounds[:3]]
    b_lo = [lo for lo, _ in bounds[3:]]
    b_hi = [lo + w for lo, w in bounds[3:]]
    ab = relate_pair(a_lo, a_hi, b_lo, b_hi, 1 / 32)
    ba = relate_pair(b_lo, b_hi, a_lo, a_hi, 1 / 32)
    for axis in "XYZ":
        (r,) = [n[2:] for n in ab if n[0] == axis and n[2:] in RCC8]
        assert f"{axis}-{CONVERSE[r]}" in ba


def test_depth_tolerance() -> None:
    t = DEFAULT_TOLERANCE
    assert float(depth_tolerance(t, 0.05, 0.3)) == t
    assert float(depth_tolerance(t, 0.343 * MM, 0.3)) == pytest.approx(0.1715 * MM)
    assert float(depth_tolerance(t, 0.0, 0.3)) == t  # a point or a plate does not lower it
    np.testing.assert_allclose(depth_tolerance(t, np.array([0.004, 0.0005, 0.0]), 0.1), [t, 0.00025, t])
    with pytest.raises(ValueError):
        depth_tolerance(-1.0, 0.1)


# --- the simulated cell -----------------------------------------------------------------------

def test_a_narrow_part_let_go_over_a_table_rests_on_it() -> None:
    """The footprint of a 0.5 mm part overlaps the table by all its width: it rests on the
    table (with one tolerance for every footprint, it fell through to the floor)."""
    scene = Scene.from_files([DATA / "init.ttl"])
    world = World.from_scene(scene)
    i, table = world.index[NS + "part_shaft_1"], world.index[NS + "work_table_1"]
    world.local_lo[i], world.local_hi[i] = (-0.00025, -0.00025, 0.0), (0.00025, 0.00025, SHAFT[1])
    lo, hi = world.box(table)
    pose = np.array(world.poses[i])
    pose[:3, 3] = ((lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, hi[2] + 0.05)
    world.parent[i] = -1
    world.set_pose(i, pose)
    assert world.drop(i) == table
    assert world.box(i)[0][2] == pytest.approx(hi[2], abs=1e-12)
    # its middle off the table's edge: it falls
    pose[:3, 3] = (hi[0] + 0.00001, (lo[1] + hi[1]) / 2, hi[2] + 0.05)
    world.set_pose(i, pose)
    assert world.drop(i) != table


def test_a_part_let_go_over_a_washer_in_a_tray_rests_on_the_washer() -> None:
    scene = Scene.from_files([DATA / "init.ttl"])
    world = World.from_scene(scene)
    tray, below, above = (world.index[NS + n] for n in ("part_washer_tray", "part_washer_1", "part_washer_2"))
    pose = np.array(world.poses[below])
    pose[2, 3] += 0.01
    world.parent[above] = -1
    world.set_pose(above, pose)
    assert world.drop(above) == below
    assert world.box(above)[0][2] == pytest.approx(world.box(below)[1][2], abs=1e-12)
    assert world.parent[below] == tray


def test_the_sweep_finds_a_washer_carried_through_a_solid() -> None:
    """Contacts along a move are penetration depths of the swept volume: a washer carried
    through a tray's wall or down into a table is found, one laid on a floor or slid along a
    table top is not (kb.spatial.sweep keeps its tolerance: a thin part moving through a solid
    sweeps a volume as deep as its way)."""
    poses = np.array([from_xyz_rpy(0, 0, FLOOR, 0, 0, 0), from_xyz_rpy(0.5, 0, 0, 0, 0, 0)])
    lo, hi = np.array([[-0.05, -0.05, 0], [-0.3, -0.3, 0]]), np.array([[0.05, 0.05, 0.02], [0.3, 0.3, FLOOR]])
    pieces = solid_pieces(lo, hi, np.array([True, False]), np.array([0, 1]))  # an open tray on z = FLOOR, a table
    r = WASHER[0] / 2
    body_lo, body_hi = np.array([[-r, -r, -WASHER_H]]), np.array([[r, r, 0.0]])  # a washer under the tool tip

    def owners(*points) -> list[int]:  # noqa: ANN002
        path = np.array([from_xyz_rpy(*p, 0, 0, 0) for p in points])
        return [c.owner for c in sweep_contacts(path, np.eye(4)[None], body_lo, body_hi, poses, pieces)]

    assert owners((-0.2, 0, FLOOR + 0.01), (0, 0, FLOOR + 0.01)) == [0]           # through the tray's wall
    assert owners((0.5, 0, FLOOR + 0.1), (0.5, 0, FLOOR - 0.005 + WASHER_H)) == [1]  # 5 mm into the table
    assert owners((0, 0, FLOOR + 0.1), (0, 0, FLOOR + WASHER_H)) == []              # onto the tray's floor
    assert owners((0.4, 0, FLOOR + WASHER_H), (0.6, 0, FLOOR + WASHER_H)) == []     # along the table top


# --- end to end -----------------------------------------------------------------------------------

@pytest.mark.slow
def test_run_builds_the_washer_kit(tmp_path: Path) -> None:
    """``kitkb run`` on the millimetre state: geometry agrees with the facts, the plan is
    executed with every check from geometry, and the kit of washers is built."""
    report = tmp_path / "run.json"
    code = main(["run", str(DATA / "init.ttl"), str(DATA / "goal.ttl"), "-o", str(tmp_path), "--report", str(report),
                 "--quiet"])
    data = json.loads(report.read_text())
    assert code == 0, data.get("reason") or data.get("stopped")
    assert data["executed"] is True and data["goal_holds"] is True and data["failures"] == []
    assert data["units"]["length"] == "millimeter"
    puts = [e["args"][1] for e in data["timeline"] if e.get("kind") == "action" and e["action"] == "put-part"]
    assert sorted(puts) == [f"part_washer_{k}" for k in range(1, 5)]
    assert data["kits"] == [{"kit": "kit_1", "design": "kit_design_washers", "score": 7, "max_score": 7, "lost": []}]
    assert data["violations"] == []


@pytest.mark.slow
def test_run_diagnoses_faults_on_thin_parts(tmp_path: Path) -> None:
    """A grasp that misses a washer and a washer missing from its tray are told apart by the
    failure model from the washers' geometry, and recovered."""
    report = tmp_path / "run.json"
    code = main(["run", str(DATA / "init.ttl"), str(DATA / "goal.ttl"), "-o", str(tmp_path), "--report", str(report),
                 "--faults", "missed-grasp=0.2,part-missing=0.1", "--seed", "5", "--quiet"])
    data = json.loads(report.read_text())
    assert data["executed"] is True and data["injected"]
    expected = {"missed-grasp": "missed-grasp", "part-missing": "part-missing-from-tray"}
    assert sorted(f["mode"] for f in data["failures"]) == sorted(expected[f["kind"]] for f in data["injected"])
    assert code == 0 and data["goal_holds"] is True, data.get("stopped")  # 2 spare washers: enough here
