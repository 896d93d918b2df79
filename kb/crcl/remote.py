"""A cell behind sockets: :class:`RemoteCell` implements the cell contract
(:class:`kb.crcl.cell.CellInterface`) over kitkb's cell protocol (:mod:`kb.crcl.wire`), so
``kitkb sim serve`` — or another simulator, or a real cell speaking the protocol — stands in
for an in-process cell.

One persistent connection per port, made on first use. Before each request a connection the
cell has closed (or that holds unread bytes) is replaced by a new one; a sensor query that
fails on a reused connection because the cell closed it is sent once more on a new one. A
program is never sent twice: a connection lost after sending it is a
:class:`~kb.core.errors.CellError` (what the cell did is then unknown). Every failure to reach
the cell, an answer outside the protocol or past its bounds is a
:class:`~kb.core.errors.CellError` naming ``host:port`` (exit code 2).

Every answer is bounded (:class:`Bounds`): in total time from the request to its ``{End}``
(not per ``recv``: a peer that keeps sending lines without ``{End}`` is stopped at the bound
too), in lines, in bytes, and each line at :data:`~kb.crcl.wire.MAX_LINE` bytes. The defaults
are the named limits ``KITKB_MAX_CELL_SECONDS``, ``KITKB_MAX_CELL_LINES`` and
``KITKB_MAX_CELL_BYTES`` (:mod:`kb.core.limits`, docs/limits.md); a peer past one is given up
as soon as it is, the error naming the bound and the variable that raises it.
"""

from __future__ import annotations

import select
import socket
import time
from dataclasses import dataclass, replace
from typing import Literal, Sequence

from kb.core import limits
from kb.core.errors import CellError
from kb.crcl.cell import NOT_EXECUTED, Observation, Status, parse_truth_line
from kb.crcl.commands import Command, EndCanon, InitCanon, Program
from kb.crcl.wire import (COMMAND_PORT, END, EXTRA_FIELDS, MAX_LINE, SENSOR_PORT, action_message, fields,
                          frame_message, length_line, parse_address, parse_status_line, query_line)
from kb.crcl.xml import unwritable, write_xml

#: bytes asked of the socket at a time
_CHUNK = 1 << 16


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
        try:
            self.sock = socket.create_connection((self.host, self.port), timeout=self.timeout)
        except OSError as exc:
            why = "timed out" if isinstance(exc, TimeoutError) else (exc.strerror or str(exc))
            raise CellError(f"cannot reach the cell's {self.role} port: {why}", self.address) from None
        self.sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)

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
        if self.sock is not None:
            try:
                self.sock.close()
            except OSError:
                pass
        self.sock = None


class RemoteCell:
    """A :class:`~kb.crcl.cell.CellInterface` over kitkb's cell protocol (:mod:`kb.crcl.wire`):
    sensor queries on ``sensor_port``, CRCL XML programs on ``command_port`` of ``host``.
    ``bounds``: how much of each answer to wait for (default: :meth:`Bounds.from_env`, the
    named limits); ``timeout``: its ``seconds`` instead (to connect, and for each answer in
    all). Sensor queries ask for kitkb's extra fields (``{Fields Sku}``). For one thread at a
    time."""

    def __init__(self, host: str = "127.0.0.1", sensor_port: int = SENSOR_PORT,
                 command_port: int = COMMAND_PORT, timeout: float | None = None,
                 bounds: Bounds | None = None) -> None:
        self.bounds = bounds if bounds is not None else Bounds.from_env()
        if timeout is not None:
            self.bounds = replace(self.bounds, seconds=timeout)
        self.sensor = Connection(host, sensor_port, self.bounds, "sensor")
        self.command = Connection(host, command_port, self.bounds, "command")

    @classmethod
    def from_address(cls, address: str, timeout: float | None = None, bounds: Bounds | None = None) -> "RemoteCell":
        """The cell at ``HOST:PORT`` (command port PORT + 1) or ``HOST:SENSOR_PORT,COMMAND_PORT``
        (:func:`kb.crcl.wire.parse_address`)."""
        host, sensor, command = parse_address(address)
        return cls(host, sensor, command, timeout, bounds)

    def __repr__(self) -> str:
        return f"RemoteCell(sensor {self.sensor.address}, command {self.command.address})"

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
        """Carry out one action's commands in one round trip: one status per command, those
        after a failed one not executed (as :func:`kb.crcl.cell.execute_program`).

        The commands travel as one CRCL.xsd program, framed where they are not a whole one
        (kitkb-frame, :mod:`kb.crcl.wire`): the cell executes these commands and no other.
        A command CRCL.xsd cannot hold (``SetCoordinateFrame``, ``StopMotion``, an
        ``Unreadable`` line, InitCanon not first or EndCanon not last, ...) is not sent: the
        commands before it are, and it answers ``Status.error`` saying why.
        """
        commands = list(commands)
        k = next((i for i, c in enumerate(commands) if _unsendable(c, i, len(commands))), len(commands))
        statuses = self._send(commands[:k]) if k else []
        if k < len(commands):
            why = _unsendable(commands[k], k, len(commands))
            statuses.append(Status.error(why or "") if not statuses or statuses[-1].done
                            else Status.error(NOT_EXECUTED))
        return statuses + [Status.error(NOT_EXECUTED)] * (len(commands) - len(statuses))

    def begin_action(self, index: int, action: str, args: tuple[str, ...]) -> None:
        """Start plan action ``index`` on the cell (a ``kitkb-action`` message, :mod:`kb.crcl.wire`)."""
        [status] = self._send([action_message(index, action, tuple(args))])
        if not status.done:
            raise CellError(f"the cell refused to begin action {index} {action}: {status.message}",
                            self.command.address)

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
        """Close both connections."""
        self.sensor.close()
        self.command.close()

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
