"""Existing PDDL files as planning problems (NIST's hand-written domain, classic IPC domains).

:func:`read_pddl` reads a domain and a problem through :mod:`kb.planning.pddl`: checked
(errors are one-line :class:`~kb.core.errors.InputError` naming the file and line), rewritten
where unified-planning's reader cannot take the PDDL as written (derived predicates,
``either`` types, clashing names, IPC action costs; docs/pddl.md), and read by
unified-planning's reader. A ``:derived-predicates`` requirement the domain never uses
(NIST's declares it) gets a warning.
"""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Callable

from kb.planning.pddl import PddlTask, read_task


def is_pddl(path: str | Path) -> bool:
    """True if ``path`` looks like a PDDL file (extension, else first non-comment character)."""
    p = Path(path)
    if p.suffix.lower() == ".pddl":
        return True
    try:
        head = p.read_text(encoding="utf-8", errors="replace")[:4096]
    except OSError:
        return False
    body = "\n".join(line.split(";", 1)[0] for line in head.splitlines()).lstrip()
    return body.lower().startswith("(define")


def read_pddl(domain_path: str | Path, problem_path: str | Path,
              warn: Callable[[str], None] | None = None) -> PddlTask:
    """The PDDL task of a domain and a problem file: its unified-planning problem
    (``.problem``), the names renamed for unified-planning, where each feature is used."""
    warn = warn or (lambda msg: print(msg, file=sys.stderr))
    return read_task(domain_path, problem_path, warn)
