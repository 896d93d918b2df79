"""The cell contract: what an executor talks to, and what a simulator or a real cell implements.

As in the seeds' own system (USARSim behind CRCL and the USARTruth pose query, later swapped
for a real robot), an executor sees the world only through a :class:`CellInterface`:

* :meth:`~CellInterface.execute`: one CRCL command (:mod:`kb.crcl.commands`) -> a :class:`Status`;
* :meth:`~CellInterface.sense`: a focus-of-attention query by class or by name ->
  :class:`Observation` s (seed 004 §3.2: name, class, time, location, roll/pitch/yaw; kitkb
  adds the SKU the sensor recognises);
  (:func:`sense_names`: several objects by name, in one query where the cell offers it);
* :meth:`~CellInterface.inspect`: a quality inspection of one part;
* :meth:`~CellInterface.begin_action`: the executor announces each plan action before its
  commands (a real cell may log it; the simulator keys fault injection on it).

:func:`execute_program` runs one action's command list on any cell, in one round trip where
the cell offers ``execute_program`` (:class:`kb.crcl.remote.RemoteCell`), with the same
meaning everywhere: commands in order, those after a failed one not executed.
:func:`truth_line` / :func:`parse_truth_line` are USARTruth's key-value text form of an
observation. Ground truth (a simulator's ``scene()``) is not part of the contract.

The contract lives in ``kb.crcl`` (layer 5) so the executor can type against it without
importing the simulator (``kb.sim``, above it).
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Callable, Literal, Protocol, Sequence, TypeVar, runtime_checkable

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


@runtime_checkable
class CellInterface(Protocol):
    """A kitting workcell, simulated (:class:`kb.sim.SimulatedCell`) or behind sockets
    (:class:`kb.crcl.remote.RemoteCell`)."""

    def execute(self, command: Command) -> Status:
        """Carry out one CRCL command."""
        ...

    def sense(self, query: str, *, by: Literal["class", "name"] = "class") -> list[Observation]:
        """Objects of a class (local name or IRI, subclasses included) or of a name, as sensed now."""
        ...

    def inspect(self, name: str) -> bool:
        """Quality inspection of a part: False when it is defective (or not in the cell)."""
        ...

    def begin_action(self, index: int, action: str, args: tuple[str, ...]) -> None:
        """The executor starts plan action ``index`` (PDDL name and its argument IRIs)."""
        ...


def run_in_order(run: Callable[[T], Status], commands: Sequence[T]) -> list[Status]:
    """One status per command: each run in order until one fails; the rest are not run
    (``Status.error(NOT_EXECUTED)``)."""
    out: list[Status] = []
    for command in commands:
        failed = bool(out) and not out[-1].done
        out.append(Status.error(NOT_EXECUTED) if failed else run(command))
    return out


def sense_names(cell: CellInterface, names: Sequence[str]) -> list[Observation]:
    """The named objects (IRIs) as sensed now, in the order asked, those not in the cell left
    out: in one query where the cell offers ``sense_names`` (:class:`kb.sim.SimulatedCell`),
    else one ``sense(name, by="name")`` per name. The executor's focus of attention asks for an
    action's neighbourhood this way (a query's cost then follows its answer, not the cell)."""
    own = getattr(cell, "sense_names", None)
    if callable(own):
        return list(own(names))
    return [o for n in names for o in cell.sense(n, by="name")]


def execute_program(cell: CellInterface, commands: Sequence[Command]) -> list[Status]:
    """Run one action's commands on ``cell``: one status per command, in order, the commands
    after a failed one not executed. A cell with its own ``execute_program`` (one round trip
    to a remote cell) does it; any other cell command by command."""
    own = getattr(cell, "execute_program", None)
    if callable(own):
        return list(own(commands))
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
