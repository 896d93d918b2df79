"""From SHACL results and rule findings to the report: messages, lines, compact names.

:func:`diagnostics` turns the results of one SHACL run over one file into
:class:`kb.core.diagnostics.Diagnostic` objects (rule names, messages that name the offending
node, source lines), dropping results that repeat or only follow from another finding;
:func:`dedupe` makes the report one line per problem; :class:`Namer` spells terms the way
the file does (``:part_a_1``, ``ktw:Point``).
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any, Iterable

from rdflib import OWL, RDF, RDFS, XSD, Graph, Literal, URIRef
from rdflib.collection import Collection
from rdflib.term import Node

from kb.core.diagnostics import Diagnostic
from kb.core.namespaces import KTW, NAMESPACE_MAP, PREFIXES, SH, local_name
from kb.model.owl import is_w3c
from kb.shacl import ShaclResult
from kb.validation import rules
from kb.validation.shapes import EXPECTS, READ_AS, SHAPES_NS
from kb.validation.suggest import closest, resembles

RULE = URIRef(SHAPES_NS + "rule")


_COMPONENT_RULES = {
    "MinCount": "min-count", "QualifiedMinCount": "min-count", "MaxCount": "max-count",
    "QualifiedMaxCount": "max-count", "Datatype": "datatype", "In": "enumeration", "Class": "class",
    "NodeKind": "node-kind", "Closed": "closed", "Not": "disjoint-classes", "MinExclusive": "value-range",
    "MinInclusive": "value-range", "MaxExclusive": "value-range", "MaxInclusive": "value-range",
    "Pattern": "pattern", "SPARQL": "sparql", "Or": "datatype",
}


def diagnostics(results: Iterable[ShaclResult], src: Any, data: Graph, shapes: Graph,
                 namer: "Namer", ctx: rules.RuleContext, user: Graph | None = None) -> list[Diagnostic]:
    """The report lines of the SHACL ``results`` for ``src`` (``data``: what was validated;
    ``user``: the users' shapes, whose results say the shape's own sh:message)."""
    out = []
    kept = _one_closed_result_each(results, data, shapes)
    named = [(r, _rule(r, shapes)) for r in kept]
    # a value of the wrong type (or ill-formed) is not also out of range: one finding
    mistyped = {(r.focus, r.path, r.value) for r, rule in named if rule == "datatype"}
    for r, rule in named:
        if rule == "value-range" and (r.focus, r.path, r.value) in mistyped:
            continue
        if _suppressed(rule, r, ctx, namer, src, data) or not _mentions(rules.graph_of(src), r.focus):
            continue
        if user is not None and (r.source_shape, None, None) in user:
            message = _user_message(r, src, shapes, namer)
        else:
            message = _message(rule, r, src, data, shapes, namer)
        severity = "warning" if r.severity in (SH.Warning, SH.Info) else "error"
        out.append(Diagnostic(str(src.path), _result_line(rule, r, src, data), severity,  # type: ignore[arg-type]
                              message, rule, namer.name(r.focus, src)))
    return out


def _rule(r: ShaclResult, shapes: Graph) -> str:
    """The rule name of a result: the shape's ``kitkbsh:rule``, else after its component."""
    comp = str(r.component).rpartition("#")[2].removesuffix("ConstraintComponent")
    rule = str(shapes.value(r.source_shape, RULE) or _COMPONENT_RULES.get(comp, comp.lower()))
    if comp == "Or" and _or_has_class(shapes, r.source_shape):
        rule = "class"
    if isinstance(r.path, Node) and shapes.value(r.path, SH.inversePath) is not None:
        rule = "inverse-functional"
    return rule


def _one_closed_result_each(results: Iterable[ShaclResult], data: Graph, shapes: Graph) -> list[ShaclResult]:
    """Keep one sh:closed result per (focus, path, value): the shape of an asserted class if any.

    An individual of a subclass is a focus of each superclass's shape, so a stray property is
    reported by several of them; the report names the individual's own class.
    """
    out: list[ShaclResult] = []
    closed: dict[tuple, ShaclResult] = {}
    for r in results:
        if not str(r.component).endswith("ClosedConstraintComponent"):
            out.append(r)
            continue
        key = (r.focus, r.path, r.value)
        asserted = shapes.value(r.source_shape, SH.targetClass) in set(data.objects(r.focus, RDF.type))
        if key not in closed or asserted:
            closed[key] = r
    return out + list(closed.values())


def _mentions(g: Any, node: Node) -> bool:
    """True when ``node`` occurs in ``g`` (results about other files' nodes belong there)."""
    return (node, None, None) in g or (None, None, node) in g


def _or_has_class(shapes: Graph, shape: Node) -> bool:
    """True when the shape's sh:or alternatives are sh:class constraints (an object range)."""
    for head in shapes.objects(shape, SH["or"]):
        if any(shapes.value(alt, SH["class"]) is not None for alt in Collection(shapes, head)):
            return True
    return False


def _suppressed(rule: str, r: ShaclResult, ctx: rules.RuleContext, namer: "Namer", src: Any,
                data: Graph) -> bool:
    """Drop a SHACL result that only repeats or follows from a Python rule's finding.

    A stray property is already an ``unknown-property``; a reference to an unknown individual
    or to one typed with an unknown class is already reported; a required property that is
    missing because it is misspelt (``hasPoint_x`` for ``hasPoint_X``), or stated on a misspelt
    subject (``:PartGipperPose`` for ``:PartGripperPose``, an ``unknown-individual``), is the
    typo's report.
    """
    known = ctx.model.properties.keys() | ctx.model.annotation_properties
    if rule == "min-count" and r.path == KTW.hasSolidObject_PrimaryLocation and r.focus in ctx.unlocated:
        return True  # an object to be sensed: its note says so (location-unknown)
    if rule == "closed" and isinstance(r.path, URIRef):
        return r.path not in known
    if rule == "class" and isinstance(r.value, URIRef):
        types = {t for _, t in _types_of(data, r.value)}
        return r.value not in ctx.individuals or any(t not in ctx.model.classes for t in types)
    if rule == "min-count" and isinstance(r.path, URIRef):
        stray = [p for p in set(data.predicates(r.focus, None)) if not is_w3c(p) and p not in known]
        want = namer.name(r.path, src)
        if any(resembles(namer.name(p, src), want) for p in stray):
            return True
        f = namer.name(r.focus, src)
        return any(r.path in told and closest(namer.name(u, src), [f]) == f for u, told in ctx.untyped.items())
    return False


def _types_of(data: Graph, node: Node) -> list[tuple[Node, URIRef]]:
    return [(node, t) for t in data.objects(node, RDF.type)
            if isinstance(t, URIRef) and t not in rules.META_TYPES and not is_w3c(t)]


def _message(rule: str, r: ShaclResult, src: Any, data: Graph, shapes: Graph, namer: "Namer") -> str:
    f = namer.name(r.focus, src)
    # the property as the file writes it, where the result is about a statement of the file
    at = (r.focus, r.path, r.value) if rule != "min-count" else None
    p = namer.name(r.path, src, at=at) if isinstance(r.path, URIRef) else ""
    v = namer.name(r.value, src, typed=rule == "datatype") if r.value is not None else ""
    expects = _expects(shapes, r.source_shape, namer, src)
    if rule == "min-count":
        n = shapes.value(r.source_shape, SH.minCount) or shapes.value(r.source_shape, SH.qualifiedMinCount)
        want = f" ({expects})" if expects else ""
        return f"{f} lacks {p}: at least {n or 1} value(s) required{want}"
    if rule == "max-count":
        n = shapes.value(r.source_shape, SH.maxCount) or shapes.value(r.source_shape, SH.qualifiedMaxCount)
        k = len(set(data.objects(r.focus, r.path))) if isinstance(r.path, URIRef) else "too many"
        return f"{f} has {k} values of {p}, at most {n} allowed"
    if rule == "inverse-functional":
        inv = shapes.value(r.path, SH.inversePath)
        subjects = sorted(data.subjects(inv, r.focus), key=str)
        owners = sorted(namer.name(s, src) for s in subjects)
        name = namer.name(inv, src, at=(subjects[0], inv, r.focus) if subjects else None)
        return f"{f} is the {name} of more than one individual ({', '.join(owners)})"
    if rule == "value-range":
        return f"{p} of {f} is {v}, out of range: expected {expects or _bound(r, shapes)}"
    if rule in ("datatype", "enumeration", "class", "node-kind", "pattern"):
        extra = ""
        if rule == "class" and isinstance(r.value, URIRef):
            types = sorted(namer.name(t, src) for t in data.objects(r.value, RDF.type)
                           if not is_w3c(t))
            extra = f" (it is {', '.join(types)})" if types else ""
        return f"{p} of {f} is {v}{extra}, expected {expects or rule}"
    if rule == "closed":
        cls = namer.name(shapes.value(r.source_shape, SH.targetClass), src)
        return f"{f} may not have {p}: not a property of {cls} (nor of its superclasses or subclasses)"
    if rule == "disjoint-classes":
        types = sorted(namer.name(t, src) for t in data.objects(r.focus, RDF.type) if not is_w3c(t))
        return f"{f} is typed with disjoint classes ({', '.join(types)})"
    template = _sparql_message(shapes, r.source_shape)
    if template:
        return template.replace("{$this}", f).replace("{?this}", f).replace("{?value}", v) \
            .replace("{$value}", v)
    return f"{f}: {r.message}"


def _expects(shapes: Graph, shape: Node, namer: "Namer", src: Any) -> str:
    """What a generated property shape wants, in words (``kitkbsh:expects``), led by the name of
    the model's datatype where it is one read as an XSD type (``ktw:positiveDecimal, an
    xsd:decimal > 0``), spelt with the file's prefixes: the classes of an object range too
    (``an individual of :RollPitchYaw``, never a prefix the shapes generator made up)."""
    words = str(shapes.value(shape, EXPECTS) or "")
    classes = _classes_of(shapes, shape)
    if classes and (not words or words.startswith("an individual of ")):
        return "an individual of " + " or ".join(namer.name(c, src) for c in classes)
    defined = [d for d in _datatypes_of(shapes, shape) if (d, READ_AS, None) in shapes]
    if words and defined:
        names = " or ".join(namer.name(d, src) for d in defined)
        return f"{names}, an {words}" if words.startswith("xsd:") else f"{names}, {words}"
    return words


def _datatypes_of(shapes: Graph, shape: Node) -> list[Node]:
    """The sh:datatype values of a shape, directly or as sh:or alternatives."""
    found = list(shapes.objects(shape, SH.datatype))
    for head in shapes.objects(shape, SH["or"]):
        found += [d for alt in Collection(shapes, head) for d in shapes.objects(alt, SH.datatype)]
    return found


def _bound(r: ShaclResult, shapes: Graph) -> str:
    """The bound a value-range result broke, in words (``> 0``)."""
    comp = str(r.component).rpartition("#")[2].removesuffix("ConstraintComponent")
    facet = comp[0].lower() + comp[1:]
    words = {"minExclusive": ">", "minInclusive": ">=", "maxExclusive": "<", "maxInclusive": "<="}
    return f"{words.get(facet, facet)} {shapes.value(r.source_shape, SH[facet])}"


def _user_message(r: ShaclResult, src: Any, shapes: Graph, namer: "Namer") -> str:
    """The line of a result of a user's shape: the focus node, then the shape's sh:message
    (the engine has filled its ``{$this}``, ``{?value}`` ...) or else the component's own
    message with the path and value."""
    f = namer.name(r.focus, src)
    if shapes.value(r.source_shape, SH.message) is not None or _sparql_message(shapes, r.source_shape):
        return f"{f}: {r.message}"
    p = f" {namer.name(r.path, src)}" if isinstance(r.path, URIRef) else ""
    v = f" = {namer.name(r.value, src)}" if r.value is not None and r.value != r.focus else ""
    return f"{f}{p}{v}: {r.message}"


def _classes_of(shapes: Graph, shape: Node) -> list[Node]:
    """The sh:class values of a shape, directly or as sh:or alternatives."""
    found = list(shapes.objects(shape, SH["class"]))
    for head in shapes.objects(shape, SH["or"]):
        found += [c for alt in Collection(shapes, head) for c in shapes.objects(alt, SH["class"])]
    return found


def _sparql_message(shapes: Graph, shape: Node) -> str:
    for c in shapes.objects(shape, SH.sparql):
        msg = shapes.value(c, SH.message)
        if msg is not None:
            return str(msg)
    msg = shapes.value(shape, SH.message)
    return str(msg) if msg is not None else ""


def _result_line(rule: str, r: ShaclResult, src: Any, data: Graph) -> int | None:
    if rule == "inverse-functional":
        lines = [line_of(src, s, None, None) for s in data.subjects(None, r.focus)]
        found = [n for n in lines if n]
        return max(found) if found else line_of(src, r.focus, None, None)
    if rule == "max-count" and isinstance(r.path, URIRef):  # point at the last (extra) value
        found = [n for o in data.objects(r.focus, r.path) if (n := line_of(src, r.focus, r.path, o))]
        if found:
            return max(found)
    if rule not in ("min-count", "disjoint-classes") and not isinstance(r.path, URIRef) \
            and r.value is not None and r.value != r.focus:
        # a rule without a path (SPARQL): the statement of the focus that carries the value
        # (a vessel's part quantity, the part it lists), where there is one
        line = _carrying_line(r.focus, r.value, src)
        if line is not None:
            return line
    if rule in ("min-count", "disjoint-classes") or not isinstance(r.path, URIRef):
        return line_of(src, r.focus, RDF.type, None) or line_of(src, r.focus, None, None)
    return line_of(src, r.focus, r.path, r.value) or line_of(src, r.focus, r.path, None) \
        or line_of(src, r.focus, None, None)


def _carrying_line(focus: Node, value: Node, src: Any) -> int | None:
    """The line of the statement of ``src`` about ``focus`` whose object is ``value`` (the
    earliest), or whose object is a literal of the same value when one statement has one (a
    query's result may give ``"12"^^xsd:integer`` for the file's ``"12"^^xsd:nonNegativeInteger``);
    None when there is none."""
    g = rules.graph_of(src)
    found = [n for q in set(g.predicates(focus, value)) if (n := line_of(src, focus, q, value))]
    if not found and isinstance(value, Literal):
        same = [(q, o) for q, o in g.predicate_objects(focus) if isinstance(o, Literal) and _same_value(o, value)]
        if len(same) == 1:
            found = [n for n in [line_of(src, focus, *same[0])] if n]
    return min(found) if found else None


def _same_value(a: Literal, b: Literal) -> bool:
    try:
        return bool(a.eq(b))
    except (TypeError, ValueError):
        return False


def line_of(src: Any, s: Node, p: Node | None, o: Node | None) -> int | None:
    try:
        return src.line_of(s, p, o)
    except Exception:  # a loader that cannot place a node: file only
        return None


def dedupe(diags: list[Diagnostic]) -> list[Diagnostic]:
    """One line per problem: the same rule, focus and message once; sorted by file and line."""
    seen: dict[tuple, Diagnostic] = {}
    for d in diags:
        key = (d.file, d.rule, d.focus, d.message)
        if key not in seen or (d.line or 0) < (seen[key].line or 0):
            seen[key] = d
    return sorted(seen.values(), key=lambda d: (d.file, d.line or 0, d.severity, d.message))


# --- naming -----------------------------------------------------------------------------

_NUMERIC = {XSD.decimal, XSD.integer, XSD.double, XSD.float, XSD.nonNegativeInteger, XSD.positiveInteger,
            XSD.nonPositiveInteger, XSD.negativeInteger, XSD.long, XSD.int, XSD.short, XSD.byte}


#: Numbers whose type a Turtle reader sees without ``^^`` (``1``, ``1.5``).
_BARE = {XSD.decimal, XSD.integer}


class Namer:
    """Compact names, as the file writes them: the file's own prefixes first (``:part_a_1``),
    then kitkb's for kitkb's model (``ktw:Point``), else the full IRI (``<http://...>``),
    never a prefix the file does not declare.

    A term of NIST's 2012 namespace that kitkb reads as a term of its model is named as the
    file writes it: with the same local name, in the file's prefix (``:ShapeDesign``); renamed
    (``hasSku_Shape``, kitkb's ``hasStockKeepingUnit_InternalShape``), where the message is
    about a statement of the file that uses it (``at``), as written with kitkb's name after it
    (``:hasSku_Shape (kitkb's hasStockKeepingUnit_InternalShape)``)."""

    def __init__(self) -> None:
        self._cache: dict[str, list[tuple[str, str]]] = {}
        self._lines: dict[str, list[str]] = {}
        self._spaces = [(ns, p) for p, ns in sorted(PREFIXES.items(), key=lambda kv: -len(kv[1]))]
        self._spaces += [(str(RDF), "rdf"), (str(RDFS), "rdfs"), (str(OWL), "owl"),
                         ("http://www.w3.org/2001/XMLSchema#", "xsd")]

    def name(self, term: Node | None, src: Any = None, typed: bool = False, at: tuple | None = None) -> str:
        """``:local``, ``prefix:local``, a literal in Turtle, or ``<iri>`` (``typed``: a number
        with its datatype too, where it is not a decimal or an integer; ``at``: the statement
        (s, p, o) of ``src`` the term is written in, for a renamed 2012 term)."""
        if term is None:
            return ""
        if isinstance(term, Literal):
            bare = _BARE if typed else _NUMERIC
            if term.datatype in bare and term.value is not None:
                return str(term)
            if term.datatype is not None and term.datatype != XSD.string:
                return f'"{term}"^^{self.name(term.datatype, src)}'
            return f'"{term}"' + (f"@{term.language}" if term.language else "")
        if not isinstance(term, URIRef):
            return "[]"
        written = getattr(src, "written_as", None)
        if written and term in written:
            said = self._as_written(term, written[term], src, at)
            if said is not None:
                return said
        return self._plain(term, src)

    def _plain(self, term: URIRef, src: Any) -> str:
        text = str(term)
        for ns, prefix in self._file_spaces(src) + self._spaces:
            if text.startswith(ns) and len(text) > len(ns):
                return f"{prefix}:{text[len(ns):]}"
        return f"<{text}>"

    def _as_written(self, term: URIRef, originals: tuple[str, ...], src: Any, at: tuple | None) -> str | None:
        """The name of ``term`` as ``src`` writes it (``originals``: the IRIs it was read
        from), None when that cannot be told."""
        local = local_name(term)
        same = [o for o in originals if local_name(o) == local]
        if same:
            return self._plain(URIRef(same[0]), src)
        if at is None:
            return None
        pick = originals[0] if len(originals) == 1 else self._on_line(originals, src, at)
        return None if pick is None else f"{self._plain(URIRef(pick), src)} (kitkb's {local})"

    def _on_line(self, originals: tuple[str, ...], src: Any, at: tuple) -> str | None:
        """The one of ``originals`` written on the line of the statement ``at``."""
        line = line_of(src, *at)
        key = str(getattr(src, "path", ""))
        if line is None or not key:
            return None
        if key not in self._lines:
            text = src.text() if hasattr(src, "text") else None
            self._lines[key] = text.splitlines() if text else []
        lines = self._lines[key]
        if line > len(lines):
            return None
        hits = [o for o in originals
                if re.search(r"[:#]" + re.escape(local_name(o)) + r"(?![\w-])", lines[line - 1])]
        return hits[0] if len(hits) == 1 else None

    def _file_spaces(self, src: Any) -> list[tuple[str, str]]:
        if src is None or not hasattr(src, "path"):
            return []
        key = str(src.path)
        if key not in self._cache:
            self._cache[key] = _declared_prefixes(Path(key))
        return self._cache[key]


_PREFIX_PATTERNS = [re.compile(r"@prefix\s+([\w.-]*):\s*<([^>]*)>", re.I),
                    re.compile(r"PREFIX\s+([\w.-]*):\s*<([^>]*)>", re.I),
                    re.compile(r"Prefix\(\s*([\w.-]*):=\s*<([^>]*)>\s*\)"),
                    re.compile(r"xmlns(?::([\w.-]+))?\s*=\s*\"([^\"]*)\"")]


def _declared_prefixes(path: Path) -> list[tuple[str, str]]:
    """The prefixes a file declares (last one wins), namespaces mapped as the loader maps them."""
    try:
        with path.open("rb") as f:  # the head only: a data file can be hundreds of megabytes
            text = f.read(200_000).decode("utf-8", errors="replace")
    except OSError:
        return []
    found: dict[str, str] = {}
    for pattern in _PREFIX_PATTERNS:
        for m in pattern.finditer(text):
            prefix, ns = m.group(1) or "", m.group(2)
            if ns and ns[-1] in "#/" and not is_w3c(URIRef(ns + "x")):
                found[prefix] = NAMESPACE_MAP.get(ns, ns)
    by_ns: dict[str, str] = {}
    for prefix, ns in found.items():
        if by_ns.get(ns) != "":  # prefer the default prefix for a namespace
            by_ns[ns] = prefix
    return sorted(((ns, p) for ns, p in by_ns.items()), key=lambda sp: -len(sp[0]))
