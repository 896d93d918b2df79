"""CRCL 1.x on the wire (issue 27, points 2 and 3), checked with peers kitkb did not write.

* ``kitkb sim serve`` (a subprocess) driven by a plain-socket client written from
  doc/Reference.md and the behaviour of NIST's Python CRCL client: command instances as NIST's
  client writes them (white space before the XML declaration, no delimiter), one command at a
  time, one status read per ``recv(1024)``; a robot and a gripper client on one port at once.
* The server's answers to what is malformed, not CRCL or garbage; status size, StatusIDs,
  heartbeats, each connection's units.
* ``kitkb crcl send`` against fake CRCL controllers (threads, parsing with the standard
  library's ElementTree): NIST's example commands and programs; a controller that never
  acknowledges InitCanon, one that answers only on GetStatus, one that answers garbage, one
  that closes, one that reports an error.
* Every command kitkb sends during ``kitkb run --cell`` validates against
  CRCLCommandInstance.xsd (recorded at the server during a real small-kit run).
* The housekeeping commands NIST's clients send: ConfigureStatusReport first (the statuses of
  that connection then carry what it asked for), Enable/DisableGripper by name, sensors, joint
  tolerances, screws, loops and guarded commands answered CRCL_Error with the reason and the
  CommandID; every
  example of ../shared/crcl/instances through ``kitkb crcl send`` against ``kitkb sim serve``.
"""

from __future__ import annotations

import json
import os
import re
import select
import socket
import subprocess
import sys
import threading
import time
import xml.etree.ElementTree as ET
from contextlib import contextmanager
from pathlib import Path
from typing import Callable, Iterator

import pytest
from lxml import etree

from kb import crcl
from kb.cli import main
from kb.core.errors import CellError
from kb.core.resources import ontology_path
from kb.crcl import RemoteCell
from kb.crcl.cell import NOT_EXECUTED, Status
from kb.crcl import instance
from kb.crcl.instance import read_status, write_command_instance
from kb.crcl.wire import DocumentError, Documents
from kb.sim import CellServer, SimulatedCell

REPO = Path(__file__).resolve().parents[1]
CRCL_DIR = REPO.parent / "shared" / "crcl"
INSTANCES = CRCL_DIR / "instances"
INIT = ontology_path("scenarios/small-kit/init.ttl")
GOAL = ontology_path("scenarios/small-kit/goal.ttl")
GRIPPER_MOUNT = (2.85, 0.0, 0.8)  # the part gripper's mount face in its holder (tests/test_sim.py)
needs_crcl = pytest.mark.skipif(not (CRCL_DIR / "schemas" / "CRCLCommandInstance.xsd").is_file(),
                                reason="NIST's CRCL 1.x data (../shared/crcl) not beside the checkout")

# --- a client written from Reference.md and NIST's Python client --------------------------------

HEAD = '''<?xml version="1.0" encoding="UTF-8"?>
<CRCLCommandInstance
  xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance"
  xsi:noNamespaceSchemaLocation="../xmlSchemas/CRCLCommandInstance.xsd">
'''


def nist_command(kind: str, command_id: int, body: str = "", lead: str = "") -> bytes:
    """A command instance as NIST's Python client formats it (``lead``: its GetStatus and
    Dwell strings start with a line break and spaces before the XML declaration)."""
    return (lead + HEAD + f'  <CRCLCommand xsi:type="{kind}">\n    <CommandID>{command_id}</CommandID>\n'
            f"{body}  </CRCLCommand>\n</CRCLCommandInstance>").encode()


def nist_move(command_id: int, x: float, y: float, z: float) -> bytes:
    return nist_command("MoveToType", command_id, f"""    <MoveStraight>true</MoveStraight>
    <EndPosition>
      <Point><X>{x}</X> <Y>{y}</Y> <Z>{z}</Z></Point>
      <XAxis><I>1</I> <J>0</J> <K>0</K></XAxis>
      <ZAxis><I>0</I> <J>0</J> <K>-1</K></ZAxis>
    </EndPosition>
""")


def unit(command_id: int, kind: str, name: str) -> bytes:
    return nist_command(kind, command_id, f"    <UnitName>{name}</UnitName>\n")


def end_effector(command_id: int, setting: float) -> bytes:
    return nist_command("SetEndEffectorType", command_id, f"    <Setting>{setting}</Setting>\n")


class SimpleClient:
    """Sends one command at a time and reads one status per ``recv(1024)``, parsing it with
    ElementTree: what a simple CRCL client does."""

    def __init__(self, port: int) -> None:
        self.sock = socket.create_connection(("127.0.0.1", port), timeout=10)

    def status(self) -> ET.Element:
        data = self.sock.recv(1024)
        assert data, "the controller closed the connection"
        return ET.fromstring(data.strip())

    def send(self, data: bytes, command_id: int | None = None) -> ET.Element:
        """Send a command; the status that names it Done or Error (other statuses read past)."""
        self.sock.send(data)
        while True:
            st = self.status()
            cid = int(st.findtext("CommandStatus/CommandID") or -1)
            if command_id is None or (cid == command_id and state(st) in ("CRCL_Done", "CRCL_Error")):
                return st

    def close(self) -> None:
        self.sock.close()


def state(st: ET.Element) -> str:
    return st.findtext("CommandStatus/CommandState") or ""


def point(st: ET.Element) -> tuple[float, float, float]:
    p = st.find("PoseStatus/Pose/Point")
    assert p is not None, ET.tostring(st)
    return (float(p.findtext("X") or "nan"), float(p.findtext("Y") or "nan"), float(p.findtext("Z") or "nan"))


@contextmanager
def sim_serve(*extra: str) -> Iterator[tuple[int, int]]:
    """``kitkb sim serve`` small-kit as a subprocess on free ports: (sensor port, command port)."""
    env = dict(os.environ, PYTHONPATH=str(REPO))
    proc = subprocess.Popen([sys.executable, "-m", "kb.cli", "sim", "serve", str(INIT), "--sensor-port", "0",
                             "--command-port", "0", *extra], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True, env=env)
    try:
        assert proc.stdout is not None
        ready, _, _ = select.select([proc.stdout], [], [], 60)
        assert ready, "kitkb sim serve printed no line"
        m = re.search(r"sensor port (\d+), command port (\d+)", proc.stdout.readline())
        assert m
        yield int(m.group(1)), int(m.group(2))
    finally:
        proc.terminate()
        assert proc.wait(timeout=30) == 0


def test_a_client_kitkb_did_not_write_drives_kitkb_sim_serve() -> None:
    x, y, z = GRIPPER_MOUNT
    with sim_serve() as (_, port):
        robot = SimpleClient(port)
        try:
            st = robot.send(nist_command("InitCanonType", 1), 1)
            assert state(st) == "CRCL_Done" and int(st.findtext("CommandStatus/StatusID") or 0) >= 1
            start = point(st)
            assert state(robot.send(unit(2, "SetLengthUnitsType", "millimeter"), 2)) == "CRCL_Done"
            st = robot.send(nist_move(3, x * 1000, y * 1000, (z + 0.2) * 1000), 3)  # millimetres now
            assert state(st) == "CRCL_Done" and point(st) == pytest.approx((x * 1000, y * 1000, (z + 0.2) * 1000))
            assert point(st) != start
            robot.send(nist_move(4, x * 1000, y * 1000, z * 1000), 4)
            st = robot.send(nist_command("CloseToolChangerType", 5), 5)
            assert state(st) == "CRCL_Done" and "mounted" in (st.findtext("CommandStatus/StateDescription") or "")
            gripper = st.find("GripperStatus")
            assert gripper is not None and gripper.findtext("GripperName") == "part_gripper"
            assert gripper.get("{http://www.w3.org/2001/XMLSchema-instance}type") == "ParallelGripperStatusType"
            assert state(robot.send(end_effector(6, 0.0), 6)) == "CRCL_Done"  # close the gripper
            assert state(robot.send(end_effector(7, 1.0), 7)) == "CRCL_Done"
            assert state(robot.send(nist_command("OpenToolChangerType", 8), 8)) == "CRCL_Done"
            st = robot.send(nist_command("DwellType", 9, "    <DwellTime>0.5</DwellTime>\n", lead="\n "), 9)
            assert state(st) == "CRCL_Done"
            st = robot.send(nist_command("EndCanonType", 10), 10)
            assert state(st) == "CRCL_Done" and st.findtext("CommandStatus/CommandID") == "10"
            # GetStatus (written as NIST's client writes it): the status of the last command, now
            st = robot.send(nist_command("GetStatusType", 11, lead="\n    "))
            assert st.findtext("CommandStatus/CommandID") == "10" and state(st) == "CRCL_Done"
            assert point(st) == pytest.approx((x * 1000, y * 1000, z * 1000))
            assert int(st.findtext("CommandStatus/StatusID") or 0) >= 11  # a status per command (and heartbeats)
        finally:
            robot.close()


def test_a_robot_and_a_gripper_client_on_one_port_drive_the_same_robot() -> None:
    x, y, z = GRIPPER_MOUNT
    with sim_serve("--status-period", "0") as (sensor_port, port):
        robot, gripper = SimpleClient(port), SimpleClient(port)
        try:
            assert state(robot.send(nist_command("InitCanonType", 1), 1)) == "CRCL_Done"
            assert state(gripper.send(nist_command("InitCanonType", 1), 1)) == "CRCL_Done"
            assert state(gripper.send(unit(2, "SetLengthUnitsType", "inch"), 2)) == "CRCL_Done"
            for n, zz in ((2, z + 0.2), (3, z)):
                robot.send(nist_move(n, x, y, zz), n)  # metres: the gripper client's inches are its own
            st = robot.send(nist_command("CloseToolChangerType", 4), 4)
            tip = point(st)  # the pose of the gripper now mounted (Reference.md VIII): its length below
            assert state(st) == "CRCL_Done" and tip[:2] == pytest.approx((x, y)) and 0.5 < tip[2] < z
            st = gripper.send(end_effector(3, 0.0), 3)  # the gripper's own stream: its own CommandID
            assert state(st) == "CRCL_Done" and st.findtext("CommandStatus/CommandID") == "3"
            assert st.find("PoseStatus") is None  # a gripper channel's status has no pose (Reference.md VIII)
            assert st.find("GripperStatus/GripperName").text == "part_gripper"  # type: ignore[union-attr]
            st = robot.send(nist_command("GetStatusType", 5))
            assert st.findtext("CommandStatus/CommandID") == "4" and point(st) == pytest.approx(tip)
        finally:
            robot.close()
            gripper.close()
        with RemoteCell("127.0.0.1", sensor_port, port, timeout=10) as remote:  # the same robot, mounted
            assert remote.execute(crcl.OpenToolChanger()).done


# --- the server's side, in process ----------------------------------------------------------------

@contextmanager
def served(cell: SimulatedCell | None = None, period: float = 0.0) -> Iterator[CellServer]:
    with CellServer(cell or SimulatedCell(INIT), sensor_port=0, command_port=0, status_period=period) as server:
        yield server


def statuses(sock: socket.socket, until: Callable[[list[bytes]], bool], seconds: float = 10) -> list[bytes]:
    """Status documents read from ``sock`` until ``until(docs)`` (or the connection closes)."""
    docs, splitter, end = [], Documents(), time.monotonic() + seconds
    while not until([d.data for d in docs]) and time.monotonic() < end:
        ready, _, _ = select.select([sock], [], [], 0.2)
        if ready:
            chunk = sock.recv(4096)
            if not chunk:
                break
            docs += splitter.feed(chunk)
    return [d.data for d in docs]


def test_malformed_documents_get_an_error_status_and_the_connection_keeps_serving() -> None:
    with served() as server, socket.create_connection(("127.0.0.1", server.command_port), timeout=10) as s:
        bad_number = write_command_instance(crcl.Dwell(1.0), 7).replace(b"<DwellTime>1</DwellTime>",
                                                                        b"<DwellTime>soon</DwellTime>")
        unknown = nist_command("FlyType", 8)
        s.sendall(bad_number + b"\n" + unknown + write_command_instance(crcl.Dwell(2.0), 9))
        got = [read_status(d) for d in statuses(s, lambda d: len(d) >= 3)]
        assert [(g.command_id, g.state) for g in got] == [(7, "CRCL_Error"), (8, "CRCL_Error"), (9, "CRCL_Done")]
        assert "DwellTime" in got[0].description and "Fly" in got[1].description
        assert [g.status_id for g in got] == [1, 2, 3]
    assert server.cell.time == 2.0


@pytest.mark.parametrize("data, why", [
    (b"{Line 1} hello\n", "not XML"),  # not kitkb's protocol either: its first byte is '{' ... of a line
    (b"hello there\n", "not XML: a document starts with '<'"),
    (b"<CRCLProgramm><InitCanon/></CRCLProgramm>", "a <CRCLProgramm> document is not a CRCL command"),
    (b'<!DOCTYPE x [<!ENTITY a "b">]><CRCLCommandInstance/>', "DOCTYPE is not allowed"),
    (b"<CRCLCommandInstance><CRCLCommand></Oops>", "mismatched tag"),
])
def test_garbage_or_a_document_that_is_not_crcl_closes_that_connection_with_an_error_status(
        data: bytes, why: str) -> None:
    with served() as server:
        with socket.create_connection(("127.0.0.1", server.command_port), timeout=10) as s:
            s.sendall(write_command_instance(crcl.Dwell(1.0), 1) + data)
            if data.startswith(b"{"):
                answer = b"".join(iter(lambda: s.recv(4096), b""))  # kitkb's protocol's error line
                assert answer.startswith(b"{Status error}") or b"CRCL_Error" in answer
                return
            docs = statuses(s, lambda d: False, seconds=10)
        last = read_status(docs[-1])
        assert read_status(docs[0]).state == "CRCL_Done" and last.state == "CRCL_Error"
        assert why in last.description and "the connection is closed" in last.description
        with RemoteCell("127.0.0.1", server.sensor_port, server.command_port, timeout=10) as remote:
            assert remote.execute(crcl.Dwell(1.0)).done  # the server keeps serving


def test_a_status_with_a_pose_and_a_gripper_fits_one_recv_of_1024_bytes() -> None:
    with served() as server, RemoteCell("127.0.0.1", server.sensor_port, server.command_port, timeout=10) as remote:
        x, y, z = GRIPPER_MOUNT
        remote.execute_program([crcl.MoveTo(crcl.Pose((x + 0.123456789, y - 0.987654321, z + 0.2), (1, 0, 0),
                                                      (0, 0, -1))),
                                crcl.MoveTo(crcl.Pose((x, y, z), (1, 0, 0), (0, 0, -1))), crcl.CloseToolChanger(),
                                crcl.Message("x" * 5000)])
        last = remote.crcl.last
        assert last is not None and last.gripper is not None and last.pose is not None
        with socket.create_connection(("127.0.0.1", server.command_port), timeout=10) as s:
            s.sendall(nist_command("X" * 3000 + "Type", 1))  # an error naming a long command type
            [doc] = statuses(s, lambda d: len(d) >= 1)
        assert len(doc) < 1024 and b"<PoseStatus>" in doc and b"<GripperStatus" in doc
        assert read_status(doc).state == "CRCL_Error" and read_status(doc).description.endswith("...")


def test_a_long_description_of_escaped_and_multibyte_text_is_cut_to_fit_1024_bytes() -> None:
    cell = SimulatedCell(INIT)
    cell.execute = lambda c: Status.error("<&é>" * 400)  # type: ignore[method-assign]
    with served(cell) as server, socket.create_connection(("127.0.0.1", server.command_port), timeout=10) as s:
        s.sendall(write_command_instance(crcl.Dwell(1.0), 1))
        [doc] = statuses(s, lambda d: len(d) >= 1)
    status = read_status(doc)
    assert len(doc) < 1024 and status.state == "CRCL_Error" and status.description.startswith("<&é>")
    assert status.description.endswith("...") and len(doc) > 900


def test_a_quiet_connection_gets_a_heartbeat_status_and_a_client_that_never_reads_blocks_nothing() -> None:
    with served(period=0.2) as server:
        with socket.create_connection(("127.0.0.1", server.command_port), timeout=10) as s:
            s.sendall(write_command_instance(crcl.Dwell(1.0), 4))
            docs = statuses(s, lambda d: len(d) >= 3, seconds=5)
            got = [read_status(d) for d in docs]
            assert [(g.command_id, g.state) for g in got] == [(4, "CRCL_Done")] * 3
            assert [g.status_id for g in got] == [1, 2, 3]
            mute = socket.create_connection(("127.0.0.1", server.command_port), timeout=10)
            mute.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)
            mute.sendall(write_command_instance(crcl.InitCanon(), 1))
            time.sleep(1.0)  # it never reads: heartbeats pile up in its buffers, then stop
            s.sendall(write_command_instance(crcl.Dwell(1.0), 5))
            assert (5, "CRCL_Done") in [(g.command_id, g.state) for g in map(read_status, statuses(
                s, lambda d: any(b"<CommandID>5<" in x for x in d), seconds=5))]
            mute.close()


def test_each_connection_keeps_its_own_units() -> None:
    cell = SimulatedCell(INIT)
    with served(cell) as server, socket.create_connection(("127.0.0.1", server.command_port), timeout=10) as mm:
        mm.sendall(write_command_instance(crcl.SetLengthUnits("millimeter"), 1))
        assert read_status(statuses(mm, lambda d: len(d) >= 1)[0]).state == "CRCL_Done"
        with RemoteCell("127.0.0.1", server.sensor_port, server.command_port, timeout=10) as remote:
            assert remote.execute(crcl.MoveTo(crcl.Pose((1.4, 0.1, 1.2), (1, 0, 0), (0, 0, -1)))).done
            assert remote.crcl.last is not None and remote.crcl.last.pose.point == pytest.approx((1.4, 0.1, 1.2))
        mm.sendall(write_command_instance(crcl.GetStatus(), 2))
        pose = read_status(statuses(mm, lambda d: len(d) >= 1)[0]).pose
        assert pose is not None and pose.point == pytest.approx((1400, 100, 1200))  # in its millimetres


def test_a_program_instance_on_the_wire_runs_command_by_command() -> None:
    with served() as server, socket.create_connection(("127.0.0.1", server.command_port), timeout=10) as s:
        s.sendall((INSTANCES / "programExample.xml").read_bytes() if INSTANCES.is_dir() else
                  b"<CRCLProgram><InitCanon><CommandID>1</CommandID></InitCanon>"
                  b"<EndCanon><CommandID>2</CommandID></EndCanon></CRCLProgram>")
        docs = statuses(s, lambda d: any(b"EndCanon" in x or b"<CommandState>CRCL_Error" in x for x in d)
                        or len(d) >= 41, seconds=10)
        got = [read_status(d) for d in docs]
        assert all(g.state == "CRCL_Done" for g in got) and len(got) >= 2
        assert [g.command_id for g in got] == sorted(g.command_id for g in got)


# --- RemoteCell over CRCL 1.x ---------------------------------------------------------------------

def test_remote_cell_starts_each_session_with_its_units_and_sends_exactly_the_commands() -> None:
    cell = SimulatedCell(INIT)
    executed: list[crcl.Command] = []
    execute = cell.execute
    cell.execute = lambda c: executed.append(c) or execute(c)  # type: ignore[method-assign]
    with served(cell) as server, RemoteCell("127.0.0.1", server.sensor_port, server.command_port,
                                            timeout=10) as remote:
        assert remote.execute_program([crcl.Dwell(1), crcl.Dwell(2)]) == [Status.ok()] * 2
        assert executed == [crcl.InitCanon(), crcl.SetLengthUnits("meter"), crcl.SetAngleUnits("radian"),
                            crcl.Dwell(1), crcl.Dwell(2)]
        statuses_ = remote.execute_program([crcl.Dwell(1), crcl.SetCoordinateFrame("Workstation"), crcl.Dwell(1)])
        assert statuses_[0].done and statuses_[2] == Status.error(NOT_EXECUTED)
        assert "not sent" in statuses_[1].message
        bad = remote.execute_program([crcl.Dwell(-1), crcl.Dwell(1)])
        assert bad[0].state == "error" and "negative dwell" in bad[0].message and bad[1] == Status.error(NOT_EXECUTED)
        remote.crcl.close()  # a new connection: a new session
        remote.execute(crcl.Dwell(1))
        assert executed[-4:] == [crcl.InitCanon(), crcl.SetLengthUnits("meter"), crcl.SetAngleUnits("radian"),
                                 crcl.Dwell(1)]


# --- kitkb crcl send against controllers kitkb did not write ---------------------------------------

class Controller:
    """A CRCL 1.x controller on a free loopback port (a thread): splits the command stream at
    each ``</CRCLCommandInstance>`` and parses it with ElementTree; ``answer(root, n, sock)``
    handles the n-th command. The default answers CRCL_Done with a pose."""

    def __init__(self, answer: Callable[[ET.Element, int, socket.socket], None] | None = None) -> None:
        self.answer = answer or done
        self.listener = socket.create_server(("127.0.0.1", 0))
        self.port = int(self.listener.getsockname()[1])
        self.received: list[ET.Element] = []
        self.thread = threading.Thread(target=self._serve, daemon=True)
        self.thread.start()

    def _serve(self) -> None:
        self.listener.settimeout(20)
        try:
            conn, _ = self.listener.accept()
        except OSError:
            return
        with conn:
            data = b""
            try:
                while chunk := conn.recv(4096):
                    data += chunk
                    while b"</CRCLCommandInstance>" in data:
                        doc, _, data = data.partition(b"</CRCLCommandInstance>")
                        root = ET.fromstring(doc.strip() + b"</CRCLCommandInstance>")
                        self.received.append(root)
                        self.answer(root, len(self.received), conn)
            except OSError:
                pass

    def close(self) -> None:
        self.listener.close()
        self.thread.join(timeout=20)


def status_doc(command_id: int, status_id: int, state_: str, description: str = "") -> bytes:
    text = f"<StateDescription>{description}</StateDescription>" if description else ""
    return (f'<?xml version="1.0" encoding="UTF-8"?>\n<CRCLStatus><CommandStatus><CommandID>{command_id}</CommandID>'
            f"<StatusID>{status_id}</StatusID><CommandState>{state_}</CommandState>{text}</CommandStatus>"
            "<PoseStatus><Pose><Point><X>1.5</X><Y>1</Y><Z>1</Z></Point><XAxis><I>1</I><J>0</J><K>0</K></XAxis>"
            "<ZAxis><I>0</I><J>0</J><K>-1</K></ZAxis></Pose></PoseStatus></CRCLStatus>\n").encode()


def command_id(root: ET.Element) -> int:
    return int(root.findtext("CRCLCommand/CommandID") or 0)


def kind(root: ET.Element) -> str:
    return root.find("CRCLCommand").get("{http://www.w3.org/2001/XMLSchema-instance}type", "")  # type: ignore


def done(root: ET.Element, n: int, conn: socket.socket) -> None:
    """Working, then Done, as a controller that takes its time."""
    if kind(root) == "GetStatusType":
        conn.sendall(status_doc(command_id(root) - 1, 2 * n, "CRCL_Done"))
        return
    conn.sendall(status_doc(command_id(root), 2 * n - 1, "CRCL_Working"))
    conn.sendall(status_doc(command_id(root), 2 * n, "CRCL_Done"))


def send(file: Path | str, port: int, *extra: str) -> tuple[int, str, str]:
    """``kitkb crcl send`` in process: exit code, standard output, standard error."""
    import contextlib
    import io
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(["crcl", "send", str(file), "--to", f"127.0.0.1:{port}", *extra])
    return code, out.getvalue(), err.getvalue()


#: NIST's example commands and programs (../shared/crcl/instances: 11 command instances, 4 programs,
#: 7 force-sensor programs; the rest are statuses).
SENDABLE = sorted(p.name for p in INSTANCES.glob("*.xml")
                  if ET.parse(p).getroot().tag in ("CRCLCommandInstance", "CRCLProgram")) if INSTANCES.is_dir() else []


@needs_crcl
def test_the_examples_are_all_there() -> None:
    assert len(SENDABLE) == 22


@needs_crcl
@pytest.mark.parametrize("name", SENDABLE)
def test_crcl_send_runs_nists_examples_on_a_controller(name: str) -> None:
    source = ET.parse(INSTANCES / name).getroot()
    expected = 1 if source.tag == "CRCLCommandInstance" else len([el for el in source if el.tag != "Name"])
    controller = Controller()
    try:
        code, out, err = send(INSTANCES / name, controller.port, "--format", "json", "--timeout", "5")
    finally:
        controller.close()
    assert code == 0, err
    report = json.loads(out)
    # each command as it is written in the file, as its own CRCLCommandInstance with a CommandID of
    # the session (1, 2, ...; a GetStatus the client sends when the controller is slow takes one too)
    sent = [r for r in controller.received if command_id(r) in {c["id"] for c in report["commands"]}]
    assert report["all_done"] and report["sent"] == expected == len(sent)
    ids = [c["id"] for c in report["commands"]]
    assert ids[0] == 1 and ids == sorted(set(ids)) and [command_id(r) for r in sent] == ids
    assert report["last_status"]["pose"]["point"] == [1.5, 1.0, 1.0]
    names = [kind(r) for r in sent]
    assert [n[:-4] for n in names] == [c["command"] for c in report["commands"]]
    schema = etree.XMLSchema(etree.parse(str(CRCL_DIR / "schemas" / "CRCLCommandInstance.xsd")))
    for root in controller.received:  # as sent, each a valid command instance
        assert schema.validate(etree.fromstring(ET.tostring(root))), schema.error_log
    if source.tag == "CRCLProgram":
        assert names[0] == "InitCanonType" and names[-1] == "EndCanonType"


@needs_crcl
def test_every_document_crcl_send_writes_validates_against_the_schema(tmp_path: Path) -> None:
    schema = etree.XMLSchema(etree.parse(str(CRCL_DIR / "schemas" / "CRCLCommandInstance.xsd")))
    controller = Controller()
    try:
        code, _, err = send(REPO.parent / "shared" / "nist" / "commands1.xml", controller.port)
    finally:
        controller.close()
    assert code == 0, err
    for root in controller.received:
        assert schema.validate(etree.fromstring(ET.tostring(root))), schema.error_log
    # a 2014 program is in millimetres and degrees (the first paper's) where it does not say: its
    # angle unit is said right after InitCanon (its own SetLengthUnits meter follows)
    mine = [r for r in controller.received if kind(r) != "GetStatusType"]
    assert [kind(r) for r in mine[:3]] == ["InitCanonType", "SetAngleUnitsType", "SetLengthUnitsType"]
    assert mine[1].findtext("CRCLCommand/UnitName") == "degree"


def test_a_controller_that_never_acknowledges_initcanon_is_named_within_the_timeout(tmp_path: Path) -> None:
    def mute_on_init(root: ET.Element, n: int, conn: socket.socket) -> None:
        if kind(root) != "InitCanonType" and kind(root) != "GetStatusType":
            done(root, n, conn)
        elif kind(root) == "GetStatusType":
            conn.sendall(status_doc(0, n, "CRCL_Ready"))
    program = tmp_path / "p.xml"
    program.write_bytes(crcl.instance.write_program_instance([crcl.InitCanon(), crcl.Dwell(1), crcl.EndCanon()]))
    controller = Controller(mute_on_init)
    start = time.monotonic()
    try:
        code, _, err = send(program, controller.port, "--timeout", "1.5")
    finally:
        controller.close()
    assert code == 1 and time.monotonic() - start < 1.5 + 3
    assert ": InitCanon command 1 was not acknowledged Done or Error within 1.5 s; last heard: CommandID 0 " \
           "CRCL_Ready" in err and "never acknowledges InitCanon" in err
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err


def test_a_controller_that_answers_only_on_getstatus(tmp_path: Path) -> None:
    finished: list[int] = []

    def lazy(root: ET.Element, n: int, conn: socket.socket) -> None:
        if kind(root) == "GetStatusType":
            conn.sendall(status_doc(finished[-1], n, "CRCL_Done"))
        else:
            finished.append(command_id(root))
    program = tmp_path / "p.xml"
    program.write_bytes(crcl.instance.write_program_instance([crcl.InitCanon(), crcl.Dwell(1), crcl.EndCanon()]))
    controller = Controller(lazy)
    try:
        code, out, err = send(program, controller.port, "--format", "json", "--timeout", "5")
    finally:
        controller.close()
    assert code == 0, err
    assert [c["command"] for c in json.loads(out)["commands"]] == ["InitCanon", "Dwell", "EndCanon"]
    assert any(kind(r) == "GetStatusType" for r in controller.received)


def test_an_error_status_is_exit_1_naming_the_command(tmp_path: Path) -> None:
    def refuse_moves(root: ET.Element, n: int, conn: socket.socket) -> None:
        if kind(root) == "MoveToType":
            conn.sendall(status_doc(command_id(root), n, "CRCL_Error", "joint 3 at its limit"))
        else:
            done(root, n, conn)
    program = tmp_path / "p.crcl"
    program.write_text("InitCanon()\nMoveTo({{1, 2, 3}, {0, 0, -1}, {1, 0, 0}})\nDwell(1)\nEndCanon(0)\n")
    controller = Controller(refuse_moves)
    try:
        code, out, err = send(program, controller.port, "--format", "json")
    finally:
        controller.close()
    assert code == 1
    assert re.search(r"command \d+ \(MoveTo\) ended in CRCL_Error: joint 3 at its limit$", err.strip())
    report = json.loads(out)
    assert [(c["command"], c["state"]) for c in report["commands"]] == [
        ("InitCanon", "CRCL_Done"), ("SetLengthUnits", "CRCL_Done"), ("SetAngleUnits", "CRCL_Done"),
        ("MoveTo", "CRCL_Error")]
    [moved] = [r for r in controller.received if kind(r) == "MoveToType"]
    move = ET.tostring(moved.find("CRCLCommand/EndPosition/Point"))  # type: ignore[arg-type]
    assert b"<X>1</X>" in move  # in the text form's millimetres, said by SetLengthUnits


@pytest.mark.parametrize("behave, why", [
    (lambda root, n, conn: conn.sendall(b"{Line 1} {Status done}\n"), "broke the protocol: not XML"),
    (lambda root, n, conn: conn.sendall(b"<CRCLCommandInstance/>"), "a <CRCLCommandInstance> document, not a "
                                                                    "CRCLStatus"),
    (lambda root, n, conn: conn.sendall(b"<CRCLStatus><Oops/></CRCLStatus>"), "broke the protocol"),
    (lambda root, n, conn: conn.close(), "closed the connection"),
])
def test_a_controller_that_breaks_the_protocol_or_closes_is_exit_2(
        behave: Callable[[ET.Element, int, socket.socket], None], why: str, tmp_path: Path) -> None:
    program = tmp_path / "p.xml"
    program.write_bytes(write_command_instance(crcl.Dwell(1.0), 1))
    controller = Controller(behave)
    try:
        code, _, err = send(program, controller.port, "--timeout", "5")
    finally:
        controller.close()
    assert code == 2 and why in err and f"127.0.0.1:{controller.port}: error: " in err
    assert len(err.strip().splitlines()) == 1


def test_crcl_send_bad_input_and_an_unreachable_controller_are_exit_2(tmp_path: Path) -> None:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        free = int(s.getsockname()[1])
    program = tmp_path / "p.xml"
    program.write_bytes(write_command_instance(crcl.Dwell(1.0), 1))
    code, _, err = send(program, free)
    assert code == 2 and "cannot reach the controller" in err
    assert main(["crcl", "send", str(program), "--to", "nowhere"]) == 2
    assert main(["crcl", "send", str(program), "--to", f"127.0.0.1:{free}", "--timeout", "0"]) == 2
    broken = tmp_path / "b.xml"
    broken.write_text("<CRCLCommandInstance><CRCLCommand>")
    assert send(broken, free)[0] == 2
    assert main(["sim", "serve", str(INIT), "--status-period", "-1"]) == 2
    paper = tmp_path / "end.crcl"
    paper.write_text("InitCanon()\nEndCanon(2)\n")
    code, _, err = send(paper, free)
    assert code == 2 and f"{paper}:2: error:" in err


# --- the splitter --------------------------------------------------------------------------------

def test_the_stream_is_split_at_each_root_elements_end_however_it_arrives() -> None:
    one = write_command_instance(crcl.Dwell(1.5), 1)
    stream = b"\n  " + one + b"\r\n" + one.replace(b"\n", b"") + b'<a x="/>">t</a>' + b"<b/>   " + one
    for step in (1, 3, 64, len(stream)):
        splitter, docs = Documents(), []
        for i in range(0, len(stream), step):
            docs += splitter.feed(stream[i:i + step])
        assert [d.root for d in docs] == ["CRCLCommandInstance", "CRCLCommandInstance", "a", "b",
                                          "CRCLCommandInstance"]
        assert docs[0].data == one and docs[2].data == b'<a x="/>">t</a>' and splitter.pending == 0
    with pytest.raises(DocumentError, match="longer than 100 bytes"):
        Documents(max_bytes=100).feed(b"<a>" + b"x" * 200)
    with pytest.raises(DocumentError, match="nested deeper than 3"):
        Documents(max_depth=3).feed(b"<a><b><c><d>")
    with pytest.raises(DocumentError) as info:
        Documents().feed(one + b" junk")
    assert len(info.value.documents) == 1 and "not XML" in str(info.value)


# --- what kitkb run sends through a cell server ------------------------------------------------------

@needs_crcl
def test_every_command_kitkb_run_sends_through_a_cell_server_validates(monkeypatch: pytest.MonkeyPatch,
                                                                     tmp_path: Path) -> None:
    import kb.sim.server as server_module
    received: list[bytes] = []
    read = server_module._commands
    monkeypatch.setattr(server_module, "_commands", lambda doc: received.append(doc.data) or read(doc))
    schema = etree.XMLSchema(etree.parse(str(CRCL_DIR / "schemas" / "CRCLCommandInstance.xsd")))
    cell = SimulatedCell(str(INIT), declared=[str(GOAL)])
    with CellServer(cell, sensor_port=0, command_port=0) as server:
        code = main(["run", str(INIT), str(GOAL), "--cell", f"127.0.0.1:{server.sensor_port},{server.command_port}",
                     "-o", str(tmp_path), "--quiet", "--faults", "missed-grasp@6", "--seed", "1"])
    assert code == 0
    assert len(received) > 50
    kinds = set()
    for data in received:
        doc = etree.fromstring(data)
        assert schema.validate(doc), (schema.error_log, data[:300])
        kinds.add(doc[0].get("{http://www.w3.org/2001/XMLSchema-instance}type"))
    assert {"InitCanonType", "SetLengthUnitsType", "SetAngleUnitsType", "MoveToType", "MessageType",
            "EndCanonType", "SetEndEffectorType"} <= kinds


def test_a_remote_cell_refuses_a_peer_that_never_starts_a_session() -> None:
    controller = Controller(lambda root, n, conn: conn.sendall(status_doc(command_id(root), n, "CRCL_Error",
                                                                          "not ready")))
    try:
        with RemoteCell("127.0.0.1", controller.port, controller.port, timeout=5) as remote:
            with pytest.raises(CellError, match="did not start a CRCL session: InitCanon .* CRCL_Error: not ready"):
                remote.execute(crcl.Dwell(1))
    finally:
        controller.close()


@needs_crcl
def test_every_status_the_server_writes_validates_against_crcl_status_xsd() -> None:
    schema = etree.XMLSchema(etree.parse(str(CRCL_DIR / "schemas" / "CRCLStatus.xsd")))
    x, y, z = GRIPPER_MOUNT
    commands = [crcl.GetStatus(), crcl.InitCanon(), crcl.SetLengthUnits("inch"), crcl.SetLengthUnits("meter"),
                crcl.MoveTo(crcl.Pose((x, y, z + 0.2), (1, 0, 0), (0, 0, -1))),
                crcl.MoveTo(crcl.Pose((x, y, z), (1, 0, 0), (0, 0, -1))), crcl.CloseToolChanger(),
                crcl.CloseGripper(), crcl.OpenGripper(), crcl.Dwell(-1), crcl.Message("a <b> & 'c'"), crcl.EndCanon(),
                crcl.ConfigureStatusReport(True, True, True, True, True, True), crcl.SetLengthUnits("inch")]
    with served(period=0.1) as server, socket.create_connection(("127.0.0.1", server.command_port), timeout=10) as s:
        for i, command in enumerate(commands, 1):
            s.sendall(write_command_instance(command, i))
        s.sendall(nist_command("NoSuchType", 99))
        docs = statuses(s, lambda d: sum(b"<CommandID>99<" in x for x in d) >= 1, seconds=10)
        time.sleep(0.3)
        docs += statuses(s, lambda d: len(d) >= 1, seconds=2)  # a heartbeat
    assert len(docs) >= len(commands) + 2
    for doc in docs:
        assert schema.validate(etree.fromstring(doc)), (schema.error_log, doc)
    states = [read_status(d) for d in docs]
    assert (states[0].command_id, states[0].state) == (0, "CRCL_Ready")  # GetStatus before any command
    assert any(st.state == "CRCL_Error" and st.command_id == 10 for st in states)  # the negative Dwell
    inch = next(st for st in states if st.command_id == 14)  # after ConfigureStatusReport: settings too
    assert inch.settings == instance.SettingsStatus("inch", "radian", 1.0, pytest.approx(1 / 0.0254))


# --- the housekeeping commands NIST's clients send (ConfigureStatusReport, grippers, sensors ...) -----

def report_config(command_id: int, joints: bool, pose: bool, gripper: bool, rest: bool = False) -> bytes:
    flags = {"ReportJointStatuses": joints, "ReportPoseStatus": pose, "ReportGripperStatus": gripper,
             "ReportSettingsStatus": rest, "ReportSensorsStatus": rest, "ReportGuardsStatus": rest}
    return nist_command("ConfigureStatusReportType", command_id,
                        "".join(f"    <{k}>{str(v).lower()}</{k}>\n" for k, v in flags.items()))


def gripper_switch(command_id: int, enable: bool, name: str, options: str = "") -> bytes:
    return nist_command("EnableGripperType" if enable else "DisableGripperType", command_id,
                        f"    <GripperName>{name}</GripperName>\n{options}")


def describe(st: ET.Element) -> str:
    return st.findtext("CommandStatus/StateDescription") or ""


def test_a_nist_style_client_configures_the_status_report_first_then_moves() -> None:
    x, y, z = GRIPPER_MOUNT
    with sim_serve("--status-period", "0") as (_, port):
        client = SimpleClient(port)
        try:
            # right after connecting, as crcl4java's clients do: everything asked for
            st = client.send(report_config(1, True, True, True, rest=True), 1)
            assert state(st) == "CRCL_Done" and st.findtext("CommandStatus/CommandID") == "1"
            assert "no joint statuses: the simulated robot has no joint model" in describe(st)
            assert "no sensors or guards" in describe(st) and st.find("JointStatuses") is None
            st = client.send(nist_command("InitCanonType", 2), 2)
            assert state(st) == "CRCL_Done" and st.findtext("SettingsStatus/LengthUnitName") == "meter"
            assert st.findtext("SettingsStatus/AngleUnitName") == "radian"
            assert float(st.findtext("SettingsStatus/TransSpeedAbsolute/Setting") or "nan") > 0
            for n, zz in ((3, z + 0.2), (4, z)):
                st = client.send(nist_move(n, x, y, zz), n)
                assert state(st) == "CRCL_Done" and point(st) == pytest.approx((x, y, zz))
            st = client.send(nist_command("CloseToolChangerType", 5), 5)
            assert st.findtext("GripperStatus/GripperName") == "part_gripper"
            assert st.findtext("SettingsStatus/EndEffectorSetting") == "1"  # the jaws open
            # the pose only: no gripper status (nor settings) from now on, on this connection
            st = client.send(report_config(6, False, True, False), 6)
            assert state(st) == "CRCL_Done" and st.find("GripperStatus") is None and st.find("PoseStatus") is not None
            assert st.find("SettingsStatus") is None
            st = client.send(end_effector(7, 0.0), 7)
            assert state(st) == "CRCL_Done" and st.find("GripperStatus") is None
            other = SimpleClient(port)  # another connection keeps the default: pose and gripper
            try:
                st = other.send(nist_command("GetStatusType", 1))
                assert st.find("PoseStatus") is not None and st.find("GripperStatus") is not None
            finally:
                other.close()
            # neither: the command's state alone
            st = client.send(report_config(8, False, False, False), 8)
            assert st.find("PoseStatus") is None and st.find("GripperStatus") is None
            assert state(client.send(end_effector(9, 1.0), 9)) == "CRCL_Done"
            st = client.send(nist_command("GetStatusType", 10))
            assert st.findtext("CommandStatus/CommandID") == "9" and st.find("PoseStatus") is None
            assert state(client.send(nist_command("EndCanonType", 11), 11)) == "CRCL_Done"
        finally:
            client.close()


def mounted(server: CellServer, s: socket.socket) -> None:
    """The part gripper mounted on the server's robot (over ``s``, CommandIDs 1 to 3)."""
    x, y, z = GRIPPER_MOUNT
    s.sendall(nist_move(1, x, y, z + 0.2) + nist_move(2, x, y, z) + nist_command("CloseToolChangerType", 3))
    got = [read_status(d) for d in statuses(s, lambda d: len(d) >= 3)]
    assert [g.state for g in got] == ["CRCL_Done"] * 3 and got[-1].gripper is not None


def answers(s: socket.socket, *docs: bytes) -> list[tuple[int, str, str]]:
    """(CommandID, state, description) of the status of each document sent."""
    s.sendall(b"".join(docs))
    return [(g.command_id, g.state, g.description)
            for g in map(read_status, statuses(s, lambda d: len(d) >= len(docs)))]


def test_enable_and_disable_gripper_by_its_name() -> None:
    with served() as server, socket.create_connection(("127.0.0.1", server.command_port), timeout=10) as s:
        got = answers(s, gripper_switch(1, True, "part_gripper"))
        assert got[0][:2] == (1, "CRCL_Error") and "no gripper is mounted" in got[0][2]
        mounted(server, s)
        option = ("    <GripperOption><ParameterName>force</ParameterName>"
                  "<ParameterValue>20</ParameterValue></GripperOption>\n")
        got = answers(s, gripper_switch(4, True, "part_gripper", option), gripper_switch(5, False, "jaws"),
                      gripper_switch(6, False, "part_gripper"), end_effector(7, 0.0),
                      nist_command("SetEndEffectorType", 8, "    <Setting>0.5</Setting>\n"))
        assert [g[:2] for g in got] == [(4, "CRCL_Done"), (5, "CRCL_Error"), (6, "CRCL_Done"), (7, "CRCL_Error"),
                                        (8, "CRCL_Error")]
        assert "no gripper jaws on this controller (the mounted gripper is part_gripper)" in got[1][2]
        assert "gripper part_gripper is disabled (DisableGripper): EnableGripper part_gripper first" in got[3][2]
        jaws = server.jaws_open  # open still: the refused SetEndEffectors did not close them
        got = answers(s, gripper_switch(9, True, "part_gripper"), end_effector(10, 0.0))
        assert [g[:2] for g in got] == [(9, "CRCL_Done"), (10, "CRCL_Done")] and jaws and not server.jaws_open
    # the in-process cell answers the same: the controller is the robot's
    cell = SimulatedCell(INIT)
    cell.robot.effector = cell.world.index[next(n for n in cell.world.names if n.endswith("part_gripper"))]
    assert cell.execute(crcl.DisableGripper("part_gripper")).done
    assert not cell.execute(crcl.OpenGripper()).done and not cell.execute(crcl.CloseGripper()).done
    assert cell.execute(crcl.EnableGripper(cell.world.names[cell.robot.effector])).done  # its IRI names it too
    assert cell.execute(crcl.OpenGripper()).done


def test_sensors_joint_tolerances_screws_and_loops_are_errors_with_the_reason_and_the_command_id() -> None:
    param = ("    <RobotParameterName>speedOverride</RobotParameterName>\n")
    with served() as server, socket.create_connection(("127.0.0.1", server.command_port), timeout=10) as s:
        got = answers(
            s, nist_command("EnableRobotParameterStatusType", 3, param),
            nist_command("DisableRobotParameterStatusType", 4, param),
            nist_command("EnableSensorType", 5, "    <SensorID>ATINetFT</SensorID>\n    <SensorOption>"
                         "<ParameterName>host</ParameterName><ParameterValue>192.168.1.1</ParameterValue>"
                         "</SensorOption>\n"),
            nist_command("DisableSensorType", 6, "    <SensorID>ATINetFT</SensorID>\n"),
            nist_command("SetDefaultJointPositonsTolerancesType", 7, "    <JointTolerances><Setting><JointNumber>1"
                         "</JointNumber><JointPositionTolerance>0.1</JointPositionTolerance></Setting>"
                         "</JointTolerances>\n"),
            nist_command("MoveScrewType", 8, "    <AxialDistanceScrew>0.01</AxialDistanceScrew><Turn>6.28</Turn>\n"),
            nist_command("LoopBlockStartType", 9, "    <LoopName>twice</LoopName>\n"),
            nist_command("LoopBlockEndType", 10, "    <LoopName>twice</LoopName><MaxCount>2</MaxCount>\n"))
    assert [g[:2] for g in got] == [(3, "CRCL_Done"), (4, "CRCL_Done")] + [
        (n, "CRCL_Error") for n in range(5, 11)]
    assert "recorded" in got[0][2] and "nothing is reported" in got[0][2]
    assert "no sensor ATINetFT on this controller" in got[2][2] and "no sensor ATINetFT" in got[3][2]
    assert "no joint model" in got[4][2] and "does not screw" in got[5][2]
    assert all("executes no loops" in g[2] for g in got[6:])
    assert server.cell.robot.parameter_status == set()  # enabled, then disabled


def test_a_guarded_command_or_one_refused_when_read_is_answered_with_its_own_command_id() -> None:
    guard = ("    <Guard><SensorID>ATINetFT</SensorID><LimitType>OVER_MAX</LimitType>"
             "<LimitValue>10</LimitValue></Guard>\n")
    moved = nist_move(7, *GRIPPER_MOUNT).replace(b"<CommandID>7</CommandID>\n", b"<CommandID>7</CommandID>\n"
                                                 + guard.encode())
    program = (b'<CRCLProgram xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance">\n'
               b"<InitCanon><CommandID>1</CommandID></InitCanon>\n"
               b'<MiddleCommand xsi:type="DwellType">\n<CommandID>2</CommandID><DwellTime>1</DwellTime>'
               b"</MiddleCommand>\n"
               b'<MiddleCommand xsi:type="StopMotionType">\n<CommandID>3</CommandID>\n'
               b"<StopCondition>Fast</StopCondition></MiddleCommand>\n"
               b"<EndCanon><CommandID>4</CommandID></EndCanon></CRCLProgram>")
    with served() as server, socket.create_connection(("127.0.0.1", server.command_port), timeout=10) as s:
        start = server.cell.robot.tip().copy()
        got = answers(s, moved, program)
        assert (server.cell.robot.tip() == start).all()  # the guarded move was not made unguarded
    assert [g[:2] for g in got] == [(7, "CRCL_Error"), (3, "CRCL_Error")]
    assert "MoveStraightTo guarded by ATINetFT: no sensor ATINetFT on this controller" in got[0][2]
    assert "StopMotion Fast" in got[1][2]
    assert server.cell.time == 0.0  # nothing of the program ran


#: What each of NIST's example commands and programs does through ``kitkb crcl send`` against
#: ``kitkb sim serve`` small-kit, sent in name order to one server: exit 0 (all done), or exit 1
#: and the command (sent CommandID, type) that ended in CRCL_Error. Never exit 2: each is valid CRCL 1.x.
THROUGH_SIM = {
    **{name: 0 for name in SENDABLE if name.startswith("command") or name.startswith("programExample")},
    "programAll.xml": (2, "ActuateJoints"), "programAllWithNames.xml": (2, "ActuateJoints"),
    **{f"testForceSensorProgram{n}.xml": (4, "EnableSensor") for n in ("", 2, 3, 4)},
    **{f"testForceSensorProgram{n}.xml": (5, "EnableSensor") for n in (5, 6)},
    "testForceSensorProgram7.xml": (7, "EnableSensor"),
}


@needs_crcl
def test_every_example_through_crcl_send_against_kitkb_sim_serve_completes_or_stops_at_a_named_error() -> None:
    assert sorted(THROUGH_SIM) == SENDABLE and len(SENDABLE) == 22
    outcomes = {}
    with sim_serve("--status-period", "0") as (_, port):
        for name in SENDABLE:
            code, out, err = send(INSTANCES / name, port, "--format", "json", "--timeout", "10")
            assert code in (0, 1), (name, err)
            report = json.loads(out)
            rows = report["commands"]
            if code == 0:
                outcomes[name] = 0
                assert report["all_done"] and all(r["state"] == "CRCL_Done" for r in rows), name
            else:
                last = rows[-1]
                outcomes[name] = (last["id"], last["command"])
                assert last["state"] == "CRCL_Error" and last["command"] in err, (name, err)
    assert outcomes == THROUGH_SIM
