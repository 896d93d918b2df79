"""``kitkb ariac import|run|score`` and ``kitkb run --scoring ariac-YEAR`` (kb.ariac's shim)."""

from __future__ import annotations

import inspect
import json
import os
import tempfile
from pathlib import Path
from typing import Any

from kb.ariac import import_trial, read_manifest, run_trial, score_run
from kb.cli.output import Output
from kb.core.errors import InputError
from kb.core.files import write_atomic


def import_command(trial: str, output: str, out: Output) -> int:
    """Write the trial's init.ttl, goal.ttl and ariac.json into ``output``."""
    with out.progress(f"importing {Path(trial).name}"):
        imported = import_trial(trial, output)
    for w in imported.warnings:
        out.warn(f"warning: {w}")
    out.done(f"wrote {imported.init}, {imported.goal} and {imported.manifest} ({len(imported.data['kits'])} kitting "
             f"order(s) as kits, {len(imported.data['parts'])} part(s), {len(imported.warnings)} warning(s))",
             init=str(imported.init), goal=str(imported.goal), manifest=str(imported.manifest),
             kits=[k["kit"] for k in imported.data["kits"]], warnings=imported.warnings)
    return 0


def run_command(trial: str, output: str, report: str | None, out: Output, cell: str | None = None,
                seed: int = 0, faults: str | None = None, partial_kits: str = "deliver") -> int:
    """Import, run and score the trial; 0 when every kit the parts allow was built."""
    say = None if out.is_json or out.quiet else (lambda text: print(text, file=out.stdout, flush=True))
    data = run_trial(trial, output, cell=cell, seed=seed, faults=faults, partial_kits=partial_kits, progress=say)
    if report:
        write_atomic(report, json.dumps(data, indent=1) + "\n")
    if out.is_json:
        out.emit(data)
    else:
        for w in data["ariac"]["warnings"]:
            out.warn(f"warning: {w}")
        _print_scores(out, data["ariac"]["scores"])
    done = not data.get("executed", True) or data.get("completion") == 1.0
    if not out.is_json:
        what = data.get("reason") or (f"kits built as the parts allow" if done else "kits not all built")
        out.done(f"{Path(trial).name}: {what}" + (f"; report {report}" if report else ""))
    return 0 if done else 1


def score_command(report: str, scoring: str, out: Output, trial: str | None = None) -> int:
    """ARIAC's kitting score of a recorded run (its report, the import's ariac.json)."""
    try:
        data = json.loads(Path(report).read_text(encoding="utf-8"))
    except (OSError, ValueError) as e:
        raise InputError(f"cannot read the run's report: {e}", file=report) from None
    if isinstance(data, list):  # a report of several scenarios: the one of this import
        data = data[0] if len(data) == 1 else None
    if not isinstance(data, dict) or "scene" not in data:
        raise InputError("not the report of one kitkb run (kitkb run INIT GOAL --report FILE)", file=report)
    manifest = read_manifest(trial or data.get("ariac", {}).get("states", {}).get("manifest") or report)
    scores = score_run(data, manifest, scoring)
    if out.is_json:
        out.emit(scores)
        return 0
    _print_scores(out, {scoring: scores})
    return 0


def _print_scores(out: Output, scores: dict[str, Any]) -> None:
    for year, s in scores.items():
        print(f"{year}: {s['total']} of {s['max_score']} ({s['note']})", file=out.stdout)
        for o in s["orders"]:
            if o.get("score") is None:
                print(f"  order {o['order']}: {o['reason']}", file=out.stdout)
                continue
            print(f"  order {o['order']}: {o['score']} of {o['max_score']} (tray {o['tray']}, bonus {o['bonus']}, "
                  f"penalty {o['penalty']}, destination x{o['destination']})", file=out.stdout)
            for q in o["quadrants"]:
                for p in q["reasons"]:
                    print(f"    {p['reason']}", file=out.stdout)
            for p in o["reasons"]:
                print(f"    {p['reason']}", file=out.stdout)


def scored_run(out: Output, scoring: str | None = None, **options: Any) -> int:
    """``kitkb run`` with ``--scoring ariac-YEAR``: the run as ever, then ARIAC's kitting score of
    its report (the import's ariac.json beside INIT) printed and added to ``--report`` as ``ariac``."""
    from kb.cli.pipeline import run

    if scoring is None:
        return run(out=out, **options)
    files = options.get("files") or []
    if len(files) != 2:
        raise InputError("--scoring takes an imported trial's states: kitkb run INIT GOAL --scoring ariac-YEAR")
    manifest = read_manifest(files[0])
    given = options.get("report")
    # the rewritten report's file is made before the run, so that it cannot take the inode of a file
    # the run reads and deletes (its database's journal): the command's guard would take it for that file
    spare = tempfile.NamedTemporaryFile("w", dir=Path(given).resolve().parent if given else None,
                                        prefix=".kitkb-ariac-", suffix=".tmp", delete=False, encoding="utf-8")
    try:
        options["report"] = given or spare.name
        code = run(out=out, **options)
        try:
            data = json.loads(Path(options["report"]).read_text(encoding="utf-8"))
        except (OSError, ValueError):
            return code
        run_data = data[0] if isinstance(data, list) else data
        if "scene" not in run_data:
            return code
        scores = score_run(run_data, manifest, scoring)
        if given:
            run_data["ariac"] = {"scores": {scoring: scores}}
            with spare:
                spare.write(json.dumps(data, indent=1) + "\n")
                spare.flush()
                os.fsync(spare.fileno())
            os.replace(spare.name, given)
    finally:
        spare.close()
        if os.path.exists(spare.name) and spare.name != given:
            os.unlink(spare.name)
    if not out.is_json:
        _print_scores(out, {scoring: scores})
    return code


def _signature() -> inspect.Signature:
    from kb.cli.pipeline import run

    sig = inspect.signature(run)
    extra = inspect.Parameter("scoring", inspect.Parameter.KEYWORD_ONLY, default=None)
    params = [p.replace(kind=inspect.Parameter.KEYWORD_ONLY) for p in sig.parameters.values()]
    return sig.replace(parameters=params + [extra])


scored_run.__signature__ = _signature()  # type: ignore[attr-defined]  # the dispatcher passes run's options
