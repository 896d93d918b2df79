"""What a closed loop tells its watchers, as typed events (:mod:`kb.execution.loop`).

The loop and the executor call one callback (``on_event``) with these frozen dataclasses, in
the order things happen; nobody parses text back. A stage of the loop is bracketed by
:class:`StageStarted` and :class:`StageEnded` (with the stage's result object); inside the
``execute`` stage each plan action is bracketed by :class:`ActionStarted` and
:class:`ActionEnded`, with the :class:`CheckMade`, :class:`FailureFound`, :class:`Recovered`,
:class:`Replanned`, :class:`Notified` and :class:`StableState` events of the action between
them, and a run that cannot go on ends with :class:`Stopped`.

Each event's :meth:`Event.text` is the line ``kitkb run`` prints for it (None: no line), so the
command line, a log and the API's ``progress`` callback say the same thing in the same words.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Callable

#: the stages of the closed loop, in their order
STAGES = ("validate", "pddl", "plan", "geometry", "world", "execute")


@dataclass(frozen=True)
class Event:
    """Something that happened in a closed loop."""

    def text(self) -> str | None:
        """The line ``kitkb run`` prints for this event (None: none)."""
        return None


@dataclass(frozen=True)
class StageStarted(Event):
    """A stage of the loop (one of :data:`STAGES`) starts; ``scenario`` names the run."""

    stage: str
    scenario: str
    detail: dict[str, Any] = field(default_factory=dict, compare=False)


@dataclass(frozen=True)
class StageEnded(Event):
    """A stage ended after ``seconds``; ``result`` is what it made: a ``ValidationReport``
    (validate), a ``KittingModel`` (pddl), a ``PlanResult`` (plan), an ``Agreement``
    (geometry), a :class:`WorldLoaded` (world), a ``Run`` (execute). ``ok`` False: the loop
    goes no further (``reason`` says why, as the report does). ``cpu``: this process's CPU
    seconds in the stage (a planner's own process not counted)."""

    stage: str
    scenario: str
    seconds: float
    result: Any = field(default=None, compare=False)
    ok: bool = True
    reason: str | None = None
    cpu: float = field(default=0.0, compare=False)


@dataclass(frozen=True)
class WorldLoaded:
    """The ``world`` stage's result: the database, what the load stored, the global poses read
    back from it."""

    url: str
    individuals: int
    poses: int


@dataclass(frozen=True)
class ActionStarted(Event):
    """Plan action ``index`` (``line``: its PDDL text) starts."""

    index: int
    action: str
    args: tuple[str, ...]
    line: str


@dataclass(frozen=True)
class ActionEnded(Event):
    """Plan action ``index`` ended with ``status`` (``done``, ``failed``, ``rebound``, ...)."""

    index: int
    action: str
    args: tuple[str, ...]
    line: str
    status: str

    def text(self) -> str | None:
        return f"  {self.index:>3} {self.line}  ok" if self.status == "done" else None


@dataclass(frozen=True)
class CheckMade(Event):
    """Action ``index``'s preconditions (``phase`` "precondition") or effects ("effect") were decided from
    geometry; ``violated`` and ``undecidable`` are the atoms' texts."""

    index: int
    phase: str
    ok: bool
    violated: tuple[str, ...] = ()
    undecidable: tuple[str, ...] = ()

    def text(self) -> str | None:
        if not self.undecidable:
            return None
        return f"  action {self.index}: undecidable under the sensor's noise: " + ", ".join(self.undecidable)


@dataclass(frozen=True)
class FailureFound(Event):
    """A check of action ``index`` failed and was diagnosed as ``mode``."""

    index: int
    action: str
    line: str
    phase: str
    violated: tuple[str, ...]
    mode: str

    def text(self) -> str | None:
        return f"  failure at action {self.index} ({self.line}, {self.phase}): {', '.join(self.violated)} -> {self.mode}"


@dataclass(frozen=True)
class Recovered(Event):
    """A recovery step: ``kind`` ``retry``, ``rebind`` (``old`` -> ``new`` part, ``why``),
    ``reject`` (the held part ``old`` put back where it was taken) or ``recovery-plan`` (its
    actions queued, ``why``: their lines)."""

    index: int
    kind: str
    old: str | None = None
    new: str | None = None
    why: str = ""

    def text(self) -> str | None:
        if self.kind == "rebind":
            return f"  rebound {self.old} -> {self.new} ({self.why})"
        if self.kind == "reject":
            return f"  rejected {self.old}: put back where it was taken"
        if self.kind == "recovery-plan":
            return f"  recovery plan: {self.why}"
        return None


@dataclass(frozen=True)
class Replanned(Event):
    """A new plan of ``actions`` actions replaces the rest of the old one."""

    actions: int

    def text(self) -> str | None:
        return f"  replanned: {self.actions} actions"


@dataclass(frozen=True)
class KitsChosen(Event):
    """The usable parts cannot fill every kit (:mod:`kb.execution.partial`): the kits the next
    plan finishes, and each other kit with how it ends (``delivered partial`` | ``left``) and
    what it lacks ((SKU, count), ...)."""

    finished: tuple[str, ...] | list[str]
    partial: tuple[tuple[str, str, tuple[tuple[str, int], ...]], ...] | list

    def text(self) -> str | None:
        rest = "; ".join(f"{kit} {how} (lacks {', '.join(f'{sku} {n}' for sku, n in lacks)})"
                         for kit, how, lacks in self.partial)
        return f"  kits the parts allow: {', '.join(self.finished) or 'none'} finished; {rest}"


@dataclass(frozen=True)
class StableState(Event):
    """Action ``index``'s effects hold: the belief's poses are the new stable state (and are
    committed to the run's store, if it has one)."""

    index: int


@dataclass(frozen=True)
class Notified(Event):
    """A failure mode's remediation notifies ``recipient`` of ``message``."""

    recipient: str
    message: str

    def text(self) -> str | None:
        return f"    notify {self.recipient}: {self.message}"


@dataclass(frozen=True)
class Stopped(Event):
    """The run cannot go on: ``reason``; ``internal``: a fault of kitkb's own stopped it."""

    reason: str
    internal: bool = False

    def text(self) -> str | None:
        return self.reason if self.internal else f"stopped: {self.reason}"


Listener = Callable[[Event], None]


def ignore(event: Event) -> None:
    """The listener that does nothing (the default of every ``on_event``)."""


def lines(say: Callable[[str], None]) -> Listener:
    """A listener that gives ``say`` each event's line (the executor's old ``progress``)."""
    def listen(event: Event) -> None:
        text = event.text()
        if text is not None:
            say(text)
    return listen
