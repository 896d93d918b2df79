"""Recovery: what the executor does when a check fails.

A violated check is diagnosed (:mod:`kb.diagnosis`: the ontology's failure modes of that action
and phase), recorded with the objects' expected and seen positions (:class:`FailureRecord`),
notified (the remediation's recipients; each notification carries the failure's data: its
violated atoms, where its objects were expected and seen, the pose a held object was grasped at:
:class:`~kb.execution.records.Notice`) and recovered as the remediation says. Everything here
follows from the failure mode's data (:mod:`kb.model.failures`); no mode is known by name:

* what the mode implies about its objects (``soap:hasFailureMode_ObjectConsequence``) is kept
  in the belief before anything else is done (:data:`CONSEQUENCES`): a **condemned** or
  **missing** object is never used again (:attr:`Belief.unusable
  <kb.execution.belief.Belief.unusable>`: no later rebinding, replan or step takes it, so one
  fault gives one diagnosis); one **reusable after inspection** is not used until an inspection
  passes it; a **moved** one is expected where it was sensed;
* an operator intervention stops the run (:class:`~kb.execution.steps.Stop`), saying why;
* else the remediation's strategy (``soap:hasFailureRemediation_Recovery``) is carried out by
  its handler (:data:`STRATEGIES`, the one place strategies are named): **retry** the action up
  to the remediation's limit; **rebind** another usable object of the same SKU in place of the
  remediation's object, in this step and the rest of the plan; **reject** the held object (put
  it down where it was grasped); **execute the recovery plan** (its steps are domain actions,
  their arguments bound from the failure, queued before the rest of the plan and checked like
  any plan action); **replan** from the current state, decided from geometry, with the same goal
  (:mod:`kb.planning.replan`), objects found unusable excluded; **abort**. A retry, rebinding
  or recovery plan that cannot be done replans; recovery plans are bounded (``max_replans``), and
  so are replans that make no progress (``max_replans`` in a row whose plan is no shorter than
  the shortest before). A failure without a diagnosis replans.

A step that still names an unusable part (no spare was left to put in its place) is rebound or
replanned when it comes up, without a new diagnosis, and the run stops, saying which SKU ran
out, when neither finds a part.

:class:`Recovery` is the half of :class:`kb.execution.executor.Executor` that does this; the
executor provides the cell, the belief, the records and the methods declared at the top.
"""

from __future__ import annotations

import time
from collections import deque
from dataclasses import dataclass
from typing import Any, Callable

import numpy as np

from kb.core.errors import KitkbError, NotSolvableError
from kb.core.namespaces import KTW, SOAP
from kb.crcl import COMMANDS, EndCanon, InitCanon, Message, MoveTo, Pose
from kb.crcl.cell import CellInterface, has
from kb.crcl.units import said_units
from kb.diagnosis import diagnose
from kb.execution.belief import SKU_OF, Belief
from kb.execution.events import Event, FailureFound, Recovered, Replanned
from kb.execution.partial import PartialKits
from kb.execution.records import AtomCheck, Check, FailureRecord, Notice, RunRecord, Sighting, StoreLike, local
from kb.execution.steps import Fields, Step, Stop
from kb.execution.targets import Targets, raised
from kb.model.failures import PRE, FailureModel, FailureModeDef, Remediation
from kb.model.soap import ActionSpec, DomainSpec
from kb.planning.problem import ProblemSpec
from kb.planning.state import pddl_name
from kb.spatial.predicates import Evaluator


#: the one place recovery strategies are named: soap:RecoveryStrategy individual -> its handler
#: (a method of :class:`Recovery` taking the :class:`Failed` and returning what ``_do`` does next)
STRATEGIES: dict[str, str] = {
    str(SOAP.RetryAction): "_retry", str(SOAP.Replan): "_replan_failed", str(SOAP.Abort): "_abort",
    str(SOAP.ExecuteRecoveryPlan): "_run_recovery_plan", str(SOAP.RebindObject): "_rebind",
    str(SOAP.RejectHeldObject): "_reject",
}
#: the one place consequence kinds are named: soap:ConsequenceKind individual -> what the belief keeps
CONSEQUENCES: dict[str, str] = {
    str(SOAP.Condemned): "_condemned", str(SOAP.Missing): "_condemned",
    str(SOAP.ReusableAfterInspection): "_to_inspect", str(SOAP.Moved): "_moved",
}


@dataclass
class Failed:
    """A diagnosed failure being recovered: the step (as it failed), its index, the queue of the
    rest of the plan, the failure's record and its mode (None: unexplained)."""

    step: Step
    index: int
    queue: deque
    failure: FailureRecord
    mode: FailureModeDef | None

    @property
    def remediation(self) -> Remediation | None:
        return self.mode.remediation if self.mode is not None else None


class Recovery(PartialKits):
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
    actions: dict[str, ActionSpec]
    stable: np.ndarray
    targets: Targets
    taken_from: dict[str, np.ndarray]
    index: int  # the next action's index
    _queue: deque
    _near: np.ndarray | None
    #: recovery plans run so far (bounded by ``max_replans``); the last step of a recovery
    #: plan after which the executor replans (``soap:hasFailureRemediation_ThenReplan``)
    _plans_run: int = 0
    #: replanning's bound: the shortest plan left so far, and the replans since one was shorter
    #: (``max_replans`` of those in a row and the run stops: a plan that keeps failing the same
    #: way; a run whose replans keep making progress goes on however many faults it meets)
    _least_left: int | None = None
    _stalled: int = 0
    _replan_after: Step | None = None
    #: each object's SKU when the run started (what the plan was made for; a recognised SKU
    #: replaces the belief's)
    _skus: dict[str, str] | None = None
    #: object -> (action index, mode) of the last failure whose diagnosis was about it
    #: (:meth:`_note_diagnosed`)
    _diagnosed: dict[str, tuple[int, str]] | None = None

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

    def remember_skus(self) -> None:
        """Keep each object's SKU as the run starts (the SKU the plan was made for)."""
        self._skus = {n: s for n, s in sorted(self.belief.facts.get(SKU_OF, ()))}

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
        self._note_diagnosed(failure, step, mode)
        self._emit(FailureFound(i, step.action, step.line(), phase, tuple(a.text() for a in violated), failure.mode))
        if mode is not None:
            fields = Fields({k: local(v) for k, v in step.args.items()})
            if witnesses:  # {found}: what the check found (the part left on a table, say)
                fields["found"] = ", ".join(map(local, witnesses))
            attached = self._attachments(step, failure)
            for n in mode.remediation.notifications:
                message = n.message.format_map(fields)
                failure.notifications.append(Notice(n.recipient, message, attached))
                self.notifier(n.recipient, message)
        return failure

    def _note_diagnosed(self, failure: FailureRecord, step: Step, mode: FailureModeDef | None) -> None:
        """Keep what this diagnosis is about (the objects of its mode's consequences and what its
        check found: the part left on a table, say), and count it a repeated diagnosis
        (``record.repeated_diagnoses``) where an earlier failure diagnosed the same object and no
        action has had the object as an argument since: the same event diagnosed twice."""
        if self._diagnosed is None:
            self._diagnosed = {}
        subjects = [step.args[c.parameter] for c in (mode.consequences if mode is not None else ())
                    if c.parameter in step.args]
        subjects += [w for w in failure.witnesses if w not in subjects]
        for obj in subjects:
            first = self._diagnosed.get(obj)
            if first is not None and not any(a.index > first[0] and obj in a.args for a in self.record.actions):
                self.record.repeated_diagnoses.append(
                    {"object": local(obj), "first": {"action_index": first[0], "mode": first[1]},
                     "again": {"action_index": failure.action_index, "mode": failure.mode}})
            self._diagnosed[obj] = (failure.action_index, failure.mode)

    def _attachments(self, step: Step, failure: FailureRecord) -> dict[str, Any]:
        """What a notification carries: the failure's violated atoms, where its objects were
        expected and seen (the sensor's answers), what the check found, and the pose each of
        the step's objects was grasped at (the tool tip, m), if it was."""
        grasps = {local(v): [_micro(row) for row in self.taken_from[v]]
                  for v in step.args.values() if v in self.taken_from}
        return {"action": step.action, "args": {k: local(v) for k, v in step.args.items()},
                "phase": failure.phase, "violated": [a.text() for a in failure.violated],
                "sightings": [{"object": local(s.name), "expected": _micro(s.expected), "seen": _micro(s.seen)}
                              for s in failure.sightings],
                "found": [local(w) for w in failure.witnesses], "grasps": grasps}

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

    # --- recovery: the mode's data, then its strategy's handler ------------------------
    def _recover(self, step: Step, i: int, queue: deque, failure: FailureRecord, mode: FailureModeDef | None) -> str:
        failed = Failed(step, i, queue, failure, mode)
        for c in mode.consequences if mode is not None else ():
            obj = step.args.get(c.parameter)
            if obj is not None:
                getattr(self, _handler(CONSEQUENCES, c.kind, "consequence kind"))(obj, c.reason)
        rem = failed.remediation
        if rem is None:  # unexplained: plan again from what is sensed
            return self._replan(queue, failure)
        if rem.operator:
            return self._stop(failed, "the remediation asks for an operator", "stopped for an operator")
        try:
            handler = _handler(STRATEGIES, rem.strategy, "recovery strategy")
        except Stop as stop:  # a strategy declared in Turtle that kitkb cannot carry out
            failure.recovery, failure.outcome = "stop", f"stopped: {stop}"
            self._store_failure(failure)
            raise
        return getattr(self, handler)(failed)

    # consequences
    def _condemned(self, obj: str, reason: str) -> None:
        self.belief.learn(obj, reason)

    def _to_inspect(self, obj: str, reason: str) -> None:
        self.belief.learn(obj, reason, until_inspected=True)

    def _moved(self, obj: str, reason: str) -> None:
        j = self.belief.index.get(obj)
        if j is not None and self.belief.placed(obj):
            self.stable[j] = self.belief.poses[j]

    def _usable_after_inspection(self, obj: str) -> bool:
        """An object kept out until an inspection passes it is inspected now, where the cell
        can: True when it passes (it is usable again)."""
        if not self.belief.awaits_inspection(obj) or not has(self.cell, "inspect") or not self.belief.placed(obj):
            return False
        self.belief.passed_inspection(obj, self.cell.inspect(obj))
        return self.belief.usable(obj)

    # strategies
    def _abort(self, f: Failed) -> str:
        return self._stop(f, "the remediation aborts the run", "aborted")

    def _stop(self, f: Failed, why: str, outcome: str) -> str:
        if f.remediation is not None and f.remediation.operator and self.short_and_decided(self._shortage(f)):
            # for want of parts: the kits the parts allow instead (kb.execution.partial)
            return self._replan(f.queue, f.failure)
        f.failure.recovery, f.failure.outcome = "stop", outcome
        self._store_failure(f.failure)
        mode = f.mode
        raise Stop(f"{f.failure.mode} at action {f.index} {f.step.line()}: {mode.consequence if mode else ''} "
                   f"({why})" + self._shortage(f))

    def _retry(self, f: Failed) -> str:
        rem, step = f.remediation, f.step
        if rem is None or step.retries >= rem.max_retries:
            return self._replan(f.queue, f.failure)
        step.retries += 1
        f.failure.recovery, f.failure.outcome = "retry", f"retry {step.retries} of {rem.max_retries}"
        self._store_failure(f.failure)
        self._emit(Recovered(f.index, "retry", why=f.failure.outcome))
        f.queue.appendleft(step)
        return "next"

    def _replan_failed(self, f: Failed) -> str:
        return self._replan(f.queue, f.failure)

    def _rebind(self, f: Failed) -> str:
        param = f.remediation.obj if f.remediation is not None else None
        if param is None or param not in f.step.args:
            return self._replan(f.queue, f.failure)
        return self._rebind_or_replan(f.step, f.index, f.queue, f.failure, f.failure.mode, param)

    def _reject(self, f: Failed) -> str:
        rem = f.remediation
        obj = f.step.args.get(rem.obj) if rem is not None and rem.obj else None
        if obj is not None:
            self._reject_held(obj, "rejected")
        if rem is not None and not rem.then_replan:  # the rest of the plan, without the step
            f.failure.recovery, f.failure.outcome = "reject", f"recovered: {local(obj or '')} rejected"
            self._store_failure(f.failure)
            return "next"
        return self._replan(f.queue, f.failure)

    def _rebind_or_replan(self, step: Step, i: int, queue: deque, failure: FailureRecord | None, why: str,
                          param: str = "part") -> str:
        old = step.args[param]
        if not self.belief.usable(old) and self._usable_after_inspection(old):
            queue.appendleft(step)  # it passed: the step takes it after all
            return "next"
        new = self._another(old, step, param, queue)
        if new is None:
            return self._replan(queue, failure)
        obj, places = new
        self._substitute(old, obj, param, step, queue)
        step.args[param] = obj
        step.args.update(places)
        if failure is not None:
            where = "".join(f" from {local(v)}" for v in places.values())
            failure.recovery, failure.outcome = "rebind", f"recovered: bound {local(obj)}{where}"
            self._store_failure(failure)
        self._emit(Recovered(i, "rebind", local(old), local(obj), why))
        queue.appendleft(step)
        return "next"

    def _shortage(self, f: Failed) -> str:
        """Why an object the mode's consequences made unusable cannot be replaced: no usable
        object of its SKU left where the step could take it."""
        for c in f.mode.consequences if f.mode is not None else ():
            obj = f.step.args.get(c.parameter)
            if obj is None or self.belief.usable(obj) or self._another(obj, f.step, c.parameter, f.queue) is not None:
                continue
            return f"; no usable part of {local(self._planned_sku(obj))} is left in a parts tray"
        return ""

    def _locating(self, action: str, param: str) -> list[tuple[str, tuple[str, ...], str]]:
        """The action's precondition atoms that relate ``param``'s object to one other
        parameter's (the object their reference, as in where it lies): (predicate, argument
        parameters, the other parameter)."""
        spec = self.actions.get(action)
        out = []
        for atom in spec.pre if spec is not None else ():
            if not atom.negated and len(atom.args) == 2 and atom.args[0] == param and atom.args[1] != param:
                out.append((atom.predicate, tuple(atom.args), atom.args[1]))
        return out

    def _placed_for(self, step: Step, param: str, obj: str) -> dict[str, str] | None:
        """The parameters that locate ``obj`` bound in ``step`` as ``param`` (its
        :meth:`_locating` atoms true: the step's own object where it is true already, else the
        first by name that makes it true); None when one cannot be made true."""
        ev = self.evaluator()
        out: dict[str, str] = {}
        for pred, _args, other in self._locating(step.action, param):
            current = out.get(other, step.args.get(other))
            if current is None:
                continue
            try:
                if ev.holds(pred, obj, current):
                    out[other] = current
                    continue
                _refs, tgts, truth = ev.table(pred, [obj], None)
            except KitkbError:
                return None
            found = sorted(tgts[k] for k in np.flatnonzero(np.asarray(truth).reshape(-1)))
            if not found:
                return None
            out[other] = found[0]
        return out

    def _another(self, old: str, step: Step, param: str, queue: deque,
                 exclude: set[str] = frozenset()) -> tuple[str, dict[str, str]] | None:  # type: ignore[assignment]
        """A usable object of ``old``'s SKU that ``step`` can take as ``param`` (its locating
        preconditions can be made true), preferring one the rest of the plan does not use; with
        the locating parameters to bind."""
        sku = self._planned_sku(old)
        later = {a for s in queue for a in s.args.values()}
        found = []
        for p, s in sorted(self.belief.facts.get(SKU_OF, ())):
            if s != sku or p == old or p in exclude or not self.belief.usable(p) or not self.belief.placed(p) \
                    or self.belief.related(SKU_OF, p) != [sku]:
                continue
            places = self._placed_for(step, param, p)
            if places is not None:
                found.append((p in later, p, places))
        if not found:
            return None
        found.sort(key=lambda x: (x[0], x[1]))
        return found[0][1], found[0][2]

    def _planned_sku(self, obj: str) -> str:
        if self._skus is not None and obj in self._skus:
            return self._skus[obj]
        skus = self.belief.related(SKU_OF, obj)
        return skus[0] if skus else ""

    def _substitute(self, old: str, new: str, param: str, failed: Step, queue: deque) -> None:
        """``new`` replaces ``old`` in the rest of the plan; steps that planned to use ``new``
        get another usable object of its SKU (``old`` only if it is still usable where it was;
        when no spare is left they keep ``old``, known unusable, and are rebound or replanned
        without a new diagnosis when they come up), with the parameters locating it bound anew."""
        took_new = [s for s in queue if new in s.args.values()]
        for s in queue:
            for k, v in s.args.items():
                if v == old:
                    s.args[k] = new
        if not took_new:
            return
        usable = self.belief.usable(old) and self._placed_for(failed, param, old) is not None
        # a spare the rest of the plan does not take already (else the SKU would come up one
        # part short far later, at a step no fault touched)
        later = {a for s in queue if s not in took_new for a in s.args.values()}
        spare = (old, {}) if usable else self._another(new, failed, param, queue, exclude={old} | later)
        for s in took_new:
            for k, v in list(s.args.items()):
                if v == new and k == param:
                    s.args[k] = spare[0] if spare else old
                    if spare:
                        s.args.update({q: w for q, w in spare[1].items() if q in s.args})

    def _reject_held(self, obj: str, reason: str) -> None:
        """Put a held object that must not be used down where it was taken."""
        self.belief.learn(obj, reason)
        grasp = self.taken_from.get(obj)
        if grasp is None:
            return
        commands = [InitCanon(), *said_units(), Message(f"reject {local(obj)}"), MoveTo(Pose.from_matrix(raised(grasp, 0.1))),
                    MoveTo(Pose.from_matrix(grasp)), COMMANDS["OpenGripper"](),
                    MoveTo(Pose.from_matrix(raised(grasp, 0.1))), EndCanon()]
        self._send(commands)
        self.targets.tip = raised(grasp, 0.1)
        self._emit(Recovered(self.index - 1, "reject", local(obj)))

    # --- recovery plans -------------------------------------------------------------
    def _run_recovery_plan(self, f: Failed) -> str:
        """The remediation's recovery plan, its steps bound (:meth:`_bind`) and queued before the
        rest of the plan (the failed step again first when its precondition failed: it has not
        run), each checked like any action; then the rest, or a replan after the last step
        (``then_replan``). A plan that cannot be bound, or one too many, replans."""
        rem = f.remediation
        if rem is None or not rem.steps or self._plans_run >= self.max_replans:
            return self._replan(f.queue, f.failure)
        try:
            steps = self._bind(rem, f.step)
        except _Unbound as e:  # (a false alarm, say: the effector to attach is not in its holder)
            out = self._replan(f.queue, f.failure)
            f.failure.outcome += f" (the recovery plan could not be bound: {e})"
            self._store_failure(f.failure)
            return out
        self._plans_run += 1
        if rem.then_replan:
            self._replan_after = steps[-1]
        elif f.failure.phase == PRE:
            f.queue.appendleft(f.step)
        for s in reversed(steps):
            f.queue.appendleft(s)
        lines = " ".join(s.line() for s in steps)
        f.failure.recovery = "recovery-plan"
        f.failure.outcome = f"recovered: recovery plan {lines}" + (", then a replan" if rem.then_replan else "")
        self._store_failure(f.failure)
        self._emit(Recovered(f.index, "recovery-plan", why=lines))
        return "next"

    def _bind(self, rem: Remediation, failed: Step) -> list[Step]:
        """The recovery plan's steps with their arguments: a binding of the step's (the failed
        action's argument, or a named object), else the argument of the same name of the failed
        step or an earlier recovery step, else the first object (by name) of the parameter's
        class for which the step action's preconditions over the parameters bound so far hold."""
        known = dict(failed.args)
        out = []
        for sd in rem.steps:
            spec = self.actions.get(sd.action)
            if spec is None:
                raise _Unbound(f"{sd.action} is not an action of the domain")
            given = dict(sd.bindings)
            args: dict[str, str] = {}
            for name, _cls in spec.params:
                how = given.get(name)
                if how is not None:
                    kind, what = how
                    value = failed.args.get(what) if kind == "failed" else self._object(what)
                    if value is None:
                        raise _Unbound(f"{sd.action}'s {name}: {what} is not bound")
                    args[name] = value
                elif name in known:
                    args[name] = known[name]
            self._choose(spec, args)
            missing = [n for n, _c in spec.params if n not in args]
            if missing:
                raise _Unbound(f"no object for {sd.action}'s {', '.join(missing)}")
            step = Step(sd.action, {n: args[n] for n, _c in spec.params}, recovery=True)
            known.update(step.args)
            out.append(step)
        return out

    def _object(self, iri: str) -> str | None:
        return iri if iri in self.belief.index else self.by_name.get(local(iri))

    def _choose(self, spec: ActionSpec, args: dict[str, str]) -> None:
        """Bind the action's unbound parameters, one at a time, to the first object of their
        class for which every precondition over the bound parameters and it holds."""
        ev = self.evaluator()
        progress = True
        while progress:
            progress = False
            for name, cls in spec.params:
                if name in args:
                    continue
                atoms = [a for a in spec.pre if name in a.args and all(x == name or x in args for x in a.args)]
                if not atoms:
                    continue
                for obj in sorted(self.belief.of_class(cls)):
                    if not self.belief.placed(obj) or not self.belief.usable(obj):
                        continue
                    trial = dict(args, **{name: obj})
                    try:
                        if all(ev.holds(a.predicate, *(trial[x] for x in a.args)) != a.negated for a in atoms):
                            args[name] = obj
                            progress = True
                            break
                    except KitkbError:
                        continue
        # a parameter no precondition constrains (where to put a rejected part): the first placed
        # object of its class, by name (the preconditions over it hold vacuously)
        for name, cls in spec.params:
            if name not in args and not any(name in a.args for a in spec.pre):
                found = sorted(o for o in self.belief.of_class(cls) if self.belief.placed(o))
                if found:
                    args[name] = found[0]

    def _after_recovery_step(self, step: Step, queue: deque) -> None:
        """Called by the executor when ``step`` is done: after a recovery plan's last step whose
        remediation replans, plan again."""
        if step is self._replan_after:
            self._replan_after = None
            self._replan(queue, None)

    # --- replanning -----------------------------------------------------------------
    def _replan(self, queue: deque, failure: FailureRecord | None) -> str:
        if self._stalled >= self.max_replans:
            raise Stop(f"gave up after {self.record.replans} replans ({self._stalled} in a row that did not "
                       f"shorten the plan left)")
        self.record.replans += 1
        self._sense_all()
        ev = self.evaluator()
        facts = {(n, *map(pddl_name, a)) for n, a in ev.facts()}
        values: dict[tuple[str, ...], float] = {}
        for fn in self.domain.functions:
            for args, v in ev.function_values(fn).items():
                values[(fn, *map(pddl_name, args))] = v
        # a part kept out until an inspection passes it (it fell: ReusableAfterInspection) is one
        # the planner may use from where it lies: the executor inspects it before it is taken
        # (a cell that cannot inspect: it stays out)
        inspects = has(self.cell, "inspect")
        excluded = {pddl_name(p) for p in self.belief.unusable if not (inspects and self.belief.awaits_inspection(p))}
        started = time.perf_counter()
        try:
            result = self.plan_within_parts(facts, values, excluded)
        except Exception as e:  # no plan, or a planner that broke: the run stops, saying why
            why = str(e) if isinstance(e, NotSolvableError) else f"replanning failed: {type(e).__name__}: {e}"
            if failure is not None:
                failure.recovery, failure.outcome = "replan", f"stopped: {why}"
                self._store_failure(failure)
            raise Stop(why) from None
        finally:
            self.record.replan_time += time.perf_counter() - started
        # progress is a plan left shorter than any before (a part placed, a kit done, a goal cut
        # to the kits the parts allow); replans that do not shorten it are bounded by max_replans
        if self._least_left is None or len(result.lines) < self._least_left:
            self._least_left, self._stalled = len(result.lines), 0
        else:
            self._stalled += 1
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


class _Unbound(KitkbError):
    """A recovery plan's step whose arguments cannot be bound."""


def _handler(table: dict[str, str], iri: str, what: str) -> str:
    name = table.get(iri)
    if name is None:
        raise Stop(f"{what} {local(iri)} has no handler in kitkb (known: "
                   + ", ".join(sorted(local(k) for k in table)) + ")")
    return name


def _micro(values: Any) -> list[float] | None:
    """Coordinates to the micrometre (m): what a notification carries, the same in any file unit."""
    return None if values is None else [round(float(x), 6) + 0.0 for x in values]
