"""The physical parameters of the MuJoCo cell, in one place (SI units), each chosen and said why.

These are data of the simulation, not of a scenario: a state file gives shapes, poses and SKU
weights; what the kitting model does not say (friction, how hard a contact is, how thick a
tray's floor is, how a vacuum cup gives under load) is here, documented in docs/physics.md.
Nothing here is tuned to a shipped scenario.
"""

from __future__ import annotations

from dataclasses import dataclass

#: Integration step (s). 4 ms: stable for the scenarios' parts (centimetres) at a kitting robot's
#: speeds (1 m/s), the contact time constant below five steps (MuJoCo wants at least two); 2 ms
#: gave the same kits and final poses at 1.3x the cost (docs/benchmarks.md).
TIMESTEP = 0.004
#: MuJoCo's contact softness (solref: time constant s, damping ratio): critically damped, 20 ms.
CONTACT_SOLREF = (0.02, 1.0)
#: Sliding, torsional and rolling friction of every contact (MuJoCo's geom friction): 0.6 is
#: plastic or painted metal on plastic or wood; torsional and rolling small, so a cylinder rolls.
FRICTION = (0.6, 0.005, 0.0001)
#: Density (kg/m^3) of an object whose SKU gives no weight (hard plastic).
DENSITY = 900.0
#: Thickness (m) of an open container's floor and walls, where the model gives only its outer
#: box: the walls lie inside the box; the floor plate lies just under the box's bottom face, so
#: that what the state puts on the floor rests on it where the state says (docs/physics.md).
PLATE = 0.004
#: The tool tip's acceleration (m/s^2) at the start and end of every straight leg (a
#: trapezoidal speed profile up to the commanded speed): what a held part feels.
ACCELERATION = 2.0
#: A body comes to rest when its speed stays under this (m/s, rad/s)...
REST_SPEED = 2e-3
#: ...for this long (s); a release is stepped until everything is at rest, or at most SETTLE s.
REST_TIME = 0.05
SETTLE = 3.0
#: How long (s) the cell lets its initial state settle before the first command.
INITIAL_SETTLE = 0.3
#: A weld's softness for a parallel gripper (fingers clamp: stiff) and a vacuum cup (bellows:
#: softer, and its rotational part weaker: ``torquescale``, so an off-centre load tilts it).
GRIPPER_WELD = (0.004, 1.0, 1.0)  # (time constant, damping ratio, torquescale)
VACUUM_WELD = (0.008, 1.0, 1.0)
#: A weld's impedance (MuJoCo solimp): near 1, so a held load sags by micrometres, not millimetres.
WELD_SOLIMP = (0.99, 0.999, 0.001, 0.5, 2.0)
#: At the end of a leg the controller waits until what it holds has caught up with the tool
#: (moves slower than REST_SPEED), at most this long (s): a robot's in-position wait.
CATCH_UP = 0.3
#: How much of a part's top face a parallel gripper's fingers must bracket, as a fraction of the
#: half-length from the centre: a grasp farther off the centre than this misses.
FINGER_REACH = 0.8
#: A vacuum cup seals when this fraction of its disc lies on the top face; under it, nothing is
#: held. Between this and a full seal, the grip's strength is the fraction covered.
SEAL = 0.6
#: A grip's nominal strength, as a multiple of what it holds weighs (when the state gives no
#: effector load limit): a sound grip never lets go in a kitting move.
GRIP_MARGIN = 10.0
#: How far (m) a held part is carried sideways before a weak grip may let go, and the range of
#: the seeded moment of letting go, as a fraction of that leg's duration.
WEAK_GRIP_AFTER = 0.05
WEAK_GRIP_MOMENT = (0.2, 0.8)
#: A seeded push: the speed (m/s) given to the object pushed, range drawn uniformly, sideways
#: in a seeded direction; the object then slides, tips or falls as physics has it.
PUSH_SPEED = (0.3, 0.8)
#: A kit tray bumped: its speed range (m/s), lower (it is heavier and carries its parts).
BUMP_SPEED = (0.15, 0.4)
#: MuJoCo's contacts are read every this many steps of a move (10 ms: a tool at 1 m/s moves
#: 1 cm), and a grip's force checked as often.
CONTACT_EVERY = 5
#: MuJoCo contacts that count as the robot touching something (m of penetration): as the
#: kinematic cell, touching within 1 mm is not contact.
CONTACT_DEPTH = 0.001


@dataclass(frozen=True)
class Weld:
    """A grip's weld constraint: time constant, damping ratio, rotational stiffness scale."""

    timeconst: float
    damping: float
    torquescale: float


GRIPPER = Weld(*GRIPPER_WELD)
VACUUM = Weld(*VACUUM_WELD)
