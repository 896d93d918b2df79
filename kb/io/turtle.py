"""Writing Turtle: the one writer behind every Turtle file kitkb writes (scenario states,
database dumps), fast on files of millions of statements where rdflib's pretty printer
takes minutes.

:class:`TurtleWriter` streams statements whose terms are already spelled (``:part_1``,
``ktw:Point``, ``"0.5"``); :class:`Names` spells rdflib terms (``prefix:local`` where that is
valid Turtle, ``<iri>`` otherwise; literals escaped); :func:`decimal` and :func:`string`
spell plain values. :func:`turtle` writes a whole rdflib graph, grouped by subject and sorted.
"""

from __future__ import annotations

import io
import re
from typing import IO, Iterable, Sequence

from rdflib import RDF, BNode, Graph, Literal
from rdflib.term import Node

from kb.core.errors import InputError

_PN_LOCAL = re.compile(r"[A-Za-z_][A-Za-z0-9_-]*\Z")
_BNODE_LABEL = re.compile(r"[A-Za-z0-9_]+\Z")
_ESCAPES = str.maketrans({"\\": "\\\\", '"': '\\"', "\n": "\\n", "\r": "\\r"})
_DECIMALS: dict[float, str] = {}


def string(text: str) -> str:
    """``text`` as a Turtle string literal (quoted, escaped)."""
    return '"' + text.translate(_ESCAPES) + '"'


def decimal(v: float) -> str:
    """``v`` as an ``xsd:decimal`` lexical form (fixed point, 12 decimals at most)."""
    text = _DECIMALS.get(v)
    if text is None:
        text = f"{v:.12f}".rstrip("0")
        if text.endswith("."):
            text += "0"
        if text == "-0.0":
            text = "0.0"
        if len(_DECIMALS) < 1_000_000:
            _DECIMALS[v] = text
    return text


class Names:
    """Turtle spellings of rdflib terms: ``prefix:local`` where that is valid Turtle, else ``<iri>``."""

    def __init__(self, prefixes: dict[str, str]):
        self.prefixes = sorted(prefixes.items(), key=lambda kv: -len(kv[1]))
        self.cache: dict[str, str] = {}
        self.bnodes: dict[str, str] = {}

    def iri(self, iri: str) -> str:
        """``prefix:local`` or ``<iri>``; an IRI Turtle cannot hold is an InputError."""
        text = self.cache.get(iri)
        if text is None:
            text = self._iri(iri)
            self.cache[iri] = text
        return text

    def _iri(self, iri: str) -> str:
        for prefix, ns in self.prefixes:
            if iri.startswith(ns) and _PN_LOCAL.match(iri[len(ns):]):
                return f"{prefix}:{iri[len(ns):]}"
        if any(c in iri for c in '<>"{}|^`\\ \n'):
            raise InputError(f"cannot write the IRI {iri!r} in Turtle")
        return f"<{iri}>"

    def term(self, node: Node) -> str:
        """The spelling of an IRI, blank node or literal."""
        if isinstance(node, Literal):
            text = string(str(node))
            if node.language:
                return f"{text}@{node.language}"
            return f"{text}^^{self.iri(str(node.datatype))}" if node.datatype else text
        if isinstance(node, BNode):
            label = self.bnodes.get(str(node))
            if label is None:
                label = str(node) if _BNODE_LABEL.match(str(node)) else f"b{len(self.bnodes)}"
                self.bnodes[str(node)] = label
            return f"_:{label}"
        return self.iri(str(node))

    def used(self) -> set[str]:
        """The prefixes the spellings made so far use."""
        return {text.split(":", 1)[0] for text in self.cache.values() if not text.startswith("<")}


class TurtleWriter:
    """Streams Turtle to ``out``: one ``subject p o ; p o .`` statement per :meth:`statement`,
    buffered in chunks."""

    def __init__(self, out: IO[str], chunk: int = 4096):
        self.out = out
        self.chunk = chunk
        self._buf: list[str] = []

    def text(self, raw: str) -> None:
        """Write already formatted Turtle (prefix lines, comments)."""
        self._buf.append(raw)
        self._spill()

    def prefixes(self, mapping: Iterable[tuple[str, str]]) -> None:
        """``@prefix`` lines, in the order given."""
        self.text("".join(f"@prefix {p}: <{ns}> .\n" for p, ns in mapping))

    def statement(self, subject: str, pairs: Sequence[tuple[str, str]]) -> None:
        """``subject`` with its (predicate, object) pairs, spelled already (an object may be a
        comma-separated list)."""
        self._buf.append(subject + " " + " ;\n    ".join(p + " " + o for p, o in pairs) + " .\n")
        self._spill()

    def _spill(self) -> None:
        if len(self._buf) >= self.chunk:
            self.flush()

    def flush(self) -> None:
        """Write what is buffered."""
        self.out.write("".join(self._buf))
        self._buf.clear()


def turtle(graph: Graph) -> str:
    """``graph`` as Turtle, grouped by subject and sorted; ``rdf:type`` written ``a``."""
    prefixes = {p: str(ns) for p, ns in graph.namespace_manager.namespaces()}
    names = Names(prefixes)
    by_subject: dict[Node, list[tuple[Node, Node]]] = {}
    for s, p, o in graph:
        by_subject.setdefault(s, []).append((p, o))
    body = io.StringIO()
    writer = TurtleWriter(body)
    for s in sorted(by_subject, key=lambda n: (isinstance(n, BNode), str(n))):
        pairs = sorted(by_subject[s], key=lambda po: (po[0] != RDF.type, str(po[0]), str(po[1])))
        writer.statement(names.term(s), [("a" if p == RDF.type else names.term(p), names.term(o)) for p, o in pairs])
    writer.flush()
    used = names.used()
    head = io.StringIO()
    header = TurtleWriter(head)
    header.prefixes((p, ns) for p, ns in sorted(prefixes.items()) if p in used)
    header.flush()
    return head.getvalue() + "\n" + body.getvalue()
