"""Ontology files in and out: parsing, loading with imports, triple views, line indexes,
Turtle writing and conversion between syntaxes.

:func:`load` and :func:`load_file` (:mod:`.loader`) are the entry points: a file of any
supported syntax (:mod:`.parsing`: Turtle, N-Triples, RDF/XML, OWL/XML, OWL functional
syntax; NIST's namespace mapped) becomes a :class:`Source` with its triples, a cheap
:class:`~kb.io.views.TripleView` and a lazy ``file:line`` index (:mod:`.lines`).
:mod:`.turtle` writes Turtle, :mod:`.convert` is ``kitkb convert``.
"""

from kb.io.loader import KnowledgeBase, Source, load, load_file

__all__ = ["KnowledgeBase", "Source", "load", "load_file"]
