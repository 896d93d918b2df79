"""``kitkb convert IN -o OUT``: rewrite one ontology file in another syntax.

The input is read by :func:`kb.io.loader.load_file` (any supported format, NIST namespace
mapped onto ktw). The output syntax follows OUT's extension: ``.ttl`` Turtle, ``.owl`` /
``.rdf`` RDF/XML (with an ontology header, which Protégé needs), ``.nt`` N-Triples. The file
is written atomically (:func:`kb.core.files.write_atomic`): a failure never leaves half a
file behind nor clobbers an existing one.

Imports that the loader resolves to a shipped ontology are rewritten to that ontology's
IRI (a NIST ``Import(<file:/home/...kittingWorkstationClasses.owl>)`` becomes an import of
``https://w3id.org/kitkb/kitting``), since the converted terms now live in its namespace.
"""

from __future__ import annotations

from pathlib import Path

from rdflib import Graph, URIRef
from rdflib.namespace import OWL, RDF

from kb.core import namespaces as ns
from kb.core.errors import InputError
from kb.core import limits
from kb.core.files import write_atomic
from kb.io.loader import Source, catalog, load_file, resolve_import

OUTPUT_FORMATS = {".ttl": "turtle", ".owl": "xml", ".rdf": "xml", ".nt": "nt"}


def convert(in_path: Path, out_path: Path) -> int:
    """Read ``in_path`` and write it to ``out_path`` in the syntax of its extension; the
    number of statements written."""
    in_path, out_path = Path(in_path), Path(out_path)
    fmt = OUTPUT_FORMATS.get(out_path.suffix.lower())
    if fmt is None:
        known = ", ".join(sorted(OUTPUT_FORMATS))
        raise InputError(f"unknown output extension '{out_path.suffix}' (use one of {known})", out_path)
    source = load_file(in_path)
    graph = output_graph(source)
    try:
        with limits.deep_calls():  # rdflib's Turtle writer recurses into nested blank nodes
            data = graph.serialize(format=fmt, encoding="utf-8")
    except RecursionError:
        raise limits.NESTING.error(None, in_path, None, "blank nodes nested too deep to write") from None
    if fmt == "nt":  # rdflib writes a graph's statements in hash order: the same file every run
        data = b"".join(sorted(data.splitlines(keepends=True)))
    write_atomic(out_path, data)
    return len(graph)


def output_graph(source: Source) -> Graph:
    """The graph to write: the source's triples, prefixes bound, imports pointed at the catalog."""
    graph = Graph()
    for prefix, iri in ns.PREFIXES.items():
        graph.bind(prefix, iri)
    for prefix, iri in source.graph.namespaces():
        if prefix not in ns.PREFIXES and str(iri) not in ns.PREFIXES.values():
            graph.bind(prefix, iri, override=False)
    graph += source.graph
    onto = URIRef(source.ontology_iri) if source.ontology_iri else URIRef(source.path.resolve().as_uri())
    graph.add((onto, RDF.type, OWL.Ontology))
    shipped = {path: iri for iri, path in catalog().items() if iri.startswith(ns.BASE)}
    for iri in source.imports:
        target = resolve_import(iri, source, [source])
        if target in shipped and URIRef(iri) != URIRef(shipped[target]):
            graph.remove((onto, OWL.imports, URIRef(iri)))
            graph.add((onto, OWL.imports, URIRef(shipped[target])))
    return graph
