"""Line index of one source file: where each statement is written, for ``file:line`` reports.

Built only when asked (:meth:`kb.io.loader.Source.line_of`). One small reader per syntax:
:mod:`.turtle` (Turtle/N-Triples tokenizer), :mod:`.owl` (OWL functional syntax and OWL/XML
axioms) and :mod:`.rdfxml` (expat walk of RDF/XML), each filling a :class:`LineIndex`. The
readers are tolerant: the file has already been parsed properly, so anything they do not
understand is skipped, never raised. Big Turtle files are indexed only for the subjects a
report names (:class:`.turtle.TargetedTurtleIndex`).
"""

from __future__ import annotations

from kb.io.lines import owl, rdfxml, turtle
from kb.io.lines.index import Key, LineIndex

__all__ = ["Key", "LineIndex", "build_index"]


def build_index(text: str, fmt: str, base: str) -> LineIndex:
    """The line index of ``text`` (format as in :data:`kb.io.parsing.FORMATS`)."""
    index = LineIndex()
    if fmt in ("turtle", "ntriples"):
        turtle.index_turtle(text, base, index)
    elif fmt in ("ofn", "owlxml"):
        owl.index_owl(text, fmt, base, index)
    elif fmt == "rdfxml":
        rdfxml.index_rdfxml(text, base, index)
    return index
