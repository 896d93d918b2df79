"""The page of one run (or of the main job's several runs): facts, the 3-D view of the
workstation, metrics, kit scores, the timeline, failures and injected faults."""

from __future__ import annotations

from typing import Any

from kb.report.html import esc, figure, note, page, section, table, yes_no
from kb.report.replay import replay_data, replay_html, replay_traces
from kb.report.scene import scene_figure
from kb.report.source import normalise
from kb.report.tables import failures_table, injected_table, kits_table, metrics_table, run_facts
from kb.report.timeline import timeline_figure


def headline(report: dict[str, Any]) -> str:
    """One line under the title: did the run build its kits, what went wrong."""
    failures = report.get("failures") or []
    if report.get("executed") is False:
        state = f'<span class="bad">not executed</span>: {esc(report.get("reason"))}'
    else:
        state = "goal " + yes_no(report.get("goal_holds"), "holds", "does not hold")
        unmet = report.get("goal_unmet")
        if isinstance(unmet, list) and unmet:
            state += f' (unmet: {esc(", ".join(map(str, unmet)))})'
        partial = [p for p in report.get("partial_kits") or [] if isinstance(p, dict)] \
            if isinstance(report.get("partial_kits"), list) else []
        if partial:  # kits the usable parts could not finish (kb.execution.partial)
            state += "; partial kits: " + "; ".join(
                f'{esc(p.get("kit"))} {esc(p.get("outcome"))} (lacks '
                + esc(", ".join(f"{sku} {n}" for sku, n in (p["lacks"] if isinstance(p.get("lacks"), dict)
                                                            else {}).items())) + ")"
                for p in partial)
        if report.get("stopped"):
            state += f'; <span class="bad">stopped</span>: {esc(report["stopped"])}'
        state += buildable_text(report)
    return (f'<p class="facts">{state}; {esc(report.get("actions", 0))} actions, {len(failures)} '
            f'failure{"s" if len(failures) != 1 else ""}, {esc(report.get("time_s", "?"))} s</p>')


def buildable_text(report: dict[str, Any]) -> str:
    """The oracle of what was buildable in the headline (:mod:`kb.metrics.oracle`): kits built of
    kits buildable and the completion, or why it is unknown; nothing for a report without one."""
    oracle = report.get("oracle")
    if not isinstance(oracle, dict):
        return ""
    able, done = report.get("kits_buildable"), report.get("completion")
    if not all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in (able, done)):
        return f"; kits buildable unknown ({esc(oracle.get('unknown', 'no oracle'))})"
    done = float(done)
    text = f'{esc(oracle.get("kits_built", "?"))} of {esc(report["kits_buildable"])} buildable'
    return f'; kits built {text}, completion {yes_no(done >= 1.0, f"{done:.2f}", f"{done:.2f}")}'


def _figure_or_note(fig: dict[str, Any] | str, div_id: str) -> str:
    return note(fig) if isinstance(fig, str) else figure(fig, div_id) + colour_key(fig.get("key") or [])


def colour_key(key: list[tuple[str, str, int]]) -> str:
    """The classes' colours under the 3-D view: a swatch, the class, how many."""
    items = "".join(f'<span class="key"><i style="background:{esc(c)}"></i>{esc(cls)} ({n})</span>'
                    for cls, c, n in key)
    return f'<p class="keys">{items}</p>' if items else ""


def workstation(report: dict[str, Any], prefix: str) -> str:
    """The 3-D view, and under it the replay of the run (:mod:`kb.report.replay`) where the
    report has its timed commands and the view could be drawn."""
    data = replay_data(report)
    replayable = isinstance(data, dict)
    fig = scene_figure(report, (lambda colours: replay_traces(data, colours)) if replayable else None)
    out = _figure_or_note(fig, f"{prefix}-scene") + (
        '<p class="note">Drag to turn, scroll to zoom, double-click to go back; the buttons switch '
        'between the final and the initial state; hover an object, the path or a failure for its name.</p>')
    if isinstance(fig, str):
        return out
    if not replayable:
        return out + note(str(data))
    return out + (
        '<h3>Replay</h3><p class="note">Plays the run\'s CRCL commands on the cell\'s clock (the TET of the '
        'metrics): the tool tip at the commanded speeds, the objects it grasps with it, each failure when '
        'it was found; the Metrics &amp; Settings after each completed command (the first paper\'s Fig. 14). '
        'Keys: <kbd>g</kbd> the next action, <kbd>n</kbd> the next command, <kbd>p</kbd> play or pause.</p>'
        + replay_html(data, prefix, f"{prefix}-scene"))


def _figure(value: Any) -> Any:
    return value if isinstance(value, (int, float, str)) or value is None else None


def paper_table(report: dict[str, Any], prefix: str = "run") -> str:
    """Transporting components, manipulation robustness by stage, failure classes and failure
    modes recovery (:mod:`kb.metrics.robustness`), or why the report has none."""
    m = report.get("metrics") if isinstance(report.get("metrics"), dict) else {}
    t, r, c = (m.get(k) if isinstance(m.get(k), dict) else None for k in ("transporting", "robustness", "failure_classes"))
    if t is None and r is None and c is None:
        return note("This report has none of them: it was written before kitkb computed them (issue 31).")
    rows: list[tuple[Any, ...]] = []
    if t is not None:
        rows.append(("Transporting components", "parts delivered into a kit without a drop / parts transported",
                     f'{_figure(t.get("parts_delivered"))} / {_figure(t.get("parts_transported"))} '
                     f'({_figure(t.get("dropped"))} dropped)', _figure(t.get("rate"))))
    if r is not None:
        for stage in ("detection", "approach", "manipulation"):
            s = r.get(stage) if isinstance(r.get(stage), dict) else {}
            rows.append(("Manipulation robustness", f"{stage}: failures / attempts",
                         f'{_figure(s.get("failures"))} / {_figure(s.get("attempts"))}', _figure(s.get("per_attempt"))))
        rows.append(("Manipulation robustness", "operator interventions", _figure(r.get("operator_interventions")), None))
    if c is not None:
        rows.append(("Failures by class", "precondition / action / unattributable",
                     " / ".join(str(_figure(c.get(k))) for k in ("precondition", "action", "unattributable")), None))
    if "failure_modes" in m:
        rows.append(("Failure modes recovery", "failure modes recovered from / seen (instances recovered)",
                     f'{_figure(m.get("failure_modes_recovered"))} / {_figure(m.get("failure_modes"))} '
                     f'({_figure(m.get("recovered"))})', None))
    return table(["metric", "what", "count", "rate"], rows, tid=f"{prefix}-paper-table")


def run_sections(report: dict[str, Any], prefix: str = "run") -> str:
    """The sections of one run's report (``prefix`` keeps element ids apart on a page of several)."""
    return "".join([
        section("Run", run_facts(report), f"{prefix}-facts"),
        section("Workstation (3-D)", workstation(report, prefix), f"{prefix}-workstation"),
        section("Metrics", metrics_table(report), f"{prefix}-metrics"),
        section("The first paper's execution metrics (§IV-B)", paper_table(report, prefix), f"{prefix}-paper"),
        section("Kit scores", kits_table(report), f"{prefix}-kits"),
        section("Timeline", _figure_or_note(timeline_figure(report), f"{prefix}-timeline"), f"{prefix}-time"),
        section("Failures and recoveries", failures_table(report), f"{prefix}-failures"),
        section("Injected faults", injected_table(report), f"{prefix}-injected"),
    ])


def run_body(report: dict[str, Any], *, links: str = "", extra: str = "", title: str = "") -> str:
    """The body of a run's page: title, headline, ``extra`` (a trial's facts), the sections;
    a report of several runs gets a summary table and a part per run."""
    runs = report.get("runs")
    if isinstance(runs, list):
        rows = [(f'<a href="#run{n}">{esc(r.get("scenario"))}</a>', yes_no(r.get("goal_holds")),
                 esc(r.get("actions")), esc(len(r.get("failures") or [])), esc(r.get("time_s")))
                for n, r in enumerate(runs)]
        summary = table(["scenario", "goal holds", "actions", "failures", "time (s)"], rows, raw=[True] * 5,
                        tid="runs-table")
        parts = "".join(f'<div id="run{n}"><h1>Run {esc(r.get("scenario"))}</h1>{headline(r)}'
                        f'{run_sections(r, f"run{n}")}</div>' for n, r in enumerate(runs))
        total = report | {"actions": _sum(runs, "actions"), "time_s": round(_sum(runs, "time_s"), 3)}
        return f"{links}<h1>kitkb runs</h1>{headline(total)}{summary}{parts}"
    return (f"{links}<h1>{esc(title or 'Run ' + str(report.get('scenario')))}</h1>{headline(report)}{extra}"
            f"{run_sections(report)}")


def _sum(runs: list[dict[str, Any]], key: str) -> float:
    return sum(r[key] for r in runs if isinstance(r.get(key), (int, float)) and not isinstance(r.get(key), bool))


def run_page(report: dict[str, Any], *, script_src: str | None = None, links: str = "", extra: str = "",
             title: str = "") -> str:
    """The HTML page of a run report (plotly.js inlined unless ``script_src`` names a copy)."""
    report = normalise(report)
    head = f"kitkb report: {title or report.get('scenario') or 'runs'}"
    return page(head, run_body(report, links=links, extra=extra, title=title), script_src=script_src)
