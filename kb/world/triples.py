"""The statements of one data file as a stream, for the loader: no graph, no list of triples.

Turtle and N-Triples are streamed by pyoxigraph straight from the file (the terms stay
pyoxigraph's; :class:`OxTerms` reads them); other syntaxes (RDF/XML, OWL/XML, OWL functional
syntax) go through :func:`kb.io.loader.load_file`, whose XML guard and OWL conversion they
need (:class:`RdfTerms`). Either way the NIST namespace is mapped onto ours. Syntax errors
and line look-ups are answered by :mod:`kb.io` (on demand: only a failing load pays for them).
"""

from __future__ import annotations

import io
from functools import cached_property
from pathlib import Path
from typing import Any, Iterable

import pyoxigraph as ox
from rdflib import BNode, Literal, URIRef

from kb.core.errors import InputError
from kb.core.progress import Task
from kb.io.loader import Source, load_file
from kb.io.parsing import detect_format, make_literal, map_iri

_XSD_STRING = "http://www.w3.org/2001/XMLSchema#string"
_OX_FORMATS = {"turtle": ox.RdfFormat.TURTLE, "ntriples": ox.RdfFormat.N_TRIPLES}
_BOM = b"\xef\xbb\xbf"

#: A literal as the loader sees it: (lexical form, datatype IRI or None, language or None);
#: plain and ``xsd:string`` literals have no datatype, as in :func:`kb.io.parsing.make_literal`.
LiteralParts = tuple[str, "str | None", "str | None"]


class OxTerms:
    """Reads pyoxigraph terms."""

    @staticmethod
    def resource(term: Any) -> str | None:
        """The key of an IRI (namespace-mapped) or blank node (``_:label``); None for a literal."""
        kind = type(term)
        if kind is ox.NamedNode:
            return map_iri(term.value)
        if kind is ox.BlankNode:
            return "_:" + term.value
        return None

    @staticmethod
    def is_iri(term: Any) -> bool:
        """True for an IRI."""
        return type(term) is ox.NamedNode

    @staticmethod
    def literal(term: Any) -> LiteralParts:
        """The parts of a literal."""
        lang = term.language
        if lang:
            return term.value, None, lang
        dt = term.datatype.value
        return term.value, (None if dt == _XSD_STRING else map_iri(dt)), None


class RdfTerms:
    """Reads rdflib terms (already namespace-mapped by :mod:`kb.io`)."""

    @staticmethod
    def resource(term: Any) -> str | None:
        """The key of an IRI or blank node; None for a literal."""
        if isinstance(term, Literal):
            return None
        return f"_:{term}" if isinstance(term, BNode) else str(term)

    @staticmethod
    def is_iri(term: Any) -> bool:
        """True for an IRI."""
        return isinstance(term, URIRef)

    @staticmethod
    def literal(term: Any) -> LiteralParts:
        """The parts of a literal."""
        dt = term.datatype
        return str(term), (str(dt) if dt is not None else None), term.language


class DataFile:
    """One data file being read: its statements as ``(s, p, o, graph)`` tuples (read once),
    how to read their terms (:attr:`terms`), its prefixes once read, and lines of statements."""

    def __init__(self, path: str | Path, progress: Task | None = None):
        self.path = Path(path)
        self._parser: Any = None
        self._source: Source | None = None
        head = self._head()
        fmt = detect_format(head.decode("utf-8", "replace"), self.path)
        if fmt in _OX_FORMATS and not head.startswith(_BOM):
            self.terms: Any = OxTerms()
            # ``progress`` (shown on a terminal): advanced by the bytes the parser reads
            source = {"path": self.path} if progress is None else {"input": _Counted(self.path, progress)}
            self._parser = ox.parse(**source, format=_OX_FORMATS[fmt], base_iri=self.path.resolve().as_uri())
        else:
            self._source = load_file(self.path)
            self.terms = RdfTerms()

    def _head(self) -> bytes:
        try:
            with open(self.path, "rb") as f:
                return f.read(20000)
        except OSError:
            load_file(self.path)  # the InputError kb.io gives for this file (missing, a folder...)
            raise

    def quads(self) -> Iterable[Any]:
        """The statements, once. The parser may raise ``SyntaxError``, ``ValueError`` or
        ``OSError`` while they are read: :meth:`parse_error` turns those into kb.io's message."""
        if self._source is not None:
            return ((s, p, o, None) for s, p, o in self._source.triples())
        return self._parser  # type: ignore[no-any-return]

    #: What a parser raises on a bad file.
    PARSE_ERRORS = (SyntaxError, ValueError, OSError)

    def parse_error(self, exc: BaseException) -> InputError | None:
        """The error :mod:`kb.io` reports for this file (it parses it again to say it its way);
        None when the file parses (``exc`` did not come from the parser)."""
        if self._parser is None:
            return None
        try:
            load_file(self.path)
        except InputError as err:
            return err
        return None

    @property
    def prefixes(self) -> dict[str, str]:
        """The file's prefix declarations (namespace-mapped), once its statements were read."""
        if self._source is not None:
            return dict(self._source.prefixes)
        return {name: map_iri(iri) for name, iri in (getattr(self._parser, "prefixes", None) or {}).items()}

    # --- lines, for error messages ----------------------------------------------------------
    @cached_property
    def _lines(self) -> Source:
        return self._source if self._source is not None else load_file(self.path)

    def line_of(self, subject: str, predicate: str | None = None, obj: Any = None) -> int | None:
        """Line of the statement (subject key, predicate IRI, object term), else of its subject."""
        src = self._lines
        o = self._rdflib(obj) if obj is not None else None
        p = URIRef(predicate) if predicate else None
        if subject.startswith("_:"):
            if self._source is not None:
                return src.line_of(BNode(subject[2:]), p, o)
            return self._blank_line(src, p, o)
        return src.line_of(URIRef(subject), p, o)

    def _rdflib(self, term: Any) -> Any:
        if self._source is not None:
            return term
        key = self.terms.resource(term)
        if key is None:
            return make_literal(*_literal_args(self.terms.literal(term)))
        return None if key.startswith("_:") else URIRef(key)

    @staticmethod
    def _blank_line(src: Source, p: URIRef | None, o: Any) -> int | None:
        """A blank node's labels differ between two parses: find it by its statement."""
        if p is None:
            return None
        hits = [s for s in src.view().subjects(p, o)] if o is not None else []
        blanks = [s for s in hits if isinstance(s, BNode)]
        return src.line_of(blanks[0], p, o) if len(blanks) == 1 else None


def _literal_args(parts: LiteralParts) -> tuple[str, str | None, str | None]:
    lex, dt, lang = parts
    return lex, lang, dt


class _Counted(io.RawIOBase):
    """A file read by the parser, ``task`` advanced by each chunk's bytes (closed at its end)."""

    def __init__(self, path: Path, task: Task):
        self._file, self._task = open(path, "rb"), task

    def readable(self) -> bool:
        return True

    def readinto(self, buffer: Any) -> int:
        if self._file.closed:
            return 0
        n = self._file.readinto(buffer) or 0
        if n:
            self._task.advance(n)
        else:
            self._file.close()
        return n
