"""The main job: everything kitkb does, end to end, on the shipped scenarios.

Each stage is a library call; this module only sequences them and prints one line per
stage, so that ``./main.sh`` shows a new user what the project does.
"""

from __future__ import annotations

import time
from typing import TextIO

from kb.resources import ontologies_dir, scenario_dirs


def _stage(out: TextIO, label: str, started: float) -> None:
    print(f"  {label} ({time.perf_counter() - started:.2f} s)", file=out)


def run_main_job(out: TextIO) -> int:
    """Validate the shipped model and scenarios; then plan each scenario.

    Returns the exit code: 0 when every stage succeeded, 1 otherwise.
    """
    from kb.validate import validate

    status = 0
    model = sorted(ontologies_dir().glob("*.ttl"))
    print(f"kitkb: main job on {len(scenario_dirs())} shipped scenarios", file=out)
    t = time.perf_counter()
    report = validate([str(p) for p in model])
    _stage(out, f"model: {len(model)} files, {report.summary()}", t)
    status |= 0 if report.conforms else 1
    for scenario in scenario_dirs():
        files = [str(scenario / "init.ttl"), str(scenario / "goal.ttl")]
        t = time.perf_counter()
        report = validate(files)
        _stage(out, f"{scenario.name}: validate {report.summary()}", t)
        for diag in report.diagnostics:
            print("    " + diag.format(), file=out)
        status |= 0 if report.conforms else 1
    print("kitkb: main job " + ("succeeded" if status == 0 else "found problems"), file=out)
    return status
