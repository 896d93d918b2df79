"""The text form of CRCL: ``Name(arguments)`` in C++ call syntax, one command per statement,
in either of its two published layouts.

* **NIST's form** (the kittingViewer's ``commandFiles`` and its parser, ``CommandParser`` in
  usnistgov/el-robotics-core): a ``MoveThroughTo`` holds its poses in braces, one pose a line,
  a newline right after each comma between poses, the count after the closing brace::

      MoveThroughTo({ {{1.5,1,1}, {0,0,-1}, {1,0,0}},
        {{1.5,1,0.0001}, {0,0,-1}, {1,0,0}} }, 2)

  every other command on one line; length units ``"inch"``, ``"millimeter"``, ``"meter"``.
* **The first paper's form** (Fig. 11): the poses of a ``MoveThroughTo`` are its first
  arguments, without braces around them (``MoveThroughTo(pose, pose, 2)``), and millimetres
  may be ``"mm"``.

Reading takes both, and a pose is ``{{x, y, z}, {i, j, k}, {i, j, k}}`` in both (point, Z axis,
X axis). Names are case-sensitive (``initCannon()`` does not parse); spaces may stand between a
name and its ``(``; numbers are C literals (``5``, ``-0.03``, ``.5``, ``1e-3``, hexadecimal
``0x1.8p1``, as ``strtod`` reads them); strings are in double quotes (``\\"``, ``\\\\``,
``\\n``, ``\\r``, ``\\t`` escaped, any other backslash kept as it stands; typographic quotes “…” are
read too). A command may go on over the next lines while its brackets are open, until a line
that starts another command; it keeps the line where it starts. Blank lines and comment lines
(first non-blank characters ``#`` or ``//``; kitkb's, NIST's parser has none) are skipped.
What does not parse becomes an :class:`~kb.crcl.commands.Unreadable` with its text and first
line.

Writing (:func:`write_text`): NIST's form by default (``style="nist"``), which NIST's parser
reads back as kitkb does, or refuses to write: a command that parser does not know
(``SetCoordinateFrame``, ``StartObjectScan``, ``StopObjectScan``, ``StopMotion``), a message it
cannot hold (empty, a double quote, a line break, a NUL, or a backslash kitkb would read as an
escape: NIST's parser has no escapes), an ``EndCanon`` reason outside a C ``int``, or a line
longer than its 200-byte line buffer holds (:data:`NIST_LINE_BYTES`; a pose first tries a
compact spelling of the same numbers) is an :class:`~kb.core.errors.InputError` at the
command's line. ``style="paper"`` writes the paper's form, one command a line, strings escaped,
millimetres as ``"mm"``. Either way an unreadable command is written back as it was read, and
a CRCL 1.x command the paper's language lacks (:data:`~kb.crcl.commands.CRCL1_COMMANDS`, a
``MoveThroughTo`` in straight lines) is an InputError at its line.

A program read from text is in the paper's units until it sets others: InitCanon resets to
millimetre and degree in both layouts (``Program.units``; docs/crcl.md).
"""

from __future__ import annotations

import os
import re
from dataclasses import fields
from pathlib import Path
from typing import Any, Iterable, Iterator

from kb.core import limits
from kb.core.errors import InputError
from kb.core.files import utf8_lines
from kb.crcl.commands import (COMMANDS, PAPER_UNITS, Command, EndCanon, Message, MoveStraightTo, MoveThroughTo,
                              MoveTo, Program, SetLengthUnits, Unreadable)
from kb.crcl.pose import Pose

_START = re.compile(r"\s*[A-Za-z_]\w*\s*\(")
_TOKEN = re.compile(r"""
    \s*(?:
      (?P<hex>[+-]?0[xX](?:[0-9a-fA-F]+\.?[0-9a-fA-F]*|\.[0-9a-fA-F]+)(?:[pP][+-]?\d+)?)
    | (?P<number>[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)
    | (?P<name>[A-Za-z_]\w*)
    | "(?P<string>(?:[^"\\\n]|\\.)*)"
    | \u201c(?P<curly>[^\u201d\n]*)\u201d
    | (?P<punct>[(){},])
    )""", re.VERBOSE)
_ESCAPES = {"n": "\n", "r": "\r", "t": "\t", '"': '"', "\\": "\\"}
_UNESCAPE = re.compile(r"\\(.)", re.DOTALL)
#: The text form's name of a length unit, where it differs from CRCL.xsd's.
_TEXT_UNITS = {"millimeter": "mm"}
_READ_UNITS = {"mm": "millimeter"}


class _Bad(Exception):
    """A statement does not parse; the message says why."""


# --- reading ----------------------------------------------------------------------------------

def read_text(source: str | os.PathLike[str], *, name: str | None = None) -> Program:
    """The program of CRCL text: ``source`` is the text itself (a ``str``) or a file path
    (a :class:`~pathlib.Path` or other path object). ``name`` is the program's source name
    (default: the path). An unreadable file is an :class:`~kb.core.errors.InputError`;
    unparsable lines are :class:`~kb.crcl.commands.Unreadable` commands, not errors.

    A file is read line by line (a program of millions of lines costs its commands, not its
    text as well); more commands than :data:`kb.core.limits.CRCL_COMMANDS`, or a statement
    longer than :data:`kb.core.limits.LITERAL`, is an InputError at its line."""
    if isinstance(source, str):
        lines = source.removeprefix("\ufeff").split("\n")
        return Program(tuple(_commands(lines, name)), source=name, units=PAPER_UNITS)
    path = Path(source)
    try:
        with open(path, "rb") as f:
            return Program(tuple(_commands(utf8_lines(f, path), str(path))), source=name or str(path),
                           units=PAPER_UNITS)
    except OSError as exc:
        raise InputError(f"cannot read: {exc.strerror or exc}", path) from None


def _commands(lines: Iterable[str], name: str | None = None) -> Iterator[Command]:
    most = limits.CRCL_COMMANDS.value()
    count = 0
    for line, statement in _statements(lines, name):
        count += 1
        if most is not None and count > most:
            raise limits.CRCL_COMMANDS.error(None, name, line, "too many commands")
        try:
            yield _command(statement, line)
        except _Bad as bad:
            yield Unreadable(statement, reason=str(bad), line=line)


def _skipped(line: str) -> bool:
    stripped = line.strip()
    return not stripped or stripped.startswith(("#", "//"))


def _statements(lines: Iterable[str], name: str | None = None) -> Iterator[tuple[int, str]]:
    """(first line number, text) of each statement; continuation lines joined with ``\\n``.
    ``lines`` is read once, one line ahead."""
    longest = limits.LITERAL.value()
    numbered = enumerate((line.removesuffix("\r") for line in lines), 1)
    ahead = next(numbered, None)
    while ahead is not None:
        first, text = ahead
        ahead = next(numbered, None)
        if _skipped(text):
            continue
        parts, size = [text], len(text)
        open_ = _opened(text)
        while (open_ > 0 and ahead is not None and not _skipped(ahead[1])
               and not _START.match(ahead[1])):
            parts.append(ahead[1])
            size += len(ahead[1]) + 1
            if longest is not None and size > longest:
                raise limits.LITERAL.error(None, name, first, f"a statement of more than {longest:,} characters")
            open_ = _depth(parts)
            ahead = next(numbered, None)
        if longest is not None and size > longest:
            raise limits.LITERAL.error(None, name, first, f"a statement of {size:,} characters")
        yield first, "\n".join(parts)


def _opened(line: str) -> int:
    """:func:`_depth` of one line, by ``str.count`` where that gives the same answer: no
    string on the line and no bracket left open (the common, one-line command)."""
    if '"' not in line and "\u201c" not in line:
        depth = line.count("(") + line.count("{") - line.count(")") - line.count("}")
        if depth <= 0:  # _depth says the same or 0 (cannot tokenize): the statement ends
            return depth
    return _depth([line])


def _depth(parts: list[str]) -> int:
    """How many brackets the text leaves open (strings skipped; 0 once it cannot tokenize)."""
    depth = 0
    try:
        for kind, value in _tokens("\n".join(parts)):
            if kind == "punct":
                depth += {"(": 1, "{": 1, ")": -1, "}": -1}.get(value, 0)
    except _Bad:
        return 0
    return depth


def _tokens(text: str) -> list[tuple[str, str]]:
    """(kind, value) of each token of ``text``; _Bad at the first character that starts none."""
    pos, end = 0, len(text.rstrip())
    out = []
    for m in _TOKEN.finditer(text, 0, end):  # each match must start where the last ended
        if m.start() != pos:
            break
        kind = m.lastgroup or ""
        out.append(("string", m.group(kind)) if kind == "curly" else (kind, m.group(kind)))
        pos = m.end()
    if pos < end:
        raise _Bad(f"unexpected {text[pos:].strip()[:20]!r}")
    return out


def _command(statement: str, line: int) -> Command:
    tokens = _tokens(statement)
    if len(tokens) < 3 or tokens[0][0] != "name" or tokens[1] != ("punct", "("):
        raise _Bad("expected Name(arguments)")
    cls = COMMANDS.get(tokens[0][1])
    if cls is None:
        raise _Bad(f"unknown command {tokens[0][1]}")
    args, rest = _arguments(tokens, 2, ")")
    if rest != len(tokens):
        raise _Bad("text after the closing parenthesis")
    try:
        return _build(cls, args, line)
    except ValueError as exc:
        raise _Bad(str(exc)) from None


def _arguments(tokens: list[tuple[str, str]], pos: int, close: str) -> tuple[list[Any], int]:
    """Comma-separated values up to ``close``; the values and the position after ``close``."""
    values: list[Any] = []
    if pos < len(tokens) and tokens[pos] == ("punct", close):
        return values, pos + 1
    while pos < len(tokens):
        value, pos = _value(tokens, pos)
        values.append(value)
        if pos < len(tokens) and tokens[pos] == ("punct", close):
            return values, pos + 1
        if pos >= len(tokens) or tokens[pos] != ("punct", ","):
            break
        pos += 1
    raise _Bad(f"expected ',' or '{close}'")


def _value(tokens: list[tuple[str, str]], pos: int) -> tuple[Any, int]:
    kind, text = tokens[pos]
    if kind == "number":
        is_int = re.fullmatch(r"[+-]?\d+", text)
        if is_int and len(text) > 4000:  # int() refuses more than sys.get_int_max_str_digits() (4300)
            raise _Bad(f"a number of {len(text):,} digits")
        return (int(text) if is_int else float(text)), pos + 1
    if kind == "hex":  # a C99 hexadecimal floating constant, as strtod reads it
        try:
            return float.fromhex(text), pos + 1
        except OverflowError:
            raise _Bad(f"{text} is too large for a number") from None
    if kind == "string":
        return _Str(_UNESCAPE.sub(lambda m: _ESCAPES.get(m.group(1), m.group(0)), text)), pos + 1
    if (kind, text) == ("punct", "{"):
        return _arguments(tokens, pos + 1, "}")
    raise _Bad(f"unexpected {text!r}")


#: Command class -> the types of its fields but ``line`` (``dataclasses.fields`` is slow).
_KINDS: dict[type, list[Any]] = {}


class _Str(str):
    """A string argument (told apart from a bare name)."""


def _build(cls: type[Command], args: list[Any], line: int) -> Command:
    name = cls.__name__
    if cls is MoveThroughTo:
        if len(args) < 2 or type(args[-1]) is not int:
            raise _Bad("expected poses and their number")
        given = args[:-1]
        if len(given) == 1 and _pose_list(given[0]):  # NIST's form: the poses in braces
            given = given[0]
        poses = tuple(_pose(a) for a in given)
        if args[-1] != len(poses):
            raise _Bad(f"{args[-1]} poses announced, {len(poses)} given")
        return MoveThroughTo(poses, line=line)
    kinds = _KINDS.get(cls) or _KINDS.setdefault(cls, [f.type for f in fields(cls) if f.name != "line"])
    if cls is EndCanon and not args:
        args = [0]
    if len(args) != len(kinds):
        raise _Bad(f"{name} takes {len(kinds)} argument(s), {len(args)} given")
    values = [_convert(kind, arg, name) for kind, arg in zip(kinds, args)]
    if cls is SetLengthUnits:
        values = [_READ_UNITS.get(values[0], values[0])]
    return cls(*values, line=line)


def _convert(kind: Any, arg: Any, name: str) -> Any:
    if kind == "Pose":
        return _pose(arg)
    if kind == "str" and not isinstance(arg, _Str):
        raise _Bad(f"{name} takes a string in double quotes")
    if kind == "str":
        return str(arg)
    if kind == "int" and type(arg) is not int:
        raise _Bad(f"{name} takes an integer")
    if kind == "float" and type(arg) not in (int, float):
        raise _Bad(f"{name} takes a number")
    return arg


def _pose_list(arg: Any) -> bool:
    """Whether ``arg`` is a braced list of poses (NIST's ``{ pose, pose }``), not one pose."""
    return bool(isinstance(arg, list) and arg and isinstance(arg[0], list) and arg[0]
                and isinstance(arg[0][0], list))


def _pose(arg: Any) -> Pose:
    if (not isinstance(arg, list) or len(arg) != 3
            or not all(isinstance(v, list) and len(v) == 3 for v in arg)
            or not all(type(x) in (int, float) for v in arg for x in v)):
        raise _Bad("expected a pose {{x, y, z}, {i, j, k}, {i, j, k}}")
    point, z_axis, x_axis = arg
    return Pose(point=point, x_axis=x_axis, z_axis=z_axis)


# --- writing ----------------------------------------------------------------------------------

#: The layouts :func:`write_text` writes: NIST's kittingViewer form (the default), the paper's Fig. 11.
TEXT_STYLES = ("nist", "paper")
#: The longest line NIST's parser reads whole, in bytes without its newline: it reads a line with
#: ``fgets`` into ``char lineIn[TEXTSIZE]``, TEXTSIZE 200, which keeps 199 bytes and the end
#: NUL; the newline is one of the 199, and ``MoveThroughTo`` needs it after each comma.
NIST_LINE_BYTES = 198
#: The commands NIST's parser reads (``CommandParser::readCommandFile``).
NIST_COMMANDS = frozenset({
    "InitCanon", "EndCanon", "Message", "Dwell", "MoveTo", "MoveStraightTo", "MoveThroughTo", "OpenGripper",
    "CloseGripper", "OpenToolChanger", "CloseToolChanger", "SetLengthUnits", "SetAngleUnits", "SetAbsoluteSpeed",
    "SetRelativeSpeed", "SetAbsoluteAcceleration", "SetRelativeAcceleration", "SetEndAngleTolerance",
    "SetEndPointTolerance", "SetIntermediatePointTolerance"})
#: A C ``int`` (``sscanf("%d")``), the type of EndCanon's reason in NIST's parser.
_C_INT = (-2 ** 31, 2 ** 31 - 1)
#: A backslash kitkb's reader takes as an escape (NIST's parser reads every backslash as it stands).
_ESCAPE_READ = re.compile(r'\\(?:[nrt"\\]|$)')
#: Between two poses of a MoveThroughTo: NIST's parser needs the newline right after the comma.
_POSE_BREAK = ",\n  "
_MESSAGE_PROBLEMS = (('"', "a double quote"), ("\n", "a line break"), ("\r", "a carriage return"),
                     ("\0", "a NUL character"))


def write_text(program: Program, style: str = "nist") -> str:
    """The text form of ``program``, each statement ending with a newline: NIST's form
    (``style="nist"``, the default) or the first paper's (``"paper"``), as the module says.

    In NIST's form a command that NIST's parser would not read back as kitkb reads it is an
    :class:`~kb.core.errors.InputError` naming the program's source and the command's line
    (:func:`nist_unwritable` says why)."""
    if style == "paper":
        for c in program:
            problem = paper_unwritable(c)
            if problem:
                raise InputError(f"{problem}; the CRCL text form cannot hold it (CRCL 1.x XML can)",
                                 program.source, c.line)
        return "".join(f"{_line(c)}\n" for c in program)
    if style != "nist":
        raise ValueError(f"unknown CRCL text style {style!r}: {' or '.join(TEXT_STYLES)}")
    return "".join(f"{_nist_statement(c, program.source)}\n" for c in program)


def paper_unwritable(command: Command) -> str | None:
    """Why ``command`` has no statement in the first paper's text form (None when it has):
    a CRCL 1.x command the paper's language lacks, a MoveThroughTo in straight lines."""
    if isinstance(command, Unreadable):
        return None
    if type(command).__name__ not in COMMANDS:
        return f"{type(command).__name__} is a CRCL 1.x command the paper's language lacks"
    if isinstance(command, MoveThroughTo) and command.straight:
        return "a MoveThroughTo in straight lines (CRCL 1.x's MoveStraight true)"
    return None


def nist_unwritable(command: Command) -> str | None:
    """Why ``command`` cannot be written in NIST's text form so that NIST's parser reads what
    kitkb reads (None when it can); an :class:`~kb.crcl.commands.Unreadable` is written back
    as it stands, so it can."""
    if isinstance(command, Unreadable):
        return None
    problem = _nist_problem(command)
    if problem is not None:
        return problem
    longest = _longest_line(_nist_text(command, compact=True))
    if longest > NIST_LINE_BYTES:
        return (f"{type(command).__name__} needs a line of {longest} bytes, more than the {NIST_LINE_BYTES} "
                "NIST's parser reads on a line (its 200-byte line buffer)")
    return None


def _nist_statement(command: Command, source: str | None) -> str:
    if isinstance(command, Unreadable):
        return command.text
    problem = _nist_problem(command)
    if problem is None:
        text = _nist_text(command, compact=False)
        if len(text) <= NIST_LINE_BYTES // 4 or _longest_line(text) <= NIST_LINE_BYTES:
            return text
        text = _nist_text(command, compact=True)  # the same numbers, spelt shorter
        if _longest_line(text) <= NIST_LINE_BYTES:
            return text
        problem = nist_unwritable(command)
    raise InputError(f"{problem}; NIST's CRCL text form cannot hold it (the paper's form can: "
                     "--text-style paper)", source, command.line)


def _nist_problem(command: Command) -> str | None:
    """What NIST's parser cannot read of ``command``, but for its lines' length."""
    name = type(command).__name__
    if name not in NIST_COMMANDS:
        return f"{name} is not a command of NIST's CRCL text form (the kittingViewer's parser)"
    if isinstance(command, MoveThroughTo) and command.straight:
        return "a MoveThroughTo in straight lines (CRCL 1.x's MoveStraight true) has no text form"
    if isinstance(command, Message):
        text = command.message
        if not text:
            return "an empty Message (NIST's parser reads one character or more between the quotes)"
        for char, what in _MESSAGE_PROBLEMS:
            if char in text:
                return f"a Message holding {what}"
        if _ESCAPE_READ.search(text):
            return ("a Message holding a backslash that kitkb reads as an escape (\\\\, \\\", \\n, \\r, \\t, "
                    "or one at its end); NIST's parser has no escapes")
    if isinstance(command, EndCanon) and not _C_INT[0] <= command.reason <= _C_INT[1]:
        return f"EndCanon({command.reason}): NIST's parser reads the reason as a C int"
    return None


def _longest_line(text: str) -> int:
    """The UTF-8 bytes of the longest line of ``text``."""
    return max(len(line.encode()) if not line.isascii() else len(line) for line in text.split("\n"))


def _nist_text(command: Command, compact: bool) -> str:
    """``command`` as NIST's files write it (``compact``: poses without spaces, numbers without
    a leading zero or exponent padding: the same values in fewer bytes)."""
    name = type(command).__name__
    if isinstance(command, MoveThroughTo):
        poses = [_nist_pose(p, compact) for p in command.waypoints]
        return f"{name}({{ {_POSE_BREAK.join(poses)} }}, {len(poses)})"
    if isinstance(command, (MoveTo, MoveStraightTo)):
        return f"{name}({_nist_pose(command.end_position, compact)})"
    if isinstance(command, Message):
        return f'{name}("{command.message}")'
    args = []
    for f in fields(command):
        if f.name == "line":
            continue
        value = getattr(command, f.name)
        args.append(f'"{value}"' if isinstance(value, str) else str(value) if isinstance(value, int)
                    else _short(value) if compact else _number(value))
    return f"{name}({', '.join(args)})"


def _nist_pose(pose: Pose, compact: bool) -> str:
    """``{{x,y,z}, {i,j,k}, {i,j,k}}`` as the kittingViewer's files have it (compact: no spaces)."""
    number = _short if compact else _number
    triples = ("{" + ",".join(number(v) for v in vec) + "}" for vec in (pose.point, pose.z_axis, pose.x_axis))
    return "{" + ("," if compact else ", ").join(triples) + "}"


def _short(x: float) -> str:
    """:func:`_number` in fewer characters that ``strtod`` reads as the same value: ``.5`` for
    ``0.5``, ``1e-5`` for ``1e-05``."""
    mantissa, e, exponent = _number(x).partition("e")
    if mantissa.startswith(("0.", "-0.")):
        mantissa = mantissa.replace("0.", ".", 1)
    return f"{mantissa}e{int(exponent)}" if e else mantissa


def _line(command: Command) -> str:
    if isinstance(command, Unreadable):
        return command.text
    if isinstance(command, MoveThroughTo):
        args = [_pose_text(p) for p in command.waypoints] + [str(command.num_positions)]
    else:
        args = [_arg(getattr(command, f.name)) for f in fields(command) if f.name != "line"]
        if isinstance(command, SetLengthUnits):
            args = [_string(_TEXT_UNITS.get(command.unit_name, command.unit_name))]
    return f"{type(command).__name__}({', '.join(args)})"


def _arg(value: Any) -> str:
    if isinstance(value, Pose):
        return _pose_text(value)
    if isinstance(value, str):
        return _string(value)
    if isinstance(value, int):
        return str(value)
    return _number(value)


def _number(x: float) -> str:
    """Shortest text that reads back as ``x`` (``5`` for 5.0)."""
    text = repr(float(x))
    return text[:-2] if text.endswith(".0") else text


def _string(s: str) -> str:
    escaped = (s.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n")
               .replace("\r", "\\r").replace("\t", "\\t"))
    return f'"{escaped}"'


def _pose_text(pose: Pose) -> str:
    return "{" + ", ".join("{" + ", ".join(_number(v) for v in vec) + "}"
                           for vec in (pose.point, pose.z_axis, pose.x_axis)) + "}"
