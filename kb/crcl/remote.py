"""A cell behind sockets: :class:`RemoteCell` implements the cell contract
(:class:`kb.crcl.cell.CellInterface`) over kitkb's cell protocol (:mod:`kb.crcl.wire`: USARTruth
lines on the sensor port, CRCL 1.x on the command port), so ``kitkb sim serve`` — or another
simulator, or a real cell speaking the protocol — stands in for an in-process cell;
:class:`CrclClient` is a CRCL 1.x session with any controller (``kitkb crcl send``:
:func:`stream`, :func:`forwarded`).

One persistent connection per port, made on first use. Sensor port: before each query a
connection the cell has closed (or that holds unread bytes) is replaced by a new one; a query
that fails on a reused connection because the cell closed it is sent once more on a new one.
Command port: a CRCL session per connection (InitCanon, SetLengthUnits meter, SetAngleUnits
radian, then the commands one at a time, each waited for until a status names its CommandID
Done or Error); a connection the cell closed between commands is replaced by a new session. A
command is never sent twice: a connection lost after sending it is a
:class:`~kb.core.errors.CellError` (what the cell did is then unknown). Every failure to reach
the cell, an answer outside the protocol or past its bounds is a
:class:`~kb.core.errors.CellError` naming ``host:port`` (exit code 2).

Every answer is bounded (:class:`Bounds`): in total time from the request to its ``{End}``, or
from a CRCL command to its Done or Error (not per ``recv``: a peer that keeps sending lines
without ``{End}``, or ``CRCL_Working`` statuses, is stopped at the bound too), in lines, in
bytes, and each line at :data:`~kb.crcl.wire.MAX_LINE` bytes (a status document at
:data:`MAX_STATUS`). The defaults are the named limits ``KITKB_MAX_CELL_SECONDS``,
``KITKB_MAX_CELL_LINES`` and ``KITKB_MAX_CELL_BYTES`` (:mod:`kb.core.limits`, docs/limits.md);
a peer past one is given up as soon as it is, the error naming the bound and the variable that
raises it.
"""
from __future__ import annotations

import copy
import select
import socket
import time
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any, Callable, Literal, Sequence

from lxml import etree

from kb.core import limits
from kb.core.limits import check_file_size
from kb.core.errors import CellError, InputError
from kb.crcl.cell import NOT_EXECUTED, Observation, Status, parse_truth_line
from kb.crcl.commands import (Command, EndCanon, GetStatus, InitCanon, Program, SetAngleUnits,
                              SetLengthUnits)
from kb.crcl.instance import XSI, CommandStatus, default_schemas, read_status, validate, write_command_instance
from kb.crcl.instance import unwritable as unwritable_1x
from kb.crcl.wire import (COMMAND_PORT, DONE, END, ERROR, EXTRA_FIELDS, MAX_LINE, SENSOR_PORT, DocumentError,
                          Documents, action_message, fields, frame_message, length_line, parse_address,
                          parse_status_line, query_line)
from kb.crcl.xml import hardened_parser, unwritable, write_xml
from kb.crcl.xmlbase import syntax_error

#: bytes asked of the socket at a time
_CHUNK = 1 << 16


def _open(host: str, port: int, timeout: float | None, who: str, address: str) -> socket.socket:
    """A TCP connection to ``host:port`` without Nagle's delay; a CellError naming ``who`` if
    it cannot be made."""
    try:
        sock = socket.create_connection((host, port), timeout=timeout)
    except OSError as exc:
        why = "timed out" if isinstance(exc, TimeoutError) else (exc.strerror or str(exc))
        raise CellError(f"cannot reach {who}: {why}", address) from None
    sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
    return sock


def _shut(sock: socket.socket | None) -> None:
    """Close ``sock`` if there is one (a socket already broken is closed all the same)."""
    if sock is not None:
        try:
            sock.close()
        except OSError:
            pass
    return None


@dataclass(frozen=True)
class Bounds:
    """How much of one answer a client waits for (None: no bound): ``seconds`` from the
    request to its ``{End}`` (and to connect), ``lines`` before ``{End}``, ``bytes`` in all."""

    seconds: float | None
    lines: int | None
    bytes: int | None

    @classmethod
    def from_env(cls) -> "Bounds":
        """The named limits in force (:data:`kb.core.limits.CELL_BOUNDS`); an
        :class:`~kb.core.errors.InputError` for a malformed variable."""
        return cls(limits.CELL_SECONDS.value(), limits.CELL_LINES.value(), limits.CELL_BYTES.value())


class _Past(Exception):
    """An answer past one of its bounds (the message says which): never retried."""


class Connection:
    """One persistent connection to ``host:port``: a request is bytes out, lines in up to
    ``{End}``, within ``bounds``."""

    def __init__(self, host: str, port: int, bounds: Bounds, role: str) -> None:
        self.host, self.port, self.bounds, self.role = host, port, bounds, role
        self.sock: socket.socket | None = None

    @property
    def address(self) -> str:
        """``host:port``."""
        return f"{self.host}:{self.port}"

    @property
    def timeout(self) -> float | None:
        """The bound on an answer's time (and on connecting), in seconds."""
        return self.bounds.seconds

    def request(self, data: bytes, *, retry: bool) -> list[str]:
        """Send ``data`` and return the answer's lines before ``{End}``; with ``retry`` a
        connection the cell closed under a reused connection is tried once more on a new one."""
        for attempt in (0, 1):
            reused = self._usable()
            if not reused:
                self._connect()
            try:
                return self._exchange(data)
            except _Past as exc:
                self.close()
                raise CellError(str(exc), self.address) from None
            except (OSError, EOFError, ValueError) as exc:
                self.close()
                if retry and reused and attempt == 0 and not isinstance(exc, (TimeoutError, ValueError)):
                    continue
                raise CellError(self._why(exc), self.address) from None
        raise AssertionError("unreachable")  # pragma: no cover

    def _why(self, exc: BaseException) -> str:
        if isinstance(exc, EOFError):
            return f"the {self.role} port closed the connection before {END}"
        if isinstance(exc, ValueError):
            return f"the {self.role} port broke the protocol: {exc}"
        return f"connection to the {self.role} port lost: {getattr(exc, 'strerror', None) or exc}"

    def _usable(self) -> bool:
        """True when the open connection can take a request (nothing unread, not closed by the cell)."""
        if self.sock is None:
            return False
        try:
            readable, _, _ = select.select([self.sock], [], [], 0)
        except (OSError, ValueError):
            readable = [self.sock]
        if readable:
            self.close()
        return not readable

    def _connect(self) -> None:
        self.sock = _open(self.host, self.port, self.timeout, f"the cell's {self.role} port", self.address)

    def _exchange(self, data: bytes) -> list[str]:
        """Send ``data``, read the answer up to ``{End}`` within the bounds."""
        sock = self.sock
        assert sock is not None
        seconds = self.bounds.seconds
        deadline = None if seconds is None else time.monotonic() + seconds
        self._wait(sock, deadline)
        try:
            sock.sendall(data)
        except TimeoutError:
            raise _Past(f"the {self.role} port did not take the request within {self._bound(limits.CELL_SECONDS)}") \
                from None
        lines: list[str] = []
        pending = b""  # the line begun, not ended yet
        received = 0
        bounds, most = self.bounds, self.bounds.lines
        end = END.encode()
        while True:
            self._wait(sock, deadline, lines, received)
            try:
                chunk = sock.recv(_CHUNK)
            except TimeoutError:
                self._wait(sock, deadline, lines, received, expired=True)
                raise
            if not chunk:
                raise EOFError
            received += len(chunk)
            if bounds.bytes is not None and received > bounds.bytes:
                raise _Past(self._past(limits.CELL_BYTES, lines, received))
            head, newline, pending = (pending + chunk).rpartition(b"\n")
            if len(pending) >= MAX_LINE:
                raise ValueError(f"a line longer than {MAX_LINE} bytes")
            if not newline:
                continue
            raws = head.split(b"\n")
            for k, raw in enumerate(raws):
                if len(raw) >= MAX_LINE:
                    raise ValueError(f"a line longer than {MAX_LINE} bytes")
                if raw.strip() == end:
                    if k + 1 < len(raws) or pending:  # bytes after the answer: the next request starts anew
                        self.close()
                    return lines
                lines.append(raw.decode("utf-8", "replace").rstrip("\r"))
                if most is not None and len(lines) > most:
                    raise _Past(self._past(limits.CELL_LINES, lines, received))

    def _wait(self, sock: socket.socket, deadline: float | None, lines: list[str] | None = None,
              received: int = 0, expired: bool = False) -> None:
        """Let the socket wait until ``deadline`` at most; :class:`_Past` when it has come."""
        if deadline is None:
            sock.settimeout(None)
            return
        left = deadline - time.monotonic()
        if expired or left <= 0:
            raise _Past(self._past(limits.CELL_SECONDS, lines or [], received))
        sock.settimeout(left)

    def _bound(self, limit: limits.Limit) -> str:
        """The bound of ``limit`` in force on this connection, and the variable that raises it."""
        if limit is limits.CELL_SECONDS:
            shown = f"{self.bounds.seconds:g} s"
        else:
            shown = limit.show(int((self.bounds.lines if limit is limits.CELL_LINES else self.bounds.bytes) or 0))
        return f"{shown} (the bound on {limit.name}; set {limit.env} to raise it)"

    def _past(self, limit: limits.Limit, lines: list[str], received: int) -> str:
        """Why an answer is given up: the bound it passed, and what had come of it."""
        if limit is limits.CELL_SECONDS and not received:
            return f"no answer from the {self.role} port within {self._bound(limit)}"
        what = {limits.CELL_SECONDS: "took longer than", limits.CELL_LINES: "had more lines than",
                limits.CELL_BYTES: "was longer than"}[limit]
        return (f"the {self.role} port's answer {what} {self._bound(limit)} without {END} "
                f"({len(lines):,} lines, {limits.CELL_BYTES.show(received)} so far)")

    def close(self) -> None:
        """Close the connection (the next request opens a new one)."""
        self.sock = _shut(self.sock)


# --- CRCL 1.x ------------------------------------------------------------------------------------

#: Largest status document a client takes (bytes).
MAX_STATUS = 1 << 20
#: Seconds without any status after which a client first asks with GetStatus (controllers that
#: report only when asked); the wait doubles while none comes, up to :data:`POLL`.
FIRST_POLL = 0.1
POLL = 0.25


@dataclass(frozen=True)
class Outcome:
    """How one command sent to a CRCL 1.x controller ended: its ``command_id``, the ``status``
    naming it Done or Error (None when none came), ``seconds`` from sending it to that status,
    and why it is not done (``why``: "" when done)."""

    command: "Command | Forwarded"
    command_id: int
    status: "CommandStatus | None"
    seconds: float
    why: str = ""

    @property
    def name(self) -> str:
        """The command's name (``MoveTo``, ``MoveScrew``, ...)."""
        return self.command.name if isinstance(self.command, Forwarded) else type(self.command).__name__

    @property
    def done(self) -> bool:
        """True when the controller reported the command CRCL_Done (a GetStatus: when it
        answered with a status)."""
        return self.status is not None and not self.why and (self.status.state == DONE or self.name == "GetStatus")


class CrclClient:
    """One CRCL 1.x session with a controller at ``host:port`` (:mod:`kb.crcl.wire`): command
    instances written one at a time (CommandIDs 1, 2, 3, ... of this session), each waited for
    until a status names its CommandID with CRCL_Done or CRCL_Error, statuses of other
    CommandIDs and CRCL_Working read and waited through, GetStatus sent when the controller
    has said nothing for :data:`FIRST_POLL` seconds, then at growing intervals up to
    :data:`POLL` while it stays silent. ``bounds``: per command, the time from sending
    it to its end (a command not acknowledged within it is an :class:`Outcome` with ``why``),
    and the bytes of statuses read meanwhile. A controller that cannot be reached, closes
    the connection, or writes what is not a CRCLStatus document is a
    :class:`~kb.core.errors.CellError` naming ``host:port`` (exit code 2)."""

    def __init__(self, host: str, port: int, bounds: Bounds, who: str = "the controller", poll: float = POLL) -> None:
        self.host, self.port, self.bounds, self.who, self.poll = host, port, bounds, who, poll
        self.sock: socket.socket | None = None
        self.docs = Documents(MAX_STATUS)
        self.next_id = 1
        self.last: CommandStatus | None = None  # the last status read
        self.polls: set[int] = set()  # the CommandIDs of our GetStatus commands

    @property
    def address(self) -> str:
        """``host:port``."""
        return f"{self.host}:{self.port}"

    @property
    def connected(self) -> bool:
        """True while the connection is open (and the controller has not closed it)."""
        if self.sock is None:
            return False
        try:
            self._drain()
        except CellError:
            self.close()
        return self.sock is not None

    def connect(self) -> None:
        """Open the connection (a new session: CommandIDs from 1)."""
        self.close()
        self.sock = _open(self.host, self.port, self.bounds.seconds, self.who, self.address)
        self.docs, self.next_id, self.last, self.polls = Documents(MAX_STATUS), 1, None, set()

    def close(self) -> None:
        """Close the connection."""
        self.sock = _shut(self.sock)

    def run(self, command: "Command | Forwarded", timeout: float | None = None) -> Outcome:
        """Send ``command`` (an InputError, before anything is sent, for one CRCL 1.x cannot
        hold) and wait for its end, at most ``timeout`` seconds (default: the time bound)."""
        data = command.instance(self.next_id) if isinstance(command, Forwarded) else \
            write_command_instance(command, self.next_id)
        if self.sock is None:
            self.connect()
        command_id, self.next_id = self.next_id, self.next_id + 1
        seconds = self.bounds.seconds if timeout is None else timeout
        start = time.monotonic()
        self._drain()
        self._received = 0
        self._send(data)
        asks = isinstance(command, GetStatus) or (isinstance(command, Forwarded) and command.name == "GetStatus")
        status, why = self._wait(command_id, start + seconds if seconds is not None else None, seconds, asks)
        return Outcome(command, command_id, status, time.monotonic() - start, why)

    def _wait(self, command_id: int, deadline: float | None, seconds: float | None,
              asks: bool = False) -> tuple[CommandStatus | None, str]:
        """The status that ends ``command_id`` (``asks``, a GetStatus: the next status, of any
        CommandID), or (None or the last status, why) at the deadline."""
        heard = time.monotonic()
        silence = min(FIRST_POLL, self.poll)  # grows to self.poll while the controller says nothing
        mine: CommandStatus | None = None
        while True:
            now = time.monotonic()
            if deadline is not None and now >= deadline:
                return mine, self._unanswered(command_id, seconds)
            wait = silence - (now - heard)
            if wait <= 0:
                self._poll()
                heard, silence = now, min(2 * silence, self.poll)
                wait = silence
            if deadline is not None:
                wait = min(wait, deadline - now)
            for status in self._read(max(wait, 0.0)):
                heard, silence = time.monotonic(), min(FIRST_POLL, self.poll)
                if asks:
                    return status, ""
                if status.command_id == command_id:
                    mine = status
                    if status.state in (DONE, ERROR):
                        return status, ""

    def _unanswered(self, command_id: int, seconds: float | None) -> str:
        last = self.last
        heard = ("nothing" if last is None else
                 f"CommandID {last.command_id} {last.state}" + (f" ({last.description})" if last.description else ""))
        return (f"command {command_id} was not acknowledged Done or Error within {seconds:g} s; last heard: {heard}"
                if seconds is not None else f"command {command_id} was not acknowledged; last heard: {heard}")

    def _poll(self) -> None:
        """Ask for the status (a GetStatus of its own CommandID)."""
        command_id, self.next_id = self.next_id, self.next_id + 1
        self.polls.add(command_id)
        self._send(write_command_instance(GetStatus(), command_id))

    def _send(self, data: bytes) -> None:
        assert self.sock is not None
        try:
            self.sock.settimeout(self.bounds.seconds)
            self.sock.sendall(data)
        except OSError as exc:
            self.close()
            raise CellError(f"connection to {self.who} lost: {getattr(exc, 'strerror', None) or exc}",
                            self.address) from None

    _received = 0  # bytes read since the command was sent

    def _read(self, wait: float) -> list[CommandStatus]:
        """The statuses that arrive within ``wait`` seconds (the first chunk that comes)."""
        sock = self.sock
        assert sock is not None
        try:
            ready, _, _ = select.select([sock], [], [], wait)
            chunk = sock.recv(_CHUNK) if ready else None
        except OSError as exc:
            self.close()
            raise CellError(f"connection to {self.who} lost: {getattr(exc, 'strerror', None) or exc}",
                            self.address) from None
        if chunk is None:
            return []
        if not chunk:
            self.close()
            raise CellError(f"{self.who} closed the connection", self.address)
        self._received += len(chunk)
        if self.bounds.bytes is not None and self._received > self.bounds.bytes:
            self.close()
            raise CellError(f"{self.who} sent more than {limits.CELL_BYTES.show(self.bounds.bytes)} while one command "
                            f"ran (the bound on {limits.CELL_BYTES.name}; set {limits.CELL_BYTES.env} to raise it)",
                            self.address)
        return self._statuses(chunk)

    def _statuses(self, chunk: bytes) -> list[CommandStatus]:
        try:
            docs = self.docs.feed(chunk)
        except DocumentError as exc:
            self.close()
            hint = (" (it answers in kitkb's earlier {Length N} protocol: a kitkb sim serve from before CRCL 1.x, "
                    "which RemoteCell(..., protocol='kitkb') speaks)") if chunk.lstrip().startswith(b"{") else ""
            raise CellError(f"{self.who} broke the protocol: {exc}{hint}", self.address) from None
        out = []
        for doc in docs:
            if doc.root != "CRCLStatus":
                self.close()
                raise CellError(f"{self.who} broke the protocol: a <{doc.root}> document, not a "
                                "CRCLStatus", self.address)
            try:
                status = read_status(doc.data, f"{self.address} status")
            except (InputError, ValueError) as exc:
                self.close()
                raise CellError(f"{self.who} broke the protocol: {exc}", self.address) from None
            self.last = status
            out.append(status)
        return out

    def _drain(self) -> None:
        """Read what has come since the last command (heartbeats) without waiting; a closed
        connection is closed here."""
        sock = self.sock
        while sock is not None:
            try:
                ready, _, _ = select.select([sock], [], [], 0)
            except (OSError, ValueError):
                ready = [sock]
            if not ready:
                return
            try:
                chunk = sock.recv(_CHUNK)
            except OSError:
                chunk = b""
            if not chunk:
                self.close()
                raise CellError(f"{self.who} closed the connection", self.address)
            self._statuses(chunk)


@dataclass(frozen=True)
class Forwarded:
    """A command of a CRCL 1.x document sent as it is written (kitkb need not read it: a
    ``MoveScrew``, guards, ...): its ``name`` and its element, which :meth:`instance` puts in
    a ``CRCLCommandInstance`` with a CommandID of the session."""

    name: str
    element: Any
    line: int | None = None

    def instance(self, command_id: int) -> bytes:
        """The command instance document of this command with ``command_id``."""
        el = copy.deepcopy(self.element)
        el.tag = "CRCLCommand"
        if el.get(_XSI_TYPE) is None:
            el.set(_XSI_TYPE, self.name + "Type")
        ids = [ch for ch in el if ch.tag == "CommandID"]
        ids[0].text = str(int(command_id))
        root = etree.Element("CRCLCommandInstance", nsmap={"xsi": XSI})
        root.append(el)
        return etree.tostring(root, encoding="UTF-8", xml_declaration=True)


_XSI_TYPE = f"{{{XSI}}}type"


def forwarded(path: str | Path) -> list[Forwarded] | None:
    """The commands of a CRCL 1.x program or command instance file, each to be sent as it is
    written (checked against NIST's CRCL 1.x schemas when they are found); None for a file
    that is not CRCL 1.x (a 2014 CRCL.xsd program, the text form). An InputError at its line
    for a 1.x file that is broken."""
    if Path(path).suffix.lower() != ".xml":
        return None
    check_file_size(path)
    data = Path(path).read_bytes()
    try:
        root = etree.fromstring(data, hardened_parser())
    except etree.XMLSyntaxError as exc:
        raise syntax_error(exc, path) from None
    kids = [ch for ch in root if isinstance(ch.tag, str) and ch.tag != "Name"]
    if root.tag == "CRCLCommandInstance":
        kind, elements = "command", [ch for ch in kids if ch.tag == "CRCLCommand"]
    elif root.tag == "CRCLProgram" and any(ch.tag == "MiddleCommand" or ch.find("CommandID") is not None
                                           for ch in kids):
        kind, elements = "program", kids
    else:
        return None
    if default_schemas() is not None:
        validate(data, kind, str(path))
    out = []
    for el in elements:
        if el.find("CommandID") is None:
            raise InputError(f"<{el.tag}> has no <CommandID>", path, el.sourceline)
        name = (el.get(_XSI_TYPE) or el.tag).rpartition(":")[2]
        out.append(Forwarded(name[:-4] if name.endswith("Type") else name, el, el.sourceline))
    if not out:
        raise InputError("no command in this CRCL 1.x document", path, root.sourceline)
    return out


def stream(commands: "Sequence[Command | Forwarded]", host: str, port: int, timeout: float | None,
           on_outcome: Callable[[Outcome], None] | None = None) -> tuple[list[Outcome], CommandStatus | None]:
    """Send ``commands`` to the CRCL 1.x controller at ``host:port`` one at a time on one
    connection (CommandIDs 1, 2, ...), each waited for at most ``timeout`` seconds, stopping
    after the first that is not done; the outcomes and the last status heard. A controller
    that cannot be reached or breaks the protocol is a :class:`~kb.core.errors.CellError`."""
    client = CrclClient(host, port, Bounds(timeout, None, limits.CELL_BYTES.value()))
    outcomes: list[Outcome] = []
    client.connect()
    try:
        for command in commands:
            outcome = client.run(command, timeout)
            outcomes.append(outcome)
            if on_outcome is not None:
                on_outcome(outcome)
            if not outcome.done:
                break
    finally:
        client.close()
    return outcomes, client.last


class RemoteCell:
    """A :class:`~kb.crcl.cell.CellInterface` behind sockets: sensor queries (USARTruth lines,
    :mod:`kb.crcl.wire`) on ``sensor_port``, CRCL on ``command_port`` of ``host``.

    ``protocol`` ``"crcl"`` (the default): the command port is a CRCL 1.x controller — one
    command instance at a time, each waited for until its Done or Error (:class:`CrclClient`);
    each session (connection) starts with InitCanon, SetLengthUnits meter and SetAngleUnits
    radian, and a connection the cell closed between commands is replaced by a new session.
    ``"kitkb"``: kitkb's earlier ``{Length N}`` protocol (an action's commands as one CRCL.xsd
    program, framed), for a ``kitkb sim serve`` before CRCL 1.x.

    ``bounds``: how much of each answer to wait for (default: :meth:`Bounds.from_env`, the
    named limits; for a CRCL command, the time from sending it to its Done or Error);
    ``timeout``: its ``seconds`` instead. Sensor queries ask for kitkb's extra fields
    (``{Fields Sku}``). For one thread at a time."""

    def __init__(self, host: str = "127.0.0.1", sensor_port: int = SENSOR_PORT,
                 command_port: int = COMMAND_PORT, timeout: float | None = None,
                 bounds: Bounds | None = None, protocol: Literal["crcl", "kitkb"] = "crcl") -> None:
        if protocol not in ("crcl", "kitkb"):
            raise ValueError(f"protocol must be 'crcl' or 'kitkb', not {protocol!r}")
        self.bounds = bounds if bounds is not None else Bounds.from_env()
        if timeout is not None:
            self.bounds = replace(self.bounds, seconds=timeout)
        self.protocol = protocol
        self.sensor = Connection(host, sensor_port, self.bounds, "sensor")
        self.command = Connection(host, command_port, self.bounds, "command")
        self.crcl = CrclClient(host, command_port, self.bounds, "the cell's command port")

    @classmethod
    def from_address(cls, address: str, timeout: float | None = None, bounds: Bounds | None = None,
                     protocol: Literal["crcl", "kitkb"] = "crcl") -> "RemoteCell":
        """The cell at ``HOST:PORT`` (command port PORT + 1) or ``HOST:SENSOR_PORT,COMMAND_PORT``
        (:func:`kb.crcl.wire.parse_address`)."""
        host, sensor, command = parse_address(address)
        return cls(host, sensor, command, timeout, bounds, protocol)

    def __repr__(self) -> str:
        return f"RemoteCell(sensor {self.sensor.address}, command {self.command.address}, {self.protocol})"

    # --- the sensor port --------------------------------------------------------------------
    def sense(self, query: str, *, by: Literal["class", "name"] = "class") -> list[Observation]:
        """Objects of a class (local name or IRI) or of a name, as the cell's sensor reports them."""
        if by not in ("class", "name"):
            raise ValueError(f"by must be 'class' or 'name', not {by!r}")
        lines = self._query(query_line(by, query, EXTRA_FIELDS))
        try:
            return [parse_truth_line(line) for line in lines]
        except ValueError as exc:
            raise CellError(f"the sensor port broke the protocol: {exc}", self.sensor.address) from None

    def inspect(self, name: str) -> bool:
        """Quality inspection of a part: False when the cell finds it defective (or not there)."""
        lines = self._query(query_line("inspect", name))
        quality = [v.strip() for line in lines for k, v in _fields(line, self.sensor) if k.lower() == "quality"]
        if len(lines) != 1 or quality not in (["ok"], ["defective"]):
            raise CellError(f"the sensor port answered an inspection with {lines!r}", self.sensor.address)
        return quality == ["ok"]

    def _query(self, line: str) -> list[str]:
        lines = self.sensor.request((line + "\r\n").encode(), retry=True)
        for line in lines:
            for key, value in _fields(line, self.sensor):
                if key.lower() == "error":
                    raise CellError(f"the sensor refused the query: {value}", self.sensor.address)
        return lines

    # --- the command port -------------------------------------------------------------------
    def execute(self, command: Command) -> Status:
        """Carry out one CRCL command (a one-command :meth:`execute_program`)."""
        return self.execute_program([command])[0]

    def execute_program(self, commands: Sequence[Command]) -> list[Status]:
        """Carry out one action's commands: one status per command, those after a failed one
        not executed (as :func:`kb.crcl.cell.execute_program`).

        CRCL 1.x: each command sent and waited for in turn; a command CRCL 1.x cannot hold
        (``SetCoordinateFrame``, an ``Unreadable`` line, ...) is not sent and answers
        ``Status.error`` saying why. kitkb's protocol: the commands travel as one CRCL.xsd
        program, framed where they are not a whole one (kitkb-frame, :mod:`kb.crcl.wire`), a
        command CRCL.xsd cannot hold not sent.
        """
        commands = list(commands)
        if self.protocol == "kitkb":
            return self._execute_kitkb(commands)
        statuses: list[Status] = []
        for command in commands:
            if statuses and not statuses[-1].done:
                statuses.append(Status.error(NOT_EXECUTED))
                continue
            statuses.append(self._run(command))
        return statuses

    def _run(self, command: Command) -> Status:
        """One command on the CRCL 1.x session (started first where there is none)."""
        why = unwritable_1x(command)
        if why:
            return Status.error(f"{why}; not sent")
        if not self.crcl.connected:
            self._begin()
        status = self._outcome(self.crcl.run(command))
        return Status.ok(status.description) if status.state == DONE else Status.error(status.description)

    def _begin(self) -> None:
        """A new CRCL session: InitCanon, then the length and angle units said (metre, radian:
        kitkb computes in SI), each waited for; a CellError when one is not done."""
        self.crcl.connect()
        for command in (InitCanon(), SetLengthUnits("meter"), SetAngleUnits("radian")):
            status = self._outcome(self.crcl.run(command))
            if status.state != DONE:
                self.crcl.close()
                raise CellError(f"the cell did not start a CRCL session: {type(command).__name__} "
                                f"(CommandID {status.command_id}) ended in {status.state}: {status.description}",
                                self.crcl.address)

    def _outcome(self, outcome: Outcome) -> CommandStatus:
        """The status that ended a command; a CellError when none came within the time bound."""
        if outcome.why or outcome.status is None:
            self.crcl.close()  # what the cell does with it is unknown: the next command starts a new session
            raise CellError(f"the cell's command port: {type(outcome.command).__name__} {outcome.why} (the bound on "
                            f"{limits.CELL_SECONDS.name}; set {limits.CELL_SECONDS.env} to raise it)",
                            self.crcl.address)
        return outcome.status

    def begin_action(self, index: int, action: str, args: tuple[str, ...]) -> None:
        """Start plan action ``index`` on the cell (a ``kitkb-action`` message, :mod:`kb.crcl.wire`)."""
        message = action_message(index, action, tuple(args))
        [status] = self._send([message]) if self.protocol == "kitkb" else [self._run(message)]
        if not status.done:
            raise CellError(f"the cell refused to begin action {index} {action}: {status.message}",
                            self.command.address)

    def _execute_kitkb(self, commands: list[Command]) -> list[Status]:
        k = next((i for i, c in enumerate(commands) if _unsendable(c, i, len(commands))), len(commands))
        statuses = self._send(commands[:k]) if k else []
        if k < len(commands):
            why = _unsendable(commands[k], k, len(commands))
            statuses.append(Status.error(why or "") if not statuses or statuses[-1].done
                            else Status.error(NOT_EXECUTED))
        return statuses + [Status.error(NOT_EXECUTED)] * (len(commands) - len(statuses))

    def _send(self, body: list[Command]) -> list[Status]:
        wire, where = _envelope(body)
        data = write_xml(Program(tuple(wire), source="RemoteCell"))
        lines = self.command.request(length_line(len(data)).encode() + b"\n" + data, retry=False)
        try:
            answers = [parse_status_line(line) for line in lines]
        except ValueError as exc:
            raise CellError(f"the command port broke the protocol: {exc}", self.command.address) from None
        if len(answers) == 1 and answers[0][0] is None and not answers[0][1].done:
            raise CellError(f"the cell refused the program: {answers[0][1].message}", self.command.address)
        if [n for n, _ in answers] != list(range(1, len(wire) + 1)):
            raise CellError(f"the command port answered {len(answers)} status lines for a program of "
                            f"{len(wire)} commands", self.command.address)
        return [answers[i][1] for i in where]

    def close(self) -> None:
        """Close every connection."""
        self.sensor.close()
        self.command.close()
        self.crcl.close()

    def __enter__(self) -> "RemoteCell":
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def _fields(line: str, conn: Connection) -> list[tuple[str, str]]:
    try:
        return fields(line)
    except ValueError as exc:
        raise CellError(f"the {conn.role} port broke the protocol: {exc}", conn.address) from None


def _unsendable(command: Command, i: int, n: int) -> str | None:
    """Why the ``i``-th of ``n`` commands cannot travel in one CRCL.xsd program (None: it can)."""
    if isinstance(command, InitCanon) and i > 0:
        return "InitCanon only as the first command of a program in CRCL.xsd; not sent"
    if isinstance(command, EndCanon) and i < n - 1:
        return "EndCanon only as the last command of a program in CRCL.xsd; not sent"
    why = unwritable(command)
    return f"{why}; not sent" if why else None


def _envelope(body: list[Command]) -> tuple[list[Command], list[int]]:
    """The CRCL.xsd program that carries ``body`` — ``body`` itself when it is a whole program,
    else framed (a kitkb-frame message second, InitCanon / EndCanon added where missing) — and
    the position of each of ``body``'s commands in it."""
    lead = not isinstance(body[0], InitCanon)
    tail = not isinstance(body[-1], EndCanon)
    if not (lead or tail) and len(body) >= 3:
        return body, list(range(len(body)))
    wire = [InitCanon()] * lead + body + [EndCanon()] * tail
    wire.insert(1, frame_message(lead, tail))
    return wire, [lead + i + (lead + i >= 1) for i in range(len(body))]
