"""CRCL files by their suffix: ``.crcl`` the text form (NIST's layout written by default, the
first paper's with ``text_style="paper"``; both read), ``.xml`` CRCL.xsd instances."""

from __future__ import annotations

from pathlib import Path

from lxml import etree

from kb.core.errors import InputError
from kb.core.files import note_input, write_atomic
from kb.crcl.commands import Program, Unreadable
from kb.crcl.text import read_text, write_text
from kb.crcl.xml import read_xml, write_xml

#: File suffix -> form.
FORMS = {".crcl": "text", ".xml": "xml"}


def form_of(path: str | Path) -> str:
    """``"text"`` or ``"xml"`` by the suffix of ``path``; another suffix is an InputError."""
    suffix = Path(path).suffix.lower()
    if suffix not in FORMS:
        raise InputError(f"unknown CRCL file suffix {suffix or '(none)'!r}: "
                         ".crcl for the text form, .xml for CRCL XML", path)
    return FORMS[suffix]


def read_file(path: str | Path, schema: etree.XMLSchema | None = None) -> Program:
    """The program in ``path`` (an XML file validated against ``schema`` when given)."""
    note_input(path)
    if form_of(path) == "xml":
        return read_xml(Path(path), schema)
    return read_text(Path(path))


def write_file(program: Program, path: str | Path, schema: etree.XMLSchema | None = None,
               text_style: str = "nist") -> Path:
    """Write ``program`` to ``path`` in the form of its suffix, completely or not at all; text
    in ``text_style`` (:data:`kb.crcl.text.TEXT_STYLES`)."""
    if form_of(path) == "xml":
        return write_atomic(path, write_xml(program, schema))
    return write_atomic(path, write_text(program, text_style))


def convert(source: str | Path, target: str | Path, schema: etree.XMLSchema | None = None,
            text_style: str = "nist") -> Program:
    """Read ``source`` and write it to ``target``, each in the form of its suffix (text in
    ``text_style``); the program. Nothing is written when reading or writing fails, or when
    nothing in ``source`` is a command (:func:`require_commands`)."""
    form_of(target)
    program = require_commands(read_file(source, schema), source)
    write_file(program, target, schema, text_style)
    return program


#: What a CRCL file is looked at for, in the error that finds none.
LOOKED_FOR = {
    "text": ("CRCL commands as Name(arguments), e.g. InitCanon(), MoveTo({{x, y, z}, {i, j, k}, {i, j, k}}), "
             "in NIST's kittingViewer form or the first paper's Fig. 11"),
    "xml": "CRCL commands as elements of a CRCL.xsd CRCLProgram (InitCanon, MoveTo, ...)",
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
