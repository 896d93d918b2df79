"""``kitkb testmethod METHOD``: a seeded campaign of one of the first paper's test methods on
Dask (kb.testmethod)."""

from __future__ import annotations

from pathlib import Path

from kb.cli.output import Output
from kb.core.errors import InputError
from kb.testmethod import Options, brief, run_campaign, write_table


def testmethod(method: str, trials: int, seed: int, parts: str | None, kits: int | None, faults: str | None,
               workers: int | None, scheduler: str | None, output: str | None, out: Output,
               sensor_noise: str | None = None, noise_sweep: str | None = None, cell: str | None = None,
               domain: list[str] | None = None, partial_kits: str | None = None) -> int:
    """Run the campaign (resuming what ``output`` holds of it), print its rows and summary;
    0 when every trial ran and built its kits, 1 otherwise. ``domain``: extension files added
    to the shipped domain, for every trial."""
    options = Options(method, trials, seed, _sizes(parts), kits if kits is not None else 3, faults, sensor_noise,
                      noise_sweep, cell, tuple(domain or ()), partial_kits=partial_kits)
    if kits is not None and method != "multi":
        raise InputError(f"--kits is for the multi method, not {method}")
    options.reach()
    folder = Path(output or f"out/testmethod-{method}")
    campaign = run_campaign(options, folder, workers=workers, scheduler=scheduler, progress=out.tracker)
    s = campaign.summary
    runs = (f"{trials} trials at {options.levels} noise levels, {s['trials']} runs" if options.noise_sweep
            else f"{s['trials']} trials")
    message = (f"{method}: {runs} in {folder}/ ({campaign.ran} run now, {campaign.resumed} resumed"
               + (f", {len(campaign.lost)} lost with their workers" if campaign.lost else "")
               + f"), kits built {s['kits_built']} of {s['kits']}")
    if out.is_json:
        out.emit({"message": message, "out": str(folder), "method": method, "seed": seed, "trials": trials,
                  "options": options.as_dict(), "summary": s, "rows": [brief(r) for r in campaign.rows]})
    else:
        write_table(campaign.rows, s, out.results, receipt=method == "new-variety")
        out.done(message)
    ok = not campaign.lost and s["errors"] == 0 and s["kits_built"] == s["kits"] and s["trials"] == options.rows
    return 0 if ok else 1


def _sizes(text: str | None) -> tuple[int, ...]:
    """``--parts 10`` or ``--parts 4,6`` (one size per design)."""
    if text is None:
        return ()
    try:
        return tuple(int(x) for x in text.split(","))
    except ValueError:
        raise InputError(f"--parts takes whole numbers separated by commas (got {text!r})") from None
