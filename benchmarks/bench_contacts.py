"""Continuous contact detection: kitkb's swept oriented boxes (numpy) against python-fcl.

A generated 160-part cell (``kitkb scenario generate --parts 160 --kits 8 --seed 0``) is
planned and executed in the simulated cell (``kb.execution.run_scenario``); every contact
check the robot makes along its moves is captured with its inputs (the path of the tool tip,
the moving boxes, the poses of every object then, the solid pieces: floors and walls of open
containers, closed boxes). The same checks are then timed, ``--repeat`` times:

* ``numpy``: :func:`kb.spatial.sweep.sweep_contacts` (broad phase on swept world boxes, the
  separating axis test on the pairs left, vectorised);
* ``fcl``: python-fcl's continuous collision (``fcl.continuousCollide``, conservative
  advancement, translation motion, screw motion where the tool turns) on the same boxes: the
  pieces in a ``DynamicAABBTreeCollisionManager`` built for the check, the swept world box of
  each moving box as the broad-phase query, ``continuousCollide`` on the candidates. FCL has no
  contact tolerance: the boxes are shrunk by the tolerance (half on each face; plates keep no
  thickness) so that touching is not a collision;
* ``fcl narrow``: the FCL narrow phase alone, on the candidate pairs of kitkb's broad phase
  (what FCL would cost with a free broad phase).

The correct plan makes no contact, so the checks are run again with every path lowered by
``--lower`` (3 cm): the two methods' contacts are compared there, (moving box, object) pairs
per check. A 5 mm cube crossed at full speed by a part carried 2 mm too low (both end poses
free) is found by both and missed by a check of the end poses alone.

    .venv/bin/python benchmarks/bench_contacts.py                     # 160 parts, 5 runs
    .venv/bin/python benchmarks/bench_contacts.py --parts 40 --kits 2 --repeat 2 --no-doc
    .venv/bin/python benchmarks/bench_contacts.py --render            # the section from the latest results

Results are appended to ``benchmarks/results/contacts.json``; the run rewrites the
"## Continuous contact detection" section of ``docs/benchmarks.md``. Needs python-fcl
(``pip install python-fcl``; not a kitkb dependency).
"""

from __future__ import annotations

import argparse
import datetime as dt
import json
import os
import platform
import statistics
import sys
import tempfile
import time
from pathlib import Path
from typing import Any, Callable

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from common import ROOT, cpu_model, write_doc  # noqa: E402

from kb.spatial.rcc8 import DEFAULT_TOLERANCE  # noqa: E402
from kb.spatial.sweep import Pieces, solid_pieces, sweep_contacts  # noqa: E402

RESULTS = ROOT / "benchmarks" / "results" / "contacts.json"
TITLE = "Continuous contact detection"
TOL = DEFAULT_TOLERANCE
Check = tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, Pieces]


# --- the checks of a run ------------------------------------------------------------------------

def capture(parts: int, kits: int, seed: int, folder: Path) -> tuple[list[Check], dict[str, Any]]:
    """Every contact check of the executed plan of a generated cell, with its inputs."""
    import kb.sim.robot as robot
    from kb.execution import run_scenario
    from kb.scenario import write_scenario

    init, goal = write_scenario(folder, parts=parts, kits=kits, seed=seed)
    checks: list[Check] = []
    original = robot.sweep_contacts

    def record(path, rel, lo, hi, poses, pieces, *a, **kw):  # noqa: ANN001, ANN002, ANN003, ANN202
        checks.append((np.array(path), np.array(rel), np.array(lo), np.array(hi), np.array(poses), pieces))
        return original(path, rel, lo, hi, poses, pieces, *a, **kw)
    robot.sweep_contacts = record
    t = time.perf_counter()
    try:
        run = run_scenario(init, goal)
    finally:
        robot.sweep_contacts = original
    info = {"goal_holds": run.goal_holds, "run_s": round(time.perf_counter() - t, 2), "checks": len(checks),
            "pieces_median": int(statistics.median(len(c[5]) for c in checks)),
            "moving_boxes_median": int(statistics.median(len(c[1]) for c in checks))}
    return checks, info


def lowered(checks: list[Check], by: float) -> list[Check]:
    out = []
    for path, rel, lo, hi, poses, pieces in checks:
        p = path.copy()
        p[:, 2, 3] -= by
        out.append((p, rel, lo, hi, poses, pieces))
    return out


# --- the two methods --------------------------------------------------------------------------

def numpy_contacts(check: Check) -> set[tuple[int, int]]:
    return {(c.body, c.owner) for c in sweep_contacts(*check, tol=TOL)}


class FclChecks:
    """The same checks with python-fcl: boxes shrunk by the tolerance, continuousCollide."""

    def __init__(self) -> None:
        import fcl
        self.fcl = fcl

    def _box(self, size: np.ndarray, shrink: float) -> Any:
        dims = [max(float(d) - shrink, 1e-7) if d > 0 else 1e-7 for d in size]
        return self.fcl.Box(*dims)

    def _tf(self, pose: np.ndarray, centre: np.ndarray) -> Any:
        return self.fcl.Transform(pose[:3, :3], pose[:3, :3] @ centre + pose[:3, 3])

    def _request(self, turning: bool) -> Any:
        fcl = self.fcl
        motion = fcl.CCDMotionType.CCDM_SCREW if turning else fcl.CCDMotionType.CCDM_TRANS
        return fcl.ContinuousCollisionRequest(ccd_motion_type=motion,
                                              ccd_solver_type=fcl.CCDSolverType.CCDC_CONSERVATIVE_ADVANCEMENT)

    def obstacles(self, poses: np.ndarray, pieces: Pieces) -> tuple[list[Any], list[Any], list[Any]]:
        geoms, objs, tfs = [], [], []
        for owner, lo, hi in zip(pieces.owner, pieces.lo, pieces.hi):
            g = self._box(hi - lo, TOL)
            tf = self._tf(poses[owner], (lo + hi) / 2)
            geoms.append(g)
            tfs.append(tf)
            objs.append(self.fcl.CollisionObject(g, tf))
        return geoms, objs, tfs

    def contacts(self, check: Check, candidates: Callable[..., list[int]] | None = None) -> set[tuple[int, int]]:
        """Contacts of one check; ``candidates(leg, body)`` -> piece indices (default: FCL's
        own broad phase, a dynamic AABB tree queried with the swept world box)."""
        fcl = self.fcl
        path, rel, lo, hi, poses, pieces = check
        manager, index, made = None, {}, {}
        if candidates is None:  # every piece in FCL's tree
            geoms, objs, tfs = self.obstacles(poses, pieces)
            manager = fcl.DynamicAABBTreeCollisionManager()
            manager.registerObjects(objs)
            manager.setup()
            index = {id(g): k for k, g in enumerate(geoms)}
            made = {k: (objs[k], tfs[k]) for k in range(len(objs))}
        found: set[tuple[int, int]] = set()
        for leg in range(len(path) - 1):
            turning = not np.allclose(path[leg][:3, :3], path[leg + 1][:3, :3])
            for m in range(len(rel)):
                a, b = path[leg] @ rel[m], path[leg + 1] @ rel[m]
                centre = (lo[m] + hi[m]) / 2
                geom = self._box(hi[m] - lo[m], TOL)
                if manager is not None:
                    near = self._query(manager, a, b, lo[m], hi[m], index)
                else:
                    near = candidates(leg, m)
                for k in near:
                    if k not in made:  # narrow phase only: the candidates' objects alone
                        tf = self._tf(poses[pieces.owner[k]], (pieces.lo[k] + pieces.hi[k]) / 2)
                        made[k] = (fcl.CollisionObject(self._box(pieces.hi[k] - pieces.lo[k], TOL), tf), tf)
                    body = fcl.CollisionObject(geom, self._tf(a, centre))
                    result = fcl.ContinuousCollisionResult()
                    fcl.continuousCollide(body, self._tf(b, centre), made[k][0], made[k][1], self._request(turning),
                                          result)
                    if result.is_collide:
                        found.add((m, int(pieces.owner[k])))
        return found

    def at_waypoint(self, check: Check, m: int, owner: int) -> bool:
        """Whether FCL's discrete check finds moving box ``m`` in object ``owner`` at a pose of
        the path (its start, a waypoint, its end)."""
        fcl = self.fcl
        path, rel, lo, hi, poses, pieces = check
        geom = self._box(hi[m] - lo[m], TOL)
        for k in np.flatnonzero(pieces.owner == owner):
            obj = fcl.CollisionObject(self._box(pieces.hi[k] - pieces.lo[k], TOL),
                                      self._tf(poses[owner], (pieces.lo[k] + pieces.hi[k]) / 2))
            for p in path:
                body = fcl.CollisionObject(geom, self._tf(p @ rel[m], (lo[m] + hi[m]) / 2))
                if fcl.collide(body, obj, fcl.CollisionRequest(), fcl.CollisionResult()):
                    return True
        return False

    def _query(self, manager: Any, a: np.ndarray, b: np.ndarray, lo: np.ndarray, hi: np.ndarray,
               index: dict[int, int]) -> list[int]:
        """Pieces whose boxes meet the swept world box of a moving box (FCL's broad phase)."""
        fcl = self.fcl
        corners = np.array([[x, y, z, 1.0] for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])])
        pts = np.concatenate([corners @ a.T, corners @ b.T])[:, :3]
        wlo, whi = pts.min(axis=0), pts.max(axis=0)
        query = fcl.CollisionObject(fcl.Box(*np.maximum(whi - wlo, 1e-7)), fcl.Transform((wlo + whi) / 2))
        data = fcl.CollisionData(request=fcl.CollisionRequest(num_max_contacts=100000, enable_contact=True))
        manager.collide(query, data, fcl.defaultCollisionCallback)
        return sorted({index[id(c.o1)] for c in data.result.contacts if id(c.o1) in index} |
                      {index[id(c.o2)] for c in data.result.contacts if id(c.o2) in index})


def broad_candidates(check: Check) -> Callable[[int, int], list[int]]:
    """kitkb's broad phase (swept world boxes, push-out depth above the tolerance) per (leg, box)."""
    path, rel, lo, hi, poses, pieces = check
    g = poses[pieces.owner]
    centre = np.einsum("pij,pj->pi", g[:, :3, :3], (pieces.lo + pieces.hi) / 2) + g[:, :3, 3]
    ext = np.einsum("pij,pj->pi", np.abs(g[:, :3, :3]), (pieces.hi - pieces.lo) / 2)
    blo, bhi = centre - ext, centre + ext

    def near(leg: int, m: int) -> list[int]:
        corners = np.array([[x, y, z, 1.0] for x in (lo[m][0], hi[m][0]) for y in (lo[m][1], hi[m][1])
                            for z in (lo[m][2], hi[m][2])])
        pts = np.concatenate([corners @ (path[leg] @ rel[m]).T, corners @ (path[leg + 1] @ rel[m]).T])[:, :3]
        wlo, whi = pts.min(axis=0), pts.max(axis=0)
        return np.flatnonzero(np.all(np.minimum(whi - blo, bhi - wlo) > TOL, axis=1)).tolist()
    return near


# --- timing -----------------------------------------------------------------------------------

def timed(fn: Callable[[Check], Any], checks: list[Check]) -> tuple[float, list[float], list[Any]]:
    """(total s, per-check s, results) of ``fn`` over ``checks`` (CPU time)."""
    per, out = [], []
    for c in checks:
        t = time.process_time()
        out.append(fn(c))
        per.append(time.process_time() - t)
    return sum(per), per, out


def small_part() -> dict[str, Any]:
    """A 5 mm cube crossed at full speed by a carried part 2 mm too low: found by both methods,
    missed by a check of the end poses alone."""
    poses = np.array([np.eye(4)])
    poses[0, :3, 3] = (0.5, 0.0, 0.0)
    pieces = solid_pieces(np.array([[-0.0025, -0.0025, 0.0]]), np.array([[0.0025, 0.0025, 0.005]]),
                          np.array([False]), np.array([0]))
    path = np.array([np.eye(4), np.eye(4)])
    path[:, 2, 3] = 0.003  # the part's bottom 3 mm up: 2 mm into the cube
    path[1, 0, 3] = 1.0  # one metre in one command: at 1 m/s, one second
    rel = np.array([np.eye(4)])
    lo, hi = np.array([[-0.05, -0.04, 0.0]]), np.array([[0.05, 0.04, 0.06]])
    check = (path, rel, lo, hi, poses, pieces)
    ends = [sweep_contacts(np.array([p, p]), rel, lo, hi, poses, pieces) for p in path]
    out = {"numpy": sorted(numpy_contacts(check)), "end_poses": sorted({(c.body, c.owner) for e in ends for c in e})}
    try:
        out["fcl"] = sorted(FclChecks().contacts(check))
    except ImportError:
        out["fcl"] = None
    return out


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--parts", type=int, default=160)
    ap.add_argument("--kits", type=int, default=8)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--lower", type=float, default=0.03, help="metres every path is lowered by for the comparison")
    ap.add_argument("--no-doc", action="store_true", help="do not rewrite docs/benchmarks.md")
    ap.add_argument("--render", action="store_true", help="only rewrite the section from the latest results")
    args = ap.parse_args()
    if args.render:
        write_doc(TITLE, render(json.loads(RESULTS.read_text())[-1]))
        return 0
    try:
        fcl_checks: FclChecks | None = FclChecks()
    except ImportError:
        print("python-fcl is not installed: timing kitkb's method only (pip install python-fcl)")
        fcl_checks = None
    load0 = os.getloadavg()[0]
    with tempfile.TemporaryDirectory() as tmp:
        checks, info = capture(args.parts, args.kits, args.seed, Path(tmp))
    print(f"{info['checks']} checks captured from a {args.parts}-part run ({info['run_s']} s, goal holds: "
          f"{info['goal_holds']}); median {info['pieces_median']} solid pieces, {info['moving_boxes_median']} moving boxes")
    low = lowered(checks, args.lower)
    runs: dict[str, list[float]] = {"numpy": [], "fcl": [], "fcl_narrow": []}
    per: dict[str, list[float]] = {}
    results: dict[str, list[Any]] = {}
    for _ in range(args.repeat):
        total, each, results["numpy"] = timed(numpy_contacts, checks)
        runs["numpy"].append(total)
        per["numpy"] = each
        if fcl_checks is not None:
            total, each, results["fcl"] = timed(fcl_checks.contacts, checks)
            runs["fcl"].append(total)
            per["fcl"] = each
            total, each, _ = timed(lambda c: fcl_checks.contacts(c, broad_candidates(c)), checks)
            runs["fcl_narrow"].append(total)
            per["fcl_narrow"] = each
    agree: dict[str, Any] = {}
    _, _, lo_numpy = timed(numpy_contacts, low)
    agree["numpy_contacts_lowered"] = sum(len(r) for r in lo_numpy)
    agree["numpy_contacts_plan"] = sum(len(r) for r in results["numpy"])
    if fcl_checks is not None:
        lo_t, _, lo_fcl = timed(fcl_checks.contacts, low)
        lo_n, _, _ = timed(numpy_contacts, low)
        agree["fcl_contacts_lowered"] = sum(len(r) for r in lo_fcl)
        agree["fcl_contacts_plan"] = sum(len(r) for r in results["fcl"])
        agree["checks_disagreeing_lowered"] = sum(a != b for a, b in zip(lo_numpy, lo_fcl))
        agree["numpy_only"], agree["fcl_only"] = 0, 0
        for check, a, b in zip(low, lo_numpy, lo_fcl):
            agree["numpy_only"] += len(a - b)
            agree["fcl_only"] += len(b - a)
            agree["numpy_only_in_fcl_at_a_waypoint"] = agree.get("numpy_only_in_fcl_at_a_waypoint", 0) + sum(
                fcl_checks.at_waypoint(check, m, o) for m, o in a - b)
        agree["lowered_s"] = {"numpy": round(lo_n, 3), "fcl": round(lo_t, 3)}
    record = {
        "date": dt.datetime.now().isoformat(timespec="seconds"), "parts": args.parts, "kits": args.kits,
        "seed": args.seed, "repeat": args.repeat, "lower": args.lower, **info,
        "machine": {"cpu": cpu_model(), "cores": os.cpu_count(), "python": platform.python_version(),
                    "load": [round(load0, 2), round(os.getloadavg()[0], 2)]},
        "total_s": {k: round(statistics.median(v), 4) for k, v in runs.items() if v},
        "per_check_us": {k: round(statistics.median(v) * 1e6, 1) for k, v in per.items()},
        "per_check_p95_us": {k: round(float(np.percentile(v, 95)) * 1e6, 1) for k, v in per.items()},
        "agreement": agree, "small_part": small_part(),
    }
    print(json.dumps(record, indent=1))
    RESULTS.parent.mkdir(parents=True, exist_ok=True)
    history = json.loads(RESULTS.read_text()) if RESULTS.is_file() else []
    RESULTS.write_text(json.dumps(history + [record], indent=1) + "\n")
    if not args.no_doc:
        write_doc(TITLE, render(record))
    return 0


def render(r: dict[str, Any]) -> str:
    t, each, p95 = r["total_s"], r["per_check_us"], r["per_check_p95_us"]
    m = r["machine"]
    lines = [f"## {TITLE}", "",
             f"`benchmarks/bench_contacts.py`: the {r['checks']:,} contact checks of the executed plan of a generated "
             f"{r['parts']}-part cell ({r['kits']} kits, seed {r['seed']}; every move of the robot, each with the "
             f"flange, the effector and what it holds — median {r['moving_boxes_median']} moving boxes — against every "
             f"other solid, median {r['pieces_median']} pieces: floors and walls of open containers, closed boxes), "
             f"captured from the run and timed again, CPU time, medians of {r['repeat']} runs. Machine: "
             f"{m['cpu']}, {m['cores']} cores, Python {m['python']}, load {m['load'][0]} to {m['load'][1]}, "
             f"{r['date'][:10]}.", "",
             "| method | all checks | per check (median) | per check (95th percentile) |", "|---|---|---|---|"]
    label = {"numpy": "kitkb: swept oriented boxes, numpy (`kb.spatial.sweep`)",
             "fcl": "python-fcl 0.7.0.11: `continuousCollide`, its AABB-tree broad phase",
             "fcl_narrow": "python-fcl narrow phase only, on kitkb's broad-phase candidates"}
    for k in ("numpy", "fcl", "fcl_narrow"):
        if k in t:
            lines.append(f"| {label[k]} | {t[k]:.3f} s | {each[k]:.0f} µs | {p95[k]:.0f} µs |")
    a = r["agreement"]
    lines.append("")
    if "fcl" in t:
        lines.append(f"kitkb's method is **{t['fcl'] / t['numpy']:.0f} times faster** than python-fcl's over the run "
                     f"({t['fcl_narrow'] / t['numpy']:.1f} times faster than FCL's narrow phase alone). On the "
                     f"correct plan's checks both find the same {a['numpy_contacts_plan']} contacts (numpy) and "
                     f"{a['fcl_contacts_plan']} (FCL), all of them with what the tip starts or ends on or an "
                     "effector's holder, which the simulator then leaves out (the run records none); "
                     f"with every path lowered by {r['lower'] * 100:g} cm, numpy finds {a['numpy_contacts_lowered']:,} "
                     f"(moving box, object) contacts and FCL {a['fcl_contacts_lowered']:,}, "
                     f"{a['checks_disagreeing_lowered']} of {r['checks']:,} checks disagreeing: "
                     f"{a.get('numpy_only', '?')} contacts only kitkb finds, {a.get('fcl_only', '?')} only FCL finds; "
                     f"{a.get('numpy_only_in_fcl_at_a_waypoint', '?')} of kitkb's are in FCL's own discrete check at a pose of the "
                     "path (its start or end), which its `continuousCollide` did not report.")
    s = r["small_part"]
    lines.append(f"A 5 mm cube crossed in one 1 m move by a part 2 mm too low: kitkb {len(s['numpy'])} contact, "
                 f"FCL {'-' if s['fcl'] is None else len(s['fcl'])}, the end poses alone {len(s['end_poses'])}.")
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    sys.exit(main())
