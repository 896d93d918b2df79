"""``kitkb crcl convert``."""

from __future__ import annotations

from pathlib import Path

from kb.cli.output import Output
from kb.crcl import convert as convert_file
from kb.crcl import default_xsd, schema
from kb.crcl.files import form_of

_FORM = {"text": "CRCL text", "xml": "CRCL XML"}


def convert(input: str, output: str, xsd: str | None, out: Output) -> int:
    """Convert ``input`` to ``output`` (``.crcl`` text, ``.xml`` CRCL.xsd instances), XML
    read and written checked against CRCL.xsd (``xsd``, else the one beside the checkout)."""
    path = Path(xsd) if xsd else default_xsd()
    with out.progress(f"converting {Path(input).name} to {Path(output).name}"):
        program = convert_file(input, output, schema(path) if path else None)
    notes = [f"{len(program)} commands"]
    if program.unreadable:
        notes.append(f"{len(program.unreadable)} unreadable line(s) kept")
    unchecked = path is None and "xml" in (form_of(input), form_of(output))
    if unchecked:
        notes.append("XML not validated: CRCL.xsd not found, give --xsd")
    out.done(f"wrote {output} ({_FORM[form_of(output)]}, {'; '.join(notes)})", output=output, input=input,
             form=form_of(output), commands=len(program), unreadable=len(program.unreadable),
             xsd=str(path) if path else None, xml_not_validated=unchecked)
    return 0
