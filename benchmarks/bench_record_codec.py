"""Run records with one dict form (issue 27, point 7): what storing and reading a run costs,
beside the commit before the work, and what checking every record field costs the executor.

    git worktree add /tmp/kitkb-before 472f1d7
    .venv/bin/python benchmarks/bench_record_codec.py --before /tmp/kitkb-before [--rounds 5]

Data: ``kb.scenario.write_scenario(parts=160, kits=4, seed=0)``, planned once (strips), run
with faults ``missed-grasp=0.05,part-missing=0.05`` and sensor noise
``position=1mm,orientation=0.5deg,misdetection=0.01`` (seed 1) into a new SQLite file (and
PostgreSQL with ``KITKB_PG_URL``). Each checkout runs in a process of its own (its tree first
on ``PYTHONPATH``), the two taking turns, ``--rounds`` times:

* **store**: the seconds the run store spends in ``begin_run``, ``record_action``,
  ``record_failure`` and ``end_run`` during the run (the records written; the stable states,
  which this work did not change, are not counted);
* **open_run**: reading the run back (median of 3 in each process);
* **lost**: the fields of the run read back that differ from the run in memory.

In the current checkout only: the run's record to JSON text through its dict form and back
(median of 5), and the same run in memory with and without the fields checked when they are set
(``Record.__setattr__`` replaced by ``object.__setattr__``), 5 turns each, taking turns: the
executor's cost of refusing what a record cannot hold.

Writes ``results/record_codec.json`` and the section "Run records: one dict form" of
docs/benchmarks.md.
"""

from __future__ import annotations

import argparse
import datetime as dt
import json
import os
import platform
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "benchmarks"))
import common  # noqa: E402

TITLE = "Run records: one dict form"
FAULTS = "missed-grasp=0.05,part-missing=0.05"
NOISE = "position=1mm,orientation=0.5deg,misdetection=0.01"

_CHILD = r'''
import dataclasses, json, statistics, sys, tempfile, time
from pathlib import Path
init, goal, plan_file, db, mode = sys.argv[1:6]
plan = Path(plan_file).read_text().splitlines()
from kb.execution import open_run, run_plan
from kb.execution import store as S
spent = {"s": 0.0}
def timed(fn):
    def wrapper(*a, **kw):
        t = time.perf_counter()
        try:
            return fn(*a, **kw)
        finally:
            spent["s"] += time.perf_counter() - t
    return wrapper
quiet = lambda *a: None
if mode == "memory":
    from kb.execution.codec import Record
    checking = Record.__dict__["__setattr__"]
    out = {}
    for turn in range(10):
        checked = turn % 2 == 0
        Record.__setattr__ = checking if checked else object.__setattr__
        t = time.perf_counter()
        run_plan(plan, init, goal, faults=FAULTS, seed=1, notifier=quiet, sensor_noise=NOISE)
        out.setdefault("checked" if checked else "unchecked", []).append(time.perf_counter() - t)
    Record.__setattr__ = checking
    print(json.dumps(out))
    sys.exit(0)
for name in ("begin_run", "record_action", "record_failure", "end_run"):
    setattr(S.RunStore, name, timed(getattr(S.RunStore, name)))
run = run_plan(plan, init, goal, faults=FAULTS, seed=1, notifier=quiet, sensor_noise=NOISE, db=db)
reads = []
for _ in range(3):
    t = time.perf_counter()
    back = open_run(db)
    reads.append(time.perf_counter() - t)
lost = set()
def cmp(a, b, path):
    if dataclasses.is_dataclass(a):
        for f in dataclasses.fields(a):
            cmp(getattr(a, f.name), getattr(b, f.name), f"{path}.{f.name}")
    elif isinstance(a, (list, tuple)) and type(a) is type(b) and len(a) == len(b):
        for x, y in zip(a, b):
            cmp(x, y, path + "[]")
    elif a != b or type(a) is not type(b):
        lost.add(path)
cmp(run.record, back.record, "run")
r = run.record
codec = {}
try:
    from kb.execution.codec import dumps, loads
except ImportError:  # the checkout before: no dict form
    pass
else:
    enc, dec = [], []
    for _ in range(5):
        t = time.perf_counter()
        text = dumps(r.to_dict())
        enc.append(time.perf_counter() - t)
        t = time.perf_counter()
        type(r).from_dict(loads(text))
        dec.append(time.perf_counter() - t)
    codec = {"encode": statistics.median(enc), "decode": statistics.median(dec), "bytes": len(text)}
print(json.dumps({"codec": codec, "store": spent["s"], "open_run": statistics.median(reads), "lost": sorted(lost),
                  "actions": len(r.actions), "checks": len(r.checks), "failures": len(r.failures)}))
'''


def child(checkout: Path, init: Path, goal: Path, plan: Path, db: str, mode: str) -> dict:
    env = dict(os.environ, PYTHONPATH=str(checkout))
    code = f"FAULTS, NOISE = {FAULTS!r}, {NOISE!r}\n" + _CHILD
    out = subprocess.run([sys.executable, "-c", code, str(init), str(goal), str(plan), db, mode], env=env,
                         cwd=checkout, capture_output=True, text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--before", type=Path, required=True, help="a checkout of the commit before the work")
    ap.add_argument("--rounds", type=int, default=5)
    args = ap.parse_args()
    sys.path.insert(0, str(ROOT))
    from kb import planning
    from kb.scenario import write_scenario
    from kb import world
    work = Path(tempfile.mkdtemp(prefix="bench-records-"))
    init, goal = write_scenario(work, parts=160, kits=4, seed=0)
    plan = work / "plan.txt"
    plan.write_text("\n".join(planning.run(planning.kitting_model([init], [goal], "strips").up_problem, None).lines))
    sides = {"before": args.before.resolve(), "after": ROOT}
    pg = os.environ.get("KITKB_PG_URL")
    results: dict = {"sqlite": {k: [] for k in sides}, **({"postgresql": {k: [] for k in sides}} if pg else {})}
    for i in range(args.rounds):
        for side in (("before", "after") if i % 2 == 0 else ("after", "before")):
            db = str(work / f"{side}-{i}.sqlite")
            results["sqlite"][side].append(child(sides[side], init, goal, plan, db, "db"))
            if pg:
                world.drop_all(pg)
                results["postgresql"][side].append(child(sides[side], init, goal, plan, pg, "db"))
                world.drop_all(pg)
        print(f"round {i + 1} of {args.rounds}", file=sys.stderr)
    memory = child(ROOT, init, goal, plan, "", "memory")
    result = {"date": dt.datetime.now(dt.timezone.utc).isoformat(timespec="seconds"), "cpu": common.cpu_model(),
              "cores": os.cpu_count(), "python": platform.python_version(), "rounds": args.rounds,
              "before": str(args.before), "databases": results, "memory": memory}
    (ROOT / "benchmarks" / "results").mkdir(exist_ok=True)
    (ROOT / "benchmarks" / "results" / "record_codec.json").write_text(json.dumps(result, indent=1))
    common.write_doc(TITLE, section(result))
    print(section(result))


def section(r: dict) -> str:
    med = statistics.median
    lines = [f"## {TITLE}", "",
             f"`benchmarks/bench_record_codec.py --before <checkout of 472f1d7>` ({r['date']}, {r['cpu']}, "
             f"{r['cores']} cores shared with other work, Python {r['python']}; {r['rounds']} rounds, the two "
             f"checkouts taking turns; medians). A generated 160-part, 4-kit scenario run with faults "
             f"`{FAULTS}` and sensor noise `{NOISE}` (seed 1) into a new database.", "",
             "| database | checkout | actions | checks | failures | store (s) | open_run (s) | fields lost on reading back |",
             "|---|---|---:|---:|---:|---:|---:|---|"]
    for name, sides in r["databases"].items():
        for side, runs in sides.items():
            lost = sorted({x for run in runs for x in run["lost"]})
            lines.append(f"| {name} | {side} | {runs[0]['actions']} | {runs[0]['checks']} | {runs[0]['failures']} | "
                         f"{med(x['store'] for x in runs):.3f} | {med(x['open_run'] for x in runs):.3f} | "
                         f"{', '.join(f'`{x}`' for x in lost) or 'none'} |")
        b, a = (med(x["store"] for x in sides[s]) for s in ("before", "after"))
        rb, ra = (med(x["open_run"] for x in sides[s]) for s in ("before", "after"))
        lines.append(f"| {name} | after / before | | | | {a / b:.2f}x | {ra / rb:.2f}x | |")
    m = r["memory"]
    c, u = med(m["checked"]), med(m["unchecked"])
    codec = r["databases"]["sqlite"]["after"][0]["codec"]
    lines += ["", f"The run's record (every field, {codec['bytes']:,} bytes of JSON) through its dict form: "
                  f"{codec['encode'] * 1000:.0f} ms to JSON text, {codec['decode'] * 1000:.0f} ms back "
                  f"(checked as it is decoded). The store's time is mostly one transaction per action "
                  f"and failure (as before); reading back now decodes every check the run made.",
              "", f"The same run in memory (no database), current checkout, 5 turns each: "
                  f"{c:.2f} s with every record field checked when it is set, {u:.2f} s without "
                  f"({(c / u - 1) * 100:+.1f} %).", ""]
    return "\n".join(lines)


if __name__ == "__main__":
    main()
