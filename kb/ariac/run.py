"""``kitkb ariac run TRIAL.yaml``: a trial end to end — imported, planned, run in a cell, scored.

The trial is imported into a folder (:func:`kb.ariac.importer.import_trial`), its kitting
orders are planned and carried out by kitkb's closed loop (:func:`kb.execution.run_scenario`,
on ``cell``: any cell URL ``kitkb run --cell`` takes; by default the simulated cell), a kit the
bins cannot finish delivered partial (ARIAC's insufficient-parts rule: submit incomplete
orders), and the run is scored by kitkb's kit score and by ARIAC's kitting score of 2023 and
2024 (:mod:`kb.ariac.scoring`). The report is kitkb's run report with an ``ariac`` section.
"""

from __future__ import annotations

import time
from pathlib import Path
from typing import Any, Callable

from kb.ariac.importer import import_trial
from kb.ariac.scoring import YEARS, score_run


def run_trial(trial: str | Path, out_dir: str | Path, *, cell: str | None = None, seed: int = 0,
              faults: str | None = None, partial_kits: str = "deliver",
              progress: Callable[[str], None] | None = None) -> dict[str, Any]:
    """Import ``trial`` into ``out_dir``, run it and score it; the report (a dict)."""
    from kb.execution import run_scenario  # the closed loop and its stages: only when a trial runs

    t0 = time.perf_counter()
    imported = import_trial(trial, out_dir)
    import_s = time.perf_counter() - t0
    ariac: dict[str, Any] = {"trial": str(trial), "import_s": round(import_s, 4), "warnings": imported.warnings,
                             "states": {"init": str(imported.init), "goal": str(imported.goal),
                                        "manifest": str(imported.manifest)}}
    if not imported.data["kits"]:
        ariac["scores"] = {y: score_run({"scene": {"objects": []}}, imported.data, y) for y in YEARS}
        return {"executed": False, "goal_holds": True, "stopped": None,
                "reason": "no kitting order kitkb models: nothing to build", "ariac": ariac}
    kw: dict[str, Any] = {"seed": seed, "partial_kits": partial_kits, "out_dir": Path(out_dir) / "run"}
    if faults:
        kw["faults"] = faults
    if cell is not None:
        kw["cell"] = cell  # a cell URL, opened by the loop (kb.cells)
    run = run_scenario(imported.init, imported.goal, validate=True, geometry=True, progress=progress, **kw)
    report = run.report()
    ariac["scores"] = {y: score_run(report, imported.data, y) for y in YEARS}
    report["ariac"] = ariac
    return report
