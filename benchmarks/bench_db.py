"""Benchmark of the world-model database, side by side with pyoxigraph's on-disk bulk load.

    python benchmarks/bench_db.py                          # 10,000 and 50,000 parts, SQLite (+ PostgreSQL
                                                           # if KITKB_PG_URL is set; that database is wiped)
    python benchmarks/bench_db.py --parts 2000 --runs 1 --pg postgresql+psycopg2://user@host/db

For each workstation (``kb.scenario.write_scenario(parts, kits, seed=0)``, its ``init.ttl``):

* the anchor: a whole process that bulk-loads the file into pyoxigraph's on-disk store
  (``Store(path).bulk_load``, all its indexes), wall time and peak memory;
* ``kitkb db load`` (into a new SQLite file / an empty PostgreSQL database, then again with
  ``--replace`` over it) and ``kitkb db dump`` as whole processes (Python start, imports, the
  work), wall time and peak memory (the children's ``ru_maxrss``), on SQLite and PostgreSQL;
* in one process on the loaded database: global poses of every solid object, one global pose,
  sensed pose updates with eq. (1) one transaction each, and stable-state batches of 1,000.

Each figure is the median of ``--runs`` runs, the anchor and kitkb taking turns; ratios are
against the anchor's median of the same run. Prints a Markdown table per size and the machine.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import random
import sqlite3
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))
sys.path.insert(0, str(REPO / "benchmarks"))

from common import cpu_model  # noqa: E402
from kb import world  # noqa: E402
from kb.spatial.transforms import from_xyz_rpy  # noqa: E402

_ANCHOR = """
import sys, pyoxigraph as ox
store = ox.Store(sys.argv[2])
store.bulk_load(path=sys.argv[1], format=ox.RdfFormat.TURTLE)
store.flush()
assert len(store) > 0
"""


def machine() -> dict[str, str]:
    """The machine and the versions that ran the benchmark."""
    import pyoxigraph

    cpu = cpu_model()

    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    return {"cpu": cpu, "cores": str(os.cpu_count()), "system": f"{platform.system()} {platform.release()}",
            "python": platform.python_version(), "sqlite": sqlite3.sqlite_version,
            "pyoxigraph": pyoxigraph.__version__, "load_average": f"{load:.1f}"}


def run_process(argv: list[str]) -> tuple[float, float]:
    """(wall seconds, peak resident MB) of one whole process; it must succeed."""
    env = {**os.environ, "PYTHONPATH": str(REPO)}
    t = time.perf_counter()
    proc = subprocess.Popen(argv, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    _, status, usage = os.wait4(proc.pid, 0)
    wall = time.perf_counter() - t
    proc.returncode = os.waitstatus_to_exitcode(status)
    err = proc.stderr.read().decode() if proc.stderr else ""
    if proc.returncode != 0:
        raise SystemExit(f"{' '.join(argv)} failed: {err}")
    return wall, usage.ru_maxrss / 1024  # Linux: KiB


def _kitkb(*args: str) -> list[str]:
    return [sys.executable, "-m", "kb.cli", *args, "-q"]


def poses(url: str, updates: int, batch: int, batches: int, seed: int) -> dict[str, float]:
    """Pose figures on a loaded database (one process, one WorldModel)."""
    rnd = random.Random(seed)
    out: dict[str, float] = {}
    with world.WorldModel(url) as wm:
        parts = [o.name for o in wm.objects("Part")]
        out["parts"] = len(parts)
        t = time.perf_counter()
        out["objects"] = len(wm.global_poses())
        out["global_all_first_s"] = time.perf_counter() - t  # reads the transformation tree too
        out["global_all_s"] = statistics.median(_timed(wm.global_poses) for _ in range(3))
        sample = [rnd.choice(parts) for _ in range(300)]
        out["global_one_ms"] = 1000 * statistics.median(_timed(wm.global_pose, p) for p in sample)
        targets = [(rnd.choice(parts), from_xyz_rpy(rnd.random(), rnd.random(), 1.0, 0, 0, rnd.random()))
                   for _ in range(updates)]
        single = [_timed(wm.set_global_pose, n, g) for n, g in targets]
        out["update_one_ms"] = 1000 * statistics.median(single)
        out["updates_per_s"] = len(single) / sum(single)
        rates = []
        for _ in range(batches):
            chosen = rnd.sample(parts, min(batch, len(parts)))
            sensed = {n: from_xyz_rpy(rnd.random(), rnd.random(), 1.0, 0, 0, rnd.random()) for n in chosen}
            t = time.perf_counter()
            result = wm.commit_stable_state(sensed, True)
            rates.append(len(sensed) / (time.perf_counter() - t))
            assert result.committed
            assert all(np.allclose(wm.global_pose(n), g) for n, g in list(sensed.items())[:10])
        out["batch_updates_per_s"] = statistics.median(rates)
    return out


def _timed(fn, *args) -> float:  # noqa: ANN001
    t = time.perf_counter()
    fn(*args)
    return time.perf_counter() - t


def bench_size(parts: int, kits: int, runs: int, pg: str | None, tmp: Path, args: argparse.Namespace) -> dict:
    """All figures for one workstation size."""
    from kb.scenario import write_scenario

    t = time.perf_counter()
    init, _ = write_scenario(tmp / f"s{parts}", parts=parts, kits=kits, seed=0)
    info = {"parts": parts, "kits": kits, "file_mb": init.stat().st_size / 1e6, "written_s": time.perf_counter() - t}
    info["statements"] = sum(1 for _ in __import__("pyoxigraph").parse(path=init, format=__import__("pyoxigraph").RdfFormat.TURTLE))
    samples: dict[str, list[float]] = {}

    def add(key: str, value: float) -> None:
        samples.setdefault(key, []).append(value)

    targets = {"sqlite": None} | ({"postgresql": pg} if pg else {})
    for r in range(runs):
        store = tmp / f"ox{parts}-{r}"
        wall, mem = run_process([sys.executable, "-c", _ANCHOR, str(init), str(store)])
        add("anchor_load_s", wall)
        add("anchor_load_mb", mem)
        for name, url in targets.items():
            if url is None:
                url = world.normalize_url(tmp / f"w{parts}-{r}.sqlite")
            else:
                world.drop_all(url)
            wall, mem = run_process(_kitkb("db", "load", str(init), "--db", url))
            add(f"{name}_load_s", wall)
            add(f"{name}_load_mb", mem)
            wall, mem = run_process(_kitkb("db", "dump", "--db", url, "-o", str(tmp / "dump.ttl")))
            add(f"{name}_dump_s", wall)
            add(f"{name}_dump_mb", mem)
            wall, mem = run_process(_kitkb("db", "load", str(init), "--db", url, "--replace"))
            add(f"{name}_replace_s", wall)
            if r == runs - 1:  # pose figures once, on the last load
                for key, value in poses(url, args.updates, args.batch, args.batches, seed=1).items():
                    add(f"{name}_{key}", value)
    return {"info": info, "median": {k: statistics.median(v) for k, v in samples.items()}, "samples": samples}


_ROWS = [
    # label, key (without database prefix), format, anchor key or None
    ("load `init.ttl`, whole process", "load_s", "{:.2f} s", "anchor_load_s"),
    ("peak memory of the load", "load_mb", "{:.0f} MB", "anchor_load_mb"),
    ("load again with `--replace` (over the same world model)", "replace_s", "{:.2f} s", None),
    ("dump to Turtle, whole process", "dump_s", "{:.2f} s", None),
    ("peak memory of the dump", "dump_mb", "{:.0f} MB", None),
    ("global poses of all solid objects (first call reads the tree)", "global_all_first_s", "{:.3f} s", None),
    ("global poses of all solid objects (one query + numpy)", "global_all_s", "{:.3f} s", None),
    ("global pose of one part (one query for its chain)", "global_one_ms", "{:.2f} ms", None),
    ("sensed pose update with eq. (1), one transaction", "update_one_ms", "{:.2f} ms", None),
    ("sensed pose updates, one transaction each", "updates_per_s", "{:,.0f} /s", None),
    ("pose updates in a stable-state batch of 1,000", "batch_updates_per_s", "{:,.0f} /s", None),
]


def table(result: dict, databases: list[str]) -> str:
    """The Markdown table of one size."""
    med = result["median"]
    head = "| measure | anchor (pyoxigraph) | " + " | ".join(databases) + " |\n|---|---|" + "---|" * len(databases)
    lines = [head]
    for label, key, fmt, anchor in _ROWS:
        cells = []
        for db in databases:
            value = med.get(f"{db}_{key}")
            cell = fmt.format(value) if value is not None else "-"
            if anchor and value is not None:
                cell += f" ({value / med[anchor]:.2f}x)"
            cells.append(cell)
        a = fmt.format(med[anchor]) if anchor else ""
        lines.append(f"| {label} | {a} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    """Run the benchmark and print the Markdown tables."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--parts", type=int, nargs="+", default=[10_000, 50_000])
    ap.add_argument("--kits", type=int, default=50)
    ap.add_argument("--runs", type=int, default=3, help="runs of each whole process (medians)")
    ap.add_argument("--updates", type=int, default=300, help="single-update transactions to time")
    ap.add_argument("--batch", type=int, default=1000, help="updates in one stable-state commit")
    ap.add_argument("--batches", type=int, default=5, help="stable-state commits to time")
    ap.add_argument("--pg", default=os.environ.get("KITKB_PG_URL"), help="PostgreSQL URL (wiped!)")
    ap.add_argument("--json", help="also write the figures to this JSON file")
    args = ap.parse_args(argv)
    facts = machine()
    print("machine: " + ", ".join(f"{k} {v}" for k, v in facts.items()))
    results = {}
    with tempfile.TemporaryDirectory(prefix="kitkb-bench-db-") as tmp:
        for parts in args.parts:
            result = bench_size(parts, args.kits, args.runs, args.pg, Path(tmp), args)
            results[str(parts)] = result
            info = result["info"]
            print(f"\n{parts:,} parts, {args.kits} kits: init.ttl {info['file_mb']:.1f} MB, "
                  f"{info['statements']:,} statements; medians of {args.runs} runs\n")
            print(table(result, ["sqlite"] + (["postgresql"] if args.pg else [])))
        if args.pg:
            world.drop_all(args.pg)
    if args.json:
        Path(args.json).write_text(json.dumps({"machine": facts, "results": results}, indent=2))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
