"""What a run leaves behind: actions, checks, commands, failures and recoveries.

Plain dataclasses, written to the world-model database by :mod:`kb.execution.store` and to the
JSON report (:meth:`RunRecord.report`); the executives' API (:mod:`kb.execution.api`) queries them.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Protocol

import numpy as np


def local(iri: str) -> str:
    return str(iri).rsplit("#", 1)[-1].rsplit("/", 1)[-1]


@dataclass
class AtomCheck:
    """One predicate atom checked from geometry: expected true (or false, if negated)."""

    predicate: str
    args: tuple[str, ...]
    negated: bool
    holds: bool

    @property
    def ok(self) -> bool:
        return self.holds != self.negated

    def text(self) -> str:
        atom = f"{self.predicate}({', '.join(map(local, self.args))})"
        return f"not {atom}" if self.negated else atom


@dataclass
class Check:
    action_index: int
    phase: str  # "precondition" or "effect"
    atoms: list[AtomCheck]
    time: float

    @property
    def ok(self) -> bool:
        return all(a.ok for a in self.atoms)

    @property
    def violated(self) -> list[AtomCheck]:
        return [a for a in self.atoms if not a.ok]


@dataclass
class Sighting:
    """Where an object of a violated atom was expected (last stable state) and where it was seen."""

    name: str
    expected: tuple[float, float, float] | None
    seen: tuple[float, float, float] | None


@dataclass
class FailureRecord:
    """An action failure: the check that found it, its diagnosis and what was done."""

    action_index: int
    action: str
    args: tuple[str, ...]
    phase: str
    violated: list[AtomCheck]
    sightings: list[Sighting]
    mode: str  # failure mode name, or "unexplained"
    consequence: str = ""
    severity: int = 0
    recovery: str = ""  # retry, rebind, replan, recovery-plan, stop
    outcome: str = ""  # recovered, gave up, stopped: <reason>
    time: float = 0.0
    considered: list[str] = field(default_factory=list)
    kit: str | None = None  # the kit the failed action worked for

    @property
    def objects(self) -> list[str]:
        seen: list[str] = []
        for a in self.violated:
            for x in a.args:
                if x not in seen:
                    seen.append(x)
        return seen

    def why(self) -> str:
        """One paragraph: what was violated, where the objects were expected and seen."""
        lines = [f"action {self.action_index} ({self.action} {' '.join(map(local, self.args))}) failed its "
                 f"{self.phase} check: " + "; ".join(a.text() + " is " + ("true" if a.holds else "false")
                                                       for a in self.violated)]
        for s in self.sightings:
            exp = "unknown" if s.expected is None else "(%.3f, %.3f, %.3f)" % s.expected
            seen = "not seen" if s.seen is None else "(%.3f, %.3f, %.3f)" % s.seen
            lines.append(f"  {local(s.name)}: expected at {exp}, seen at {seen}")
        lines.append(f"  diagnosis: {self.mode}" + (f" ({self.consequence})" if self.consequence else ""))
        lines.append(f"  recovery: {self.recovery} -> {self.outcome}")
        return "\n".join(lines)


@dataclass
class ActionRecord:
    index: int
    action: str
    args: tuple[str, ...]
    status: str = "pending"  # done, failed, skipped
    commands: list[str] = field(default_factory=list)
    started: float = 0.0
    ended: float = 0.0


@dataclass
class RunRecord:
    """Everything one run did, in order."""

    scenario: str
    seed: int | None = None
    actions: list[ActionRecord] = field(default_factory=list)
    checks: list[Check] = field(default_factory=list)
    failures: list[FailureRecord] = field(default_factory=list)
    replans: int = 0
    goal_holds: bool | None = None
    stopped: str | None = None  # reason the run stopped early
    injected: list[dict[str, Any]] = field(default_factory=list)
    started: float = 0.0
    ended: float = 0.0
    run_id: int | None = None

    @property
    def succeeded(self) -> bool:
        return self.stopped is None and bool(self.goal_holds)

    def report(self) -> dict[str, Any]:
        """The JSON report: goal_holds, injected faults, failures (diagnoses), and counts."""
        return {
            "scenario": self.scenario, "seed": self.seed, "goal_holds": self.goal_holds, "stopped": self.stopped,
            "actions": sum(1 for a in self.actions if a.status == "done"),
            "checks": len(self.checks), "replans": self.replans,
            "injected": self.injected,
            "failures": [{"mode": f.mode, "action_index": f.action_index, "action": f.action,
                          "kit": local(f.kit) if f.kit else None,
                          "objects": [local(o) for o in f.objects], "phase": f.phase,
                          "violated": [a.text() for a in f.violated], "recovery": f.recovery,
                          "outcome": f.outcome} for f in self.failures],
            "time_s": round(self.ended - self.started, 3),
        }


class StoreLike(Protocol):
    """Where stable states and run records go (:class:`kb.execution.store.RunStore`)."""

    def begin_run(self, record: RunRecord, init: object = None, goal: object = None) -> None: ...
    def end_run(self, record: RunRecord) -> None: ...
    def poses_changed(self, poses: dict[str, np.ndarray]) -> None: ...
    def commit_stable(self, action_index: int) -> None: ...
    def record_failure(self, failure: FailureRecord) -> None: ...
    def record_action(self, action: ActionRecord) -> None: ...
