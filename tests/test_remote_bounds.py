"""A misbehaving peer cannot hang a run (issue 26, point 10): RemoteCell bounds every answer in
total time, lines and bytes (and each line's length), and gives a peer past a bound up within
the bound, as a CellError (exit 2) naming the peer's host:port and the bound.

The peers are fakes on loopback: one never answers, one sends lines without ever sending
{End} (fast, or slowly: one line at a time, each well inside any per-recv timeout), one sends a
line that never ends, one streams status lines forever on the command port."""

from __future__ import annotations

import socket
import threading
import time
from contextlib import contextmanager
from typing import Callable, Iterator

import pytest

from kb import crcl
from kb.cli import main
from kb.core import limits
from kb.core.errors import CellError, InputError
from kb.core.resources import ontology_path
from kb.crcl import RemoteCell
from kb.crcl.remote import Bounds
from kb.crcl.wire import MAX_LINE

#: what a test allows beyond a time bound (a loaded 2-core machine)
SLACK = 1.5
LINE = b"{Name part_a_1} {Class Part} {Time 0.0} {Location 0.1,0.2,0.3} {Rotation 0.0,0.0,0.0}\r\n"
INIT = ontology_path("scenarios/small-kit/init.ttl")
GOAL = ontology_path("scenarios/small-kit/goal.ttl")


class Peer:
    """A TCP server on a free loopback port; each connection is handed to ``behave(conn, stop)``
    in a thread of its own. Closing it stops every connection."""

    def __init__(self, behave: Callable[[socket.socket, threading.Event], None]) -> None:
        self.behave = behave
        self.stop = threading.Event()
        self.listener = socket.create_server(("127.0.0.1", 0))
        self.port = int(self.listener.getsockname()[1])
        self.threads: list[threading.Thread] = []
        self.accepts = 0
        self.first: float | None = None  # when the first connection came (time.monotonic)
        self.thread = threading.Thread(target=self._accept, daemon=True)
        self.thread.start()

    def _accept(self) -> None:
        self.listener.settimeout(0.05)
        while not self.stop.is_set():
            try:
                conn, _ = self.listener.accept()
            except (TimeoutError, OSError):
                continue
            self.accepts += 1
            self.first = self.first or time.monotonic()
            t = threading.Thread(target=self._serve, args=(conn,), daemon=True)
            t.start()
            self.threads.append(t)

    def _serve(self, conn: socket.socket) -> None:
        with conn:
            try:
                self.behave(conn, self.stop)
            except OSError:  # the client gave up and closed
                pass

    def close(self) -> None:
        self.stop.set()
        self.thread.join()
        self.listener.close()
        for t in self.threads:
            t.join(timeout=5)


@contextmanager
def peer(behave: Callable[[socket.socket, threading.Event], None]) -> Iterator[Peer]:
    p = Peer(behave)
    try:
        yield p
    finally:
        p.close()


def read_request(conn: socket.socket) -> None:
    """Wait for the client's first line."""
    data = b""
    while b"\n" not in data:
        chunk = conn.recv(4096)
        if not chunk:
            raise OSError("closed")
        data += chunk


def silent(conn: socket.socket, stop: threading.Event) -> None:
    read_request(conn)
    stop.wait()


def endless_lines(pause: float) -> Callable[[socket.socket, threading.Event], None]:
    def behave(conn: socket.socket, stop: threading.Event) -> None:
        read_request(conn)
        while not stop.is_set():
            conn.sendall(LINE)
            if pause:
                stop.wait(pause)
    return behave


def endless_line(conn: socket.socket, stop: threading.Event) -> None:
    read_request(conn)
    block = b"x" * 4096
    while not stop.is_set():
        conn.sendall(block)


def status_stream(conn: socket.socket, stop: threading.Event) -> None:
    """A CRCL 1.x command port that answers a command with CRCL_Working statuses forever."""
    read_request(conn)
    n = 0
    while not stop.is_set():
        n += 1
        conn.sendall(f"<CRCLStatus><CommandStatus><CommandID>1</CommandID><StatusID>{n}</StatusID>"
                     "<CommandState>CRCL_Working</CommandState></CommandStatus></CRCLStatus>".encode())
        stop.wait(0.05)


def cell(p: Peer, seconds: float | None = 1.0, lines: int | None = None, size: int | None = None) -> RemoteCell:
    return RemoteCell("127.0.0.1", p.port, p.port, bounds=Bounds(seconds, lines, size))


def fails_within(call: Callable[[], object], bound: float) -> tuple[str, float]:
    """The CellError ``call`` raises, and how long it took; it must come within ``bound`` + SLACK."""
    start = time.monotonic()
    with pytest.raises(CellError) as info:
        call()
    took = time.monotonic() - start
    assert took < bound + SLACK, f"took {took:.2f} s for a bound of {bound} s: {info.value}"
    assert info.value.exit_code == 2
    return str(info.value), took


# --- time ---------------------------------------------------------------------------------------

def test_a_peer_that_never_answers_fails_at_the_time_bound() -> None:
    with peer(silent) as p, cell(p) as remote:
        message, took = fails_within(lambda: remote.sense("Part"), 1.0)
    assert took >= 0.95
    assert message == (f"127.0.0.1:{p.port}: error: no answer from the sensor port within 1 s (the bound on the "
                       "time a cell's answer takes; set KITKB_MAX_CELL_SECONDS to raise it)")


def test_a_peer_streaming_slowly_without_end_fails_at_the_time_bound_not_per_recv() -> None:
    with peer(endless_lines(0.1)) as p, cell(p, seconds=1.5) as remote:
        message, took = fails_within(lambda: remote.sense("Part"), 1.5)
    assert took >= 1.45
    assert message.startswith(f"127.0.0.1:{p.port}: error: the sensor port's answer took longer than 1.5 s (the "
                              "bound on the time a cell's answer takes; set KITKB_MAX_CELL_SECONDS to raise it) "
                              "without {End} (")
    assert " lines, " in message and "so far)" in message


def test_a_command_port_streaming_status_fails_at_the_time_bound() -> None:
    with peer(status_stream) as p, cell(p) as remote:
        message, _ = fails_within(lambda: remote.execute(crcl.Dwell(1)), 1.0)
    assert message.startswith(f"127.0.0.1:{p.port}: error: the cell's command port: InitCanon command 1 was not "
                              "acknowledged Done or Error within 1 s; last heard: CommandID 1 CRCL_Working")
    assert "KITKB_MAX_CELL_SECONDS" in message


def test_a_stall_on_a_reused_connection_is_not_retried_past_the_bound() -> None:
    answered = threading.Event()

    def once(conn: socket.socket, stop: threading.Event) -> None:
        read_request(conn)
        if not answered.is_set():
            answered.set()
            conn.sendall(LINE + b"{End}\r\n")
            read_request(conn)
        stop.wait()
    with peer(once) as p, cell(p) as remote:
        assert [o.name for o in remote.sense("Part")] == ["part_a_1"]
        fails_within(lambda: remote.sense("Part"), 1.0)
        assert p.accepts == 1


# --- lines and bytes ------------------------------------------------------------------------------

def test_a_peer_sending_lines_without_end_fails_at_the_line_bound() -> None:
    with peer(endless_lines(0)) as p, cell(p, seconds=60, lines=1000) as remote:
        message, took = fails_within(lambda: remote.sense("Part"), 0.0)
    assert f"127.0.0.1:{p.port}: error: the sensor port's answer had more lines than 1,000 lines (the bound on " \
           "lines in a cell's answer; set KITKB_MAX_CELL_LINES to raise it) without {End} (1,001 lines" in message


def test_a_peer_sending_too_many_bytes_fails_at_the_byte_bound() -> None:
    with peer(endless_lines(0)) as p, cell(p, seconds=60, size=100_000) as remote:
        message, _ = fails_within(lambda: remote.sense("Part"), 0.0)
    assert "the sensor port's answer was longer than 100.0 kB (the bound on a cell's answer's size; set " \
           "KITKB_MAX_CELL_BYTES to raise it)" in message


def test_a_line_that_never_ends_fails_at_the_line_length() -> None:
    with peer(endless_line) as p, cell(p, seconds=60) as remote:
        message, _ = fails_within(lambda: remote.sense("Part"), 0.0)
    assert message == (f"127.0.0.1:{p.port}: error: the sensor port broke the protocol: a line longer than "
                       f"{MAX_LINE} bytes")


def test_an_answer_within_the_bounds_is_read_whole() -> None:
    def answer(conn: socket.socket, stop: threading.Event) -> None:
        read_request(conn)
        for _ in range(5):  # in pieces, slowly, but within a second in all
            conn.sendall(LINE[:30])
            stop.wait(0.05)
            conn.sendall(LINE[30:])
        conn.sendall(b"{End}\r\n")
        stop.wait()
    with peer(answer) as p, cell(p, seconds=5, lines=5, size=5 * len(LINE) + 7) as remote:
        assert len(remote.sense("Part")) == 5


# --- configuration ---------------------------------------------------------------------------------

def test_the_bounds_are_named_limits_read_from_the_environment(monkeypatch: pytest.MonkeyPatch) -> None:
    for limit in limits.CELL_BOUNDS:
        assert limit.env.startswith("KITKB_MAX_CELL_") and limit.default > 0
    assert RemoteCell().bounds == Bounds(limits.CELL_SECONDS.default, limits.CELL_LINES.default,
                                         limits.CELL_BYTES.default)
    monkeypatch.setenv("KITKB_MAX_CELL_SECONDS", "2")
    monkeypatch.setenv("KITKB_MAX_CELL_LINES", "10k")
    monkeypatch.setenv("KITKB_MAX_CELL_BYTES", "0")
    assert RemoteCell().bounds == Bounds(2, 10_000, None)
    assert RemoteCell(timeout=0.5).bounds == Bounds(0.5, 10_000, None)
    monkeypatch.setenv("KITKB_MAX_CELL_SECONDS", "soon")
    with pytest.raises(InputError, match="KITKB_MAX_CELL_SECONDS='soon' is not a whole number"):
        RemoteCell.from_address("127.0.0.1:3989")


def test_kitkb_run_against_a_peer_that_streams_forever_exits_2_within_the_bound(
        monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str], tmp_path) -> None:  # noqa: ANN001
    monkeypatch.setenv("KITKB_MAX_CELL_SECONDS", "2")
    with peer(endless_lines(0.05)) as sensor, peer(status_stream) as p:  # each streams forever
        code = main(["run", str(INIT), str(GOAL), "--cell", f"127.0.0.1:{sensor.port},{p.port}", "-o",
                     str(tmp_path), "--quiet"])
        assert p.first is not None
        took = time.monotonic() - p.first
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2
    assert err[-1].startswith(f"127.0.0.1:{p.port}: error: the ") and "KITKB_MAX_CELL_SECONDS" in err[-1]
    assert "Traceback" not in "\n".join(err)
    assert 1.95 <= took < 2 + SLACK  # from the first request to the exit
