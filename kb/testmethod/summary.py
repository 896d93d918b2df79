"""A campaign's rows summed up: kits built, kits buildable and completion by the oracle of what was
buildable (:mod:`kb.metrics.oracle`), each metric's mean / median / 95th percentile,
failures by mode, recoveries, detection quality (:mod:`kb.execution.quality`: faults injected,
detected, diagnosed right and wrong, missed, false alarms), and for a noise sweep the detection
quality per level; the rows as comparable data and as a text table.

A row is one trial's report (``kitkb run``'s, :meth:`kb.execution.Run.report`) with its
``trial`` facts; fields a report does not have (an older report without ``metrics`` or
``kits``) are left out of the figures, not guessed.
"""

from __future__ import annotations

from collections import Counter
from typing import Any, Iterable, TextIO

import numpy as np

from kb.execution.quality import score_detection

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


def buildable_of(row: dict[str, Any]) -> tuple[int, int, float] | None:
    """(kits built, kits buildable, completion) of a trial by the oracle of what was buildable
    (its report's ``oracle``, :mod:`kb.metrics.oracle`); None when the run has none (a cell
    without ground truth, an older report, a trial not executed)."""
    oracle = row.get("oracle") or {}
    built, able, done = oracle.get("kits_built"), oracle.get("kits_buildable"), oracle.get("completion")
    if not all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in (built, able, done)):
        return None
    return int(built), int(able), float(done)


def completion(rows: Iterable[dict[str, Any]]) -> dict[str, Any]:
    """The campaign's completion by the oracle: ``runs`` with one, their ``kits_buildable`` and
    ``kits_built`` summed, ``overall`` = built / buildable over them (1.0 when nothing was
    buildable), ``mean`` of the runs' completions, ``complete`` runs (completion 1.0), and
    ``unknown`` trials without an oracle; ``overall`` and ``mean`` null when no run has one."""
    rows = list(rows)
    found = [b for b in map(buildable_of, rows) if b is not None]
    built, able = sum(b for b, _, _ in found), sum(a for _, a, _ in found)
    return {"runs": len(found), "kits_buildable": able, "kits_built": built,
            "overall": (round(built / able, 6) if able else 1.0) if found else None,
            "mean": round(float(np.mean([c for _, _, c in found])), 6) if found else None,
            "complete": sum(1 for _, _, c in found if c >= 1.0), "unknown": len(rows) - len(found)}


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
        elif key in PAPER_KEYS and isinstance(value, dict):  # the first paper's §IV-B (kb.metrics.robustness)
            out.update({f"metrics.{key}.{k}": float(v) for k, v in _flat(value).items()})
    kits = row.get("kits") or []
    scored = [k["score"] / k["max_score"] for k in kits if k.get("max_score")]
    if scored:
        out["kit_score"] = float(np.mean(scored))
    return out


#: the nested §IV-B metrics of a run (kb.metrics.robustness) a summary pools and keeps per trial
PAPER_KEYS = ("transporting", "robustness", "failure_classes")


def _flat(value: dict[str, Any], prefix: str = "") -> dict[str, float]:
    out: dict[str, float] = {}
    for k, v in value.items():
        if isinstance(v, dict):
            out.update(_flat(v, f"{prefix}{k}."))
        elif isinstance(v, (int, float)) and not isinstance(v, bool):
            out[f"{prefix}{k}"] = float(v)
    return out


def paper_metrics(rows: Iterable[dict[str, Any]]) -> dict[str, Any]:
    """The first paper's §IV-B metrics over the trials (kb.metrics.robustness): parts delivered
    and transported, each stage's failures and attempts pooled (and their ratio), failures by
    class, operator interventions, and the distinct failure modes recovered from in any trial."""
    sums: Counter[str] = Counter()
    seen: set[str] = set()
    got: set[str] = set()
    for row in rows:
        m = row.get("metrics") or {}
        sums.update({k: v for k, v in _flat({k: m[k] for k in PAPER_KEYS if isinstance(m.get(k), dict)}).items()
                     if not k.endswith(("rate", "per_attempt"))})
        seen.update(str(f.get("mode")) for f in row.get("failures") or [])
        got.update((m.get("recovered_by_mode") or {}).keys())
    def ratio(a: str, b: str) -> float | None:
        return round(sums[a] / sums[b], 6) if sums[b] else None
    stages = {s: {"failures": int(sums[f"robustness.{s}.failures"]), "attempts": int(sums[f"robustness.{s}.attempts"]),
                  "per_attempt": ratio(f"robustness.{s}.failures", f"robustness.{s}.attempts")}
              for s in ("detection", "approach", "manipulation")}
    return {"transporting": {"parts_delivered": int(sums["transporting.parts_delivered"]),
                             "parts_transported": int(sums["transporting.parts_transported"]),
                             "dropped": int(sums["transporting.dropped"]),
                             "rate": ratio("transporting.parts_delivered", "transporting.parts_transported")},
            "robustness": {**stages, "operator_interventions": int(sums["robustness.operator_interventions"])},
            "failure_classes": {c: int(sums[f"failure_classes.{c}"]) for c in ("precondition", "action", "unattributable")},
            "failure_modes": len(seen), "failure_modes_recovered": len(got & seen)}


def _stats(values: list[float]) -> dict[str, float]:
    a = np.asarray(values, float)
    return {"n": len(values), "mean": round(float(a.mean()), 6), "median": round(float(np.median(a)), 6),
            "p95": round(float(np.percentile(a, 95)), 6)}


def summarize(rows: Iterable[dict[str, Any]], *, sweep: str | None = None, base: str | None = None,
              kinds: Any = None) -> dict[str, Any]:
    """The campaign's summary over its trial rows; ``sweep``: the campaign's ``--noise-sweep``
    (over ``base``, its ``--sensor-noise``), whose levels get their detection quality;
    ``kinds``: the fault kinds the detection quality is judged by (the campaign's domain's
    :class:`kb.model.faults.FaultKinds`; None: the shipped domain's)."""
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
        "goal_unmet": goal_unmet(rows),
        "kits_built": built, "kits": asked,
        "kits_buildable": sum(b[1] for b in map(buildable_of, rows) if b is not None),
        "completion": completion(rows),
        "errors": sum(1 for r in rows if r.get("trial", {}).get("error")),
        "metrics": {name: _stats(values) for name, values in sorted(series.items())},
        "failures_by_mode": dict(sorted(modes.items())),
        "repeated_diagnoses": repeated_diagnoses(rows),
        "recoveries": {"by_strategy": dict(sorted(strategies.items())),
                       "recovered_by_mode": dict(sorted(recovered.items())),
                       "recovered": sum(recovered.values()),
                       "failures": sum(modes.values())},
        "injected_by_kind": dict(sorted(injected.items())),
        "paper": paper_metrics(rows),  # the first paper's §IV-B, pooled
        "detection": score_detection(rows, kinds).as_dict(),
        **({"sweep": sweep_summary(rows, sweep, base, kinds)} if sweep else {}),
    }


#: how a swept key is shown: (unit, SI value -> shown value)
SHOWN = {"length": ("mm", 1e3), "angle": ("deg", 180 / np.pi), "rate": ("%", 100.0)}


def sweep_summary(rows: list[dict[str, Any]], sweep: str, base: str | None = None, kinds: Any = None) -> dict[str, Any]:
    """Detection quality per level of a noise sweep: ``key`` (the swept noise), ``unit``,
    ``levels``: per level its ``value`` (in ``unit``), ``noise`` (the sensor, spelled as
    ``--sensor-noise``), the runs' kits built, and :func:`~kb.execution.quality.score_detection`
    of its rows (injected, detected, diagnosed right and wrong, missed, false alarms, their
    rates; ``false_alarm_count``: the false alarms of every mode)."""
    from kb.testmethod.methods import sweep_key, sweep_levels, sweep_values
    name, kind = sweep_key(sweep)
    unit, scale = SHOWN[kind]
    by_level: dict[int, list[dict[str, Any]]] = {}
    for row in rows:
        level = (row.get("trial", {}).get("sweep") or {}).get("level")
        if isinstance(level, int):
            by_level.setdefault(level, []).append(row)
    levels = []
    for level, (noise, value) in enumerate(zip(sweep_levels(sweep, base), sweep_values(sweep))):
        group = by_level.get(level, [])
        quality = score_detection(group, kinds)
        built = [kits_of(r) for r in group]
        levels.append({"level": level, "value": round(value * scale, 9), "noise": noise.text(),
                       "kits_built": sum(b for b, _ in built), "kits": sum(a for _, a in built),
                       **quality.as_dict(), "false_alarm_count": quality.false_alarm_count})
    return {"key": name, "unit": unit, "sweep": sweep, "base": base, "levels": levels}


def repeated_diagnoses(rows: Iterable[dict[str, Any]]) -> dict[str, Any]:
    """Diagnoses of an event already diagnosed (issue 29, one fault one diagnosis; each run's
    report counts them, kb.execution.recovery): the total, the trials with one, and per mode of
    the second diagnosis. A row without the count (an older report) adds none."""
    total, trials, by_mode = 0, 0, Counter()
    for row in rows:
        n = int(row.get("repeated_diagnoses") or 0)
        total, trials = total + n, trials + (1 if n else 0)
        by_mode.update(str(r.get("again", {}).get("mode")) for r in row.get("repeated") or [])
    return {"total": total, "trials": trials, "by_mode": dict(sorted(by_mode.items()))}


def goal_unmet(rows: Iterable[dict[str, Any]]) -> dict[str, int]:
    """Per goal predicate (or goal count's function), the number of trials whose run ended with
    an atom of it not holding (the reports' ``goal_unmet``: every goal fact is a goal, so a
    trial may build its kits and still leave, say, a part on the work table)."""
    out: Counter[str] = Counter()
    for row in rows:
        out.update({str(atom).split("(", 1)[0] for atom in row.get("goal_unmet") or []})
    return dict(sorted(out.items()))


def brief(row: dict[str, Any]) -> dict[str, Any]:
    """A trial's row as the command prints it (one line of the table, one object of the JSON)."""
    trial = row.get("trial", {})
    built, asked = kits_of(row)
    metrics = row.get("metrics") or {}
    kits = row.get("kits") or []
    return {
        "index": trial.get("index"), "seed": trial.get("seed"), "design": trial.get("design"),
        "goal_holds": bool(row.get("goal_holds")), "goal_unmet": list(row.get("goal_unmet") or []),
        "kits_built": built, "kits": asked,
        "kits_buildable": row.get("kits_buildable"), "completion": row.get("completion"),
        "score": sum(k.get("score", 0) for k in kits) if kits else None,
        "max_score": sum(k.get("max_score", 0) for k in kits) if kits else None,
        "actions": row.get("actions"), "failures": len(row.get("failures") or []),
        "recovered": metrics.get("recovered"), "stopped": row.get("stopped"),
        "receipt_to_first_command_s": trial.get("receipt_to_first_command_s"),
        "time_s": trial.get("time_s"), "error": trial.get("error"),
        **({"noise": trial["noise"]} if "noise" in trial else {}),
        **({"level": trial["sweep"].get("level")} if isinstance(trial.get("sweep"), dict) else {}),
    }


def write_table(rows: list[dict[str, Any]], summary: dict[str, Any], stream: TextIO, *, receipt: bool = False) -> None:
    """The rows (one line a trial) and the summary, as text."""
    head = f"{'trial':>5} {'seed':>10}  {'kits':>5} {'score':>7} {'actions':>7} {'fail':>4} {'recov':>5}"
    head += f" {'receipt s':>9}" if receipt else ""
    noisy = any("noise" in (r.get("trial") or {}) for r in rows)
    print(head + f" {'time s':>7}  design" + (" @ noise" if noisy else "") + " / outcome", file=stream)
    for row in rows:
        b = brief(row)
        score = f"{b['score']}/{b['max_score']}" if b["score"] is not None else "-"
        line = (f"{b['index']:>5} {b['seed']:>10}  {b['kits_built']:>2}/{b['kits']:<2} {score:>7} "
                f"{_n(b['actions']):>7} {b['failures']:>4} {_n(b['recovered']):>5}")
        if receipt:
            line += f" {_n(b['receipt_to_first_command_s'], '.3f'):>9}"
        outcome = b["error"] or b["stopped"] or (f"goal unmet: {', '.join(b['goal_unmet'])}" if b["goal_unmet"] else "")
        line += f" {_n(b['time_s'], '.2f'):>7}  {b['design']}" + (f" @ {b['noise']}" if "noise" in b else "")
        line += f": {outcome}" if outcome else ""
        print(line, file=stream)
    _summary(summary, stream)


def _summary(s: dict[str, Any], stream: TextIO) -> None:
    unmet = ", ".join(f"{name} {n}" for name, n in (s.get("goal_unmet") or {}).items())
    print(f"\n{s['trials']} trials: kits built {s['kits_built']} of {s['kits']}, goal held in {s['goal_holds']}"
          + (f" (unmet: {unmet})" if unmet else "") + f", errors {s['errors']}", file=stream)
    done = s.get("completion") or {}
    if done.get("runs"):
        print(f"completion: {done['overall']:.4f} overall (kits built {done['kits_built']} of "
              f"{done['kits_buildable']} buildable), mean {done['mean']:.4f} over {done['runs']} run(s), "
              f"{done['complete']} complete" + (f", {done['unknown']} without an oracle" if done["unknown"] else ""),
              file=stream)
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
    rep = s.get("repeated_diagnoses") or {}
    if rep:
        print(f"repeated diagnoses: {rep['total']}" + (f" in {rep['trials']} trial(s) ("
              + ", ".join(f"{k} {v}" for k, v in rep["by_mode"].items()) + ")" if rep["total"] else ""), file=stream)
    if s.get("detection"):
        print(_detection_line(s["detection"]), file=stream)
    if s.get("sweep"):
        write_sweep(s["sweep"], stream)


def _detection_line(d: dict[str, Any]) -> str:
    t = d["total"]
    alarms = sum(d["false_alarms"].values())
    per = d["false_alarms_per_10k_actions"]
    line = (f"detection: {t['injected']} injected, {t['detected']} detected, {t['diagnosed_right']} diagnosed right, "
            f"{t['diagnosed_wrong']} wrong, {t['missed']} missed; {alarms} false alarm(s) in {d['actions']} actions")
    line += f" ({per:.3g} per 10,000)" if per is not None else ""
    return line + (f"; detection rate {100 * d['detection']:.1f}%" if d["detection"] is not None else "")


SWEEP_COLUMNS = ("runs", "actions", "kits built", "injected", "detected", "right", "wrong", "missed", "false alarms",
                 "per 10k", "detection %")


def sweep_rows(sweep: dict[str, Any]) -> list[list[Any]]:
    """The per-level table of a sweep summary (:func:`sweep_summary`): the value and the noise,
    then :data:`SWEEP_COLUMNS`."""
    out = []
    for lv in sweep["levels"]:
        t = lv["total"]
        out.append([lv["value"], lv["noise"], lv["runs"], lv["actions"], f"{lv['kits_built']}/{lv['kits']}",
                    t["injected"], t["detected"], t["diagnosed_right"], t["diagnosed_wrong"], t["missed"],
                    lv["false_alarm_count"],
                    None if lv["false_alarms_per_10k_actions"] is None else round(lv["false_alarms_per_10k_actions"], 2),
                    None if lv["detection"] is None else round(100 * lv["detection"], 1)])
    return out


def write_sweep(sweep: dict[str, Any], stream: TextIO) -> None:
    """A sweep's detection quality per level, as a text table."""
    print(f"\ndetection quality by {sweep['key']} noise ({sweep['sweep']}):", file=stream)
    rows = [[_n(v) for v in row] for row in sweep_rows(sweep)]
    head = [f"{sweep['key']} {sweep['unit']}", "noise", *SWEEP_COLUMNS]
    widths = [max(len(h), *(len(r[i]) for r in rows)) for i, h in enumerate(head)]
    for line in [head, *rows]:
        print("  ".join(c.ljust(w) if i == 1 else c.rjust(w) for i, (c, w) in enumerate(zip(line, widths))).rstrip(),
              file=stream)


def _n(value: Any, fmt: str = "") -> str:
    return "-" if value is None else format(value, fmt)
