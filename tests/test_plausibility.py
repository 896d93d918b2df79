"""Physical plausibility in ``kitkb validate``: interpenetrating and floating objects, as
warnings at the pose's line with both objects named and the depth in the file's unit.

The cases are the shipped small-kit initial state with one pose edited (in the frame of the
object's reference object, so they hold in a tray turned by any yaw), then written turned or
in another unit by :func:`kb.scenario.variants.write_variant`.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest

from kb.cli import main
from kb.core.resources import scenario_dirs
from kb.scenario import write_scenario
from kb.scenario.variants import write_variant
from kb.spatial.plausibility import Boxes, check, in_frame_of, overlapping_pairs, sat_depth
from kb.spatial.scene import Scene
from kb.validation import validate
from tests.shared_data import NIST_DIR

SMALL_KIT = next(d for d in scenario_dirs() if d.name == "small-kit") / "init.ttl"
SHIPPED = sorted(p for d in scenario_dirs() for p in d.glob("*.ttl"))
NIST_STATES = [NIST_DIR / "kittingInstancesInit1.owl", NIST_DIR / "kittingInstancesGoal1.owl"]
GEOMETRY = ("interpenetration", "floating-object")


def _edit(text: str, obj: str, ref: str | None = None, **xyz: float) -> str:
    """``text`` with ``obj``'s pose point moved (X=, Y=, Z= in its reference frame) and its
    reference object replaced by ``ref``."""
    def point(m: re.Match) -> str:
        block = m.group(0)
        for axis, v in xyz.items():
            block, n = re.subn(rf"(ktw:hasPoint_{axis}) [-0-9.eE]+", rf"\g<1> {v}", block)
            assert n == 1
        return block
    text, n = re.subn(rf":{obj}_point a .*?\.\n", point, text, count=1, flags=re.S)
    assert n == 1
    if ref is not None:
        text, n = re.subn(rf"(:{obj}_pose a .*?ktw:hasPhysicalLocation_RefObject) :\w+", rf"\g<1> :{ref}", text,
                          count=1, flags=re.S)
        assert n == 1
    return text


def _state(tmp_path: Path, *, unit: str | None = None, turn: str | None = None, **edit: dict) -> Path:
    text = SMALL_KIT.read_text()
    for obj, change in edit.items():
        text = _edit(text, obj, **change)
    path = tmp_path / "init.ttl"
    path.write_text(text)
    if unit or turn:
        out = tmp_path / "variant.ttl"
        write_variant(path, out, unit=unit, yaw=37.0 if turn else 0.0, objects=[turn] if turn else None)
        return out
    return path


def _line(path: Path, subject: str) -> int:
    """The line where ``subject`` is first described in ``path`` (Turtle)."""
    for n, text in enumerate(path.read_text().splitlines(), 1):
        if text.startswith(f":{subject} a "):
            return n
    raise AssertionError(subject)


def _found(path: Path) -> list[tuple]:
    """(rule, line, message) of the geometry warnings of ``path``; everything else conforms."""
    report = validate([path])
    assert report.conforms, [d.format() for d in report.errors]
    others = [d for d in report.diagnostics if d.rule not in GEOMETRY]
    assert others == [], [d.format() for d in others]
    assert all(d.severity == "warning" for d in report.diagnostics)
    return [(d.rule, d.line, d.message) for d in report.diagnostics]


# --- what validate reports ----------------------------------------------------------------------

#: pose edits of the small kit -> the findings (rule, object, message) they must give
CASES = {
    "half into the table": (
        {"part_a_1": {"ref": "parts_table_1", "X": -0.26, "Y": -0.165, "Z": 0.72}},
        [("interpenetration", "part_a_1", ":part_a_1 and :parts_table_1 interpenetrate by {30}")]),
    "two parts in one space": (
        {"part_a_2": {"X": -0.09}},
        [("interpenetration", "part_a_1", ":part_a_1 and :part_a_2 interpenetrate by {50}")]),
    "through the tray's floor": (
        {"part_a_1": {"Z": -0.02}},
        [("interpenetration", "part_a_1", ":part_a_1 and :parts_table_1 interpenetrate by {20}"),
         ("interpenetration", "part_a_1", ":part_a_1 goes through the floor of :part_a_tray, {20} below it")]),
    "through the tray's wall": (
        {"part_a_1": {"X": -0.24}},
        [("interpenetration", "part_a_1", ":part_a_1 goes through the -x wall of :part_a_tray, {60} beyond it and {40} inside")]),
    "floating": (
        {"part_a_1": {"Z": 0.05}},
        [("floating-object", "part_a_1", ":part_a_1 floats {50} above the floor of :part_a_tray")]),
    "a holder off its changing station": (
        {"part_gripper_holder": {"Z": 0.9}},
        [("floating-object", "part_gripper_holder",
          ":part_gripper_holder floats {100} above :changing_station_base")]),
    "an effector out of its holder": (
        {"part_gripper": {"Z": 0.4}},
        [("floating-object", "part_gripper", ":part_gripper floats {220} above :changing_station_base")]),
    "below the ground": (
        {"work_table_1": {"Z": -0.02}},
        [("interpenetration", "work_table_1", ":work_table_1 is {20} below the ground (z = 0 of the workstation)")]),
    "floating above the table": (
        {"part_a_tray": {"Z": 0.8}},
        [("floating-object", "part_a_tray", ":part_a_tray floats {50} above :parts_table_1")]),
}
#: how a depth in millimetres reads in each unit
WRITTEN = {None: lambda mm: f"{mm / 1000:g} m", "millimeter": lambda mm: f"{mm:g} mm",
           "inch": lambda mm: f"{mm / 25.4:.4g} in"}


def _expected(path: Path, findings: list, unit: str | None) -> list[tuple]:
    def text(message: str) -> str:
        return re.sub(r"\{(\d+)\}", lambda m: WRITTEN[unit](int(m.group(1))), message)
    return sorted((rule, _line(path, f"{obj}_pose"), text(message)) for rule, obj, message in findings)


@pytest.mark.parametrize("case", sorted(CASES))
def test_an_implausible_pose_is_reported_at_its_line_with_its_depth(case: str, tmp_path: Path) -> None:
    edit, findings = CASES[case]
    path = _state(tmp_path, **edit)
    assert sorted(_found(path)) == _expected(path, findings, None)


@pytest.mark.parametrize("case", sorted(c for c in CASES if c != "half into the table"))
def test_the_same_inside_a_tray_turned_37_degrees(case: str, tmp_path: Path) -> None:
    edit, findings = CASES[case]
    path = _state(tmp_path, turn="part_a_tray", **edit)
    assert sorted(_found(path)) == _expected(path, findings, None)


@pytest.mark.parametrize("yaw", [-151.3, 23.0, 98.6])
@pytest.mark.parametrize("case", ["two parts in one space", "through the tray's wall", "floating above the table"])
def test_the_same_with_the_whole_workstation_turned(case: str, yaw: float, tmp_path: Path) -> None:
    edit, findings = CASES[case]
    path = _state(tmp_path, **edit)
    turned = tmp_path / "turned.ttl"
    write_variant(path, turned, yaw=yaw)
    assert sorted(_found(turned)) == _expected(turned, findings, None)


@pytest.mark.parametrize("unit", ["millimeter", "inch"])
@pytest.mark.parametrize("case", ["through the tray's floor", "floating", "two parts in one space"])
def test_the_depth_is_in_the_files_unit(case: str, unit: str, tmp_path: Path) -> None:
    edit, findings = CASES[case]
    path = _state(tmp_path, unit=unit, turn="part_a_tray", **edit)
    assert sorted(_found(path)) == _expected(path, findings, unit)


def test_depths_in_metres_whatever_the_unit(tmp_path: Path) -> None:
    edit, _ = CASES["through the tray's floor"]
    (tmp_path / "m").mkdir()
    (tmp_path / "mm").mkdir()
    metres = check(Scene.from_files([_state(tmp_path / "m", **edit)]))
    millimetres = check(Scene.from_files([_state(tmp_path / "mm", unit="millimeter", turn="part_a_tray", **edit)]))
    assert [(f.rule, f.obj, f.other, f.how) for f in metres] == [(f.rule, f.obj, f.other, f.how) for f in millimetres]
    assert [f.depth for f in millimetres] == pytest.approx([0.02, 0.02], abs=1e-9)


def test_within_the_tolerance_is_plausible(tmp_path: Path) -> None:
    path = _state(tmp_path, part_a_1={"Z": 0.0009}, part_a_2={"Z": -0.0009}, part_a_3={"X": 0.0991})
    assert _found(path) == []
    (tmp_path / "2mm").mkdir()
    path = _state(tmp_path / "2mm", part_a_1={"Z": 0.002}, part_a_2={"Z": -0.002})
    assert [message for _, _, message in _found(path)] == [
        ":part_a_1 floats 0.002 m above the floor of :part_a_tray",
        ":part_a_2 and :parts_table_1 interpenetrate by 0.002 m",
        ":part_a_2 goes through the floor of :part_a_tray, 0.002 m below it"]


def test_warnings_keep_exit_code_0_and_ignore_leaves_them_out(tmp_path: Path, capsys) -> None:
    path = _state(tmp_path, part_a_1={"Z": 0.05}, part_a_2={"X": 0.05})
    assert main(["validate", str(path)]) == 0
    out = capsys.readouterr().out.splitlines()
    assert sorted(re.search(r"\[(.*)\]$", line).group(1) for line in out[:-1]) == list(sorted(GEOMETRY))
    assert out[-1] == "1 file(s): conforms, 2 warnings"
    assert main(["validate", "--ignore", "floating-object", str(path)]) == 0
    assert "[floating-object]" not in capsys.readouterr().out
    assert main(["validate", "--ignore", "interpenetration,floating-object", str(path)]) == 0
    assert capsys.readouterr().out.splitlines() == ["1 file(s): conforms"]
    assert validate([path], ignore={"floating-object", "interpenetration"}).diagnostics == []


def test_geometry_that_cannot_be_read_is_an_error_of_its_own(tmp_path: Path) -> None:
    """A part whose SKU has no shape stops `kitkb predicates`: validate says so as an error at
    each part's line (issue 26, point 5: no more a `geometry-unchecked` warning), and checks no
    plausibility (the scene cannot be built)."""
    text = re.sub(r"(:sku_part_a a .*?)ktw:hasStockKeepingUnit_InternalShape :\w+ ;\n\s*", r"\1",
                  SMALL_KIT.read_text(), count=1, flags=re.S)
    path = tmp_path / "init.ttl"
    path.write_text(text)
    report = validate([path])
    assert {d.rule for d in report.diagnostics} == {"no-shape"}
    parts = sorted(set(re.findall(r"^:(part_a_\d+) a ", text, re.M)))
    assert [(d.severity, d.line, d.message.split(" is placed")[0]) for d in report.diagnostics] == \
        [("error", _line(path, p), p) for p in parts]
    assert main(["validate", str(path)]) == 1


def test_a_pose_that_is_an_error_gets_no_geometry_warnings(tmp_path: Path) -> None:
    """A z axis of length 1.4 (an error at its line) tilts the part into the table: the
    error is the one finding, as a typo gives one line."""
    text = re.sub(r"(:part_a_1_z_axis a .*?ktw:hasVector_I) [-0-9.]+", r"\1 1.0", SMALL_KIT.read_text(),
                  count=1, flags=re.S)
    path = tmp_path / "init.ttl"
    path.write_text(text)
    assert check(Scene.from_files([path]))  # the geometry is implausible ...
    report = validate([path])  # ... because of the errors, which are all that is reported
    assert {d.rule for d in report.diagnostics} == {"axis-unit-length", "axes-orthogonal"}


def test_a_kit_held_by_the_robot_hangs(tmp_path: Path) -> None:
    """The small kit's finished kit held 0.3 m under the robot's flange (the flange's z axis
    points down, so the kit's is -z in its frame): the kit, its tray (placed in the kit) and
    its parts hang from the robot; nothing floats or interpenetrates."""
    text = _edit(SMALL_KIT.with_name("goal.ttl").read_text(), "kit_1", ref="robot_1", X=0.0, Y=0.0, Z=0.3)
    text, n = re.subn(r"(:kit_1_z_axis a .*?ktw:hasVector_K) [-0-9.]+", r"\1 -1.0", text, count=1, flags=re.S)
    assert n == 1
    path = tmp_path / "goal.ttl"
    path.write_text(text)
    scene = Scene.from_files([path])
    assert scene.lo[scene.index[next(n for n in scene.names if n.endswith("#kit_tray_1"))], 2] == pytest.approx(0.9)
    assert check(scene) == []


# --- real files: nothing that is not really there -------------------------------------------------

@pytest.mark.parametrize("path", SHIPPED, ids=lambda p: f"{p.parent.name}/{p.name}")
def test_shipped_scenarios_are_plausible(path: Path) -> None:
    assert len(SHIPPED) == 6
    assert check(Scene.from_files([path])) == []


@pytest.mark.parametrize("parts,kits,seed", [(5, 1, 0), (40, 2, 3), (160, 4, 11)])
def test_generated_scenarios_are_plausible(parts: int, kits: int, seed: int, tmp_path: Path) -> None:
    write_scenario(tmp_path, parts=parts, kits=kits, seed=seed)
    for name in ("init.ttl", "goal.ttl"):
        assert check(Scene.from_files([tmp_path / name])) == [], name


@pytest.mark.skipif(not NIST_DIR.is_dir(), reason="NIST files not found")
@pytest.mark.parametrize("path", NIST_STATES, ids=lambda p: p.name)
def test_nist_states_are_plausible(path: Path) -> None:
    """Checked by hand: parts exactly as tall as the kit tray, resting 0.1 mm above its floor;
    holders against the ends of the changing-station base (a 1 mm plate, the effector hanging
    under it); the tray gripper on the robot's flange (a point); kits and large boxes are the
    boxes of their trays and containers. Nothing interpenetrates or floats."""
    scene = Scene.from_files([path])
    assert check(scene) == []


# --- the geometry -----------------------------------------------------------------------------

def _boxes(centres, yaws, half) -> Boxes:  # noqa: ANN001
    k = len(centres)
    poses = np.tile(np.eye(4), (k, 1, 1))
    for i, (c, yaw) in enumerate(zip(centres, yaws)):
        a = math.radians(yaw)
        poses[i, :3, :3] = [[math.cos(a), -math.sin(a), 0], [math.sin(a), math.cos(a), 0], [0, 0, 1]]
        poses[i, :3, 3] = c
    half = np.asarray(half, float)
    return Boxes.of(poses, -half, half)


def test_separating_axes_of_turned_boxes() -> None:
    a = _boxes([(0, 0, 0)], [0], [(0.5, 0.5, 0.5)])
    b = _boxes([(1.2, 0, 0)], [45], [(0.5, 0.5, 0.5)])
    assert sat_depth(a, b) == pytest.approx([0.5 + 0.5 * math.sqrt(2) - 1.2])
    # their world boxes overlap, the boxes do not: an edge-on corner 0.05 away
    c = _boxes([(0.5 + 0.5 * math.sqrt(2) + 0.05, 0.3, 0)], [45], [(0.5, 0.5, 0.5)])
    assert sat_depth(a, c)[0] < 0


def test_separating_axes_agree_with_points_inside_for_any_rotation() -> None:
    """Boxes turned about any axis: clearly apart by the test (less than -1 cm) -> no point of
    one inside the other; clearly in (more than 5 cm) -> some point of one inside the other."""
    rng = np.random.default_rng(7)
    n = 300
    q = rng.normal(size=(2 * n, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    w, x, y, z = q.T
    rot = np.stack([np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)], -1),
                    np.stack([2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)], -1),
                    np.stack([2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)], -1)], 1)
    poses = np.tile(np.eye(4), (2 * n, 1, 1))
    poses[:, :3, :3] = rot
    poses[n:, :3, 3] = rng.uniform(-1.2, 1.2, (n, 3))
    half = rng.uniform(0.1, 0.6, (2 * n, 3))
    boxes = Boxes.of(poses, -half, half)
    a, b = boxes.take(np.arange(n)), boxes.take(np.arange(n, 2 * n))
    depth = sat_depth(a, b)
    grid = np.stack(np.meshgrid(*[np.linspace(-1, 1, 15)] * 3), -1).reshape(-1, 3)
    for k in range(n):
        points = a.centre[k] + (grid * a.half[k]) @ a.axes[k].T
        local = (points - b.centre[k]) @ b.axes[k]
        inside = np.all(np.abs(local) <= b.half[k], axis=1).any()
        if depth[k] < -0.01:
            assert not inside, k
        elif depth[k] > 0.05:
            assert inside, k
    assert (depth < -0.01).sum() > 50 and (depth > 0.05).sum() > 50


def test_candidate_pairs_are_every_overlapping_pair() -> None:
    rng = np.random.default_rng(5)
    lo = rng.uniform(0, 10, (600, 3)) * [1, 1, 0.1]
    size = np.where(rng.random((600, 1)) < 0.05, rng.uniform(1, 4, (600, 3)), rng.uniform(0.05, 0.3, (600, 3)))
    hi = lo + size
    i, j = overlapping_pairs(lo, hi, 0.001)
    near = np.all((lo[:, None] <= hi[None] + 0.001) & (lo[None] <= hi[:, None] + 0.001), axis=2)
    want = set(zip(*np.nonzero(np.triu(near, 1))))
    assert set(zip(i.tolist(), j.tolist())) == want
    assert len(want) > 600


def test_candidate_pairs_with_huge_and_unbounded_boxes() -> None:
    """Large boxes go in a grid of cells in plan; one reaching more cells than the grid takes
    (a 1 km floor), or one that is not finite, is swept against all: every near pair is found
    all the same."""
    rng = np.random.default_rng(9)
    n = 500
    lo = rng.uniform(0, 10, (n, 3)) * [1, 1, 0.1]
    size = np.where(rng.random((n, 1)) < 0.08, rng.uniform(0.5, 3, (n, 3)), rng.uniform(0.05, 0.3, (n, 3)))
    hi = lo + size
    lo[7], hi[7] = [-500, -500, -1], [500, 500, 2]  # a block a kilometre wide
    lo[8], hi[8] = [2, 2, -np.inf], [3, 3, 0.5]  # a column down for ever
    lo[9], hi[9] = [np.nan, 1, 0], [np.nan, 2, 1]  # no number: near nothing
    lo[10], hi[10] = [4, -np.inf, 0], [4.5, np.inf, 0.2]  # a wall across the world
    i, j = overlapping_pairs(lo, hi, 0.001)
    with np.errstate(invalid="ignore"):
        near = np.all((lo[:, None] <= hi[None] + 0.001) & (lo[None] <= hi[:, None] + 0.001), axis=2)
    want = set(zip(*np.nonzero(np.triu(near, 1))))
    assert set(zip(i.tolist(), j.tolist())) == want
    assert sum(7 in p for p in want) == n - 2 and not any(9 in p for p in want)


def test_findings_of_generated_workstations_with_moved_parts(tmp_path: Path) -> None:
    """A generated workstation with one part in ten moved (5 cm up, 2 cm down, 4 cm along x),
    as it is and turned 37 degrees in millimetres: the same findings, each at its line."""
    import sys
    sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "benchmarks"))
    from bench_validate_geometry import implausible

    init, _ = write_scenario(tmp_path, parts=120, kits=2, seed=4)
    moved = tmp_path / "moved.ttl"
    text, kinds = implausible(init.read_text(), 0.1, 3)
    moved.write_text(text)
    turned = tmp_path / "turned.ttl"
    write_variant(moved, turned, unit="millimeter", yaw=37.0)
    found = {path: [(d.rule, d.focus, d.line) for d in validate([path]).diagnostics] for path in (moved, turned)}
    assert [f[:2] for f in found[moved]] == [f[:2] for f in found[turned]]
    assert {f[0] for f in found[moved]} == set(GEOMETRY)
    named = {m for d in validate([moved]).diagnostics for m in re.findall(r":(part_\w+)", d.message)}
    blocks = [dict(re.findall(r"^:(part_[a-z]+_\d+)_point a (.*?)\.\n", t, re.M | re.S)) for t in (init.read_text(), text)]
    moved_parts = {n for n in blocks[0] if blocks[0][n] != blocks[1][n]}
    assert len(moved_parts) == sum(kinds.values()) == 13
    z = [{n: re.search(r"hasPoint_Z (\S+)", b).group(1) for n, b in block.items()} for block in blocks]
    assert {n for n in moved_parts if z[0][n] != z[1][n]} <= named  # each part moved up or down is found



# --- through an open container: the faces, by how much (issue 26, point 3) --------------------------

@pytest.mark.parametrize("yaw", [0.0, 30.0])
def test_a_part_on_its_side_through_a_wall_and_the_floor_names_both(tmp_path: Path, yaw: float) -> None:
    """NIST's GearBox parts lie on their side with their origin at the floor (half of them
    below it), some past a wall of their tray: GearBox_top_1 reaches 91.5 mm beyond the -y wall
    and 47.8 mm below the floor, and validate said "goes 29 mm through a wall" (29 mm: how far
    it must move along x to clear the whole tray, the separating-axis depth; "a wall" because
    the wall's 91.5 mm is more than the floor's 47.8). Shaped so in the GearBox-like millimetre
    workstation (a shaft lying along y, its axis at the floor, 20 mm past the -y wall, in a tray
    as it is and turned): each face is named with how far the part reaches beyond it, in the
    tray's frame — numbers a reader checks against the boxes."""
    from kb.io.turtle import turtle
    from kb.scenario.variants import turn
    from tests.test_thin_parts import gearbox_graphs
    from tests.test_thin_plausibility import _move

    g = gearbox_graphs()["init"]
    if yaw:
        turn(g, yaw, ["part_shaft_tray"])
    path = tmp_path / "init.ttl"
    path.write_text(_move(turtle(g), "part_shaft_1", Y=-94.239, Z=0.0))  # the tray's -y wall is at y = -74.239 mm
    assert [m for _, _, m in _found(path) if "part_shaft_tray" in m] == [
        ":part_shaft_1 goes through the -y wall of :part_shaft_tray, 20 mm beyond it and 14.24 mm inside, and through "
        "its floor, 2.483 mm below it"]
    scene = Scene.from_files([path])
    i, tray = (scene.index[next(n for n in scene.names if n.endswith("#" + k))] for k in ("part_shaft_1", "part_shaft_tray"))
    part = Boxes.of(scene.poses[[i]], scene.local_lo[[i]], scene.local_hi[[i]])
    lo, hi = (x[0] * 1000 for x in in_frame_of(part, Boxes.of(scene.poses[[tray]], scene.local_lo[[tray]],
                                                                 scene.local_hi[[tray]])))
    t_lo = scene.local_lo[tray] * 1000
    assert (t_lo[1] - lo[1], hi[1] - t_lo[1], t_lo[2] - lo[2]) == pytest.approx((20.0, 14.239, 2.483))
    (finding,) = [f for f in check(scene) if f.other and f.other.endswith("#part_shaft_tray")]
    assert [(face, round(b * 1000, 6), round(c * 1000, 6)) for face, b, c in finding.faces] == [
        ("-y", 20.0, 14.239), ("floor", 2.483, 2.483)]
