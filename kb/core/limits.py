"""Named bounds on what kitkb reads and generates, each overridable by an environment variable.

An input past a bound would exhaust this machine's memory (or, for nesting, a parser's stack)
long before it gave an answer; kitkb refuses it instead, up front where it can, as an
:class:`~kb.core.errors.InputError` (exit code 2) naming the file, the line where there is
one, the limit, its value and the variable that raises it::

    big.ttl: error: 3.1 GB: over the limit on a file's size (2.3 GB; set KITKB_MAX_FILE_BYTES to raise it)

The defaults that guard memory are sized from measurements (docs/limits.md has them) and this
machine's memory: :func:`memory_budget` is three quarters of the physical memory (or of the
cgroup's ``memory.max``, if lower). Every default is read again at each check, so a test or
a user can set the variable at any time. ``KITKB_MAX_...=0`` or ``none`` lifts a limit.

:data:`CELL_BOUNDS` bound, in the same way, what a peer sends: a cell's answers to
:class:`kb.crcl.remote.RemoteCell` (time, lines, bytes), given up past a bound as a
:class:`~kb.core.errors.CellError` naming the peer.
"""

from __future__ import annotations

import os
import sys
from contextlib import contextmanager
from dataclasses import dataclass
from functools import lru_cache
from typing import Callable, Iterator

from kb.core.errors import InputError

#: Share of the machine's memory a command may plan to use.
MEMORY_SHARE = 0.75

# --- measurements (docs/limits.md, "How the defaults were measured") --------------------------
#: Memory per byte of a file read whole before its statements are counted: the bytes, their
#: decoded text (1 to 4 bytes a character) and the parser's buffers. What the statements then
#: cost is :data:`BYTES_PER_STATEMENT`'s to bound.
BYTES_PER_FILE_BYTE = 8
#: Peak resident memory per statement of ``kitkb validate`` on generated scenarios (``init.ttl``
#: of 20,000 and 100,000 parts: 24 MB, 0.71 million statements, 0.72 GB peak; 120 MB,
#: 3.5 million statements, 3.3 GB peak: 1,020 and 950 bytes a statement).
BYTES_PER_STATEMENT = 1000
#: Peak resident memory per command of ``kitkb crcl convert`` text -> XML with CRCL.xsd (a
#: program of a million lines: 0.74 GB peak).
BYTES_PER_CRCL_COMMAND = 800
#: Peak resident memory per part of ``kitkb scenario generate`` (20,000 parts: 68 MB peak;
#: 100,000 parts: 118 MB: 640 bytes a part).
BYTES_PER_PART = 700
#: Bytes ``kitkb scenario generate`` writes per part (init.ttl and goal.ttl, meters: 2.8 kB a
#: part at 1,000 parts, 2.6 kB at 100,000).
DISK_BYTES_PER_PART = 2800


@lru_cache(maxsize=1)
def physical_memory() -> int:
    """Bytes of memory this process may have: the machine's physical memory, or the cgroup's
    ``memory.max`` where that is lower (a container)."""
    try:
        total = os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (ValueError, OSError, AttributeError):
        total = 8 << 30
    for path in ("/sys/fs/cgroup/memory.max", "/sys/fs/cgroup/memory/memory.limit_in_bytes"):
        try:
            with open(path, encoding="ascii") as f:
                text = f.read().strip()
        except OSError:
            continue
        if text.isdigit() and 0 < int(text) < total:
            total = int(text)
    return total


def memory_budget() -> int:
    """Bytes a command may plan to use: :data:`MEMORY_SHARE` of :func:`physical_memory`."""
    return int(physical_memory() * MEMORY_SHARE)


_SUFFIXES = {"k": 10**3, "m": 10**6, "g": 10**9, "t": 10**12,
             "ki": 2**10, "mi": 2**20, "gi": 2**30, "ti": 2**40}


def parse_amount(text: str) -> int | None:
    """``"2G"``, ``"512Mi"``, ``"1_000_000"``, ``"10000"`` as a whole number; ``"0"`` or
    ``"none"`` as None (no limit). ValueError for anything else."""
    raw = text.strip().lower().replace("_", "")
    if raw in ("0", "none", "off", "unlimited"):
        return None
    raw = raw.removesuffix("b")
    for suffix in sorted(_SUFFIXES, key=len, reverse=True):
        if raw.endswith(suffix):
            number = float(raw[: -len(suffix)])
            if number < 0:
                raise ValueError(text)
            return int(number * _SUFFIXES[suffix])
    value = int(raw)
    if value < 0:
        raise ValueError(text)
    return value or None


def _size(n: int) -> str:
    """``n`` bytes for a person: ``3.1 GB``."""
    for unit, scale in (("GB", 10**9), ("MB", 10**6), ("kB", 10**3)):
        if n >= scale:
            return f"{n / scale:.1f} {unit}"
    return f"{n} bytes"


@dataclass(frozen=True)
class Limit:
    """One named bound: ``name`` reads in a sentence ("the limit on ..."), ``env`` overrides
    the default, ``unit`` says what is counted (``bytes`` prints as kB/MB/GB)."""

    name: str
    env: str
    unit: str
    guards: str
    _default: Callable[[], int]

    @property
    def default(self) -> int:
        """The value on this machine when ``env`` is not set."""
        return self._default()

    def value(self) -> int | None:
        """The limit in force (None: lifted). A malformed ``env`` value is an InputError."""
        raw = os.environ.get(self.env)
        if raw is None or not raw.strip():
            return self.default
        try:
            return parse_amount(raw)
        except ValueError:
            raise InputError(f"{self.env}={raw!r} is not a whole number (like 5000000, 2G, "
                             "512Mi; 0 or none lifts the limit)") from None

    def show(self, n: int) -> str:
        """``n`` in this limit's unit."""
        return _size(n) if self.unit == "bytes" else f"{n:,} {self.unit}"

    def error(self, amount: int | None, file: object = None, line: int | None = None,
              what: str | None = None) -> InputError:
        """The InputError of going past this limit (``amount`` counted so far, if known)."""
        limit = self.value()
        said = what or (self.show(amount) if amount is not None else "this input")
        shown = self.show(limit) if limit is not None else "none"
        return InputError(f"{said}: over the limit on {self.name} ({shown}; set {self.env} to raise it)",
                          None if file is None else str(file), line)

    def check(self, amount: int, file: object = None, line: int | None = None,
              what: str | None = None) -> None:
        """Raise :meth:`error` if ``amount`` is past the limit in force."""
        limit = self.value()
        if limit is not None and amount > limit:
            raise self.error(amount, file, line, what)


def _round(n: float) -> int:
    """``n`` rounded down to two significant digits (defaults that read as measurements)."""
    n = int(n)
    digits = len(str(n))
    scale = 10 ** max(digits - 2, 0)
    return max(n // scale * scale, 1)


FILE_BYTES = Limit(
    "a file's size", "KITKB_MAX_FILE_BYTES", "bytes",
    "an ontology or data file read whole (Turtle, N-Triples, RDF/XML, OWL/XML, OWL functional "
    "syntax) and a CRCL XML file; checked before reading",
    lambda: _round(memory_budget() / BYTES_PER_FILE_BYTE))
STATEMENTS = Limit(
    "statements in a file", "KITKB_MAX_STATEMENTS", "statements",
    "the statements (triples) one file may hold, so the individuals it describes; counted while parsing",
    lambda: _round(memory_budget() / BYTES_PER_STATEMENT))
LITERAL = Limit(
    "a literal's length", "KITKB_MAX_LITERAL", "characters",
    "one RDF literal, one XML text or entity, one CRCL statement (a command and its continuation lines)",
    lambda: 10_000_000)
NESTING = Limit(
    "nesting depth", "KITKB_MAX_NESTING", "levels",
    "nested blank nodes '[' and collections '(' in Turtle, parentheses in OWL functional syntax, "
    "XML elements (RDF/XML, OWL/XML, CRCL XML); parsers and writers recurse once per level",
    lambda: 1000)
CRCL_COMMANDS = Limit(
    "commands in a CRCL program", "KITKB_MAX_CRCL_COMMANDS", "commands",
    "the commands of one CRCL program (the text form is read line by line, the commands are kept)",
    lambda: _round(memory_budget() / BYTES_PER_CRCL_COMMAND))
PARTS = Limit(
    "parts in a generated scenario", "KITKB_MAX_PARTS", "parts",
    "kitkb scenario generate --parts; checked before anything is built",
    lambda: _round(memory_budget() / BYTES_PER_PART))

#: Every limit, in the order docs/limits.md lists them.
ALL = (FILE_BYTES, STATEMENTS, LITERAL, NESTING, CRCL_COMMANDS, PARTS)

# --- bounds on what a peer sends (docs/limits.md, "Bounds on a cell's answers") ----------------
#: Peak memory per byte of a cell's answer while kitkb reads it: the bytes, the decoded lines,
#: the observations parsed from them (a 100,000-object sensor answer, 21 MB: 112 MB peak, 5.3
#: bytes a byte, 1,120 a line; docs/limits.md).
BYTES_PER_ANSWER_BYTE = 6
#: Peak memory per line of a cell's answer (its text and the observation parsed from it).
BYTES_PER_ANSWER_LINE = 1200

CELL_SECONDS = Limit(
    "the time a cell's answer takes", "KITKB_MAX_CELL_SECONDS", "seconds",
    "one answer of a cell (kb.crcl.RemoteCell, kitkb run --cell): from sending the request to "
    "its {End} line; also the time to connect",
    lambda: 30)
CELL_LINES = Limit(
    "lines in a cell's answer", "KITKB_MAX_CELL_LINES", "lines",
    "the lines of one answer of a cell before its {End}",
    lambda: _round(memory_budget() / BYTES_PER_ANSWER_LINE))
CELL_BYTES = Limit(
    "a cell's answer's size", "KITKB_MAX_CELL_BYTES", "bytes",
    "the bytes of one answer of a cell, its {End} line included",
    lambda: _round(memory_budget() / BYTES_PER_ANSWER_BYTE))
#: The bounds on a peer's answer, in the order docs/limits.md lists them.
CELL_BOUNDS = (CELL_SECONDS, CELL_LINES, CELL_BYTES)


def check_file_size(path: object, size: int | None = None) -> None:
    """Refuse a file larger than :data:`FILE_BYTES` before it is read (``size``: its size, if
    known; else it is asked of the file system, and a file that cannot be asked passes, the
    read will say why)."""
    if size is None:
        try:
            size = os.stat(str(path)).st_size
        except OSError:
            return
    FILE_BYTES.check(size, path)


#: Python frames a recursive reader or writer uses per level of nesting (rdflib's Turtle
#: writer: 5 measured; kitkb's OFN line index: 2).
FRAMES_PER_LEVEL = 6
#: Levels :func:`deep_calls` makes room for when the nesting limit is lifted.
_LIFTED_NESTING = 20_000


@contextmanager
def deep_calls() -> Iterator[None]:
    """Make room on Python's stack for walking input as deep as :data:`NESTING` allows (a
    recursive writer or line index), restoring the recursion limit afterwards."""
    old = sys.getrecursionlimit()
    sys.setrecursionlimit(old + FRAMES_PER_LEVEL * (NESTING.value() or _LIFTED_NESTING))
    try:
        yield
    finally:
        sys.setrecursionlimit(old)
