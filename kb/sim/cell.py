"""The simulated workcell: ground truth, a robot executing CRCL, a sensor, seeded faults."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any, Literal, Sequence


from kb.cells.registry import CellRequest, CellURL
from kb.core.errors import InputError
from kb.core.namespaces import KTW, local_name
from kb.crcl import Command, EndCanon
from kb.crcl.cell import Fate, Observation, Status
from kb.scenario.partial import Placement
from kb.sim.fates import fates
from kb.sim.faults import FaultSpec, Injected, Injector
from kb.sim.noise import SensorAccuracy, SensorNoise
from kb.sim.robot import VIOLATION_KINDS, Robot
from kb.sim.sensor import Sensor, observe
from kb.sim.hidden import place_unknown
from kb.sim.world import KIT_TRAY, SKU, World
from kb.spatial.scene import Scene, class_ancestors
from kb.spatial.unlocated import unlocated


@dataclass(frozen=True)
class Violation:
    """A constraint the robot broke (ground truth, like :class:`~kb.sim.faults.Injected`):
    ``kind`` (one of :data:`~kb.sim.robot.VIOLATION_KINDS`: overweight, work-volume,
    wrong-effector, contact), ``command`` the index of the command among all the cell executed
    (from 0), ``action`` the plan action announced by ``begin_action`` (None before any),
    ``objects`` (IRIs: overweight the object and the effector, work-volume the robot,
    wrong-effector the effector and the object, contact the moving object and the one it
    passed through) and ``detail``."""

    kind: str
    command: int
    action: int | None
    objects: tuple[str, ...]
    detail: str

    def as_dict(self) -> dict[str, Any]:
        """The violation as JSON data (objects by local name)."""
        return {"kind": self.kind, "command": self.command, "action": self.action,
                "objects": [local_name(o) for o in self.objects], "detail": self.detail}


class SimulatedCell:
    """A :class:`~kb.crcl.cell.CellInterface` on a simulated ground truth.

    ``init``: a state file (its scene is ``Scene.from_files([init], declared)``) or a scene;
    ``faults``: what goes wrong (:class:`FaultSpec`); ``noise``: the sensor's
    :class:`~kb.sim.noise.SensorNoise` (or a (position sigma in metres, orientation sigma in
    radians) pair); ``seed``: of the sensor noise generators (the faults have their own seed in
    their spec). ``sensor`` (:class:`~kb.sim.sensor.Sensor`) keeps what the sensor did wrong
    (``sensor.errors``: misdetections, misclassifications), ground truth like ``injected``.

    A state whose objects are not all located (:mod:`kb.spatial.unlocated`: no primary
    location, or a relative one) is completed by :func:`ground_truth`: the cell puts each such
    object, seeded, in a free spot of a container that suits it; ``hidden`` lists where
    (:class:`kb.scenario.partial.Placement`), ground truth like ``injected`` (empty when every
    object was located).

    ``violations`` lists the constraints the robot broke (:class:`Violation`: an overweight
    grasp, a move out of the work volume, a grasp with an effector the object's SKU does not
    list, a contact along a move; what the robot then does is in :mod:`kb.sim.robot`), as
    ``injected`` lists the faults: ground truth, for scoring, never for the executor.

    Besides faults, ``begin_action`` carries out the one plan action that moves nothing:
    ``create-kit(kit, kittray, worktable)`` makes the kit exist where its tray is (the tray then
    moves with the kit).
    """

    def __init__(self, init: str | Path | Scene, faults: FaultSpec | None = None,
                 noise: SensorNoise | tuple[float, float] = (0.0, 0.0), seed: int = 0,
                 declared: Sequence[str | Path] = ()) -> None:
        scene = init if isinstance(init, Scene) else Scene.from_files([init], declared)
        scene, self.hidden = ground_truth(scene, seed, declared)
        self.world = World.from_scene(scene)
        self.robot = Robot(self.world, on_violation=self._violated)
        self.violations: list[Violation] = []
        self.commands = 0  # commands executed so far
        try:
            self.sensor = Sensor(SensorNoise.of(noise), seed)
        except ValueError as exc:
            raise ValueError(f"sensor noise: {exc}") from None
        self.noise = (self.sensor.noise.position, self.sensor.noise.orientation)
        self.rng = self.sensor.rng  # the pose noise's generator
        self.injected: list[Injected] = []
        self.faults = Injector(faults or FaultSpec(), self.world, self.robot, self.injected.append)
        self.action: tuple[int, str, tuple[str, ...]] | None = None
        self._pending_kit: tuple[str, str] | None = None
        self.url: str | None = None  # the URL it was opened from (kb.cells), for messages

    @property
    def accuracy(self) -> SensorAccuracy:
        """The accuracy of its sensor: the noise it adds (what an executor should verify with)."""
        return self.sensor.noise

    @property
    def sensor_errors(self) -> list:
        """What its sensor got wrong (``sensor.errors``: misdetections, misclassifications):
        ground truth, like ``injected`` and ``violations``."""
        return self.sensor.errors

    @property
    def time(self) -> float:
        """Simulated seconds since the cell started."""
        return self.robot.time

    def execute(self, command: Command) -> Status:
        """Carry out one CRCL command (:mod:`kb.sim.robot`); the EndCanon of an action that starts
        a kit (create-kit) is when the kit comes into being at its tray."""
        self.commands += 1
        status = self.robot.execute(command)
        if isinstance(command, EndCanon) and self._pending_kit is not None:
            kit, tray = self._pending_kit
            self._pending_kit = None
            self._create_kit(kit, tray)
        return status

    def _violated(self, kind: str, objects: tuple[str, ...], detail: str) -> None:
        assert kind in VIOLATION_KINDS, kind
        action = self.action[0] if self.action is not None else None
        self.violations.append(Violation(kind, self.commands - 1, action, tuple(objects), detail))

    def sense(self, query: str, *, by: Literal["class", "name"] = "class") -> list[Observation]:
        """Placed objects of a class (local name or IRI) or of a name, with the cell's sensor noise."""
        return observe(self.world, query, by, self.time, sensor=self.sensor)

    def sense_names(self, names: Sequence[str]) -> list[Observation]:
        """The placed objects among ``names`` (IRIs), in the order asked: what one
        ``sense(name, by="name")`` per name gives (noise drawn in that order), looked up by name
        instead of matched against every object of the cell."""
        w = self.world
        chosen = [i for i in (w.index.get(n) for n in names) if i is not None and w.placed(i)]
        if not chosen:
            return []
        skus, kits = self._skus(), None
        names = w.names

        def sku_of(i: int) -> str | None:
            nonlocal kits
            if names[i] in skus:
                return skus[names[i]]
            if not w.is_a(i, "Kit"):
                return None
            kits = kits if kits is not None else self._kit_skus()
            return kits.get(names[i])
        return self.sensor.report(w, chosen, self.time, sku_of)

    def _skus(self) -> dict[str, str]:
        """Each object's SKU as :func:`kb.sim.sensor.observe` reports it (its least), kept while
        the world's SKU facts are the same set of the same size."""
        facts = self.world.facts.get(SKU, set())
        key = self._skus_key()
        if getattr(self, "_sku_key", None) != key:
            skus: dict[str, str] = {}
            for s, o in facts:
                if s not in skus or o < skus[s]:
                    skus[s] = o
            self._sku_key, self._sku_facts, self._sku_of = key, facts, skus
        return self._sku_of

    def _kit_skus(self) -> dict[str, str]:
        """A kit's SKU as :meth:`World.sku <kb.sim.world.World.sku>` gives it: its first kit
        tray's (kept like :meth:`_skus`)."""
        trays = self.world.facts.get(KIT_TRAY, set())
        key = (self._skus_key(), id(trays), len(trays))
        if getattr(self, "_kit_key", None) != key:
            skus, first = self._skus(), {}
            for kit, tray in sorted(trays):
                first.setdefault(kit, tray)
            self._kit_key, self._kit_facts = key, trays
            self._kit_of = {k: skus[t] for k, t in first.items() if t in skus}
        return self._kit_of

    def _skus_key(self) -> tuple[int, int]:
        facts = self.world.facts.get(SKU, set())
        return id(facts), len(facts)

    def inspect(self, name: str) -> bool:
        """Quality inspection: False for a defective part or one not in the cell; a pass is recorded."""
        i = self.world.index.get(name)
        if i is None or not self.world.placed(i) or name in self.world.defective:
            return False
        self.world.passed.add(name)
        return True

    def begin_action(self, index: int, action: str, args: tuple[str, ...]) -> None:
        """Plan action ``index`` starts: faults are chosen and applied or armed; a kit the action
        starts comes into being when its program ends (:meth:`_kit_started`)."""
        self.action = (index, action, tuple(args))
        self.sensor.action = index
        self._pending_kit = self._kit_started(tuple(args))
        self.faults.begin_action(index, action, tuple(args))

    def _kit_started(self, args: tuple[str, ...]) -> tuple[str, str] | None:
        """(kit, kit tray) when the action names a kit the cell does not have yet (an object of
        the goal only, which only a kit may be, or a kit not placed) and a placed kit tray: the
        kit is made on that tray when the action's program ends (kitkb's create-kit, or any
        domain action that starts a kit so; the cell reads no action by name)."""
        w = self.world
        kit = tray = None
        for a in args:
            i = w.index.get(a)
            if kit is None and (i is None or (w.is_a(i, "Kit") and not w.placed(i))):
                kit = a
            elif tray is None and i is not None and w.placed(i) and w.is_a(i, "KitTray"):
                tray = a
        return (kit, tray) if kit is not None and tray is not None else None

    def part_fates(self) -> list[Fate]:
        """Every part's and kit tray's fate now (:mod:`kb.sim.fates`): ground truth, for the
        oracle of what was buildable, never for the executor."""
        return fates(self.world, self.robot.index)

    def scene(self) -> Scene:
        """Ground truth now (simulation only: for tests and scoring, never for the executor)."""
        return self.world.to_scene()

    def create_kit(self, kit: str, tray: str) -> None:
        """Make ``kit`` exist where its kit ``tray`` is (what a create-kit action does)."""
        self._create_kit(kit, tray)

    def _create_kit(self, kit: str, tray: str) -> None:
        """The kit comes into being where its kit tray is; nothing happens when the tray is no
        placed kit tray, or the kit exists already or names another kind of object (a repeated
        create-kit once made the kit its own support: a cycle)."""
        w = self.world
        t = w.index.get(tray)
        if t is None or not w.placed(t) or not w.is_a(t, "KitTray") or w.kit_of_tray(t) is not None:
            return
        k = w.index.get(kit)
        if k is not None and (w.placed(k) or not w.is_a(k, "Kit") or k in w.subtree(t)):
            return
        if k is None:
            k = w.add(kit, class_ancestors().get(str(KTW.Kit), frozenset({str(KTW.Kit)})))
        w.poses[k] = w.poses[t]
        w.local_lo[k], w.local_hi[k], w.open_top[k] = w.local_lo[t], w.local_hi[t], w.open_top[t]
        w.parent[k], w.parent[t] = w.parent[t], k
        w.facts.setdefault(KIT_TRAY, set()).add((kit, tray))


def ground_truth(scene: Scene, seed: int = 0, declared: Sequence[str | Path] = (),
                 match_names: bool = False) -> tuple[Scene, list[Placement]]:
    """``scene`` as a simulator's ground truth: unchanged when every object of the state file
    it was read from is located (one look at its types), else that state with each unlocated
    object placed by :func:`kb.scenario.partial.place_unknown` with ``seed`` (``declared``:
    the files whose individuals the scene declares besides, the goal), and the placements."""
    source = scene.source
    if source is None or not unlocated(source):
        return scene, []
    return place_unknown(source, seed, declared, match_names)


def open_simulated(url: CellURL, request: CellRequest) -> SimulatedCell:
    """The ``sim:`` cell (:mod:`kb.cells.registry`): a :class:`SimulatedCell` holding
    ``request.scene``, with the faults, seed and sensor accuracy of the request or of the URL's
    ``faults=``, ``seed=`` and ``noise=`` (noise over the request's accuracy); a parameter and a
    different value of the request at once are refused, as is a request without a scene.

    ``world=FILE``: the cell holds the state of FILE instead (where the objects truly are: the
    same objects, placed otherwise or where the run's state does not say); objects of a state
    that are not located (the run's or FILE's) are placed by the cell, seeded
    (:func:`ground_truth`)."""
    spec, seed, accuracy = check_simulated(url, request)
    declared = [request.goal] if request.goal is not None else []
    scene = request.scene
    world = url.params.get("world")
    if world is not None:
        scene = Scene.from_files([world], declared, match_names=request.match_names)
    if scene is None:
        raise url.refuse("a simulated cell needs the initial state it holds (no scene was given)")
    try:
        scene, hidden = ground_truth(scene, seed, declared, request.match_names)
        cell = SimulatedCell(scene, faults=spec, seed=seed,
                             **({"noise": accuracy} if accuracy is not None else {}))
        cell.hidden = hidden
    except ValueError as exc:
        raise InputError(str(exc)) from None
    cell.url = url.text
    return cell


def check_simulated(url: CellURL, request: CellRequest) -> tuple[FaultSpec | None, int, SensorAccuracy | None]:
    """The faults, seed and accuracy a ``sim:`` cell of ``url`` and ``request`` would have
    (the scene not needed); an InputError naming what is wrong (``reason`` without the URL)."""
    url.only("faults", "seed", "noise", "world")
    world = url.params.get("world")
    if world is not None and not Path(world).is_file():
        raise url.refuse(f"world={world}: no such file")
    seed = url.number("seed", int)
    if seed is not None and request.seed not in (None, seed):
        raise url.refuse(f"seed={seed} and a seed of {request.seed} given besides")
    seed = seed if seed is not None else (request.seed or 0)
    faults = request.faults
    text = url.params.get("faults")
    if text is not None and faults not in (None, "", text):
        raise url.refuse(f"faults={text!r} and faults {faults!r} given besides")
    faults = text if text is not None else faults
    accuracy = request.accuracy
    try:
        spec = (FaultSpec.parse(faults, seed=seed, kinds=request.fault_kinds)
                if isinstance(faults, str) and faults.strip() else faults)
        if "noise" in url.params:
            accuracy = SensorAccuracy.parse(url.params["noise"], accuracy)
    except ValueError as exc:
        raise url.refuse(str(exc)) from None
    return (spec if spec else None), seed, accuracy


open_simulated.check = check_simulated  # type: ignore[attr-defined]
