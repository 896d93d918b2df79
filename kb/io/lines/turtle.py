"""Line index of Turtle and N-Triples: a small tokenizer that follows subjects, predicates
and objects and records the line each is written on (see :mod:`kb.io.lines`)."""

from __future__ import annotations

import re
from typing import Iterator
from urllib.parse import urljoin

from rdflib import Literal, URIRef
from rdflib.namespace import RDF, XSD

from kb.core.namespaces import NAMESPACE_MAP
from kb.io.lines.index import Key, LineIndex
from kb.io.parsing import make_literal, map_iri


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
  |(?P<num>[+-]?(?:\d+(?:\.\d*)?[eE][+-]?\d+|\.\d+[eE][+-]?\d+|\d*\.\d+|\d+))
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
        self.text = text
        self.tokens = self._tokens(text)
        self.buf = next(self.tokens, _EOF)
        self.base = base
        self.prefixes: dict[str, str] = {}
        self.index = index
        self.terms: dict[str, Key | None] = {}  # token text -> term, cleared when prefixes change
        self.literals: dict[tuple, Literal] = {}

    @staticmethod
    def _tokens(text: str, start: int = 0, line: int = 1) -> Iterator[tuple[str, str, int]]:
        for m in _TTL_TOKEN.finditer(text, start):
            kind = m.lastgroup
            value = m.group()
            if kind == "ws":
                line += value.count("\n")
                continue
            yield kind, value, line
            if kind == "lstr":
                line += value.count("\n")

    def statement_at(self, start: int, line: int, prefixes: dict[str, str], wanted: set) -> None:
        """Index the statement starting at offset ``start`` (on ``line``) if its subject is
        in ``wanted``."""
        if prefixes != self.prefixes:
            self.prefixes = dict(prefixes)
            self.terms.clear()
        self.tokens = self._tokens(self.text, start, line)
        self.buf = next(self.tokens, _EOF)
        kind, value, _ = self.buf
        try:
            if self.term(kind, value) in wanted:
                self.statement()
        except (KeyError, ValueError, IndexError, RecursionError):
            pass

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


# --- targeted index ---------------------------------------------------------------------

_PREFIX_AT = re.compile(r"(?:@prefix|prefix)\s+([A-Za-z][\w.-]*)?:\s*<([^<>\s]*)>", re.I)
_BASE_AT = re.compile(r"(?:@base|base)\s*<", re.I)
_LINE_HEAD = re.compile(r"^[ \t]*(<[^<>\s]*>|(?:[A-Za-z][\w.-]*)?:[^\s;,()\[\]\"#]*)", re.M)
_COMMENT = re.compile(r"\s#")


def _trie_regex(words: set[str]) -> re.Pattern[str]:
    """A regular expression matching any of ``words``, shaped as a trie (one walk per position
    instead of one attempt per word)."""
    trie: dict = {}
    for w in words:
        node = trie
        for ch in w:
            node = node.setdefault(ch, {})
        node[""] = {}

    def pattern(node: dict) -> str:
        ends = "" in node
        alts = [re.escape(ch) + pattern(sub) for ch, sub in sorted(node.items()) if ch]
        if not alts:
            return ""
        body = alts[0] if len(alts) == 1 else "(?:" + "|".join(alts) + ")"
        return f"(?:{body})?" if ends else body

    return re.compile(pattern(trie) if trie else r"(?!)")


def _directives(text: str, words: tuple[str, ...], low: str | None = None) -> list[int]:
    """Offsets where one of ``words`` (or it with a leading ``@``) starts a token, in order.

    ``low``: ``text.lower()`` of an ASCII text, searched for the lower-case word instead
    (any mix of cases; one pass per word instead of one per spelling)."""
    found: set[int] = set()
    for w, hay in ([(words[0].lower(), low)] if low is not None else [(w, text) for w in words]):
        i = hay.find(w)
        while i >= 0:
            start = i - 1 if i > 0 and text[i - 1] == "@" else i
            if start == 0 or not (text[start - 1].isalnum() or text[start - 1] in "_@:/#.-"):
                found.add(start)
            i = hay.find(w, i + 1)
    return sorted(found)


class TargetedTurtleIndex:
    """Line index of a big Turtle/N-Triples file built for a few subjects at a time.

    The full index tokenizes the whole file (minutes at a million statements). Here one
    regular-expression pass over line starts finds the statements that begin with one of
    the subjects' spellings (``<iri>`` or ``prefix:local``, the NIST namespace included)
    right after the end of the previous statement, and only those statements are tokenized.
    Entries are the ones the full index makes for those subjects (first line wins, file
    order). A statement must start its line; files with ``@base`` are not handled
    (``usable`` is False, and the caller builds the full index).
    """

    def __init__(self, text: str, base: str) -> None:
        self.text = text
        self.base = base
        self.prefixes: list[tuple[int, str, str]] = []
        low = text.lower() if text.isascii() else None  # same offsets as text
        for i in _directives(text, ("prefix", "PREFIX", "Prefix"), low):
            m = _PREFIX_AT.match(text, i)
            if m:
                self.prefixes.append((i, m.group(1) or "", urljoin(base, m.group(2))))
        self.usable = not any(_BASE_AT.match(text, i) for i in _directives(text, ("base", "BASE", "Base"), low))

    def spellings(self, term: URIRef) -> set[str]:
        """How ``term`` may be written as a subject (before namespace mapping)."""
        iri = str(term)
        raws = {iri} | {old + iri[len(new):] for old, new in NAMESPACE_MAP.items() if iri.startswith(new)}
        out = {f"<{r}>" for r in raws}
        for _, name, ns in self.prefixes:
            for r in raws:
                if r.startswith(ns) and len(r) > len(ns):
                    out.add(f"{name}:{r[len(ns):]}")
        return out

    def index(self, subjects: set, index: LineIndex) -> None:
        """Add the statements about ``subjects`` (URIRefs) to ``index``."""
        text = self.text
        spelled = set()
        for s in subjects:
            spelled |= self.spellings(s)
        indexer = _TurtleIndexer(text, self.base, index)
        decls, d = self.prefixes, 0
        prefixes: dict[str, str] = {}
        line, at = 1, 0
        for m in _trie_regex(spelled).finditer(text):
            start = m.start()
            end = m.end()
            if end < len(text) and not (text[end].isspace() or text[end] in ";,.(["):
                continue  # a longer name that starts like a wanted one
            if not self._after_statement(start):
                continue
            while d < len(decls) and decls[d][0] < start:
                prefixes[decls[d][1]] = decls[d][2]
                d += 1
            line += text.count("\n", at, start)
            at = start
            indexer.statement_at(start, line, prefixes, subjects)

    def _after_statement(self, pos: int) -> bool:
        """True when only blanks and comments separate ``pos`` from the end of a statement or
        directive (or the start of the file)."""
        text = self.text
        j = text.rfind("\n", 0, pos) + 1
        if text[j:pos].strip():
            return False
        while j > 0:
            k = text.rfind("\n", 0, j - 1) + 1
            seg = text[k:j - 1].strip()
            j = k
            if not seg or seg[0] == "#":
                continue
            if seg.endswith("."):
                return True
            low = seg.lower()
            if low.startswith(("prefix", "base")) and seg.endswith(">"):
                return True
            head = _COMMENT.split(seg, 1)[0].rstrip()
            return head.endswith(".") or (head.lower().startswith(("prefix", "base")) and head.endswith(">"))
        return True
