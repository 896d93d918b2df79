"""Run a compiled shapes program over a data index."""

from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import dataclass, field

from rdflib import Graph, URIRef
from rdflib.term import Node

from kb.shacl.constraints import Hit
from kb.shacl.fallback import run_pyshacl
from kb.shacl.index import DataIndex
from kb.shacl.model import SH, ShaclResult
from kb.shacl.shapes import Program, Shape, compile_program
from kb.shacl.sparql import SparqlC, SparqlRunner
from kb.shacl.terms import to_node

STANDARD_PREFIXES = {
    "rdf": "http://www.w3.org/1999/02/22-rdf-syntax-ns#",
    "rdfs": "http://www.w3.org/2000/01/rdf-schema#",
    "xsd": "http://www.w3.org/2001/XMLSchema#",
    "owl": "http://www.w3.org/2002/07/owl#",
    "sh": "http://www.w3.org/ns/shacl#",
}
_PREFIX_NAME = re.compile(r"(?:[A-Za-z][\w\-.]*[\w\-])?|[A-Za-z]")


@dataclass
class Context:
    """What constraints need while they run: the index and the SPARQL runner."""

    index: DataIndex
    rdf11_strings: bool
    sparql: SparqlRunner = field(init=False)


@dataclass
class Run:
    """Results of one validation, and which shapes went to pySHACL (with the reasons)."""

    results: list[ShaclResult]
    fallback: dict[Node, str]


def prefixes_of(*graphs: Graph | None) -> dict[str, str]:
    """Standard prefixes plus those bound in the graphs (what rdflib queries see by default)."""
    found = dict(STANDARD_PREFIXES)
    for g in graphs:
        if g is None:
            continue
        for p, ns in g.namespaces():
            if _PREFIX_NAME.fullmatch(p) and ">" not in ns:
                found[p] = str(ns)
    return found


def focus_nodes(index: DataIndex, targets: dict[URIRef, list[str]]) -> set[str]:
    """Focus nodes of a shape from its target declarations (pySHACL's rules)."""
    foci: set[str] = set(targets.get(SH.targetNode, ()))
    for cls in targets.get(SH.targetClass, ()):
        foci |= index.instances(cls)
    for p in targets.get(SH.targetSubjectsOf, ()):
        foci.update(index.subjects_with(p))
    for p in targets.get(SH.targetObjectsOf, ()):
        foci |= index.objects_of(p)
    return foci


def evaluate(
    index: DataIndex, program: Program, *, rdf11_strings: bool, sparql: str = "oxigraph"
) -> list[ShaclResult]:
    """Validate ``index`` with the supported shapes of ``program``."""
    ctx = Context(index, rdf11_strings)
    ctx.sparql = SparqlRunner(ctx, program.sparql_constraints(), sparql)  # type: ignore[arg-type]
    inverse = {s.path[1] for s in program.shapes.values() if s.path and s.path[0] == "inv"}
    for _, targets in program.top:
        inverse.update(targets.get(SH.targetObjectsOf, ()))
    index.prepare_inverse(inverse)
    active = [(shape, targets) for shape, targets in program.top if not shape.deactivated]
    # shapes reaching SPARQL constraints run last, while the SPARQL store loads in a
    # background thread; each shape's hits are kept apart and merged in the original
    # order, so the results are the same as in one sequential pass
    uses_sparql = [_reaches_sparql(shape) for shape, _ in active]
    if any(uses_sparql):
        ctx.sparql.prefetch()
    per_shape: list[list[Hit]] = [[] for _ in active]
    order = [i for i, u in enumerate(uses_sparql) if not u] + [i for i, u in enumerate(uses_sparql) if u]
    try:
        for i in order:
            shape, targets = active[i]
            shape.validate(ctx, focus_nodes(index, targets), per_shape[i])
    finally:
        ctx.sparql.join()
        # Context <-> SparqlRunner is a reference cycle: break it, so the index (millions
        # of objects) is freed by reference counting, not by a long cyclic collection
        ctx.sparql.ctx = None  # type: ignore[assignment]
    hits: list[Hit] = [h for found in per_shape for h in found]
    return [
        ShaclResult(
            to_node(f), path, to_node(v) if v is not None else None, src, comp, sev,
            msg if isinstance(msg, str) else msg.generic(v),
        )
        for f, path, v, src, comp, sev, msg in hits
    ]


def _reaches_sparql(shape: Shape) -> bool:
    """Does evaluating ``shape`` (with the shapes it refers to) run a SPARQL constraint?"""
    seen: set[int] = set()
    todo = [shape]
    while todo:
        s = todo.pop()
        if id(s) in seen:
            continue
        seen.add(id(s))
        for c in s.constraints:
            if isinstance(c, SparqlC):
                return True
            for attr in ("prop", "other"):
                ref = getattr(c, attr, None)
                if isinstance(ref, Shape):
                    todo.append(ref)
            todo.extend(m for m in getattr(c, "members", ()) if isinstance(m, Shape))
        todo.extend(r for r in s.refs if isinstance(r, Shape))
    return False


def run(
    index: DataIndex,
    shapes: Graph,
    *,
    rdf11_strings: bool,
    prefixes: dict[str, str],
    data_graph: Callable[[], Graph],
    ont: Graph | None = None,
    sparql: str = "oxigraph",
) -> Run:
    """Compile ``shapes``, evaluate the supported ones, send the rest to pySHACL."""
    program = compile_program(shapes, rdf11_strings=rdf11_strings, prefixes=prefixes)
    results = evaluate(index, program, rdf11_strings=rdf11_strings, sparql=sparql)
    if program.unsupported:
        results += run_pyshacl(data_graph(), shapes, ont, program.unsupported)
    return Run(results, dict(program.unsupported))
