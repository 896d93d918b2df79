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
_XML_FORM = {"2014": "NIST's 2014 CRCL.xsd: --xml-form 2014", "1.x": "a CRCL 1.x program: --xml-form 1.x",
             "command": "a CRCL 1.x command instance: --xml-form command"}


def convert(input: str, output: str, xsd: str | None, out: Output, text_style: str | None = None,
            xml_form: str | None = None) -> int:
    """Convert ``input`` to ``output`` (``.crcl`` text, ``.xml`` CRCL XML: 2014 CRCL.xsd or CRCL
    1.x, ``xml_form``), 2014 XML read and written checked against CRCL.xsd (``xsd``, else the
    one beside the checkout), CRCL 1.x against NIST's 1.x schemas when found; text written in
    ``text_style`` (NIST's kittingViewer form unless ``paper``); units said after InitCanon
    where the two forms' defaults differ."""
    from kb.crcl.files import xml_form_of
    from kb.crcl.instance import default_schemas
    if text_style is not None and form_of(output) != "text":
        raise InputError(f"--text-style chooses the layout of CRCL text (.crcl); {output} is CRCL XML")
    if xml_form is not None and form_of(output) != "xml":
        raise InputError(f"--xml-form chooses the CRCL XML written (.xml); {output} is CRCL text")
    style = text_style or "nist"
    path = Path(xsd) if xsd else default_xsd()
    with out.progress(f"converting {Path(input).name} to {Path(output).name}"):
        program = convert_file(input, output, schema(path) if path else None, style, xml_form)
    form = form_of(output)
    written = xml_form_of(program, xml_form) if form == "xml" else None
    notes = [f"{len(program)} commands"]
    if program.unreadable:
        notes.append(f"{len(program.unreadable)} unreadable line(s) kept")
    crcl1 = program.units == ("meter", "radian") or written in ("1.x", "command")
    unchecked = (path is None and "xml" in (form_of(input), form) and not crcl1) or (crcl1 and default_schemas() is None)
    if unchecked:
        notes.append("XML not validated: " + ("CRCL 1.x schemas not found, set $KITKB_CRCL_DIR" if crcl1
                                               else "CRCL.xsd not found, give --xsd"))
    what = (f"{_FORM[form]}, {_STYLE[style]}" if form == "text"
            else f"{_FORM[form]}, {_XML_FORM[written]}" if written in ("1.x", "command") else _FORM[form])
    out.done(f"wrote {output} ({what}, {'; '.join(notes)})", output=output, input=input,
             form=form, text_style=style if form == "text" else None, xml_form=written, commands=len(program),
             unreadable=len(program.unreadable), xsd=str(path) if path else None, xml_not_validated=unchecked)
    return 0
