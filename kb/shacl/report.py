"""The W3C validation report (``sh:ValidationReport``) of a list of results.

SHACL's own output: ``sh:conforms`` (true exactly when there is no result, whatever its
severity) and one ``sh:result`` per result with its focus node, path, value, source shape,
constraint component, severity and message. A blank-node path or source shape is described
in the report as in the shapes graph (its triples copied), so a complex ``sh:resultPath``
reads as the path it is.
"""

from __future__ import annotations

from collections.abc import Iterable

from rdflib import RDF, XSD, BNode, Graph, Literal
from rdflib.term import Node

from kb.core.namespaces import SH
from kb.shacl.result import ShaclResult

#: Most triples copied from the shapes graph for one blank node (a path, an inline shape).
COPY_LIMIT = 10_000


def conforms(results: Iterable[ShaclResult]) -> bool:
    """SHACL's ``sh:conforms``: no result at all (a warning is a result too)."""
    return not any(True for _ in results)


def report_graph(results: list[ShaclResult], shapes: Graph | None = None) -> Graph:
    """``results`` as a W3C ``sh:ValidationReport`` graph (blank nodes of ``shapes`` that
    results name are copied with their description)."""
    g = Graph()
    g.bind("sh", str(SH))
    if shapes is not None:
        for prefix, ns in shapes.namespaces():
            if prefix and prefix != "sh":
                g.bind(prefix, ns, override=False)
    report = BNode("report")
    g.add((report, RDF.type, SH.ValidationReport))
    g.add((report, SH.conforms, Literal(conforms(results), datatype=XSD.boolean)))
    copies: dict[Node, BNode] = {}  # shapes-graph blank node -> its copy (stable labels)
    width = len(str(len(results)))
    for i, r in enumerate(results, 1):
        node = BNode(f"result{i:0{width}d}")
        g.add((report, SH.result, node))
        g.add((node, RDF.type, SH.ValidationResult))
        g.add((node, SH.focusNode, r.focus))
        g.add((node, SH.resultSeverity, r.severity))
        g.add((node, SH.sourceConstraintComponent, r.component))
        g.add((node, SH.sourceShape, _copied(shapes, r.source_shape, g, copies)))
        if r.path is not None:
            g.add((node, SH.resultPath, _copied(shapes, r.path, g, copies)))
        if r.value is not None:
            g.add((node, SH.value, r.value))
        if r.message:
            g.add((node, SH.resultMessage, Literal(r.message)))
    return g


def _copied(source: Graph | None, term: Node, into: Graph, copies: dict[Node, BNode]) -> Node:
    """``term``, or for a blank node of ``source`` its copy in ``into``: the triples of the
    blank nodes it reaches, copied once, labelled ``s1``, ``s2``, ... in order of copying."""
    if source is None or not isinstance(term, BNode):
        return term
    if term in copies:
        return copies[term]

    def copy_of(node: BNode) -> BNode:
        if node not in copies:
            copies[node] = BNode(f"s{len(copies) + 1}")
            todo.append(node)
        return copies[node]

    todo: list[BNode] = []
    top = copy_of(term)
    n = 0
    while todo and n < COPY_LIMIT:
        node = todo.pop(0)
        for p, o in sorted(source.predicate_objects(node), key=lambda po: (str(po[0]), str(po[1]))):
            into.add((copies[node], p, copy_of(o) if isinstance(o, BNode) else o))
            n += 1
    return top
