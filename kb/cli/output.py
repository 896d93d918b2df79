"""What the command line prints besides its results: one short line on standard error per
command that wrote something (``kitkb: wrote out/plan.txt (30 actions ...)``), unless
``--quiet``; warnings always."""

from __future__ import annotations

import sys
from dataclasses import dataclass
from typing import TextIO


@dataclass
class Output:
    """Where a command reports: its results to ``stdout``, notes to ``stderr``."""

    quiet: bool = False
    stdout: TextIO | None = None
    stderr: TextIO | None = None

    @property
    def results(self) -> TextIO:
        """The stream for the command's results (reports, DDL on ``-o -``)."""
        return self.stdout or sys.stdout

    def done(self, message: str) -> None:
        """The one success line of a command (nothing with ``--quiet``)."""
        if not self.quiet:
            print(f"kitkb: {message}", file=self.stderr or sys.stderr)

    def warn(self, message: str) -> None:
        """A warning line (printed even with ``--quiet``)."""
        print(message, file=self.stderr or sys.stderr)
