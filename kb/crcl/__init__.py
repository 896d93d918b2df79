"""CRCL, the canonical robot command language of the first paper (§V-C): commands as typed
values (:mod:`.commands`, :mod:`.pose`), their text form (:mod:`.text`, Fig. 11) and XML
instances of NIST's early CRCL.xsd (:mod:`.xml`), files by suffix (:mod:`.files`,
``kitkb crcl convert``).
"""

from kb.crcl.commands import (ANGLE_UNITS, COMMANDS, COORDINATE_FRAMES, LENGTH_UNITS, CloseGripper,
                              CloseToolChanger, Command, Dwell, EndCanon, InitCanon, Message,
                              MoveStraightTo, MoveThroughTo, MoveTo, OpenGripper, OpenToolChanger,
                              Program, SetAbsoluteAcceleration, SetAbsoluteSpeed, SetAngleUnits,
                              SetCoordinateFrame, SetEndAngleTolerance, SetEndPointTolerance,
                              SetIntermediatePointTolerance, SetLengthUnits,
                              SetRelativeAcceleration, SetRelativeSpeed, StartObjectScan,
                              StopMotion, StopObjectScan, Unreadable)
from kb.crcl.files import convert, read_file, write_file
from kb.crcl.pose import Pose
from kb.crcl.text import read_text, write_text
from kb.crcl.xml import default_xsd, read_xml, schema, write_xml

__all__ = [
    "ANGLE_UNITS", "COMMANDS", "COORDINATE_FRAMES", "LENGTH_UNITS", "CloseGripper", "CloseToolChanger",
    "Command", "Dwell", "EndCanon", "InitCanon", "Message", "MoveStraightTo", "MoveThroughTo", "MoveTo",
    "OpenGripper", "OpenToolChanger", "Pose", "Program", "SetAbsoluteAcceleration", "SetAbsoluteSpeed",
    "SetAngleUnits", "SetCoordinateFrame", "SetEndAngleTolerance", "SetEndPointTolerance",
    "SetIntermediatePointTolerance", "SetLengthUnits", "SetRelativeAcceleration", "SetRelativeSpeed",
    "StartObjectScan", "StopMotion", "StopObjectScan", "Unreadable",
    "convert", "default_xsd", "read_file", "read_text", "read_xml", "schema", "write_file",
    "write_text", "write_xml",
]
