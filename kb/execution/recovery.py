"""Recovery: what the executor does when a check fails.

A violated check is diagnosed (:mod:`kb.diagnosis`: the ontology's failure modes of that action
and phase), recorded with the objects' expected and seen positions (:class:`FailureRecord`),
notified (the remediation's recipients) and recovered as the remediation says:

* **retry** the action, up to the remediation's limit;
* **rebind**: another usable part of the planned part's SKU lying in a parts tray replaces the
  missing or defective one, in this step and the rest of the plan;
* **replan** from the current state, decided from geometry, with the same goal
  (:mod:`kb.planning.replan`), parts the executor rejected excluded;
* **stop** for an operator (:class:`~kb.execution.steps.Stop`), saying why.

What a diagnosis learned about the planned part (:data:`LEARNED`: missing from its tray,
defective, of another SKU, dropped) is kept in the belief (:attr:`Belief.unusable
<kb.execution.belief.Belief.unusable>`) before anything else is done: no later rebinding,
replan (the planning state leaves the part out) or step of the plan uses it again, so one
fault gives one diagnosis. A step that still names such a part (no spare was left to put in
its place) is rebound or replanned when it comes up, without a new diagnosis, and the run
stops, saying which SKU ran out, when neither finds a part.

:class:`Recovery` is the half of :class:`kb.execution.executor.Executor` that does this; the
executor provides the cell, the belief, the records and the methods declared at the top.
"""

from __future__ import annotations

import time
from collections import deque
from typing import Callable

import numpy as np

from kb.core.errors import KitkbError, NotSolvableError
from kb.core.namespaces import KTW
from kb.crcl import COMMANDS, EndCanon, InitCanon, Message, MoveTo, Pose
from kb.crcl.cell import CellInterface
from kb.crcl.units import said_units
from kb.diagnosis import diagnose
from kb.execution.belief import SKU_OF, Belief
from kb.execution.events import Event, FailureFound, Recovered, Replanned
from kb.execution.records import AtomCheck, Check, FailureRecord, RunRecord, Sighting, StoreLike, local
from kb.execution.steps import Fields, Step, Stop
from kb.execution.targets import Targets, raised
from kb.model.failures import FailureModel, FailureModeDef
from kb.model.soap import DomainSpec
from kb.planning.problem import ProblemSpec
from kb.planning.replan import replan
from kb.planning.state import pddl_name
from kb.spatial.predicates import Evaluator


#: failure mode -> what it says about the planned part (``step.args["part"]``): never use it again
LEARNED: dict[str, str] = {
    "part-missing-from-tray": "missing", "parts-tray-empty": "missing", "defective-part": "defective",
    "wrong-sku": "wrong-sku", "dropped-part": "dropped", "dropped-part-in-transit": "dropped",
}


class Recovery:
    """Diagnosis, records and recovery of failed checks (a base of the executor)."""

    cell: CellInterface
    domain: DomainSpec
    spec: ProblemSpec
    failures: FailureModel
    belief: Belief
    store: StoreLike | None
    notifier: Callable[[str, str], None]
    planner: str | None
    max_replans: int
    record: RunRecord
    by_name: dict[str, str]
    stable: np.ndarray
    targets: Targets
    taken_from: dict[str, np.ndarray]
    index: int  # the next action's index
    _queue: deque
    _near: np.ndarray | None

    # provided by the executor
    def evaluator(self) -> Evaluator:
        raise NotImplementedError

    def _send(self, commands: list) -> list:
        raise NotImplementedError

    def parse_plan(self, lines: list[str]) -> list[Step]:
        raise NotImplementedError

    def _sense_all(self) -> None:
        raise NotImplementedError

    def _sense_classes(self, step: Step) -> None:
        raise NotImplementedError

    def _emit(self, event: Event) -> None:
        raise NotImplementedError

    # --- failures -------------------------------------------------------------------
    def _failed(self, step: Step, i: int, phase: str, check: Check, queue: deque) -> str:
        violated = check.violated
        if self._near is not None:  # the check saw the neighbourhood: diagnosis and recovery see all
            self._sense_classes(step)
        diag = diagnose(self.failures, self.evaluator(), step.action, phase, {a.predicate for a in violated},
                        step.args)
        failure = self._record_failure(i, step, phase, violated, diag)
        return self._recover(step, i, queue, failure, diag.mode)

    def _record_failure(self, i: int, step: Step, phase: str, violated: list[AtomCheck], diag) -> FailureRecord:  # noqa: ANN001
        names = []
        for a in violated:
            names.extend(x for x in a.args if x not in names)
        witnesses = self._witnesses(violated)
        names.extend(x for x in witnesses if x not in names)
        sightings = []
        for n in names:
            j = self.belief.index.get(n)
            if j is None:
                continue
            exp = None if np.isnan(self.stable[j, 0, 0]) else tuple(float(v) for v in self.stable[j, :3, 3])
            seen = tuple(float(v) for v in self.belief.poses[j, :3, 3]) if self.belief.placed(n) else None
            sightings.append(Sighting(n, exp, seen))
        mode = diag.mode
        failure = FailureRecord(i, step.action, tuple(step.args.values()), phase, list(violated), sightings,
                                diag.name, mode.consequence if mode else "", mode.severity if mode else 0,
                                time=time.perf_counter(), considered=list(diag.considered),
                                kit=self._kit_of(step), witnesses=witnesses)
        self.record.failures.append(failure)
        self._emit(FailureFound(i, step.action, step.line(), phase, tuple(a.text() for a in violated), failure.mode))
        if mode is not None:
            fields = Fields({k: local(v) for k, v in step.args.items()})
            if witnesses:  # {found}: what the check found (the part left on a table, say)
                fields["found"] = ", ".join(map(local, witnesses))
            for n in mode.remediation.notifications:
                self.notifier(n.recipient, n.message.format_map(fields))
        return failure

    def _witnesses(self, violated: list[AtomCheck]) -> list[str]:
        """The objects behind the violated existential atoms (what makes ``worktable-empty``
        false, say), on the belief as the diagnosis saw it; not the atoms' own arguments."""
        ev = self.evaluator()
        out: list[str] = []
        for a in violated:
            try:
                found = ev.witnesses(a.predicate, *a.args)
            except KitkbError:  # what the failure found is an aid: never a reason for the run to stop
                continue
            for x in found:
                if x not in a.args and x not in out:
                    out.append(x)
        return out

    def _kit_of(self, step: Step) -> str | None:
        """The kit an action works for: its kit argument, the kit its part is planned for, or
        the kit of its kit tray."""
        if "kit" in step.args:
            return step.args["kit"]
        part = step.args.get("part")
        if part is not None:
            for s in self._queue:
                if s.action == "put-part" and s.args.get("part") == part:
                    return s.args.get("kit")
        tray = step.args.get("kittray")
        if tray is not None:
            kits = [k for k, t in self.belief.facts.get(str(KTW.hasKit_KitTray), ()) if t == tray]
            return kits[0] if kits else None
        return None

    def _recover(self, step: Step, i: int, queue: deque, failure: FailureRecord, mode: FailureModeDef | None) -> str:
        rem = mode.remediation if mode is not None else None
        kind = rem.recovery if rem is not None else "Replan"
        learned, part = LEARNED.get(failure.mode), step.args.get("part")
        if learned is not None and part is not None:
            self.belief.learn(part, learned)
        if rem is not None and (kind == "Abort" or rem.operator):
            why = "the remediation asks for an operator" if rem.operator else "the remediation aborts the run"
            failure.recovery, failure.outcome = "stop", "stopped for an operator" if rem.operator else "aborted"
            self._store_failure(failure)
            raise Stop(f"{failure.mode} at action {i} {step.line()}: {mode.consequence if mode else ''} "
                       f"({why})" + self._shortage(step, queue))
        if kind == "RetryAction" and step.retries < (rem.max_retries if rem else 0):
            step.retries += 1
            failure.recovery, failure.outcome = "retry", f"retry {step.retries} of {rem.max_retries}"
            self._store_failure(failure)
            self._emit(Recovered(i, "retry", why=failure.outcome))
            queue.appendleft(step)
            return "next"
        if failure.mode in ("part-missing-from-tray", "parts-tray-empty", "defective-part"):
            return self._rebind_or_replan(step, i, queue, failure, failure.mode)
        if failure.mode == "wrong-sku":
            self._reject_held(step.args["part"])
        if kind == "ExecuteRecoveryPlan" and rem is not None and rem.plan:
            # the recovery plan's actions (e.g. attach-endeffector) need arguments the failed
            # step does not have; the planner finds them, from the current state
            failure.recovery = "recovery-plan (" + ", ".join(rem.plan) + ") by replanning"
        return self._replan(queue, failure)

    def _rebind_or_replan(self, step: Step, i: int, queue: deque, failure: FailureRecord | None, why: str) -> str:
        old = step.args["part"]
        new = self._another_part(old, queue)
        if new is None:
            return self._replan(queue, failure)
        part, tray = new
        self._substitute(old, part, queue)
        step.args["part"], step.args["partstray"] = part, tray
        if failure is not None:
            failure.recovery, failure.outcome = "rebind", f"recovered: bound {local(part)} from {local(tray)}"
            self._store_failure(failure)
        self._emit(Recovered(i, "rebind", local(old), local(part), why))
        queue.appendleft(step)
        return "next"

    def _shortage(self, step: Step, queue: deque) -> str:
        """Why a part to take cannot be replaced: no usable part of its SKU left in a tray."""
        part = step.args.get("part") if step.action == "take-part" else None
        if part is None or self._another_part(part, queue) is not None:
            return ""
        return f"; no usable part of {local(self._planned_sku(part))} is left in a parts tray"

    def _another_part(self, old: str, queue: deque, exclude: set[str] = frozenset()) -> tuple[str, str] | None:  # type: ignore[assignment]
        """A usable part of ``old``'s SKU lying in a parts tray, preferring one the rest of the
        plan does not use."""
        sku = self._planned_sku(old)
        ev = self.evaluator()
        refs, trays, truth = ev.table("part-location-partstray")
        later = {a for s in queue for a in s.args.values()}
        found = []
        for r, t in zip(*np.nonzero(truth)):
            p = refs[r]
            if p == old or p in exclude or not self.belief.usable(p) or self.belief.related(SKU_OF, p) != [sku]:
                continue
            found.append((p in later, p, trays[t]))
        if not found:
            return None
        found.sort()
        return found[0][1], found[0][2]

    def _planned_sku(self, part: str) -> str:
        name = pddl_name(part)
        for f in self.spec.facts:
            if f[0] == "part-sku" and f[1] == name:
                return self.by_name.get(f[2], f[2])
        skus = self.belief.related(SKU_OF, part)
        return skus[0] if skus else ""

    def _substitute(self, old: str, new: str, queue: deque) -> None:
        """``new`` replaces ``old`` in the rest of the plan; steps that planned to use ``new``
        get another usable part of its SKU (``old`` only if it is still usable; when no spare is
        left they keep ``old``, known unusable, and are rebound or replanned without a new
        diagnosis when they come up)."""
        took_new = [s for s in queue if new in s.args.values()]
        for s in queue:
            for k, v in s.args.items():
                if v == old:
                    s.args[k] = new
        if not took_new:
            return
        usable = self.belief.usable(old) and self._in_a_tray(old)
        # a spare the rest of the plan does not take already (else the SKU would come up one
        # part short far later, at a step no fault touched)
        later = {a for s in queue if s not in took_new for a in s.args.values()}
        spare = (old, None) if usable else self._another_part(new, queue, exclude={old} | later)
        for s in took_new:
            for k, v in list(s.args.items()):
                if v == new and k == "part":
                    s.args["part"] = spare[0] if spare else old
                    if spare and spare[1] is not None and "partstray" in s.args:
                        s.args["partstray"] = spare[1]

    def _in_a_tray(self, part: str) -> bool:
        refs, _trays, truth = self.evaluator().table("part-location-partstray", [part])
        return bool(truth.any())

    def _reject_held(self, part: str) -> None:
        """Put a held part that must not go into a kit back where it was taken."""
        self.belief.learn(part, "wrong-sku")
        grasp = self.taken_from.get(part)
        if grasp is None:
            return
        commands = [InitCanon(), *said_units(), Message(f"reject {local(part)}"), MoveTo(Pose.from_matrix(raised(grasp, 0.1))),
                    MoveTo(Pose.from_matrix(grasp)), COMMANDS["OpenGripper"](),
                    MoveTo(Pose.from_matrix(raised(grasp, 0.1))), EndCanon()]
        self._send(commands)
        self.targets.tip = raised(grasp, 0.1)
        self._emit(Recovered(self.index - 1, "reject", local(part)))

    def _replan(self, queue: deque, failure: FailureRecord | None) -> str:
        if self.record.replans >= self.max_replans:
            raise Stop(f"gave up after {self.record.replans} replans")
        self.record.replans += 1
        self._sense_all()
        ev = self.evaluator()
        facts = {(n, *map(pddl_name, a)) for n, a in ev.facts()}
        values: dict[tuple[str, ...], float] = {}
        for fn in self.domain.functions:
            for args, v in ev.function_values(fn).items():
                values[(fn, *map(pddl_name, args))] = v
        excluded = {pddl_name(p) for p in self.belief.unusable}
        started = time.perf_counter()
        try:
            result = replan(self.domain, self.spec, facts, values, excluded, self.planner)
        except Exception as e:  # no plan, or a planner that broke: the run stops, saying why
            why = str(e) if isinstance(e, NotSolvableError) else f"replanning failed: {type(e).__name__}: {e}"
            if failure is not None:
                failure.recovery, failure.outcome = "replan", f"stopped: {why}"
                self._store_failure(failure)
            raise Stop(why) from None
        finally:
            self.record.replan_time += time.perf_counter() - started
        queue.clear()
        queue.extend(self.parse_plan(result.lines))
        if failure is not None:
            failure.recovery = failure.recovery or "replan"
            failure.outcome = failure.outcome or f"recovered: new plan of {len(result.lines)} actions"
            self._store_failure(failure)
        self._emit(Replanned(len(result.lines)))
        return "next"

    def _store_failure(self, failure: FailureRecord) -> None:
        if self.store is not None:
            self.store.record_failure(failure)
