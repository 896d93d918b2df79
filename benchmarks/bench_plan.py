"""Planning benchmark: kitkb's generated encodings against NIST's hand-written numeric one.

For each workstation size it writes a scenario with ``kitkb scenario generate`` (not timed),
then times whole processes, from files to a validated plan file:

* ``kitkb``: ``kitkb plan INIT GOAL -o PLAN`` - load the ontologies and the two state files,
  generate the STRIPS encoding, plan (Fast Downward, chosen from the problem kind), validate
  with unified-planning's plan validator, write the plan;
* ``nist``: ``kitkb plan domain-fluents.pddl PROBLEM -o PLAN --planner enhsp --engine-defaults``
  - NIST's domain with a problem of the same size in NIST's own format
  (``benchmarks/nist_format.py``, same parts, trays and kits), solved by ENHSP with
  unified-planning's default settings (as in the issue's reference figures), validated the
  same way;
* optionally (``--numeric``) ``kitkb plan ... --encoding numeric`` (kitkb's numeric encoding,
  ENHSP with kitkb's settings).

Medians of ``--repeat`` runs (NIST: ``--nist-repeat``); a NIST run that exceeds
``--nist-timeout`` is recorded as such. Measurements accumulate in
``benchmarks/results/plan.json``; each run rewrites the "## Planning" section of
``docs/benchmarks.md`` from it.

    .venv/bin/python benchmarks/bench_plan.py                       # all sizes
    .venv/bin/python benchmarks/bench_plan.py --sizes 10 160 --repeat 5
"""

from __future__ import annotations

import argparse
import datetime as dt
import json
import os
import platform
import re
import resource
import signal
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import common

ROOT = Path(__file__).resolve().parent.parent
RESULTS = ROOT / "benchmarks" / "results" / "plan.json"
DOC = ROOT / "docs" / "benchmarks.md"
NIST_DOMAIN = Path(__file__).resolve().parent.parent.parent / "shared" / "nist" / "domain-fluents.pddl"
if not NIST_DOMAIN.is_file():
    NIST_DOMAIN = Path("/work/shared/nist/domain-fluents.pddl")
PY = sys.executable
#: (label, parts, kits): kits of 10, 40, 160, 640 parts, and 4 kits of 40 parts
CASES = [("10", 10, 1), ("40", 40, 1), ("160", 160, 1), ("640", 640, 1), ("4x40", 160, 4)]


def kitkb(*args: str, timeout: float | None = None) -> tuple[float, float, subprocess.CompletedProcess | None]:
    """Run ``kitkb ARGS`` as a fresh process: (wall s, cpu s incl. children, result or None on timeout)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    env = dict(os.environ, KITKB_TIMING="1")
    # kitkb passes --timeout to the planner; the outer limit (60 s later) is a safety net
    child = subprocess.Popen([PY, "-m", "kb.cli", *args], cwd=ROOT, stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True, env=env)
    try:
        out, err = child.communicate(timeout=None if timeout is None else timeout + 60)
    except subprocess.TimeoutExpired:
        _kill_tree(child.pid)
        child.communicate()
        return time.perf_counter() - start, float("nan"), None
    proc = subprocess.CompletedProcess(child.args, child.returncode, out, err)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu, proc


def _kill_tree(pid: int) -> None:
    """Kill a process and all its descendants (unified-planning starts planners in new sessions)."""
    listing = subprocess.run(["ps", "-eo", "pid=,ppid="], capture_output=True, text=True).stdout
    children: dict[int, list[int]] = {}
    for line in listing.splitlines():
        child, parent = map(int, line.split())
        children.setdefault(parent, []).append(child)
    todo, found = [pid], []
    while todo:
        p = todo.pop()
        found.append(p)
        todo.extend(children.get(p, []))
    for p in reversed(found):
        try:
            os.kill(p, signal.SIGKILL)
        except ProcessLookupError:
            pass


def plan_length(path: Path) -> int:
    return sum(1 for line in path.read_text().splitlines() if line.strip())


def minimum_length(parts: int, kits: int, per_part: int) -> int:
    """Shortest possible plan for the generated workstations.

    The robot starts without an end effector; kit trays and kits need the tray gripper,
    parts the part gripper; one work table holds one kit at a time. Per kit: take and put
    the tray, create the kit, swap to the part gripper (2), swap back (2), take and put the
    kit = 9; plus ``per_part`` actions per part (kitkb: take, put; NIST: look-for, take,
    put) and the first attach.
    """
    return per_part * parts + 9 * kits + 1


def measure(label: str, parts: int, kits: int, args: argparse.Namespace, work: Path, results: dict) -> None:
    sys.path.insert(0, str(ROOT))
    from benchmarks.nist_format import nist_problem

    folder = work / label
    subprocess.run([PY, "-m", "kb.cli", "scenario", "generate", "--parts", str(parts), "--kits", str(kits),
                    "--seed", "0", "-o", str(folder)], cwd=ROOT, check=True, capture_output=True)
    init, goal = folder / "init.ttl", folder / "goal.ttl"
    text, nist_parts, nist_kits = nist_problem(init, goal)
    assert (nist_parts, nist_kits) == (parts, kits), (nist_parts, nist_kits)
    (folder / "nist-problem.pddl").write_text(text)
    runs = [("kitkb", ["plan", str(init), str(goal)], args.repeat, None, 2),
            ("nist", ["plan", str(NIST_DOMAIN), str(folder / "nist-problem.pddl"), "--planner", "enhsp",
                      "--engine-defaults"], args.nist_repeat, args.nist_timeout, 3)]
    runs.append(("nist-tuned", ["plan", str(NIST_DOMAIN), str(folder / "nist-problem.pddl"), "--planner", "enhsp"],
                 args.nist_repeat, args.nist_timeout, 3))
    runs.append(("kitkb-numeric", ["plan", str(init), str(goal), "--encoding", "numeric"],
                 args.nist_repeat, args.nist_timeout, 2))
    for system, cmd, repeat, timeout, per_part in runs:
        if system not in args.systems or (system.startswith("nist") and (
                parts > args.nist_max_parts or (args.nist_sizes is not None and label not in args.nist_sizes))):
            continue
        walls, cpus, length, timing, status = [], [], None, "", "ok"
        for _ in range(repeat):
            out = folder / f"{system}.plan"
            limit = ["--timeout", str(timeout)] if timeout else []
            wall, cpu, proc = kitkb(*cmd, "-o", str(out), *limit, timeout=timeout)
            if proc is None or (proc.returncode == 1 and "TIMEOUT" in proc.stderr):
                status = f"timeout {timeout:.0f} s"
                break
            if proc.returncode != 0:
                status = f"exit {proc.returncode}: {proc.stderr.strip().splitlines()[-1][:120]}"
                break
            walls.append(wall)
            cpus.append(cpu)
            length = plan_length(out)
            timing = next((l for l in proc.stderr.splitlines() if l.startswith("timing:")), "")
        key = f"{label}|{system}"
        results[key] = {
            "label": label, "parts": parts, "kits": kits, "system": system, "status": status,
            "wall_median": statistics.median(walls) if walls else None,
            "cpu_median": statistics.median(cpus) if cpus else None,
            "runs": len(walls), "plan_length": length,
            "minimum_length": minimum_length(parts, kits, per_part), "timing": timing,
            "load_before": os.getloadavg()[0], "date": dt.datetime.now(dt.timezone.utc).isoformat(timespec="seconds"),
            "run": args.run, "cpu": common.cpu_model(),
        }
        print(json.dumps(results[key]), flush=True)
        save(results)



def save(results: dict) -> None:
    RESULTS.parent.mkdir(parents=True, exist_ok=True)
    RESULTS.write_text(json.dumps(results, indent=1, sort_keys=True) + "\n")


def fmt(value: float | None) -> str:
    return "-" if value is None else f"{value:.2f}"


def _cell(entry: dict | None, latest: str = "") -> str:
    if entry is None:
        return "not run"
    earlier = (f" ({entry['date'][:10]}, earlier run, {entry.get('cpu', 'AMD EPYC')})"
               if latest and entry.get("run") != latest else "")
    if entry["wall_median"] is None:
        return entry["status"] + earlier
    return f"{fmt(entry['wall_median'])} ({fmt(entry['cpu_median'])}){earlier}"


def _length(entry: dict | None) -> str:
    return f"{entry['plan_length']} / {entry['minimum_length']}" if entry and entry["plan_length"] else "-"


def _speedup(ours: dict, other: dict | None) -> str:
    if other and other["wall_median"] and ours["wall_median"]:
        return f"{other['wall_median'] / ours['wall_median']:.1f}x"
    if other and other["status"].startswith("timeout"):
        return f"> {float(other['status'].split()[1]) / ours['wall_median']:.0f}x"
    return "-"


def section(results: dict) -> str:
    rows = []
    latest = max((r.get("run", "") for r in results.values() if r["system"] == "kitkb"), default="")
    for label, parts, kits in CASES:
        ours = results.get(f"{label}|kitkb")
        if ours is None:
            continue
        nist, tuned, num = (results.get(f"{label}|{k}") for k in ("nist", "nist-tuned", "kitkb-numeric"))
        rows.append(f"| {label} | {parts} | {kits} | {_cell(ours, latest)} | {_length(ours)} | {_cell(nist, latest)} | "
                    f"{_length(nist)} | {_speedup(ours, nist)} | {_cell(tuned, latest)} | {_cell(num, latest)} |")
    summary = []
    ours160, nist160, tuned160 = (results.get(f"160|{k}") for k in ("kitkb", "nist", "nist-tuned"))
    if ours160 and nist160 and nist160["wall_median"]:
        summary.append(f"At 160 parts kitkb is {_speedup(ours160, nist160)} faster than NIST's encoding with "
                       f"ENHSP as unified-planning runs it" + (f", and {_speedup(ours160, tuned160)} faster than "
                       "NIST's encoding with ENHSP under kitkb's ENHSP settings" if tuned160 and tuned160["wall_median"]
                       else "") + ".")
    ours640 = results.get("640|kitkb")
    if ours640 and ours640["wall_median"]:
        summary.append(f"640 parts take {fmt(ours640['wall_median'])} s end to end "
                       f"({'within' if ours640['wall_median'] < 5 else 'above'} the 5 s aim).")
    growth = [results.get(f"{n}|kitkb") for n in ("10", "40", "160", "640")]
    if all(g and g["cpu_median"] for g in growth):
        summary.append("CPU time per 4x more parts: " + ", ".join(
            f"x{b['cpu_median'] / a['cpu_median']:.1f}" for a, b in zip(growth, growth[1:]))
            + " (start-up, about 1 s of CPU, dominates small kits; from 160 to 640 parts the planner and "
            "the validator grow about linearly).")
    timings = [f"- {label}: {results[f'{label}|kitkb']['timing'].removeprefix('timing: ')}"
               for label, _p, _k in CASES if results.get(f"{label}|kitkb", {}).get("timing")]
    loads = sorted(r["load_before"] for r in results.values() if r.get("run") == latest) or [float("nan")]
    day = latest[:16].replace("T", " ") + " UTC" if latest else "?"
    return f"""## Planning

Command: `.venv/bin/python benchmarks/bench_plan.py` (raw figures in `benchmarks/results/plan.json`;
`--systems nist-tuned kitkb-numeric` adds the last two columns).
Whole processes, from files to a validated plan file: `kitkb plan INIT GOAL -o PLAN` (ontologies and
state files -> generated STRIPS encoding -> Fast Downward -> unified-planning's plan validator -> plan)
against NIST's hand-written numeric domain `domain-fluents.pddl` with a problem of the same size in
NIST's own format (`benchmarks/nist_format.py`: same parts, trays, kits) solved by ENHSP with
unified-planning's default settings, through `kitkb plan DOMAIN PROBLEM --planner enhsp
--engine-defaults` (unified-planning's PDDL reader, same validator). Workstations from
`kitkb scenario generate --parts N --kits K --seed 0`. Median wall time in seconds, CPU time
(process + child processes: file reader, planner) in brackets; medians of 3 runs (others: 1 run);
cells marked "earlier run" were not re-run in the latest run (their date is given). Extra columns:
NIST's encoding with ENHSP under kitkb's ENHSP settings (`-planner sat-hmrphj`), and kitkb's own
numeric encoding (`--encoding numeric`, ENHSP with kitkb's settings).

Machine of the latest run: {common.cpu_model()}, {os.cpu_count()} cores, Python {platform.python_version()} (an earlier
run names its CPU: compare figures of one CPU);
latest run {day}, shared with other jobs (1-minute load average {loads[0]:.1f} to {loads[-1]:.1f} on 2 cores when runs started):
wall times are pessimistic and noisy, CPU times are the steadier measure.

| kit | parts | kits | kitkb: s (cpu) | kitkb length / min | NIST + ENHSP: s (cpu) | NIST length / min | speed-up (wall) | NIST + ENHSP, kitkb settings | kitkb numeric + ENHSP |
|---|---|---|---|---|---|---|---|---|---|
""" + "\n".join(rows) + "\n\n" + " ".join(summary) + """

Minimum lengths: the robot starts without an end effector and one work table holds one kit at a
time, so a plan needs per kit 9 actions (tray in, kit made, two gripper swaps each way, kit out),
plus the first attach, plus 2 actions per part in kitkb's domain (take-part, put-part) and 3 in
NIST's (look-for-part is forced before every take-part by its `part-not-searched` flag).

Why the generated encoding plans faster than NIST's: (1) it is classical STRIPS - the only
numeric pattern of the SOAP domain, "count < capacity, then count + 1" on `quantity-kit`, is
compiled into tokens: the parts that will fill a kit are named up front (parts of one SKU are
interchangeable), so `put-part` is grounded once per part instead of per part x kit x tray, and
Fast Downward's heuristic sees each missing part as a goal; (2) no `part-not-searched` flag and
`look-for-part` is optional, so a part costs 2 actions instead of 3 and the search has no forced
detours; (3) Fast Downward runs lazy greedy best-first search with one FF heuristic that also gives
the preferred operators (`let(h,ff(),lazy_greedy([h],preferred=[h]))`; writing `[ff()],
preferred=[ff()]` builds two heuristics and evaluates every state twice, which cost 40% of the
search), with the translator's invariant synthesis and variable reordering switched off (they cost
seconds on large kits here and the search does not need them). Start-up is kept lean:
unified-planning is imported only by commands that plan, and its engines package is loaded without
ConfigSpace/scipy (`generators/pddl/up_env.py`); `kitkb plan` reads the ontology and state files in
a forked child process while the parent imports unified-planning (2 cores), and falls back to
reading in-process if the child fails, so errors are reported the same way.

Where kitkb's time goes (one run each; `KITKB_TIMING=1` prints it; wall seconds, then CPU of
the kitkb process and of its child processes, the file reader and the planner):
""" + "\n".join(timings) + """

At 640 parts, the latest round of work measured A/B (HEAD before it against the working tree,
interleaved, 3 runs each, `kitkb plan`, 2026-11-21 15:55 UTC, load average 1.9-2.0): before 5.68 s
wall (5.69 s CPU), after 4.30 s wall (4.30 s CPU), the same 1,290-step plan; more runs at that
load: 4.26-4.76 s wall. Wall times swing by 40% with the other jobs on the machine (the table's
640-part run started at load 2.6). CPU seconds per phase at 640 parts, one run each, before ->
after: start-up and imports 0.5 s (now hidden behind reading, which a forked child does in
parallel), reading the ontologies and state files about 1 s (unchanged; `kb/loader.py` builds
rdflib graphs), building and writing the PDDL 0.45 s, Fast Downward 2.0 -> 1.35 s (search 1.1 ->
0.65 s; translator 0.8 s), unified-planning's plan validator 2.9 -> 1.3 s, interpreter exit about
0.3 s. The validator is unified-planning's `SequentialPlanValidator` on the same problem and plan;
`kb.planning` speeds up three of its internals without changing what it checks: the parameter
map is promoted once per action instead of once per precondition and effect, ground literals
(`f(o1, o2)`, `not f(o)`) are substituted and evaluated with the same expression-manager calls the
generic walkers make (hash-consed, so the results are identical nodes; tests compare them with
the walkers' results and check that broken plans are rejected), and `UPState.MAX_ANCESTORS` is
raised so the 5,000-fact state is flattened less often.
"""


def write_doc(results: dict) -> None:
    text = DOC.read_text(encoding="utf-8") if DOC.exists() else "# Benchmarks\n\n## Validation\n\n"
    new = section(results)
    match = re.search(r"^## Planning\n.*?(?=^## |\Z)", text, flags=re.M | re.S)
    text = text[:match.start()] + new + "\n" + text[match.end():] if match else text.rstrip("\n") + "\n\n" + new
    DOC.write_text(text.rstrip("\n") + "\n", encoding="utf-8")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", nargs="*", default=[c[0] for c in CASES], help="labels: 10 40 160 640 4x40")
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--nist-repeat", type=int, default=1)
    parser.add_argument("--nist-timeout", type=float, default=900.0)
    parser.add_argument("--nist-max-parts", type=int, default=10**9, help="skip NIST above this many parts")
    parser.add_argument("--nist-sizes", nargs="*", default=None,
                        help="labels on which to run NIST's encoding (default: all of --sizes)")
    parser.add_argument("--numeric", action="store_true", help="also time kitkb's numeric encoding (ENHSP)")
    parser.add_argument("--systems", nargs="*", default=None,
                        help="which to run: kitkb nist nist-tuned kitkb-numeric (default: kitkb nist, "
                             "plus kitkb-numeric with --numeric)")
    parser.add_argument("--doc-only", action="store_true", help="only rewrite docs/benchmarks.md from the results")
    args = parser.parse_args()
    if args.systems is None:
        args.systems = ["kitkb", "nist"] + (["kitkb-numeric"] if args.numeric else [])
    results = json.loads(RESULTS.read_text()) if RESULTS.exists() else {}
    args.run = dt.datetime.now(dt.timezone.utc).isoformat(timespec="seconds")
    if not args.doc_only:
        with tempfile.TemporaryDirectory(prefix="kitkb-bench-plan-") as tmp:
            for label, parts, kits in CASES:
                if label in args.sizes:
                    measure(label, parts, kits, args, Path(tmp), results)
    write_doc(results)
    print(f"wrote {DOC.relative_to(ROOT)} (## Planning)")


if __name__ == "__main__":
    main()
