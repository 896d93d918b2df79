"""Execution metrics of kit building (the first paper's §IV-B) from what a run recorded.

Computed from plain records (a run in memory or read back from its database give the same
figures, :func:`execution_metrics`):

* **failures** and **failures per kit** — "if a failure occurs during the execution of the new
  plan ... the number of failures for building the current kit is incremented": every
  diagnosed failure counts once for the kit its action worked for, across retries and
  replans (failures of no kit, e.g. changing an end effector, under ``"-"``);
* **failure modes recovered** — "the number of failure modes the system recovers from through
  the use of contingency plans": a failure whose remediation worked — a rebind or replan that
  went on (its outcome ``recovered: ...``), or a retry after which the same action was done;
  the others are unrecovered; both by mode;
* **plan generation** — the first plan's time, the replans and the time they took;
* **contact errors** and the other constraint violations, where the cell reports its ground
  truth (a simulated cell; a real cell reports none: ``None``), also as the constraint metrics
  a program's playback gives (``constraints``: OVW, WVE, WEE, CTE);
* the **static metrics** (§IV-A) of the CRCL the run sent, one program per action
  (:func:`~kb.metrics.static.session_metrics`).
"""

from __future__ import annotations

from collections import Counter
from typing import Any, Iterable, Protocol, Sequence

from kb.metrics.clock import timed_commands
from kb.metrics.motion import Robot
from kb.metrics.robustness import paper_metrics
from kb.metrics.score import CONSTRAINT_OF_KIND
from kb.metrics.static import session_metrics
from kb.metrics.steps import text_steps


class FailureLike(Protocol):
    action_index: int
    action: str
    args: tuple[str, ...]
    mode: str
    recovery: str
    outcome: str
    kit: str | None


class ActionLike(Protocol):
    index: int
    action: str
    args: tuple[str, ...]
    status: str
    programs: list[list[str]]


def _local(iri: str) -> str:
    return str(iri).rsplit("#", 1)[-1].rsplit("/", 1)[-1]


def recovered(failure: FailureLike, actions: Sequence[ActionLike]) -> bool:
    """Whether the failure's remediation worked (see the module's docstring)."""
    if failure.outcome.startswith("recovered"):
        return True
    if failure.recovery == "retry":
        return any(a.index > failure.action_index and a.action == failure.action and a.args == failure.args
                   and a.status == "done" for a in actions)
    return False


def crcl_metrics(actions: Iterable[ActionLike], robot: Robot | None = None) -> dict[str, float]:
    """The static metrics of the CRCL programs the actions sent, in order (distances and times
    to the micrometre and microsecond)."""
    programs = (list(text_steps(program)) for a in actions for program in a.programs)
    # the executor computes in SI and says so after each InitCanon (older runs' programs did not)
    totals = session_metrics(programs, robot or Robot(length_unit="meter", angle_unit="radian")).totals
    return {k: round(v, 6) if isinstance(v, float) else v for k, v in totals.items()}


def execution_metrics(failures: Sequence[FailureLike], actions: Sequence[ActionLike], *, replans: int,
                      plan_time: float | None = None, replan_time: float = 0.0,
                      violations: Sequence[dict[str, Any]] | None = None,
                      robot: Robot | None = None, scene: dict[str, Any] | None = None,
                      injected: Sequence[dict[str, Any]] = (), sensor_errors: Sequence[Any] | None = None,
                      checks: int = 0, resumes: int = 0, stopped: str | None = None) -> dict[str, Any]:
    """The execution metrics of a run (JSON data; see the module's docstring), with the first
    paper's transporting components, manipulation robustness, failure classes and failure modes
    recovery (:func:`kb.metrics.robustness.paper_metrics`; ``scene``, ``injected``,
    ``sensor_errors``: the run's, ``checks`` how many it made, ``resumes`` how many times an
    operator resumed it, ``stopped`` why it stopped)."""
    per_kit = Counter(_local(f.kit) if f.kit else "-" for f in failures)
    done = [recovered(f, actions) for f in failures]
    by_mode = Counter(f.mode for f in failures)
    rec_mode = Counter(f.mode for f, ok in zip(failures, done) if ok)
    out: dict[str, Any] = {
        "failures": len(failures), "failures_per_kit": dict(sorted(per_kit.items())),
        "failures_by_mode": dict(sorted(by_mode.items())),
        "recovered": sum(done), "unrecovered": len(failures) - sum(done),
        "recovered_by_mode": dict(sorted(rec_mode.items())),
        "plan_time_s": None if plan_time is None else round(plan_time, 4),
        "replans": replans, "replan_time_s": round(replan_time, 4),
        "contact_errors": None, "violations": None, "constraints": None,
        "static": crcl_metrics(actions, robot),
    }
    out.update(paper_metrics(failures, done, timed_commands(actions, robot), scene=scene, injected=injected,
                             violations=violations, sensor_errors=sensor_errors, checks=checks, resumes=resumes,
                             stopped=stopped))
    if violations is not None:
        kinds = Counter(str(v.get("kind")) for v in violations)
        out["contact_errors"] = kinds.get("contact", 0)
        out["violations"] = dict(sorted(kinds.items()))
        out["constraints"] = {metric: kinds.get(kind, 0) for kind, metric in CONSTRAINT_OF_KIND.items()}
    return out
