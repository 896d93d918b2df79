"""``kitkb crcl convert``."""

from __future__ import annotations

from pathlib import Path

from kb.cli.output import Output
from kb.core.errors import InputError
from kb.crcl import convert as convert_file
from kb.crcl import default_xsd, schema
from kb.crcl.files import form_of

_FORM = {"text": "CRCL text", "xml": "CRCL XML"}
_STYLE = {"nist": "NIST's kittingViewer form: --text-style nist", "paper": "the paper's Fig. 11 form: --text-style paper"}


def convert(input: str, output: str, xsd: str | None, out: Output, text_style: str | None = None) -> int:
    """Convert ``input`` to ``output`` (``.crcl`` text, ``.xml`` CRCL.xsd instances), XML
    read and written checked against CRCL.xsd (``xsd``, else the one beside the checkout);
    text written in ``text_style`` (NIST's kittingViewer form unless ``paper``)."""
    if text_style is not None and form_of(output) != "text":
        raise InputError(f"--text-style chooses the layout of CRCL text (.crcl); {output} is CRCL XML")
    style = text_style or "nist"
    path = Path(xsd) if xsd else default_xsd()
    with out.progress(f"converting {Path(input).name} to {Path(output).name}"):
        program = convert_file(input, output, schema(path) if path else None, style)
    form = form_of(output)
    notes = [f"{len(program)} commands"]
    if program.unreadable:
        notes.append(f"{len(program.unreadable)} unreadable line(s) kept")
    unchecked = path is None and "xml" in (form_of(input), form)
    if unchecked:
        notes.append("XML not validated: CRCL.xsd not found, give --xsd")
    what = f"{_FORM[form]}, {_STYLE[style]}" if form == "text" else _FORM[form]
    out.done(f"wrote {output} ({what}, {'; '.join(notes)})", output=output, input=input,
             form=form, text_style=style if form == "text" else None, commands=len(program),
             unreadable=len(program.unreadable), xsd=str(path) if path else None, xml_not_validated=unchecked)
    return 0
