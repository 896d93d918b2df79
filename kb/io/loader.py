"""Load ontology files into rdflib graphs, resolve their imports, and find statements' lines.

Formats (detected by content; the extension only breaks ties): Turtle, N-Triples, RDF/XML,
OWL/XML and OWL functional syntax (the NIST ``.owl`` files). See :mod:`kb.io.parsing` for the
parsers and :mod:`kb.sources` for the lazy ``file:line`` index.

Import resolution (:func:`resolve_import`) never touches the network nor an arbitrary
``file:`` path. In order, an ``owl:imports`` IRI resolves to:

1. a shipped ontology whose IRI it is (:func:`catalog`);
2. a file named on the command line whose ontology IRI it is;
3. kitkb's ``kitting.ttl`` if the IRI ends with ``kittingWorkstationClasses.owl`` or
   ``kittingClasses.owl`` (NIST's 2013 and 2012 models; their namespaces are mapped onto ours;
   NIST's 2012 model found beside the importing file, and not named, is left unread with a
   note at the import's line, rule ``model-stand-in``, once per load);
4. a file named on the command line with the IRI's file name (``.../soapClasses.owl``);
5. the file a Protégé catalog (``catalog-v001.xml`` in the folder of the importing file) gives
   for the IRI, if it lies in that folder or below;
6. a file with the IRI's file name in the folder of the importing file (same-folder rule);
otherwise it is a warning at the line of the import.
"""

from __future__ import annotations

import re
import xml.etree.ElementTree as ElementTree
from contextlib import contextmanager
from pathlib import Path
from typing import Iterable, Iterator, Sequence
from urllib.parse import unquote, urlsplit

from rdflib import BNode, Graph, URIRef
from rdflib.namespace import OWL, RDF, RDFS, XSD

from kb.core import namespaces as ns
from kb.core.diagnostics import Diagnostic
from kb.core.errors import InputError
from kb.core.files import note_input
from kb.core.limits import check_file_size, deep_calls
from kb.core.memory import gc_paused
from kb.core.resources import ontologies_dir, ontology_path, shapes_dir
from kb.io import nist2012
from kb.io.lines import LineIndex, build_index
from kb.io.lines.turtle import TargetedTurtleIndex
from kb.io.parsing import Triple, check_xml, new_graph, parse_text, prepare
from kb.io.views import TripleView

#: File names of NIST's kitting models (2013, 2012): an import of either is kitkb's model.
_NIST_MODEL_FILES = ("kittingWorkstationClasses.owl", "kittingClasses.owl")
_VOCABULARY = (str(RDF), str(RDFS), str(OWL), str(XSD))
#: The file name Protégé gives the catalog it writes beside an ontology.
PROTEGE_CATALOG = "catalog-v001.xml"
#: Rules of the loader's warnings about parts of a file that are not read (every command
#: that reads files shows them, not only ``validate``: see :func:`reading_notes`).
NOT_READ_RULES = frozenset({"nist-2012-term", "model-stand-in"})
#: The rule of the warning naming the terms of NIST's 2012 namespace kitkb does not read.
NIST_2012_TERM = "nist-2012-term"
#: The rule of the note saying that kitkb's model stands in for NIST's 2012 model file found
#: beside the importing file (which is then not read).
MODEL_STAND_IN = "model-stand-in"
#: The file name of NIST's 2012 kitting model.
NIST_2012_MODEL_FILE = "kittingClasses.owl"
_notes: list[list[Diagnostic]] = []


@contextmanager
def reading_notes() -> Iterator[list[Diagnostic]]:
    """Collect, while the ``with`` block runs, the warnings of :data:`NOT_READ_RULES` of every
    file loaded (for a command to show: what it read and did not understand)."""
    found: list[Diagnostic] = []
    _notes.append(found)
    try:
        yield found
    finally:
        _notes.remove(found)


class Source:
    """One loaded file: its triples (namespace-mapped), header, warnings, and line index.

    ``graph`` is built on first use from the parsed triples (a knowledge base's union graph
    is filled straight from them, so a per-file graph costs nothing until asked for).
    """

    def __init__(self, path: Path, format: str, graph: Graph | None = None, ontology_iri: str | None = None,
                 imports: list[str] | None = None, warnings: list[Diagnostic] | None = None,
                 *, triples: list[Triple] | None = None, prefixes: dict[str, str] | None = None):
        self.path = Path(path)
        self.format = format
        self.ontology_iri = ontology_iri
        self.imports = list(imports or [])
        self.warnings = list(warnings or [])
        self._graph = graph
        self._triples = triples
        self._view: TripleView | None = None
        self._index: LineIndex | None = None
        #: Targeted line index of big Turtle files: only the subjects asked for are indexed.
        self._partial: LineIndex | None = None
        self._covered: set = set()
        self._mode: str | None = None  # "full" or "targeted", decided on the first lookup
        self._target = None
        #: The file's prefix declarations (namespace-mapped); bound in ``graph``.
        self.prefixes = dict(prefixes or {})
        #: kitkb's term -> the IRIs of NIST's 2012 namespace the file writes it as (only the
        #: 2012 terms mapped onto kitkb's model; a message names a term as the file writes it)
        self.written_as: dict[URIRef, tuple[str, ...]] = {}
        #: the local names of the 2012 terms kitkb does not read -> the line of their first use
        #: (what the ``nist-2012-term`` warning lists)
        self.unmapped_2012: dict[str, int | None] = {}

    def __repr__(self) -> str:
        return f"Source({str(self.path)!r}, {self.format!r}, ontology_iri={self.ontology_iri!r})"

    def copy(self) -> "Source":
        """A new Source over the same parsed statements (the list of triples copied, the
        triples themselves shared: they are immutable); its graph, views and line index are
        built again on first use, so nothing one holder does to them reaches the other."""
        twin = Source(self.path, self.format, None, self.ontology_iri, self.imports, self.warnings,
                      triples=list(self.triples()), prefixes=self.prefixes)
        twin.written_as = dict(self.written_as)
        twin.unmapped_2012 = dict(self.unmapped_2012)
        return twin

    @property
    def graph(self) -> Graph:
        """This file's triples as an rdflib graph."""
        if self._graph is None:
            with gc_paused():
                triples = self._triples if self._triples is not None else (self._view or ())
                self._graph = new_graph(triples, self.prefixes)
            self._triples = None
        return self._graph

    def triples(self) -> Iterable[Triple]:
        """This file's triples (without building its graph)."""
        if self._triples is not None:
            return self._triples
        return iter(self._view) if self._view is not None else iter(self.graph)

    def view(self) -> TripleView:
        """This file's triples as a :class:`kb.io.views.TripleView` (much cheaper to build than
        ``graph``; what validation queries)."""
        if self._view is None:
            with gc_paused():
                self._view = TripleView(self._triples if self._triples is not None else self.graph)
            self._triples = None  # the view holds them (without duplicates)
        return self._view

    def line_of(self, subject, predicate=None, obj=None) -> int | None:  # noqa: ANN001
        """1-based line of (s,p,o), else of (s,p), else of the first statement about s.

        A blank node is located through the statement that refers to it. The index is
        built on the first call.
        """
        line = self._lookup(subject, predicate, obj)
        if line is None and isinstance(subject, BNode):
            root = subject
            for depth, parent in enumerate(self._referrers(subject)):
                line = self._lookup(*parent)
                root = parent[0]
                if line is not None or depth > 20:
                    break
            if line is None and isinstance(root, BNode):
                line = self._full_index().axiom_line(self._named_closure(root))
        return line

    #: Turtle files at least this big are indexed only for the subjects asked about.
    TARGETED_BYTES = 4_000_000

    def prepare_lines(self, subjects: Iterable) -> None:  # noqa: ANN001
        """Index, in one pass over a big Turtle file, the statements of ``subjects`` (and of
        the named nodes blank ones hang off), before asking their lines one by one."""
        if self._index is not None or not self._targeted():
            return
        wanted = set()
        for s in subjects:
            if isinstance(s, BNode):
                wanted.update(p[0] for p in self._referrers(s) if isinstance(p[0], URIRef))
            elif isinstance(s, URIRef):
                wanted.add(s)
        self._scan(wanted - self._covered)

    def warm_lines(self) -> None:
        """Get ready for line look-ups without indexing anything yet (a big Turtle file is
        read and its directives found; see :meth:`prepare_lines`)."""
        if self._index is None:
            self._targeted()

    def _lookup(self, subject, predicate=None, obj=None) -> int | None:  # noqa: ANN001
        if self._index is None and self._targeted():
            if isinstance(subject, URIRef) and subject not in self._covered:
                self._scan({subject})
            return self._partial.lookup(subject, predicate, obj) if self._partial is not None else None
        return self._full_index().lookup(subject, predicate, obj)

    def _full_index(self) -> LineIndex:
        if self._index is None:
            with gc_paused():
                self._index = self._build_index()
        return self._index

    def _targeted(self) -> bool:
        """True for a big Turtle/N-Triples file (without @base, which the scan does not follow)."""
        if self._mode is None:
            self._mode = "full"
            if self.format not in ("turtle", "ntriples"):
                return False
            try:
                if self.path.stat().st_size < self.TARGETED_BYTES:
                    return False
                text = self.path.read_bytes().decode("utf-8-sig")
            except (OSError, UnicodeDecodeError):
                return False
            target = TargetedTurtleIndex(text, self.path.resolve().as_uri())
            if target.usable:
                self._partial, self._target, self._mode = LineIndex(), target, "targeted"
        return self._mode == "targeted"

    def _scan(self, subjects: set) -> None:
        if subjects:
            with gc_paused(), deep_calls():
                self._target.index(subjects, self._partial)
            self._covered |= subjects

    def _named_closure(self, node: BNode, limit: int = 10_000) -> set[URIRef]:
        """Named non-vocabulary terms reachable from a blank node (what its axiom mentions)."""
        found: set[URIRef] = set()
        seen, stack = {node}, [node]
        while stack and len(seen) < limit:
            for p, o in self.view().predicate_objects(stack.pop()):
                if isinstance(o, BNode) and o not in seen:
                    seen.add(o)
                    stack.append(o)
                for term in (p, o):
                    if isinstance(term, URIRef) and not str(term).startswith(_VOCABULARY):
                        found.add(term)
        return found

    def _referrers(self, node: BNode):  # noqa: ANN202
        seen = {node}
        while isinstance(node, BNode):
            parent = next(iter(self.view().subject_predicates(node)), None)
            if parent is None or parent[0] in seen:
                return
            seen.add(parent[0])
            yield parent
            node = parent[0]

    def text(self) -> str | None:
        """The file's text as it was parsed (:func:`kb.io.parsing.prepare`), None if it cannot
        be read again."""
        try:
            return prepare(self.path.read_bytes(), self.path).text
        except (OSError, InputError):
            return None

    def _build_index(self) -> LineIndex:
        text = self.text()
        if text is None:
            return LineIndex()
        try:
            with deep_calls():  # the readers recurse once per level of nesting
                return build_index(text, self.format, self.path.resolve().as_uri())
        except RecursionError:  # nesting limit lifted: no lines rather than a crash
            return LineIndex()


class KnowledgeBase:
    """Sources (named files first, then resolved imports) and the union of their triples.

    ``graph`` is built on first use (validation never asks for it). With a single source it
    is that source's graph (the same object, not a copy).
    """

    def __init__(self, sources: list[Source], graph: Graph | None = None) -> None:
        self.sources = sources
        self._graph = graph

    def __repr__(self) -> str:
        return f"KnowledgeBase({self.sources!r})"

    @property
    def graph(self) -> Graph:
        """The union of all sources' triples as one rdflib graph."""
        if self._graph is None:
            with gc_paused():
                self._graph = _union(self.sources)
        return self._graph

    def source_of(self, subject, predicate=None, obj=None) -> tuple[Source, int | None] | None:  # noqa: ANN001
        """The source stating (s,p,o) / (s,p) / something about s, preferring named files."""
        for source in self.sources:
            if (subject, predicate, obj) in source.graph:
                return source, source.line_of(subject, predicate, obj)
        return None

    @property
    def warnings(self) -> list[Diagnostic]:
        """Every source's warnings, in source order."""
        return [w for s in self.sources for w in s.warnings]

    @property
    def unresolved_imports(self) -> list[Diagnostic]:
        """The warnings of the imports that were not resolved, in source order."""
        return [w for w in self.warnings if w.rule == "unresolved-import"]


def catalog() -> dict[str, Path]:
    """Ontology IRI (and known aliases) -> shipped file."""
    kitting = ontology_path("kitting.ttl")
    return {
        ns.KITTING_ONTOLOGY: kitting,
        ns.SOAP_ONTOLOGY: ontology_path("soap.ttl"),
        ns.KITTING_DOMAIN_ONTOLOGY: ontology_path("kitting-domain.ttl"),
        ns.NIST_ONTOLOGY: kitting,
        ns.NIST_ONTOLOGY_2012: kitting,
    }


def load_file(path: str | Path) -> Source:
    """Read one file (any supported format); InputError if it is missing or malformed, or
    past a limit of :mod:`kb.core.limits` (size, statements, literal length, nesting).

    kitkb's own model ontologies and shapes (the files directly in the shipped ``ontologies/``
    and ``shapes/`` folders, which the validator, the scene, the units and the domain each
    import) are parsed once per process: a later read gets a new :class:`Source` over the same
    parsed statements, while the file is unchanged (same size, modification time, inode)."""
    path = Path(path)
    key = _shipped_key(path)
    if key is not None and key in _SHIPPED:
        note_input(path)
        source = _SHIPPED[key].copy()
        for notes in _notes:  # as a first reading tells them
            notes.extend(w for w in source.warnings if w.rule in NOT_READ_RULES)
        return source
    with gc_paused():
        source = _load_file(path)
    if key is not None:
        _SHIPPED[key] = source.copy()
    return source


#: shipped model file's (path, size, mtime_ns, inode) -> its first reading (never handed out)
_SHIPPED: dict[tuple, "Source"] = {}


def _shipped_key(path: Path) -> tuple | None:
    """The cache key of a shipped model ontology or shapes file, else None."""
    try:
        folder = path.resolve().parent
        if folder not in _shipped_folders():
            return None
        st = path.stat()
    except OSError:
        return None
    return (str(path.resolve()), st.st_size, st.st_mtime_ns, st.st_ino)


_FOLDERS: list[frozenset[Path]] = []


def _shipped_folders() -> frozenset[Path]:
    if not _FOLDERS:
        _FOLDERS.append(frozenset(p.resolve() for p in (ontologies_dir(), shapes_dir())))
    return _FOLDERS[0]


def _load_file(path: Path) -> Source:
    note_input(path)
    try:
        check_file_size(path, path.stat().st_size if path.is_file() else None)
        data = path.read_bytes()
    except FileNotFoundError:
        raise InputError("no such file", path) from None
    except IsADirectoryError:
        raise InputError("is a folder, not a file", path) from None
    except OSError as exc:
        raise InputError(f"cannot read: {exc.strerror or exc}", path) from None
    prepared = prepare(data, path)
    text, fmt, warnings = prepared.text, prepared.format, prepared.warnings
    terms: dict[str, URIRef] = {}
    prefixes: dict[str, str] = {}
    triples = parse_text(text, fmt, path, terms, prefixes, raw=data if prepared.utf8 else None)
    if ns.NIST_KTW_2012 in text:  # (written out, or in a prefix declaration)
        triples = nist2012.read_groups(triples, path, lambda local: _first_line(text, local))
    a, ontology, imports_ = (terms.get(str(t)) for t in (RDF.type, OWL.Ontology, OWL.imports))
    onto = next((s for s, p, o in triples if o is ontology and p is a), None) if ontology is not None else None
    imports = [str(o) for s, p, o in triples if p is imports_ and s == onto] if imports_ is not None else []
    ontology_iri = str(onto) if isinstance(onto, URIRef) else None
    unmapped = _unmapped_2012(terms, triples, text)
    warning = not_read_warning(path, unmapped)
    if warning is not None:
        warnings.append(warning)
    for notes in _notes:
        notes.extend(w for w in warnings if w.rule in NOT_READ_RULES)
    source = Source(path, fmt, None, ontology_iri, imports, warnings, triples=triples, prefixes=prefixes)
    source.unmapped_2012 = unmapped
    if unmapped or ns.NIST_KTW_2012 in text:
        source.written_as = _written_as(terms)
    return source


_DECLARED_TERMS = frozenset(map(str, (OWL.Class, OWL.ObjectProperty, OWL.DatatypeProperty,
                                       OWL.AnnotationProperty, RDFS.Datatype)))


def _unmapped_2012(terms: dict[str, URIRef], triples: list[Triple], text: str) -> dict[str, int | None]:
    """The classes and properties of NIST's 2012 namespace that have no counterpart in kitkb's
    model (kept as they are, so no rule of kitkb reads them), local name -> the line of its
    first use, in the order of those lines. (NIST's 2012 files name their individuals in that
    namespace too; they are not terms.)"""
    ns2012 = ns.NIST_KTW_2012
    if ns2012 not in text:
        return {}
    a = terms.get(str(RDF.type))
    found: set[str] = set()
    for s, p, o in triples:
        if str(p).startswith(ns2012):
            found.add(str(p))
        if p is a and isinstance(o, URIRef):
            if str(o).startswith(ns2012):
                found.add(str(o))
            elif str(o) in _DECLARED_TERMS and str(s).startswith(ns2012):
                found.add(str(s))
    names = [iri[len(ns2012):] for iri in found if len(iri) > len(ns2012)]
    lines = {name: _first_line(text, name) for name in names}
    return dict(sorted(lines.items(), key=lambda nl: (nl[1] or 0, nl[0])))


def not_read_warning(path: str | Path, unmapped: dict[str, int | None]) -> Diagnostic | None:
    """The warning (``nist-2012-term``, at the first line) naming the terms of NIST's 2012
    namespace kitkb does not read (local name -> line of its first use, in line order); None
    when there are none."""
    if not unmapped:
        return None
    names = list(unmapped)
    shown = [f"{n} (line {unmapped[n]})" if unmapped[n] else n for n in names[:8]]
    more = f" and {len(names) - 8} more" if len(names) > 8 else ""
    return Diagnostic(str(path), unmapped[names[0]], "warning",
                      f"{len(names)} term(s) of NIST's 2012 kitting vocabulary <{ns.NIST_KTW_2012}> have no "
                      f"counterpart in kitkb's model and are not read: {', '.join(shown)}{more} "
                      "(docs/validation.md, \"NIST's 2012 vocabulary\")", rule=NIST_2012_TERM)


def _written_as(terms: dict[str, URIRef]) -> dict[URIRef, tuple[str, ...]]:
    """kitkb's term -> the IRIs the file writes it as, for the terms of NIST's 2012 namespace
    read as kitkb's (a term the file also writes in kitkb's namespace lists that IRI too)."""
    out: dict[URIRef, list[str]] = {}
    for written, read in terms.items():
        if written.startswith(ns.NIST_KTW_2012) and str(read) != written:
            out.setdefault(read, []).append(written)
    for read, written in out.items():
        if str(read) in terms:
            written.append(str(read))
    return {read: tuple(sorted(written)) for read, written in out.items()}


def _first_line(text: str, local: str) -> int | None:
    m = re.search(r"[:#]" + re.escape(local) + r"(?![\w-])", text)
    return text.count("\n", 0, m.start()) + 1 if m else None


def load(paths: Sequence[str | Path], *, resolve_imports: bool = True) -> KnowledgeBase:
    """Load the named files and (transitively) their imports into one knowledge base."""
    unique: dict[Path, Path] = {}
    for p in paths:
        unique.setdefault(Path(p).resolve(), Path(p))
    return _knowledge_base([load_file(p) for p in unique.values()], resolve_imports)


#: The shipped domain file, the first file of every domain (:func:`domain_knowledge`).
SHIPPED_DOMAIN = "kitting-domain.ttl"


def domain_knowledge(extensions: Sequence[str | Path] | None = None) -> KnowledgeBase:
    """The planning domain as one knowledge base: the shipped ``kitting-domain.ttl`` first, then
    each extension file in ``extensions`` (``--domain FILE``), with their imports.

    This is the one way kitkb reads a domain; its own domain file is simply the list's first
    entry. An extension adds actions (with their programs), predicates, functions, failure
    modes, fault kinds ... to the shipped ones; it may ``owl:imports`` kitkb's ontologies by IRI
    (``https://w3id.org/kitkb/soap``, ``.../kitting``, ``.../kitting-domain``: the shipped files,
    never the network). A file that declares the shipped domain's own ontology IRI
    (``<https://w3id.org/kitkb/kitting-domain> a owl:Ontology``: a modified copy of it) takes the
    shipped file's place instead of adding to it. Errors in a file (syntax, limits) are
    InputErrors at its ``file:line``; what the domain's readers find wrong in the knowledge
    (:mod:`kb.model.soap`, :mod:`kb.model.definitions`) they report at the line of the node."""
    unique: dict[Path, Path] = {}
    for p in extensions or ():
        unique.setdefault(Path(p).resolve(), Path(p))
    given = [load_file(p) for p in unique.values()]
    shipped = ontology_path(SHIPPED_DOMAIN)
    replaced = shipped.resolve() in unique or any(
        (s.ontology_iri or "").rstrip("#/") == ns.KITTING_DOMAIN_ONTOLOGY.rstrip("#/") for s in given)
    kb = _knowledge_base(given if replaced else [load_file(shipped), *given], True)
    if given and not replaced:
        _check_terms(given, kb)
    declare_classes(kb.sources)
    return kb


#: the classes of objects that domain files declare beyond the kitting model (a domain
#: extension's new kind of object, ``xp:BufferBox rdfs:subClassOf ktw:LargeContainer``): class
#: -> its named superclasses. The object classes of the domains loaded in this process, read
#: by everything that types objects from state files (:func:`kb.spatial.scene.class_ancestors`).
#: A class of another namespace is harmless where no state file names it.
_EXTENSION_CLASSES: dict[str, frozenset[str]] = {}


def declare_classes(sources: Iterable[Source]) -> None:
    """Add the classes that ``sources`` declare outside kitkb's model namespaces (with their
    ``rdfs:subClassOf`` parents) to the process's extension classes: a domain's files, when the
    domain is loaded (:func:`domain_knowledge`). Only a class that descends from a class of the
    kitting model types objects (:func:`kb.spatial.scene.class_ancestors`)."""
    ours = (str(ns.KTW), str(ns.SOAP))
    found: dict[str, set[str]] = {}
    for src in sources:
        g = src.graph
        for c in g.subjects(RDF.type, OWL.Class):
            if isinstance(c, URIRef) and not str(c).startswith(ours):
                found.setdefault(str(c), set())
        for c, parent in g.subject_objects(RDFS.subClassOf):
            if isinstance(c, URIRef) and isinstance(parent, URIRef) and not str(c).startswith(ours):
                found.setdefault(str(c), set()).add(str(parent))
    # added to what earlier domains of the process declared (a class's parents as read last): a
    # reader of the shipped domain alone, in the middle of a run with extensions, forgets nothing
    _EXTENSION_CLASSES.update((c, frozenset(ps)) for c, ps in found.items())


def extension_classes() -> dict[str, frozenset[str]]:
    """The classes of objects the domains loaded declare beyond the kitting model (class -> its
    named superclasses; :func:`declare_classes`); the shipped domain's (``kd:RejectBin``) always,
    read once per process when none was loaded yet."""
    global _SHIPPED_DECLARED
    if not _SHIPPED_DECLARED:
        _SHIPPED_DECLARED = True
        declare_classes([s for s in load([ontology_path(SHIPPED_DOMAIN)]).sources
                         if str(s.path).endswith(SHIPPED_DOMAIN)])
    return _EXTENSION_CLASSES


_SHIPPED_DECLARED = False


def _check_terms(extensions: list[Source], kb: KnowledgeBase) -> None:
    """InputError at its line for the first term of kitkb's namespaces (SOAP, the kitting model,
    the kitting domain) that an extension uses but no file of the domain states anything
    about: a misspelt property or class (``soap:hasPredicate_Defintion``), or a reference to
    an action, predicate or individual that is not defined."""
    known = {s for s in kb.graph.subjects() if isinstance(s, URIRef)}
    ours = (str(ns.SOAP), str(ns.KTW), str(ns.KD))
    for source in extensions:
        for s, p, o in source.triples():
            for term in (p, o):
                if isinstance(term, URIRef) and term not in known and str(term).startswith(ours):
                    what = "property" if term is p else "term"
                    raise InputError(f"unknown {what} {_curie(term)}: no file of the "
                                     "domain (the shipped kitting-domain.ttl, soap.ttl, kitting.ttl and the "
                                     "extensions) defines it", source.path, source.line_of(s, p, o))


def _curie(term: URIRef) -> str:
    """``soap:Name`` / ``ktw:Name`` / ``kd:Name`` for a term of kitkb's namespaces."""
    for prefix, space in (("soap", ns.SOAP), ("ktw", ns.KTW), ("kd", ns.KD)):
        if str(term).startswith(str(space)):
            return f"{prefix}:{str(term)[len(str(space)):]}"
    return f"<{term}>"


def domain_paths(extensions: Sequence[str | Path] | None = None) -> list[Path]:
    """The files :func:`domain_knowledge` reads for ``extensions`` (the shipped domain first), without
    the model ontologies (``soap.ttl``, ``kitting.ttl``) they import."""
    model = {ontology_path(name).resolve() for name in ("soap.ttl", "kitting.ttl")}
    return [s.path for s in domain_knowledge(extensions).sources if s.path.resolve() not in model]


def _knowledge_base(sources: list[Source], resolve_imports: bool) -> KnowledgeBase:
    """The knowledge base of the files ``sources`` (already read) and, with
    ``resolve_imports``, the files they import (transitively)."""
    named = list(sources)
    _stand_in_notes(named)
    if resolve_imports:
        seen_paths = {s.path.resolve() for s in sources}
        seen_iris = {s.ontology_iri for s in sources if s.ontology_iri}
        queue = list(sources)
        while queue:
            importer = queue.pop(0)
            for iri in importer.imports:
                if iri in seen_iris:
                    continue
                target = resolve_import(iri, importer, named)
                if target is None:
                    importer.warnings.append(_unresolved(iri, importer))
                    continue
                if target.resolve() in seen_paths:
                    continue
                if not target.is_file():
                    importer.warnings.append(_unresolved(iri, importer, f" (catalog file {target.name} missing)"))
                    continue
                seen_paths.add(target.resolve())
                source = load_file(target)
                seen_iris.update(i for i in (iri, source.ontology_iri) if i)
                sources.append(source)
                queue.append(source)
    return KnowledgeBase(sources)


def _stand_in_notes(named: list[Source]) -> None:
    """A note (``model-stand-in``, severity info) at the import of NIST's 2012 model
    (``kittingClasses.owl``) by a named file when that model lies beside it and is not named
    itself: kitkb's model stands in for it (the import resolves to ``kitting.ttl``, its terms
    mapped), so the file is not read. One note per model file, at its first importer."""
    given = {s.path.resolve() for s in named}
    said: set[Path] = set()
    for importer in named:
        for iri in importer.imports:
            name = _file_name(iri.rstrip("#/"))
            if name != NIST_2012_MODEL_FILE:
                continue
            beside = importer.path.parent / name
            try:
                found = beside.resolve() if beside.is_file() else None
            except OSError:
                found = None
            if found is None or found in given or found in said:
                continue
            said.add(found)
            note = Diagnostic(
                str(importer.path), _import_line(importer, iri), "info",
                f"{name} beside {importer.path.name} is not read: kitkb's model stands in for NIST's 2012 model "
                f"(the import of <{iri}> is read as kitkb's kitting.ttl, the 2012 terms mapped onto it); name "
                f"{name} on the command line to check it as a model file", rule=MODEL_STAND_IN, focus=str(found))
            importer.warnings.append(note)
            for notes in _notes:
                if not any(n.rule == note.rule and n.focus == note.focus for n in notes):
                    notes.append(note)


def _union(sources: list[Source]) -> Graph:
    if len(sources) == 1:
        return sources[0].graph
    return new_graph(t for source in sources for t in source.triples())


def resolve_import(iri: str, importer: Source, named: Sequence[Source]) -> Path | None:
    """The file an ``owl:imports`` IRI stands for (rules in the module docstring), or None."""
    table = catalog()
    bare = iri.rstrip("#/")
    if bare in table:
        return table[bare]
    for source in named:
        if source.ontology_iri and source.ontology_iri.rstrip("#/") == bare:
            return source.path
    name = _file_name(bare)
    if name in _NIST_MODEL_FILES:
        return table[ns.KITTING_ONTOLOGY]
    if not name:
        return None
    for source in named:
        if source.path.name == name:
            return source.path
    listing = protege_catalog(importer.path.parent)
    listed = listing.get(iri) or listing.get(bare)
    if listed is not None:
        return listed
    sibling = importer.path.parent / name
    return sibling if sibling.is_file() else None


def protege_catalog(folder: Path) -> dict[str, Path]:
    """IRI -> file of the Protégé catalog (``catalog-v001.xml``, OASIS XML catalog ``uri``
    entries) in ``folder``; only files in that folder or below (nothing is fetched, no path
    leads out). Empty when there is no catalog or it cannot be read."""
    path = folder / PROTEGE_CATALOG
    try:
        text = path.read_text("utf-8")
        check_xml(text, path)
        root = ElementTree.fromstring(text)
    except (OSError, UnicodeDecodeError, InputError, ElementTree.ParseError):
        return {}
    top = folder.resolve()
    out: dict[str, Path] = {}
    for element in root.iter():
        if element.tag.rsplit("}", 1)[-1] != "uri" or not element.get("name") or not element.get("uri"):
            continue
        target = unquote(urlsplit(element.get("uri", "")).path) if element.get("uri", "").startswith("file:") \
            else unquote(element.get("uri", ""))
        found = (folder / target).resolve()
        if (found == top or top in found.parents) and found.is_file():
            out.setdefault(element.get("name", ""), found)
    return out


def _file_name(iri: str) -> str:
    """Last path segment of an IRI (no folders, no traversal), '' if there is none."""
    path = unquote(urlsplit(iri).path)
    name = path.rsplit("/", 1)[-1]
    return "" if name in ("", ".", "..") or "\\" in name else name


def _unresolved(iri: str, importer: Source, extra: str = "") -> Diagnostic:
    line = importer.line_of(URIRef(importer.ontology_iri), OWL.imports, URIRef(iri)) if importer.ontology_iri else None
    if line is None:
        line = _import_line(importer, iri)
    name = _file_name(iri.rstrip("#/"))
    where = f" (no {name} beside {importer.path.name}, in a {PROTEGE_CATALOG} there, or on the command line)" \
        if name and not extra else ""
    return Diagnostic(str(importer.path), line, "warning", f"import <{iri}> not resolved{extra}{where}; "
                      "only shipped ontologies and files named on the command line or found beside the "
                      "importing file are used", rule="unresolved-import", focus=iri)


def _import_line(importer: Source, iri: str) -> int | None:
    """The line of the import of ``iri`` found in the importing file's text."""
    text = importer.text()
    if not text:
        return None
    at = text.find(iri)
    return text.count("\n", 0, at) + 1 if at >= 0 else None
