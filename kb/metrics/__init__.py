"""Metrics of kit building (the first paper's §IV): the static metrics of a CRCL program
(:func:`static_metrics`, :func:`program_metrics` — ACE, OCE, TCE, TDM, CCE, TET, RE, PE, CSE,
TE, UCE, as NIST's kittingViewer showed them, on a simulated :class:`Robot`) and a total
score from a user's weights (:func:`score`, :func:`read_weights`). docs/metrics.md defines
every metric and the choices kitkb made.
"""

from __future__ import annotations

from pathlib import Path

from kb.metrics.motion import Robot, cell_robot, move_time
from kb.metrics.score import DEFAULT_WEIGHTS, Score, read_weights, score
from kb.metrics.static import METRICS, NAMES, UNITS, Row, StaticMetrics, describe, static_metrics
from kb.metrics.steps import Step, read_steps, step_of, steps_of, text_steps


def program_metrics(path: str | Path, robot: Robot | None = None, *, rows: bool = False) -> StaticMetrics:
    """The static metrics of the CRCL program in ``path`` (``.crcl`` text or ``.xml``)."""
    return static_metrics(read_steps(path), robot, rows=rows, source=str(path))


__all__ = [
    "DEFAULT_WEIGHTS", "METRICS", "NAMES", "UNITS", "Robot", "Row", "cell_robot", "Score", "StaticMetrics", "Step",
    "describe", "move_time", "program_metrics", "read_steps", "read_weights", "score", "static_metrics",
    "step_of", "steps_of", "text_steps",
]
