"""The execution metrics the first paper names in §IV-B that a run's failures alone do not give,
computed alike for every system from what the harness observes — the commands sent (timed:
:mod:`kb.metrics.clock`), the scene, the cell's ground truth (injected faults, constraint
violations, sensor errors) — and from the failures a system diagnosed:

* **transporting components** — "how well a robotic arm can grasp objects and move these objects
  from an initial position to a goal position without dropping them": the parts the robot
  transported (grasped and carried, :mod:`kb.metrics.handling`), those of them that ended in a
  kit tray and were never dropped, and the share;
* **manipulation robustness**, decomposed as the paper envisions it — "failures can occur during
  object detection ..., object approach ..., and object manipulation ... operations" and "operator
  interventions": per stage its attempts, the robot's failures (ground truth) and failures per
  attempt — detection: each check's look at the action's objects, failed when the sensor missed
  or misclassified an object; approach: each move, failed by a contact or a target outside the
  work volume; manipulation: each gripper or tool changer command, failed by a grasp that missed,
  a part dropped, an overweight or a wrong-effector grasp —, and the operator's interventions (each
  stop and resume, and a run that stopped short of its goal);
* **failure classes** — "precondition failures, action failures, and unattributable failures":
  a diagnosed failure is *unattributable* when an external agent (a fault whose mechanism is
  not the robot's: a part or tray moved or taken away, a part swapped or defective) struck one of
  its objects at or before its action; an *action* failure when the robot's own grasp failed on
  one of them (a grasp that missed, a part dropped: ground truth; the next action's
  preconditions may be what finds it), or it was found by an effect check or an inspection;
  else a *precondition* failure;
* **failure modes recovery** — "the number of failure modes the system recovers from": the
  distinct modes with a recovered failure, beside the count of recovered instances.

Without a cell's ground truth (a real cell) the ground-truth figures are ``None``.
"""

from __future__ import annotations

from typing import Any, Sequence

import numpy as np

from kb.metrics.handling import (CONTENT_REACH, DROPPED, EXTERNAL, GRASP_MISSED, box_corners, fault_mechanisms,
                                 handled, placed)

#: the constraint violations (kb.sim.robot's kinds) that are an approach's or a manipulation's failure
APPROACH_VIOLATIONS = ("contact", "work-volume")
MANIPULATION_VIOLATIONS = ("overweight", "wrong-effector")
_MOVES = ("MoveTo(", "MoveStraightTo(", "MoveThroughTo(")
_GRIPS = ("CloseGripper(", "OpenGripper(", "CloseToolChanger(", "OpenToolChanger(", "SetEndEffector(")


def _local(name: Any) -> str:
    return str(name).rsplit("#", 1)[-1].rsplit("/", 1)[-1]


def _share(failures: int | None, attempts: int) -> float | None:
    return None if failures is None or attempts == 0 else round(failures / attempts, 6)


def _stage(attempts: int, failures: int | None) -> dict[str, Any]:
    return {"attempts": attempts, "failures": failures, "per_attempt": _share(failures, attempts)}


def transporting(commands: dict[str, Any], scene: dict[str, Any] | None, injected: Sequence[dict[str, Any]],
                 mechanisms: dict[str, str]) -> dict[str, Any]:
    """Transporting components (module docstring); None figures without a scene."""
    if not isinstance(scene, dict) or not scene.get("objects"):
        return {"parts_transported": None, "parts_delivered": None, "dropped": None, "rate": None}
    moves = handled(commands, scene, injected, mechanisms).transports
    parts = [m for m in moves if m.cls == "Part" and (m.dropped or m.carried > 0.01)]
    names = {m.name for m in parts}
    dropped = {m.name for m in parts if m.dropped}
    in_kit = _in_kit_trays(scene)
    delivered = {n for n in names - dropped if n in in_kit}
    return {"parts_transported": len(names), "parts_delivered": len(delivered), "dropped": len(dropped),
            "rate": _share(len(delivered), len(names))}


def _in_kit_trays(scene: dict[str, Any]) -> set[str]:
    """The parts whose final box centre lies in a kit tray's final box (up to a little above it)."""
    objs = [o for o in scene.get("objects") or [] if placed(o, "final")]
    trays = [box_corners(o["lo"], o["hi"], o["final"]) for o in objs if o.get("class") == "KitTray"]
    bounds = [(c.min(axis=0), c.max(axis=0)) for c in trays]
    out = set()
    for o in objs:
        if o.get("class") != "Part":
            continue
        centre = box_corners(o["lo"], o["hi"], o["final"]).mean(axis=0)
        if any(np.all(centre[:2] >= lo[:2]) and np.all(centre[:2] <= hi[:2]) and lo[2] <= centre[2] <= hi[2] + CONTENT_REACH
               for lo, hi in bounds):
            out.add(str(o.get("name")))
    return out


def robustness(commands: dict[str, Any], *, checks: int, injected: Sequence[dict[str, Any]],
               mechanisms: dict[str, str], violations: Sequence[dict[str, Any]] | None,
               sensor_errors: Sequence[Any] | None, resumes: int, stopped: str | None) -> dict[str, Any]:
    """Manipulation robustness by stage (module docstring)."""
    texts = [str(r[1]) for r in commands.get("rows") or []]
    truth = violations is not None
    kinds = [str(v.get("kind")) for v in violations or []]
    robot_faults = sum(1 for x in injected if mechanisms.get(str(x.get("kind"))) in (GRASP_MISSED, DROPPED))
    return {
        "detection": _stage(checks, len(sensor_errors or []) if truth or sensor_errors is not None else None),
        "approach": _stage(sum(t.startswith(_MOVES) for t in texts),
                           sum(k in APPROACH_VIOLATIONS for k in kinds) if truth else None),
        "manipulation": _stage(sum(t.startswith(_GRIPS) for t in texts),
                               robot_faults + sum(k in MANIPULATION_VIOLATIONS for k in kinds) if truth or injected
                               else None),
        "operator_interventions": resumes + (1 if stopped and stopped != "interrupted" else 0),
    }


def failure_classes(failures: Sequence[Any], injected: Sequence[dict[str, Any]], mechanisms: dict[str, str],
                    ground_truth: bool) -> dict[str, Any]:
    """Each diagnosed failure as precondition, action or unattributable (module docstring)."""
    struck: dict[str, list[int]] = {}  # by an external agent
    slipped: dict[str, list[int]] = {}  # by the robot's own grasp
    for x in injected:
        mechanism = mechanisms.get(str(x.get("kind")))
        into = struck if mechanism in EXTERNAL else slipped if mechanism in (GRASP_MISSED, DROPPED) else None
        if into is not None and isinstance(x.get("action_index"), int):
            for o in x.get("objects") or []:
                into.setdefault(_local(o), []).append(x["action_index"])
    out: dict[str, Any] = {"precondition": 0, "action": 0, "unattributable": 0 if ground_truth else None}
    for f in failures:
        objects = {_local(o) for o in getattr(f, "objects", ())}
        if ground_truth and any(k <= f.action_index for o in objects for k in struck.get(o, ())):
            out["unattributable"] += 1
        elif any(k <= f.action_index for o in objects for k in slipped.get(o, ())):
            out["action"] += 1  # the robot's grasp failed (found, perhaps, by the next action's preconditions)
        elif getattr(f, "phase", "") == "precondition":
            out["precondition"] += 1
        else:
            out["action"] += 1
    return out


def modes_recovery(failures: Sequence[Any], recovered: Sequence[bool]) -> dict[str, Any]:
    """Failure modes recovery: distinct modes recovered from, beside the instances."""
    seen = sorted({f.mode for f in failures})
    got = sorted({f.mode for f, ok in zip(failures, recovered) if ok})
    return {"failure_modes": len(seen), "failure_modes_recovered": len(got),
            "modes_not_recovered": [m for m in seen if m not in got]}


def paper_metrics(failures: Sequence[Any], recovered: Sequence[bool], commands: dict[str, Any], *,
                  scene: dict[str, Any] | None = None, injected: Sequence[dict[str, Any]] = (),
                  violations: Sequence[dict[str, Any]] | None = None, sensor_errors: Sequence[Any] | None = None,
                  checks: int = 0, resumes: int = 0, stopped: str | None = None) -> dict[str, Any]:
    """The §IV-B metrics of this module for one run (JSON data): ``transporting``,
    ``robustness``, ``failure_classes`` and the modes recovery's keys."""
    injected = [x for x in injected if isinstance(x, dict)]
    mechanisms = fault_mechanisms(sorted({str(x.get("kind")) for x in injected}))
    truth = violations is not None
    return {"transporting": transporting(commands, scene, injected, mechanisms),
            "robustness": robustness(commands, checks=checks, injected=injected, mechanisms=mechanisms,
                                     violations=violations, sensor_errors=sensor_errors, resumes=resumes,
                                     stopped=stopped),
            "failure_classes": failure_classes(failures, injected, mechanisms, truth),
            **modes_recovery(failures, recovered)}
