"""NIST ARIAC's kitting trials in kitkb (issue 32): trial files read and imported as kitkb states,
run end to end, and scored by ARIAC's kitting score of a year.

    >>> from kb.ariac import import_trial, read_trial, run_trial, score_run     # doctest: +SKIP
    >>> imported = import_trial("trials-2024/kitting.yaml", "out/ariac")        # init.ttl, goal.ttl, ariac.json
    >>> report = run_trial("trials-2024/kitting.yaml", "out/ariac")             # ... and report["ariac"]["scores"]

Modules: :mod:`~kb.ariac.yamlfile` (YAML with lines), :mod:`~kb.ariac.trial` (the trial
format), :mod:`~kb.ariac.workcell` (ARIAC's geometry), :mod:`~kb.ariac.states` (the workstation
as kitkb states), :mod:`~kb.ariac.importer`, :mod:`~kb.ariac.scoring` (ARIAC's kitting score by
year), :mod:`~kb.ariac.run`.
"""

from kb.ariac.importer import Imported, import_trial, read_manifest
from kb.ariac.run import run_trial
from kb.ariac.scoring import YEARS, KittingScore, Shipment, Task, TrayPart, score_kitting, score_run
from kb.ariac.trial import Trial, read_trial

__all__ = ["YEARS", "Imported", "KittingScore", "Shipment", "Task", "Trial", "TrayPart", "import_trial",
           "read_manifest", "read_trial", "run_trial", "score_kitting", "score_run"]
