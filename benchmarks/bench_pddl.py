"""Reading PDDL files: kitkb's reader (kb/planning/pddl/) beside the one of a baseline checkout.

Since issue 26 (point 8) ``kitkb plan DOMAIN PROBLEM`` reads the files itself, rewrites what
unified-planning's reader cannot take and then has that reader read the result; before, the
files went to unified-planning's reader as they were. This measures what the extra pass
costs on big files — a generated 640-part kitting problem (kitkb's STRIPS encoding) and the
same workstation in NIST's numeric format — by reading each with the baseline's
``kb/planning/pddl_files.py`` (``git show BASELINE:...``) and with this checkout's, taking
turns in one process, medians of ``--repeat`` reads; and how long kitkb's own pass takes
(everything before unified-planning's reader). It also lists which of the test domains in
tests/data/pddl_classic/ each reader reads.

    .venv/bin/python benchmarks/bench_pddl.py --baseline f6522b9 --repeat 5

Results go to benchmarks/results/pddl.json and the "Reading PDDL files" section of
docs/benchmarks.md.
"""

from __future__ import annotations

import argparse
import datetime as dt
import importlib.util
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from unittest import mock

import common

ROOT = common.ROOT
RESULTS = ROOT / "benchmarks" / "results" / "pddl.json"
DATA = ROOT / "tests" / "data" / "pddl_classic"
NIST_DOMAIN = ROOT.parent / "shared" / "nist" / "domain-fluents.pddl"
sys.path.insert(0, str(ROOT))


def baseline_reader(commit: str):  # noqa: ANN201 - a module
    """The ``read_pddl`` of ``commit`` (its kb/planning/pddl_files.py, loaded on its own)."""
    text = subprocess.run(["git", "show", f"{commit}:kb/planning/pddl_files.py"], cwd=ROOT, check=True,
                          capture_output=True, text=True).stdout
    path = Path(tempfile.mkdtemp()) / "baseline_pddl_files.py"
    path.write_text(text)
    spec = importlib.util.spec_from_file_location("baseline_pddl_files", path)
    module = importlib.util.module_from_spec(spec)
    assert spec.loader is not None
    spec.loader.exec_module(module)
    return module


def make_inputs(folder: Path, parts: int) -> list[tuple[str, Path, Path]]:
    """A generated workstation's PDDL (kitkb's STRIPS encoding) and its NIST-format problem."""
    kitkb = [sys.executable, "-m", "kb.cli", "-q"]
    subprocess.run([*kitkb, "scenario", "generate", "--parts", str(parts), "--kits", "1", "--seed", "7",
                    "-o", str(folder / "s")], check=True, cwd=ROOT)
    subprocess.run([*kitkb, "generate", "pddl", str(folder / "s" / "init.ttl"), str(folder / "s" / "goal.ttl"),
                    "-o", str(folder / "g")], check=True, cwd=ROOT)
    cases = [(f"generated, {parts} parts (STRIPS)", folder / "g" / "domain.pddl", folder / "g" / "problem.pddl")]
    if NIST_DOMAIN.is_file():
        subprocess.run([sys.executable, str(ROOT / "benchmarks" / "nist_format.py"), str(folder / "s" / "init.ttl"),
                        str(folder / "s" / "goal.ttl"), "-o", str(folder / "nist.pddl")], check=True, cwd=ROOT,
                       capture_output=True)
        cases.append((f"NIST format, {parts} parts (numeric)", NIST_DOMAIN, folder / "nist.pddl"))
    return cases


def timed(fn) -> float:  # noqa: ANN001
    start = time.perf_counter()
    fn()
    return time.perf_counter() - start


def measure(cases: list[tuple[str, Path, Path]], old, repeat: int) -> list[dict]:  # noqa: ANN001
    from kb.planning.pddl import task

    quiet = lambda message: None  # noqa: E731
    rows = []
    for label, domain, problem in cases:
        times: dict[str, list[float]] = {"baseline": [], "now": [], "kitkb pass": []}
        for _ in range(repeat):  # taking turns, so a busy moment hits both
            times["baseline"].append(timed(lambda: old.read_pddl(domain, problem, quiet)))
            times["now"].append(timed(lambda: task.read_task(domain, problem, quiet)))
            with mock.patch.object(task, "_up_read", lambda *a: None), \
                    mock.patch("kb.planning.pddl.costs.Costs.install", lambda *a: None), \
                    mock.patch("kb.planning.pddl.axioms.install", lambda *a: None):
                times["kitkb pass"].append(timed(lambda: task.read_task(domain, problem, quiet)))
        med = {k: statistics.median(v) for k, v in times.items()}
        rows.append({"case": label, "bytes": problem.stat().st_size, **{k: round(v, 3) for k, v in med.items()},
                     "ratio": round(med["now"] / med["baseline"], 3),
                     "pass share": round(med["kitkb pass"] / med["now"], 4)})
        print(rows[-1], flush=True)
    return rows


def shapes(old) -> list[dict]:  # noqa: ANN001
    """Which reader reads each test domain (the planner is not run)."""
    from kb.planning.pddl import task

    out = []
    for domain in sorted(DATA.glob("*-domain.pddl")):
        name = domain.name.removesuffix("-domain.pddl")
        problem = DATA / f"{name}-problem.pddl"
        row = {"domain": name}
        for key, read in (("baseline", lambda: old.read_pddl(domain, problem, lambda m: None)),
                          ("now", lambda: task.read_task(domain, problem, lambda m: None))):
            try:
                read()
                row[key] = "read"
            except Exception as exc:  # noqa: BLE001 - what the reader says is the result
                row[key] = str(exc).split(": error: ", 1)[-1][:90]
        out.append(row)
    return out


def render(run: dict) -> str:
    lines = ["## Reading PDDL files", "",
             f"`benchmarks/bench_pddl.py` ({run['date']}, {run['machine']}, load average {run['load']}): "
             f"reading a domain and problem with this checkout's reader and with {run['baseline']}'s "
             f"(unified-planning's reader on the files as they are), taking turns in one process, medians of "
             f"{run['repeat']} reads; \"kitkb pass\" is the part before unified-planning's reader.", "",
             "| files | problem size | baseline | now | now / baseline | kitkb pass | share of now |",
             "|---|---|---|---|---|---|---|"]
    for r in run["rows"]:
        lines.append(f"| {r['case']} | {r['bytes'] / 1000:.0f} kB | {r['baseline']:.2f} s | {r['now']:.2f} s | "
                     f"{r['ratio']:.2f} | {r['kitkb pass']:.3f} s | {100 * r['pass share']:.1f} % |")
    lines += ["", "The test domains (tests/data/pddl_classic/), read by each (planning is "
              "tests/test_pddl_classic.py's; the baseline read the cost domains, planned them, and "
              "then refused its plan: the validator does not take undefined numeric values):", "",
              "| domain | baseline | now |", "|---|---|---|"]
    lines += [f"| {s['domain']} | {s['baseline']} | {s['now']} |" for s in run["shapes"]]
    return "\n".join(lines) + "\n"


def rewrite_doc() -> None:
    """The docs/benchmarks.md section again from benchmarks/results/pddl.json (no new run)."""
    common.write_doc("Reading PDDL files", render(json.loads(RESULTS.read_text())))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--baseline", default="f6522b9", help="the checkout to compare with (a commit)")
    parser.add_argument("--parts", type=int, default=640)
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--doc-only", action="store_true", help="rewrite the doc section from the results file")
    args = parser.parse_args()
    if args.doc_only:
        rewrite_doc()
        return
    old = baseline_reader(args.baseline)
    with tempfile.TemporaryDirectory() as work:
        rows = measure(make_inputs(Path(work), args.parts), old, args.repeat)
    run = {"date": dt.date.today().isoformat(), "machine": f"{common.cpu_model()}, {os.cpu_count()} cores",
           "load": f"{os.getloadavg()[0]:.1f}", "baseline": args.baseline, "repeat": args.repeat, "rows": rows,
           "shapes": shapes(old)}
    RESULTS.write_text(json.dumps(run, indent=1) + "\n")
    common.write_doc("Reading PDDL files", render(run))


if __name__ == "__main__":
    main()
