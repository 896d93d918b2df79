"""What a run leaves behind: actions, checks, commands, failures and recoveries.

Dataclasses with one dict form each (:class:`~kb.execution.codec.Record`: ``to_dict`` /
``from_dict``, derived from their fields; every field checked when it is set, see
:mod:`kb.execution.codec` for what is legal). The world-model database's run rows
(:mod:`kb.execution.store`) hold that dict form, which :func:`kb.execution.open_run` reads back
equal to the run in memory; the JSON report (:meth:`RunRecord.report`) is a view of it with the
figures computed from it. The executives' API (:mod:`kb.execution.api`) queries them.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Protocol

import numpy as np

from kb.execution.codec import Record, field_codec
from kb.metrics.clock import timed_commands
from kb.metrics.execution import execution_metrics
from kb.metrics.kits import KitScore
from kb.metrics.motion import cell_robot
from kb.metrics.steps import text_steps


def local(iri: str) -> str:
    return str(iri).rsplit("#", 1)[-1].rsplit("/", 1)[-1]


@dataclass
class AtomCheck(Record):
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
class Check(Record):
    action_index: int
    phase: str  # "precondition" or "effect"
    atoms: list[AtomCheck]
    time: float
    #: with a noisy sensor: atoms violated at the noise tolerance but not at the exact one even
    #: after more looks, so noise makes them undecidable; the check does not fail on them
    undecidable: list[AtomCheck] = field(default_factory=list)

    @property
    def ok(self) -> bool:
        return all(a.ok for a in self.atoms)

    @property
    def violated(self) -> list[AtomCheck]:
        return [a for a in self.atoms if not a.ok]


@dataclass
class Sighting(Record):
    """Where an object of a violated atom was expected (last stable state) and where it was seen."""

    name: str
    expected: tuple[float, float, float] | None
    seen: tuple[float, float, float] | None


@dataclass
class Notice(Record):
    """A notification sent about a failure: its recipient, its message, and what it carries as
    data (:meth:`kb.execution.recovery.Recovery._attachments`: the failed action and its
    arguments, the violated atoms, where the objects were expected and seen, what the check
    found, the poses the step's objects were grasped at)."""

    recipient: str
    message: str
    attachments: dict[str, Any] = field(default_factory=dict)


@dataclass
class FailureRecord(Record):
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
    #: with a noisy sensor, how sure the failure is: "certain" (every violated atom violated at
    #: the exact tolerance and at the noise tolerance) or "uncertain"; None: an exact sensor
    certainty: str | None = None
    #: the objects that decided an existential atom violated (``worktable-empty(table)``
    #: false: what rests on the table), found when the failure was diagnosed
    witnesses: list[str] = field(default_factory=list)
    #: the notifications the remediation sent, each with its attachments
    notifications: list[Notice] = field(default_factory=list)

    @property
    def objects(self) -> list[str]:
        """The violated atoms' arguments, then the witnesses that are not among them."""
        seen: list[str] = []
        for x in [x for a in self.violated for x in a.args] + self.witnesses:
            if x not in seen:
                seen.append(x)
        return seen

    @property
    def where(self) -> tuple[float, float, float] | None:
        """Where the failure happened: where the first witness was seen (what was found where
        nothing should be), else the first object seen away from its expected place (the object
        that moved), else the first object seen, else the first expected."""
        for s in self.sightings:
            if s.name in self.witnesses and s.seen is not None:
                return s.seen
        for s in self.sightings:
            if s.seen is not None and s.expected is not None and \
                    max(abs(a - b) for a, b in zip(s.seen, s.expected)) > 1e-3:
                return s.seen
        for s in self.sightings:
            if s.seen is not None:
                return s.seen
        return next((s.expected for s in self.sightings if s.expected is not None), None)

    def why(self) -> str:
        """One paragraph: what was violated, where the objects were expected and seen."""
        lines = [f"action {self.action_index} ({self.action} {' '.join(map(local, self.args))}) failed its "
                 f"{self.phase} check: " + "; ".join(a.text() + " is " + ("true" if a.holds else "false")
                                                       for a in self.violated)]
        if self.witnesses:
            lines[0] += " (found: " + ", ".join(map(local, self.witnesses)) + ")"
        for s in self.sightings:
            exp = "unknown" if s.expected is None else "(%.3f, %.3f, %.3f)" % s.expected
            seen = "not seen" if s.seen is None else "(%.3f, %.3f, %.3f)" % s.seen
            lines.append(f"  {local(s.name)}: expected at {exp}, seen at {seen}")
        lines.append(f"  diagnosis: {self.mode}" + (f" ({self.consequence})" if self.consequence else "")
                     + (f", {self.certainty}" if self.certainty else ""))
        lines.append(f"  recovery: {self.recovery} -> {self.outcome}")
        return "\n".join(lines)


@dataclass
class ActionRecord(Record):
    index: int
    action: str
    args: tuple[str, ...]
    status: str = "pending"  # done, failed, skipped
    commands: list[str] = field(default_factory=list)
    started: float = 0.0
    ended: float = 0.0
    #: the CRCL programs sent for the action, in order, each as its statements (CRCL text)
    programs: list[list[str]] = field(default_factory=list)


@dataclass
class RunRecord(Record):
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
    plan_time: float | None = None  # seconds the first plan took, where the run planned it
    replan_time: float = 0.0  # seconds all replans took
    #: diagnoses of an event already diagnosed (issue 29: one fault, one diagnosis): each the
    #: object, the failure that first diagnosed it and the one that diagnosed it again (action
    #: index, mode), with no action on the object between them (kb.execution.recovery); target []
    repeated_diagnoses: list[dict[str, Any]] = field(default_factory=list)
    #: the constraint violations the cell reported as its ground truth (a simulated cell:
    #: contacts, overweight grasps, ...); None: a cell that reports none
    violations: list[dict[str, Any]] | None = None
    kits: list[KitScore] = field(default_factory=list)  # each goal kit's score at the end
    tip_start: tuple[float, float, float] | None = None  # the tool tip at the start (m)
    #: the objects as the report draws them: name, class, box, initial and final pose
    scene: dict[str, Any] | None = None
    #: with a sensor that is not exact: its accuracy as the executor assumed it (SI), the sensor
    #: queries made, the undecidable atoms; None with an exact one (the report then has no
    #: "sensor" key)
    sensor: dict[str, Any] | None = None
    #: what a simulated sensor did wrong (misdetections, misclassifications), like ``injected``
    sensor_errors: list[dict[str, Any]] | None = None
    #: the goal atoms and counts that did not hold at the end (``robot-with-no-endeffector(robot_1)``,
    #: ``quantity-kit(kit_1, sku_a) = capacity-kit(kit_1, sku_a) (1, not 2)``; kb.planning.goal.unmet)
    goal_unmet: list[str] = field(default_factory=list)
    #: the kits the usable parts could not finish (kb.execution.partial): each kit, how it ended
    #: (``delivered partial`` | ``left``) and what it lacks (SKU -> count); [] when every kit could be
    partial_kits: list[dict[str, Any]] = field(default_factory=list)
    #: each time the run was stopped and resumed (kb.execution.resume): the last action before
    #: the stop (``after``), why it stopped, when it stopped and was resumed (seconds since the
    #: run started), the state file the operator's cell held (``truth``, None: as at the stop)
    resumes: list[dict[str, Any]] = field(default_factory=list)
    #: what was buildable, from the cell's ground truth at the end (kb.metrics.oracle:
    #: ``kits_buildable``, ``kits_built``, ``completion``, the usable parts per SKU, those not
    #: counted and why); ``{"unknown": why}`` from a cell that tells no part fates; None: not made
    oracle: dict[str, Any] | None = None

    @property
    def succeeded(self) -> bool:
        return self.stopped is None and bool(self.goal_holds)

    def metrics(self) -> dict[str, Any]:
        """The execution metrics of the run (:func:`kb.metrics.execution.execution_metrics`), its
        times on the cell's clock (:func:`kb.metrics.motion.cell_robot`)."""
        robot = cell_robot(self.tip_start)
        return execution_metrics(self.failures, self.actions, replans=self.replans, plan_time=self.plan_time,
                                 replan_time=self.replan_time, violations=self.violations, robot=robot,
                                 scene=self.scene, injected=self.injected, sensor_errors=self.sensor_errors,
                                 checks=len(self.checks), resumes=len(self.resumes), stopped=self.stopped)

    def path(self) -> list[dict[str, Any]]:
        """The tool tip's commanded positions (m, to the micrometre), per action, in order."""
        out = []
        for a in self.actions:
            points = [[round(float(v), 6) for v in p[:3]] for program in a.programs for kind, _line, value in text_steps(program)
                      if kind in ("MoveTo", "MoveStraightTo", "MoveThroughTo") for p in value]
            if points:
                out.append({"index": a.index, "points": points})
        return out

    def timeline(self) -> list[dict[str, Any]]:
        """Actions and failures in time order (seconds since the run started)."""
        t0 = self.started
        events: list[tuple[float, int, dict[str, Any]]] = []
        for a in self.actions:
            events.append((a.started - t0, 0, {"kind": "action", "index": a.index, "action": a.action,
                                               "args": [local(x) for x in a.args], "status": a.status,
                                               "seconds": round(max(0.0, a.ended - a.started), 4)}))
        for f in self.failures:
            events.append((f.time - t0, 1, {"kind": "failure", "index": f.action_index, "action": f.action,
                                            "mode": f.mode, "recovery": f.recovery, "outcome": f.outcome,
                                            "objects": [local(o) for o in f.objects]}))
        for r in self.resumes:  # the stop, and the resume after the operator (kb.execution.resume)
            events.append((float(r["stopped_t"]), 2, {"kind": "stop", "index": r["after"], "why": r["stopped"]}))
            events.append((float(r["resumed_t"]), 2, {"kind": "resume", "index": r["after"] + 1,
                                                      "truth": r.get("truth")}))
        events.sort(key=lambda e: (e[0], e[1]))
        return [dict(e[2], t=round(max(0.0, e[0]), 4)) for e in events]

    def report(self) -> dict[str, Any]:
        """The JSON report: goal_holds, injected faults, failures (diagnoses), counts, the
        execution metrics, each kit's score, and what a report page draws (scene, path,
        timeline). The run's own fields are as in its dict form (:meth:`to_dict`)."""
        own = {name: field_codec(RunRecord, name)(getattr(self, name), f"RunRecord.{name}") for name in _REPORTED}
        return {
            "scenario": own["scenario"], "seed": own["seed"], "goal_holds": own["goal_holds"],
            "goal_unmet": own["goal_unmet"], "partial_kits": own["partial_kits"], "stopped": own["stopped"],
            "kits_buildable": (self.oracle or {}).get("kits_buildable"),
            "completion": (self.oracle or {}).get("completion"),
            "actions": sum(1 for a in self.actions if a.status == "done"),
            "checks": len(self.checks), "replans": self.replans,
            "repeated_diagnoses": len(self.repeated_diagnoses),
            **({"repeated": [dict(r) for r in self.repeated_diagnoses]} if self.repeated_diagnoses else {}),
            "injected": own["injected"],
            "failures": [{"mode": f.mode, "action_index": f.action_index, "action": f.action,
                          "kit": local(f.kit) if f.kit else None,
                          "objects": [local(o) for o in f.objects], "phase": f.phase,
                          "violated": [a.text() for a in f.violated], "recovery": f.recovery,
                          "outcome": f.outcome, **({"certainty": f.certainty} if f.certainty else {}),
                          **({"notifications": [n.to_dict() for n in f.notifications]} if f.notifications else {}),
                          **({"where": [round(v, 4) for v in f.where]} if f.where is not None else {})}
                         for f in self.failures],
            "time_s": round(self.ended - self.started, 3),
            "metrics": self.metrics(),
            "kits": [k.as_dict() for k in self.kits],
            "violations": own["violations"], "tip_start": own["tip_start"] or None,
            "scene": own["scene"], "path": self.path(), "timeline": self.timeline(),
            "commands": timed_commands(self.actions, cell_robot(self.tip_start)),  # the replay's, on the cell's clock
            **({"resumes": own["resumes"]} if self.resumes else {}),
            **({"oracle": own["oracle"]} if self.oracle is not None else {}),
            **({"sensor": own["sensor"]} if own["sensor"] is not None else {}),
            **({"sensor_errors": own["sensor_errors"]} if own["sensor_errors"] is not None else {}),
        }


#: the run's fields its JSON report holds as they are (in their dict form)
_REPORTED = ("scenario", "seed", "goal_holds", "goal_unmet", "partial_kits", "stopped", "injected", "violations", "tip_start", "scene", "sensor",
             "sensor_errors", "resumes", "oracle")


#: where a report holds what the clock decides (seconds): top-level keys, metrics keys, timeline keys
TIMINGS = {"report": ("time_s",), "metrics": ("plan_time_s", "replan_time_s"), "timeline": ("t", "seconds")}


def without_timings(report: dict[str, Any]) -> dict[str, Any]:
    """A run's report without its times (:data:`TIMINGS`): what the same seed, faults and
    files must give again."""
    out = {k: v for k, v in report.items() if k not in TIMINGS["report"]}
    if isinstance(out.get("metrics"), dict):
        out["metrics"] = {k: v for k, v in out["metrics"].items() if k not in TIMINGS["metrics"]}
    if isinstance(out.get("timeline"), list):
        out["timeline"] = [{k: v for k, v in e.items() if k not in TIMINGS["timeline"]} for e in out["timeline"]]
    return out


class StoreLike(Protocol):
    """Where stable states and run records go (:class:`kb.execution.store.RunStore`)."""

    def begin_run(self, record: RunRecord, init: object = None, goal: object = None) -> None: ...
    def end_run(self, record: RunRecord) -> None: ...
    def poses_changed(self, poses: dict[str, np.ndarray]) -> None: ...
    def commit_stable(self, action_index: int) -> None: ...
    def record_failure(self, failure: FailureRecord) -> None: ...
    def record_action(self, action: ActionRecord) -> None: ...
