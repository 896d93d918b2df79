"""CRCL 1.x documents, as NIST publishes CRCL today (``../shared/crcl``: doc/Reference.md and the
schemas CRCLCommandInstance.xsd, CRCLProgramInstance.xsd, CRCLStatus.xsd, CRCLCommands.xsd,
DataPrimitives.xsd): one command sent to a controller (``CRCLCommandInstance``), a whole program
(``CRCLProgram`` of CRCLProgramInstance.xsd: ``InitCanon``, ``MiddleCommand xsi:type=...``,
``EndCanon``) and the controller's answer (``CRCLStatus``), each command with its ``CommandID``.

Reading and writing map CRCL 1.x onto kitkb's commands (:mod:`kb.crcl.commands`; the table is in
docs/crcl.md): ``MoveTo`` with ``MoveStraight`` true is :class:`MoveStraightTo`; ``SetEndEffector``
1 and 0 are :class:`OpenGripper` and :class:`CloseGripper`; ``SetTransSpeed`` /
``SetTransAccel`` are the paper's absolute or relative speed and acceleration (a relative one
is a fraction in CRCL 1.x, a percentage in the paper); ``SetEndPoseTolerance`` /
``SetIntermediatePoseTolerance`` with equal point (or, for the end, axis) tolerances are the
paper's point and angle tolerances; ``StopMotion`` Immediate is an emergency stop, Normal a
graceful one. Every command of CRCLCommands.xsd is read (the housekeeping ones, ``MoveScrew``
and the loop blocks too: what a controller cannot do it answers with ``CRCL_Error``); what cannot
be represented (a ``Guard``, a ``Fast`` stop, a waypoint with settings ...) is an
:class:`~kb.core.errors.InputError` naming it at its line;
what CRCL 1.x cannot hold (``SetCoordinateFrame``, ``StartObjectScan``, ``StopObjectScan``,
``EndCanon`` with a reason, an unreadable line) likewise when written. Optional ``Name``
elements are skipped.

Documents are parsed by :func:`kb.crcl.xml.hardened_parser` (no DTD, no entity, no network).
Numbers are written short (the shortest text that reads back as the same float; a magnitude
under :data:`TINY` as 0, sin(pi)-sized noise; no exponent unless the number needs more than
24 digits without one), so libxml2's xmllint accepts every document kitkb writes.
"""

from __future__ import annotations

import os
import re
from dataclasses import dataclass, field
from decimal import Decimal
from pathlib import Path
from typing import Any, Callable, Iterable, Sequence

from lxml import etree

from kb.core.errors import InputError
from kb.crcl import commands as c
from kb.crcl.pose import Pose
from kb.crcl.xmlbase import _XML_CHARS, schema
from kb.crcl.xmlbase import _parse as _parse_bytes

XSI = "http://www.w3.org/2001/XMLSchema-instance"
_TYPE = f"{{{XSI}}}type"
_NSMAP = {"xsi": XSI}
#: Magnitudes below this are written as 0 (the noise of sin(pi), cos(pi/2) ...).
TINY = 1e-12
#: The command states of CRCLStatus.xsd's ``CommandStateEnumType``.
STATES = ("CRCL_Working", "CRCL_Done", "CRCL_Error", "CRCL_Ready")
#: The schema files of the three documents (in :func:`default_schemas`).
SCHEMA_FILES = {"command": "CRCLCommandInstance.xsd", "program": "CRCLProgramInstance.xsd",
                "status": "CRCLStatus.xsd"}
_REPO = Path(__file__).resolve().parents[2]


# --- status -----------------------------------------------------------------------------------

@dataclass(frozen=True)
class GripperStatus:
    """CRCLStatus.xsd's ``GripperStatus``: ``kind`` ``parallel`` (``separation`` between the
    jaws, length units), ``vacuum`` (``powered``) or ``three_finger`` (``fingers``: positions,
    0 closed to 1 open, each optional); ``holding`` whether it holds an object (optional)."""

    name: str
    kind: str = "parallel"
    separation: float | None = None
    powered: bool | None = None
    fingers: tuple[float | None, float | None, float | None] = (None, None, None)
    holding: bool | None = None

    def __post_init__(self) -> None:
        if self.kind not in _GRIPPER_TYPES:
            raise ValueError(f"GripperStatus.kind must be one of {', '.join(_GRIPPER_TYPES)}, not {self.kind!r}")
        if not re.fullmatch(r"[\w.:-]+", self.name):
            raise ValueError(f"GripperStatus.name must be an XML name token, not {self.name!r}")
        object.__setattr__(self, "fingers", tuple(self.fingers))


@dataclass(frozen=True)
class JointStatus:
    """One joint of a status: its number and, each optional, position, torque or force, velocity."""

    number: int
    position: float | None = None
    torque_or_force: float | None = None
    velocity: float | None = None


@dataclass(frozen=True)
class SettingsStatus:
    """The part of CRCLStatus.xsd's ``SettingsStatus`` kitkb reads and writes: the length and
    angle unit names in force, the end effector's setting (0 closed to 1 open) and the absolute
    translational speed (length units per second), each optional."""

    length_unit: str | None = None
    angle_unit: str | None = None
    end_effector: float | None = None
    speed: float | None = None

    def __post_init__(self) -> None:
        for attr, allowed in (("length_unit", c.LENGTH_UNITS), ("angle_unit", c.ANGLE_UNITS)):
            value = getattr(self, attr)
            if value is not None and value not in allowed:
                raise ValueError(f"SettingsStatus.{attr} must be one of {', '.join(allowed)}, not {value!r}")
        if self.end_effector is not None and not 0.0 <= self.end_effector <= 1.0:
            raise ValueError(f"SettingsStatus.end_effector must be a fraction from 0 to 1, not {self.end_effector!r}")


@dataclass(frozen=True)
class CommandStatus:
    """A ``CRCLStatus`` document: the ``command_id`` it is about, its own ``status_id``,
    ``state`` (one of :data:`STATES`), and optionally the pose of the controlled point, the
    gripper, joint statuses, ``settings`` (:class:`SettingsStatus`: its units, end effector
    setting and speed; its other elements are not read) and ``description``
    (``StateDescription``). The status's sensors and guards are not read."""

    command_id: int
    status_id: int
    state: str
    pose: Pose | None = None
    gripper: GripperStatus | None = None
    description: str = ""
    joints: tuple[JointStatus, ...] = field(default=())
    settings: SettingsStatus | None = None

    def __post_init__(self) -> None:
        if self.state not in STATES:
            raise ValueError(f"CommandStatus.state must be one of {', '.join(STATES)}, not {self.state!r}")
        object.__setattr__(self, "joints", tuple(self.joints))


_GRIPPER_TYPES = {"parallel": "ParallelGripperStatusType", "vacuum": "VacuumGripperStatusType",
                  "three_finger": "ThreeFingerGripperStatusType"}


# --- schemas ----------------------------------------------------------------------------------

def default_schemas() -> Path | None:
    """The folder of NIST's CRCL 1.x schemas: ``$KITKB_CRCL_DIR/schemas`` (or that folder
    itself), else ``../shared/crcl/schemas`` beside the checkout; None when absent."""
    folders = []
    if os.environ.get("KITKB_CRCL_DIR"):
        folders += [Path(os.environ["KITKB_CRCL_DIR"]) / "schemas", Path(os.environ["KITKB_CRCL_DIR"])]
    folders.append(_REPO.parent / "shared" / "crcl" / "schemas")
    return next((f for f in folders if (f / SCHEMA_FILES["command"]).is_file()), None)


_SCHEMAS: dict[tuple[str, str], etree.XMLSchema] = {}


def instance_schema(kind: str, folder: str | os.PathLike[str] | None = None) -> etree.XMLSchema:
    """The schema of ``kind`` (``command``, ``program``, ``status``) from ``folder`` (default
    :func:`default_schemas`), loaded once; missing is an InputError."""
    found = Path(folder) if folder is not None else default_schemas()
    if found is None:
        raise InputError("the CRCL 1.x schemas were not found (looked in $KITKB_CRCL_DIR and "
                         "../shared/crcl/schemas beside the checkout)")
    key = (kind, str(found.resolve()))
    if key not in _SCHEMAS:
        _SCHEMAS[key] = schema(found / SCHEMA_FILES[kind])
    return _SCHEMAS[key]


def validate(data: bytes, kind: str, source: str = "<crcl>", folder: str | os.PathLike[str] | None = None) -> None:
    """InputError at the first line where ``data`` breaks the ``kind`` schema."""
    xsd = instance_schema(kind, folder)
    tree = _parse(data, source)
    if not xsd.validate(tree):
        errors = list(xsd.error_log)
        more = f" (and {len(errors) - 1} more)" if len(errors) > 1 else ""
        raise InputError(f"does not conform to {SCHEMA_FILES[kind]}: {errors[0].message}{more}",
                         source, errors[0].line)


# --- numbers ----------------------------------------------------------------------------------

def number_text(x: float) -> str:
    """``x`` as an ``xs:double`` (and ``xs:decimal`` where it can be one): the shortest text
    that reads back as ``x``, 0 for a magnitude under :data:`TINY`, ``5`` for 5.0, no
    exponent unless more than 24 digits would be needed without one."""
    x = float(x)
    if abs(x) < TINY:
        return "0"
    text = repr(x)
    if "e" in text or "E" in text:
        fixed = format(Decimal(text), "f")
        if sum(ch.isdigit() for ch in fixed) <= 24:
            text = fixed
    return text[:-2] if text.endswith(".0") else text


_DOUBLE = re.compile(r"\s*[+-]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][+-]?\d+)?\s*|\s*(?:-?INF|NaN)\s*")
_INT = re.compile(r"\s*[+-]?\d{1,19}\s*")


# --- writing ----------------------------------------------------------------------------------

class _Unwritable(Exception):
    """A command CRCL 1.x cannot hold; the message says why."""


def unwritable(command: c.Command) -> str | None:
    """Why ``command`` cannot be written as CRCL 1.x (None when it can)."""
    try:
        _element(command, 1, "CRCLCommand")
    except _Unwritable as exc:
        return str(exc)
    return None


def write_command_instance(command: c.Command, command_id: int, *, pretty: bool = False,
                           program_file: str | None = None, program_index: int | None = None,
                           program_length: int | None = None) -> bytes:
    """``command`` as one complete ``CRCLCommandInstance`` document (UTF-8, XML declaration,
    one line unless ``pretty``) with ``command_id``; a command CRCL 1.x cannot hold is an
    :class:`~kb.core.errors.InputError` at its line."""
    root = etree.Element("CRCLCommandInstance", nsmap=_NSMAP)
    root.append(_checked_element(command, command_id, "CRCLCommand", None))
    for tag, value in (("ProgramFile", program_file), ("ProgramIndex", program_index),
                       ("ProgramLength", program_length)):
        if value is not None:
            _sub(root, tag, _string(value) if isinstance(value, str) else str(int(value)))
    return _document(root, pretty)


def write_program_instance(commands: c.Program | Iterable[c.Command | tuple[c.Command, int]], *,
                           name: str | None = None, pretty: bool = True) -> bytes:
    """A ``CRCLProgram`` of CRCLProgramInstance.xsd: InitCanon first, EndCanon last, the
    rest ``MiddleCommand``s. Commands given as (command, id) keep their ids (each its own, in
    any order, as Reference.md asks and NIST's examples have them); others are numbered from 1
    (after the largest id given so far). A program of another
    form with other units (:attr:`~kb.crcl.commands.Program.units`) should first pass
    :func:`kb.crcl.units.restate` (:func:`kb.crcl.files.write_file` does)."""
    source = commands.source if isinstance(commands, c.Program) else None
    pairs = _numbered(commands, source)
    if len(pairs) < 2:
        raise InputError("a CRCL 1.x program needs InitCanon, then EndCanon (at least two commands)", source,
                         pairs[0][0].line if pairs else None)
    root = etree.Element("CRCLProgram", nsmap=_NSMAP)
    if name:
        _sub(root, "Name", _string(name))
    last = len(pairs) - 1
    for i, (command, command_id) in enumerate(pairs):
        problem = _misplaced(c.unguarded(command), i == 0, i == last)
        if problem:
            raise InputError(problem, source, command.line)
        tag = "InitCanon" if i == 0 else "EndCanon" if i == last else "MiddleCommand"
        root.append(_checked_element(command, command_id, tag, source))
    return _document(root, pretty)


def write_status(status: CommandStatus, *, pretty: bool = False) -> bytes:
    """``status`` as one complete ``CRCLStatus`` document (UTF-8, XML declaration, one line
    unless ``pretty``); small: a status with a pose and a gripper is well under 1,024 bytes."""
    root = etree.Element("CRCLStatus", nsmap=_NSMAP)
    cs = _sub(root, "CommandStatus")
    _sub(cs, "CommandID", str(int(status.command_id)))
    _sub(cs, "StatusID", str(int(status.status_id)))
    _sub(cs, "CommandState", status.state)
    if status.description:
        _sub(cs, "StateDescription", _string(status.description))
    if status.joints:
        js = _sub(root, "JointStatuses")
        for j in status.joints:
            el = _sub(js, "JointStatus")
            _sub(el, "JointNumber", str(int(j.number)))
            for tag, value in (("JointPosition", j.position), ("JointTorqueOrForce", j.torque_or_force),
                               ("JointVelocity", j.velocity)):
                if value is not None:
                    _sub(el, tag, number_text(value))
    if status.pose is not None:
        _write_pose(_sub(_sub(root, "PoseStatus"), "Pose"), status.pose)
    if status.gripper is not None:
        _write_gripper(root, status.gripper)
    if status.settings is not None:
        _write_settings(_sub(root, "SettingsStatus"), status.settings)
    return _document(root, pretty)


def _write_settings(el: Any, st: SettingsStatus) -> None:
    # in SettingsStatusType's order: AngleUnitName, EndEffectorSetting, LengthUnitName, TransSpeedAbsolute
    if st.angle_unit is not None:
        _sub(el, "AngleUnitName", st.angle_unit)
    if st.end_effector is not None:
        _sub(el, "EndEffectorSetting", number_text(st.end_effector))
    if st.length_unit is not None:
        _sub(el, "LengthUnitName", st.length_unit)
    if st.speed is not None:
        _sub(_sub(el, "TransSpeedAbsolute"), "Setting", number_text(st.speed))


def _read_settings(el: Any, source: str) -> SettingsStatus:
    values: dict[str, Any] = {}
    for ch in _named(el, source):
        if ch.tag in ("AngleUnitName", "LengthUnitName"):
            values["angle_unit" if ch.tag == "AngleUnitName" else "length_unit"] = _text(ch, source).strip()
        elif ch.tag == "EndEffectorSetting":
            values["end_effector"] = _double(ch, source)
        elif ch.tag == "TransSpeedAbsolute":
            values["speed"] = _double(_expect(ch, ["Setting"], source)[0], source)
    return _made(SettingsStatus, el, source, **values)


def _write_gripper(root: Any, g: GripperStatus) -> None:
    el = _sub(root, "GripperStatus")
    el.set(_TYPE, _GRIPPER_TYPES[g.kind])
    _sub(el, "GripperName", g.name)
    if g.holding is not None:
        _sub(el, "HoldingObject", _bool(g.holding))
    if g.kind == "parallel":
        _sub(el, "Separation", number_text(g.separation or 0.0))
    elif g.kind == "vacuum":
        _sub(el, "IsPowered", _bool(bool(g.powered)))
    else:
        for i, value in enumerate(g.fingers, 1):
            if value is not None:
                _sub(el, f"Finger{i}Position", number_text(value))


def _numbered(commands: c.Program | Iterable[c.Command | tuple[c.Command, int]],
              source: str | None) -> list[tuple[c.Command, int]]:
    pairs: list[tuple[c.Command, int]] = []
    largest, seen = 0, set()
    for item in commands:
        command, command_id = item if isinstance(item, tuple) else (item, largest + 1)
        if command_id in seen:
            raise InputError(f"CommandID {command_id} again: each command of a program has its own "
                             "(Reference.md)", source, command.line)
        seen.add(command_id)
        pairs.append((command, command_id))
        largest = max(largest, command_id) if isinstance(command_id, int) else largest
    return pairs


def _misplaced(command: c.Command, first: bool, last: bool) -> str | None:
    kind = type(command).__name__
    if first and not isinstance(command, c.InitCanon):
        return f"a CRCL 1.x program starts with InitCanon, not {kind}"
    if last and not isinstance(command, c.EndCanon):
        return f"a CRCL 1.x program ends with EndCanon, not {kind}"
    if isinstance(command, (c.InitCanon, c.EndCanon)) and not (first or last):
        return f"{kind} only as the {'first' if isinstance(command, c.InitCanon) else 'last'} command of a CRCL 1.x program"
    return None


_DECLARATION = b'<?xml version="1.0" encoding="UTF-8"?>\n'


def _document(root: Any, pretty: bool) -> bytes:
    body = etree.tostring(root, encoding="UTF-8", xml_declaration=False, pretty_print=pretty)
    return _DECLARATION + body


def _sub(parent: Any, tag: str, text: str | None = None) -> Any:
    el = etree.SubElement(parent, tag)
    if text is not None:
        el.text = text
    return el


def _bool(value: bool) -> str:
    return "true" if value else "false"


def _string(text: str) -> str:
    """``text`` with the characters XML 1.0 cannot hold replaced (U+FFFD)."""
    return _XML_CHARS.sub("\ufffd", text)


def _checked_element(command: c.Command, command_id: int, tag: str, source: str | None) -> Any:
    if isinstance(command_id, bool) or not isinstance(command_id, int) or not 0 <= command_id < 2 ** 63:
        raise InputError(f"CommandID must be an integer from 0 to 2**63-1, not {command_id!r}", source,
                         command.line)
    try:
        return _element(command, command_id, tag)
    except _Unwritable as exc:
        raise InputError(f"{exc}; cannot write it as CRCL 1.x", source, command.line) from None


def _element(command: c.Command, command_id: int, tag: str) -> Any:
    if isinstance(command, c.Guarded):
        el = _element(command.command, command_id, tag)
        for n, guard in enumerate(command.guards, 1):
            el.insert(n, _guard_element(guard))  # after the CommandID
        return el
    writer = _WRITERS.get(type(command))
    if writer is None:
        if isinstance(command, c.Unreadable):
            raise _Unwritable(f"unreadable line {command.text.strip().splitlines()[0]!r} ({command.reason})")
        raise _Unwritable(f"{type(command).__name__} has no CRCL 1.x command")
    type_name, fill = writer
    el = etree.Element(tag)
    if tag not in ("InitCanon", "EndCanon"):
        el.set(_TYPE, type_name)
    _sub(el, "CommandID", str(command_id))
    fill(el, command)
    return el


def _guard_element(g: c.Guard) -> Any:
    el = etree.Element("Guard")
    if g.name is not None:
        _sub(el, "Name", _token(g.name, "Guard's Name"))
    _sub(el, "SensorID", _token(g.sensor_id, "SensorID"))
    if g.sub_field is not None:
        _sub(el, "SubField", _token(g.sub_field, "SubField"))
    _sub(el, "LimitType", g.limit_type)
    _sub(el, "LimitValue", number_text(g.limit_value))
    for tag, value in (("RecheckTimeMicroSeconds", g.recheck_us), ("CheckCount", g.check_count),
                       ("LastCheckTime", g.last_check_time)):
        if value is not None:
            if not -2 ** 63 <= value < 2 ** 63:
                raise _Unwritable(f"Guard {tag} {value}: CRCL 1.x's is a 64-bit integer")
            _sub(el, tag, str(value))
    if g.last_check_value is not None:
        _sub(el, "LastCheckValue", number_text(g.last_check_value))
    for tag, flag in (("RequireTrigger", g.require_trigger), ("ErrorOnTrigger", g.error_on_trigger)):
        if flag is not None:
            _sub(el, tag, _bool(flag))
    return el


def _token(value: str, what: str) -> str:
    """``value`` as an ``xs:token``; _Unwritable when it is not one."""
    if value != " ".join(value.split()) or _XML_CHARS.search(value):
        raise _Unwritable(f"{what} {value!r}: an xs:token has no leading, trailing or repeated white space "
                          "and no control characters")
    return value


def _write_pose(el: Any, pose: Pose) -> None:
    for tag, names, values in (("Point", "XYZ", pose.point), ("XAxis", "IJK", pose.x_axis),
                               ("ZAxis", "IJK", pose.z_axis)):
        vec = _sub(el, tag)
        for n, v in zip(names, values):
            _sub(vec, n, number_text(v))


def _w_none(el: Any, command: c.Command) -> None:
    if isinstance(command, c.EndCanon) and command.reason != 0:
        raise _Unwritable(f"EndCanon({command.reason}): CRCL 1.x's EndCanon has no reason")


def _w_message(el: Any, command: c.Message) -> None:
    if _XML_CHARS.search(command.message):
        raise _Unwritable("Message holds control characters that XML 1.0 cannot hold")
    _sub(el, "Message", command.message)


def _w_move(straight: bool) -> Callable[[Any, Any], None]:
    def fill(el: Any, command: Any) -> None:
        _sub(el, "MoveStraight", _bool(straight))
        _write_pose(_sub(el, "EndPosition"), command.end_position)
    return fill


def _w_through(el: Any, command: c.MoveThroughTo) -> None:
    if command.num_positions < 2:
        raise _Unwritable("a MoveThroughTo of one waypoint: CRCL 1.x's has two or more (a MoveTo goes to one pose)")
    _sub(el, "MoveStraight", _bool(command.straight))
    for pose in command.waypoints:
        _write_pose(_sub(el, "Waypoint"), pose)
    _sub(el, "NumPositions", str(command.num_positions))


def _w_setting(outer: str, kind: str, relative: bool, scale: float = 1.0) -> Callable[[Any, Any], None]:
    """SetTransSpeed & co.: ``<outer xsi:type="{kind}{Absolute|Relative}Type"><Setting|Fraction>``."""
    def fill(el: Any, command: Any) -> None:
        value = command.setting if hasattr(command, "setting") else getattr(command, _FIELD[type(command)])
        is_relative = command.relative if isinstance(command, c.RotSetting) else relative
        inner = _sub(el, outer)
        if is_relative:
            fraction = float(Decimal(repr(float(value))) / Decimal(repr(scale)))
            if not 0.0 <= fraction <= 1.0:
                raise _Unwritable(f"{type(command).__name__}({number_text(value)}): CRCL 1.x's relative setting "
                                  f"is a fraction of the maximum from 0 to 1 ({number_text(scale)} here)")
            inner.set(_TYPE, f"{kind}RelativeType")
            _sub(inner, "Fraction", number_text(fraction))
        else:
            inner.set(_TYPE, f"{kind}AbsoluteType")
            _sub(inner, "Setting", number_text(value))
    return fill


_FIELD = {c.SetAbsoluteSpeed: "speed", c.SetRelativeSpeed: "percent", c.SetAbsoluteAcceleration: "acceleration",
          c.SetRelativeAcceleration: "percent"}
_TOLERANCE_TAGS = (("x_point", "XPointTolerance"), ("y_point", "YPointTolerance"), ("z_point", "ZPointTolerance"),
                   ("x_axis", "XAxisTolerance"), ("z_axis", "ZAxisTolerance"))


def _w_tolerance(make: Callable[[Any], c.PoseTolerance]) -> Callable[[Any, Any], None]:
    def fill(el: Any, command: Any) -> None:
        tolerance = make(command)
        inner = _sub(el, "Tolerance")
        for attr, tag in _TOLERANCE_TAGS:
            value = getattr(tolerance, attr)
            if value is not None:
                _sub(inner, tag, number_text(value))
    return fill


def _w_units(el: Any, command: Any) -> None:
    _sub(el, "UnitName", command.unit_name)


def _w_stop(el: Any, command: c.StopMotion) -> None:
    _sub(el, "StopCondition", "Immediate" if command.is_emergency else "Normal")


def _w_parameters(el: Any, command: c.SetEndEffectorParameters) -> None:
    for p in command.settings:
        ps = _sub(el, "ParameterSetting")
        _sub(ps, "ParameterName", _string(p.name))
        _sub(ps, "ParameterValue", _string(p.value))


def _w_actuate(el: Any, command: c.ActuateJoints) -> None:
    for j in command.joints:
        aj = _sub(el, "ActuateJoint")
        _sub(aj, "JointNumber", str(int(j.number)))
        _sub(aj, "JointPosition", number_text(j.position))
        details = _sub(aj, "JointDetails")
        if j.force_control:
            details.set(_TYPE, "JointForceTorqueType")
            pairs = (("Setting", j.force), ("ChangeRate", j.change_rate))
        else:
            details.set(_TYPE, "JointSpeedAccelType")
            pairs = (("JointSpeed", j.speed), ("JointAccel", j.accel))
        for tag, value in pairs:
            if value is not None:
                _sub(details, tag, number_text(value))


def _w_reports(el: Any, command: c.ConfigureJointReports) -> None:
    _sub(el, "ResetAll", _bool(command.reset_all))
    for r in command.reports:
        cr = _sub(el, "ConfigureJointReport")
        _sub(cr, "JointNumber", str(int(r.number)))
        for tag, value in (("ReportPosition", r.position), ("ReportTorqueOrForce", r.torque_or_force),
                           ("ReportVelocity", r.velocity)):
            _sub(cr, tag, _bool(value))


def _gripper(setting: float) -> Callable[[Any, Any], None]:
    return lambda el, command: _sub(el, "Setting", number_text(setting))


def _w_named(tag: str, attr: str, options: str | None = None, nmtoken: bool = False) -> Callable[[Any, Any], None]:
    """A writer of ``tag`` (an ``xs:token``, or with ``nmtoken`` an ``xs:NMTOKEN``) and its options."""
    def fill(el: Any, command: Any) -> None:
        value = getattr(command, attr)
        if nmtoken and not re.fullmatch(r"[\w.:-]+", value):
            raise _Unwritable(f"{type(command).__name__} {value!r}: a {tag} is an XML name token (letters, "
                              "digits, '.', ':', '-', '_')")
        if value != " ".join(value.split()) or _XML_CHARS.search(value):
            raise _Unwritable(f"{type(command).__name__} {value!r}: a {tag} has no leading, trailing or "
                              "repeated white space and no control characters")
        _sub(el, tag, value)
        for p in (command.options if options else ()):
            ps = _sub(el, options)
            _sub(ps, "ParameterName", _string(p.name))
            _sub(ps, "ParameterValue", _string(p.value))
    return fill


def _w_status_report(el: Any, command: c.ConfigureStatusReport) -> None:
    for tag, attr in _REPORT_TAGS:
        _sub(el, tag, _bool(getattr(command, attr)))


_REPORT_TAGS = (("ReportJointStatuses", "joints"), ("ReportPoseStatus", "pose"), ("ReportGripperStatus", "gripper"),
                ("ReportSettingsStatus", "settings"), ("ReportSensorsStatus", "sensors"),
                ("ReportGuardsStatus", "guards"))


def _w_joint_tolerances(el: Any, command: c.SetDefaultJointPositionsTolerances) -> None:
    inner = _sub(el, "JointTolerances")
    for t in command.tolerances:
        setting = _sub(inner, "Setting")
        _sub(setting, "JointNumber", str(int(t.number)))
        _sub(setting, "JointPositionTolerance", number_text(t.tolerance))


def _w_screw(el: Any, command: c.MoveScrew) -> None:
    if command.start_position is not None:
        _write_pose(_sub(el, "StartPosition"), command.start_position)
    if command.axis_point is not None:
        point = _sub(el, "AxisPoint")
        for n, v in zip("XYZ", command.axis_point):
            _sub(point, n, number_text(v))
    if command.axial_distance_free is not None:
        _sub(el, "AxialDistanceFree", number_text(command.axial_distance_free))
    _sub(el, "AxialDistanceScrew", number_text(command.axial_distance_screw))
    _sub(el, "Turn", number_text(command.turn))


def _w_loop_end(el: Any, command: c.LoopBlockEnd) -> None:
    if not -2 ** 31 <= command.max_count < 2 ** 31:
        raise _Unwritable(f"LoopBlockEnd MaxCount {command.max_count}: CRCL 1.x's is a 32-bit integer")
    _sub(el, "LoopName", _string(command.name))
    _sub(el, "MaxCount", str(command.max_count))


_WRITERS: dict[type[c.Command], tuple[str, Callable[[Any, Any], None]]] = {
    c.InitCanon: ("InitCanonType", _w_none),
    c.EndCanon: ("EndCanonType", _w_none),
    c.Message: ("MessageType", _w_message),
    c.Dwell: ("DwellType", lambda el, cmd: _sub(el, "DwellTime", number_text(cmd.dwell_time))),
    c.MoveTo: ("MoveToType", _w_move(False)),
    c.MoveStraightTo: ("MoveToType", _w_move(True)),
    c.MoveThroughTo: ("MoveThroughToType", _w_through),
    c.StopMotion: ("StopMotionType", _w_stop),
    c.OpenGripper: ("SetEndEffectorType", _gripper(1.0)),
    c.CloseGripper: ("SetEndEffectorType", _gripper(0.0)),
    c.SetEndEffector: ("SetEndEffectorType", lambda el, cmd: _sub(el, "Setting", number_text(cmd.setting))),
    c.OpenToolChanger: ("OpenToolChangerType", _w_none),
    c.CloseToolChanger: ("CloseToolChangerType", _w_none),
    c.SetLengthUnits: ("SetLengthUnitsType", _w_units),
    c.SetAngleUnits: ("SetAngleUnitsType", _w_units),
    c.SetForceUnits: ("SetForceUnitsType", _w_units),
    c.SetTorqueUnits: ("SetTorqueUnitsType", _w_units),
    c.SetAbsoluteSpeed: ("SetTransSpeedType", _w_setting("TransSpeed", "TransSpeed", False)),
    c.SetRelativeSpeed: ("SetTransSpeedType", _w_setting("TransSpeed", "TransSpeed", True, 100.0)),
    c.SetAbsoluteAcceleration: ("SetTransAccelType", _w_setting("TransAccel", "TransAccel", False)),
    c.SetRelativeAcceleration: ("SetTransAccelType", _w_setting("TransAccel", "TransAccel", True, 100.0)),
    c.SetRotSpeed: ("SetRotSpeedType", _w_setting("RotSpeed", "RotSpeed", False)),
    c.SetRotAccel: ("SetRotAccelType", _w_setting("RotAccel", "RotAccel", False)),
    c.SetEndPointTolerance: ("SetEndPoseToleranceType", _w_tolerance(
        lambda cmd: c.PoseTolerance(cmd.tolerance, cmd.tolerance, cmd.tolerance))),
    c.SetEndAngleTolerance: ("SetEndPoseToleranceType", _w_tolerance(
        lambda cmd: c.PoseTolerance(x_axis=cmd.tolerance, z_axis=cmd.tolerance))),
    c.SetEndPoseTolerance: ("SetEndPoseToleranceType", _w_tolerance(lambda cmd: cmd.tolerance)),
    c.SetIntermediatePointTolerance: ("SetIntermediatePoseToleranceType", _w_tolerance(
        lambda cmd: c.PoseTolerance(cmd.tolerance, cmd.tolerance, cmd.tolerance))),
    c.SetIntermediatePoseTolerance: ("SetIntermediatePoseToleranceType", _w_tolerance(lambda cmd: cmd.tolerance)),
    c.SetMotionCoordination: ("SetMotionCoordinationType",
                              lambda el, cmd: _sub(el, "Coordinated", _bool(cmd.coordinated))),
    c.SetEndEffectorParameters: ("SetEndEffectorParametersType", _w_parameters),
    c.SetRobotParameters: ("SetRobotParametersType", _w_parameters),
    c.ActuateJoints: ("ActuateJointsType", _w_actuate),
    c.ConfigureJointReports: ("ConfigureJointReportsType", _w_reports),
    c.RunProgram: ("RunProgramType", lambda el, cmd: _sub(el, "ProgramText", _string(cmd.program_text))),
    c.GetStatus: ("GetStatusType", _w_none),
    c.ConfigureStatusReport: ("ConfigureStatusReportType", _w_status_report),
    c.EnableGripper: ("EnableGripperType", _w_named("GripperName", "name", "GripperOption", nmtoken=True)),
    c.DisableGripper: ("DisableGripperType", _w_named("GripperName", "name", nmtoken=True)),
    c.EnableSensor: ("EnableSensorType", _w_named("SensorID", "sensor_id", "SensorOption")),
    c.DisableSensor: ("DisableSensorType", _w_named("SensorID", "sensor_id")),
    c.EnableRobotParameterStatus: ("EnableRobotParameterStatusType", _w_named("RobotParameterName", "name")),
    c.DisableRobotParameterStatus: ("DisableRobotParameterStatusType", _w_named("RobotParameterName", "name")),
    c.SetDefaultJointPositionsTolerances: ("SetDefaultJointPositonsTolerancesType", _w_joint_tolerances),
    c.MoveScrew: ("MoveScrewType", _w_screw),
    c.LoopBlockStart: ("LoopBlockStartType", lambda el, cmd: _sub(el, "LoopName", _string(cmd.name))),
    c.LoopBlockEnd: ("LoopBlockEndType", _w_loop_end),
}


# --- reading ----------------------------------------------------------------------------------

def read_command_instance(data: bytes | str, source: str = "<crcl>") -> tuple[c.Command, int]:
    """The command and CommandID of one ``CRCLCommandInstance`` document; anything else is an
    :class:`~kb.core.errors.InputError` at ``source``'s line."""
    root = _parse(data, source).getroot()
    _root(root, "CRCLCommandInstance", source)
    children = _named(root, source)
    if not children or children[0].tag != "CRCLCommand":
        raise InputError("<CRCLCommandInstance> holds a <CRCLCommand>", source, root.sourceline)
    for extra in children[1:]:
        if extra.tag not in ("ProgramFile", "ProgramIndex", "ProgramLength"):
            raise InputError(f"<{extra.tag}> is not part of a CRCLCommandInstance", source, extra.sourceline)
    return _command(children[0], source, None)


def read_program_instance(data: bytes | str, source: str = "<crcl>") -> list[tuple[c.Command, int]]:
    """The (command, CommandID) pairs of a ``CRCLProgram`` of CRCLProgramInstance.xsd, in
    order; anything else is an InputError at its line (as are two commands with one id)."""
    root = _parse(data, source).getroot()
    _root(root, "CRCLProgram", source)
    children = _named(root, source)
    if len(children) < 2 or children[0].tag != "InitCanon" or children[-1].tag != "EndCanon":
        raise InputError("a CRCL 1.x program is InitCanon, MiddleCommand elements, then EndCanon", source,
                         (children[0] if children else root).sourceline)
    pairs = []
    seen: dict[int, int] = {}
    for i, el in enumerate(children):
        tag = "InitCanon" if i == 0 else "EndCanon" if i == len(children) - 1 else "MiddleCommand"
        if el.tag != tag:
            raise InputError(f"<{el.tag}> where a CRCL 1.x program has <{tag}>", source, el.sourceline)
        command, command_id = _command(el, source, {0: "InitCanonType", len(children) - 1: "EndCanonType"}.get(i))
        if command_id in seen:
            raise InputError(f"CommandID {command_id} again (first at line {seen[command_id]}): "
                             "each command of a session has its own", source, el.sourceline)
        seen[command_id] = el.sourceline
        pairs.append((command, command_id))
    return pairs


def read_status(data: bytes | str, source: str = "<crcl>") -> CommandStatus:
    """The :class:`CommandStatus` of one ``CRCLStatus`` document (its settings, sensor and
    guard statuses skipped); anything else is an InputError at its line."""
    root = _parse(data, source).getroot()
    _root(root, "CRCLStatus", source)
    children = _named(root, source)
    if not children or children[0].tag != "CommandStatus":
        raise InputError("<CRCLStatus> starts with <CommandStatus>", source, root.sourceline)
    cs = {el.tag: el for el in _named(children[0], source)}
    for tag in ("CommandID", "StatusID", "CommandState"):
        if tag not in cs:
            raise InputError(f"<CommandStatus> lacks <{tag}>", source, children[0].sourceline)
    state = _text(cs["CommandState"], source).strip()
    if state not in STATES:
        raise InputError(f"<CommandState> is one of {', '.join(STATES)}, not {state!r}", source,
                         cs["CommandState"].sourceline)
    values: dict[str, Any] = {}
    for el in children[1:]:
        if el.tag == "PoseStatus":
            pose = next((p for p in _named(el, source) if p.tag == "Pose"), None)
            if pose is None:
                raise InputError("<PoseStatus> holds a <Pose>", source, el.sourceline)
            values["pose"] = _pose(pose, source)
        elif el.tag == "GripperStatus":
            values["gripper"] = _read_gripper(el, source)
        elif el.tag == "SettingsStatus":
            values["settings"] = _read_settings(el, source)
        elif el.tag == "JointStatuses":
            values["joints"] = tuple(_read_joint(j, source) for j in _named(el, source) if j.tag == "JointStatus")
    description = _text(cs["StateDescription"], source) if "StateDescription" in cs else ""
    return CommandStatus(_int(cs["CommandID"], source), _int(cs["StatusID"], source), state,
                         description=description, **values)


def _read_gripper(el: Any, source: str) -> GripperStatus:
    kinds = {v: k for k, v in _GRIPPER_TYPES.items()}
    type_name = _type_of(el)
    if type_name not in kinds:
        raise InputError(f"<GripperStatus> of xsi:type {type_name or '(none)'}: one of {', '.join(kinds)}",
                         source, el.sourceline)
    parts = {ch.tag: ch for ch in _named(el, source)}
    if "GripperName" not in parts:
        raise InputError("<GripperStatus> lacks <GripperName>", source, el.sourceline)
    values: dict[str, Any] = {"name": _text(parts["GripperName"], source).strip(), "kind": kinds[type_name]}
    if "HoldingObject" in parts:
        values["holding"] = _boolean(parts["HoldingObject"], source)
    if "Separation" in parts:
        values["separation"] = _double(parts["Separation"], source)
    if "IsPowered" in parts:
        values["powered"] = _boolean(parts["IsPowered"], source)
    fingers = tuple(_double(parts[f"Finger{i}Position"], source) if f"Finger{i}Position" in parts else None
                    for i in (1, 2, 3))
    return _made(GripperStatus, el, source, fingers=fingers, **values)


def _read_joint(el: Any, source: str) -> JointStatus:
    parts = {ch.tag: ch for ch in _named(el, source)}
    if "JointNumber" not in parts:
        raise InputError("<JointStatus> lacks <JointNumber>", source, el.sourceline)
    opt = {attr: _double(parts[tag], source) for attr, tag in (
        ("position", "JointPosition"), ("torque_or_force", "JointTorqueOrForce"), ("velocity", "JointVelocity"))
        if tag in parts}
    return JointStatus(_int(parts["JointNumber"], source), **opt)


def _parse(data: bytes | str, source: str) -> Any:
    if isinstance(data, str):
        data = data.encode("utf-8") if not data.lstrip().startswith("<?xml") else _recode(data)
    return _parse_bytes(data, source)


def _recode(text: str) -> bytes:
    """A str whose XML declaration names an encoding, as UTF-8 bytes with the declaration saying so."""
    return re.sub(r"""^(\s*<\?xml[^>]*?encoding\s*=\s*)(["'])[^"']*\2""", r"\1\2UTF-8\2", text, count=1).encode()


def _root(root: Any, expected: str, source: str) -> None:
    if root.tag != expected:
        what = {"CRCLCommandInstance": "a CRCL 1.x command instance", "CRCLProgram": "a CRCL 1.x program",
                "CRCLStatus": "a CRCL 1.x status"}[expected]
        raise InputError(f"the root element is <{root.tag}>, not <{expected}> ({what})", source, root.sourceline)


def _named(el: Any, source: str) -> list[Any]:
    """The child elements of ``el`` but ``Name`` (comments skipped); text between them is an error."""
    for text in [el.text, *(child.tail for child in el)]:
        if text and text.strip():
            raise InputError(f"unexpected text {text.strip()[:30]!r} in <{el.tag}>", source, el.sourceline)
    kids = [child for child in el if isinstance(child.tag, str)]
    for child in kids:
        if "}" in child.tag:
            raise InputError(f"<{child.tag}>: CRCL 1.x elements are in no namespace", source, child.sourceline)
    return [child for child in kids if child.tag != "Name"]


def _type_of(el: Any) -> str:
    value = (el.get(_TYPE) or "").strip()
    return value.rpartition(":")[2]


def _text(el: Any, source: str) -> str:
    if len(el):
        raise InputError(f"<{el.tag}> holds text only", source, el.sourceline)
    return el.text or ""


def _double(el: Any, source: str) -> float:
    text = _text(el, source)
    if not _DOUBLE.fullmatch(text):
        raise InputError(f"<{el.tag}> must be a number, not {text.strip()[:30]!r}", source, el.sourceline)
    return float(text.strip().replace("INF", "inf"))


def _int(el: Any, source: str) -> int:
    text = _text(el, source)
    if not _INT.fullmatch(text):
        raise InputError(f"<{el.tag}> must be an integer, not {text.strip()[:30]!r}", source, el.sourceline)
    return int(text)


def _boolean(el: Any, source: str) -> bool:
    text = _text(el, source).strip()
    if text not in ("true", "false", "1", "0"):
        raise InputError(f"<{el.tag}> must be true or false, not {text[:30]!r}", source, el.sourceline)
    return text in ("true", "1")


def _made(cls: Any, el: Any, source: str, *args: Any, **kwargs: Any) -> Any:
    """``cls(*args, **kwargs)``; its ValueError as an InputError at ``el``."""
    try:
        return cls(*args, **kwargs)
    except ValueError as exc:
        raise InputError(str(exc), source, el.sourceline) from None


def _pose(el: Any, source: str) -> Pose:
    if _type_of(el) not in ("", "PoseType"):
        raise InputError(f"a pose of xsi:type {_type_of(el)} (speeds, accelerations or tolerances with it) "
                         "is not read by kitkb: give them as commands before the motion", source, el.sourceline)
    parts = _expect(el, ["Point", "XAxis", "ZAxis"], source)
    point, x_axis, z_axis = ([_double(n, source) for n in _expect(v, names, source)]
                             for v, names in zip(parts, (["X", "Y", "Z"], ["I", "J", "K"], ["I", "J", "K"])))
    return _made(Pose, el, source, point=point, x_axis=x_axis, z_axis=z_axis)


def _expect(el: Any, names: Sequence[str], source: str) -> list[Any]:
    children = _named(el, source)
    if [ch.tag for ch in children] != list(names):
        found = ", ".join(str(ch.tag) for ch in children) or "none"
        raise InputError(f"<{el.tag}> holds {', '.join(names) or 'nothing'} in CRCL 1.x, found {found}", source,
                         el.sourceline)
    return children


def _command(el: Any, source: str, fixed_type: str | None) -> tuple[c.Command, int]:
    """The command of ``el`` (a ``CRCLCommand``, ``InitCanon``, ``MiddleCommand`` or ``EndCanon``
    element) and its CommandID."""
    type_name = _type_of(el) or fixed_type or ""
    if fixed_type and type_name != fixed_type:
        raise InputError(f"<{el.tag}> of xsi:type {type_name}, not {fixed_type}", source, el.sourceline)
    children = _named(el, source)
    if not children or children[0].tag != "CommandID":
        raise InputError(f"<{el.tag}> ({type_name or 'no xsi:type'}) starts with its <CommandID>", source,
                         el.sourceline)
    command_id = _int(children[0], source)
    rest = children[1:]
    count = next((i for i, ch in enumerate(rest) if ch.tag != "Guard"), len(rest))
    guards, rest = tuple(_read_guard(g, source) for g in rest[:count]), rest[count:]
    reader = _READERS.get(type_name)
    if reader is None:
        raise InputError(f"xsi:type {type_name or '(none)'} is not a command of CRCLCommands.xsd", source,
                         el.sourceline)
    names, build = reader
    if names is not None:
        rest = _expect_list(el, rest, names, source)
    command = build(rest, el, source)
    if guards:
        command = c.Guarded(command, guards, line=el.sourceline)
    return command, command_id


_GUARD_TAGS = ("SensorID", "SubField", "LimitType", "LimitValue", "RecheckTimeMicroSeconds", "CheckCount",
               "LastCheckTime", "LastCheckValue", "RequireTrigger", "ErrorOnTrigger")


def _read_guard(el: Any, source: str) -> c.Guard:
    name_el = next((ch for ch in el if isinstance(ch.tag, str) and ch.tag == "Name"), None)
    children = _named(el, source)
    tags = [ch.tag for ch in children]
    if tags != [t for t in _GUARD_TAGS if t in tags] or not {"SensorID", "LimitType", "LimitValue"} <= set(tags):
        raise InputError(f"<Guard> holds SensorID, SubField?, LimitType, LimitValue, RecheckTimeMicroSeconds?, "
                         f"CheckCount?, LastCheckTime?, LastCheckValue?, RequireTrigger?, ErrorOnTrigger?; "
                         f"found {', '.join(map(str, tags)) or 'none'}", source, el.sourceline)
    parts = dict(zip(tags, children))
    token = {"SensorID": "sensor_id", "SubField": "sub_field", "LimitType": "limit_type"}
    values: dict[str, Any] = {attr: " ".join(_text(parts[tag], source).split()) for tag, attr in token.items()
                              if tag in parts}
    for tag, attr, read in (("LimitValue", "limit_value", _double), ("RecheckTimeMicroSeconds", "recheck_us", _int),
                            ("CheckCount", "check_count", _int), ("LastCheckTime", "last_check_time", _int),
                            ("LastCheckValue", "last_check_value", _double),
                            ("RequireTrigger", "require_trigger", _boolean),
                            ("ErrorOnTrigger", "error_on_trigger", _boolean)):
        if tag in parts:
            values[attr] = read(parts[tag], source)
    if name_el is not None:
        values["name"] = " ".join(_text(name_el, source).split())
    return _made(c.Guard, el, source, **values)


def _expect_list(el: Any, children: list[Any], names: Sequence[str], source: str) -> list[Any]:
    if [ch.tag for ch in children] != list(names):
        found = ", ".join(str(ch.tag) for ch in children) or "none"
        wanted = ", ".join(["CommandID", *names])
        raise InputError(f"<{el.tag}> ({_type_of(el) or el.tag}) holds {wanted}, found CommandID, {found}",
                         source, el.sourceline)
    return children


def _line(cls: type[c.Command]) -> Callable[..., Any]:
    """A reader of a command without parameters."""
    return lambda rest, el, source: cls(line=el.sourceline)


def _r_move(rest: list[Any], el: Any, source: str) -> c.Command:
    straight = _boolean(rest[0], source)
    pose = _pose(rest[1], source)
    return (c.MoveStraightTo if straight else c.MoveTo)(pose, line=el.sourceline)


def _r_through(rest: list[Any], el: Any, source: str) -> c.Command:
    if len(rest) < 3 or rest[0].tag != "MoveStraight" or rest[-1].tag != "NumPositions" or any(
            w.tag != "Waypoint" for w in rest[1:-1]):
        raise InputError("<MoveThroughTo> holds CommandID, MoveStraight, Waypoint (one or more), NumPositions",
                         source, el.sourceline)
    waypoints = tuple(_pose(w, source) for w in rest[1:-1])
    count = _int(rest[-1], source)
    if count != len(waypoints):
        raise InputError(f"NumPositions is {count} but there are {len(waypoints)} Waypoints", source,
                         rest[-1].sourceline)
    return c.MoveThroughTo(waypoints, straight=_boolean(rest[0], source), line=el.sourceline)


def _r_end_effector(rest: list[Any], el: Any, source: str) -> c.Command:
    setting = _double(rest[0], source)
    if setting == 1.0:
        return c.OpenGripper(line=el.sourceline)
    if setting == 0.0:
        return c.CloseGripper(line=el.sourceline)
    return _made(c.SetEndEffector, rest[0], source, setting, line=el.sourceline)


def _r_units(cls: type[c.Command]) -> Callable[..., Any]:
    return lambda rest, el, source: _made(cls, rest[0], source, _text(rest[0], source).strip(), line=el.sourceline)


def _r_stop(rest: list[Any], el: Any, source: str) -> c.Command:
    condition = _text(rest[0], source).strip()
    if condition == "Fast":
        raise InputError("StopMotion Fast (a fast controlled stop, drives off after one second) has no kitkb "
                         "command: kitkb's StopMotion is Immediate (an emergency) or Normal", source, rest[0].sourceline)
    if condition not in ("Immediate", "Normal"):
        raise InputError(f"<StopCondition> is Immediate, Fast or Normal, not {condition[:30]!r}", source,
                         rest[0].sourceline)
    return c.StopMotion(int(condition == "Immediate"), line=el.sourceline)


def _r_setting(outer: str, kind: str, absolute: type[c.Command] | None, relative: type[c.Command] | None,
               rot: type[c.RotSetting] | None = None) -> Callable[..., Any]:
    def build(rest: list[Any], el: Any, source: str) -> c.Command:
        inner = rest[0]
        type_name = _type_of(inner)
        if type_name == f"{kind}AbsoluteType":
            value = _double(_expect(inner, ["Setting"], source)[0], source)
            if rot is not None:
                return _made(rot, inner, source, value, line=el.sourceline)
            return _made(absolute, inner, source, value, line=el.sourceline)
        if type_name == f"{kind}RelativeType":
            fraction_el = _expect(inner, ["Fraction"], source)[0]
            fraction = _double(fraction_el, source)
            if not 0.0 <= fraction <= 1.0:
                raise InputError(f"<Fraction> is from 0 to 1, not {fraction!r}", source, fraction_el.sourceline)
            if rot is not None:
                return _made(rot, inner, source, fraction, True, line=el.sourceline)
            percent = float(Decimal(_text(fraction_el, source).strip()) * 100)
            return _made(relative, inner, source, percent, line=el.sourceline)
        raise InputError(f"<{outer}> of xsi:type {type_name or '(none)'}: {kind}AbsoluteType or {kind}RelativeType",
                         source, inner.sourceline)
    return build


def _r_tolerance(point_cls: type[c.Command], angle_cls: type[c.Command] | None,
                 pose_cls: type[c.Command]) -> Callable[..., Any]:
    def build(rest: list[Any], el: Any, source: str) -> c.Command:
        tags = {tag: attr for attr, tag in _TOLERANCE_TAGS}
        values = {}
        for ch in _named(rest[0], source):
            if ch.tag not in tags:
                raise InputError(f"<{ch.tag}> is not part of a PoseToleranceType", source, ch.sourceline)
            values[tags[ch.tag]] = _double(ch, source)
        tolerance = _made(c.PoseTolerance, rest[0], source, **values)
        points = {values.get(a) for a in ("x_point", "y_point", "z_point")}
        axes = {values.get(a) for a in ("x_axis", "z_axis")}
        if len(points) == 1 and None not in points and axes == {None}:
            return _made(point_cls, rest[0], source, points.pop(), line=el.sourceline)
        if angle_cls is not None and len(axes) == 1 and None not in axes and points == {None}:
            return _made(angle_cls, rest[0], source, axes.pop(), line=el.sourceline)
        return pose_cls(tolerance, line=el.sourceline)
    return build


def _r_parameters(cls: type[c.SetEndEffectorParameters]) -> Callable[..., Any]:
    def build(rest: list[Any], el: Any, source: str) -> c.Command:
        settings = []
        for ps in rest:
            if ps.tag != "ParameterSetting":
                raise InputError(f"<{ps.tag}> where {cls.__name__} holds ParameterSettings", source, ps.sourceline)
            name, value = _expect(ps, ["ParameterName", "ParameterValue"], source)
            settings.append(c.Parameter(_text(name, source).strip(), _text(value, source).strip()))
        return _made(cls, el, source, tuple(settings), line=el.sourceline)
    return build


def _r_actuate(rest: list[Any], el: Any, source: str) -> c.Command:
    joints = []
    for aj in rest:
        if aj.tag == "JointTolerances":
            raise InputError("ActuateJoints' JointTolerances are not read by kitkb", source, aj.sourceline)
        if aj.tag != "ActuateJoint":
            raise InputError(f"<{aj.tag}> where ActuateJoints holds ActuateJoint elements", source, aj.sourceline)
        number, position, details = _expect(aj, ["JointNumber", "JointPosition", "JointDetails"], source)
        kind = _type_of(details)
        parts = {ch.tag: _double(ch, source) for ch in _named(details, source)}
        if kind == "JointSpeedAccelType" and set(parts) <= {"JointSpeed", "JointAccel"}:
            extra: dict[str, Any] = {"speed": parts.get("JointSpeed"), "accel": parts.get("JointAccel")}
        elif kind == "JointForceTorqueType" and set(parts) <= {"Setting", "ChangeRate"}:
            extra = {"force_control": True, "force": parts.get("Setting"), "change_rate": parts.get("ChangeRate")}
        else:
            raise InputError(f"<JointDetails> of xsi:type {kind or '(none)'} holding {', '.join(parts) or 'nothing'}: "
                             "JointSpeedAccelType (JointSpeed, JointAccel) or JointForceTorqueType (Setting, ChangeRate)",
                             source, details.sourceline)
        joints.append(c.JointActuation(_int(number, source), _double(position, source), **extra))
    return _made(c.ActuateJoints, el, source, tuple(joints), line=el.sourceline)


def _r_reports(rest: list[Any], el: Any, source: str) -> c.Command:
    if not rest or rest[0].tag != "ResetAll":
        raise InputError("<ConfigureJointReports> holds CommandID, ResetAll, ConfigureJointReport ...", source,
                         el.sourceline)
    reports = []
    for cr in rest[1:]:
        if cr.tag != "ConfigureJointReport":
            raise InputError(f"<{cr.tag}> in ConfigureJointReports", source, cr.sourceline)
        number, pos, force, vel = _expect(cr, ["JointNumber", "ReportPosition", "ReportTorqueOrForce",
                                               "ReportVelocity"], source)
        reports.append(c.JointReport(_int(number, source), _boolean(pos, source), _boolean(force, source),
                                     _boolean(vel, source)))
    return c.ConfigureJointReports(_boolean(rest[0], source), tuple(reports), line=el.sourceline)


def _parameter_list(el: Any, children: list[Any], tag: str, source: str) -> tuple[c.Parameter, ...]:
    out = []
    for ps in children:
        if ps.tag != tag:
            raise InputError(f"<{ps.tag}> where {_type_of(el).removesuffix('Type')} holds {tag} elements", source,
                             ps.sourceline)
        name, value = _expect(ps, ["ParameterName", "ParameterValue"], source)
        out.append(c.Parameter(_text(name, source).strip(), _text(value, source).strip()))
    return tuple(out)


def _r_named(cls: type[c.Command], first: str, options: str | None = None) -> Callable[..., Any]:
    """A reader of ``first`` (a token) and, if ``options`` names them, its parameter settings."""
    def build(rest: list[Any], el: Any, source: str) -> c.Command:
        if not rest or rest[0].tag != first or (options is None and len(rest) > 1):
            wanted = ", ".join(["CommandID", first] + ([f"{options} ..."] if options else []))
            found = ", ".join(str(ch.tag) for ch in rest) or "none"
            raise InputError(f"<{el.tag}> ({_type_of(el) or el.tag}) holds {wanted}, found CommandID, {found}",
                             source, el.sourceline)
        value = " ".join(_text(rest[0], source).split())
        extra = (_parameter_list(el, rest[1:], options, source),) if options else ()
        return _made(cls, rest[0], source, value, *extra, line=el.sourceline)
    return build


def _r_status_report(rest: list[Any], el: Any, source: str) -> c.Command:
    return c.ConfigureStatusReport(*(_boolean(ch, source) for ch in rest), line=el.sourceline)


def _r_joint_tolerances(rest: list[Any], el: Any, source: str) -> c.Command:
    settings = _named(rest[0], source)
    if not settings or any(s.tag != "Setting" for s in settings):
        raise InputError("<JointTolerances> holds one or more <Setting> elements", source, rest[0].sourceline)
    tolerances = []
    for s in settings:
        number, tolerance = _expect(s, ["JointNumber", "JointPositionTolerance"], source)
        tolerances.append(_made(c.JointTolerance, s, source, _int(number, source), _double(tolerance, source)))
    return c.SetDefaultJointPositionsTolerances(tuple(tolerances), line=el.sourceline)


_SCREW_TAGS = ("StartPosition", "AxisPoint", "AxialDistanceFree", "AxialDistanceScrew", "Turn")


def _r_screw(rest: list[Any], el: Any, source: str) -> c.Command:
    tags = [ch.tag for ch in rest]
    optional = [t for t in _SCREW_TAGS[:3] if t in tags]
    if tags != [*optional, "AxialDistanceScrew", "Turn"]:
        raise InputError("<MoveScrew> holds CommandID, StartPosition?, AxisPoint?, AxialDistanceFree?, "
                         f"AxialDistanceScrew, Turn; found CommandID, {', '.join(map(str, tags)) or 'none'}",
                         source, el.sourceline)
    parts = dict(zip(tags, rest))
    values: dict[str, Any] = {}
    if "StartPosition" in parts:
        values["start_position"] = _pose(parts["StartPosition"], source)
    if "AxisPoint" in parts:
        values["axis_point"] = tuple(_double(v, source) for v in _expect(parts["AxisPoint"], ["X", "Y", "Z"], source))
    if "AxialDistanceFree" in parts:
        values["axial_distance_free"] = _double(parts["AxialDistanceFree"], source)
    return _made(c.MoveScrew, el, source, _double(parts["AxialDistanceScrew"], source), _double(parts["Turn"], source),
                 line=el.sourceline, **values)


#: xsi:type -> (its elements after CommandID, or None: checked by the reader; reader).
_READERS: dict[str, tuple[Sequence[str] | None, Callable[[list[Any], Any, str], c.Command]]] = {
    "InitCanonType": ((), _line(c.InitCanon)),
    "EndCanonType": ((), _line(c.EndCanon)),
    "GetStatusType": ((), _line(c.GetStatus)),
    "OpenToolChangerType": ((), _line(c.OpenToolChanger)),
    "CloseToolChangerType": ((), _line(c.CloseToolChanger)),
    "MessageType": (("Message",), lambda rest, el, source: c.Message(_text(rest[0], source), line=el.sourceline)),
    "DwellType": (("DwellTime",), lambda rest, el, source: _made(c.Dwell, rest[0], source, _double(rest[0], source),
                                                                  line=el.sourceline)),
    "RunProgramType": (("ProgramText",), lambda rest, el, source: c.RunProgram(_text(rest[0], source),
                                                                                line=el.sourceline)),
    "MoveToType": (("MoveStraight", "EndPosition"), _r_move),
    "MoveThroughToType": (None, _r_through),
    "StopMotionType": (("StopCondition",), _r_stop),
    "SetEndEffectorType": (("Setting",), _r_end_effector),
    "SetLengthUnitsType": (("UnitName",), _r_units(c.SetLengthUnits)),
    "SetAngleUnitsType": (("UnitName",), _r_units(c.SetAngleUnits)),
    "SetForceUnitsType": (("UnitName",), _r_units(c.SetForceUnits)),
    "SetTorqueUnitsType": (("UnitName",), _r_units(c.SetTorqueUnits)),
    "SetTransSpeedType": (("TransSpeed",), _r_setting("TransSpeed", "TransSpeed", c.SetAbsoluteSpeed,
                                                      c.SetRelativeSpeed)),
    "SetTransAccelType": (("TransAccel",), _r_setting("TransAccel", "TransAccel", c.SetAbsoluteAcceleration,
                                                      c.SetRelativeAcceleration)),
    "SetRotSpeedType": (("RotSpeed",), _r_setting("RotSpeed", "RotSpeed", None, None, c.SetRotSpeed)),
    "SetRotAccelType": (("RotAccel",), _r_setting("RotAccel", "RotAccel", None, None, c.SetRotAccel)),
    "SetEndPoseToleranceType": (("Tolerance",), _r_tolerance(c.SetEndPointTolerance, c.SetEndAngleTolerance,
                                                             c.SetEndPoseTolerance)),
    "SetIntermediatePoseToleranceType": (("Tolerance",), _r_tolerance(c.SetIntermediatePointTolerance, None,
                                                                      c.SetIntermediatePoseTolerance)),
    "SetMotionCoordinationType": (("Coordinated",), lambda rest, el, source: c.SetMotionCoordination(
        _boolean(rest[0], source), line=el.sourceline)),
    "SetEndEffectorParametersType": (None, _r_parameters(c.SetEndEffectorParameters)),
    "SetRobotParametersType": (None, _r_parameters(c.SetRobotParameters)),
    "ActuateJointsType": (None, _r_actuate),
    "ConfigureJointReportsType": (None, _r_reports),
    "ConfigureStatusReportType": (("ReportJointStatuses", "ReportPoseStatus", "ReportGripperStatus",
                                   "ReportSettingsStatus", "ReportSensorsStatus", "ReportGuardsStatus"),
                                  _r_status_report),
    "EnableGripperType": (None, _r_named(c.EnableGripper, "GripperName", "GripperOption")),
    "DisableGripperType": (None, _r_named(c.DisableGripper, "GripperName")),
    "EnableSensorType": (None, _r_named(c.EnableSensor, "SensorID", "SensorOption")),
    "DisableSensorType": (None, _r_named(c.DisableSensor, "SensorID")),
    "EnableRobotParameterStatusType": (None, _r_named(c.EnableRobotParameterStatus, "RobotParameterName")),
    "DisableRobotParameterStatusType": (None, _r_named(c.DisableRobotParameterStatus, "RobotParameterName")),
    "SetDefaultJointPositonsTolerancesType": (("JointTolerances",), _r_joint_tolerances),
    "MoveScrewType": (None, _r_screw),
    "LoopBlockStartType": (("LoopName",), lambda rest, el, source: c.LoopBlockStart(_text(rest[0], source),
                                                                                    line=el.sourceline)),
    "LoopBlockEndType": (("LoopName", "MaxCount"), lambda rest, el, source: _made(
        c.LoopBlockEnd, el, source, _text(rest[0], source), _int(rest[1], source), line=el.sourceline)),
}

#: Every ``xsi:type`` of CRCLCommands.xsd's commands: each is read.
COMMAND_TYPES = frozenset(_READERS)
