"""CRCL: typed commands, the text form of the first paper's Fig. 11, XML instances of NIST's
CRCL.xsd, and ``kitkb crcl convert``."""

from __future__ import annotations

from collections import Counter
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from lxml import etree

from kb.cli import main
from kb.core.errors import InputError
from kb.crcl import (CloseGripper, CloseToolChanger, Dwell, EndCanon, InitCanon, Message, MoveStraightTo,
                     MoveThroughTo, MoveTo, OpenGripper, OpenToolChanger, Pose, Program,
                     SetAbsoluteAcceleration, SetAbsoluteSpeed, SetAngleUnits, SetCoordinateFrame,
                     SetEndAngleTolerance, SetEndPointTolerance, SetIntermediatePointTolerance,
                     SetLengthUnits, SetRelativeAcceleration, SetRelativeSpeed, StartObjectScan,
                     StopMotion, StopObjectScan, Unreadable, read_text, read_xml, schema, write_text,
                     write_xml)
from kb.crcl.xml import _decimal_text, hardened_parser
from shared_data import NIST_DIR

XSD = NIST_DIR / "CRCL.xsd"
COMMANDS1 = NIST_DIR / "commands1.xml"
needs_nist = pytest.mark.skipif(not XSD.exists() or not COMMANDS1.exists(), reason="NIST CRCL files not present")

#: The first paper's Fig. 11, as printed (a few intentional errors included).
FIG11 = """InitCanon()
SetLengthUnits("meter")
CloseGripper()
CloseToolChanger()
Dwell(1.7)
Message("This message is false")
SetRelativeSpeed(50.0)
SetAbsoluteSpeed(3.8)
MoveThroughTo({{5,0,2}, {0,0,1}, {1,0,0}},
  {{5,8,2}, {0,0,1}, {1,0,0}},
  {{7,8,2}, {0,0,1}, {1,0,0}}, 3)
MoveStraightTo({{4,8,2}, {0,0,1}, {1,0,0}})
MoveTo({{9,8,2}, {0,0,1}, {1,0,0}})
OpenGripper()
OpenToolChanger()
SetAbsoluteAcceleration(0.95)
SetAngleUnits("degree")
SetEndAngleTolerance(1.3)
SetEndPointTolerance(0.4)
SetIntermediatePointTolerance(10.734)
SetLengthUnits("mm")
SetRelativeAcceleration(0.8)
SetRelativeSpeed(0.75)
SetRelativeAcceleration(-110)
MoveStraightTo(87)
EndCanon(2)
"""

#: What kitkb writes for Fig. 11: one command a line, the unreadable line as it was.
FIG11_WRITTEN = """InitCanon()
SetLengthUnits("meter")
CloseGripper()
CloseToolChanger()
Dwell(1.7)
Message("This message is false")
SetRelativeSpeed(50)
SetAbsoluteSpeed(3.8)
MoveThroughTo({{5, 0, 2}, {0, 0, 1}, {1, 0, 0}}, {{5, 8, 2}, {0, 0, 1}, {1, 0, 0}}, {{7, 8, 2}, {0, 0, 1}, {1, 0, 0}}, 3)
MoveStraightTo({{4, 8, 2}, {0, 0, 1}, {1, 0, 0}})
MoveTo({{9, 8, 2}, {0, 0, 1}, {1, 0, 0}})
OpenGripper()
OpenToolChanger()
SetAbsoluteAcceleration(0.95)
SetAngleUnits("degree")
SetEndAngleTolerance(1.3)
SetEndPointTolerance(0.4)
SetIntermediatePointTolerance(10.734)
SetLengthUnits("mm")
SetRelativeAcceleration(0.8)
SetRelativeSpeed(0.75)
SetRelativeAcceleration(-110)
MoveStraightTo(87)
EndCanon(2)
"""

#: The third paper's Table 1 as printed: typographic quotes, and InitCanon / EndCanon misspelt.
TABLE1 = """
initCannon()
Message (\u201ctake part part_e1\u201d)
MoveTo({{-0.03, 1.62, -0.25}, {0, 0, 1}, {1, 0, 0}})
Dwell (0.05)
MoveTo({{-0.03, 1.62, 0.1325}, {0, 0, 1}, {1, 0, 0}})
CloseGripper ()
MoveTo({{-0.03, 1.62, -0.25}, {0, 0, 1}, {1, 0, 0}})
Dwell (0.05)
endCannon()
"""

DOWN = Pose(point=(0, 0, 0), x_axis=(1, 0, 0), z_axis=(0, 0, -1))


def _pose(x: float, y: float, z: float, zk: float = 1.0) -> Pose:
    return Pose(point=(x, y, z), x_axis=(1, 0, 0), z_axis=(0, 0, zk))


@pytest.fixture(scope="module")
def xsd() -> etree.XMLSchema:
    if not XSD.exists():
        pytest.skip("NIST CRCL.xsd not present")
    return schema(XSD)


# --- typed values -------------------------------------------------------------------------------

def test_line_is_keyword_only_and_not_compared() -> None:
    assert Dwell(1.5, line=3) == Dwell(1.5, line=9) == Dwell(1.5)
    assert Dwell(1.5, line=3).line == 3 and Dwell(1.5).line is None
    assert Dwell(1.5) != Dwell(2.5) and Dwell(1.5) != SetAbsoluteSpeed(1.5)
    assert Unreadable("x(", reason="a", line=1) == Unreadable("x(", reason="b")
    assert Program([InitCanon(line=1)], source="a.crcl") == Program((InitCanon(),), source=None)


def test_field_values_are_checked_and_numbers_kept_as_floats() -> None:
    assert Dwell(2).dwell_time == 2.0 and isinstance(Dwell(2).dwell_time, float)
    assert Dwell(np.float32(0.5)).dwell_time == 0.5 and type(Dwell(np.float32(0.5)).dwell_time) is float
    assert StopMotion(np.int64(1)).is_emergency == 1 and type(StopMotion(np.int64(1)).is_emergency) is int
    for bad in (lambda: Dwell(float("nan")), lambda: Dwell(True), lambda: Dwell("1"),
                lambda: SetLengthUnits("mm"), lambda: SetLengthUnits("furlong"),
                lambda: SetAngleUnits("grad"), lambda: SetCoordinateFrame("World"),
                lambda: EndCanon(1.0), lambda: StopMotion(True), lambda: Message(3),
                lambda: MoveTo((1, 2, 3)), lambda: MoveThroughTo(()),
                lambda: Pose(point=(1, 2), x_axis=(1, 0, 0), z_axis=(0, 0, 1)),
                lambda: Pose(point=(1, 2, float("inf")), x_axis=(1, 0, 0), z_axis=(0, 0, 1))):
        with pytest.raises(ValueError):
            bad()
    assert MoveThroughTo([DOWN, DOWN]).waypoints == (DOWN, DOWN)
    assert MoveThroughTo([DOWN, DOWN]).num_positions == 2


def test_pose_matrix_round_trip() -> None:
    c, s = np.cos(0.3), np.sin(0.3)
    m = np.array([[c, -s, 0, 1.5], [s, c, 0, -2.0], [0, 0, 1, 0.25], [0, 0, 0, 1]])
    pose = Pose.from_matrix(m)
    assert pose.point == (1.5, -2.0, 0.25)
    assert pose.x_axis == pytest.approx((c, s, 0)) and pose.z_axis == (0.0, 0.0, 1.0)
    assert np.allclose(pose.matrix(), m)
    # gripper pointing down (as in commands1.xml): Y = Z x X = (0, -1, 0)
    assert np.allclose(DOWN.matrix()[:3, :3], [[1, 0, 0], [0, -1, 0], [0, 0, -1]])
    # axes not unit nor perpendicular: Z normalised, X made perpendicular to it
    skew = Pose(point=(0, 0, 0), x_axis=(2, 0, 2), z_axis=(0, 0, 3)).matrix()
    assert np.allclose(skew[:3, :3], np.eye(3))
    with pytest.raises(ValueError, match="parallel"):
        Pose(point=(0, 0, 0), x_axis=(0, 0, 2), z_axis=(0, 0, 1)).matrix()
    with pytest.raises(ValueError, match="4x4"):
        Pose.from_matrix(np.eye(3))


# --- text form ----------------------------------------------------------------------------------

def test_fig11_reads_as_typed_commands_with_their_lines() -> None:
    program = read_text(FIG11)
    assert program == Program([
        InitCanon(), SetLengthUnits("meter"), CloseGripper(), CloseToolChanger(), Dwell(1.7),
        Message("This message is false"), SetRelativeSpeed(50.0), SetAbsoluteSpeed(3.8),
        MoveThroughTo([_pose(5, 0, 2), _pose(5, 8, 2), _pose(7, 8, 2)]),
        MoveStraightTo(_pose(4, 8, 2)), MoveTo(_pose(9, 8, 2)), OpenGripper(), OpenToolChanger(),
        SetAbsoluteAcceleration(0.95), SetAngleUnits("degree"), SetEndAngleTolerance(1.3),
        SetEndPointTolerance(0.4), SetIntermediatePointTolerance(10.734), SetLengthUnits("millimeter"),
        SetRelativeAcceleration(0.8), SetRelativeSpeed(0.75), SetRelativeAcceleration(-110.0),
        Unreadable("MoveStraightTo(87)"), EndCanon(2)])
    # the three-line MoveThroughTo keeps its first line; later lines are counted on from there
    assert [c.line for c in program] == [*range(1, 10), *range(12, 27)]
    assert program[8].waypoints[0].z_axis == (0.0, 0.0, 1.0) and program[8].waypoints[0].x_axis == (1.0, 0.0, 0.0)
    assert program.unreadable == (Unreadable("MoveStraightTo(87)"),)
    assert program.unreadable[0].line == 25 and "pose" in program.unreadable[0].reason


def test_text_round_trip() -> None:
    program = read_text(FIG11)
    assert write_text(program, style="paper") == FIG11_WRITTEN
    assert read_text(FIG11_WRITTEN) == program
    assert write_text(read_text(FIG11_WRITTEN), style="paper") == FIG11_WRITTEN


def test_table1_of_the_third_paper() -> None:
    program = read_text(TABLE1)
    up, down = _pose(-0.03, 1.62, -0.25), _pose(-0.03, 1.62, 0.1325)
    assert program == Program([
        Unreadable("initCannon()"), Message("take part part_e1"), MoveTo(up), Dwell(0.05), MoveTo(down),
        CloseGripper(), MoveTo(up), Dwell(0.05), Unreadable("endCannon()")])
    assert [c.line for c in program] == list(range(2, 11))
    assert program[0].reason == "unknown command initCannon"
    assert write_text(program, style="paper").splitlines()[:3] == [
        "initCannon()", 'Message("take part part_e1")', "MoveTo({{-0.03, 1.62, -0.25}, {0, 0, 1}, {1, 0, 0}})"]


def test_unreadable_lines_keep_text_and_line_and_are_written_back() -> None:
    text = ("# a comment\n"
            "InitCanon()\n"
            "\n"
            "   // another comment\n"
            "Dwell(1, 2)\n"
            "  MoveTo({{1, 2, 3}, {0, 0, 1}}) \n"
            "MoveThroughTo({{1, 2, 3}, {0, 0, 1}, {1, 0, 0}},\n"
            "  {{1, 2, 4}, {0, 0, 1}, {1, 0, 0}}, 3)\n"
            "MoveThroughTo({{1, 2, 3}, {0, 0, 1}, {1, 0, 0}},\n"
            "Message(\"unclosed\"\n"
            "EndCanon(0) trailing\n"
            "Dwell(1)\r\n"
            "SetLengthUnits(meter)\n"
            "EndCanon()\n")
    program = read_text(text, name="p.crcl")
    assert program.source == "p.crcl"
    assert [(type(c).__name__, c.line) for c in program] == [
        ("InitCanon", 2), ("Unreadable", 5), ("Unreadable", 6), ("Unreadable", 7), ("Unreadable", 9),
        ("Unreadable", 10), ("Unreadable", 11), ("Dwell", 12), ("Unreadable", 13), ("EndCanon", 14)]
    assert [c.text for c in program.unreadable] == [
        "Dwell(1, 2)", "  MoveTo({{1, 2, 3}, {0, 0, 1}}) ",
        "MoveThroughTo({{1, 2, 3}, {0, 0, 1}, {1, 0, 0}},\n  {{1, 2, 4}, {0, 0, 1}, {1, 0, 0}}, 3)",
        "MoveThroughTo({{1, 2, 3}, {0, 0, 1}, {1, 0, 0}},", 'Message("unclosed"', "EndCanon(0) trailing",
        "SetLengthUnits(meter)"]
    assert [c.reason for c in program.unreadable] == [
        "Dwell takes 1 argument(s), 2 given", "expected a pose {{x, y, z}, {i, j, k}, {i, j, k}}",
        "3 poses announced, 2 given", "expected ',' or ')'", "expected ',' or ')'",
        "text after the closing parenthesis", "unexpected 'meter'"]
    assert program[-1] == EndCanon(0)
    written = write_text(program)
    assert written.splitlines()[1:4] == ["Dwell(1, 2)", "  MoveTo({{1, 2, 3}, {0, 0, 1}}) ",
                                         "MoveThroughTo({{1, 2, 3}, {0, 0, 1}, {1, 0, 0}},"]
    assert read_text(written) == program


def test_strings_escape_and_read_back() -> None:
    message = Message('say "hi"\\ \n\tthere\r')
    text = write_text(Program([message]), style="paper")
    assert text == 'Message("say \\"hi\\"\\\\ \\n\\tthere\\r")\n'
    assert read_text(text) == Program([message])


def test_reading_a_file(tmp_path: Path) -> None:
    path = tmp_path / "fig11.crcl"
    path.write_text(FIG11)
    program = read_text(path)
    assert program.source == str(path) and program == read_text(FIG11)
    with pytest.raises(InputError, match="cannot read"):
        read_text(tmp_path / "missing.crcl")
    path.write_bytes(b"InitCanon()\nMessage(\"\xff\")\n")
    with pytest.raises(InputError) as err:
        read_text(path)
    assert str(err.value) == f"{path}:2: error: not UTF-8 text"


# --- XML ----------------------------------------------------------------------------------------

@needs_nist
def test_commands1_reads_with_its_values_and_lines(xsd: etree.XMLSchema) -> None:
    for program in (read_xml(COMMANDS1), read_xml(COMMANDS1, xsd), read_xml(COMMANDS1.read_bytes())):
        assert program[:7] == (InitCanon(), SetLengthUnits("meter"), SetAbsoluteSpeed(1.0),
                               SetRelativeAcceleration(80.0), SetEndPointTolerance(0.002),
                               SetIntermediatePointTolerance(0.01), OpenGripper())
        assert program[7] == MoveThroughTo([_pose(1.5, 1, 1, -1), _pose(1.5, 1, 0.0001, -1)])
        assert program[8] == CloseGripper()
        assert program[9].waypoints[2] == _pose(4, 1, 0.5001, -1)
        assert program[-2] == MoveThroughTo([_pose(2.5, 1, 1, -1), _pose(0.5, 0, 2, -1)])
        assert program[-1] == EndCanon(0)
        assert [c.line for c in program[:9]] == [5, 6, 9, 12, 15, 18, 22, 23, 60]
        assert program[-1].line == 923
        assert Counter(type(c).__name__ for c in program) == {
            "InitCanon": 1, "SetLengthUnits": 1, "SetAbsoluteSpeed": 1, "SetRelativeAcceleration": 1,
            "SetEndPointTolerance": 1, "SetIntermediatePointTolerance": 1, "OpenGripper": 7,
            "CloseGripper": 6, "OpenToolChanger": 2, "CloseToolChanger": 2, "MoveThroughTo": 17,
            "EndCanon": 1}
    assert read_xml(COMMANDS1).source == str(COMMANDS1)


@needs_nist
def test_commands1_through_text_and_back(xsd: etree.XMLSchema) -> None:
    program = read_xml(COMMANDS1)
    text = write_text(program, style="paper")
    assert text.splitlines()[7] == "MoveThroughTo({{1.5, 1, 1}, {0, 0, -1}, {1, 0, 0}}, {{1.5, 1, 0.0001}, {0, 0, -1}, {1, 0, 0}}, 2)"
    again = write_xml(read_text(text), xsd)
    assert xsd.validate(etree.fromstring(again))
    assert read_xml(again) == program


def _every_xsd_command() -> Program:
    return Program([
        InitCanon(), SetLengthUnits("inch"), SetLengthUnits("millimeter"), SetAngleUnits("radian"),
        SetAbsoluteSpeed(3.8), SetRelativeSpeed(50), SetAbsoluteAcceleration(0.95),
        SetRelativeAcceleration(-110), SetEndAngleTolerance(1e-7), SetEndPointTolerance(0.4),
        SetIntermediatePointTolerance(1e16), Message(' <&> "quoted" \n\ttabbed\r'), Message(""),
        Dwell(0.05), OpenGripper(), CloseGripper(), OpenToolChanger(), CloseToolChanger(),
        MoveTo(_pose(-0.03, 1.62, -0.25)), MoveStraightTo(DOWN),
        MoveThroughTo([_pose(5, 0, 2), _pose(5, 8, 2), _pose(7, 8, 2)]), EndCanon(0)])


def test_every_xsd_command_through_xml_and_text(xsd: etree.XMLSchema) -> None:
    program = _every_xsd_command()
    data = write_xml(program, xsd)
    assert xsd.validate(etree.fromstring(data)), xsd.error_log
    assert data.startswith(b"<?xml version='1.0' encoding='UTF-8'?>\n<CRCLProgram>\n  <InitCanon/>\n")
    assert b"<SetEndAngleTolerance>\n    <Tolerance>0.0000001</Tolerance>" in data
    assert b"<Tolerance>10000000000000000</Tolerance>" in data
    assert (b"<MoveStraightTo>\n    <EndPosition>\n      <Point>\n        <X>0.0</X>\n        <Y>0.0</Y>\n"
            b"        <Z>0.0</Z>\n      </Point>\n      <ZAxis>\n        <I>0.0</I>\n") in data
    assert b"<NumPositions>3</NumPositions>" in data and b"<UnitName>millimeter</UnitName>" in data
    back = read_xml(data, xsd)
    assert back == program
    assert [c.line for c in back[:3]] == [3, 4, 7]
    assert read_text(write_text(back, style="paper")) == program
    assert read_xml(write_xml(read_text(write_text(program, style="paper")))) == program


@pytest.mark.parametrize("command, name", [
    (SetCoordinateFrame("RobotBase"), "SetCoordinateFrame"), (StartObjectScan("part_b_1"), "StartObjectScan"),
    (StopObjectScan(), "StopObjectScan"), (StopMotion(1), "StopMotion")])
def test_commands_the_early_schema_lacks_cannot_be_written_as_xml(command, name: str) -> None:
    text = f"InitCanon()\nDwell(1)\n\n{write_text(Program([command]), style='paper')}EndCanon(0)\n"
    program = read_text(text, name="prog.crcl")
    assert program[2] == command and program[2].line == 4
    with pytest.raises(InputError) as err:
        write_xml(program)
    assert str(err.value) == (f"prog.crcl:4: error: {name} has no element in CRCL.xsd (the early schema); "
                              "cannot write it as XML")


def test_what_else_xml_cannot_hold() -> None:
    def error(commands: list, source: str | None = "p.crcl") -> str:
        with pytest.raises(InputError) as err:
            write_xml(Program(commands, source=source))
        return str(err.value)

    assert error([InitCanon(line=1), Dwell(1, line=2), EndCanon(2, line=3)]) == (
        "p.crcl:3: error: EndCanon(2): CRCL.xsd's EndCanon has no reason; only EndCanon(0) can be written as XML")
    assert error([InitCanon(), Unreadable("MoveStraightTo(87)", reason="expected a pose", line=7), EndCanon()]) == (
        "p.crcl:7: error: unreadable line 'MoveStraightTo(87)' (expected a pose); cannot write it as XML")
    assert error([InitCanon(), Message("bell\x07", line=2), EndCanon()]) == (
        "p.crcl:2: error: Message holds control characters that XML 1.0 cannot hold; cannot write it as XML")
    # CRCL.xsd's sequence: InitCanon, one or more commands, EndCanon
    assert error([Dwell(1, line=1), EndCanon()]) == (
        "p.crcl:1: error: a CRCL.xsd program starts with InitCanon, not Dwell")
    assert error([InitCanon(), Dwell(1), InitCanon(line=3), EndCanon()]) == (
        "p.crcl:3: error: InitCanon only as the first command in CRCL.xsd")
    assert error([InitCanon(), EndCanon(line=2), Dwell(1), EndCanon()]) == (
        "p.crcl:2: error: EndCanon only as the last command in CRCL.xsd")
    assert error([InitCanon(), Dwell(1, line=2)]) == (
        "p.crcl:2: error: a CRCL.xsd program ends with EndCanon, not Dwell")
    assert error([InitCanon(line=1), EndCanon(line=2)]) == (
        "p.crcl:2: error: CRCL.xsd needs InitCanon, at least one other command, then EndCanon")
    assert error([], source=None) == "error: CRCL.xsd needs InitCanon, at least one other command, then EndCanon"


BAD_XML = {
    "no-init": ("<CRCLProgram>\n  <Dwell><DwellTime>1</DwellTime></Dwell>\n  <EndCanon/>\n</CRCLProgram>",
                "2: error: a CRCL.xsd program starts with InitCanon, not Dwell"),
    "unknown": ("<CRCLProgram>\n <InitCanon/>\n <StopMotion/>\n <EndCanon/>\n</CRCLProgram>",
                "3: error: <StopMotion> is not a command of CRCL.xsd"),
    "exponent": ("<CRCLProgram><InitCanon/>\n<Dwell><DwellTime>1e3</DwellTime></Dwell><EndCanon/></CRCLProgram>",
                 "2: error: <DwellTime> must be a decimal number, not '1e3'"),
    "count": ("<CRCLProgram><InitCanon/><MoveThroughTo>\n<Waypoint><Point><X>0</X><Y>0</Y><Z>0</Z></Point>"
              "<ZAxis><I>0</I><J>0</J><K>1</K></ZAxis><XAxis><I>1</I><J>0</J><K>0</K></XAxis></Waypoint>\n"
              "<NumPositions>2</NumPositions></MoveThroughTo><EndCanon/></CRCLProgram>",
              "3: error: NumPositions is 2 but there are 1 Waypoints"),
    "order": ("<CRCLProgram><InitCanon/>\n<Dwell><Message>x</Message></Dwell><EndCanon/></CRCLProgram>",
              "2: error: <Dwell> holds DwellTime in CRCL.xsd, found Message"),
    "unit": ("<CRCLProgram><InitCanon/>\n<SetLengthUnits><UnitName>mm</UnitName></SetLengthUnits><EndCanon/>"
             "</CRCLProgram>", "2: error: SetLengthUnits.unit_name must be one of meter, millimeter, inch, not 'mm'"),
    "root": ("<CRCL>\n</CRCL>", "1: error: the root element is <CRCL>, not <CRCLProgram>"),
    "syntax": ("<CRCLProgram>\n<InitCanon>\n</CRCLProgram>", "3: error: XML syntax error: "),
    "text": ("<CRCLProgram><InitCanon/>\n<OpenGripper>now</OpenGripper><EndCanon/></CRCLProgram>",
             "2: error: unexpected text 'now' in <OpenGripper>"),
}


@pytest.mark.parametrize("case", sorted(BAD_XML))
def test_bad_xml_is_an_input_error_at_its_line(case: str) -> None:
    data, expected = BAD_XML[case]
    with pytest.raises(InputError) as err:
        read_xml(data.encode(), name="bad.xml")
    assert str(err.value).startswith(f"bad.xml:{expected}")


def test_schema_checks_xml_as_it_is_read(xsd: etree.XMLSchema) -> None:
    data = b"<CRCLProgram>\n  <InitCanon/>\n  <EndCanon/>\n</CRCLProgram>"
    with pytest.raises(InputError) as err:
        read_xml(data, xsd, name="two.xml")
    assert str(err.value) == ("two.xml:3: error: does not conform to CRCL.xsd: Element 'EndCanon': "
                              "This element is not expected. Expected is one of ( CloseGripper, "
                              "CloseToolChanger, Dwell, Message, MoveStraightTo, MoveThroughTo, MoveTo, "
                              "OpenGripper, OpenToolChanger, SetAbsoluteAcceleration ).")
    with pytest.raises(InputError, match="no such file|No such file"):
        schema(XSD.parent / "missing.xsd")


def test_external_entities_are_never_resolved(tmp_path: Path) -> None:
    secret = tmp_path / "secret.txt"
    secret.write_text("TOP-SECRET-42")
    data = (f'<?xml version="1.0"?>\n<!DOCTYPE CRCLProgram [<!ENTITY e SYSTEM "file://{secret}">]>\n'
            "<CRCLProgram><InitCanon/><Message><Message>&e;</Message></Message><EndCanon/></CRCLProgram>").encode()
    # the parser itself leaves the entity unexpanded ...
    tree = etree.fromstring(data, hardened_parser())
    assert b"TOP-SECRET" not in etree.tostring(tree) and "TOP-SECRET" not in "".join(tree.itertext())
    # ... and the reader refuses the DOCTYPE outright
    path = tmp_path / "xxe.xml"
    path.write_bytes(data)
    with pytest.raises(InputError) as err:
        read_xml(path)
    assert str(err.value) == (f"{path}:2: error: a DOCTYPE is not allowed in CRCL XML "
                              "(no entity is expanded or fetched)")
    # the same file with /etc/passwd
    passwd = data.replace(f"file://{secret}".encode(), b"file:///etc/passwd")
    with pytest.raises(InputError) as err:
        read_xml(passwd)
    assert "root:" not in str(err.value)
    assert b"root:" not in etree.tostring(etree.fromstring(passwd, hardened_parser()))


# --- round trips over random programs -----------------------------------------------------------

_num = st.floats(allow_nan=False, allow_infinity=False)
#: numbers XML keeps exactly: not sin(pi)-sized noise (written as 0) nor a decimal of more than
#: 24 digits (rounded to 24 for libxml2); tests/test_crcl_instance.py tests those
_num = _num.filter(lambda x: float(_decimal_text(x)) == x)
_vec = st.tuples(_num, _num, _num)
_pose_st = st.builds(Pose, point=_vec, x_axis=_vec, z_axis=_vec)
_xml_text = st.text(st.characters(codec="utf-8", exclude_categories=("Cs", "Cc", "Cn")) | st.sampled_from("\t\n\r"),
                    max_size=20)
_XSD_MIDDLE = st.one_of(
    st.builds(Message, _xml_text), st.builds(Dwell, _num), st.builds(MoveTo, _pose_st),
    st.builds(MoveStraightTo, _pose_st), st.builds(MoveThroughTo, st.lists(_pose_st, min_size=1, max_size=3)),
    st.sampled_from([OpenGripper(), CloseGripper(), OpenToolChanger(), CloseToolChanger()]),
    st.builds(SetLengthUnits, st.sampled_from(["meter", "millimeter", "inch"])),
    st.builds(SetAngleUnits, st.sampled_from(["degree", "radian"])),
    *(st.builds(cls, _num) for cls in (SetAbsoluteSpeed, SetRelativeSpeed, SetAbsoluteAcceleration,
                                       SetRelativeAcceleration, SetEndAngleTolerance, SetEndPointTolerance,
                                       SetIntermediatePointTolerance)))
_ANY = st.one_of(
    _XSD_MIDDLE, st.builds(Message, st.text(max_size=20)), st.just(InitCanon()), st.builds(EndCanon, st.integers()),
    st.builds(SetCoordinateFrame, st.sampled_from(["Workstation", "RobotBase", "ToolTip"])),
    st.builds(StartObjectScan, st.text(max_size=10)), st.just(StopObjectScan()), st.builds(StopMotion, st.integers()))


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(_ANY, max_size=8))
def test_any_program_round_trips_through_text(commands: list) -> None:
    program = Program(commands)
    back = read_text(write_text(program, style="paper"))
    assert back == program
    assert [c.line for c in back] == list(range(1, len(commands) + 1))


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(_XSD_MIDDLE, min_size=1, max_size=6))
def test_any_xsd_program_round_trips_through_xml_and_text(middle: list) -> None:
    program = Program([InitCanon(), *middle, EndCanon()])
    data = write_xml(program)
    assert read_xml(data) == program
    assert read_xml(write_xml(read_text(write_text(read_xml(data), style="paper")))) == program


# --- the command line ---------------------------------------------------------------------------

@needs_nist
def test_cli_converts_both_ways(tmp_path: Path, capsys, monkeypatch) -> None:
    monkeypatch.setenv("KITKB_NIST_DIR", str(NIST_DIR))  # the default CRCL.xsd wherever the checkout is
    text, xml = tmp_path / "c1.crcl", tmp_path / "out" / "c1.xml"
    assert main(["crcl", "convert", str(COMMANDS1), "-o", str(text)]) == 0
    assert capsys.readouterr().err == f"kitkb: wrote {text} (CRCL text, NIST's kittingViewer form: --text-style nist, 41 commands)\n"
    assert main(["crcl", "convert", str(text), "-o", str(xml), "--xsd", str(XSD)]) == 0
    assert capsys.readouterr().err == f"kitkb: wrote {xml} (CRCL XML, 41 commands)\n"
    assert read_xml(xml, schema(XSD)) == read_xml(COMMANDS1)
    assert main(["-q", "crcl", "convert", str(xml), "-o", str(tmp_path / "again.crcl")]) == 0
    assert capsys.readouterr() == ("", "")
    assert (tmp_path / "again.crcl").read_text() == text.read_text()


def test_cli_keeps_unreadable_lines_in_text_and_notes_a_missing_schema(tmp_path: Path, capsys, monkeypatch) -> None:
    import kb.cli.crcl

    fig11 = tmp_path / "fig11.crcl"
    fig11.write_text(FIG11)
    assert main(["crcl", "convert", str(fig11), "-o", str(tmp_path / "copy.crcl"), "--text-style", "paper"]) == 0
    assert capsys.readouterr().err == (f"kitkb: wrote {tmp_path / 'copy.crcl'} (CRCL text, the paper's Fig. 11 form: --text-style paper, "
                                       "24 commands; 1 unreadable line(s) kept)\n")
    assert (tmp_path / "copy.crcl").read_text() == FIG11_WRITTEN
    monkeypatch.setattr(kb.cli.crcl, "default_xsd", lambda: None)
    good = tmp_path / "good.crcl"
    good.write_text("InitCanon()\nDwell(0.5)\nEndCanon(0)\n")
    assert main(["crcl", "convert", str(good), "-o", str(tmp_path / "good.xml")]) == 0
    assert capsys.readouterr().err == (f"kitkb: wrote {tmp_path / 'good.xml'} (CRCL XML, 3 commands; "
                                       "XML not validated: CRCL.xsd not found, give --xsd)\n")
    assert read_xml(tmp_path / "good.xml") == read_text(good)


@pytest.mark.parametrize("content, suffix, expected", [
    (FIG11, ".crcl", ":25: error: unreadable line 'MoveStraightTo(87)' "
                     "(expected a pose {{x, y, z}, {i, j, k}, {i, j, k}}); cannot write it as XML"),
    ("InitCanon()\nDwell(1)\n// stop\nStopMotion(1)\nEndCanon(0)\n", ".crcl",
     ":4: error: StopMotion has no element in CRCL.xsd (the early schema); cannot write it as XML"),
    ("<CRCLProgram>\n<InitCanon/>\n<Dwell/>\n<EndCanon/>\n</CRCLProgram>\n", ".xml",
     ":3: error: <Dwell> holds DwellTime in CRCL.xsd, found none"),
])
def test_cli_bad_input_is_one_line_exit_2_and_nothing_written(tmp_path: Path, capsys, monkeypatch,
                                                              content: str, suffix: str, expected: str) -> None:
    """kitkb's own reader and writer (no CRCL.xsd at hand): the same refusals, at the same lines."""
    import kb.cli.crcl

    monkeypatch.setattr(kb.cli.crcl, "default_xsd", lambda: None)
    source = tmp_path / f"prog{suffix}"
    source.write_text(content)
    target = tmp_path / "out.xml"
    target.write_text("old")
    assert main(["crcl", "convert", str(source), "-o", str(target)]) == 2
    err = capsys.readouterr().err
    assert err == f"{source}{expected}\n"
    assert target.read_text() == "old"
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted([source.name, "out.xml"])


def test_cli_refuses_unknown_suffixes_and_missing_files(tmp_path: Path, capsys) -> None:
    good = tmp_path / "good.crcl"
    good.write_text("InitCanon()\nDwell(0.5)\nEndCanon(0)\n")
    assert main(["crcl", "convert", str(good), "-o", str(tmp_path / "out.txt")]) == 2
    assert capsys.readouterr().err == (f"{tmp_path / 'out.txt'}: error: unknown CRCL file suffix '.txt': "
                                       ".crcl for the text form, .xml for CRCL XML\n")
    assert main(["crcl", "convert", str(tmp_path / "none.crcl"), "-o", str(tmp_path / "o.xml")]) == 2
    assert capsys.readouterr().err == f"{tmp_path / 'none.crcl'}: error: cannot read: No such file or directory\n"
    assert main(["crcl", "convert", str(good), "-o", str(tmp_path / "o.xml"), "--xsd", str(tmp_path / "no.xsd")]) == 2
    assert capsys.readouterr().err == f"{tmp_path / 'no.xsd'}: error: cannot read: No such file or directory\n"
    assert not (tmp_path / "o.xml").exists() and not (tmp_path / "out.txt").exists()
