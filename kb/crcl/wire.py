"""kitkb's cell protocol on the wire: two TCP ports, the sensor's UTF-8 lines of ``{Key value}``
fields (USARTruth's key-value style, seed 004 §3.2) and the robot's CRCL 1.x documents.

Sensor port (default :data:`SENSOR_PORT` 3989, USARTruth's): USARSim's USARTruth protocol, so
the USARTruth clients of NIST and GTRI (el-robotics-core) read it. The client sends one query a
line (ending in ``\n``, ``\r\n`` or a ``\r`` alone, as USARSim read them) and gets the answer
lines, each ending in ``\r\n`` as USARSim's, then ``{End}``; connections stay open for more
queries. A query is any of these fields, on one line, in any order, keys in any case, with or
without spaces between them::

    {class C}            objects of class C: a kitting class (local name in any case, or IRI;
                         subclasses included), or Unreal's names for them: a package prefix is
                         dropped (USARPhysObj.Part is Part), Actor is every object, WCObject
                         every SolidObject, Pawn every Robot (:func:`kb.sim.sensor.truth_class`)
    {name N}             the object named N (its local name or IRI)
    {class C} {name N}   the object named N if it is of class C
    (an empty line, or empty values)   every placed object
    {Fields Sku}         kitkb's fields beyond USARTruth's, in this query's answer (below)
    {Inspect part_a_1}   kitkb's quality inspection (alone on its line):
                         {Name part_a_1} {Quality ok|defective}, then {End}

The answer is one truth line per placed object asked for, in name order, then ``{End}``; a
query that matches nothing (an unknown class or name) is ``{End}`` alone, as USARSim answered.
A truth line has USARTruth's five fields and no other (GTRI's client refuses a line with any
other field)::

    {Name IRI} {Class C} {Time t} {Location x,y,z} {Rotation r,p,y}

and, when the query asks for it with ``{Fields Sku}``, ``{Sku S}`` after them (the SKU the
sensor recognises; :func:`kb.crcl.cell.truth_line`). kitkb's :class:`~kb.crcl.remote.RemoteCell`
asks for it in every query. A line that is not a query (text outside fields, an unknown key, a
key given twice, Inspect beside another key) is answered ``{Error <message>}``, then
``{End}``; no USARTruth client sends one. docs/execution.md says what still differs from
USARSim (IRIs for Unreal names, kitkb's frame and units).

Command port (default :data:`COMMAND_PORT` 3990): a CRCL 1.x controller, as NIST's tools speak
CRCL (../shared/crcl/README.md, doc/Reference.md). One TCP connection per client; the client
writes complete ``CRCLCommandInstance`` documents one after another, with no header or
delimiter (white space between them, an XML declaration in each, allowed); :class:`Documents`
splits the stream at the end of each root element. A ``CRCLProgram`` of
CRCLProgramInstance.xsd is taken too and run command by command. The controller writes
``CRCLStatus`` documents back (:func:`kb.crcl.instance.write_status`), each with its own
``send`` and under 1,024 bytes with a pose and a gripper (a simple client reads one per
``recv(1024)``):

* when a command ends: its CommandID with ``CRCL_Done`` or ``CRCL_Error`` (``StateDescription``
  says why, or what the cell did: ``grasped ...``, ``mounted ...``);
* on ``GetStatus``: the status now, of the command executing or last executed (GetStatus does
  not become that command); before any command CommandID 0, ``CRCL_Ready``;
* every :data:`STATUS_PERIOD` seconds (a heartbeat) on a connection that was sent none in that
  time, ``CRCL_Working`` while its command waits for the cell.

StatusIDs count up from 1 on each connection. The pose is the tool tip's (the mounted
gripper's, Reference.md VIII) in the connection's length unit; the gripper status is the
mounted effector's (``ParallelGripperStatusType``: the jaws' opening, ``VacuumGripperStatusType``).
Several clients may connect at once (a robot and a gripper): each connection is its own session
with its own CommandIDs, status stream and units, all driving the one robot; a connection that
has only sent gripper commands is a gripper channel, whose statuses carry no pose. A
``ConfigureStatusReport`` sets what that connection's statuses carry from then on (the pose,
the gripper, the settings: units, speed, end effector; kitkb's controller has no joint, sensor
or guard statuses to add). A document
that is well-formed CRCL but wrong (an unknown command, a bad number) gets ``CRCL_Error``
naming the problem, with its CommandID where one can be read, and the connection goes on; a
document that is not CRCL (another root element), a stream that is not XML, a DOCTYPE, or a
document past the bounds (:data:`MAX_PROGRAM` bytes, ``KITKB_MAX_NESTING`` levels) gets a
``CRCL_Error`` status saying so, and that connection is closed (it cannot be resynchronised).

kitkb's earlier protocol stays on the same port for the clients of 472f1d7: a connection whose
first byte (after white space) is ``{`` sends a header line ``{Length N}`` and then exactly N
bytes: one CRCL.xsd instance (a ``CRCLProgram`` document, :func:`kb.crcl.xml.write_xml`; at most
:data:`MAX_PROGRAM` bytes). The cell executes every command of the program in order (InitCanon
and EndCanon included), stops at the first that fails, and answers one line per command
(ending in ``\n``), then ``{End}``::

    {Line n} {Status done|error} {Message text}

``n`` is the command's position in the program (1: its InitCanon); a command after a failed
one is not executed and answers ``{Status error} {Message`` :data:`kb.crcl.cell.NOT_EXECUTED`
``}``. A program that does not parse answers one ``{Status error} {Message program:line:
error: ...}`` line (no ``{Line}``), then ``{End}``; a header that is not ``{Length N}`` gets
the same and the connection is closed (the stream cannot be resynchronised).

kitkb's two conventions, CRCL ``Message`` commands a cell of this port does not display:

* ``kitkb-action <index> <action> <arg1> <arg2> ...`` (:func:`action_message`): the cell
  starts plan action ``index`` (``begin_action``) and answers ``done``, or ``error`` when the
  text is malformed;
* ``kitkb-frame [init] [end]`` as the program's *second* command (:func:`frame_message`; the
  ``{Length N}`` protocol only: a CRCL 1.x client sends the commands it means, one by one): the
  program's first command (its InitCanon) with ``init``, its last (its EndCanon) with ``end``,
  and the message itself are only CRCL.xsd's frame around the commands a client means: they
  are not executed and answer ``{Status done} {Message frame}``. This is how a client sends
  commands that are not a whole program (an action's list, ``begin_action``) so that the cell
  executes those and nothing else. Elsewhere ``kitkb-frame`` is an ordinary message.

Text put into a field has ``{`` and ``}`` replaced by ``(`` and ``)`` and line breaks and tabs
by spaces (:func:`clean`): a value never holds a brace. Either side reads lines of at most
:data:`MAX_LINE` bytes; how much of an answer a client waits for is bounded too
(:class:`kb.crcl.remote.RemoteCell`, :class:`kb.crcl.remote.CrclClient`).
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Any
from xml.parsers import expat

from kb.core import limits
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
#: The fields of a USARTruth answer line: all a USARTruth client reads (GTRI's refuses others).
TRUTH_FIELDS = ("Name", "Class", "Time", "Location", "Rotation")
#: kitkb's fields beyond them, in an answer only when its query asks (``{Fields Sku}``).
EXTRA_FIELDS = ("Sku",)
#: The line end of the sensor port's answers (USARSim's).
CRLF = "\r\n"
_QUERY_KEYS = ("class", "name", "fields", "inspect")
#: A query's field: ``{key value}``, ``{key}`` or ``{ key  value }`` (USARSim trims both).
_QUERY_FIELD = re.compile(r"\{\s*(\w+)(?:\s+([^{}]*?))?\s*\}")
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

@dataclass(frozen=True)
class Query:
    """One sensor-port query: objects of class ``cls`` and name ``name`` ("": any), with
    kitkb's ``fields`` (of :data:`EXTRA_FIELDS`) in the answer; or the inspection of ``inspect``."""

    cls: str = ""
    name: str = ""
    fields: tuple[str, ...] = ()
    inspect: str = ""


def query_line(kind: str, value: str, fields: tuple[str, ...] | list[str] = ()) -> str:
    """The sensor query ``{Class value}``, ``{Name value}`` or ``{Inspect value}``, with
    ``{Fields ...}`` when ``fields`` (of :data:`EXTRA_FIELDS`) are asked for; ValueError for
    another kind or field, or a value that is empty or holds braces or line breaks."""
    if kind not in QUERIES:
        raise ValueError(f"a sensor query is by {', '.join(QUERIES)}, not {kind!r}")
    if not value.strip() or clean(value) != value:
        raise ValueError(f"cannot query {value!r}: empty, or with braces or line breaks")
    unknown = [f for f in fields if f not in EXTRA_FIELDS]
    if unknown:
        raise ValueError(f"no field {unknown[0]!r}: the extra fields are {', '.join(EXTRA_FIELDS)}")
    line = field(kind.capitalize(), value)
    return line + (" " + field("Fields", ",".join(fields)) if fields and kind != "inspect" else "")


def parse_query(line: str) -> Query:
    """The :class:`Query` of a sensor-port line, read as USARSim read it (keys in any case,
    fields with or without spaces between them, empty values meaning any); ValueError naming
    what is wrong for a line that is not a query."""
    found: dict[str, str] = {}
    for key, value in _QUERY_FIELD.findall(line):
        k = key.lower()
        if k not in _QUERY_KEYS:
            raise ValueError(f"unknown key {key!r} in {line.strip()[:80]!r}: a query has class, name, fields "
                             "or inspect")
        if k in found:
            raise ValueError(f"key {key!r} twice in {line.strip()[:80]!r}")
        found[k] = value.strip()
    rest = _QUERY_FIELD.sub("", line).strip()
    if rest:
        raise ValueError(f"not a line of key-value fields: {line.strip()[:80]!r}")
    if "inspect" in found:
        if len(found) > 1 or not found["inspect"]:
            raise ValueError(f"an Inspect query names one part and nothing else, not {line.strip()[:80]!r}")
        return Query(inspect=found["inspect"])
    return Query(found.get("class", ""), found.get("name", ""), _extra(found.get("fields", "")))


def _extra(text: str) -> tuple[str, ...]:
    """The extra fields a ``{Fields ...}`` value names (comma or space separated, any case)."""
    known = {f.lower(): f for f in EXTRA_FIELDS}
    out = []
    for word in filter(None, re.split(r"[\s,]+", text)):
        if word.lower() not in known:
            raise ValueError(f"no field {word!r} to ask for: the extra fields are {', '.join(EXTRA_FIELDS)}")
        out.append(known[word.lower()])
    return tuple(dict.fromkeys(out))


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


# --- CRCL 1.x on the command port -------------------------------------------------------------

#: CRCL 1.x's command states (CRCLStatus.xsd's CommandStateEnumType).
WORKING, DONE, ERROR, READY = "CRCL_Working", "CRCL_Done", "CRCL_Error", "CRCL_Ready"
#: Seconds after which a CRCL 1.x connection that was sent no status is sent one (a heartbeat).
STATUS_PERIOD = 1.0


class DocumentError(ValueError):
    """The stream is not a sequence of XML documents (not XML, a DOCTYPE, a document past its
    bounds): the connection cannot be resynchronised. ``documents``: those completed before
    the fault, in the same bytes."""

    def __init__(self, message: str, documents: "list[Document] | None" = None) -> None:
        super().__init__(message)
        self.documents = documents or []


@dataclass(frozen=True)
class Document:
    """One complete XML document of a stream: its bytes (XML declaration included) and the local
    name of its root element."""

    data: bytes
    root: str


_SPACE = b" \t\r\n"
#: The bytes a document may start with: '<', or a byte order mark (UTF-8, UTF-16).
_FIRST = frozenset(b"<\xef\xfe\xff")


class _RootEnded(Exception):
    """Raised from expat's handler when the root element ends (stops the parse there)."""


class Documents:
    """Splits a byte stream into complete XML documents, as CRCL 1.x travels on TCP: documents
    one after another with no header or delimiter, each ended by the end of its root element
    (:meth:`feed` bytes as they arrive, get the documents completed). White space between
    documents (and before a document's XML declaration, which NIST's Python client sends) is
    skipped; each document may have its own XML declaration and encoding.

    Each document is parsed incrementally (expat) only to find where it ends; a
    :class:`DocumentError` names what is wrong when the bytes are not XML, hold a DOCTYPE (no
    entity is expanded), nest deeper than ``max_depth`` or make a document longer than
    ``max_bytes`` before its end. After a DocumentError the stream cannot be read on."""

    def __init__(self, max_bytes: int | None = MAX_PROGRAM, max_depth: int | None = None) -> None:
        self.max_bytes, self.max_depth = max_bytes, max_depth if max_depth is not None else limits.NESTING.value()
        self._buf = bytearray()
        self._parser: Any = None
        self._fed = 0  # bytes of _buf the current parser has seen
        self._depth = 0
        self._root = ""
        self._end = 0  # where the root element's end tag begins (or its empty tag ends)

    @property
    def pending(self) -> int:
        """Bytes held of a document not complete yet (white space between documents excluded)."""
        return len(self._buf.lstrip(_SPACE))

    def feed(self, data: bytes) -> list[Document]:
        """The documents that ``data`` completes, in order; DocumentError when the stream is broken."""
        self._buf += data
        out: list[Document] = []
        while True:
            if self._parser is None:
                start = len(self._buf) - len(self._buf.lstrip(_SPACE))
                del self._buf[:start]
                if not self._buf:
                    return out
                if self._buf[0] not in _FIRST:  # expat would wait for more before it says so
                    raise DocumentError(f"not XML: a document starts with '<', not {bytes(self._buf[:20])!r}", out)
                self._begin()
            chunk = bytes(self._buf[self._fed:])
            if not chunk:
                return out
            try:
                self._parser.Parse(chunk, False)
            except _RootEnded:
                # expat gives where an end tag begins, or where an empty element's tag ends
                end = _tag_end(self._buf, self._end) if self._buf[self._end:self._end + 2] == b"</" else self._end
                out.append(Document(bytes(self._buf[:end]), self._root))
                del self._buf[:end]
                self._parser = None
                continue
            except expat.ExpatError as exc:
                raise DocumentError(f"not XML: line {exc.lineno}, column {exc.offset + 1}: "
                                    f"{expat.ErrorString(exc.code)}", out) from None
            except DocumentError as exc:
                exc.documents = out
                raise
            self._fed = len(self._buf)
            if self.max_bytes is not None and len(self._buf) > self.max_bytes:
                raise DocumentError(f"a document longer than {self.max_bytes:,} bytes without its end "
                                    f"(<{self._root or '?'}> not closed)", out)
            return out

    def _begin(self) -> None:
        p = expat.ParserCreate()
        p.StartElementHandler = self._start
        p.EndElementHandler = self._stop
        p.StartDoctypeDeclHandler = _no_doctype
        p.EntityDeclHandler = _no_doctype
        self._parser, self._fed, self._depth, self._root = p, 0, 0, ""

    def _start(self, name: str, attrs: object) -> None:
        if not self._depth:
            self._root = name.rpartition(":")[2]
        self._depth += 1
        if self.max_depth is not None and self._depth > self.max_depth:
            raise DocumentError(f"elements nested deeper than {self.max_depth} (the bound on "
                                f"{limits.NESTING.name}; set {limits.NESTING.env} to raise it)")

    def _stop(self, name: str) -> None:
        self._depth -= 1
        if not self._depth:
            self._end = self._parser.CurrentByteIndex
            raise _RootEnded


def _no_doctype(*args: object) -> None:
    raise DocumentError("a DOCTYPE is not allowed in a CRCL document")


def _tag_end(buf: bytearray, i: int) -> int:
    """The index just after the tag that starts at ``buf[i]`` (``>`` outside quoted values)."""
    quote = 0
    for k in range(i, len(buf)):
        c = buf[k]
        if quote:
            quote = 0 if c == quote else quote
        elif c in (0x22, 0x27):
            quote = c
        elif c == 0x3E:
            return k + 1
    return len(buf)  # pragma: no cover  (expat has seen the whole tag)


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


def parse_peer(text: str) -> tuple[str, int]:
    """(host, port) of ``HOST:PORT`` (a CRCL 1.x controller; ``[::1]:PORT`` for IPv6); an
    :class:`~kb.core.errors.InputError` otherwise."""
    host, _, port = text.strip().rpartition(":")
    if not host or not port.isdigit() or not 0 < int(port) < 65536:
        raise InputError(f"controller address {text!r}: expected HOST:PORT (a port from 1 to 65535)")
    return host.strip("[]"), int(port)
