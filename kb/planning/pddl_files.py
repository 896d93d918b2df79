"""Existing PDDL files as planning problems (NIST's hand-written domain, or any other).

:func:`read_pddl` parses a domain and a problem with unified-planning's reader; a
``:derived-predicates`` requirement the domain never uses (NIST's declares it) is removed
with a warning, since the reader rejects it. Errors become one-line
:class:`~kb.core.errors.InputError` naming the file and line.
"""

from __future__ import annotations

import re
import sys
from pathlib import Path
from typing import Any, Callable

from kb.core.errors import InputError
from kb.core.files import note_input
from kb.io.parsing import decode
from kb.patches.unified_planning import environment


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
    return body.startswith("(define")


def read_pddl(domain_path: str | Path, problem_path: str | Path,
              warn: Callable[[str], None] | None = None) -> Any:
    """The unified-planning problem of a PDDL domain and problem file."""
    warn = warn or (lambda msg: print(msg, file=sys.stderr))
    texts = {}
    for path in (domain_path, problem_path):
        note_input(path)
        try:
            texts[path] = decode(Path(path).read_bytes(), Path(path)).replace("\r\n", "\n").replace("\r", "\n")
        except OSError as exc:
            raise InputError(f"cannot read: {exc.strerror or exc}", path) from None
    domain = texts[domain_path]
    if ":derived-predicates" in domain.lower() and "(:derived" not in domain.lower():
        line = domain.lower()[:domain.lower().index(":derived-predicates")].count("\n") + 1
        warn(f"{domain_path}:{line}: warning: requirement :derived-predicates is declared but "
             "never used; ignored")
        domain = re.sub(r":derived-predicates", "", domain, flags=re.IGNORECASE)
    environment()
    from unified_planning.io import PDDLReader

    _parse(lambda: PDDLReader().parse_problem_string(domain, None), domain_path, domain)
    return _parse(lambda: PDDLReader().parse_problem_string(domain, texts[problem_path]),
                  problem_path, texts[problem_path])


def _parse(call: Callable[[], Any], path: str | Path, text: str) -> Any:
    try:
        return call()
    except KeyError as exc:  # an undeclared type or object
        name = str(exc.args[0]) if exc.args else "?"
        raise InputError(f"unknown type or object {name!r}", path, _line_of_word(text, name)) from None
    except Exception as exc:  # noqa: BLE001 - pyparsing / UP errors, reported as one line
        msg = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        line = getattr(exc, "lineno", None)
        found = re.search(r"line:? (\d+)", msg)
        if line is None and found:
            line = int(found.group(1))
        raise InputError(f"not valid PDDL: {msg}", path, line) from None


def _line_of_word(text: str, word: str) -> int | None:
    pattern = re.compile(rf"(?<![\w-]){re.escape(word)}(?![\w-])", re.IGNORECASE)
    for number, line in enumerate(text.splitlines(), 1):
        if pattern.search(line.split(";", 1)[0]):
            return number
    return None
