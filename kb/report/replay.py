"""The replay of a run on its page (issue 31 point 3; the first paper's §VI kittingViewer, which
animates a program and steps through it): what the page's player (``js/replay.js``) plays, made
from the run's report — its ``commands`` (each CRCL command with its start and end on the cell's
clock, the tool tip's path, the metrics and settings once it completed: :mod:`kb.metrics.clock`),
its ``scene`` (the objects' boxes, initial and final poses) and its ``failures``.

What the robot grasped and released, and when, is :func:`kb.metrics.handling.handled` (the
cell's rules on the commands and the scene, with the cell's ground truth of injected faults: a
missed grasp takes nothing, a dropped part leaves the tip in transit, a part or tray an external
agent moved leaves its place when the action it struck starts and is found where the robot next
grasps it); every object ends at its final pose (the replay reaches the final scene), those the
commands did not bring there listed. Each failure appears at the end of the action it was found
in; the Metrics & Settings panel shows the row of the last completed command.
"""

from __future__ import annotations

import json
from functools import lru_cache
from importlib import resources
from typing import Any

import numpy as np

from kb.metrics import NAMES, UNITS
from kb.metrics.handling import Handling, fault_mechanisms, handled
from kb.report.html import esc
from kb.report.scene import failure_text, recovered


def replay_data(report: dict[str, Any]) -> dict[str, Any] | str:
    """The replay of a run report (JSON data for ``js/replay.js``), or why there is none (text)."""
    commands = report.get("commands")
    if not isinstance(commands, dict) or not isinstance(commands.get("rows"), list) or not commands["rows"]:
        return ("This report has no timed commands, so there is no replay: it was written before kitkb "
                "recorded them (issue 31), or by a run that sent no command.")
    settings = commands.get("settings") if isinstance(commands.get("settings"), list) else []
    if not all(isinstance(x, dict) for x in settings):
        settings = []
    metrics = commands.get("metrics")
    metrics = [str(m) for m in metrics if isinstance(m, str)] if isinstance(metrics, list) else []
    rows = [r for r in commands["rows"] if _row_ok(r, len(settings))]
    if not rows:
        return "This report's timed commands are not of the shape kitkb writes, so there is no replay."
    start = commands["start"] if _point(commands.get("start")) else [0.0, 0.0, 0.0]
    injected = [x for x in report.get("injected") or [] if isinstance(x, dict)]
    moved = handled({"rows": rows, "start": start}, report.get("scene") or {}, injected,
                    fault_mechanisms(sorted({str(x.get("kind")) for x in injected})))
    t_last = moved.t_end
    return {"t_end": t_last, "start": start, "metrics": metrics,
            "settings": settings, "rows": rows,
            "objects": [{"name": name, "class": cls, "segments": seg}
                        for name, cls, seg in zip(moved.names, moved.classes, moved.segments)],
            "put_right": moved.put_right, "failures": _failures(report, rows, moved, t_last),
            }


def _number(v: Any) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool) and v == v and abs(v) < 1e12


def _point(v: Any) -> bool:
    return isinstance(v, list) and len(v) == 3 and all(_number(x) for x in v)


def _row_ok(r: Any, settings: int) -> bool:
    """A command's row as :func:`kb.metrics.clock.timed_commands` writes it."""
    return (isinstance(r, list) and len(r) == 8 and isinstance(r[0], int) and isinstance(r[1], str)
            and _number(r[2]) and _number(r[3]) and _point(r[4]) and isinstance(r[5], list)
            and all(_point(p) for p in r[5]) and isinstance(r[6], list) and all(_number(v) for v in r[6])
            and isinstance(r[7], int) and 0 <= r[7] < settings)


def _failures(report: dict[str, Any], rows: list[list[Any]], objects: Handling, t_end: float) -> list[dict[str, Any]]:
    """Each failure at the end of the action it was found in (before it, with no command of
    its own), with a place to mark: where it was seen, else its first object's box where the
    replay had it at the start."""
    ends: dict[int, float] = {}
    for r in rows:
        if isinstance(r[0], int):
            ends[r[0]] = max(ends.get(r[0], 0.0), float(r[3]))
    where = {name: c for name, c in zip(objects.names, (s[0][2] if s[0][1] == "rest" else None
                                                        for s in objects.segments)) if c is not None}
    out = []
    for k, f in enumerate(report.get("failures") or []):
        index = f.get("action_index")
        t = ends.get(index) if isinstance(index, int) else None
        if t is None:
            later = [float(r[2]) for r in rows if isinstance(r[0], int) and isinstance(index, int) and r[0] > index]
            t = min(later) if later else t_end
        at = f.get("where")
        if not (isinstance(at, list) and len(at) == 3):
            box = next((np.asarray(where[o]) for o in f.get("objects") or [] if o in where), None)
            at = None if box is None else [float(box[:, 0].mean()), float(box[:, 1].mean()), float(box[:, 2].max())]
        out.append({"t": round(t, 6), "label": f"F{k + 1}", "mode": f.get("mode"), "at": at,
                    "recovered": recovered(f, report), "text": failure_text(k + 1, f)})
    return out


# --- the page: the replay's traces in the 3-D view, its controls and panel, the player --------

_TRIANGLES = [[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7], [0, 1, 5], [0, 5, 4],
              [1, 2, 6], [1, 6, 5], [2, 3, 7], [2, 7, 6], [3, 0, 4], [3, 4, 7]]
#: the settings of the Metrics & Settings panel, as the kittingViewer named them, and their keys
PANEL_SETTINGS = (("length units", "length_unit"), ("angle units", "angle_unit"), ("speed", "speed"),
                  ("relative speed (%)", "relative_speed"), ("acceleration", "acceleration"),
                  ("relative acceleration (%)", "relative_acceleration"),
                  ("end point tolerance", "end_point_tolerance"), ("end angle tolerance", "end_angle_tolerance"),
                  ("intermediate point tolerance", "intermediate_point_tolerance"), ("gripper", "gripper"),
                  ("tool changer", "tool_changer"), ("coordinate frame", "coordinate_frame"),
                  ("position", "position"))


def replay_traces(data: dict[str, Any], colours: dict[str, str]) -> list[dict[str, Any]]:
    """The 3-D view's traces the player moves (hidden until it plays; ``meta`` names them for
    it): one mesh of the movable objects, the tool tip, the failures found so far."""
    objects = data["objects"]
    xs: list[float] = []
    ys: list[float] = []
    zs: list[float] = []
    start = data["start"]
    for obj in objects:
        first = obj["segments"][0]
        for p in first[2] if first[1] == "rest" else [start] * 8:
            xs.append(p[0]), ys.append(p[1]), zs.append(p[2])
    tri = [[a + 8 * n, b + 8 * n, c + 8 * n] for n in range(len(objects)) for a, b, c in _TRIANGLES]
    faces = [colours.get(obj["class"], "#7f8c8d") for obj in objects for _ in _TRIANGLES]
    hover = [f"{esc(obj['name'])} ({esc(obj['class'])})" for obj in objects for _ in range(8)]
    return [
        {"type": "mesh3d", "meta": "replay-objects", "name": f"replay: objects ({len(objects)})", "x": xs, "y": ys,
         "z": zs, "i": [t[0] for t in tri], "j": [t[1] for t in tri], "k": [t[2] for t in tri], "facecolor": faces,
         "opacity": 0.85, "flatshading": True, "hovertext": hover, "hoverinfo": "text", "visible": False},
        {"type": "scatter3d", "meta": "replay-tool", "name": "replay: tool tip", "mode": "markers",
         "x": [start[0]], "y": [start[1]], "z": [start[2]], "hoverinfo": "name",
         "marker": {"size": 7, "symbol": "diamond", "color": "#111"}, "visible": False},
        {"type": "scatter3d", "meta": "replay-failures", "name": "replay: failures", "mode": "markers+text",
         "x": [], "y": [], "z": [], "text": [], "hovertext": [], "hoverinfo": "text", "textposition": "top center",
         "marker": {"size": 7, "symbol": "x", "color": []}, "visible": False},
    ]


def replay_html(data: dict[str, Any], prefix: str, plot_id: str) -> str:
    """The player's controls, its Metrics & Settings panel (filled by the player), the data, and
    the player's script (once per page: it starts every replay on it)."""
    root = f"{prefix}-replay"
    names = dict(NAMES)
    metrics = "".join(f'<tr><th title="{esc(names.get(m, m))}">{esc(m)}</th><td class="num" data-metric="{esc(m)}">0</td>'
                      f'<td>{esc(UNITS.get(m, ""))}</td></tr>' for m in data["metrics"])
    settings = "".join(f'<tr><th>{esc(label)}</th><td data-setting="{esc(key)}">&ndash;</td></tr>'
                       for label, key in PANEL_SETTINGS)
    put_right = (f'<p class="note">Put right at the end (moved, taken away or come into being where the commands do '
                 f'not show it): {esc(", ".join(data["put_right"]))}.</p>') if data["put_right"] else ""
    controls = (f'<div class="replay-controls" hidden><button data-do="play">&#9654; play</button> '
                f'<button data-do="command" title="key n">next command</button> '
                f'<button data-do="action" title="key g">next action (g)</button> '
                f'<button data-do="restart">restart</button> speed &times;<select data-do="rate">'
                + "".join(f'<option{" selected" if r == 2 else ""}>{r}</option>' for r in (0.5, 1, 2, 5, 10, 20))
                + f'</select><br><input type="range" min="0" max="{data["t_end"]}" step="0.001" value="0" '
                f'style="width:100%"> <span class="replay-clock"></span></div>')
    panel = (f'<div class="grid"><div><h3>Metrics</h3><table class="nested replay-metrics">{metrics}</table></div>'
             f'<div><h3>Settings</h3><table class="nested replay-settings">{settings}</table></div>'
             f'<div><h3>Command</h3><p class="replay-command"></p><p class="replay-failures"></p></div></div>')
    # JSON inside the page: <, > and & as JSON escapes (JSON.parse gives the text back; no tag can close the script)
    text = json.dumps(data, separators=(",", ":")).replace("<", "\\u003c").replace(">", "\\u003e").replace("&", "\\u0026")
    return (f'<div id="{esc(root)}" class="replay">{controls}{put_right}{panel}</div>'
            f'<script type="application/json" data-replay="{esc(plot_id)}" data-root="{esc(root)}">{text}</script>'
            f'<script>{player_js()}</script>')


@lru_cache(maxsize=1)
def player_js() -> str:
    """The player (``replay.js`` beside this module)."""
    return resources.files(__package__).joinpath("replay.js").read_text(encoding="utf-8")
