"""The report pages in a real browser: headless Chromium (Debian's ``chromium``, installed by
scripts/setup.sh) opens the page of a real run and of a campaign, and the tests check that the
plotly figures drew (the 3-D view's WebGL canvas, every plot's data), that the tables are
there, that nothing went to the console as an error, and take a screenshot (a PNG that is
not blank) into the test's folder.

One browser per module, driven over the DevTools protocol (``websocket-client``). Where no
Chromium is installed the tests are skipped with the reason, except in CI (``CI`` set), where
that is a failure: CI runs scripts/setup.sh, which installs it.
"""

from __future__ import annotations

import base64
import itertools
import json
import os
import shutil
import subprocess
import tempfile
import time
from pathlib import Path
from typing import Any, Iterator, Sequence

import pytest
import websocket

from kb.report import write_report
from kb.report.html import Bundle, bundles, page
from test_report_inputs import run_report, with_metrics, write_campaign

pytestmark = pytest.mark.slow

CANDIDATES = ("chromium", "chromium-browser", "google-chrome", "chrome")
#: How long a page may take to load and draw its figures before a test fails.
LOAD_TIMEOUT = 30.0


def chromium_path() -> str | None:
    """The Chromium to drive: ``$KITKB_CHROMIUM``, else the first on PATH."""
    env = os.environ.get("KITKB_CHROMIUM")
    if env:
        return env
    return next((p for p in map(shutil.which, CANDIDATES) if p), None)


class Browser:
    """A headless Chromium and one DevTools connection to it; :meth:`open` loads a page in a
    new tab and returns what the tests look at."""

    def __init__(self, binary: str, profile: str, flags: Sequence[str] = ()) -> None:
        args = [binary, "--headless", "--remote-debugging-port=0", f"--user-data-dir={profile}",
                "--no-first-run", "--no-default-browser-check", "--disable-extensions", "--mute-audio",
                "--enable-unsafe-swiftshader", "--window-size=1280,900", *flags, "about:blank"]
        if os.geteuid() == 0:
            args.insert(1, "--no-sandbox")  # Chromium's sandbox refuses to run as root
        self.profile = Path(profile)
        self.log = self.profile / "chromium.log"  # a file, not a pipe: a full pipe would stop Chromium
        with open(self.log, "w") as log:
            self.proc = subprocess.Popen(args, stdin=subprocess.DEVNULL, stdout=log, stderr=log)
        try:
            self.ws = websocket.create_connection(self._address(), timeout=LOAD_TIMEOUT, suppress_origin=True)
        except BaseException:
            self.proc.kill()
            self.proc.wait()
            raise
        self.ids = itertools.count(1)
        self.events: list[dict[str, Any]] = []

    def _address(self) -> str:
        """The browser's DevTools address, from the DevToolsActivePort file it writes in its profile."""
        deadline = time.monotonic() + LOAD_TIMEOUT
        port_file = self.profile / "DevToolsActivePort"
        while time.monotonic() < deadline and self.proc.poll() is None:
            lines = port_file.read_text().split() if port_file.exists() else []
            if len(lines) == 2:
                return f"ws://127.0.0.1:{lines[0]}{lines[1]}"
            time.sleep(0.05)
        self.proc.kill()
        raise RuntimeError("Chromium did not start: " + self.log.read_text()[-2000:])

    def send(self, method: str, session: str | None = None, **params: Any) -> dict[str, Any]:
        """One DevTools command; its result (events that arrive meanwhile are kept)."""
        ident = next(self.ids)
        message = {"id": ident, "method": method, "params": params}
        if session:
            message["sessionId"] = session
        self.ws.send(json.dumps(message))
        while True:
            answer = json.loads(self.ws.recv())
            if answer.get("id") == ident:
                if "error" in answer:
                    raise RuntimeError(f"{method}: {answer['error']}")
                return answer.get("result", {})
            self.events.append(answer)

    def wait_event(self, method: str, session: str, timeout: float = LOAD_TIMEOUT) -> None:
        deadline = time.monotonic() + timeout
        try:
            while time.monotonic() < deadline:
                if any(e.get("method") == method and e.get("sessionId") == session for e in self.events):
                    return
                self.ws.settimeout(max(0.05, deadline - time.monotonic()))
                self.events.append(json.loads(self.ws.recv()))
        except websocket.WebSocketTimeoutException:
            pass
        finally:
            self.ws.settimeout(LOAD_TIMEOUT)
        raise TimeoutError(f"no {method} in {timeout} s")

    def evaluate(self, session: str, expression: str) -> Any:
        """The value of a JavaScript expression (promises awaited)."""
        result = self.send("Runtime.evaluate", session, expression=expression, awaitPromise=True,
                           returnByValue=True, timeout=int(LOAD_TIMEOUT * 1000))
        if "exceptionDetails" in result:
            raise RuntimeError(f"{expression[:60]}...: {result['exceptionDetails']}")
        return result["result"].get("value")

    def open(self, url: str, screenshot: Path | None = None) -> dict[str, Any]:
        """Load ``url`` in a new tab and wait until every plot drew. The page's facts
        (:data:`FACTS`), its console errors, the seconds from navigation to loaded and to drawn,
        and with ``screenshot`` a PNG of the whole page there."""
        target = self.send("Target.createTarget", url="about:blank")["targetId"]
        session = self.send("Target.attachToTarget", targetId=target, flatten=True)["sessionId"]
        try:
            for domain in ("Page", "Runtime", "Log"):
                self.send(f"{domain}.enable", session)
            self.events.clear()
            t = time.perf_counter()
            self.send("Page.navigate", session, url=url)
            self.wait_event("Page.loadEventFired", session)
            loaded = time.perf_counter() - t
            facts = self.evaluate(session, DRAWN)
            drawn = time.perf_counter() - t
            facts.update(self.evaluate(session, FACTS))
            facts.update(errors=self.console_errors(session), loaded_s=loaded, drawn_s=drawn)
            if screenshot is not None:
                shot = self.send("Page.captureScreenshot", session, format="png", captureBeyondViewport=True)
                screenshot.write_bytes(base64.b64decode(shot["data"]))
                facts["screenshot"] = self.evaluate(session, PIXELS % json.dumps(shot["data"]))
            return facts
        finally:
            self.send("Target.closeTarget", targetId=target)

    def console_errors(self, session: str) -> list[str]:
        """The page's console errors, uncaught exceptions and error log entries so far."""
        out = []
        for e in self.events:
            if e.get("sessionId") != session:
                continue
            p = e.get("params", {})
            if e.get("method") == "Runtime.exceptionThrown":
                out.append(str(p.get("exceptionDetails", {}).get("exception", {}).get("description")
                               or p.get("exceptionDetails")))
            elif e.get("method") == "Runtime.consoleAPICalled" and p.get("type") in ("error", "assert"):
                out.append(" ".join(str(a.get("value", a.get("description"))) for a in p.get("args", [])))
            elif e.get("method") == "Log.entryAdded" and p.get("entry", {}).get("level") == "error":
                out.append(p["entry"].get("text", ""))
        return out

    def close(self) -> None:
        try:
            self.send("Browser.close")
        except Exception:
            pass
        self.ws.close()
        try:
            self.proc.wait(10)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()


#: A promise that resolves when the page says it drew every figure (``<body data-drawn="N">``,
#: kb.report.html.DRAW), or rejects after the load time-out.
DRAWN = """new Promise((resolve, reject) => {
  const t0 = performance.now();
  const check = () => {
    if (document.body && document.body.dataset.drawn !== undefined)
      return resolve({drawn: Number(document.body.dataset.drawn), plots: document.querySelectorAll('div.plot').length});
    if (performance.now() - t0 > %d) return reject(new Error('figures not drawn'));
    setTimeout(check, 20);
  };
  check();
})""" % int(LOAD_TIMEOUT * 1000)

#: What a test asserts of a page: each plot's id, trace count and points; the WebGL canvases
#: and their size; each table's id and rows; the links.
FACTS = """(() => ({
  title: document.title,
  figures: [...document.querySelectorAll('div.plot')].map(p => ({
    id: p.id, drawn: !!(p._fullLayout && p.data), traces: (p.data || []).length,
    types: [...new Set((p.data || []).map(d => d.type))],
    points: (p.data || []).reduce((n, d) => n + ((d.x && d.x.length) || (d.y && d.y.length) || 0), 0),
    scene: !!(p._fullLayout && p._fullLayout.scene), canvas: !!p.querySelector('.gl-container canvas')})),
  canvases: [...document.querySelectorAll('.gl-container canvas')].map(c => [c.width, c.height]),
  tables: Object.fromEntries([...document.querySelectorAll('table[id]')].map(t => [t.id, t.querySelectorAll('tbody tr').length])),
  links: [...document.querySelectorAll('a[href]')].map(a => a.getAttribute('href')),
  text: document.body.innerText,
  paint_ms: (performance.getEntriesByName('first-contentful-paint')[0] || {startTime: null}).startTime,
  load_ms: performance.getEntriesByType('navigation')[0].loadEventEnd,
  drawn_ms: Number(document.body.dataset.drawnMs),
  plotly_ms: (performance.getEntriesByName('kitkb-plotly-ready')[0] || {startTime: null}).startTime,
  draw_ms: Object.fromEntries(performance.getEntriesByType('measure').filter(m => m.name.startsWith('kitkb-draw '))
    .map(m => [m.name.slice(11), m.duration])),
}))()"""

#: The screenshot decoded by the browser itself: its size, how many colours, and the share of
#: pixels that are not the page's white.
PIXELS = """new Promise((resolve, reject) => {
  const img = new Image();
  img.onload = () => {
    const c = document.createElement('canvas'); c.width = img.width; c.height = img.height;
    const ctx = c.getContext('2d'); ctx.drawImage(img, 0, 0);
    const d = ctx.getImageData(0, 0, c.width, c.height).data;
    const colours = new Set(); let ink = 0;
    for (let i = 0; i < d.length; i += 4 * 7) {
      colours.add((d[i] << 16) | (d[i + 1] << 8) | d[i + 2]);
      if (d[i] < 235 || d[i + 1] < 235 || d[i + 2] < 235) ink++;
    }
    resolve({width: img.width, height: img.height, colours: colours.size, ink: ink / (d.length / 28)});
  };
  img.onerror = () => reject(new Error('screenshot is no image'));
  img.src = 'data:image/png;base64,' + %s;
})"""


@pytest.fixture(scope="module")
def browser() -> Iterator[Browser]:
    binary = chromium_path()
    if binary is None:
        if os.environ.get("CI"):
            pytest.fail("no Chromium on this CI machine: scripts/setup.sh installs Debian's chromium")
        pytest.skip("no Chromium here (scripts/setup.sh installs Debian's chromium)")
    with tempfile.TemporaryDirectory(prefix="kitkb-chromium-") as profile:
        b = Browser(binary, profile)
        try:
            yield b
        finally:
            b.close()


@pytest.fixture(scope="module")
def report() -> dict[str, Any]:
    return with_metrics(run_report())


def _assert_drawn(facts: dict[str, Any]) -> None:
    assert facts["errors"] == [], facts["errors"]
    assert facts["drawn"] == facts["plots"] == len(facts["figures"]) > 0
    assert all(f["drawn"] and f["traces"] > 0 and f["points"] > 0 for f in facts["figures"])
    assert all(f["canvas"] for f in facts["figures"] if f["scene"])  # WebGL drew the 3-D view
    shot = facts["screenshot"]
    assert shot["width"] >= 800 and shot["height"] > 900
    assert shot["colours"] > 50 and shot["ink"] > 0.02, shot  # not a blank page


def test_run_page_in_chromium(browser: Browser, report: dict[str, Any], tmp_path: Path) -> None:
    source = tmp_path / "run.json"
    source.write_text(json.dumps(report))
    write_report(source, tmp_path / "run.html")
    facts = browser.open((tmp_path / "run.html").as_uri(), screenshot=tmp_path / "run.png")
    _assert_drawn(facts)
    scene = [f for f in facts["figures"] if f["scene"]]
    assert len(scene) == 1 and "mesh3d" in scene[0]["types"] and "scatter3d" in scene[0]["types"]
    assert facts["canvases"] and all(w > 300 and h > 300 for w, h in facts["canvases"])
    assert [f["id"] for f in facts["figures"]] == ["run-scene", "run-timeline"]
    assert set(facts["draw_ms"]) == {"run-scene", "run-timeline"} and 0 < facts["plotly_ms"] < facts["drawn_ms"]
    assert facts["tables"]["metrics-table"] >= 11 + 5  # the static metrics and the execution metrics
    assert facts["tables"]["kits-table"] == 1 and facts["tables"]["failures-table"] == 1
    assert "missed-grasp" in facts["text"] and "Total Distance Moved" in facts["text"]
    assert (tmp_path / "run.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_page_without_sections_in_chromium(browser: Browser, tmp_path: Path) -> None:
    """An older report (no scene, path, timeline, metrics, kits) with names holding < and &:
    the page says what it lacks, shows the names as written, and runs no injected script."""
    old = {"scenario": "<script>alert(1)</script> & co", "seed": 0, "goal_holds": False, "stopped": "gave up",
           "actions": 3, "checks": 6, "replans": 0, "injected": [],
           "failures": [{"mode": "part-missing", "action_index": 2, "action": "take-part", "kit": "k<1>",
                         "objects": ["p&1"], "phase": "precondition", "violated": ["part-in(<p>)"],
                         "recovery": "stop", "outcome": "gave up"}], "time_s": 0.5}
    (tmp_path / "old.json").write_text(json.dumps(old))
    write_report(tmp_path / "old.json", tmp_path / "old.html")
    facts = browser.open((tmp_path / "old.html").as_uri(), screenshot=tmp_path / "old.png")
    assert facts["errors"] == [] and facts["figures"] == []
    assert "<script>alert(1)</script> & co" in facts["title"] and "part-in(<p>)" in facts["text"]
    assert "has no scene" in facts["text"] and "has no timeline" in facts["text"]


def test_campaign_pages_in_chromium(browser: Browser, report: dict[str, Any], tmp_path: Path) -> None:
    bad = dict(report, goal_holds=False, stopped="gave up after 3 retries",
               failures=[dict(report["failures"][0], outcome="gave up")])
    folder = write_campaign(tmp_path / "campaign", [report, bad, report])
    summary = write_report(folder, tmp_path / "campaign.html")
    assert summary["trials"] == 3 and summary["failed"] == 1
    facts = browser.open((tmp_path / "campaign.html").as_uri(), screenshot=tmp_path / "campaign.png")
    _assert_drawn(facts)
    assert facts["tables"]["failed-table"] == 1 and facts["tables"]["trials-table"] == 3
    assert len([f for f in facts["figures"] if f["id"].startswith("dist-")]) >= 10
    link = "campaign/report/trial-00001.html"
    assert link in facts["links"]
    trial = browser.open((tmp_path / link).as_uri(), screenshot=tmp_path / "trial.png")
    _assert_drawn(trial)  # its plotly.js is the copy beside it
    assert any(f["scene"] for f in trial["figures"]) and trial["tables"]["trial-table"] >= 5
    assert "../../campaign.html" in trial["links"]


def test_sweep_campaign_page_in_chromium(browser: Browser, report: dict[str, Any], tmp_path: Path) -> None:
    """A noise sweep's page (kitkb testmethod errors --noise-sweep): its summary made by
    kb.testmethod from the trials, as the command writes it; the detection rate and the false
    alarms drawn against the noise, a row per level in the table."""
    from kb.testmethod.summary import summarize
    sweep = "position=0mm:2mm:3"
    alarm = dict(report["failures"][0], objects=["part_nobody_touched"], action_index=1, mode="part-missing")
    rows = []
    for trial in range(2):
        for level in range(3):
            row = dict(report, failures=report["failures"] + ([alarm] if level == 2 else []))
            row["trial"] = {"index": 3 * trial + level, "seed": 100 + trial, "method": "errors",
                            "design": "kit_design_1", "layout": None, "time_s": 0.5, "error": None,
                            "noise": ["none", "position=1mm", "position=2mm"][level],
                            "sweep": {"trial": trial, "level": level}}
            rows.append(row)
    folder = tmp_path / "sweep"
    (folder / "trials").mkdir(parents=True)
    for row in rows:
        (folder / "trials" / f"{row['trial']['index']:05d}.json").write_text(json.dumps(row))
    summary = summarize(rows, sweep=sweep)
    meta = {"method": "errors", "seed": 7, "trials": 2, "summary": summary,
            "options": {"parts": [3], "kits": None, "faults": "missed-grasp@6", "noise_sweep": sweep}}
    (folder / "campaign.json").write_text(json.dumps(meta))
    write_report(folder, tmp_path / "sweep.html")
    facts = browser.open((tmp_path / "sweep.html").as_uri(), screenshot=tmp_path / "sweep.png")
    _assert_drawn(facts)
    figures = {f["id"]: f for f in facts["figures"]}
    assert figures["sweep-detection"]["traces"] == 2 and figures["sweep-detection"]["points"] == 6
    assert figures["sweep-false-alarms"]["points"] == 3
    assert facts["tables"]["sweep-table"] == 3 and facts["tables"]["trials-table"] == 6
    assert "Detection quality against sensor noise" in facts["text"] and "kit_design_1 @ position=2mm" in facts["text"]
    levels = summary["sweep"]["levels"]
    assert [lv["false_alarm_count"] for lv in levels] == [0, 0, 2] and levels[0]["detection"] == 1.0


@pytest.mark.parametrize("bundle", bundles(), ids=lambda b: b.name)
def test_bundle_has_the_trace_types_it_is_chosen_for(browser: Browser, bundle: Bundle, tmp_path: Path) -> None:
    """Each partial bundle of kb/report/js/ holds exactly the trace types bundles.json names, and
    is the version it says: kb.report picks a page's bundle by them."""
    schema = ('<pre id="schema"></pre><script>new MutationObserver(() => { if (window.Plotly) '
              'document.getElementById("schema").textContent = JSON.stringify([Plotly.version, '
              'Object.keys(Plotly.PlotSchema.get().traces).sort()]); }).observe(document.body, {attributes: true});'
              '</script>')  # when the page marks its body drawn, plotly.js has run
    (tmp_path / "bundle.html").write_text(page(bundle.name, schema, plotly_js_text=bundle.text()))
    facts = browser.open((tmp_path / "bundle.html").as_uri())
    assert facts["errors"] == []
    assert json.loads(facts["text"].strip()) == [bundle.version, sorted(bundle.traces)]
