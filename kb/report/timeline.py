"""The timeline of a run: each action by the time it started (seconds since the run started)
and its index, coloured by its status; each failure where it was found; each recovery where
the action it led to started. From a run report's ``timeline``."""

from __future__ import annotations

from typing import Any

from kb.report.html import esc
from kb.report.scene import failure_text, recovered

STATUS_COLOURS = {"done": "#27ae60", "failed": "#c0392b", "skipped": "#95a5a6", "pending": "#95a5a6"}


def _events(report: dict[str, Any], kind: str) -> list[dict[str, Any]]:
    return [e for e in report.get("timeline") or []
            if isinstance(e, dict) and e.get("kind") == kind and isinstance(e.get("t"), (int, float))]


def _took(event: dict[str, Any]) -> str:
    took = event.get("seconds")
    return f", took {took:.3f} s" if isinstance(took, (int, float)) else ""


def action_trace(actions: list[dict[str, Any]]) -> dict[str, Any]:
    """The actions in time order, one marker each."""
    text = [f"action {esc(a.get('index'))}: {esc(a.get('action'))} {esc(' '.join(map(str, a.get('args') or [])))}"
            f"<br>{esc(a.get('status'))}, started at {a['t']:.3f} s{_took(a)}" for a in actions]
    return {"type": "scatter", "mode": "lines+markers", "name": "actions", "x": [a["t"] for a in actions],
            "y": [a.get("index") for a in actions], "hovertext": text, "hoverinfo": "text",
            "line": {"color": "#c8ced8", "width": 1},
            "marker": {"size": 7, "color": [STATUS_COLOURS.get(str(a.get("status")), "#2e86de") for a in actions]}}


def failure_trace(failures: list[dict[str, Any]], report: dict[str, Any]) -> dict[str, Any]:
    """The failures where they were found (red: not recovered, orange: recovered)."""
    return {"type": "scatter", "mode": "markers", "name": "failures", "x": [f["t"] for f in failures],
            "y": [f.get("index") for f in failures],
            "hovertext": [failure_text(n + 1, {**f, "action_index": f.get("index")}) for n, f in enumerate(failures)],
            "hoverinfo": "text",
            "marker": {"size": 13, "symbol": "x", "color": ["#e67e22" if recovered(f, report) else "#c0392b" for f in failures]}}


def recovery_trace(failures: list[dict[str, Any]], actions: list[dict[str, Any]]) -> dict[str, Any] | None:
    """Each recovery at the next action started after its failure (a retry, the rebound or
    replanned action), or at the failure itself when none followed."""
    xs, ys, text = [], [], []
    for f in failures:
        if not f.get("recovery"):
            continue
        after = [a for a in actions if a["t"] >= f["t"]]
        same = [a for a in after if a.get("index") == f.get("index")]
        at = (same or after or [f])[0]
        xs.append(at["t"]), ys.append(at.get("index"))
        text.append(f"recovery of {esc(f.get('mode'))} (action {esc(f.get('index'))}): "
                    f"{esc(f.get('recovery'))} &rarr; {esc(f.get('outcome'))}")
    if not xs:
        return None
    return {"type": "scatter", "mode": "markers", "name": "recoveries", "x": xs, "y": ys, "hovertext": text,
            "hoverinfo": "text", "marker": {"size": 12, "symbol": "diamond-open", "color": "#2e86de",
                                            "line": {"width": 2}}}


def timeline_figure(report: dict[str, Any]) -> dict[str, Any] | str:
    """The timeline figure of a run report, or the reason there is none (text)."""
    if not isinstance(report.get("timeline"), list):
        return ("This report has no timeline (the actions and failures with their times): it was written "
                "before kitkb recorded one, or by a run that did not execute. The failures are listed below.")
    actions = sorted(_events(report, "action"), key=lambda e: e["t"])
    failures = sorted(_events(report, "failure"), key=lambda e: e["t"])
    if not actions and not failures:
        return "The run carried out no action."
    data = [action_trace(actions)] if actions else []
    if failures:
        data.append(failure_trace(failures, report))
    recov = recovery_trace(failures, actions)
    if recov is not None:
        data.append(recov)
    layout = {"height": 360, "margin": {"l": 60, "r": 20, "t": 20, "b": 50}, "hovermode": "closest",
              "xaxis": {"title": {"text": "time since the run started (s)"}, "zeroline": False},
              "yaxis": {"title": {"text": "action index"}, "rangemode": "tozero"},
              "legend": {"orientation": "h", "y": 1.08}}
    return {"data": data, "layout": layout}
