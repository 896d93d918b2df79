"""The simulated workcell as a server on loopback: kitkb's cell protocol (:mod:`kb.crcl.wire`)
around one :class:`~kb.sim.cell.SimulatedCell`, so :class:`kb.crcl.remote.RemoteCell` — or any
client speaking USARTruth and CRCL 1.x, NIST's own among them — drives it as it would a real cell.

Two threaded TCP servers (stdlib ``socketserver``, a thread per connection, connections kept
open): the sensor port answers USARTruth queries as USARSim did (NIST's and GTRI's USARTruth
clients read it: combined ``{class C} {name N}`` queries, an empty line for every object,
CR LF line ends, USARTruth's five fields unless kitkb's are asked for); the command port is a
CRCL 1.x controller: each connection a session of its own (``_CrclSession``: its documents
split from the stream by :class:`kb.crcl.wire.Documents`, executed in order on the one cell,
its own status stream, units and status report: ``ConfigureStatusReport`` says whether its
statuses carry the pose, the gripper, the settings), or, when a connection's first byte is ``{``, kitkb's earlier
``{Length N}`` programs. One lock serialises every access to the cell, so a command (or an old
program) runs whole between two queries, whichever connection sent it; a heartbeat thread
sends each quiet CRCL connection its status every :attr:`CellServer.status_period` seconds,
never waiting on a client that does not read. Nothing a client sends stops the server: a
malformed query, document or program gets an error answer, a dropped connection ends only its
own thread.

:meth:`CellServer.answer_query` and :meth:`CellServer.answer_program` are the line protocols
without sockets (the answer lines, ``{End}`` last).
"""
from __future__ import annotations

import math
import re
import selectors
import socket
import socketserver
import threading
import time
from typing import Any, Iterator, Sequence
from xml.sax.saxutils import escape

from kb.core.errors import CellError, InputError
from kb.core.units import ANGLE, LENGTH
from kb.crcl.cell import Observation, Status, run_in_order, truth_line
from kb.crcl.commands import (CloseGripper, Command, ConfigureStatusReport, DisableGripper, EnableGripper, GetStatus,
                              Message, OpenGripper, SetEndEffector)
from kb.crcl.instance import (CommandStatus, GripperStatus, SettingsStatus, read_command_instance,
                              read_program_instance, write_status)
from kb.crcl.pose import Pose
from kb.crcl.wire import (COMMAND_PORT, CRLF, DONE, END, ERROR, MAX_LINE, MAX_PROGRAM, READY, SENSOR_PORT,
                          STATUS_PERIOD, WORKING, Document, DocumentError, Documents, Query, error_line, field,
                          parse_action, parse_frame, parse_length, parse_query, status_line)
from kb.crcl.xml import read_xml
from kb.sim.cell import SimulatedCell
from kb.sim.sensor import matches, observe_where, truth_class


#: The status of a command that is only a program's frame.
FRAMED = Status.ok("frame")
#: What ends a sensor-port line: LF, CR LF, or a CR alone (as USARSim read them).
_LINE_END = re.compile(rb"\r\n|\r|\n")


class CellServer:
    """``cell`` served on ``host`` (loopback by default): sensor queries on ``sensor_port``,
    CRCL programs on ``command_port`` (0: any free port; :attr:`sensor_port` and
    :attr:`command_port` are the ones bound). The ports are bound when the server is made
    (a :class:`~kb.core.errors.CellError` when one cannot be), served from :meth:`start` (or
    ``with``) until :meth:`close`."""

    def __init__(self, cell: SimulatedCell, host: str = "127.0.0.1", sensor_port: int = SENSOR_PORT,
                 command_port: int = COMMAND_PORT, status_period: float = STATUS_PERIOD) -> None:
        self.cell = cell
        self.lock = threading.Lock()
        #: seconds after which a quiet CRCL 1.x connection is sent its status again (0: never)
        self.status_period = float(status_period)
        self.sessions: set[_CrclSession] = set()  # the open CRCL 1.x connections
        self.jaws_open = True  # the gripper's jaws, as the last gripper command left them
        self._stopped = threading.Event()
        self._known: tuple[tuple[int, int] | None, frozenset[str]] = (None, frozenset())
        self.sensor = _listen(host, sensor_port, _SensorHandler, self)
        try:
            self.command = _listen(host, command_port, _CommandHandler, self)
        except CellError:
            self.sensor.server_close()
            raise
        self.threads: list[threading.Thread] = []

    @property
    def host(self) -> str:
        """The address the ports are bound on."""
        return str(self.sensor.server_address[0])

    @property
    def sensor_port(self) -> int:
        """The bound sensor port."""
        return int(self.sensor.server_address[1])

    @property
    def command_port(self) -> int:
        """The bound command port."""
        return int(self.command.server_address[1])

    def start(self) -> "CellServer":
        """Serve both ports, each from a background thread (and one for the CRCL heartbeats)."""
        self._stopped.clear()
        targets = [(listener.serve, f"kitkb-cell-{listener.role}") for listener in (self.sensor, self.command)]
        if self.status_period > 0:
            targets.append((self._heartbeats, "kitkb-cell-status"))
        for target, name in targets:
            thread = threading.Thread(target=target, name=name, daemon=True)
            thread.start()
            self.threads.append(thread)
        return self

    def close(self) -> None:
        """Stop serving, close every open connection and both ports."""
        self._stopped.set()
        for listener in (self.sensor, self.command):
            listener.stop()
        for thread in self.threads:
            thread.join()
        self.threads = []
        for listener in (self.sensor, self.command):
            listener.close_connections()
            listener.server_close()

    def __enter__(self) -> "CellServer":
        return self.start()

    def __exit__(self, *exc: object) -> None:
        self.close()

    # --- the protocol ---------------------------------------------------------------------
    def answer_query(self, line: str) -> list[str]:
        """The answer to one sensor-port line (:mod:`kb.crcl.wire`): truth lines (``{End}``
        alone when nothing matches), an inspection or an error; ``{End}`` last."""
        try:
            query = parse_query(line)
            with self.lock:
                if query.inspect:
                    ok = self.cell.inspect(self._resolve(query.inspect))
                    return [field("Name", query.inspect) + " " + field("Quality", "ok" if ok else "defective"), END]
                sku = "Sku" in query.fields
                return [truth_line(o, sku) for o in self._observe(query)] + [END]
        except ValueError as exc:
            return [error_line(str(exc)), END]
        except Exception as exc:  # a bug of ours: answered, and the server keeps serving
            return [error_line(f"internal error: {type(exc).__name__}: {exc}"), END]

    def _observe(self, query: Query) -> list[Observation]:
        """The placed objects a query asks for, as the cell senses them now: by class or by name
        alone as ``cell.sense`` gives them, else of the class and the name (either may be any)."""
        cell = self.cell
        if not query.cls:
            return cell.sense(query.name, by="name") if query.name else \
                observe_where(cell.world, cell.time, sensor=cell.sensor)
        cls = truth_class(query.cls, self._classes())
        if cls is None:  # a class the cell does not have: nothing answers it
            return []
        if not query.name:
            return cell.sense(cls, by="class") if cls else observe_where(cell.world, cell.time, sensor=cell.sensor)
        return observe_where(cell.world, cell.time, cls=cls or None, name=query.name, sensor=cell.sensor)

    def _classes(self) -> frozenset[str]:
        """Every class IRI of the cell's objects (kept while the world has the same objects)."""
        world = self.cell.world
        key = (id(world), len(world))
        if self._known[0] != key:
            self._known = (key, frozenset().union(*world.classes))
        return self._known[1]

    def answer_program(self, data: bytes) -> list[str]:
        """The answer to one CRCL XML program: a status line per command, or one error line
        when it does not parse; ``{End}`` last."""
        try:
            program = read_xml(data, name="program")
        except InputError as exc:
            return [status_line(None, Status.error(str(exc))), END]
        except Exception as exc:
            return [status_line(None, Status.error(f"program: error: cannot read it: {exc}")), END]
        frame = _frame(program.commands)

        def run(item: tuple[int, Command]) -> Status:
            return FRAMED if item[0] in frame else self._run(item[1])
        with self.lock:
            statuses = run_in_order(run, list(enumerate(program.commands)))
        return [status_line(n, s) for n, s in enumerate(statuses, 1)] + [END]

    def _run(self, command: Command) -> Status:
        """Execute one command; a ``kitkb-action`` message begins a plan action instead."""
        try:
            action = parse_action(command.message) if isinstance(command, Message) else None
            if action is None:
                return self.cell.execute(command)
            self.cell.begin_action(*action)
            return Status.ok(f"action {action[0]} {action[1]} begun")
        except ValueError as exc:
            return Status.error(str(exc))
        except Exception as exc:  # a bug of ours: an error status, not a dead server
            return Status.error(f"internal error: {type(exc).__name__}: {exc}")

    # --- CRCL 1.x ---------------------------------------------------------------------------
    def execute_for(self, session: "_CrclSession", command: Command) -> Status:
        """Execute one command of a CRCL 1.x connection, in that connection's units (each
        connection sets its own; the robot is shared)."""
        kind = type(command).__name__
        if isinstance(command, _GRIPPER_COMMANDS):
            session.channel = session.channel or "gripper"
        elif kind not in _NEUTRAL:
            session.channel = "robot"
        robot = self.cell.robot
        with self.lock:
            shared = _units(robot)
            if session.units is not None:
                _set_units(robot, session.units)
            try:
                status = self._run(command)
            finally:
                session.units = _units(robot)
                _set_units(robot, shared)
            if status.done and isinstance(command, _JAW_COMMANDS):
                self.jaws_open = not isinstance(command, CloseGripper) and getattr(command, "setting", 1.0) > 0
            return status

    def pose_and_gripper(self, session: "_CrclSession") -> tuple[Pose, GripperStatus | None]:
        """The tool tip's pose in ``session``'s length unit and the mounted effector's status."""
        robot, world = self.cell.robot, self.cell.world
        with self.lock:
            tip = robot.tip().copy()
            effector, held = robot.effector, robot.held
            metres = float((session.units if session.units is not None else _units(robot)).get("metres", 1.0))
            tip[:3, 3] /= metres
            pose = Pose.from_matrix(tip)
            if effector is None:
                return pose, None
            name = robot.gripper_name()
            holding = held is not None
            if world.is_a(effector, "VacuumEffector"):
                return pose, GripperStatus(name, "vacuum", powered=holding, holding=holding)
            # the jaws: open, the effector's width; closed, what they hold (0 when nothing)
            target = effector if self.jaws_open else held
            width = 0.0 if target is None else float(min((world.local_hi[target] - world.local_lo[target])[:2]))
            width = width if width == width and width != float("inf") else 0.0  # no shape: NaN
            return pose, GripperStatus(name, "parallel", separation=width / metres, holding=holding)

    def settings(self, session: "_CrclSession") -> SettingsStatus:
        """``session``'s settings now: its length and angle units, the translational speed in
        them, and (a gripper mounted) the end effector's setting, 1 open, 0 closed."""
        robot = self.cell.robot
        with self.lock:
            units = session.units if session.units is not None else _units(robot)
            metres, radians = float(units.get("metres", 1.0)), float(units.get("radians", 1.0))
            effector = None if robot.effector is None else float(self.jaws_open)
            speed = robot.speed / metres
        return SettingsStatus(_unit_name(LENGTH, metres), _unit_name(ANGLE, radians), effector,
                              speed if math.isfinite(speed) else None)

    def _heartbeats(self) -> None:
        """Send each quiet CRCL 1.x connection its status every :attr:`status_period` seconds."""
        tick = min(self.status_period / 4, 0.25)
        while not self._stopped.wait(tick):
            now = time.monotonic()
            for session in list(self.sessions):
                try:
                    session.heartbeat(now)
                except Exception:  # a connection going away: its own thread ends it
                    pass

    def _resolve(self, name: str) -> str:
        """The IRI of the object ``name`` (an IRI or a local name) names; ``name`` when none."""
        world = self.cell.world
        if name in world.index:
            return name
        found = [world.names[i] for i in range(len(world)) if matches(world, i, name, "name")]
        if len(found) > 1:
            raise ValueError(f"{name!r} names {len(found)} objects; give its IRI")
        return found[0] if found else name


#: The robot's attributes that hold the units of the commands it is given (saved per connection).
_UNIT_ATTRIBUTES = ("metres", "length_unit", "radians", "angle_unit", "units")


def _unit_name(table: dict[str, float], scale: float) -> str | None:
    """The name of the unit of ``table`` that is ``scale`` base units (None when none is)."""
    return next((name for name, value in table.items() if math.isclose(value, scale, rel_tol=1e-12)), None)


def _units(robot: Any) -> dict[str, Any]:
    return {a: getattr(robot, a) for a in _UNIT_ATTRIBUTES if hasattr(robot, a)}


def _set_units(robot: Any, units: dict[str, Any]) -> None:
    for a, v in units.items():
        setattr(robot, a, v)


def _frame(commands: Sequence[Command]) -> set[int]:
    """Positions of the commands that are only the program's frame (kitkb-frame, :mod:`kb.crcl.wire`)."""
    second = commands[1] if len(commands) > 2 else None
    flags = parse_frame(second.message) if isinstance(second, Message) else None
    if flags is None:
        return set()
    return {1} | ({0} if flags[0] else set()) | ({len(commands) - 1} if flags[1] else set())


# --- sockets ------------------------------------------------------------------------------------

class _Listener(socketserver.ThreadingTCPServer):
    """One port: a thread per connection; remembers its open connections to close them.
    :meth:`serve` blocks in ``select`` (no polling) until a connection or :meth:`stop`."""

    allow_reuse_address = True
    daemon_threads = True
    block_on_close = False

    def __init__(self, address: tuple[str, int], handler: type, owner: CellServer, role: str) -> None:
        self.owner, self.role = owner, role
        self.connections: set[socket.socket] = set()
        self.guard = threading.Lock()
        self.stopping = False
        self.wake_r, self.wake_w = socket.socketpair()
        try:
            super().__init__(address, handler)
        except OSError:
            self.wake_r.close()
            self.wake_w.close()
            raise

    def serve(self) -> None:
        """Accept connections until :meth:`stop`."""
        with selectors.DefaultSelector() as selector:
            selector.register(self, selectors.EVENT_READ)
            selector.register(self.wake_r, selectors.EVENT_READ)
            while not self.stopping:
                for key, _ in selector.select():
                    if key.fileobj is self and not self.stopping:
                        self.handle_request()

    def stop(self) -> None:
        """End :meth:`serve` now (it may not have started)."""
        self.stopping = True
        try:
            self.wake_w.send(b"\0")
        except OSError:
            pass

    def server_close(self) -> None:
        super().server_close()
        self.wake_r.close()
        self.wake_w.close()

    def process_request(self, request: Any, client_address: Any) -> None:
        with self.guard:
            self.connections.add(request)
        super().process_request(request, client_address)

    def shutdown_request(self, request: Any) -> None:
        with self.guard:
            self.connections.discard(request)
        super().shutdown_request(request)

    def close_connections(self) -> None:
        """Shut every open connection down (its thread then sees the end and finishes)."""
        with self.guard:
            for conn in self.connections:
                try:
                    conn.shutdown(socket.SHUT_RDWR)
                except OSError:
                    pass


def _listen(host: str, port: int, handler: type, owner: CellServer) -> _Listener:
    role = "sensor" if handler is _SensorHandler else "command"
    try:
        return _Listener((host, port), handler, owner, role)
    except OSError as exc:
        raise CellError(f"cannot listen as the {role} port: {exc.strerror or exc}", f"{host}:{port}") from None


class _Handler(socketserver.StreamRequestHandler):
    """Reads lines of at most :data:`~kb.crcl.wire.MAX_LINE` bytes, writes answers."""

    server: _Listener
    disable_nagle_algorithm = True
    #: what ends an answer's lines
    newline = "\n"

    def handle(self) -> None:
        try:
            self.serve()
        except (OSError, ValueError):  # the client went away (or closed mid-answer)
            pass

    def serve(self) -> None:
        raise NotImplementedError

    def read_line(self) -> str | None:
        """The next line (None at the end); ValueError for one longer than MAX_LINE."""
        raw = self.rfile.readline(MAX_LINE + 1)
        if not raw:
            return None
        if len(raw) > MAX_LINE and not raw.endswith(b"\n"):
            raise _TooLong(f"a line longer than {MAX_LINE} bytes")
        return raw.decode("utf-8", "replace")

    def reply(self, lines: list[str]) -> None:
        """Send ``lines``."""
        self.wfile.write((self.newline.join(lines) + self.newline).encode("utf-8"))


class _TooLong(Exception):
    """A line longer than the protocol allows: answered, then the connection is closed."""


class _SensorHandler(_Handler):
    newline = CRLF  # USARSim's

    def serve(self) -> None:
        try:
            for line in self.queries():
                self.reply(self.server.owner.answer_query(line))
        except _TooLong as exc:
            self.reply([error_line(str(exc)), END])

    def queries(self) -> Iterator[str]:
        """The client's lines, each ended by LF, CR LF or a CR alone (USARSim's TcpLink ended a
        line at CR and dropped an LF right after it, even one that came later); _TooLong for a
        line longer than MAX_LINE."""
        pending, after_cr = b"", False
        while chunk := self.rfile.read1(MAX_LINE):
            if after_cr and chunk.startswith(b"\n"):
                chunk = chunk[1:]
            data = pending + chunk
            if not data:
                continue
            *lines, pending = _LINE_END.split(data)
            after_cr = data.endswith(b"\r")
            if len(pending) >= MAX_LINE or any(len(x) >= MAX_LINE for x in lines):
                raise _TooLong(f"a line longer than {MAX_LINE} bytes")
            yield from (x.decode("utf-8", "replace") for x in lines)


class _CommandHandler(_Handler):
    """The command port: CRCL 1.x documents, or kitkb's ``{Length N}`` programs when the
    connection's first byte (after white space) is ``{``."""

    def serve(self) -> None:
        while True:
            head = self.rfile.peek(1)
            if not head:
                return
            if head.strip():
                break
            self.rfile.read(len(head))  # white space before anything: skipped by both protocols
        if head.lstrip()[:1] == b"{":
            self.serve_kitkb()
        else:
            _CrclSession(self.server.owner, self.request, self.rfile).run()

    def serve_kitkb(self) -> None:
        """kitkb's ``{Length N}`` protocol (:mod:`kb.crcl.wire`)."""
        try:
            while (header := self.read_line()) is not None:
                if not header.strip():
                    continue
                try:
                    size = parse_length(header)
                except ValueError as exc:  # the stream cannot be resynchronised: answer, then close
                    self.reply([status_line(None, Status.error(str(exc))), END])
                    return
                data = self.rfile.read(size)
                if len(data) < size:
                    return
                self.reply(self.server.owner.answer_program(data))
        except _TooLong as exc:
            self.reply([status_line(None, Status.error(str(exc))), END])


# --- CRCL 1.x sessions -----------------------------------------------------------------------------

#: A status document is shorter than this (a simple client reads one per ``recv(1024)``).
STATUS_BYTES = 1024
#: The root elements of the documents a CRCL 1.x controller takes.
_CRCL_ROOTS = ("CRCLCommandInstance", "CRCLProgram")
_COMMAND_ID = re.compile(rb"<(?:\w+:)?CommandID>\s*(-?\d{1,18})\s*</")
#: Commands that open or close the jaws.
_JAW_COMMANDS = (OpenGripper, CloseGripper, SetEndEffector)
#: Commands of a gripper channel (its status has no pose, Reference.md VIII).
_GRIPPER_COMMANDS = (*_JAW_COMMANDS, EnableGripper, DisableGripper)
#: Commands that say nothing of which device a connection drives.
_NEUTRAL = frozenset({"InitCanon", "EndCanon", "Message", "Dwell", "SetLengthUnits", "SetAngleUnits",
                      "SetForceUnits", "SetTorqueUnits", "SetEndEffectorParameters", "ConfigureStatusReport",
                      "EnableSensor", "DisableSensor", "EnableRobotParameterStatus",
                      "DisableRobotParameterStatus"})
#: What a connection's statuses carry until its ConfigureStatusReport: the pose and the gripper.
DEFAULT_REPORT = ConfigureStatusReport(joints=False, pose=True, gripper=True, settings=False, sensors=False,
                                       guards=False)


class _CrclSession:
    """One CRCL 1.x connection to the command port: its documents executed in order on the
    server's cell, its own status stream (CommandID echoed, StatusID increasing). Statuses go
    out when a command ends, on ``GetStatus``, and (a heartbeat) when the connection has been
    sent none for :attr:`CellServer.status_period` seconds; each status is one ``send``."""

    def __init__(self, server: "CellServer", sock: socket.socket, reader: Any) -> None:
        self.server, self.sock, self.reader = server, sock, reader
        self.lock = threading.Lock()  # one writer at a time: the reader's thread, the heartbeat
        self.command_id, self.status_id = 0, 0
        self.state: str = READY
        self.description = ""
        self.sent = time.monotonic()  # when the last status went out
        self.unsent = b""  # the rest of a heartbeat the socket took only in part
        #: "gripper" while the connection has sent gripper commands and no motion (its statuses
        #: have no pose, Reference.md VIII), "robot" once it moves the robot
        self.channel: str | None = None
        self.units: Any = None  # this connection's units on the robot (between its commands)
        self.report = DEFAULT_REPORT  # what its statuses carry (ConfigureStatusReport)

    # --- reading ---------------------------------------------------------------------------
    def run(self) -> None:
        docs = Documents(max_bytes=MAX_PROGRAM)
        self.server.sessions.add(self)
        try:
            while chunk := self.reader.read1(1 << 16):
                try:
                    batch = docs.feed(chunk)
                except DocumentError as exc:
                    if all(self.handle(d) for d in exc.documents):
                        self.error(self.command_id, f"{exc}; the connection is closed")
                    return
                if not all(self.handle(d) for d in batch):
                    return
        finally:
            self.server.sessions.discard(self)

    def handle(self, doc: Document) -> bool:
        """Execute one document and send its status; False when the connection must close."""
        if doc.root not in _CRCL_ROOTS:
            self.error(self.command_id, f"a <{doc.root}> document is not a CRCL command (CRCLCommandInstance); "
                                        "the connection is closed")
            return False
        try:
            items = _commands(doc)
        except Exception as exc:  # InputError, ValueError; anything else is a bug of ours: answered too
            why = str(exc) if isinstance(exc, (InputError, ValueError)) else \
                f"internal error: {type(exc).__name__}: {exc}"
            found = _failed_id(doc, exc.line if isinstance(exc, InputError) else None)
            self.error(found if found is not None else self.command_id, why)
            return True
        for command, command_id in items:
            if isinstance(command, GetStatus):
                self.send_status()
                continue
            if isinstance(command, ConfigureStatusReport):
                self.report = command
                self.command_id, self.state, self.description = command_id, DONE, _report_note(command)
                self.send_status()
                continue
            self.command_id, self.state, self.description = command_id, WORKING, ""
            status = self.server.execute_for(self, command)
            self.state, self.description = (DONE, status.message) if status.done else (ERROR, status.message)
            self.send_status()
            if not status.done:
                break
        return True

    # --- writing ---------------------------------------------------------------------------
    def error(self, command_id: int, why: str) -> None:
        self.command_id, self.state, self.description = command_id, ERROR, why
        self.send_status()

    def status(self) -> bytes:
        """This connection's status now, as a CRCLStatus document (StatusID taken) of fewer than
        :data:`STATUS_BYTES` bytes: a long description is cut to fit."""
        self.status_id += 1
        pose, gripper = self.server.pose_and_gripper(self)
        settings = self.server.settings(self) if self.report.settings else None
        text = " ".join(self.description.split())
        while True:
            doc = write_status(CommandStatus(self.command_id, self.status_id, self.state,
                                             pose=pose if self.report.pose and self.channel != "gripper" else None,
                                             gripper=gripper if self.report.gripper else None, description=text,
                                             settings=settings))
            if len(doc) < STATUS_BYTES or not text:
                return doc
            text = _cut(text, len(doc) - STATUS_BYTES + 1)

    def send_status(self) -> None:
        """Send the status now (blocking: the client reads it)."""
        with self.lock:
            data = self.unsent + self.status()
            self.unsent = b""
            try:
                self.sock.sendall(data)
            except OSError:
                return
            self.sent = time.monotonic()

    def heartbeat(self, now: float) -> None:
        """Send the status if the connection has been sent none for a period; never blocks (a
        client that does not read gets no more until it does)."""
        if now - self.sent < self.server.status_period or not self.lock.acquire(blocking=False):
            return
        try:
            if self.unsent:
                self.unsent = self.unsent[_send_some(self.sock, self.unsent):]
                return
            data = self.status()
            n = _send_some(self.sock, data)
            self.unsent = data[n:] if n else b""
            if n:
                self.sent = now
        finally:
            self.lock.release()


def _send_some(sock: socket.socket, data: bytes) -> int:
    """The bytes of ``data`` the socket takes now, without waiting."""
    try:
        return sock.send(data, socket.MSG_DONTWAIT)
    except (BlockingIOError, InterruptedError):
        return 0
    except OSError:
        return len(data)  # the connection is gone: nothing to keep


def _commands(doc: Document) -> list[tuple[Command, int]]:
    """The (command, CommandID) pairs of a CRCL 1.x document; InputError naming what is wrong."""
    if doc.root == "CRCLProgram":
        return list(read_program_instance(doc.data, "program"))
    return [read_command_instance(doc.data, "command")]


def _report_note(report: ConfigureStatusReport) -> str:
    """What a connection's statuses carry after ``report``, and what they cannot."""
    carried = [part for part, on in (("pose", report.pose), ("gripper", report.gripper),
                                     ("settings (units, speed, end effector)", report.settings)) if on]
    said = ["status reports " + (", ".join(carried) if carried else "the command's state only")]
    if report.joints:
        said.append("no joint statuses: the simulated robot has no joint model")
    if report.sensors or report.guards:
        said.append("no sensors or guards on this controller")
    return "; ".join(said)


def _failed_id(doc: Document, line: int | None) -> int | None:
    """The CommandID of the command of ``doc`` at ``line`` (a program's: the command element
    holding that line; else the document's first CommandID); None when none can be read."""
    data = doc.data
    if line is not None and doc.root == "CRCLProgram":
        lines = data.split(b"\n")
        starts = [i for i in range(min(line, len(lines))) if _COMMAND_START.search(lines[i])]
        if starts:
            data = b"\n".join(lines[starts[-1]:])
    found = _COMMAND_ID.search(data)
    return int(found.group(1)) if found else None


#: A line where one of a program's commands begins.
_COMMAND_START = re.compile(rb"<(?:\w+:)?(?:InitCanon|MiddleCommand|EndCanon)[\s>/]")


def _cut(text: str, over: int) -> str:
    """``text`` shorter by at least ``over`` bytes as written in XML (``...`` at its end)."""
    body = text[:-3] if text.endswith("...") else text
    while body and len(escape(text).encode()) - len(escape(body + "...").encode()) < over:
        body = body[:-max(1, len(body) // 8)]
    return body + "..." if body else ""
