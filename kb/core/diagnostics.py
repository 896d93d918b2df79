"""Diagnostics: one problem found in one place of one file, formatted one per line."""

from __future__ import annotations

import json
from dataclasses import asdict, dataclass
from typing import Iterable, Literal

Severity = Literal["error", "warning", "info"]


@dataclass(frozen=True, order=True)
class Diagnostic:
    """A problem with a source position.

    ``rule`` names the check that found it (a shape or constraint component), ``focus``
    the node it is about (a compact name such as ``:part_a_1``).
    """

    file: str
    line: int | None
    severity: Severity
    message: str
    rule: str = ""
    focus: str = ""

    def format(self) -> str:
        """``file:line: severity: message [rule]`` (line omitted when unknown)."""
        where = f"{self.file}:{self.line}" if self.line else self.file
        rule = f" [{self.rule}]" if self.rule else ""
        return f"{where}: {self.severity}: {self.message}{rule}"


def to_json(diagnostics: Iterable[Diagnostic]) -> str:
    """The diagnostics as a JSON array of objects (the ``--format json`` report)."""
    return json.dumps([asdict(d) for d in diagnostics], indent=2)
