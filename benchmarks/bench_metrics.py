"""The static metrics of a CRCL program: ``kitkb metrics PROGRAM`` on a generated program.

The program (``generate``: seeded, in metres) is what a kitting plan's CRCL looks like —
about 60 % moves (MoveTo, MoveStraightTo, a few MoveThroughTo), gripper commands, dwells,
messages, speed and acceleration settings — with a few faults mixed in (unreadable lines,
values out of range, useless commands), so every metric has work to do. Timed, medians of
``--repeat``:

* ``process``: ``python -m kb.cli metrics PROGRAM --format json`` as a user runs it (interpreter
  start, imports, reading, evaluation, output), wall time and the child's CPU time; also with
  ``--per-command`` (a JSON row per command), and the same program as CRCL XML;
* in one process: reading (``kb.metrics.read_steps``: the fast text path) against reading
  with ``kb.crcl.read_file`` and converting the commands (``steps_of``), and the evaluation
  (``static_metrics``) alone. The two readers must give the same steps (checked each run).

    .venv/bin/python benchmarks/bench_metrics.py                    # 100,000 commands, 5 runs
    .venv/bin/python benchmarks/bench_metrics.py --commands 10000 --repeat 3 --no-doc
    .venv/bin/python benchmarks/bench_metrics.py --render        # the section from the latest results

Results are appended to ``benchmarks/results/metrics.json``; the run rewrites the
"## CRCL metrics" section of ``docs/benchmarks.md``.
"""

from __future__ import annotations

import argparse
import datetime as dt
import json
import os
import platform
import random
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any, Callable

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

from common import cpu_model, write_doc  # noqa: E402

from kb.crcl import read_file, read_text, write_xml  # noqa: E402
from kb.metrics import read_steps, static_metrics, steps_of  # noqa: E402

RESULTS = ROOT / "benchmarks" / "results" / "metrics.json"
TITLE = "CRCL metrics"


def generate(commands: int, seed: int = 0, faults: bool = True) -> str:
    """A CRCL program of ``commands`` commands (InitCanon ... EndCanon), in metres."""
    rng = random.Random(seed)
    down = "{0, 0, -1}, {1, 0, 0}"
    lines = ["InitCanon()", 'SetLengthUnits("meter")', "SetRelativeSpeed(50)"]

    def pose() -> str:
        x, y, z = (round(rng.uniform(0.0, 2.0), 4) for _ in range(3))
        return f"{{{{{x}, {y}, {z}}}, {down}}}"

    while len(lines) < commands - 1:
        r = rng.random()
        if r < 0.45:
            lines.append(f"MoveTo({pose()})")
        elif r < 0.57:
            lines.append(f"MoveStraightTo({pose()})")
        elif r < 0.60:
            lines.append(f"MoveThroughTo({pose()}, {pose()}, {pose()}, 3)")
        elif r < 0.70:
            lines.append(rng.choice(["CloseGripper()", "OpenGripper()"]))
        elif r < 0.78:
            lines.append(f"Dwell({rng.choice([0.05, 0.1, 0.0])})")
        elif r < 0.86:
            lines.append(f'Message("take part part_b_{rng.randrange(1000)}")')
        elif r < 0.93:
            lines.append(f"SetRelativeSpeed({rng.randint(10, 100)})")
        elif r < 0.99:
            lines.append(f"SetAbsoluteAcceleration({rng.choice([0.5, 1, 2, 5])})")
        elif faults:
            lines.append(rng.choice(["SetRelativeAcceleration(-110)", "MoveStraightTo(87)", "Dwell(-1)",
                                     "SetAbsoluteSpeed(3.8)"]))
    lines.append("EndCanon()")
    return "\n".join(lines) + "\n"


def _process(args: list[str], repeat: int) -> dict[str, float]:
    """Medians of wall and CPU seconds of ``python -m kb.cli ARGS`` (output discarded)."""
    walls, cpus = [], []
    for _ in range(repeat):
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        start = time.perf_counter()
        done = subprocess.run([sys.executable, "-m", "kb.cli", *args], cwd=ROOT, stdout=subprocess.DEVNULL,
                              stderr=subprocess.PIPE, text=True)
        walls.append(time.perf_counter() - start)
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        if done.returncode != 0:
            raise SystemExit(f"kitkb {' '.join(args)} failed: {done.stderr.strip()}")
        cpus.append(after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime)
    return {"wall": statistics.median(walls), "cpu": statistics.median(cpus), "runs": repeat,
            "best_wall": min(walls), "best_cpu": min(cpus)}


def _timed(fn: Callable[[], Any], repeat: int) -> tuple[dict[str, float], Any]:
    """Medians of wall and CPU seconds of ``fn()`` in this process, and its value."""
    walls, cpus, value = [], [], None
    for _ in range(repeat):
        start, cpu = time.perf_counter(), time.process_time()
        value = fn()
        walls.append(time.perf_counter() - start)
        cpus.append(time.process_time() - cpu)
    return {"wall": statistics.median(walls), "cpu": statistics.median(cpus)}, value


def reference_loop() -> float:
    """CPU seconds of a fixed pure-Python loop (10,000,000 additions): how fast this machine
    runs Python during the run, to compare runs on different or busy machines."""
    start = time.process_time()
    total = 0
    for i in range(10_000_000):
        total += i
    return time.process_time() - start


def measure(commands: int, repeat: int, seed: int) -> dict[str, Any]:
    """Every figure of one run."""
    with tempfile.TemporaryDirectory(prefix="kitkb-bench-metrics-") as tmp:
        text_path, xml_path = Path(tmp) / "program.crcl", Path(tmp) / "program.xml"
        text = generate(commands, seed)
        text_path.write_text(text)
        xml_path.write_bytes(write_xml(read_text(generate(commands, seed, faults=False))))
        load_before = os.getloadavg()[0]
        read_fast, steps = _timed(lambda: read_steps(text_path), repeat)
        read_crcl, commands_read = _timed(lambda: read_file(text_path), repeat)
        convert, converted = _timed(lambda: steps_of(commands_read), repeat)
        if steps != converted:
            raise SystemExit("the fast reader and kb.crcl disagree on the generated program")
        evaluate, result = _timed(lambda: static_metrics(steps), repeat)
        rows, _ = _timed(lambda: static_metrics(steps, rows=True), repeat)
        figures = {
            "process": _process(["metrics", str(text_path), "--format", "json"], repeat),
            "process_per_command": _process(["metrics", str(text_path), "--format", "json", "--per-command"],
                                            repeat),
            "process_xml": _process(["metrics", str(xml_path), "--format", "json"], repeat),
            "read_fast": read_fast, "evaluate": evaluate,
            "read_kb_crcl": {k: read_crcl[k] + convert[k] for k in ("wall", "cpu")},
            "evaluate_rows": rows,
            "reference_loop": statistics.median(reference_loop() for _ in range(3)),
        }
        return {
            "date": dt.datetime.now(dt.timezone.utc).isoformat(timespec="seconds"),
            "commands": len(steps), "bytes": len(text.encode()), "seed": seed, "repeat": repeat,
            "metrics": result.totals, "figures": figures,
            "load": [load_before, os.getloadavg()[0]],
            "machine": {"cpu": cpu_model(), "cores": os.cpu_count(), "python": platform.python_version(),
                        "system": f"{platform.system()} {platform.release()}"},
        }


def render(run: dict[str, Any]) -> str:
    """The "## CRCL metrics" section of docs/benchmarks.md."""
    f, m = run["figures"], run["machine"]
    n = run["commands"]
    p = f["process"]
    lines = [
        f"## {TITLE}",
        "",
        f"Command: `.venv/bin/python benchmarks/bench_metrics.py` ({n:,} commands, medians of {run['repeat']} "
        "runs; raw figures in `benchmarks/results/metrics.json`). The program is generated (seed "
        f"{run['seed']}, {run['bytes'] / 1e6:.1f} MB of CRCL text): about 60 % moves, gripper commands, dwells, "
        "messages, speed and acceleration settings, 1 % faults (unreadable lines, values out of range). "
        "Whole processes are `python -m kb.cli metrics PROGRAM --format json` (interpreter start, imports, "
        "reading, evaluation, output); CPU is the child's user + system time, in process the process's "
        "CPU time.",
        "",
        f"Machine: {m['cpu']}, {m['cores']} cores, {m['system']}, Python {m['python']}; load average "
        f"{run['load'][0]:.1f} at the start and {run['load'][1]:.1f} at the end (other jobs share the "
        "machine: wall times above the CPU times are waiting for a core).",
        "",
        "| measure | wall | CPU |",
        "|---|---|---|",
        f"| `kitkb metrics` whole process, {n:,} commands (goal: under 2 s) | {p['wall']:.2f} s "
        f"(best {p['best_wall']:.2f} s) | {p['cpu']:.2f} s (best {p['best_cpu']:.2f} s) |",
        f"| the same with `--per-command` (a JSON row per command) | {f['process_per_command']['wall']:.2f} s | "
        f"{f['process_per_command']['cpu']:.2f} s |",
        f"| the same program as CRCL XML (no faults: XML cannot hold them) | {f['process_xml']['wall']:.2f} s | "
        f"{f['process_xml']['cpu']:.2f} s |",
        *(f"| in process: {what} | {f[key]['wall']:.2f} s | {f[key]['cpu']:.2f} s |" for key, what in (
            ("read_fast", "reading, kb.metrics' fast text path"),
            ("read_kb_crcl", "reading with `kb.crcl.read_file` + `steps_of`"),
            ("evaluate", "evaluating the metrics (`static_metrics`)"),
            ("evaluate_rows", "evaluating with a row per command"))),
        "",
        f"The goal, a {n:,}-command program's metrics in under 2 s whole process: median {p['wall']:.2f} s, "
        f"best of {p['runs']} {p['best_wall']:.2f} s. The machine is shared (load {run['load'][0]:.1f} to "
        f"{run['load'][1]:.1f}): the same command, run again and again, took anywhere from 1.3 to 2.3 s of CPU "
        "within minutes, so the best run is the closer figure for an idle machine. For scale: a pure-Python loop "
        f"of 10,000,000 additions took {f['reference_loop']:.2f} s of CPU in the same run "
        "(`reference_loop` in the script).",
        "",
        "Without the fast path (every line through `kb.crcl.read_text`'s tokenizer and a "
        "`Command` per line) reading alone takes longer than the whole budget; the fast path reads a plainly "
        "written one-line command without a `Command` object (a table of the bare commands, one or two regular "
        "expressions) and hands every other line to kb.crcl, which (with numpy and lxml) is imported only "
        "then; `tests/test_metrics.py` holds both readers equal.",
    ]
    return "\n".join(lines) + "\n"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--commands", type=int, default=100_000, help="commands in the program (default 100,000)")
    parser.add_argument("--repeat", type=int, default=5, help="runs of each measure; medians (default 5)")
    parser.add_argument("--seed", type=int, default=0, help="seed of the generated program (default 0)")
    parser.add_argument("--no-doc", action="store_true", help="do not rewrite docs/benchmarks.md")
    parser.add_argument("--render", action="store_true",
                        help="rewrite the docs/benchmarks.md section from the latest results, measuring nothing")
    args = parser.parse_args()
    if args.render:
        write_doc(TITLE, render(json.loads(RESULTS.read_text())[-1]))
        return
    run = measure(args.commands, args.repeat, args.seed)
    f = run["figures"]
    print(f"{run['commands']:,} commands; load {run['load'][0]:.1f} -> {run['load'][1]:.1f}")
    for name in ("process", "process_per_command", "process_xml"):
        print(f"{name:>22}: median wall {f[name]['wall']:.3f} s, CPU {f[name]['cpu']:.3f} s; "
              f"best wall {f[name]['best_wall']:.3f} s, CPU {f[name]['best_cpu']:.3f} s")
    for name in ("read_fast", "read_kb_crcl", "evaluate", "evaluate_rows"):
        print(f"{name:>22}: median wall {f[name]['wall']:.3f} s, CPU {f[name]['cpu']:.3f} s")
    print(f"{'reference_loop':>22}: CPU {f['reference_loop']:.3f} s")
    history = json.loads(RESULTS.read_text()) if RESULTS.exists() else []
    history.append(run)
    RESULTS.write_text(json.dumps(history, indent=1) + "\n")
    if not args.no_doc:
        write_doc(TITLE, render(run))


if __name__ == "__main__":
    main()
