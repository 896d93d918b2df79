"""``kitkb scenario generate``."""

from __future__ import annotations

from pathlib import Path

from kb.cli.output import Output
from kb.scenario import write_scenario


def generate(parts: int, kits: int, seed: int, output: str, out: Output) -> int:
    """Write a generated scenario's ``init.ttl`` and ``goal.ttl`` into ``output``."""
    init, goal = write_scenario(Path(output), parts=parts, kits=kits, seed=seed)
    out.done(f"wrote {init} and {goal} ({parts} parts, {kits} kit(s), seed {seed})")
    return 0
