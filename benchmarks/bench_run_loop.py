"""``kitkb run`` as a whole process, before and after the closed loop read its inputs once (issue 27).

Two checkouts measured in the same run, each a git worktree of its commit (so that edits in
the shared working tree do not mix in): the baseline (default ``472f1d7``, the commit before
the work) and the new (default ``HEAD``). For each:

* ``kitkb run INIT GOAL -o DIR --quiet`` of a generated scenario (``kitkb scenario generate
  --parts 160 --kits 4 --seed 1``): the whole process's wall time and CPU time (its own and its
  children's: Fast Downward, the SHACL fork), old and new interleaved with the order alternating;
* the stage times ``kitkb run`` prints (validate, pddl, plan, geometry, world model, execute),
  of the same runs and of a 500-part scenario (``--parts 500 --kits 4``);
* the 500-part geometry stage alone, in process (wall and CPU seconds): the old pipeline's
  ``check_geometry`` after validation and the planning model, the loop's ``geometry`` stage;
* how often each file is parsed in one run of small-kit: calls of the loader's parser
  (``kb.io.loader.parse_text``) by file name, and pyoxigraph's streaming parser
  (``pyoxigraph.parse``: the world-model load's N-Triples) by file name.

Both checkouts run with their bytecode compiled and kept (``compileall`` first; the runs get
the caller's environment without ``PYTHONDONTWRITEBYTECODE``), as an installed kitkb does.
Medians, ratios new / old, the machine and its load. ``python benchmarks/bench_run_loop.py
[--runs 5] [--runs500 3] [--baseline 472f1d7] [--new HEAD] [--json out.json]``.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_execution import machine  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
PYTHON = ROOT / ".venv" / "bin" / "python"
STAGES = ("validate", "pddl", "plan", "geometry", "world model", "execute")
_STAGE = re.compile(r"^  (validate|pddl|plan|geometry|world model|execute): .*\(([0-9.]+) s\)$")

#: run by the measured checkout's Python: kitkb's console script (kb.cli:run, as .venv/bin/kitkb runs it)
RUN = "import sys; from kb.cli import run; sys.argv[0] = 'kitkb'; run()"
#: the same, counting parses by file name (printed as JSON on the last line of stderr)
COUNT = r"""
import collections, json, sys
from pathlib import Path
import pyoxigraph
import kb.io.loader as loader
counts = collections.Counter()
real_text, real_ox = loader.parse_text, pyoxigraph.parse
def parse_text(text, fmt, path, *a, **k):
    counts["parse_text " + Path(path).name] += 1
    return real_text(text, fmt, path, *a, **k)
def ox_parse(*a, **k):
    counts["pyoxigraph.parse " + Path(str(k.get("path") or "input")).name] += 1
    return real_ox(*a, **k)
loader.parse_text, pyoxigraph.parse = parse_text, ox_parse
from kb.cli import main
code = main(sys.argv[1:])
print(json.dumps(counts), file=sys.stderr)
sys.exit(code)
"""


#: the geometry stage of a scenario, wall and CPU seconds of this process, after what the run does
#: before it (validation, the planning model), as JSON on stdout: the old pipeline's call ...
GEOMETRY_OLD = r"""
import json, sys, time
from kb import planning
from kb.planning.geometry import check_geometry
from kb.validation import validate
init, goal = sys.argv[1:3]
validate([init, goal]); planning.kitting_model([init], [goal], "strips")
t, c = time.perf_counter(), time.process_time()
check_geometry([init], [goal])
print(json.dumps({"wall": time.perf_counter() - t, "cpu": time.process_time() - c}))
"""
#: ... and the loop's stage (its event)
GEOMETRY_NEW = r"""
import json, sys
from kb.execution import ClosedLoop, LoopOptions, events
init, goal = sys.argv[1:3]
found = {}
def on(e):
    if isinstance(e, events.StageEnded) and e.stage == "geometry":
        found.update(wall=e.seconds, cpu=e.cpu)
ClosedLoop(init, goal, LoopOptions(execute=False), on_event=on).run()
print(json.dumps(found))
"""


def geometry(trees: dict[str, Path], scenario: Path, runs: int) -> dict[str, list[dict]]:
    """The geometry stage alone, in process, old and new interleaved."""
    found: dict[str, list[dict]] = {name: [] for name in trees}
    names = list(trees)
    for i in range(runs):
        for name in names if i % 2 == 0 else names[::-1]:
            code = GEOMETRY_OLD if name == "old" else GEOMETRY_NEW
            _w, _c, out, _e = kitkb(trees[name], [str(scenario / "init.ttl"), str(scenario / "goal.ttl")], code)
            found[name].append(json.loads(out.strip().splitlines()[-1]))
            print(f"  {scenario.name} geometry {name} run {i + 1}: {found[name][-1]}", file=sys.stderr)
    return found


def worktree(commit: str, folder: Path) -> Path:
    path = folder / commit.replace("/", "_")
    subprocess.run(["git", "worktree", "add", "--detach", "-f", str(path), commit], cwd=ROOT, check=True,
                   capture_output=True)
    return path


def remove(path: Path) -> None:
    subprocess.run(["git", "worktree", "remove", "--force", str(path)], cwd=ROOT, capture_output=True)


#: the measured processes' environment: bytecode written and read (as an installed kitkb runs, with
#: its .pyc files; PYTHONDONTWRITEBYTECODE in the caller's environment would have every run compile
#: kitkb's modules from source, a cost of the benchmark and not of kitkb), no progress display
ENV = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"} | {"KITKB_PROGRESS": "0"}


def kitkb(tree: Path, args: list[str], code: str = RUN) -> tuple[float, float, str, str]:
    """Wall and CPU seconds (the process and its children) of one kitkb command of ``tree``."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t = time.perf_counter()
    done = subprocess.run([str(PYTHON), "-c", code, *args], cwd=tree, capture_output=True, text=True,
                          env=ENV | {"PYTHONPATH": str(tree)})
    wall = time.perf_counter() - t
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if done.returncode != 0:
        raise SystemExit(f"{tree}: kitkb {' '.join(args)} exited {done.returncode}:\n{done.stderr[-2000:]}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu, done.stdout, done.stderr


def stages(text: str) -> dict[str, float]:
    return {m.group(1): float(m.group(2)) for line in text.splitlines() if (m := _STAGE.match(line))}


def measure(trees: dict[str, Path], scenario: Path, runs: int, out: Path) -> dict[str, list[dict]]:
    """``runs`` of each tree on ``scenario``, interleaved (the order alternating)."""
    found: dict[str, list[dict]] = {name: [] for name in trees}
    names = list(trees)
    for i in range(runs):
        for name in names if i % 2 == 0 else names[::-1]:
            wall, cpu, stdout, _ = kitkb(trees[name], ["run", str(scenario / "init.ttl"), str(scenario / "goal.ttl"),
                                                       "-o", str(out / name)])
            found[name].append({"wall": wall, "cpu": cpu, "load": os.getloadavg()[0], **stages(stdout)})
            print(f"  {scenario.name} {name} run {i + 1}: wall {wall:.2f} s, cpu {cpu:.2f} s, "
                  + ", ".join(f"{k} {v:.2f}" for k, v in stages(stdout).items()), file=sys.stderr)
    return found


def medians(rows: list[dict]) -> dict[str, float]:
    return {k: round(statistics.median(r[k] for r in rows if k in r), 3) for k in ("wall", "cpu", *STAGES)
            if any(k in r for r in rows)}


def parses(trees: dict[str, Path], scenario: Path, out: Path) -> dict[str, dict[str, int]]:
    counts = {}
    for name, tree in trees.items():
        _w, _c, _o, err = kitkb(tree, ["-q", "run", str(scenario / "init.ttl"), str(scenario / "goal.ttl"),
                                       "-o", str(out / f"count-{name}")], COUNT)
        counts[name] = dict(sorted(json.loads(err.strip().splitlines()[-1]).items()))
    return counts


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--baseline", default="472f1d7")
    ap.add_argument("--new", default="HEAD")
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--runs500", type=int, default=3)
    ap.add_argument("--json", type=Path)
    ap.add_argument("--no-500", action="store_true", help="leave out the 500-part whole runs (slow)")
    args = ap.parse_args()
    with tempfile.TemporaryDirectory(prefix="bench-run-loop-") as tmp:
        folder = Path(tmp)
        trees = {"old": worktree(args.baseline, folder), "new": worktree(args.new, folder)}
        try:
            scenarios = {}
            for parts in (160, 500):
                target = folder / f"p{parts}"
                kitkb(trees["new"], ["scenario", "generate", "--parts", str(parts), "--kits", "4", "--seed", "1",
                                     "-o", str(target)])
                scenarios[parts] = target
            for tree in trees.values():  # compiled once (every module, bytecode kept), untimed
                subprocess.run([str(PYTHON), "-m", "compileall", "-q", "kb"], cwd=tree, env=ENV, check=True,
                               capture_output=True)
                kitkb(tree, ["-q", "validate", str(ROOT / "ontologies" / "scenarios" / "small-kit" / "init.ttl")])
            commits = {name: subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=tree, capture_output=True,
                                            text=True).stdout.strip() for name, tree in trees.items()}
            small = ROOT / "ontologies" / "scenarios" / "small-kit"
            result = {"machine": machine(), "commits": commits, "parse_counts_small_kit": parses(trees, small, folder)}
            for parts, runs in ((160, args.runs), (500, 0 if args.no_500 else args.runs500)):
                if not runs:
                    continue
                rows = measure(trees, scenarios[parts], runs, folder / "out")
                med = {name: medians(r) for name, r in rows.items()}
                ratio = {k: round(med["new"][k] / med["old"][k], 3) for k in med["new"] if med["old"].get(k)}
                pairs = [round(n["wall"] / o["wall"], 3) for o, n in zip(rows["old"], rows["new"])]
                result[f"p{parts}"] = {"runs": rows, "medians": med, "ratio_new_old": ratio, "wall_ratio_per_pair": pairs}
            if args.runs500:
                rows = geometry(trees, scenarios[500], args.runs500)
                result["geometry_p500"] = {"runs": rows, "medians": {
                    name: {k: round(statistics.median(r[k] for r in rs), 3) for k in ("wall", "cpu")}
                    for name, rs in rows.items()}}
            result["machine"]["load_average_end"] = round(os.getloadavg()[0], 2)
        finally:
            for tree in trees.values():
                remove(tree)
    text = json.dumps(result, indent=1)
    if args.json:
        args.json.write_text(text + "\n")
    print(json.dumps({k: ({"medians": v["medians"], "ratio_new_old": v.get("ratio_new_old")}
                          if isinstance(v, dict) and "runs" in v else v) for k, v in result.items()}, indent=1))


if __name__ == "__main__":
    main()
