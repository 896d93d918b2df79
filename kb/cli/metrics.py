"""``kitkb metrics PROGRAM``: the static metrics of a CRCL program (kb.metrics); with
``--init`` (and ``--goal``) the program is also played on a simulated cell of that state for
the object and constraint metrics (kb.sim.playback)."""

from __future__ import annotations

import math
from typing import Any, TextIO

from kb.cli.output import Output
from kb.core.errors import InputError
from kb.metrics import (METRICS, NAMES, UNITS, Robot, Score, StaticMetrics, read_steps, read_weights, score,
                        static_metrics)
from kb.metrics.motion import DEFAULT_MAX_ACCELERATION, DEFAULT_MAX_SPEED
from kb.metrics.score import CONSTRAINT_METRICS, OBJECT_METRICS, OBJECT_NAMES
from kb.metrics.steps import require_steps

#: Index of TCE in a row's values: a command was executed when TCE grew.
_TCE = METRICS.index("TCE")


def metrics(program: str, format: str, per_command: bool, max_speed: float | None,
            max_acceleration: float | None, config: str | None, out: Output, init: str | None = None,
            goal: str | None = None, match_names: bool = False, length_unit: str | None = None,
            run: int | None = None, db: str | None = None) -> int:
    """Print the metrics of ``program`` (text: a table, with ``per_command`` a row per command
    first; json: one object with ``metrics``, ``score`` and ``rows``; with ``init``, the
    object and constraint metrics, ``objects`` and ``violations`` too)."""
    for option, value in (("--max-speed", max_speed), ("--max-acceleration", max_acceleration)):
        if value is not None and not (math.isfinite(value) and value > 0):
            raise InputError(f"{option} must be a positive number, not {value:g}")
    if run is not None or db is not None:
        if program is not None or run is None or db is None or init is not None or per_command:
            raise InputError("kitkb metrics takes a PROGRAM, or --run RUN_ID --db URL (a recorded run; no "
                             "PROGRAM, --init or --per-command with it)")
        return run_metrics(run, db, config, out)
    if program is None:
        raise InputError("kitkb metrics needs a PROGRAM (a .crcl or .xml CRCL file), or --run RUN_ID --db URL")
    if init is None and (goal is not None or match_names):
        raise InputError(f"{'--goal' if goal is not None else '--match-names'} needs --init (the state the "
                         "program is played from)")
    weights = read_weights(config) if config else None
    robot = _robot(max_speed, max_acceleration, length_unit)
    with out.progress(f"evaluating {program}"):
        steps = require_steps(read_steps(program), program)  # nothing understood is not a program
        result = static_metrics(steps, robot, rows=per_command or init is not None, source=program)
    played = None
    if init is not None:
        from kb.sim.playback import play  # the simulator only when a state is given
        rows = result.rows or []
        executed = [r.values[_TCE] > (rows[k - 1].values[_TCE] if k else 0) for k, r in enumerate(rows)]
        with out.progress(f"playing {program} on {init}"):
            played = play(steps, init, goal, executed=executed, length_unit=length_unit or robot_unit(robot),
                          match_names=match_names)
    totals: dict[str, Any] = {**result.totals, **(played.totals() if played is not None else {})}
    total = score(totals, weights)
    if out.is_json:
        data = result.as_dict()
        if not per_command:
            data.pop("rows", None)
        if played is not None:
            data["metrics"] = totals
            data["names"] = {**data["names"], **{m: OBJECT_NAMES[m] for m in OBJECT_METRICS + CONSTRAINT_METRICS}}
            data.update({"init": init, "goal": goal, "objects": played.objects.as_dict(),
                         "violations": [v.as_dict() for v in played.violations]})
            if per_command:
                for row, extra in zip(data["rows"], played.rows()):
                    row.update({m: extra[m] for m in CONSTRAINT_METRICS}, notes=row["notes"] + extra["notes"])
        # rows: on one line (the C encoder; an indented 100,000-row object takes seconds)
        out.emit({**data, "score": total.as_dict(), "config": config}, indent=None if per_command else 1)
        return 0
    if per_command:
        _rows(result, played.rows() if played is not None else None, out.results)
    _summary(result, totals, total, out.results)
    if played is not None:
        _objects(played, init, goal, [r.line for r in result.rows or []], out.results)
    print(f"score {total.total:.3f}", file=out.results)
    return 0


def _robot(max_speed: float | None, max_acceleration: float | None, length_unit: str | None) -> Robot:
    """The metrics' robot; ``length_unit`` where kb.metrics' robot takes one."""
    kw: dict[str, Any] = {}
    if length_unit is not None and "length_unit" in getattr(Robot, "__dataclass_fields__", {}):
        kw["length_unit"] = length_unit
    return Robot(max_speed=DEFAULT_MAX_SPEED if max_speed is None else max_speed,
                 max_acceleration=DEFAULT_MAX_ACCELERATION if max_acceleration is None else max_acceleration, **kw)


def robot_unit(robot: Robot) -> str | None:
    """The unit the metrics read a program's lengths in before it sets one (None: its form's)."""
    return getattr(robot, "length_unit", None)


def _number(metric: str, value: float) -> str:
    return f"{value:.3f}" if metric in UNITS else f"{int(value)}"


def _rows(result: StaticMetrics, played: list[dict[str, Any]] | None, stream: TextIO) -> None:
    width = max([len(r.command) for r in result.rows or []] + [7])
    width = min(width, 48)
    extra = CONSTRAINT_METRICS if played is not None else ()
    print(f"{'line':>5}  {'command':<{width}}  " + "  ".join(f"{m:>8}" for m in METRICS + extra) + "  notes",
          file=stream)
    for k, row in enumerate(result.rows or []):
        command = row.command if len(row.command) <= width else row.command[:width - 3] + "..."
        line = "" if row.line is None else str(row.line)
        cells = "  ".join(f"{_number(m, v):>8}" for m, v in zip(METRICS, row.values))
        notes = list(row.notes)
        if played is not None:
            cells += "  " + "  ".join(f"{played[k][m]:>8}" for m in extra)
            notes += played[k]["notes"]
        print(f"{line:>5}  {command:<{width}}  {cells}  {'; '.join(notes)}".rstrip(), file=stream)
    print(file=stream)


def _summary(result: StaticMetrics, totals: dict[str, Any], total: Score, stream: TextIO) -> None:
    robot = result.robot
    print(f"{result.source}: {result.commands} commands; robot: max speed {robot.max_speed:g} m/s, "
          f"max acceleration {robot.max_acceleration:g} m/s²", file=stream)
    names = {**NAMES, **OBJECT_NAMES}
    for m in METRICS + OBJECT_METRICS + CONSTRAINT_METRICS:
        if m not in totals:
            continue
        unit = f" {UNITS[m]}" if m in UNITS else ""
        value = totals[m]
        shown = "-" if value is None else _number(m, value)
        weight = total.weights[m]
        part = f"  x {weight:g} = {total.contributions[m] + 0.0:.3f}" if weight and m in total.contributions else ""
        print(f"{m:<4} {names[m]:<32} {shown:>12}{unit:<2}{part}", file=stream)


def _objects(played: Any, init: str, goal: str | None, lines: list[int | None], stream: TextIO) -> None:
    """The objects behind the object metrics, and each violation (at its command's line)."""
    objects = played.objects.as_dict()
    print(f"played on {init}" + (f", judged against {goal}" if goal else " (no --goal: OSM, OMR, OMW not decided)"),
          file=stream)
    for key, label in (("should_move", "should have moved"), ("moved", "moved"), ("right", "moved to the right place"),
                       ("wrong", "moved to a wrong place")):
        if objects[key]:
            print(f"  {label}: {', '.join(objects[key])}", file=stream)
    for v in played.violations:
        line = lines[v.command] if 0 <= v.command < len(lines) else None
        where = f"line {line}" if line is not None else f"command {v.command + 1}"
        print(f"  {v.kind} ({where}): {v.detail}", file=stream)


def run_metrics(run_id: int, db: str, config: str | None, out: Output) -> int:
    """``kitkb metrics --run RUN_ID --db URL``: the execution metrics, kit scores and the static
    metrics of the CRCL a recorded run sent (:func:`kb.execution.open_run`), and the score of
    the static and constraint metrics."""
    from kb.execution import open_run
    from kb.world.database import safe_url
    weights = read_weights(config) if config else None
    with out.progress(f"reading run {run_id}"):
        recorded = open_run(db, run_id)
    m = recorded.metrics
    totals: dict[str, Any] = dict(m["static"])
    if m.get("constraints") is not None:
        totals.update(m["constraints"])
    total = score(totals, weights)
    kits = [k.as_dict() for k in recorded.kit_scores]
    rec = recorded.record
    if out.is_json:
        out.emit({"run": rec.run_id, "db": safe_url(db), "scenario": rec.scenario, "seed": rec.seed,
                  "goal_holds": rec.goal_holds, "goal_unmet": rec.goal_unmet, "stopped": rec.stopped, "metrics": m, "kits": kits,
                  "score": total.as_dict(), "config": config})
        return 0
    stream = out.results
    print(f"run {rec.run_id} ({rec.scenario}, seed {rec.seed}) in {safe_url(db)}: goal "
          f"{'holds' if rec.goal_holds else 'does not hold'}"
          + (f" (unmet: {', '.join(rec.goal_unmet)})" if rec.goal_unmet else "")
          + (f"; stopped: {rec.stopped}" if rec.stopped else ""),
          file=stream)
    by_mode = ", ".join(f"{k} {v}" for k, v in m["failures_by_mode"].items()) or "none"
    per_kit = ", ".join(f"{k} {v}" for k, v in m["failures_per_kit"].items()) or "none"
    recovered = ", ".join(f"{k} {v}" for k, v in m["recovered_by_mode"].items()) or "none"
    plan = "-" if m["plan_time_s"] is None else f"{m['plan_time_s']:.3f} s"
    contacts = "not reported by the cell" if m["contact_errors"] is None else str(m["contact_errors"])
    for label, value in (("failures", f"{m['failures']} ({by_mode})"), ("failures per kit", per_kit),
                         ("recovered", f"{m['recovered']} ({recovered}); unrecovered {m['unrecovered']}"),
                         ("plan generation", f"{plan}; replans {m['replans']} ({m['replan_time_s']:.3f} s)"),
                         ("contact errors", contacts)):
        print(f"  {label:<18} {value}", file=stream)
    if m.get("violations"):
        print(f"  {'violations':<18} " + ", ".join(f"{k} {v}" for k, v in m["violations"].items()), file=stream)
    print("  static metrics of the CRCL sent:", file=stream)
    for name in METRICS:
        print(f"    {name:<4} {_number(name, m['static'][name]):>12} {UNITS.get(name, ''):<2} {NAMES[name]}",
              file=stream)
    for kit in kits:
        print(f"  kit {kit['kit']}: {kit['score']} of {kit['max_score']} points", file=stream)
        for lost in kit["lost"]:
            print(f"    lost {lost['points']}: {lost['reason']} ({lost['predicate']}"
                  f"({', '.join(lost['objects'])}) {'holds' if lost['holds'] else 'does not hold'})", file=stream)
    print(f"  score {total.total:.3f}", file=stream)
    return 0
