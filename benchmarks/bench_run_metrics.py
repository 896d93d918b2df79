"""What a run's execution metrics and kit scores cost ``kitkb run`` (issue 18: under 5 %).

``kitkb run INIT GOAL`` on ``kitkb scenario generate --parts N --kits 1 --seed S`` (validate,
plan, geometry, world model on SQLite, execution with verification), in this process through
the CLI's own function, ``--repeat`` times. Every function that exists for the metrics and the
scores is wrapped with a timer that counts only its outermost call:

* ``crcl_lines``: the CRCL text of each program sent, kept per action;
* ``kit_goals`` and ``score_kits``: the goal's kits and their scores at the end;
* ``scene_data``: the objects as a report page draws them;
* ``RunRecord.report``: the JSON report with the metrics (the CRCL read back and measured), the
  path and the timeline — called by the store at the end and by the CLI;
* ``RunStore.end_run``: the report and the kit rows written to the database.

The figure is their time over the whole run's, each run; medians. (The rows the store writes
per action carry the CRCL too; that JSON is inside ``record_action`` and is not separated.)

    .venv/bin/python benchmarks/bench_run_metrics.py                 # 160 parts, 3 runs
    .venv/bin/python benchmarks/bench_run_metrics.py --parts 40 --repeat 2 --no-doc

Results are appended to ``benchmarks/results/run_metrics.json``; the run rewrites the
"## Run metrics and kit scores" section of ``docs/benchmarks.md``.
"""

from __future__ import annotations

import argparse
import datetime as dt
import functools
import io
import json
import os
import platform
import statistics
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from common import ROOT, cpu_model, write_doc  # noqa: E402

RESULTS = ROOT / "benchmarks" / "results" / "run_metrics.json"
TITLE = "Run metrics and kit scores"


class Timers:
    """Seconds spent in wrapped functions, outermost calls only."""

    def __init__(self) -> None:
        self.seconds: dict[str, float] = {}
        self.depth = 0

    def wrap(self, owner: object, attribute: str, label: str) -> None:
        original = getattr(owner, attribute)

        @functools.wraps(original)
        def timed(*args, **kwargs):  # noqa: ANN002, ANN003, ANN202
            if self.depth:
                return original(*args, **kwargs)
            self.depth += 1
            t = time.perf_counter()
            try:
                return original(*args, **kwargs)
            finally:
                self.depth -= 1
                self.seconds[label] = self.seconds.get(label, 0.0) + time.perf_counter() - t

        setattr(owner, attribute, timed)


def measure(parts: int, seed: int, repeat: int) -> dict:
    from kb.cli.pipeline import RunOptions, run_files
    from kb.execution import executor, records, scoring, store
    from kb.scenario import write_scenario

    timers = Timers()
    timers.wrap(executor, "crcl_lines", "crcl_lines")
    timers.wrap(executor, "kit_goals", "kit_goals + score_kits")
    timers.wrap(executor, "score_kits", "kit_goals + score_kits")
    timers.wrap(executor, "scene_data", "scene_data")
    timers.wrap(records.RunRecord, "report", "report (metrics, path, timeline)")
    timers.wrap(store.RunStore, "end_run", "end_run (report, kit rows)")
    assert scoring  # the module the wrapped names come from
    runs = []
    with tempfile.TemporaryDirectory(prefix="kitkb-bench-run-metrics-") as tmp:
        scenario = Path(tmp) / "scenario"
        write_scenario(scenario, parts=parts, kits=1, seed=seed)
        for r in range(repeat):
            timers.seconds = {}
            out = Path(tmp) / f"out{r}"
            t = time.perf_counter()
            code = run_files(io.StringIO(), scenario / "init.ttl", scenario / "goal.ttl", out, RunOptions(),
                             str(Path(tmp) / f"report{r}.json"), quiet=True)
            total = time.perf_counter() - t
            report = json.loads((Path(tmp) / f"report{r}.json").read_text())
            added = sum(timers.seconds.values())
            runs.append({"total_s": total, "added_s": added, "share": added / total, "exit": code,
                         "actions": report["actions"], "kits": report["kits"],
                         "parts": dict(sorted(timers.seconds.items()))})
            print(f"run {r}: {total:.2f} s, metrics and scores {added * 1000:.0f} ms ({100 * added / total:.2f} %), "
                  f"exit {code}, {report['actions']} actions", flush=True)
    return {"parts": parts, "seed": seed, "runs": runs,
            "median_share": statistics.median(r["share"] for r in runs),
            "median_total_s": statistics.median(r["total_s"] for r in runs),
            "median_added_s": statistics.median(r["added_s"] for r in runs)}


def section(result: dict) -> str:
    lines = [f"## {TITLE}", "",
             "`benchmarks/bench_run_metrics.py`: `kitkb run` on a generated "
             f"{result['parts']}-part kit (seed {result['seed']}), in process, "
             f"{len(result['runs'])} runs; the time of every function that exists for the execution metrics, "
             "kit scores and the report's scene, path and timeline (outermost calls), over the whole run's. "
             f"Machine: {result['machine']}, {result['date']}.", "",
             "| | median |", "|---|---|",
             f"| whole run | {result['median_total_s']:.2f} s |",
             f"| metrics, scores, report data | {result['median_added_s'] * 1000:.0f} ms |",
             f"| share of the run | **{100 * result['median_share']:.2f} %** (goal: under 5 %) |", "",
             "Per part (last run): " + ", ".join(f"{k} {v * 1000:.0f} ms" for k, v in result["runs"][-1]["parts"].items())
             + ".", ""]
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--parts", type=int, default=160)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--no-doc", action="store_true", help="do not rewrite docs/benchmarks.md")
    args = parser.parse_args()
    result = measure(args.parts, args.seed, args.repeat)
    result.update(date=dt.date.today().isoformat(), machine=f"{cpu_model()}, {os.cpu_count()} cores, "
                  f"Python {platform.python_version()}, load {os.getloadavg()[0]:.1f}")
    RESULTS.parent.mkdir(exist_ok=True)
    history = json.loads(RESULTS.read_text()) if RESULTS.exists() else []
    RESULTS.write_text(json.dumps(history + [result], indent=1) + "\n")
    print(f"median share {100 * result['median_share']:.2f} % of {result['median_total_s']:.2f} s")
    if not args.no_doc:
        write_doc(TITLE, section(result))


if __name__ == "__main__":
    main()
