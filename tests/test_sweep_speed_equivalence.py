"""The contact sweep's two-level broad phase (kb.spatial.sweep._overlapping) loses no pair: the
pairs it finds are those of the dense test of every swept box against every piece, in the same
order, so ``sweep_contacts`` and ``clearance`` give what the dense test gives, to the last bit
(issue 19: faster trials, the same results). The dense versions below are the functions as
they were before the broad phase, kept here as the reference."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from kb.spatial.sweep import (Contact, _depths, _in_frame, _moving_boxes, _overlapping, _piece_boxes, _reach_box,
                              _stretches, clearance, solid_pieces, sweep_contacts)
from kb.spatial.transforms import from_xyz_rpy

TOL = 0.001


def dense_pairs(lo_a: np.ndarray, hi_a: np.ndarray, lo_b: np.ndarray, hi_b: np.ndarray, tol: float):  # noqa: ANN201
    return np.nonzero(np.all(np.minimum(hi_a[:, None, :] - lo_b[None], hi_b[None] - lo_a[:, None, :]) > tol, axis=2))


def dense_clearance(path, rel, lo, hi, poses, pieces, tol=TOL) -> float:  # noqa: ANN001
    *_, lo_a, hi_a = _moving_boxes(path, rel, lo, hi, tol, None)
    lo_a, hi_a = lo_a.reshape(-1, 3), hi_a.reshape(-1, 3)
    *_, blo, bhi = _piece_boxes(poses, pieces)
    under = np.all(np.minimum(hi_a[:, None, :2] - blo[None, :, :2], bhi[None, :, :2] - lo_a[:, None, :2]) > tol, axis=2)
    if not under.any():
        return -math.inf
    q, p = np.nonzero(under)
    return float(np.max(bhi[p, 2] - lo_a[q, 2]))


def dense_contacts(path, rel, lo, hi, poses, pieces, tol=TOL) -> list[Contact]:  # noqa: ANN001
    """Every swept box against every piece (no broad phase at all), then the narrow phase."""
    legs, ua, ca, half_a, moves, grow, lo_a, hi_a = _moving_boxes(path, rel, lo, hi, tol, None)
    vb, half_b, cb, blo, bhi = _piece_boxes(poses, pieces)
    m_n = lo_a.shape[1]
    q, pi = dense_pairs(lo_a.reshape(-1, 3), hi_a.reshape(-1, 3), blo, bhi, tol)
    if not len(q):
        return []
    si, mi = q // m_n, q % m_n
    depth = _depths(ua[si, mi], half_a[mi], ca[si, mi], moves[si], grow[si], vb[pi], half_b[pi], cb[pi])
    found: dict[tuple[int, int], Contact] = {}
    for s, m, piece, dep in zip(si.tolist(), mi.tolist(), pi.tolist(), depth.tolist()):
        if dep <= tol:
            continue
        key, leg = (m, int(pieces.owner[piece])), int(legs[s])
        old = found.get(key)
        if old is None or leg < old.leg or (leg == old.leg and dep > old.depth):
            found[key] = Contact(m, key[1], leg, dep)
    return sorted(found.values(), key=lambda c: (c.leg, c.body, c.owner))


def cell(rng: np.random.Generator, n: int):  # noqa: ANN201
    """``n`` objects on a 1 m square, open trays and closed boxes, turned about z: (poses, pieces)."""
    poses = np.array([from_xyz_rpy(*rng.uniform(-0.5, 0.5, 2), rng.uniform(0.0, 0.1), 0.0, 0.0, rng.uniform(-3, 3))
                      for _ in range(n)])
    half = rng.uniform(0.005, 0.15, (n, 3))
    lo, hi = np.column_stack([-half[:, :2], np.zeros(n)]), np.column_stack([half[:, :2], 2 * half[:, 2]])
    return poses, solid_pieces(lo, hi, rng.random(n) < 0.5, np.arange(n))


def carried(rng: np.random.Generator, m: int):  # noqa: ANN201
    """``m`` boxes hanging below the tip: (rel, lo, hi)."""
    rel = np.array([from_xyz_rpy(*rng.uniform(-0.05, 0.05, 2), -rng.uniform(0, 0.1), 0.0, 0.0, rng.uniform(-1, 1))
                    for _ in range(m)])
    half = rng.uniform(0.002, 0.06, (m, 3))
    return rel, -half, half


@settings(max_examples=40, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow])
@given(st.integers(0, 2**32 - 1), st.integers(1, 200), st.integers(1, 40), st.integers(1, 8), st.booleans())
def test_the_two_level_pairs_are_the_dense_pairs(seed: int, q_n: int, p_n: int, chunk: int, nan: bool) -> None:
    """Random boxes (some rows NaN): the same pairs as the dense test, in its order."""
    rng = np.random.default_rng(seed)
    lo_a = rng.uniform(-1, 1, (q_n, 3))
    hi_a = lo_a + rng.uniform(0, 0.3, (q_n, 3))
    if nan:
        lo_a[rng.random(q_n) < 0.2] = np.nan
    lo_b = rng.uniform(-1, 1, (p_n, 3))
    hi_b = lo_b + rng.uniform(0, 0.5, (p_n, 3))
    want = dense_pairs(lo_a, hi_a, lo_b, hi_b, TOL)
    got = _overlapping(lo_a, hi_a, lo_b, hi_b, TOL, chunk=chunk)
    assert np.array_equal(got[0], want[0]) and np.array_equal(got[1], want[1])


@settings(max_examples=60, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow])
@given(st.integers(0, 2**32 - 1), st.integers(1, 30), st.integers(1, 4), st.floats(-3.0, 3.0), st.floats(0.0, 0.3))
def test_random_moves_find_what_the_dense_test_finds(seed: int, n: int, m: int, turn: float, z: float) -> None:
    """Random moves (turning ones cut into hundreds of stretches) through a random cell: the
    same contacts (body, object, leg, depth) and the same transfer clearance as every swept box
    tested against every piece."""
    rng = np.random.default_rng(seed)
    poses, pieces = cell(rng, n)
    rel, lo, hi = carried(rng, m)
    a = from_xyz_rpy(*rng.uniform(-0.6, 0.6, 2), z, math.pi, 0.0, rng.uniform(-3, 3))
    b = from_xyz_rpy(*rng.uniform(-0.6, 0.6, 2), z + rng.uniform(-0.1, 0.1), math.pi, 0.0, 0.0) @ from_xyz_rpy(
        0, 0, 0, 0, 0, turn)
    path = np.array([a, b])
    got = sweep_contacts(path, rel, lo, hi, poses, pieces, tol=TOL)
    assert got == dense_contacts(path, rel, lo, hi, poses, pieces)
    assert clearance(path, rel, lo, hi, poses, pieces, tol=TOL) == dense_clearance(path, rel, lo, hi, poses, pieces)


def test_a_long_turning_move_over_a_crowded_cell_misses_nothing() -> None:
    """A half turn carried low across 60 objects (hundreds of stretches, many contacts): the
    contacts and the clearance of the dense test; and there are contacts to find."""
    rng = np.random.default_rng(19)
    poses, pieces = cell(rng, 60)
    rel, lo, hi = carried(rng, 3)
    path = np.array([from_xyz_rpy(-0.6, -0.5, 0.12, math.pi, 0, 0), from_xyz_rpy(0.6, 0.5, 0.12, math.pi, 0, 3.0)])
    got = sweep_contacts(path, rel, lo, hi, poses, pieces, tol=TOL)
    assert len(_moving_boxes(path, rel, lo, hi, TOL, None)[0]) > 100
    assert len(got) >= 3
    assert got == dense_contacts(path, rel, lo, hi, poses, pieces)
    assert clearance(path, rel, lo, hi, poses, pieces, tol=TOL) == dense_clearance(path, rel, lo, hi, poses, pieces)


@settings(max_examples=80, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow])
@given(st.integers(0, 2**32 - 1), st.integers(1, 30), st.integers(1, 4), st.floats(-3.0, 3.0), st.floats(-0.6, 0.6),
       st.one_of(st.floats(-0.003, 0.0), st.floats(-0.2, 0.2)))
def test_a_clearance_bound_never_hides_a_rise_above_the_end_points(seed: int, n: int, m: int, turn: float, tilt: float,
                                                                   margin: float) -> None:
    """``clearance(..., above=h)`` (what MoveTo asks: it lifts to h anyway) is the clearance
    itself whenever that is above h (h just below it too), and -inf only when it is not; on
    moves that turn about any axis (tilted as well as about the tool)."""
    rng = np.random.default_rng(seed)
    poses, pieces = cell(rng, n)
    rel, lo, hi = carried(rng, m)
    a = from_xyz_rpy(*rng.uniform(-0.6, 0.6, 2), 0.0, math.pi, 0.0, rng.uniform(-3, 3))
    b = from_xyz_rpy(*rng.uniform(-0.6, 0.6, 2), 0.0, math.pi + tilt, tilt / 2, 0.0) @ from_xyz_rpy(0, 0, 0, 0, 0, turn)
    path = np.array([a, b])
    exact = clearance(path, rel, lo, hi, poses, pieces, tol=TOL)
    high = (exact if exact > -math.inf else 0.1) + margin
    bounded = clearance(path, rel, lo, hi, poses, pieces, tol=TOL, above=high)
    assert bounded == exact if exact > high else bounded in (-math.inf, exact)
    assert max(high, bounded) == max(high, exact)


@settings(max_examples=80, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow])
@given(st.integers(0, 2**32 - 1), st.integers(1, 4), st.floats(-3.0, 3.0), st.floats(-0.6, 0.6), st.floats(-0.2, 0.2))
def test_the_box_around_a_path_holds_every_swept_box(seed: int, m: int, turn: float, tilt: float, dz: float) -> None:
    """The box sweep_contacts and clearance decide on before making a turning path's swept
    boxes (a contact is ruled out, a clearance bounded) holds all of them."""
    rng = np.random.default_rng(seed)
    rel, lo, hi = carried(rng, m)
    a = from_xyz_rpy(*rng.uniform(-0.6, 0.6, 3), math.pi, 0.0, rng.uniform(-3, 3))
    b = from_xyz_rpy(*rng.uniform(-0.6, 0.6, 2), a[2, 3] + dz, math.pi + tilt, tilt / 2, 0.0) @ from_xyz_rpy(
        0, 0, 0, 0, 0, turn)
    path = np.array([a, b])
    half_a, centre_a, reach = _in_frame(rel, lo, hi)
    legs, rots, starts, moves, grow = _stretches(path, reach, TOL / 4)
    box_lo, box_hi = _reach_box(rots, starts, moves, grow, rel, centre_a, half_a)
    *_, lo_a, hi_a = _moving_boxes(path, rel, lo, hi, TOL, None)
    assert np.all(box_lo <= lo_a.reshape(-1, 3).min(axis=0)) and np.all(box_hi >= hi_a.reshape(-1, 3).max(axis=0))
