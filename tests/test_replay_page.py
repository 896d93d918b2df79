"""The replay on a run's page (issue 31 point 3): the data it plays (kb.report.replay, fast) and
the player in headless Chromium (slow): stepping moves the tool and what it holds, the
Metrics & Settings panel follows each command, and the end is the final scene with the panel
equal to the report's metrics."""

from __future__ import annotations

import json
import tempfile
import time
from pathlib import Path
from typing import Any, Iterator

import numpy as np
import pytest

from kb.execution.loop import run_scenario
from kb.report import run_page, write_report
from kb.report.replay import replay_data
from kb.report.scene import corners
from kb.sim import FaultSpec
from kb.sim.cell import SimulatedCell

ROOT = Path(__file__).resolve().parent.parent
SMALL = ROOT / "ontologies" / "scenarios" / "small-kit"


@pytest.fixture(scope="module")
def report() -> dict[str, Any]:
    """small-kit with a missed grasp at action 6 (seed 1): the kit tray, parts and two grippers move."""
    cell = SimulatedCell(SMALL / "init.ttl", faults=FaultSpec.parse("missed-grasp@6", seed=1), seed=1)
    run = run_scenario(SMALL / "init.ttl", SMALL / "goal.ttl", cell=cell, seed=1, notifier=lambda *a: None)
    return json.loads(json.dumps(run.record.report()))


def _centre(c: Any) -> np.ndarray:
    return np.asarray(c, float).mean(axis=0)


def _final_centres(report: dict[str, Any]) -> dict[str, np.ndarray]:
    return {o["name"]: corners(o["lo"], o["hi"], o["final"]).mean(axis=0)
            for o in report["scene"]["objects"] if o.get("final")}


def test_replay_data_moves_what_the_gripper_takes(report: dict[str, Any]) -> None:
    data = replay_data(report)
    assert isinstance(data, dict)
    assert data["t_end"] == pytest.approx(report["metrics"]["static"]["TET"])
    segments = {o["name"]: o["segments"] for o in data["objects"]}
    # the kit tray: taken from its supply box, put on the work table, later into the finished kit box
    tray = [s[1] for s in segments["kit_tray_1"]]
    assert tray[:3] == ["rest", "held", "rest"] and tray.count("held") == 2
    table = _centre(next(s[2] for s in segments["kit_tray_1"][1:] if s[1] == "rest"))
    assert table[2] == pytest.approx(0.77, abs=1e-3)  # on the work table's top (0.75), 2 cm tray
    # the parts put in the kit ride with the kit tray into the box: held at the same moment
    tray_grasps = [s[0] for s in segments["kit_tray_1"] if s[1] == "held"]
    parts = {o["name"] for o in data["objects"] if o["class"] == "Part"}
    in_kit = [n for n, seg in segments.items() if n in parts and "held" in [s[1] for s in seg]]
    assert len(in_kit) == 3 and all(tray_grasps[1] in [s[0] for s in segments[n] if s[1] == "held"] for n in in_kit)
    # the tool changer mounts and removes both effectors
    assert [s[1] for s in segments["tray_gripper"]].count("held") == 2
    assert "held" in [s[1] for s in segments["part_gripper"]]
    # the commands bring every object where it ends but the kit, which comes into being
    assert data["put_right"] == ["kit_1"]
    # the failure appears at the end of the action it was found in
    (failure,) = data["failures"]
    ends = [r[3] for r in data["rows"] if r[0] == report["failures"][0]["action_index"]]
    assert failure["t"] == pytest.approx(max(ends)) and failure["mode"] == "missed-grasp"


def test_a_missed_grasp_takes_nothing(report: dict[str, Any]) -> None:
    data = replay_data(report)
    assert isinstance(data, dict)
    (failure,) = data["failures"]
    held = [seg[0] for seg in next(o["segments"] for o in data["objects"] if o["name"] == "part_a_1") if seg[1] == "held"]
    assert held and held[0] > failure["t"]  # taken by the retry, not by the grasp that missed


def test_a_dropped_part_and_a_part_an_agent_moved_leave_their_place_when_it_happened() -> None:
    cell = SimulatedCell(SMALL / "init.ttl", faults=FaultSpec.parse("dropped-part@6,part-moved@10", seed=1), seed=1)
    run = run_scenario(SMALL / "init.ttl", SMALL / "goal.ttl", cell=cell, seed=1, notifier=lambda *a: None)
    report = json.loads(json.dumps(run.record.report()))
    assert sorted(x["kind"] for x in report["injected"]) == ["dropped-part", "part-moved"]
    data = replay_data(report)
    assert isinstance(data, dict) and data["put_right"] == ["kit_1"]  # both found where they went
    final = _final_centres(report)
    seg = {o["name"]: o["segments"] for o in data["objects"]}
    dropped = seg["part_a_1"]
    assert [s[1] for s in dropped] == ["rest", "held", "rest"] and dropped[2][0] < data["t_end"]
    assert _centre(dropped[2][2]) == pytest.approx(final["part_a_1"].tolist(), abs=1e-4)  # on the floor
    moved = seg["part_a_3"]
    rows10 = [r[2] for r in data["rows"] if r[0] >= 10]
    assert [s[1] for s in moved] == ["rest", "rest"] and moved[1][0] == pytest.approx(min(rows10))
    assert _centre(moved[1][2]) == pytest.approx(final["part_a_3"].tolist(), abs=1e-4)


def test_a_report_without_timed_commands_says_why(report: dict[str, Any]) -> None:
    old = {k: v for k, v in report.items() if k != "commands"}
    assert "no timed commands" in replay_data(old)
    html = run_page(old)
    assert "there is no replay" in html and "kitkbReplays" not in html
    broken = dict(report, commands={"rows": [[0, "MoveTo()", "x", 1, [0, 0], [], [], 0]], "settings": []})
    assert "not of the shape" in replay_data(broken)
    assert "there is no replay" in run_page(broken)
    odd = dict(report, commands=[1, 2])
    assert "there is no replay" in run_page(odd)  # a section of another shape: left out, said missing


# --- in Chromium -------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def browser() -> Iterator[Any]:
    from test_report_browser import Browser, chromium_path
    binary = chromium_path()
    if binary is None:
        pytest.skip("no Chromium here (scripts/setup.sh installs Debian's chromium)")
    with tempfile.TemporaryDirectory(prefix="kitkb-chromium-") as profile:
        b = Browser(binary, profile)
        try:
            yield b
        finally:
            b.close()


def _open(browser: Any, url: str) -> str:
    from test_report_browser import DRAWN
    target = browser.send("Target.createTarget", url="about:blank")["targetId"]
    session = browser.send("Target.attachToTarget", targetId=target, flatten=True)["sessionId"]
    for domain in ("Page", "Runtime", "Log"):
        browser.send(f"{domain}.enable", session)
    browser.send("Page.navigate", session, url=url)
    browser.wait_event("Page.loadEventFired", session)
    browser.evaluate(session, DRAWN)
    deadline = time.monotonic() + 20
    while not browser.evaluate(session, "!!(window.kitkbReplays && window.kitkbReplays['run-scene'])"):
        assert time.monotonic() < deadline, "the replay did not start"
        time.sleep(0.05)
    return session


def _state(browser: Any, session: str, call: str = "") -> dict[str, Any]:
    return browser.evaluate(session, "(() => { const r = window.kitkbReplays['run-scene']; " + call
                            + "; return r.state(); })()")


@pytest.mark.slow
def test_the_replay_steps_plays_and_ends_on_the_final_scene(browser: Any, report: dict[str, Any],
                                                              tmp_path: Path) -> None:
    page = tmp_path / "run.html"
    write_report(report, page)
    session = _open(browser, page.as_uri())
    rows = report["commands"]["rows"]
    first = _state(browser, session)
    assert first["done"] == 0 and first["panel"]["TCE"] == "0"
    # the next command: the first is InitCanon, the panel counts it
    after = _state(browser, session, "r.command()")
    assert after["done"] == 1 and after["panel"]["TCE"] == "1" and after["panel"]["OCE"] == "1"
    # the next action, again and again (the g key): the tool moves, and at the kit tray's grasp the
    # tray goes with it
    tray0 = np.asarray(after["where"]["kit_tray_1"])
    browser.evaluate(session, "document.dispatchEvent(new KeyboardEvent('keydown', {key: 'g'}))")
    moved = _state(browser, session)
    assert moved["done"] > 1 and moved["tip"] != after["tip"]
    assert rows[moved["done"] - 1][0] == rows[1][0]  # the whole of the first action
    grasp = next(k for k, r in enumerate(rows) if r[1] == "CloseGripper()")
    held = _state(browser, session, f"r.toCommand({grasp + 2})")  # the move after the grasp
    assert float(held["panel"]["TET"]) == pytest.approx(rows[grasp + 1][3], abs=1e-3)
    tray1 = np.asarray(held["where"]["kit_tray_1"])
    tip_move = np.asarray(held["tip"]) - np.asarray(rows[grasp][4])
    assert np.linalg.norm(tray1 - tray0) > 0.05 and tray1 - tray0 == pytest.approx(tip_move, abs=1e-6)
    # play: the clock runs
    browser.evaluate(session, "window.kitkbReplays['run-scene'].play()")
    time.sleep(0.6)
    playing = _state(browser, session, "r.pause()")
    assert playing["t"] > held["t"]
    # the end: the final scene, the failures shown, the panel equal to the report's metrics
    end = _state(browser, session, "r.seek(1e9)")
    assert end["done"] == len(rows) and end["t"] == pytest.approx(report["metrics"]["static"]["TET"])
    for name, centre in _final_centres(report).items():
        if name in end["where"]:
            assert end["where"][name] == pytest.approx(centre.tolist(), abs=1e-4), name
    assert end["failures"] == ["F1"]
    static = report["metrics"]["static"]
    for metric in ("ACE", "OCE", "TCE", "RE", "PE", "CSE", "TE", "UCE"):
        assert end["panel"][metric] == str(static[metric]), metric
    for metric in ("TDM", "TET"):
        assert float(end["panel"][metric]) == pytest.approx(static[metric], abs=5e-4)
    assert browser.console_errors(session) == []
