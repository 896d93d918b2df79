"""The XML ground kitkb's CRCL readers stand on (:mod:`kb.crcl.xml` for NIST's 2014 CRCL.xsd,
:mod:`kb.crcl.instance` for CRCL 1.x): a hardened parser (no DTD, no entity, no network; a
DOCTYPE refused) and schemas loaded from their folder, so their relative includes are found."""

from __future__ import annotations

import io
import os
import re
from pathlib import Path
from typing import Any

from lxml import etree

from kb.core.errors import InputError

#: Characters XML 1.0 cannot hold.
_XML_CHARS = re.compile("[^\t\n\r\x20-\ud7ff\ue000-\ufffd\U00010000-\U0010ffff]")
_REPO = Path(__file__).resolve().parents[2]


def default_xsd() -> Path | None:
    """NIST's CRCL.xsd where kitkb looks for it: ``$KITKB_NIST_DIR/CRCL.xsd``, else
    ``../shared/nist/CRCL.xsd`` beside the checkout; None when neither exists."""
    folders = [Path(d) for d in [os.environ.get("KITKB_NIST_DIR")] if d]
    folders.append(_REPO.parent / "shared" / "nist")
    return next((f / "CRCL.xsd" for f in folders if (f / "CRCL.xsd").is_file()), None)


def schema(path: str | os.PathLike[str] | None = None) -> etree.XMLSchema:
    """The XML schema at ``path`` (default :func:`default_xsd`), for :func:`read_xml` and
    :func:`write_xml`; a missing or broken file is an :class:`~kb.core.errors.InputError`."""
    found = Path(path) if path is not None else default_xsd()
    if found is None:
        raise InputError("CRCL.xsd not found (looked in $KITKB_NIST_DIR and ../shared/nist "
                         "beside the checkout); give its path")
    # the schema's own folder is its base, so its relative xs:include / xs:import are found
    # (CRCL 1.x's CRCLProgramInstance.xsd includes CRCLCommands.xsd ...); no network
    tree = _parse(_read(found), str(found), base_url=str(found.resolve()))
    try:
        return etree.XMLSchema(tree)
    except etree.XMLSchemaParseError as exc:
        raise InputError(f"not a usable XML schema: {exc}", found) from None


def _read(path: Path) -> bytes:
    try:
        return path.read_bytes()
    except OSError as exc:
        raise InputError(f"cannot read: {exc.strerror or exc}", path) from None


def hardened_parser() -> etree.XMLParser:
    """An lxml parser that loads no DTD, resolves no entity and never uses the network."""
    return etree.XMLParser(resolve_entities=False, no_network=True, load_dtd=False,
                           dtd_validation=False, huge_tree=False)


def _parse(data: bytes, name: str | None, base_url: str | None = None) -> Any:
    """The document of ``data``, parsed by :func:`hardened_parser` (relative references from
    ``base_url``); a DOCTYPE is refused."""
    try:
        tree = etree.parse(io.BytesIO(data), hardened_parser(), base_url=base_url)
    except etree.XMLSyntaxError as exc:
        raise syntax_error(exc, name) from None
    if tree.docinfo.internalDTD is not None or tree.docinfo.doctype:
        line = data.count(b"\n", 0, max(data.find(b"<!DOCTYPE"), 0)) + 1
        raise InputError("a DOCTYPE is not allowed in CRCL XML (no entity is expanded or fetched)",
                         name, line)
    return tree


def syntax_error(exc: etree.XMLSyntaxError, name: "str | Path | None") -> InputError:
    """lxml's syntax error as one line at its file and line: libxml2's first line of the
    message, without the ", line L, column C" lxml adds (the line is the error's own)."""
    message = ((exc.msg or str(exc)).strip().splitlines() or ["not well-formed"])[0]
    message = re.sub(r",? line \d+, column \d+$", "", message).rstrip(", ") or "not well-formed"
    return InputError(f"XML syntax error: {message}", name, exc.lineno)
