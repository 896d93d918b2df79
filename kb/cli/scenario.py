"""``kitkb scenario generate`` and ``kitkb scenario transform``."""

from __future__ import annotations

from pathlib import Path

from kb.cli.output import Output
from kb.scenario import write_scenario
from kb.scenario.variants import write_variant


def generate(parts: int, kits: int, seed: int, output: str, out: Output, unit: str = "meter") -> int:
    """Write a generated scenario's ``init.ttl`` and ``goal.ttl`` into ``output``."""
    with out.progress(f"generating a scenario of {parts} parts, {kits} kit(s)"):
        init, goal = write_scenario(Path(output), parts=parts, kits=kits, seed=seed, progress=out.tracker)
        if unit != "meter":
            with out.progress(f"rewriting both files in {unit}", total=2, unit="files") as task:
                for path in (init, goal):
                    write_variant(path, path, unit=unit)
                    task.advance()
    out.done(f"wrote {init} and {goal} ({parts} parts, {kits} kit(s), seed {seed}, length unit {unit})",
             init=str(init), goal=str(goal), parts=parts, kits=kits, seed=seed, unit=unit)
    return 0


def transform(file: str, output: str, out: Output, unit: str | None = None, yaw: float = 0.0,
              turn: str | None = None) -> int:
    """Write ``file`` in another length unit and/or turned about z into ``output``."""
    objects = [o.strip() for o in turn.split(",") if o.strip()] if turn else None
    with out.progress(f"rewriting {Path(file).name}"):
        n = write_variant(file, output, unit=unit, yaw=yaw, objects=objects)
    what = ([f"length unit {unit}"] if unit else []) + (
        [f"turned {yaw:g} deg" + (f" ({len(objects)} object(s) about their own z)" if objects else "")] if yaw else [])
    out.done(f"wrote {output} ({n} statements{': ' + ', '.join(what) if what else ''})", output=output,
             input=file, statements=n, unit=unit, yaw=yaw, turned=objects or [])
    return 0
