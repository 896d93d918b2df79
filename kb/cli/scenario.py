"""``kitkb scenario generate`` and ``kitkb scenario transform``."""

from __future__ import annotations

from pathlib import Path

from kb.cli.output import Output
from kb.core.errors import InputError
from kb.core.namespaces import local_name
from kb.scenario import write_scenario
from kb.scenario.partial import write_partial
from kb.scenario.variants import write_variant


def generate(parts: int, kits: int, seed: int, output: str, out: Output, unit: str = "meter",
             unlocated: int = 0, mark_unlocated: bool = False) -> int:
    """Write a generated scenario's ``init.ttl`` and ``goal.ttl`` into ``output`` (``unlocated``:
    that many parts of the initial state without a location, :mod:`kb.scenario.partial`)."""
    if unlocated < 0 or unlocated > parts:
        raise InputError(f"--unlocated must be between 0 and --parts ({parts}), not {unlocated}")
    if mark_unlocated and not unlocated:
        raise InputError("--mark-unlocated needs --unlocated N")
    with out.progress(f"generating a scenario of {parts} parts, {kits} kit(s)"):
        init, goal = write_scenario(Path(output), parts=parts, kits=kits, seed=seed, progress=out.tracker)
        if unit != "meter":
            with out.progress(f"rewriting both files in {unit}", total=2, unit="files") as task:
                for path in (init, goal):
                    write_variant(path, path, unit=unit)
                    task.advance()
        taken = write_partial(init, count=unlocated, seed=seed, mark=mark_unlocated) if unlocated else []
    partial = f", {len(taken)} part(s) unlocated" if taken else ""
    out.done(f"wrote {init} and {goal} ({parts} parts, {kits} kit(s), seed {seed}, length unit {unit}{partial})",
             init=str(init), goal=str(goal), parts=parts, kits=kits, seed=seed, unit=unit,
             unlocated=[local_name(t) for t in taken])
    return 0


def transform(file: str, output: str, out: Output, unit: str | None = None, yaw: float = 0.0,
              turn: str | None = None, unlocate: str | None = None, mark_unlocated: bool = False) -> int:
    """Write ``file`` in another length unit and/or turned about z into ``output`` (``unlocate``:
    objects written without their location, :mod:`kb.scenario.partial`)."""
    objects = [o.strip() for o in turn.split(",") if o.strip()] if turn else None
    names = [o.strip() for o in unlocate.split(",") if o.strip()] if unlocate else []
    if mark_unlocated and not names:
        raise InputError("--mark-unlocated needs --unlocate OBJ,...")
    with out.progress(f"rewriting {Path(file).name}"):
        n = write_variant(file, output, unit=unit, yaw=yaw, objects=objects)
        taken = write_partial(output, names=names, mark=mark_unlocated) if names else []
    what = ([f"length unit {unit}"] if unit else []) + (
        [f"turned {yaw:g} deg" + (f" ({len(objects)} object(s) about their own z)" if objects else "")] if yaw else []) + (
        [f"{len(taken)} object(s) unlocated"] if taken else [])
    out.done(f"wrote {output} ({n} statements{': ' + ', '.join(what) if what else ''})", output=output,
             input=file, statements=n, unit=unit, yaw=yaw, turned=objects or [],
             unlocated=[local_name(t) for t in taken])
    return 0
