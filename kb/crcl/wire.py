"""kitkb's cell protocol on the wire: two TCP ports, UTF-8 lines of ``{Key value}`` fields
(USARTruth's key-value style, seed 004 §3.2), each line ending in ``\\n``.

Sensor port (default :data:`SENSOR_PORT` 3989, USARTruth's). The client sends one query a
line and gets the answer lines, then ``{End}``; connections stay open for more queries::

    {Class Part}         -> one truth_line per placed object of the class (local name or IRI,
                            subclasses included), in name order, then {End}
    {Name part_a_1}      -> the truth_line of that object (local name or IRI), then {End}
    {Inspect part_a_1}   -> {Name part_a_1} {Quality ok|defective}, then {End}
    anything else        -> {Error <message>}, then {End}

A truth line is ``{Name IRI} {Class C} {Time t} {Location x,y,z} {Rotation r,p,y} [{Sku S}]``
(:func:`kb.crcl.cell.truth_line`). Keys are read case-insensitively.

Command port (default :data:`COMMAND_PORT` 3990). The client sends a header line
``{Length N}`` and then exactly N bytes: one CRCL.xsd instance (a ``CRCLProgram`` document,
:func:`kb.crcl.xml.write_xml`; at most :data:`MAX_PROGRAM` bytes). The cell executes every
command of the program in order (InitCanon and EndCanon included), stops at the first that
fails, and answers one line per command, then ``{End}``::

    {Line n} {Status done|error} {Message text}

``n`` is the command's position in the program (1: its InitCanon); a command after a failed
one is not executed and answers ``{Status error} {Message`` :data:`kb.crcl.cell.NOT_EXECUTED`
``}``. A program that does not parse answers one ``{Status error} {Message program:line:
error: ...}`` line (no ``{Line}``), then ``{End}``; a header that is not ``{Length N}`` gets
the same and the connection is closed (the stream cannot be resynchronised).

kitkb's two conventions, CRCL ``Message`` commands a cell of this protocol does not display:

* ``kitkb-action <index> <action> <arg1> <arg2> ...`` (:func:`action_message`): the cell
  starts plan action ``index`` (``begin_action``) and answers ``done``, or ``error`` when the
  text is malformed;
* ``kitkb-frame [init] [end]`` as the program's *second* command (:func:`frame_message`): the
  program's first command (its InitCanon) with ``init``, its last (its EndCanon) with ``end``,
  and the message itself are only CRCL.xsd's frame around the commands a client means: they
  are not executed and answer ``{Status done} {Message frame}``. This is how a client sends
  commands that are not a whole program (an action's list, ``begin_action``) so that the cell
  executes those and nothing else. Elsewhere ``kitkb-frame`` is an ordinary message.

Text put into a field has ``{`` and ``}`` replaced by ``(`` and ``)`` and line breaks and tabs
by spaces (:func:`clean`): a value never holds a brace.
"""

from __future__ import annotations

import re

from kb.core.errors import InputError
from kb.crcl.cell import FIELD, Status
from kb.crcl.commands import Message

#: The sensor port (USARTruth's) and the command port, by default.
SENSOR_PORT = 3989
COMMAND_PORT = 3990
#: The last line of every answer.
END = "{End}"
#: The first word of a ``Message`` that starts a plan action (kitkb's convention).
ACTION = "kitkb-action"
#: The text of a ``Message`` that marks a program's frame (kitkb's convention).
FRAME = "kitkb-frame"
#: Longest line either side reads (bytes, with its newline).
MAX_LINE = 1 << 16
#: Largest program the command port takes (bytes).
MAX_PROGRAM = 1 << 24
QUERIES = ("class", "name", "inspect")
_UNSAFE = str.maketrans({"{": "(", "}": ")", "\n": " ", "\r": " ", "\t": " "})
_LENGTH = re.compile(r"\s*\{Length (\d{1,9})\}\s*", re.IGNORECASE)
_WHITESPACE = re.compile(r"\s")


def clean(text: str) -> str:
    """``text`` fit to be a field's value: braces as parentheses, line breaks as spaces."""
    return text.translate(_UNSAFE)


def field(key: str, value: object) -> str:
    """The field ``{Key value}`` (value :func:`clean` ed)."""
    return f"{{{key} {clean(str(value))}}}"


def fields(line: str) -> list[tuple[str, str]]:
    """The (key, value) fields of a key-value line; ValueError when the line holds anything else."""
    rest = FIELD.sub("", line).strip()
    if rest:
        raise ValueError(f"not a line of key-value fields: {line.strip()[:80]!r}")
    return FIELD.findall(line)


def error_line(message: str) -> str:
    """``{Error message}``."""
    return field("Error", message)


# --- the sensor port --------------------------------------------------------------------------

def query_line(kind: str, value: str) -> str:
    """The sensor query ``{Class value}``, ``{Name value}`` or ``{Inspect value}``; ValueError
    for another kind or a value that is empty or holds braces or line breaks."""
    if kind not in QUERIES:
        raise ValueError(f"a sensor query is by {', '.join(QUERIES)}, not {kind!r}")
    if not value.strip() or clean(value) != value:
        raise ValueError(f"cannot query {value!r}: empty, or with braces or line breaks")
    return field(kind.capitalize(), value)


def parse_query(line: str) -> tuple[str, str]:
    """(kind, value) of a sensor query line (kind ``class``, ``name`` or ``inspect``); ValueError
    naming what is wrong."""
    found = fields(line)
    if len(found) != 1 or found[0][0].lower() not in QUERIES or not found[0][1].strip():
        raise ValueError(f"expected one Class, Name or Inspect field, not {line.strip()[:80]!r}")
    return found[0][0].lower(), found[0][1].strip()


# --- the command port -------------------------------------------------------------------------

def length_line(size: int) -> str:
    """The header ``{Length size}`` of a program of ``size`` bytes."""
    return field("Length", int(size))


def parse_length(line: str) -> int:
    """The byte count of a ``{Length N}`` header; ValueError when it is not one or N is too big."""
    m = _LENGTH.fullmatch(line)
    if not m:
        raise ValueError(f"expected a Length header before the program, not {line.strip()[:80]!r}")
    if int(m.group(1)) > MAX_PROGRAM:
        raise ValueError(f"program of {m.group(1)} bytes; at most {MAX_PROGRAM} are taken")
    return int(m.group(1))


def status_line(n: int | None, status: Status) -> str:
    """``{Line n} {Status done|error} {Message text}`` (no ``{Line}`` when ``n`` is None)."""
    line = field("Line", n) + " " if n is not None else ""
    return line + field("Status", status.state) + " " + field("Message", status.message)


def parse_status_line(line: str) -> tuple[int | None, Status]:
    """(n, status) of a status line; ValueError when it is not one."""
    found = {k.lower(): v for k, v in fields(line)}
    state = found.get("status", "").strip()
    if state not in ("done", "error"):
        raise ValueError(f"not a status line: {line.strip()[:80]!r}")
    n = found.get("line")
    if n is not None and not n.strip().isdigit():
        raise ValueError(f"Line {n!r} is not a command number")
    return (int(n) if n is not None else None), Status(state, found.get("message", ""))  # type: ignore[arg-type]


def action_message(index: int, action: str, args: tuple[str, ...] | list[str]) -> Message:
    """The ``Message`` that starts plan action ``index`` on a remote cell (kitkb's convention);
    ValueError when the index is negative or a name is empty or holds white space."""
    names = [action, *args]
    if int(index) < 0 or any(not n or _WHITESPACE.search(n) for n in names):
        raise ValueError(f"cannot send action {index} {action}{tuple(args)}: a negative index, or an "
                         "empty name or one with white space")
    return Message(" ".join([ACTION, str(int(index)), *names]))


def parse_action(text: str) -> tuple[int, str, tuple[str, ...]] | None:
    """(index, action, args) of a ``kitkb-action`` message text; None for any other message;
    ValueError for a malformed one."""
    words = text.split()
    if not words or words[0] != ACTION:
        return None
    if len(words) < 3 or not words[1].isdigit():
        raise ValueError(f"expected '{ACTION} <index> <action> <args...>', not {text.strip()[:80]!r}")
    return int(words[1]), words[2], tuple(words[3:])


def frame_message(init: bool, end: bool) -> Message:
    """The second command of a program whose first command (``init``) and last (``end``) are
    only its frame (kitkb's convention)."""
    return Message(" ".join([FRAME] + ["init"] * init + ["end"] * end))


def parse_frame(text: str) -> tuple[bool, bool] | None:
    """(init, end) of a ``kitkb-frame`` message text; None for any other message."""
    words = text.split()
    if not words or words[0] != FRAME or not set(words[1:]) <= {"init", "end"}:
        return None
    return "init" in words, "end" in words


def parse_address(text: str) -> tuple[str, int, int]:
    """(host, sensor port, command port) of ``HOST:PORT`` (the command port is PORT + 1, as
    the defaults 3989 and 3990) or ``HOST:SENSOR_PORT,COMMAND_PORT``; an
    :class:`~kb.core.errors.InputError` otherwise."""
    host, _, ports = text.strip().rpartition(":")
    parts = ports.split(",")
    if not host or len(parts) > 2 or not all(p.strip().isdigit() for p in parts):
        raise InputError(f"cell address {text!r}: expected HOST:PORT or HOST:SENSOR_PORT,COMMAND_PORT")
    numbers = [int(p) for p in parts] + ([int(parts[0]) + 1] if len(parts) == 1 else [])
    if not all(0 < n < 65536 for n in numbers):
        raise InputError(f"cell address {text!r}: ports are 1 to 65535")
    return host.strip("[]"), numbers[0], numbers[1]
