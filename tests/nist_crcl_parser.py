"""What NIST's kittingViewer reads of CRCL text: an emulation of its command parser, written
for kitkb's tests from a reading of ``kittingViewer/source/commandParser.cc`` in
usnistgov/el-robotics-core (``CommandParser::readCommandFile`` and the functions it calls). No
code of NIST's is here; the grammar, as that code applies it:

* the file is read with ``fgets`` into a 200-byte buffer (``TEXTSIZE``): a line of more than 198
  bytes and its newline is read as two pieces;
* a piece that is blank up to its ``\\n`` or ``\\r`` (spaces and tabs only) is skipped; there are no
  comments;
* the command's name is the run of letters at the start (after spaces and tabs), and it matches
  a command whose name *begins* with it (``strncmp`` over the run's length), in this order:
  CloseGripper, CloseToolChanger, Dwell, EndCanon, InitCanon, Message, MoveStraightTo,
  MoveThroughTo, MoveTo, OpenGripper, OpenToolChanger, SetAbsoluteAcceleration,
  SetAbsoluteSpeed, SetAngleUnits, SetEndAngleTolerance, SetEndPointTolerance,
  SetIntermediatePointTolerance, SetLengthUnits, SetRelativeAcceleration, SetRelativeSpeed;
* arguments are read by ``sscanf`` formats, where a space is any white space, or none:
  ``" ( )"`` and nothing after; ``" ( %lf ) %s"`` (a ``strtod`` number) and ``" ( %d ) %s"``,
  accepted when nothing that is not white space follows the ``)``, and also when the ``)`` is
  missing (``sscanf`` has then assigned its one value); ``" ( \\"%[^\\"]\\" ) %s"``, a string of
  one or more characters without a double quote and without escapes, the same way;
  ``SetLengthUnits`` only ``inch``, ``millimeter``, ``meter`` and ``SetAngleUnits`` only
  ``radian``, ``degree`` (else a parse error);
* a pose is ``{ { x , y , z } , { i , j , k } , { i , j , k } }`` (point, Z axis, X axis) on one
  piece; MoveTo and MoveStraightTo take one pose and nothing after their ``)``;
* ``MoveThroughTo ( {`` starts with its first pose on the same piece; after each pose but the last
  a comma, and right after the comma the end of the line (``\\n`` or ``\\r``); each further pose
  starts the next piece; the last pose is followed by ``} , n )`` with ``n`` the number of poses;
* whatever else is one parse error (``UnreadableMsg``); the pieces a failed MoveThroughTo has
  read are gone, and the commands after MoveThroughTo in the order above are tried on the last
  of them (NIST's line buffer), read from where the first line's name began.

Where NIST's code reads memory it did not set (a pose's literals that do not match after its
numbers), this emulation refuses. ``tests/test_crcl_text.py`` checks it against NIST's own file
and the first paper's Fig. 11 (the parse errors NIST's parser reports, compiled from its
source, were 0 and 5).
"""

from __future__ import annotations

import re
from typing import Any

#: ``char lineIn[TEXTSIZE]`` read by ``fgets``: at most TEXTSIZE - 1 bytes a piece.
TEXTSIZE = 200
_NUM = (r"[+-]?(?:0[xX](?:[0-9a-fA-F]+\.?[0-9a-fA-F]*|\.[0-9a-fA-F]+)(?:[pP][+-]?\d+)?"
        r"|(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?|[iI][nN][fF](?:[iI][nN][iI][tT][yY])?|[nN][aA][nN])")
_INT = r"[+-]?\d+"
_TRIPLE = rf"\s*\{{\s*({_NUM})\s*,\s*({_NUM})\s*,\s*({_NUM})\s*\}}\s*"
_POSE = re.compile(rf"\s*\{{{_TRIPLE},{_TRIPLE},{_TRIPLE}\}}\s*")
ORDER = ("CloseGripper", "CloseToolChanger", "Dwell", "EndCanon", "InitCanon", "Message", "MoveStraightTo",
         "MoveThroughTo", "MoveTo", "OpenGripper", "OpenToolChanger", "SetAbsoluteAcceleration",
         "SetAbsoluteSpeed", "SetAngleUnits", "SetEndAngleTolerance", "SetEndPointTolerance",
         "SetIntermediatePointTolerance", "SetLengthUnits", "SetRelativeAcceleration", "SetRelativeSpeed")
_KIND = {"CloseGripper": "none", "CloseToolChanger": "none", "InitCanon": "none", "OpenGripper": "none",
         "OpenToolChanger": "none", "EndCanon": "int", "Message": "string", "SetAngleUnits": "string",
         "SetLengthUnits": "string", "MoveStraightTo": "pose", "MoveTo": "pose", "MoveThroughTo": "through"}
_ALLOWED = {"SetAngleUnits": ("radian", "degree"), "SetLengthUnits": ("inch", "millimeter", "meter")}


def _number(text: str) -> float:
    return float.fromhex(text) if "x" in text.lower() else float(text)


def pieces(data: bytes) -> list[str]:
    """The pieces ``fgets`` reads (as Latin-1 text, a character a byte)."""
    out, start = [], 0
    while start < len(data):
        end = data.find(b"\n", start, start + TEXTSIZE - 1)
        end = end + 1 if end >= 0 else min(len(data), start + TEXTSIZE - 1)
        out.append(data[start:end].decode("latin-1"))
        start = end
    return out


def _after_value(rest: str) -> bool:
    """``" ) %s"`` after a value: accepted unless a ``)`` is followed by more than white space."""
    return re.match(r"\s*\)\s*\S", rest) is None


def _pose(text: str) -> tuple[tuple[float, ...], int] | None:
    m = _POSE.match(text)
    return (tuple(_number(v) for v in m.groups()), m.end()) if m else None


def _one(name: str, line: str, length: int) -> Any:
    """The command ``name`` read from ``line`` (after its indentation), or None."""
    if length > len(name) or line[:length] != name[:length]:
        return None
    rest, kind = line[length:], _KIND.get(name, "double")
    if kind == "none":
        return (name,) if re.fullmatch(r"\s*\(\s*\)\s*", rest) else None
    if kind in ("double", "int"):
        m = re.match(rf"\s*\(\s*({_NUM if kind == 'double' else _INT})", rest)
        if m is None or not _after_value(rest[m.end():]):
            return None
        return name, _number(m.group(1)) if kind == "double" else int(m.group(1))
    if kind == "string":
        m = re.match(r'\s*\(\s*"([^"]+)', rest)
        if m is None or (rest[m.end():].startswith('"') and not _after_value(rest[m.end() + 1:])):
            return None
        return name, m.group(1)
    m = re.match(r"\s*\(\s*", rest)
    pose = _pose(rest[m.end():]) if m else None
    if pose is None or not re.fullmatch(r"\s*\)\s*", rest[m.end() + pose[1]:]):  # type: ignore[union-attr]
        return None
    return name, pose[0]


def _through(piece: str, rest: list[str]) -> tuple[Any, int]:
    """A MoveThroughTo starting at ``piece`` and the pieces after it: (the command or None, how
    many further pieces it read)."""
    m = re.match(r"\s*MoveThroughTo\s*\(\s*\{\s*", piece)
    if m is None:
        return None, 0
    first = _pose(piece[m.end():])
    # NIST's code: a first pose that does not read is left out, and the reading goes on as many
    # characters further again as ``MoveThroughTo ( {`` took (``readHere += chars``)
    poses, text, used = ([first[0]], piece[m.end() + first[1]:], 0) if first else ([], piece[2 * m.end():], 0)
    if first is None and 2 * m.end() > len(piece):
        return None, 0  # beyond the line: what stays in NIST's buffer from earlier lines
    while re.match(r"\s*,", text):
        if text[1:2] not in ("\n", "\r") or used == len(rest):
            return None, used
        text = rest[used]
        used += 1
        pose = _pose(text)
        if pose is None:
            return None, used
        poses.append(pose[0])
        text = text[pose[1]:]
    end = re.match(rf"\}}\s*,\s*({_INT})", text)
    if end is None or int(end.group(1)) != len(poses):
        return None, used
    return ("MoveThroughTo", tuple(poses)), used


def parse(data: bytes) -> tuple[list[tuple[Any, ...]], int]:
    """The commands NIST's parser reads from ``data`` — ``(name, value)``: a number, a string, a
    pose as (x, y, z, Z axis, X axis), MoveThroughTo's tuple of poses; ``("Unreadable", text)`` —
    and its count of parse errors. Strings are its bytes read as UTF-8."""
    commands: list[tuple[Any, ...]] = []
    errors = 0
    todo = pieces(data)
    at = 0
    while at < len(todo):
        piece = todo[at]
        at += 1
        line = piece.lstrip(" \t")
        if line[:1] in ("\n", "\r"):
            continue
        indent = len(piece) - len(line)
        length = len(re.match(r"[A-Za-z]*", line).group())  # type: ignore[union-attr]
        found = None
        for name in ORDER:
            if name == "MoveThroughTo":
                found, used = _through(piece, todo[at:])
                at += used
                if found is None and used:  # NIST's buffer now holds the last piece read, the
                    piece = todo[at - 1]    # later checks read it where the first line's name began
                    line = piece[indent:]
            else:
                found = _one(name, line, length)
            if found is not None:
                break
        if found is not None and found[0] in _ALLOWED and found[1] not in _ALLOWED[found[0]]:
            found = None
        if found is None:
            found = ("Unreadable", piece)
            errors += 1
        if isinstance(found[-1], str):  # the bytes NIST's parser keeps, as UTF-8 text
            found = (*found[:-1], found[-1].encode("latin-1").decode("utf-8", "replace"))
        commands.append(found)
    return commands, errors
