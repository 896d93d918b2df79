"""``kitkb validate`` of a 10,000-part workstation: what the geometry checks cost, beside a
checkout without them, and whether they find what they found before.

The geometry checks of ``validate`` (``kb.validation.geometry``: the file read as a scene by
``kb.spatial.survey``, the defects that stop the commands, kit design slots outside their
tray, and ``kb.spatial.plausibility``'s interpenetrating and floating objects) came after commit
66febab, which has none of them (issue 26, point 13: validate took 1.2 to 1.3x its time). Data:
``kb.scenario.write_scenario(parts=N, kits=N/1000, seed=1)`` from this checkout, its initial
state as it is and with about 1 % of its parts moved (floating 5 cm above their tray, 2 cm
into their tray's floor, or 4 cm along x into a neighbour or a wall).

In one run, taking turns (the order alternating), each ``--runs`` times after a warm-up:

* ``baseline``: ``kitkb validate FILE`` of ``--baseline DIR`` (e.g. ``git worktree add
  /tmp/kitkb-66febab 66febab``);
* ``now``: the same command of this checkout, and ``now-no-geometry`` with every geometry rule
  ``--ignore``d (so not computed);
* ``before`` (``--before DIR``, optional): a checkout with the earlier geometry checks
  (8749b58), for its time and its findings.

Whole processes (``bench_validate.run_e2e``: wall and CPU seconds, children included), medians.
Then, in one process of this checkout per file: the time ``check_geometry`` takes inside
``validate`` (wall and the thread's CPU) against validate's own wall time, medians of
``--runs``. The findings (the ``interpenetration`` and ``floating-object`` lines) of ``now``
and ``before`` are compared line by line: the place, the rule and the objects named (the words of a
part through a container changed with 34c1ce9).

    git worktree add /tmp/kitkb-66febab 66febab
    git worktree add /tmp/kitkb-8749b58 8749b58
    .venv/bin/python benchmarks/bench_validate_geometry.py --baseline /tmp/kitkb-66febab --before /tmp/kitkb-8749b58
    .venv/bin/python benchmarks/bench_validate_geometry.py --render     # the section from the latest results

Results are appended to ``benchmarks/results/validate_geometry.json``; the run rewrites the
"## Validation: geometry checks at 10,000 parts" section of ``docs/benchmarks.md``.
"""

from __future__ import annotations

import argparse
import datetime as dt
import json
import os
import platform
import random
import re
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from bench_validate import run_e2e, tree_command  # noqa: E402
from common import ROOT, cpu_model, write_doc  # noqa: E402

RESULTS = ROOT / "benchmarks" / "results" / "validate_geometry.json"
TITLE = "Validation: geometry checks at 10,000 parts"
#: every rule of the geometry checks (``--ignore``d: none is computed)
GEOMETRY_RULES = ("no-shape,reference-cycle,missing-value,unusable-number,degenerate-pose,unit,unknown-reference,"
                  "slot-outside-tray,interpenetration,floating-object")
PLAUSIBILITY = ("[interpenetration]", "[floating-object]")

_IN_PROCESS = """
import json, statistics, sys, time
sys.path.insert(0, sys.argv[1])
import kb.validation.validator as V
from kb.validation import validate
inner = V.check_geometry
took = []
def timed(*a, **k):
    t, c = time.perf_counter(), time.thread_time()
    out = inner(*a, **k)
    took.append((time.perf_counter() - t, time.thread_time() - c))
    return out
V.check_geometry = timed
rows, without = [], []
ignore = set(sys.argv[4].split(","))
validate([sys.argv[2]])  # warm-up: the shapes read and cached, the imports done
for i in range(int(sys.argv[3])):
    for skip in ((False, True) if i % 2 == 0 else (True, False)):
        took.clear()
        t = time.perf_counter()
        validate([sys.argv[2]], ignore=ignore if skip else ())
        if skip:
            without.append(time.perf_counter() - t)
        else:
            rows.append((time.perf_counter() - t, sum(w for w, _ in took), sum(c for _, c in took)))
print(json.dumps({"rows": rows, "without": without}))
"""


def implausible(text: str, rate: float, seed: int) -> tuple[str, dict[str, int]]:
    """The generated state ``text`` (Turtle) with about ``rate`` of its parts moved: 5 cm up,
    2 cm down, or 4 cm along x (in their reference object's frame)."""
    rnd = random.Random(seed)
    parts = sorted(set(re.findall(r"^:(part_[a-z]+_\d+)_point a ", text, re.M)))
    chosen = sorted(rnd.sample(parts, max(1, round(len(parts) * rate))))
    kinds = {"float": ("Z", 0.05), "sink": ("Z", -0.02), "shift": ("X", 0.04)}
    done = {k: 0 for k in kinds}
    for n, part in enumerate(chosen):
        kind = list(kinds)[n % len(kinds)]
        axis, by = kinds[kind]

        def move(m: re.Match, axis: str = axis, by: float = by) -> str:
            return re.sub(rf"(ktw:hasPoint_{axis}) ([-0-9.eE]+)", lambda v: f"{v.group(1)} {float(v.group(2)) + by:.6f}",
                          m.group(0), count=1)
        text, k = re.subn(rf"^:{part}_point a .*?\.\n", move, text, count=1, flags=re.M | re.S)
        done[kind] += k
    return text, done


def data(parts: int, out: Path, rate: float) -> dict[str, Path]:
    from kb.scenario import write_scenario

    init, _goal = write_scenario(out, parts=parts, kits=max(1, parts // 1000), seed=1)
    moved, kinds = implausible(init.read_text(), rate, seed=1)
    target = out / "init-implausible.ttl"
    target.write_text(moved)
    print(f"data: {init} ({init.stat().st_size / 1e6:.1f} MB), {target.name} (moved: {kinds})")
    return {"init": init, "init-implausible": target}


def findings(report: str) -> list[tuple[str, str, tuple[str, ...]]]:
    """The plausibility findings of a report: (file:line, rule, the objects named), the words
    aside (a part through a container names the faces it goes through since 34c1ce9)."""
    out = []
    for line in report.splitlines():
        if line.endswith(PLAUSIBILITY):
            where, message = line.split(": warning: ", 1)
            out.append((where, message.rsplit("[", 1)[1].rstrip("]"), tuple(re.findall(r":[\w.-]+", message))))
    return sorted(out)


def in_process(tree: Path, path: Path, runs: int) -> dict[str, float]:
    """Medians of validate's wall time and of check_geometry's wall and thread CPU in it."""
    done = subprocess.run([sys.executable, "-c", _IN_PROCESS, str(tree), str(path), str(runs), GEOMETRY_RULES],
                          capture_output=True, text=True, check=True, cwd=ROOT)
    got = json.loads(done.stdout.splitlines()[-1])
    rows = got["rows"]
    wall, geo_wall, geo_cpu = (statistics.median(col) for col in zip(*rows))
    without = statistics.median(got["without"])
    return {"validate_wall_s": round(wall, 3), "geometry_wall_s": round(geo_wall, 3),
            "geometry_cpu_s": round(geo_cpu, 3), "share_wall": round(geo_wall / wall, 4),
            "share_cpu": round(geo_cpu / wall, 4), "validate_without_s": round(without, 3),
            "share_difference": round((wall - without) / wall, 4),
            "runs": [[round(x, 3) for x in r] for r in rows], "without": [round(x, 3) for x in got["without"]]}


def measure(files: dict[str, Path], trees: dict[str, list[str]], runs: int) -> dict[str, Any]:
    out: dict[str, Any] = {}
    for name, path in files.items():
        variants = {key: (cmd, []) for key, cmd in trees.items()}
        variants["now-no-geometry"] = (trees["now"], ["--ignore", GEOMETRY_RULES])
        order = list(variants)
        walls: dict[str, list[float]] = {k: [] for k in order}
        cpus: dict[str, list[float]] = {k: [] for k in order}
        reports: dict[str, str] = {}
        loads = [os.getloadavg()[0]]
        for key in order:  # warm-up (the file in the page cache, Python's bytecode)
            run_e2e(str(path), variants[key][0], variants[key][1])
        for i in range(runs):
            for key in (order if i % 2 == 0 else order[::-1]):
                got = run_e2e(str(path), variants[key][0], variants[key][1])
                walls[key].append(got["wall_s"])
                cpus[key].append(got["cpu_s"])
                reports[key] = got["report"]
                print(f"  {name} {key}: {got['wall_s']:.2f} s wall, {got['cpu_s']:.2f} s CPU; {got['summary']}")
            loads.append(os.getloadavg()[0])
        row: dict[str, Any] = {k: {"wall_s": round(statistics.median(walls[k]), 3),
                                   "cpu_s": round(statistics.median(cpus[k]), 3),
                                   "walls": [round(w, 2) for w in walls[k]]} for k in order}
        base = row["baseline"]["wall_s"]
        row["ratio_now_baseline"] = round(row["now"]["wall_s"] / base, 3)
        if "before" in row:
            row["ratio_before_baseline"] = round(row["before"]["wall_s"] / base, 3)
        row["findings"] = len(findings(reports["now"]))
        if "before" in reports:
            row["same_findings_as_before"] = findings(reports["now"]) == findings(reports["before"])
        row["summary"] = reports["now"].splitlines()[-1]
        row["load"] = [round(x, 2) for x in loads]
        out[name] = row
    return out


def render(rec: dict[str, Any], earlier: list[dict[str, Any]] = ()) -> str:  # type: ignore[assignment]
    m = rec["machine"]
    lines = [f"## {TITLE}", "",
             f"`benchmarks/bench_validate_geometry.py` ({rec['date']}; {m['cpu']}, {m['cores']} cores, Python "
             f"{m['python']}; load average {rec['load'][0]:.1f} to {rec['load'][1]:.1f} — the machine was shared with "
             "other sessions). `kitkb validate` of a generated workstation of "
             f"{rec['parts']:,} parts (`write_scenario(parts={rec['parts']}, kits={rec['kits']}, seed=1)`: "
             f"{rec['objects']:,} placed objects) and of the same with {rec['moved']} parts moved (floating, into the "
             "floor, into a neighbour or a wall); whole processes taking turns in one run, medians of "
             f"{rec['runs']} after a warm-up. `baseline` is {rec['baseline_rev']}, which has no geometry checks; "
             "`now-no-geometry` is this checkout with every geometry rule `--ignore`d (not computed)"
             + (f"; `before` is {rec['before_rev']}, the earlier checks." if rec.get("before_rev") else "."), "",
             "| file | checkout | wall (s) | CPU (s) | wall / baseline |", "|---|---|---|---|---|"]
    for name, row in rec["files"].items():
        base = row["baseline"]["wall_s"]
        for key in ("baseline", "before", "now", "now-no-geometry"):
            if key in row:
                lines.append(f"| {name} | {key} | {row[key]['wall_s']:.2f} | {row[key]['cpu_s']:.2f} | "
                             f"{row[key]['wall_s'] / base:.2f} |")
    lines += ["", "Inside one process of this checkout, `kb.validation.validate` with and without the geometry rules "
              "ignored, taking turns (medians of the same number of runs): the geometry checks (`check_geometry`: "
              "reading the scene, the defects, the slots, plausibility; wall and the thread's CPU) against validate's "
              "wall time, and validate's wall time without them:", "",
              "| file | validate wall (s) | geometry wall (s) | geometry CPU (s) | share of validate's wall | "
              "validate without geometry (s) |", "|---|---|---|---|---|---|"]
    for name, row in rec["in_process"].items():
        lines.append(f"| {name} | {row['validate_wall_s']:.2f} | {row['geometry_wall_s']:.3f} | "
                     f"{row['geometry_cpu_s']:.3f} | {100 * row['share_wall']:.1f} % (CPU {100 * row['share_cpu']:.1f} %) | "
                     f"{row['validate_without_s']:.2f} |")
    lines.append("")
    for name, row in rec["files"].items():
        same = row.get("same_findings_as_before")
        lines.append(f"- {name}: {row['findings']} plausibility findings"
                     + ("" if same is None else (", the same as `before`'s (each line, rule and objects)" if same
                                                 else ", NOT the same as `before`'s"))
                     + f"; now / baseline {row['ratio_now_baseline']:.2f}"
                     + (f" (before / baseline {row['ratio_before_baseline']:.2f})" if "ratio_before_baseline" in row
                        else "")
                     + f"; the geometry checks add {row['now']['wall_s'] - row['now-no-geometry']['wall_s']:+.2f} s wall "
                       f"and {row['now']['cpu_s'] - row['now-no-geometry']['cpu_s']:+.2f} s CPU to the whole process "
                       "(they run while SHACL runs in its forked helper).")
    if rec.get("note"):
        lines += ["", rec["note"]]
    if earlier:
        lines += ["", "Earlier runs (`benchmarks/results/validate_geometry.json`), wall / baseline and the geometry's "
                      "share of validate's wall in one process:", ""]
        for old in earlier:
            ratios = "; ".join(
                f"{name} now {row['ratio_now_baseline']:.2f}"
                + (f", before ({old['before_rev']}) {row['ratio_before_baseline']:.2f}" if "ratio_before_baseline" in row
                   else "")
                + f", share {100 * old['in_process'][name]['share_wall']:.1f} %"
                for name, row in old["files"].items())
            lines.append(f"- {old['date'][:10]}, now {old.get('now_rev', '?')} (load {old['load'][0]:.1f} to "
                         f"{old['load'][1]:.1f}): {ratios}")
    return "\n".join(lines) + "\n"


def _rev(tree: Path) -> str:
    try:
        return subprocess.run(["git", "-C", str(tree), "rev-parse", "--short", "HEAD"], capture_output=True, text=True,
                              check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return str(tree)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--baseline", type=Path, help="a checkout without the geometry checks (66febab)")
    ap.add_argument("--before", type=Path, help="a checkout with the earlier geometry checks (8749b58)")
    ap.add_argument("--parts", type=int, default=10_000)
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--rate", type=float, default=0.01, help="share of the parts moved in the second file")
    ap.add_argument("--no-doc", action="store_true", help="do not rewrite docs/benchmarks.md")
    ap.add_argument("--render", action="store_true", help="only rewrite the section from the latest results")
    args = ap.parse_args()
    if args.render:
        history = json.loads(RESULTS.read_text())
        write_doc(TITLE, render(history[-1], history[-3:-1]))
        return 0
    if args.baseline is None:
        ap.error("--baseline DIR is needed (git worktree add /tmp/kitkb-66febab 66febab)")
    load0 = os.getloadavg()[0]
    trees = {"baseline": tree_command(args.baseline), "now": tree_command(ROOT)}
    if args.before is not None:
        trees["before"] = tree_command(args.before)
    with tempfile.TemporaryDirectory() as tmp:
        files = data(args.parts, Path(tmp), args.rate)
        measured = measure(files, trees, args.runs)
        inside = {name: in_process(ROOT, path, args.runs) for name, path in files.items()}
        from kb.io.loader import load
        from kb.spatial.survey import survey
        objects = int(survey(load([files["init"]], resolve_imports=False).sources[0]).scene.placed.sum())
    record = {"date": dt.datetime.now().isoformat(timespec="seconds"), "parts": args.parts,
              "kits": max(1, args.parts // 1000), "runs": args.runs, "moved": round(args.parts * args.rate),
              "objects": objects, "baseline_rev": _rev(args.baseline),
              "before_rev": _rev(args.before) if args.before else None, "now_rev": _rev(ROOT),
              "files": measured, "in_process": inside,
              "machine": {"cpu": cpu_model(), "cores": os.cpu_count(), "python": platform.python_version()},
              "load": [round(load0, 2), round(os.getloadavg()[0], 2)]}
    history = json.loads(RESULTS.read_text()) if RESULTS.exists() else []
    RESULTS.write_text(json.dumps(history + [record], indent=1) + "\n")
    print(render(record, history[-2:]))
    if not args.no_doc:
        write_doc(TITLE, render(record, history[-2:]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
