"""Read one RDF/OWL file into rdflib terms: its text, format detection, safe XML, syntax errors.

:func:`prepare` makes the text the parsers read, line for line the file: the encoding of its
byte order mark or XML declaration transcoded, the entities of an internal DTD expanded within
bounds (as Protégé writes them), ``//`` comment lines blanked, ``file:`` paths made IRIs.
Turtle, N-Triples and RDF/XML are parsed by pyoxigraph; OWL functional syntax and OWL/XML
by py-horned-owl, which re-serialises them as RDF/XML for pyoxigraph; their errors become one
line at ``file:line``. Every IRI is passed through :func:`map_iri` on the way into rdflib
terms (NIST's namespaces onto kitkb's).
"""

from __future__ import annotations

import codecs
import logging
import re
import xml.parsers.expat
from dataclasses import dataclass, field
from functools import lru_cache
from itertools import islice
from urllib.parse import quote
from pathlib import Path
from typing import Iterable

import pyoxigraph as ox
from rdflib import BNode, Graph, Literal, URIRef

from kb.core.diagnostics import Diagnostic
from kb.core import limits
from kb.core.errors import InputError
from kb.core.namespaces import (KTW, NAMESPACE_MAP, NIST_2012_RENAMES, NIST_2012_UNMAPPED, NIST_KTW_2012,
                                 PREFIXES)
from kb.core.resources import ontology_path
from kb.patches.rdflib import memory_graph

Triple = tuple[URIRef | BNode, URIRef, URIRef | BNode | Literal]

FORMATS = ("turtle", "ntriples", "rdfxml", "owlxml", "ofn")
_EXTENSION_FORMAT = {".ttl": "turtle", ".nt": "ntriples", ".ofn": "ofn", ".owx": "owlxml"}
_OX_FORMAT = {"turtle": ox.RdfFormat.TURTLE, "ntriples": ox.RdfFormat.N_TRIPLES, "rdfxml": ox.RdfFormat.RDF_XML}
_OWL_NS = "http://www.w3.org/2002/07/owl#"
_XML_ROOT = re.compile(r"<(?:([A-Za-z_][\w.-]*):)?([A-Za-z_][\w.-]*)[\s>/]")
_OFN_START = re.compile(r"(?:Prefix|Ontology)\s*\(")
_MAX_ENTITY_TEXT = 10_000
# Nesting (kb.core.limits.NESTING): py-horned-owl recurses natively per level, rdflib's Turtle
# writer and kitkb's line indexes in Python; tokens that open and close a level, per syntax.
_OFN_NESTING = re.compile(r'"(?:[^"\\]|\\.)*"|<[^<>\s]*>|[()]')
_TURTLE_NESTING = re.compile("|".join((
    r'"""(?:[^"\\]|\\.|"(?!""))*"""', r"'''(?:[^'\\]|\\.|'(?!''))*'''",  # long strings
    r'"(?:[^"\\\n]|\\.)*"', r"'(?:[^'\\\n]|\\.)*'",  # strings
    r'<[^<>"{}|^`\\\s]*>', r"#[^\n]*", r"[\[\]()]")))  # IRIs, comments, the nesting tokens
_XSD_STRING = "http://www.w3.org/2001/XMLSchema#string"
_PREFIX_NAME = re.compile(r"(?:[A-Za-z][\w.-]*)?")


class _QuietIllTypedLiterals(logging.Filter):
    """rdflib logs a traceback for every ill-typed literal it builds ("abc"^^xsd:decimal)
    and a warning for odd IRIs; both are data to validate (``Literal.ill_typed``), and the
    command line must not print tracebacks."""

    def filter(self, record: logging.LogRecord) -> bool:
        message = str(record.msg)
        return not (message.startswith("Failed to convert Literal lexical form")
                    or "does not look like a valid URI" in message)


logging.getLogger("rdflib.term").addFilter(_QuietIllTypedLiterals())


_MAPPED = (*NAMESPACE_MAP, NIST_KTW_2012)


def map_iri(iri: str) -> str:
    """``iri`` with a foreign namespace (NIST kitting) rewritten to ours (a term of NIST's 2012
    namespace only where :func:`nist_2012_name` finds its counterpart)."""
    if not iri.startswith(_MAPPED):  # one C call for the common case
        return iri
    if iri.startswith(NIST_KTW_2012):
        return _map_2012(iri)
    for old, new in NAMESPACE_MAP.items():
        if iri.startswith(old):
            return new + iri[len(old):]
    return iri


@lru_cache(maxsize=4096)
def _map_2012(iri: str) -> str:
    name = nist_2012_name(iri[len(NIST_KTW_2012):])
    return iri if name is None else str(KTW) + name


def nist_2012_name(local: str) -> str | None:
    """kitkb's local name for the term ``local`` of NIST's 2012 namespace (``kittingClasses.owl#``):
    the same name, or its 2013 renaming (:data:`kb.core.namespaces.NIST_2012_RENAMES`), when
    kitkb's model has it; None when it has no counterpart (the term is kept as it is)."""
    if local in NIST_2012_UNMAPPED:
        return None
    name = NIST_2012_RENAMES.get(local, local)
    return name if name in model_names() else None


@lru_cache(maxsize=1)
def model_names() -> frozenset[str]:
    """The local names of the classes, properties and datatypes of kitkb's kitting model."""
    ktw = str(KTW)
    quads = ox.parse(path=str(ontology_path("kitting.ttl")), format=ox.RdfFormat.TURTLE)
    return frozenset(q.subject.value[len(ktw):] for q in quads
                     if isinstance(q.subject, ox.NamedNode) and q.subject.value.startswith(ktw))


def make_literal(lexical: str, lang: str | None, datatype: str | None) -> Literal:
    """The rdflib literal the loader builds (one place, so line indexes build equal keys)."""
    if lang:
        return Literal(lexical, lang=lang)
    if datatype is None or datatype == _XSD_STRING:
        return Literal(lexical)  # RDF 1.1: a plain literal is an xsd:string
    return Literal(lexical, datatype=URIRef(map_iri(datatype)))


def new_graph(triples: Iterable[Triple] = (), prefixes: dict[str, str] | None = None) -> Graph:
    """A graph holding ``triples``, with the ktw/soap/kd prefixes (then ``prefixes``) bound."""
    graph = memory_graph(triples)
    for prefix, iri in PREFIXES.items():
        graph.bind(prefix, iri)
    taken = set(PREFIXES) | set(PREFIXES.values())
    for prefix, iri in (prefixes or {}).items():
        if prefix not in taken and iri not in taken and _PREFIX_NAME.fullmatch(prefix):
            graph.bind(prefix, iri, override=False)
    return graph


# --- text and format ---------------------------------------------------------------------

_BOMS = ((codecs.BOM_UTF8, "utf-8"), (codecs.BOM_UTF32_LE, "utf-32-le"), (codecs.BOM_UTF32_BE, "utf-32-be"),
         (codecs.BOM_UTF16_LE, "utf-16-le"), (codecs.BOM_UTF16_BE, "utf-16-be"))
# an XML declaration's encoding, read from the bytes of an ASCII-compatible file's first line
_DECLARED = re.compile(rb"""<\?xml[ \t\r\n][^>]*?encoding[ \t\r\n]*=[ \t\r\n]*(["'])([^"'>]*)\1""")
_DECLARATION = re.compile(r"""(<\?xml[ \t\r\n][^>]*?encoding[ \t\r\n]*=[ \t\r\n]*)(["'])([^"'>]*)\2""")


def decode(data: bytes, path: Path) -> str:
    """``data`` as text (see :func:`decode_text`)."""
    return decode_text(data, path)[0]


def decode_text(data: bytes, path: Path) -> tuple[str, str]:
    """``data`` as text, and the encoding it was read in: by its byte order mark, else the
    encoding its XML declaration names (``<?xml version="1.0" encoding="ISO-8859-1"?>``; any
    encoding Python's codecs know), else UTF-8. The declaration in the text then says UTF-8
    (what the parsers are given). An unknown encoding is an InputError at line 1, a byte the
    encoding cannot read one at its line."""
    encoding, body, declared = _encoding_of(data, path)
    text = _decoded(body, encoding, path, declared)
    if encoding != "utf-8":
        if detect_format(text, path) not in ("rdfxml", "owlxml"):  # Turtle, N-Triples: UTF-8 only
            return _decoded(data, "utf-8", path, None).removeprefix("\ufeff"), "utf-8"
        text = _DECLARATION.sub(lambda m: f"{m.group(1)}{m.group(2)}UTF-8{m.group(2)}", text, count=1)
    return text, encoding


def _decoded(body: bytes, encoding: str, path: Path, declared: str | None) -> str:
    try:
        return body.decode(encoding)
    except UnicodeDecodeError as exc:
        line = body[: exc.start].decode(encoding, "replace").count("\n") + 1
        name = "UTF-8" if encoding == "utf-8" else encoding
        raise InputError(f"not {name} text (byte 0x{body[exc.start]:02x})", path, line) from None
    except LookupError:  # a codec that does not decode bytes to text (base64, rot13...)
        raise InputError(f"unknown character encoding '{declared or encoding}'", path, 1) from None


def _encoding_of(data: bytes, path: Path) -> tuple[str, bytes, str | None]:
    """(codec name, the bytes to decode, the declared name) of ``data``."""
    for bom, name in _BOMS:
        if data.startswith(bom):
            return name, data[len(bom):], None
    if data.startswith(b"<\x00?\x00"):
        return "utf-16-le", data, None
    if data.startswith(b"\x00<\x00?"):
        return "utf-16-be", data, None
    m = _DECLARED.match(data, 0, 400)
    if m is None:
        return "utf-8", data, None
    declared = m.group(2).decode("ascii", "replace").strip()
    try:
        info = codecs.lookup(declared)
    except LookupError:
        info = None
    if info is None or not getattr(info, "_is_text_encoding", True):
        raise InputError(f"unknown character encoding '{declared}' in the XML declaration", path, 1)
    name = "utf-8" if info.name in ("utf-8", "utf-8-sig") else info.name
    if name.startswith(("utf-16", "utf-32")):  # declared so, but written without a BOM in ASCII
        raise InputError(f"the XML declaration says {declared} but the file is not written in it", path, 1)
    return name, data, declared


def detect_format(text: str, path: Path) -> str:
    """The format of ``text`` by its content, with the file extension as a tie-breaker."""
    head = _skip_comments(text[:20000])
    if head.startswith("<") and not head.startswith("<http") and not re.match(r"<[^>\s]*>\s", head):
        return _xml_flavour(head, path)
    if _OFN_START.match(head):
        return "ofn"
    ext = _EXTENSION_FORMAT.get(path.suffix.lower())
    if ext in ("turtle", "ntriples"):
        return ext
    if ext is not None:
        return ext
    return "turtle"


def _skip_comments(head: str) -> str:
    while True:
        head = head.lstrip("\ufeff \t\r\n")
        if head.startswith("//") or head.startswith("#"):
            nl = head.find("\n")
            head = "" if nl < 0 else head[nl + 1:]
            continue
        if head.startswith("<?") or head.startswith("<!--") or head.startswith("<!DOCTYPE"):
            end = {"<?": "?>", "<!--": "-->", "<!DOCTYPE": "]>" if "[" in head.split(">", 1)[0] else ">"}
            key = next(k for k in end if head.startswith(k))
            pos = head.find(end[key])
            if pos < 0:
                return head
            head = head[pos + len(end[key]):]
            continue
        return head


def _xml_flavour(head: str, path: Path) -> str:
    m = _XML_ROOT.match(head)
    local = m.group(2) if m else ""
    if local == "Ontology":
        return "owlxml"
    if local == "RDF" or path.suffix.lower() in (".rdf", ".owl", ".xml"):
        return "rdfxml"
    return "rdfxml"


# --- reading a file's text ----------------------------------------------------------------

@dataclass
class Prepared:
    """A file's text as the parsers and the line indexes read it: decoded, XML entities of
    its internal DTD expanded, ``//`` comment lines blanked, ``file:`` paths made IRIs — line
    for line the file as written, so ``file:line`` stays true. ``utf8``: the file's bytes are
    this text in UTF-8 (the Turtle parser may then read them instead of the text)."""

    text: str
    format: str
    warnings: list[Diagnostic] = field(default_factory=list)
    utf8: bool = True


def prepare(data: bytes, path: Path) -> Prepared:
    """The :class:`Prepared` text of a file's bytes; InputError for bytes no encoding reads,
    an XML entity that is not allowed or that expands past the limits."""
    text, encoding = decode_text(data, path)
    fmt = detect_format(text, path)
    warnings: list[Diagnostic] = []
    if fmt in ("rdfxml", "owlxml"):
        text = expand_entities(text, path)
    elif fmt == "ofn":
        text, warnings = strip_slash_comments(text, path)
    text, repaired = repair_file_iris(text, fmt, path)
    return Prepared(text, fmt, warnings + repaired, encoding == "utf-8" and not repaired)


# --- internal DTD entities -----------------------------------------------------------------

_PREDEFINED = frozenset({"lt", "gt", "amp", "apos", "quot"})
_ENTITY_REF = re.compile(r"&([A-Za-z_:\u00C0-\uFFFF][\w.:\-\u00B7\u00C0-\uFFFF]*);")
#: An entity's replacement may name others this deep (a deeper chain is refused).
_MAX_ENTITY_DEPTH = 50
#: A file's entities may make it this many times longer (past :data:`_EXPANSION_FLOOR`
#: characters), as expat's own guard allows: more is an entity bomb.
_AMPLIFICATION = 100
_EXPANSION_FLOOR = 8 << 20
def expand_entities(text: str, path: Path) -> str:
    """``text`` with the general entities its internal DTD declares expanded and the DOCTYPE
    blanked (its lines kept), as Protégé writes them (``<!DOCTYPE Ontology [<!ENTITY xsd
    "...">]>``, ``&xsd;`` in attributes). Entities may refer to one another; what they expand
    to is measured before anything is expanded: one entity past :data:`kb.core.limits.LITERAL`
    or the whole file past :data:`kb.core.limits.FILE_BYTES` (an entity bomb) is an InputError,
    as are parameter and external entities and attribute-list declarations. A reference in
    element content keeps its line: line breaks in the replacement become ``&#10;``."""
    span = _doctype(text)
    if span is None:
        return text
    start, end = span
    decls = _entity_decls(text[:end], path)
    body = text[end:]
    expanded = _Expansions(decls, path)
    for name in decls:  # a bomb is refused whether it is used or not
        expanded.size(name)
    used = [name for name in decls if f"&{name};" in body]
    if used:
        simple = all(_simple(value, decls) for value, _ in decls.values()) and not (
            ("<!--" in body or "<![CDATA[" in body or "<?" in body)
            and any("&" in m.group() for m in _XML_VERBATIM.finditer(body)))
        if simple:  # IRIs, as Protégé's: the same text in content and attributes, replaced in C
            counts = {name: body.count(f"&{name};") for name in used}
            total = len(text) + sum(n * (expanded.size(name) - len(name) - 2) for name, n in counts.items())
            first = min(body.find(f"&{name};") for name in used)
        else:
            refs = _references(body, decls)
            total = len(text) + sum(expanded.size(name) - length for name, _, length, _ in refs)
            first = refs[0][1] if refs else 0
        allowed = max(_EXPANSION_FLOOR, _AMPLIFICATION * len(text))
        if total > allowed:
            raise InputError(f"XML entities would expand this file to {total:,} characters, "
                             f"{total / len(text):,.0f} times its size: over the amplification limit "
                             f"({_AMPLIFICATION} times, an entity bomb)", path, text.count("\n", 0, end + first) + 1)
        limits.FILE_BYTES.check(total, path, None, f"{total:,} characters once its XML entities are expanded")
        if simple:
            for name in used:
                body = body.replace(f"&{name};", expanded.text(name))
        else:
            body = _substituted(body, refs, expanded)
    return text[:start] + "\n" * text.count("\n", start, end) + body


def _doctype(text: str) -> tuple[int, int] | None:
    """(start, end) of the DOCTYPE declaration if it has an internal subset, else None."""
    pos, n = 0, len(text)
    while pos < n:
        while pos < n and text[pos] in "\ufeff \t\r\n":
            pos += 1
        if text.startswith("<?", pos) or text.startswith("<!--", pos):
            close = text.find("?>" if text.startswith("<?", pos) else "-->", pos)
            if close < 0:
                return None
            pos = close + 2
            continue
        break
    if not text.startswith("<!DOCTYPE", pos):
        return None
    i, subset, seen = pos + 9, False, False
    while i < n:
        c = text[i]
        if c in "\"'":
            close = text.find(c, i + 1)
            if close < 0:
                return None
            i = close + 1
            continue
        if subset and (text.startswith("<!--", i) or text.startswith("<?", i)):
            close = text.find("-->" if text.startswith("<!--", i) else "?>", i)
            if close < 0:
                return None
            i = close + 2
        elif c == "[" and not subset:
            subset = seen = True
        elif c == "]" and subset:
            subset = False
        elif c == ">" and not subset:
            return (pos, i + 1) if seen else None
        i += 1
    return None


def _entity_decls(prolog: str, path: Path) -> dict[str, tuple[str, int]]:
    """name -> (replacement text, line) of the general entities the internal DTD of
    ``prolog`` (the text up to the end of the DOCTYPE) declares; InputError for a parameter,
    external or unparsed entity, or an attribute-list declaration."""
    parser = xml.parsers.expat.ParserCreate()
    parser.SetParamEntityParsing(xml.parsers.expat.XML_PARAM_ENTITY_PARSING_NEVER)
    decls: dict[str, tuple[str, int]] = {}

    def entity_decl(name, is_param, value, base, system_id, public_id, notation):  # noqa: ANN001
        line = parser.CurrentLineNumber
        if is_param:
            raise InputError(f"XML parameter entity '{name}' is not allowed", path, line)
        if value is None:
            raise InputError(f"external XML entity '{name}' is not allowed (nothing is fetched)", path, line)
        decls.setdefault(name, (value, line))

    def attlist(*args) -> None:  # noqa: ANN002
        raise InputError("an XML attribute-list declaration (<!ATTLIST>) is not read (its default values "
                         "would be lost)", path, parser.CurrentLineNumber)

    parser.EntityDeclHandler = entity_decl
    parser.UnparsedEntityDeclHandler = lambda name, *a: entity_decl(name, False, None, None, "x", None, None)
    parser.AttlistDeclHandler = attlist
    parser.ExternalEntityRefHandler = lambda *a: 1
    try:
        parser.Parse((prolog + "<_/>").encode("utf-8"), True)
    except xml.parsers.expat.ExpatError as exc:
        raise InputError(f"XML syntax error: {xml.parsers.expat.ErrorString(exc.code)}", path, exc.lineno) from None
    return decls


class _Expansions:
    """What each declared entity expands to: sizes first (no text built), then the text."""

    def __init__(self, decls: dict[str, tuple[str, int]], path: Path):
        self.decls, self.path = decls, path
        self._sizes: dict[str, int] = {}
        self._texts: dict[str, str] = {}

    def size(self, name: str, depth: int = 0, chain: tuple[str, ...] = ()) -> int:
        """Characters ``name`` expands to; InputError past the limits or for a cycle."""
        if name in self._sizes:
            return self._sizes[name]
        value, line = self.decls[name]
        if name in chain:
            raise InputError(f"XML entity '{name}' refers to itself", self.path, line)
        if depth > _MAX_ENTITY_DEPTH:
            raise InputError(f"XML entities refer to one another more than {_MAX_ENTITY_DEPTH} deep",
                             self.path, line)
        n = len(value)
        for m in _ENTITY_REF.finditer(value):
            if m.group(1) in self.decls:
                n += self.size(m.group(1), depth + 1, chain + (name,)) - len(m.group())
        limits.LITERAL.check(n, self.path, line, f"XML entity '{name}' expands to {n:,} characters")
        self._sizes[name] = n
        return n

    def text(self, name: str) -> str:
        """The text ``name`` expands to (its size checked first)."""
        if name not in self._texts:
            self.size(name)
            value = self.decls[name][0]
            self._texts[name] = _ENTITY_REF.sub(
                lambda m: self.text(m.group(1)) if m.group(1) in self.decls else m.group(), value)
        return self._texts[name]


# what makes an entity's text differ between content and attributes
_NOT_SIMPLE = re.compile(r"""[<"'\t\n\r]""")


def _simple(value: str, decls: dict) -> bool:
    """True if an entity's text reads the same in content and in attributes, and refers only
    to declared entities (so its expansion holds no reference)."""
    return _NOT_SIMPLE.search(value) is None and all(
        m.group(1) in decls for m in _ENTITY_REF.finditer(value)) and value.count("&") == len(
        _ENTITY_REF.findall(value))
# what a reference may not be expanded in: comments, CDATA sections, processing instructions
_XML_VERBATIM = re.compile(r"<!--.*?-->|<!\[CDATA\[.*?\]\]>|<\?.*?\?>", re.S)


def _references(body: str, decls: dict) -> list[tuple[str, int, int, str | None]]:
    """(name, offset, length, quote) of each reference to a declared entity in ``body``, not in
    a comment, CDATA section or processing instruction; ``quote`` is the delimiter of the
    attribute value it is in (None: element content)."""
    names = "|".join(re.escape(n) for n in sorted(decls, key=len, reverse=True))
    pattern = re.compile(rf"&({names});")
    verbatim = [(m.start(), m.end()) for m in _XML_VERBATIM.finditer(body)] if "<!" in body or "<?" in body else []
    out: list[tuple[str, int, int, str | None]] = []
    v = 0
    for m in pattern.finditer(body):
        at = m.start()
        while v < len(verbatim) and verbatim[v][1] <= at:
            v += 1
        if v < len(verbatim) and verbatim[v][0] <= at:
            continue
        out.append((m.group(1), at, len(m.group()), _quote_at(body, at)))
    return out


def _quote_at(body: str, at: int) -> str | None:
    """The quote delimiting the attribute value at ``at``, None when ``at`` is in content."""
    tag = body.rfind("<", 0, at)
    if tag < body.rfind(">", 0, at) or tag < 0:
        return None
    before = body[tag:at]
    if "'" not in before:
        return '"'
    if '"' not in before:
        return "'"
    quote = None
    for c in before:  # both kinds of quote: walk the tag from its start
        if quote is None and c in "\"'":
            quote = c
        elif c == quote:
            quote = None
    return quote or '"'


def _substituted(body: str, refs: list[tuple[str, int, int, str | None]], expanded: _Expansions) -> str:
    """``body`` with ``refs`` replaced by their entities' text (see :func:`_in_attribute` and
    :func:`_in_content`)."""
    pieces, last = [], 0
    said: dict[tuple[str, str | None], str] = {}
    for name, at, length, quote in refs:
        text = said.get((name, quote))
        if text is None:
            value = expanded.text(name)
            text = said[name, quote] = _in_content(value) if quote is None else _in_attribute(value, quote)
        pieces += (body[last:at], text)
        last = at + length
    pieces.append(body[last:])
    return "".join(pieces)


def _in_content(value: str) -> str:
    """An entity's text in element content: line breaks written ``&#10;`` (no line added),
    unless it holds markup, which is parsed as written."""
    return value if "<" in value else value.replace("\r", "&#13;").replace("\n", "&#10;")


def _in_attribute(value: str, quote_char: str) -> str:
    """An entity's text inside an attribute value: white space normalised (as XML does, so
    no line is added), ``<`` and the delimiting quote escaped."""
    value = value.replace("<", "&lt;").translate({9: " ", 10: " ", 13: " "})
    return value.replace(quote_char, "&quot;" if quote_char == '"' else "&apos;")


# --- file: paths that are not IRIs ---------------------------------------------------------

# an IRI token of OWL functional syntax or Turtle (strings and comments skipped)
_IRI_TOKENS = re.compile(r'"""(?:[^"\\]|\\.|"(?!""))*"""|\'\'\'(?:[^\'\\]|\\.|\'(?!\'\'))*\'\'\''
                         r'|"(?:[^"\\\n]|\\.)*"|\'(?:[^\'\\\n]|\\.)*\'|<(file:[^<>"\n]*)>|<[^<>"\n]*>|#[^\n]*')
_XML_FILE_IRIS = re.compile(r"""(?<==)(\s*)(["'])(file:[^"'<]*)\2|(?<=>)(\s*)(file:[^<]*?)(\s*)(?=<)""")
# what an IRI cannot hold (RFC 3987) and a file path may: escaped as %XX
_NOT_IRI = re.compile(r'[\x00-\x20"<>\\^`{|}\x7f]')
# a file: IRI (or something like one) holding such a character
_BAD_FILE_IRI = re.compile(r'file:[^<>"\'\n]*?[\x00-\x09\x0b-\x20\\^`{|}\x7f]')


def repair_file_iris(text: str, fmt: str, path: Path) -> tuple[str, list[Diagnostic]]:
    """``text`` with each ``file:`` IRI that is not an IRI (a Windows path such as
    ``file:C:\\Documents and Settings\\kitting.owl``: backslashes, spaces) rewritten as one
    (``file:C:/Documents%20and%20Settings/kitting.owl``), with a warning at the first."""
    if "file:" not in text or _BAD_FILE_IRI.search(text) is None:  # C speed for the common case
        return text, []
    found: list[tuple[int, str, str]] = []

    def fixed(iri: str, at: int) -> str:
        if _NOT_IRI.search(iri) is None:
            return iri
        good = _NOT_IRI.sub(lambda c: quote(c.group(), safe=""), iri.replace("\\", "/"))
        found.append((at, iri, good))
        return good

    if fmt in ("rdfxml", "owlxml"):
        def xml_iri(m: re.Match) -> str:
            if m.group(3) is not None:
                return m.group(1) + m.group(2) + fixed(m.group(3), m.start(3)) + m.group(2)
            return m.group(4) + fixed(m.group(5), m.start(5)) + m.group(6)
        text = _XML_FILE_IRIS.sub(xml_iri, text)
    elif fmt == "ofn":  # (Turtle and N-Triples are read as their grammars say: the world
        # model's loader streams them straight to pyoxigraph)
        text = _IRI_TOKENS.sub(lambda m: m.group() if m.group(1) is None
                               else "<" + fixed(m.group(1), m.start(1)) + ">", text)
    if not found:
        return text, []
    at, bad, good = found[0]
    more = f" ({len(found) - 1} more in this file)" if len(found) > 1 else ""
    return text, [Diagnostic(str(path), text.count("\n", 0, at) + 1, "warning",
                             f"<{bad}> is a file path, not an IRI; read as <{good}>{more}", rule="file-iri")]


# --- XML safety ----------------------------------------------------------------------------

def check_xml(text: str, path: Path) -> None:
    """Refuse XML that could reach outside the file or blow up (XXE, parameter entities,
    nested entities); report XML syntax errors with their line. Never fetches anything."""
    parser = xml.parsers.expat.ParserCreate(namespace_separator=" ")
    parser.SetParamEntityParsing(xml.parsers.expat.XML_PARAM_ENTITY_PARSING_NEVER)

    def entity_decl(name, is_param, value, base, system_id, public_id, notation):  # noqa: ANN001
        line = parser.CurrentLineNumber
        if is_param:
            raise InputError(f"XML parameter entity '{name}' is not allowed", path, line)
        if system_id is not None or public_id is not None or value is None:
            raise InputError(f"external XML entity '{name}' is not allowed (nothing is fetched)", path, line)
        if "&" in value or len(value) > _MAX_ENTITY_TEXT:
            raise InputError(f"XML entity '{name}' refers to other entities or is too long", path, line)

    def external_ref(context, base, system_id, public_id):  # noqa: ANN001
        raise InputError("external XML reference is not allowed (nothing is fetched)", path, parser.CurrentLineNumber)

    depth = [0]
    deepest = limits.NESTING.value() or float("inf")

    def start(name, attrs):  # noqa: ANN001
        depth[0] += 1
        if depth[0] > deepest:
            raise limits.NESTING.error(None, path, parser.CurrentLineNumber,
                                       "XML elements nested too deep")

    def end(name):  # noqa: ANN001
        depth[0] -= 1

    parser.StartElementHandler = start
    parser.EndElementHandler = end
    parser.EntityDeclHandler = entity_decl
    parser.ExternalEntityRefHandler = external_ref
    parser.UnparsedEntityDeclHandler = lambda name, *a: entity_decl(name, False, None, None, "x", None, None)
    try:
        parser.Parse(text.encode("utf-8"), True)
    except xml.parsers.expat.ExpatError as exc:
        message = xml.parsers.expat.ErrorString(exc.code)
        raise InputError(f"XML syntax error: {message}", path, exc.lineno) from None


# --- parsing -------------------------------------------------------------------------------

def strip_slash_comments(text: str, path: Path) -> tuple[str, list[Diagnostic]]:
    """Blank out ``//`` comment lines (not OWL functional syntax), keeping line numbers."""
    lines = text.split("\n")
    hits = [i for i, line in enumerate(lines) if line.lstrip().startswith("//")]
    if not hits:
        return text, []
    for i in hits:
        lines[i] = ""
    message = (f"{len(hits)} `//` comment lines ignored (not OWL functional syntax), "
               f"first at line {hits[0] + 1}")
    return "\n".join(lines), [Diagnostic(str(path), hits[0] + 1, "warning", message, rule="ofn-comment")]


def parse_text(text: str, fmt: str, path: Path, terms: dict | None = None,
               prefixes: dict[str, str] | None = None, raw: bytes | None = None) -> list[Triple]:
    """The triples of ``text`` in format ``fmt`` (IRIs namespace-mapped).

    ``terms``, if given, receives the IRI -> term map used, so callers can find triples
    by term identity (much faster than rdflib's ``==`` over a million triples);
    ``prefixes`` receives the file's prefix declarations (namespace-mapped). ``raw``: the
    UTF-8 bytes ``text`` was decoded from, if the caller has them (Turtle and N-Triples are
    then parsed from them, without encoding ``text`` again).
    """
    prefixes = {} if prefixes is None else prefixes
    if fmt in ("rdfxml", "owlxml"):
        check_xml(text, path)
    if fmt in ("ofn", "turtle"):
        check_nesting(text, path, fmt)
    rewritten = fmt in ("ofn", "owlxml")
    written = text  # the file's text (a line in py-horned-owl's RDF/XML is not the file's)
    if rewritten:
        text = _horned_to_rdfxml(text, fmt, path, prefixes)
        fmt = "rdfxml"
    if raw is None or fmt not in ("turtle", "ntriples"):
        raw = text.encode("utf-8")
    elif raw.startswith(b"\xef\xbb\xbf"):  # the byte order mark decode() dropped
        raw = raw[3:]
    try:
        quads = ox.parse(raw, format=_OX_FORMAT[fmt], base_iri=path.resolve().as_uri())
        triples = _convert(quads, {} if terms is None else terms, path, None if rewritten else raw)
        for name, iri in (getattr(quads, "prefixes", None) or {}).items():
            prefixes.setdefault(name, map_iri(iri))
        return triples
    except SyntaxError as exc:
        message = _syntax_message(exc)
        line = None if rewritten else exc.lineno
        raise InputError(message, path, line or locate_message(message, written)) from None
    except (ValueError, OSError) as exc:
        message = f"cannot parse: {_one_line(str(exc))}"
        raise InputError(message, path, locate_message(message, written)) from None


def check_nesting(text: str, path: Path, fmt: str = "ofn") -> None:
    """Refuse OWL functional syntax nested deeper than :data:`kb.core.limits.NESTING`
    parentheses, or Turtle with blank nodes ``[`` and collections ``(`` nested deeper."""
    deepest = limits.NESTING.value()
    if deepest is None:
        return
    opening = "(" if fmt == "ofn" else "[("
    if sum(text.count(c) for c in opening) <= deepest:  # cannot nest deeper: no scan (C speed)
        return
    depth = 0
    for m in (_OFN_NESTING if fmt == "ofn" else _TURTLE_NESTING).finditer(text):
        token = m.group()
        if token in opening:
            depth += 1
            if depth > deepest:
                line = text.count("\n", 0, m.start()) + 1
                what = "parentheses" if fmt == "ofn" else "blank nodes '[' and collections '('"
                raise limits.NESTING.error(None, path, line, f"{what} nested too deep")
        elif token in ")]":
            depth -= 1


def _syntax_message(exc: SyntaxError) -> str:
    msg = str(exc.msg if exc.msg else exc)
    msg = re.sub(r"^Parser error [^:]*: ", "", msg)
    return _one_line(f"syntax error: {msg}")


def _one_line(message: str) -> str:
    """``message`` on one line of at most 300 characters."""
    text = " ".join(message.split())
    return text if len(text) <= 300 else text[:297] + "..."


_QUOTED_PART = re.compile(r"'([^'\n]{2,200})'|\"([^\"\n]{2,200})\"|<([^<>\s]{2,200})>")


def locate_message(message: str, text: str) -> int | None:
    """The line of ``text`` where the first quoted part of a library's ``message`` (an IRI,
    an entity, a token it names) is written, None if none is."""
    for m in _QUOTED_PART.finditer(message):
        part = next(g for g in m.groups() if g is not None)
        for candidate in (part, f"&{part};", part.replace("\\\\", "\\")):
            at = text.find(candidate)
            if at >= 0:
                return text.count("\n", 0, at) + 1
    return None


_HORNED_POS = re.compile(r"line_col: Pos\(\((\d+), (\d+)\)\)")
_HORNED_BYTE = re.compile(r"BytePosition\((\d+)\)")
_HORNED_EXPECTED = re.compile(r"positives: \[([^\]]*)\]")


def _horned_to_rdfxml(text: str, fmt: str, path: Path, prefixes: dict[str, str]) -> str:
    import pyhornedowl

    try:
        onto = pyhornedowl.open_ontology_from_string(text, "ofn" if fmt == "ofn" else "owx")
        prefixes.update((name, map_iri(iri)) for name, iri in onto.prefix_mapping)
        return onto.save_to_string("rdf")
    except BaseException as exc:  # py-horned-owl raises ValueError, or a pyo3 PanicException
        if isinstance(exc, (KeyboardInterrupt, SystemExit, MemoryError)):
            raise
        raise _horned_error(str(exc), text, fmt, path) from None


def _horned_error(raw: str, text: str, fmt: str, path: Path) -> InputError:
    line = None
    if m := _HORNED_POS.search(raw):
        line = int(m.group(1))
    elif m := _HORNED_BYTE.search(raw):
        line = text.encode("utf-8")[: int(m.group(1))].count(b"\n") + 1
    kind = "OWL functional syntax" if fmt == "ofn" else "OWL/XML"
    kind = f"syntax error ({kind})"
    if m := _HORNED_EXPECTED.search(raw):
        detail = f"expected {m.group(1).replace(', ', ' or ')}" if m.group(1) else "unexpected input"
    else:
        detail = _rust_message(raw)
    return InputError(_one_line(f"{kind}: {detail}"), path, line or locate_message(raw, text))


_RUST_TEXT = re.compile(r'^\w+\("((?:[^"\\]|\\.)*)"')
_RUST_VARIANT = re.compile(r"^(?:\w*Error\()*([A-Z]\w*)(?:\(([^()]*)\))?")


def _rust_message(raw: str) -> str:
    """A sentence from py-horned-owl's error, which is a Rust debug string such as
    ``ValidityError("Missing Element: expected IRI", BytePosition(162))`` or
    ``ParserError(UnrecognizedEntity(1..4, "xsd"), Unknown)``."""
    text = re.sub(r"^Failed to open ontology: ", "", raw.strip())
    if not text:
        return "unreadable"
    if m := _RUST_TEXT.match(text):
        return m.group(1)
    if m := _RUST_VARIANT.match(text):
        words = re.sub(r"(?<=[a-z])(?=[A-Z])", " ", m.group(1)).lower()
        names = re.findall(r'"((?:[^"\\]|\\.)*)"', m.group(2) or "")
        if m.group(1) == "UnrecognizedEntity" and names:
            return f"undeclared XML entity &{names[0]};"
        return words + "".join(f" '{n}'" for n in names)
    return text


def _convert(quads: Iterable[ox.Quad], iris: dict, path: Path | None = None,
             raw: bytes | None = None) -> list[Triple]:
    """rdflib triples of pyoxigraph quads; each distinct term is converted once. More than
    :data:`kb.core.limits.STATEMENTS` statements, or a literal longer than
    :data:`kb.core.limits.LITERAL`, is an InputError (``path``, ``raw``: the file and its
    bytes, to name them)."""
    cache: dict[object, object] = {}
    bnodes: dict[str, BNode] = {}
    NamedNode, OxLiteral = ox.NamedNode, ox.Literal
    most = limits.STATEMENTS.value()
    longest = limits.LITERAL.value()
    if most is not None:
        quads = islice(quads, most + 1)  # counted in C: nothing per statement here

    def term(x):  # noqa: ANN001, ANN202
        r = cache.get(x)
        if r is None:
            if isinstance(x, NamedNode):
                r = iris[x.value] = URIRef(map_iri(x.value))
            elif isinstance(x, OxLiteral):
                if longest is not None and len(x.value) > longest:
                    raise limits.LITERAL.error(None, path, _line_of(raw, x.value),
                                               f"a literal of {len(x.value):,} characters")
                r = make_literal(x.value, x.language, x.datatype.value)
            else:
                r = bnodes.setdefault(x.value, BNode())
            cache[x] = r
        return r

    get = cache.get
    out: list[Triple] = []
    append = out.append
    for s, p, o, _ in quads:
        # the cache hit is a C call; term() only runs for new terms (no ``get(x) or term(x)``:
        # that asks a literal for its truth value, a Python-level call)
        a = get(s)
        if a is None:
            a = term(s)
        b = get(p)
        if b is None:
            b = term(p)
        c = get(o)
        if c is None:
            c = term(o)
        append((a, b, c))
    if most is not None and len(out) > most:
        raise limits.STATEMENTS.error(None, path, None, "too many statements")
    return out


def _line_of(raw: bytes | None, text: str) -> int | None:
    """The line where ``text`` (its first characters) first appears in ``raw``, if it does."""
    if raw is None:
        return None
    at = raw.find(text[:200].encode("utf-8"))
    return raw.count(b"\n", 0, at) + 1 if at >= 0 else None


def expat_parser(namespace_separator: str) -> xml.parsers.expat.XMLParserType:
    """An expat parser for the line indexes: namespaces split by ``namespace_separator``,
    parameter entities never read (the entity guard has already vetted the text)."""
    parser = xml.parsers.expat.ParserCreate(namespace_separator=namespace_separator)
    parser.SetParamEntityParsing(xml.parsers.expat.XML_PARAM_ENTITY_PARSING_NEVER)
    return parser


def run_expat(parser: xml.parsers.expat.XMLParserType, text: str, start, end, chars) -> None:  # noqa: ANN001
    """Feed ``text`` through ``parser`` with the given handlers. A line index is best effort:
    the file was already parsed, so an expat error just ends the walk where it is."""
    parser.StartElementHandler = start
    parser.EndElementHandler = end
    parser.CharacterDataHandler = chars
    try:
        parser.Parse(text.encode("utf-8"), True)
    except xml.parsers.expat.ExpatError:
        pass
