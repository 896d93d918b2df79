"""A/B of two checkouts of kitkb: the same ``kitkb validate`` and ``kitkb plan`` commands,
interleaved, in one session, on the same files; reports and plans compared byte for byte.

For changes that must not change cost or output (a re-layout, a refactor)::

    git worktree add /tmp/kitkb-before <rev>
    .venv/bin/python benchmarks/bench_ab.py --before /tmp/kitkb-before --label "issue 8 re-layout"

Each checkout runs as ``python -m kb.cli`` with its own tree first on ``PYTHONPATH`` (same
interpreter and packages). Validation data: the end-to-end files of ``bench_validate.py``
(made if missing); planning data: ``kitkb scenario generate --parts N --kits K --seed 0``.
Rewrites the section ``## A/B of two checkouts`` of docs/benchmarks.md.
"""

from __future__ import annotations

import argparse
import datetime as dt
import json
import os
import re
import statistics
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

import common  # noqa: E402
sys.path.insert(0, str(ROOT / "benchmarks"))

from bench_validate import machine, make_e2e  # noqa: E402

PLAN_CASES = {"10": (10, 1), "160": (160, 1), "640": (640, 1), "4x40": (160, 4)}
SECTION = "A/B of two checkouts"

_LAUNCHER = """
import json, os, subprocess, sys, time
cmd, env = json.loads(sys.argv[1]), json.loads(sys.argv[2])
t = time.perf_counter()
proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, env={**os.environ, **env})
out, err = proc.communicate()
wall = time.perf_counter() - t
usage = os.times()
print(json.dumps({"wall": wall, "cpu": usage.children_user + usage.children_system, "code": proc.returncode,
                  "out": out.decode(errors="replace"), "err": err.decode(errors="replace")[-2000:]}))
"""


def run(tree: Path, args: list[str]) -> dict:
    """One ``kitkb ARGS`` of checkout ``tree`` in a fresh process (started by a small launcher)."""
    cmd = [sys.executable, "-m", "kb.cli", *args]
    done = subprocess.run([sys.executable, "-c", _LAUNCHER, json.dumps(cmd), json.dumps({"PYTHONPATH": str(tree)})],
                          capture_output=True, text=True, check=True)
    got = json.loads(done.stdout)
    if got["code"] not in (0, 1):
        raise RuntimeError(f"{tree}: kitkb {' '.join(args)} failed ({got['code']}): {got['err']}")
    return got


def compare(trees: dict[str, Path], make_args, repeat: int) -> dict:
    """Interleaved runs (the order alternates); medians, and whether the outputs are equal."""
    walls: dict[str, list[float]] = {k: [] for k in trees}
    cpus: dict[str, list[float]] = {k: [] for k in trees}
    outs: dict[str, str] = {}
    for i in range(repeat):
        for name in (list(trees) if i % 2 == 0 else list(trees)[::-1]):
            got = run(trees[name], make_args(name))
            walls[name].append(got["wall"])
            cpus[name].append(got["cpu"])
            outs[name] = got["out"]
    row = {name: {"wall": statistics.median(walls[name]), "cpu": statistics.median(cpus[name]),
                  "walls": [round(w, 2) for w in walls[name]]} for name in trees}
    row["same_output"] = len(set(outs.values())) == 1
    row["load"] = round(os.getloadavg()[0], 1)
    return row


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--before", type=Path, required=True, help="checkout of the earlier revision")
    ap.add_argument("--after", type=Path, default=ROOT, help="checkout of the later one (default: this one)")
    ap.add_argument("--label", default="", help="what changed between the two (for the doc)")
    ap.add_argument("--validate-sizes", type=int, nargs="*", default=[1000, 10000])
    ap.add_argument("--plan-sizes", nargs="*", default=list(PLAN_CASES), help="labels: 10 160 640 4x40")
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--workdir", type=Path, default=Path("/tmp/kitkb-bench-ab"))
    ap.add_argument("--no-doc", action="store_true")
    args = ap.parse_args(argv)
    trees = {"before": args.before.resolve(), "after": args.after.resolve()}
    started = dt.datetime.now(dt.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    rows: list[tuple[str, dict]] = []
    for n in args.validate_sizes:
        data = args.workdir / f"e2e-{n}" / "init.ttl"
        if not data.exists():
            make_e2e(n, data.parent)
        rows.append((f"validate, {n:,} parts (N-Triples, ~1% violations)",
                     compare(trees, lambda name, d=data: ["validate", str(d)], args.repeat)))
        print(rows[-1], flush=True)
    for label in args.plan_sizes:
        parts, kits = PLAN_CASES[label]
        d = args.workdir / f"plan-{label}"
        if not (d / "init.ttl").exists():
            subprocess.run([sys.executable, "-m", "kb.cli", "-q", "scenario", "generate", "--parts", str(parts),
                            "--kits", str(kits), "--seed", "0", "-o", str(d)], check=True, cwd=ROOT)
        row = compare(trees, lambda name, d=d: ["-q", "plan", str(d / "init.ttl"), str(d / "goal.ttl"),
                                                "-o", str(d / f"plan-{name}.txt")], args.repeat)
        row["same_output"] = len({(d / f"plan-{name}.txt").read_text() for name in trees}) == 1
        rows.append((f"plan, {label} ({parts} parts, {kits} kit(s))", row))
        print(rows[-1], flush=True)
    if not args.no_doc:
        write_doc(render(rows, args, started))


def write_doc(section: str) -> None:
    """Replace this benchmark's section of docs/benchmarks.md (or append it)."""
    common.write_doc(SECTION, section)


def render(rows: list[tuple[str, dict]], args: argparse.Namespace, started: str) -> str:
    lines = [f"## {SECTION}", "",
             f"Command: `.venv/bin/python benchmarks/bench_ab.py --before DIR` (a checkout of the earlier "
             f"revision). Latest: {args.label or 'two checkouts'}; run {started}, {args.repeat} interleaved runs "
             "of each whole command per checkout, same interpreter, packages and files. Median wall seconds, "
             "CPU seconds in brackets; 'same output' compares the validation reports and the plan files byte "
             "for byte.", "",
             "Machine: {nproc} cores, {memory_gb} GB, {cpu}; Python {python}; load average in the table."
             .format(**machine()), "",
             "| command | before: s (cpu) | after: s (cpu) | after / before (wall) | same output | load |",
             "|---|---:|---:|---:|---|---:|"]
    for label, row in rows:
        b, a = row["before"], row["after"]
        lines.append(f"| {label} | {b['wall']:.2f} ({b['cpu']:.2f}) | {a['wall']:.2f} ({a['cpu']:.2f}) | "
                     f"{a['wall'] / b['wall']:.2f} | {'yes' if row['same_output'] else 'NO'} | {row['load']} |")
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    main()
