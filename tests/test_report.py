"""kb.report and ``kitkb report`` without a browser: the pages of a run and of a campaign hold
what they should, everything from the files is escaped, missing sections are said, and bad
inputs are one line and exit 2. (tests/test_report_browser.py renders them in Chromium.)"""

from __future__ import annotations

import json
import re
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from kb.cli import main
from kb.report import campaign_page, run_page, write_report
from kb.report.campaign import distribution_figures, failed_because, trial_page
from kb.report.html import bundle_for, plotly_js, trace_types
from kb.report.scene import CLASS_COLOURS, corners, recovered, scene_figure
from kb.report.source import normalise
from kb.report.timeline import timeline_figure
from test_report_inputs import run_report, with_metrics, write_campaign

EVIL = '<img src=x onerror="alert(1)">&amp;'


@pytest.fixture(scope="module")
def report() -> dict[str, Any]:
    return with_metrics(run_report())


def _plotly_copies(page: str) -> int:
    """How many plotly.js the page holds (the full one or a partial bundle: each opens with its
    licence header, ``* plotly.js (gl3d - minified) v4.1.1``)."""
    return len(re.findall(r"\* plotly\.js (?:\([^)]*\) )?v\d+\.\d+\.\d+", page))


def _figures(page: str) -> dict[str, list[dict[str, Any]]]:
    """div id -> the traces plotly.js is given (the JSON plotly.io.to_json wrote)."""
    found = re.findall(r'kitkbPlots\.push\(\["([^"]+)", (\{.*?\})\]\);</script>', page, re.S)
    return {div: json.loads(spec)["data"] for div, spec in found}


def test_a_box_is_placed_by_its_pose() -> None:
    yaw = np.array([[0.0, -1.0, 0.0, 1.0], [1.0, 0.0, 0.0, 2.0], [0.0, 0.0, 1.0, 0.5], [0, 0, 0, 1]])  # 90 degrees
    c = corners([-0.2, -0.1, 0.0], [0.2, 0.1, 0.05], yaw)
    assert c.shape == (8, 3)
    assert np.allclose(c.min(axis=0), [0.9, 1.8, 0.5]) and np.allclose(c.max(axis=0), [1.1, 2.2, 0.55])


def test_run_page_has_every_part_and_plotly_once(report: dict[str, Any]) -> None:
    page = run_page(report)
    assert page.startswith("<!DOCTYPE html>") and _plotly_copies(page) == 1
    assert not re.search(r'<script[^>]+src=', page)  # nothing to fetch: works with no network
    for tid in ("run-table", "metrics-table", "kits-table", "failures-table", "injected-table"):
        assert f'id="{tid}"' in page
    figures = _figures(page)
    assert set(figures) == {"run-scene", "run-timeline"}
    types = {t["type"] for t in figures["run-scene"]}
    assert {"mesh3d", "scatter3d"} <= types
    assert "Total Distance Moved" in page and "missed-grasp" in page


def test_the_scene_draws_each_object_coloured_by_class_and_marks_the_failure(report: dict[str, Any]) -> None:
    fig = scene_figure(report)
    assert isinstance(fig, dict)
    meshes = [t for t in fig["data"] if t["type"] == "mesh3d"]
    placed = [o for o in report["scene"]["objects"] if o["final"] is not None]
    final = [t for t in meshes if t["legendgroup"] == "final"]
    assert sum(len(t["x"]) for t in final) == 8 * len(placed) and all(t["visible"] for t in final)
    assert not any(t["visible"] for t in meshes if t["legendgroup"] == "initial")  # the buttons show them
    objects = [t for t in final if t["name"].startswith("objects")][0]
    parts = [n for n, text in enumerate(objects["hovertext"][::8]) if "<br>Part (" in text]
    assert parts and {objects["facecolor"][12 * n] for n in parts} == {CLASS_COLOURS["Part"]}
    assert {c for c, _, _ in fig["key"]} == {o["class"] for o in report["scene"]["objects"]}
    path = [t for t in fig["data"] if t["name"] == "tool tip path"][0]
    assert len(path["x"]) == sum(len(p["points"]) for p in report["path"]) + ("tip_start" in report)
    failure = [t for t in fig["data"] if t["name"] == "failures"][0]
    part = [o for o in report["scene"]["objects"] if o["name"] == "part_a_1"][0]
    top = corners(part["lo"], part["hi"], part["initial"])
    assert np.allclose([failure["x"][0], failure["y"][0]], top.mean(axis=0)[:2])  # above the part it missed
    assert failure["z"][0] > top[:, 2].max() and "missed-grasp" in failure["hovertext"][0]
    assert [b["label"] for b in fig["layout"]["updatemenus"][0]["buttons"]] == ["final state", "initial state", "both"]


def test_the_timeline_has_actions_failures_and_recoveries(report: dict[str, Any]) -> None:
    fig = timeline_figure(report)
    assert isinstance(fig, dict)
    actions, failures, recoveries = fig["data"]
    assert len(actions["x"]) == len([e for e in report["timeline"] if e["kind"] == "action"])
    assert actions["x"] == sorted(actions["x"]) and failures["y"] == [6]
    retry = min((t, i) for t, i in zip(actions["x"], actions["y"]) if t >= failures["x"][0])  # the action after it
    assert (recoveries["x"][0], recoveries["y"][0]) == retry and "retry" in recoveries["hovertext"][0]


def test_recovered_as_the_run_metrics_count_it(report: dict[str, Any]) -> None:
    failure = report["failures"][0]  # a missed grasp, retried: the same take-part was then done
    assert recovered(failure, report) and report["metrics"]["recovered"] == 1
    failed = [e for e in report["timeline"] if e["kind"] == "action" and e["index"] == 6][0]
    gone = dict(report, timeline=[e for e in report["timeline"]
                                  if not (e["kind"] == "action" and e["index"] > 6 and e["args"] == failed["args"])])
    assert not recovered(failure, gone)  # the retried grasp never done
    assert recovered(dict(failure, recovery="rebind", outcome="recovered: bound part_a_2"), gone)
    old = {k: v for k, v in report.items() if k != "timeline"}
    assert recovered(failure, old) and not recovered(dict(failure, outcome="gave up"), old)


def test_an_old_report_says_what_it_lacks() -> None:
    old = {k: v for k, v in run_report().items() if k not in ("scene", "path", "timeline", "metrics", "kits")}
    page = run_page(old)
    for missing in ("has no scene", "has no metrics", "has no kit scores", "has no timeline"):
        assert missing in page
    assert _figures(page) == {} and 'id="failures-table"' in page
    not_run = {"scenario": "x", "executed": False, "reason": "no plan: goal unreachable", "goal_holds": False,
               "stopped": None, "actions": 0, "injected": [], "failures": []}
    assert "not executed" in run_page(not_run) and "no plan: goal unreachable" in run_page(not_run)


def test_everything_from_the_files_is_escaped(report: dict[str, Any]) -> None:
    evil = json.loads(json.dumps(report).replace("part_a_1", EVIL.replace('"', "'")))
    evil["scenario"] = EVIL
    evil["kits"][0]["lost"] = [{"points": 1, "reason": EVIL, "predicate": "p<q", "objects": [EVIL]}]
    evil["scene"]["objects"][0]["class"] = "</script><script>alert(2)</script>"
    page = run_page(evil)
    assert "<img" not in page and "</script><script>alert(2)" not in page
    assert "&lt;img src=x onerror=&quot;alert(1)&quot;&gt;&amp;amp;" in page
    figures = _figures(page)  # plotly's JSON escapes < and >; the names in it are HTML-escaped for plotly.js
    texts = [h for t in figures["run-scene"] for h in t.get("hovertext") or []]
    assert any("&lt;/script&gt;&lt;script&gt;alert(2)" in h for h in texts)
    assert "&lt;/script&gt;&lt;script&gt;alert(2)&lt;/script&gt; (1)" in page  # the colour key


def _paths(value: Any, prefix: tuple = ()) -> list[tuple]:
    """Paths to the values of a report (the first 2 items of each list)."""
    out = [prefix] if prefix else []
    items = value.items() if isinstance(value, dict) else enumerate(value[:2]) if isinstance(value, list) else ()
    for key, item in items:
        out += _paths(item, prefix + (key,))
    return out


JSON = st.recursive(st.none() | st.booleans() | st.integers() | st.floats() | st.text(max_size=5),
                    lambda inner: st.lists(inner, max_size=3) | st.dictionaries(st.text(max_size=3), inner, max_size=3),
                    max_leaves=6)


@settings(max_examples=15, derandomize=True, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(data=st.data())
def test_any_json_anywhere_in_a_report_still_gives_a_page(report: dict[str, Any], data: st.DataObject) -> None:
    report = json.loads(json.dumps(report))
    report["trial"] = {"index": 3, "seed": 1, "error": None}
    paths = _paths(report)
    for _ in range(data.draw(st.integers(1, 3))):
        path = data.draw(st.sampled_from(paths))
        target = report
        try:
            for key in path[:-1]:
                target = target[key]
            target[path[-1]] = data.draw(JSON)
        except (KeyError, IndexError, TypeError):
            pass  # an earlier change replaced what this path went through
    assert run_page(report).endswith("</html>\n") and trial_page(report).endswith("</html>\n")
    distribution_figures([normalise(report)])


def test_several_runs_on_one_page(report: dict[str, Any]) -> None:
    both = {"goal_holds": True, "injected": [], "failures": report["failures"],
            "runs": [report, dict(report, scenario="second")]}
    page = run_page(both)
    assert set(_figures(page)) == {"run0-scene", "run0-timeline", "run1-scene", "run1-timeline"}
    assert 'id="runs-table"' in page and _plotly_copies(page) == 1


def _campaign(tmp_path: Path, report: dict[str, Any]) -> Path:
    bad = dict(report, goal_holds=False, stopped="gave up", failures=[dict(report["failures"][0], outcome="gave up")])
    errored = dict(report, trial={"error": "worker died twice"})
    return write_campaign(tmp_path / "camp", [report, bad, errored])


def test_campaign_page_and_a_page_per_trial(tmp_path: Path, report: dict[str, Any]) -> None:
    folder = _campaign(tmp_path, report)
    facts = write_report(folder, tmp_path / "out" / "campaign.html")
    assert facts["kind"] == "campaign" and facts["trials"] == 3 and facts["failed"] == 2
    page = (tmp_path / "out" / "campaign.html").read_text()
    assert _plotly_copies(page) == 1 and 'id="failed-table"' in page and 'id="trials-table"' in page
    figures = _figures(page)
    assert "modes-plot" in figures and sum(d.startswith("dist-") for d in figures) >= 10
    assert "0 in every trial: " in page and "RE Range Errors" in page  # named, not drawn
    links = re.findall(r'<a href="([^"]+)"', page.replace(plotly_js(), ""))
    assert len(links) == 2 + 3 and all((tmp_path / "out" / link).is_file() for link in links)
    trial = (folder / "report" / "trial-00001.html").read_text()
    assert 'src="plotly.min.js"' in trial and _plotly_copies(trial) == 0 and (folder / "report" / "plotly.min.js").is_file()
    # the copy they share is the smallest bundle that draws every trial page (the run pages' gl3d)
    assert (folder / "report" / "plotly.min.js").read_text() == bundle_for(trace_types(trial) or ()).text()
    assert '<a href="../../out/campaign.html"' in trial and 'id="trial-table"' in trial
    assert "worker died twice" in page and "stopped: gave up" in page


def test_campaign_distributions_and_why_trials_failed(report: dict[str, Any]) -> None:
    trials = [dict(report, trial={"index": i, "time_s": 1.0 + i}) for i in range(4)]
    figs = dict(distribution_figures(trials))
    assert figs["TDM"]["data"][0]["y"] == [report["metrics"]["static"]["TDM"]] * 4
    assert figs["time_s"]["data"][0]["y"] == [1.0, 2.0, 3.0, 4.0] and "(s)" in figs["time_s"]["layout"]["title"]["text"]
    assert failed_because(report) is None and failed_because(dict(report, goal_holds=False)) == "the goal does not hold"


def test_a_campaign_with_no_trials_yet(tmp_path: Path) -> None:
    folder = tmp_path / "empty"
    folder.mkdir()
    (folder / "campaign.json").write_text(json.dumps({"method": "basic", "seed": 0, "trials": 5, "summary": {}}))
    page = campaign_page(folder)
    assert "The folder has no trial yet" in page and "No trial failed" in page


# --- the command ------------------------------------------------------------------------------

def test_kitkb_report_writes_the_page(tmp_path: Path, report: dict[str, Any], capsys) -> None:
    (tmp_path / "run.json").write_text(json.dumps(report))
    assert main(["report", str(tmp_path / "run.json"), "-o", str(tmp_path / "run.html")]) == 0
    err = capsys.readouterr().err
    assert err.startswith(f"kitkb: wrote {tmp_path / 'run.html'} (1 run, 1 failure;") and err.count("\n") == 1
    assert main(["report", str(_campaign(tmp_path, report)), "-o", str(tmp_path / "c.html"), "--format", "json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["command"] == "report" and data["kind"] == "campaign" and data["trials"] == 3


def test_a_report_in_memory_is_written_too(tmp_path: Path, report: dict[str, Any]) -> None:
    """``kitkb run --report-html`` hands the report over without a file."""
    facts = write_report(report, tmp_path / "run.html")
    assert facts["kind"] == "run" and facts["scene"] and (tmp_path / "run.html").read_text().endswith("</html>\n")
    with pytest.raises(ValueError):
        write_report({"not": "a report"}, tmp_path / "x.html")


@pytest.mark.parametrize("name, content, message", [
    ("run.json", "{\n  \"scenario\": \"x\",\n  oops\n}", r"run\.json:3: error: not JSON: Expecting property name"),
    ("run.json", "[1, 2]", r"run\.json: error: not a kitkb run report"),
    ("run.json", '{"scenario": "x", "failures": []}', r"run\.json: error: not a kitkb run report"),
    ("run.json", "\xff\xfe", r"run\.json: error: not UTF-8 text"),
    ("run.json", "[" * 100_000, r"run\.json:1: error: not JSON|run\.json: error: not a kitkb report"),
    ("missing.json", None, r"missing\.json: error: no such file or folder"),
    ("folder", "dir", r"folder: error: not a campaign folder: it has no campaign\.json"),
    ("badtrial", "campaign", r"00001\.json: error: not a kitkb trial report"),
])
def test_bad_inputs_are_one_line_and_exit_2(tmp_path: Path, capsys, name: str, content: str | None,
                                            message: str) -> None:
    path = tmp_path / name
    if content == "dir":
        path.mkdir()
    elif content == "campaign":
        write_campaign(path, [])
        (path / "trials" / "00001.json").write_text('{"a": 1}')
    elif content is not None:
        path.write_bytes(content.encode("latin-1") if content.startswith("\xff") else content.encode())
    assert main(["report", str(path), "-o", str(tmp_path / "r.html")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and re.search(message, err), err
    assert not (tmp_path / "r.html").exists()


def test_the_report_is_never_written_over_its_input(tmp_path: Path, report: dict[str, Any], capsys) -> None:
    (tmp_path / "run.json").write_text(json.dumps(report))
    assert main(["report", str(tmp_path / "run.json"), "-o", str(tmp_path / "run.json")]) == 2
    assert "refusing to write over" in capsys.readouterr().err
    assert json.loads((tmp_path / "run.json").read_text()) == report
