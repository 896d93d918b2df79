"""The openers of cells behind sockets: ``kitkb://`` (a kitkb cell server) and ``crcl://`` (a
CRCL 1.x controller paired with a USARTruth-style pose sensor).

Both are :class:`kb.crcl.RemoteCell` s, built through its public constructor: a kitkb cell
server is one whole (it moves, senses, inspects and hears each action); a CRCL controller and
a sensor are two peers, possibly on two hosts, so :class:`CrclCell` pairs a RemoteCell used
for its command port only with one used for its sensor port only (a RemoteCell connects to a
port on first use: the port it never uses is never reached). Each opener first checks that
the ports it will use accept a connection, so an unreachable cell is refused before the run
starts (:func:`kb.cells.registry.reach`).
"""

from __future__ import annotations

from typing import Literal, Sequence

from kb.cells.registry import CellRequest, CellURL, reach
from kb.crcl.cell import Observation, Status
from kb.crcl.commands import Command
from kb.crcl.remote import RemoteCell
from kb.crcl.wire import action_message

#: kitkb's sensor port (USARTruth's) and NIST's CRCL port, where a URL names none
SENSOR_PORT = 3989
CRCL_PORT = 64444


def open_kitkb(url: CellURL, request: CellRequest) -> RemoteCell:
    """``kitkb://HOST[:PORT][?command=PORT&timeout=S]``: the cell server ``kitkb sim serve``
    (sensor port PORT, default 3989; command port PORT + 1 or ``command=``)."""
    url.only("command", "timeout")
    host, sensor = url.host or "127.0.0.1", url.port if url.port is not None else SENSOR_PORT
    command = url.number("command", int)
    command = command if command is not None else sensor + 1
    timeout = _timeout(url, request)
    for port in (sensor, command):
        _port(url, port)
        reach(url, host, port, timeout)
    return RemoteCell(host, sensor, command, timeout=timeout)


def open_crcl(url: CellURL, request: CellRequest) -> "CrclCell":
    """``crcl://HOST[:PORT]?sensor=HOST[:PORT][&timeout=S]``: a CRCL 1.x controller (default
    port 64444) and the USARTruth-style sensor that sees its cell (default port 3989)."""
    url.only("sensor", "timeout")
    raw = url.params.get("sensor")
    if not raw:
        raise url.refuse("a CRCL controller needs the sensor that sees its cell: ?sensor=HOST:PORT")
    sensor_host, _, sensor_port = raw.rpartition(":") if ":" in raw else (raw, "", "")
    try:
        s_port = int(sensor_port) if sensor_port else SENSOR_PORT
    except ValueError:
        raise url.refuse(f"sensor={raw!r}: expected HOST:PORT") from None
    c_host, c_port = url.host or "127.0.0.1", url.port if url.port is not None else CRCL_PORT
    s_host = sensor_host.strip("[]") or "127.0.0.1"
    timeout = _timeout(url, request)
    for host, port in ((c_host, c_port), (s_host, s_port)):
        _port(url, port)
        reach(url, host, port, timeout)
    return CrclCell(RemoteCell(c_host, s_port, c_port, timeout=timeout),
                    RemoteCell(s_host, s_port, c_port, timeout=timeout), url.text)


class CrclCell:
    """A CRCL controller and a pose sensor as one cell: it moves (``execute``,
    ``execute_program``: the controller), senses (``sense``: the sensor) and announces each
    plan action to the controller as a CRCL ``Message`` command (``kitkb-action ...``,
    :func:`kb.crcl.wire.action_message`: kitkb's cell server makes a kit there; any other
    controller may ignore it, and one that refuses it is driven on without); it cannot inspect
    or tell ground truth."""

    def __init__(self, controller: RemoteCell, sensor: RemoteCell, url: str = "crcl:") -> None:
        self.controller = controller
        self.sensor = sensor
        self.url = url

    def __repr__(self) -> str:
        return f"CrclCell({self.url})"

    def execute(self, command: Command) -> Status:
        """Carry out one CRCL command on the controller."""
        return self.controller.execute(command)

    def execute_program(self, commands: Sequence[Command]) -> list[Status]:
        """Carry out one action's commands on the controller, stopping at the first failure."""
        return self.controller.execute_program(commands)

    def sense(self, query: str, *, by: Literal["class", "name"] = "class") -> list[Observation]:
        """Objects of a class or of a name, as the sensor reports them."""
        return self.sensor.sense(query, by=by)

    def begin_action(self, index: int, action: str, args: tuple[str, ...]) -> None:
        """Announce plan action ``index`` as a CRCL Message; a refusal is no error (a lost
        connection is: :class:`~kb.core.errors.CellError`)."""
        self.controller.execute(action_message(index, action, tuple(args)))

    def close(self) -> None:
        """Close both peers' connections."""
        self.controller.close()
        self.sensor.close()


def _timeout(url: CellURL, request: CellRequest) -> float | None:
    value = url.number("timeout")
    return float(value) if value is not None else request.timeout


def _port(url: CellURL, port: int) -> None:
    if not 0 < port < 65536:
        raise url.refuse(f"port {port} is not a TCP port")
