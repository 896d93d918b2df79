"""Closed-world validation of ontology files: ``kitkb validate FILE...``.

:func:`validate` loads the files (with their imports), tells model files from data files,
runs the Python rules of :mod:`kb.validation.rules`, generates SHACL shapes from the loaded
OWL model (the shipped kitting model's shapes are checked in and cached), adds the
hand-written rules of ``shapes/kitting-rules.ttl``, runs SHACL over each data file together
with the model, and turns every finding into a :class:`kb.core.diagnostics.Diagnostic` with a
file and line, in a :class:`ValidationReport` (which the command line prints; unusable input
raises :class:`kb.core.errors.InputError`). See docs/validation.md for the rules.
"""

from __future__ import annotations

import contextlib
import dataclasses
import functools
import hashlib
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Collection, Iterable, NamedTuple, Sequence

from rdflib import OWL, RDF, Graph, URIRef

from kb import shacl
from kb.core.diagnostics import Diagnostic
from kb.core.errors import InputError
from kb.core.memory import gc_paused
from kb.core.progress import SILENT, Progress, Task
from kb.core.namespaces import KITTING_DOMAIN_ONTOLOGY, KTW, NIST_KTW_2012, local_name
from kb.core.resources import ontologies_dir, ontology_path, scenario_dirs, shapes_path
from kb.io.loader import (NIST_2012_TERM, SHIPPED_DOMAIN, KnowledgeBase, declare_classes, load, load_file,
                          not_read_warning)
from kb.io.views import UnionView
from kb.io.vocabulary import no_model
from kb.model.owl import OwlModel
from kb.shacl import ShaclResult
from kb.spatial.unlocated import unlocated
from kb.validation import rules, user_shapes
from kb.validation.geometry import check_geometry
from kb.validation.report import Namer, dedupe, diagnostics, line_of
from kb.validation.shapes import DerivedShapes
from kb.validation.user_shapes import ShapesFiles

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
        """One phrase: ``conforms`` or ``3 errors, 1 warning`` (``, 1 note`` for the infos)."""
        n_err = len(self.errors)
        n_info = sum(d.severity == "info" for d in self.diagnostics)
        n_warn = len(self.diagnostics) - n_err - n_info
        if not self.diagnostics:
            return "conforms"
        parts = [f"{n_err} error{'s' * (n_err != 1)}"] if n_err else ["conforms"]
        if n_warn:
            parts.append(f"{n_warn} warning{'s' * (n_warn != 1)}")
        if n_info:
            parts.append(f"{n_info} note{'s' * (n_info != 1)}")
        return ", ".join(parts)

    def as_dict(self) -> dict[str, Any]:
        """The report as plain data: ``conforms``, ``files``, ``counts`` by severity,
        ``diagnostics`` (what ``kitkb validate --format json`` prints)."""
        counts = {severity: 0 for severity in ("error", "warning", "info")}
        for d in self.diagnostics:
            counts[d.severity] = counts.get(d.severity, 0) + 1
        return {"conforms": self.conforms, "files": list(self.files), "counts": counts,
                "diagnostics": [dataclasses.asdict(d) for d in self.diagnostics]}


def default_files() -> list[str]:
    """The shipped model files and scenario files (what ``kitkb validate`` checks by default)."""
    files = sorted(str(p) for p in ontologies_dir().glob("*.ttl"))
    for d in scenario_dirs():
        files += [str(p) for p in sorted(d.glob("*.ttl"))]
    return files


# --- validation -------------------------------------------------------------------------

def validate(paths: Sequence[str | Path], *, shapes_files: Sequence[str | Path] | None = None,
             extra_shapes: Sequence[str | Path] = (), ignore: Collection[str] = (),
             progress: Progress = SILENT, loaded: KnowledgeBase | None = None,
             domain: Sequence[str | Path] = ()) -> ValidationReport:
    """Validate ``paths`` (model and data files) closed-world; see the module docstring.

    ``shapes_files`` replaces the hand-written rule files (for tests); an empty shapes
    graph raises :class:`InputError`. ``extra_shapes``: users' shapes files, applied to the
    data files besides the shipped shapes (``kitkb validate --shapes``; read and checked by
    :mod:`kb.validation.user_shapes`, a bad one is an InputError at its ``file:line``).
    ``ignore``: rule names left out of the report (the geometry rules are then not even
    computed). ``progress``: where each step says what it does (:mod:`kb.core.progress`).
    ``loaded``: ``paths`` already loaded with their imports (:func:`kb.io.load`), so that a
    caller that goes on with the files (the closed loop) parses each once. ``domain``: domain
    extensions (``kitkb validate --domain FILE``), read as the other commands read them (the
    shipped ``kitting-domain.ttl`` first, unless one of them replaces it) and validated too: the
    classes of objects they declare, and their individuals, are known to ``paths``
    (docs/validation.md, "A domain extension's classes").
    """
    started = time.perf_counter()
    if not paths and not domain:
        raise InputError("nothing to validate: no files given")
    # millions of long-lived acyclic objects (terms, index dictionaries): the cyclic garbage
    # collector would walk them all again and again, for nothing
    with gc_paused(), progress.task(f"reading {len(paths)} file(s)") as step:
        user = ShapesFiles.read(extra_shapes) if extra_shapes else None
        if domain:
            loaded = _with_domain(loaded if loaded is not None else load([str(p) for p in paths]), domain)
            paths = [*domain, *paths]
        elif paths:
            loaded = loaded if loaded is not None else load([str(p) for p in paths])
            if _types_from_domain(loaded):  # a state placing an object of a class the shipped domain declares
                loaded = _with_domain(loaded, [])
        report = _validate(paths, shapes_files, started, frozenset(ignore), step, user, loaded)
    if ignore:
        report.diagnostics = [d for d in report.diagnostics if d.rule not in ignore]
    return report


def _validate(paths: Sequence[str | Path], shapes_files: Sequence[str | Path] | None,
              started: float, ignore: frozenset[str] = frozenset(), step: Task | None = None,
              user: ShapesFiles | None = None, loaded: KnowledgeBase | None = None) -> ValidationReport:
    step = step or SILENT.task("")
    located = user.located if user is not None else contextlib.nullcontext
    kb = loaded if loaded is not None else load([str(p) for p in paths])
    given = {_key(p) for p in paths}
    sources = [s for s in kb.sources if _key(s.path) in given] or list(kb.sources)
    data = [s for s in kb.sources if rules.is_data_graph(rules.graph_of(s))]
    model_graph = _merge(*(s.graph for s in kb.sources if s not in data))
    model = shapes_model = OwlModel(model_graph)
    namer = Namer()
    later = _Deferred()
    # the classes of objects the domain files declare under the model's join it for every file
    domain = rules.domain_classes(data, model, namer.name)
    if domain.accepted:
        model = OwlModel(_merge(model_graph, domain.graph))
        declare_classes([s for s in data if any(domain.declares(s, c) for c in domain.accepted)])
    checked = {id(src): g for src in sources
               if (g := _shacl_data(src, data, model_graph, domain)) is not None}
    found: dict[int, list[ShaclResult]] = {}
    shapes = None
    pending: list[tuple[int, shacl.Finish]] = []
    if checked or shapes_files is not None or user is not None:
        if not model.classes:  # before _shapes says so: the imports that did not resolve, at their lines
            raise no_model(kb)
        shapes = _shapes(shapes_model, shapes_files, user)
        if user is not None:
            with located():  # a shape SHACL forbids: refused before any work, at its line
                shacl.check_shapes(shapes)
        # the first file's SHACL run starts now (on a big file, part of it in a forked
        # process), the Python rules run meanwhile; the other files follow one by one
        todo = [src for src in sources if id(src) in checked]
        if todo:
            pending.append((id(todo[0]), shacl.start(checked[id(todo[0])], shapes)))
        pending += [(id(src), functools.partial(_later_shacl, checked[id(src)], shapes)) for src in todo[1:]]
    step.update(description="the Python rules and geometry" + (", SHACL meanwhile" if pending else ""))
    ctx = rules.RuleContext(model, _individuals(kb.sources), namer.name, later.locate, domain=domain)
    for src in sources:
        ctx.out.extend(w for w in getattr(src, "warnings", None) or [] if w.rule != NIST_2012_TERM)
        (rules.check_data_source if src in data else rules.check_model_source)(ctx, src)
        if src in data:
            _unlocated_notes(ctx, src)
            check_geometry(ctx, src, ignore)
        ctx.out.extend(_not_read(src, ctx, ignore))
    step.update(description=f"SHACL shapes on {len(checked)} file(s)")
    for key, finish in pending:
        # while a forked child is still evaluating, the big files get ready for line look-ups
        with located():  # pySHACL may refuse a user's shape it was handed
            found[key] = finish(functools.partial(later.warm, sources))
    # every line asked for is looked up in one pass over each (big) file
    for src in sources:
        later.want(src, (r.focus for r in found.get(id(src), ())))
        later.want(src, (s for r in found.get(id(src), ()) if r.path is not None and not isinstance(r.path, URIRef)
                         for s in checked[id(src)].subjects(None, r.focus)))
    step.update(description="finding the lines of the results")
    later.prepare()
    ctx.out = [later.resolve(d) for d in ctx.out]
    ctx.locate = line_of
    shacl_diags: list[Diagnostic] = []
    for src in sources:
        if id(src) in found:
            g = checked[id(src)]
            shacl_diags += diagnostics(found[id(src)], src, g, shapes, namer, ctx,
                                       user.graph if user is not None else None)
    diags = _follows(dedupe(ctx.out + shacl_diags), ctx.follows, ignore)
    return ValidationReport(diags, [str(s.path) for s in sources], time.perf_counter() - started)


def _unlocated_notes(ctx: rules.RuleContext, src: Any) -> None:
    """A note (``location-unknown``) at each object of a data file whose location is unknown
    (:mod:`kb.spatial.unlocated`): valid partial data, sensed by ``kitkb run`` before it plans;
    its missing primary location is then no ``min-count`` error (docs/validation.md, "Partial
    data: objects to be sensed")."""
    for u in unlocated(src):
        ctx.unlocated.add(URIRef(u.name))
        ctx.report(src, u.line, "info", f"{ctx.name(URIRef(u.name), src)}'s location is unknown ({u.why}): "
                   f"kitkb run senses it (class {local_name(u.cls)}) before it plans; generate pddl and plan "
                   "need it placed", "location-unknown", URIRef(u.name))


def _not_read(src: Any, ctx: rules.RuleContext, ignore: frozenset[str]) -> list[Diagnostic]:
    """The loader's warning about the terms of NIST's 2012 namespace kitkb does not read, less
    the terms reported at each statement that uses them (``unknown-property``,
    ``unknown-class``, ``data-declares-term``, unless ignored): one defect, one report. The
    other commands, which have no such errors, print the loader's warning whole."""
    warnings = [w for w in getattr(src, "warnings", None) or [] if w.rule == NIST_2012_TERM]
    unmapped = getattr(src, "unmapped_2012", None)
    if not warnings or unmapped is None:
        return warnings
    path = str(src.path)
    reported = {str(term) for file, rule, term in ctx.reported_terms if file == path and rule not in ignore}
    left = {name: line for name, line in unmapped.items() if NIST_KTW_2012 + name not in reported}
    warning = not_read_warning(src.path, left)
    return [warning] if warning is not None else []


def _follows(diags: list[Diagnostic], follows: dict[tuple[str, str, str, str], frozenset[Any]],
             ignore: frozenset[str] = frozenset()) -> list[Diagnostic]:
    """Without the findings that only follow from another error of the same file: geometry
    that cannot be read once an error says why (a misspelt coordinate is an unknown property,
    not also a missing value); a pose found implausible when one of its nodes has an error (an
    axis not of unit length). A finding's nodes are names (any other error there) or pairs
    (name, word): another error there whose message has the word in it (case aside). An error
    of a rule in ``ignore`` is left out of the report, so it stands for nothing: what follows from
    it is reported (``--ignore unknown-individual`` must not hide the unknown-reference that
    ``predicates`` then refuses)."""
    wrong: dict[tuple[str, str], list[Diagnostic]] = {}
    for d in diags:
        if d.severity == "error" and d.rule not in ignore:
            wrong.setdefault((d.file, d.focus), []).append(d)

    def follows_error(d: Diagnostic) -> bool:
        for n in follows.get((d.file, d.rule, d.focus, d.message), ()):
            name, word = n if isinstance(n, tuple) else (n, None)
            if any(e is not d and (word is None or word.lower() in e.message.lower())
                   for e in wrong.get((d.file, name), ())):
                return True
        return False
    return [d for d in diags if not follows_error(d)]


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


def _shacl_data(src: Any, data: list[Any], model_graph: Graph,
                domain: rules.DomainClasses | None = None) -> Any:
    """The graph SHACL checks for ``src``: a data file with the model (and data files it
    imports, and the domain files' classes of objects: their superclasses are what the shapes
    of the model's classes target them by); a model file holding individuals: the model;
    otherwise None (nothing to check)."""
    if src in data:
        imported = {str(i) for i in (getattr(src, "imports", None) or [])}
        others = [rules.graph_of(d) for d in data if d is not src and str(getattr(d, "ontology_iri", "")) in imported]
        if domain is not None and domain.accepted and not any(domain.declares(src, c) for c in domain.accepted):
            others.append(domain.graph)  # (a file declaring them has them already: no duplicates)
        return _union_view(model_graph, rules.graph_of(src), *others)
    if any(True for _ in rules.individual_types(rules.graph_of(src))):
        return model_graph
    return None


def _with_domain(kb: KnowledgeBase, extensions: Sequence[str | Path]) -> KnowledgeBase:
    """``kb`` with the domain of ``extensions`` (``--domain``): the extension files, the shipped
    ``kitting-domain.ttl`` unless one of them replaces it (declares its ontology IRI), and their
    imports; each file once, ``kb``'s sources first."""
    ext = load([str(p) for p in extensions])
    wanted = KITTING_DOMAIN_ONTOLOGY.rstrip("#/")
    if not any((s.ontology_iri or "").rstrip("#/") == wanted for s in ext.sources):
        ext = KnowledgeBase([*ext.sources, *load([ontology_path(SHIPPED_DOMAIN)]).sources])
    seen = {_key(s.path) for s in kb.sources}
    extra = []
    for s in ext.sources:
        if _key(s.path) not in seen:
            seen.add(_key(s.path))
            extra.append(s)
    return KnowledgeBase([*kb.sources, *extra]) if extra else kb


def _types_from_domain(kb: KnowledgeBase) -> bool:
    """Whether a file of ``kb`` types an individual with a term of the shipped kitting domain's
    namespace (``kd:RejectBin``): the domain's classes of objects are then known to the files, as
    with ``--domain``, without naming it."""
    kd = KITTING_DOMAIN_ONTOLOGY + "#"
    wanted = KITTING_DOMAIN_ONTOLOGY.rstrip("#/")
    if any((s.ontology_iri or "").rstrip("#/") == wanted for s in kb.sources):
        return False  # the domain is among the files already
    return any(str(o).startswith(kd) for s in kb.sources for o in set(s.graph.objects(None, RDF.type)))


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


def _later_shacl(data: Any, shapes: Graph, meanwhile: Any = None) -> list[ShaclResult]:
    """SHACL over ``data``, started when its results are wanted (``meanwhile`` runs first)."""
    return shacl.start(data, shapes)(meanwhile)


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
    return _signature(OwlModel(load_file(ontology_path("kitting.ttl")).graph))


_generated: dict[str, Graph] = {}


def _shapes(model: OwlModel, shapes_files: Sequence[str | Path] | None, user: ShapesFiles | None = None) -> Graph:
    """Derived shapes for ``model`` plus the hand-written rule files and the users' shapes;
    never empty."""
    if not model.classes:
        raise InputError("no model to validate against: the files declare no classes and import no "
                         "model (add owl:imports <https://w3id.org/kitkb/kitting>)")
    sig = _signature(model)
    shipped = shapes_path(KITTING_SHAPES)
    if sig == _shipped_signature() and shipped.exists():
        generated = user_shapes.read(shipped).graph
    else:
        if sig not in _generated:
            _generated[sig] = DerivedShapes(model).graph()
        generated = _generated[sig]
    user_shapes.require_shapes(generated, str(shipped))
    extra = [Path(p) for p in shapes_files] if shapes_files is not None else (
        [shapes_path(KITTING_RULES)] if any(str(c).startswith(str(KTW)) for c in model.classes) else [])
    graphs = [generated]
    for p in extra:
        g = user_shapes.read(p).graph
        user_shapes.require_shapes(g, str(p))
        graphs.append(g)
    if user is not None:
        graphs.append(user.graph)
    key = tuple(id(g) for g in graphs)
    if key not in _merged:
        _merged[key] = user_shapes.union(graphs) if len(graphs) > 1 else generated
    return _merged[key]


_merged: dict[tuple[int, ...], Graph] = {}


__all__ = ["ValidationReport", "validate", "default_files"]
