"""The executor: a plan carried out on a cell, every action checked from geometry.

For each plan action (seed 004 §4, seed 002 §4-5):

1. the cell hears which action starts (``begin_action``; a simulator injects its faults there);
2. focus of attention: the action's objects and the classes its predicates search (their
   arguments' and quantified variables' classes) are sensed, the belief updated
   (:mod:`kb.execution.belief`) and the world-model store told the new poses;
3. late binding: a part to take is inspected (a defective part never goes into a kit) and, if
   it is missing or defective, another part of the same SKU lying in a tray is bound instead,
   in this step and the rest of the plan, before replanning is considered;
4. preconditions are evaluated from geometry (:mod:`kb.spatial.predicates`);
5. the action's CRCL commands come from its program in the ontology
   (:class:`kb.model.failures.ActionProgram`), targets computed now (:mod:`.targets`), and go
   to the cell; the effects are evaluated from geometry;
6. all hold: the stable state is committed to the store. A violated check is diagnosed
   (:mod:`kb.diagnosis`), recorded with the objects' expected and seen positions, notified,
   and recovered as its remediation says: retry (up to its limit), rebind, replan from the
   current state with the same goal (:mod:`kb.planning.replan`), or stop.
"""

from __future__ import annotations

import logging
import re
import time
from collections import deque
from dataclasses import dataclass, field
from typing import Callable, Protocol

import numpy as np

from kb.core.errors import KitkbError, NotSolvableError
from kb.core.namespaces import KTW
from kb.crcl import COMMANDS, Command, Dwell, EndCanon, InitCanon, Message, MoveTo, Pose
from kb.crcl.cell import CellInterface, execute_program
from kb.diagnosis import diagnose
from kb.execution.belief import SKU_OF, Belief
from kb.execution.records import (ActionRecord, AtomCheck, Check, FailureRecord, RunRecord, Sighting, local)
from kb.execution.targets import TargetError, Targets, raised
from kb.model.definitions import Definitions, variable_classes
from kb.model.failures import EFF, PRE, FailureModel, FailureModeDef
from kb.model.soap import ActionSpec, DomainSpec
from kb.planning.problem import ProblemSpec
from kb.planning.replan import replan
from kb.planning.state import pddl_name
from kb.spatial.predicates import Evaluator
from kb.spatial.rcc8 import DEFAULT_TOLERANCE

log = logging.getLogger("kitkb.execution")
_PLAN_LINE = re.compile(r"^\(\s*([^\s()]+)((?:\s+[^\s()]+)*)\s*\)$")
SOLID = str(KTW.SolidObject)


class StoreLike(Protocol):
    """Where stable states and run records go (:class:`kb.execution.store.RunStore`)."""

    def begin_run(self, record: RunRecord, init: object = None, goal: object = None) -> None: ...
    def end_run(self, record: RunRecord) -> None: ...
    def poses_changed(self, poses: dict[str, np.ndarray]) -> None: ...
    def commit_stable(self, action_index: int) -> None: ...
    def record_failure(self, failure: FailureRecord) -> None: ...
    def record_action(self, action: ActionRecord) -> None: ...


def log_notifier(recipient: str, message: str) -> None:
    """The default notifier: a warning on the ``kitkb.execution`` logger."""
    log.warning("notify %s: %s", recipient, message)


class Stop(KitkbError):
    """The run cannot go on (no plan left, a remediation that stops for an operator)."""

    exit_code = 1


@dataclass
class Step:
    action: str
    args: dict[str, str]  # parameter name -> IRI
    retries: int = 0

    def line(self) -> str:
        return f"({self.action} {' '.join(pddl_name(a) for a in self.args.values())})"


@dataclass
class Executor:
    """Carries out plans on ``cell`` against the problem ``spec`` (numeric encoding)."""

    cell: CellInterface
    domain: DomainSpec
    spec: ProblemSpec
    defs: Definitions
    failures: FailureModel
    belief: Belief
    store: StoreLike | None = None
    notifier: Callable[[str, str], None] = log_notifier
    progress: Callable[[str], None] | None = None
    planner: str | None = None
    tolerance: float = DEFAULT_TOLERANCE
    max_replans: int = 10
    record: RunRecord = field(default_factory=lambda: RunRecord("run"))

    def __post_init__(self) -> None:
        self.actions: dict[str, ActionSpec] = {a.name: a for a in self.domain.actions}
        self.by_name = {name: iri for name, (_kind, iri) in self.spec.objects.items()}
        robots = self.belief.of_class(str(KTW.Robot))
        if not robots:
            raise KitkbError("the initial state has no robot")
        self.robot = robots[0]
        self.targets = Targets(self.belief, self.robot)
        self.stable = self.belief.poses.copy()
        self.index = 0
        self.taken_from: dict[str, np.ndarray] = {}  # part -> tip pose it was grasped at
        self._focus: dict[str, set[str]] = {}
        self.targets.mounted = self._mounted()

    # --- plans ----------------------------------------------------------------------
    def parse_plan(self, lines: list[str]) -> list[Step]:
        steps = []
        for line in lines:
            m = _PLAN_LINE.match(line.strip())
            if m is None:
                raise KitkbError(f"not a plan action: {line!r}")
            name, args = m.group(1), m.group(2).split()
            spec = self.actions.get(name)
            if spec is None:
                raise KitkbError(f"plan action {name} is not in the domain")
            if len(args) != len(spec.params):
                raise KitkbError(f"plan action {line.strip()}: {name} takes {len(spec.params)} arguments")
            steps.append(Step(name, {p: self.by_name.get(a, a) for (p, _t), a in zip(spec.params, args)}))
        return steps

    def run(self, plan: list[str]) -> RunRecord:
        """Carry out ``plan`` (PDDL action lines); the record says what happened."""
        rec = self.record
        rec.started = time.perf_counter()
        queue = deque(self.parse_plan(plan))
        self._queue = queue
        try:
            while queue:
                step = queue.popleft()
                self._do(step, queue)
        except Stop as stop:
            rec.stopped = str(stop)
            self._say(f"stopped: {stop}")
        rec.goal_holds = self.goal_holds()
        rec.ended = time.perf_counter()
        return rec

    # --- one action -----------------------------------------------------------------
    def _do(self, step: Step, queue: deque) -> None:
        while True:
            i = self.index
            self.index += 1
            act = ActionRecord(i, step.action, tuple(step.args.values()), started=time.perf_counter())
            self.record.actions.append(act)
            self.cell.begin_action(i, step.action, tuple(step.args.values()))
            self._sense(step)
            outcome = self._attempt(step, act, queue)
            act.ended = time.perf_counter()
            if self.store is not None:
                self.store.record_action(act)
            if outcome == "done":
                return
            if outcome == "next":  # the queue was rewritten: its head is what to do now
                return

    def _attempt(self, step: Step, act: ActionRecord, queue: deque) -> str:
        i = act.index
        if step.action == "take-part":
            rebound = self._inspect(step, i, queue)
            if rebound is not None:
                act.status = "rebound"
                return rebound
        approach = self._program(step, act, approach=True)
        if approach:  # the transit to where the action happens; the check is made on arrival
            execute_program(self.cell, approach)
            self._sense(step)
        pre = self._check(i, step, PRE)
        if not pre.ok:
            act.status = "failed"
            return self._failed(step, i, PRE, pre, queue)
        commands = self._program(step, act, approach=False)
        statuses = execute_program(self.cell, commands)
        bad = [s for s in statuses if not s.done]
        self._sense(step)
        eff = self._check(i, step, EFF)
        if bad and eff.ok:
            log.info("action %d: %d command(s) reported errors but every effect holds", i, len(bad))
        if not eff.ok:
            act.status = "failed"
            return self._failed(step, i, EFF, eff, queue)
        act.status = "done"
        self._commit(i, step)
        return "done"

    # --- sensing --------------------------------------------------------------------
    def _focus_classes(self, action: str) -> set[str]:
        """Classes the action's predicates search: argument types and quantified variables'."""
        if action not in self._focus:
            classes: set[str] = set()
            spec = self.actions[action]
            for atom in spec.pre + spec.effects:
                p = self.defs.predicates.get(atom.predicate)
                if p is None:
                    continue
                classes.update(c for c in (p.reference_type, p.target_type) if c)
                classes.update(variable_classes(p.formula))
            if action == "take-part":
                classes.add(str(KTW.Part))
            self._focus[action] = classes
        return self._focus[action]

    def _sense(self, step: Step) -> None:
        classes = self._focus_classes(step.action)
        queries = [SOLID] if SOLID in classes else sorted(classes)
        seen, expected = [], set()
        for cls in queries:
            obs = self.cell.sense(cls.rsplit("#", 1)[-1], by="class")
            seen.extend(obs)
            expected.update(n for n in self.belief.of_class(cls) if self.belief.placed(n))
        for name in step.args.values():
            if name in self.belief.index and not any(o.name == name for o in seen):
                seen.extend(self.cell.sense(local(name), by="name"))
                expected.add(name)
        changed = self.belief.observe(seen, asked=expected)
        if changed and self.store is not None:
            self.store.poses_changed({n: self.belief.pose(n) for n in changed if self.belief.placed(n)})

    # --- checks ---------------------------------------------------------------------
    def evaluator(self) -> Evaluator:
        return Evaluator(self.defs, self.belief.scene(), self.tolerance)

    def _check(self, i: int, step: Step, phase: str) -> Check:
        spec = self.actions[step.action]
        ev = self.evaluator()
        atoms = []
        for atom in (spec.pre if phase == PRE else spec.effects):
            objs = tuple(step.args[a] for a in atom.args)
            try:
                holds = ev.holds(atom.predicate, *objs)
            except KitkbError:
                holds = False
            atoms.append(AtomCheck(atom.predicate, objs, atom.negated, holds))
        check = Check(i, phase, atoms, time.perf_counter())
        self.record.checks.append(check)
        return check

    def _inspect(self, step: Step, i: int, queue: deque) -> str | None:
        """Inspect the part to take (look-for-part): a defective one is replaced, never taken."""
        part = step.args["part"]
        if part in self.belief.rejected or not self.belief.placed(part):
            return None if part not in self.belief.rejected else self._rebind_or_replan(
                step, i, queue, None, "already rejected")
        ok = self.cell.inspect(part)
        self.belief.passed_inspection(part, ok)
        if ok:
            return None
        args = {"robot": step.args["robot"], "part": part, "partstray": step.args["partstray"]}
        atom = AtomCheck("part-quality-ok", (part,), False, False)
        self.record.checks.append(Check(i, EFF, [atom], time.perf_counter()))
        diag = diagnose(self.failures, self.evaluator(), "look-for-part", EFF, {"part-quality-ok"}, args)
        failure = self._record_failure(i, Step("look-for-part", args), EFF, [atom], diag)
        return self._recover(step, i, queue, failure, diag.mode)

    # --- failures -------------------------------------------------------------------
    def _failed(self, step: Step, i: int, phase: str, check: Check, queue: deque) -> str:
        violated = check.violated
        diag = diagnose(self.failures, self.evaluator(), step.action, phase, {a.predicate for a in violated},
                        step.args)
        failure = self._record_failure(i, step, phase, violated, diag)
        return self._recover(step, i, queue, failure, diag.mode)

    def _record_failure(self, i: int, step: Step, phase: str, violated: list[AtomCheck], diag) -> FailureRecord:  # noqa: ANN001
        names = []
        for a in violated:
            names.extend(x for x in a.args if x not in names)
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
                                kit=self._kit_of(step))
        self.record.failures.append(failure)
        self._say(f"  failure at action {i} ({step.line()}, {phase}): " + ", ".join(a.text() for a in violated)
                  + f" -> {failure.mode}")
        if mode is not None:
            fields = _Fields({k: local(v) for k, v in step.args.items()})
            for n in mode.remediation.notifications:
                self.notifier(n.recipient, n.message.format_map(fields))
        return failure

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
        self._say(f"  rebound {local(old)} -> {local(part)} ({why})")
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
            if p == old or p in exclude or p in self.belief.rejected or self.belief.related(SKU_OF, p) != [sku]:
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
        get another usable part of its SKU (``old`` only if it is still usable, so a part known
        missing or rejected never comes back into the plan)."""
        took_new = [s for s in queue if new in s.args.values()]
        for s in queue:
            for k, v in s.args.items():
                if v == old:
                    s.args[k] = new
        if not took_new:
            return
        usable = old not in self.belief.rejected and self._in_a_tray(old)
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
        self.belief.rejected.add(part)
        grasp = self.taken_from.get(part)
        if grasp is None:
            return
        commands = [InitCanon(), Message(f"reject {local(part)}"), MoveTo(Pose.from_matrix(raised(grasp, 0.1))),
                    MoveTo(Pose.from_matrix(grasp)), COMMANDS["OpenGripper"](),
                    MoveTo(Pose.from_matrix(raised(grasp, 0.1))), EndCanon()]
        execute_program(self.cell, commands)
        self.targets.tip = raised(grasp, 0.1)
        self._say(f"  rejected {local(part)}: put back where it was taken")

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
        excluded = {pddl_name(p) for p in self.belief.rejected}
        try:
            result = replan(self.domain, self.spec, facts, values, excluded, self.planner)
        except Exception as e:  # no plan, or a planner that broke: the run stops, saying why
            why = str(e) if isinstance(e, NotSolvableError) else f"replanning failed: {type(e).__name__}: {e}"
            if failure is not None:
                failure.recovery, failure.outcome = "replan", f"stopped: {why}"
                self._store_failure(failure)
            raise Stop(why) from None
        queue.clear()
        queue.extend(self.parse_plan(result.lines))
        if failure is not None:
            failure.recovery = failure.recovery or "replan"
            failure.outcome = failure.outcome or f"recovered: new plan of {len(result.lines)} actions"
            self._store_failure(failure)
        self._say(f"  replanned: {len(result.lines)} actions")
        return "next"

    def _store_failure(self, failure: FailureRecord) -> None:
        if self.store is not None:
            self.store.record_failure(failure)

    # --- commands -------------------------------------------------------------------
    def _program(self, step: Step, act: ActionRecord, approach: bool) -> list[Command]:
        """The action's approach commands, or the rest, targets computed now; [] when none."""
        try:
            commands = self._commands(step, approach)
        except TargetError as e:
            act.status = "failed"
            raise Stop(f"action {act.index} {step.line()}: {e}") from None
        act.commands.extend(type(c).__name__ for c in commands)
        return commands

    def _commands(self, step: Step, approach: bool = False) -> list[Command]:
        program = self.failures.programs.get(step.action)
        if program is None:
            raise TargetError(f"no action program for {step.action} in the ontology")
        chosen = [s for s in program.steps if s.approach == approach]
        if approach and not chosen:
            return []
        out: list[Command] = [InitCanon()]
        fields = _Fields({k: local(v) for k, v in step.args.items()})
        for s in chosen:
            if s.command == "Message":
                out.append(Message((s.text or "").format_map(fields)))
            elif s.command == "Dwell":
                out.append(Dwell(float(s.duration or 0.0)))
            elif s.target is not None:
                pose = self.targets.compute(s.target, step.args)
                out.append(COMMANDS[s.command](Pose.from_matrix(pose)))
                self.targets.tip = pose
                if s.target.startswith("grasp(") and step.action == "take-part":
                    self.taken_from[step.args["part"]] = pose
            else:
                out.append(COMMANDS[s.command]())
                self._tool_changed(s.command)
        out.append(EndCanon())
        return out

    def _tool_changed(self, command: str) -> None:
        """Keep the tip where it is after the tool changer closes or opens."""
        t = self.targets
        if command == "CloseToolChanger":
            near = [e for e in self.belief.of_class(str(KTW.EndEffector)) if self.belief.placed(e)
                    and np.linalg.norm(self.belief.pose(e)[:3, 3] - t.tip[:3, 3]) < 0.005]
            if near:
                t.mounted = near[0]
                t.tip = t.tip @ _along(float(self.belief.box(near[0])[1][2]))
        elif command == "OpenToolChanger" and t.mounted is not None:
            t.tip = t.tip @ _along(-float(self.belief.box(t.mounted)[1][2]))
            t.mounted = None

    def _mounted(self) -> str | None:
        ev = self.evaluator()
        for e in self.belief.of_class(str(KTW.EndEffector)):
            try:
                if ev.holds("endeffector-location-robot", e, self.robot):
                    return e
            except KitkbError:
                continue
        return None

    # --- stable states and the goal -------------------------------------------------
    def _commit(self, i: int, step: Step) -> None:
        self.stable = self.belief.poses.copy()
        if self.store is not None:
            self.store.commit_stable(i)
        self._say(f"  {i:>3} {step.line()}  ok")

    def _sense_all(self) -> None:
        obs = self.cell.sense("SolidObject", by="class")
        self.belief.observe(obs, asked=[n for n in self.belief.of_class(SOLID) if self.belief.placed(n)])

    def goal_holds(self) -> bool:
        """The goal of the problem, checked from the sensed geometry now."""
        self._sense_all()
        ev = self.evaluator()
        true = {(n, *map(pddl_name, a)) for n, a in ev.facts({g[0] for g in self.spec.goal})}
        if not all(tuple(g) in true for g in self.spec.goal):
            return False
        counts: dict[str, dict] = {}
        for left, right in self.spec.goal_equal:
            for term in (left, right):
                if term[0] not in counts:
                    counts[term[0]] = {tuple(map(pddl_name, a)): v for a, v in ev.function_values(term[0]).items()}
            if counts[left[0]].get(tuple(left[1:]), 0) != counts[right[0]].get(tuple(right[1:]), 0):
                return False
        return True

    def _say(self, text: str) -> None:
        if self.progress is not None:
            self.progress(text)


class _Fields(dict):
    def __missing__(self, key: str) -> str:
        return "{" + key + "}"


def _along(d: float) -> np.ndarray:
    m = np.eye(4)
    m[2, 3] = d
    return m
