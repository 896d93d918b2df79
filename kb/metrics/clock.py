"""A run's commands on one clock: each CRCL command the run sent, in order, with when it
started and ended (seconds of the robot's clock since the first command: the clock the run's
TET is on, :func:`kb.metrics.motion.cell_robot`), the tool tip's path through it, and the static
metrics and the robot's settings once it completed (the first paper's Fig. 14, the
kittingViewer's Metrics & Settings window). What a run page's replay plays
(:mod:`kb.report.replay`); the last command's end is the run's TET.
"""

from __future__ import annotations

from typing import Any, Iterable

from kb.metrics.motion import Robot, cell_robot
from kb.metrics.static import METRICS, session_metrics
from kb.metrics.steps import text_steps

#: the settings a command's row refers to by number (they change seldom: kept once each)
SETTING_KEYS = ("length_unit", "angle_unit", "speed", "relative_speed", "acceleration", "relative_acceleration",
                "end_angle_tolerance", "end_point_tolerance", "intermediate_point_tolerance", "gripper",
                "tool_changer", "coordinate_frame")


def timed_commands(actions: Iterable[Any], robot: Robot | None = None) -> dict[str, Any]:
    """The commands of ``actions`` (records with ``index`` and ``programs``, CRCL text) on the
    clock of ``robot`` (default the cell's): JSON data, columns kept short —

    * ``metrics``: the names of the values in each row (:data:`~kb.metrics.static.METRICS`);
    * ``settings``: the distinct settings after a command (:data:`SETTING_KEYS`);
    * ``rows``: per command ``[action index, text, start s, end s, tip point after (m),
      path (points passed, m; [] when it did not move), metric values, settings number]``."""
    actions = list(actions)
    owners = [a.index for a in actions for program in a.programs for _ in program]
    programs = (list(text_steps(program)) for a in actions for program in a.programs)
    result = session_metrics(programs, robot or cell_robot(), rows=True)
    settings: list[dict[str, Any]] = []
    seen: dict[tuple[Any, ...], int] = {}
    rows = []
    t = 0.0
    for owner, row in zip(owners, result.rows or []):
        values = dict(zip(METRICS, row.values))
        end = float(values["TET"])
        start = end - float(values["CCE"])
        s = {k: _round(row.settings.get(k)) for k in SETTING_KEYS} if row.settings else {}
        key = tuple(s.values())
        if key not in seen:
            seen[key] = len(settings)
            settings.append(s)
        tip = [_round(v) for v in (row.settings or {}).get("position", [])]
        rows.append([owner, row.command, round(max(start, t), 6), round(end, 6), tip,
                     [[_round(v) for v in p] for p in row.path], [_round(v) for v in row.values], seen[key]])
        t = end
    return {"metrics": list(METRICS), "settings": settings, "rows": rows,
            "start": [_round(v) for v in result.robot.start]}


def _round(value: Any) -> Any:
    return round(value, 6) if isinstance(value, float) else value
