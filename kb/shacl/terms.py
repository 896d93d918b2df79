"""Terms as N-Triples strings ("keys"), and the way back to rdflib terms.

The engine indexes data by the N-Triples spelling of each term: ``<iri>``, ``_:id``,
``"lex"``, ``"lex"@lang`` or ``"lex"^^<datatype>``. Strings hash and compare fast, pyoxigraph
writes them directly, and only the few terms that end up in results (or need a value
comparison) are turned into rdflib terms.

Two spellings exist for xsd:string literals. pyoxigraph writes ``"abc"^^xsd:string`` as
``"abc"`` (RDF 1.1); rdflib keeps the datatype and treats the two as different terms. Keys
made from rdflib graphs keep the ``^^<...#string>`` suffix, so ``sh:in``/``sh:hasValue`` behave
exactly as in pySHACL there; keys read through pyoxigraph follow RDF 1.1.
"""

from __future__ import annotations

import logging
import re
import warnings
from functools import lru_cache

from rdflib import BNode, Literal, URIRef
from rdflib.term import Node

XSD_NS = "http://www.w3.org/2001/XMLSchema#"
XSD_STRING = XSD_NS + "string"
XSD_BOOLEAN = XSD_NS + "boolean"
#: Added to the lexical form of an ill-typed boolean in its key (see :func:`key_of`).
ILL_TYPED = " (ill-typed)"

_ESCAPES = {"\b": "\\b", "\t": "\\t", "\n": "\\n", "\f": "\\f", "\r": "\\r", '"': '\\"', "\\": "\\\\"}
_NEEDS_ESCAPE = re.compile(r'[\x00-\x1f\x7f"\\]')
_UNESCAPE = re.compile(r"\\(u[0-9A-Fa-f]{4}|U[0-9A-Fa-f]{8}|[tbnrf\"'\\])")
_SIMPLE = {"t": "\t", "b": "\b", "n": "\n", "r": "\r", "f": "\f", '"': '"', "'": "'", "\\": "\\"}


def _escape_char(m: re.Match[str]) -> str:
    c = m.group(0)
    return _ESCAPES.get(c) or f"\\u{ord(c):04X}"


def escape_lexical(text: str) -> str:
    """Escape a lexical form the way pyoxigraph's N-Triples writer does."""
    return _NEEDS_ESCAPE.sub(_escape_char, text) if _NEEDS_ESCAPE.search(text) else text


def _unescape_one(m: re.Match[str]) -> str:
    g = m.group(1)
    return chr(int(g[1:], 16)) if g[0] in "uU" else _SIMPLE[g]


def unescape(text: str) -> str:
    """Undo N-Triples string escapes."""
    return _UNESCAPE.sub(_unescape_one, text) if "\\" in text else text


def key_of(term: Node, *, rdf11_strings: bool = False) -> str:
    """The key of an rdflib term (``rdf11_strings`` drops an explicit ``^^xsd:string``).

    rdflib reads an ill-typed boolean (``"none"^^xsd:boolean``) as ``"false"``, marked
    ill-typed; its key keeps it ill-typed (``"false (ill-typed)"^^xsd:boolean``, which rdflib
    reads back as the same term), so sh:datatype still rejects it."""
    if isinstance(term, URIRef):
        return f"<{term}>"
    if isinstance(term, BNode):
        return f"_:{term}"
    if isinstance(term, Literal):
        dt = term.datatype
        lex = str(term)
        if term.ill_typed and str(dt) == XSD_BOOLEAN and lex in ("true", "false"):
            lex += ILL_TYPED
        body = '"' + escape_lexical(lex) + '"'
        if term.language:
            return f"{body}@{term.language}"
        if dt is None or (rdf11_strings and str(dt) == XSD_STRING):
            return body
        return f"{body}^^<{dt}>"
    raise TypeError(f"not an RDF term: {term!r}")


def is_literal(key: str) -> bool:
    return key[0] == '"'


def is_bnode(key: str) -> bool:
    return key[0] == "_"


def is_iri(key: str) -> bool:
    return key[0] == "<"


def split_literal(key: str) -> tuple[str, str | None, str | None]:
    """(lexical form, datatype IRI or None, language or None) of a literal key."""
    end = key.rindex('"')
    lex = unescape(key[1:end])
    rest = key[end + 1 :]
    if rest.startswith("^^<"):
        return lex, rest[3:-1], None
    if rest.startswith("@"):
        return lex, None, rest[1:]
    return lex, None, None


@lru_cache(maxsize=200_000)
def to_node(key: str) -> Node:
    """The rdflib term of a key (cached; ill-typed literals are built without logging noise)."""
    if key[0] == "<":
        return URIRef(key[1:-1])
    if key[0] == "_":
        return BNode(key[2:])
    lex, dt, lang = split_literal(key)
    if lang:
        return Literal(lex, lang=lang)
    if dt is None:
        return Literal(lex)
    return _quiet_literal(lex, dt)


_RDFLIB_TERM_LOG = logging.getLogger("rdflib.term")


def _drop_record(record: logging.LogRecord) -> bool:
    return False


def _quiet_literal(lex: str, dt: str) -> Literal:
    """rdflib logs a traceback for every ill-typed literal (and warns of weird booleans);
    keep that out of reports."""
    _RDFLIB_TERM_LOG.addFilter(_drop_record)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return Literal(lex, datatype=URIRef(dt))
    finally:
        _RDFLIB_TERM_LOG.removeFilter(_drop_record)


def literal_datatype(key: str) -> str | None:
    """Datatype IRI written on a literal key (None for plain and language-tagged literals)."""
    end = key.rindex('"')
    rest = key[end + 1 :]
    return rest[3:-1] if rest.startswith("^^<") else None
