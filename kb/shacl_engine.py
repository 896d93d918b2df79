"""Fast SHACL validation with the same results as pySHACL.

The data graph is indexed once (subject -> predicate -> objects, class membership with the
rdfs:subClassOf closure), each shape's constraints run over all its focus nodes in bulk, and
each SHACL-SPARQL constraint runs once over the whole graph in pyoxigraph instead of once per
focus node. Shapes using something the engine does not implement go to pySHACL (logged as a
warning on the ``kb.shacl`` logger; :func:`unsupported_shapes` lists them beforehand).

``ont`` is the model graph. As pySHACL does when given ``ont_graph``, it is merged into the
data graph before validation: targets (sh:targetClass) and sh:class use rdfs:subClassOf
triples from data and model together, and model individuals are validated too.
"""

from __future__ import annotations

from collections.abc import Iterable
from pathlib import Path

import pyoxigraph as ox
from rdflib import Graph
from rdflib.term import Node

from kb.errors import InputError
from kb.shacl.engine import Run, prefixes_of, run
from kb.shacl.index import DataIndex
from kb.shacl.model import SH, ShaclResult
from kb.shacl.shapes import compile_program

__all__ = [
    "SH",
    "ShaclResult",
    "validate_graph",
    "validate_files",
    "validate_index",
    "load_index",
    "unsupported_shapes",
]


def validate_graph(
    data: Graph, shapes: Graph, *, ont: Graph | None = None, sparql: str = "oxigraph"
) -> list[ShaclResult]:
    """Validate rdflib graphs; same results as ``pyshacl.validate(data, shacl_graph=shapes, ont_graph=ont)``.

    ``sparql="rdflib"`` evaluates SHACL-SPARQL constraints with rdflib's engine, as pySHACL
    does (once over the graph, not per focus node); the default, pyoxigraph, is much faster
    and differs only where rdflib departs from SPARQL (see :mod:`kb.shacl.sparql`).
    """
    index = DataIndex()
    index.add_graph(data)
    if ont is not None:
        index.add_graph(ont)
    return run(
        index,
        shapes,
        rdf11_strings=False,
        prefixes=prefixes_of(shapes, data),
        data_graph=lambda: data,
        ont=ont,
        sparql=sparql,
    ).results


def _format(path: Path) -> ox.RdfFormat:
    fmt = ox.RdfFormat.from_extension(path.suffix.lstrip(".").lower())
    if fmt is None and path.suffix.lower() == ".owl":
        fmt = ox.RdfFormat.RDF_XML
    if fmt is None:
        raise InputError(f"unknown RDF file type {path.suffix!r}", path)
    return fmt


def read_ntriples(path: str | Path) -> str:
    """Parse an RDF file with pyoxigraph and return it as N-Triples text (one triple a line)."""
    p = Path(path)
    if not p.is_file():
        raise InputError("no such file", p)
    try:
        triples = ox.parse(path=str(p), format=_format(p))
        return ox.serialize(triples, format=ox.RdfFormat.N_TRIPLES).decode("utf-8")
    except SyntaxError as exc:
        raise InputError(str(exc.msg if hasattr(exc, "msg") else exc), p, getattr(exc, "lineno", None)) from None


def load_index(paths: Iterable[str | Path]) -> DataIndex:
    """Index RDF files (data and model) with pyoxigraph's parsers."""
    index = DataIndex()
    for p in paths:
        index.add_ntriples(read_ntriples(p))
    return index


def validate_index(
    index: DataIndex,
    shapes: Graph,
    *,
    data_graph: Graph | None = None,
    sources: Iterable[str | Path] = (),
    sparql: str = "oxigraph",
) -> Run:
    """Validate an index made by :func:`load_index`.

    ``data_graph`` (or else the ``sources`` files, parsed with rdflib) is only used when a shape
    falls back to pySHACL.
    """
    files = list(sources)

    def fallback_graph() -> Graph:
        if data_graph is not None:
            return data_graph
        g = Graph()
        for f in files:
            g.parse(str(f))
        return g

    return run(
        index, shapes, rdf11_strings=True, prefixes=prefixes_of(shapes), data_graph=fallback_graph, sparql=sparql
    )


def validate_files(
    data: Iterable[str | Path],
    shapes: Graph | str | Path,
    *,
    ont: Iterable[str | Path] = (),
    sparql: str = "oxigraph",
) -> list[ShaclResult]:
    """Validate RDF files (data plus model files in ``ont``) against a shapes graph or file."""
    files = [*data, *ont]
    if not isinstance(shapes, Graph):
        shapes_file = Path(shapes)
        if not shapes_file.is_file():
            raise InputError("no such file", shapes_file)
        shapes = Graph().parse(str(shapes_file))
    return validate_index(load_index(files), shapes, sources=files, sparql=sparql).results


def unsupported_shapes(shapes: Graph) -> dict[Node, str]:
    """Target-bearing shapes the engine hands to pySHACL, with the reason for each."""
    return dict(compile_program(shapes, rdf11_strings=False, prefixes=prefixes_of(shapes)).unsupported)
