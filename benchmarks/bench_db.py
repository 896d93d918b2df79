"""Benchmark of the world-model database: load a large workstation, pose updates, global poses.

    python benchmarks/bench_db.py                       # 10,000 parts, SQLite (+ PostgreSQL if KITKB_PG_URL)
    python benchmarks/bench_db.py --parts 2000 --pg postgresql+psycopg2://user@host/db

Prints a Markdown table (the figures of docs/benchmarks.md, section "World model database")
and the machine it ran on. A PostgreSQL database given here is wiped first.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import random
import sqlite3
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from kb import world  # noqa: E402
from kb.world.load import read_data  # noqa: E402
from kb.spatial.transforms import from_xyz_rpy  # noqa: E402


def machine() -> str:
    """One line describing this machine."""
    cpu = platform.processor() or "unknown CPU"
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    return (f"{cpu}, {os.cpu_count()} cores, {platform.system()} {platform.release()}, Python "
            f"{platform.python_version()}, SQLite {sqlite3.sqlite_version}, load average {load:.1f} at start")


def _timed(fn, *args):  # noqa: ANN001, ANN202
    t = time.perf_counter()
    out = fn(*args)
    return time.perf_counter() - t, out


def bench(url: str, init: Path, updates: int, batch: int, seed: int) -> dict[str, float]:
    """Figures for one database."""
    rnd = random.Random(seed)
    out: dict[str, float] = {}
    out["load_s"], report = _timed(world.load, init, url)
    out["individuals"] = report.individuals
    with world.WorldModel(url) as wm:
        parts = [o.name for o in wm.objects("Part")]
        out["parts"] = len(parts)
        times = [_timed(wm.global_poses)[0] for _ in range(3)]
        out["global_all_s"] = min(times)
        out["objects"] = len(wm.global_poses())
        sample = [rnd.choice(parts) for _ in range(200)]
        t, _ = _timed(lambda: [wm.global_pose(p) for p in sample])
        out["global_one_ms"] = 1000 * t / len(sample)
        targets = [(rnd.choice(parts), from_xyz_rpy(rnd.random(), rnd.random(), 1.0, 0, 0, rnd.random()))
                   for _ in range(updates)]
        t, _ = _timed(lambda: [wm.set_global_pose(n, g) for n, g in targets])
        out["updates_per_s"] = updates / t
        chosen = rnd.sample(parts, min(batch, len(parts)))
        poses = {n: from_xyz_rpy(rnd.random(), rnd.random(), 1.0, 0, 0, 0.1) for n in chosen}
        t, result = _timed(wm.commit_stable_state, poses, True)
        assert result.committed
        out["batch_updates_per_s"] = len(poses) / t
        assert all(np.allclose(wm.global_pose(n), g) for n, g in list(poses.items())[:20])
    with tempfile.TemporaryDirectory() as tmp:
        out["dump_s"], _ = _timed(world.dump, url, Path(tmp) / "dump.ttl")
    return out


def main(argv: list[str] | None = None) -> int:
    """Run the benchmark and print the Markdown table."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--parts", type=int, default=10_000)
    ap.add_argument("--kits", type=int, default=50)
    ap.add_argument("--updates", type=int, default=500, help="single-update transactions to time")
    ap.add_argument("--batch", type=int, default=1000, help="updates in one stable-state commit")
    ap.add_argument("--pg", default=os.environ.get("KITKB_PG_URL"), help="PostgreSQL URL (wiped!)")
    ap.add_argument("--json", help="also write the figures to this JSON file")
    args = ap.parse_args(argv)
    from kb.scenario import write_scenario

    print(f"machine: {machine()}")
    with tempfile.TemporaryDirectory() as tmp:
        t, (init, _) = _timed(lambda: write_scenario(Path(tmp) / "sc", parts=args.parts, kits=args.kits, seed=0))
        parse_s, (graph, _) = _timed(read_data, init)
        print(f"scenario: {args.parts} parts, {args.kits} kits, {len(graph)} statements in init.ttl "
              f"({init.stat().st_size / 1e6:.1f} MB); written in {t:.1f} s, parsed in {parse_s:.1f} s")
        results = {"sqlite": bench(world.normalize_url(Path(tmp) / "world.sqlite"), init, args.updates, args.batch, 1)}
        if args.pg:
            world.drop_all(args.pg)
            results["postgresql"] = bench(args.pg, init, args.updates, args.batch, 1)
            world.drop_all(args.pg)
    rows = [("load init.ttl (parse + insert, one transaction)", "load_s", "{:.1f} s"),
            ("individuals stored", "individuals", "{:.0f}"),
            ("global poses of all solid objects (one query + numpy)", "global_all_s", "{:.2f} s"),
            ("solid objects", "objects", "{:.0f}"),
            ("global pose of one part (walk up the tree)", "global_one_ms", "{:.1f} ms"),
            ("sensed pose updates, eq. (1), one transaction each", "updates_per_s", "{:.0f} /s"),
            (f"pose updates in one stable-state commit ({args.batch})", "batch_updates_per_s", "{:.0f} /s"),
            ("dump to Turtle", "dump_s", "{:.1f} s")]
    names = list(results)
    print("\n| measure | " + " | ".join(names) + " |\n|---|" + "---|" * len(names))
    for label, key, fmt in rows:
        print(f"| {label} | " + " | ".join(fmt.format(results[n][key]) for n in names) + " |")
    if args.json:
        Path(args.json).write_text(json.dumps({"machine": machine(), "results": results}, indent=2))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
