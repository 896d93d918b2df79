"""The cell contract: what an executor talks to, and what a simulator or a real cell implements.

As in the seeds' own system (USARSim behind CRCL and the USARTruth pose query, later swapped
for a real robot), an executor sees the world only through a cell. What a cell can do is a set
of capabilities, each a :class:`typing.Protocol` (runtime-checkable):

* :class:`Moves` (``"move"``): ``execute`` one CRCL command (:mod:`kb.crcl.commands`) -> a
  :class:`Status`; :class:`MovesPrograms` (``"move-program"``): ``execute_program``, one
  action's commands in one round trip (:func:`execute_program` runs a program on any cell that
  moves, with the same meaning everywhere: commands in order, those after a failed one not
  executed);
* :class:`Senses` (``"sense"``): ``sense`` a focus-of-attention query by class or by name ->
  :class:`Observation` s (seed 004 §3.2: name, class, time, location, roll/pitch/yaw; kitkb
  adds the SKU the sensor recognises); :class:`SensesNames` (``"sense-names"``): several
  objects by name in one query (:func:`sense_names` asks any cell that senses);
* :class:`Inspects` (``"inspect"``): a quality inspection of one part;
* :class:`AnnouncesActions` (``"begin-action"``): the executor announces each plan action
  before its commands (a real cell may log it; the simulator keys fault injection on it);
* :class:`GroundTruth` (``"ground-truth"``): the faults injected, the constraints violated and
  the sensor's mistakes; simulation only, for scoring, never for the executor;
* :class:`PartFates` (``"part-fates"``): every part's and kit tray's fate now (:class:`Fate`:
  where it truly is, its true SKU, whether it is defective, whether the robot can take it
  from there); simulation only, for the oracle of what was buildable (:mod:`kb.metrics.oracle`).

:class:`CellInterface` is the whole cell (move, sense, inspect, begin-action): the simulator
and kitkb's cell server are that. :func:`capabilities` names what a cell has (its own
``capabilities`` declaration, else the protocols it implements); :func:`require` refuses a
cell that lacks what a run needs with a one-line reason (the executor needs ``move`` and
``sense`` always, ``inspect`` for a plan with ``look-for-part``). Cells are chosen by URL
(:mod:`kb.cells`). :func:`truth_line` / :func:`parse_truth_line` are USARTruth's key-value
text form of an observation.

The contract lives in ``kb.crcl`` (layer 5) so the executor can type against it without
importing the simulator (``kb.sim``, above it).
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Any, Callable, Literal, Protocol, Sequence, TypeVar, runtime_checkable

from kb.core.errors import InputError
from kb.crcl.commands import Command

Vector = tuple[float, float, float]
T = TypeVar("T")
#: One ``{Key value}`` field of a USARTruth-style key-value line.
FIELD = re.compile(r"\{(\w+) ([^{}]*)\}")
_KEYS = ("Name", "Class", "Time", "Location", "Rotation")
#: The message of a command not executed because an earlier one of its program failed.
NOT_EXECUTED = "not executed: an earlier command of the program failed"


@dataclass(frozen=True)
class Status:
    """The outcome of one command: ``"done"`` or ``"error"`` with a message naming the problem."""

    state: Literal["done", "error"]
    message: str = ""

    @property
    def done(self) -> bool:
        """True when the command was carried out."""
        return self.state == "done"

    @classmethod
    def ok(cls, message: str = "") -> "Status":
        """A command carried out."""
        return cls("done", message)

    @classmethod
    def error(cls, message: str) -> "Status":
        """A command refused or failed, with why."""
        return cls("error", message)


@dataclass(frozen=True)
class Observation:
    """One sensed object, as a USARTruth line gives it (seed 004 §3.2).

    ``name``: the object's IRI; ``cls``: the local name of its most specific kitting class;
    ``time``: seconds since the cell started; ``location``: (x, y, z) of its frame in the
    world, in metres; ``orientation``: (roll, pitch, yaw) in radians, the rotation
    ``Rz(yaw) Ry(pitch) Rx(roll)`` (:func:`kb.spatial.transforms.from_xyz_rpy`); ``sku``: the
    local name of the stock keeping unit the sensor recognises the object as (None when it
    recognises none), so a part of the wrong SKU shows.
    """

    name: str
    cls: str
    time: float
    location: Vector
    orientation: Vector
    sku: str | None = None


# --- capabilities ------------------------------------------------------------------------------
# Each optional ability of a cell is a protocol of its own; :func:`capabilities` names those a
# cell has, :func:`require` refuses a cell that lacks one a run needs. No getattr probing.

@runtime_checkable
class Moves(Protocol):
    """A cell that carries out CRCL commands (a robot's controller)."""

    def execute(self, command: Command) -> Status:
        """Carry out one CRCL command."""
        ...


@runtime_checkable
class MovesPrograms(Protocol):
    """A cell that carries out one action's commands at once (one round trip to a remote cell):
    one status per command, in order, those after a failed one not executed."""

    def execute_program(self, commands: Sequence[Command]) -> list[Status]:
        """Carry out ``commands`` in order, stopping at the first failure."""
        ...


@runtime_checkable
class Senses(Protocol):
    """A cell with a pose sensor answering focus-of-attention queries by class and by name
    (USARTruth's, seed 004 §3.2)."""

    def sense(self, query: str, *, by: Literal["class", "name"] = "class") -> list[Observation]:
        """Objects of a class (local name or IRI, subclasses included) or of a name, as sensed now."""
        ...


@runtime_checkable
class SensesNames(Protocol):
    """A cell that senses several objects by name in one query."""

    def sense_names(self, names: Sequence[str]) -> list[Observation]:
        """The named objects as sensed now, in the order asked, those not in the cell left out."""
        ...


@runtime_checkable
class Inspects(Protocol):
    """A cell that inspects the quality of a part."""

    def inspect(self, name: str) -> bool:
        """Quality inspection of a part: False when it is defective (or not in the cell)."""
        ...


@runtime_checkable
class AnnouncesActions(Protocol):
    """A cell that hears which plan action starts before its commands (a real cell may log
    it; the simulator injects its faults and makes a kit there)."""

    def begin_action(self, index: int, action: str, args: tuple[str, ...]) -> None:
        """The executor starts plan action ``index`` (PDDL name and its argument IRIs)."""
        ...


@runtime_checkable
class GroundTruth(Protocol):
    """What only a simulation knows and the executor is never told, for scoring a run: the
    faults it injected, the constraints its robot violated, what its sensor got wrong (each a
    list of records with ``as_dict()`` or dataclasses)."""

    @property
    def injected(self) -> Sequence[Any]: ...

    @property
    def violations(self) -> Sequence[Any]: ...

    @property
    def sensor_errors(self) -> Sequence[Any]: ...


#: where a :class:`Fate` says an object is: in a kit, in a parts tray, on or in another object
#: (a work table, a box), on the floor, held by the robot, or gone from the cell
PLACES = ("kit", "parts-tray", "on", "floor", "held", "gone")


@dataclass(frozen=True)
class Fate:
    """One part's or kit tray's fate, as ground truth knows it (:class:`PartFates`).

    ``name``: its IRI; ``kind``: ``"part"`` or ``"kit-tray"``; ``sku``: the SKU it truly is
    now (IRI; None when it has none); ``defective``: a quality inspection would reject it;
    ``place``: one of :data:`PLACES`; ``holder``: what it rests in or on or is held by (IRI;
    None on the floor or gone); ``kit``: the kit it lies in (or, for a kit tray, whose tray it
    is), None when none; ``reachable``: the robot could take it from where it is (placed, not on
    the floor, its grasp point inside the robot's work volume where the cell knows one; what
    the robot holds is reachable)."""

    name: str
    kind: str
    sku: str | None
    defective: bool
    place: str
    holder: str | None
    kit: str | None
    reachable: bool

    def __post_init__(self) -> None:
        if self.place not in PLACES:
            raise ValueError(f"fate of {self.name}: place {self.place!r} is not one of {', '.join(PLACES)}")
        if self.kind not in ("part", "kit-tray"):
            raise ValueError(f"fate of {self.name}: kind {self.kind!r} is not part or kit-tray")


@runtime_checkable
class PartFates(Protocol):
    """A cell that knows every part's and kit tray's fate (simulation only: for scoring what was
    buildable, never for the executor)."""

    def part_fates(self) -> list[Fate]:
        """Each part and kit tray of the cell (those taken out of it too), its fate now."""
        ...


@runtime_checkable
class CellInterface(Moves, Senses, Inspects, AnnouncesActions, Protocol):
    """A whole kitting workcell, simulated (:class:`kb.sim.SimulatedCell`) or behind sockets
    (:class:`kb.crcl.remote.RemoteCell`): it moves, senses, inspects and hears each action.
    A cell may have less (a CRCL controller paired with a sensor moves and senses only): the
    executor asks for what a run needs (:func:`require`), not for all of this."""


#: each capability's name -> its protocol (the names :func:`capabilities` and :func:`require` use)
CAPABILITIES: dict[str, type] = {
    "move": Moves, "move-program": MovesPrograms, "sense": Senses, "sense-names": SensesNames,
    "inspect": Inspects, "begin-action": AnnouncesActions, "ground-truth": GroundTruth,
    "part-fates": PartFates,
}
#: what any run needs of its cell
RUN_NEEDS = ("move", "sense")


def capabilities(cell: object) -> frozenset[str]:
    """The capabilities of ``cell``: its own ``capabilities`` declaration when it has one (a
    set of :data:`CAPABILITIES` names; a wrapper declares what it forwards), else those whose
    protocol it implements (worked out once per class: a cell's abilities are its class's,
    unless the class forwards attributes with ``__getattr__`` or the cell declares them)."""
    declared = getattr(cell, "capabilities", None)
    if isinstance(declared, (set, frozenset, tuple, list)):
        return frozenset(declared)
    kind = type(cell)
    found = _BY_CLASS.get(kind)
    if found is None:
        found = frozenset(name for name, proto in CAPABILITIES.items() if isinstance(cell, proto))
        if not hasattr(kind, "__getattr__"):
            _BY_CLASS[kind] = found
    return found


#: the capabilities of each class of cell met so far (:func:`capabilities`)
_BY_CLASS: dict[type, frozenset[str]] = {}


def has(cell: object, capability: str) -> bool:
    """True when ``cell`` has ``capability`` (a :data:`CAPABILITIES` name)."""
    return capability in capabilities(cell)


def missing(cell: object, needs: Sequence[str]) -> list[str]:
    """The capabilities of ``needs`` that ``cell`` lacks, in the order asked."""
    have = capabilities(cell)
    return [n for n in needs if n not in have]


def require(cell: object, needs: Sequence[str], why: str = "the run") -> None:
    """Refuse ``cell`` with a one-line :class:`~kb.core.errors.InputError` when it lacks a
    capability of ``needs`` (names of :data:`CAPABILITIES`), saying what needs it."""
    lacking = missing(cell, needs)
    if lacking:
        name = getattr(cell, "url", None) or type(cell).__name__
        raise InputError(f"the cell {name} cannot {', '.join(_VERBS.get(n, n) for n in lacking)}, "
                         f"which {why} needs")


_VERBS = {"move": "execute CRCL commands", "move-program": "execute CRCL programs", "sense": "sense objects",
          "sense-names": "sense objects by name in one query", "inspect": "inspect parts",
          "begin-action": "hear which action starts", "ground-truth": "tell its ground truth",
          "part-fates": "tell where its parts truly are"}


def run_in_order(run: Callable[[T], Status], commands: Sequence[T]) -> list[Status]:
    """One status per command: each run in order until one fails; the rest are not run
    (``Status.error(NOT_EXECUTED)``)."""
    out: list[Status] = []
    for command in commands:
        failed = bool(out) and not out[-1].done
        out.append(Status.error(NOT_EXECUTED) if failed else run(command))
    return out


def sense_names(cell: Senses, names: Sequence[str]) -> list[Observation]:
    """The named objects (IRIs) as sensed now, in the order asked, those not in the cell left
    out: in one query where the cell :class:`SensesNames` (:class:`kb.sim.SimulatedCell`),
    else one ``sense(name, by="name")`` per name. The executor's focus of attention asks for an
    action's neighbourhood this way (a query's cost then follows its answer, not the cell)."""
    if has(cell, "sense-names"):
        return list(cell.sense_names(names))  # type: ignore[attr-defined]
    return [o for n in names for o in cell.sense(n, by="name")]


def execute_program(cell: Moves, commands: Sequence[Command]) -> list[Status]:
    """Run one action's commands on ``cell``: one status per command, in order, the commands
    after a failed one not executed. A cell that :class:`MovesPrograms` (one round trip to a
    remote cell) does it; any other cell command by command."""
    if has(cell, "move-program"):
        return list(cell.execute_program(commands))  # type: ignore[attr-defined]
    return run_in_order(cell.execute, commands)


# --- USARTruth's text form --------------------------------------------------------------------

def truth_line(obs: Observation, sku: bool = True) -> str:
    """The USARTruth line of an observation (numbers with ``repr``: they read back the same):
    USARTruth's five fields, then ``{Sku ...}`` when ``sku`` and the observation has one."""
    def vec(v: tuple[float, ...]) -> str:
        return ",".join(repr(float(x)) for x in v)
    line = (f"{{Name {obs.name}}} {{Class {obs.cls}}} {{Time {float(obs.time)!r}}} "
            f"{{Location {vec(obs.location)}}} {{Rotation {vec(obs.orientation)}}}")
    return line + (f" {{Sku {obs.sku}}}" if sku and obs.sku is not None else "")


def parse_truth_line(line: str) -> Observation:
    """The observation of a USARTruth line (keys in any case, other fields ignored); ValueError
    naming what is missing or malformed."""
    fields = dict(FIELD.findall(line))
    if not all(k in fields for k in _KEYS):  # keys in another case
        fields = {k.capitalize(): v for k, v in FIELD.findall(line)}
    missing = [k for k in _KEYS if k not in fields]
    if missing:
        raise ValueError(f"USARTruth line without {', '.join(missing)}: {line!r}")

    def vec(key: str) -> Vector:
        parts = fields[key].split(",")
        if len(parts) != 3:
            raise ValueError(f"{key} must be three comma-separated numbers: {fields[key]!r}")
        return tuple(float(p) for p in parts)  # type: ignore[return-value]
    sku = fields["Sku"].strip() if "Sku" in fields else None
    return Observation(fields["Name"].strip(), fields["Class"].strip(), float(fields["Time"]), vec("Location"),
                       vec("Rotation"), sku)
