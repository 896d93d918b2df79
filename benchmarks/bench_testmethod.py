"""Test method campaigns on Dask: where a trial's time goes, trials per second with 1 and 2
workers, and 1,000 trials of a 10-part basic kit.

Three parts:

* ``profile``: ``--profile-trials`` trials of the basic method (``--parts``, default 10) run in
  this process after a first one (which plans and imports), under cProfile; the seconds per
  trial by stage: the real placement (trays drawn, its scene), the executor's own work, the
  simulated cell (robot, sensor, contact sweeps), the report (metrics, kit scores);
* ``scaling``: ``kitkb testmethod basic --parts 10 --trials N`` (``--trials``, default 60) on a
  LocalCluster of 1 worker and of 2 (``kb.testmethod.run_campaign`` in this process, each
  campaign in a fresh folder and with a fresh cluster), ``--repeat`` pairs (default 3, which
  of the two goes first alternating), medians; trials per second over the whole
  campaign (cluster start, imports and each worker's plan included) and over the steady part
  (from the first trial's row to the last); the ratio of the two workers' rate to the one
  worker's; and whether the rows are the same (``kb.testmethod.comparable``: timings left out);
* ``thousand``: ``kitkb testmethod basic --parts 10 --trials 1000 --workers 2`` as a whole
  process (``--thousand N`` changes the count), its wall time;
* ``ab`` (with ``--before DIR``, a checkout of an earlier revision): the CPU seconds of a
  basic trial (``--ab-trials`` trials after a first, in one process) with this checkout and
  with DIR, taking turns (``--ab-rounds`` each, the order alternating), medians; and whether
  the two give the same trial reports (``kb.testmethod.comparable``: timings left out).

    .venv/bin/python benchmarks/bench_testmethod.py                       # the first three
    .venv/bin/python benchmarks/bench_testmethod.py --parts-of-run ab --before /tmp/kitkb-before --no-doc
    .venv/bin/python benchmarks/bench_testmethod.py --parts-of-run scaling --trials 40 --no-doc
    .venv/bin/python benchmarks/bench_testmethod.py --render              # the doc from the latest results

Results are appended to ``benchmarks/results/testmethod.json``; the run rewrites the
"## Test method campaigns" section of ``docs/benchmarks.md``. The machine is shared: each part
records the 1-minute load average when it started.
"""

from __future__ import annotations

import argparse
import cProfile
import datetime as dt
import json
import os
import pstats
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

import common  # noqa: E402

from kb.testmethod import Options, comparable, jobs, run_campaign  # noqa: E402

SECTION = "Test method campaigns"
RESULTS = ROOT / "benchmarks" / "results" / "testmethod.json"
KITKB = [sys.executable, "-m", "kb.cli"]  # the kb/ on sys.path (PYTHONPATH: a checkout exported elsewhere)


def load() -> float:
    return round(os.getloadavg()[0], 2)


# --- profile ---------------------------------------------------------------------------------

class _TimedCell:
    """Sums the seconds spent in the simulated cell (every call the executor makes to it)."""

    def __init__(self, cell: Any) -> None:
        self.cell, self.seconds = cell, 0.0

    def __getattr__(self, name: str) -> Any:
        attr = getattr(self.cell, name)
        if not callable(attr):
            return attr

        def timed(*a: Any, **kw: Any) -> Any:
            t = time.perf_counter()
            try:
                return attr(*a, **kw)
            finally:
                self.seconds += time.perf_counter() - t
        return timed


def profile(parts: int, trials: int) -> dict[str, Any]:
    """Seconds per trial by stage, timed directly: the real placement and its scene, the
    simulated cell (every call into it), the executor (the rest of the run), the report; then
    the same trials under cProfile for the functions that take the most time of their own."""
    from kb.scenario.placement import place_trays
    from kb.sim import SimulatedCell
    from kb.testmethod.trial import WatchedCell, execute, placed_scene, prepared, run_trial
    started = load()
    batch = jobs(Options("basic", trials=trials + 1, seed=0, parts=(parts,)))
    run_trial(batch[0])  # imports and the plan
    stages = {"placement": 0.0, "simulated cell": 0.0, "executor": 0.0, "report": 0.0}
    t_all, cpu_all = time.perf_counter(), time.process_time()
    for job in batch[1:]:
        prep = prepared(job.spec)
        t0 = time.perf_counter()
        _, placed = place_trays(prep.scenario, job.seed)
        timed = _TimedCell(SimulatedCell(placed_scene(prep.scene, prep.scenario.namespace, placed), seed=job.seed))
        t1 = time.perf_counter()
        run = execute(prep, WatchedCell(timed), job.spec.name, job.seed)  # type: ignore[arg-type]
        t2 = time.perf_counter()
        run.report()
        t3 = time.perf_counter()
        stages["placement"] += t1 - t0
        stages["simulated cell"] += timed.seconds
        stages["executor"] += t2 - t1 - timed.seconds
        stages["report"] += t3 - t2
    wall, cpu = (time.perf_counter() - t_all) / trials, (time.process_time() - cpu_all) / trials
    prof = cProfile.Profile()
    prof.enable()
    for job in batch[1:]:
        run_trial(job)
    prof.disable()
    stats = pstats.Stats(prof)
    top = sorted(stats.stats.items(), key=lambda kv: -kv[1][2])[:8]  # type: ignore[attr-defined]
    return {"parts": parts, "trials": trials, "load": started, "seconds_per_trial": round(wall, 4),
            "cpu_s_per_trial": round(cpu, 4),
            "stages": {k: round(v / trials, 4) for k, v in stages.items()},
            "top_own_time": [{"function": f"{Path(path).name}:{func}", "seconds_per_trial": round(tt / trials, 4)}
                             for (path, _line, func), (_cc, _nc, tt, _ct, _callers) in top]}


# --- scaling ---------------------------------------------------------------------------------

class _Clock:
    """A progress sink that notes when each trial's row arrived."""

    enabled = True

    def __init__(self) -> None:
        self.times: list[float] = []

    def task(self, description: str, total: float | None = None, unit: str = "") -> "_Clock":
        return self

    def __enter__(self) -> "_Clock":
        return self

    def __exit__(self, *exc: object) -> None:
        return None

    def advance(self, amount: float = 1) -> None:
        self.times.append(time.perf_counter())

    def update(self, **kw: Any) -> None:
        pass


def campaign(parts: int, trials: int, workers: int, folder: Path) -> tuple[dict[str, Any], list[dict]]:
    options = Options("basic", trials=trials, seed=0, parts=(parts,))
    clock = _Clock()
    started = load()
    cpu = _cpu()
    t = time.perf_counter()
    c = run_campaign(options, folder, workers=workers, progress=clock)
    wall = time.perf_counter() - t
    own, workers_cpu = (b - a for a, b in zip(cpu, _cpu()))
    steady = (len(clock.times) - 1) / (clock.times[-1] - clock.times[0]) if len(clock.times) > 1 else None
    out = {"workers": workers, "trials": trials, "load": started, "wall_s": round(wall, 2),
           "trials_per_s": round(trials / wall, 4), "steady_trials_per_s": round(steady, 4) if steady else None,
           "first_row_s": round(clock.times[0] - t, 2) if clock.times else None,
           "kits_built": c.summary["kits_built"], "median_trial_s": c.summary["metrics"]["trial.time_s"]["median"],
           "worker_cpu_s_per_trial": round(workers_cpu / trials, 4), "client_cpu_s_per_trial": round(own / trials, 4)}
    return out, [comparable(r) for r in c.rows]


def _cpu() -> tuple[float, float]:
    """CPU seconds (user + system) of this process, and of its children that have ended (the
    Dask workers, once their cluster is closed)."""
    me, kids = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return me.ru_utime + me.ru_stime, kids.ru_utime + kids.ru_stime


def scaling(parts: int, trials: int, repeat: int) -> dict[str, Any]:
    """``repeat`` pairs of campaigns (1 worker, 2 workers; which goes first alternates, so that a
    change of the machine's load falls on both alike); the median of each figure."""
    runs: dict[int, list[dict[str, Any]]] = {1: [], 2: []}
    same = True
    with tempfile.TemporaryDirectory(prefix="kitkb-bench-tm-") as tmp:
        for r in range(repeat):
            rows: dict[int, list] = {}
            for workers in ((1, 2) if r % 2 == 0 else (2, 1)):
                figures, rows[workers] = campaign(parts, trials, workers, Path(tmp) / f"r{r}w{workers}")
                runs[workers].append(figures)
                print(json.dumps(figures), flush=True)
            same = same and rows[1] == rows[2]
    one, two = (_median(runs[w]) for w in (1, 2))
    steady = two["steady_trials_per_s"] / one["steady_trials_per_s"] if one["steady_trials_per_s"] else None
    return {"parts": parts, "trials": trials, "repeat": repeat, "one": one, "two": two,
            "ratio": round(two["trials_per_s"] / one["trials_per_s"], 3),
            "steady_ratio": round(steady, 3) if steady else None, "same_rows": same, "runs": runs}


def _median(runs: list[dict[str, Any]]) -> dict[str, Any]:
    out = dict(runs[0])
    for key, value in runs[0].items():
        if isinstance(value, (int, float)) and key not in ("workers", "trials", "kits_built"):
            out[key] = round(statistics.median(r[key] for r in runs), 4)
    return out


# --- a thousand trials -------------------------------------------------------------------------

def thousand(parts: int, trials: int) -> dict[str, Any]:
    with tempfile.TemporaryDirectory(prefix="kitkb-bench-tm-") as tmp:
        started = load()
        cpu = _cpu()[1]
        t = time.perf_counter()
        proc = subprocess.run([*KITKB, "testmethod", "basic", "--parts", str(parts), "--trials", str(trials),
                               "--workers", "2", "--out", str(Path(tmp) / "c"), "--format", "json", "-q"],
                              capture_output=True, text=True, cwd=tmp)
        wall = time.perf_counter() - t
        cpu = _cpu()[1] - cpu
        summary = json.loads(proc.stdout)["summary"] if proc.stdout.strip() else {}
    return {"parts": parts, "trials": trials, "load": started, "exit": proc.returncode, "wall_s": round(wall, 1),
            "cpu_s": round(cpu, 1), "load_after": load(),
            "kits_built": summary.get("kits_built"), "errors": summary.get("errors"),
            "median_trial_s": ((summary.get("metrics") or {}).get("trial.time_s") or {}).get("median"),
            "stderr": proc.stderr[-400:] if proc.returncode not in (0, 1) else ""}


# --- before and after ---------------------------------------------------------------------------

#: Run in a checkout (its kb/ first on PYTHONPATH): trials of the basic method after a first one,
#: their CPU and wall seconds, and a digest of their reports without timings.
_AB_TRIALS = r"""
import hashlib, json, sys, time
from kb.testmethod import Options, comparable, jobs
from kb.testmethod.trial import run_trial
parts, trials = int(sys.argv[1]), int(sys.argv[2])
batch = jobs(Options("basic", trials=trials + 1, seed=0, parts=(parts,)))
run_trial(batch[0])
t, cpu = time.perf_counter(), time.process_time()
reports = [run_trial(job) for job in batch[1:]]
wall, cpu = time.perf_counter() - t, time.process_time() - cpu
digest = hashlib.sha256(json.dumps(comparable(reports), sort_keys=True).encode()).hexdigest()[:16]
print(json.dumps({"cpu_s_per_trial": round(cpu / trials, 4), "s_per_trial": round(wall / trials, 4), "digest": digest}))
"""


def ab(before: Path, parts: int, trials: int, rounds: int) -> dict[str, Any]:
    """The CPU seconds of a basic trial in ``before`` (a checkout) and in this one, taking turns
    (``rounds`` runs each, each a fresh process, the order alternating), medians."""
    head = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True, cwd=before)
    checkouts = {"before": before.resolve(), "after": ROOT}
    runs: dict[str, list[dict[str, Any]]] = {"before": [], "after": []}
    for r in range(rounds):
        for name in (("before", "after") if r % 2 == 0 else ("after", "before")):
            started = load()
            env = {**os.environ, "PYTHONPATH": str(checkouts[name]), "KITKB_PROGRESS": "0"}
            proc = subprocess.run([sys.executable, "-c", _AB_TRIALS, str(parts), str(trials)], capture_output=True,
                                  text=True, env=env, cwd=checkouts[name], check=True)
            figures = {**json.loads(proc.stdout.strip().splitlines()[-1]), "load": started}
            runs[name].append(figures)
            print(json.dumps({name: figures}), flush=True)
    med = {name: {key: round(statistics.median(f[key] for f in found), 4)
                  for key in ("cpu_s_per_trial", "s_per_trial", "load")} for name, found in runs.items()}
    return {"parts": parts, "trials": trials, "rounds": rounds, "before_checkout": head.stdout.strip() or str(before),
            **med, "speedup_cpu": round(med["before"]["cpu_s_per_trial"] / med["after"]["cpu_s_per_trial"], 2),
            "same_reports": len({f["digest"] for found in runs.values() for f in found}) == 1, "runs": runs}


# --- the doc ----------------------------------------------------------------------------------

def render(run: dict[str, Any]) -> str:
    lines = [f"## {SECTION}", "",
             "`benchmarks/bench_testmethod.py` (`kitkb testmethod`, kb.testmethod on Dask distributed). "
             f"Machine: {run['machine']}, {run['cores']} cores, shared with other sessions (1-minute load "
             f"average at the start of each part given); measured {run['date']} at {run['checkout']}.", ""]
    p = run.get("profile")
    if p:
        lines += [f"**Where a trial's time goes** (basic, {p['parts']}-part kit, {p['trials']} trials in one "
                  f"process after the first; load {p['load']}): {p['seconds_per_trial']} s a trial "
                  f"({p.get('cpu_s_per_trial', '-')} CPU s): "
                  + ", ".join(f"{k} {v} s" for k, v in p["stages"].items())
                  + ". The plan, the nominal scene and the domain are made once per design and worker, not per "
                  "trial. Most own time under cProfile (s a trial): "
                  + ", ".join(f"`{f['function']}` {f['seconds_per_trial']}" for f in p["top_own_time"][:5]) + ".",
                  ""]
    a = run.get("ab")
    if a:
        lines += [f"**Before and after** (basic, {a['parts']}-part kit, {a['trials']} trials in one process after "
                  f"the first, {a['rounds']} runs of each checkout taking turns, medians; load: the median at their "
                  f"starts): {a['before_checkout']} {a['before']['cpu_s_per_trial']} CPU s a trial "
                  f"({a['before']['s_per_trial']} s, load {a['before']['load']}), {run['checkout']} "
                  f"{a['after']['cpu_s_per_trial']} CPU s ({a['after']['s_per_trial']} s, load {a['after']['load']}): "
                  f"{a['speedup_cpu']}x less CPU a trial; the trial reports are "
                  f"{'the same' if a['same_reports'] else 'NOT the same'} (timings left out).", ""]
    s = run.get("scaling")
    if s:
        lines += [f"**1 and 2 workers** (basic, {s['parts']}-part kit, {s['trials']} trials a campaign, a LocalCluster "
                  f"started for each; medians of {s.get('repeat', 1)} pairs of campaigns, the order alternating; "
                  "load: the median at their starts):", "",
                  "| workers | load | wall s | trials/s (whole) | trials/s (steady) | first row s | median trial s "
                  "| worker CPU s / trial | client CPU s / trial | kits built |", "|---|---|---|---|---|---|---|---|---|---|"]
        for key in ("one", "two"):
            r = s[key]
            lines.append(f"| {r['workers']} | {r['load']} | {r['wall_s']} | {r['trials_per_s']} | "
                         f"{r['steady_trials_per_s']} | {r['first_row_s']} | {r['median_trial_s']} | "
                         f"{r.get('worker_cpu_s_per_trial', '-')} | {r.get('client_cpu_s_per_trial', '-')} | "
                         f"{r['kits_built']} |")
        lines += ["", f"2 workers / 1 worker: {s['ratio']}x over the whole campaign, {s['steady_ratio']}x steady "
                  f"(goal: at least 1.7x); the rows are {'the same' if s['same_rows'] else 'NOT the same'} "
                  "(timings left out).", ""]
    t = run.get("thousand")
    if t:
        verdict = "under" if t["wall_s"] < 300 else "over"
        cpu = f", {t['cpu_s']} CPU s ({t['cpu_s'] / t['trials']:.3f} a trial)" if t.get("cpu_s") else ""
        lines += [f"**{t['trials']:,} trials** of the {t['parts']}-part basic kit on 2 workers, `kitkb testmethod` as "
                  f"a whole process (load {t['load']} at the start, {t.get('load_after', '-')} at the end): "
                  f"{t['wall_s']} s{cpu}, {verdict} the 5-minute goal; exit {t['exit']}, kits built "
                  f"{t['kits_built']}, median trial {t['median_trial_s']} s.", ""]
    for note in run.get("notes", []):
        lines += [note, ""]
    return "\n".join(lines)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--parts-of-run", nargs="+", choices=["profile", "ab", "scaling", "thousand"],
                    default=["profile", "scaling", "thousand"])
    ap.add_argument("--before", type=Path, help="ab: a checkout of the earlier revision")
    ap.add_argument("--ab-trials", type=int, default=10, help="ab: trials timed in each run (default 10)")
    ap.add_argument("--ab-rounds", type=int, default=3, help="ab: runs of each checkout (default 3; medians)")
    ap.add_argument("--parts", type=int, default=10, help="parts of the basic kit (default 10)")
    ap.add_argument("--trials", type=int, default=60, help="trials of each scaling campaign (default 60)")
    ap.add_argument("--repeat", type=int, default=3, help="pairs of scaling campaigns (default 3; medians)")
    ap.add_argument("--profile-trials", type=int, default=10)
    ap.add_argument("--thousand", type=int, default=1000, help="trials of the big campaign (default 1000)")
    ap.add_argument("--checkout", help="what was measured, for the doc (default: git HEAD of the checkout)")
    ap.add_argument("--no-doc", action="store_true")
    ap.add_argument("--render", action="store_true", help="rewrite the doc section from the latest results")
    ap.add_argument("--note", action="append", default=[], help="a line for the doc section")
    args = ap.parse_args()
    history = json.loads(RESULTS.read_text()) if RESULTS.exists() else []
    if args.render:
        common.write_doc(SECTION, render(history[-1]))
        return 0
    head = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True, cwd=ROOT)
    run: dict[str, Any] = {"date": dt.date.today().isoformat(), "checkout": args.checkout or head.stdout.strip(),
                           "machine": common.cpu_model(), "cores": os.cpu_count(), "notes": args.note}
    if "profile" in args.parts_of_run:
        run["profile"] = profile(args.parts, args.profile_trials)
        print(json.dumps(run["profile"]), flush=True)
    if "ab" in args.parts_of_run:
        if args.before is None:
            ap.error("--parts-of-run ab needs --before DIR")
        run["ab"] = ab(args.before, args.parts, args.ab_trials, args.ab_rounds)
        print(json.dumps({k: v for k, v in run["ab"].items() if k != "runs"}), flush=True)
    if "scaling" in args.parts_of_run:
        run["scaling"] = scaling(args.parts, args.trials, args.repeat)
        print(json.dumps(run["scaling"]), flush=True)
    if "thousand" in args.parts_of_run:
        run["thousand"] = thousand(args.parts, args.thousand)
        print(json.dumps(run["thousand"]), flush=True)
    RESULTS.parent.mkdir(exist_ok=True)
    RESULTS.write_text(json.dumps(history + [run], indent=1) + "\n")
    if not args.no_doc:
        common.write_doc(SECTION, render(run))
    ok = (run.get("scaling", {}).get("same_rows", True) and run.get("ab", {}).get("same_reports", True)
          and run.get("thousand", {}).get("exit", 0) in (0, 1))
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
