"""The page of a campaign (``kitkb testmethod ... --out DIR``): what was run, the summary, for a
noise sweep the detection rate and the false alarms against the noise level (from the summary's
``sweep``, what the command prints), the distribution of each metric across the trials, the
failures by mode, the trials that failed and every trial, each linked to its own page."""

from __future__ import annotations

from collections import Counter
from pathlib import Path
from typing import Any, Callable

from kb.metrics import METRICS, NAMES
from kb.report.html import esc, figure, note, page, section, table, value_html, yes_no
from kb.report.run import run_page
from kb.report.scene import recovered
from kb.report.source import Campaign, normalise, read_campaign
from kb.report.tables import EXECUTION_NAMES, unit_of

#: The file name of trial ``index``'s page (beside the others in ``DIR/report/``).
TRIAL_PAGE = "trial-{:05d}.html"


def trial_index(report: dict[str, Any]) -> int:
    """The index of a trial report (its ``trial.index``)."""
    index = (report.get("trial") or {}).get("index")
    return index if isinstance(index, int) else -1


def failed_because(report: dict[str, Any]) -> str | None:
    """Why a trial failed (an error, a stop, the goal not reached), or None if it did not."""
    trial = report.get("trial") or {}
    if trial.get("error"):
        return f"error: {trial['error']}"
    if report.get("executed") is False:
        return f"not executed: {report.get('reason')}"
    if report.get("stopped"):
        return f"stopped: {report['stopped']}"
    if not report.get("goal_holds"):
        return "the goal does not hold"
    return None


def kit_score(report: dict[str, Any]) -> float | None:
    """The trial's kit score in per cent of the points possible (None without kit scores)."""
    kits = [k for k in report.get("kits") or [] if isinstance(k, dict)]
    total = sum(k.get("max_score") or 0 for k in kits if isinstance(k.get("max_score"), (int, float)))
    if not total:
        return None
    return 100.0 * sum(k.get("score") or 0 for k in kits if isinstance(k.get("score"), (int, float))) / total


def trial_values(report: dict[str, Any]) -> dict[str, float]:
    """The numbers of one trial that the campaign page shows as distributions."""
    out: dict[str, float] = {}
    t = (report.get("trial") or {}).get("time_s", report.get("time_s"))
    for key, value in (("time_s", t), ("actions", report.get("actions")),
                       ("failures", len(report.get("failures") or [])), ("kit score %", kit_score(report))):
        if isinstance(value, (int, float)) and not isinstance(value, bool):
            out[key] = value
    metrics = report.get("metrics")
    if isinstance(metrics, dict):
        for key, value in metrics.items():
            if isinstance(value, (int, float)) and not isinstance(value, bool):
                out[key] = value
            elif key == "violations" and isinstance(value, list):
                out[key] = len(value)
        static = metrics.get("static")
        if isinstance(static, dict):
            out.update({k: v for k, v in static.items() if isinstance(v, (int, float)) and not isinstance(v, bool)})
    return out


def metric_label(key: str) -> str:
    """A metric's name with its unit, for a plot title."""
    name = EXECUTION_NAMES.get(key) or NAMES.get(key) or key.replace("_", " ")
    if key in METRICS:
        name = f"{key} {name}"
    unit = unit_of(key)
    return f"{name} ({unit})" if unit else name


def metric_values(trials: list[dict[str, Any]]) -> dict[str, list[tuple[int, float]]]:
    """Metric -> (trial index, value) of every trial that has it."""
    values: dict[str, list[tuple[int, float]]] = {}
    for report in trials:
        for key, v in trial_values(report).items():
            values.setdefault(key, []).append((trial_index(report), v))
    return values


def distribution_figures(trials: list[dict[str, Any]]) -> list[tuple[str, dict[str, Any]]]:
    """(metric, box plot with every trial as a point) for each metric some trial has, but for
    those that are 0 in every trial (:func:`always_zero`)."""
    figs = []
    for key, pairs in metric_values(trials).items():
        if all(v == 0 for _, v in pairs):
            continue
        data = [{"type": "box", "name": "", "y": [v for _, v in pairs], "boxpoints": "all", "jitter": 0.4,
                 "pointpos": 0, "hovertext": [f"trial {i}" for i, _ in pairs], "hoverinfo": "text+y",
                 "marker": {"size": 4, "color": "#2e86de"}, "line": {"color": "#34495e"}}]
        layout = {"title": {"text": esc(metric_label(key)), "font": {"size": 13}, "x": 0.02, "xanchor": "left"},
                  "height": 250, "margin": {"l": 50, "r": 10, "t": 34, "b": 16}, "showlegend": False,
                  "xaxis": {"showticklabels": False}}
        figs.append((key, {"data": data, "layout": layout}))
    return figs


def always_zero(trials: list[dict[str, Any]]) -> list[str]:
    """The metrics that are 0 in every trial (named in a line, not drawn)."""
    return [k for k, pairs in metric_values(trials).items() if all(v == 0 for _, v in pairs)]


def modes_figure(trials: list[dict[str, Any]]) -> dict[str, Any] | None:
    """Failures by mode across the trials, recovered and not."""
    done: Counter[str] = Counter()
    lost: Counter[str] = Counter()
    for report in trials:
        for f in report.get("failures") or []:
            if isinstance(f, dict):
                (done if recovered(f, report) else lost)[str(f.get("mode"))] += 1
    modes = sorted(set(done) | set(lost))
    if not modes:
        return None
    names = [esc(m) for m in modes]
    data = [{"type": "bar", "name": "recovered", "x": names, "y": [done[m] for m in modes], "marker": {"color": "#e67e22"}},
            {"type": "bar", "name": "not recovered", "x": names, "y": [lost[m] for m in modes],
             "marker": {"color": "#c0392b"}}]
    return {"data": data, "layout": {"barmode": "stack", "height": 320, "yaxis": {"title": {"text": "failures"}},
                                     "margin": {"l": 50, "r": 10, "t": 20, "b": 60}}}


def sweep_of(summary: Any) -> tuple[dict[str, Any], list[dict[str, Any]]] | None:
    """(the sweep, its levels) of a campaign summary's ``sweep`` (``kitkb testmethod errors
    --noise-sweep``), or None when the campaign is no sweep (or the summary not of that shape)."""
    sweep = summary.get("sweep") if isinstance(summary, dict) else None
    if not isinstance(sweep, dict) or not isinstance(sweep.get("levels"), list):
        return None
    levels = [lv for lv in sweep["levels"] if isinstance(lv, dict) and _num(lv.get("value")) is not None]
    return (sweep, levels) if levels else None


def _num(value: Any) -> float | None:
    return float(value) if isinstance(value, (int, float)) and not isinstance(value, bool) else None


def _percent(value: Any) -> float | None:
    v = _num(value)
    return None if v is None else round(100 * v, 3)


def sweep_figures(sweep: dict[str, Any], levels: list[dict[str, Any]]) -> list[tuple[str, dict[str, Any]]]:
    """(id, figure) of a sweep: the detection rate and the right-diagnosis rate (%), and the
    false alarms per 10,000 actions, against the swept noise."""
    x = [_num(lv["value"]) for lv in levels]
    names = [esc(lv.get("noise")) for lv in levels]
    axis = {"title": {"text": esc(f"{sweep.get('key', 'noise')} noise ({sweep.get('unit', '')})")}, "zeroline": False}

    def line(name: str, y: list[Any], color: str) -> dict[str, Any]:
        return {"type": "scatter", "mode": "lines+markers", "name": name, "x": x, "y": y, "text": names,
                "hovertemplate": "%{text}: %{y}<extra>" + name + "</extra>", "marker": {"size": 8, "color": color},
                "line": {"color": color}}

    detection = {"data": [line("detection rate", [_percent(lv.get("detection")) for lv in levels], "#2e86de"),
                          line("diagnosed right", [_percent(lv.get("diagnosed_right")) for lv in levels], "#27ae60")],
                 "layout": {"height": 320, "xaxis": axis, "yaxis": {"title": {"text": "% of the faults"},
                                                                     "range": [0, 105]},
                            "title": {"text": "Detection rate", "font": {"size": 13}, "x": 0.02, "xanchor": "left"},
                            "legend": {"orientation": "h", "y": -0.3}, "margin": {"l": 55, "r": 10, "t": 34, "b": 50}}}
    alarms = [_num(lv.get("false_alarms_per_10k_actions")) for lv in levels]
    false = {"data": [line("false alarms", alarms, "#c0392b")],
             "layout": {"height": 320, "xaxis": axis, "showlegend": False,
                        "yaxis": {"title": {"text": "per 10,000 actions"}, "rangemode": "tozero"},
                        "title": {"text": "False alarms", "font": {"size": 13}, "x": 0.02, "xanchor": "left"},
                        "margin": {"l": 55, "r": 10, "t": 34, "b": 50}}}
    return [("sweep-detection", detection), ("sweep-false-alarms", false)]


SWEEP_HEADERS = ["noise", "runs", "actions", "kits built", "injected", "detected", "diagnosed right",
                 "diagnosed wrong", "missed", "false alarms", "false alarms per 10,000 actions", "detection rate %"]


def sweep_table(sweep: dict[str, Any], levels: list[dict[str, Any]]) -> str:
    """The detection quality of each level of a sweep, a row a level."""
    rows = []
    for lv in levels:
        total = lv.get("total") if isinstance(lv.get("total"), dict) else {}
        per = _num(lv.get("false_alarms_per_10k_actions"))
        rate = _percent(lv.get("detection"))
        rows.append((lv.get("value"), lv.get("noise"), lv.get("runs"), lv.get("actions"),
                     f"{lv.get('kits_built', '?')}/{lv.get('kits', '?')}", total.get("injected"), total.get("detected"),
                     total.get("diagnosed_right"), total.get("diagnosed_wrong"), total.get("missed"),
                     lv.get("false_alarm_count"), None if per is None else round(per, 2),
                     None if rate is None else round(rate, 1)))
    headers = [f"{sweep.get('key', 'noise')} ({sweep.get('unit', '')})", *SWEEP_HEADERS]
    return table(headers, rows, tid="sweep-table")


def sweep_section(summary: Any) -> str:
    """The section of a sweep's detection quality against noise ("" for a campaign that is no sweep)."""
    found = sweep_of(summary)
    if found is None:
        return ""
    sweep, levels = found
    figs = "".join(f"<div>{figure(fig, fid)}</div>" for fid, fig in sweep_figures(sweep, levels))
    grid = f'<div class="grid" style="grid-template-columns: repeat(auto-fill, minmax(460px, 1fr))">{figs}</div>'
    text = (f"Every trial run at each level of --noise-sweep {sweep.get('sweep')}"
            + (f" over --sensor-noise {sweep['base']}" if sweep.get("base") else "")
            + ", with the same seed: the levels differ only by the sensor's noise.")
    return section("Detection quality against sensor noise",
                   f'<p class="facts">{esc(text)}</p>{grid}' + sweep_table(sweep, levels),
                   "sweep")


def _default_href(index: int) -> str:
    return "report/" + TRIAL_PAGE.format(index)


def trial_rows(trials: list[dict[str, Any]], href: Callable[[int], str] | None) -> list[tuple[Any, ...]]:
    """A row per trial: link, seed, design, goal, failures, kit score, time, why it failed."""
    rows = []
    for report in trials:
        trial = report.get("trial") or {}
        i = trial_index(report)
        link = f'<a href="{esc(href(i))}">trial {i}</a>' if href else f"trial {i}"
        score = kit_score(report)
        design = trial.get("design") if trial.get("noise") is None else f"{trial.get('design')} @ {trial['noise']}"
        rows.append((link, esc(trial.get("seed")), esc(design), yes_no(report.get("goal_holds")),
                     esc(len(report.get("failures") or [])), "&ndash;" if score is None else f"{score:.1f}",
                     _completion(report), esc(trial.get("time_s", report.get("time_s"))), esc(failed_because(report) or "")))
    return rows


def _completion(report: dict[str, Any]) -> str:
    """A trial's kits built / kits buildable and completion (kb.metrics.oracle), or a dash."""
    oracle, done = report.get("oracle") or {}, report.get("completion")
    if not isinstance(done, (int, float)) or isinstance(done, bool):
        return "&ndash;"
    return f'{esc(oracle.get("kits_built", "?"))}/{esc(report.get("kits_buildable"))} ({float(done):.2f})'


def completion_line(summary: Any) -> str:
    """The campaign's completion by the oracle of what was buildable (its summary's
    ``completion``), as a sentence; empty when no trial has an oracle."""
    done = summary.get("completion") if isinstance(summary, dict) else None
    if not isinstance(done, dict) or not done.get("runs"):
        return ""
    return (f'; completion {float(done["overall"]):.4f} overall ({esc(done["kits_built"])} kits built of '
            f'{esc(done["kits_buildable"])} buildable), mean {float(done["mean"]):.4f}, '
            f'{esc(done["complete"])} of {esc(done["runs"])} runs complete')


TRIAL_HEADERS = ["trial", "seed", "design", "goal holds", "failures", "kit score %", "built/buildable", "time (s)",
                 "failed because"]


def campaign_body(campaign: Campaign, href: Callable[[int], str] | None = _default_href) -> str:
    """The body of a campaign's page; ``href(index)``: the link to trial ``index``'s page."""
    meta = campaign.meta
    trials = [normalise(r) for _, r in campaign.trials]
    failed = [r for r in trials if failed_because(r)]
    facts = table(["", "value"], [("method", meta.get("method")), ("seed", meta.get("seed")),
                                  ("trials asked", meta.get("trials")), ("trials found", len(trials)),
                                  ("trials failed", len(failed)), ("options", meta.get("options")),
                                  ("folder", str(campaign.directory))], tid="campaign-table")
    summary = meta.get("summary")
    parts = [f"<h1>Campaign: {esc(meta.get('method'))}</h1>",
             f'<p class="facts">{len(trials)} trials, {len(failed)} failed, seed {esc(meta.get("seed"))}'
             f'{completion_line(summary)}</p>',
             section("Campaign", facts, "campaign"),
             sweep_section(summary)]
    if sweep_of(summary) is not None:  # the levels are in the sweep's section
        summary = {k: v for k, v in summary.items() if k != "sweep"}
    parts.append(section("Summary", f'<div id="summary-table">{value_html(summary)}</div>' if summary
                         else note("campaign.json has no summary."), "summary"))
    figs = distribution_figures(trials)
    grid = "".join(f'<div>{figure(fig, f"dist-{n}", toolbar=False)}</div>' for n, (_, fig) in enumerate(figs))
    zero = always_zero(trials)
    zero_line = note("0 in every trial: " + ", ".join(metric_label(k) for k in zero) + ".") if zero else ""
    parts.append(section("Metrics across the trials", (f'<div class="grid">{grid}</div>' if figs
                         else note("No trial has a metric to show.")) + zero_line, "distributions"))
    modes = modes_figure(trials)
    parts.append(section("Failures by mode", figure(modes, "modes-plot") if modes else note("No failure was found."),
                         "modes"))
    rows = trial_rows(failed, href)
    parts.append(section("Trials that failed", table(TRIAL_HEADERS, rows, raw=[True] * len(TRIAL_HEADERS), tid="failed-table")
                         if rows else note("No trial failed."), "failed"))
    parts.append(section("Every trial", table(TRIAL_HEADERS, trial_rows(trials, href), raw=[True] * len(TRIAL_HEADERS),
                                              tid="trials-table") if trials else note("The folder has no trial yet."),
                         "trials"))
    return "".join(parts)


def campaign_page(directory: str | Path | Campaign, href: Callable[[int], str] | None = _default_href) -> str:
    """The HTML page of the campaign in folder ``directory`` (plotly.js inlined); its trial links
    point at ``report/trial-NNNNN.html`` under the folder unless ``href`` says otherwise."""
    campaign = directory if isinstance(directory, Campaign) else read_campaign(directory)
    return page(f"kitkb campaign: {campaign.meta.get('method')}", campaign_body(campaign, href))


def trial_extra(report: dict[str, Any]) -> str:
    """A trial's own facts (seed, method, design, layout, error) for the top of its page."""
    trial = report.get("trial")
    if not isinstance(trial, dict):
        return ""
    return section("Trial", table(["", "value"], list(trial.items()), tid="trial-table"), "trial")


def trial_page(report: dict[str, Any], *, back: str | None = None, script_src: str | None = None) -> str:
    """The page of one trial: its run's page with the trial's facts and a link ``back`` to the campaign."""
    report = normalise(report)
    links = f'<nav><a href="{esc(back)}">&larr; campaign</a></nav>' if back else ""
    title = f"Trial {trial_index(report)}: {report.get('scenario')}"
    return run_page(report, script_src=script_src, links=links, extra=trial_extra(report), title=title)
