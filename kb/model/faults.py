"""Fault kinds, declared once in Turtle, as typed records.

A seeded fault a simulated cell can inject is a ``soap:FaultKind`` individual of the domain
(the shipped kinds are the last section of ``kitting-domain.ttl``; an extension given with
``--domain`` adds kinds, or adds diagnosing modes to a kind, in the same way; soap.ttl section 7
is the vocabulary). One :class:`FaultKind` per individual says everything every reader needs:

* the simulator (:mod:`kb.sim.faults`): the actions it strikes (:class:`Strike`: the action and
  the argument naming the object it acts on, with that parameter's type), the
  :class:`FaultMechanism` that carries it out (its code is per mechanism IRI, never per kind),
  and its place in the order of kinds (how one draw per action is shared among them);
* the detection scorer (:mod:`kb.execution.quality`): the failure modes that are a right
  diagnosis of it, whether every injection must be detected, whether the right diagnosis
  rejects the object;
* ``kitkb faults`` and the fault options' help, and the errors test method's default mix
  (:meth:`FaultKinds.default_mix`: each kind's ``soap:hasFaultKind_TestMethodRate``).

:class:`FaultKinds` is the ordered catalogue of a domain's kinds; :func:`fault_kinds` reads it
from a loaded domain (:class:`kb.execution.inputs.DomainInputs`' ``kb``),
:func:`shipped_fault_kinds` from the shipped domain (read once per process). A malformed kind
is an :class:`~kb.core.errors.InputError` at its file and line.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path
from typing import Any, Iterator, Sequence

from rdflib import Graph, Literal, URIRef
from rdflib.namespace import RDF, RDFS

from kb.core.errors import InputError
from kb.core.namespaces import SOAP, local_name
from kb.io import KnowledgeBase
from kb.io.loader import domain_knowledge
from kb.model.definitions import Locator, _Malformed, _Reader, _short, locator


@dataclass(frozen=True)
class FaultMechanism:
    """A primitive the simulated cell implements (``soap:FaultMechanism``): whether it acts on
    an object the struck action names (else it arms the robot), and its distances (metres)."""

    iri: str
    acts_on_object: bool
    min_shift: float | None = None
    max_shift: float | None = None
    beside: float | None = None

    @property
    def name(self) -> str:
        return local_name(self.iri)


@dataclass(frozen=True)
class Strike:
    """One action a kind strikes: its name and, for a mechanism acting on an object, the
    argument (0-based, in the action's parameter order) naming the object and the class
    (IRI) that object must be of."""

    action: str
    argument: int | None = None
    type: str | None = None


@dataclass(frozen=True)
class FaultKind:
    """One fault kind, everything about it that the simulator, the scorer, the CLI and the
    test methods read."""

    iri: str
    name: str
    strikes: tuple[Strike, ...]
    mechanism: FaultMechanism
    diagnosed_by: frozenset[str]  # failure-mode names that are a right diagnosis
    must_detect: bool
    rejecting: bool = False
    position: int | None = None
    test_rate: float | None = None  # chance per struck action in the errors method's default mix
    also_names: tuple[str, ...] = ()  # model properties: the struck object's related objects named too
    comment: str = ""
    undeclared_modes: tuple[str, ...] = ()  # hasFaultKind_DiagnosedBy values that are no failure mode of the domain

    @property
    def actions(self) -> tuple[str, ...]:
        return tuple(s.action for s in self.strikes)

    def strike(self, action: str) -> Strike | None:
        """How the kind strikes ``action`` (None: it does not)."""
        return next((s for s in self.strikes if s.action == action), None)

    def as_dict(self) -> dict[str, Any]:
        """The kind as JSON data (``kitkb faults --format json``)."""
        return {"name": self.name, "iri": self.iri, "actions": list(self.actions),
                "mechanism": self.mechanism.name, "diagnosed_by": sorted(self.diagnosed_by),
                "must_detect": self.must_detect, "rejecting": self.rejecting, "position": self.position,
                "test_rate": self.test_rate, "comment": self.comment}


@dataclass(frozen=True)
class FaultKinds:
    """A domain's fault kinds, in their order (``soap:hasFaultKind_Position``, then name)."""

    kinds: tuple[FaultKind, ...] = ()
    _by_name: dict[str, FaultKind] = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "_by_name", {k.name: k for k in self.kinds})

    def __iter__(self) -> Iterator[FaultKind]:
        return iter(self.kinds)

    def __len__(self) -> int:
        return len(self.kinds)

    def __contains__(self, name: object) -> bool:
        return name in self._by_name

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(k.name for k in self.kinds)

    def get(self, name: str) -> FaultKind | None:
        return self._by_name.get(name)

    def check(self, name: str) -> FaultKind:
        """The kind called ``name``; ValueError naming the known ones if there is none."""
        kind = self._by_name.get(name)
        if kind is None:
            raise ValueError(f"unknown fault kind {name!r}; known: {', '.join(self.names) or 'none'}")
        return kind

    def order(self, name: str) -> int:
        """The place of kind ``name`` in the order of kinds."""
        return self.names.index(name)

    @property
    def actions(self) -> tuple[str, ...]:
        """The actions some kind strikes, in the order first met."""
        return tuple(dict.fromkeys(a for k in self.kinds for a in k.actions))

    def eligible(self, action: str) -> tuple[FaultKind, ...]:
        """The kinds that strike ``action``, in order."""
        return tuple(k for k in self.kinds if k.strike(action) is not None)

    def rejecting_modes(self) -> frozenset[str]:
        """Failure modes after which the object is rejected: the right diagnoses of rejecting kinds."""
        return frozenset(m for k in self.kinds if k.rejecting for m in k.diagnosed_by)

    def default_mix(self) -> str:
        """The errors test method's default faults (``KIND=RATE,...``): each kind with a test
        method rate, the most frequent first (ties in the order of kinds)."""
        rated = [k for k in self.kinds if k.test_rate]
        rated.sort(key=lambda k: -float(k.test_rate or 0.0))  # stable: ties keep the order of kinds
        return ",".join(f"{k.name}={_rate(k.test_rate)}" for k in rated)


def _rate(p: float | None) -> str:
    return f"{p:g}"


# ------------------------------------------------------------------------------ reading

def fault_kinds(kb: KnowledgeBase) -> FaultKinds:
    """The fault kinds of a loaded domain (errors at their file and line)."""
    return read_fault_kinds(kb.graph, locator(kb))


@lru_cache(maxsize=1)
def shipped_fault_kinds() -> FaultKinds:
    """The fault kinds of the shipped domain alone (read once per process)."""
    return fault_kinds(domain_knowledge(None))


def domain_fault_kinds(extensions: Sequence[str | Path] | None = None) -> FaultKinds:
    """The fault kinds of the shipped domain with the extension files ``extensions`` (``--domain``),
    read as every reader of the domain reads it (:func:`kb.io.loader.domain_knowledge`)."""
    return fault_kinds(domain_knowledge(extensions)) if extensions else shipped_fault_kinds()


def read_fault_kinds(graph: Graph, locate: Locator | None = None) -> FaultKinds:
    """Every ``soap:FaultKind`` of ``graph``; InputError at the first malformed one."""
    problems: list[InputError] = []
    reader = _Reader(graph, locate or (lambda n: (None, None)), problems)
    kinds: list[FaultKind] = []
    seen: dict[str, URIRef] = {}
    for node in sorted(graph.subjects(RDF.type, SOAP.FaultKind), key=str):
        try:
            kind = _kind(reader, node)
        except _Malformed as e:
            reader.error(e.node, f"fault kind {_short(node)}: {e.message}")
            continue
        if kind.name in seen:
            reader.error(node, f"fault kind {_short(node)}: the name {kind.name!r} is also "
                               f"{_short(seen[kind.name])}'s")
            continue
        seen[kind.name] = node
        kinds.append(kind)
    if problems:
        raise problems[0]
    kinds.sort(key=lambda k: (k.position is None, k.position or 0, k.name))
    return FaultKinds(tuple(kinds))


def _kind(r: _Reader, node: URIRef) -> FaultKind:
    name = str(r.one(node, SOAP.hasFaultKind_Name, "fault kind"))
    if not name or any(c in name for c in ",=@ "):
        raise _Malformed(node, f"the name {name!r} must be non-empty, without ',', '=', '@' or spaces")
    mechanism = _mechanism(r, r.one(node, SOAP.hasFaultKind_Mechanism, "fault kind"), node)
    actions = r.values(node, SOAP.hasFaultKind_Action)
    if not actions:
        raise _Malformed(node, "needs at least one hasFaultKind_Action")
    targets = {_owner(r, p, node): p for p in r.values(node, SOAP.hasFaultKind_Target)}
    strikes = []
    for action in actions:
        if (action, RDF.type, SOAP.Action) not in r.g:
            raise _Malformed(node, f"hasFaultKind_Action {_short(action)} is not a soap:Action")
        action_name = str(r.one(action, SOAP.hasAction_Name, "action"))
        target = targets.pop(action, None)
        if target is None:
            if mechanism.acts_on_object:
                raise _Malformed(node, f"mechanism {mechanism.name} acts on an object: give the parameter of "
                                       f"{action_name} naming it (hasFaultKind_Target)")
            strikes.append(Strike(action_name))
            continue
        position = _number(r.one(target, SOAP.hasParameter_Position, "parameter"), target, int)
        strikes.append(Strike(action_name, position - 1, str(r.one(target, SOAP.hasParameter_Type, "parameter"))))
    if targets:
        param = next(iter(targets.values()))
        raise _Malformed(node, f"hasFaultKind_Target {_short(param)} is a parameter of none of its actions")
    # a mode the domain does not declare (a domain without it) is no right diagnosis: kept aside, so
    # that runs in such a domain still inject the kind (kitkb faults warns of it)
    declared = [m for m in r.values(node, SOAP.hasFaultKind_DiagnosedBy) if (m, RDF.type, SOAP.FailureMode) in r.g]
    undeclared = tuple(str(m) for m in r.values(node, SOAP.hasFaultKind_DiagnosedBy) if m not in declared)
    position = r.optional(node, SOAP.hasFaultKind_Position)
    rate = r.optional(node, SOAP.hasFaultKind_TestMethodRate)
    rate_value = _number(rate, node, float) if rate is not None else None
    if rate_value is not None and not 0.0 <= rate_value <= 1.0:
        raise _Malformed(node, f"hasFaultKind_TestMethodRate must be from 0 to 1, not {rate_value}")
    comment = r.optional(node, RDFS.comment)
    return FaultKind(str(node), name, tuple(strikes), mechanism,
                     frozenset(str(r.one(m, SOAP.hasFailureMode_Name, "failure mode")) for m in declared),
                     _flag(r, node, SOAP.hasFaultKind_MustBeDetected, required=True),
                     _flag(r, node, SOAP.hasFaultKind_Rejecting),
                     _number(position, node, int) if position is not None else None, rate_value,
                     tuple(str(p) for p in r.values(node, SOAP.hasFaultKind_AlsoNames)),
                     str(comment) if comment is not None else "", undeclared)


def _mechanism(r: _Reader, node: Any, kind: URIRef) -> FaultMechanism:
    if not isinstance(node, URIRef) or (node, RDF.type, SOAP.FaultMechanism) not in r.g:
        raise _Malformed(kind, f"hasFaultKind_Mechanism {_short(node)} is not a soap:FaultMechanism")

    def distance(prop: URIRef) -> float | None:
        value = r.optional(node, prop)
        return _number(value, node, float) if value is not None else None

    return FaultMechanism(str(node), _flag(r, node, SOAP.hasFaultMechanism_ActsOnObject),
                          distance(SOAP.hasFaultMechanism_MinShift), distance(SOAP.hasFaultMechanism_MaxShift),
                          distance(SOAP.hasFaultMechanism_Beside))


def _owner(r: _Reader, parameter: Any, kind: URIRef) -> Any:
    """The action a target parameter belongs to."""
    owners = sorted(r.g.subjects(SOAP.hasAction_Parameter, parameter), key=str)
    if len(owners) != 1:
        raise _Malformed(kind, f"hasFaultKind_Target {_short(parameter)} is not the parameter of one action")
    return owners[0]


def _flag(r: _Reader, node: Any, prop: URIRef, required: bool = False) -> bool:
    what = "fault mechanism" if str(prop).startswith(str(SOAP.hasFaultMechanism_)) else "fault kind"
    value = r.one(node, prop, what) if required else r.optional(node, prop)
    if value is None:
        return False
    if not isinstance(value, Literal) or not isinstance(value.toPython(), bool):
        raise _Malformed(node, f"{local_name(str(prop))} must be true or false, not {value}")
    return bool(value.toPython())


def _number(value: Any, node: Any, kind: type) -> Any:
    try:
        if not isinstance(value, Literal):
            raise ValueError
        return kind(value.toPython())
    except (TypeError, ValueError):
        raise _Malformed(node, f"{value} is not a number") from None
