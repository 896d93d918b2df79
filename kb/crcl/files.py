"""CRCL files by their suffix: ``.crcl`` the text form, ``.xml`` CRCL.xsd instances."""

from __future__ import annotations

from pathlib import Path

from lxml import etree

from kb.core.errors import InputError
from kb.core.files import note_input, write_atomic
from kb.crcl.commands import Program
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


def write_file(program: Program, path: str | Path, schema: etree.XMLSchema | None = None) -> Path:
    """Write ``program`` to ``path`` in the form of its suffix, completely or not at all."""
    if form_of(path) == "xml":
        return write_atomic(path, write_xml(program, schema))
    return write_atomic(path, write_text(program))


def convert(source: str | Path, target: str | Path, schema: etree.XMLSchema | None = None) -> Program:
    """Read ``source`` and write it to ``target``, each in the form of its suffix; the
    program. Nothing is written when reading or writing fails."""
    form_of(target)
    program = read_file(source, schema)
    write_file(program, target, schema)
    return program
