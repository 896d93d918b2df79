"""Inputs of the report tests: a real run's report (small-kit, a missed grasp injected) with the
sections the page draws — ``scene``, ``path``, ``timeline`` — taken from the run itself where
the report does not have them yet (the simulated cell's ground truth at the start and the end,
the tool tip's commanded positions, the run's history), and campaign folders made of such
reports. Shared by tests/test_report.py and tests/test_report_browser.py."""

from __future__ import annotations

import copy
import json
from functools import lru_cache
from pathlib import Path
from typing import Any

import numpy as np

from kb.crcl.commands import MoveStraightTo, MoveThroughTo, MoveTo
from kb.execution import run_scenario
from kb.sim import FaultSpec, SimulatedCell
from kb.spatial.scene import Scene

SMALL = Path(__file__).resolve().parent.parent / "ontologies" / "scenarios" / "small-kit"
#: Most specific first: the class an object is drawn as.
_CLASSES = ("Part", "KitTray", "PartsTray", "Kit", "LargeBoxWithKits", "LargeBoxWithEmptyKitTrays", "LargeContainer",
            "WorkTable", "Robot", "EndEffectorHolder", "EndEffectorChangingStation", "EndEffector",
            "MechanicalComponent")


def local(iri: str) -> str:
    return str(iri).rsplit("#", 1)[-1].rsplit("/", 1)[-1]


class RecordingCell(SimulatedCell):
    """A simulated cell that keeps the tool tip's commanded positions, per action."""

    def __init__(self, *args: Any, **kw: Any) -> None:
        super().__init__(*args, **kw)
        self.path: list[dict[str, Any]] = []

    def begin_action(self, index: int, action: str, args: tuple[str, ...]) -> None:
        self.path.append({"index": index, "points": []})
        super().begin_action(index, action, args)

    def execute(self, command: Any) -> Any:
        poses = ([command.end_position] if isinstance(command, (MoveTo, MoveStraightTo))
                 else list(command.waypoints) if isinstance(command, MoveThroughTo) else [])
        if poses and self.path:
            self.path[-1]["points"].extend([round(float(v), 5) for v in p.point] for p in poses)
        return super().execute(command)


def _class(classes: frozenset[str]) -> str:
    names = {local(c) for c in classes}
    return next((c for c in _CLASSES if c in names), min(names) if names else "object")


def scene_section(start: Scene, end: Scene) -> dict[str, Any]:
    """The report's ``scene``: each object with a box, its class, the box and both poses."""
    objects = []
    for i, name in enumerate(start.names):
        if start.local_lo is None or np.isnan(start.local_lo[i]).any() or np.isnan(start.poses[i]).any():
            continue
        j = end.index.get(name)
        final = None if j is None or np.isnan(end.poses[j]).any() else np.round(end.poses[j], 6).tolist()
        objects.append({"name": local(name), "class": _class(start.classes[i]),
                        "lo": start.local_lo[i].tolist(), "hi": start.local_hi[i].tolist(),
                        "initial": np.round(start.poses[i], 6).tolist(), "final": final})
    return {"objects": objects}


def timeline_section(history: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """The report's ``timeline`` from :meth:`kb.execution.Run.history`."""
    out = []
    for e in history:
        if e["kind"] == "action":
            out.append({"t": e["time"], "kind": "action", "index": e["index"], "action": e["action"],
                        "args": e["args"], "status": e["status"]})
        elif e["kind"] == "failure":
            out.append({"t": e["time"], "kind": "failure", "index": e["index"], "mode": e["mode"],
                        "recovery": e["recovery"], "outcome": e["outcome"], "objects": []})
    return out


@lru_cache(maxsize=1)
def _recorded() -> str:
    init, goal = SMALL / "init.ttl", SMALL / "goal.ttl"
    start = Scene.from_files([init], declared=[goal])
    cell = RecordingCell(Scene.from_files([init], declared=[goal]), faults=FaultSpec.parse("missed-grasp@6", seed=1),
                         seed=1)
    run = run_scenario(init, goal, cell=cell, seed=1, notifier=lambda *a: None)
    report = run.report()
    report.setdefault("scene", scene_section(start, cell.scene()))
    report.setdefault("path", cell.path)
    report.setdefault("timeline", timeline_section(run.history()))
    return json.dumps(report)


def run_report() -> dict[str, Any]:
    """A fresh copy of the small-kit run's report (missed grasp at action 6, seed 1), every section."""
    return json.loads(_recorded())


def with_metrics(report: dict[str, Any]) -> dict[str, Any]:
    """``report`` with ``metrics`` and ``kits`` as issue 18 writes them, where it has none yet."""
    report = copy.deepcopy(report)
    failures = report.get("failures") or []
    report.setdefault("metrics", {
        "failures": len(failures), "failures_per_kit": {"kit_1": len(failures)}, "recovered": len(failures),
        "unrecovered": 0, "recovered_by_mode": {f["mode"]: 1 for f in failures}, "plan_time_s": 0.21,
        "replans": report.get("replans", 0), "contact_errors": 0, "violations": [],
        "static": {"ACE": 70, "OCE": 40, "TCE": 110, "TDM": 21.5, "CCE": 0.1, "TET": 41.2, "RE": 0, "PE": 0,
                   "CSE": 0, "TE": 0, "UCE": 2}})
    report.setdefault("kits", [{"kit": "kit_1", "design": "kit_design_a2b1", "score": 3, "max_score": 4,
                                "lost": [{"points": 1, "reason": "part not in its slot", "predicate":
                                          "part-location-kit", "objects": ["part_b_1", "kit_1"]}]}])
    return report


def write_campaign(folder: Path, reports: list[dict[str, Any]], method: str = "errors") -> Path:
    """A campaign folder as ``kitkb testmethod --out`` writes it, of ``reports`` as trials."""
    (folder / "trials").mkdir(parents=True, exist_ok=True)
    for i, report in enumerate(reports):
        trial = {"index": i, "seed": 100 + i, "method": method, "design": "kit_design_a2b1",
                 "layout": {"kit_tray_yaw_deg": 30 * i}, "time_s": report.get("time_s"), "error": None}
        (folder / "trials" / f"{i:05d}.json").write_text(json.dumps({**report, "trial": {**trial,
                                                                    **report.get("trial", {})}}))
    meta = {"method": method, "seed": 7, "trials": len(reports), "options": {"parts": 3, "faults": "errors"},
            "summary": {"kits_built": sum(1 for r in reports if r.get("goal_holds")),
                        "failures": {"mean": 1.0, "median": 1, "p95": 1}}}
    (folder / "campaign.json").write_text(json.dumps(meta))
    return folder


def test_recorded_run_has_every_section():
    report = run_report()
    assert report["goal_holds"] and [f["mode"] for f in report["failures"]] == ["missed-grasp"]
    kinds = {o["class"] for o in report["scene"]["objects"]}
    assert {"Part", "KitTray", "PartsTray", "WorkTable"} <= kinds
    moved = [o for o in report["scene"]["objects"] if o["name"] == "part_a_2"][0]
    assert moved["final"] != moved["initial"]  # a part went into the kit
    assert sum(len(p["points"]) for p in report["path"]) > 20
    assert [e["mode"] for e in report["timeline"] if e["kind"] == "failure"] == ["missed-grasp"]
