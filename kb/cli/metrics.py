"""``kitkb metrics PROGRAM``: the static metrics of a CRCL program (kb.metrics)."""

from __future__ import annotations

import math
from typing import TextIO

from kb.cli.output import Output
from kb.core.errors import InputError
from kb.metrics import (METRICS, NAMES, UNITS, Robot, Score, StaticMetrics, program_metrics, read_weights,
                        score)
from kb.metrics.motion import DEFAULT_MAX_ACCELERATION, DEFAULT_MAX_SPEED


def metrics(program: str, format: str, per_command: bool, max_speed: float | None,
            max_acceleration: float | None, config: str | None, out: Output) -> int:
    """Print the static metrics of ``program`` (text: a table, with ``per_command`` a row per
    command first; json: one object with ``metrics``, ``score`` and ``rows``)."""
    for option, value in (("--max-speed", max_speed), ("--max-acceleration", max_acceleration)):
        if value is not None and not (math.isfinite(value) and value > 0):
            raise InputError(f"{option} must be a positive number, not {value:g}")
    weights = read_weights(config) if config else None
    robot = Robot(max_speed=DEFAULT_MAX_SPEED if max_speed is None else max_speed,
                  max_acceleration=DEFAULT_MAX_ACCELERATION if max_acceleration is None else max_acceleration)
    with out.progress(f"evaluating {program}"):
        result = program_metrics(program, robot, rows=per_command)
    total = score(result.totals, weights)
    if out.is_json:
        # rows: on one line (the C encoder; an indented 100,000-row object takes seconds)
        out.emit({**result.as_dict(), "score": total.as_dict(), "config": config},
                 indent=None if per_command else 1)
        return 0
    if per_command:
        _rows(result, out.results)
    _summary(result, total, out.results)
    return 0


def _number(metric: str, value: float) -> str:
    return f"{value:.3f}" if metric in UNITS else f"{int(value)}"


def _rows(result: StaticMetrics, stream: TextIO) -> None:
    width = max([len(r.command) for r in result.rows or []] + [7])
    width = min(width, 48)
    print(f"{'line':>5}  {'command':<{width}}  " + "  ".join(f"{m:>8}" for m in METRICS) + "  notes",
          file=stream)
    for row in result.rows or []:
        command = row.command if len(row.command) <= width else row.command[:width - 3] + "..."
        line = "" if row.line is None else str(row.line)
        cells = "  ".join(f"{_number(m, v):>8}" for m, v in zip(METRICS, row.values))
        print(f"{line:>5}  {command:<{width}}  {cells}  {'; '.join(row.notes)}".rstrip(), file=stream)
    print(file=stream)


def _summary(result: StaticMetrics, total: Score, stream: TextIO) -> None:
    robot = result.robot
    print(f"{result.source}: {result.commands} commands; robot: max speed {robot.max_speed:g} m/s, "
          f"max acceleration {robot.max_acceleration:g} m/s²", file=stream)
    for m in METRICS:
        unit = f" {UNITS[m]}" if m in UNITS else ""
        weight = total.weights[m]
        part = f"  x {weight:g} = {total.contributions[m] + 0.0:.3f}" if weight else ""
        print(f"{m:<4} {NAMES[m]:<32} {_number(m, result.totals[m]):>12}{unit:<2}{part}", file=stream)
    print(f"score {total.total:.3f}", file=stream)
