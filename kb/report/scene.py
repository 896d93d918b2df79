"""The 3-D view of the workstation: the objects' oriented boxes (plotly ``Mesh3d``, each face
coloured by its object's class; per state one mesh of the objects and one, faint, of the
furniture, with their edges), the robot's tool tip path, and a marker where each failure
happened, from a run report's ``scene``, ``path`` and ``failures``.

A box is the object's ``lo``/``hi`` corners in its own frame, placed by its global pose (a
4x4 matrix, metres). The view shows the final state; buttons switch to the initial state or
both. A few traces, not one per class: each trace costs WebGL set-up when the page loads
(docs/benchmarks.md, "Report pages"); the page shows the colours of the classes as a key.
"""

from __future__ import annotations

from types import SimpleNamespace
from typing import Any, Callable, Sequence

import numpy as np

from kb.metrics.execution import recovered as recovered_by_metrics
from kb.report.html import esc

#: Colours of the classes a workstation has, others from :data:`PALETTE` in order of appearance.
CLASS_COLOURS = {
    "Part": "#e4572e", "KitTray": "#2e86de", "PartsTray": "#17a589", "Kit": "#8e44ad",
    "WorkTable": "#b0a48a", "LargeContainer": "#c49a6c", "LargeBoxWithKits": "#c49a6c",
    "LargeBoxWithEmptyKitTrays": "#c49a6c", "Robot": "#34495e", "EndEffector": "#f1c40f",
    "EndEffectorHolder": "#95a5a6", "EndEffectorChangingStation": "#7f8c8d",
}
PALETTE = ("#d35400", "#16a085", "#2980b9", "#8e44ad", "#c0392b", "#27ae60", "#f39c12", "#7f8c8d")
#: The corners of a unit box (0/1 per axis) and its 12 triangles and 12 edges.
_CORNERS = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]])
_TRIANGLES = np.array([[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7], [0, 1, 5], [0, 5, 4],
                       [1, 2, 6], [1, 6, 5], [2, 3, 7], [2, 7, 6], [3, 0, 4], [3, 4, 7]])
_EDGES = np.array([[0, 1], [1, 2], [2, 3], [3, 0], [4, 5], [5, 6], [6, 7], [7, 4], [0, 4], [1, 5], [2, 6], [3, 7]])
#: The classes drawn faint (big furniture, so that the parts show through).
_FAINT = frozenset({"WorkTable", "LargeContainer", "LargeBoxWithKits", "LargeBoxWithEmptyKitTrays",
                    "EndEffectorChangingStation", "MechanicalComponent"})


def corners(lo: Sequence[float], hi: Sequence[float], pose: Any) -> np.ndarray:
    """The 8 world corners (8 x 3) of the box ``lo``..``hi`` in the frame of the 4x4 ``pose``."""
    lo_a, hi_a = np.asarray(lo, float), np.asarray(hi, float)
    local = lo_a + _CORNERS * (hi_a - lo_a)
    m = np.asarray(pose, float)
    return local @ m[:3, :3].T + m[:3, 3]


def _numbers(value: Any, n: int) -> bool:
    return (isinstance(value, list) and len(value) == n
            and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in value))


def _placed(obj: Any, state: str) -> bool:
    """Whether ``obj`` has a box and a 4x4 pose in ``state``, all numbers."""
    if not isinstance(obj, dict) or not (_numbers(obj.get("lo"), 3) and _numbers(obj.get("hi"), 3)):
        return False
    pose = obj.get(state)
    return isinstance(pose, list) and len(pose) == 4 and all(_numbers(row, 4) for row in pose)


def boxes(scene: dict[str, Any], state: str) -> dict[str, list[tuple[str, np.ndarray]]]:
    """Class -> [(object name, its 8 corners)] of the objects placed in ``state`` (initial, final),
    all boxes placed by their poses at once."""
    objs = [o for o in scene.get("objects") or [] if _placed(o, state)]
    if not objs:
        return {}
    lo = np.array([o["lo"] for o in objs], float)
    hi = np.array([o["hi"] for o in objs], float)
    poses = np.array([o[state] for o in objs], float)
    local = lo[:, None, :] + _CORNERS[None, :, :] * (hi - lo)[:, None, :]
    world = np.einsum("kij,kcj->kci", poses[:, :3, :3], local) + poses[:, None, :3, 3]
    ok = np.isfinite(world).all(axis=(1, 2))
    out: dict[str, list[tuple[str, np.ndarray]]] = {}
    for obj, box, good in zip(objs, world, ok):
        if good:
            out.setdefault(str(obj.get("class") or "object"), []).append((str(obj.get("name", "")), box))
    return out


def colour(cls: str, order: list[str]) -> str:
    """The colour of class ``cls`` (``order``: the classes seen so far, for the palette)."""
    if cls in CLASS_COLOURS:
        return CLASS_COLOURS[cls]
    if cls not in order:
        order.append(cls)
    return PALETTE[order.index(cls) % len(PALETTE)]


def mesh_trace(label: str, items: list[tuple[str, str, np.ndarray]], state: str, colours: dict[str, str],
               opacity: float) -> dict[str, Any]:
    """One Mesh3d of the boxes ``items`` ((class, name, corners)) in ``state``, each face
    coloured by its object's class (one trace for many classes: WebGL set-up is per trace)."""
    pts = np.concatenate([c for _, _, c in items])
    tri = np.concatenate([_TRIANGLES + 8 * n for n in range(len(items))])
    names = [label for cls, name, _ in items for label in [f"{esc(name)}<br>{esc(cls)} ({state})"] * 8]
    faces = [colours[cls] for cls, _, _ in items for _ in range(len(_TRIANGLES))]
    return {"type": "mesh3d", "name": f"{label} ({len(items)})", "legendgroup": state,
            "legendgrouptitle": {"text": f"{state} state"}, "x": _r(pts[:, 0]), "y": _r(pts[:, 1]),
            "z": _r(pts[:, 2]), "i": tri[:, 0].tolist(), "j": tri[:, 1].tolist(), "k": tri[:, 2].tolist(),
            "facecolor": faces, "opacity": opacity, "flatshading": True, "hovertext": names, "hoverinfo": "text",
            "showlegend": True}


def edge_trace(all_boxes: list[np.ndarray], state: str) -> dict[str, Any]:
    """The boxes' edges as one line trace (a gap, null, between segments)."""
    seg = np.stack(all_boxes)[:, _EDGES]  # (K, 12, 2, 3)
    gap = np.full(seg.shape[:2] + (1, 3), np.nan)
    pts = np.round(np.concatenate([seg, gap], axis=2).reshape(-1, 3), 5)

    def column(v: np.ndarray) -> list[float | None]:
        return [None if x != x else x for x in v.tolist()]
    return {"type": "scatter3d", "mode": "lines", "x": column(pts[:, 0]), "y": column(pts[:, 1]),
            "z": column(pts[:, 2]), "name": f"edges ({state})", "legendgroup": state, "showlegend": False,
            "hoverinfo": "skip", "line": {"color": "rgba(40,40,40,0.45)", "width": 1}}


def _r(values: np.ndarray) -> list[float]:
    return np.round(values, 5).tolist()


def _point(p: Any) -> bool:
    return isinstance(p, (list, tuple)) and len(p) == 3 and all(isinstance(v, (int, float)) for v in p)


def path_trace(path: list[Any], start: Any = None) -> dict[str, Any] | None:
    """The tool tip's commanded positions in order from ``start`` (where it stood), coloured by
    action index."""
    xs, ys, zs, idx = [], [], [], []
    if _point(start):
        xs.append(start[0]), ys.append(start[1]), zs.append(start[2]), idx.append("start")
    for seg in path or []:
        if not isinstance(seg, dict):
            continue
        for p in seg.get("points") or []:
            if _point(p):
                xs.append(p[0]), ys.append(p[1]), zs.append(p[2]), idx.append(seg.get("index"))
    if not xs:
        return None
    colours = [i if isinstance(i, (int, float)) and not isinstance(i, bool) else 0 for i in idx]
    return {"type": "scatter3d", "mode": "lines+markers", "name": "tool tip path", "x": xs, "y": ys, "z": zs,
            "line": {"color": colours, "colorscale": "Viridis", "width": 4},
            "marker": {"size": 2, "color": colours, "colorscale": "Viridis"},
            "hovertext": [f"action {esc(i)}" if i != "start" else "start" for i in idx], "hoverinfo": "text+x+y+z"}


def failure_trace(report: dict[str, Any], where: dict[str, np.ndarray]) -> dict[str, Any] | None:
    """A marker above the first of each failure's objects that the scene places, with the
    failure's mode, action, violated predicates and recovery as hover text."""
    xs, ys, zs, text, colours, labels = [], [], [], [], [], []
    stacked: dict[str, int] = {}
    for n, f in enumerate(report.get("failures") or []):
        point = _failure_point(f, where)
        if point is None:
            continue
        key = f"{point[0]:.4f},{point[1]:.4f}"
        lift = 0.04 * stacked.get(key, 0)
        stacked[key] = stacked.get(key, 0) + 1
        xs.append(point[0]), ys.append(point[1]), zs.append(point[2] + 0.04 + lift)
        text.append(failure_text(n + 1, f))
        colours.append("#e67e22" if recovered(f, report) else "#c0392b")
        labels.append(f"F{n + 1}")
    if not xs:
        return None
    return {"type": "scatter3d", "mode": "markers+text", "name": "failures", "x": xs, "y": ys, "z": zs,
            "text": labels, "textposition": "top center", "hovertext": text, "hoverinfo": "text",
            "marker": {"size": 7, "symbol": "x", "color": colours, "line": {"width": 1}}}


def _failure_point(f: dict[str, Any], where: dict[str, np.ndarray]) -> tuple[float, float, float] | None:
    at = f.get("where")
    if _point(at):
        return (float(at[0]), float(at[1]), float(at[2]))
    for name in f.get("objects") or []:
        box = where.get(str(name))
        if box is not None:
            c = box.mean(axis=0)
            return (float(c[0]), float(c[1]), float(box[:, 2].max()))
    return None


def recovered(f: dict[str, Any], report: dict[str, Any]) -> bool:
    """Whether a failure (of ``failures`` or of the ``timeline``) was recovered from, by the rule
    of the run's metrics (:func:`kb.metrics.execution.recovered`: an outcome ``recovered: ...``,
    or a retry after which the same action was done), on the report's timeline; a report
    without a timeline: an outcome that names no giving up or stop."""
    actions = [SimpleNamespace(index=e.get("index"), action=e.get("action"), args=tuple(map(str, e.get("args") or ())),
                               status=e.get("status")) for e in report.get("timeline") or [] if e.get("kind") == "action"]
    outcome = str(f.get("outcome") or "")
    if not actions:
        return bool(outcome) and not any(w in outcome for w in ("gave up", "stopped", "failed", "unrecovered"))
    index = f.get("action_index", f.get("index"))
    failed = next((a for a in actions if a.index == index and a.action == f.get("action")), None)
    failure = SimpleNamespace(outcome=outcome, recovery=f.get("recovery"), action_index=index, action=f.get("action"),
                              args=failed.args if failed else ())
    try:
        return recovered_by_metrics(failure, actions)
    except TypeError:  # an index that is no number
        return False


def failure_text(number: int, f: dict[str, Any]) -> str:
    """Hover text of failure ``number`` (escaped; ``<br>`` between lines)."""
    lines = [f"<b>failure {number}: {esc(f.get('mode'))}</b>",
             f"action {esc(f.get('action_index'))} {esc(f.get('action'))} ({esc(f.get('phase'))} check)",
             "objects: " + esc(", ".join(map(str, f.get("objects") or [])))]
    lines += ["violated: " + esc(v) for v in (f.get("violated") or [])[:6]]
    lines.append(f"recovery: {esc(f.get('recovery'))} &rarr; {esc(f.get('outcome'))}")
    return "<br>".join(lines)


def scene_figure(report: dict[str, Any],
                 replay: Callable[[dict[str, str]], list[dict[str, Any]]] | None = None) -> dict[str, Any] | str:
    """The 3-D figure of a run report, or the reason there is none (text); ``replay``: the
    replay's traces given the classes' colours (:func:`kb.report.replay.replay_traces`), hidden
    until it plays, with a button that shows them."""
    scene = report.get("scene")
    if not isinstance(scene, dict) or not isinstance(scene.get("objects"), list):
        return ("This report has no scene (the objects' boxes and poses): it was written before kitkb "
                "recorded them, or by a run that did not execute.")
    by_state = {state: boxes(scene, state) for state in ("initial", "final")}
    states = [s for s in ("final", "initial") if by_state[s]]
    if not states:
        return "The report's scene places no object with a box, so there is nothing to draw."
    order: list[str] = []
    colours = {cls: colour(cls, order) for cls in sorted({c for st in states for c in by_state[st]})}
    traces, visible_in = [], []
    where: dict[str, np.ndarray] = {}
    for state in ("initial", "final"):
        by_class = by_state[state]
        items = [(cls, name, box) for cls in sorted(by_class) for name, box in by_class[cls]]
        for label, faint in (("objects", False), ("tables, boxes, stations", True)):
            part = [x for x in items if (x[0] in _FAINT) == faint]
            if part:
                traces.append(mesh_trace(label, part, state, colours, 0.2 if faint else 0.8))
                visible_in.append(state)
        if items:
            traces.append(edge_trace([box for _, _, box in items], state))
            visible_in.append(state)
        if state == "initial":
            where.update({name: box for _, name, box in items})
    if not where:
        where = {name: box for items in by_state["final"].values() for name, box in items}
    path, failed = path_trace(report.get("path") or [], report.get("tip_start")), failure_trace(report, where)
    extra = [dict(t, meta=name) for t, name in ((path, "path"), (failed, "failures")) if t is not None]
    shown = states[0]
    for t, state in zip(traces, visible_in):
        t["visible"] = state == shown
    more = replay(colours) if replay is not None else []
    data = traces + extra + more
    key = [(cls, colours[cls], max(len(by_state[st].get(cls, [])) for st in states)) for cls in colours]
    furniture = [t.get("legendgroup") == "initial" and t.get("type") == "mesh3d" and str(t["name"]).startswith("tables")
                 for t in traces]
    return {"data": data, "layout": _layout(states, visible_in, [t["meta"] for t in extra], len(more), furniture),
            "key": key}


def _layout(states: list[str], visible_in: list[str], extra: list[str], replayed: int = 0,
            furniture: list[bool] | None = None) -> dict[str, Any]:
    buttons = []
    for label, show in (("final state", {"final"}), ("initial state", {"initial"}), ("both", {"initial", "final"})):
        if show <= set(states):
            buttons.append({"label": label, "method": "restyle",
                            "args": [{"visible": [s in show for s in visible_in] + [True] * len(extra)
                                      + [False] * replayed}]})
    if replayed:  # the replay: the furniture as at the start, the tool's path, the replay's traces
        buttons.append({"label": "replay", "method": "restyle",
                        "args": [{"visible": list(furniture or [False] * len(visible_in))
                                  + [m == "path" for m in extra] + [True] * replayed}]})
    axis = {"showbackground": True, "backgroundcolor": "#f4f6f9", "gridcolor": "#d0d5dd"}
    return {"margin": {"l": 0, "r": 0, "t": 30, "b": 0}, "height": 620, "legend": {"groupclick": "toggleitem"},
            "scene": {"aspectmode": "data", "xaxis": {**axis, "title": {"text": "x (m)"}},
                      "yaxis": {**axis, "title": {"text": "y (m)"}}, "zaxis": {**axis, "title": {"text": "z (m)"}},
                      "camera": {"eye": {"x": -1.3, "y": -1.5, "z": 1.1}}},
            "updatemenus": [{"type": "buttons", "direction": "right", "x": 0, "y": 1.06, "xanchor": "left",
                             "yanchor": "top", "buttons": buttons, "showactive": True}] if len(buttons) > 1 else []}
