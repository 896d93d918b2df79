"""The MuJoCo cell: kitkb's cell interface on a physics-based world (``--cell mujoco:``).

:class:`MujocoCell` is a :class:`kb.sim.SimulatedCell` (the same ground-truth bookkeeping, sensor,
inspection, kits made by create-kit, fault draws, part fates and cell server) whose robot is a
:class:`~kb.physics.robot.PhysicsRobot` and whose faults are carried out by physics
(:mod:`kb.physics.faults`): after every command the free bodies' poses are MuJoCo's, so the
sensor (USARTruth-style, with kitkb's noise model on top) reads where MuJoCo has them, and the
ground truth (``injected``, ``violations``, ``part_fates``) is where things came to rest and
what MuJoCo's contacts say touched what.

Ground truth beside the kinematic cell's: ``violations`` has the robot's overweight,
work-volume and wrong-effector violations and the contacts MuJoCo found (kind ``contact``);
``swept_contacts`` keeps the kinematic robot's swept-box contacts on the same moves, for
comparison; ``let_go`` the grips that let go on their own (force over strength); ``physics``
the engine (``physics.time``: simulated seconds, ``physics.wall``: seconds spent stepping).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, Sequence

import numpy as np

from kb.cells.registry import CellRequest, CellURL
from kb.core.errors import InputError
from kb.physics import params as P
from kb.physics.engine import Physics
from kb.physics.faults import PhysicsInjector
from kb.physics.mjcf import cylinders
from kb.physics.robot import PhysicsRobot
from kb.sim.cell import SimulatedCell, Violation, check_simulated, ground_truth
from kb.sim.faults import FaultSpec
from kb.sim.noise import SensorAccuracy
from kb.spatial.scene import Scene


class MujocoCell(SimulatedCell):
    """A :class:`~kb.sim.SimulatedCell` whose world is stepped by MuJoCo (arguments as its)."""

    capabilities = frozenset({"move", "sense", "sense-names", "inspect", "begin-action", "ground-truth",
                              "part-fates"})

    def __init__(self, init: str | Path | Scene, faults: FaultSpec | None = None,
                 noise: SensorAccuracy | tuple[float, float] = (0.0, 0.0), seed: int = 0,
                 declared: Sequence[str | Path] = ()) -> None:
        scene = init if isinstance(init, Scene) else Scene.from_files([init], declared)
        super().__init__(scene, faults=None, noise=noise, seed=seed, declared=declared)
        self.swept_contacts: list[Violation] = []
        self.physics = Physics(self.world, cylinders(scene))
        spec = faults or FaultSpec()
        self.robot = PhysicsRobot(self.world, self.physics, np.random.default_rng([spec.seed, 30]),
                                  on_violation=self._violated, on_contact=self._contact)
        self.faults = PhysicsInjector(spec, self.world, self.robot, self.physics, self.injected.append)
        self.physics.settle(P.INITIAL_SETTLE)
        self.robot._sync(moved_only=True, skip=set())
        self.physics_start = self.physics.time

    @property
    def let_go(self) -> list[tuple[str, str]]:
        """(object, why) of each grip that let go on its own (its force over its strength)."""
        return self.robot.let_go

    def _violated(self, kind: str, objects: tuple[str, ...], detail: str) -> None:
        """The kinematic robot's violations; its swept-box contacts are kept apart (MuJoCo's
        contacts are this cell's)."""
        if kind == "contact":
            action = self.action[0] if self.action is not None else None
            self.swept_contacts.append(Violation(kind, self.commands - 1, action, tuple(objects), detail))
            return
        super()._violated(kind, objects, detail)

    def _contact(self, objects: tuple[str, ...], detail: str) -> None:
        super()._violated("contact", objects, detail)

    def _create_kit(self, kit: str, tray: str) -> None:
        super()._create_kit(kit, tray)

    def physics_figures(self) -> dict[str, Any]:
        """Simulated seconds, steps and the wall seconds spent stepping MuJoCo."""
        ph = self.physics
        return {"simulated_s": ph.time, "steps": ph.steps, "stepping_wall_s": ph.wall,
                "swept_contacts": len(self.swept_contacts),
                "mujoco_contacts": sum(1 for v in self.violations if v.kind == "contact")}


def open_mujoco(url: CellURL, request: CellRequest) -> MujocoCell:
    """The ``mujoco:`` cell (:mod:`kb.cells.registry`): a :class:`MujocoCell` of
    ``request.scene``, with the parameters of ``sim:`` (``faults=``, ``seed=``, ``noise=``,
    ``world=``)."""
    spec, seed, accuracy = check_mujoco(url, request)
    declared = [request.goal] if request.goal is not None else []
    scene = request.scene
    world = url.params.get("world")
    if world is not None:
        scene = Scene.from_files([world], declared, match_names=request.match_names)
    if scene is None:
        raise url.refuse("a MuJoCo cell needs the initial state it holds (no scene was given)")
    try:
        scene, hidden = ground_truth(scene, seed, declared, request.match_names)
        cell = MujocoCell(scene, faults=spec, seed=seed, **({"noise": accuracy} if accuracy is not None else {}))
        cell.hidden = hidden
    except ValueError as exc:
        raise InputError(str(exc)) from None
    cell.url = url.text
    return cell


def check_mujoco(url: CellURL, request: CellRequest) -> tuple[FaultSpec | None, int, SensorAccuracy | None]:
    """What :func:`open_mujoco` would open, checked without building anything (``sim:``'s rules)."""
    return check_simulated(url, request)


open_mujoco.check = check_mujoco  # type: ignore[attr-defined]
