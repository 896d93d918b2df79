"""Plausibility of thin and narrow parts agrees with their predicates (issue 26, point 1).

The predicates decide each bound pair within the tolerance only where the two bounds are each
other's nearest (kb.spatial.rcc8, "Thin boxes"): a washer 0.343 mm thick is in its tray while
its middle is above the floor. ``kitkb validate``'s interpenetration and floating-object checks
(kb.spatial.plausibility) compare each depth with the tolerance along its axis, or half the
boxes' extents along it where that is less (rcc8.depth_tolerance), and keep the whole
tolerance for gaps: a washer sunk into its tray's floor is flagged exactly when the predicates
take it out of the tray, one sensed 0.5 mm above a table still rests on it. For boxes at least
``2 t`` across, nothing changes (the tolerance is exactly ``t``).

The workstation is tests/data/thin (NIST GearBox-like, millimetres; tests/test_thin_parts.py
builds it), edited pose by pose, and the same in metres.
"""

from __future__ import annotations

import itertools
import re
from pathlib import Path

import numpy as np
import pytest

from kb.core.namespaces import KTW
from kb.spatial import Scene, true_predicates
from kb.spatial.plausibility import Boxes, check, sat_depth, sat_excess, thin_boxes
from kb.spatial.rcc8 import relate_pair
from kb.validation import validate
from tests.test_thin_parts import DATA, MM, local, write_states

GEOMETRY = ("interpenetration", "floating-object")
HALF_WASHER = 0.343 / 2  # mm: where a washer's middle is


def _move(text: str, obj: str, ref: str | None = None, **xyz: float) -> str:
    """``text`` (Turtle, lengths in the file's unit) with ``obj``'s point set (X=, Y=, Z=)
    and its reference object replaced by ``ref``."""
    def point(m: re.Match) -> str:
        block = m.group(0)
        for axis, v in xyz.items():
            block, n = re.subn(rf'(ktw:hasPoint_{axis}) "[-0-9.eE]+"', rf'\g<1> "{v!r}"', block)
            assert n == 1, (obj, axis)
        return block
    text, n = re.subn(rf"^:{obj}_point a .*?\.\n", point, text, count=1, flags=re.S | re.M)
    assert n == 1, obj
    if ref is not None:
        text, n = re.subn(rf"(:{obj}_pose a .*?ktw:hasPhysicalLocation_RefObject) :\w+", rf"\g<1> :{ref}", text,
                          count=1, flags=re.S)
        assert n == 1
    return text


def _state(tmp_path: Path, unit: str, edits: dict[str, dict], **sizes: float) -> tuple[Path, float]:
    """The thin workstation in ``unit`` (sizes: write_states' washer_height, shaft_diameter in
    metres) with ``edits`` (object -> _move's arguments, lengths in millimetres); returns the
    file and how many of its units a millimetre is."""
    scale = {"millimeter": 1.0, "meter": 0.001}[unit]
    if unit == "millimeter" and not sizes:
        text = (DATA / "init.ttl").read_text()
    else:
        init, _ = write_states(tmp_path / "made", unit=unit, **sizes)
        text = init.read_text()
    for obj, change in edits.items():
        change = {k: (v * scale if isinstance(v, float) else v) for k, v in change.items()}
        text = _move(text, obj, **change)
    path = tmp_path / "init.ttl"
    path.write_text(text)
    return path, scale


def _findings(path: Path) -> list[str]:
    """The geometry warnings of ``path`` (anything else it reports fails the test)."""
    report = validate([path])
    assert report.conforms and not [d for d in report.diagnostics if d.rule not in GEOMETRY], \
        [d.format() for d in report.diagnostics]
    return [f"{d.message} [{d.rule}]" for d in report.diagnostics]


def _in_tray(path: Path, part: str, tray: str) -> bool:
    return ("part-location-partstray", part, tray) in local(true_predicates([path]))


# --- the files as they are ---------------------------------------------------------------------------

@pytest.mark.parametrize(("height", "diameter"), [(0.343, 4.966), (0.1, 0.1), (0.2, 0.5)])
@pytest.mark.parametrize("unit", ["millimeter", "meter"])
def test_thin_and_narrow_parts_lying_in_their_trays_are_plausible(tmp_path: Path, unit: str, height: float,
                                                                  diameter: float) -> None:
    """Washers and shafts as thin as a tenth of a millimetre, on their trays' floors: nothing
    interpenetrates or floats (and the goal's kit of washers neither)."""
    init, goal = write_states(tmp_path, washer_height=height * MM, shaft_diameter=diameter * MM, unit=unit)
    assert check(Scene.from_files([init])) == []
    assert check(Scene.from_files([goal])) == []


# --- sunk into the floor: flagged where the predicates say it is through it ---------------------------

@pytest.mark.parametrize("unit", ["millimeter", "meter"])
@pytest.mark.parametrize("sunk", [0.05, 0.15, 0.17, 0.175, 0.25, 0.3])
def test_a_washer_sunk_into_its_trays_floor(tmp_path: Path, unit: str, sunk: float) -> None:
    """Its middle above the floor (sunk less than 0.1715 mm): in its tray, plausible. Below it:
    out of its tray (under the floor, in the table the tray stands on), and validate says it
    goes into the table, by how much (before, nothing was reported up to 1 mm)."""
    path, scale = _state(tmp_path, unit, {"part_washer_1": {"Z": -sunk}})
    inside = _in_tray(path, "part_washer_1", "part_washer_tray")
    found = _findings(path)
    assert inside == (sunk < HALF_WASHER)
    if inside:
        assert found == []
    else:
        depth = f"{sunk:g} mm" if unit == "millimeter" else f"{sunk * scale:.4g} m"
        assert found == [f":part_washer_1 and :parts_table_1 interpenetrate by {depth} [interpenetration]"]


@pytest.mark.parametrize("sunk", [0.2, 0.3])
def test_a_narrow_shaft_sunk_into_its_trays_floor(tmp_path: Path, sunk: float) -> None:
    """A shaft 0.5 mm across lying on the floor: sunk 0.2 mm it is in its tray, 0.3 mm (past
    its middle) it goes into the table."""
    path, _ = _state(tmp_path, "millimeter", {"part_shaft_1": {"Z": 0.25 - sunk}}, shaft_diameter=0.5 * MM)
    inside = _in_tray(path, "part_shaft_1", "part_shaft_tray")
    assert inside == (sunk < 0.25)
    assert _findings(path) == ([] if inside else
                               [f":part_shaft_1 and :parts_table_1 interpenetrate by {sunk:g} mm [interpenetration]"])


def test_a_washer_sunk_into_a_turned_tray(tmp_path: Path) -> None:
    """The same in a tray turned 30 degrees (the cavity is read in the tray's frame)."""
    from kb.io.turtle import turtle
    from kb.scenario.variants import turn
    from tests.test_thin_parts import gearbox_graphs

    for sunk, flagged in ((0.15, False), (0.3, True)):
        g = gearbox_graphs()["init"]
        turn(g, 30.0, ["part_washer_tray"])
        path = tmp_path / f"turned-{sunk}.ttl"
        path.write_text(_move(turtle(g), "part_washer_1", Z=-sunk))
        assert bool(_findings(path)) == flagged == (not _in_tray(path, "part_washer_1", "part_washer_tray"))


# --- gaps keep the whole tolerance ----------------------------------------------------------------------

@pytest.mark.parametrize("unit", ["millimeter", "meter"])
def test_a_washer_half_a_millimetre_above_its_floor_rests_on_it(tmp_path: Path, unit: str) -> None:
    path, _ = _state(tmp_path, unit, {"part_washer_1": {"Z": 0.5}})
    assert _findings(path) == []
    assert _in_tray(path, "part_washer_1", "part_washer_tray")
    (tmp_path / "far").mkdir()
    path, _ = _state(tmp_path / "far", unit, {"part_washer_1": {"Z": 1.5}})
    depth = "1.5 mm" if unit == "millimeter" else "0.0015 m"
    assert _findings(path) == [f":part_washer_1 floats {depth} above the floor of :part_washer_tray [floating-object]"]


def test_a_washer_half_a_millimetre_above_a_table_rests_on_it(tmp_path: Path) -> None:
    """On the work table (its top 750 mm up): 0.5 mm above it, it rests (its relation to the
    table is Z-EC, in contact, as the predicates read it); 1.5 mm above, it floats."""
    for gap, found in ((0.0, []), (0.5, []), (0.9, []),
                       (1.5, [":part_washer_1 floats 1.5 mm above :work_table_1 [floating-object]"])):
        path, _ = _state(tmp_path, "millimeter", {"part_washer_1": {"ref": "work_table_1", "X": 450.0, "Y": -250.0,
                                                                    "Z": 750.0 + gap}})
        assert _findings(path) == found, gap
        scene = Scene.from_files([path])
        w, t = (scene.index[next(n for n in scene.names if n.endswith("#" + k))] for k in ("part_washer_1",
                                                                                             "work_table_1"))
        z = {r for r in relate_pair(scene.lo[w], scene.hi[w], scene.lo[t], scene.hi[t]) if r.startswith("Z-")}
        assert ("Z-EC" in z) == (found == []), (gap, z)


def test_stacked_washers_rest_on_each_other(tmp_path: Path) -> None:
    """Five washers in a stack on the floor: each rests on the one below it."""
    edits = {f"part_washer_{n}": {"X": -54.239, "Y": -27.1195, "Z": round(0.343 * k, 3)}
             for k, n in enumerate((2, 3, 4, 5), 1)}
    path, _ = _state(tmp_path, "millimeter", edits)
    assert _findings(path) == []
    scene = Scene.from_files([path])
    assert check(scene) == []


# --- the rule, on boxes ----------------------------------------------------------------------------

def _aligned(lo: np.ndarray, hi: np.ndarray) -> Boxes:
    poses = np.tile(np.eye(4), (len(lo), 1, 1))
    return Boxes.of(poses, lo, hi)


def _grid_boxes(rng: np.random.Generator, n: int, step: float) -> tuple[np.ndarray, np.ndarray]:
    """``n`` axis-aligned boxes on a grid of ``step``: about a third of their extents thinner
    than 2 (the tolerance is 1), some zero."""
    lo = rng.integers(-12, 12, (n, 3)) * step
    size = np.where(rng.random((n, 3)) < 0.35, rng.integers(0, 8, (n, 3)) * step, rng.integers(8, 40, (n, 3)) * step)
    return lo, lo + size


def test_interpenetration_is_exactly_what_rcc8_does_not_call_apart_or_touching() -> None:
    """Axis-aligned boxes, many thinner than 2 t: the separating-axis test with the tolerance
    along each axis finds two boxes interpenetrating exactly when relate_pair decides them DC
    or EC on no axis (same tolerance rule, same ties), but for the ties of boxes of no extent:
    a point (or plane) at the very middle of a thin interval, or two within t of each other,
    are EQ to rcc8 and touching to the depth (neither holds any volume of the other)."""
    rng = np.random.default_rng(26)
    a_lo, a_hi = _grid_boxes(rng, 4000, 0.25)
    b_lo, b_hi = _grid_boxes(rng, 4000, 0.25)
    a, b = _aligned(a_lo, a_hi), _aligned(b_lo, b_hi)
    thin = thin_boxes(a.half, 1.0) | thin_boxes(b.half, 1.0)
    _, excess = sat_excess(a, b, 1.0, thin)
    rel = [relate_pair(a_lo[k], a_hi[k], b_lo[k], b_hi[k], 1.0) for k in range(len(a_lo))]
    meet = np.array([not any(r.endswith(("-DC", "-EC")) for r in rs) for rs in rel])
    flat = (a_lo == a_hi) | (b_lo == b_hi)
    tie = np.array([any(f"{x}-EQ" in rs and flat[k, i] for i, x in enumerate("XYZ")) for k, rs in enumerate(rel)])
    assert np.array_equal((excess > 0)[~tie], meet[~tie])
    assert tie.sum() < 20 and not (excess > 0)[tie].any()
    assert thin.sum() > 1000 and (meet & thin).sum() > 100 and (~meet & thin).sum() > 100


def test_in_an_open_container_is_what_rcc8_calls_in() -> None:
    """A part and an open tray (axis-aligned, thin parts among them): check reports the part
    interpenetrating the tray exactly when relate_pair decides them DC or EC on no axis and the
    part is not in the tray's cavity by rcc8 (X-Plus, X-Minus, Y-Plus, Y-Minus and Z-Plus: within
    its walls, not below its floor)."""
    rng = np.random.default_rng(7)
    tray_lo = np.array([-4.0, -4.0, 10.0])
    tray_hi = np.array([4.0, 4.0, 14.0])
    seen = {True: 0, False: 0}
    for _ in range(600):  # (tolerance 0.25: a third of the parts' extents under 0.5)
        size = np.where(rng.random(3) < 0.35, rng.integers(0, 16, 3) * 0.03125, rng.integers(4, 24, 3) * 0.125)
        lo = np.array([*(rng.choice([-4.0, 4.0], 2) - size[:2] / 2 + rng.integers(-12, 12, 2) * 0.03125),
                       10.0 - size[2] / 2 + rng.integers(-12, 12) * 0.03125])
        hi = lo + size
        scene = Scene.from_parts(["urn:x#part", "urn:x#tray"], [[str(KTW.Part)], [str(KTW.PartsTray)]],
                                 np.tile(np.eye(4), (2, 1, 1)), np.array([lo, tray_lo]), np.array([hi, tray_hi]),
                                 open_top=np.array([False, True]))
        found = [f for f in check(scene, 0.25, rules=("interpenetration",)) if f.other]
        rel = relate_pair(lo, hi, tray_lo, tray_hi, 0.25)
        inside = {"X-Plus", "X-Minus", "Y-Plus", "Y-Minus", "Z-Plus"} <= rel
        meet = not any(r.endswith(("-DC", "-EC")) for r in rel)
        assert bool(found) == (meet and not inside), (lo, hi, rel, found)
        seen[bool(found)] += 1
        for f in found:  # each face named is one the part reaches beyond by more than its tolerance
            assert f.faces and f.depth == f.faces[0][1]
    assert min(seen.values()) > 100


@pytest.mark.parametrize("seed", [1, 2])
def test_boxes_at_least_two_tolerances_across_get_the_tolerance(seed: int) -> None:
    """Any rotation, every extent at least 2.2 t: the tolerance along every axis is t, so the
    excess is the depth less t to the last bit (the findings of ordinary parts are unchanged)."""
    rng = np.random.default_rng(seed)
    n = 500
    q = rng.normal(size=(2 * n, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    w, x, y, z = q.T
    rot = np.stack([np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)], -1),
                    np.stack([2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)], -1),
                    np.stack([2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)], -1)], 1)
    poses = np.tile(np.eye(4), (2 * n, 1, 1))
    poses[:, :3, :3] = rot
    poses[n:, :3, 3] = rng.uniform(-0.03, 0.03, (n, 3))
    half = rng.uniform(0.0011, 0.02, (2 * n, 3))
    boxes = Boxes.of(poses, -half, half)
    a, b = boxes.take(np.arange(n)), boxes.take(np.arange(n, 2 * n))
    depth, excess = sat_excess(a, b, 0.001, np.ones(n, bool))
    assert np.array_equal(depth, sat_depth(a, b))
    assert np.array_equal(excess, depth - 0.001)
    assert ((depth > 0.001) & (depth < 0.01)).sum() > 20


def test_a_zero_extent_does_not_lower_the_tolerance() -> None:
    """A point (NIST's robot) or a plate of no thickness keeps the whole tolerance, as
    depth_tolerance has it: a point 0.5 mm inside a box touches it."""
    lo = np.array([[0.0, 0.0, 0.0], [-0.01, -0.01, 0.0]])
    hi = np.array([[0.0, 0.0, 0.0], [0.01, 0.01, 0.02]])
    point, box = _aligned(lo[:1] + [0, 0, 0.0195], hi[:1] + [0, 0, 0.0195]), _aligned(lo[1:], hi[1:])
    assert not thin_boxes(point.half, 0.001).any()
    assert sat_excess(point, box, 0.001, np.ones(1, bool))[1][0] < 0
    assert list(itertools.chain(thin_boxes(np.array([[0.0, 0.0004, 0.2]]), 0.001))) == [True]
