"""``kitkb scenario generate`` and ``kitkb scenario transform``."""

from __future__ import annotations

from pathlib import Path

from kb.cli.output import Output
from kb.scenario import write_scenario
from kb.scenario.variants import write_variant


def generate(parts: int, kits: int, seed: int, output: str, out: Output, unit: str = "meter") -> int:
    """Write a generated scenario's ``init.ttl`` and ``goal.ttl`` into ``output``."""
    init, goal = write_scenario(Path(output), parts=parts, kits=kits, seed=seed)
    if unit != "meter":
        for path in (init, goal):
            write_variant(path, path, unit=unit)
    out.done(f"wrote {init} and {goal} ({parts} parts, {kits} kit(s), seed {seed}, length unit {unit})")
    return 0


def transform(file: str, output: str, out: Output, unit: str | None = None, yaw: float = 0.0,
              turn: str | None = None) -> int:
    """Write ``file`` in another length unit and/or turned about z into ``output``."""
    objects = [o.strip() for o in turn.split(",") if o.strip()] if turn else None
    n = write_variant(file, output, unit=unit, yaw=yaw, objects=objects)
    what = ([f"length unit {unit}"] if unit else []) + (
        [f"turned {yaw:g} deg" + (f" ({len(objects)} object(s) about their own z)" if objects else "")] if yaw else [])
    out.done(f"wrote {output} ({n} statements{': ' + ', '.join(what) if what else ''})")
    return 0
