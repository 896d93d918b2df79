"""The cell interface: what the executor talks to, and what a simulator or a real cell implements.

As in the seeds' own system (USARSim behind CRCL and the USARTruth pose query, later swapped
for a real robot), the executor sees the world only through

* :meth:`CellInterface.execute`: one CRCL command (:mod:`kb.crcl`) -> a :class:`Status`;
* :meth:`CellInterface.sense`: a focus-of-attention query by class or by name ->
  :class:`Observation` s (seed 004 §3.2: name, class, time, location, roll/pitch/yaw);
* :meth:`CellInterface.inspect`: a quality inspection of one part;
* :meth:`CellInterface.begin_action`: the executor announces each plan action before its
  commands (a real cell may log it; the simulator keys fault injection on it).

:meth:`CellInterface.scene` is ground truth, for tests and scoring in simulation only: a real
cell cannot give it, and an executor must never use it to decide anything.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal, Protocol, runtime_checkable

from kb.crcl import Command
from kb.spatial.scene import Scene

Vector = tuple[float, float, float]


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
    ``time``: simulated seconds since the cell started; ``location``: (x, y, z) of its frame
    in the world, in metres; ``orientation``: (roll, pitch, yaw) in radians, the rotation
    ``Rz(yaw) Ry(pitch) Rx(roll)`` (:func:`kb.spatial.transforms.from_xyz_rpy`).
    """

    name: str
    cls: str
    time: float
    location: Vector
    orientation: Vector


@runtime_checkable
class CellInterface(Protocol):
    """A kitting workcell, simulated or real."""

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

    def scene(self) -> Scene:
        """Ground truth now. Simulation only (tests, scoring): a real cell cannot give it."""
        ...
