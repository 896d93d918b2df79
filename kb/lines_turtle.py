"""Line index of Turtle and N-Triples: a small tokenizer that follows subjects, predicates
and objects and records the line each is written on (see :mod:`kb.sources`)."""

from __future__ import annotations

import re
from typing import Iterator
from urllib.parse import urljoin

from rdflib import Literal, URIRef
from rdflib.namespace import RDF, XSD

from kb.parsing import make_literal, map_iri
from kb.sources import Key, LineIndex


def index_turtle(text: str, base: str, index: LineIndex) -> None:
    """Record the statements of Turtle ``text`` in ``index``."""
    _TurtleIndexer(text, base, index).run()


_TTL_TOKEN = re.compile(r'''
   (?P<ws>\s+|\#[^\n]*)
  |(?P<iri><[^<>"{}|^`\\\s]*>)
  |(?P<lstr>"""(?:[^"\\]|\\.|"(?!""))*"""|\'\'\'(?:[^'\\]|\\.|'(?!''))*\'\'\')
  |(?P<str>"(?:[^"\\\n]|\\.)*"|'(?:[^'\\\n]|\\.)*')
  |(?P<lang>@[A-Za-z]+(?:-[A-Za-z0-9]+)*)
  |(?P<dt>\^\^)
  |(?P<num>[+-]?(?:\d+\.?\d*[eE][+-]?\d+|\.\d+[eE][+-]?\d+|\d*\.\d+|\d+))
  |(?P<bnode>_:[\w.-]*\w|_:\w)
  |(?P<pname>(?:[A-Za-z][\w.-]*)?:(?:[\w:%-]|\\[^\s]|\.(?=[\w:%-]))*)
  |(?P<word>[A-Za-z]+)
  |(?P<punct>[;,.\[\]()])
  |(?P<other>.)
''', re.VERBOSE | re.DOTALL)

_ESCAPE = re.compile(r"\\(u[0-9A-Fa-f]{4}|U[0-9A-Fa-f]{8}|.)", re.DOTALL)
_SIMPLE_ESCAPES = {"t": "\t", "b": "\b", "n": "\n", "r": "\r", "f": "\f"}


def _unescape(s: str) -> str:
    def sub(m: re.Match) -> str:
        e = m.group(1)
        if e[0] in "uU" and len(e) > 1:
            return chr(int(e[1:], 16))
        return _SIMPLE_ESCAPES.get(e, e)

    return _ESCAPE.sub(sub, s) if "\\" in s else s


_EOF = ("eof", "", 0)


class _TurtleIndexer:
    def __init__(self, text: str, base: str, index: LineIndex):
        self.tokens = self._tokens(text)
        self.buf = next(self.tokens, _EOF)
        self.base = base
        self.prefixes: dict[str, str] = {}
        self.index = index
        self.terms: dict[str, Key | None] = {}  # token text -> term, cleared when prefixes change
        self.literals: dict[tuple, Literal] = {}

    @staticmethod
    def _tokens(text: str) -> Iterator[tuple[str, str, int]]:
        line = 1
        for m in _TTL_TOKEN.finditer(text):
            kind = m.lastgroup
            value = m.group()
            if kind == "ws":
                line += value.count("\n")
                continue
            yield kind, value, line
            if kind == "lstr":
                line += value.count("\n")

    def peek(self) -> tuple[str, str, int]:
        return self.buf

    def next(self) -> tuple[str, str, int]:
        tok = self.buf
        self.buf = next(self.tokens, _EOF)
        return tok

    def run(self) -> None:
        while self.buf[0] != "eof":
            start = self.buf
            try:
                self.statement()
            except (KeyError, ValueError, IndexError, RecursionError):
                self.skip_to_dot()
            if self.buf is start:
                self.next()

    def skip_to_dot(self) -> None:
        while self.peek()[0] != "eof" and self.next()[1] != ".":
            pass

    def statement(self) -> None:
        kind, value, _ = self.peek()
        low = value.lower()
        if low in ("@prefix", "prefix"):
            self.next()
            name = self.next()[1]
            iri = self.next()[1]
            self.prefixes[name[:-1]] = urljoin(self.base, iri[1:-1])
            self.terms.clear()
            if self.peek()[1] == ".":
                self.next()
            return
        if low in ("@base", "base"):
            self.next()
            self.base = urljoin(self.base, self.next()[1][1:-1])
            self.terms.clear()
            if self.peek()[1] == ".":
                self.next()
            return
        subject = self.subject()
        if self.peek()[1] not in (".", "eof"):
            self.predicate_objects(subject, ".")
        if self.peek()[1] == ".":
            self.next()
        else:
            self.skip_to_dot()

    def subject(self) -> Key | None:
        kind, value, line = self.next()
        if value == "[":
            if self.peek()[1] != "]":
                self.predicate_objects(None, "]")
            self.next()
            return None
        if value == "(":
            self.collection()
            return None
        term = self.term(kind, value)
        if term is not None:
            self.index.add(line, term)
        return term

    def predicate_objects(self, subject: Key | None, end: str) -> None:
        while True:
            kind, value, line = self.next()
            if kind == "eof":
                return
            pred = RDF.type if value == "a" else self.term(kind, value)
            self.index.add(line, subject, pred)
            while True:
                obj, oline = self.object()
                self.index.add(oline, subject, pred, obj)
                if self.peek()[1] != ",":
                    break
                self.next()
            if self.peek()[1] != ";":
                return
            while self.peek()[1] == ";":
                self.next()
            if self.peek()[1] in (end, ".", "eof"):
                return

    def object(self) -> tuple[Key | None, int]:
        kind, value, line = self.next()
        if value == "[":
            if self.peek()[1] != "]":
                self.predicate_objects(None, "]")
            self.next()
            return None, line
        if value == "(":
            self.collection()
            return None, line
        if kind in ("str", "lstr"):
            lex = _unescape(value[3:-3] if kind == "lstr" else value[1:-1])
            nk, nv, _ = self.peek()
            if nk == "lang":
                self.next()
                return self.literal(lex, nv[1:], None), line
            if nk == "dt":
                self.next()
                dk, dv, _ = self.next()
                return self.literal(lex, None, str(self.term(dk, dv))), line
            return self.literal(lex, None, None), line
        if kind == "num":
            dt = XSD.double if "e" in value.lower() else XSD.decimal if "." in value else XSD.integer
            return self.literal(value, None, str(dt)), line
        if value in ("true", "false"):
            return self.literal(value, None, str(XSD.boolean)), line
        return self.term(kind, value), line

    def collection(self) -> None:
        while self.peek()[1] not in (")", "eof"):
            self.object()
        self.next()

    def literal(self, lex: str, lang: str | None, datatype: str | None) -> Literal:
        key = (lex, lang, datatype)
        lit = self.literals.get(key)
        if lit is None:
            lit = self.literals[key] = make_literal(lex, lang, datatype)
        return lit

    def term(self, kind: str, value: str) -> Key | None:
        try:
            return self.terms[value]
        except KeyError:
            term = self.terms[value] = self._term(kind, value)
            return term

    def _term(self, kind: str, value: str) -> Key | None:
        if kind == "iri":
            return URIRef(map_iri(urljoin(self.base, _unescape(value[1:-1]))))
        if kind == "pname":
            prefix, _, local = value.partition(":")
            local = re.sub(r"\\(.)", r"\1", local)
            return URIRef(map_iri(self.prefixes[prefix] + local))
        return None
