"""What the benchmarks share: the machine they ran on, and their sections of docs/benchmarks.md."""

from __future__ import annotations

import platform
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
DOC = ROOT / "docs" / "benchmarks.md"


def cpu_model() -> str:
    """The processor's model name (``/proc/cpuinfo``), else the architecture."""
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.machine()


def write_doc(title: str, section: str) -> None:
    """Replace the section ``## title`` of docs/benchmarks.md with ``section`` (or append it)."""
    text = DOC.read_text()
    pattern = re.compile(rf"^## {re.escape(title)}\n.*?(?=^## |\Z)", re.S | re.M)
    text = pattern.sub(lambda _: section.rstrip("\n") + "\n\n", text) if pattern.search(text) \
        else text.rstrip("\n") + "\n\n" + section
    DOC.write_text(text.rstrip("\n") + "\n")
