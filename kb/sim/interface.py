"""The cell interface, as the simulator sees it: the contract itself lives in
:mod:`kb.crcl.cell` (so the executor, a layer below ``kb.sim``, can type against it without
importing the simulator); its names are kept importable from here.

Ground truth (:meth:`kb.sim.SimulatedCell.scene`, and the :class:`~kb.crcl.cell.GroundTruth`
capability: the faults injected, the constraints violated, the sensor's mistakes) is for tests
and scoring in simulation only — a real cell cannot give it, and an executor must never use it
to decide anything.
"""

from kb.crcl.cell import CellInterface, Observation, Status, Vector

__all__ = ["CellInterface", "Observation", "Status", "Vector"]
