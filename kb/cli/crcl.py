"""``kitkb crcl convert`` and ``kitkb crcl send``."""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Any

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


# --- kitkb crcl send --------------------------------------------------------------------------------

def send(file: str, to: str, timeout: float, out: Output) -> int:
    """Stream the program (or command instance) in ``file`` to the CRCL 1.x controller at ``to``
    one command at a time, each waited for until its Done or Error (``timeout`` seconds); 0 when
    every command is done, 1 when one ended in CRCL_Error or was not acknowledged in time."""
    from kb.core.errors import CellError
    from kb.crcl.remote import stream
    from kb.crcl.wire import parse_peer

    host, port = parse_peer(to)
    if not timeout > 0:
        raise InputError(f"--timeout {timeout:g}: a positive number of seconds")
    commands = _for_controller(file)
    with out.progress(f"sending {Path(file).name} to {to}", total=len(commands), unit="commands") as task:
        try:
            outcomes, last = stream(commands, host, port, timeout, lambda o: task.advance())
        except CellError as exc:
            raise CellError(f"{exc.message} (sending {file})", exc.address) from None
    rows = [_row(o) for o in outcomes]
    failed = next((o for o in outcomes if not o.done), None)
    facts = {"file": file, "to": to, "sent": len(outcomes), "commands": rows, "all_done": failed is None,
             "last_status": _status(last)}
    if failed is None:
        out.done(f"sent {len(outcomes)} commands of {file} to {to}: all done{_where(last)}", **facts)
        return 0
    line = f"{file}: error: {_failure(failed, to)}"
    if out.is_json:
        out.emit({"message": line, **facts})
    print(line, file=out.stderr or sys.stderr)
    return 1


def _for_controller(file: str) -> list[Any]:
    """The commands of ``file`` as a CRCL 1.x controller reads them: a CRCL 1.x document's as
    they are written (kitkb need not read them), a program of another form converted, with its
    units said (after each InitCanon, and first when it does not start with one)."""
    from kb.core.files import note_input
    from kb.crcl.commands import CRCL1_UNITS, InitCanon, SetAngleUnits, SetLengthUnits
    from kb.crcl.files import read_file, require_commands
    from kb.crcl.instance import unwritable
    from kb.crcl.remote import forwarded
    from kb.crcl.units import restate

    note_input(file)
    try:
        as_written = forwarded(file)
    except OSError as exc:
        raise InputError(f"cannot read it: {exc.strerror or exc}", file) from None
    if as_written is not None:
        return as_written
    program = require_commands(read_file(file), file)
    unreadable = program.unreadable
    if unreadable:
        first = unreadable[0]
        raise InputError(f"{len(unreadable)} statement(s) that do not parse, the first: {first.reason or first.text}",
                         file, first.line)
    for command in program:
        why = unwritable(command)
        if why:
            raise InputError(f"{why}: a CRCL 1.x controller cannot be sent it", file, command.line)
    commands = list(restate(program, CRCL1_UNITS).commands)
    own = program.units
    if own is not None and tuple(own) != tuple(CRCL1_UNITS) and not isinstance(commands[0], InitCanon):
        commands = [SetLengthUnits(own[0]), SetAngleUnits(own[1])] + commands
    return commands


def _row(o: Any) -> dict[str, Any]:
    st = o.status
    return {"id": o.command_id, "command": o.name,
            "state": st.state if st is not None else None,
            "status_command_id": st.command_id if st is not None else None,
            "seconds": round(o.seconds, 6), "description": st.description if st is not None else "",
            **({"why": o.why} if o.why else {})}


def _status(st: Any) -> dict[str, Any] | None:
    if st is None:
        return None
    pose = st.pose
    g = st.gripper
    return {"command_id": st.command_id, "status_id": st.status_id, "state": st.state,
            "description": st.description,
            "pose": None if pose is None else {"point": list(pose.point), "x_axis": list(pose.x_axis),
                                               "z_axis": list(pose.z_axis)},
            "gripper": None if g is None else {"name": g.name, "kind": g.kind, "separation": g.separation,
                                               "powered": g.powered, "holding": g.holding}}


def _where(st: Any) -> str:
    if st is None or st.pose is None:
        return ""
    return " (pose " + ", ".join(f"{v:g}" for v in st.pose.point) + ")"


def _failure(o: Any, to: str) -> str:
    name = f"command {o.command_id} ({o.name})"
    if o.why:
        hint = " (a controller that never acknowledges InitCanon?)" if o.name == "InitCanon" else ""
        return f"{to}: {o.name} {o.why}{hint}"
    return f"{to}: {name} ended in CRCL_Error: {o.status.description or 'no description'}"
