"""Kit designs that do not fit their tray (issue 26, point 2).

A kit design's slot (``PartRefAndPose``) gives the pose, in the kit tray's frame, that a part
of its SKU is put at. A slot whose part would not lie in (or on) the design's kit tray is a
``slot-outside-tray`` error of ``kitkb validate`` at the slot's line, saying by how much and on
which side in the file's length unit, and ``kitkb run`` refuses such a state before executing
(exit 1, ``executed: false`` and the reason in the report).

Files: a NIST-shaped second state pair (design ``a3b6c4``: 13 slots at x -0.372 .. 0.35 m,
y -0.306 .. 0.287 m of a 0.5 x 0.4 m kit tray; ``tests/data/kit_design_fit``), the shipped
small kit with one slot edited (in metres, millimetres, inches, the whole workstation turned),
and the GearBox-like millimetre workstation's washers 0.343 mm thick.
"""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

import numpy as np
import pytest

from kb.cli import main
from kb.core.resources import scenario_dirs
from kb.scenario import write_scenario
from kb.scenario.variants import write_variant
from kb.spatial.plausibility import SIDES, slot_misfits
from kb.validation import validate
from tests.shared_data import NIST_DIR

DATA = Path(__file__).parent / "data"
A3B6C4 = DATA / "kit_design_fit" / "kittingInstancesInit-a3b6c4.owl"
A3B6C4_GOAL = DATA / "kit_design_fit" / "kittingInstancesGoal-a3b6c4.owl"
THIN = DATA / "thin" / "init.ttl"
SMALL_KIT = next(d for d in scenario_dirs() if d.name == "small-kit") / "init.ttl"
SHIPPED = sorted(p for d in scenario_dirs() for p in d.glob("*.ttl"))
RULE = "slot-outside-tray"


def _slots(path: Path) -> list[tuple[int | None, str]]:
    return [(d.line, d.message) for d in validate([path]).diagnostics if d.rule == RULE]


def _line(path: Path, marker: str) -> int:
    return next(n for n, text in enumerate(path.read_text().splitlines(), 1) if marker in text)


# --- NIST's second state pair -------------------------------------------------------------------

#: slot of a3b6c4 -> (by how much in metres, side); the other four (b_3, b_4, c_1, c_2) fit
A3B6C4_OUT = {"a_1": ("0.172 m", "-x"), "a_2": ("0.146 m", "-y"), "a_3": ("0.146 m", "-y"),
              "b_1": ("0.16 m", "+x"), "b_2": ("0.182 m", "-x"), "b_5": ("0.16 m", "+x"),
              "b_6": ("0.182 m", "-x"), "c_3": ("0.175 m", "+x"), "c_4": ("0.127 m", "+y")}


def test_nist_design_a3b6c4_is_an_error_at_each_slot_that_does_not_fit() -> None:
    report = validate([A3B6C4])
    errors = [d for d in report.errors if d.rule == RULE]
    assert report.errors == errors  # nothing else is wrong with the file
    assert len(errors) == len(A3B6C4_OUT) == 9
    for d in errors:
        slot = re.search(r"part_ref_and_pose_kit_a3b6c4_(\w_\d)", d.message).group(1)
        by, side = A3B6C4_OUT[slot]
        assert d.line == _line(A3B6C4, f"start ktw:PartRefAndPose part_ref_and_pose_kit_a3b6c4_{slot}") + 1
        assert d.focus == f":part_ref_and_pose_kit_a3b6c4_{slot}"
        assert f" {by} beyond the {side} side of its kit tray (:stock_keeping_unit_kit_tray, 0.5 x 0.4 m)" in d.message
        assert d.message.startswith(f"slot :part_ref_and_pose_kit_a3b6c4_{slot} of :kit_design_a3b6c4 puts its part "
                                    f"(:stock_keeping_unit_part_{slot[0]}, ")


def test_validate_exits_1_on_it(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["validate", str(A3B6C4)]) == 1
    out = capsys.readouterr().out.splitlines()
    assert out[-1] == "1 file(s): 9 errors, 1 warning"
    assert sum(line.endswith(f"[{RULE}]") for line in out) == 9


def test_run_refuses_before_executing_and_says_so(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    report = tmp_path / "run.json"
    code = main(["run", str(A3B6C4), str(A3B6C4_GOAL), "--match-names", "-o", str(tmp_path / "out"),
                 "--report", str(report), "--db", str(tmp_path / "run.sqlite")])
    assert code == 1
    data = json.loads(report.read_text())
    assert data["executed"] is False and data["goal_holds"] is False and data["failures"] == []
    assert data["reason"].startswith("the state files do not validate (18 error(s): slot-outside-tray 18); first: ")
    assert "beyond the -x side of its kit tray (:stock_keeping_unit_kit_tray, 0.5 x 0.4 m)" in data["reason"]
    out = capsys.readouterr().out
    assert "not executed: the state files do not validate" in out and "execute in" not in out
    assert not list((tmp_path / "out").rglob("plan.txt"))  # refused before planning


# --- one slot of the small kit, in any unit, turned ---------------------------------------------

def _slot(text: str, slot: str = "a_2", x: float | None = None, y: float | None = None, z: float | None = None,
          yaw: float | None = None) -> str:
    """The small kit with slot ``kit_design_a2b1_prp_<slot>`` moved and turned about z."""
    def edit(m: re.Match) -> str:
        block = m.group(0)
        for axis, v in (("X", x), ("Y", y), ("Z", z)):
            if v is not None:
                block, n = re.subn(rf"(ktw:hasPoint_{axis}) [-0-9.eE]+", rf"\g<1> {v}", block)
                assert n == 1
        return block
    text, n = re.subn(rf":kit_design_a2b1_prp_{slot}_point a .*?\.\n", edit, text, count=1, flags=re.S)
    assert n == 1
    if yaw is not None:
        c, s = math.cos(math.radians(yaw)), math.sin(math.radians(yaw))
        text, n = re.subn(rf"(:kit_design_a2b1_prp_{slot}_x_axis a .*?ktw:hasVector_I) [-0-9.]+ ;(\s*ktw:hasVector_J)"
                          r" [-0-9.]+", rf"\g<1> {c:.12f} ;\g<2> {s:.12f}", text, count=1, flags=re.S)
        assert n == 1
    return text


#: slot edits (of a_2, part A 0.1 x 0.08 m, in a kit tray 0.32 x 0.24 x 0.04 m, open) -> what is
#: reported (None: it fits)
CASES = {
    "as shipped": ({}, None),
    "beyond the +x wall": ({"x": 0.2}, ("90", "beyond the +x side")),
    "beyond the -y wall": ({"y": -0.2}, ("120", "beyond the -y side")),
    "0.9 mm out: within the tolerance": ({"x": 0.1109}, None),
    "2 mm out": ({"x": 0.112}, ("2", "beyond the +x side")),
    "below the floor": ({"z": -0.01}, ("10", "below the floor")),
    "above the top: on nothing": ({"z": 0.05}, ("10", "above the top")),
    "taller than the tray is fine": ({"z": 0.0}, None),
    "fits along its length": ({"y": 0.075}, None),
    "turned 90 degrees it does not": ({"y": 0.075, "yaw": 90.0}, ("5", "beyond the +y side")),
    "turned 45 degrees": ({"y": 0.07, "yaw": 45.0}, ("13.64", "beyond the +y side")),
    "turned -135 degrees": ({"y": 0.07, "yaw": -135.0}, ("13.64", "beyond the +y side")),
}
#: millimetres -> the text in each unit
WRITTEN = {None: lambda mm: f"{float(mm) / 1000:g} m", "millimeter": lambda mm: f"{float(mm):g} mm",
           "inch": lambda mm: f"{float(mm) / 25.4:.4g} in"}


def _expected(path: Path, found: tuple | None, unit: str | None) -> list[tuple]:
    if found is None:
        return []
    mm, where = found
    line = _line(path, ":kit_design_a2b1_prp_a_2 a ")
    return [(line, f"slot :kit_design_a2b1_prp_a_2 of :kit_design_a2b1 puts its part (:sku_part_a, "
                   f"{_size(0.1, unit)} x {WRITTEN[unit](80)}) {WRITTEN[unit](mm)} {where} of its kit tray "
                   f"(:sku_kit_tray, {_size(0.32, unit)} x {WRITTEN[unit](240)})")]


def _size(metres: float, unit: str | None) -> str:
    return WRITTEN[unit](metres * 1000).rsplit(" ", 1)[0]


@pytest.mark.parametrize("case", sorted(CASES))
def test_a_slot_that_does_not_fit_its_tray(case: str, tmp_path: Path) -> None:
    edit, found = CASES[case]
    path = tmp_path / "init.ttl"
    path.write_text(_slot(SMALL_KIT.read_text(), **edit))
    assert _slots(path) == _expected(path, found, None)


@pytest.mark.parametrize("unit", ["millimeter", "inch"])
@pytest.mark.parametrize("case", ["beyond the +x wall", "below the floor", "turned 45 degrees", "as shipped"])
def test_the_same_in_another_unit(case: str, unit: str, tmp_path: Path) -> None:
    edit, found = CASES[case]
    path = tmp_path / "init.ttl"
    path.write_text(_slot(SMALL_KIT.read_text(), **edit))
    variant = tmp_path / "variant.ttl"
    write_variant(path, variant, unit=unit)
    assert _slots(variant) == _expected(variant, found, unit)


@pytest.mark.parametrize("yaw", [-151.3, 37.0])
def test_the_same_with_the_workstation_turned(yaw: float, tmp_path: Path) -> None:
    """Slots are poses in their tray's frame: turning the workstation changes nothing."""
    edit, found = CASES["turned 45 degrees"]
    path = tmp_path / "init.ttl"
    path.write_text(_slot(SMALL_KIT.read_text(), **edit))
    turned = tmp_path / "turned.ttl"
    write_variant(path, turned, yaw=yaw)
    assert _slots(turned) == _expected(turned, found, None)


# --- thin parts ------------------------------------------------------------------------------------

@pytest.mark.parametrize("z,found", [("-0.1", None), ("-0.2", "0.2 mm below the floor"), ("0.0", None),
                                     ("40.1", None), ("40.2", "0.2 mm above the top")])
def test_a_washer_0343_mm_thick_is_out_once_half_of_it_is(z: str, found: str | None, tmp_path: Path) -> None:
    """The GearBox-like workstation in millimetres: a washer slot 0.2 mm below the tray's
    floor leaves more than half the washer under it (the tolerance is half the washer's
    thickness, not 1 mm, which would swallow it); 0.1 mm is within it; the same above the top of
    the tray (40 mm tall), where the washer would lie on nothing."""
    text, n = re.subn(r'(:kit_design_washers_prp_washer_2_point a .*?ktw:hasPoint_Z) "[-0-9.]+"',
                      rf'\g<1> "{z}"', THIN.read_text(), count=1, flags=re.S)
    assert n == 1
    path = tmp_path / "init.ttl"
    path.write_text(text)
    found_now = _slots(path)
    if found is None:
        assert found_now == []
    else:
        assert len(found_now) == 1 and f"puts its part (:sku_part_washer, 10.16 x 10.16 mm) {found}" in found_now[0][1]
        assert found_now[0][0] == _line(path, ":kit_design_washers_prp_washer_2 a ")


# --- nothing that conformed stops conforming -------------------------------------------------------

@pytest.mark.parametrize("path", SHIPPED + [THIN, THIN.with_name("goal.ttl")], ids=lambda p: f"{p.parent.name}/{p.name}")
def test_shipped_and_thin_designs_fit(path: Path) -> None:
    assert _slots(path) == []


@pytest.mark.skipif(not NIST_DIR.is_dir(), reason="NIST files not found")
@pytest.mark.parametrize("name", ["kittingInstancesInit1.owl", "kittingInstancesGoal1.owl"])
def test_nist_first_pair_fits(name: str) -> None:
    assert validate([NIST_DIR / name]).conforms
    assert _slots(NIST_DIR / name) == []


@pytest.mark.parametrize("unit", [None, "millimeter"])
def test_generated_designs_fit(unit: str | None, tmp_path: Path) -> None:
    init, goal = write_scenario(tmp_path, parts=60, kits=3, seed=5)
    for path in (init, goal):
        if unit:
            write_variant(path, path, unit=unit)
        assert _slots(path) == [], path.name


# --- the geometry ---------------------------------------------------------------------------------

def test_slot_misfits_agree_with_the_corners_of_the_part() -> None:
    """Random slots, turned about any axis: a slot is a misfit exactly when a corner of its
    part's box is out of the tray's box by more than the tolerance (hull of the corners)."""
    rng = np.random.default_rng(11)
    n = 400
    q = rng.normal(size=(n, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    q[: n // 2, 1:3] = 0.0  # half of them turned about z only
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    w, x, y, z = q.T
    rot = np.stack([np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)], -1),
                    np.stack([2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)], -1),
                    np.stack([2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)], -1)], 1)
    pose = np.tile(np.eye(4), (n, 1, 1))
    pose[:, :3, :3] = rot
    pose[:, :3, 3] = rng.uniform([-0.3, -0.2, -0.02], [0.3, 0.2, 0.1], (n, 3))
    size = rng.uniform(0.01, 0.15, (n, 3))
    part_lo, part_hi = np.c_[-size[:, :2] / 2, np.zeros(n)], np.c_[size[:, :2] / 2, size[:, 2]]
    tray_lo, tray_hi = np.tile([-0.25, -0.2, 0.0], (n, 1)), np.tile([0.25, 0.2, 0.08], (n, 1))
    misfit, by, side = slot_misfits(pose, part_lo, part_hi, tray_lo, tray_hi, 0.001)
    corners = np.stack(np.meshgrid(*[[0, 1]] * 3, indexing="ij"), -1).reshape(-1, 3)
    for k in range(n):
        pts = part_lo[k] + corners * (part_hi[k] - part_lo[k])
        pts = pts @ pose[k, :3, :3].T + pose[k, :3, 3]
        out = [tray_lo[k, 0] - pts[:, 0].min(), pts[:, 0].max() - tray_hi[k, 0], tray_lo[k, 1] - pts[:, 1].min(),
               pts[:, 1].max() - tray_hi[k, 1], tray_lo[k, 2] - pts[:, 2].min(), pts[:, 2].min() - tray_hi[k, 2]]
        assert misfit[k] == (max(out) > 0.001), k
        if misfit[k]:
            assert by[k] == pytest.approx(max(out)) and SIDES[side[k]] == SIDES[int(np.argmax(out))]
    assert 50 < misfit.sum() < n - 50


def test_slot_misfits_of_no_slots() -> None:
    misfit, by, side = slot_misfits(np.zeros((0, 4, 4)), *(np.zeros((0, 3)),) * 4)
    assert misfit.shape == by.shape == side.shape == (0,)
