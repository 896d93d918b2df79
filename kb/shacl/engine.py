"""Run a compiled shapes program over a data index."""

from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import dataclass

from rdflib import Graph, URIRef
from rdflib.term import Node

from kb.core.namespaces import SH
from kb.shacl import parallel as par
from kb.shacl.compiler import Program, compile_program
from kb.shacl.fallback import run_pyshacl
from kb.shacl.index import DataIndex
from kb.shacl.result import ShaclResult
from kb.shacl.shape import Context, Hit, Shape
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
    index: DataIndex, program: Program, *, rdf11_strings: bool, sparql: str = "oxigraph",
    parallel: bool | None = None,
) -> list[ShaclResult]:
    """Validate ``index`` with the supported shapes of ``program``.

    ``parallel``: share the work with a forked child process (:mod:`kb.shacl.parallel`);
    None decides by the size of the index and the machine.
    """
    return Evaluation(index, program, rdf11_strings=rdf11_strings, sparql=sparql, parallel=parallel).finish()


class Evaluation:
    """One validation of ``index``, started at construction and collected by :meth:`finish`.

    With a forked child (see :mod:`kb.shacl.parallel`) the child is already at work when the
    constructor returns, so the caller can do something else before :meth:`finish`, which
    evaluates the parent's share of the shapes and merges the results in program order.
    """

    def __init__(self, index: DataIndex, program: Program, *, rdf11_strings: bool, sparql: str = "oxigraph",
                 parallel: bool | None = None, share: float | None = None) -> None:
        ctx = self.ctx = Context(index, rdf11_strings)
        ctx.sparql = SparqlRunner(ctx, program.sparql_constraints(), sparql)  # type: ignore[arg-type]
        inverse = {s.path[1] for s in program.shapes.values() if s.path and s.path[0] == "inv"}
        for _, targets in program.top:
            inverse.update(targets.get(SH.targetObjectsOf, ()))
        index.prepare_inverse(inverse)
        self.index = index
        self.active = [(shape, targets) for shape, targets in program.top if not shape.deactivated]
        self.uses_sparql = [_reaches_sparql(shape) for shape, _ in self.active]
        n = len(self.active)
        fork = par.can_fork(index.triples) if parallel is None else (parallel and par.can_fork(0, min_triples=0))
        child: set[int] = set()
        if fork and n > 1:
            self.foci = [focus_nodes(index, targets) for _, targets in self.active]
            costs = [len(f) * max(1, par.shape_weight(shape)) for f, (shape, _) in zip(self.foci, self.active)]
            child = par.plan(costs, self.uses_sparql, par.CHILD_SHARE if share is None else share)
            if len(child) == n:  # the parent keeps something to do
                child.discard(max(child, key=lambda i: (not self.uses_sparql[i], costs[i])))
        else:
            self.foci = None
        self.split = par.Split(n, self._run, child)
        self.split.start()

    def _run(self, which: list[int]) -> dict[int, list[Hit]]:
        """Evaluate the shapes ``which``: plain shapes first, then those reaching SPARQL
        constraints, while the SPARQL store loads in a background thread."""
        ctx, index = self.ctx, self.index
        plain = [i for i in which if not self.uses_sparql[i]]
        late = [i for i in which if self.uses_sparql[i]]
        if late:
            ctx.sparql.prefetch()
        out: dict[int, list[Hit]] = {}
        try:
            for i in plain + late:
                shape, targets = self.active[i]
                foci = self.foci[i] if self.foci is not None else focus_nodes(index, targets)
                shape.validate(ctx, foci, out.setdefault(i, []))
        finally:
            ctx.sparql.join()
        return out

    def finish(self, meanwhile: Callable[[], None] | None = None) -> list[ShaclResult]:
        """All results, in the order of one sequential pass over the program's shapes
        (``meanwhile``: see :meth:`kb.shacl.parallel.Split.finish`)."""
        try:
            per_shape = self.split.finish(meanwhile)
        finally:
            # Context <-> SparqlRunner is a reference cycle: break it, so the index (millions
            # of objects) is freed by reference counting, not by a long cyclic collection
            self.ctx.sparql.ctx = None  # type: ignore[assignment]
            self.foci = None
            self.split = None  # type: ignore[assignment]  # it refers back to self._run
        return [
            ShaclResult(to_node(f), path, to_node(v) if v is not None else None, src, comp, sev, msg)
            for found in per_shape for f, path, v, src, comp, sev, msg in found
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
