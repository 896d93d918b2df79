"""``kitkb report RUN.json|CAMPAIGN_DIR -o report.html``: the HTML report (kb.report)."""

from __future__ import annotations

from kb.cli.output import Output
from kb.report import write_report


def report(input: str, output: str, out: Output) -> int:
    """Write the page of a run report or a campaign folder; one line (or JSON object) saying what."""
    with out.progress(f"drawing the report of {input}"):
        facts = write_report(input, output)
    size = f"{facts['bytes'] / 1e6:.1f} MB"
    if facts["kind"] == "run":
        what = (f"{facts['runs']} run{'s' if facts['runs'] != 1 else ''}, {facts['failures']} failure"
                f"{'s' if facts['failures'] != 1 else ''}" + ("" if facts["scene"] else ", no 3-D scene in the report"))
    else:
        what = (f"campaign of {facts['trials']} trials, {facts['failed']} failed; a page per trial in "
                f"{facts['pages_dir']}")
    out.done(f"wrote {output} ({what}; {size})", **facts)
    return 0
