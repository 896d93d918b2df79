"""Importing NIST ARIAC trials: the time ``kitkb ariac import`` takes (the issue's bound: 1 s).

For each shared trial (``../shared/ariac/trials-2023``, ``trials-2024``) and the trials written
for kitkb's tests (``tests/data/ariac``), and a synthetic full trial (all 8 bins x 9 slots, 6 kit
trays, 4 kitting orders of 4 parts), ``--repeats`` imports in this process (read, check, lay out,
write init.ttl, goal.ttl and ariac.json: ``kb.ariac.import_trial``) and, once per trial, the whole
command in a fresh process (``kitkb ariac import``, Python's start and imports included).
Recorded: the median and the largest in-process time, the command's wall time, the states'
sizes. Results are printed as a Markdown table (for docs/benchmarks.md, "ARIAC trial import").

    .venv/bin/python benchmarks/bench_ariac.py --repeats 20
"""

from __future__ import annotations

import argparse
import platform
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))

from kb.ariac import import_trial  # noqa: E402

COLORS = ["red", "green", "blue", "orange", "purple"]
TYPES = ["battery", "pump", "sensor", "regulator"]


def full_trial(path: Path) -> Path:
    """Every bin slot filled, six kit trays, four four-part orders on the four AGVs."""
    lines = ["time_limit: -1", "kitting_trays:", "  tray_ids: [1, 2, 3, 4, 5, 6]", "  slots: [1, 2, 3, 4, 5, 6]",
             "parts:", "  bins:"]
    for b in range(1, 9):
        lines.append(f"    bin{b}:")
        for s in range(1, 10):
            lines += [f"      - type: '{TYPES[(b + s) % 4]}'", f"        color: '{COLORS[(b * s) % 5]}'",
                      f"        slots: [{s}]", f"        rotation: 'pi/{s}'", f"        flipped: {str(s == 9).lower()}"]
    lines.append("orders:")
    for o in range(4):
        lines += [f"  - id: 'FULL{o}'", "    type: 'kitting'", "    announcement:", f"      time_condition: {o * 10}",
                  "    priority: false", "    kitting_task:", f"      agv_number: {o + 1}", f"      tray_id: {o + 1}",
                  "      destination: 'warehouse'", "      products:"]
        for q in range(1, 5):
            lines += [f"        - type: '{TYPES[(o + q) % 4]}'", f"          color: '{COLORS[(o + q) % 5]}'",
                      f"          quadrant: {q}"]
    path.write_text("\n".join(lines) + "\n")
    return path


def trials(tmp: Path) -> list[Path]:
    shared = REPO.parent / "shared" / "ariac"
    if not shared.is_dir():
        shared = Path("/work/shared/ariac")
    return sorted(shared.glob("trials-20*/*.yaml")) + sorted((REPO / "tests" / "data" / "ariac").glob("*.yaml")) + [
        full_trial(tmp / "full.yaml")]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=20)
    args = ap.parse_args()
    print(f"machine: {platform.machine()}, {platform.processor() or '?'}, Python {platform.python_version()}, "
          f"{args.repeats} imports per trial in process")
    print("| trial | parts | kits | median (ms) | max (ms) | `kitkb ariac import` (s) | init.ttl (KB) |")
    print("|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as t:
        tmp = Path(t)
        for trial in trials(tmp):
            out = tmp / trial.stem
            times = []
            for _ in range(args.repeats):
                t0 = time.perf_counter()
                imported = import_trial(trial, out)
                times.append(time.perf_counter() - t0)
            t0 = time.perf_counter()
            subprocess.run([str(REPO / ".venv" / "bin" / "kitkb"), "--quiet", "ariac", "import", str(trial), "-o",
                            str(tmp / "cmd")], check=True, capture_output=True)
            command = time.perf_counter() - t0
            name = f"{trial.parent.name}/{trial.name}" if trial.parent != tmp else "synthetic full (72 parts)"
            print(f"| {name} | {len(imported.data['parts'])} | {len(imported.data['kits'])} | "
                  f"{statistics.median(times) * 1000:.1f} | {max(times) * 1000:.1f} | {command:.2f} | "
                  f"{imported.init.stat().st_size / 1024:.0f} |")


if __name__ == "__main__":
    main()
