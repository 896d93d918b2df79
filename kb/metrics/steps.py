"""A CRCL program as the metrics read it: one :data:`Step` per command, in file order.

A step is a plain tuple ``(kind, line, value)``: ``kind`` the command's name (CRCL.xsd's, or
``"Unreadable"``), ``line`` where it stands in its file, ``value`` its one argument (a number,
a name, the unreadable text) or, for the three moves, its poses as 9-tuples (point, Z axis,
X axis). :func:`steps_of` makes them from :mod:`kb.crcl` commands, so any program kitkb reads
(text or CRCL.xsd XML) can be measured.

:func:`read_steps` reads a file. For the text form it has a fast path: a line holding one
complete, plainly written command (numbers, poses, a name in double quotes without escapes)
becomes its step directly, without a :class:`~kb.crcl.commands.Command` in between; every
other line — continued statements, escapes, typographic quotes, comments after a command,
anything that does not parse — is read by :func:`kb.crcl.read_text` itself, so what kitkb
reads and what the metrics count cannot differ (``tests/test_metrics.py`` holds them equal).
"""

from __future__ import annotations

import math
import re
from pathlib import Path
from typing import TYPE_CHECKING, Any, Iterable, Iterator, Literal

from kb.core import limits
from kb.core.errors import InputError
from kb.core.files import note_input, utf8_lines

if TYPE_CHECKING:
    from kb.crcl.commands import Command
    from kb.crcl.pose import Pose

# kb.crcl (with numpy and lxml) is imported only where a line needs it, so that a plainly
# written program is measured without it; tests/test_metrics.py holds these names equal to its.
#: CRCL.xsd's angle units (kb.crcl.ANGLE_UNITS) and the paper's frames (kb.crcl.COORDINATE_FRAMES).
ANGLE_UNITS = ("degree", "radian")
COORDINATE_FRAMES = ("Workstation", "RobotBase", "ToolTip")
#: The units InitCanon sets in the text form (kb.crcl.PAPER_UNITS: the first paper's).
_PAPER_UNITS = ("millimeter", "degree")
#: Length unit names the text form reads (kb.crcl.LENGTH_UNITS and the paper's "mm").
TEXT_LENGTH_UNITS = frozenset({"meter", "millimeter", "inch", "mm"})

#: ``(kind, line, value)``; see the module's docstring.
Step = tuple[str, "int | None", Any]
#: A pose as the metrics keep it: x, y, z, the Z axis (i, j, k), the X axis (i, j, k).
PoseTuple = tuple[float, float, float, float, float, float, float, float, float]

#: Commands without arguments.
BARE = frozenset({"InitCanon", "CloseGripper", "OpenGripper", "CloseToolChanger", "OpenToolChanger",
                  "StopObjectScan"})
#: Commands with one number (a float field).
NUMBER = frozenset({"Dwell", "SetAbsoluteSpeed", "SetRelativeSpeed", "SetAbsoluteAcceleration",
                    "SetRelativeAcceleration", "SetEndAngleTolerance", "SetEndPointTolerance",
                    "SetIntermediatePointTolerance"})
#: Commands with one name, and the names each allows (None: any).
NAMED: dict[str, frozenset[str] | None] = {
    "SetLengthUnits": TEXT_LENGTH_UNITS,
    "SetAngleUnits": frozenset(ANGLE_UNITS),
    "SetCoordinateFrame": frozenset(COORDINATE_FRAMES),
    "StartObjectScan": None,
    "Message": None,
}
MOVES = frozenset({"MoveTo", "MoveStraightTo", "MoveThroughTo"})


# --- from kb.crcl commands ------------------------------------------------------------------------

def pose_tuple(pose: Pose) -> PoseTuple:
    """``pose`` as (x, y, z, Z axis, X axis)."""
    return (*pose.point, *pose.z_axis, *pose.x_axis)  # type: ignore[return-value]


def step_of(command: Command, line_offset: int = 0) -> Step:
    """The step of one :mod:`kb.crcl` command (its line moved on by ``line_offset``)."""
    kind = type(command).__name__
    line = None if command.line is None else command.line + line_offset
    c: Any = command
    if kind in ("MoveTo", "MoveStraightTo"):
        return kind, line, (pose_tuple(c.end_position),)
    if kind == "MoveThroughTo":
        return kind, line, tuple(pose_tuple(p) for p in c.waypoints)
    if kind == "Unreadable":
        return kind, line, (c.text, c.reason)
    if kind in ("EndCanon", "StopMotion"):
        return kind, line, c.reason if kind == "EndCanon" else c.is_emergency
    if kind in NUMBER or kind in NAMED:
        return kind, line, getattr(command, _FIELD[kind])
    if kind == "SetEndEffector":
        return kind, line, c.setting
    if kind in BARE:
        return kind, line, None
    return kind, line, command  # a CRCL 1.x command the paper's language lacks, kept whole


class Steps(list):  # type: ignore[type-arg]
    """A program's steps and ``units``: the (length, angle) units its form's InitCanon sets
    (:data:`kb.crcl.commands.PAPER_UNITS` for text and 2014 XML, CRCL 1.x's metre and radian;
    None: not known)."""

    def __init__(self, steps: Iterable[Step] = (), units: tuple[str, str] | None = None) -> None:
        super().__init__(steps)
        self.units = units


_FIELD = {**{k: "percent" for k in ("SetRelativeSpeed", "SetRelativeAcceleration")},
          "Dwell": "dwell_time", "SetAbsoluteSpeed": "speed", "SetAbsoluteAcceleration": "acceleration",
          **{k: "tolerance" for k in ("SetEndAngleTolerance", "SetEndPointTolerance",
                                      "SetIntermediatePointTolerance")},
          "SetLengthUnits": "unit_name", "SetAngleUnits": "unit_name", "SetCoordinateFrame": "coord_system",
          "StartObjectScan": "name", "Message": "message"}


def steps_of(commands: Iterable[Command], line_offset: int = 0) -> list[Step]:
    """The steps of :mod:`kb.crcl` commands (a :class:`~kb.crcl.commands.Program`, whose
    ``units`` they keep)."""
    return Steps((step_of(c, line_offset) for c in commands), getattr(commands, "units", None))


# --- reading files ----------------------------------------------------------------------------------

def read_steps(path: str | Path) -> Steps:
    """The steps of the CRCL program in ``path`` (``.crcl`` text, ``.xml`` CRCL.xsd or CRCL 1.x
    XML) with its form's units (:class:`Steps`); an unreadable file or an unknown suffix is an
    :class:`~kb.core.errors.InputError`."""
    if Path(path).suffix.lower() != ".crcl":
        from kb.crcl import read_xml
        from kb.crcl.files import form_of
        form_of(path)  # .xml, or an InputError naming the suffixes
        note_input(path)
        return steps_of(read_xml(Path(path)))
    note_input(path)
    try:
        try:  # decoded by the io layer, line by line ("\n" ends a line, as in kb.crcl)
            with open(path, encoding="utf-8", newline="\n") as f:
                return Steps(text_steps(_text_lines(f), str(path)), _PAPER_UNITS)
        except UnicodeDecodeError:  # find the line that is not UTF-8
            with open(path, "rb") as f:
                return Steps(text_steps(_lines(f, Path(path)), str(path)), _PAPER_UNITS)
    except OSError as exc:
        raise InputError(f"cannot read: {exc.strerror or exc}", path) from None


def require_steps(steps: list[Step], source: str | Path | None = None) -> list[Step]:
    """``steps``, if one of them is a command understood; else an
    :class:`~kb.core.errors.InputError` at the first unreadable line saying what was looked for
    (a file of which nothing is read is not a program: its metrics would be a success of nothing)."""
    if any(step[0] != "Unreadable" for step in steps):
        return steps
    from kb.crcl.files import nothing_understood
    first = steps[0] if steps else None
    form = "xml" if source is not None and Path(source).suffix.lower() == ".xml" else "text"
    raise nothing_understood(source, len(steps), first[1] if first else None, first[2][1] if first else "", form)


def _text_lines(f: Any) -> Iterator[str]:
    """The lines of a text file with their ``\\n`` (:func:`text_steps` takes them off where it
    needs to), the first without a byte order mark."""
    first = f.readline()
    if first:
        yield first.removeprefix("\ufeff")
        yield from f


def _lines(f: Any, path: Path) -> Iterator[str]:
    return (line.removesuffix("\r") for line in utf8_lines(f, path))


def text_steps(lines: Iterable[str], name: str | None = None) -> Iterator[Step]:
    """The steps of CRCL text given as lines (with or without their ``\\n``): fast lines
    directly, runs of the other lines through :func:`kb.crcl.read_text`. More commands than
    :data:`kb.core.limits.CRCL_COMMANDS` (kb.crcl's bound) is an InputError at its line."""
    most = limits.CRCL_COMMANDS.value()
    count = 0
    for step in _text_steps(lines, name):
        count += 1
        if most is not None and count > most:
            raise limits.CRCL_COMMANDS.error(None, name, step[1], "too many commands")
        yield step


def _text_steps(lines: Iterable[str], name: str | None) -> Iterator[Step]:
    slow: list[str] = []
    first = 0
    through: _Through | None = None
    for number, line in enumerate(lines, 1):
        if through is not None:
            done = through.add(line)
            if done is None:  # a pose of the middle
                continue
            if done is not False:
                through = None
                yield done
                continue
            # not NIST's layout after all: its lines go the slow way, and this line after them
            first, slow, through = through.first, through.text(), None
        step = _fast(line, number)
        if step is None:
            start = _THROUGH_FIRST.fullmatch(line)
            if start is not None:
                values = tuple(map(float, start.groups()))
                if math.isfinite(sum(values)):
                    if slow:  # the MoveThroughTo starts a statement in kb.crcl too
                        yield from _slow(slow, first, name)
                        slow = []
                    through = _Through(number, line, values)
                    continue
            if not slow and _skipped(line):
                continue
            if not slow:
                first = number
            slow.append(line.removesuffix("\n"))
            continue
        if slow:
            yield from _slow(slow, first, name)
            slow = []
        yield step
    if through is not None:  # the file ends inside it
        first, slow = through.first, through.text()
    if slow:
        yield from _slow(slow, first, name)


def _skipped(line: str) -> bool:
    stripped = line.strip()
    return not stripped or stripped.startswith(("#", "//"))


def _slow(lines: list[str], first: int, name: str | None) -> list[Step]:
    from kb.crcl import read_text
    try:
        program = read_text("\n".join(lines), name=name)
    except InputError as exc:  # a limit: name the line in the whole file
        raise InputError(exc.message, name, None if exc.line is None else exc.line + first - 1) from None
    return steps_of(program, first - 1)


# --- the fast path ----------------------------------------------------------------------------------

_NUM = r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?"
_TRIPLE = rf"\{{\s*({_NUM})\s*,\s*({_NUM})\s*,\s*({_NUM})\s*\}}"
_POSE = rf"\{{\s*{_TRIPLE}\s*,\s*{_TRIPLE}\s*,\s*{_TRIPLE}\s*\}}"
_TRIPLE_ANY = rf"\{{\s*{_NUM}\s*,\s*{_NUM}\s*,\s*{_NUM}\s*\}}"
_POSE_ANY = rf"\{{\s*{_TRIPLE_ANY}\s*,\s*{_TRIPLE_ANY}\s*,\s*{_TRIPLE_ANY}\s*\}}"
_STATEMENT = re.compile(r"\s*([A-Za-z_]\w*)\s*\(\s*(.*?)\s*\)\s*")
_INT = re.compile(r"[+-]?\d+")
#: ``Name(number)``, ``Name("text")`` (no escapes) or ``Name()``.
_SIMPLE = re.compile(rf'\s*([A-Za-z_]\w*)\s*\(\s*(?:({_NUM})|"([^"\\\n]*)")?\s*\)\s*')
#: The commands without arguments, as they are usually written.
_BARE_TEXT = {f"{kind}()": (kind, None) for kind in BARE} | {"EndCanon()": ("EndCanon", 0)}
_ONE_POSE = re.compile(_POSE)
_MOVE = re.compile(rf"\s*(MoveTo|MoveStraightTo)\s*\(\s*{_POSE}\s*\)\s*")
_POSES = re.compile(rf"((?:{_POSE_ANY}\s*,\s*)+)({_INT.pattern})")
_VALUES = re.compile(_NUM)


#: NIST's MoveThroughTo over several lines (``MoveThroughTo({ pose,`` / ``pose,`` / ``pose }, n)``).
_THROUGH_FIRST = re.compile(rf"\s*MoveThroughTo\s*\(\s*\{{\s*{_POSE}\s*,\s*")
_THROUGH_NEXT = re.compile(rf"\s*{_POSE}\s*,\s*")
_THROUGH_LAST = re.compile(rf"\s*{_POSE}\s*\}}\s*,\s*({_INT.pattern})\s*\)\s*")
#: One line of NIST's MoveThroughTo: the poses in braces, then their number.
_BRACED_POSES = re.compile(rf"\{{\s*((?:{_POSE_ANY}\s*,\s*)*{_POSE_ANY})\s*\}}\s*,\s*({_INT.pattern})")


class _Through:
    """A MoveThroughTo in NIST's layout read fast, a pose a line. :meth:`add` takes the next
    line: None, a pose of the middle (go on); the step, at the last pose and the count; False,
    anything else (the line is not taken: :meth:`text` gives the lines taken back, for kb.crcl
    to read with the lines after them)."""

    __slots__ = ("first", "lines", "poses", "size", "longest")

    def __init__(self, first: int, line: str, values: tuple[float, ...]) -> None:
        self.first, self.lines, self.poses = first, [line], [values]
        self.size, self.longest = len(line), limits.LITERAL.value()

    def add(self, line: str) -> Step | None | Literal[False]:
        """Take ``line`` if it goes on NIST's layout; see the class."""
        if self.longest is not None and self.size + len(line) > self.longest:
            return False  # kb.crcl says how long the statement is
        m = _THROUGH_NEXT.fullmatch(line)
        last = None if m is not None else _THROUGH_LAST.fullmatch(line)
        if m is None and last is None:
            return False
        values = tuple(map(float, (m or last).groups()[:9]))  # type: ignore[union-attr]
        if not math.isfinite(sum(values)) or (last is not None and int(last.group(10)) != len(self.poses) + 1):
            return False  # kb.crcl says what is wrong
        self.lines.append(line)
        self.size += len(line)
        self.poses.append(values)
        return None if last is None else ("MoveThroughTo", self.first, tuple(self.poses))

    def text(self) -> list[str]:
        """The lines taken, without their newlines."""
        return [line.removesuffix("\n") for line in self.lines]


def _fast(line: str, number: int) -> Step | None:
    """The step of a plainly written one-line command, or None (read it the slow way)."""
    m = _MOVE.fullmatch(line)
    if m is not None:  # the commonest command first, in one match
        groups = m.groups()
        values = tuple(map(float, groups[1:]))
        # a sum of finite numbers can overflow: such a line only takes the slow path
        return (groups[0], number, (values,)) if math.isfinite(sum(values)) else None
    bare = _BARE_TEXT.get(line.strip())
    if bare is not None:  # CloseGripper() and the like, without a regular expression
        return bare[0], number, bare[1]
    m = _SIMPLE.fullmatch(line)
    if m is not None:
        return _simple(*m.groups(), number)
    m = _STATEMENT.fullmatch(line)
    if m is not None and m.group(1) in MOVES:
        return _fast_move(m.group(1), m.group(2), number)
    return None


def _simple(kind: str, number_text: str | None, text: str | None, number: int) -> Step | None:
    """``Name(number)``, ``Name("text")`` or ``Name()``."""
    if number_text is not None:
        if kind in NUMBER:
            value = float(number_text)
            return (kind, number, value) if math.isfinite(value) else None
        if kind in ("EndCanon", "StopMotion") and _INT.fullmatch(number_text):
            return kind, number, int(number_text)
        return None
    if text is not None:
        if kind not in NAMED:
            return None
        allowed = NAMED[kind]
        if allowed is not None and text not in allowed:
            return None
        return kind, number, "millimeter" if text == "mm" and kind == "SetLengthUnits" else text
    if kind in BARE:
        return kind, number, None
    return (kind, number, 0) if kind == "EndCanon" else None


def _fast_move(kind: str, args: str, number: int) -> Step | None:
    if kind == "MoveThroughTo":  # the paper's poses, or NIST's in braces
        m = _POSES.fullmatch(args) or _BRACED_POSES.fullmatch(args)
        if m is None:
            return None
        values = tuple(map(float, _VALUES.findall(m.group(1))))
        count = len(values) // 9
        # a sum of finite numbers can overflow (math.fsum would raise): such a line takes the slow path
        if int(m.group(2)) != count or not math.isfinite(sum(values)):
            return None
        return kind, number, tuple(values[i:i + 9] for i in range(0, len(values), 9))
    m = _ONE_POSE.fullmatch(args)
    if m is None:
        return None
    values = tuple(map(float, m.groups()))
    # a sum of finite numbers can overflow: such a line only takes the slow path
    return (kind, number, (values,)) if math.isfinite(sum(values)) else None
