"""``kitkb sim serve``: the simulated workcell on loopback until SIGINT or SIGTERM."""

from __future__ import annotations

import signal
import sys
import time
from pathlib import Path
from types import FrameType
from typing import Callable

from kb.cli.output import Output
from kb.core.errors import InputError
from kb.core.files import write_atomic
from kb.crcl.wire import STATUS_PERIOD
from kb.model.faults import domain_fault_kinds
from kb.sim import CellServer, FaultSpec, SimulatedCell
from kb.sim.noise import SensorNoise
from kb.spatial.scene import Scene


class _Stop(Exception):
    """SIGINT or SIGTERM arrived."""


def serve(init: str, goal: str | None, faults: str | None, seed: int, noise: str | None,
          sensor_port: int, command_port: int, out: Output, sensor_noise: str | None = None,
          status_period: float = STATUS_PERIOD, domain: list[str] | None = None, engine: str = "kinematic") -> int:
    """Serve a :class:`SimulatedCell` of ``init`` (with the individuals only ``goal`` names)
    on 127.0.0.1, its command port a CRCL 1.x controller (a heartbeat status every
    ``status_period`` seconds on a quiet connection, 0: none); print one line with the bound
    ports; 0 when stopped by SIGINT or SIGTERM. ``domain``: extension files (``--domain``):
    their fault kinds may be injected, their classes of objects typed in ``init``. ``engine``:
    ``kinematic`` (:class:`SimulatedCell`) or ``mujoco`` (:class:`kb.physics.MujocoCell`)."""
    if not (status_period >= 0 and status_period != float("inf")):
        raise InputError(f"--status-period {status_period:g}: seconds, 0 or more")
    with out.progress(f"building the simulated cell of {Path(init).name}"):
        cell = _cell(init, goal, faults, seed, noise, sensor_noise, domain, engine)
    with CellServer(cell, sensor_port=sensor_port, command_port=command_port, status_period=status_period) as server:
        address = f"{server.host}:{server.sensor_port},{server.command_port}"
        line = (f"kitkb: serving {init}: sensor port {server.sensor_port}, command port {server.command_port} on "
                f"{server.host} (--cell {address})")
        facts = {"message": line[len("kitkb: "):], "init": init, "host": server.host,
                 "sensor_port": server.sensor_port, "command_port": server.command_port, "cell": address}
        _until_signal(lambda: out.emit(facts, indent=None) if out.is_json else print(line, file=out.results, flush=True))
    if not out.is_json:  # the JSON object is the ready line; stopping is the exit code 0
        out.done("cell server stopped")
    return 0


def _cell(init: str, goal: str | None, faults: str | None, seed: int, noise: str | None,
          sensor_noise: str | None = None, domain: list[str] | None = None, engine: str = "kinematic") -> SimulatedCell:
    if noise is not None:
        raise InputError(_replaced(noise))
    kinds = domain_fault_kinds(domain) if domain else None  # the extensions read (their classes known) first
    try:
        spec = FaultSpec.parse(faults or "", seed=seed, kinds=kinds)
    except ValueError as exc:
        raise InputError(f"--faults: {exc}") from None
    scene = Scene.from_files([init], [Path(goal)] if goal else ())
    try:
        base = SensorNoise.from_scene(scene)
    except ValueError as exc:
        raise InputError(str(exc), init) from None
    try:
        sensor = SensorNoise.parse(sensor_noise, base) if sensor_noise is not None else base
    except ValueError as exc:
        raise InputError(f"--sensor-noise: {exc}") from None
    kind = SimulatedCell
    if engine == "mujoco":
        from kb.physics import MujocoCell  # MuJoCo only for the physics engine
        kind = MujocoCell
    try:
        return kind(scene, faults=spec, noise=sensor or SensorNoise(), seed=seed,
                    declared=[Path(goal)] if goal else ())  # a partial state's objects placed by the cell
    except ValueError as exc:
        raise InputError(str(exc), init) from None


def export_mjcf(init: str, output: str, out: Output, goal: str | None = None) -> int:
    """Write the MJCF scene of ``init`` that the MuJoCo cell builds (:mod:`kb.physics.mjcf`) to
    ``output``, its objects placed by the cell where the state leaves them unlocated."""
    from kb.physics.mjcf import build, cylinders  # MuJoCo only for this command
    from kb.sim.cell import ground_truth
    from kb.sim.world import World
    declared = [Path(goal)] if goal else []
    with out.progress(f"building the MuJoCo scene of {Path(init).name}"):
        scene, _ = ground_truth(Scene.from_files([init], declared), 0, declared)
        try:
            mjcf = build(World.from_scene(scene), cylinders(scene), title=Path(init).stem)
        except ValueError as exc:
            raise InputError(str(exc), init) from None
        write_atomic(output, mjcf.xml)
    kinds = [b.kind for b in mjcf.bodies.values()]
    counts = {k: kinds.count(k) for k in ("free", "static", "mocap")}
    out.done(f"wrote {output}: {len(kinds)} bodies ({counts['free']} free, {counts['static']} fixed, "
             f"{counts['mocap']} mocap)", output=output, bodies=len(kinds), free=counts["free"],
             fixed=counts["static"], mocap=counts["mocap"])
    return 0


def _replaced(text: str) -> str:
    """Why ``--noise POS_SIGMA,ANGLE_SIGMA`` is refused, with its new spelling where it reads."""
    try:
        pos, angle = (float(s) for s in text.split(","))
        spelled = SensorNoise(position=pos, orientation=angle).text()
        hint = f" (--noise {text} is --sensor-noise {spelled if spelled != 'none' else 'position=0mm'})"
    except ValueError:
        hint = ""
    return ("--noise is replaced by --sensor-noise KEY=VALUE,... with units, e.g. position=1mm,orientation=0.5deg"
            + hint)


def _until_signal(ready: Callable[[], None]) -> None:
    """Call ``ready`` and sleep until SIGINT or SIGTERM (their previous handlers restored after)."""
    def stop(signum: int, frame: FrameType | None) -> None:
        raise _Stop(signum)
    previous = {s: signal.getsignal(s) for s in (signal.SIGINT, signal.SIGTERM)}
    try:
        for s in previous:
            signal.signal(s, stop)
        ready()
        while True:
            time.sleep(3600)
    except _Stop:
        pass
    finally:
        for s, handler in previous.items():
            signal.signal(s, handler)
        sys.stdout.flush()
