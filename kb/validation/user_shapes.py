"""Shapes files that users bring (``kitkb validate --shapes``, ``kitkb shacl -s``).

Each file is read by kitkb's loader (a syntax error is an input error at its line) and must
hold shapes: a file with none (typically a misspelt ``sh:`` prefix) is refused rather than
letting everything conform, and so are files whose shapes all lack a target (they would check
nothing). The shapes are compiled before any data is looked at, so a shape the SHACL
specification forbids (MINUS or VALUES in a SPARQL constraint, ...) is refused at its
``file:line`` (:meth:`ShapesFiles.input_error`), as is a shape pySHACL refuses later.
"""

from __future__ import annotations

import functools
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path

from rdflib import RDF, BNode, Graph, URIRef
from rdflib.term import Node

from kb import shacl
from kb.core.errors import InputError
from kb.core.namespaces import SH
from kb.io.loader import Source, load_file
from kb.shacl import ShapeError
from kb.validation.report import Namer


@functools.lru_cache(maxsize=16)
def read_source(path: str, mtime: float) -> Source:
    """A shapes file read by kitkb's loader, cached by path and modification time (the shipped
    shapes are read once per process). A syntax error says it is a shapes file."""
    try:
        return load_file(path)
    except InputError as exc:
        raise InputError(f"cannot read shapes: {exc.message}", exc.file or path, exc.line) from None


def read(path: str | Path) -> Source:
    """:func:`read_source` of ``path`` (an InputError when it does not exist)."""
    p = Path(path)
    try:
        mtime = p.stat().st_mtime
    except OSError:
        mtime = 0.0  # the loader says what is wrong with it
    return read_source(str(p), mtime)


def require_shapes(g: Graph, where: str) -> None:
    """InputError naming ``where`` when ``g`` holds no shape at all."""
    typed = any(True for kind in (SH.NodeShape, SH.PropertyShape) for _ in g.subjects(RDF.type, kind))
    if not typed and not shacl.targeted_shapes(g):
        raise InputError("no SHACL shapes found (is the sh: prefix right?); refusing to validate "
                         "against an empty shapes graph", where)


@dataclass
class ShapesFiles:
    """Users' shapes files: their sources and the union of their shapes."""

    sources: list[Source]
    graph: Graph = field(default_factory=Graph)

    @classmethod
    def read(cls, paths: Sequence[str | Path]) -> "ShapesFiles":
        """Read ``paths``; InputError for a missing or broken file, a file without shapes,
        files whose shapes have no target at all, or a shape no engine may evaluate (at its
        ``file:line``)."""
        sources = [read(p) for p in paths]
        for src in sources:
            require_shapes(src.graph, str(src.path))
        if sources and not any(shacl.targeted_shapes(src.graph) for src in sources):
            others = f" (nor of {', '.join(str(s.path) for s in sources[1:])})" if len(sources) > 1 else ""
            raise InputError(f"no shape has a target{others} (sh:targetClass, sh:targetNode, "
                             "sh:targetSubjectsOf, sh:targetObjectsOf or a shape that is a class): "
                             "the shapes would check nothing", sources[0].path)
        graph = sources[0].graph if len(sources) == 1 else union([s.graph for s in sources])
        found = cls(sources, graph)
        with found.located():  # compiled now: a shape SHACL forbids is refused before any work
            shacl.check_shapes(graph)
        return found

    def input_error(self, exc: ShapeError) -> InputError:
        """``exc`` as an input error at the file and line of the shape (of its constraint),
        names spelled with the file's prefixes; ``exc`` itself when no file holds it."""
        for node in (exc.node, exc.shape):
            for src in self.sources:
                if node is not None and ((node, None, None) in src.graph or (None, None, node) in src.graph):
                    shape = exc.shape
                    name = f"shape {Namer().name(shape, src)}" if isinstance(shape, URIRef) else "a blank-node shape"
                    line = _line(src, node)
                    if isinstance(shape, BNode) and line is None:
                        line = _line(src, shape)
                    return InputError(f"{name}: {exc.what}", src.path, line)
        return exc

    @contextmanager
    def located(self) -> Iterator[None]:
        """Turn a :class:`ShapeError` raised in the block into :meth:`input_error`."""
        try:
            yield
        except ShapeError as exc:
            raise self.input_error(exc) from None


def _line(src: Source, node: Node) -> int | None:
    try:
        return src.line_of(node)
    except Exception:  # a loader that cannot place the node: the file alone
        return None


def union(graphs: Sequence[Graph]) -> Graph:
    """One graph of ``graphs``, their prefixes bound (SPARQL constraints may use a file's
    prefixes without sh:prefixes, as pySHACL lets them)."""
    out = Graph()
    for g in graphs:
        for prefix, ns in g.namespaces():
            out.bind(prefix, ns, override=False)
        for t in g:
            out.add(t)
    return out
