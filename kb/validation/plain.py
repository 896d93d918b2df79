"""Plain SHACL over files: ``kitkb shacl DATA... -s SHAPES...``.

No kitting model, no closed-world rules, no imports followed: the data files (read by
kitkb's loader, any syntax it reads) are one data graph, the shapes files one shapes graph,
and the result is SHACL's validation report, each result placed at the ``file:line`` of its
focus node. The shapes run on kitkb's engine (:mod:`kb.shacl`; pySHACL for what it does not
implement); the shapes files are read and checked by :mod:`kb.validation.user_shapes`, so a
shape the specification forbids is an input error at its line, never a report.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Sequence

from rdflib import RDF, BNode, Graph, URIRef
from rdflib.collection import Collection
from rdflib.term import Node

from kb import shacl
from kb.core.diagnostics import Diagnostic
from kb.core.errors import InputError
from kb.core.memory import gc_paused
from kb.core.namespaces import SH
from kb.core.progress import SILENT, Progress
from kb.io.loader import Source, load_file
from kb.io.turtle import turtle
from kb.io.views import UnionView
from kb.shacl import ShaclResult
from kb.shacl.report import report_graph
from kb.validation.report import Namer
from kb.validation.user_shapes import ShapesFiles

SEVERITIES = {SH.Violation: "violation", SH.Warning: "warning", SH.Info: "info"}
_DIAGNOSTIC = {"violation": "error", "warning": "warning", "info": "info"}


@dataclass
class Placed:
    """A result and where its focus node is stated (file and line; None where unknown)."""

    result: ShaclResult
    source: Source | None
    line: int | None


@dataclass
class ShaclReport:
    """What :func:`validate_files` found."""

    results: list[Placed]
    data_files: list[str]
    shapes_files: ShapesFiles
    #: Shapes pySHACL evaluated (kitkb's engine does not implement them), with the reason.
    fallback: dict[Node, str] = field(default_factory=dict)
    seconds: float = 0.0

    @property
    def conforms(self) -> bool:
        """SHACL's ``sh:conforms``: no result of any severity."""
        return not self.results

    def counts(self) -> dict[str, int]:
        """Results by severity (``violation``, ``warning``, ``info``)."""
        out = dict.fromkeys(SEVERITIES.values(), 0)
        for p in self.results:
            word = severity(p.result)
            out[word] = out.get(word, 0) + 1
        return out

    def summary(self) -> str:
        """``conforms`` or ``does not conform: 3 results (2 violations, 1 warning)``."""
        if self.conforms:
            return "conforms"
        n = len(self.results)
        parts = [f"{k} {w}{'s' * (k != 1)}" for w, k in self.counts().items() if k]
        return f"does not conform: {n} result{'s' * (n != 1)} ({', '.join(parts)})"

    def turtle(self) -> str:
        """The W3C validation report (``sh:ValidationReport``) as Turtle."""
        return turtle(report_graph([p.result for p in self.results], self.shapes_files.graph))

    def diagnostics(self) -> list[Diagnostic]:
        """One ``file:line`` line per result (severity error for sh:Violation)."""
        namer = Namer()
        return [_diagnostic(p, namer, self.shapes_files.graph) for p in self.results]

    def as_dict(self) -> dict[str, Any]:
        """The report as plain data (``kitkb shacl --format json``)."""
        rows = []
        for p in self.results:
            r = p.result
            rows.append({
                "file": str(p.source.path) if p.source is not None else None, "line": p.line,
                "severity": severity(r), "focus": _n3(r.focus), "path": _n3(r.path), "value": _n3(r.value),
                "source_shape": _n3(r.source_shape), "component": _n3(r.component), "message": r.message,
            })
        return {"conforms": self.conforms, "data": list(self.data_files),
                "shapes": [str(s.path) for s in self.shapes_files.sources], "counts": self.counts(),
                "results": rows, "pyshacl_shapes": {_n3(k): v for k, v in self.fallback.items()}}


def severity(r: ShaclResult) -> str:
    """``violation``, ``warning``, ``info`` (a custom severity: its local name)."""
    return SEVERITIES.get(r.severity) or str(r.severity).replace("#", "/").rsplit("/", 1)[-1]


def validate_files(data: Sequence[str | Path], shapes: Sequence[str | Path],
                   progress: Progress = SILENT) -> ShaclReport:
    """Validate the ``data`` files (one data graph) against the ``shapes`` files (one shapes
    graph); InputError for unusable input: a missing or broken file, shapes files without
    shapes, a shape the specification forbids (at its ``file:line``)."""
    started = time.perf_counter()
    if not data:
        raise InputError("nothing to validate: no data files given")
    if not shapes:
        raise InputError("no shapes files given (-s SHAPES)")
    with gc_paused(), progress.task(f"reading {len(shapes)} shapes file(s)") as step:
        user = ShapesFiles.read(shapes)
        fallback = shacl.check_shapes(user.graph)  # compiled by read() already: the reasons
        step.update(description=f"reading {len(data)} data file(s)")
        unique = {str(Path(p).resolve()): p for p in data}
        sources = [load_file(p) for p in unique.values()]
        step.update(description=f"SHACL shapes on {len(sources)} file(s)")
        graph = UnionView([s.view() for s in sources])
        with user.located():
            results = shacl.start(graph, user.graph)()
        step.update(description="finding the lines of the results")
        _prepare_lines(sources, results)
        placed = sorted((_place(r, sources) for r in results), key=_order)
    return ShaclReport(placed, [str(s.path) for s in sources], user, fallback, time.perf_counter() - started)


def _prepare_lines(sources: list[Source], results: list[ShaclResult]) -> None:
    """Index the statements of the results' focus nodes in one pass over each big file
    (else each look-up reads the file again), and of the nodes that refer to a focus node
    stated only as an object."""
    for src in sources:
        view = src.view()
        wanted = {r.focus for r in results if (r.focus, None, None) in view}
        wanted.update(next(iter(view.subjects(None, r.focus)), None) for r in results
                      if r.focus not in wanted and (None, None, r.focus) in view)
        wanted.discard(None)
        if wanted:
            try:
                src.prepare_lines(wanted)
            except Exception:  # only an optimisation: line_of looks up one by one
                pass


def _place(r: ShaclResult, sources: list[Source]) -> Placed:
    """The file stating the result's focus node and the line (of the value, else the path,
    else the node)."""
    for src in sources:
        view = src.view()
        if (r.focus, None, None) in view or (None, None, r.focus) in view:
            tries = [(r.focus, r.path, r.value), (r.focus, r.path, None), (r.focus, None, None)]
            tries += [(s, p, r.focus) for s, p in view.subject_predicates(r.focus)][:1]  # an object only
            for s, p, o in tries:
                if p is not None and not isinstance(p, URIRef):
                    continue
                try:
                    line = src.line_of(s, p, o)
                except Exception:  # a node the line index cannot place: the file alone
                    line = None
                if line:
                    return Placed(r, src, line)
            return Placed(r, src, None)
    return Placed(r, None, None)


def _order(p: Placed) -> tuple[Any, ...]:
    r = p.result
    return (str(p.source.path) if p.source is not None else "~", p.line or 0, str(r.focus), str(r.path),
            str(r.source_shape), str(r.component), str(r.value))


def _diagnostic(p: Placed, namer: Namer, shapes: Graph) -> Diagnostic:
    r, src = p.result, p.source
    f = namer.name(r.focus, src)
    path = f" {path_text(r.path, shapes, namer, src)}" if r.path is not None else ""
    value = f" = {namer.name(r.value, src)}" if r.value is not None and r.value != r.focus else ""
    comp = str(r.component).replace("#", "/").rsplit("/", 1)[-1].removesuffix("ConstraintComponent")
    rule = comp if isinstance(r.source_shape, BNode) else f"{comp} of {namer.name(r.source_shape, src)}"
    return Diagnostic(str(src.path) if src is not None else "(data)", p.line, _DIAGNOSTIC.get(severity(r), "info"),  # type: ignore[arg-type]
                      f"{f}{path}{value}: {r.message}", rule, f)


def path_text(path: Node, shapes: Graph, namer: Namer, src: Any = None, depth: int = 0) -> str:
    """A SHACL property path in SPARQL's path syntax (``^ex:p``, ``ex:p/ex:q``, ``ex:p*``)."""
    if isinstance(path, URIRef):
        return namer.name(path, src)
    if depth > 20:
        return "..."

    def sub(node: Node) -> str:
        text = path_text(node, shapes, namer, src, depth + 1)
        return text if isinstance(node, URIRef) else f"({text})"

    if (path, RDF.first, None) in shapes:
        return "/".join(sub(n) for n in Collection(shapes, path))
    for pred, fmt in ((SH.inversePath, "^{}"), (SH.zeroOrMorePath, "{}*"), (SH.oneOrMorePath, "{}+"),
                      (SH.zeroOrOnePath, "{}?")):
        inner = shapes.value(path, pred)
        if inner is not None:
            return fmt.format(sub(inner))
    alt = shapes.value(path, SH.alternativePath)
    if alt is not None:
        return "|".join(sub(n) for n in Collection(shapes, alt))
    return "[]"


def _n3(term: Node | None) -> str | None:
    return None if term is None else term.n3()
