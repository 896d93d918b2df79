"""What the replay costs a run's page (issue 31 point 3): the same run's page with its replay and
without it (the report without ``commands``, as a report written before the replay), written by
``kb.report.write_report`` and loaded in headless Chromium (Debian's ``chromium``, software
WebGL), taking turns in one browser; then the player's own costs in the browser.

The run: ``kitkb scenario generate --parts N --kits 1 --seed 0`` (default 160 parts, as
bench_report.py), ``kitkb run ... --faults missed-grasp@6,dropped-part=0.02 --seed 1 --report``.
Timed, medians of ``--repeat``:

* the report's size with and without ``commands``; the page's size; writing the page in one
  process (``write_report``, after a first call);
* loading: first contentful paint, every figure drawn (``<body data-drawn-ms>``), and the player
  ready (``window.kitkbReplays`` set), from navigation start;
* the player: one frame at a random time (``seek``: the tip, every object's corners, the
  panel, one ``Plotly.restyle``), one step of an action with ``g`` (the first 40 actions), one
  command step.

    .venv/bin/python benchmarks/bench_replay.py                 # 160 parts, 5 runs
    .venv/bin/python benchmarks/bench_replay.py --parts 40 --repeat 3 --no-doc

Results are appended to ``benchmarks/results/replay.json``; the run rewrites the "## Run page
replay" section of ``docs/benchmarks.md``.
"""

from __future__ import annotations

import argparse
import datetime as dt
import json
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))
sys.path.insert(0, str(ROOT / "tests"))

from common import cpu_model, write_doc  # noqa: E402

RESULTS = ROOT / "benchmarks" / "results" / "replay.json"
TITLE = "Run page replay"
KITKB = [sys.executable, "-m", "kb.cli"]

READY = """new Promise((resolve, reject) => {
  const t0 = performance.now();
  const check = () => {
    if (window.kitkbReplays && window.kitkbReplays['run-scene']) return resolve(window.kitkbReplays['run-scene'].readyMs);
    if (performance.now() - t0 > 30000) return reject(new Error('no replay'));
    setTimeout(check, 5);
  };
  check();
})"""

FRAMES = """(() => {
  const r = window.kitkbReplays['run-scene'];
  r.seek(1e9); const tEnd = r.state().t;
  const frames = [];
  for (let i = 0; i < %d; i++) { const t0 = performance.now(); r.seek(tEnd * ((i * 0.6180339) %% 1)); frames.push(performance.now() - t0); }
  frames.sort((a, b) => a - b);
  return {frame_ms: frames[frames.length >> 1], frame_p95_ms: frames[Math.floor(frames.length * 0.95)],
          commands: r.state().commands};
})()"""

#: stepping actions with g from the start: as many as ``STEPS``, the time of each
STEPS = 40
STEPPING = """(() => {
  const r = window.kitkbReplays['run-scene'];
  r.toCommand(0);
  const steps = [];
  while (steps.length < %d && r.state().done < r.state().commands) {
    const t0 = performance.now(); r.action(); steps.push(performance.now() - t0);
  }
  r.toCommand(0); let t0 = performance.now(); r.command(); const one = performance.now() - t0;
  steps.sort((a, b) => a - b);
  return {action_step_ms: steps[steps.length >> 1], action_steps: steps.length, command_step_ms: one};
})()"""


def kitkb(*args: str) -> float:
    t = time.perf_counter()
    subprocess.run(KITKB + list(args), check=True, cwd=ROOT, stdout=subprocess.DEVNULL)
    return time.perf_counter() - t


def median(values: list[float]) -> float:
    return round(statistics.median(values), 3)


def make_run(folder: Path, parts: int) -> tuple[dict[str, Any], dict[str, Any]]:
    kitkb("scenario", "generate", "--parts", str(parts), "--kits", "1", "--seed", "0", "-o", str(folder), "-q")
    kitkb("run", str(folder / "init.ttl"), str(folder / "goal.ttl"), "-o", str(folder / "out"), "--faults",
          "missed-grasp@6,dropped-part=0.02", "--seed", "1", "--report", str(folder / "run.json"), "-q")
    report = json.loads((folder / "run.json").read_text())
    without = {k: v for k, v in report.items() if k != "commands"}
    facts = {"actions": report.get("actions"), "failures": len(report.get("failures") or []),
             "commands": len(report["commands"]["rows"]), "objects": len(report["scene"]["objects"]),
             "report_bytes": len(json.dumps(report)), "report_without_commands_bytes": len(json.dumps(without)),
             "tet_s": report["metrics"]["static"]["TET"]}
    return {"replay": report, "no replay": without}, facts


def write_pages(reports: dict[str, dict[str, Any]], folder: Path, repeat: int) -> dict[str, dict[str, Any]]:
    from kb.report import write_report
    out = {}
    for name, report in reports.items():
        page = folder / f"{name.replace(' ', '-')}.html"
        write_report(report, page)
        times = []
        for _ in range(repeat):
            t = time.perf_counter()
            write_report(report, page)
            times.append(time.perf_counter() - t)
        out[name] = {"page": page, "write_s": median(times), "page_bytes": page.stat().st_size}
    return out


def load(pages: dict[str, dict[str, Any]], repeat: int, frames: int) -> dict[str, dict[str, Any]]:
    from test_report_browser import Browser, chromium_path
    binary = chromium_path()
    if binary is None:
        return {name: {"error": "no Chromium"} for name in pages}
    samples: dict[str, list[dict[str, Any]]] = {name: [] for name in pages}
    with tempfile.TemporaryDirectory(prefix="kitkb-bench-replay-") as profile:
        browser = Browser(binary, profile)
        try:
            browser.open(pages["replay"]["page"].as_uri())  # the first load apart
            for _ in range(repeat):  # loading, taking turns; nothing else runs in the browser meanwhile
                for name, page in pages.items():
                    samples[name].append(_open(browser, page["page"].as_uri(), False, frames))
            player = [_open(browser, pages["replay"]["page"].as_uri(), True, frames) for _ in range(repeat)]
        finally:
            browser.close()
    out = {}
    for name, runs in samples.items():
        keys = [k for k in runs[0] if isinstance(runs[0][k], (int, float))]
        out[name] = {k: median([r[k] for r in runs if isinstance(r.get(k), (int, float))]) for k in keys}
        out[name]["errors"] = sorted({e for r in runs for e in r.get("errors", [])})
    keys = [k for k in player[0] if isinstance(player[0][k], (int, float)) and k not in ("paint_ms", "drawn_ms", "player_ready_ms")]
    out["replay"].update({k: median([r[k] for r in player]) for k in keys})
    out["replay"]["errors"] = sorted(set(out["replay"]["errors"]) | {e for r in player for e in r.get("errors", [])})
    return out


def _open(browser: Any, url: str, replay: bool, frames: int) -> dict[str, Any]:
    from test_report_browser import DRAWN
    target = browser.send("Target.createTarget", url="about:blank")["targetId"]
    session = browser.send("Target.attachToTarget", targetId=target, flatten=True)["sessionId"]
    try:
        for domain in ("Page", "Runtime", "Log"):
            browser.send(f"{domain}.enable", session)
        browser.events.clear()
        browser.send("Page.navigate", session, url=url)
        browser.wait_event("Page.loadEventFired", session)
        browser.evaluate(session, DRAWN)
        facts = browser.evaluate(session, "({paint_ms: (performance.getEntriesByName('first-contentful-paint')[0] "
                                          "|| {startTime: null}).startTime, drawn_ms: Number(document.body.dataset.drawnMs)})")
        facts["player_ready_ms"] = browser.evaluate(session, READY) if "kitkbReplays" in str(
            browser.evaluate(session, "Object.keys(window).filter(k => k.startsWith('kitkb')).join(' ')")) else None
        if replay:
            facts.update(browser.evaluate(session, FRAMES % frames))
            facts.update(browser.evaluate(session, STEPPING % STEPS))
        facts["errors"] = browser.console_errors(session)
        return facts
    finally:
        browser.send("Target.closeTarget", targetId=target)


def chromium_version() -> str:
    from test_report_browser import chromium_path
    binary = chromium_path()
    if binary is None:
        return "no Chromium"
    return subprocess.run([binary, "--version"], capture_output=True, text=True).stdout.strip()


def render(r: dict[str, Any]) -> str:
    f, w, b = r["run"], r["writing"], r["loading"]
    rb, nb = b["replay"], b["no replay"]
    lines = [f"## {TITLE}", "",
             "Command: `.venv/bin/python benchmarks/bench_replay.py` (raw figures in `benchmarks/results/replay.json`).", "",
             f"Machine: {r['machine']}, {r['cpus']} cores, Python {r['python']}, {r['chromium']} (headless, software "
             f"WebGL: SwiftShader); run {r['when']} at commit `{r['commit']}`, 1-minute load average {r['load'][0]:.2f} "
             f"at the start and {r['load'][1]:.2f} at the end (the machine is shared: wall times are noisy). Medians of "
             f"{r['repeat']} loads of each page taking turns in one browser (the first load apart), then "
             f"{r['repeat']} loads of the replay's page for the player's times.", "",
             f"The run: `kitkb scenario generate --parts {r['parts']} --kits 1 --seed 0`, `kitkb run ... --faults "
             f"missed-grasp@6,dropped-part=0.02 --seed 1 --report run.json` ({f['actions']} actions, {f['failures']} "
             f"failures, {f['commands']:,} CRCL commands, {f['objects']} objects, TET {f['tet_s']:.1f} s on the cell's "
             f"clock). The page without replay is the same report without `commands` (as one written before issue 31).", "",
             "| | without replay | with replay | ratio |", "|---|---:|---:|---:|",
             f"| report JSON (MB) | {f['report_without_commands_bytes'] / 1e6:.2f} | {f['report_bytes'] / 1e6:.2f} | "
             f"{f['report_bytes'] / f['report_without_commands_bytes']:.2f} |",
             f"| page (MB) | {w['no replay']['page_bytes'] / 1e6:.2f} | {w['replay']['page_bytes'] / 1e6:.2f} | "
             f"{w['replay']['page_bytes'] / w['no replay']['page_bytes']:.2f} |",
             f"| `write_report` in one process (s) | {w['no replay']['write_s']:.2f} | {w['replay']['write_s']:.2f} | "
             f"{w['replay']['write_s'] / w['no replay']['write_s']:.2f} |",
             f"| Chromium: first contentful paint (s) | {nb['paint_ms'] / 1000:.2f} | {rb['paint_ms'] / 1000:.2f} | "
             f"{rb['paint_ms'] / nb['paint_ms']:.2f} |",
             f"| Chromium: every figure drawn (s) | {nb['drawn_ms'] / 1000:.2f} | {rb['drawn_ms'] / 1000:.2f} | "
             f"{rb['drawn_ms'] / nb['drawn_ms']:.2f} |",
             f"| Chromium: the player ready (s) | &ndash; | {rb['player_ready_ms'] / 1000:.2f} | |", "",
             f"The player, in the same browser (medians): one frame at a random time (tip, {f['objects']} objects' "
             f"corners, the panel, one `Plotly.restyle`) {rb['frame_ms']:.1f} ms (95th percentile "
             f"{rb['frame_p95_ms']:.1f} ms); one action step with `g` {rb['action_step_ms']:.1f} ms (the first "
             f"{int(rb['action_steps'])} actions); one command step {rb['command_step_ms']:.1f} ms. Console errors: "
             f"{', '.join(rb['errors'] + nb['errors']) or 'none'}.", "",
             f"Reading it: the replay adds {(w['replay']['page_bytes'] - w['no replay']['page_bytes']) / 1e6:.2f} MB to "
             f"the page and {(f['report_bytes'] - f['report_without_commands_bytes']) / 1e6:.2f} MB to the report (the "
             f"`commands` rows, {(f['report_bytes'] - f['report_without_commands_bytes']) / f['commands']:.0f} bytes a "
             f"command: its text, times, tip, path, the eleven metrics and a settings number), and nothing to the time "
             f"to the first paint or to every figure drawn: the player starts once the figures are drawn "
             f"({(rb['player_ready_ms'] - rb['drawn_ms']):.0f} ms after). Writing the page takes "
             f"{w['replay']['write_s'] - w['no replay']['write_s']:.2f} s more (what was grasped and released, "
             f"kb.metrics.handling, over {f['commands']:,} commands and {f['objects']} objects). A frame of "
             f"{rb['frame_ms']:.0f} ms is about {1000 / rb['frame_ms']:.0f} frames a second while playing in software "
             f"WebGL. Not measured here: a campaign's trial reports grow by the same share (each carries its "
             f"`commands`).", ""]
    return "\n".join(lines)


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--parts", type=int, default=160)
    p.add_argument("--repeat", type=int, default=5)
    p.add_argument("--frames", type=int, default=60)
    p.add_argument("--no-doc", action="store_true")
    p.add_argument("--render", action="store_true", help="only rewrite the section from the latest results")
    args = p.parse_args()
    if args.render:
        write_doc(TITLE, render(json.loads(RESULTS.read_text())[-1]))
        return 0
    load_start = os.getloadavg()[0]
    with tempfile.TemporaryDirectory(prefix="kitkb-bench-replay-") as tmp:
        folder = Path(tmp)
        reports, facts = make_run(folder / "run", args.parts)
        writing = write_pages(reports, folder, args.repeat)
        loading = load(writing, args.repeat, args.frames)
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True, cwd=ROOT).stdout.strip()
    result = {"when": dt.datetime.now(dt.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"), "commit": commit,
              "machine": cpu_model(), "cpus": os.cpu_count(), "python": platform.python_version(),
              "chromium": chromium_version(), "parts": args.parts, "repeat": args.repeat, "run": facts,
              "writing": {k: {kk: vv for kk, vv in v.items() if kk != "page"} for k, v in writing.items()},
              "loading": loading, "load": [load_start, os.getloadavg()[0]]}
    RESULTS.parent.mkdir(parents=True, exist_ok=True)
    history = json.loads(RESULTS.read_text()) if RESULTS.exists() else []
    RESULTS.write_text(json.dumps(history + [result], indent=1) + "\n")
    print(json.dumps(result, indent=1))
    if not args.no_doc:
        write_doc(TITLE, render(result))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
