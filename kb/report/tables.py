"""The tables of a run's page: the run's facts, its metrics (with their names and units), the
kit scores with every lost point, the failures (and the notifications they sent, with their
attachments) and the injected faults."""

from __future__ import annotations

from typing import Any

from kb.metrics import METRICS, NAMES, UNITS
from kb.report.html import esc, note, table, value_html

#: The run metrics of a report's ``metrics`` (the first paper's §IV-B execution metrics), by key.
EXECUTION_NAMES = {
    "failures": "Failures during kit building",
    "failures_per_kit": "Failures per kit",
    "failures_by_mode": "Failures by mode",
    "recovered": "Failure modes recovered",
    "unrecovered": "Failures not recovered",
    "recovered_by_mode": "Recoveries by failure mode",
    "plan_time_s": "Planning time",
    "replan_time_s": "Replanning time",
    "replans": "Plan generation (replans)",
    "contact_errors": "Contact errors",
    "violations": "Constraint violations",
    "constraints": "Constraint violations by kind",
}
_SUFFIX_UNITS = {"_s": "s", "_m": "m", "_kg": "kg", "_rad": "rad"}


def unit_of(key: str) -> str:
    """The unit of a metric key: kb.metrics' for the static metrics, else from a ``_s`` or ``_m`` suffix."""
    if key in UNITS:
        return UNITS[key]
    return next((u for suffix, u in _SUFFIX_UNITS.items() if key.endswith(suffix)), "")


def run_facts(report: dict[str, Any]) -> str:
    """What the run was and how it ended, as a key / value table."""
    units = report.get("units")
    rows = [("scenario", report.get("scenario")), ("seed", report.get("seed")),
            ("executed", report.get("executed", True)), ("goal holds", report.get("goal_holds")),
            ("stopped", report.get("stopped") or "no"), ("actions done", report.get("actions")),
            ("checks", report.get("checks")), ("replans", report.get("replans")),
            ("failures", len(report.get("failures") or [])), ("faults injected", len(report.get("injected") or [])),
            ("time (s)", report.get("time_s"))]
    if report.get("reason"):
        rows.insert(3, ("not executed because", report["reason"]))
    if isinstance(units, dict):
        rows.append(("units of the state files", ", ".join(f"{k}: {v}" for k, v in units.items())))
    return table(["", "value"], rows, css="facts-table", tid="run-table")


def metrics_table(report: dict[str, Any]) -> str:
    """The run's metrics: execution metrics, then the static CRCL metrics (ACE ... UCE)."""
    metrics = report.get("metrics")
    if not isinstance(metrics, dict):
        return note("This report has no metrics: it was written before kitkb computed run metrics, or by a "
                    "run that did not execute.")
    rows = []
    for key, value in metrics.items():
        if key == "static":
            continue
        shown = len(value) if key == "violations" and isinstance(value, list) else value
        rows.append((key, EXECUTION_NAMES.get(key, key.replace("_", " ")), shown, unit_of(key)))
    static = metrics.get("static")
    if isinstance(static, dict):
        keys = [m for m in METRICS if m in static] + [k for k in static if k not in METRICS]
        rows += [(k, NAMES.get(k, k), static[k], unit_of(k)) for k in keys]
    out = table(["metric", "name", "value", "unit"], rows, tid="metrics-table")
    violations = metrics.get("violations") or report.get("violations")
    if isinstance(violations, list) and violations:
        out += f"<h3>Constraint violations</h3>{value_html(violations)}"
    return out


def kits_table(report: dict[str, Any]) -> str:
    """Each kit's score, then every lost point with its reason, predicate and objects."""
    kits = [k for k in report.get("kits") or [] if isinstance(k, dict)]
    if not isinstance(report.get("kits"), list):
        return note("This report has no kit scores: it was written before kitkb scored kits, or by a run "
                    "that did not execute.")
    if not kits:
        return note("The run built no kit.")
    scores = table(["kit", "design", "score", "max score", "lost points"],
                   ([k.get("kit"), k.get("design"), k.get("score"), k.get("max_score"), len(k.get("lost") or [])]
                    for k in kits), tid="kits-table")
    lost = [(k.get("kit"), p.get("points"), p.get("reason"), p.get("predicate"), p.get("objects"))
            for k in kits for p in (k.get("lost") or []) if isinstance(p, dict)]
    if not lost:
        return scores + note("No point was lost.")
    return scores + "<h3>Lost points</h3>" + table(["kit", "points", "reason", "predicate", "objects"], lost,
                                                   tid="lost-table", row_css=["lost"] * len(lost))


def failures_table(report: dict[str, Any]) -> str:
    """The failures: mode, action, kit, objects, the violated predicates, recovery and outcome."""
    failures = [f for f in report.get("failures") or [] if isinstance(f, dict)]
    if not failures:
        return note("No failure was found.")
    rows = [(f"F{n}", f.get("mode"), f.get("action_index"), f.get("action"), f.get("kit"), f.get("phase"),
             f.get("objects"), "<br>".join(esc(v) for v in f.get("violated") or []), f.get("recovery"),
             f.get("outcome")) for n, f in enumerate(failures, 1)]
    raw = [False] * 7 + [True, False, False]
    return table(["", "mode", "action", "name", "kit", "check", "objects", "violated", "recovery", "outcome"], rows,
                 raw=raw, tid="failures-table") + notifications_table(report)


def notifications_table(report: dict[str, Any]) -> str:
    """The notifications the failures' remediations sent: the failure (F1, ...), recipient,
    message and the data they carry (violated atoms, sightings, grasp poses); "" when none."""
    failures = [f for f in report.get("failures") or [] if isinstance(f, dict)]
    rows = [(f"F{n}", x.get("recipient"), x.get("message"), x.get("attachments"))
            for n, f in enumerate(failures, 1) for x in f.get("notifications") or [] if isinstance(x, dict)]
    if not rows:
        return ""
    return table(["failure", "recipient", "message", "attachments"], rows, caption="Notifications",
                 tid="notifications-table")


def injected_table(report: dict[str, Any]) -> str:
    """The faults the simulated cell injected (its ground truth, to compare with the diagnoses)."""
    injected = [x for x in report.get("injected") or [] if isinstance(x, dict)]
    if not injected:
        return note("No fault was injected.")
    return table(["kind", "action", "objects", "detail"],
                 ([x.get("kind"), x.get("action_index"), x.get("objects"), x.get("detail")] for x in injected),
                 tid="injected-table")
