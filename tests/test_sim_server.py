"""kb.sim.server and kb.crcl.remote: the simulated cell over its sockets (kitkb's cell protocol,
kb.crcl.wire) behaves as the same cell in-process — sensing, CRCL programs, seeded faults,
inspection — answers what is malformed and keeps serving, and fails clearly when unreachable;
``kitkb sim serve`` as a process."""

from __future__ import annotations

import os
import re
import select
import signal
import socket
import subprocess
import sys
from contextlib import contextmanager
from pathlib import Path
from typing import Iterator, Sequence

import numpy as np
import pytest

from kb import crcl
from kb.cli import main
from kb.core.errors import CellError, InputError
from kb.core.resources import ontology_path
from kb.crcl import RemoteCell, execute_program
from kb.crcl.cell import NOT_EXECUTED, Observation, Status, parse_truth_line, truth_line
from kb.crcl.wire import (END, action_message, length_line, parse_action, parse_address, parse_status_line,
                          status_line)
from kb.sim import CellInterface, CellServer, FaultSpec, SimulatedCell

INIT = ontology_path("scenarios/small-kit/init.ttl")
NS = "https://w3id.org/kitkb/scenario/small-kit#"
ROBOT, PART, TRAY, GRIPPER = NS + "robot_1", NS + "part_a_1", NS + "part_a_tray", NS + "part_gripper"
GRIPPER_MOUNT = (2.85, 0.0, 0.8)  # as tests/test_sim.py: the part gripper's mount face in its holder
PART_TOP = (0.165, 0.945, 0.81)  # top face of part_a_1 in part_a_tray
SPEC = "missed-grasp=0.25,dropped-part=0.25,part-moved=0.25,wrong-sku=0.25"
REPO = Path(__file__).resolve().parents[1]


@contextmanager
def served(cell: SimulatedCell, protocol: str = "crcl") -> Iterator[tuple[CellServer, RemoteCell]]:
    """``cell`` served on free loopback ports, and a RemoteCell on it (CRCL 1.x, or kitkb's
    ``{Length N}`` protocol)."""
    with CellServer(cell, sensor_port=0, command_port=0) as server:
        with RemoteCell("127.0.0.1", server.sensor_port, server.command_port, timeout=10,
                        protocol=protocol) as remote:  # type: ignore[arg-type]
            yield server, remote


def move(x: float, y: float, z: float) -> crcl.MoveTo:
    return crcl.MoveTo(crcl.Pose((x, y, z), (1, 0, 0), (0, 0, -1)))


def mount_commands(at: tuple[float, float, float] = GRIPPER_MOUNT) -> list[crcl.Command]:
    x, y, z = at
    return [crcl.InitCanon(), move(x, y, z + 0.2), move(x, y, z), crcl.CloseToolChanger(), move(x, y, z + 0.2)]


def pick_commands(top: tuple[float, float, float] = PART_TOP) -> list[crcl.Command]:
    x, y, z = top
    return [move(x, y, 1.0), move(x, y, z), crcl.CloseGripper(), move(x, y, 1.0)]


def same_ground_truth(a: SimulatedCell, b: SimulatedCell) -> None:
    sa, sb = a.scene(), b.scene()
    assert sa.names == sb.names
    np.testing.assert_array_equal(sa.lo, sb.lo)
    np.testing.assert_array_equal(sa.hi, sb.hi)
    np.testing.assert_array_equal(sa.poses, sb.poses)
    np.testing.assert_array_equal(sa.parents, sb.parents)
    assert sa.facts == sb.facts and sa.inspections == sb.inspections and a.time == b.time


def play(cell: CellInterface) -> list[list[Status]]:
    """tests/test_sim.py's stream of take-part / put-part actions, an action's commands at once."""
    statuses = [execute_program(cell, mount_commands())]
    index = 1
    for n, (px, py) in enumerate([(0.165, 0.945), (0.305, 0.945), (0.445, 0.945), (0.165, 1.045)]):
        part = NS + f"part_a_{n + 1}"
        cell.begin_action(index, "take-part", (ROBOT, part, TRAY, GRIPPER))
        statuses.append(execute_program(cell, pick_commands((px, py, 0.81))))
        cell.begin_action(index + 1, "put-part", (ROBOT, part, NS + "kit_1", NS + "work_table_1", TRAY))
        statuses.append(execute_program(cell, [move(1.2 + 0.15 * n, 0.0, 1.0), crcl.OpenGripper()]))
        index += 2
    return statuses


def talk(port: int, data: bytes, answers: int = 1) -> list[str]:
    """Raw bytes to a port; the lines of ``answers`` answers (each up to {End})."""
    with socket.create_connection(("127.0.0.1", port), timeout=10) as s:
        s.sendall(data)
        reader = s.makefile("rb")
        lines: list[str] = []
        while answers:
            raw = reader.readline()
            assert raw.endswith(b"\n"), f"connection closed early, after {lines}"
            line = raw.decode().rstrip("\r\n")  # the sensor port ends lines in CR LF, as USARSim
            lines.append(line)
            answers -= line == END
        return lines


def program(commands: Sequence[crcl.Command]) -> bytes:
    data = crcl.write_xml(crcl.Program(tuple(commands)))
    return length_line(len(data)).encode() + b"\n" + data


# --- the same cell, in-process and over the sockets --------------------------------------------

def test_a_remote_cell_implements_the_interface() -> None:
    assert isinstance(RemoteCell(), CellInterface)
    assert isinstance(SimulatedCell(INIT), crcl.CellInterface)


def test_sense_by_class_and_by_name_equals_the_cell_in_process() -> None:
    local = SimulatedCell(INIT, noise=(0.01, 0.02), seed=5)
    with served(SimulatedCell(INIT, noise=(0.01, 0.02), seed=5)) as (_, remote):
        for query, by in [("Part", "class"), ("https://w3id.org/kitkb/kitting#Part", "class"),
                          ("part_a_1", "name"), (GRIPPER, "name"), ("EndEffector", "class"), ("Nothing", "class"),
                          ("Part", "class")]:
            assert remote.sense(query, by=by) == local.sense(query, by=by)  # type: ignore[arg-type]
    parts = SimulatedCell(INIT).sense("Part")
    assert [o.sku for o in parts] == ["sku_part_a"] * 4 + ["sku_part_b"] * 3


def test_a_pick_program_gives_the_same_ground_truth_as_in_process() -> None:
    local, served_cell = SimulatedCell(INIT), SimulatedCell(INIT)
    expected = [[local.execute(c) for c in commands] for commands in (mount_commands(), pick_commands())]
    with served(served_cell) as (_, remote):
        got = [remote.execute_program(commands) for commands in (mount_commands(), pick_commands())]
        assert got == expected and all(s.done for s in got[0] + got[1])
        assert got[1][2] == Status.ok(f"grasped {PART}")
        same_ground_truth(served_cell, local)
        assert remote.execute(move(1.4, 0.1, 1.2)) == local.execute(move(1.4, 0.1, 1.2))  # one by one
        assert remote.execute(crcl.OpenGripper()).done and local.execute(crcl.OpenGripper()).done
    same_ground_truth(served_cell, local)


def test_begin_action_over_the_wire_injects_the_same_seeded_faults() -> None:
    local, served_cell = SimulatedCell(INIT, faults=FaultSpec.parse(SPEC, seed=7)), \
        SimulatedCell(INIT, faults=FaultSpec.parse(SPEC, seed=7))
    expected = play(local)
    with served(served_cell) as (_, remote):
        assert play(remote) == expected
    assert served_cell.injected == local.injected
    assert [(i.kind, i.action_index) for i in local.injected] == [
        ("part-moved", 1), ("part-moved", 3), ("wrong-sku", 5), ("dropped-part", 7)]
    same_ground_truth(served_cell, local)


def test_a_wrong_sku_shows_in_the_sensors_answer() -> None:
    with served(SimulatedCell(INIT, faults=FaultSpec(at={0: "wrong-sku"}, seed=1))) as (_, remote):
        assert remote.sense("part_a_1", by="name")[0].sku == "sku_part_a"
        remote.begin_action(0, "take-part", (ROBOT, PART, TRAY, GRIPPER))
        assert remote.sense("part_a_1", by="name")[0].sku == "sku_part_b"


def test_inspect_over_the_wire() -> None:
    cell = SimulatedCell(INIT, faults=FaultSpec(at={0: "defective-part"}, seed=1))
    with served(cell) as (server, remote):
        remote.begin_action(0, "take-part", (ROBOT, PART, TRAY, GRIPPER))
        assert remote.inspect(PART) is False
        assert remote.inspect("part_a_2") is True
        assert remote.inspect("no_such_part") is False
        assert cell.scene().inspections == {"quality-inspection": {NS + "part_a_2"}}
        assert talk(server.sensor_port, b"{Inspect part_a_1}\n") == ["{Name part_a_1} {Quality defective}", END]


# --- what is malformed is answered, and the server keeps serving -------------------------------

def test_a_malformed_sensor_line_gets_an_error_and_the_server_keeps_serving() -> None:
    with served(SimulatedCell(INIT)) as (server, remote):
        # (an empty line, {Name} and {Class Part} {Name x} are USARTruth queries: tests/test_usartruth_clients.py)
        lines = talk(server.sensor_port, b"garbage\n{Name a} {name b}\n{Inspect part_a_1} {Name x}\n{Class Part} text\n"
                                         b"{Colour red}\n{Name part_a_1}\n", answers=6)
        errors = [line for line in lines if line.startswith("{Error ")]
        assert len(errors) == 5 and lines.count(END) == 6
        assert "not a line of key-value fields: 'garbage'" in errors[0]
        assert parse_truth_line(lines[-2]).name == PART
        assert talk(server.sensor_port, b"x" * 70000 + b"\n") [0].startswith("{Error a line longer than")
        assert [o.name for o in remote.sense("part_b_1", by="name")] == [NS + "part_b_1"]
        with pytest.raises(ValueError, match="braces"):
            remote.sense("Part} {Name x")


def test_a_program_that_does_not_parse_gets_one_error_line_and_the_server_keeps_serving() -> None:
    good = program([crcl.InitCanon(), crcl.Dwell(1.5), crcl.EndCanon()])
    broken = b"<CRCLProgram>\n<InitCanon/>\n<Dwell><DwellTime>x</DwellTime></Dwell>\n<EndCanon/>\n</CRCLProgram>\n"
    unclosed = b"<CRCLProgram>\n<InitCanon/>\n"
    entity = (b'<?xml version="1.0"?>\n<!DOCTYPE CRCLProgram [<!ENTITY x SYSTEM "file:///etc/passwd">]>\n'
              b"<CRCLProgram><InitCanon/><Message><Message>&x;</Message></Message><EndCanon/></CRCLProgram>")
    with served(SimulatedCell(INIT)) as (server, remote):
        frames = b"".join(length_line(len(d)).encode() + b"\n" + d for d in (broken, unclosed, entity))
        lines = talk(server.command_port, frames + good, answers=4)
        assert lines[0] == "{Status error} {Message program:3: error: <DwellTime> must be a decimal number, not 'x'}"
        assert lines[2].startswith("{Status error} {Message program:") and "XML syntax error" in lines[2]
        assert "DOCTYPE is not allowed" in lines[4] and "passwd" not in "".join(lines)
        assert [parse_status_line(x) for x in lines[6:9]] == [(1, Status.ok()), (2, Status.ok()), (3, Status.ok())]
        assert lines[1::2][:3] == [END] * 3 and lines[-1] == END
        # a header that is not {Length N}: answered, that connection closed, the server serving
        assert talk(server.command_port, b"{hello}\n<CRCLProgram/>\n")[0].startswith(
            "{Status error} {Message expected a Length header")
        # what is neither kitkb's protocol nor XML: a CRCL 1.x error status, that connection closed
        with socket.create_connection(("127.0.0.1", server.command_port), timeout=10) as s:
            s.sendall(b"hello\n<CRCLProgram/>\n")
            answer = b"".join(iter(lambda: s.recv(4096), b""))
        assert b"<CommandState>CRCL_Error</CommandState>" in answer and b"not XML" in answer
        assert remote.execute(crcl.Dwell(0.5)) == Status.ok()
        assert remote.sense("Robot")[0].time == 2.0


def test_a_malformed_action_message_is_an_error_status() -> None:
    with served(SimulatedCell(INIT)) as (server, remote):
        statuses = remote.execute_program([crcl.Message("kitkb-action x take-part"), crcl.Dwell(1)])
        assert statuses[0].state == "error" and "kitkb-action <index>" in statuses[0].message
        assert statuses[1] == Status.error(NOT_EXECUTED)
        assert remote.execute(crcl.Message("hello")) == Status.ok()


# --- the client's side of the protocol ----------------------------------------------------------

def test_programs_get_the_envelope_crcl_xsd_needs_and_unsendable_commands_are_errors() -> None:
    with served(SimulatedCell(INIT), protocol="kitkb") as (_, remote):  # (CRCL 1.x: tests/test_crcl_wire.py)
        assert remote.execute_program([]) == []
        assert remote.execute(crcl.InitCanon()) == Status.ok()
        assert remote.execute(crcl.EndCanon()) == Status.ok()
        assert remote.execute_program([crcl.InitCanon(), crcl.EndCanon()]) == [Status.ok()] * 2
        statuses = remote.execute_program([crcl.Dwell(1), crcl.SetCoordinateFrame("Workstation"), crcl.Dwell(1)])
        assert statuses[0] == Status.ok() and statuses[2] == Status.error(NOT_EXECUTED)
        assert "SetCoordinateFrame has no element in CRCL.xsd" in statuses[1].message
        statuses = remote.execute_program([crcl.Dwell(1), crcl.InitCanon()])
        assert statuses[1].state == "error" and "InitCanon only as the first" in statuses[1].message
        assert remote.execute(crcl.Unreadable("MoveTo(", "bad")).state == "error"
        assert remote.execute(crcl.SetCoordinateFrame("ToolTip")).state == "error"  # not in CRCL.xsd: not sent
        assert remote.execute(crcl.SetLengthUnits("inch")) == Status.ok()  # the cell takes inches from now on
        assert remote.sense("Robot")[0].time == 2.0  # the two Dwell(1) that ran


def test_the_cell_executes_the_commands_sent_and_not_their_frame() -> None:
    cell = SimulatedCell(INIT)
    executed: list[crcl.Command] = []
    execute = cell.execute
    cell.execute = lambda c: executed.append(c) or execute(c)  # type: ignore[method-assign]
    with served(cell, protocol="kitkb") as (server, remote):  # (CRCL 1.x: tests/test_crcl_wire.py)
        assert remote.execute_program([crcl.Dwell(1)]) == [Status.ok()]
        remote.begin_action(0, "attach-endeffector", (ROBOT, GRIPPER))
        assert cell.action == (0, "attach-endeffector", (ROBOT, GRIPPER))
        remote.execute_program([crcl.InitCanon(), crcl.Dwell(2)])
        remote.execute_program([crcl.Dwell(3), crcl.EndCanon()])
        remote.execute_program([crcl.InitCanon(), crcl.EndCanon()])
        remote.execute_program([crcl.InitCanon(), crcl.Dwell(4), crcl.EndCanon()])  # a whole program: as it is
        assert executed == [crcl.Dwell(1), crcl.InitCanon(), crcl.Dwell(2), crcl.Dwell(3), crcl.EndCanon(),
                            crcl.InitCanon(), crcl.EndCanon(), crcl.InitCanon(), crcl.Dwell(4), crcl.EndCanon()]
        framed = program([crcl.InitCanon(), crcl.Message("kitkb-frame init end"), crcl.Dwell(1), crcl.EndCanon()])
        assert talk(server.command_port, framed) == [
            "{Line 1} {Status done} {Message frame}", "{Line 2} {Status done} {Message frame}",
            "{Line 3} {Status done} {Message }", "{Line 4} {Status done} {Message frame}", END]
        assert executed[-1] == crcl.Dwell(1) and len(executed) == 11


def test_a_kit_created_over_the_wire_is_the_kit_created_in_process() -> None:
    kit_tray_top, tray_gripper = (0.235, -0.995, 0.04), (2.55, 0.0, 0.8)
    create = (NS + "kit_1", NS + "kit_tray_1", NS + "work_table_1")

    def build(cell: CellInterface) -> None:
        execute_program(cell, mount_commands(tray_gripper))
        execute_program(cell, pick_commands(kit_tray_top) + [move(1.4, 0.0, 0.9), crcl.OpenGripper(),
                                                             move(1.4, 0.0, 1.2)])
        cell.begin_action(4, "create-kit", create)
        execute_program(cell, [crcl.Dwell(0.5), crcl.EndCanon()])

    local, served_cell = SimulatedCell(INIT), SimulatedCell(INIT)
    build(local)
    with served(served_cell) as (_, remote):
        build(remote)
        assert remote.sense("Kit") == local.sense("Kit") != []
    same_ground_truth(served_cell, local)


def test_wire_forms() -> None:
    obs = Observation(PART, "Part", 1.5, (1.0, 2.0, 0.3), (0.0, 0.1, 0.2), "sku_part_a")
    assert truth_line(obs).endswith("{Rotation 0.0,0.1,0.2} {Sku sku_part_a}")
    assert parse_truth_line(truth_line(obs)) == obs
    assert status_line(3, Status.error("bad {x}\nline")) == "{Line 3} {Status error} {Message bad (x) line}"
    assert parse_status_line("{Line 3} {Status done} {Message }") == (3, Status.ok())
    message = action_message(4, "take-part", (ROBOT, PART))
    assert message.message == f"kitkb-action 4 take-part {ROBOT} {PART}"
    assert parse_action(message.message) == (4, "take-part", (ROBOT, PART))
    assert parse_action("hello") is None
    with pytest.raises(ValueError):
        action_message(1, "take part", ())
    assert parse_address("localhost:3989") == ("localhost", 3989, 3990)
    assert parse_address("127.0.0.1:5000,6000") == ("127.0.0.1", 5000, 6000)
    with pytest.raises(InputError, match="HOST:PORT"):
        parse_address("3989")


# --- an unreachable cell ------------------------------------------------------------------------

def free_ports() -> tuple[int, int]:
    """Two ports nothing listens on (bound to find them, then released)."""
    with socket.socket() as a, socket.socket() as b:
        a.bind(("127.0.0.1", 0))
        b.bind(("127.0.0.1", 0))
        return int(a.getsockname()[1]), int(b.getsockname()[1])


def test_an_unreachable_cell_is_a_clear_error() -> None:
    port, other = free_ports()
    remote = RemoteCell("127.0.0.1", port, other, timeout=2)
    with pytest.raises(CellError) as info:
        remote.sense("Part")
    assert str(info.value).startswith(f"127.0.0.1:{port}: error: cannot reach the cell's sensor port")
    assert info.value.exit_code == 2
    with pytest.raises(CellError, match=f"127.0.0.1:{other}: error: cannot reach the cell's command port"):
        remote.execute(crcl.Dwell(1))


def test_a_restarted_server_is_reconnected_and_a_stopped_one_is_an_error() -> None:
    first = CellServer(SimulatedCell(INIT), sensor_port=0, command_port=0).start()
    ports = first.sensor_port, first.command_port
    remote = RemoteCell("127.0.0.1", *ports, timeout=5)
    assert len(remote.sense("Part")) == 7 and remote.execute(crcl.Dwell(1)).done
    first.close()
    with CellServer(SimulatedCell(INIT), sensor_port=ports[0], command_port=ports[1]):
        assert len(remote.sense("Part")) == 7  # the old connections are replaced
        assert remote.execute(crcl.Dwell(1)).done
    with pytest.raises(CellError, match="cannot reach"):
        remote.sense("Part")
    remote.close()


def test_a_busy_port_is_a_clear_error() -> None:
    with CellServer(SimulatedCell(INIT), sensor_port=0, command_port=0) as server:
        with pytest.raises(CellError, match=f"127.0.0.1:{server.sensor_port}: error: cannot listen"):
            CellServer(SimulatedCell(INIT), sensor_port=server.sensor_port, command_port=0)
        assert main(["sim", "serve", str(INIT), "--sensor-port", str(server.sensor_port)]) == 2
    assert main(["sim", "serve", str(INIT), "--faults", "lost-part=0.1"]) == 2
    assert main(["sim", "serve", str(INIT), "--noise", "0.1"]) == 2


# --- kitkb sim serve ------------------------------------------------------------------------------

@pytest.mark.parametrize("stop", [signal.SIGINT, signal.SIGTERM])
def test_kitkb_sim_serve_answers_and_stops_on_a_signal(stop: signal.Signals) -> None:
    env = dict(os.environ, PYTHONPATH=str(REPO))
    proc = subprocess.Popen([sys.executable, "-m", "kb.cli", "sim", "serve", str(INIT), "--sensor-port", "0",
                             "--command-port", "0", "--faults", "part-missing@0", "--seed", "3",
                             "--goal", str(ontology_path("scenarios/small-kit/goal.ttl"))],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
    try:
        assert proc.stdout is not None
        ready, _, _ = select.select([proc.stdout], [], [], 60)
        assert ready, "kitkb sim serve printed no line"
        line = proc.stdout.readline()
        m = re.search(r"sensor port (\d+), command port (\d+) on 127\.0\.0\.1 \(--cell (\S+)\)", line)
        assert m, line
        with RemoteCell.from_address(m.group(3)) as remote:
            assert (remote.sensor.port, remote.command.port) == (int(m.group(1)), int(m.group(2)))
            assert [o.name for o in remote.sense("part_a_1", by="name")] == [PART]
            remote.begin_action(0, "take-part", (ROBOT, PART, TRAY, GRIPPER))
            assert remote.sense("part_a_1", by="name") == []
        proc.send_signal(stop)
        assert proc.wait(timeout=30) == 0
        assert "cell server stopped" in (proc.stderr.read() if proc.stderr else "")
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
