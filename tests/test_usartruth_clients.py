"""The sensor port answers USARTruth clients as USARSim's USARTruth did (issue 26, point 9).

Two fake clients behave like the C++ clients of usnistgov/el-robotics-core, written anew in
Python from what those clients send and accept:

* GTRI's ``USARTruth::getTruth(class, name)``: sends ``{class C} {name N}`` and CR LF on one
  line (both keys always, values possibly empty), reads the socket until a chunk holds a line
  end, parses the first line only: ``{End}`` first is no answer, any key other than Name,
  Class, Time, Location, Rotation (and Bone) makes the answer invalid. It turns USARSim's
  Location into its own frame as ``(x, -y, -z)``.
* NIST's ``UsarTruth::getData(class, name)``: sends ``{class C}{name N}`` and CR LF (a key only
  when its value is not empty; ``{class Engine.Actor}`` when both are), reads lines up to
  ``{End}``; a line past 2,048 bytes is an overrun; an unknown key is skipped, so an
  ``{Error ...}`` line would become an object with no name.
"""

from __future__ import annotations

import os
import re
import select
import socket
import subprocess
import sys
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Iterator

import pytest

from kb.core.resources import ontology_path
from kb.crcl import RemoteCell
from kb.crcl.wire import END, Query, parse_query, query_line
from kb.sim import CellServer, FaultSpec, SimulatedCell
from kb.sim.sensor import truth_class

INIT = ontology_path("scenarios/small-kit/init.ttl")
NS = "https://w3id.org/kitkb/scenario/small-kit#"
KTW = "https://w3id.org/kitkb/kitting#"
REPO = Path(__file__).resolve().parents[1]
USARTRUTH_KEYS = ("Name", "Class", "Time", "Location", "Rotation")


# --- the clients' parsing: getKey / getValue / getDouble / getVector of el-robotics-core -----

def get_key(msg: str, pos: int) -> tuple[str, int] | None:
    """The key after the next ``{`` (up to white space); None where the C code returns the
    pointer it was given (no ``{``, or a delimiter inside the key)."""
    at = msg.find("{", pos)
    if at < 0:
        return None
    at += 1
    while at < len(msg) and msg[at].isspace():
        at += 1
    start = at
    while True:
        if at >= len(msg) or msg[at] in ",{}":
            return None
        if msg[at].isspace():
            return msg[start:at], at
        at += 1


def get_value(msg: str, pos: int) -> tuple[str, int] | None:
    """A value: delimiters (white space, commas) skipped, then up to white space, ``,`` or ``}``."""
    at = pos
    while at < len(msg) and (msg[at].isspace() or msg[at] == ","):
        at += 1
    start = at
    while at < len(msg) and not msg[at].isspace() and msg[at] not in ",}":
        at += 1
    return (msg[start:at], at) if at != pos else None


def get_double(msg: str, pos: int) -> tuple[float, int] | None:
    got = get_value(msg, pos)
    if got is None:
        return None
    m = re.match(r"[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?|[-+]?(inf|nan)", got[0])  # sscanf("%lf")
    return (float(m.group(0)), got[1]) if m else None


def get_vector(msg: str, pos: int) -> tuple[tuple[float, float, float], int] | None:
    out = []
    for _ in range(3):
        got = get_double(msg, pos)
        if got is None:
            return None
        out.append(got[0])
        pos = got[1]
    return (out[0], out[1], out[2]), pos


# --- GTRI's client ----------------------------------------------------------------------------

@dataclass
class SensorReturn:
    valid: bool = False
    name: str = ""
    object_class: str = ""
    time: float = 0.0
    point: tuple[float, float, float] = (0.0, 0.0, 0.0)
    rpy: tuple[float, float, float] = (0.0, 0.0, 0.0)
    keys: list[str] = field(default_factory=list)


class GtriClient:
    """GTRI's USARTruth class: one connection, getTruth(class, name) per call."""

    def __init__(self, port: int) -> None:
        self.sock = socket.create_connection(("127.0.0.1", port), timeout=10)

    def get_truth(self, class_name: str, instance: str) -> SensorReturn:
        self.sock.sendall(f"{{class {class_name}}} {{name {instance}}}\r\n".encode())
        return self.read()

    def send_raw(self, line: bytes) -> SensorReturn:
        self.sock.sendall(line)
        return self.read()

    def read(self) -> SensorReturn:
        text = ""
        while "\n" not in text:  # 255 bytes a read; the rest of that read is dropped
            chunk = self.sock.recv(255)
            assert chunk, "connection closed"
            text += chunk.decode()
        return self.handle_message(text)

    @staticmethod
    def handle_message(msg: str) -> SensorReturn:
        out = SensorReturn()
        if msg.startswith(END):
            return out
        out.valid = True
        pos = 0
        while True:
            got = get_key(msg, pos)
            if got is None:
                break
            key, pos = got
            out.keys.append(key)
            if key in ("Name", "Class"):
                value = get_value(msg, pos)
                if value is None:
                    break
                if key == "Name":
                    out.name = value[0]
                else:
                    out.object_class = value[0]
                pos = value[1]
            elif key == "Time":
                number = get_double(msg, pos)
                if number is None:
                    break
                out.time, pos = number
            elif key in ("Location", "Rotation"):
                vec = get_vector(msg, pos)
                if vec is None:
                    break
                (x, y, z), pos = vec
                if key == "Location":
                    out.point = (x, -y, -z)  # "swap axis (rotation about x)"
                else:
                    out.rpy = (x, y, z)
            else:  # "unknown token from USARTruth"
                out.valid = False
                break
        return out

    def close(self) -> None:
        self.sock.close()


# --- NIST's client ----------------------------------------------------------------------------

@dataclass
class UsarData:
    object_name: str = ""
    class_name: str = ""
    time: float = 0.0
    location: tuple[float, float, float] = (0.0, 0.0, 0.0)
    rotation: tuple[float, float, float] = (0.0, 0.0, 0.0)
    skipped: list[str] = field(default_factory=list)


class NistClient:
    """NIST's UsarTruth class (el-robotics-core's usarTruth.cpp): getData(class, name)."""

    BUILD_MAX = 2048  # its line buffer doubles from 256 while under 1,024 bytes

    def __init__(self, port: int) -> None:
        self.sock = socket.create_connection(("127.0.0.1", port), timeout=10)
        self.raw = b""

    def get_data(self, class_name: str = "", object_name: str = "") -> list[UsarData]:
        out = ""
        if class_name:
            out += "{class " + class_name + "}"
        if object_name:
            out += "{name " + object_name + "}"
        out += "\r\n"
        if out == "\r\n":
            out = "{class Engine.Actor}\r\n"
        return self.send_raw(out.encode())

    def send_raw(self, line: bytes) -> list[UsarData]:
        self.sock.sendall(line)
        self.raw = b""
        data: list[UsarData] = []
        build = b""
        while True:
            chunk = self.sock.recv(255)
            assert chunk, "connection closed before {End}"
            self.raw += chunk
            for byte in chunk:
                build += bytes([byte])
                assert len(build) <= self.BUILD_MAX, "message overrun in reader"
                if byte == ord("\n"):
                    message, build = build.decode(), b""
                    if message.startswith(END):
                        return data
                    data.append(self.handle_message(message))

    @staticmethod
    def handle_message(msg: str) -> UsarData:
        data = UsarData()
        pos = 0
        while True:
            got = get_key(msg, pos)
            if got is None:
                return data
            key, pos = got
            if key in ("Name", "Class"):
                value = get_value(msg, pos)
                if value is None:
                    return data
                if key == "Name":
                    data.object_name = value[0]
                else:
                    data.class_name = value[0]
                pos = value[1]
            elif key == "Time":
                number = get_double(msg, pos)
                if number is None:
                    return data
                data.time, pos = number
            elif key in ("Location", "Rotation"):
                vec = get_vector(msg, pos)
                if vec is None:
                    return data
                if key == "Location":
                    data.location = vec[0]
                else:
                    data.rotation = vec[0]
                pos = vec[1]
            else:  # "Not reading token"
                data.skipped.append(key)

    def close(self) -> None:
        self.sock.close()


# --- fixtures ---------------------------------------------------------------------------------

@contextmanager
def served(cell: SimulatedCell | None = None) -> Iterator[CellServer]:
    with CellServer(cell or SimulatedCell(INIT), sensor_port=0, command_port=0) as server:
        yield server


def truth(local: str) -> tuple[str, str, tuple[float, ...], tuple[float, ...]]:
    """(IRI, class, location, rotation) of an object of the small kit, from the cell in-process."""
    [obs] = SimulatedCell(INIT).sense(local, by="name")
    return obs.name, obs.cls, obs.location, obs.orientation


PLACED = sorted(o.name.rsplit("#", 1)[1] for o in SimulatedCell(INIT).sense("SolidObject"))


def test_the_small_kit_has_the_objects_these_tests_ask_for() -> None:
    assert len(PLACED) == 23 and {"part_a_1", "kit_tray_1", "robot_1", "part_gripper"} <= set(PLACED)


# --- GTRI's client ------------------------------------------------------------------------------

def test_gtri_client_gets_a_valid_answer_for_every_object_by_name_and_by_class_and_name() -> None:
    with served() as server:
        client = GtriClient(server.sensor_port)
        try:
            for local in PLACED:
                iri, cls, loc, rot = truth(local)
                for class_name in ("", cls, "USARPhysObj." + cls, cls.lower()):
                    got = client.get_truth(class_name, local)
                    assert got.valid, (class_name, local, got)
                    assert got.keys == list(USARTRUTH_KEYS)  # no other field: GTRI's client refuses one
                    assert (got.name, got.object_class) == (iri, cls)
                    assert got.point == pytest.approx((loc[0], -loc[1], -loc[2]))  # its own frame turn
                    assert got.rpy == pytest.approx(rot)
        finally:
            client.close()


def test_gtri_client_a_query_that_matches_nothing_is_end_alone() -> None:
    with served() as server:
        client = GtriClient(server.sensor_port)
        try:
            for class_name, name in [("Part", "kit_tray_1"), ("USARPhysObj.PartC", "part_c_6"), ("", "no_such"),
                                     ("NoSuchClass", "")]:
                client.sock.sendall(f"{{class {class_name}}} {{name {name}}}\r\n".encode())
                assert client.sock.recv(4096) == b"{End}\r\n"
            assert not client.get_truth("Part", "kit_tray_1").valid  # {End} first: no answer
            assert client.get_truth("Part", "part_a_1").valid  # and the connection serves on
        finally:
            client.close()


def test_gtri_client_refuses_kitkbs_extra_fields_so_they_come_only_on_request() -> None:
    with served() as server:
        client = GtriClient(server.sensor_port)
        try:
            assert client.send_raw(b"{class Part} {name part_a_1}\r\n").valid
            asked = client.send_raw(b"{class Part} {name part_a_1} {Fields Sku}\r\n")
            assert not asked.valid and asked.keys[-1] == "Sku"
        finally:
            client.close()


# --- NIST's client ------------------------------------------------------------------------------

def test_nist_client_an_empty_query_is_every_object() -> None:
    with served() as server:
        client = NistClient(server.sensor_port)
        try:
            every = client.get_data()  # {class Engine.Actor}
            assert sorted(d.object_name.rsplit("#", 1)[1] for d in every) == PLACED
            assert all(d.skipped == [] and d.class_name for d in every)
            assert client.raw.endswith(b"{End}\r\n") and client.raw.count(b"\r\n") == len(PLACED) + 1
            assert all(line.endswith(b"\r") for line in client.raw.split(b"\n")[:-1])  # CR LF, as USARSim
            for empty in (b"\r\n", b"\n", b"{class } {name }\r\n", b"{name}\r\n"):
                assert [d.object_name for d in client.send_raw(empty)] == [d.object_name for d in every]
        finally:
            client.close()


def test_nist_client_class_name_and_combined_queries() -> None:
    with served() as server:
        client = NistClient(server.sensor_port)
        try:
            parts = client.get_data("Part")
            assert [d.object_name for d in parts] == [NS + f"part_a_{i}" for i in range(1, 5)] + \
                [NS + f"part_b_{i}" for i in range(1, 4)]
            assert [d.object_name for d in client.get_data("USARPhysObj.part")] == [d.object_name for d in parts]
            [one] = client.get_data("KitTray", "kit_tray_1")
            iri, cls, loc, rot = truth("kit_tray_1")
            assert (one.object_name, one.class_name, one.location, one.rotation) == (iri, cls, loc, rot)
            assert [d.object_name for d in client.get_data(object_name="part_b_2")] == [NS + "part_b_2"]
            assert [d.object_name for d in client.get_data("Pawn")] == [NS + "robot_1"]
            assert len(client.get_data("WCObject")) == len(PLACED)
            for class_name, name in [("USARPhysObj.PartC", "part_c_6"), ("Part", "kit_tray_1"), ("", "nothing")]:
                assert client.get_data(class_name, name) == []  # {End} alone: no bogus object of an {Error}
                assert client.raw == b"{End}\r\n"
            # keys in any case, with or without spaces, a name given as its IRI
            for line in (b"{CLASS Part}{NAME part_a_1}\r\n", b"{ Name  part_a_1 } {Class part}\n",
                         b"{name " + NS.encode() + b"part_a_1}\r\n"):
                assert [d.object_name for d in client.send_raw(line)] == [NS + "part_a_1"]
        finally:
            client.close()


# --- kitkb's own client asks for what it needs ----------------------------------------------------

def test_remote_cell_asks_for_the_sku_and_gets_it() -> None:
    assert query_line("class", "Part", ("Sku",)) == "{Class Part} {Fields Sku}"
    assert query_line("inspect", "part_a_1", ("Sku",)) == "{Inspect part_a_1}"
    with served(SimulatedCell(INIT, faults=FaultSpec(at={0: "wrong-sku"}, seed=1))) as server:
        with RemoteCell("127.0.0.1", server.sensor_port, server.command_port) as remote:
            assert [o.sku for o in remote.sense("Part")] == ["sku_part_a"] * 4 + ["sku_part_b"] * 3
            remote.begin_action(0, "take-part", (NS + "robot_1", NS + "part_a_1", NS + "part_a_tray",
                                                 NS + "part_gripper"))
            assert remote.sense("part_a_1", by="name")[0].sku == "sku_part_b"
        nist = NistClient(server.sensor_port)
        try:
            [seen] = nist.get_data("Part", "part_a_1")
            assert seen.skipped == []  # the SKU only to whom asks for it
            [asked] = nist.send_raw(b"{class Part}{name part_a_1}{fields sku}\r\n")
            assert asked.skipped == ["Sku"]
        finally:
            nist.close()


def test_queries_are_read_as_usarsim_read_them() -> None:
    assert parse_query("{class USARPhysObj.PartC} {name part_c_6}\r\n") == Query("USARPhysObj.PartC", "part_c_6")
    assert parse_query("{class Part}{name part_a_1}") == Query("Part", "part_a_1")
    assert parse_query("\r\n") == parse_query("{class } {name }") == parse_query("{Name}") == Query()
    assert parse_query("{Class Part} {Fields sku, Sku}") == Query("Part", fields=("Sku",))
    assert parse_query("{inspect part_a_1}") == Query(inspect="part_a_1")
    for bad, why in [("garbage", "not a line of key-value fields"), ("{Colour red}", "unknown key 'Colour'"),
                     ("{class A} {Class B}", "twice"), ("{Inspect p} {Name q}", "Inspect query"),
                     ("{Inspect}", "Inspect query"), ("{Fields Colour}", "no field 'Colour'"),
                     ("{Class Part} and", "not a line")]:
        with pytest.raises(ValueError, match=why):
            parse_query(bad)
    known = {KTW + "Part", KTW + "KitTray", KTW + "SolidObject", KTW + "Robot"}
    assert truth_class("USARPhysObj.partc", known) is None
    assert truth_class("USARPhysObj.kittray", known) == KTW + "KitTray"
    assert truth_class("Engine.Actor", known) == truth_class("", known) == ""
    assert truth_class("Engine.Pawn", known) == KTW + "Robot"
    assert truth_class(KTW + "Part", known) == KTW + "Part"


def test_a_gtri_client_against_kitkb_sim_serve() -> None:
    env = dict(os.environ, PYTHONPATH=str(REPO))
    proc = subprocess.Popen([sys.executable, "-m", "kb.cli", "sim", "serve", str(INIT), "--sensor-port", "0",
                             "--command-port", "0"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
    try:
        assert proc.stdout is not None
        ready, _, _ = select.select([proc.stdout], [], [], 60)
        assert ready, "kitkb sim serve printed no line"
        m = re.search(r"sensor port (\d+)", proc.stdout.readline())
        assert m
        client = GtriClient(int(m.group(1)))
        try:
            answers = [client.get_truth("", local) for local in PLACED]
            assert all(a.valid for a in answers) and len(answers) == len(PLACED)
        finally:
            client.close()
    finally:
        proc.terminate()
        proc.wait(timeout=30)


def test_a_line_may_end_in_cr_alone_as_usarsim_read_it() -> None:
    """USARSim's TcpLink ended a line at CR and dropped an LF right after it, even one that came
    in a later packet: that LF is not an empty query (which would answer every object)."""
    with served() as server, socket.create_connection(("127.0.0.1", server.sensor_port), timeout=10) as s, \
            s.makefile("rb") as reader:

        def answer() -> list[bytes]:
            lines = []
            while (line := reader.readline()) != b"{End}\r\n":
                assert line, "connection closed"
                lines.append(line)
            return lines
        s.sendall(b"{name part_a_1}\r")
        assert [x.split(b"}")[0] for x in answer()] == [b"{Name " + NS.encode() + b"part_a_1"]
        s.sendall(b"\n{name part_b_1}\r{name part_b_2}\n\n")
        assert len(answer()) == 1 and len(answer()) == 1  # part_b_1, part_b_2
        assert len(answer()) == len(PLACED)  # the empty line after an LF: every object
