"""Fault campaigns never crash: many seeded ``kitkb run`` runs with every fault kind at high rates.

``--runs`` runs (default 1,000) on kits generated with ``kb.scenario.write_scenario`` (the code of
``kitkb scenario generate``) of ``--sizes`` parts (default 10, 10, 20, 20, 40, 40, 80, 160: a size
listed twice gets twice the runs; one kit per 40 parts, at least one; scenario seed 1). Run ``r``
has fault seed ``r`` (``--first-seed`` adds to it), size ``sizes[r mod len(sizes)]`` and fault
mix ``MIXES[(r div len(sizes)) mod 8]``: every
kind at once (each take-part kind 0.15, so nine take-parts in ten get a fault, and
kit-tray-moved 0.5), or one kind mostly (0.6 for a take-part kind with the five others at 0.02
and kit-tray-moved 0.3; kit-tray-moved 0.9 with the take-part kinds at 0.02): a generated kit
has few spare parts, and with every kind high a run soon has no part of a SKU left, so the
mostly-one-kind runs are those that reach the later actions (put-kit) and the goal. Every size meets
every mix once in ``8 x len(sizes)`` runs.

Every run is ``kitkb run INIT GOAL --faults MIX --seed r --report FILE -o DIR -q``: in
``--workers`` processes, each calling the command line's entry point ``kb.cli.main(argv)`` (the
whole of ``kitkb run``: validation, PDDL, planning, the geometry check, the world-model
database, execution with verification and recovery, the report; only the interpreter's
start-up and imports are shared between runs). The first ``--process-sample`` runs are run a
second time as whole processes (``.venv/bin/kitkb run ...``): same exit code and same report
(apart from its timings) expected, and the difference in wall time is the start-up that
in-process runs save. A run that does not end within ``--timeout`` seconds is a hang.

Recorded per run: exit code, whether the report was written, whether the plan was executed,
goal, stop reason, faults injected / detected / diagnosed (scored from the report against the
simulator's ground truth as ``bench_execution.py`` scores its campaign), wall time and CPU time
(the run's process and its children: the planner), and for a
run that ended otherwise than with exit 0 or 1 and a report its last lines of output. The
script exits 1 when any run ended with exit 2 or 3, without a report, with a traceback, or hung.

    .venv/bin/python benchmarks/bench_campaign.py                                  # 1,000 runs, 2 workers
    .venv/bin/python benchmarks/bench_campaign.py --runs 16 --sizes 10 40 --process-sample 1 --no-doc --no-save  # a minute

Results go to ``benchmarks/results/campaign.json`` (the latest campaign keeps every run; older
ones their summaries) and the "## Fault campaign" section of ``docs/benchmarks.md`` (``--render``
rewrites it from the latest results).
"""

from __future__ import annotations

import argparse
import concurrent.futures as cf
import contextlib
import datetime as dt
import io
import json
import logging
import os
import resource
import shutil
import signal
import statistics
import subprocess
import sys
import tempfile
import time
from collections import Counter
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

import common  # noqa: E402
from bench_execution import ELIGIBLE, FAULT_KINDS, checkout, machine, score, stop_reason  # noqa: E402

SECTION = "Fault campaign"
RESULTS = ROOT / "benchmarks" / "results" / "campaign.json"
KITKB = ROOT / ".venv" / "bin" / "kitkb"
#: sizes cycled through run by run: a size listed twice gets twice the runs (the small kits, whose
#: runs are short, get more of them, so that 1,000 runs fit in about 25 minutes on two cores)
SIZES = (10, 10, 20, 20, 40, 40, 80, 160)
TAKE = ELIGIBLE["take-part"]


def _mixes() -> list[tuple[str, dict[str, float]]]:
    """(name, rates): every kind at once, then each kind mostly."""
    out = [("all", {**{k: 0.15 for k in TAKE}, "kit-tray-moved": 0.5})]
    for kind in FAULT_KINDS:
        if kind in TAKE:
            rates = {**{k: 0.02 for k in TAKE}, kind: 0.6, "kit-tray-moved": 0.3}
        else:
            rates = {**{k: 0.02 for k in TAKE}, kind: 0.9}
        out.append((f"mostly {kind}", rates))
    return out


MIXES = _mixes()


def faults_text(rates: dict[str, float]) -> str:
    return ",".join(f"{k}={rates[k]:g}" for k in FAULT_KINDS if k in rates)


def kits_for(parts: int) -> int:
    return max(1, parts // 40)


def tasks(runs: int, sizes: list[int], first_seed: int, folder: Path) -> list[dict]:
    out = []
    for r in range(runs):
        size = sizes[r % len(sizes)]
        mix, rates = MIXES[(r // len(sizes)) % len(MIXES)]
        d = folder / f"p{size}"
        out.append({"run": r, "seed": first_seed + r, "parts": size, "kits": kits_for(size), "mix": mix,
                    "faults": faults_text(rates), "init": str(d / "init.ttl"), "goal": str(d / "goal.ttl"),
                    "out": str(folder / "runs" / f"r{r}")})
    return out


# --- one run --------------------------------------------------------------------------------

class Hang(BaseException):
    """Raised by the alarm in a run that outlived its time (a BaseException: kitkb's ``main``
    turns an Exception into exit 3, and a hang must not look like that)."""


def _alarm(signum: int, frame: Any) -> None:
    raise Hang()


def worker_init() -> None:
    """A worker: its own working directory (Fast Downward writes ``output.sas`` into the
    current one), kitkb imported once, quiet loggers, the alarm for hangs."""
    os.chdir(tempfile.mkdtemp(prefix="cwd-", dir=os.environ.get("KITKB_CAMPAIGN_DIR") or None))
    logging.getLogger("kitkb").setLevel(logging.CRITICAL)
    signal.signal(signal.SIGALRM, _alarm)
    import kb.cli  # noqa: F401  (the imports are the start-up the in-process runs share)


def argv_of(task: dict, report: Path) -> list[str]:
    return ["run", task["init"], task["goal"], "--faults", task["faults"], "--seed", str(task["seed"]),
            "--report", str(report), "-o", task["out"], "-q"]


def run_in_process(task: dict, timeout: float) -> dict:
    """``kb.cli.main(argv)`` of the run, its output captured; what it left (then deleted)."""
    from kb.cli import main
    out_dir = Path(task["out"])
    report = out_dir / "report.json"
    buf = io.StringIO()
    t, cpu = time.perf_counter(), _cpu()
    signal.alarm(max(1, int(timeout)))
    try:
        with contextlib.redirect_stdout(buf), contextlib.redirect_stderr(buf):
            code: int | str = main(argv_of(task, report))
    except Hang:
        code = "hang"
    except BaseException as e:  # noqa: BLE001  (anything escaping main is a finding)
        code = f"escaped: {type(e).__name__}: {e}"
    finally:
        signal.alarm(0)
    wall, cpu = time.perf_counter() - t, _cpu() - cpu
    rep = json.loads(report.read_text()) if report.exists() else None
    shutil.rmtree(out_dir, ignore_errors=True)
    return dict(record(task, code, rep, buf.getvalue(), wall), cpu_s=round(cpu, 3))


def _cpu() -> float:
    """CPU seconds of this process and its finished children (the planner runs as one)."""
    me, kids = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return me.ru_utime + me.ru_stime + kids.ru_utime + kids.ru_stime


def run_process(task: dict, timeout: float) -> dict:
    """The same run as a whole ``kitkb run`` process."""
    out_dir = Path(task["out"] + "-process")
    report = out_dir / "report.json"
    t = time.perf_counter()
    try:
        p = subprocess.run([str(KITKB), *argv_of(dict(task, out=str(out_dir)), report)], capture_output=True,
                           text=True, timeout=timeout, cwd=tempfile.mkdtemp(prefix="cwd-"))
        code: int | str = p.returncode
        text = p.stdout + p.stderr
    except subprocess.TimeoutExpired:
        code, text = "hang", ""
    wall = time.perf_counter() - t
    rep = json.loads(report.read_text()) if report.exists() else None
    shutil.rmtree(out_dir, ignore_errors=True)
    return record(task, code, rep, text, wall)


def record(task: dict, code: int | str, rep: dict | None, output: str, wall: float) -> dict:
    """What the campaign keeps of a run."""
    out = {k: task[k] for k in ("run", "seed", "parts", "kits", "mix")}
    out.update(exit=code, report=rep is not None, wall_s=round(wall, 3), traceback="Traceback (most recent" in output)
    if rep is not None:
        sc = score(rep)
        out.update(executed=bool(rep.get("executed", True)), goal_holds=bool(rep.get("goal_holds")),
                   stopped=rep.get("stopped") or rep.get("reason"), stop=stop_reason(rep.get("stopped"))
                   or (f"not executed: {rep['reason'][:60]}" if rep.get("reason") else None),
                   actions=rep.get("actions", 0), replans=rep.get("replans", 0),
                   injected=Counter(x["kind"] for x in rep.get("injected", [])),
                   detected=Counter(x["kind"] for x, d in zip(rep.get("injected", []), sc["detected"]) if d),
                   failures=len(rep.get("failures", [])), diagnosed=sc["verdicts"].count("correct"),
                   wrong=sc["verdicts"].count("wrong"), unmatched=sc["verdicts"].count("unmatched"),
                   time_s=rep.get("time_s"), kits_buildable=rep.get("kits_buildable"),
                   kits_built=(rep.get("oracle") or {}).get("kits_built"), completion=rep.get("completion"),
                   repeated=rep.get("repeated_diagnoses", 0),
                   repeated_modes=Counter(x.get("mode") for x in rep.get("repeated", [])),
                   partial=[(p.get("kit"), p.get("outcome")) for p in rep.get("partial_kits", [])])
    if not ok(out):
        out["output"] = output[-2000:]
    return out


def ok(r: dict) -> bool:
    """Exit 0 or 1, a report, no traceback."""
    return r["exit"] in (0, 1) and r["report"] and not r["traceback"]


def same_run(a: dict, b: dict) -> bool:
    """Two records of one run agree apart from their timings."""
    keys = ("exit", "report", "executed", "goal_holds", "stopped", "injected", "failures", "diagnosed", "actions")
    return all(a.get(k) == b.get(k) for k in keys)


# --- the campaign ------------------------------------------------------------------------------

def generate(sizes: list[int], folder: Path) -> dict[int, float]:
    """The generated kits; seconds each took."""
    from kb.scenario import write_scenario
    took = {}
    for n in sizes:
        t = time.perf_counter()
        write_scenario(folder / f"p{n}", parts=n, kits=kits_for(n), seed=1)
        took[n] = round(time.perf_counter() - t, 3)
    return took


def campaign(args: argparse.Namespace, folder: Path) -> dict:
    todo = tasks(args.runs, args.sizes, args.first_seed, folder)
    sample = todo[:args.process_sample]
    processes = [run_process(t, args.timeout) for t in sample]
    results: list[dict] = []
    started = time.perf_counter()
    exits: Counter = Counter()
    every = max(1, len(todo) // 100)
    with cf.ProcessPoolExecutor(args.workers, initializer=worker_init) as pool:
        futures = [pool.submit(run_in_process, t, args.timeout) for t in todo]
        for fut in cf.as_completed(futures):
            r = fut.result()
            results.append(r)
            exits[str(r["exit"])] += 1
            done = len(results)
            if done % every == 0 or not ok(r) or done == len(todo):
                el = time.perf_counter() - started
                print(f"[{done}/{len(todo)}] {el:.0f} s, ETA {el / done * (len(todo) - done):.0f} s; exits "
                      f"{dict(sorted(exits.items()))}; run {r['run']} ({r['parts']} parts, {r['mix']}, seed "
                      f"{r['seed']}): exit {r['exit']} in {r['wall_s']:.1f} s{'' if ok(r) else '  <-- FINDING'}",
                      flush=True)
    results.sort(key=lambda r: r["run"])
    wall = time.perf_counter() - started
    sample_rows = [{"run": p["run"], "parts": p["parts"], "process_s": p["wall_s"],
                    "in_process_s": results[p["run"]]["wall_s"], "same": same_run(p, results[p["run"]])}
                   for p in processes]
    return {"results": results, "wall_s": round(wall, 1), "process_sample": sample_rows,
            "process_findings": [p for p in processes if not ok(p)]}


def summarise(c: dict) -> dict:
    res = c["results"]
    findings = [r for r in res if not ok(r)] + c["process_findings"]
    by_size = {}
    for n in sorted({r["parts"] for r in res}):
        rows = [r for r in res if r["parts"] == n]
        walls = sorted(r["wall_s"] for r in rows)
        by_size[n] = {"runs": len(rows), "kits": rows[0]["kits"], "exit": dict(Counter(str(r["exit"]) for r in rows)),
                      "mean_cpu_s": round(statistics.mean(r.get("cpu_s", 0) for r in rows), 2),
                      "reports": sum(r["report"] for r in rows), "goal_holds": sum(r.get("goal_holds", 0) for r in rows),
                      "median_s": round(statistics.median(walls), 2), "max_s": round(walls[-1], 2)}
    faults: dict[str, dict[str, int]] = {k: {"injected": 0, "detected": 0} for k in FAULT_KINDS}
    for r in res:
        for k, v in r.get("injected", {}).items():
            faults[k]["injected"] += v
        for k, v in r.get("detected", {}).items():
            faults[k]["detected"] += v
    stops = Counter(r.get("stop") or ("goal holds" if r.get("goal_holds") else "goal does not hold")
                    for r in res if r["report"])
    return {"runs": len(res), "exit": dict(Counter(str(r["exit"]) for r in res)),
            "reports": sum(r["report"] for r in res), "tracebacks": sum(r["traceback"] for r in res),
            "hangs": sum(r["exit"] == "hang" for r in res), "findings": len(findings),
            "by_size": by_size, "faults": faults, "stops": dict(stops.most_common()),
            "failures": sum(r.get("failures", 0) for r in res), "diagnosed": sum(r.get("diagnosed", 0) for r in res),
            "wrong": sum(r.get("wrong", 0) for r in res), "unmatched": sum(r.get("unmatched", 0) for r in res),
            "mean_run_s": round(statistics.mean(r["wall_s"] for r in res), 2) if res else 0,
            "mean_cpu_s": round(statistics.mean(r.get("cpu_s", 0) for r in res), 2) if res else 0,
            "wall_s": c["wall_s"], "completion": completion_of(res),
            "actions": sum(r.get("actions", 0) for r in res),
            "repeated": sum(r.get("repeated", 0) for r in res),
            "repeated_runs": sum(bool(r.get("repeated")) for r in res),
            "repeated_modes": dict(sum((Counter(r.get("repeated_modes", {})) for r in res), Counter())),
            "partial_kits": dict(Counter(o for r in res for _k, o in r.get("partial", []))),
            "incomplete": [r["run"] for r in res if isinstance(r.get("completion"), (int, float)) and r["completion"] < 1.0]}


def completion_of(res: list[dict]) -> dict:
    """The oracle of what was buildable over the runs with one (kb.metrics.oracle): kits built
    and buildable summed, overall = built / buildable (1.0 when nothing was buildable), the mean
    of the runs' completions, complete runs, runs without one."""
    found = [r for r in res if isinstance(r.get("completion"), (int, float)) and r.get("kits_buildable") is not None]
    built, able = sum(r["kits_built"] for r in found), sum(r["kits_buildable"] for r in found)
    return {"runs": len(found), "kits_built": built, "kits_buildable": able,
            "overall": (round(built / able, 4) if able else 1.0) if found else None,
            "mean": round(statistics.mean(r["completion"] for r in found), 4) if found else None,
            "complete": sum(r["completion"] >= 1.0 for r in found), "unknown": len(res) - len(found)}


# --- results and the doc -------------------------------------------------------------------------

def save(run: dict) -> None:
    """Append to results/campaign.json; older campaigns keep their summaries, not every run."""
    old = json.loads(RESULTS.read_text()) if RESULTS.exists() else []
    for r in old:
        r.get("campaign", {}).pop("results", None)
    RESULTS.parent.mkdir(exist_ok=True)
    RESULTS.write_text(json.dumps(old + [run], indent=1, default=str) + "\n")


def render(run: dict) -> str:
    s, c, o = run["summary"], run["campaign"], run["options"]
    m = run["machine"]
    lines = [f"## {SECTION}", "",
             "`benchmarks/bench_campaign.py`: seeded `kitkb run` runs with every fault kind at high rates on "
             "generated kits (one kit per 40 parts, at least one), each run the whole command "
             "(validate, plan, geometry check, world-model database, execution with verification and "
             "recovery, report) through `kb.cli.main` in a worker process; eight fault mixes (every kind at "
             "once: each take-part kind 0.15 and kit-tray-moved 0.5; or one kind mostly: 0.6, the other "
             "take-part kinds 0.02, kit-tray-moved 0.3; kit-tray-moved mostly: 0.9, the take-part kinds 0.02) "
             "over the sizes, fault seed = "
             "run number. Every run must end with exit 0 or 1 and its JSON report: never 2 or 3, never a "
             "traceback, never a hang.", "",
             f"Run of {run['date']} on {m['cpu']} ({m['cores']} cores, load average {m['load_average']} at the "
             f"start; the machine is shared), commit {run['checkout']['commit']}"
             + (f" with changes to {', '.join(run['checkout']['kb_changes'])}" if run['checkout']['kb_changes'] else "")
             + f"; {o['runs']} runs, sizes {_sizes(o['sizes'])} parts, {o['workers']} worker(s), "
               f"{c['wall_s'] / 60:.1f} min in all (mean run {s['mean_run_s']} s wall, {s['mean_cpu_s']} s CPU: "
               f"1,000 such runs are about {1000 * s['mean_cpu_s'] / 2 / 60:.0f} min on two free cores).", "",
             f"**{s['runs']} runs: exit codes {', '.join(f'{k}: {v}' for k, v in sorted(s['exit'].items()))}; "
             f"{s['reports']} reports written; {s['tracebacks']} tracebacks; {s['hangs']} hangs; "
             f"{s['findings']} findings.**", "",
             "| parts | kits | runs | exit 0 | exit 1 | other exits | reports | goal holds | median s | max s | "
             "mean CPU s |", "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for n, b in s["by_size"].items():
        other = sum(v for k, v in b["exit"].items() if k not in ("0", "1"))
        lines.append(f"| {n} | {b['kits']} | {b['runs']} | {b['exit'].get('0', 0)} | {b['exit'].get('1', 0)} | "
                     f"{other} | {b['reports']} | {b['goal_holds']} | {b['median_s']} | {b['max_s']} | {b['mean_cpu_s']} |")
    lines += ["", "Faults (injected by the simulator; detected: a failure of the run names the fault's object "
                  "at or after it; part-moved and kit-tray-moved are often absorbed by late binding, and a fault "
                  "on a part already rejected needs no detection):", "",
              "| kind | injected | detected |", "|---|---:|---:|"]
    for k, f in s["faults"].items():
        lines.append(f"| {k} | {f['injected']} | {f['detected']} |")
    done = s.get("completion") or {}
    if done.get("runs"):
        lines += ["", f"Completion by the oracle of what was buildable (docs/metrics.md): {done['overall']} overall "
                      f"({done['kits_built']} kits built of {done['kits_buildable']} buildable), mean {done['mean']} "
                      f"over {done['runs']} runs, {done['complete']} complete"
                      + (f", {done['unknown']} runs without an oracle" if done["unknown"] else "") + "."]
    if "repeated" in s:
        per = 10000 * s["unmatched"] / s["actions"] if s.get("actions") else 0.0
        lines += ["", f"Repeated diagnoses (a failure diagnosing an object an earlier failure of the run diagnosed, "
                      f"with no action on it between): {s['repeated']} in {s['repeated_runs']} runs"
                      + (f" ({', '.join(f'{k}: {v}' for k, v in sorted(s['repeated_modes'].items()))})"
                         if s["repeated_modes"] else "")
                      + f". False alarms (failures matched to no injected fault): {s['unmatched']} in "
                        f"{s['actions']:,} actions ({per:.2f} per 10,000). Kits not finished, by the partial-kit "
                        f"policy: " + (", ".join(f"{k} {v}" for k, v in sorted(s["partial_kits"].items()))
                                       if s["partial_kits"] else "none") + "."]
        if s.get("incomplete"):
            lines += ["", f"Runs with completion below 1: {len(s['incomplete'])} (runs "
                          + ", ".join(map(str, s["incomplete"][:20])) + (", ..." if len(s["incomplete"]) > 20 else "") + ")."]
    before = run.get("before")
    if before:
        b = before["summary"]
        lines += ["", f"Beside the campaign of {before['date']} (commit {before['commit']}, {b['runs']} runs, same "
                      f"mixes, sizes and seeds): goal holds {b['stops'].get('goal holds', 0)} then, "
                      f"{s['stops'].get('goal holds', 0)} now; stopped for want of a part "
                      f"{sum(v for k, v in b['stops'].items() if k.startswith('no usable part'))} then, "
                      f"{sum(v for k, v in s['stops'].items() if k.startswith('no usable part'))} now; failures "
                      f"{b['failures']} then, {s['failures']} now; another mode {b['wrong']} then, {s['wrong']} now; "
                      f"matched to no fault {b['unmatched']} then, {s['unmatched']} now; mean run {b['mean_run_s']} s "
                      f"then, {s['mean_run_s']} s now."]
    lines += ["", f"Failures diagnosed: {s['failures']}, of which {s['diagnosed']} with a mode the injected fault "
                  f"allows, {s['wrong']} another mode, {s['unmatched']} matched to no injected fault.", "",
              "How runs ended (stop reasons as `bench_execution.py` groups them):", "",
              "| end | runs |", "|---|---:|"]
    for k, v in s["stops"].items():
        lines.append(f"| {k} | {v} |")
    sample = c["process_sample"]
    if sample:
        gap = statistics.median(p["process_s"] - p["in_process_s"] for p in sample)
        lines += ["", f"Whole process against in process: the first {len(sample)} runs again as `kitkb run` "
                      f"processes gave {'the same' if all(p['same'] for p in sample) else 'DIFFERENT'} exit codes "
                      f"and reports; a process took {gap:.2f} s longer (median), the interpreter's start-up and "
                      f"imports, which the in-process runs share (mean run {s['mean_run_s']} s in process)."]
    if s["findings"]:
        lines += ["", "Findings (runs that did not end with exit 0 or 1 and a report):", ""]
        for r in [r for r in c["results"] if not ok(r)][:10]:
            tail = (r.get("output") or "").strip().splitlines()[-1:] or [""]
            lines.append(f"- run {r['run']} ({r['parts']} parts, {r['mix']}, seed {r['seed']}): exit {r['exit']}: "
                         f"`{tail[0][:160]}`")
    lines += ["", "Found by campaigns and fixed: a part whose new pose was queued for the next stable state and "
                  "that was gone before it (shifted in its tray, grasp missed, then missing at the retry) reached "
                  "the database as NaN, because the run store kept views of the executor's belief: exit 2 "
                  "\"pose of ...: a pose must be a finite 4x4 matrix\", one run in ten on a 40-part kit (now copied; "
                  "`tests/test_campaign.py`). The property test of the simulator (`tests/test_sim_properties.py`) "
                  "found a repeated create-kit making the kit its own support (a cycle: a hang), and targets that "
                  "overflow (now error statuses)."]
    lines += ["", "Every run's record (exit, report, stop, faults injected / detected, diagnoses, wall time) is in "
                  "`benchmarks/results/campaign.json`."]
    return "\n".join(lines) + "\n"


def earlier(options: dict) -> dict | None:
    """The latest saved campaign with the same runs, sizes and first seed (today's figures to
    set the new ones beside)."""
    old = json.loads(RESULTS.read_text()) if RESULTS.exists() else []
    keys = ("runs", "sizes", "first_seed")
    same = [r for r in old if all(r.get("options", {}).get(k) == options.get(k) for k in keys)]
    if not same:
        return None
    r = same[-1]
    return {"date": r["date"], "commit": r.get("checkout", {}).get("commit"), "summary":
            {k: v for k, v in r["summary"].items() if k not in ("by_size", "faults", "incomplete")}}


def _sizes(sizes: list[int]) -> str:
    n = Counter(sizes)
    return ", ".join(f"{k}" + (f" (x{n[k]})" if n[k] > 1 else "") for k in sorted(n))


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--runs", type=int, default=1000)
    ap.add_argument("--sizes", type=int, nargs="+", default=list(SIZES), help="parts of the generated kits")
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--first-seed", type=int, default=0, help="fault seed of run 0")
    ap.add_argument("--process-sample", type=int, default=4, help="runs repeated as whole kitkb processes")
    ap.add_argument("--timeout", type=float, default=300.0, help="seconds before a run counts as a hang")
    ap.add_argument("--no-doc", action="store_true", help="do not rewrite docs/benchmarks.md")
    ap.add_argument("--no-save", action="store_true", help="do not write benchmarks/results/campaign.json")
    ap.add_argument("--render", action="store_true", help="rewrite the doc section from the latest results")
    args = ap.parse_args(argv)
    if args.render:
        common.write_doc(SECTION, render(json.loads(RESULTS.read_text())[-1]))
        return 0
    with tempfile.TemporaryDirectory(prefix="kitkb-campaign-") as tmp:
        folder = Path(tmp)
        os.environ["KITKB_CAMPAIGN_DIR"] = tmp
        run: dict[str, Any] = {"date": dt.datetime.now(dt.timezone.utc).isoformat(timespec="seconds"),
                               "machine": machine(), "checkout": checkout(),
                               "options": {k: getattr(args, k) for k in ("runs", "sizes", "workers", "first_seed",
                                                                        "process_sample", "timeout")}}
        run["generate_s"] = generate(sorted(set(args.sizes)), folder)
        run["campaign"] = campaign(args, folder)
    run["summary"] = summarise(run["campaign"])
    run["before"] = earlier(run["options"])
    print(json.dumps({k: v for k, v in run["summary"].items() if k != "by_size"}, default=str))
    for n, b in run["summary"]["by_size"].items():
        print(f"  {n} parts: {b}")
    if not args.no_save:
        save(run)
    if not args.no_doc:
        common.write_doc(SECTION, render(run))
    return 1 if run["summary"]["findings"] else 0


if __name__ == "__main__":
    sys.exit(main())
