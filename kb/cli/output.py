"""What the command line prints besides its results: one short line on standard error per
command that wrote something (``kitkb: wrote out/plan.txt (30 actions ...)``), unless
``--quiet``; warnings always; with ``--format json`` one JSON object on standard output
instead of the line, with the same facts (and the line itself, as ``message``). Progress of
long work goes to standard error while it runs, on a terminal only (:mod:`kb.cli.progress`)."""

from __future__ import annotations

import json
import sys
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any, ContextManager, TextIO

from kb.cli.progress import tracker
from kb.core.progress import Progress, Task


@dataclass
class Output:
    """Where a command reports: its results to ``stdout``, notes to ``stderr``; ``format``
    ``"json"``: the success line becomes a JSON object on ``stdout``. ``show_progress`` None
    shows progress where ``stderr`` is a terminal (True: always, False: never)."""

    quiet: bool = False
    stdout: TextIO | None = None
    stderr: TextIO | None = None
    format: str = "text"
    show_progress: bool | None = None
    command: str | None = None
    #: warnings printed so far (the JSON object lists them)
    warnings: list[str] = field(default_factory=list)

    @property
    def results(self) -> TextIO:
        """The stream for the command's results (reports, DDL on ``-o -``)."""
        return self.stdout or sys.stdout

    @property
    def is_json(self) -> bool:
        """True with ``--format json``."""
        return self.format == "json"

    def done(self, message: str, **facts: Any) -> None:
        """The one success line of a command (nothing with ``--quiet``); with ``--format json``
        the object ``{command, message, **facts, warnings}`` on standard output instead."""
        if self.is_json:
            self.emit({"message": message, **facts})
        elif not self.quiet:
            print(f"kitkb: {message}", file=self.stderr or sys.stderr)

    def emit(self, data: dict[str, Any], indent: int | None = 1) -> None:
        """One JSON object on standard output (``command`` and ``warnings`` added; ``indent``
        None: on one line)."""
        head = {"command": self.command} if self.command else {}
        print(json.dumps({**head, **data, "warnings": self.warnings}, indent=indent), file=self.results, flush=True)

    def warn(self, message: str) -> None:
        """A warning line (printed even with ``--quiet``)."""
        self.warnings.append(message)
        print(message, file=self.stderr or sys.stderr)

    @cached_property
    def tracker(self) -> Progress:
        """The progress display the library calls report to (silent when not shown)."""
        return tracker(self.stderr, quiet=self.quiet, force=self.show_progress)

    def progress(self, description: str, total: float | None = None, unit: str = "") -> ContextManager[Task]:
        """A progress task for the ``with`` block (``total`` None: a spinner and the time elapsed)."""
        return self.tracker.task(description, total, unit)
