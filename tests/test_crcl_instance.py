"""CRCL 1.x documents (kb.crcl.instance): NIST's example files read or refused for a stated
reason, everything kitkb writes valid against NIST's schemas by two validators (lxml's libxml2
and xmlschema) and by libxml2's xmllint, round trips between the forms, errors at file:line."""

from __future__ import annotations

import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from kb.core.errors import InputError
from kb.crcl import commands as c
from kb.crcl import instance as inst
from kb.crcl.files import read_file, write_file
from kb.crcl.pose import Pose
from kb.crcl.text import read_text, write_text
from kb.crcl.units import restate
from kb.crcl.xml import _decimal_text, read_xml, write_xml

from shared_data import NIST_DIR

CRCL = NIST_DIR.parent / "crcl"
SCHEMAS = CRCL / "schemas"
INSTANCES = CRCL / "instances"
pytestmark = pytest.mark.skipif(not (SCHEMAS / "CRCLCommandInstance.xsd").exists(),
                                reason="NIST's CRCL 1.x schemas are not beside the checkout")
XMLLINT = shutil.which("xmllint")
DOWN = Pose((0.5, -0.25, 0.125), (1, 0, 0), (0, 0, -1))

#: every NIST example file: what kitkb makes of it (root kind, or the reason it refuses it)
EXPECTED = {
    "commandEndCanon.xml": "command", "commandEndCanonWithNames.xml": "command",
    "commandInitCanon.xml": "command", "commandInitCanonWithNames.xml": "command",
    "commandMoveThroughTo.xml": "command", "commandMoveThroughToWithNames.xml": "command",
    "commandMoveTo.xml": "command", "commandSetTransSpeed1.xml": "command",
    "commandSetTransSpeed1WithNames.xml": "command", "commandSetTransSpeed2.xml": "command",
    "commandSetTransSpeed2WithNames.xml": "command",
    "programAll.xml": "PoseAndSetType", "programAllWithNames.xml": "PoseAndSetType",
    "programExample.xml": "program", "programExampleWithNames.xml": "program",
    "requiredTriggerErrorStatus.xml": "status", "statusExample.xml": "status", "statusExampleGen.xml": "status",
    "statusExampleStr.xml": "status", "statusExampleWithNames.xml": "status", "triggeredStatusExample.xml": "status",
    # a CommandID twice (Reference.md: each command of a session has its own): 5 in the first, 0 in the 7th
    "testForceSensorProgram.xml": "CommandID 5 again", "testForceSensorProgram7.xml": "CommandID 0 again",
    **{f"testForceSensorProgram{n}.xml": "program" for n in (2, 3, 4, 5, 6)},  # guarded moves
}


def _xmllint(data: bytes, kind: str, tmp_path: Path) -> subprocess.CompletedProcess:
    path = tmp_path / f"{kind}.xml"
    path.write_bytes(data)
    return subprocess.run([XMLLINT, "--noout", "--nonet", "--schema", str(SCHEMAS / inst.SCHEMA_FILES[kind]),
                           str(path)], capture_output=True, text=True)


def _valid(data: bytes, kind: str, tmp_path: Path | None = None) -> None:
    """``data`` conforms to the ``kind`` schema by lxml (libxml2), xmlschema and, with a
    ``tmp_path``, xmllint."""
    import xmlschema
    inst.validate(data, kind)
    xmlschema.XMLSchema(str(SCHEMAS / inst.SCHEMA_FILES[kind])).validate(data.decode())
    if tmp_path is not None and XMLLINT:
        done = _xmllint(data, kind, tmp_path)
        assert done.returncode == 0, done.stderr


def _read(path: Path) -> tuple[str, object]:
    data = path.read_bytes()
    if b"<CRCLCommandInstance" in data:
        return "command", inst.read_command_instance(data, path.name)
    if b"<CRCLStatus" in data:
        return "status", inst.read_status(data, path.name)
    return "program", inst.read_program_instance(data, path.name)


def test_every_nist_example_is_read_or_refused_for_its_stated_reason(tmp_path):
    files = sorted(p.name for p in INSTANCES.glob("*.xml"))
    assert files == sorted(EXPECTED) and len(files) == 28  # the suite does not silently shrink
    for name in files:
        expected = EXPECTED[name]
        if expected in ("command", "program", "status"):
            kind, value = _read(INSTANCES / name)
            assert kind == expected, name
            data = {"command": lambda v: inst.write_command_instance(*v),
                    "program": inst.write_program_instance, "status": inst.write_status}[kind](value)
            _valid(data, kind, tmp_path)  # what kitkb writes back conforms
            assert _read_bytes(data, kind) == _read_bytes(data, kind)
        else:
            with pytest.raises(InputError) as err:
                _read(INSTANCES / name)
            assert expected in err.value.message, (name, err.value.message)
            assert err.value.file == name and err.value.line is not None


def _read_bytes(data: bytes, kind: str) -> object:
    return {"command": inst.read_command_instance, "program": inst.read_program_instance,
            "status": inst.read_status}[kind](data)


def test_nist_examples_read_as_kitkb_commands():
    cmd, cid = inst.read_command_instance((INSTANCES / "commandSetTransSpeed2.xml").read_bytes())
    assert isinstance(cmd, c.SetRelativeSpeed) and cid == 123
    cmd, _ = inst.read_command_instance((INSTANCES / "commandMoveThroughTo.xml").read_bytes())
    assert isinstance(cmd, c.MoveThroughTo) and cmd.num_positions >= 2
    status = inst.read_status((INSTANCES / "statusExample.xml").read_bytes())
    assert (status.command_id, status.status_id, status.state) == (1, 1, "CRCL_Working")
    assert status.pose.point == (1.5, 1.0, 1.0) and status.pose.z_axis == (0.0, 0.0, -1.0)
    assert status.gripper == inst.GripperStatus("jaws", "parallel", separation=0.44)
    pairs = inst.read_program_instance((INSTANCES / "programExample.xml").read_bytes())
    assert [i for _, i in pairs] == list(range(1, len(pairs) + 1))
    assert isinstance(pairs[0][0], c.InitCanon) and isinstance(pairs[-1][0], c.EndCanon)


def test_a_command_instance_is_one_small_document_with_its_id():
    data = inst.write_command_instance(c.MoveStraightTo(DOWN), 7)
    assert data.startswith(b'<?xml version="1.0" encoding="UTF-8"?>\n<CRCLCommandInstance')
    assert data.endswith(b"</CRCLCommandInstance>") and data.count(b"\n") == 1 and len(data) < 1024
    assert b'xsi:type="MoveToType"' in data and b"<MoveStraight>true</MoveStraight>" in data
    assert inst.read_command_instance(data) == (c.MoveStraightTo(DOWN), 7)
    _valid(data, "command")


def test_a_status_with_pose_and_gripper_fits_one_read_of_1024_bytes():
    pose = Pose((1.2345678901234567, -2.345678901234567, 0.1 + 0.2), (0.7071067811865476, 0.7071067811865475, 0),
                (1.2246467991473532e-16, 0, -1))
    status = inst.CommandStatus(2 ** 40, 2 ** 41, "CRCL_Done", pose, inst.GripperStatus("part_gripper", separation=0.05),
                                description="moved")
    data = inst.write_status(status)
    assert len(data) < 1024 and data.count(b"\n") == 1
    back = inst.read_status(data)
    assert back.pose.z_axis == (0.0, 0.0, -1.0)  # sin(pi)-sized noise written as 0
    assert back.command_id == 2 ** 40 and back.gripper == status.gripper and back.description == "moved"
    _valid(data, "status")


@pytest.mark.parametrize("command, type_name", [
    (c.OpenGripper(), "SetEndEffectorType"), (c.CloseGripper(), "SetEndEffectorType"),
    (c.SetEndEffector(0.5), "SetEndEffectorType"), (c.SetAbsoluteSpeed(0.25), "SetTransSpeedType"),
    (c.SetRelativeSpeed(50), "SetTransSpeedType"), (c.SetAbsoluteAcceleration(2), "SetTransAccelType"),
    (c.SetRelativeAcceleration(80), "SetTransAccelType"), (c.SetEndPointTolerance(0.002), "SetEndPoseToleranceType"),
    (c.SetEndAngleTolerance(0.01), "SetEndPoseToleranceType"),
    (c.SetIntermediatePointTolerance(0.01), "SetIntermediatePoseToleranceType"),
    (c.SetEndPoseTolerance(c.PoseTolerance(0.1, 0.2, 0.3, 0.4)), "SetEndPoseToleranceType"),
    (c.SetIntermediatePoseTolerance(c.PoseTolerance(z_axis=0.5)), "SetIntermediatePoseToleranceType"),
    (c.StopMotion(1), "StopMotionType"), (c.StopMotion(0), "StopMotionType"), (c.GetStatus(), "GetStatusType"),
    (c.SetForceUnits("pound"), "SetForceUnitsType"), (c.SetTorqueUnits("footPound"), "SetTorqueUnitsType"),
    (c.SetMotionCoordination(True), "SetMotionCoordinationType"), (c.SetRotSpeed(1.5), "SetRotSpeedType"),
    (c.SetRotAccel(0.25, relative=True), "SetRotAccelType"), (c.RunProgram("G0 X1"), "RunProgramType"),
    (c.SetEndEffectorParameters([c.Parameter("force", "12")]), "SetEndEffectorParametersType"),
    (c.SetRobotParameters([c.Parameter("speedOverride", "0.5")]), "SetRobotParametersType"),
    (c.ActuateJoints([c.JointActuation(1, 0.5, speed=1.0), c.JointActuation(3, -0.2, force_control=True, force=2.0)]),
     "ActuateJointsType"),
    (c.ConfigureJointReports(True, [c.JointReport(1, True, False, True)]), "ConfigureJointReportsType"),
    (c.MoveThroughTo([DOWN, DOWN], straight=True), "MoveThroughToType"), (c.Dwell(1.5), "DwellType"),
    (c.Message("<&> ok"), "MessageType"), (c.SetLengthUnits("inch"), "SetLengthUnitsType"),
    (c.SetAngleUnits("degree"), "SetAngleUnitsType"), (c.OpenToolChanger(), "OpenToolChangerType"),
    # the housekeeping commands NIST's clients send, and the rest of CRCLCommands.xsd
    (c.ConfigureStatusReport(True, True, False, True, False, True), "ConfigureStatusReportType"),
    (c.EnableGripper("part_gripper", [c.Parameter("force", "20")]), "EnableGripperType"),
    (c.EnableGripper("jaws"), "EnableGripperType"), (c.DisableGripper("jaws"), "DisableGripperType"),
    (c.EnableSensor("ATINetFT", [c.Parameter("host", "192.168.1.1")]), "EnableSensorType"),
    (c.DisableSensor("ATINetFT"), "DisableSensorType"),
    (c.EnableRobotParameterStatus("speedOverride"), "EnableRobotParameterStatusType"),
    (c.DisableRobotParameterStatus("speedOverride"), "DisableRobotParameterStatusType"),
    (c.SetDefaultJointPositionsTolerances([c.JointTolerance(1, 0.01), c.JointTolerance(6, 0.5)]),
     "SetDefaultJointPositonsTolerancesType"),
    (c.MoveScrew(0.02, 6.28), "MoveScrewType"),
    (c.MoveScrew(0.02, -3.14, start_position=DOWN, axis_point=(0.5, -0.25, 0), axial_distance_free=0.01),
     "MoveScrewType"),
    (c.LoopBlockStart("again and again"), "LoopBlockStartType"), (c.LoopBlockEnd("again and again", 3), "LoopBlockEndType"),
])
def test_every_command_is_written_valid_and_read_back(command, type_name, tmp_path):
    data = inst.write_command_instance(command, 5)
    assert f'xsi:type="{type_name}"'.encode() in data
    _valid(data, "command", tmp_path)
    assert inst.read_command_instance(data) == (command, 5)


@pytest.mark.parametrize("command, why", [
    (c.SetCoordinateFrame("RobotBase"), "SetCoordinateFrame has no CRCL 1.x command"),
    (c.StartObjectScan("part_a_1"), "StartObjectScan has no CRCL 1.x command"),
    (c.MoveThroughTo([DOWN]), "two or more"),
    (c.SetRelativeSpeed(150), "from 0 to 1"),
    (c.Unreadable("Foo(1)", reason="unknown command Foo"), "unreadable line"),
])
def test_what_crcl_1x_cannot_hold_is_refused_at_its_line(command, why):
    program = c.Program([c.InitCanon(), command, c.EndCanon()], source="prog.crcl")
    object.__setattr__(program.commands[1], "line", 2)
    with pytest.raises(InputError) as err:
        inst.write_program_instance(program)
    assert why in err.value.message and err.value.line == 2 and err.value.file == "prog.crcl"
    with pytest.raises(InputError, match="cannot write it as CRCL 1.x"):
        inst.write_command_instance(command, 1)


@pytest.mark.parametrize("command, why", [
    (c.EnableGripper("two words"), "XML name token"), (c.DisableGripper(""), "XML name token"),
    (c.EnableSensor(" padded "), "white space"), (c.EnableRobotParameterStatus("a  b"), "white space"),
    (c.LoopBlockEnd("l", 2 ** 31), "32-bit integer"),
])
def test_names_and_counts_crcl_1x_cannot_hold_are_refused(command, why):
    with pytest.raises(InputError, match=why):
        inst.write_command_instance(command, 1)


def test_the_housekeeping_commands_of_nists_clients_read_with_their_command_ids():
    pairs = dict((i, x) for x, i in inst.read_program_instance(
        (INSTANCES / "testForceSensorProgram.xml").read_bytes().replace(b"<CommandID>5</CommandID>\n        <MoveS",
                                                                        b"<CommandID>8</CommandID>\n        <MoveS")))
    assert pairs[5] == c.ConfigureStatusReport(True, True, True, True, True, True)
    assert pairs[6] == c.EnableSensor("ATINetFT", (c.Parameter("host", "192.168.1.1"),))
    assert isinstance(pairs[8], c.MoveStraightTo)
    doc = (b'<CRCLCommandInstance xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance"><CRCLCommand '
           b'xsi:type="EnableGripperType"><Name>g</Name><CommandID>12</CommandID><GripperName> jaws </GripperName>'
           b'</CRCLCommand></CRCLCommandInstance>')
    assert inst.read_command_instance(doc) == (c.EnableGripper("jaws"), 12)
    with pytest.raises(InputError, match="holds CommandID, GripperName, found CommandID, GripperName, GripperOption"):
        inst.read_command_instance(doc.replace(b"EnableGripperType", b"DisableGripperType").replace(
            b"</GripperName>", b"</GripperName><GripperOption><ParameterName>a</ParameterName>"
                               b"<ParameterValue>b</ParameterValue></GripperOption>"))
    with pytest.raises(InputError, match="AxialDistanceScrew, Turn; found CommandID, Turn"):
        inst.read_command_instance(doc.replace(b"EnableGripperType", b"MoveScrewType").replace(
            b"<GripperName> jaws </GripperName>", b"<Turn>1</Turn>"))


def test_guards_are_read_on_any_command_and_written_back_after_the_command_id(tmp_path):
    pairs = inst.read_program_instance((INSTANCES / "testForceSensorProgram2.xml").read_bytes())
    guarded = [x for x, _ in pairs if isinstance(x, c.Guarded)]
    assert len(guarded) == 1 and isinstance(guarded[0].command, c.MoveStraightTo)
    assert guarded[0].guards == (c.Guard("ATINetFT", "DECREASE_BEYOND_LIMIT", -1.0, recheck_us=20,
                                         name="ATINetFTFz"),)
    full = c.Guard("ft", "OVER_MAX", 12.5, sub_field="Fz", recheck_us=10, check_count=3, last_check_time=99,
                   last_check_value=1.25, require_trigger=True, error_on_trigger=False)
    for command in (c.Guarded(c.Dwell(2.0), [full, c.Guard("ft", "UNDER_MIN", -1)]),
                    c.Guarded(c.SetEndEffector(0.5), [full])):
        data = inst.write_command_instance(command, 4)
        _valid(data, "command", tmp_path)
        assert inst.read_command_instance(data) == (command, 4)
    program = [c.Guarded(c.InitCanon(), [full]), c.MoveTo(DOWN), c.Guarded(c.EndCanon(), [full])]
    data = inst.write_program_instance(program)
    _valid(data, "program", tmp_path)
    assert [x for x, _ in inst.read_program_instance(data)] == program
    with pytest.raises(ValueError, match="limit_type must be one of"):
        c.Guard("ft", "SIDEWAYS", 1)
    with pytest.raises(ValueError, match="without guards"):
        c.Guarded(c.Guarded(c.Dwell(1), [full]), [full])
    misplaced = inst.write_command_instance(c.Guarded(c.Dwell(1.0), [full]), 4).replace(
        b"<DwellTime>1</DwellTime>", b"").replace(b"<CommandID>4</CommandID>", b"<CommandID>4</CommandID>"
                                                  b"<DwellTime>1</DwellTime>")
    with pytest.raises(InputError, match="holds CommandID, DwellTime, found CommandID, DwellTime, Guard"):
        inst.read_command_instance(misplaced)


def test_a_status_with_settings_reads_and_writes_back_valid(tmp_path):
    read = inst.read_status((INSTANCES / "triggeredStatusExample.xml").read_bytes())
    assert read.settings == inst.SettingsStatus("millimeter", "degree", 1.0, 10.0)
    status = inst.CommandStatus(3, 9, "CRCL_Working", DOWN, inst.GripperStatus("jaws", separation=0.02),
                                settings=inst.SettingsStatus("inch", "radian", None, 39.37))
    data = inst.write_status(status)
    _valid(data, "status", tmp_path)
    assert inst.read_status(data) == status and len(data) < 1024
    with pytest.raises(ValueError, match="length_unit must be one of"):
        inst.SettingsStatus("furlong")


def test_an_end_canon_with_a_reason_is_refused():
    with pytest.raises(InputError, match=r"EndCanon\(2\): CRCL 1.x's EndCanon has no reason"):
        inst.write_command_instance(c.EndCanon(2), 9)


@pytest.mark.parametrize("document, message, line", [
    (b"<CRCLCommandInstance>\n<CRCLCommand>\n</CRCLCommand></CRCLCommandInstance>", "starts with its <CommandID>", 2),
    (b'<CRCLCommandInstance xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance">\n'
     b'<CRCLCommand xsi:type="FlyType"><CommandID>1</CommandID></CRCLCommand></CRCLCommandInstance>',
     "FlyType is not a command of CRCLCommands.xsd", 2),
    (b'<CRCLCommandInstance xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance">\n<CRCLCommand '
     b'xsi:type="DwellType">\n<CommandID>x</CommandID><DwellTime>1</DwellTime></CRCLCommand></CRCLCommandInstance>',
     "<CommandID> must be an integer", 3),
    (b"<CRCLStatus><CommandStatus><CommandID>1</CommandID></CommandStatus></CRCLStatus>", "lacks <StatusID>", 1),
    (b"<CRCLCommandInstance>", "XML syntax error", 1),
    (b'<!DOCTYPE x [<!ENTITY e "e">]>\n<CRCLCommandInstance/>', "DOCTYPE is not allowed", 1),
])
def test_bad_documents_are_one_line_errors_at_their_line(document, message, line):
    reader = inst.read_status if b"<CRCLStatus" in document else inst.read_command_instance
    with pytest.raises(InputError) as err:
        reader(document, "wire")
    assert message in err.value.message and err.value.line == line and err.value.file == "wire"
    assert "\n" not in str(err.value)


def test_a_program_keeps_its_ids_and_refuses_a_repeated_one():
    pairs = [(c.InitCanon(), 10), (c.Dwell(1), 20), (c.EndCanon(), 30)]
    data = inst.write_program_instance(pairs)
    assert inst.read_program_instance(data) == pairs
    repeated = data.replace(b"<CommandID>20</CommandID>", b"<CommandID>10</CommandID>")
    with pytest.raises(InputError, match="CommandID 10 again"):
        inst.read_program_instance(repeated)
    with pytest.raises(InputError, match="CommandID 3 again"):
        inst.write_program_instance([(c.InitCanon(), 3), (c.EndCanon(), 3)])
    # ids in any order (NIST's testForceSensorProgram5 has 3211 before 0), each kept
    out_of_order = [(c.InitCanon(), 3211), (c.Dwell(1.0), 0), c.Dwell(2.0), (c.EndCanon(), 7)]
    assert inst.read_program_instance(inst.write_program_instance(out_of_order)) == [
        (c.InitCanon(), 3211), (c.Dwell(1.0), 0), (c.Dwell(2.0), 3212), (c.EndCanon(), 7)]


def test_numbers_are_short_without_noise_and_xmllint_accepts_them(tmp_path):
    assert [inst.number_text(x) for x in (5.0, -0.0, 1e-13, 0.1 + 0.2, 1e-7, 1e30)] == [
        "5", "0", "0", "0.30000000000000004", "0.0000001", "1e+30"]
    poses = [Pose((x, -x, 1e16), (1, 1e-17, 0), (0, 0, -1)) for x in (1.2345678901234567e-11, 123456789.12345679)]
    data = inst.write_program_instance([c.InitCanon(), c.MoveThroughTo(poses), c.EndCanon()])
    _valid(data, "program", tmp_path)
    xml2014 = write_xml(c.Program([c.InitCanon(), c.MoveThroughTo(poses), c.EndCanon()]))
    assert not re.search(rb">[-+0-9.]*[eE]", xml2014)  # no exponent in an xs:decimal
    if XMLLINT:
        path = tmp_path / "p2014.xml"
        path.write_bytes(xml2014)
        done = subprocess.run([XMLLINT, "--noout", "--nonet", "--schema", str(NIST_DIR / "CRCL.xsd"), str(path)],
                              capture_output=True, text=True)
        assert done.returncode == 0, done.stderr


def test_xmllint_is_present():
    if XMLLINT is None:
        pytest.skip("xmllint is absent: scripts/setup.sh installs libxml2-utils (CI has it)")
    assert subprocess.run([XMLLINT, "--version"], capture_output=True).returncode == 0


# --- forms and files ------------------------------------------------------------------------------

def test_nist_2014_program_as_1x_and_back_keeps_its_commands(tmp_path):
    early = read_file(NIST_DIR / "commands1.xml")
    write_file(early, tmp_path / "p1x.xml", xml_form="1.x")
    data = (tmp_path / "p1x.xml").read_bytes()
    _valid(data, "program", tmp_path)
    back = read_file(tmp_path / "p1x.xml")
    assert back.units == c.CRCL1_UNITS
    # the 2014 program is in the paper's units: its angle unit (degree) said after InitCanon
    assert back.commands == restate(early, c.CRCL1_UNITS).commands
    assert back[1] == c.SetAngleUnits("degree")
    write_file(back, tmp_path / "again.xml", xml_form="2014")
    again = read_file(tmp_path / "again.xml")
    assert [x for x in again.commands if not isinstance(x, (c.SetLengthUnits, c.SetAngleUnits))] == \
        [x for x in early.commands if not isinstance(x, (c.SetLengthUnits, c.SetAngleUnits))]


def test_cli_converts_to_a_command_instance_and_refuses_several_commands(tmp_path):
    one = tmp_path / "one.xml"
    one.write_bytes(inst.write_command_instance(c.Dwell(2), 4))
    out = tmp_path / "one.crcl"
    done = subprocess.run([sys.executable, "-m", "kb.cli", "crcl", "convert", str(one), "-o", str(out)],
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert out.read_text() == "Dwell(2)\n"
    back = tmp_path / "back.xml"
    done = subprocess.run([sys.executable, "-m", "kb.cli", "crcl", "convert", str(out), "-o", str(back),
                           "--xml-form", "command"], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert inst.read_command_instance(back.read_bytes()) == (c.Dwell(2), 1)
    done = subprocess.run([sys.executable, "-m", "kb.cli", "crcl", "convert", str(NIST_DIR / "commands1.xml"), "-o",
                           str(tmp_path / "x.xml"), "--xml-form", "command"], capture_output=True, text=True)
    assert done.returncode == 2 and "holds one command" in done.stderr and "Traceback" not in done.stderr
    assert not (tmp_path / "x.xml").exists()


# --- round trips over random programs -------------------------------------------------------------

_num = st.floats(allow_nan=False, allow_infinity=False, min_value=-1e9, max_value=1e9).filter(
    lambda x: x == 0 or abs(x) >= inst.TINY)
_vec = st.tuples(_num, _num, _num)
_pose = st.builds(Pose, point=_vec, x_axis=_vec, z_axis=_vec)
_fraction = st.floats(0, 1).filter(lambda x: x == 0 or x >= inst.TINY)
_text = st.text(st.characters(codec="utf-8", exclude_categories=("Cs", "Cc", "Cn")), max_size=12)
_token = st.from_regex(r"[A-Za-z][A-Za-z0-9_]{0,8}", fullmatch=True)
_MIDDLE = st.one_of(
    st.builds(c.Message, _text), st.builds(c.Dwell, _num), st.builds(c.MoveTo, _pose),
    st.builds(c.MoveStraightTo, _pose),
    st.builds(c.MoveThroughTo, st.lists(_pose, min_size=2, max_size=3), straight=st.booleans()),
    st.sampled_from([c.OpenGripper(), c.CloseGripper(), c.OpenToolChanger(), c.CloseToolChanger(), c.GetStatus(),
                     c.StopMotion(1), c.StopMotion(0)]),
    st.builds(c.SetEndEffector, _fraction.filter(lambda x: inst.TINY <= x < 1)),
    st.builds(c.SetLengthUnits, st.sampled_from(c.LENGTH_UNITS)), st.builds(c.SetAngleUnits, st.sampled_from(c.ANGLE_UNITS)),
    st.builds(c.SetForceUnits, st.sampled_from(c.FORCE_UNITS)), st.builds(c.SetTorqueUnits, st.sampled_from(c.TORQUE_UNITS)),
    *(st.builds(cls, _num) for cls in (c.SetAbsoluteSpeed, c.SetAbsoluteAcceleration, c.SetEndAngleTolerance,
                                       c.SetEndPointTolerance, c.SetIntermediatePointTolerance)),
    st.builds(c.SetRotSpeed, _num), st.builds(c.SetRotAccel, _fraction, relative=st.just(True)),
    st.builds(c.SetMotionCoordination, st.booleans()), st.builds(c.RunProgram, _text),
    st.builds(c.SetRobotParameters, st.lists(st.builds(c.Parameter, _token, _token), min_size=1, max_size=2)),
    st.builds(c.ConfigureStatusReport, *[st.booleans()] * 6),
    st.builds(c.EnableGripper, _token, st.lists(st.builds(c.Parameter, _token, _token), max_size=2)),
    st.builds(c.DisableGripper, _token), st.builds(c.DisableSensor, _token),
    st.builds(c.EnableSensor, _token, st.lists(st.builds(c.Parameter, _token, _token), max_size=2)),
    st.builds(c.EnableRobotParameterStatus, _token), st.builds(c.DisableRobotParameterStatus, _token),
    st.builds(c.SetDefaultJointPositionsTolerances, st.lists(st.builds(c.JointTolerance, st.integers(1, 12), _num),
                                                             min_size=1, max_size=3)),
    st.builds(c.MoveScrew, _num, _num, start_position=st.none() | _pose, axis_point=st.none() | _vec,
              axial_distance_free=st.none() | _num),
    st.builds(c.LoopBlockStart, _text), st.builds(c.LoopBlockEnd, _text, st.integers(-2 ** 31, 2 ** 31 - 1)),
    st.builds(c.Guarded, st.builds(c.MoveTo, _pose) | st.builds(c.Dwell, _num), st.lists(st.builds(
        c.Guard, _token, st.sampled_from(c.GUARD_LIMITS), _num, sub_field=st.none() | _token,
        recheck_us=st.none() | st.integers(0, 2 ** 40), require_trigger=st.none() | st.booleans(),
        name=st.none() | _token), min_size=1, max_size=2)),
)


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(_MIDDLE, max_size=6), st.integers(1, 2 ** 40))
def test_any_program_round_trips_through_crcl_1x_and_validates(middle, first_id):
    commands = [c.InitCanon(), *middle, c.EndCanon()]
    pairs = [(x, first_id + i) for i, x in enumerate(commands)]
    data = inst.write_program_instance(pairs)
    inst.validate(data, "program")
    assert inst.read_program_instance(data) == pairs
    for command, command_id in pairs:
        one = inst.write_command_instance(command, command_id)
        assert inst.read_command_instance(one) == (command, command_id)


_num = _num.filter(lambda x: float(_decimal_text(x)) == x)  # what 2014's xs:decimal keeps exactly (24 digits)
_vec = st.tuples(_num, _num, _num)
_pose = st.builds(Pose, point=_vec, x_axis=_vec, z_axis=_vec)
_PAPER_MIDDLE = st.one_of(
    st.builds(c.Dwell, _num), st.builds(c.MoveTo, _pose), st.builds(c.MoveStraightTo, _pose),
    st.builds(c.MoveThroughTo, st.lists(_pose, min_size=2, max_size=3)),
    st.sampled_from([c.OpenGripper(), c.CloseGripper(), c.OpenToolChanger(), c.CloseToolChanger()]),
    st.builds(c.SetLengthUnits, st.sampled_from(c.LENGTH_UNITS)), st.builds(c.SetAngleUnits, st.sampled_from(c.ANGLE_UNITS)),
    st.builds(c.SetAbsoluteSpeed, _num), st.builds(c.SetEndPointTolerance, _num),
    st.builds(c.SetRelativeSpeed, st.sampled_from([0.0, 10.0, 50.0, 75.5, 100.0])),
)


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(_PAPER_MIDDLE, min_size=1, max_size=6))
def test_paper_text_through_1x_and_2014_means_the_same(middle):
    text = write_text(c.Program([c.InitCanon(), *middle, c.EndCanon()]), style="paper")
    paper = read_text(text)
    crcl1 = read_xml(inst.write_program_instance(restate(paper, c.CRCL1_UNITS)))
    # the units the paper's program meant, said after InitCanon where CRCL 1.x resets to others
    assert crcl1.commands == restate(paper, c.CRCL1_UNITS).commands
    again = read_text(write_text(restate(crcl1, c.PAPER_UNITS), style="paper"))
    assert [x for x in again if not isinstance(x, (c.SetLengthUnits, c.SetAngleUnits))] == \
        [x for x in paper if not isinstance(x, (c.SetLengthUnits, c.SetAngleUnits))]
    assert restate(again, c.CRCL1_UNITS).commands == crcl1.commands  # a fixed point after one trip
    early = read_xml(write_xml(restate(crcl1, c.PAPER_UNITS)))
    assert early.commands == again.commands


def test_every_command_type_of_the_schema_is_read():
    from lxml import etree
    xs = "{http://www.w3.org/2001/XMLSchema}"
    tree = etree.parse(str(SCHEMAS / "CRCLCommands.xsd"))
    bases = {t.get("name"): t.find(f".//{xs}extension").get("base")
             for t in tree.getroot().iter(f"{xs}complexType") if t.find(f".//{xs}extension") is not None}

    def command(name: str) -> bool:
        while name in bases:
            name = bases[name]
            if name == "CRCLCommandType":
                return True
        return False

    in_schema = {n for n in bases if command(n) and n != "MiddleCommandType"}
    assert len(in_schema) == 38 and in_schema == inst.COMMAND_TYPES


def test_a_document_given_as_text_with_its_declaration_reads():
    text = inst.write_command_instance(c.Message("é ok"), 3).decode().replace("UTF-8", "utf-8")
    assert inst.read_command_instance(text) == (c.Message("é ok"), 3)
