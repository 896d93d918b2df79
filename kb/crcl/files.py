"""CRCL files by their suffix: ``.crcl`` the text form (NIST's layout written by default, the
first paper's with ``text_style="paper"``; both read), ``.xml`` CRCL XML: NIST's 2014 CRCL.xsd
programs and CRCL 1.x documents (a ``CRCLProgramInstance`` program or one
``CRCLCommandInstance``), told apart when read, chosen by ``xml_form`` when written
(:data:`XML_FORMS`; by default the form the program was read in, 2014 for a text program).

Each form has its own default units (:data:`kb.crcl.units.FORM_UNITS`); a program written in a
form with other defaults says its units after each InitCanon (:func:`kb.crcl.units.restate`)."""

from __future__ import annotations

from pathlib import Path

from lxml import etree

from kb.core.errors import InputError
from kb.core.files import note_input, write_atomic
from kb.crcl import commands as c
from kb.crcl.commands import CRCL1_UNITS, Program, Unreadable
from kb.crcl.text import read_text, write_text
from kb.crcl.units import FORM_UNITS, UNIT_FREE, check_lone, restate
from kb.crcl.xml import read_xml, write_xml

#: File suffix -> form.
FORMS = {".crcl": "text", ".xml": "xml"}
#: The XML forms :func:`write_file` writes: NIST's 2014 CRCL.xsd program, a CRCL 1.x program
#: (CRCLProgramInstance.xsd), a CRCL 1.x command instance (one command, CRCLCommandInstance.xsd).
XML_FORMS = ("2014", "1.x", "command")


def form_of(path: str | Path) -> str:
    """``"text"`` or ``"xml"`` by the suffix of ``path``; another suffix is an InputError."""
    suffix = Path(path).suffix.lower()
    if suffix not in FORMS:
        raise InputError(f"unknown CRCL file suffix {suffix or '(none)'!r}: "
                         ".crcl for the text form, .xml for CRCL XML", path)
    return FORMS[suffix]


def read_file(path: str | Path, schema: etree.XMLSchema | None = None) -> Program:
    """The program in ``path`` (a 2014 XML file validated against ``schema`` when given, a
    CRCL 1.x one against NIST's 1.x schemas when they are found); it carries its form's units."""
    note_input(path)
    if form_of(path) == "xml":
        return read_xml(Path(path), schema)
    return read_text(Path(path))


def xml_form_of(program: Program, xml_form: str | None = None) -> str:
    """The XML form to write ``program`` in: ``xml_form`` (one of :data:`XML_FORMS`), else
    CRCL 1.x for a program read from CRCL 1.x, else 2014."""
    if xml_form is None:
        return "1.x" if program.units == CRCL1_UNITS else "2014"
    if xml_form not in XML_FORMS:
        raise InputError(f"unknown CRCL XML form {xml_form!r}: {', '.join(XML_FORMS)}")
    return xml_form


def write_file(program: Program, path: str | Path, schema: etree.XMLSchema | None = None,
               text_style: str = "nist", xml_form: str | None = None) -> Path:
    """Write ``program`` to ``path`` in the form of its suffix, completely or not at all; text
    in ``text_style`` (:data:`kb.crcl.text.TEXT_STYLES`), XML in ``xml_form``
    (:func:`xml_form_of`); its units said after InitCanon where the form's defaults differ.
    ``schema`` (CRCL.xsd) checks 2014 XML; CRCL 1.x is checked against NIST's 1.x schemas when
    they are found (:func:`kb.crcl.instance.default_schemas`)."""
    if form_of(path) == "text":
        check_lone(program, FORM_UNITS["text"])
        return write_atomic(path, write_text(restate(program, FORM_UNITS["text"]), text_style))
    return write_atomic(path, xml_bytes(program, xml_form, schema))


def xml_bytes(program: Program, xml_form: str | None = None, schema: etree.XMLSchema | None = None) -> bytes:
    """``program`` as CRCL XML in ``xml_form`` (:func:`xml_form_of`)."""
    from kb.crcl import instance  # lxml schemas of CRCL 1.x only when written
    form = xml_form_of(program, xml_form)
    if form == "2014":
        check_lone(program, FORM_UNITS["xml"])
        return write_xml(restate(program, FORM_UNITS["xml"]), schema)
    if form == "1.x":
        check_lone(program, CRCL1_UNITS)
        data = instance.write_program_instance(restate(program, CRCL1_UNITS))
        kind = "program"
    else:
        data = instance.write_command_instance(_one(program), 1, pretty=True)
        kind = "command"
    if instance.default_schemas() is not None:
        instance.validate(data, kind, f"kitkb's CRCL 1.x for {program.source or 'a program'}")
    return data


def _one(program: Program) -> c.Command:
    """The one command of ``program``, which a command instance can hold with its meaning."""
    if len(program) != 1:
        raise InputError(f"a CRCL 1.x command instance holds one command; this program has {len(program)} "
                         "(--xml-form 1.x writes a program)", program.source)
    command = program[0]
    if program.units not in (None, CRCL1_UNITS) and not isinstance(command, UNIT_FREE):
        raise InputError(f"{type(command).__name__} is in {' and '.join(program.units)} here, and a command "
                         "instance cannot say so (a CRCL 1.x controller reads meter and radian): write a "
                         "CRCL 1.x program (--xml-form 1.x), which says its units after InitCanon",
                         program.source, command.line)
    return command


def convert(source: str | Path, target: str | Path, schema: etree.XMLSchema | None = None,
            text_style: str = "nist", xml_form: str | None = None) -> Program:
    """Read ``source`` and write it to ``target``, each in the form of its suffix (text in
    ``text_style``, XML in ``xml_form``); the program as read. Nothing is written when reading
    or writing fails, or when nothing in ``source`` is a command (:func:`require_commands`)."""
    form_of(target)
    if xml_form is not None:
        xml_form_of(Program(()), xml_form)
    program = require_commands(read_file(source, schema), source)
    write_file(program, target, schema, text_style, xml_form)
    return program


#: What a CRCL file is looked at for, in the error that finds none.
LOOKED_FOR = {
    "text": ("CRCL commands as Name(arguments), e.g. InitCanon(), MoveTo({{x, y, z}, {i, j, k}, {i, j, k}}), "
             "in NIST's kittingViewer form or the first paper's Fig. 11"),
    "xml": "CRCL commands as elements of a CRCL.xsd CRCLProgram (InitCanon, MoveTo, ...) or of a CRCL 1.x "
           "CRCLProgram / CRCLCommandInstance",
}


def nothing_understood(source: str | Path | None, statements: int, line: int | None, reason: str,
                       form: str = "text") -> InputError:
    """The error of a CRCL file none of whose ``statements`` is a command (the first
    unreadable one at ``line``, for ``reason``), saying what was looked for."""
    looked = f"looked for {LOOKED_FOR[form]}"
    if not statements:
        return InputError(f"no CRCL command in it: {looked}", source)
    why = f" (the first at this line: {reason})" if reason else ""
    return InputError(f"none of its {statements} statement(s) is a CRCL command kitkb reads{why}; {looked}",
                      source, line)


def require_commands(program: Program, source: str | Path | None = None) -> Program:
    """``program``, if one of its commands was understood; else the InputError of
    :func:`nothing_understood` (a file of which nothing is read is not a program)."""
    if any(not isinstance(c, Unreadable) for c in program):
        return program
    first = program[0] if len(program) else None
    form = "xml" if source is not None and Path(source).suffix.lower() == ".xml" else "text"
    raise nothing_understood(source if source is not None else program.source, len(program),
                             first.line if first else None,
                             first.reason if isinstance(first, Unreadable) else "", form)
