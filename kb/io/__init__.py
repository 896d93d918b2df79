"""Ontology files in and out: parsing, loading with imports, triple views, line indexes,
Turtle writing and conversion between syntaxes.

:func:`load` and :func:`load_file` (:mod:`.loader`) are the entry points: a file of any
supported syntax (:mod:`.parsing`: Turtle, N-Triples, RDF/XML, OWL/XML, OWL functional
syntax; NIST's namespaces mapped, :mod:`.nist2012` for the 2012 one's groups) becomes a
:class:`Source` with its triples, a cheap :class:`~kb.io.views.TripleView` and a lazy
``file:line`` index (:mod:`.lines`). :mod:`.vocabulary` says what a file is written in when a
command understood nothing in it. :mod:`.turtle` writes Turtle, :mod:`.convert` is ``kitkb convert``.
"""

from kb.io.loader import KnowledgeBase, Source, load, load_file

__all__ = ["KnowledgeBase", "Source", "load", "load_file"]
