"""Read one RDF/OWL file into rdflib terms: format detection, safe XML, syntax errors.

Turtle, N-Triples and RDF/XML are parsed by pyoxigraph; OWL functional syntax and OWL/XML
by py-horned-owl, which re-serialises them as RDF/XML for pyoxigraph. Every IRI is passed
through :data:`kb.core.namespaces.NAMESPACE_MAP` on the way into rdflib terms.
"""

from __future__ import annotations

import logging
import re
import xml.parsers.expat
from itertools import islice
from pathlib import Path
from typing import Iterable

import pyoxigraph as ox
from rdflib import BNode, Graph, Literal, URIRef

from kb.core.diagnostics import Diagnostic
from kb.core import limits
from kb.core.errors import InputError
from kb.core.namespaces import NAMESPACE_MAP, PREFIXES
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


_MAPPED = tuple(NAMESPACE_MAP)


def map_iri(iri: str) -> str:
    """``iri`` with a foreign namespace (NIST kitting) rewritten to ours."""
    if not iri.startswith(_MAPPED):  # one C call for the common case
        return iri
    for old, new in NAMESPACE_MAP.items():
        if iri.startswith(old):
            return new + iri[len(old):]
    return iri


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

def decode(data: bytes, path: Path) -> str:
    """``data`` as UTF-8 text, or an InputError at the line of the first bad byte."""
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        line = data[: exc.start].count(b"\n") + 1
        raise InputError(f"not UTF-8 text (byte 0x{data[exc.start]:02x})", path, line) from None


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
        raise InputError(_syntax_message(exc), path, exc.lineno) from None
    except (ValueError, OSError) as exc:
        raise InputError(f"cannot parse: {exc}", path) from None


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
    return f"syntax error: {msg}".splitlines()[0]


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
        detail = re.sub(r"^Failed to open ontology: ", "", raw).splitlines()[0][:200] if raw else "unreadable"
    return InputError(f"{kind}: {detail}", path, line)


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
