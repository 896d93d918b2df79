"""kb.spatial.rcc8: the 3-D RCC8 and cardinal direction kernel against hand-worked boxes and its
plain-Python reference, and world boxes against transformed corners."""

from __future__ import annotations

import itertools
import math
from contextlib import contextmanager
from typing import Iterator

import numpy as np
import pytest
import rdflib
from hypothesis import given, settings
from hypothesis import strategies as st

from kb.core.resources import ontology_path
from kb.spatial import rcc8
from kb.spatial.rcc8 import BIT, DEFAULT_TOLERANCE, RELATIONS, relate, relate_pair, world_boxes
from kb.spatial.transforms import from_xyz_rpy

SOAP = rdflib.Namespace("https://w3id.org/kitkb/soap#")
RCC8 = ("DC", "EC", "PO", "EQ", "TPP", "NTPP", "TPPi", "NTPPi")


#: Settings of relate's kernels that make small inputs take every code path: the rank kernel
#: in chunks of 3-5 objects and ragged blocks, its binary-search fallback, the compare kernel
#: in chunks.
KERNELS = {
    "default": {},
    "rank": {"_RANK_MIN_SUBJECTS": 0, "_RANK_CHUNK": (3, 5), "_BLOCK": 7},
    "rank-binary-search": {"_RANK_MIN_SUBJECTS": 0, "_MAX_LEVELS": 0},
    "compare": {"_RANK_MIN_SUBJECTS": 10**9, "_COMPARE_PAIRS": 16, "_BLOCK": 5},
}


@contextmanager
def kernel(name: str) -> Iterator[None]:
    """relate() with the settings KERNELS[name] (module constants, restored afterwards)."""
    saved = {key: getattr(rcc8, key) for key in KERNELS[name]}
    for key, value in KERNELS[name].items():
        setattr(rcc8, key, value)
    try:
        yield
    finally:
        for key, value in saved.items():
            setattr(rcc8, key, value)


def names(mask: int) -> frozenset[str]:
    """The relation names of one mask."""
    return frozenset(n for n in RELATIONS if int(mask) & BIT[n])


def both(a_lo, a_hi, b_lo, b_hi, tol: float = DEFAULT_TOLERANCE) -> frozenset[str]:
    """The relations of one pair by relate_pair, checked equal to relate's mask."""
    ref = relate_pair(a_lo, a_hi, b_lo, b_hi, tol)
    for name in KERNELS:
        with kernel(name):
            mask = relate(np.array([a_lo]), np.array([a_hi]), np.array([b_lo]), np.array([b_hi]), tol)
        assert mask.shape == (1, 1) and mask.dtype == np.uint32
        assert names(mask[0, 0]) == ref, name
    return ref


def on_x(a0: float, a1: float, b0: float, b1: float, tol: float = DEFAULT_TOLERANCE) -> frozenset[str]:
    """The X relations of intervals [a0, a1], [b0, b1] (y and z: equal unit extents)."""
    got = both((a0, 0, 0), (a1, 1, 1), (b0, 0, 0), (b1, 1, 1), tol)
    assert {"Y-EQ", "Z-EQ", "Y-Plus", "Y-Minus", "Z-Plus", "Z-Minus"} <= got
    return frozenset(n for n in got if n.startswith("X-"))


# --- names --------------------------------------------------------------------------------------

def test_relation_names_and_bits() -> None:
    assert len(RELATIONS) == 30 and len(set(RELATIONS)) == 30
    assert RELATIONS[:8] == tuple(f"X-{r}" for r in RCC8)
    assert RELATIONS[8:16] == tuple(f"Y-{r}" for r in RCC8)
    assert RELATIONS[16:24] == tuple(f"Z-{r}" for r in RCC8)
    assert RELATIONS[24:] == ("X-Plus", "X-Minus", "Y-Plus", "Y-Minus", "Z-Plus", "Z-Minus")
    assert BIT == {n: 1 << i for i, n in enumerate(RELATIONS)}
    assert DEFAULT_TOLERANCE == 0.001


def test_names_are_the_soap_classes() -> None:
    g = rdflib.Graph().parse(ontology_path("soap.ttl"))
    rcc8 = {str(c).rsplit("#", 1)[1] for c in g.subjects(rdflib.RDFS.subClassOf, SOAP["RCC8Relation"])}
    cardinal = {str(c).rsplit("#", 1)[1] for c in g.subjects(rdflib.RDFS.subClassOf, SOAP["CardinalDirectionRelation"])}
    assert rcc8 == set(RELATIONS[:24])
    assert cardinal == set(RELATIONS[24:])


# --- hand-worked boxes --------------------------------------------------------------------------

@pytest.mark.parametrize(("a", "b", "rel"), [
    ((0.0, 1.0), (2.0, 3.0), "DC"),      # subject left of object
    ((4.0, 5.0), (2.0, 3.0), "DC"),      # subject right of object
    ((0.0, 2.0), (2.0, 3.0), "EC"),      # touching from below
    ((3.0, 4.0), (2.0, 3.0), "EC"),      # touching from above
    ((0.0, 2.5), (2.0, 3.0), "PO"),
    ((2.5, 4.0), (2.0, 3.0), "PO"),
    ((2.0, 3.0), (2.0, 3.0), "EQ"),
    ((2.0, 2.5), (2.0, 3.0), "TPP"),     # shares the lower end
    ((2.5, 3.0), (2.0, 3.0), "TPP"),     # shares the upper end
    ((2.2, 2.8), (2.0, 3.0), "NTPP"),
    ((2.0, 3.0), (2.0, 2.5), "TPPi"),
    ((2.0, 3.0), (2.5, 3.0), "TPPi"),
    ((2.0, 3.0), (2.2, 2.8), "NTPPi"),
])
def test_each_rcc8_relation_on_an_axis(a, b, rel) -> None:
    got = on_x(*a, *b)
    assert {n for n in got if n[2:] in RCC8} == {f"X-{rel}"}


@pytest.mark.parametrize(("a", "b", "cardinal"), [
    ((4.0, 5.0), (2.0, 3.0), {"X-Plus"}),              # entirely on the + side
    ((0.0, 1.0), (2.0, 3.0), {"X-Minus"}),             # entirely on the - side
    ((2.2, 2.8), (2.0, 3.0), {"X-Plus", "X-Minus"}),   # inside: neither below nor beyond
    ((1.0, 4.0), (2.0, 3.0), set()),                   # reaches out on both sides
    ((2.5, 4.0), (2.0, 3.0), {"X-Plus"}),              # sticks out on the + side
    ((1.0, 2.5), (2.0, 3.0), {"X-Minus"}),
    ((1.9995, 3.0005), (2.0, 3.0), {"X-Plus", "X-Minus"}),  # within tolerance
])
def test_cardinal_directions(a, b, cardinal) -> None:
    got = on_x(*a, *b)
    assert {n for n in got if n.endswith(("Plus", "Minus"))} == cardinal


def test_part_on_a_table() -> None:
    table = ((0.0, 0.0, 0.0), (1.2, 0.8, 0.75))
    part = ((0.5, 0.3, 0.75), (0.55, 0.36, 0.80))
    got = both(*part, *table)
    assert got == {"X-NTPP", "Y-NTPP", "Z-EC", "X-Plus", "X-Minus", "Y-Plus", "Y-Minus", "Z-Plus"}
    # and the table seen from the part
    assert both(*table, *part) == {"X-NTPPi", "Y-NTPPi", "Z-EC", "Z-Minus"}


def test_part_resting_on_a_tray_floor_and_sticking_out() -> None:
    tray = ((0.0, 0.0, 0.0), (0.3, 0.2, 0.04))
    resting = ((0.1, 0.05, 0.0005), (0.15, 0.1, 0.0205))   # floor 0.5 mm thick: within tolerance
    got = both(*resting, *tray)
    assert {"X-NTPP", "Y-NTPP", "Z-TPP", "Z-Plus", "Z-Minus"} <= got
    tall = ((0.1, 0.05, 0.005), (0.15, 0.1, 0.09))                # on a 5 mm floor, above the rim
    got = both(*tall, *tray)
    assert {"X-NTPP", "Y-NTPP", "Z-PO", "Z-Plus"} <= got and "Z-Minus" not in got
    tall_on_thin_floor = ((0.1, 0.05, 0.0005), (0.15, 0.1, 0.09))  # shares the tray's bottom
    assert "Z-TPPi" in both(*tall_on_thin_floor, *tray)


def test_tolerance_gap() -> None:
    table_top = 0.75
    for gap, rel in ((0.0005, "Z-EC"), (0.002, "Z-DC")):
        part = ((0.0, 0.0, table_top + gap), (0.1, 0.1, table_top + gap + 0.05))
        got = both(*part, (0.0, 0.0, 0.0), (0.1, 0.1, table_top))
        assert rel in got and "Z-Plus" in got and "Z-Minus" not in got
    part = ((0.0, 0.0, table_top + 0.0005), (0.1, 0.1, table_top + 0.05))
    assert "Z-DC" in both(*part, (0.0, 0.0, 0.0), (0.1, 0.1, table_top), tol=0.0)
    assert "Z-EC" in both(*part, (0.0, 0.0, 0.0), (0.1, 0.1, table_top), tol=0.001)
    assert "Z-DC" in both(*part, (0.0, 0.0, 0.0), (0.1, 0.1, table_top), tol=0.0004)


def test_bad_arguments() -> None:
    one = np.zeros((1, 3))
    with pytest.raises(ValueError):
        relate(one, one, one, one, tol=-0.001)
    with pytest.raises(ValueError):
        relate(one, one, one, one, tol=math.nan)
    with pytest.raises(ValueError):
        relate_pair((0, 0, 0), (1, 1, 1), (0, 0, 0), (1, 1, 1), tol=-1)
    with pytest.raises(ValueError):
        relate(np.zeros((2, 2)), np.ones((2, 2)), one, one)
    with pytest.raises(ValueError):
        relate(np.ones((1, 3)), np.zeros((1, 3)), one, one)  # lo > hi
    with pytest.raises(ValueError):
        relate(np.full((1, 3), np.nan), one, one, one)


@pytest.mark.parametrize("name", KERNELS)
def test_empty_inputs(name: str) -> None:
    with kernel(name):
        assert relate(np.zeros((0, 3)), np.zeros((0, 3)), np.zeros((4, 3)), np.ones((4, 3))).shape == (0, 4)
        assert relate(np.zeros((4, 3)), np.ones((4, 3)), np.zeros((0, 3)), np.zeros((0, 3))).shape == (4, 0)


# --- random boxes on a coarse grid: ties are frequent -------------------------------------------

def grid_boxes(rng: np.random.Generator, n: int, step: float) -> tuple[np.ndarray, np.ndarray]:
    """n boxes with corners on a grid of ``step`` (zero widths included), jittered by < step/4."""
    lo = rng.integers(0, 6, (n, 3)) * step
    hi = lo + rng.integers(0, 4, (n, 3)) * step
    jitter = rng.choice([0.0, 0.0, step / 8, -step / 8], (2, n, 3))
    lo, hi = lo + jitter[0], hi + jitter[1]
    return np.minimum(lo, hi), np.maximum(lo, hi)


def test_exactly_one_rcc8_relation_per_axis() -> None:
    rng = np.random.default_rng(4)
    a_lo, a_hi = grid_boxes(rng, 300, 0.001)
    b_lo, b_hi = grid_boxes(rng, 70, 0.001)
    masks = relate(a_lo, a_hi, b_lo, b_hi)
    for axis in range(3):
        axis_bits = (masks >> np.uint32(8 * axis)) & np.uint32(0xFF)
        assert (np.bitwise_count(axis_bits) == 1).all()
    assert not (masks >> np.uint32(30)).any()
    seen = {n for n in RELATIONS if (masks & np.uint32(BIT[n])).any()}
    assert seen == set(RELATIONS)  # the grid reaches every relation


@pytest.mark.parametrize("name", KERNELS)
def test_relate_equals_relate_pair_on_a_grid(name: str) -> None:
    rng = np.random.default_rng(7)
    for step, tol in ((0.001, 0.001), (0.0005, 0.001), (1.0, 0.0), (0.1, 0.1)):
        a_lo, a_hi = grid_boxes(rng, 40, step)
        b_lo, b_hi = grid_boxes(rng, 25, step)
        with kernel(name):
            masks = relate(a_lo, a_hi, b_lo, b_hi, tol)
        for i, j in itertools.product(range(40), range(25)):
            assert names(masks[i, j]) == relate_pair(a_lo[i], a_hi[i], b_lo[j], b_hi[j], tol), (i, j, step, tol)


coord = st.integers(-4, 4)
scale = st.sampled_from([0.001, 0.0005, 0.0015, 1.0, 0.3])
box = st.tuples(st.tuples(coord, coord, coord), st.tuples(st.integers(0, 4), st.integers(0, 4), st.integers(0, 4)))


@settings(max_examples=200, deadline=None)
@given(st.lists(box, min_size=1, max_size=12), st.lists(box, min_size=1, max_size=12), scale,
       st.sampled_from([DEFAULT_TOLERANCE, 0.0, 0.0005, 0.3]), st.sampled_from(sorted(KERNELS)))
def test_relate_equals_relate_pair(subjects, objects, step, tol, name) -> None:
    def arrays(boxes):
        lo = np.array([c for c, _ in boxes], dtype=float) * step
        return lo, lo + np.array([w for _, w in boxes], dtype=float) * step

    a_lo, a_hi = arrays(subjects)
    b_lo, b_hi = arrays(objects)
    with kernel(name):
        masks = relate(a_lo, a_hi, b_lo, b_hi, tol)
    assert masks.shape == (len(subjects), len(objects))
    for i, j in itertools.product(range(len(subjects)), range(len(objects))):
        ref = relate_pair(a_lo[i], a_hi[i], b_lo[j], b_hi[j], tol)
        assert names(masks[i, j]) == ref
        assert sum(1 for n in ref if n[2:] in RCC8) == 3


def test_many_boxes_blocks_and_chunks() -> None:
    """Default settings on sizes that take the rank kernel in several blocks and chunks of objects."""
    rng = np.random.default_rng(11)
    a_lo, a_hi = grid_boxes(rng, 2100, 0.001)
    b_lo, b_hi = grid_boxes(rng, 300, 0.001)
    masks = relate(a_lo, a_hi, b_lo, b_hi)
    with kernel("compare"):
        assert (relate(a_lo[:700], a_hi[:700], b_lo, b_hi) == masks[:700]).all()
    for i, j in zip(rng.integers(0, 2100, 3000), rng.integers(0, 300, 3000)):
        assert names(masks[i, j]) == relate_pair(a_lo[i], a_hi[i], b_lo[j], b_hi[j])


@pytest.mark.parametrize("values", [
    np.array([0.5]),                                    # one value: no width
    np.array([-1e308, 0.0, 1e308]),                     # width overflows
    np.linspace(0.0, 1.0, 50),
    np.concatenate([np.linspace(0.0, 1.0, 30) + k * 1e-9 for k in range(3)]),  # 3 values per bucket
    np.concatenate([np.linspace(0.0, 1.0, 20), 0.5 + np.arange(1, 9) * 1e-12]),  # a crowded bucket
])
def test_bucket_ranks_equal_binary_search(values: np.ndarray) -> None:
    u = np.unique(values)
    probes = np.concatenate([u, np.nextafter(u, -np.inf), np.nextafter(u, np.inf),
                             np.random.default_rng(0).uniform(-2.0, 2.0, 500), [-1e308, 1e308]])
    assert (rcc8._ranks(u, probes) == np.searchsorted(u, probes, "right")).all()


# --- world boxes --------------------------------------------------------------------------------

def corners_box(pose: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The world box of the 8 transformed corners, by hand."""
    pts = np.array([[(lo, hi)[bx][0], (lo, hi)[by][1], (lo, hi)[bz][2], 1.0]
                    for bx, by, bz in itertools.product((0, 1), repeat=3)])
    world = (pose @ pts.T).T[:, :3]
    return world.min(axis=0), world.max(axis=0)


angle = st.floats(-math.pi, math.pi, allow_nan=False)
length = st.floats(-2.0, 2.0, allow_nan=False)


@settings(max_examples=100, deadline=None)
@given(st.lists(st.tuples(st.tuples(length, length, length), st.tuples(angle, angle, angle),
                          st.tuples(length, length, length), st.tuples(length, length, length)),
                min_size=1, max_size=6))
def test_world_boxes_against_corners(objects) -> None:
    poses = np.array([from_xyz_rpy(*xyz, *rpy) for xyz, rpy, _, _ in objects])
    lo = np.array([np.minimum(p, q) for _, _, p, q in objects])
    hi = np.array([np.maximum(p, q) for _, _, p, q in objects])
    lo_w, hi_w = world_boxes(poses, lo, hi)
    assert lo_w.shape == hi_w.shape == (len(objects), 3)
    for k in range(len(objects)):
        want_lo, want_hi = corners_box(poses[k], lo[k], hi[k])
        np.testing.assert_allclose(lo_w[k], want_lo, atol=1e-12)
        np.testing.assert_allclose(hi_w[k], want_hi, atol=1e-12)


def test_world_boxes_exact_for_axis_aligned_poses() -> None:
    pose = np.eye(4)
    pose[:3, 3] = (0.1, 0.2, 0.75)
    quarter = from_xyz_rpy(0.0, 0.0, 0.0, 0.0, 0.0, math.pi / 2)
    lo_w, hi_w = world_boxes(np.array([pose, quarter]), np.array([[0.0, 0.0, 0.0], [0.0, 0.0, 0.0]]),
                             np.array([[0.05, 0.06, 0.05], [2.0, 1.0, 0.5]]))
    assert lo_w[0].tolist() == [0.1, 0.2, 0.75] and hi_w[0].tolist() == [0.1 + 0.05, 0.2 + 0.06, 0.75 + 0.05]
    np.testing.assert_allclose(lo_w[1], [-1.0, 0.0, 0.0], atol=1e-12)
    np.testing.assert_allclose(hi_w[1], [0.0, 2.0, 0.5], atol=1e-12)
    with pytest.raises(ValueError):
        world_boxes(np.eye(4), np.zeros(3), np.ones(3))
