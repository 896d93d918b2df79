"""The executor: a plan carried out on a cell, every action checked from geometry.

Before the first, the cell is asked for the capabilities the plan needs (:func:`needs`: to move
and to sense; to inspect for an action whose effect is an inspection's, :func:`inspecting_actions`)
and refused without them.

For each plan action (seed 004 §4, seed 002 §4-5):

1. the cell hears which action starts (``begin_action``, where the cell has that capability,
   :mod:`kb.crcl.cell`; a simulator injects its faults there);
2. focus of attention: the action's neighbourhood (:mod:`.focus`: its objects and what its
   predicates' quantified variables can be, the objects touching those) is sensed, or, for an
   action whose definitions do not allow it, the classes its predicates search; the belief is
   updated (:mod:`kb.execution.belief`) and the world-model store told the new poses;
3. late binding: the object an action takes (its program's ``grasp`` target) is inspected where
   the domain has an action inspecting it (:meth:`Executor._inspector`: kitkb's take-part's part,
   by look-for-part; a defective part never goes into a kit) and, if it is missing or defective,
   another of the same SKU is bound instead, in this step and the rest of the plan, before
   replanning is considered;
4. preconditions are evaluated from geometry (:mod:`kb.spatial.predicates`), on the
   neighbourhood's scene (the same truth as the whole cell's);
5. the action's CRCL commands come from its program in the ontology
   (:class:`kb.model.failures.ActionProgram`), targets computed now (:mod:`.targets`), and go
   to the cell; the effects are evaluated from geometry;
6. all hold: the stable state is committed to the store. A violated check is diagnosed
   (:mod:`kb.diagnosis`), recorded with the objects' expected and seen positions, notified,
   and recovered as its remediation's strategy says (retry up to its limit, rebind, reject the
   held part, run the mode's recovery plan, replan from the current state with the same goal:
   :mod:`kb.planning.replan`, or stop), read from the ontology — the executor's base
   :class:`kb.execution.recovery.Recovery`.

At the end of a run the goal is checked from the whole cell sensed anew, every part lying in a
goal kit is inspected through the cell (:meth:`Executor.inspect_kits`), and each kit is scored
on that (:mod:`kb.metrics.kits`): what is sensed and inspected at the end, not what was
believed or inspected during the run.

With a sensor that is not exact (``accuracy``, a :class:`~kb.cells.accuracy.SensorAccuracy`), the
executor looks again where one look is not enough (:mod:`.looks`): the belief filters the
looks (:mod:`.belief`), the objects a motion target is computed from get enough looks first,
a check is decided with a tolerance derived from the accuracy and the looks, a violated check
is looked at again before it fails, and a failure says how sure it is (``certainty``); an
atom that the exact tolerance, the check's and twice its margin decide differently is
undecidable and does not fail its check. An object not seen is looked for again before it is
believed gone, a new SKU confirmed by further looks. With an exact sensor (the default) every
run is as before.
"""

from __future__ import annotations

import logging
import time
from collections import deque
from dataclasses import dataclass, field
from typing import Callable, Collection

import numpy as np

from kb.core.errors import CellError, KitkbError
from kb.core.namespaces import KTW
from kb.crcl import COMMANDS, Command, Dwell, EndCanon, InitCanon, Message, Pose
from kb.cells.accuracy import SensorAccuracy
from kb.crcl.cell import RUN_NEEDS, CellInterface, execute_program, has, require
from kb.crcl.units import said_units
from kb.diagnosis import diagnose
from kb.execution.belief import Belief
from kb.execution.events import (ActionEnded, ActionStarted, CheckMade, Event, StableState, Stopped)
from kb.execution.focus import Focus
from kb.execution.looks import RECHECK, RELEASE, WIDEST, Looks
from kb.execution.records import ActionRecord, AtomCheck, Check, FailureRecord, RunRecord, StoreLike, local
from kb.execution.recovery import Recovery
from kb.execution.scoring import crcl_lines, kit_goals, scene_data
from kb.execution.steps import Fields, Step, Stop, parse_plan
from kb.execution.targets import TargetError, Targets, parse as parse_target, raised
from kb.model.definitions import Definitions, Sensor, subformulas, variable_classes
from kb.model.failures import EFF, PRE, FailureModel
from kb.metrics.kits import KitGoal, score_kits
from kb.model.soap import ActionSpec, DomainSpec
from kb.planning.goal import unmet as unmet_goal
from kb.planning.problem import ProblemSpec
from kb.spatial.predicates import Evaluator
from kb.spatial.rcc8 import DEFAULT_TOLERANCE

log = logging.getLogger("kitkb.execution")
SOLID = str(KTW.SolidObject)
#: the predicate a kit's slot needs of its part besides its place and SKU (an inspection)
QUALITY = "part-quality-ok"
#: sensings of a neighbourhood before it is given up for the whole cell
NEIGHBOURHOOD_ROUNDS = 4
#: target functions -> their arguments whose pose must be known within what a gripper or tool
#: changer captures: the object grasped or mounted; where a held object is put down (it is
#: released just above it, and must not end up more than the capture above it either)
CAPTURED = {"grasp": slice(0, 1), "mount": slice(0, 1), "place": slice(1, 2)}


def log_notifier(recipient: str, message: str) -> None:
    """The default notifier: a warning on the ``kitkb.execution`` logger."""
    log.warning("notify %s: %s", recipient, message)


@dataclass
class Executor(Recovery):
    """Carries out plans on ``cell`` against the problem ``spec`` (numeric encoding)."""

    cell: CellInterface
    domain: DomainSpec
    spec: ProblemSpec
    defs: Definitions
    failures: FailureModel
    belief: Belief
    store: StoreLike | None = None
    notifier: Callable[[str, str], None] = log_notifier
    progress: Callable[[str], None] | None = None  # each event's line (kb.execution.events)
    on_event: Callable[[Event], None] | None = None  # each event (kb.execution.events)
    planner: str | None = None
    tolerance: float = DEFAULT_TOLERANCE
    max_replans: int = 10
    record: RunRecord = field(default_factory=lambda: RunRecord("run"))
    #: the sensor's accuracy; None or zero: exact
    accuracy: SensorAccuracy | None = None

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
        self.remember_skus()  # the SKUs the plan was made for (a rebinding keeps to them)
        self._classes: dict[str, set[str]] = {}  # action -> classes its predicates search
        self._grasps: dict[str, tuple[str, ...]] = {}  # action -> parameters its program grasps
        self._inspecting = inspecting_actions(self.domain, self.defs)  # action -> (parameter, predicate)
        self._inspectors: dict[str, tuple[str, str, str] | None] = {}  # action -> how what it takes is inspected
        self.belief.use_noise(self.accuracy)
        self.looks = Looks(self.cell, self.belief, self.accuracy, self.tolerance)
        self.noisy = self.looks.poses  # poses are not exact: filtered, looked at again, wider tolerances
        self.focus = Focus(self.defs, self.actions, self.belief.classes, WIDEST if self.noisy else self.tolerance)
        if self.noisy:  # what stands level with an object, as the checks see it
            self.targets.tolerance = WIDEST
        self._target_args: dict[str, tuple[str, ...]] = {}  # action -> parameters its targets read
        if self.looks.active:
            self.record.sensor = {"accuracy": self.accuracy.as_dict(), "queries": 0, "undecidable": 0}
        self._near: np.ndarray | None = None  # the neighbourhood sensed last (None: the whole cell)
        self.targets.mounted = self._mounted()
        self.record.tip_start = tuple(round(float(v), 6) for v in self.targets.tip[:3, 3])  # type: ignore[assignment]

    # --- plans ----------------------------------------------------------------------
    def parse_plan(self, lines: list[str]) -> list[Step]:
        return parse_plan(lines, self.actions, self.by_name)

    def needs(self, steps: list[Step]) -> tuple[str, ...]:
        """The capabilities the plan ``steps`` needs of the cell (:func:`needs`)."""
        return needs(steps, self._inspecting)

    def run(self, plan: list[str]) -> RunRecord:
        """Carry out ``plan`` (PDDL action lines); the record says what happened."""
        rec = self.record
        rec.started = rec.started or time.perf_counter()  # a caller's clock (since planning) is kept
        steps = self.parse_plan(plan)
        require(self.cell, self.needs(steps), "the plan")  # before anything is sent: a cell that cannot do it
        queue = deque(steps)
        self._queue = queue
        try:
            while queue:
                step = queue.popleft()
                self._do(step, queue)
        except Stop as stop:
            rec.stopped = str(stop)
            self._emit(Stopped(str(stop)))
        except CellError:  # the cell is gone: nothing more can be sensed or done (exit 2, as at the start)
            raise
        except Exception as exc:  # noqa: BLE001 - a fault of kitkb's own: the run stops, the report says why
            log.exception("execution stopped by an internal error")
            rec.stopped = f"stopped for the operator: internal error at action {self.index}: {type(exc).__name__}: {exc}"
            self._emit(Stopped(rec.stopped, internal=True))
        try:
            rec.goal_holds = self.goal_holds()
        except CellError:
            raise
        except Exception:  # noqa: BLE001 - the goal cannot be decided: it does not hold
            log.exception("the goal could not be checked")
            rec.goal_holds = False
        goals = None
        try:  # the kits as sensed for the goal, the parts in them inspected now
            goals = kit_goals(self.belief, self.spec, self.by_name)
            self.inspect_kits(goals)
        except CellError:
            raise
        except Exception:  # noqa: BLE001 - a score that cannot be made is left out, the run stands
            log.exception("the kits could not be inspected")
            goals = None
        rec.ended = time.perf_counter()
        if rec.sensor is not None:
            rec.sensor["queries"] = self.looks.count
            rec.sensor["undecidable"] = sum(len(c.undecidable) for c in rec.checks)
        try:
            if goals is not None:
                rec.kits = score_kits(goals, self.evaluator())
            rec.scene = scene_data(self.belief)
        except Exception:  # noqa: BLE001 - a score that cannot be made is left out, the run stands
            log.exception("the kits could not be scored")
        return rec

    # --- one action -----------------------------------------------------------------
    def _do(self, step: Step, queue: deque) -> None:
        for param in () if step.recovery else self._grasped(step.action):  # an object to take a diagnosis found unusable: no new one
            obj = step.args.get(param)
            if obj is not None and not self.belief.usable(obj) and not self._inspected_here(step, param, obj):
                self._rebind_or_replan(step, self.index, queue, None, f"{self.belief.unusable[obj]} already", param)
                return
        while True:
            i = self.index
            self.index += 1
            act = ActionRecord(i, step.action, tuple(step.args.values()), started=time.perf_counter())
            self.record.actions.append(act)
            self._emit(ActionStarted(i, step.action, act.args, step.line()))
            if has(self.cell, "begin-action"):  # a cell that cannot hear it is driven without
                self.cell.begin_action(i, step.action, tuple(step.args.values()))
            try:
                self._sense(step)
                outcome = self._attempt(step, act, queue)
            finally:  # an action that stopped the run is recorded too
                act.ended = time.perf_counter()
                if self.store is not None:
                    self.store.record_action(act)
                self._emit(ActionEnded(i, step.action, act.args, step.line(), act.status))
            if outcome == "done":
                self._after_recovery_step(step, queue)  # the last step of a recovery plan that replans
                return
            if outcome == "next":  # the queue was rewritten: its head is what to do now
                return

    def _attempt(self, step: Step, act: ActionRecord, queue: deque) -> str:
        i = act.index
        if not step.recovery and self._inspector(step.action) is not None:
            rebound = self._inspect(step, i, queue)
            if rebound is not None:
                act.status = "rebound"
                return rebound
        approach = self._program(step, act, approach=True)
        if approach:  # the transit to where the action happens; the check is made on arrival
            self._send(approach)
            self._sense(step)
        pre = self._check(i, step, PRE)
        if not pre.ok:
            act.status = "failed"
            return self._failed(step, i, PRE, pre, queue)
        self._look_for_targets(step)
        commands = self._program(step, act, approach=False)
        statuses = self._send(commands)
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
        if action not in self._classes:
            classes: set[str] = set()
            spec = self.actions[action]
            for atom in spec.pre + spec.effects:
                p = self.defs.predicates.get(atom.predicate)
                if p is None:
                    continue
                classes.update(c for c in (p.reference_type, p.target_type) if c)
                classes.update(variable_classes(p.formula))
            inspector = self._inspector(action)
            if inspector is not None:  # the objects that may be bound instead of the one to take
                classes.add(spec.param_type(inspector[0]))
            self._classes[action] = classes
        return self._classes[action]

    def _sense(self, step: Step) -> None:
        """Focus of attention: a local action's neighbourhood (:mod:`.focus`), sensed by name
        until it holds still (what was seen where it now is can bring new objects into it); any
        other action's searched classes (:meth:`_sense_classes`)."""
        self._near = None
        if self.focus.plan(step.action) is None:
            self._sense_classes(step)
            return
        args = {p: self.belief.index[n] for p, n in step.args.items() if n in self.belief.index}
        index = self.belief.index
        # first where the belief has the neighbourhood; then where it is seen now, with what
        # touched an object that moved (it may have been carried along), until nothing is new
        todo = self.focus.neighbourhood(step.action, args, *self.belief.world_boxes()).tolist()
        sensed: set[int] = set()
        changed: list[str] = []
        for _ in range(NEIGHBOURHOOD_ROUNDS):
            before = self.belief.world_boxes()
            names = [self.belief.names[i] for i in todo]
            changed += self.belief.observe(self.looks.sense(names), asked=names)
            moved = self.belief.last_moved  # with noise: outside the gate (a look averaged in did not move)
            sensed.update(todo)
            if not moved:  # the belief is as it was: so is the neighbourhood, sensed in full now
                self._near = np.array(sorted(sensed), np.int64)
                break
            near = set(self.focus.neighbourhood(step.action, args, *self.belief.world_boxes()).tolist())
            near.update(self.focus.touching([index[n] for n in moved], *before).tolist())
            todo = sorted(near - sensed)
            if not todo:
                self._near = np.array(sorted(sensed), np.int64)
                break
        else:  # a neighbourhood that keeps growing: the whole cell
            self._sense_classes(step)
        if self.belief.claims:
            self.looks.confirm()
        if changed and self.store is not None:
            self.store.poses_changed({n: self.belief.pose(n) for n in dict.fromkeys(changed) if self.belief.placed(n)})

    def _sense_classes(self, step: Step) -> None:
        """Every object of the classes the action's predicates search (the whole cell when they
        search solid objects), and its arguments by name."""
        classes = self._focus_classes(step.action)
        queries = [SOLID] if SOLID in classes else sorted(classes)
        seen, expected = [], set()
        for cls in queries:
            placed = [n for n in self.belief.of_class(cls) if self.belief.placed(n)]
            obs = self.looks.sense_class(cls.rsplit("#", 1)[-1], placed)
            seen.extend(obs)
            expected.update(placed)
        for name in step.args.values():
            if name in self.belief.index and not any(o.name == name for o in seen):
                seen.extend(self.looks.sense([name]) if self.looks.active else self.cell.sense(local(name), by="name"))
                expected.add(name)
        changed = self.belief.observe(seen, asked=expected)
        if self.belief.claims:
            self.looks.confirm()
        if changed and self.store is not None:
            self.store.poses_changed({n: self.belief.pose(n) for n in changed if self.belief.placed(n)})

    # --- checks ---------------------------------------------------------------------
    def evaluator(self) -> Evaluator:
        """The predicates on the whole belief (with noise: at the tolerance its looks allow,
        after more looks when it is wider than :data:`~kb.execution.looks.WIDEST`)."""
        if not self.noisy:
            return Evaluator(self.defs, self.belief.scene(), self.tolerance)
        tol = self.looks.narrow(np.flatnonzero(~np.isnan(self.belief.poses[:, 0, 0])))
        return self.looks.evaluator(self.defs, self.belief.scene(), tol)

    def _check(self, i: int, step: Step, phase: str) -> Check:
        """The action's preconditions or effects, decided on its neighbourhood when it was sensed
        as one (the same truth as on the whole belief: :mod:`.focus`), else on the whole belief.
        With noise: at the tolerance the objects' looks allow; a violated check is looked at
        again (:data:`~kb.execution.looks.RECHECK` more looks of its objects) and decided anew,
        and each atom still violated is decided at the exact tolerance and with twice the noise
        margin too (:meth:`Looks.wide <kb.execution.looks.Looks.wide>`): violated at all three,
        it fails the check; else the tolerance decides it, so noise can: it is undecidable."""
        if not self.noisy:
            atoms = self._atoms(step, phase, self.tolerance)
            check = Check(i, phase, atoms, time.perf_counter())
            self.record.checks.append(check)
            self._emit_check(check)
            return check
        objects = self._near if self._near is not None else np.flatnonzero(~np.isnan(self.belief.poses[:, 0, 0]))
        tol = self.looks.narrow(objects)
        atoms = self._atoms(step, phase, tol)
        undecidable: list[AtomCheck] = []
        if not all(a.ok for a in atoms):
            self.looks.until(objects, int(self.belief.looks[objects].min(initial=1)) + RECHECK)
            if self.belief.claims:
                self.looks.confirm()
            tol = self.looks.tolerance_of(objects)
            atoms = self._atoms(step, phase, tol)
            if not all(a.ok for a in atoms):
                wide = {(a.predicate, a.args): a.ok for a in self._atoms(step, phase, self.looks.wide(tol))}
                exact = {(a.predicate, a.args): a.ok for a in self._atoms(step, phase, self.tolerance)}
                for k, a in enumerate(atoms):
                    if not a.ok and (wide[(a.predicate, a.args)] or exact[(a.predicate, a.args)]):
                        undecidable.append(a)  # the tolerance decides it: noise can make it so
                        atoms[k] = AtomCheck(a.predicate, a.args, a.negated, not a.negated)  # not failing
        check = Check(i, phase, atoms, time.perf_counter(), undecidable)
        self.record.checks.append(check)
        self._emit_check(check)
        return check

    def _emit_check(self, check: Check) -> None:
        self._emit(CheckMade(check.action_index, check.phase, check.ok, tuple(a.text() for a in check.violated),
                             tuple(a.text() for a in check.undecidable)))

    def _atoms(self, step: Step, phase: str, tolerance: float) -> list[AtomCheck]:
        spec = self.actions[step.action]
        if not self.noisy:
            ev = self.evaluator() if self._near is None else \
                Evaluator(self.defs, self.belief.subscene(self._near), tolerance)
        else:
            ev = self.looks.evaluator(self.defs, self.belief.scene() if self._near is None else
                                      self.belief.subscene(self._near), tolerance)
        atoms = []
        for atom in (spec.pre if phase == PRE else spec.effects):
            objs = tuple(step.args[a] for a in atom.args)
            try:
                holds = ev.holds(atom.predicate, *objs)
            except KitkbError:
                holds = False
            atoms.append(AtomCheck(atom.predicate, objs, atom.negated, holds))
        return atoms

    def _record_failure(self, i: int, step: Step, phase: str, violated: list[AtomCheck], diag) -> FailureRecord:  # noqa: ANN001
        """:meth:`Recovery._record_failure <kb.execution.recovery.Recovery._record_failure>`, and
        with a noisy sensor how sure the failure is: certain when every violated atom is violated
        at the exact tolerance and with twice the noise margin too (:meth:`_check` lets no other
        fail) and the diagnosis is the same with twice the noise margin; else uncertain."""
        failure = super()._record_failure(i, step, phase, violated, diag)
        if self.looks.active:
            failure.certainty = "certain" if not self.noisy or self._sure(step, phase, violated, diag.name) \
                else "uncertain"
        return failure

    def _sure(self, step: Step, phase: str, violated: list[AtomCheck], mode: str) -> bool:
        placed = np.flatnonzero(~np.isnan(self.belief.poses[:, 0, 0]))
        wide = self.looks.wide(self.looks.tolerance_of(placed))
        for ev in (Evaluator(self.defs, self.belief.scene(), self.tolerance),
                   self.looks.evaluator(self.defs, self.belief.scene(), wide)):
            for a in violated:
                try:
                    holds = ev.holds(a.predicate, *a.args)
                except KitkbError:
                    holds = False
                if holds != a.holds:
                    return False
        ev = self.looks.evaluator(self.defs, self.belief.scene(), wide)
        return diagnose(self.failures, ev, step.action, phase, {a.predicate for a in violated}, step.args).name == mode

    def _look_for_targets(self, step: Step) -> None:
        """With noise: enough looks of the objects the action's motion targets are computed from
        (:mod:`.looks`) before they are computed."""
        if not self.noisy:
            return
        names = [step.args[p] for p in self._targets_read(step.action) if p in step.args]
        idx = [self.belief.index[n] for n in names if n in self.belief.index]
        if idx:
            changed = self.looks.until(idx, self.looks.capture_looks)
            changed += self.belief.settle(names)  # the mean of the looks, to the last of them
            if changed and self.store is not None:
                self.store.poses_changed({n: self.belief.pose(n) for n in changed if self.belief.placed(n)})

    def _targets_read(self, action: str) -> tuple[str, ...]:
        """The parameters whose pose a gripper or tool changer must meet (:data:`CAPTURED`: the
        objects of the action program's ``grasp`` and ``mount`` targets, where its ``place``
        puts something; an effector is stowed with room in its holder, an approach only passes
        by)."""
        if action not in self._target_args:
            program = self.failures.programs.get(action)
            params: dict[str, None] = {}
            for s in program.steps if program is not None else ():
                if s.target is None or s.approach:
                    continue
                try:
                    name, args = parse_target(s.target)
                except ValueError:
                    continue
                if name in CAPTURED:
                    params.update(dict.fromkeys(a for a in args[CAPTURED[name]] if not _number(a)))
            self._target_args[action] = tuple(params)
        return self._target_args[action]

    # --- what an action takes: inspected before it is grasped, rebound when unusable ------
    def _grasped(self, action: str) -> tuple[str, ...]:
        """The parameters whose object the action's program grasps (its ``grasp`` targets)."""
        if action not in self._grasps:
            program = self.failures.programs.get(action)
            params: dict[str, None] = {}
            for s in program.steps if program is not None else ():
                if s.target is None:
                    continue
                try:
                    name, args = parse_target(s.target)
                except ValueError:
                    continue
                if name == "grasp" and args and not _number(args[0]):
                    params[args[0]] = None
            self._grasps[action] = tuple(params)
        return self._grasps[action]

    def _inspector(self, action: str) -> tuple[str, str, str] | None:
        """How the object ``action`` takes is inspected before it is grasped: (its parameter,
        the inspecting action, the inspection's predicate), or None. The inspecting action is a
        domain action whose effect is a predicate decided by an inspection (a sensor atom) of
        that parameter's object, and whose parameters ``action`` has too, by name and class
        (kitkb's domain: take-part's part, by look-for-part and part-quality-ok). An action
        without one takes what it was planned with."""
        if action not in self._inspectors:
            params = dict(self.actions[action].params)
            found = None
            for param in self._grasped(action):
                for other, (on, predicate) in self._inspecting.items():
                    if on == param and all(params.get(n) == t for n, t in self.actions[other].params):
                        found = (param, other, predicate)
                        break
                if found is not None:
                    break
            self._inspectors[action] = found
        return self._inspectors[action]

    def _inspected_here(self, step: Step, param: str, obj: str) -> bool:
        """``obj``, kept out until an inspection passes it (a part that fell), is taken by a step
        that inspects it first (:meth:`_inspector`): the step goes ahead, and the inspection
        decides (a part that fails is diagnosed as the inspecting action's failure)."""
        inspector = self._inspector(step.action)
        return (self.belief.awaits_inspection(obj) and inspector is not None and inspector[0] == param
                and has(self.cell, "inspect") and self.belief.placed(obj))

    def _inspect(self, step: Step, i: int, queue: deque) -> str | None:
        """Inspect the object the step takes (:meth:`_inspector`): a defective one is
        replaced, never taken; its failure is diagnosed as the inspecting action's."""
        param, action, predicate = self._inspector(step.action)  # type: ignore[misc]
        obj = step.args[param]
        if not self.belief.placed(obj) or not has(self.cell, "inspect"):  # a cell that cannot: not inspected
            return None
        ok = self.cell.inspect(obj)
        self.belief.passed_inspection(obj, ok)
        if ok:
            return None
        args = {n: step.args[n] for n, _ in self.actions[action].params}
        atom = AtomCheck(predicate, (obj,), False, False)
        self.record.checks.append(Check(i, EFF, [atom], time.perf_counter()))
        self._emit_check(self.record.checks[-1])
        if self._near is not None:
            self._sense_classes(step)
        diag = diagnose(self.failures, self.evaluator(), action, EFF, {predicate}, args)
        failure = self._record_failure(i, Step(action, args), EFF, [atom], diag)
        return self._recover(step, i, queue, failure, diag.mode)

    # --- commands -------------------------------------------------------------------
    def _send(self, commands: list[Command]) -> list:
        """Execute a CRCL program on the cell; its statements are kept in the current action's
        record (the run's static metrics, its report's path)."""
        if self.record.actions:
            self.record.actions[-1].programs.append(crcl_lines(commands))
        return execute_program(self.cell, commands)

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
        out: list[Command] = [InitCanon(), *said_units()]  # the executor computes in SI: says so
        fields = Fields({k: local(v) for k, v in step.args.items()})
        for s in chosen:
            if s.command == "Message":
                out.append(Message((s.text or "").format_map(fields)))
            elif s.command == "Dwell":
                out.append(Dwell(float(s.duration or 0.0)))
            elif s.target is not None:
                pose = self.targets.compute(s.target, step.args)
                if self.noisy and s.target.lstrip().startswith("place("):  # released above where it goes
                    pose = raised(pose, RELEASE)
                out.append(COMMANDS[s.command](Pose.from_matrix(pose)))
                self.targets.tip = pose
                if s.target.lstrip().startswith("grasp("):  # where the object was taken (to put it back)
                    grasped = parse_target(s.target)[1][0]
                    if grasped in step.args:
                        self.taken_from[step.args[grasped]] = pose
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
                    and np.linalg.norm(self.belief.pose(e)[:3, 3] - t.tip[:3, 3])
                    < 0.005 + 5 * self.belief.sigma(self.belief.index[e])]
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
        self._emit(StableState(i))

    def _sense_all(self) -> None:
        placed = [n for n in self.belief.of_class(SOLID) if self.belief.placed(n)]
        obs = self.looks.sense_class("SolidObject", placed) if self.looks.active else \
            self.cell.sense("SolidObject", by="class")
        self.belief.observe(obs, asked=placed)
        if self.belief.claims:
            self.looks.confirm()

    def goal_holds(self) -> bool:
        """The goal of the problem — every goal atom and count (:mod:`kb.planning.goal`) —
        checked from the sensed geometry now; the record keeps what does not hold
        (``goal_unmet``)."""
        self._sense_all()
        self.record.goal_unmet = unmet_goal(self.spec.goal, self.spec.goal_equal, self.evaluator())
        return not self.record.goal_unmet

    def inspect_kits(self, goals: list[KitGoal]) -> None:
        """Inspect, through the cell, every part that lies in a goal kit as sensed now (after
        :meth:`goal_holds`): a kit's score rests on what is sensed and inspected at the end of
        the run, not on what inspections during it said (a part may have changed since, and a
        run that found its kit built inspected nothing). Nothing is asked when the domain has no
        ``part-quality-ok``."""
        if QUALITY not in self.defs.predicates or not has(self.cell, "inspect"):  # then no part is found good
            return
        ev = self.evaluator()
        for goal in goals:
            try:
                parts, _kits, truth = ev.table("part-location-kit", None, [goal.kit])
            except KitkbError:  # a kit the scene does not know: nothing lies in it
                continue
            for part, inside in zip(parts, np.asarray(truth).reshape(-1)):
                if inside:
                    self.belief.passed_inspection(part, self.cell.inspect(part))

    def _emit(self, event: Event) -> None:
        if self.on_event is not None:
            self.on_event(event)
        if self.progress is not None and (text := event.text()) is not None:
            self.progress(text)


def needs(steps: list[Step], inspecting: Collection[str] = ()) -> tuple[str, ...]:
    """The capabilities (:mod:`kb.crcl.cell`) a plan needs of its cell: to move and to sense
    always; to inspect for an action of ``inspecting`` (its effect is an inspection's:
    :func:`inspecting_actions`; kitkb's domain: ``look-for-part``). The executor's own
    inspection before a grasp and of the finished kits is left out on a cell that cannot
    inspect (no part is then found good)."""
    return RUN_NEEDS + (("inspect",) if any(s.action in inspecting for s in steps) else ())


def inspecting_actions(domain: DomainSpec, defs: Definitions) -> dict[str, tuple[str, str]]:
    """The actions whose effect is a predicate decided by an inspection (a sensor atom, docs/soap.md)
    of one of their parameters' objects: action -> (that parameter, the predicate)."""
    out: dict[str, tuple[str, str]] = {}
    for spec in domain.actions:
        for atom in spec.effects:
            p = defs.predicates.get(atom.predicate)
            if atom.negated or p is None or len(atom.args) != 1:
                continue
            if any(isinstance(f, Sensor) for f in subformulas(p.formula)):
                out.setdefault(spec.name, (atom.args[0], atom.predicate))
    return out


def _number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def _along(d: float) -> np.ndarray:
    m = np.eye(4)
    m[2, 3] = d
    return m
