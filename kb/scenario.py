"""Kitting scenarios: generate and write initial and goal states of a kitting workstation.

A scenario is a workstation in two states, each a complete Turtle data file importing the
kitting model: ``init.ttl`` (parts in parts trays on a parts table, empty kit trays in a
large box, end effectors in their holders, robot empty) and ``goal.ttl`` (every kit finished:
kit tray with the design's parts at their PartRefAndPose, inside the large box with kits of
its design; end effectors back in their holders, robot empty).

Pipeline: :class:`~kb.scenario_spec.ScenarioSpec` (what) -> :func:`layout`
(:mod:`kb.scenario_layout`: geometry and names) -> blocks (:mod:`kb.scenario_blocks`) ->
streaming Turtle (:mod:`kb.scenario_turtle`).

Public API: :func:`build_scenario`, :func:`write_scenario`, :func:`write_spec`,
:func:`write_shipped`, :func:`layout`, :class:`Scenario`.
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

from kb.errors import InputError
from kb.scenario_layout import Scenario, layout
from kb.scenario_spec import SHIPPED, ScenarioSpec, random_spec
from kb.scenario_turtle import header, write_turtle

def build_scenario(parts: int, kits: int, seed: int) -> Scenario:
    """A generated scenario of ``parts`` parts in ``kits`` kits; deterministic for ``seed``."""
    for what, value in (("parts", parts), ("kits", kits)):
        if not isinstance(value, int) or isinstance(value, bool) or value < 1:
            raise InputError(f"--{what} must be a whole number of at least 1 (got {value!r})")
    if kits > parts:
        raise InputError(f"--kits ({kits}) cannot exceed --parts ({parts}): every kit needs a part")
    return layout(random_spec(parts, kits, seed))


def write_spec(spec: ScenarioSpec | Scenario, out_dir: Path) -> tuple[Path, Path]:
    """Write ``init.ttl`` and ``goal.ttl`` of a spec (or laid-out scenario) into ``out_dir``."""
    sc = spec if isinstance(spec, Scenario) else layout(spec)
    out_dir = Path(out_dir)
    if out_dir.exists() and not out_dir.is_dir():
        raise InputError("output path exists and is not a folder", file=out_dir)
    try:
        out_dir.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(f"cannot create output folder: {exc.strerror}", file=out_dir) from None
    temps: list[tuple[str, Path]] = []
    try:
        for state in ("init", "goal"):
            fd, tmp = tempfile.mkstemp(prefix=f".{state}.", suffix=".tmp", dir=out_dir)
            os.close(fd)
            temps.append((tmp, out_dir / f"{state}.ttl"))
        _write_states(sc, [tmp for tmp, _ in temps])
        for tmp, final in temps:
            os.chmod(tmp, 0o644)
            os.replace(tmp, final)
    except OSError as exc:
        raise InputError(f"cannot write scenario: {exc.strerror or exc}", file=out_dir) from None
    finally:
        for tmp, _ in temps:
            if os.path.exists(tmp):
                os.unlink(tmp)
    return out_dir / "init.ttl", out_dir / "goal.ttl"


PARALLEL_FROM_PARTS = 5000  # write the two states in two processes from this many parts on


def _write_state(sc: Scenario, state: str, path: str) -> None:
    with open(path, "w", encoding="utf-8", newline="\n") as out:
        write_turtle(out, header(sc.namespace, sc.ontology_iri(state), _comment(sc, state)), sc.blocks(state))


def _write_states(sc: Scenario, paths: list[str]) -> None:
    """Write init and goal; large scenarios write the goal in a forked child meanwhile."""
    n_parts = sum(len(t.parts) for t in sc.trays)
    if n_parts < PARALLEL_FROM_PARTS or not hasattr(os, "fork"):
        _write_state(sc, "init", paths[0])
        _write_state(sc, "goal", paths[1])
        return
    pid = os.fork()
    if pid == 0:  # pragma: no cover - runs in the child
        code = 1
        try:
            _write_state(sc, "goal", paths[1])
            code = 0
        finally:
            os._exit(code)
    try:
        _write_state(sc, "init", paths[0])
    finally:
        _, status = os.waitpid(pid, 0)
    if status != 0:
        raise OSError(f"writing the goal state failed (status {status})")


def write_scenario(out_dir: Path, *, parts: int, kits: int, seed: int) -> tuple[Path, Path]:
    """Generate a scenario (see :func:`build_scenario`) and write it into ``out_dir``."""
    return write_spec(build_scenario(parts, kits, seed), out_dir)


def write_shipped(root: Path | None = None) -> list[Path]:
    """(Re)write the shipped scenarios from :data:`kb.scenario_spec.SHIPPED` under ``root``."""
    from kb.resources import ontologies_dir

    root = Path(root) if root is not None else ontologies_dir() / "scenarios"
    written = []
    for name, spec in SHIPPED.items():
        written.extend(write_spec(spec, root / name))
    return written


def _comment(sc: Scenario, state: str) -> str:
    what = "initial state" if state == "init" else "goal state"
    n_parts = sum(len(k.slots) for k in sc.kits)
    return (
        f"kitkb scenario {sc.name}: {what}.\n"
        f"{sc.spec.description}\n"
        f"{len(sc.kits)} kit(s), {n_parts} kit parts, {len(sc.spec.designs)} design(s), "
        f"{len(sc.trays)} parts tray(s). Lengths in meters, weights in kilograms.\n"
        "Written by kb.scenario (kitkb scenario generate / kb.scenario.write_shipped); do not edit by hand."
    )


__all__ = ["Scenario", "build_scenario", "layout", "write_scenario", "write_shipped", "write_spec"]
