"""A campaign's rows summed up: kits built, each metric's mean / median / 95th percentile,
failures by mode, recoveries; the rows as comparable data and as a text table.

A row is one trial's report (``kitkb run``'s, :meth:`kb.execution.Run.report`) with its
``trial`` facts; fields a report does not have (an older report without ``metrics`` or
``kits``) are left out of the figures, not guessed.
"""

from __future__ import annotations

from collections import Counter
from typing import Any, Iterable, TextIO

import numpy as np

#: keys whose values are wall-clock seconds (left out when rows are compared)
TIMING_KEYS = frozenset({"time_s", "plan_time_s", "replan_time_s", "receipt_to_first_command_s", "t", "seconds",
                         "wall_s", "trials_per_s"})


def comparable(data: Any) -> Any:
    """``data`` without the values the clock decides (:data:`TIMING_KEYS`, at any depth): what
    the same campaign seed must give again, whatever ran it."""
    if isinstance(data, dict):
        return {k: comparable(v) for k, v in data.items() if k not in TIMING_KEYS}
    if isinstance(data, list):
        return [comparable(v) for v in data]
    return data


def kits_of(row: dict[str, Any]) -> tuple[int, int]:
    """(kits built, kits asked) of a trial: from the kit scores (a kit with every point built),
    else from whether the goal holds."""
    kits = row.get("kits")
    if kits:
        return sum(1 for k in kits if k.get("score") == k.get("max_score")), len(kits)
    asked = len(row.get("trial", {}).get("designs") or [None])
    return (asked if row.get("goal_holds") else 0), asked


def figures(row: dict[str, Any]) -> dict[str, float]:
    """A trial's numbers, by name: the run's counts, its execution and static metrics, its kit
    score (the fraction of the points built) and the trial's own times."""
    out: dict[str, float] = {}
    trial = row.get("trial", {})
    for key in ("time_s", "receipt_to_first_command_s"):
        if isinstance(trial.get(key), (int, float)):
            out[f"trial.{key}"] = float(trial[key])
    if not row.get("executed", False):
        return out
    for key in ("actions", "checks", "replans"):
        if isinstance(row.get(key), (int, float)):
            out[key] = float(row[key])
    out["failures"] = float(len(row.get("failures") or []))
    metrics = row.get("metrics") or {}
    for key, value in metrics.items():
        if isinstance(value, bool) or key in out:
            continue
        if isinstance(value, (int, float)):
            out[f"metrics.{key}"] = float(value)
        elif key == "static" and isinstance(value, dict):
            out.update({f"static.{k}": float(v) for k, v in value.items() if isinstance(v, (int, float))})
    kits = row.get("kits") or []
    scored = [k["score"] / k["max_score"] for k in kits if k.get("max_score")]
    if scored:
        out["kit_score"] = float(np.mean(scored))
    return out


def _stats(values: list[float]) -> dict[str, float]:
    a = np.asarray(values, float)
    return {"n": len(values), "mean": round(float(a.mean()), 6), "median": round(float(np.median(a)), 6),
            "p95": round(float(np.percentile(a, 95)), 6)}


def summarize(rows: Iterable[dict[str, Any]]) -> dict[str, Any]:
    """The campaign's summary over its trial rows."""
    rows = list(rows)
    built = asked = 0
    modes: Counter[str] = Counter()
    strategies: Counter[str] = Counter()
    recovered: Counter[str] = Counter()
    injected: Counter[str] = Counter()
    series: dict[str, list[float]] = {}
    for row in rows:
        b, a = kits_of(row)
        built, asked = built + b, asked + a
        for f in row.get("failures") or []:
            modes[str(f.get("mode"))] += 1
            strategies[str(f.get("recovery"))] += 1
        recovered.update((row.get("metrics") or {}).get("recovered_by_mode") or {})
        injected.update(str(x.get("kind")) for x in row.get("injected") or [])
        for name, value in figures(row).items():
            series.setdefault(name, []).append(value)
    return {
        "trials": len(rows),
        "goal_holds": sum(1 for r in rows if r.get("goal_holds")),
        "kits_built": built, "kits": asked,
        "errors": sum(1 for r in rows if r.get("trial", {}).get("error")),
        "metrics": {name: _stats(values) for name, values in sorted(series.items())},
        "failures_by_mode": dict(sorted(modes.items())),
        "recoveries": {"by_strategy": dict(sorted(strategies.items())),
                       "recovered_by_mode": dict(sorted(recovered.items())),
                       "recovered": sum(recovered.values()),
                       "failures": sum(modes.values())},
        "injected_by_kind": dict(sorted(injected.items())),
    }


def brief(row: dict[str, Any]) -> dict[str, Any]:
    """A trial's row as the command prints it (one line of the table, one object of the JSON)."""
    trial = row.get("trial", {})
    built, asked = kits_of(row)
    metrics = row.get("metrics") or {}
    kits = row.get("kits") or []
    return {
        "index": trial.get("index"), "seed": trial.get("seed"), "design": trial.get("design"),
        "goal_holds": bool(row.get("goal_holds")), "kits_built": built, "kits": asked,
        "score": sum(k.get("score", 0) for k in kits) if kits else None,
        "max_score": sum(k.get("max_score", 0) for k in kits) if kits else None,
        "actions": row.get("actions"), "failures": len(row.get("failures") or []),
        "recovered": metrics.get("recovered"), "stopped": row.get("stopped"),
        "receipt_to_first_command_s": trial.get("receipt_to_first_command_s"),
        "time_s": trial.get("time_s"), "error": trial.get("error"),
    }


def write_table(rows: list[dict[str, Any]], summary: dict[str, Any], stream: TextIO, *, receipt: bool = False) -> None:
    """The rows (one line a trial) and the summary, as text."""
    head = f"{'trial':>5} {'seed':>10}  {'kits':>5} {'score':>7} {'actions':>7} {'fail':>4} {'recov':>5}"
    head += f" {'receipt s':>9}" if receipt else ""
    print(head + f" {'time s':>7}  design / outcome", file=stream)
    for row in rows:
        b = brief(row)
        score = f"{b['score']}/{b['max_score']}" if b["score"] is not None else "-"
        line = (f"{b['index']:>5} {b['seed']:>10}  {b['kits_built']:>2}/{b['kits']:<2} {score:>7} "
                f"{_n(b['actions']):>7} {b['failures']:>4} {_n(b['recovered']):>5}")
        if receipt:
            line += f" {_n(b['receipt_to_first_command_s'], '.3f'):>9}"
        outcome = b["error"] or b["stopped"] or ""
        line += f" {_n(b['time_s'], '.2f'):>7}  {b['design']}" + (f": {outcome}" if outcome else "")
        print(line, file=stream)
    _summary(summary, stream)


def _summary(s: dict[str, Any], stream: TextIO) -> None:
    print(f"\n{s['trials']} trials: kits built {s['kits_built']} of {s['kits']}, goal held in {s['goal_holds']}, "
          f"errors {s['errors']}", file=stream)
    if s["metrics"]:
        width = max(len(n) for n in s["metrics"])
        print(f"{'metric':<{width}} {'mean':>12} {'median':>12} {'p95':>12}", file=stream)
        for name, st in s["metrics"].items():
            print(f"{name:<{width}} {st['mean']:>12.4g} {st['median']:>12.4g} {st['p95']:>12.4g}", file=stream)
    for title, counts in (("injected", s["injected_by_kind"]), ("failures by mode", s["failures_by_mode"]),
                          ("recovered by mode", s["recoveries"]["recovered_by_mode"]),
                          ("recoveries by strategy", s["recoveries"]["by_strategy"])):
        if counts:
            print(f"{title}: " + ", ".join(f"{k} {v}" for k, v in counts.items()), file=stream)


def _n(value: Any, fmt: str = "") -> str:
    return "-" if value is None else format(value, fmt)
