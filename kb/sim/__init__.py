"""The simulated workcell, behind the small interface a real cell could also implement.

:class:`SimulatedCell` implements :class:`CellInterface` (``execute`` a CRCL command ->
:class:`Status`, ``sense`` by class or name -> :class:`Observation` s, ``inspect``,
``begin_action``; ``scene`` is ground truth, for simulation only) on a ground truth built from
a state file (:mod:`.world`), with a robot executing CRCL (:mod:`.robot`), a sensor with
optional Gaussian noise and USARTruth's text form (:mod:`.sensor`), and seeded fault injection
(:mod:`.faults`: :class:`FaultSpec`, :class:`Injected`, :data:`FAULT_KINDS`).
"""

from kb.sim.cell import SimulatedCell
from kb.sim.faults import FAULT_KINDS, FaultSpec, Injected
from kb.sim.interface import CellInterface, Observation, Status
from kb.sim.sensor import parse_truth_line, truth_line

__all__ = ["FAULT_KINDS", "CellInterface", "FaultSpec", "Injected", "Observation", "SimulatedCell", "Status",
           "parse_truth_line", "truth_line"]
