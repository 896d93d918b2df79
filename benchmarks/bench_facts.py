"""Initial facts from definitions (issue 28, point 1): ``kitkb plan`` on a generated 160-part
scenario, whole process, beside a baseline checkout (HEAD before the change, a git worktree
outside the repository), alternating A/B runs; medians and the ratio.

    git worktree add /tmp/base 9ce692b
    .venv/bin/python benchmarks/bench_facts.py --baseline /tmp/base --parts 160 --repeat 7
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
PY = sys.executable


def timed(root: Path, *args: str) -> float:
    start = time.perf_counter()
    subprocess.run([PY, "-m", "kb.cli", *args], cwd=root, check=True, capture_output=True)
    return time.perf_counter() - start


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--baseline", required=True, type=Path, help="checkout of the baseline commit")
    ap.add_argument("--parts", type=int, default=160)
    ap.add_argument("--repeat", type=int, default=7)
    a = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        sc = Path(tmp) / "sc"
        subprocess.run([PY, "-m", "kb.cli", "scenario", "generate", "--parts", str(a.parts), "-o", str(sc), "-q"],
                       cwd=ROOT, check=True)
        args = ("plan", str(sc / "init.ttl"), str(sc / "goal.ttl"), "-o", str(Path(tmp) / "plan.txt"))
        timed(ROOT, *args), timed(a.baseline, *args)  # warm the caches
        now, base = [], []
        for _ in range(a.repeat):
            base.append(timed(a.baseline, *args))
            now.append(timed(ROOT, *args))
    m_now, m_base = statistics.median(now), statistics.median(base)
    print(f"kitkb plan, {a.parts} parts, whole process, {a.repeat} A/B pairs: baseline {m_base:.3f} s, "
          f"now {m_now:.3f} s, ratio {m_now / m_base:.3f}")


if __name__ == "__main__":
    main()
