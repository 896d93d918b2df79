"""The report page of a big run: ``kitkb report`` writing it, headless Chromium loading it.

The run: ``kitkb scenario generate --parts N --kits 1 --seed 0`` (default 160 parts), run by
``kitkb run INIT GOAL --faults missed-grasp@6,dropped-part=0.02 --seed 1 --report run.json``
(the report as users get it: scene, path, timeline, metrics, kits where the checkout writes
them). Timed, medians of ``--repeat``:

* writing: ``python -m kb.cli report run.json -o run.html`` as a user runs it (interpreter,
  imports, reading, drawing, writing), and ``kb.report.write_report`` in one process (the first
  call apart: it reads plotly.js from disk);
* loading: the page opened in headless Chromium (Debian's ``chromium``, software WebGL) over the
  DevTools protocol, one browser, a new tab each time (the first load apart): the first
  contentful paint (text and tables), the load event, and every figure drawn (the page's own
  mark, ``<body data-drawn-ms>``), all from navigation start;
* a campaign folder of ``--campaign-trials`` trials (copies of the small-kit run with a missed
  grasp, tests/test_report_inputs.py): writing its page and a page per trial, and loading the
  campaign page;
* with ``--baseline DIR`` (a checkout of an earlier commit, e.g. a ``git worktree``), the same
  pages written by that checkout's ``kitkb report`` from the same run, timed side by side:
  writing and loading take turns (baseline, now, baseline, ...), one browser for both;
* what any page costs (floors): plotly.js alone, full and each partial bundle kb.report ships,
  and a one-point 3-D figure (WebGL set-up).

    git worktree add /tmp/kitkb-ref-report COMMIT
    .venv/bin/python benchmarks/bench_report.py --baseline /tmp/kitkb-ref-report   # 160 parts, 5 runs, 100 trials
    .venv/bin/python benchmarks/bench_report.py --parts 40 --repeat 3 --no-doc
    .venv/bin/python benchmarks/bench_report.py --render          # the section from the latest results

Results are appended to ``benchmarks/results/report.json``; the run rewrites the "## Report
pages" section of ``docs/benchmarks.md``.
"""

from __future__ import annotations

import argparse
import contextlib
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
from typing import Any, Iterator

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))
sys.path.insert(0, str(ROOT / "tests"))

from common import cpu_model, write_doc  # noqa: E402

RESULTS = ROOT / "benchmarks" / "results" / "report.json"
TITLE = "Report pages"
KITKB = [sys.executable, "-m", "kb.cli"]
GOAL_S = 3.0


def kitkb(*args: str, cwd: Path = ROOT) -> float:
    """Run a kitkb command of the checkout ``cwd`` (its ``kb`` package comes first); its wall time."""
    t = time.perf_counter()
    subprocess.run(KITKB + list(args), check=True, cwd=cwd, stdout=subprocess.DEVNULL)
    return time.perf_counter() - t


def make_run(folder: Path, parts: int) -> tuple[Path, dict[str, Any]]:
    """The generated scenario run with faults; its report's path and what it holds."""
    kitkb("scenario", "generate", "--parts", str(parts), "--kits", "1", "--seed", "0", "-o", str(folder), "-q")
    seconds = kitkb("run", str(folder / "init.ttl"), str(folder / "goal.ttl"), "-o", str(folder / "out"),
                    "--faults", "missed-grasp@6,dropped-part=0.02", "--seed", "1", "--report", str(folder / "run.json"),
                    "-q")
    report = json.loads((folder / "run.json").read_text())
    facts = {"run_s": round(seconds, 2), "report_bytes": (folder / "run.json").stat().st_size,
             "actions": report.get("actions"), "failures": len(report.get("failures") or []),
             "sections": [k for k in ("scene", "path", "timeline", "metrics", "kits") if k in report],
             "objects": len((report.get("scene") or {}).get("objects") or []),
             "path_points": sum(len(p.get("points") or []) for p in report.get("path") or []),
             "timeline_events": len(report.get("timeline") or [])}
    return folder / "run.json", facts


def median(values: list[float]) -> float:
    return round(statistics.median(values), 3)


def time_writing(source: Path, outs: dict[str, tuple[Path, Path]], repeat: int) -> dict[str, dict[str, Any]]:
    """Whole-process times of writing the page of ``source`` with each checkout (name -> (checkout,
    page)), taking turns; for this checkout also in one process."""
    whole: dict[str, list[float]] = {name: [] for name in outs}
    for _ in range(repeat):
        for name, (cwd, out) in outs.items():
            whole[name].append(kitkb("report", str(source), "-o", str(out), "-q", cwd=cwd))
    result = {name: {"process_s": median(w), "process_best_s": round(min(w), 3),
                     "page_bytes": outs[name][1].stat().st_size} for name, w in whole.items()}
    from kb.report import write_report
    out = outs["now"][1]
    t = time.perf_counter()
    facts = write_report(source, out)
    first = time.perf_counter() - t
    inproc = []
    for _ in range(repeat):
        t = time.perf_counter()
        write_report(source, out)
        inproc.append(time.perf_counter() - t)
    result["now"].update(first_in_process_s=round(first, 3), in_process_s=median(inproc),
                         facts={k: v for k, v in facts.items() if k != "output"})
    return result


def _browser() -> Any:
    from test_report_browser import Browser, chromium_path
    binary = chromium_path()
    if binary is None:
        return None
    profile = tempfile.TemporaryDirectory(prefix="kitkb-bench-chromium-")
    browser = Browser(binary, profile.name)
    browser.profile_dir, browser.binary = profile, binary  # kept alive with the browser
    return browser


def _close(browser: Any) -> None:
    browser.close()
    browser.profile_dir.cleanup()


def time_loading(urls: dict[str, str], repeat: int) -> dict[str, dict[str, Any]]:
    """Times of loading each page (name -> url) in headless Chromium: its first load in a new
    browser apart, then ``repeat`` loads taking turns in one browser, medians."""
    firsts = {}
    for name, url in urls.items():
        browser = _browser()
        if browser is None:
            return {name: {"error": "no Chromium (scripts/setup.sh installs Debian's chromium)"} for name in urls}
        try:
            firsts[name] = browser.open(url)
        finally:
            _close(browser)
    browser = _browser()
    loads: dict[str, list[dict[str, Any]]] = {name: [] for name in urls}
    try:
        for _ in range(repeat):
            for name, url in urls.items():
                loads[name].append(browser.open(url))
    finally:
        _close(browser)
    version = subprocess.run([browser.binary, "--version"], capture_output=True, text=True).stdout.strip()
    return {name: _load_facts(firsts[name], loads[name], version) for name in urls}


def _load_facts(first: dict[str, Any], rest: list[dict[str, Any]], chromium: str) -> dict[str, Any]:
    keys = ("paint_ms", "load_ms", "drawn_ms", "plotly_ms")

    def seconds(values: list[Any]) -> float | None:  # None where the browser (or the page) recorded no time
        numbers = [v / 1000 for v in values if isinstance(v, (int, float))]
        return median(numbers) if numbers else None
    facts = {"first": {k: round(first[k]) if isinstance(first.get(k), (int, float)) else None for k in keys},
             **{k.replace("_ms", "_s"): seconds([f.get(k) for f in rest]) for k in keys},
             "drawn_best_s": round(min(f["drawn_ms"] for f in rest) / 1000, 3),
             "errors": sorted({e for f in [first, *rest] for e in f["errors"]}), "figures": len(first["figures"]),
             "chromium": chromium}
    figures = sorted({name for f in rest for name in f.get("draw_ms") or {}})
    if figures:
        facts["draw_s"] = {name: seconds([(f.get("draw_ms") or {}).get(name) for f in rest]) for name in figures}
    return facts


def floors(folder: Path, repeat: int) -> dict[str, Any]:
    """What any such page costs: plotly.js alone (no figure; the full one and each partial
    bundle), and a one-point 3-D figure (WebGL set-up) with the bundle a run's page gets, made
    with kb.report's own page and figure."""
    from kb.report.html import bundle_for, bundles, figure, page, plotly_js
    one = {"data": [{"type": "scatter3d", "x": [0], "y": [0], "z": [0]}], "layout": {"height": 620}}
    pages = {"plotly-only": page("plotly.js only", "<p>no figure</p>", plotly_js_text=plotly_js()),
             **{f"{b.name}-only": page(f"{b.name} only", "<p>no figure</p>", plotly_js_text=b.text())
                for b in bundles()},
             "one-point-3d": page("one point in 3-D", figure(one, "one"))}
    assert bundle_for({"scatter3d"}) is not None  # the one-point page gets a partial bundle
    for name, text in pages.items():
        (folder / f"{name}.html").write_text(text)
    return time_loading({name: (folder / f"{name}.html").as_uri() for name in pages}, repeat)


def campaign(folder: Path, trials: int, repeat: int, checkouts: dict[str, Path]) -> dict[str, Any]:
    """Write and load the page of a campaign folder of ``trials`` copies of the small-kit run,
    with each checkout (a folder of its own each: the trial pages are written inside it)."""
    from test_report_inputs import run_report, write_campaign
    base = run_report()
    outs = {}
    for name, cwd in checkouts.items():
        write_campaign(folder / f"campaign-{name}", [base] * trials)
        outs[name] = (cwd, folder / f"campaign-{name}.html")
    writing = time_writing_campaign(outs, repeat)
    loading = time_loading({name: out.as_uri() for name, (_, out) in outs.items()}, repeat)
    return {"trials": trials, **{name: {"writing": writing[name], "loading": loading[name]} for name in outs}}


def time_writing_campaign(outs: dict[str, tuple[Path, Path]], repeat: int) -> dict[str, dict[str, Any]]:
    """Whole-process times of ``kitkb report DIR -o PAGE`` per checkout, taking turns."""
    whole: dict[str, list[float]] = {name: [] for name in outs}
    for _ in range(repeat):
        for name, (cwd, out) in outs.items():
            source = out.with_name(out.stem)
            whole[name].append(kitkb("report", str(source), "-o", str(out), "-q", cwd=cwd))
    sizes = {name: out.stat().st_size + sum(p.stat().st_size for p in (out.with_name(out.stem) / "report").iterdir())
             for name, (_, out) in outs.items()}
    return {name: {"process_s": median(w), "process_best_s": round(min(w), 3),
                   "page_bytes": outs[name][1].stat().st_size,
                   "bytes": sizes[name]} for name, w in whole.items()}


@contextlib.contextmanager
def busy(n: int) -> Iterator[None]:
    """``n`` processes that keep a core busy each (as other jobs on a shared machine), stopped after."""
    procs = [subprocess.Popen([sys.executable, "-c", "while True: pass"]) for _ in range(n)]
    try:
        time.sleep(1.0)
        yield
    finally:
        for proc in procs:
            proc.kill()
            proc.wait()


def _commit(cwd: Path) -> str:
    return subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True,
                          cwd=cwd).stdout.strip()


def measure(args: argparse.Namespace) -> dict[str, Any]:
    import plotly
    checkouts = {"now": ROOT} if args.baseline is None else {"baseline": Path(args.baseline).resolve(), "now": ROOT}
    result: dict[str, Any] = {
        "date": dt.datetime.now(dt.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"), "parts": args.parts,
        "repeat": args.repeat, "cpu": cpu_model(), "cores": os.cpu_count(), "python": platform.python_version(),
        "plotly": plotly.__version__, "load_average": round(os.getloadavg()[0], 2), "commit": _commit(ROOT)}
    with tempfile.TemporaryDirectory(prefix="kitkb-bench-report-") as tmp:
        folder = Path(tmp)
        source, result["run"] = make_run(folder / "run", args.parts)
        outs = {name: (cwd, folder / f"run-{name}.html") for name, cwd in checkouts.items()}
        writing = time_writing(source, outs, args.repeat)
        loading = time_loading({name: out.as_uri() for name, (_, out) in outs.items()}, args.repeat)
        result["writing"], result["loading"] = writing["now"], loading["now"]
        if args.baseline is not None:
            result["baseline"] = {"commit": _commit(checkouts["baseline"]), "writing": writing["baseline"],
                                  "loading": loading["baseline"]}
        if args.busy:
            with busy(args.busy):
                before = os.getloadavg()[0]
                under = time_loading({name: out.as_uri() for name, (_, out) in outs.items()}, args.repeat)
                result["busy"] = {"processes": args.busy, "load_average": round(before, 2),
                                  "load_average_end": round(os.getloadavg()[0], 2), **under}
        result["floors"] = floors(folder, args.repeat)
        if args.campaign_trials:
            both = campaign(folder, args.campaign_trials, args.repeat, checkouts)
            result["campaign"] = {"trials": both["trials"], **both["now"]}
            if args.baseline is not None:
                result["baseline"]["campaign"] = both["baseline"]
    result["load_average_end"] = round(os.getloadavg()[0], 2)
    return result


def _s(value: Any) -> str:
    return f"{value:.2f}" if isinstance(value, (int, float)) else "&ndash;"


def _rows(r: dict[str, Any]) -> list[tuple[str, str, str]]:
    """(what, baseline, now) of the run's page, as table cells."""
    w, lo = r["writing"], r["loading"]
    b = r.get("baseline") or {}
    bw, bl = b.get("writing") or {}, b.get("loading") or {}
    rows = [("`kitkb report run.json -o run.html`, whole process (best)",
             f"{_s(bw.get('process_s'))} ({_s(bw.get('process_best_s'))})" if bw else None,
             f"{_s(w['process_s'])} ({_s(w['process_best_s'])})"),
            ("`kb.report.write_report` in one process, first call / again", None,
             f"{_s(w['first_in_process_s'])} / {_s(w['in_process_s'])}")]
    if "error" not in lo:
        rows += [("Chromium: first contentful paint (text, tables)", _s(bl.get("paint_s")), _s(lo["paint_s"])),
                 ("Chromium: load event (baseline: after plotly.js ran; now: before it runs)", _s(bl.get("load_s")),
                  _s(lo["load_s"])),
                 ("Chromium: **every figure drawn** (best)",
                  f"{_s(bl.get('drawn_s'))} ({_s(bl.get('drawn_best_s'))})" if bl else None,
                  f"{_s(lo['drawn_s'])} ({_s(lo['drawn_best_s'])})"),
                 ("Chromium, first page of a new browser: paint / load / drawn",
                  " / ".join(_s((bl["first"].get(k) or 0) / 1000) for k in ("paint_ms", "load_ms", "drawn_ms"))
                  if bl else None,
                  " / ".join(_s((lo["first"].get(k) or 0) / 1000) for k in ("paint_ms", "load_ms", "drawn_ms")))]
    u = r.get("busy")
    if u and "error" not in u["now"]:
        rows.append((f"Chromium: every figure drawn, {u['processes']} busy processes beside it (best)",
                     f"{_s(u['baseline']['drawn_s'])} ({_s(u['baseline']['drawn_best_s'])})"
                     if "baseline" in u else None,
                     f"{_s(u['now']['drawn_s'])} ({_s(u['now']['drawn_best_s'])})"))
    rows.append(("page size (MB)", f"{bw['page_bytes'] / 1e6:.1f}" if bw else None, f"{w['page_bytes'] / 1e6:.1f}"))
    return [(what, old or "&ndash;", new) for what, old, new in rows]


def render(r: dict[str, Any], history: list[dict[str, Any]] = ()) -> str:
    """The docs/benchmarks.md section of result ``r`` (``history``: the earlier results, for the
    latest one on another machine)."""
    w, lo, run = r["writing"], r["loading"], r["run"]
    b = r.get("baseline")
    lines = [f"## {TITLE}", "",
             "Command: `git worktree add /tmp/kitkb-ref-report COMMIT; .venv/bin/python benchmarks/bench_report.py "
             "--baseline /tmp/kitkb-ref-report` (raw figures in `benchmarks/results/report.json`).", "",
             f"Machine: {r['cpu']}, {r['cores']} cores, Python {r['python']}, plotly {r['plotly']}, "
             f"{lo.get('chromium', 'no Chromium')} (headless, software WebGL: SwiftShader); run {r['date']} at commit "
             f"`{r['commit']}`, 1-minute load average {r['load_average']} at the start and {r['load_average_end']} at "
             "the end (the machine is shared with other jobs: wall times are noisy). Medians of "
             f"{r['repeat']} runs" + (f", the baseline (commit `{b['commit']}`, the page before this work) and now "
                                     "taking turns, from the same run and in the same browser" if b else "") + ".", "",
             f"The run: `kitkb scenario generate --parts {r['parts']} --kits 1 --seed 0`, `kitkb run ... --faults "
             f"missed-grasp@6,dropped-part=0.02 --seed 1 --report run.json` ({run['actions']} actions, "
             f"{run['failures']} failures; report {run['report_bytes'] / 1e3:.0f} kB with "
             f"{', '.join(run['sections']) or 'no drawable section'}: {run['objects']} objects, "
             f"{run['path_points']} tool tip points, {run['timeline_events']} timeline events).", ""]
    if b:
        lines += ["| seconds | baseline | now |", "|---|---:|---:|"]
        lines += [f"| {what} | {old} | {new} |" for what, old, new in _rows(r)]
    else:
        lines += ["| seconds | now |", "|---|---:|"]
        lines += [f"| {what} | {new} |" for what, _, new in _rows(r)]
    draw = lo.get("draw_s") or {}
    if draw and lo.get("plotly_s") is not None:
        lines += ["", f"Where the time goes now (medians, seconds): plotly.js ready {lo['plotly_s']:.2f} s after "
                  "navigation started; then " + ", ".join(f"`{k}` drawn in {v:.2f}" for k, v in draw.items())
                  + f"; {lo.get('figures', '?')} figures, console errors: {len(lo.get('errors', [])) or 'none'}."]
    u = r.get("busy")
    if u and "error" not in u["now"]:
        un = u["now"]
        lines += ["", f"With {u['processes']} busy processes beside it (each `python -c 'while True: pass'`, at normal "
                  f"priority, started for that measurement only: 1-minute load average {u['load_average']} when they "
                  f"had run 1 s, {u['load_average_end']} at the end), the browser has about half the CPU it has "
                  f"otherwise: plotly.js ready at {_s(un.get('plotly_s'))} s, then "
                  + ", ".join(f"`{k}` drawn in {v:.2f}" for k, v in (un.get("draw_s") or {}).items()) + "."]
    fl = r.get("floors")
    if fl and all("error" not in v for v in fl.values()):
        only = ", ".join(f"{k.removesuffix('-only')} bundle {v['drawn_s']:.2f}" for k, v in fl.items()
                         if k.endswith("-only") and k != "plotly-only")
        lines += ["", "What any page drawn this way costs in the same browser (medians, seconds from navigation "
                  f"start to drawn): plotly.js alone, no figure: the full one {fl['plotly-only']['drawn_s']:.2f}, "
                  f"{only}; a one-point 3-D figure on the page a run gets (WebGL set-up, software rendering here): "
                  f"{fl['one-point-3d']['drawn_s']:.2f}."]
    c = r.get("campaign")
    if c:
        cw, cl = c["writing"], c["loading"]
        bc = (b or {}).get("campaign")
        was = (f" (baseline: written in {bc['writing']['process_s']:.2f} s, drawn in "
               f"{_s(bc['loading'].get('drawn_s'))} s, page {bc['writing']['page_bytes'] / 1e6:.1f} MB)") if bc else ""
        lines += ["", f"A campaign folder of {c['trials']} trials (copies of the small-kit run with a missed grasp): "
                  f"`kitkb report DIR -o campaign.html` writes the campaign page and {c['trials']} trial pages in "
                  f"{cw['process_s']:.2f} s (whole process; {cw['bytes'] / 1e6:.1f} MB in all, the campaign page "
                  f"{cw['page_bytes'] / 1e6:.1f} MB); Chromium draws the campaign page "
                  f"({cl.get('figures', '?')} figures) in {_s(cl.get('drawn_s'))} s, first paint "
                  f"{_s(cl.get('paint_s'))} s" + was + "."]
    if b and "error" not in lo and (b.get("loading") or {}).get("drawn_s"):
        lines += ["", "Reading it: the baseline inlined the plotly package's full plotly.js (4.7 MB) and let the "
                  "browser evaluate it where it stood; the page now inlines plotly's partial gl3d bundle (1.75 MB, "
                  "the trace types a run's page uses; a campaign's page gets the cartesian bundle), runs it after "
                  "the first paint, and draws the 3-D view at the screen's pixel ratio (plotly's default, 2, is four "
                  f"times the pixels on a common screen). Every figure drawn: {b['loading']['drawn_s']:.2f} s before, "
                  f"{lo['drawn_s']:.2f} s "
                  f"now ({b['loading']['drawn_s'] / lo['drawn_s']:.1f}x). What is left is mostly WebGL's set-up in "
                  "software (SwiftShader: the 3-D view's shaders are compiled and linked on the CPU, and the renderer "
                  "waits for them) and evaluating the bundle, which the page cannot avoid; a desktop browser with a "
                  "GPU on an idle machine does both far faster. docs/report.md (\"How the page loads\") says what "
                  "else was measured."]
    other = next((h for h in reversed(history) if h.get("cpu") != r["cpu"] and "error" not in h["loading"]), None)
    if other:
        lines += ["", f"The previous figures of this section were measured on another machine ({other['cpu']}, run "
                  f"{other['date']} at commit `{other['commit']}`, load average {other['load_average']} to "
                  f"{other['load_average_end']}): written in {other['writing']['process_s']:.2f} s, every figure drawn "
                  f"in {other['loading']['drawn_s']:.2f} s; they are in `benchmarks/results/report.json`."
                  + (f" The baseline column above is the page of commit `{b['commit']}` measured on this one."
                     if b else "")]
    write_ok = w["process_s"] < GOAL_S
    load_ok = "error" not in lo and lo["drawn_s"] < GOAL_S
    lines += ["", f"Goals (a {r['parts']}-part run's report written in under {GOAL_S:g} s and loaded by the browser "
              f"in under {GOAL_S:g} s): writing {'met' if write_ok else 'NOT met'} ({w['process_s']:.2f} s); "
              f"loading {'met' if load_ok else 'NOT met'} ({_s(lo.get('drawn_s'))} s to every figure "
              f"drawn, {_s(lo.get('paint_s'))} s to the first paint)"
              + (f"; with {r['busy']['processes']} busy processes beside the browser "
                 f"{'met' if r['busy']['now']['drawn_s'] < GOAL_S else 'NOT met'} ({_s(r['busy']['now']['drawn_s'])} s)"
                 if r.get("busy") and "error" not in r["busy"]["now"] else "") + "."]
    return "\n".join(lines) + "\n"


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--parts", type=int, default=160)
    p.add_argument("--repeat", type=int, default=5)
    p.add_argument("--campaign-trials", type=int, default=100, help="0: no campaign")
    p.add_argument("--baseline", metavar="DIR", help="a checkout of an earlier commit to time side by side")
    p.add_argument("--busy", type=int, default=2, metavar="N",
                   help="load the run's page again with N processes keeping a core busy each (0: not)")
    p.add_argument("--no-doc", action="store_true", help="do not rewrite docs/benchmarks.md")
    p.add_argument("--render", action="store_true", help="only rewrite the section from the latest results")
    args = p.parse_args()
    history = json.loads(RESULTS.read_text()) if RESULTS.exists() else []
    if not args.render:
        history.append(measure(args))
        RESULTS.parent.mkdir(parents=True, exist_ok=True)
        RESULTS.write_text(json.dumps(history, indent=1) + "\n")
    section = render(history[-1], history[:-1])
    print(section)
    if not args.no_doc:
        write_doc(TITLE, section)


if __name__ == "__main__":
    main()
