"""The visual report of a run or a campaign: one self-contained HTML page drawn with plotly
(plotly.js inlined, so it opens with no network), the data first and the page second — the
page shows the same JSON the CLI writes (``kitkb run --report``, ``kitkb testmethod --out``).

* :func:`run_page`: a run's page — the 3-D view of the workstation from the objects' boxes and
  poses with the tool tip's path and a marker at each failure, the metrics (names and units
  from :mod:`kb.metrics`), the kit scores with every lost point, a timeline of actions,
  failures and recoveries, the failures and the injected faults. Sections a report does not
  have (older reports, runs that did not execute) say so instead.
* :func:`campaign_page`: a campaign's page — its facts and summary, each metric's distribution
  across the trials, failures by mode, the trials that failed and every trial, each linked to
  its own page (``DIR/report/trial-NNNNN.html``, sharing one ``plotly.min.js`` beside them: the
  smallest bundle that draws them all).
* :func:`write_report`: ``kitkb report SOURCE -o OUT`` — the page(s) written atomically.

docs/report.md shows what a page holds and how to make one.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any
from urllib.parse import quote

from kb.core.files import atomic_paths
from kb.report.campaign import TRIAL_PAGE, campaign_page, failed_because, trial_index, trial_page
from kb.report.html import bundle_for, plotly_js, trace_types
from kb.report.run import run_page
from kb.report.source import Campaign, is_run_report, normalise, read_campaign, read_run, read_source

#: The folder, under a campaign's, that gets the trial pages and their shared plotly.js.
PAGES_DIR = "report"
PLOTLY_JS = "plotly.min.js"


def _href(target: Path, start: Path) -> str:
    """A relative link from a page in folder ``start`` to ``target``."""
    return quote(Path(os.path.relpath(target.resolve(), start.resolve())).as_posix())


def _write(pages: dict[Path, str]) -> int:
    """Write every page (path -> text) atomically, all renamed in place together; bytes written."""
    paths = list(pages)
    size = 0
    with atomic_paths(paths) as temps:
        for tmp, path in zip(temps, paths):
            data = pages[path].encode("utf-8")
            tmp.write_bytes(data)
            size += len(data)
    return size


def write_report(source: str | Path | dict[str, Any], output: str | Path) -> dict[str, Any]:
    """Write the page of ``source`` (a run report file, a campaign folder, or a run report
    already in memory: ``kitkb run --report-html``) to ``output``; a campaign also gets a page
    per trial in ``SOURCE/report/``. The facts of what was written."""
    if isinstance(source, dict) and not is_run_report(source):
        raise ValueError("not a kitkb run report: it needs scenario, goal_holds and failures")
    data = normalise(source) if isinstance(source, dict) else read_source(source)
    out = Path(output)
    if isinstance(data, dict):
        runs = data["runs"] if isinstance(data.get("runs"), list) else [data]
        size = _write({out: run_page(data)})
        return {"kind": "run", "output": str(out), "bytes": size, "runs": len(runs),
                "scene": any(isinstance(r.get("scene"), dict) for r in runs),
                "failures": sum(len(r.get("failures") or []) for r in runs)}
    return _write_campaign(data, out)


def _write_campaign(campaign: Campaign, out: Path) -> dict[str, Any]:
    folder = campaign.directory / PAGES_DIR
    page_of = {trial_index(r): folder / TRIAL_PAGE.format(trial_index(r)) for _, r in campaign.trials}
    back = _href(out, folder)
    pages = {out: campaign_page(campaign, lambda i: _href(page_of[i], out.parent))}
    trials = {page_of[trial_index(r)]: trial_page(r, back=back, script_src=PLOTLY_JS) for _, r in campaign.trials}
    if trials:  # the smallest plotly.js that draws every trial page's figures, shared
        types = set().union(*(trace_types(text) or set() for text in trials.values()))
        chosen = bundle_for(types)
        pages[folder / PLOTLY_JS] = chosen.text() if chosen is not None else plotly_js()
    pages.update(trials)
    size = _write(pages)
    failed = sum(1 for _, r in campaign.trials if failed_because(r))
    return {"kind": "campaign", "output": str(out), "bytes": size, "trials": len(campaign.trials),
            "failed": failed, "trial_pages": len(campaign.trials), "pages_dir": str(folder)}


__all__ = ["Campaign", "campaign_page", "is_run_report", "read_campaign", "read_run", "read_source", "run_page",
           "trial_page", "write_report"]
