"""CRCL's two text forms (issue 26, point 3): what reading and writing NIST's kittingViewer form
costs beside the first paper's form, and beside a checkout from before NIST's form was read.

Two generated programs of ``--commands`` commands (seeded), each written in both forms by
this checkout's ``kb.crcl.write_text``:

* ``plan``: ``bench_metrics.generate``'s program (about 60 % moves, 3 % of them MoveThroughTo);
* ``through``: NIST's kittingViewer programs' shape (commands1: 17 of 41 commands a
  three-pose MoveThroughTo between gripper commands).

Timed, each in a fresh process of its checkout (``PYTHONPATH``), CPU seconds of the work alone,
the checkouts and forms taking turns (``--repeat`` rounds; medians):

* reading (``kb.metrics.read_steps``, the fast reader ``kitkb metrics`` uses) each form here,
  the paper's form in the baseline checkout (``--before DIR``: a tree holding its ``kb``),
  and NIST's form read by kb.crcl alone (``read_text`` + ``steps_of``: no fast path for it);
* writing (``write_text``) each form here, the paper's form in the baseline;
* the whole ``kitkb metrics PROGRAM --format json`` process on each form here.

The steps read from both forms must be equal (checked each run), and the baseline's steps of
the paper's form equal to this checkout's.

    BEFORE=$(mktemp -d /tmp/kitkb-crcl-text-XXXX)     # a directory of its own: others' benchmarks use /tmp too
    git archive 8749b58 kb | tar -x -C $BEFORE
    .venv/bin/python benchmarks/bench_crcl_text.py --before $BEFORE --label 8749b58 --repeat 7
    .venv/bin/python benchmarks/bench_crcl_text.py --render     # the section from the latest results

Results are appended to ``benchmarks/results/crcl_text.json``; the run rewrites the
"## CRCL text forms" section of ``docs/benchmarks.md``.
"""

from __future__ import annotations

import argparse
import datetime as dt
import json
import os
import platform
import random
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

from bench_metrics import generate  # noqa: E402
from common import cpu_model, write_doc  # noqa: E402

from kb.crcl import read_text, write_text  # noqa: E402

RESULTS = ROOT / "benchmarks" / "results" / "crcl_text.json"
TITLE = "CRCL text forms"

#: Run in a fresh process of a checkout: time one job, print its CPU seconds and a digest.
_JOB = """
import hashlib, json, sys, time
job, path = sys.argv[1], sys.argv[2]
if job == "read":
    from kb.metrics import read_steps
    start = time.process_time(); steps = read_steps(path); cpu = time.process_time() - start
    digest = hashlib.sha256(repr(steps).encode()).hexdigest()
    lineless = hashlib.sha256(repr([(k, v) for k, _, v in steps]).encode()).hexdigest()
elif job == "read_kb_crcl":
    from kb.crcl import read_text
    from kb.metrics import steps_of
    from pathlib import Path
    start = time.process_time(); steps = steps_of(read_text(Path(path))); cpu = time.process_time() - start
    digest = hashlib.sha256(repr(steps).encode()).hexdigest()
    lineless = hashlib.sha256(repr([(k, v) for k, _, v in steps]).encode()).hexdigest()
else:
    from kb.crcl import read_text, write_text
    from pathlib import Path
    program = read_text(Path(path))
    style = job.split(":")[1]
    start = time.process_time()
    text = write_text(program) if style == "default" else write_text(program, style=style)
    cpu = time.process_time() - start
    digest = lineless = hashlib.sha256(text.encode()).hexdigest()
print(json.dumps({"cpu": cpu, "digest": digest, "lineless": lineless}))
"""


def through_program(commands: int, seed: int = 0) -> str:
    """A kittingViewer-shaped program in the paper's form: three-pose MoveThroughTo moves
    between gripper and tool changer commands, in metres."""
    rng = random.Random(seed)
    down = "{0, 0, -1}, {1, 0, 0}"
    lines = ["InitCanon()", 'SetLengthUnits("meter")', "SetAbsoluteSpeed(1.0)", "SetRelativeAcceleration(80.0)"]

    def pose() -> str:
        return "{{" + ", ".join(str(round(rng.uniform(0.0, 9.0), rng.choice([1, 2, 3, 4]))) for _ in range(3)) \
            + "}, " + down + "}"

    while len(lines) < commands - 1:
        lines.append(f"MoveThroughTo({pose()},\n  {pose()},\n  {pose()}, 3)")
        lines.append(rng.choice(["CloseGripper()", "OpenGripper()", "OpenToolChanger()", "CloseToolChanger()"]))
    lines.append("EndCanon(0)")
    return "\n".join(lines) + "\n"


def _job(tree: Path, job: str, path: Path) -> dict[str, Any]:
    done = subprocess.run([sys.executable, "-c", _JOB, job, str(path)], capture_output=True, text=True,
                          env={**os.environ, "PYTHONPATH": str(tree)}, cwd=tempfile.gettempdir())
    if done.returncode != 0:
        raise SystemExit(f"{tree}: {job} {path} failed: {done.stderr.strip()[-500:]}")
    return json.loads(done.stdout)


def _process(path: Path) -> float:
    """CPU seconds of a whole ``kitkb metrics PATH --format json`` of this checkout."""
    before = os.times()
    done = subprocess.run([sys.executable, "-m", "kb.cli", "metrics", str(path), "--format", "json"], cwd=ROOT,
                          stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    after = os.times()
    if done.returncode != 0:
        raise SystemExit(f"kitkb metrics {path} failed: {done.stderr.strip()}")
    return after.children_user + after.children_system - before.children_user - before.children_system


def measure(commands: int, repeat: int, seed: int, before: Path | None) -> dict[str, Any]:
    """Every figure of one run: per program, the medians of each case."""
    figures: dict[str, Any] = {}
    with tempfile.TemporaryDirectory(prefix="kitkb-bench-crcl-text-") as tmp:
        files = {}
        for name, text in (("plan", generate(commands, seed)), ("through", through_program(commands, seed))):
            program = read_text(text)
            for style in ("paper", "nist"):
                path = Path(tmp) / f"{name}-{style}.crcl"
                path.write_text(write_text(program, style=style))
                files[name, style] = path
        load_before = os.getloadavg()[0]
        for name in ("plan", "through"):
            cases = {  # label -> (tree, job, file)
                "read nist": (ROOT, "read", files[name, "nist"]),
                "read paper": (ROOT, "read", files[name, "paper"]),
                "read nist by kb.crcl": (ROOT, "read_kb_crcl", files[name, "nist"]),
                "write nist": (ROOT, "write:nist", files[name, "paper"]),
                "write paper": (ROOT, "write:paper", files[name, "paper"]),
            }
            if before is not None:
                cases["before: read paper"] = (before, "read", files[name, "paper"])
                cases["before: write paper"] = (before, "write:default", files[name, "paper"])
            cpu: dict[str, list[float]] = {label: [] for label in cases}
            cpu["process nist"], cpu["process paper"] = [], []
            digests: dict[str, set[str]] = {label: set() for label in cases}
            lineless: dict[str, set[str]] = {label: set() for label in cases}
            for _ in range(repeat):  # every case once a round: A and B take turns under the same load
                for label, (tree, job, path) in cases.items():
                    got = _job(tree, job, path)
                    cpu[label].append(got["cpu"])
                    digests[label].add(got["digest"])
                    lineless[label].add(got["lineless"])
                cpu["process nist"].append(_process(files[name, "nist"]))
                cpu["process paper"].append(_process(files[name, "paper"]))
            # the same commands from both forms (their lines differ: NIST's MoveThroughTo takes several),
            # and the same steps, lines too, from both readers of NIST's form
            same_steps = (len(lineless["read nist"] | lineless["read paper"]) == 1
                          and len(digests["read nist"] | digests["read nist by kb.crcl"]) == 1)
            if not same_steps:
                raise SystemExit(f"{name}: the two forms, or the two readers, give different steps")
            baseline_same = before is None or digests["before: read paper"] == digests["read paper"]
            if before is not None and len(digests["before: write paper"] | digests["write nist"]) == 1:
                raise SystemExit(f"{before} writes NIST's form: it is not a checkout from before it")
            figures[name] = {
                "commands": len(read_text(files[name, "paper"])),
                "bytes": {style: files[name, style].stat().st_size for style in ("paper", "nist")},
                "cpu": {label: statistics.median(v) for label, v in cpu.items()},
                "best": {label: min(v) for label, v in cpu.items()},
                "same_steps": same_steps, "baseline_same_steps": baseline_same,
                "baseline_same_paper_text": before is None or digests["before: write paper"] == digests["write paper"],
            }
    return {
        "date": dt.datetime.now(dt.timezone.utc).isoformat(timespec="seconds"), "commands": commands, "seed": seed,
        "repeat": repeat, "before": str(before) if before else None, "figures": figures,
        "load": [load_before, os.getloadavg()[0]],
        "machine": {"cpu": cpu_model(), "cores": os.cpu_count(), "python": platform.python_version(),
                    "system": f"{platform.system()} {platform.release()}"},
    }


def render(run: dict[str, Any]) -> str:
    """The "## CRCL text forms" section of docs/benchmarks.md."""
    m = run["machine"]
    lines = [
        f"## {TITLE}",
        "",
        f"Command: `.venv/bin/python benchmarks/bench_crcl_text.py --before DIR --label REV --repeat {run['repeat']}` "
        f"({run['commands']:,}-command programs, seed {run['seed']}; raw figures in "
        "`benchmarks/results/crcl_text.json`). Two generated programs, each written in NIST's kittingViewer "
        "form and in the first paper's Fig. 11 form: `plan`, `bench_metrics.py`'s program (3 % of its commands "
        "a MoveThroughTo), and `through`, NIST's kittingViewer files' shape (half of its commands a three-pose "
        "MoveThroughTo, four lines each in NIST's form). CPU seconds of the job alone, each in a fresh process, "
        "every case once a round so that the checkouts and forms take turns under the same load; medians of "
        f"{run['repeat']} rounds (best in brackets). The baseline is the checkout before NIST's form was read "
        f"({run.get('before_label') or run['before'] or 'not measured'}), which reads only the paper's form.",
        "",
        f"Machine: {m['cpu']}, {m['cores']} cores (shared with other jobs), {m['system']}, Python {m['python']}; "
        f"load average {run['load'][0]:.1f} at the start and {run['load'][1]:.1f} at the end.",
        "",
        "| program | measure | CPU s | ratio |",
        "|---|---|---|---|",
    ]
    for name, f in run["figures"].items():
        c, b = f["cpu"], f["best"]
        base = c.get("before: read paper")

        def row(label: str, what: str, against: float | None, against_name: str) -> str:
            ratio = f"{c[label] / against:.2f}x {against_name}" if against else ""
            return f"| {name} | {what} | {c[label]:.3f} ({b[label]:.3f}) | {ratio} |"

        lines += [
            row("read nist", "read NIST's form (kb.metrics' fast reader)", c["read paper"], "the paper's form here"),
            row("read paper", "read the paper's form", base, "the baseline"),
            *([row("before: read paper", "baseline: read the paper's form", None, "")] if base else []),
            row("read nist by kb.crcl", "read NIST's form by kb.crcl alone (no fast path)", c["read nist"],
                "the fast reader"),
            row("write nist", "write NIST's form (`write_text`)", c["write paper"], "the paper's form here"),
            row("write paper", "write the paper's form", c.get("before: write paper"), "the baseline"),
            *([row("before: write paper", "baseline: write the paper's form", None, "")]
              if "before: write paper" in c else []),
            row("process nist", "`kitkb metrics` whole process, NIST's form", c["process paper"], "the paper's form"),
            row("process paper", "`kitkb metrics` whole process, the paper's form", None, ""),
        ]
    sizes = "; ".join(f"{name} {f['commands']:,} commands, {f['bytes']['nist'] / 1e6:.1f} MB in NIST's form, "
                      f"{f['bytes']['paper'] / 1e6:.1f} MB in the paper's" for name, f in run["figures"].items())
    same = all(f["same_steps"] for f in run["figures"].values())
    base_same = all(f["baseline_same_steps"] and f["baseline_same_paper_text"] for f in run["figures"].values())
    lines += [
        "",
        f"Programs: {sizes}. Both forms read to the same steps, by the fast reader and by kb.crcl: "
        f"{'yes' if same else 'NO'}; the baseline reads the paper's form to the same steps and writes the same "
        f"paper text: {'yes' if base_same else 'NO'}.",
        "",
        "NIST's MoveThroughTo spans lines, which the fast reader used to hand to kb.crcl's tokenizer "
        "(and kb.crcl read it as unreadable); it now reads it a pose a line with the regular expressions of "
        "the one-line moves (`kb.metrics.steps._Through`), falling back to kb.crcl for anything else. "
        "Writing NIST's form checks each command against what NIST's parser can read back (its 198-byte "
        "lines, its messages).",
        "",
        "The same work before this change is in the baseline rows: the paper's form read and written at the "
        "same cost (ratios near 1 are the noise of a shared machine; the fast reader's MoveThroughTo count "
        "now sums its numbers with `sum`, not `math.fsum`, which raised on an overflow), NIST's form read "
        "by the fast reader at the cost of the paper's form or less (it is shorter), and 7 to 12 times "
        "faster than by kb.crcl alone.",
    ]
    return "\n".join(lines) + "\n"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--commands", type=int, default=100_000, help="commands in each program (default 100,000)")
    parser.add_argument("--repeat", type=int, default=5, help="rounds; medians (default 5)")
    parser.add_argument("--seed", type=int, default=0, help="seed of the generated programs (default 0)")
    parser.add_argument("--before", type=Path, help="a tree holding the baseline checkout's kb (git archive REV kb)")
    parser.add_argument("--label", help="the baseline's name in the section (its commit; default: the --before path)")
    parser.add_argument("--no-doc", action="store_true", help="do not rewrite docs/benchmarks.md")
    parser.add_argument("--render", action="store_true",
                        help="rewrite the docs/benchmarks.md section from the latest results, measuring nothing")
    args = parser.parse_args()
    if args.render:
        write_doc(TITLE, render(json.loads(RESULTS.read_text())[-1]))
        return
    started = time.perf_counter()
    run = measure(args.commands, args.repeat, args.seed, args.before)
    run["before_label"] = args.label
    for name, f in run["figures"].items():
        for label, value in f["cpu"].items():
            print(f"{name:>8} {label:>24}: median CPU {value:.3f} s (best {f['best'][label]:.3f})")
    print(f"load {run['load'][0]:.1f} -> {run['load'][1]:.1f}; {time.perf_counter() - started:.0f} s")
    history = json.loads(RESULTS.read_text()) if RESULTS.exists() else []
    history.append(run)
    RESULTS.write_text(json.dumps(history, indent=1) + "\n")
    if not args.no_doc:
        write_doc(TITLE, render(run))


if __name__ == "__main__":
    main()
