"""The replay of a run on its page (issue 31 point 3; the first paper's §VI kittingViewer, which
animates a program and steps through it): what the page's player (``js/replay.js``) plays, made
from the run's report — its ``commands`` (each CRCL command with its start and end on the cell's
clock, the tool tip's path, the metrics and settings once it completed: :mod:`kb.metrics.clock`),
its ``scene`` (the objects' boxes, initial and final poses) and its ``failures``.

The commands say where the tool tip goes and when the gripper closes and opens; what they grasp
is found here as the cell finds it (:mod:`kb.sim.robot`): at a ``CloseGripper`` the object whose
top face is at the tip (within :data:`GRASP_TOLERANCE`) and whose footprint holds the tip, with
what rests in it (a kit tray's parts); at a ``CloseToolChanger`` the end effector whose mount
face is there. A held object moves with the tip, keeping its orientation, until the gripper (or
the tool changer) opens; it then rests where it was let go. What the commands do not show — a
part a fault took away or pushed, a kit that came into being, a turn of a held object — is put
right at the end: every object ends at its final pose (the replay reaches the final scene), and
those put right are listed. Each failure appears at the time of the action it was found in.

Each object's motion is a list of segments ``[t, kind, corners]``: from time ``t`` on it rests
with its box's 8 world corners ``corners`` (``"rest"``), or is held with its corners relative to
the tool tip (``"held"``), or is not there (``"gone"``, no corners).
"""

from __future__ import annotations

import json
from functools import lru_cache
from importlib import resources
from typing import Any

import numpy as np

from kb.metrics import NAMES, UNITS
from kb.report.html import esc
from kb.report.scene import _FAINT, _placed, corners, failure_text, recovered

#: How far (m) an object's top may be from the tip for a grasp to take it (the cell: 2 mm; a
#: report rounds poses to the micrometre, and a released object may have settled a little).
GRASP_TOLERANCE = 0.005
#: How far above a held object's top what rests in it may reach (m).
CONTENT_REACH = 0.05
#: Classes the replay never moves.
_FIXED = _FAINT | {"Robot", "EndEffectorHolder"}
_CLOSE = {"CloseGripper()": "gripper", "CloseToolChanger()": "changer"}
_OPEN = {"OpenGripper()": "gripper", "OpenToolChanger()": "changer"}


def _r(a: np.ndarray) -> list[Any]:
    return np.round(a, 5).tolist()


class _Objects:
    """The movable objects of a scene and where the replay has them."""

    def __init__(self, scene: dict[str, Any]) -> None:
        objs = [o for o in scene.get("objects") or [] if str(o.get("class")) not in _FIXED
                and (_placed(o, "initial") or _placed(o, "final"))]
        self.items = objs
        self.names = [str(o.get("name", "")) for o in objs]
        self.classes = [str(o.get("class") or "object") for o in objs]
        self.now: list[np.ndarray | None] = [corners(o["lo"], o["hi"], o["initial"]) if _placed(o, "initial") else None
                                             for o in objs]
        self.final: list[np.ndarray | None] = [corners(o["lo"], o["hi"], o["final"]) if _placed(o, "final") else None
                                               for o in objs]
        self.segments: list[list[list[Any]]] = [[[0.0, "rest", _r(c)]] if c is not None else [[0.0, "gone"]]
                                                for c in self.now]

    def at_tip(self, tip: np.ndarray, held: set[int], effector: bool) -> int | None:
        """The object whose top is at ``tip`` and whose footprint holds it (an end effector for
        the tool changer, anything else for the gripper): the nearest top, then the smallest."""
        best: tuple[float, float, int] | None = None
        for n, c in enumerate(self.now):
            if c is None or n in held or (self.classes[n] == "EndEffector") != effector:
                continue
            lo, hi = c.min(axis=0), c.max(axis=0)
            gap = abs(hi[2] - tip[2])
            if gap > GRASP_TOLERANCE or not (lo[0] - 1e-3 <= tip[0] <= hi[0] + 1e-3 and lo[1] - 1e-3 <= tip[1] <= hi[1] + 1e-3):
                continue
            key = (round(gap, 4), float(np.prod(hi - lo)), n)
            if best is None or key < best:
                best = key
        return None if best is None else best[2]

    def contents(self, n: int, held: set[int]) -> list[int]:
        """The objects resting in object ``n`` (their centre over its footprint, between its
        bottom and a little above its top)."""
        c = self.now[n]
        assert c is not None
        lo, hi = c.min(axis=0), c.max(axis=0)
        out = []
        for m, other in enumerate(self.now):
            if m == n or other is None or m in held or self.classes[m] == "EndEffector":
                continue
            centre = other.mean(axis=0)
            if lo[0] <= centre[0] <= hi[0] and lo[1] <= centre[1] <= hi[1] and lo[2] <= centre[2] <= hi[2] + CONTENT_REACH:
                out.append(m)
        return out


def replay_data(report: dict[str, Any]) -> dict[str, Any] | str:
    """The replay of a run report (JSON data for ``js/replay.js``), or why there is none (text)."""
    commands = report.get("commands")
    if not isinstance(commands, dict) or not isinstance(commands.get("rows"), list) or not commands["rows"]:
        return ("This report has no timed commands, so there is no replay: it was written before kitkb "
                "recorded them (issue 31), or by a run that sent no command.")
    settings = commands.get("settings") if isinstance(commands.get("settings"), list) else []
    rows = [r for r in commands["rows"] if _row_ok(r, len(settings))]
    if not rows:
        return "This report's timed commands are not of the shape kitkb writes, so there is no replay."
    objects = _Objects(report.get("scene") or {})
    held: dict[int, np.ndarray] = {}  # object -> corners relative to the tip
    by: dict[str, list[int]] = {"gripper": [], "changer": []}
    start = np.asarray(commands["start"] if _point(commands.get("start")) else [0.0, 0.0, 0.0], float)
    tip = start
    for row in rows:
        t_end, tip_after = float(row[3]), row[4]
        if isinstance(tip_after, list) and len(tip_after) == 3:
            tip = np.asarray(tip_after, float)
        text = str(row[1])
        if text in _CLOSE and not by[_CLOSE[text]]:
            _grasp(objects, held, by, _CLOSE[text], tip, t_end)
        elif text in _OPEN and by[_OPEN[text]]:
            for n in by[_OPEN[text]]:
                objects.now[n] = held.pop(n) + tip
                objects.segments[n].append([t_end, "rest", _r(objects.now[n])])
            by[_OPEN[text]] = []
    t_last = float(rows[-1][3]) if rows else 0.0
    for n in list(held):  # still held at the end: where the tip left it
        objects.now[n] = held.pop(n) + tip
    put_right = _finish(objects, t_last)
    return {"t_end": t_last, "start": _r(start), "metrics": commands.get("metrics") or [],
            "settings": settings, "rows": rows,
            "objects": [{"name": name, "class": cls, "segments": seg}
                        for name, cls, seg in zip(objects.names, objects.classes, objects.segments)],
            "put_right": put_right, "failures": _failures(report, rows, objects, t_last),
            "totals": (report.get("metrics") or {}).get("static") or {}}


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


def _grasp(objects: _Objects, held: dict[int, np.ndarray], by: dict[str, list[int]], what: str, tip: np.ndarray,
           t: float) -> None:
    """Close the gripper or the tool changer at ``tip``: what it takes, and what rests in it,
    held from ``t`` on (an end effector hangs below the tip it becomes: its far face is the tip)."""
    n = objects.at_tip(tip, set(held), effector=what == "changer")
    if n is None:
        return
    taken = [n] if what == "changer" else [n, *objects.contents(n, set(held))]
    lift = np.zeros(3)
    if what == "changer":
        c = objects.now[n]
        assert c is not None
        lift[2] = float(c[:, 2].max() - c[:, 2].min())
    for m in taken:
        c = objects.now[m]
        assert c is not None
        held[m] = c - tip + lift
        objects.now[m] = None
        objects.segments[m].append([t, "held", _r(held[m])])
    by[what] = taken


def _finish(objects: _Objects, t_end: float) -> list[str]:
    """Every object to its final pose at ``t_end`` (gone if the final state has it not): the
    names of those the commands did not bring there (more than a millimetre off)."""
    out = []
    for n, (now, final) in enumerate(zip(objects.now, objects.final)):
        if final is None:
            if now is not None:
                objects.segments[n].append([t_end, "gone"])
                out.append(objects.names[n])
            continue
        if now is None or float(np.abs(now - final).max()) > 1e-3:
            objects.segments[n].append([t_end, "rest", _r(final)])
            out.append(objects.names[n])
    return out


def _failures(report: dict[str, Any], rows: list[list[Any]], objects: _Objects, t_end: float) -> list[dict[str, Any]]:
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
