"""Closed-world validation of ontology files: ``kitkb validate FILE...``.

:func:`validate` loads the files (with their imports), tells model files from data files,
runs the Python rules of :mod:`kb.validate_rules`, generates SHACL shapes from the loaded
OWL model (the shipped kitting model's shapes are checked in and cached), adds the
hand-written rules of ``shapes/kitting-rules.ttl``, runs SHACL over each data file together
with the model, and turns every finding into a :class:`kb.diagnostics.Diagnostic` with a
file and line. :func:`run_validate` is the command: it prints the report and returns the
exit code (0 conforms, 1 violations; unusable input raises :class:`kb.errors.InputError`,
exit 2). See docs/validation.md for the rules.
"""

from __future__ import annotations

import dataclasses
import functools
import hashlib
import os
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Iterable, NamedTuple, Sequence, TextIO

from rdflib import OWL, RDF, Graph, URIRef
from rdflib.graph import ReadOnlyGraphAggregate

from generators.owlmodel import OwlModel
from generators.shapes import ShapesGenerator
from kb.diagnostics import Diagnostic, to_json
from kb.errors import InputError
from kb.namespaces import KTW
from kb.parsing import gc_paused
from kb.sources import TripleView, UnionView
from kb import validate_rules as rules
from kb.validate_report import SH, Namer, ShaclResult, dedupe, diagnostics, line_of

#: Hand-written shapes applied when the model holds the kitting vocabulary.
KITTING_RULES = "kitting-rules.ttl"
KITTING_SHAPES = "kitting-shapes.ttl"


@dataclass
class ValidationReport:
    """What :func:`validate` found: diagnostics sorted by file and line."""

    diagnostics: list[Diagnostic] = field(default_factory=list)
    files: list[str] = field(default_factory=list)
    seconds: float = 0.0

    @property
    def errors(self) -> list[Diagnostic]:
        """The diagnostics of severity error."""
        return [d for d in self.diagnostics if d.severity == "error"]

    @property
    def conforms(self) -> bool:
        """True when nothing worse than a warning was found."""
        return not self.errors

    def summary(self) -> str:
        """One phrase: ``conforms`` or ``3 errors, 1 warning``."""
        n_err, n_warn = len(self.errors), len(self.diagnostics) - len(self.errors)
        if not self.diagnostics:
            return "conforms"
        parts = [f"{n_err} error{'s' * (n_err != 1)}"] if n_err else ["conforms"]
        if n_warn:
            parts.append(f"{n_warn} warning{'s' * (n_warn != 1)}")
        return ", ".join(parts)


# --- the command ------------------------------------------------------------------------

def default_files() -> list[str]:
    """The shipped model files and scenario files (what ``kitkb validate`` checks by default)."""
    from kb.resources import ontologies_dir, scenario_dirs

    files = sorted(str(p) for p in ontologies_dir().glob("*.ttl"))
    for d in scenario_dirs():
        files += [str(p) for p in sorted(d.glob("*.ttl"))]
    return files


def run_validate(files: list[str], *, fmt: str = "text", out: TextIO) -> int:
    """``kitkb validate``: print the report (text or JSON); 0 conforms, 1 violations."""
    report = validate(files or default_files())
    if fmt == "json":
        print(to_json(report.diagnostics), file=out)
    else:
        for d in report.diagnostics:
            print(d.format(), file=out)
        print(f"{len(report.files)} file(s): {report.summary()}", file=out)
    return 0 if report.conforms else 1


# --- validation -------------------------------------------------------------------------

def validate(paths: Sequence[str | Path], *, shapes_files: Sequence[str | Path] | None = None
             ) -> ValidationReport:
    """Validate ``paths`` (model and data files) closed-world; see the module docstring.

    ``shapes_files`` replaces the hand-written rule files (for tests); an empty shapes
    graph raises :class:`InputError`.
    """
    started = time.perf_counter()
    if not paths:
        raise InputError("nothing to validate: no files given")
    # millions of long-lived acyclic objects (terms, index dictionaries): the cyclic garbage
    # collector would walk them all again and again, for nothing
    with gc_paused():
        return _validate(paths, shapes_files, started)


def _validate(paths: Sequence[str | Path], shapes_files: Sequence[str | Path] | None,
              started: float) -> ValidationReport:
    kb = _load([str(p) for p in paths])
    given = {_key(p) for p in paths}
    sources = [s for s in kb.sources if _key(s.path) in given] or list(kb.sources)
    data = [s for s in kb.sources if rules.is_data_graph(rules.graph_of(s))]
    model_graph = _merge(*(s.graph for s in kb.sources if s not in data))
    model = OwlModel(model_graph)
    namer = Namer()
    later = _Deferred()
    checked = {id(src): g for src in sources if (g := _shacl_data(src, data, model_graph)) is not None}
    found: dict[int, list[ShaclResult]] = {}
    shapes = None
    pending: list[tuple[int, Finish]] = []
    if checked or shapes_files is not None:
        shapes = _shapes(model, shapes_files)
        # the first file's SHACL run starts now (on a big file, part of it in a forked
        # process), the Python rules run meanwhile; the other files follow one by one
        todo = [src for src in sources if id(src) in checked]
        if todo:
            pending.append((id(todo[0]), _start_shacl(checked[id(todo[0])], shapes)))
        pending += [(id(src), functools.partial(_later_shacl, checked[id(src)], shapes)) for src in todo[1:]]
    ctx = rules.Context(model, _individuals(kb.sources), namer.name, later.locate)
    for src in sources:
        ctx.out.extend(getattr(src, "warnings", []) or [])
        (rules.check_data_source if src in data else rules.check_model_source)(ctx, src)
    for key, finish in pending:
        # while a forked child is still evaluating, the big files get ready for line look-ups
        found[key] = finish(functools.partial(later.warm, sources))
    # every line asked for is looked up in one pass over each (big) file
    for src in sources:
        later.want(src, (r.focus for r in found.get(id(src), ())))
        later.want(src, (s for r in found.get(id(src), ()) if r.path is not None and not isinstance(r.path, URIRef)
                         for s in checked[id(src)].subjects(None, r.focus)))
    later.prepare()
    ctx.out = [later.resolve(d) for d in ctx.out]
    ctx.locate = line_of
    shacl: list[Diagnostic] = []
    for src in sources:
        if id(src) in found:
            g = checked[id(src)]
            shacl += diagnostics(found[id(src)], src, g, shapes, namer, ctx)
    diags = dedupe(ctx.out + shacl)
    return ValidationReport(diags, [str(s.path) for s in sources], time.perf_counter() - started)


class _Line(NamedTuple):
    """A line not looked up yet: (source, s, p, o) of :func:`line_of`."""

    src: Any
    s: Any
    p: Any
    o: Any


class _Deferred:
    """Collects the line look-ups of the rules, so a big file is scanned once for all of them."""

    def __init__(self) -> None:
        self.subjects: dict[int, tuple[Any, set]] = {}

    def locate(self, src: Any, s: Any, p: Any = None, o: Any = None) -> _Line:
        self.want(src, [s])
        return _Line(src, s, p, o)

    def want(self, src: Any, subjects: Iterable[Any]) -> None:
        self.subjects.setdefault(id(src), (src, set()))[1].update(subjects)

    @staticmethod
    def warm(sources: Iterable[Any]) -> None:
        """Get the sources ready for line look-ups (read a big file, find its directives)."""
        for src in sources:
            warm = getattr(src, "warm_lines", None)
            if warm is not None:
                try:
                    warm()
                except Exception:  # only an optimisation, as in prepare()
                    pass

    def prepare(self) -> None:
        for src, subjects in self.subjects.values():
            prepare = getattr(src, "prepare_lines", None)
            if prepare is not None:
                try:
                    prepare(subjects)
                except Exception:  # only an optimisation: line_of looks up one by one
                    pass

    @staticmethod
    def resolve(d: Diagnostic) -> Diagnostic:
        if isinstance(d.line, _Line):
            return dataclasses.replace(d, line=line_of(*d.line))
        return d


def _shacl_data(src: Any, data: list[Any], model_graph: Graph) -> Any:
    """The graph SHACL checks for ``src``: a data file with the model (and data files it
    imports); a model file holding individuals: the model; otherwise None (nothing to check)."""
    if src in data:
        imported = {str(i) for i in (getattr(src, "imports", None) or [])}
        others = [rules.graph_of(d) for d in data if d is not src and str(getattr(d, "ontology_iri", "")) in imported]
        return _union_view(model_graph, rules.graph_of(src), *others)
    if any(True for _ in rules.individual_types(rules.graph_of(src))):
        return model_graph
    return None


def _key(path: Any) -> str:
    return str(Path(str(path)).resolve())


def _merge(*graphs: Graph) -> Graph:
    out = Graph()
    for g in graphs:
        for t in g:
            out.add(t)
    return out


def _union_view(*graphs: Any) -> UnionView:
    """A read-only union of graphs without copying them (queried by the reporter)."""
    return UnionView(list(graphs))


def _individuals(sources: Iterable[Any]) -> set[URIRef]:
    """Individuals of all sources: subjects typed with a model class or owl:NamedIndividual."""
    out: set[URIRef] = set()
    for src in sources:
        g = rules.graph_of(src)
        out.update(s for s, _ in rules.individual_types(g))
        out.update(s for s in g.subjects(RDF.type, OWL.NamedIndividual) if isinstance(s, URIRef))
    return out


# --- shapes -----------------------------------------------------------------------------

def _signature(model: OwlModel) -> str:
    terms = sorted(str(t) for t in [*model.classes, *model.properties, *model.datatypes])
    return hashlib.sha1("\n".join(terms).encode()).hexdigest()


@functools.lru_cache(maxsize=1)
def _shipped_signature() -> str:
    from kb.loader import load_file
    from kb.resources import ontology_path

    return _signature(OwlModel(load_file(ontology_path("kitting.ttl")).graph))


@functools.lru_cache(maxsize=8)
def _parse_shapes(path: str, mtime: float) -> Graph:
    """A shapes file as an rdflib graph, read by kitkb's loader (pyoxigraph: a fifth of
    the time of rdflib's Turtle parser; syntax errors come with their line)."""
    from kb.loader import load_file

    try:
        return load_file(path).graph
    except InputError as exc:
        raise InputError(f"cannot read shapes: {exc.message}", exc.file or path, exc.line) from None


_generated: dict[str, Graph] = {}


def _shapes(model: OwlModel, shapes_files: Sequence[str | Path] | None) -> Graph:
    """Generated shapes for ``model`` plus the hand-written rule files; never empty."""
    from kb.resources import shapes_path

    if not model.classes:
        raise InputError("no model to validate against: the files declare no classes and import no "
                         "model (add owl:imports <https://w3id.org/kitkb/kitting>)")
    sig = _signature(model)
    shipped = shapes_path(KITTING_SHAPES)
    if sig == _shipped_signature() and shipped.exists():
        generated = _parse_shapes(str(shipped), shipped.stat().st_mtime)
    else:
        if sig not in _generated:
            _generated[sig] = ShapesGenerator(model).graph()
        generated = _generated[sig]
    _require_shapes(generated, str(shipped))
    extra = [Path(p) for p in shapes_files] if shapes_files is not None else (
        [shapes_path(KITTING_RULES)] if any(str(c).startswith(str(KTW)) for c in model.classes) else [])
    graphs = [generated]
    for p in extra:
        g = _parse_shapes(str(p), p.stat().st_mtime if p.exists() else 0.0)
        _require_shapes(g, str(p))
        graphs.append(g)
    key = tuple(id(g) for g in graphs)
    if key not in _merged:
        _merged[key] = _merge(*graphs) if len(graphs) > 1 else generated
    return _merged[key]


_merged: dict[tuple[int, ...], Graph] = {}


def _require_shapes(g: Graph, where: str) -> None:
    shapes = set(g.subjects(RDF.type, SH.NodeShape)) | set(g.subjects(SH.targetClass, None)) \
        | set(g.subjects(SH.targetNode, None)) | set(g.subjects(SH.targetSubjectsOf, None)) \
        | set(g.subjects(SH.targetObjectsOf, None))
    if not shapes:
        raise InputError("no SHACL shapes found (is the sh: prefix right?); refusing to validate "
                         "against an empty shapes graph", where)


# --- SHACL ------------------------------------------------------------------------------

def _run_shacl(data: Graph, shapes: Graph) -> list[ShaclResult]:
    """Run SHACL with kitkb's fast engine (``KITKB_SHACL_ENGINE=pyshacl`` selects pySHACL)."""
    return _start_shacl(data, shapes)()


def _later_shacl(data: Graph, shapes: Graph, meanwhile: Callable[[], None] | None = None) -> list[ShaclResult]:
    """:func:`_run_shacl`, called when its results are wanted (``meanwhile`` runs first)."""
    if meanwhile is not None:
        meanwhile()
    return _run_shacl(data, shapes)


Finish = Callable[..., list[ShaclResult]]


def _start_shacl(data: Graph, shapes: Graph) -> Finish:
    """Start :func:`_run_shacl`; the function returned gives its results. It takes an
    optional ``meanwhile`` function, run while a forked child may still be at work."""
    if os.environ.get("KITKB_SHACL_ENGINE", "") != "pyshacl":
        try:
            return _start_compiled(data, shapes)
        except ImportError:  # the engine's internals moved: its public function still works
            pass

    def finish(meanwhile: Callable[[], None] | None = None) -> list[ShaclResult]:
        if meanwhile is not None:
            meanwhile()
        if os.environ.get("KITKB_SHACL_ENGINE", "") == "pyshacl":
            return _run_pyshacl(_as_graph(data), shapes)
        from kb.shacl_engine import validate_graph

        return list(validate_graph(_as_graph(data), shapes))  # type: ignore[arg-type]

    return finish


_programs: dict[int, tuple[Graph, Any]] = {}


def _as_graph(data: Any) -> Graph:
    """A plain graph (pySHACL needs one) from a union view."""
    return _merge(*data.graphs) if isinstance(data, (UnionView, ReadOnlyGraphAggregate)) else data


def _start_compiled(data: Graph, shapes: Graph) -> Finish:
    """kb.shacl.engine's evaluation, started.

    On a big graph all of it runs in a forked helper process (:class:`kb.shacl.parallel.Forked`)
    while the caller goes on with the Python rules: the helper compiles the shapes, indexes
    the data and shares the evaluation with a child of its own (the SPARQL shapes and a
    little more; :mod:`kb.shacl.parallel`), so the caller's process never builds the engine's
    index. Should the helper fail, the caller runs the same code itself.
    """
    from kb.shacl import parallel

    if parallel.can_fork(len(data)):
        job = parallel.Forked(lambda: _start_in_process(data, shapes, parallel.HELPER_SHARE)())
        if job.started:
            def finish(meanwhile: Callable[[], None] | None = None) -> list[ShaclResult]:
                try:
                    if meanwhile is not None:
                        meanwhile()
                    ok, value = job.result()
                finally:
                    job.cancel()
                if ok and isinstance(value, list):
                    return value
                return _start_in_process(data, shapes)()

            return finish
    return _start_in_process(data, shapes)


def _start_in_process(data: Graph, shapes: Graph, share: float | None = None) -> Finish:
    """kb.shacl.engine's evaluation in this process (started: on a big graph a forked child
    is already at work when this returns), with each shapes graph compiled once per process.

    Compiling (parsing the SPARQL constraints) is most of the time of a small file; the
    shapes graphs passed here are cached objects, so the program is kept by identity.
    """
    from kb.shacl.engine import Evaluation, prefixes_of
    from kb.shacl.fallback import run_pyshacl
    from kb.shacl.index import DataIndex
    from kb.shacl.shapes import compile_program

    cached = _programs.get(id(shapes))
    if cached is None or cached[0] is not shapes:
        cached = (shapes, compile_program(shapes, rdf11_strings=False, prefixes=prefixes_of(shapes)))
        _programs[id(shapes)] = cached
    program = cached[1]
    index = DataIndex()
    for g in data.graphs if isinstance(data, (UnionView, ReadOnlyGraphAggregate)) else [data]:
        if isinstance(g, TripleView):
            index.add_nested(g.by_subject())
        else:
            index.add_graph(g)
    evaluation = Evaluation(index, program, rdf11_strings=False, share=share)
    # the evaluation holds the index; a caught exception's traceback could keep this frame
    # (and the index: millions of objects) alive in a reference cycle
    del index

    def finish(meanwhile: Callable[[], None] | None = None) -> list[ShaclResult]:
        nonlocal evaluation
        try:
            results = evaluation.finish(meanwhile)
        finally:
            evaluation = None  # type: ignore[assignment]  # frees the index now
        if program.unsupported:
            results += run_pyshacl(_as_graph(data), shapes, None, program.unsupported)
        return list(results)  # type: ignore[arg-type]

    return finish


def _run_pyshacl(data: Graph, shapes: Graph) -> list[ShaclResult]:
    """Run pySHACL and read its results graph into :class:`ShaclResult` tuples."""
    import pyshacl

    _conforms, results, _text = pyshacl.validate(data, shacl_graph=shapes, inference="none",
                                                 advanced=True, allow_warnings=True)
    out = []
    for r in results.objects(None, SH.result):  # top-level results, not nested sh:detail ones
        out.append(ShaclResult(results.value(r, SH.focusNode), results.value(r, SH.resultPath),
                               results.value(r, SH.value), results.value(r, SH.sourceShape),
                               results.value(r, SH.sourceConstraintComponent),
                               results.value(r, SH.resultSeverity),
                               str(results.value(r, SH.resultMessage) or "")))
    return out


# --- loading ----------------------------------------------------------------------------

def _load(paths: list[str]) -> Any:
    """Load the files and their imports (kb.loader)."""
    from kb.loader import load

    return load(paths)


__all__ = ["ValidationReport", "ShaclResult", "validate", "run_validate", "default_files", "line_of"]
