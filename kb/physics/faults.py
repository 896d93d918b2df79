"""Faults caused in the MuJoCo cell: the domain's fault kinds, each mechanism carried out by physics.

The kinds are the domain's ``soap:FaultKind`` data, as in the kinematic cell (the same names,
``--faults``, seeds and draws: :class:`kb.sim.faults.FaultSpec`); what differs is how a
mechanism happens. Where the kinematic cell places the object where the fault says, here the
fault is a cause and MuJoCo decides the outcome:

=================  ==============================================================================
mechanism          in the MuJoCo cell
=================  ==============================================================================
GraspNothing       the gripper closes on nothing (an actuator fault; the part stays where it is)
ReleaseInTransit   a weak grip: it lets go at a seeded moment of the first leg carrying the part
                   sideways (:mod:`kb.physics.robot`); the part falls, bounces and rests where it does
DisplaceObject     a seeded push: the object gets a seeded speed (:data:`~kb.physics.params.PUSH_SPEED`)
                   in a seeded direction, half the time with a flick upwards; it slides, tips, hops out
                   of its tray or off the table as physics has it
ShiftInPlane       a seeded bump: the object (a kit's tray) gets a sideways speed
                   (:data:`~kb.physics.params.BUMP_SPEED`) and slides with what lies in it
RemoveObject       as the kinematic cell (taken out of the cell: its body leaves the scene)
MarkDefective      as the kinematic cell (only inspection shows it)
SwapSku            as the kinematic cell (its SKU and shape change; its geom is resized)
=================  ==============================================================================

Every fault that took effect is an :class:`kb.sim.faults.Injected`, its detail saying where the
object came to rest (from MuJoCo, after everything is at rest), not where a fault meant it to go.
"""

from __future__ import annotations

from typing import Callable

import numpy as np

from kb.core.namespaces import SOAP
from kb.model.faults import FaultKind, Strike
from kb.physics import params as P
from kb.physics.engine import Physics
from kb.physics.robot import PhysicsRobot
from kb.sim.faults import MECHANISMS, FaultSpec, Injected, Injector, _kinds, _local
from kb.sim.world import World


class PhysicsInjector(Injector):
    """:class:`kb.sim.faults.Injector` whose object mechanisms act through MuJoCo."""

    def __init__(self, spec: FaultSpec, world: World, robot: PhysicsRobot, physics: Physics,
                 record: Callable[[Injected], None]) -> None:
        super().__init__(spec, world, robot, record)
        self.physics = physics
        self.probot = robot

    def begin_action(self, index: int, action: str, args: tuple[str, ...]) -> None:
        """Choose and apply (or arm) the faults of action ``index`` (the draws of the kinematic
        cell's :meth:`~kb.sim.faults.Injector.begin_action`, each carried out by physics)."""
        self.robot.miss_grasp = False
        self.armed.pop("miss_grasp", None)
        if not self.active:
            return
        self.pending.extend(_kinds(self.spec.at.get(index, ())))
        eligible = self.catalog.eligible(action)
        names = {k.name for k in eligible}
        chosen = [k for k in self.pending if k in names]
        self.pending = [k for k in self.pending if k not in names]
        drawn = self._draw(eligible)
        if drawn is not None and drawn not in chosen:
            chosen.append(drawn)
        for name in sorted(chosen, key=self.catalog.order):
            kind = self.catalog.check(name)
            PHYSICAL.get(kind.mechanism.iri, MECHANISMS[kind.mechanism.iri])(  # type: ignore[operator]
                self, kind, kind.strike(action), index, args)

    def push(self, kind: FaultKind, strike: Strike, index: int, args: tuple[str, ...]) -> None:
        """DisplaceObject by a push: a seeded speed and direction, sometimes a flick upwards."""
        self._shove(kind, strike, index, args, P.PUSH_SPEED, flick=True)

    def bump(self, kind: FaultKind, strike: Strike, index: int, args: tuple[str, ...]) -> None:
        """ShiftInPlane by a bump: a seeded sideways speed; what lies in it goes along or lags."""
        self._shove(kind, strike, index, args, P.BUMP_SPEED, flick=False)

    def _shove(self, kind: FaultKind, strike: Strike, index: int, args: tuple[str, ...],
               speeds: tuple[float, float], flick: bool) -> None:
        i = self._target(strike, args)
        if i is None:
            return
        body = self.probot._body(i)
        if body is None:
            return
        w = self.world
        before = w.poses[body][:3, 3].copy()
        speed = float(self.rng.uniform(*speeds))
        angle = float(self.rng.uniform(0, 2 * np.pi))
        up = float(self.rng.uniform(1.0, 1.5)) if flick and self.rng.random() < 0.5 else 0.0
        self.physics.kick(body, np.array([speed * np.cos(angle), speed * np.sin(angle), up]))
        self.probot._rest()
        after = w.poses[body][:3, 3]
        sup = int(w.parent[body])
        if sup >= 0 and w.stand_in(sup):  # a kit's tray: where the kit rests
            sup = int(w.parent[sup])
        where = _local(w.names[sup]) if sup >= 0 else "the floor"
        moved = float(np.linalg.norm(after[:2] - before[:2]))
        how = "flicked" if up else "pushed"
        related = tuple(o for prop in kind.also_names for o in w.objects(prop, w.names[i]))
        self.record(Injected(kind.name, index, (w.names[i],) + related,
                             f"{how} at {speed:.2f} m/s towards {np.degrees(angle):.0f} deg; came to rest "
                             f"{moved * 1000:.0f} mm away at {_xyz(after)} on {where}"))

    def take_out(self, kind: FaultKind, strike: Strike, index: int, args: tuple[str, ...]) -> None:
        """RemoveObject: as the kinematic cell, and its bodies leave the MuJoCo scene."""
        i = self._target(strike, args)
        if i is None:
            return
        tree = self.world.subtree(i)
        Injector.remove_object(self, kind, strike, index, args)
        for j in tree:
            self.physics.remove(j)

    def swap(self, kind: FaultKind, strike: Strike, index: int, args: tuple[str, ...]) -> None:
        """SwapSku: as the kinematic cell, its geom resized to the new SKU's shape."""
        i = self._target(strike, args)
        if i is None:
            return
        Injector.swap_sku(self, kind, strike, index, args)
        self.physics.resize(i, self.world.local_lo[i], self.world.local_hi[i])
        self.probot._rest()


def _xyz(p: np.ndarray) -> str:
    return "(" + ", ".join(f"{float(v):.3f}" for v in p) + ")"


#: the mechanisms the MuJoCo cell carries out its own way (the others: kb.sim.faults.MECHANISMS)
PHYSICAL: dict[str, Callable[..., None]] = {
    str(SOAP) + "DisplaceObject": PhysicsInjector.push,
    str(SOAP) + "ShiftInPlane": PhysicsInjector.bump,
    str(SOAP) + "RemoveObject": PhysicsInjector.take_out,
    str(SOAP) + "SwapSku": PhysicsInjector.swap,
}
