"""Execution with verification and failure recovery: a seeded fault campaign, the verification
cost per action, and a 160-part kit built end to end.

One run, three parts (and a comparison):

* ``campaign``: ``--runs-per-kind`` seeded runs (default 30) for each of the seven fault kinds of
  the domain (``kitkb faults``), spread over the shipped scenarios (``ontologies/scenarios/*``) and
  a generated scenario with spare parts (so that late binding has parts to rebind to). Run
  ``s`` of a kind uses scenario ``s mod 4`` and fault seed ``s``; even runs inject the kind at
  ``--rate`` per eligible action, odd runs once, at an eligible plan action drawn from the seed.
  Each scenario is planned once (``kb.planning``) and every run is ``kb.execution.run_plan``
  on that plan, in ``--workers`` processes. Every run is scored from its JSON report alone
  (:func:`score`) against the simulator's ground truth (:data:`ALLOWED`, the kinds' right diagnoses);
* ``cost``: the verification cost per action on fault-free generated kits (``--cost-parts``):
  the executor's time split by what it does (sensor, belief/pose updates, predicate checks,
  commit, targets, the simulated robot ...; see :class:`Timers`), in memory and, when
  :mod:`kb.execution.store` exists, with the store on SQLite and on PostgreSQL
  (``KITKB_PG_URL`` or ``--pg URL``); medians of ``--cost-repeat`` runs;
* ``kit``: ``kitkb run DIR/init.ttl DIR/goal.ttl -o OUT`` on ``kitkb scenario generate --parts
  160 --kits 1 --seed 0`` (validate, plan, geometry, world model, execute with verification),
  whole process, median of ``--repeat``, with the stages' times from its output;
* ``compare``: the verification cost per action of this checkout beside another commit's in
  the same run (``--baseline DIR``: a git worktree of it, e.g. ``git worktree add
  /tmp/kitkb-base 66febab``), on the same generated kits (``--cost-parts``; a size listed in
  ``--cost-actions N:K`` times the first K actions of its plan), in memory and on SQLite: every
  measurement a fresh process (``KITKB_BENCH_TREE`` picks the kb/ it imports), old and new
  interleaved (the order alternating), ``--cost-repeat`` each; medians and their ratio.

    .venv/bin/python benchmarks/bench_execution.py                       # all three, 30 runs per kind
    .venv/bin/python benchmarks/bench_execution.py --parts campaign --runs-per-kind 4 --no-doc
    .venv/bin/python benchmarks/bench_execution.py --parts compare --baseline /tmp/kitkb-base \
        --cost-parts 10 40 160 1000 --cost-actions 1000:600 --cost-repeat 3

Results are appended to ``benchmarks/results/execution.json`` (the latest run keeps every
campaign run's faults and diagnoses; older runs keep their summaries); the run rewrites the
"## Execution and failure recovery" section of ``docs/benchmarks.md`` (``--render``: from the
latest results, measuring nothing; ``notes`` added to a run there are printed with its parts).
PostgreSQL: ``KITKB_PG_URL`` or ``--pg URL`` (its world model is replaced); see
``scripts/postgres.sh`` for a throwaway server.
"""

from __future__ import annotations

import argparse
import dataclasses
import datetime as dt
import importlib.util
import json
import logging
import multiprocessing as mp
import os
import platform
import re
import statistics
import subprocess
import sys
import tempfile
import time
import traceback
from collections import Counter, defaultdict
from pathlib import Path
from typing import Any, Callable

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
#: the kitkb measured: this checkout, or another one (``--compare``'s child processes time an
#: older commit's kb/ from a git worktree with this same benchmark code)
TREE = Path(os.environ.get("KITKB_BENCH_TREE") or ROOT)
sys.path.insert(0, str(TREE))

import common  # noqa: E402

try:  # the fault kinds as data (kitting-domain.ttl); a --baseline tree from before them has kb.sim's tables
    from kb.model.faults import shipped_fault_kinds  # noqa: E402
except ImportError:
    from kb.sim import FAULT_KINDS  # noqa: E402
    from kb.sim.faults import ELIGIBLE  # noqa: E402
else:
    _KINDS = shipped_fault_kinds()
    FAULT_KINDS = _KINDS.names
    #: action -> the fault kinds that strike it
    ELIGIBLE = {a: tuple(k.name for k in _KINDS.eligible(a)) for a in _KINDS.actions}

SECTION = "Execution and failure recovery"
RESULTS = ROOT / "benchmarks" / "results" / "execution.json"
KITKB = ROOT / ".venv" / "bin" / "kitkb"

#: Ground truth and the scoring of a run's report: kb.execution.quality of this checkout (bench_noise.py
#: scores with it too; bench_campaign.py imports ``score`` from here), read from its file so that a
#: --baseline tree without it still runs (it scores nothing: the campaign runs in this checkout only);
#: the ground truth is the fault kinds' data (kb.model.faults).
_spec = importlib.util.spec_from_file_location("kitkb_quality", ROOT / "kb" / "execution" / "quality.py")
_quality = sys.modules["kitkb_quality"] = importlib.util.module_from_spec(_spec)  # type: ignore[arg-type]
try:
    _spec.loader.exec_module(_quality)  # type: ignore[union-attr]
    score = _quality.score
    ALLOWED = {k.name: k.diagnosed_by for k in _KINDS}
    MUST_DETECT = frozenset(k.name for k in _KINDS if k.must_detect)
    REJECTING = _KINDS.rejecting_modes()
except (ImportError, NameError):  # a --baseline tree from before the fault kinds were data
    score, ALLOWED, MUST_DETECT, REJECTING = None, {}, frozenset(), frozenset()  # type: ignore[assignment]


# --- machine --------------------------------------------------------------------------------------

def checkout() -> dict:
    """The commit measured, and the files of kb/ changed in the working tree (measured too)."""
    def git(*a: str) -> str:
        return subprocess.run(["git", *a], cwd=ROOT, capture_output=True, text=True).stdout
    dirty = [line[3:] for line in git("status", "--porcelain", "--", "kb").splitlines() if line.strip()]
    return {"commit": git("rev-parse", "--short", "HEAD").strip(), "kb_changes": dirty}


def pg_version(url: str) -> str:
    try:
        from kb.world import open_engine, normalize_url
        from sqlalchemy import text
        engine = open_engine(normalize_url(url))
        try:
            with engine.connect() as conn:
                return str(conn.execute(text("SHOW server_version")).scalar())
        finally:
            engine.dispose()
    except Exception as e:  # noqa: BLE001
        return f"unknown ({type(e).__name__})"


def machine() -> dict:
    cpu = platform.processor() or "unknown"
    try:
        cpu = next(line.split(":", 1)[1].strip() for line in Path("/proc/cpuinfo").read_text().splitlines()
                   if line.startswith("model name"))
    except (OSError, StopIteration):
        pass
    sqlite = __import__("sqlite3").sqlite_version
    return {"cpu": cpu, "cores": os.cpu_count(), "python": platform.python_version(), "sqlite": sqlite,
            "load_average": round(os.getloadavg()[0], 2)}


# --- scenarios and plans --------------------------------------------------------------------------

def scenarios(folder: Path) -> list[tuple[str, Path, Path]]:
    """The shipped scenarios and a generated one with spare parts: (name, init, goal)."""
    from kb.core.resources import scenario_dirs
    from kb.scenario import write_spec
    from kb.scenario.spec import random_spec
    out = [(d.name, d / "init.ttl", d / "goal.ttl") for d in scenario_dirs()]
    spec = random_spec(20, 2, 1)
    spec = dataclasses.replace(spec, name=spec.name + "-spare3", spare=3,
                               description=spec.description + " Three spare parts per type.")
    init, goal = write_spec(spec, folder / spec.name)
    out.append((spec.name, init, goal))
    return out


def plan_of(init: Path, goal: Path) -> list[str]:
    from kb import planning
    model = planning.kitting_model([init], [goal], "strips")
    return list(planning.run(model.up_problem, None).lines)


def eligible_indices(plan: list[str], kind: str) -> list[int]:
    actions = [a for a, kinds in ELIGIBLE.items() if kind in kinds]
    return [i for i, line in enumerate(plan) if line.strip("() \n").split()[0] in actions]


# --- timing of the executor's parts ---------------------------------------------------------------

class Timers:
    """Exclusive wall time per part of the executor, by wrapping its methods (no edit to kitkb):
    a wrapped call's time minus the wrapped calls made inside it (on :attr:`clock`)."""

    clock = staticmethod(time.perf_counter)

    PARTS = (
        ("sensor", "kb.sim.cell", "SimulatedCell", "sense"),  # the cell's sensor (simulated: a ground-truth query)
        ("sensor", "kb.sim.cell", "SimulatedCell", "sense_names"),  # the same, by names (neighbourhoods)
        ("belief", "kb.execution.belief", "Belief", "observe"),  # poses from the observations
        ("belief", "kb.execution.executor", "Executor", "_sense"),  # focus of attention, bookkeeping
        ("checks", "kb.execution.executor", "Executor", "_check"),  # preconditions and effects from geometry
        ("commit", "kb.execution.executor", "Executor", "_commit"),  # stable state
        ("targets", "kb.execution.executor", "Executor", "_commands"),  # late-bound CRCL targets
        ("robot", "kb.sim.cell", "SimulatedCell", "execute"),  # the simulated robot
        ("robot", "kb.sim.cell", "SimulatedCell", "begin_action"),  # the simulator's fault injection
        ("inspect", "kb.sim.cell", "SimulatedCell", "inspect"),
        ("diagnosis", "kb.execution.executor", "diagnose", None),  # inspection's
        ("diagnosis", "kb.execution.recovery", "diagnose", None),  # failed checks' (since the split)
        ("replan", "kb.execution.executor", "replan", None),  # before the split
        ("replan", "kb.execution.recovery", "replan", None),
        ("goal", "kb.execution.executor", "Executor", "goal_holds"),
    )
    STORE = (("store: pose updates", "poses_changed"), ("store: commit", "commit_stable"),
             ("store: records", "record_action"), ("store: records", "record_failure"),
             ("store: run", "begin_run"), ("store: run", "end_run"))  # once per run, outside the loop
    VERIFICATION = ("sensor", "belief", "checks", "commit", "store: pose updates", "store: commit")

    def __init__(self) -> None:
        self.t: dict[str, float] = defaultdict(float)
        self.n: dict[str, int] = defaultdict(int)
        self._stack: list[float] = []
        self._installed: list[tuple[Any, str, Any]] = []

    def wrap(self, key: str, f: Callable) -> Callable:
        def timed(*a: Any, **k: Any) -> Any:
            t = self.clock()
            self._stack.append(0.0)
            try:
                return f(*a, **k)
            finally:
                el = self.clock() - t
                inner = self._stack.pop()
                self.t[key] += el - inner
                self.n[key] += 1
                if self._stack:
                    self._stack[-1] += el
        return timed

    def install(self) -> "Timers":
        import importlib
        for key, module, owner, attr in self.PARTS:
            try:  # the same benchmark times older and newer layouts of the executor
                mod = importlib.import_module(module)
            except ImportError:
                continue
            target, name = (getattr(mod, owner), attr) if attr else (mod, owner)
            if not hasattr(target, name):
                continue
            original = getattr(target, name)
            self._installed.append((target, name, original))
            setattr(target, name, self.wrap(key, original))
        return self

    def store(self, store: Any) -> Any:
        for key, name in self.STORE:
            if hasattr(store, name):
                setattr(store, name, self.wrap(key, getattr(store, name)))
        return store

    def uninstall(self) -> None:
        for target, name, original in reversed(self._installed):
            setattr(target, name, original)
        self._installed.clear()

    def reset(self) -> None:
        self.t.clear()
        self.n.clear()


# --- one run ----------------------------------------------------------------------------------------

_PLANS: dict[str, tuple[list[str], str, str]] = {}  # scenario -> (plan, init, goal); set before forking
_TIMERS: Timers | None = None


def run_one(task: dict) -> dict:
    """One seeded run of a scenario's plan; its report (compact) and timings, or the crash."""
    global _TIMERS
    from kb.execution import run_plan
    logging.getLogger("kitkb").setLevel(logging.ERROR)
    if _TIMERS is None:
        _TIMERS = Timers().install()
    _TIMERS.reset()
    plan, init, goal = _PLANS[task["scenario"]]
    out = dict(task)
    t = time.perf_counter()
    try:
        run = run_plan(plan, init, goal, faults=task["faults"], seed=task["seed"], name=task["scenario"],
                       notifier=lambda who, text: None)
        rep = run.report()
        out.update(goal_holds=rep["goal_holds"], stopped=rep["stopped"], replans=rep["replans"],
                   actions=rep["actions"], attempts=len(run.record.actions), checks=rep["checks"],
                   injected=[{k: x[k] for k in ("kind", "action_index", "objects", "detail")} for x in rep["injected"]],
                   failures=[{k: f[k] for k in ("mode", "action_index", "action", "objects", "recovery", "outcome")}
                             for f in rep["failures"]])
    except Exception as e:  # a crash is a finding: keep it
        out.update(crash=f"{type(e).__name__}: {e}", traceback=traceback.format_exc(limit=8))
    out["wall_s"] = time.perf_counter() - t
    out["timings"] = {k: round(v, 6) for k, v in _TIMERS.t.items()}
    return out


def private_cwd() -> None:
    """Work in a directory of one's own: Fast Downward's driver writes ``output.sas`` into the
    current directory, so two planners running in one directory read each other's tasks."""
    os.chdir(tempfile.mkdtemp(prefix="cwd-", dir=os.getcwd()))  # inside the run's temporary folder


# --- scoring ----------------------------------------------------------------------------------------

def stop_reason(text: str | None) -> str | None:
    if not text:
        return None
    if "more part(s) of" in text or "no usable part of" in text:
        return "no usable part of a SKU left" + (" (operator)" if "operator" in text else "")
    if text.startswith("no plan"):
        return "no plan: " + text.split(" says ", 1)[-1][:60]
    if "operator" in text:
        m = re.match(r"([a-z-]+) at action", text)
        return f"operator: {m.group(1)}" if m else "operator"
    if "gave up" in text:
        return "gave up (replans)"
    return "other: " + text[:80]


def summarise(results: list[dict]) -> dict:
    """Per-kind figures of the campaign, and the runs worth a look (anomalies)."""
    by_kind: dict[str, dict] = {}
    anomalies = []
    for kind in FAULT_KINDS:
        rows = [r for r in results if r["kind"] == kind]
        s: dict[str, Any] = {"runs": len(rows), "injected": 0, "need_detection": 0, "detected": 0,
                             "absorbed": 0, "failures": 0, "correct": 0, "wrong": 0, "unmatched": 0,
                             "goal_holds": 0, "stopped": Counter(), "correct_stops": 0, "replans": 0,
                             "crashes": 0, "modes": Counter(), "wrong_modes": Counter(), "actions": 0,
                             "wall_s": 0.0, "no_injection": 0, "moot": 0}
        for r in rows:
            s["wall_s"] += r["wall_s"]
            if "crash" in r:
                s["crashes"] += 1
                anomalies.append(dict(r, why="crash"))
                continue
            sc = score(r)
            r["score"] = sc
            inj = r["injected"]
            s["injected"] += len(inj)
            s["no_injection"] += not inj
            s["failures"] += len(r["failures"])
            s["replans"] += r["replans"]
            s["actions"] += r["attempts"]
            s["goal_holds"] += bool(r["goal_holds"])
            why = []
            for x, det, moot in zip(inj, sc["detected"], sc["moot"]):
                if moot and not det:
                    s["moot"] += 1
                elif x["kind"] in MUST_DETECT:
                    s["need_detection"] += 1
                    s["detected"] += det
                    if not det:
                        why.append(f"{x['kind']}@{x['action_index']} not detected")
                else:
                    s["detected_moved"] = s.get("detected_moved", 0) + det
                    s["absorbed"] += not det
            for f, v in zip(r["failures"], sc["verdicts"]):
                s[v] += 1
                s["modes"][f["mode"]] += 1
                if v != "correct":
                    s["wrong_modes"][f["mode"]] += 1
                    why.append(f"{v}: {f['mode']}@{f['action_index']}")
            reason = stop_reason(r["stopped"])
            if reason:
                s["stopped"][reason] += 1
                correct_stop = reason.startswith("no usable part of a SKU left") or any(
                    reason == f"operator: {f['mode']}" and v == "correct"
                    for f, v in zip(r["failures"], sc["verdicts"]))
                s["correct_stops"] += correct_stop
                if not correct_stop:
                    why.append(f"stopped: {r['stopped']}")
            elif not r["goal_holds"]:
                why.append("goal does not hold")
            if why:
                anomalies.append(dict(r, why="; ".join(why)))
        s["stopped"] = dict(s["stopped"])
        s["modes"] = dict(s["modes"])
        s["wrong_modes"] = dict(s["wrong_modes"])
        by_kind[kind] = s
    return {"by_kind": by_kind, "anomalies": anomalies}


def replay_empty_trays(anomalies: list[dict]) -> list[dict]:
    """Ground truth for ``parts-tray-empty`` diagnoses the table does not allow (part-moved): replay
    the run in the simulator and look into the tray when the run stopped there."""
    from kb.execution import run_plan
    from kb.execution.records import local
    from kb.sim import FaultSpec, SimulatedCell
    from kb.spatial.scene import Scene
    out = []
    for a in anomalies:
        last = a.get("failures", [])[-1:]
        if a["kind"] != "part-moved" or not last or last[0]["mode"] != "parts-tray-empty" or not a.get("stopped"):
            continue
        plan, init, goal = _PLANS[a["scenario"]]
        cell = SimulatedCell(Scene.from_files([init], declared=[goal]), faults=FaultSpec.parse(a["faults"], seed=a["seed"]),
                             seed=a["seed"])
        run_plan(plan, init, goal, cell=cell, notifier=lambda who, text: None)
        w = cell.world
        tray = last[0]["objects"][1]
        t = next(i for i, n in enumerate(w.names) if local(n) == tray)
        out.append({"kind": a["kind"], "scenario": a["scenario"], "seed": a["seed"], "faults": a["faults"],
                    "tray": tray, "parts_in_tray": [local(w.names[j]) for j in w.children(t)]})
    return out


def campaign(scen: list[tuple[str, Path, Path]], runs_per_kind: int, rate: float, workers: int) -> dict:
    t0 = time.perf_counter()
    plan_s = {}
    for name, init, goal in scen:
        t = time.perf_counter()
        _PLANS[name] = (plan_of(init, goal), str(init), str(goal))
        plan_s[name] = round(time.perf_counter() - t, 3)
        print(f"planned {name}: {len(_PLANS[name][0])} actions ({plan_s[name]:.2f} s)", flush=True)
    tasks = []
    for kind in FAULT_KINDS:
        for s in range(runs_per_kind):
            name = scen[s % len(scen)][0]
            if s % 2 == 0:
                faults = f"{kind}={rate}"
            else:
                at = eligible_indices(_PLANS[name][0], kind)
                faults = f"{kind}@{at[int(np.random.default_rng(s).integers(len(at)))]}"
            tasks.append({"kind": kind, "scenario": name, "seed": s, "faults": faults})
    results: list[dict] = []
    if workers > 1:
        with mp.get_context("fork").Pool(workers, initializer=private_cwd) as pool:
            for i, r in enumerate(pool.imap_unordered(run_one, tasks, chunksize=1)):
                results.append(r)
                if (i + 1) % 20 == 0:
                    print(f"  {i + 1}/{len(tasks)} runs", flush=True)
    else:
        results = [run_one(t) for t in tasks]
    global _TIMERS
    if _TIMERS is not None:  # installed here when there are no worker processes
        _TIMERS.uninstall()
        _TIMERS = None
    results.sort(key=lambda r: (FAULT_KINDS.index(r["kind"]), r["seed"]))
    summary = summarise(results)
    timings: dict[str, float] = defaultdict(float)
    for r in results:
        for k, v in r["timings"].items():
            timings[k] += v
    attempts = sum(r.get("attempts", 0) for r in results)
    replays = replay_empty_trays([a for a in summary["anomalies"] if "crash" not in a])
    return {"replayed_empty_trays": replays, "runs": len(results), "rate": rate, "workers": workers, "scenarios": {n: len(_PLANS[n][0]) for n, _, _ in scen},
            "plan_s": plan_s, "wall_s": round(time.perf_counter() - t0, 2), "attempts": attempts,
            "ms_per_action": {k: round(v / attempts * 1e3, 3) for k, v in sorted(timings.items())} if attempts else {},
            "by_kind": summary["by_kind"], "anomalies": summary["anomalies"], "results": results}


# --- verification cost per action --------------------------------------------------------------------

def open_store(backend: str, url: str | None, folder: Path, init: Path) -> Any:
    """A :class:`kb.execution.store.RunStore` on a database :func:`~kb.execution.store.prepare`
    filled with ``init`` and the domain (SQLite file in ``folder``, or the PostgreSQL ``url``,
    replaced); None when the module is not there."""
    try:
        from kb.execution.store import RunStore, prepare
    except ImportError:
        return None
    target = url if backend == "postgresql" else str(folder / "cost.sqlite")
    prepare(target, init, replace=True)
    return RunStore(target)


def skip_empty_commits(store: Any) -> Any:
    """Workaround, named in the results: the store's stable-state commit skipped when no pose
    changed (kb.world's PostgreSQL batch writes ``VALUES ()`` for an empty batch)."""
    commit = store.commit_stable

    def commit_stable(action_index: int) -> None:
        if store.pending:
            commit(action_index)
    store.commit_stable = commit_stable
    return store


def cost_runs(plan: list[str], init: Path, goal: Path, repeat: int, backend: str, url: str | None, folder: Path,
              timers: Timers, workaround: bool) -> list[dict]:
    """``repeat`` fault-free runs with a store on ``backend`` (or none: "memory"), timed by part."""
    from kb.execution import run_plan
    rows = []
    for _ in range(repeat):
        store, prepared = None, 0.0
        if backend != "memory":
            t = time.perf_counter()
            store = open_store(backend, url, folder, init)
            prepared = time.perf_counter() - t
            if store is None:
                raise ImportError("kb.execution.store is not available yet")
            if workaround:
                skip_empty_commits(store)
            timers.store(store)
        timers.reset()
        t = time.perf_counter()
        try:
            run = run_plan(plan, init, goal, store=store, notifier=lambda who, text: None)
        finally:
            timers._stack.clear()
            if store is not None and hasattr(store, "close"):
                store.close()
        wall = time.perf_counter() - t
        loop = run.record.ended - run.record.started  # the executor's loop, without reading the files
        n = len(run.record.actions)
        ms = {k: v / n * 1e3 for k, v in timers.t.items()}
        row = {"wall_s": wall, "setup_s": wall - loop, "prepare_s": prepared, "attempts": n,
               "goal_holds": run.goal_holds, "store_run_s": ms.pop("store: run", 0.0) * n / 1e3, "ms_per_action": ms}
        ms["total"] = loop / n * 1e3
        ms["other"] = ms["total"] - sum(v for k, v in ms.items() if k != "total")
        rows.append(row)
    return rows


def cost(init: Path, goal: Path, repeat: int, backends: list[tuple[str, str | None]], folder: Path) -> dict:
    """Milliseconds per action by part, medians of ``repeat`` runs per backend. A backend that
    fails is recorded with its error and measured again with :func:`skip_empty_commits`."""
    logging.getLogger("kitkb").setLevel(logging.ERROR)
    plan = plan_of(init, goal)
    timers = Timers().install()
    out: dict[str, Any] = {"plan_actions": len(plan), "backends": {}}
    try:
        for backend, url in backends:
            entry: dict[str, Any] = {}
            rows: list[dict] = []
            for workaround in (False, True):
                try:
                    rows = cost_runs(plan, init, goal, repeat, backend, url, folder, timers, workaround)
                    break
                except ImportError as e:
                    entry = {"pending": str(e)}
                    break
                except Exception as e:  # a finding: recorded; measured again with the workaround
                    entry = {"error": f"{type(e).__name__}: {str(e).splitlines()[0][:300]}",
                             "traceback": traceback.format_exc(limit=8)}
                    print(f"cost {backend}: {entry['error']}", flush=True)
                    if backend == "memory":
                        break
            if rows:
                keys = sorted({k for r in rows for k in r["ms_per_action"]})
                med = {k: round(statistics.median(r["ms_per_action"].get(k, 0.0) for r in rows), 3) for k in keys}
                med["verification"] = round(statistics.median(
                    sum(r["ms_per_action"].get(k, 0.0) for k in Timers.VERIFICATION) for r in rows), 3)
                entry.update({"runs": len(rows), "attempts": rows[0]["attempts"],
                              "goal_holds": all(r["goal_holds"] for r in rows),
                              "wall_s": [round(r["wall_s"], 3) for r in rows],
                              "setup_s": round(statistics.median(r["setup_s"] for r in rows), 3),
                              "prepare_s": round(statistics.median(r["prepare_s"] for r in rows), 3),
                              "store_run_s": round(statistics.median(r["store_run_s"] for r in rows), 3),
                              "ms_per_action": med, "workaround": "error" in entry})
                print(f"cost {backend}{' (workaround)' if 'error' in entry else ''}: {med}", flush=True)
            out["backends"][backend] = entry
    finally:
        timers.uninstall()
    return out


# --- this checkout beside another commit, in the same run ---------------------------------------------

#: actions of a plan run once, untimed, before a ``--cost-one`` measurement
WARM_UP = 30


def cost_one(spec: dict) -> dict:
    """One timed fault-free run (a ``--cost-one`` child process): ``spec`` has init, goal, plan
    (a JSON file of action lines), backend, folder; ms per action by part, as :func:`cost_runs`."""
    logging.getLogger("kitkb").setLevel(logging.ERROR)
    plan = json.loads(Path(spec["plan"]).read_text())
    timers = Timers().install()
    try:  # warm: the first actions once, untimed (imports, caches filled once per process)
        cost_runs(plan[:WARM_UP], Path(spec["init"]), Path(spec["goal"]), 1, "memory", None, Path(spec["folder"]),
                  timers, False)
        [row] = cost_runs(plan, Path(spec["init"]), Path(spec["goal"]), 1, spec["backend"], None,
                          Path(spec["folder"]), timers, False)
    finally:
        timers.uninstall()
    ms = row["ms_per_action"]
    ms["verification"] = sum(ms.get(k, 0.0) for k in Timers.VERIFICATION)
    import kb.execution.executor as executor
    return dict(row, tree=str(Path(executor.__file__).resolve().parents[2]))


def compare(args: argparse.Namespace, folder: Path) -> dict:
    """Verification cost per action, this checkout and ``args.baseline`` interleaved."""
    trees = {"new": Path(args.candidate or ROOT).resolve(), "old": Path(args.baseline).resolve()}
    limits = dict(tuple(map(int, x.split(":"))) for x in args.cost_actions)
    sizes: dict[int, dict] = {}
    for n in args.cost_parts:
        d = folder / f"compare{n}"
        subprocess.run([str(KITKB), "-q", "scenario", "generate", "--parts", str(n), "--kits", "1", "--seed", "0",
                        "-o", str(d)], check=True)
        t = time.perf_counter()
        plan = plan_of(d / "init.ttl", d / "goal.ttl")
        timed = plan[:limits[n]] if n in limits else plan
        (d / "plan.json").write_text(json.dumps(timed))
        sizes[n] = {"plan_actions": len(plan), "timed_actions": len(timed), "plan_s": round(time.perf_counter() - t, 2),
                    "runs": {}}
        print(f"compare: {n} parts, plan of {len(plan)} actions, timing {len(timed)}", flush=True)
    load_start = round(os.getloadavg()[0], 2)
    repeats = {n: args.cost_repeat for n in sizes} | {
        int(a): int(b) for a, b in (x.split(":") for x in args.cost_repeat_at)}
    for r in range(max(repeats.values())):
        for n, entry in sizes.items():
            if r >= repeats[n]:
                continue
            for backend in ("memory", "sqlite"):
                order = ("new", "old") if (r + n + (backend == "sqlite")) % 2 == 0 else ("old", "new")
                for which in order:
                    d = folder / f"compare{n}"
                    spec = {"init": str(d / "init.ttl"), "goal": str(d / "goal.ttl"), "plan": str(d / "plan.json"),
                            "backend": backend, "folder": str(folder)}
                    env = dict(os.environ, KITKB_BENCH_TREE=str(trees[which]))
                    p = subprocess.run([sys.executable, str(Path(__file__).resolve()), "--cost-one", json.dumps(spec)],
                                       capture_output=True, text=True, env=env, cwd=folder)
                    if p.returncode != 0:
                        raise RuntimeError(f"{which} {n} {backend}: {p.stderr[-2000:]}")
                    row = json.loads(p.stdout.strip().splitlines()[-1])
                    row["load_average"] = round(os.getloadavg()[0], 2)
                    assert Path(row["tree"]) == trees[which], (row["tree"], trees[which])
                    entry["runs"].setdefault(f"{which} {backend}", []).append(row)
                    print(f"compare {r}: {n} parts {backend} {which}: verification "
                          f"{row['ms_per_action']['verification']:.2f} ms, total {row['ms_per_action']['total']:.2f} ms "
                          f"per action (load {os.getloadavg()[0]:.1f})", flush=True)
    for entry in sizes.values():
        entry["median"] = {}
        for key, rows in entry["runs"].items():
            parts = sorted({k for row in rows for k in row["ms_per_action"]})
            entry["median"][key] = {k: round(statistics.median(row["ms_per_action"].get(k, 0.0) for row in rows), 3)
                                    for k in parts}
            entry["median"][key]["goal_holds"] = all(row["goal_holds"] for row in rows)
    for n, entry in sizes.items():
        entry["repeat"] = repeats[n]
    return {"baseline": _commit_of(trees["old"]), "candidate": _commit_of(trees["new"]), "repeat": args.cost_repeat,
            "sizes": sizes, "load_average_start": load_start,
            "load_average_median": round(statistics.median(row["load_average"] for e in sizes.values()
                                                           for rows in e["runs"].values() for row in rows), 2),
            "load_average_end": round(os.getloadavg()[0], 2)}


def _commit_of(tree: Path) -> str:
    return subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=tree, capture_output=True, text=True).stdout.strip()


def render_compare(c: dict, checkout: dict) -> list[str]:
    """The comparison's subsection of the docs."""
    sizes = c["sizes"]
    desc = ", ".join(f"{n} parts: {v['plan_actions']} actions" + (f" (the first {v['timed_actions']} timed)"
                                                                   if v["timed_actions"] != v["plan_actions"] else "")
                     for n, v in sizes.items())
    at = " ".join(f"{n}:{v['timed_actions']}" for n, v in sizes.items() if v["timed_actions"] != v["plan_actions"])
    reps = " ".join(f"{n}:{v['repeat']}" for n, v in sizes.items() if v.get("repeat", c["repeat"]) != c["repeat"])
    lines = ["### Verification cost per action: neighbourhoods and batched checks against the whole cell", "",
             f"Command: `git worktree add /tmp/kitkb-base {c['baseline']}`, `git worktree add /tmp/kitkb-new "
             f"{c.get('candidate', 'HEAD')}`, then `.venv/bin/python benchmarks/bench_execution.py --parts compare "
             f"--baseline /tmp/kitkb-base --candidate /tmp/kitkb-new --cost-parts {' '.join(map(str, sizes))}"
             + (f" --cost-actions {at}" if at else "") + f" --cost-repeat {c['repeat']}"
             + (f" --cost-repeat-at {reps}" if reps else "") + " --keep`.", "",
             f"Today's code (commit `{c['baseline']}`) and the new (commit `{c.get('candidate', checkout.get('commit', '?'))}`), "
             "each a git worktree (so that edits in the working tree during the run do not mix in), "
             "timed in the same run on the same generated kits (`kitkb scenario generate --parts N --kits 1 --seed 0`; "
             f"{desc}), fault-free `kb.execution.run_plan`, in memory and with the run store on SQLite; every "
             "measurement a fresh process, old and new interleaved with the order alternating, "
             + ", ".join(f"{v.get('repeat', c['repeat'])} of each at {n} parts" for n, v in sizes.items())
             + f", each after an untimed run of the plan's first {WARM_UP} actions in the same process "
             "(imports and per-process caches warm, as in a long run); medians, milliseconds per action (exclusive "
             "time by part, as above). "
             "Verification = sensor + belief + predicate checks + commit + the store's pose updates and stable-state "
             "commit. The machine was shared with other jobs (1-minute load average on its 2 cores: "
             + (f"{c['load_average_start']} at the start, median {c['load_average_median']} over the measurements, "
                if "load_average_median" in c else "")
             + f"{c['load_average_end']} at the end): absolute figures are inflated and noisy, the ratios are the finding.",
             "",
             "| parts | store | verification, today | verification, now | now / today | now: sensor | belief "
             "(focus, poses) | checks, today | checks, now | store | total per action, today | total, now |",
             "|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    verdicts = []
    for n, v in sizes.items():
        for backend, label in (("memory", "in memory"), ("sqlite", "SQLite")):
            old, new = v["median"].get(f"old {backend}"), v["median"].get(f"new {backend}")
            if not old or not new:
                continue
            store = new.get("store: pose updates", 0.0) + new.get("store: commit", 0.0)
            lines.append(f"| {n} | {label} | {old['verification']:.2f} | {new['verification']:.2f} | "
                         f"{new['verification'] / old['verification']:.2f} | {new.get('sensor', 0):.2f} | "
                         f"{new.get('belief', 0):.2f} | {old.get('checks', 0):.2f} | {new.get('checks', 0):.2f} | "
                         f"{store:.2f} | {old['total']:.2f} | "
                         f"{new['total']:.2f} |")
            if backend == "sqlite":
                limit = 5.0 if int(n) <= 160 else 10.0
                verdicts.append(f"{n} parts: {new['verification']:.2f} ms ({'met' if new['verification'] <= limit else 'NOT met'}"
                                f" against {limit:g} ms; today {old['verification']:.2f} ms)")
    lines += ["", "Goal (SQLite: at most 5 ms per action at 160 parts, at most 10 ms at 1,000), as measured in this "
              "run: " + "; ".join(verdicts) + "."]
    ref = c.get("unloaded_reference") or {}
    if ref:  # today's figures from a run on a quiet machine, scaled by this run's ratios
        est = []
        for n, base in ref.items():
            v = sizes.get(int(n)) or sizes.get(n)
            old, new = (v or {}).get("median", {}).get("old sqlite"), (v or {}).get("median", {}).get("new sqlite")
            if old and new:
                est.append(f"{n} parts: {base:.2f} x {new['verification'] / old['verification']:.2f} = "
                           f"{base * new['verification'] / old['verification']:.2f} ms")
        if est:
            lines[-1] += (" Scaled to a quiet machine (today's SQLite figures of the earlier run, when the load was low, "
                          "times this run's ratio): " + "; ".join(est) + ".")
    big = list(sizes)[-1]
    old, new = sizes[big]["median"].get("old sqlite"), sizes[big]["median"].get("new sqlite")
    if old and new:
        sb_old = old.get("sensor", 0.0) + old.get("belief", 0.0)
        sb_new = new.get("sensor", 0.0) + new.get("belief", 0.0)
        lines += ["", f"Where the time goes, at {big} parts on SQLite: sensing and the belief (the focus of attention "
                  f"included) {sb_old:.2f} -> {sb_new:.2f} ms per action ({sb_new / sb_old:.2f}); the predicate checks "
                  f"{old.get('checks', 0):.2f} -> {new.get('checks', 0):.2f} ms ({new.get('checks', 0) / max(old.get('checks', 1e-9), 1e-9):.2f}), "
                  f"{new.get('checks', 0) / new['verification']:.0%} of the new verification."]
    notes = c.get("notes")
    if notes:
        lines += ["", notes]
    return lines


# --- the 160-part kit, whole process -----------------------------------------------------------------

_STAGE = re.compile(r"^\s+(validate|pddl|plan|geometry|world model|execute):.*\((\d+\.\d+) s\)\s*$")


def kit_end_to_end(parts: int, repeat: int, folder: Path) -> dict:
    d = folder / f"p{parts}"
    subprocess.run([str(KITKB), "-q", "scenario", "generate", "--parts", str(parts), "--kits", "1", "--seed", "0",
                    "-o", str(d)], check=True)
    runs = []
    for k in range(repeat):
        out = folder / f"out{parts}-{k}"
        t = time.perf_counter()
        p = subprocess.run([str(KITKB), "run", str(d / "init.ttl"), str(d / "goal.ttl"), "-o", str(out),
                            "--report", str(folder / f"report{k}.json")], capture_output=True, text=True,
                           cwd=folder)
        wall = time.perf_counter() - t
        stages = {m.group(1): float(m.group(2)) for m in map(_STAGE.match, p.stdout.splitlines()) if m}
        report = json.loads((folder / f"report{k}.json").read_text()) if p.returncode == 0 else {}
        summary = next((line.strip() for line in p.stdout.splitlines() if line.strip().startswith("execute:")), "")
        runs.append({"wall_s": round(wall, 3), "rc": p.returncode, "stages": stages,
                     "actions": report.get("actions"), "goal_holds": report.get("goal_holds"),
                     "summary": summary, "stderr": p.stderr[-2000:] if p.returncode else ""})
        print(f"kit {parts}: {wall:.2f} s rc {p.returncode} {stages}", flush=True)
    ok = [r for r in runs if r["rc"] == 0]
    med_stages = {s: round(statistics.median(r["stages"][s] for r in ok if s in r["stages"]), 3)
                  for s in (ok[0]["stages"] if ok else {})}
    return {"parts": parts, "runs": runs, "ok": len(ok), "median_s": round(statistics.median(r["wall_s"] for r in ok), 3)
            if ok else None, "stages": med_stages, "actions": ok[0]["actions"] if ok else None}


# --- report ------------------------------------------------------------------------------------------

def pct(a: int, b: int) -> str:
    return f"{a / b:.0%}" if b else "-"


def render(run: dict) -> str:
    m = run["machine"]
    lines = [f"## {SECTION}", "",
             "Command: `.venv/bin/python benchmarks/bench_execution.py` (raw figures, with every campaign "
             "run's injected faults and diagnoses, in `benchmarks/results/execution.json`).", "",
             f"Machine: {m['cpu']}, {m['cores']} cores, Python {m['python']}, SQLite {m['sqlite']}; run "
             f"{run['started']}" + (f", PostgreSQL {m['postgresql']} on loopback (a throwaway cluster, default "
                                    "settings)" if m.get("postgresql") else "")
             + f", 1-minute load average {m['load_average']} at the start (the machine is shared "
             "with other jobs: wall times are noisy).", ""]
    kept = run.get("kept")
    if kept:
        km = kept["machine"]
        lines[-2] += (f" The {', '.join(kept['parts'])} figures below are kept from the earlier run of {kept['started']}"
                      f" (commit `{kept['checkout'].get('commit', '?')}`, on {km.get('cpu')}"
                      + (f", PostgreSQL {km['postgresql']} on loopback" if km.get("postgresql") else "")
                      + f", load average {km.get('load_average')} at its start), before the change this run measures.")
    co = run.get("checkout", {})
    measured = [p for p in ("campaign", "cost", "kit") if p in run and p not in (kept or {}).get("parts", [])]
    if co and not measured:
        lines[-2] += (" This run measured only the comparison below, whose two commits ran from git worktrees "
                      "(the working tree's uncommitted changes were not measured).")
    elif co:
        lines[-2] += (f" Code: commit `{co['commit']}`" + (
            f" with uncommitted changes of {', '.join(f'`{f}`' for f in co['kb_changes'])} (measured as they were)."
            if co["kb_changes"] else "."))
    c = run.get("campaign")
    if c:
        tot = {k: sum(s[k] for s in c["by_kind"].values()) for k in
               ("runs", "injected", "need_detection", "detected", "correct", "wrong", "unmatched", "goal_holds",
                "replans", "crashes", "absorbed", "correct_stops")}
        scen = ", ".join(f"`{n}` ({a} actions)" for n, a in c["scenarios"].items())
        lines += [f"### Fault campaign: {c['runs']} seeded runs", "",
                  f"Scenarios: {scen}; the generated one has three spare parts per type. Run `s` (s = 0, 1, ...) "
                  f"of a kind uses scenario `s mod {len(c['scenarios'])}` and fault seed `s`; even runs inject the "
                  f"kind at {c['rate']} per eligible action (`KIND={c['rate']}`), odd runs once, at an eligible plan "
                  "action drawn from the seed (`KIND@i`). Each scenario is planned once; every run is "
                  f"`kb.execution.run_plan` in-process ({c['workers']} worker processes, {c['wall_s']:.0f} s for the "
                  "campaign).", "",
                  "Scoring, from each run's JSON report alone (`Run.report()`): a failure is matched to the latest "
                  "injected fault that names one of its objects (a part, kit or kit tray) at or before its action; "
                  "it is correct when its mode is allowed for the fault's kind (missed-grasp: `missed-grasp`; "
                  "dropped-part: `dropped-part` or `dropped-part-in-transit`; part-missing: "
                  "`part-missing-from-tray` or `parts-tray-empty`; wrong-sku: `wrong-sku`; defective-part: "
                  "`defective-part`; part-moved and kit-tray-moved: no failure while late binding finds the object, "
                  "else `part-missing-from-tray`, `kit-not-on-worktable` or `kittray-not-on-worktable`), wrong "
                  "otherwise, and unmatched (a false diagnosis) when no injection matches. Detection counts the "
                  "injections of the five kinds that always need it; moved objects are either absorbed by late "
                  "binding (no failure) or detected. A run that stops because no part of a SKU is left (no plan), "
                  "or for an operator after a correct diagnosis whose remediation asks for one, stops correctly.", "",
                  "| fault kind | runs | injected | detected | correct diagnoses | wrong | unmatched | kits completed "
                  "| stopped (correctly) | replans | crashes |",
                  "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
        for kind, s in c["by_kind"].items():
            if kind in MUST_DETECT:
                det = f"{s['detected']}/{s['need_detection']} ({pct(s['detected'], s['need_detection'])})"
            else:
                det = f"{s.get('detected_moved', 0)}, absorbed {s['absorbed']}"
            judged = s["correct"] + s["wrong"] + s["unmatched"]
            stops = sum(s["stopped"].values())
            lines.append(f"| {kind} | {s['runs']} | {s['injected']} | {det} | {s['correct']}/{judged} "
                         f"({pct(s['correct'], judged)}) | {s['wrong']} | {s['unmatched']} | {s['goal_holds']} "
                         f"| {stops} ({s['correct_stops']}) | {s['replans']} | {s['crashes']} |")
        judged = tot["correct"] + tot["wrong"] + tot["unmatched"]
        lines.append(f"| all | {tot['runs']} | {tot['injected']} | {tot['detected']}/{tot['need_detection']} "
                     f"({pct(tot['detected'], tot['need_detection'])}), absorbed {tot['absorbed']} | "
                     f"{tot['correct']}/{judged} ({pct(tot['correct'], judged)}) | {tot['wrong']} | {tot['unmatched']} | "
                     f"{tot['goal_holds']} | {sum(sum(s['stopped'].values()) for s in c['by_kind'].values())} "
                     f"({tot['correct_stops']}) | {tot['replans']} | {tot['crashes']} |")
        lines += ["", "Modes diagnosed, and why runs stopped:", ""]
        for kind, s in c["by_kind"].items():
            modes = ", ".join(f"{k} {v}" for k, v in sorted(s["modes"].items())) or "none"
            stops = ", ".join(f"{k} {v}" for k, v in sorted(s["stopped"].items())) or "none"
            lines.append(f"- {kind}: {modes}; stopped: {stops}; runs in which no fault took effect: "
                         f"{s['no_injection']}; faults on a part already rejected (no detection needed): {s['moot']}")
        bk = c["by_kind"]
        stops_parts = sum(v for s in bk.values() for k2, v in s["stopped"].items() if k2.startswith("no usable part"))
        lines += ["", "Reading the table: a missed grasp is seen by take-part's effect check and retried (up to 3 "
                  "times, the remediation's limit). The simulator drops a held part during its first sideways move, "
                  "i.e. in put-part's approach, so every dropped part is seen by put-part's precondition check "
                  f"(`dropped-part-in-transit`, {bk['dropped-part']['modes'].get('dropped-part-in-transit', 0)}); "
                  "`dropped-part` (seen right after take-part) does not happen in this simulator. A part shifted within "
                  "its tray is grasped where it now lies (late binding: absorbed); one moved out of its tray fails "
                  "take-part's precondition (`part-missing-from-tray`) and another part of its SKU is bound instead. "
                  f"A moved kit is always absorbed ({bk['kit-tray-moved']['absorbed']} of "
                  f"{bk['kit-tray-moved']['injected']}): put-part's place is computed from where the kit is seen now. "
                  "Defective parts are found by inspection before take-part, wrong-SKU parts by put-part's `part-sku` "
                  f"precondition (the sensor reports the SKU it sees). {stops_parts} runs stopped because no usable "
                  "part of a SKU was left in the parts trays (the scenarios have one to three spare parts per type, and "
                  "a rate of 0.3 per take-part hits several parts of a run): a correct outcome, counted as such."]
        every = all(s["correct"] == s["correct"] + s["wrong"] + s["unmatched"] for s in c["by_kind"].values())
        lines += ["", f"Goal (100% correct diagnoses for every kind): {'met' if every and not tot['crashes'] else 'NOT met'}."]
        rep = [r for r in c.get("replayed_empty_trays", []) if r["kind"] == "part-moved"]
        if rep:
            empty = [r for r in rep if not r["parts_in_tray"]]
            lines[-1] += (f" {len(rep)} of the wrong diagnoses are `parts-tray-empty` after part-moved faults, a mode the "
                          "issue's table lists for part-missing (the last part of a tray gone) but not for part-moved; "
                          f"replaying those runs in the simulator shows the tray really empty in {len(empty)} of "
                          f"{len(rep)} (" + "; ".join(f"`{r['scenario']}` seed {r['seed']}: {r['tray']} "
                                                      f"{'empty' if not r['parts_in_tray'] else 'holds ' + ', '.join(r['parts_in_tray'])}"
                                                      for r in rep) + "): earlier part-moved faults had knocked every "
                          "part of the SKU out of it. With `parts-tray-empty` allowed for part-moved when the tray is "
                          f"empty, the correct diagnoses are {tot['correct'] + len(empty)}/{judged}.")
        notes = run.get("notes", {}).get("campaign")
        if notes:
            lines += ["", notes]
        if c["anomalies"]:
            lines += ["", f"Runs worth a look ({len(c['anomalies'])}; all in the results file):", ""]
            for a in c["anomalies"][:25]:
                lines.append(f"- {a['kind']} on `{a['scenario']}`, seed {a['seed']}, `--faults {a['faults']}`: {a['why']}")
            if len(c["anomalies"]) > 25:
                lines.append(f"- ... and {len(c['anomalies']) - 25} more")
        lines.append("")
    sizes = run.get("cost")
    if sizes:
        first = next(iter(sizes.values()))
        lines += ["### Verification cost per action", "",
                  "Fault-free runs of generated kits (`kitkb scenario generate --parts N --kits 1 --seed 0`; "
                  + ", ".join(f"{n} parts: {v['plan_actions']} actions" for n, v in sizes.items())
                  + "), `kb.execution.run_plan` in one process; milliseconds per action, the executor's time split by "
                  "wrapping its methods from the benchmark (exclusive time: a part's calls minus the wrapped calls "
                  f"inside them; medians of {run['cost_repeat']} runs). Verification = sensor + belief (poses from the "
                  "sensor) + predicate checks + commit (+ the store's pose updates and stable-state commit).", ""]
        names = [("sensor", "sensor (simulated: a ground-truth query per focus class)"),
                 ("belief", "belief: poses from the observations, focus of attention"),
                 ("store: pose updates", "store: pose updates"),
                 ("checks", "predicate checks (preconditions, effects)"), ("commit", "commit (stable state)"),
                 ("store: commit", "store: stable-state commit"), ("store: records", "store: run records"),
                 ("verification", "**verification**"),
                 ("targets", "late-bound targets, CRCL programs"), ("robot", "simulated robot (CRCL), fault injection"),
                 ("inspect", "inspection"), ("goal", "goal check at the end"),
                 ("total", "**total: the executor's loop / actions**")]
        label = {"memory": "in memory", "sqlite": "SQLite", "postgresql": "PostgreSQL"}
        cols = [(n, b) for n, v in sizes.items() for b in ("memory", "sqlite", "postgresql")
                if "ms_per_action" in v["backends"].get(b, {})]
        lines += ["| ms per action | " + " | ".join(
            f"{n} parts, {label[b]}" + (" *" if sizes[n]["backends"][b].get("workaround") else "") for n, b in cols) + " |",
                  "|---|" + "---:|" * len(cols)]
        names.insert(-1, ("other", "other (the loop itself, diagnosis and replanning when they happen)"))
        for key, text in names:
            cells = [f"{sizes[n]['backends'][b]['ms_per_action'].get(key, 0.0):.2f}" for n, b in cols]
            if any(c != "0.00" for c in cells) or key in ("verification", "total"):
                lines.append(f"| {text} | " + " | ".join(cells) + " |")
        pend = sorted({f"{label[b]}: {v['backends'][b]['pending']}" for v in sizes.values()
                       for b in ("sqlite", "postgresql") if "pending" in v["backends"].get(b, {})})
        failed = sorted({(b, v["backends"][b]["error"]) for v in sizes.values() for b in ("sqlite", "postgresql")
                         if "error" in v["backends"].get(b, {})})
        for b, err in failed:
            where = [n for n, v in sizes.items() if v["backends"].get(b, {}).get("error") == err]
            redo = all(sizes[n]["backends"][b].get("workaround") for n in where)
            lines += ["", f"{'* ' if redo else ''}The run with the {label[b]} store FAILED at {', '.join(map(str, where))} parts: "
                      f"`{err}`" + (" (a fault-free run; it fails at the first action whose effects hold with no "
                                    "pose changed: the store commits one stable state per action, and kb.world's "
                                    "PostgreSQL batch update writes an empty `VALUES ()` for an empty batch). The "
                                    "column is measured with a workaround in the benchmark: the store's commit skipped "
                                    "when no pose changed." if redo else ".")]
        goals = [(n, v["backends"]["sqlite"]["ms_per_action"]["verification"]) for n, v in sizes.items()
                 if "ms_per_action" in v["backends"].get("sqlite", {})]
        mem = [(n, v["backends"]["memory"]["ms_per_action"]["verification"]) for n, v in sizes.items()
               if "ms_per_action" in v["backends"].get("memory", {})]
        if goals:
            verdict = "; ".join(f"{n} parts: {'met' if g < 5 else 'NOT met'} ({g:.2f} ms)" for n, g in goals)
        else:
            verdict = ("pending: the store is not there yet; in memory the verification costs "
                       + ", ".join(f"{g:.1f} ms at {n} parts" for n, g in mem) + " per action, "
                       + ("already over 5 ms" if any(g >= 5 for _, g in mem) else "under 5 ms") + " before any database work")
        lines += ["", f"Goal (verification under 5 ms per action on SQLite): {verdict}."
                  + (" Not measured: " + "; ".join(pend) + "." if pend else "")]
        small, big = next(iter(sizes)), list(sizes)[-1]
        ms0, ms1 = sizes[small]["backends"]["memory"]["ms_per_action"], sizes[big]["backends"]["memory"]["ms_per_action"]
        sb0, sb1 = ms0["sensor"] + ms0["belief"], ms1["sensor"] + ms1["belief"]
        text = (f"Where the time goes: before and after every action (and after its approach move) the executor "
                "senses every object of the classes the action's predicates search; the kitting predicates quantify "
                "over solid objects, so most actions sense the whole cell and the belief takes every observation. "
                f"Sensor + belief grow with the cell: {sb0:.1f} ms per action at {small} parts, {sb1:.1f} ms at {big} "
                f"parts ({sb1 / ms1['verification']:.0%} of the verification there); the predicate checks grow "
                f"less ({ms0['checks']:.1f} -> {ms1['checks']:.1f} ms: each atom is read from predicate tables "
                "over the scene, rebuilt after every sensing that changed a pose). The simulated sensor is part of the "
                "figure because the issue counts the sensor; a real cell's sensor has its own cost.")
        for b in ("sqlite", "postgresql"):
            v = sizes[big]["backends"].get(b, {})
            if "ms_per_action" in v:
                m = v["ms_per_action"]
                text += (f" The {label[b]} store adds, at {big} parts, {m.get('store: pose updates', 0):.2f} ms of pose "
                         f"updates, {m.get('store: commit', 0):.2f} ms of stable-state commit and "
                         f"{m.get('store: records', 0):.2f} ms of run records per action; loading the initial state and "
                         f"the domain into it first takes {v['prepare_s']:.1f} s, once per run.")
        lines += ["", text]
        notes = run.get("notes", {}).get("cost")
        if notes:
            lines += ["", notes]
        lines.append("")
    if run.get("compare"):
        lines += render_compare(run["compare"], run.get("checkout", {})) + [""]
    e = run.get("kit")
    if e:
        lines += [f"### A {e['parts']}-part kit end to end", ""]
        st = e["stages"]
        stage_text = ", ".join(f"{s} {v:.2f} s" for s, v in st.items())
        lines += [f"`kitkb run DIR/init.ttl DIR/goal.ttl -o OUT` on `kitkb scenario generate --parts {e['parts']} "
                  f"--kits 1 --seed 0` ({e['actions']} actions, no faults; the run store on SQLite, `kitkb run`'s "
                  "default `OUT/<scenario>/world.sqlite`), whole process, median of "
                  f"{len(e['runs'])} runs ({e['ok']} succeeded): **{e['median_s']} s**; stages (medians, as the "
                  f"command prints them): {stage_text}.", ""]
        if e["median_s"] is not None:
            ex = st.get("execute", 0.0)
            rest = e["median_s"] - ex
            lines.append(f"Goal (under 10 s): {'met' if e['median_s'] < 10 else 'NOT met'}. Executing the "
                         f"{e['actions']} actions with verification takes {ex:.1f} s ({ex / e['median_s']:.0%}; "
                         f"{ex / e['actions'] * 1e3:.0f} ms per action, the simulated cell included); everything else "
                         f"(start-up, validation, PDDL, planning, geometry check, world model) {rest:.1f} s"
                         + (f", so 10 s needs the execution under {(10 - rest) / e['actions'] * 1e3:.0f} ms per action."
                            if e["median_s"] >= 10 and rest < 10 else ".")
                         + f" The runs took {min(r['wall_s'] for r in e['runs']):.2f}-"
                         f"{max(r['wall_s'] for r in e['runs']):.2f} s.")
            same = (sizes or {}).get(e["parts"]) or (sizes or {}).get(str(e["parts"]))
            sq = (same or {}).get("backends", {}).get("sqlite", {}).get("ms_per_action")
            if sq:
                sim = sq.get("sensor", 0.0) + sq.get("robot", 0.0)
                lines[-1] += (f" In the cost table's run of the same kit with the SQLite store, the simulated cell (its "
                              f"sensor and robot) takes {sim:.1f} of the {sq['total']:.1f} ms per action "
                              f"({sim / sq['total']:.0%}), kitkb's verification without the sensor "
                              f"{sq['verification'] - sq.get('sensor', 0.0):.1f} ms.")
        notes = run.get("notes", {}).get("kit")
        if notes:
            lines += ["", notes]
        lines.append("")
    return "\n".join(lines).rstrip("\n") + "\n"


def write_doc(section: str) -> None:
    """Replace this benchmark's section of docs/benchmarks.md (or append it)."""
    common.write_doc(SECTION, section)


def save(run: dict) -> None:
    """Append to results/execution.json; older runs keep their summaries, not every run's report."""
    old = json.loads(RESULTS.read_text()) if RESULTS.exists() else []
    for r in old:
        if r.get("campaign"):
            r["campaign"].pop("results", None)
    RESULTS.parent.mkdir(exist_ok=True)
    RESULTS.write_text(json.dumps(old + [run], indent=1, default=str) + "\n")


def measure(run: dict, args: argparse.Namespace, folder: Path) -> None:
    """The parts asked for, in ``folder``."""
    if "campaign" in args.parts:
        run["campaign"] = campaign(scenarios(folder), args.runs_per_kind, args.rate, args.workers)
        for kind, s in run["campaign"]["by_kind"].items():
            print(kind, s, flush=True)
    if "cost" in args.parts:
        run["cost"] = {}
        for n in args.cost_parts:
            d = folder / f"cost{n}"
            subprocess.run([str(KITKB), "-q", "scenario", "generate", "--parts", str(n), "--kits", "1",
                            "--seed", "0", "-o", str(d)], check=True)
            backends = [("memory", None), ("sqlite", None)] + ([("postgresql", args.pg)] if args.pg else [])
            if args.pg and "postgresql" not in run["machine"]:
                run["machine"]["postgresql"] = pg_version(args.pg)
            run["cost"][n] = cost(d / "init.ttl", d / "goal.ttl", args.cost_repeat, backends, folder)
            if not args.pg:
                run["cost"][n]["backends"].setdefault("postgresql", {"pending": "no PostgreSQL server (KITKB_PG_URL / --pg)"})
    if "kit" in args.parts:
        run["kit"] = kit_end_to_end(args.kit_parts, args.repeat, folder)
    if "compare" in args.parts:
        if not args.baseline:
            raise SystemExit("--parts compare needs --baseline DIR (a git worktree of the commit to compare with)")
        run["compare"] = compare(args, folder)


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--parts", nargs="*", default=["campaign", "cost", "kit"],
                    choices=["campaign", "cost", "kit", "compare"], help="which parts to run")
    ap.add_argument("--runs-per-kind", type=int, default=30)
    ap.add_argument("--rate", type=float, default=0.3)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--repeat", type=int, default=3, help="runs of the whole kit (median)")
    ap.add_argument("--cost-repeat", type=int, default=5, help="runs per cost figure (median)")
    ap.add_argument("--cost-parts", type=int, nargs="+", default=[10, 40, 160],
                    help="parts of the fault-free kits of the cost figures")
    ap.add_argument("--kit-parts", type=int, default=160)
    ap.add_argument("--baseline", help="compare: a checkout (git worktree) of the commit to compare with")
    ap.add_argument("--candidate", help="compare: a checkout of the new code (default: this one)")
    ap.add_argument("--cost-repeat-at", nargs="*", default=[], metavar="PARTS:RUNS",
                    help="compare: runs of each at PARTS parts (default --cost-repeat)")
    ap.add_argument("--cost-actions", nargs="*", default=[], metavar="PARTS:ACTIONS",
                    help="compare: time only the first ACTIONS actions of the PARTS-part kit's plan")
    ap.add_argument("--keep", action="store_true",
                    help="keep the earlier run's campaign, cost and kit figures in the section (a run of other parts)")
    ap.add_argument("--cost-one", help=argparse.SUPPRESS)  # a child process of --parts compare
    ap.add_argument("--pg", default=os.environ.get("KITKB_PG_URL"), help="PostgreSQL URL for the store (wiped)")
    ap.add_argument("--notes", help="JSON file of notes per part (campaign, cost, kit) added to the section")
    ap.add_argument("--no-doc", action="store_true", help="do not rewrite docs/benchmarks.md")
    ap.add_argument("--render", action="store_true",
                    help="measure nothing: rewrite the docs section from the latest run in the results file")
    args = ap.parse_args(argv)
    if args.cost_one:
        print(json.dumps(cost_one(json.loads(args.cost_one)), default=str))
        return
    if args.render:
        section = render(json.loads(RESULTS.read_text())[-1])
        write_doc(section)
        print(section)
        return
    run: dict[str, Any] = {"started": dt.datetime.now(dt.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
                           "machine": machine(), "checkout": checkout(),
                           "repeat": args.repeat, "cost_repeat": args.cost_repeat}
    if args.notes:
        run["notes"] = json.loads(Path(args.notes).read_text())
    if args.keep and RESULTS.exists():  # the figures this run does not measure, from the latest run
        earlier = json.loads(RESULTS.read_text())[-1]
        for part in ("campaign", "cost", "kit"):
            if part not in args.parts and part in earlier:
                run[part] = earlier[part]
                kept = earlier.get("kept") or {}  # kept there too: the run that measured it
                origin = kept if part in kept.get("parts", ()) else {
                    "started": earlier.get("started"), "checkout": earlier.get("checkout", {}),
                    "machine": earlier.get("machine", {})}
                run.setdefault("kept", dict(origin, parts=[]))["parts"].append(part)
        if "cost" not in args.parts and "cost" in earlier:
            run["cost_repeat"] = earlier.get("cost_repeat")
    with tempfile.TemporaryDirectory(prefix="kitkb-bench-exec-") as tmp:
        folder = Path(tmp)
        os.chdir(folder)  # see private_cwd (the kitkb processes of the "kit" part run here too)
        try:
            measure(run, args, folder)
        finally:
            os.chdir(ROOT)
    save(run)
    section = render(run)
    if not args.no_doc:
        write_doc(section)
    print(section)


if __name__ == "__main__":
    main()
