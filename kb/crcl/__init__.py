"""CRCL, the canonical robot command language of the first paper (§V-C): commands as typed
values (:mod:`.commands`, :mod:`.pose`), their text form (:mod:`.text`: NIST's kittingViewer
layout, written by default, and the first paper's Fig. 11) and XML
instances of NIST's early CRCL.xsd (:mod:`.xml`), CRCL 1.x documents (:mod:`.instance`:
CRCLCommandInstance, CRCLProgramInstance, CRCLStatus), each form's default units
(:mod:`.units`; docs/crcl.md), files by suffix (:mod:`.files`,
``kitkb crcl convert``); the cell contract an executor talks to (:mod:`.cell`:
:class:`CellInterface` and its capabilities as protocols, :class:`Status`, :class:`Observation`,
USARTruth lines), the wire (:mod:`.wire`: CRCL 1.x documents split from a TCP stream, USARTruth
lines, kitkb's earlier ``{Length N}`` framing) and the clients behind sockets (:mod:`.remote`:
:class:`RemoteCell`, a CRCL 1.x session, ``kitkb crcl send``'s stream).
"""

from kb.crcl.commands import (ANGLE_UNITS, COMMANDS, COORDINATE_FRAMES, LENGTH_UNITS, CloseGripper,
                              CloseToolChanger, Command, Dwell, EndCanon, InitCanon, Message,
                              MoveStraightTo, MoveThroughTo, MoveTo, OpenGripper, OpenToolChanger,
                              Program, SetAbsoluteAcceleration, SetAbsoluteSpeed, SetAngleUnits,
                              SetCoordinateFrame, SetEndAngleTolerance, SetEndPointTolerance,
                              SetIntermediatePointTolerance, SetLengthUnits,
                              SetRelativeAcceleration, SetRelativeSpeed, StartObjectScan,
                              StopMotion, StopObjectScan, Unreadable)
from kb.crcl.cell import CellInterface, Observation, Status, execute_program, parse_truth_line, truth_line
from kb.crcl.commands import (CRCL1_COMMANDS, CRCL1_UNITS, PAPER_UNITS, ActuateJoints, ConfigureJointReports,
                              GetStatus, JointActuation, JointReport, Parameter, PoseTolerance, RotSetting,
                              RunProgram, SetEndEffector, SetEndEffectorParameters, SetEndPoseTolerance,
                              SetForceUnits, SetIntermediatePoseTolerance, SetMotionCoordination,
                              SetRobotParameters, SetRotAccel, SetRotSpeed, SetTorqueUnits,
                              ConfigureStatusReport, DisableGripper, DisableRobotParameterStatus, DisableSensor,
                              EnableGripper, EnableRobotParameterStatus, EnableSensor, JointTolerance,
                              LoopBlockEnd, LoopBlockStart, MoveScrew, SetDefaultJointPositionsTolerances,
                              Guard, Guarded)
from kb.crcl.files import convert, read_file, write_file
from kb.crcl.instance import (CommandStatus, GripperStatus, JointStatus, read_command_instance,
                              read_program_instance, read_status, write_command_instance,
                              write_program_instance, write_status)
from kb.crcl.pose import Pose
from kb.crcl.remote import RemoteCell
from kb.crcl.text import read_text, write_text
from kb.crcl.xml import default_xsd, read_xml, schema, write_xml

__all__ = [
    "ANGLE_UNITS", "COMMANDS", "COORDINATE_FRAMES", "LENGTH_UNITS", "CellInterface", "CloseGripper",
    "CloseToolChanger", "Command", "Dwell", "EndCanon", "InitCanon", "Message", "MoveStraightTo",
    "MoveThroughTo", "MoveTo", "Observation", "OpenGripper", "OpenToolChanger", "Pose", "Program",
    "RemoteCell", "SetAbsoluteAcceleration", "SetAbsoluteSpeed", "SetAngleUnits", "SetCoordinateFrame",
    "SetEndAngleTolerance", "SetEndPointTolerance", "SetIntermediatePointTolerance", "SetLengthUnits",
    "SetRelativeAcceleration", "SetRelativeSpeed", "StartObjectScan", "Status", "StopMotion",
    "StopObjectScan", "Unreadable",
    "CRCL1_COMMANDS", "CRCL1_UNITS", "PAPER_UNITS", "ActuateJoints", "ConfigureJointReports", "GetStatus",
    "JointActuation", "JointReport", "Parameter", "PoseTolerance", "RotSetting", "RunProgram", "SetEndEffector",
    "SetEndEffectorParameters", "SetEndPoseTolerance", "SetForceUnits", "SetIntermediatePoseTolerance",
    "SetMotionCoordination", "SetRobotParameters", "SetRotAccel", "SetRotSpeed", "SetTorqueUnits",
    "ConfigureStatusReport", "DisableGripper", "DisableRobotParameterStatus", "DisableSensor", "EnableGripper",
    "EnableRobotParameterStatus", "EnableSensor", "JointTolerance", "LoopBlockEnd", "LoopBlockStart", "MoveScrew",
    "SetDefaultJointPositionsTolerances", "Guard", "Guarded",
    "CommandStatus", "GripperStatus", "JointStatus", "read_command_instance", "read_program_instance",
    "read_status", "write_command_instance", "write_program_instance", "write_status",
    "convert", "default_xsd", "execute_program", "parse_truth_line", "read_file", "read_text", "read_xml",
    "schema", "truth_line", "write_file", "write_text", "write_xml",
]
