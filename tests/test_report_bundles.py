"""The partial plotly.js bundles kb.report ships (kb/report/js/, bundles.json): each is the
published npm file (its SHA-256), of the plotly package's plotly.js version, with its licence;
a page inlines the smallest one that draws its figures, the full plotly.js when none does, and
none without figures; the wheel carries them. tests/test_report_browser.py checks in Chromium
that each bundle holds the trace types bundles.json says."""

from __future__ import annotations

import hashlib
import json
import re
import subprocess
import sys
import zipfile
from importlib import resources
from pathlib import Path
from typing import Any

import plotly.offline
import pytest

from kb.report import campaign_page, run_page
from kb.report.html import bundle_for, bundles, figure, page, plotly_js, trace_types
from test_report_inputs import run_report, with_metrics, write_campaign

JS = resources.files("kb.report").joinpath("js")
REPO = Path(__file__).resolve().parent.parent


def _inlined(html: str) -> list[str]:
    """The licence headers of the plotly.js copies inlined in ``html``."""
    return re.findall(r"\* plotly\.js (?:\([^)]*\) )?v\d+\.\d+\.\d+", html)


@pytest.fixture(scope="module")
def report() -> dict[str, Any]:
    return with_metrics(run_report())


@pytest.mark.parametrize("bundle", bundles(), ids=lambda b: b.name)
def test_bundle_is_the_published_file_of_plotlys_version(bundle: Any) -> None:
    data = JS.joinpath(bundle.file).read_bytes()
    assert hashlib.sha256(data).hexdigest() == bundle.sha256
    assert bundle.version == plotly.offline.get_plotlyjs_version()  # update the bundles with plotly
    assert f"* plotly.js ({bundle.name} - minified) v{bundle.version}\n" in data[:200].decode()
    assert bundle.package == f"plotly.js-{bundle.name}-dist-min" and "scatter" in bundle.traces


def test_bundles_smallest_first_with_their_licence() -> None:
    sizes = [len(JS.joinpath(b.file).read_bytes()) for b in bundles()]
    assert len(sizes) == 2 and sizes == sorted(sizes) and sizes[-1] < len(plotly_js()) / 2
    assert "MIT License" in JS.joinpath("LICENSE").read_text() and "Plotly" in JS.joinpath("LICENSE").read_text()
    listed = {e["file"] for e in json.loads(JS.joinpath("bundles.json").read_text())["bundles"]}
    assert listed | {"LICENSE", "bundles.json"} == {p.name for p in JS.iterdir() if p.is_file()}


def test_the_smallest_bundle_with_every_trace_type() -> None:
    assert bundle_for({"scatter3d", "mesh3d", "scatter"}).name == "gl3d"
    assert bundle_for({"box", "bar", "scatter"}).name == "cartesian"
    assert bundle_for({"scatter"}).name == "cartesian" and bundle_for(set()).name == "cartesian"
    assert bundle_for({"bar", "scatter3d"}) is None and bundle_for({"scattergl"}) is None  # the full plotly.js


def test_a_figure_names_its_trace_types_and_names_cannot_forge_them() -> None:
    fig = figure({"data": [{"type": "mesh3d", "name": '" class="plot" data-traces="sankey'}, {"y": [1]}]}, "f")
    assert trace_types(fig) == {"mesh3d", "scatter"}  # no type: plotly's default, scatter
    assert trace_types("<p>no figure</p>") is None


def test_run_page_inlines_the_gl3d_bundle(report: dict[str, Any]) -> None:
    html = run_page(report)
    assert _inlined(html) == ["* plotly.js (gl3d - minified) v4.1.1"]
    assert bundles()[1].text() in html and plotly_js() not in html


def test_campaign_page_inlines_the_bundle_of_its_figures(tmp_path: Path, report: dict[str, Any]) -> None:
    html = campaign_page(write_campaign(tmp_path / "camp", [report, report]))
    chosen = bundle_for(trace_types(html) or set())
    assert len(_inlined(html)) == 1 and (chosen.text() if chosen else plotly_js()) in html


def test_page_without_figures_has_no_plotly_and_other_traces_get_the_full_one() -> None:
    assert 'id="kitkb-plotly-js"' not in page("none", "<p>text</p>") and "kitkbPlots" in page("n", "")
    full = page("gl", figure({"data": [{"type": "scattergl", "x": [1], "y": [1]}]}, "g"))
    assert plotly_js() in full and len(_inlined(full)) == 1
    odd = page("odd", figure({"data": [{"type": "Sankey_2", "x": [1]}]}, "o"))  # no bundle has it: the full one
    assert plotly_js() in odd
    assert page("forced", "<p>x</p>", plotly_js_text="/* js */").count("/* js */") == 1


@pytest.mark.slow
def test_wheel_carries_the_bundles(tmp_path: Path) -> None:
    subprocess.run([sys.executable, "-m", "pip", "wheel", "--no-deps", "-q", "-w", str(tmp_path), str(REPO)],
                   check=True)
    (whl,) = tmp_path.glob("kitkb-*.whl")
    names = set(zipfile.ZipFile(whl).namelist())
    assert {f"kb/report/js/{n}" for n in ("bundles.json", "LICENSE", *(b.file for b in bundles()))} <= names
