"""Hand shapes the engine does not support to pySHACL, and read pySHACL's report graph.

pySHACL refuses some shapes graphs instead of validating (a ``ValidationFailure`` report, a
``ReportableRuntimeError``, ``NotImplementedError`` for ``$shapesGraph``): that becomes a
:class:`kb.shacl.shape.ShapeError` naming the shape handed over, never a report.

pySHACL 0.40 takes a node for a shape, a constraint component, a validator or a class only by
its ``rdf:type`` itself or one ``rdfs:subClassOf`` step, where SHACL says "SHACL instance"
(``rdf:type/rdfs:subClassOf*``): the shapes graph it is given has those types spelt out
(:func:`spelt_out`), so a component typed two steps down is not skipped there either."""

from __future__ import annotations

import dataclasses
import logging
import re
import warnings
from collections.abc import Iterable

from rdflib import RDF, RDFS, Graph, Literal, URIRef
from rdflib.term import Node

from kb.core.namespaces import SH
from kb.shacl.compiler import TARGET_PREDICATES, read_as, targeted_shapes
from kb.shacl.components import subclasses
from kb.shacl.result import ShaclResult
from kb.shacl.shape import ShapeError

log = logging.getLogger("kb.shacl")


def results_from_report(report: Graph) -> list[ShaclResult]:
    """The results (``sh:result``) of a pySHACL (or any SHACL) validation report graph."""
    out = []
    # top-level results only: pySHACL also types the nested sh:detail results of sh:node
    for r in report.objects(None, SH.result):
        msgs = sorted(str(m) for m in report.objects(r, SH.resultMessage))
        out.append(
            ShaclResult(
                focus=report.value(r, SH.focusNode),
                path=report.value(r, SH.resultPath),
                value=report.value(r, SH.value),
                source_shape=report.value(r, SH.sourceShape),
                component=report.value(r, SH.sourceConstraintComponent),
                severity=report.value(r, SH.resultSeverity),
                message=msgs[0] if msgs else "",
            )
        )
    return out


def run_pyshacl(data: Graph, shapes: Graph, ont: Graph | None, only: Iterable[Node]) -> list[ShaclResult]:
    """Validate with pySHACL, keeping the targets of the shapes in ``only`` and no others."""
    keep = set(only)
    shapes = spelt_out(shapes)
    implicit = targeted_shapes(shapes) - keep
    classes = subclasses(shapes, RDFS.Class)
    reduced = Graph()
    for prefix, ns in shapes.namespaces():
        reduced.bind(prefix, ns, override=True)
    for s, p, o in shapes:
        if p in TARGET_PREDICATES and s not in keep:
            continue
        if p == RDF.type and s in implicit and o in classes:
            continue  # an implicit class target of a shape we evaluate ourselves
        reduced.add((s, p, o))
    log.warning("pySHACL evaluates %d shape(s) the fast engine does not support: %s",
                len(keep), ", ".join(sorted(str(k) for k in keep)))
    return pyshacl_results(data, reduced, ont, sorted(keep, key=str), advanced=False)


def pyshacl_results(data: Graph, shapes: Graph, ont: Graph | None, shapes_named: list[Node],
                    *, advanced: bool) -> list[ShaclResult]:
    """``pyshacl.validate``'s results; :class:`ShapeError` (naming the first of
    ``shapes_named``) when pySHACL refuses the shapes instead of validating."""
    import pyshacl  # imported only when a shape needs it (0.2 s of start-up)
    from pyshacl.errors import ReportableRuntimeError

    shape = shapes_named[0] if shapes_named else None
    data, back = _read_as_base(data, shapes)
    shapes = spelt_out(shapes)
    from pyshacl.errors import ShapeRecursionWarning

    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", ShapeRecursionWarning)
            _, report, _ = pyshacl.validate(data, shacl_graph=shapes, ont_graph=ont, inference="none",
                                            advanced=advanced, allow_warnings=True)
    except (ReportableRuntimeError, NotImplementedError) as exc:
        raise ShapeError(shape, f"pySHACL, which evaluates it, cannot: {_text(exc)}") from None
    stopped = [w for w in caught if issubclass(w.category, ShapeRecursionWarning)]
    if stopped:
        # pySHACL backs out of a recursive shape when it meets it a third time down one path and
        # counts what it did not check as conforming (a chain of 20 nodes, the last without a
        # required value, conformed)
        raise ShapeError(_recursive(str(stopped[0].message), shapes_named) or shape,
                         "it is recursive and pySHACL, which evaluates it, stopped short of the data "
                         "(a few levels down): what lies deeper went unchecked; SHACL leaves recursive "
                         "shapes undefined")
    for w in caught:  # the other warnings, as pySHACL would have given them
        warnings.showwarning(w.message, w.category, w.filename, w.lineno)
    if not isinstance(report, Graph):  # pySHACL's ValidationFailure, returned instead of a report
        raise ShapeError(shape, f"pySHACL, which evaluates it, refuses it: {_text(report)}")
    results = results_from_report(report)
    if back:
        results = [dataclasses.replace(r, value=back.get(r.value, r.value)) if r.value in back else r
                   for r in results]
    return results


def spelt_out(shapes: Graph) -> Graph:
    """``shapes`` with ``x rdf:type C`` added wherever ``x`` is a SHACL instance of a class
    ``C`` of SHACL's vocabulary (or of rdfs:Class) only through ``rdfs:subClassOf`` steps;
    ``shapes`` itself when nothing is missing."""
    sh = str(SH)
    wanted: dict[Node, set[Node]] = {}  # a class -> the SHACL (or rdfs:Class) classes above it
    for c in {o for o in shapes.objects(None, RDFS.subClassOf) if str(o).startswith(sh) or o == RDFS.Class}:
        for sub in subclasses(shapes, c) - {c}:
            wanted.setdefault(sub, set()).add(c)
    extra = [(x, RDF.type, c) for sub, above in wanted.items() for x in shapes.subjects(RDF.type, sub)
             for c in above if (x, RDF.type, c) not in shapes]
    if not extra:
        return shapes
    out = Graph()
    for prefix, ns in shapes.namespaces():
        out.bind(prefix, ns, override=True)
    for t in shapes:
        out.add(t)
    for t in extra:
        out.add(t)
    return out


def _read_as_base(data: Graph, shapes: Graph) -> tuple[Graph, dict[Node, Node]]:
    """``data`` with the literals of the datatypes the shapes read as XSD ones
    (``kitkbsh:readAs``) typed with those (pySHACL knows nothing of the declaration), and the
    way back from each new literal to the one written; ``data`` itself when it has none."""
    aliases = read_as(shapes)
    if not aliases:
        return data, {}
    typed = {URIRef(d): URIRef(b) for d, b in aliases.items()}
    out = Graph()
    back: dict[Node, Node] = {}
    found = False
    for s, p, o in data:
        if isinstance(o, Literal) and o.datatype in typed:
            new = Literal(str(o), datatype=typed[o.datatype])
            back.setdefault(new, o)
            o, found = new, True
        out.add((s, p, o))
    return (out, back) if found else (data, {})


def _recursive(path: str, shapes_named: list[Node]) -> Node | None:
    """The first shape of pySHACL's evaluation path (``<NodeShape IRI>->...``) that kitkb
    handed over, else None."""
    names = {str(n): n for n in shapes_named}
    for m in re.finditer(r"<(?:Node|Property)Shape ([^>\s]+)>", path):
        if m.group(1) in names:
            return names[m.group(1)]
    return None


def _text(exc: object) -> str:
    """One line of a pySHACL error (its ``message``, without the spec link it appends)."""
    text = str(getattr(exc, "message", None) or exc).strip()
    return " ".join(text.split("For reference, see")[0].split())
