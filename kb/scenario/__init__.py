"""Kitting scenarios: generate and write initial and goal states of a kitting workstation.

A scenario is a workstation in two states, each a complete Turtle data file importing the
kitting model: ``init.ttl`` (parts in parts trays on a parts table, empty kit trays in a
large box, end effectors in their holders, robot empty) and ``goal.ttl`` (every kit finished:
kit tray with the design's parts at their PartRefAndPose, inside the large box with kits of
its design; end effectors back in their holders, robot empty).

Pipeline: :class:`~kb.scenario.spec.ScenarioSpec` (what) -> :func:`layout`
(:mod:`kb.scenario.layout`: geometry and names) -> blocks (:mod:`kb.scenario.blocks`) ->
Turtle statements (:mod:`kb.scenario.turtle`, written by :mod:`kb.io.turtle`).

Public API: :func:`build_scenario`, :func:`write_scenario`, :func:`write_spec`,
:func:`write_shipped`, :func:`layout`, :func:`state_graph`, :class:`Scenario`.
"""

from __future__ import annotations

import shutil
from pathlib import Path

from kb.core import limits
from kb.core.errors import InputError
from kb.core.files import atomic_paths
from kb.core.jobs import Forked
from kb.core.progress import SILENT, Progress
from kb.core.resources import ontologies_dir
from kb.scenario.blocks import STATES, state_blocks, state_graph
from kb.scenario.layout import Scenario, layout
from kb.scenario.spec import SHIPPED, ScenarioSpec, random_spec
from kb.scenario.turtle import header, write_turtle

def build_scenario(parts: int, kits: int, seed: int) -> Scenario:
    """A generated scenario of ``parts`` parts in ``kits`` kits; deterministic for ``seed``.
    More parts than :data:`kb.core.limits.PARTS` is an InputError before anything is built."""
    for what, value in (("parts", parts), ("kits", kits)):
        if not isinstance(value, int) or isinstance(value, bool) or value < 1:
            raise InputError(f"--{what} must be a whole number of at least 1 (got {value!r})")
    limits.PARTS.check(parts, what=f"--parts {parts:,}")
    if kits > parts:
        raise InputError(f"--kits ({kits}) cannot exceed --parts ({parts}): every kit needs a part")
    return layout(random_spec(parts, kits, seed))


def write_spec(spec: ScenarioSpec | Scenario, out_dir: Path) -> tuple[Path, Path]:
    """Write ``init.ttl`` and ``goal.ttl`` of a spec (or laid-out scenario) into ``out_dir``
    (both files, or neither: they are renamed into place together)."""
    sc = spec if isinstance(spec, Scenario) else layout(spec)
    out_dir = Path(out_dir)
    if out_dir.exists() and not out_dir.is_dir():
        raise InputError("output path exists and is not a folder", file=out_dir)
    targets = [out_dir / f"{state}.ttl" for state in STATES]
    with atomic_paths(targets) as temps:
        _write_states(sc, temps)
    return targets[0], targets[1]


PARALLEL_FROM_PARTS = 5000  # write the two states in two processes from this many parts on


def _write_state(sc: Scenario, state: str, path: Path) -> None:
    with open(path, "w", encoding="utf-8", newline="\n") as out:
        write_turtle(out, header(sc.namespace, sc.ontology_iri(state), _comment(sc, state)),
                     state_blocks(sc, state))


def _write_states(sc: Scenario, paths: list[Path]) -> None:
    """Write init and goal; a large scenario writes its goal in a forked child meanwhile
    (should the child fail, this process writes the goal itself)."""
    init, goal = paths
    n_parts = sum(len(t.parts) for t in sc.trays)
    job = Forked(lambda: _write_state(sc, "goal", goal)) if n_parts >= PARALLEL_FROM_PARTS else None
    _write_state(sc, "init", init)
    if job is None or not job.result()[0]:
        _write_state(sc, "goal", goal)


def write_scenario(out_dir: Path, *, parts: int, kits: int, seed: int,
                   progress: Progress = SILENT) -> tuple[Path, Path]:
    """Generate a scenario (see :func:`build_scenario`) and write it into ``out_dir``
    (``progress``: where its two steps report, :mod:`kb.core.progress`). A folder on a disk
    without room for the files (:data:`kb.core.limits.DISK_BYTES_PER_PART` a part) is an
    InputError before anything is built."""
    limits.PARTS.check(parts, what=f"--parts {parts:,}")
    _check_room(Path(out_dir), parts)
    with progress.task(f"laying out a workstation of {parts} parts"):
        sc = build_scenario(parts, kits, seed)
    with progress.task(f"writing {Path(out_dir) / 'init.ttl'} and goal.ttl"):
        return write_spec(sc, out_dir)


def _check_room(out_dir: Path, parts: int) -> None:
    """Refuse to start writing files the disk under ``out_dir`` has no room for."""
    folder = out_dir
    while not folder.exists() and folder != folder.parent:
        folder = folder.parent
    try:
        free = shutil.disk_usage(folder).free
    except OSError:
        return
    needed = parts * limits.DISK_BYTES_PER_PART
    if needed > free:
        raise InputError(f"--parts {parts:,} needs about {limits.FILE_BYTES.show(needed)} on disk, "
                         f"{limits.FILE_BYTES.show(free)} free", file=out_dir)


def write_shipped(root: Path | None = None) -> list[Path]:
    """(Re)write the shipped scenarios from :data:`kb.scenario.spec.SHIPPED` under ``root``."""
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


__all__ = ["Scenario", "build_scenario", "layout", "state_graph", "write_scenario", "write_shipped", "write_spec"]
