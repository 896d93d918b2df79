"""The simulated workcell: ground truth, a robot executing CRCL, a sensor, seeded faults."""

from __future__ import annotations

from pathlib import Path
from typing import Literal, Sequence

import numpy as np

from kb.core.namespaces import KTW
from kb.crcl import Command, EndCanon
from kb.crcl.cell import Observation, Status
from kb.sim.faults import FaultSpec, Injected, Injector
from kb.sim.robot import Robot
from kb.sim.sensor import observe
from kb.sim.world import KIT_TRAY, World
from kb.spatial.scene import Scene, class_ancestors


class SimulatedCell:
    """A :class:`~kb.crcl.cell.CellInterface` on a simulated ground truth.

    ``init``: a state file (its scene is ``Scene.from_files([init], declared)``) or a scene;
    ``faults``: what goes wrong (:class:`FaultSpec`); ``noise``: (position sigma in metres,
    orientation sigma in radians) of the sensor; ``seed``: of the sensor noise generator (the
    faults have their own seed in their spec).

    Besides faults, ``begin_action`` carries out the one plan action that moves nothing:
    ``create-kit(kit, kittray, worktable)`` makes the kit exist where its tray is (the tray then
    moves with the kit).
    """

    def __init__(self, init: str | Path | Scene, faults: FaultSpec | None = None,
                 noise: tuple[float, float] = (0.0, 0.0), seed: int = 0,
                 declared: Sequence[str | Path] = ()) -> None:
        scene = init if isinstance(init, Scene) else Scene.from_files([init], declared)
        self.world = World.from_scene(scene)
        self.robot = Robot(self.world)
        self.noise = (float(noise[0]), float(noise[1]))
        if min(self.noise) < 0:
            raise ValueError(f"noise sigmas must be >= 0, not {noise}")
        self.rng = np.random.default_rng(seed)
        self.injected: list[Injected] = []
        self.faults = Injector(faults or FaultSpec(), self.world, self.robot, self.injected.append)
        self.action: tuple[int, str, tuple[str, ...]] | None = None
        self._pending_kit: tuple[str, str] | None = None

    @property
    def time(self) -> float:
        """Simulated seconds since the cell started."""
        return self.robot.time

    def execute(self, command: Command) -> Status:
        """Carry out one CRCL command (:mod:`kb.sim.robot`); the EndCanon of a create-kit action
        is when the kit comes into being at its tray."""
        status = self.robot.execute(command)
        if isinstance(command, EndCanon) and self._pending_kit is not None:
            kit, tray = self._pending_kit
            self._pending_kit = None
            self._create_kit(kit, tray)
        return status

    def sense(self, query: str, *, by: Literal["class", "name"] = "class") -> list[Observation]:
        """Placed objects of a class (local name or IRI) or of a name, with the cell's sensor noise."""
        return observe(self.world, query, by, self.time, self.noise, self.rng)

    def inspect(self, name: str) -> bool:
        """Quality inspection: False for a defective part or one not in the cell; a pass is recorded."""
        i = self.world.index.get(name)
        if i is None or not self.world.placed(i) or name in self.world.defective:
            return False
        self.world.passed.add(name)
        return True

    def begin_action(self, index: int, action: str, args: tuple[str, ...]) -> None:
        """Plan action ``index`` starts: faults are chosen and applied or armed; create-kit is done."""
        self.action = (index, action, tuple(args))
        self._pending_kit = (args[0], args[1]) if action == "create-kit" and len(args) >= 2 else None
        self.faults.begin_action(index, action, tuple(args))

    def scene(self) -> Scene:
        """Ground truth now (simulation only: for tests and scoring, never for the executor)."""
        return self.world.to_scene()

    def _create_kit(self, kit: str, tray: str) -> None:
        w = self.world
        t = w.index.get(tray)
        if t is None or not w.placed(t):
            return
        k = w.index.get(kit)
        if k is None:
            k = w.add(kit, class_ancestors().get(str(KTW.Kit), frozenset({str(KTW.Kit)})))
        w.poses[k] = w.poses[t]
        w.local_lo[k], w.local_hi[k], w.open_top[k] = w.local_lo[t], w.local_hi[t], w.open_top[t]
        w.parent[k], w.parent[t] = w.parent[t], k
        w.facts.setdefault(KIT_TRAY, set()).add((kit, tray))
