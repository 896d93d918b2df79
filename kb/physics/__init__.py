"""A physics-based workcell on MuJoCo, behind kitkb's cell interface (``--cell mujoco:``).

The scene from the ontology's state (:mod:`.mjcf`: ``build``, ``kitkb sim export-mjcf``), the
engine and its bodies by object (:mod:`.engine`: ``Physics``), the robot driving a mocap body
along CRCL motions with grips as welds (:mod:`.robot`: ``PhysicsRobot``), faults caused by
physics (:mod:`.faults`), the cell (:mod:`.cell`: ``MujocoCell``, ``open_mujoco``, found by
module name by :mod:`kb.cells.registry`) and its parameters (:mod:`.params`). docs/physics.md.
"""

from kb.physics.cell import MujocoCell, open_mujoco
from kb.physics.engine import Physics
from kb.physics.mjcf import Mjcf, build, cylinders

__all__ = ["Mjcf", "MujocoCell", "Physics", "build", "cylinders", "open_mujoco"]
