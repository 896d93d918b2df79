"""The simulated workcell, behind the small interface a real cell could also implement.

:class:`SimulatedCell` implements the cell contract :class:`CellInterface` (``execute`` a CRCL
command -> :class:`Status`, ``sense`` by class or name -> :class:`Observation` s, ``inspect``,
``begin_action``; the contract lives in :mod:`kb.crcl.cell`, its names are importable from here
too; ``scene`` is ground truth, for simulation only) on a ground truth built from a state file
(:mod:`.world`), with a robot executing CRCL (:mod:`.robot`), a sensor with optional Gaussian
noise and USARTruth's text form (:mod:`.sensor`), and seeded fault injection (:mod:`.faults`:
:class:`FaultSpec`, :class:`Injected`; the kinds are the domain's, :mod:`kb.model.faults`). :class:`CellServer`
(:mod:`.server`) serves a cell on loopback in kitkb's cell protocol (:mod:`kb.crcl.wire`:
USARTruth-style sensor lines, a CRCL 1.x controller on the command port), for
:class:`kb.crcl.RemoteCell` and any CRCL 1.x client.
A run opens it by URL (``sim:``, the default; :func:`kb.cells.open_cell` finds
:func:`kb.sim.cell.open_simulated` by module name, so the executor never imports this package);
its sensor's noise is the accuracy model of :mod:`kb.cells.accuracy` (:mod:`.noise` keeps the
name ``SensorNoise``), and it has every capability of :mod:`kb.crcl.cell`, ground truth
(``injected``, ``violations``, ``sensor_errors``) included.
The robot notices constraint violations (overweight grasps, moves out of its work volume,
wrong effectors, contacts along every move: :class:`Violation`, ``SimulatedCell.violations``),
and :mod:`kb.sim.playback` (imported on use) plays a CRCL program on a cell of a state and
decides the first paper's object and constraint metrics (``play``, ``object_metrics``).
"""

from kb.sim.cell import SimulatedCell, Violation
from kb.sim.faults import FaultSpec, Injected
from kb.sim.interface import CellInterface, Observation, Status
from kb.sim.robot import VIOLATION_KINDS
from kb.sim.sensor import parse_truth_line, truth_line
from kb.sim.server import CellServer

__all__ = ["VIOLATION_KINDS", "CellInterface", "CellServer", "FaultSpec", "Injected", "Observation",
           "SimulatedCell", "Status", "Violation", "parse_truth_line", "truth_line"]
