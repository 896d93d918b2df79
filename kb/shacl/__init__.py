"""kitkb's SHACL engine: the same results as pySHACL, in bulk and fast.

The data graph is indexed once (subject -> predicate -> objects, class membership with the
rdfs:subClassOf closure), each shape's constraints run over all its focus nodes in bulk, and
each SHACL-SPARQL constraint runs in pyoxigraph, once over the whole graph where that gives the
rows of pre-binding, else once per focus node with ``$this`` substituted (:mod:`.prebind`).
Shapes using something the engine does not implement go to pySHACL (logged as a warning on
the ``kb.shacl`` logger; :func:`unsupported_shapes` lists them beforehand). Shapes no engine
may evaluate (SPARQL the specification forbids, pySHACL's refusals) and shapes holding
something that would be skipped (a term that is no SHACL term, a component kitkb cannot
evaluate, a recursive shape pySHACL backs out of) raise :class:`ShapeError`, never a
"conforms"; :func:`check_shapes` compiles up front.

Entry points: :func:`start` (an evaluation started now and collected later, on big data in a
forked helper process: what ``kitkb validate`` uses), :func:`validate_graph`,
:func:`validate_files`, :func:`validate_index`. The parts: terms as N-Triples keys
(:mod:`.terms`), the data index (:mod:`.index`), shapes, constraints and their run context
(:mod:`.shape`), the core components (:mod:`.constraints`), SPARQL constraints
(:mod:`.sparql`, pre-binding in :mod:`.prebind`), SPARQL-based constraint components
(:mod:`.components`), the SHACL vocabulary and what is refused rather than skipped
(:mod:`.vocabulary`), the shape compiler (:mod:`.compiler`), the driver (:mod:`.engine`), work
shared with a forked child (:mod:`.parallel`), the pySHACL fallback (:mod:`.fallback`) and the
W3C validation report (:mod:`.report`).

``ont`` is the model graph. As pySHACL does when given ``ont_graph``, it is merged into the
data graph before validation: targets (sh:targetClass) and sh:class use rdfs:subClassOf
triples from data and model together, and model individuals are validated too.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Iterable
from pathlib import Path
from typing import Any

import pyoxigraph as ox
from rdflib import Graph
from rdflib.graph import ReadOnlyGraphAggregate
from rdflib.term import Node

from kb.core.errors import InputError
from kb.core.jobs import Forked
from kb.io.views import TripleView, UnionView
from kb.shacl import parallel
from kb.shacl.compiler import Program, compile_program, targeted_shapes
from kb.shacl.engine import Evaluation, Run, prefixes_of, run
from kb.shacl.fallback import pyshacl_results, run_pyshacl
from kb.shacl.index import DataIndex
from kb.shacl.result import ShaclResult
from kb.shacl.shape import ShapeError

__all__ = [
    "ShaclResult",
    "ShapeError",
    "Finish",
    "check_shapes",
    "targeted_shapes",
    "start",
    "validate_graph",
    "validate_files",
    "validate_index",
    "load_index",
    "unsupported_shapes",
]

#: Collects a started evaluation; an optional ``meanwhile`` function runs first, while a
#: forked helper may still be at work.
Finish = Callable[..., list[ShaclResult]]


def start(data: Any, shapes: Graph) -> Finish:
    """Start validating ``data`` (an rdflib graph, a :class:`~kb.io.views.TripleView`, or a
    union of them) against ``shapes``; the function returned gives the results.

    On a big graph all of it runs in a forked helper process while the caller goes on: the
    helper compiles the shapes, indexes the data and shares the evaluation with a child of its
    own (the SPARQL shapes and a little more; :mod:`kb.shacl.parallel`), so the caller's process
    never builds the engine's index; should the helper fail, the caller runs the same code
    itself. ``KITKB_SHACL_ENGINE=pyshacl`` runs pySHACL on the whole graph instead.
    """
    if os.environ.get("KITKB_SHACL_ENGINE", "") == "pyshacl":
        def whole_pyshacl(meanwhile: Callable[[], None] | None = None) -> list[ShaclResult]:
            if meanwhile is not None:
                meanwhile()
            return _pyshacl(_as_graph(data), shapes)

        return whole_pyshacl
    if parallel.can_fork(len(data)):
        job = Forked(lambda: _start_here(data, shapes, parallel.HELPER_SHARE)())
        if job.started:
            def from_helper(meanwhile: Callable[[], None] | None = None) -> list[ShaclResult]:
                try:
                    if meanwhile is not None:
                        meanwhile()
                    ok, value = job.result()
                finally:
                    job.cancel()
                if ok and isinstance(value, list):
                    return value
                return _start_here(data, shapes)()

            return from_helper
    return _start_here(data, shapes)


_programs: dict[int, tuple[Graph, Program]] = {}


def check_shapes(shapes: Graph) -> dict[Node, str]:
    """Compile ``shapes`` now (once per graph object, as :func:`start` would later): raises
    :class:`ShapeError` for a shape no engine may evaluate; returns the shapes handed to
    pySHACL, with the reason for each."""
    return dict(_program(shapes).unsupported)


def _program(shapes: Graph) -> Program:
    """``shapes`` compiled once per process (compiling the SPARQL constraints is most of the
    time of a small file; the shapes graphs passed here are cached objects, kept by identity)."""
    cached = _programs.get(id(shapes))
    if cached is None or cached[0] is not shapes:
        cached = (shapes, compile_program(shapes, rdf11_strings=False, prefixes=prefixes_of(shapes)))
        _programs[id(shapes)] = cached
    return cached[1]


def _start_here(data: Any, shapes: Graph, share: float | None = None) -> Finish:
    """The evaluation in this process (started: on a big graph a forked child is already at
    work when this returns)."""
    program = _program(shapes)
    index = DataIndex()
    for g in _parts(data):
        if isinstance(g, TripleView):
            index.add_nested(g.by_subject())
        else:
            index.add_graph(g)
    evaluation: Evaluation | None = Evaluation(index, program, rdf11_strings=False, share=share)
    # the evaluation holds the index; a caught exception's traceback could keep this frame
    # (and the index: millions of objects) alive in a reference cycle
    del index

    def finish(meanwhile: Callable[[], None] | None = None) -> list[ShaclResult]:
        nonlocal evaluation
        try:
            assert evaluation is not None
            results = evaluation.finish(meanwhile)
        finally:
            evaluation = None  # frees the index now
        if program.unsupported:
            results += run_pyshacl(_as_graph(data), shapes, None, program.unsupported)
        return list(results)

    return finish


def _parts(data: Any) -> list[Any]:
    return list(data.graphs) if isinstance(data, (UnionView, ReadOnlyGraphAggregate)) else [data]


def _as_graph(data: Any) -> Graph:
    """A plain rdflib graph (pySHACL needs one) of a union view or triple view."""
    parts = _parts(data)
    if len(parts) == 1 and isinstance(parts[0], Graph):
        return parts[0]
    out = Graph()
    for g in parts:
        for t in g:
            out.add(t)
    return out


def _pyshacl(data: Graph, shapes: Graph) -> list[ShaclResult]:
    """pySHACL on the whole graph (``KITKB_SHACL_ENGINE=pyshacl``)."""
    return pyshacl_results(data, shapes, None, [], advanced=True)


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
