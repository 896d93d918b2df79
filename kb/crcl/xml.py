"""CRCL programs as XML instances of NIST's early CRCL.xsd (root ``CRCLProgram``, as
``commands1.xml``).

The schema says which commands a program holds and where: ``InitCanon`` first, ``EndCanon``
last, at least one command between them, and only the commands it names in between;
:func:`read_xml` and :func:`write_xml` keep to that whether or not the schema file is at
hand. The schema has no element for ``SetCoordinateFrame``, ``StartObjectScan``,
``StopObjectScan`` and ``StopMotion``, nor for ``EndCanon``'s reason: writing them is an
:class:`~kb.core.errors.InputError` naming the command and its line.

A CRCL 1.x document (a program whose commands carry CommandIDs, a command instance) is read
through :mod:`kb.crcl.instance` into a program in CRCL 1.x's units; a status is refused as what
it is. A program read from CRCL.xsd XML is in the paper's units (millimetre and degree at
InitCanon: CRCL.xsd names none; docs/crcl.md). Numbers are written as ``xs:decimal`` without
exponent, sin(pi)-sized noise as 0 and at most 24 digits (libxml2's limit).

Files are parsed without loading a DTD, resolving entities or touching the network, and a
document type declaration is refused outright (CRCL needs none). The schema is NIST's data,
not shipped with kitkb: :func:`schema` loads it from a path, :func:`default_xsd` finds it
beside the checkout.
"""

from __future__ import annotations

import os
import re
from decimal import Decimal, localcontext
from pathlib import Path
from typing import Any, Callable

from lxml import etree

from kb.core import limits
from kb.core.errors import InputError
from kb.crcl.commands import (CRCL1_UNITS, PAPER_UNITS, CloseGripper, CloseToolChanger, Command, Dwell, EndCanon, InitCanon,
                              Message, MoveStraightTo, MoveThroughTo, MoveTo, OpenGripper,
                              OpenToolChanger, Program, SetAbsoluteAcceleration, SetAbsoluteSpeed,
                              SetAngleUnits, SetEndAngleTolerance, SetEndPointTolerance,
                              SetIntermediatePointTolerance, SetLengthUnits,
                              SetRelativeAcceleration, SetRelativeSpeed, Unreadable)
from kb.crcl.pose import Pose
from kb.crcl.xmlbase import _XML_CHARS, _parse, _read, default_xsd, hardened_parser, schema, syntax_error  # noqa: F401 (kb.crcl.xml's API)

#: Command class -> (field, child element, value kind) of each child CRCL.xsd gives it.
#: ``MoveThroughTo`` (repeated ``Waypoint`` and ``NumPositions``) is read and written apart.
ELEMENTS: dict[type[Command], tuple[tuple[str, str, str], ...]] = {
    InitCanon: (), EndCanon: (), OpenGripper: (), CloseGripper: (),
    OpenToolChanger: (), CloseToolChanger: (), MoveThroughTo: (),
    Dwell: (("dwell_time", "DwellTime", "decimal"),),
    Message: (("message", "Message", "string"),),
    MoveTo: (("end_position", "EndPosition", "pose"),),
    MoveStraightTo: (("end_position", "EndPosition", "pose"),),
    SetLengthUnits: (("unit_name", "UnitName", "token"),),
    SetAngleUnits: (("unit_name", "UnitName", "token"),),
    SetAbsoluteSpeed: (("speed", "Speed", "decimal"),),
    SetRelativeSpeed: (("percent", "Percent", "decimal"),),
    SetAbsoluteAcceleration: (("acceleration", "Acceleration", "decimal"),),
    SetRelativeAcceleration: (("percent", "Percent", "decimal"),),
    SetEndAngleTolerance: (("tolerance", "Tolerance", "decimal"),),
    SetEndPointTolerance: (("tolerance", "Tolerance", "decimal"),),
    SetIntermediatePointTolerance: (("tolerance", "Tolerance", "decimal"),),
}
_BY_NAME = {cls.__name__: cls for cls in ELEMENTS}
_DECIMAL = re.compile(r"[+-]?(?:\d+(?:\.\d*)?|\.\d+)")
_INTEGER = re.compile(r"[+-]?\d+")



# --- the schema -------------------------------------------------------------------------------

def _check_schema(tree: Any, xsd: etree.XMLSchema, name: str | None, what: str, shift: int = 0) -> None:
    """InputError at the first error of ``tree`` against ``xsd`` (its line moved by ``shift``)."""
    if not xsd.validate(tree):
        errors = list(xsd.error_log)
        more = f" (and {len(errors) - 1} more)" if len(errors) > 1 else ""
        raise InputError(f"{what} CRCL.xsd: {errors[0].message}{more}", name, errors[0].line + shift)


# --- reading ----------------------------------------------------------------------------------

def read_xml(source: bytes | str | os.PathLike[str], schema: etree.XMLSchema | None = None,
             *, name: str | None = None) -> Program:
    """The program of a CRCL XML document: ``source`` is its bytes or a file path. With
    ``schema`` the document is first validated against it. Anything that is not a CRCL.xsd
    program is an :class:`~kb.core.errors.InputError` at its line.

    A file of :data:`STREAM_FROM` bytes or more is read element by element (and validated
    :data:`CHUNK` commands at a time): a program of millions of commands costs its commands,
    not an element tree of them as well. More commands than
    :data:`kb.core.limits.CRCL_COMMANDS` is an InputError at the first one too many."""
    if isinstance(source, bytes):
        data = source
    else:
        path = Path(source)
        name = name or str(source)
        try:
            if path.stat().st_size >= STREAM_FROM:
                if _head_is_crcl1(path):
                    return _read_crcl1(_read(path), name)
                return _read_stream(path, schema, name)
        except OSError:
            pass  # _read says why
        data = _read(path)
    tree = _parse(data, name)
    root = tree.getroot()
    if _is_crcl1(root):
        return _read_crcl1(data, name)
    if schema is not None:
        _check_schema(tree, schema, name, "does not conform to")
    if root.tag != "CRCLProgram":
        raise InputError(f"the root element is <{root.tag}>, not <CRCLProgram>", name, root.sourceline)
    children = _children(root, name)
    most = limits.CRCL_COMMANDS.value()
    if most is not None and len(children) > most:
        raise limits.CRCL_COMMANDS.error(None, name, children[most].sourceline, "too many commands")
    commands = tuple(_command(el, name) for el in children)
    _check_order(commands, name)
    return Program(commands, source=name, units=PAPER_UNITS)


#: Files at least this big are read by :func:`_read_stream`.
STREAM_FROM = 16_000_000


def _read_stream(path: Path, schema: etree.XMLSchema | None, name: str) -> Program:
    """:func:`read_xml` of a big file, one command element at a time: each :data:`CHUNK` of
    them validated as a program of its own (framed by InitCanon / EndCanon where it lacks
    them, lines mapped back to the file), turned into commands, then dropped from the tree."""
    _refuse_doctype(path, name)
    most = limits.CRCL_COMMANDS.value()
    commands: list[Command] = []
    pending: list[Any] = []
    root = None
    depth = 0
    try:
        for event, el in etree.iterparse(str(path), events=("start", "end"), resolve_entities=False,
                                         no_network=True, load_dtd=False, huge_tree=False):
            if event == "start":
                depth += 1
                if root is None:
                    root = el
                    if el.getroottree().docinfo.doctype:
                        raise InputError("a DOCTYPE is not allowed in CRCL XML (no entity is expanded or fetched)",
                                         name, 1)
                    if el.tag != "CRCLProgram":
                        raise InputError(f"the root element is <{el.tag}>, not <CRCLProgram>", name, el.sourceline)
                continue
            depth -= 1
            if depth != 1 or not isinstance(el.tag, str):
                continue
            pending.append(el)
            if most is not None and len(commands) + len(pending) > most:
                raise limits.CRCL_COMMANDS.error(None, name, el.sourceline, "too many commands")
            if len(pending) > max(CHUNK, 2) + 1:  # two kept back: the last chunk is never EndCanon alone
                _take(pending[:-2], root, schema, name, commands, first=not commands, last=False)
                pending = pending[-2:]
    except etree.XMLSyntaxError as exc:
        raise syntax_error(exc, name) from None
    if root is not None and root.text and root.text.strip():
        raise InputError(f"unexpected text {root.text.strip()[:30]!r} in <{root.tag}>", name, root.sourceline)
    _take(pending, root, schema, name, commands, first=not commands, last=True)
    result = tuple(commands)
    _check_order(result, name)
    return Program(result, source=name, units=PAPER_UNITS)


def _take(elements: list[Any], root: Any, schema: etree.XMLSchema | None, name: str,
          commands: list[Command], *, first: bool, last: bool) -> None:
    """Validate ``elements`` (one chunk of the program) and append their commands; then drop
    them from the tree."""
    if not elements:
        return
    if schema is not None:
        parts = [b"<CRCLProgram>\n", b"" if first else b"<InitCanon/>\n"]
        starts = []  # (line in the chunk document, line in the file) of each element
        line = 1 + parts[1].count(b"\n")
        for el in elements:
            text = etree.tostring(el, with_tail=False) + b"\n"
            starts.append((line + 1, el.sourceline))
            parts.append(text)
            line += text.count(b"\n")
        parts.append((b"" if last else b"<EndCanon/>\n") + b"</CRCLProgram>\n")
        chunk = etree.fromstring(b"".join(parts), hardened_parser()).getroottree()
        if not schema.validate(chunk):
            errors = list(schema.error_log)
            at = errors[0].line
            where = next(((file_line + at - doc_line) for doc_line, file_line in reversed(starts) if at >= doc_line),
                          root.sourceline)  # before the first element: the program itself
            more = f" (and {len(errors) - 1} more in these {len(elements):,} commands)" if len(errors) > 1 else ""
            raise InputError(f"does not conform to CRCL.xsd: {errors[0].message}{more}", name, where)
    for el in elements:
        if el.tail and el.tail.strip():
            raise InputError(f"unexpected text {el.tail.strip()[:30]!r} in <{root.tag}>", name, root.sourceline)
        commands.append(_command(el, name))
    for el in elements:
        el.clear()
        root.remove(el)


#: the root elements of CRCL 1.x documents (NIST's CRCLProgramInstance.xsd, CRCLCommandInstance.xsd,
#: CRCLStatus.xsd) that are not CRCLProgram
_CRCL1_ROOTS = ("CRCLCommandInstance", "CRCLStatus")
_XSI_TYPE = "{http://www.w3.org/2001/XMLSchema-instance}type"


def _is_crcl1(root: Any) -> bool:
    """Whether ``root`` is a CRCL 1.x document: a command instance, a status, or a program
    whose first command carries a CommandID or an xsi:type (or a Name, which 2014 has not)."""
    first = next((el for el in root if isinstance(el.tag, str)), None)
    if root.tag in _CRCL1_ROOTS:
        return True
    if root.tag != "CRCLProgram" or first is None:
        return False
    if first.tag == "Name":
        return True
    return first.get(_XSI_TYPE) is not None or any(c.tag == "CommandID" for c in first if isinstance(c.tag, str))


def _head_is_crcl1(path: Path) -> bool:
    """:func:`_is_crcl1` of a big file, from its first 64 KiB."""
    try:
        with open(path, "rb") as f:
            head = f.read(1 << 16)
    except OSError:
        return False
    return (b"<CRCLCommandInstance" in head or b"<CRCLStatus" in head or b"<CommandID" in head
            or b"MiddleCommand" in head)


def _read_crcl1(data: bytes, name: str | None) -> Program:
    """The program of a CRCL 1.x document (:mod:`kb.crcl.instance`): a CRCLProgram, or the one
    command of a CRCLCommandInstance; a status is no program. Checked against NIST's CRCL 1.x
    schemas when they are found."""
    from kb.crcl import instance  # it builds on this module
    source = name or "<crcl>"
    root = _parse(data, name).getroot()
    if root.tag == "CRCLStatus":
        raise InputError("a CRCL 1.x status (CRCLStatus), not a program or a command", name, root.sourceline)
    kind = "command" if root.tag == "CRCLCommandInstance" else "program"
    if instance.default_schemas() is not None:
        instance.validate(data, kind, source)
    if kind == "command":
        pairs = [instance.read_command_instance(data, source)]
    else:
        pairs = instance.read_program_instance(data, source)
    most = limits.CRCL_COMMANDS.value()
    if most is not None and len(pairs) > most:
        raise limits.CRCL_COMMANDS.error(None, name, pairs[most][0].line, "too many commands")
    return Program(tuple(command for command, _ in pairs), source=name, units=CRCL1_UNITS)


def _refuse_doctype(path: Path, name: str) -> None:
    """A DOCTYPE before the root element is an InputError at its line (the head of the file
    is read: a DOCTYPE comes before the root element)."""
    try:
        with open(path, "rb") as f:
            head = f.read(1 << 16)
    except OSError as exc:
        raise InputError(f"cannot read: {exc.strerror or exc}", path) from None
    at = head.find(b"<!DOCTYPE")
    if at >= 0:
        raise InputError("a DOCTYPE is not allowed in CRCL XML (no entity is expanded or fetched)",
                         name, head.count(b"\n", 0, at) + 1)


def _children(el: Any, name: str | None) -> list[Any]:
    """The child elements of ``el`` (comments skipped); text between them is an error."""
    for text in [el.text, *(child.tail for child in el)]:
        if text and text.strip():
            raise InputError(f"unexpected text {text.strip()[:30]!r} in <{el.tag}>", name, el.sourceline)
    return [child for child in el if isinstance(child.tag, str)]


def _expect(el: Any, names: list[str], name: str | None) -> list[Any]:
    """The children of ``el``, which must be elements named ``names`` in this order."""
    children = _children(el, name)
    if [c.tag for c in children] != names:
        wanted = ", ".join(names) or "no child elements"
        found = ", ".join(str(c.tag) for c in children) or "none"
        raise InputError(f"<{el.tag}> holds {wanted} in CRCL.xsd, found {found}", name, el.sourceline)
    return children


def _command(el: Any, name: str | None) -> Command:
    cls = _BY_NAME.get(el.tag)
    if cls is None:
        raise InputError(f"<{el.tag}> is not a command of CRCL.xsd", name, el.sourceline)
    if cls is MoveThroughTo:
        return _move_through(el, name)
    spec = ELEMENTS[cls]
    children = _expect(el, [child for _, child, _ in spec], name)
    values = {f: _VALUE[kind](child, name) for (f, _, kind), child in zip(spec, children)}
    try:
        return cls(**values, line=el.sourceline)
    except ValueError as exc:
        raise InputError(str(exc), name, el.sourceline) from None


def _move_through(el: Any, name: str | None) -> MoveThroughTo:
    children = _children(el, name)
    n = len(children) - 1
    _expect(el, ["Waypoint"] * max(n, 1) + ["NumPositions"], name)
    count = _integer(children[-1], name)
    if count != n:
        raise InputError(f"NumPositions is {count} but there are {n} Waypoints", name,
                         children[-1].sourceline)
    return MoveThroughTo(tuple(_pose(w, name) for w in children[:-1]), line=el.sourceline)


def _leaf(el: Any, name: str | None) -> str:
    if len(el):
        raise InputError(f"<{el.tag}> holds text only", name, el.sourceline)
    return el.text or ""


def _decimal(el: Any, name: str | None) -> float:
    text = _leaf(el, name).strip()
    if not _DECIMAL.fullmatch(text):
        raise InputError(f"<{el.tag}> must be a decimal number, not {text!r}", name, el.sourceline)
    return float(text)


def _integer(el: Any, name: str | None) -> int:
    text = _leaf(el, name).strip()
    if not _INTEGER.fullmatch(text):
        raise InputError(f"<{el.tag}> must be an integer, not {text!r}", name, el.sourceline)
    return int(text)


def _pose(el: Any, name: str | None) -> Pose:
    point, z_axis, x_axis = _expect(el, ["Point", "ZAxis", "XAxis"], name)
    xyz = [_decimal(c, name) for c in _expect(point, ["X", "Y", "Z"], name)]
    z, x = ([_decimal(c, name) for c in _expect(v, ["I", "J", "K"], name)] for v in (z_axis, x_axis))
    try:
        return Pose(point=xyz, x_axis=x, z_axis=z)
    except ValueError as exc:  # a number too large for a float (inf), axes that are no frame
        raise InputError(str(exc), name, el.sourceline) from None


_VALUE: dict[str, Callable[[Any, str | None], Any]] = {
    "decimal": _decimal, "pose": _pose, "string": _leaf,
    "token": lambda el, name: _leaf(el, name).strip(),
}


def _check_order(commands: tuple[Command, ...], name: str | None) -> None:
    """CRCL.xsd's sequence: InitCanon, one or more other commands, EndCanon."""
    for i, command in enumerate(commands):
        problem = _misplaced(command, i == 0, i == len(commands) - 1)
        if problem:
            raise InputError(problem, name, command.line)
    if len(commands) < 3:
        raise InputError("CRCL.xsd needs InitCanon, at least one other command, then EndCanon", name,
                         commands[-1].line if commands else None)


def _misplaced(command: Command, first: bool, last: bool) -> str | None:
    kind = type(command).__name__
    if first and not isinstance(command, InitCanon):
        return f"a CRCL.xsd program starts with InitCanon, not {kind}"
    if last and not isinstance(command, EndCanon):
        return f"a CRCL.xsd program ends with EndCanon, not {kind}"
    if isinstance(command, (InitCanon, EndCanon)) and not (first or last):
        return f"{kind} only as the {'first' if isinstance(command, InitCanon) else 'last'} command in CRCL.xsd"
    return None


# --- writing ----------------------------------------------------------------------------------

def write_xml(program: Program, schema: etree.XMLSchema | None = None) -> bytes:
    """``program`` as a CRCL.xsd instance (UTF-8, indented). A command the schema cannot
    hold, or a program out of its sequence, is an :class:`~kb.core.errors.InputError` naming
    the program's source and the command's line. With ``schema`` the result is validated.

    Written (and validated) :data:`CHUNK` commands at a time, so a program of millions of
    commands costs its output bytes, not an element tree of them all."""
    commands = program.commands
    for i, command in enumerate(commands):
        problem = _unwritable(command) or _misplaced(command, i == 0, i == len(commands) - 1)
        if problem:
            raise InputError(problem, program.source, command.line)
    _check_order(commands, program.source)
    out = [b"<?xml version='1.0' encoding='UTF-8'?>\n<CRCLProgram>\n"]
    line = 3  # of the first command
    starts = list(range(0, len(commands), max(CHUNK, 2)))
    if len(starts) > 1 and len(commands) - starts[-1] < 2:
        starts.pop()  # a last chunk of EndCanon alone would not be a program by itself
    for start, end in zip(starts, starts[1:] + [len(commands)]):
        root = etree.Element("CRCLProgram")
        for command in commands[start:end]:
            _write_command(etree.SubElement(root, type(command).__name__), command)
        body = etree.tostring(root, encoding="UTF-8", pretty_print=True)
        body = body[len(b"<CRCLProgram>\n"): -len(b"</CRCLProgram>\n")]
        if schema is not None:  # a chunk alone, framed by InitCanon / EndCanon where it lacks them
            head = b"" if start == 0 else b"  <InitCanon/>\n"
            tail = b"" if end == len(commands) else b"  <EndCanon/>\n"
            chunk = b"<CRCLProgram>\n" + head + body + tail + b"</CRCLProgram>\n"
            _check_schema(_parse(chunk, program.source), schema, program.source,
                          "kitkb wrote XML that breaks", line - 2 - head.count(b"\n"))
        out.append(body)
        line += body.count(b"\n")
    out.append(b"</CRCLProgram>\n")
    return b"".join(out)


#: Commands :func:`write_xml` turns into XML (and validates) at a time.
CHUNK = 10_000


def unwritable(command: Command) -> str | None:
    """Why ``command`` cannot be written as CRCL.xsd XML (None when it can); where a program
    may hold it (InitCanon first, EndCanon last) is not checked here."""
    return _unwritable(command)


def _unwritable(command: Command) -> str | None:
    if isinstance(command, Unreadable):
        first = command.text.strip().split("\n")[0]
        return f"unreadable line {first!r} ({command.reason}); cannot write it as XML"
    if type(command) not in ELEMENTS:
        return f"{type(command).__name__} has no element in CRCL.xsd (the early schema); cannot write it as XML"
    if isinstance(command, MoveThroughTo) and command.straight:
        return "a MoveThroughTo in straight lines (CRCL 1.x's MoveStraight true) has no CRCL.xsd form"
    if isinstance(command, EndCanon) and command.reason != 0:
        return (f"EndCanon({command.reason}): CRCL.xsd's EndCanon has no reason; "
                "only EndCanon(0) can be written as XML")
    if isinstance(command, Message) and _XML_CHARS.search(command.message):
        return "Message holds control characters that XML 1.0 cannot hold; cannot write it as XML"
    return None


def _write_command(el: Any, command: Command) -> None:
    if isinstance(command, MoveThroughTo):
        for pose in command.waypoints:
            _write_pose(etree.SubElement(el, "Waypoint"), pose)
        etree.SubElement(el, "NumPositions").text = str(command.num_positions)
        return
    for field_name, child, kind in ELEMENTS[type(command)]:
        value = getattr(command, field_name)
        if kind == "pose":
            _write_pose(etree.SubElement(el, child), value)
        else:
            etree.SubElement(el, child).text = _decimal_text(value) if kind == "decimal" else value


def _write_pose(el: Any, pose: Pose) -> None:
    for tag, names, values in (("Point", "XYZ", pose.point), ("ZAxis", "IJK", pose.z_axis),
                               ("XAxis", "IJK", pose.x_axis)):
        vec = etree.SubElement(el, tag)
        for n, v in zip(names, values):
            etree.SubElement(vec, n).text = _decimal_text(v)


#: Magnitudes below this are written as 0 (sin(pi)-sized noise), as in :mod:`kb.crcl.instance`.
TINY = 1e-12
#: The most digits libxml2 (xmllint) reads in an ``xs:decimal``.
DECIMAL_DIGITS = 24


def _decimal_text(x: float) -> str:
    """``x`` as an ``xs:decimal`` (no exponent) that reads back as the same float: 0.0 for a
    magnitude under :data:`TINY`; rounded to :data:`DECIMAL_DIGITS` digits where it has more
    (libxml2 refuses longer decimals), which only a number beyond 1e10 or below 1e-7 with all
    its 17 significant digits can need."""
    x = float(x)
    if abs(x) < TINY:
        return "0.0"
    text = format(Decimal(repr(x)), "f")
    digits = sum(ch.isdigit() for ch in text)
    if digits > DECIMAL_DIGITS:
        integer = len(text.lstrip("-").split(".")[0].lstrip("0"))
        places = max(DECIMAL_DIGITS - max(integer, 1), 0)
        with localcontext(prec=1000):
            text = format(round(Decimal(repr(x)), places), "f")
        text = text.rstrip("0").rstrip(".") if "." in text else text
    return text
