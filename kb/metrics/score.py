"""A total score of the metrics from a user's weights (the first paper's "subjective
combination of the other metrics in which the other metrics will be weighted and combined as
desired by the user"): ``total = Σ weight × metric``, each metric's contribution kept.

Every metric kitkb computes for a program is named here (:data:`SCORED`): the static metrics
of §IV-A (ACE, OCE, TCE, TDM, CCE, TET, RE, PE, CSE, TE, UCE), and, when the program is played
on a state (``kitkb metrics PROGRAM --init STATE [--goal STATE]``, :mod:`kb.sim.playback`),
the object metrics of §VI (:data:`OBJECT_METRICS`: OSM, OM, OMR, OMW) and its constraint
metrics (:data:`CONSTRAINT_METRICS`: OVW, WVE, WEE, CTE). A metric that was not computed
(no state given) contributes nothing.

A weights file is TOML; every key of its ``[weights]`` table is one of those short names
with a number. A metric the file does not name keeps its default weight
(:data:`DEFAULT_WEIGHTS`, :data:`PLAYBACK_WEIGHTS`)::

    [weights]
    TET = -1.0    # per second
    RE = -10      # per range error
    UCE = 0       # useless commands do not count here
    CTE = -50     # a collision costs more than an error here
"""

from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Mapping

from kb.core.errors import InputError
from kb.core.files import note_input
from kb.metrics.static import METRICS

#: The object metrics of a program played on a state (the first paper, §VI: "the number of
#: objects that should have been moved, ... that were moved, ... moved to the correct place,
#: ... moved to the wrong place"), and their names.
OBJECT_METRICS = ("OSM", "OM", "OMR", "OMW")
#: The constraint metrics (§VI: "picking up an object that weighs more than the robot's load
#: capacity, ... moving outside of its work volume, ... using a gripper ... not qualified to
#: move the object"; §IV-B: contact errors).
CONSTRAINT_METRICS = ("OVW", "WVE", "WEE", "CTE")
#: The kind of a violation a cell reports (kb.sim's ``Violation.kind``) -> its constraint metric.
CONSTRAINT_OF_KIND = {"overweight": "OVW", "work-volume": "WVE", "wrong-effector": "WEE", "contact": "CTE"}
OBJECT_NAMES = {
    "OSM": "Objects that Should have Moved", "OM": "Objects Moved", "OMR": "Objects Moved to the Right place",
    "OMW": "Objects Moved to a Wrong place", "OVW": "OVerWeight grasps", "WVE": "Work Volume Errors",
    "WEE": "Wrong Effector Errors", "CTE": "ConTact Errors",
}
#: Every metric a weights file may name, in the order they are shown.
SCORED = METRICS + OBJECT_METRICS + CONSTRAINT_METRICS

#: Default weights of the static metrics: every error costs 10 points, a useless command 1, a
#: second of execution 1; counts of commands, the distance and the last command's time do not
#: count (TE is not weighted, so that an error is not counted twice with RE, PE, CSE).
DEFAULT_WEIGHTS: dict[str, float] = {
    "ACE": 0.0, "OCE": 0.0, "TCE": 0.0, "TDM": 0.0, "CCE": 0.0, "TET": -1.0,
    "RE": -10.0, "PE": -10.0, "CSE": -10.0, "TE": 0.0, "UCE": -1.0,
}
#: Default weights of the object and constraint metrics: an object moved to its right place
#: earns 10 points and one moved to a wrong place costs 10, every constraint violation costs
#: 10; the counts of objects that should have moved and that moved do not count.
PLAYBACK_WEIGHTS: dict[str, float] = {
    "OSM": 0.0, "OM": 0.0, "OMR": 10.0, "OMW": -10.0,
    "OVW": -10.0, "WVE": -10.0, "WEE": -10.0, "CTE": -10.0,
}


@dataclass(frozen=True)
class Score:
    """``total`` and each metric's ``contributions`` (weight × value) under ``weights``."""

    total: float
    weights: dict[str, float]
    contributions: dict[str, float]

    def as_dict(self) -> dict[str, Any]:
        """The score as JSON data."""
        return {"total": self.total, "weights": dict(self.weights), "contributions": dict(self.contributions)}


def score(totals: Mapping[str, float | None], weights: Mapping[str, float] | None = None) -> Score:
    """The weighted total of ``totals`` (a metric -> value mapping, as
    :attr:`StaticMetrics.totals <kb.metrics.static.StaticMetrics.totals>`, with the object and
    constraint metrics when a program was played on a state); a metric absent from ``totals``
    or None there (not computed) contributes nothing and has no contribution."""
    used = {**DEFAULT_WEIGHTS, **PLAYBACK_WEIGHTS, **(weights or {})}
    contributions = {m: used[m] * totals[m] for m in SCORED if totals.get(m) is not None}  # type: ignore[operator]
    return Score(math.fsum(contributions.values()), used, contributions)


def read_weights(path: str | Path) -> dict[str, float]:
    """The weights a TOML file names; an unreadable file, an unknown metric or a weight that
    is not a finite number is an :class:`~kb.core.errors.InputError`."""
    note_input(path)
    try:
        with open(path, "rb") as f:
            data = tomllib.load(f)
    except OSError as exc:
        raise InputError(f"cannot read: {exc.strerror or exc}", path) from None
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"not TOML: {exc}", path, getattr(exc, "lineno", None)) from None
    table = data.get("weights")
    unknown_tables = sorted(k for k in data if k != "weights")
    if unknown_tables or not isinstance(table, dict):
        raise InputError("a weights file holds one [weights] table of metric = number "
                         f"(metrics: {', '.join(SCORED)})", path)
    weights: dict[str, float] = {}
    for name, value in table.items():
        if name not in SCORED:
            raise InputError(f"unknown metric {name!r} in [weights] (metrics: {', '.join(SCORED)})", path)
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            raise InputError(f"the weight of {name} must be a finite number, not {value!r}", path)
        weights[name] = float(value)
    return weights
