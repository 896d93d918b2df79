"""Failure modes, their remediations, and the robot programs of actions, as typed values.

Read from a SOAP domain (``kitting-domain.ttl``): a :class:`FailureModeDef` says for which
action and check phase it applies, which predicates its signal violates, the condition on where
the objects really are that tells it from the others (a formula over the action's parameters,
read by :mod:`kb.model.definitions`), what it implies about its objects
(:class:`ObjectConsequence`: condemned, missing, reusable after inspection, moved) and its
:class:`Remediation` (notifications, the recovery strategy's IRI, retries, operator, the object a
strategy acts on, a recovery plan of :class:`RecoveryStepDef` with its parameter bindings, and
whether to replan after it). An :class:`ActionProgram` is the list of CRCL command steps of an
action (command name, late-bound target expression, duration, message text).

Nothing here knows a mode, strategy or consequence by name: the executor dispatches on the
strategy's and the consequence kind's IRIs (:mod:`kb.execution.recovery`).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Sequence

from rdflib import Graph, URIRef
from rdflib.namespace import RDF

from kb.core.errors import InputError
from kb.core.namespaces import SOAP
from kb.io.loader import domain_knowledge
from kb.model.definitions import Formula, Locator, _Malformed, _Reader, _short, locator
from kb.model.policy import delivers_partial_kits

PRE, EFF = "precondition", "effect"


@dataclass(frozen=True)
class Notification:
    recipient: str
    message: str  # with {parameter} placeholders


@dataclass(frozen=True)
class RecoveryStepDef:
    """One action of a recovery plan: its name and how its parameters are bound (parameter
    name -> ``("failed", failed action's parameter name)`` or ``("object", IRI)``); a parameter
    without one is bound by name, else chosen by the action's preconditions."""

    action: str
    bindings: tuple[tuple[str, tuple[str, str]], ...] = ()


@dataclass(frozen=True)
class ObjectConsequence:
    """What a mode implies about the object of one parameter of its action: ``kind`` is a
    soap:ConsequenceKind IRI, ``reason`` the word the run keeps for it."""

    parameter: str
    kind: str
    reason: str


@dataclass(frozen=True)
class Remediation:
    """What to do about a failure: ``strategy`` is the soap:RecoveryStrategy individual's IRI
    (``recovery`` its local name, as the run reports it)."""

    iri: str
    recovery: str
    max_retries: int = 0
    operator: bool = False
    notifications: tuple[Notification, ...] = ()
    plan: tuple[str, ...] = ()  # action names of a recovery plan, in order
    strategy: str = ""
    obj: str | None = None  # the failed action's parameter a strategy acts on (rebind, reject)
    then_replan: bool = False  # after a recovery plan or a rejection: plan again
    steps: tuple[RecoveryStepDef, ...] = ()  # the recovery plan, in order


@dataclass(frozen=True)
class FailureModeDef:
    iri: str
    name: str
    action: str  # action name
    phase: str  # PRE or EFF
    violated: frozenset[str]  # predicate names
    condition: Formula | None
    consequence: str
    severity: int
    likelihood: float
    remediation: Remediation
    consequences: tuple[ObjectConsequence, ...] = ()


@dataclass(frozen=True)
class CommandStep:
    command: str
    target: str | None = None
    duration: float | None = None
    text: str | None = None
    approach: bool = False  # runs before the precondition check (the transit to the action's place)


@dataclass(frozen=True)
class ActionProgram:
    action: str
    steps: tuple[CommandStep, ...]


@dataclass
class FailureModel:
    """The failure modes (by name) and action programs (by action name) of a domain."""

    modes: dict[str, FailureModeDef] = field(default_factory=dict)
    programs: dict[str, ActionProgram] = field(default_factory=dict)
    #: action name -> parameter IRI -> parameter name (the terms of failure conditions)
    parameters: dict[str, dict[str, str]] = field(default_factory=dict)
    #: the domain's partial-kit policy (:func:`kb.model.policy.delivers_partial_kits`): True
    #: deliver a kit that cannot be finished partial, False leave it, None: none declared
    delivers_partial_kits: bool | None = None

    def candidates(self, action: str, phase: str) -> list[FailureModeDef]:
        """Modes of ``action`` in ``phase``, most likely first."""
        return sorted((m for m in self.modes.values() if m.action == action and m.phase == phase),
                      key=lambda m: (-m.likelihood, m.name))


def load_failure_model(domain_files: Sequence[str | Path] | None = None) -> FailureModel:
    """The failure model of the domain files (default: the shipped ``kitting-domain.ttl``)."""
    kb = domain_knowledge(domain_files)
    return read_failure_model(kb.graph, locator(kb))


def read_failure_model(graph: Graph, locate: Locator | None = None) -> FailureModel:
    """Failure modes and action programs of ``graph``; InputError at the first malformed one."""
    problems: list[InputError] = []
    reader = _Reader(graph, locate or (lambda n: (None, None)), problems)
    out = FailureModel()
    for node in sorted(graph.subjects(RDF.type, SOAP.FailureMode), key=str):
        try:
            mode = _mode(reader, node)
            out.modes[mode.name] = mode
        except _Malformed as e:
            reader.error(e.node, f"failure mode {_short(node)}: {e.message}")
    for action in graph.subjects(RDF.type, SOAP.Action):
        try:
            out.parameters[_name(reader, action)] = {
                str(p): str(reader.one(p, SOAP.hasParameter_Name, "parameter"))
                for p in reader.values(action, SOAP.hasAction_Parameter)}
        except _Malformed as e:
            reader.error(e.node, e.message)
    for node in sorted(graph.subjects(RDF.type, SOAP.ActionProgram), key=str):
        try:
            prog = _program(reader, node)
            out.programs[prog.action] = prog
        except _Malformed as e:
            reader.error(e.node, f"action program {_short(node)}: {e.message}")
    if problems:
        raise problems[0]
    out.delivers_partial_kits = delivers_partial_kits(graph, locate)
    return out


def _name(reader: _Reader, action) -> str:  # noqa: ANN001
    return str(reader.one(action, SOAP.hasAction_Name, "action"))


def _mode(r: _Reader, node) -> FailureModeDef:  # noqa: ANN001
    name = str(r.one(node, SOAP.hasFailureMode_Name, "failure mode"))
    action = r.one(node, SOAP.hasFailureMode_Action, "failure mode")
    phase_node = r.one(node, SOAP.hasFailureMode_Phase, "failure mode")
    if phase_node not in (SOAP.PreconditionCheck, SOAP.EffectCheck):
        raise _Malformed(node, f"phase {_short(phase_node)} is neither soap:PreconditionCheck nor soap:EffectCheck")
    violated = frozenset(str(r.one(p, SOAP.hasPredicate_Name, "predicate"))
                         for p in r.values(node, SOAP.hasFailureMode_ViolatedPredicate))
    params = tuple(str(p) for p in r.values(action, SOAP.hasAction_Parameter))
    cond_node = r.optional(node, SOAP.hasFailureMode_Condition)
    condition = r.formula(cond_node, params, (), owner=node) if cond_node is not None else None
    rem = r.one(node, SOAP.hasFailureMode_Remediation, "failure mode")
    sev, lik = r.optional(node, SOAP.hasFailureMode_Severity), r.optional(node, SOAP.hasFailureMode_Likelihood)
    cons = r.optional(node, SOAP.hasFailureMode_Consequence)
    return FailureModeDef(str(node), name, _name(r, action), PRE if phase_node == SOAP.PreconditionCheck else EFF,
                          violated, condition, str(cons or ""), int(sev.toPython()) if sev is not None else 0,
                          float(lik.toPython()) if lik is not None else 0.0, _remediation(r, rem, action),
                          tuple(_consequence(r, c, action) for c in sorted(r.values(node, SOAP.hasFailureMode_ObjectConsequence),
                                                                            key=str)))


def _individual(r: _Reader, node, cls) -> bool:  # noqa: ANN001
    """``node`` is an IRI typed ``cls`` (where the graph holds soap.ttl's individuals of it: a
    graph of a domain file alone is not checked)."""
    if not isinstance(node, URIRef):
        return False
    return (node, RDF.type, cls) in r.g or next(r.g.subjects(RDF.type, cls), None) is None


def _parameter(r: _Reader, param, action, owner, what: str) -> str:  # noqa: ANN001
    """The name of ``param``, which must be a parameter of ``action``."""
    if param not in set(r.values(action, SOAP.hasAction_Parameter)):
        raise _Malformed(owner, f"{what} {_short(param)} is not a parameter of {_short(action)}")
    return str(r.one(param, SOAP.hasParameter_Name, "parameter"))


def _consequence(r: _Reader, node, action) -> ObjectConsequence:  # noqa: ANN001
    kind = r.one(node, SOAP.hasObjectConsequence_Kind, "object consequence")
    if not _individual(r, kind, SOAP.ConsequenceKind):
        raise _Malformed(node, f"consequence kind {_short(kind)} is not a soap:ConsequenceKind individual")
    reason = r.optional(node, SOAP.hasObjectConsequence_Reason)
    param = _parameter(r, r.one(node, SOAP.hasObjectConsequence_Parameter, "object consequence"), action, node,
                       "consequence parameter")
    return ObjectConsequence(param, str(kind), str(reason) if reason is not None else _short(kind).lower())


def _remediation(r: _Reader, node, action) -> Remediation:  # noqa: ANN001
    recovery = r.one(node, SOAP.hasFailureRemediation_Recovery, "remediation")
    if not _individual(r, recovery, SOAP.RecoveryStrategy):
        raise _Malformed(node, f"recovery {_short(recovery)} is not a soap:RecoveryStrategy individual")
    retries = r.optional(node, SOAP.hasFailureRemediation_MaxRetries)
    operator = r.optional(node, SOAP.hasFailureRemediation_OperatorIntervention)
    notes = tuple(Notification(str(r.one(n, SOAP.hasNotification_Recipient, "notification")),
                               str(r.one(n, SOAP.hasNotification_Message, "notification")))
                  for n in r.values(node, SOAP.hasFailureRemediation_Notification))
    steps: tuple[RecoveryStepDef, ...] = ()
    plan_node = r.optional(node, SOAP.hasFailureRemediation_RecoveryPlan)
    if plan_node is not None:
        nodes = sorted(r.values(plan_node, SOAP.hasRecoveryPlan_Step),
                       key=lambda s: int(r.one(s, SOAP.hasRecoveryStep_Position, "recovery step").toPython()))
        steps = tuple(_step(r, s, action) for s in nodes)
    obj = r.optional(node, SOAP.hasFailureRemediation_Object)
    then = r.optional(node, SOAP.hasFailureRemediation_ThenReplan)
    return Remediation(str(node), _short(recovery), int(retries.toPython()) if retries is not None else 0,
                       bool(operator.toPython()) if operator is not None else False, notes,
                       tuple(s.action for s in steps), str(recovery),
                       _parameter(r, obj, action, node, "object") if obj is not None else None,
                       bool(then.toPython()) if then is not None else False, steps)


def _step(r: _Reader, node, failed) -> RecoveryStepDef:  # noqa: ANN001
    action = r.one(node, SOAP.hasRecoveryStep_Action, "recovery step")
    bindings = []
    for b in sorted(r.values(node, SOAP.hasRecoveryStep_Binding), key=str):
        param = _parameter(r, r.one(b, SOAP.hasParameterBinding_Parameter, "parameter binding"), action, b,
                           "bound parameter")
        source, obj = r.optional(b, SOAP.hasParameterBinding_FailedParameter), r.optional(b, SOAP.hasParameterBinding_Object)
        if (source is None) == (obj is None):
            raise _Malformed(b, "a parameter binding needs one of hasParameterBinding_FailedParameter, "
                                "hasParameterBinding_Object")
        bindings.append((param, ("failed", _parameter(r, source, failed, b, "failed parameter")) if source is not None
                         else ("object", str(obj))))
    return RecoveryStepDef(_name(r, action), tuple(bindings))


def _program(r: _Reader, node) -> ActionProgram:  # noqa: ANN001
    action = r.one(node, SOAP.hasActionProgram_Action, "action program")
    steps = []
    for s in r.values(node, SOAP.hasActionProgram_Step):
        pos = int(r.one(s, SOAP.hasCommandStep_Position, "command step").toPython())
        dur = r.optional(s, SOAP.hasCommandStep_Duration)
        target, text = r.optional(s, SOAP.hasCommandStep_Target), r.optional(s, SOAP.hasCommandStep_Text)
        approach = r.optional(s, SOAP.hasCommandStep_Approach)
        steps.append((pos, CommandStep(str(r.one(s, SOAP.hasCommandStep_Command, "command step")),
                                       str(target) if target is not None else None,
                                       float(dur.toPython()) if dur is not None else None,
                                       str(text) if text is not None else None,
                                       bool(approach.toPython()) if approach is not None else False)))
    steps.sort(key=lambda x: x[0])
    if [p for p, _ in steps] != list(range(1, len(steps) + 1)):
        raise _Malformed(node, "command step positions must run 1, 2, 3 ... without gaps")
    return ActionProgram(_name(r, action), tuple(s for _, s in steps))
