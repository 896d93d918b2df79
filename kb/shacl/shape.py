"""What the engine evaluates: shapes, constraints, results as tuples, and the context they run in.

One low module that the constraint components (:mod:`.constraints`), the SPARQL
constraints (:mod:`.sparql`), the compiler (:mod:`.compiler`) and the driver (:mod:`.engine`)
all build on, so that none of them imports another back (pySHACL keeps its run context low
in the same way). A result is the tuple ``(focus, path, value, source_shape, component,
severity, message)`` with focus and value as N-Triples keys; the engine turns it into a
:class:`~kb.shacl.result.ShaclResult`.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field
from typing import Any, Protocol

from rdflib import URIRef
from rdflib.term import Node

from kb.core.errors import InputError
from kb.core.namespaces import SH
from kb.shacl.index import DataIndex
from kb.shacl.paths import sparql, values

_EMPTY: dict[str, list[str]] = {}


class ShapeError(InputError):
    """A shape that cannot be evaluated as written: SPARQL the specification forbids, a query
    that does not parse, shapes pySHACL refuses. ``shape`` is the shape, ``node`` the node to
    point at (the shape or its sh:sparql constraint), ``what`` the problem; callers that know
    the shapes file turn it into ``file:line`` (:mod:`kb.validation.user_shapes`)."""

    def __init__(self, shape: Node | None, what: str, node: Node | None = None) -> None:
        self.shape = shape
        self.node = node if node is not None else shape
        self.what = what
        super().__init__(f"shape {_spell(shape)}: {what}" if shape is not None else what)


def _spell(node: Node) -> str:
    return f"<{node}>" if isinstance(node, URIRef) else f"[] ({node.n3()})"


class SparqlRows(Protocol):
    """Where SPARQL constraints get their rows (:class:`kb.shacl.sparql.SparqlRunner`)."""

    def rows(self, c: "Constraint", focus: str) -> list[dict[str, str]]: ...


@dataclass
class Context:
    """What constraints need while they run: the index and the SPARQL runner."""

    index: DataIndex
    rdf11_strings: bool
    sparql: SparqlRows = field(init=False)



Hit = tuple[str, Node | None, str | None, Node, URIRef, URIRef, "str | Constraint"]  # message or its maker
Pairs = list[tuple[str, list[str]]]


class Constraint:
    """Base: ``check`` appends the results for (focus, value nodes) pairs to ``out``."""

    component: URIRef
    #: The property shape of an sh:property constraint (validated with each value as focus).
    prop: Shape | None = None
    #: True for constraints that judge each value node on its own (:class:`PerValue`).
    per_value = False

    def __init__(self, shape: Shape) -> None:
        self.shape = shape

    def check(self, ctx: Context, pairs: Pairs, out: list[Hit]) -> None:
        raise NotImplementedError

    def generic(self, value: str | None) -> str:
        return f"{self.component.split('#')[-1]} failed"

    def hit(self, focus: str, value: str | None, path: Node | None = None, message: str | None = None) -> Hit:
        """A result tuple; the generic message is made later (``self`` stands in for it)."""
        s = self.shape
        return (
            focus,
            path if path is not None else s.path_node,
            value,
            s.node,
            self.component,
            s.severity,
            message or s.message or self,  # type: ignore[return-value]
        )


class PerValue(Constraint):
    """A constraint that judges each value node on its own (``ok(ctx, value)``)."""

    per_value = True

    def ok(self, ctx: Context, value: str) -> bool:
        raise NotImplementedError

    def check(self, ctx: Context, pairs: Pairs, out: list[Hit]) -> None:
        ok = self.ok
        for focus, values in pairs:
            for v in values:
                if not ok(ctx, v):
                    out.append(self.hit(focus, v))



@dataclass(eq=False)
class Shape:
    """A node or property shape with its compiled constraints."""

    node: Node
    path_node: Node | None = None
    #: ("pred" | "inv", predicate key), or ("path", a complex path of :mod:`kb.shacl.paths`)
    path: tuple[str, Any] | None = None
    severity: URIRef = SH.Violation
    message: str | None = None
    deactivated: bool = False
    constraints: list[Constraint] = field(default_factory=list)
    problems: list[str] = field(default_factory=list)
    refs: list["Shape"] = field(default_factory=list)

    @property
    def path_text(self) -> str:
        """The path for messages: the predicate's IRI, else the path in SPARQL's syntax."""
        if self.path is None or self.path_node is None:
            return "the node"
        kind, arg = self.path
        return str(self.path_node) if kind == "pred" else f"^{arg}" if kind == "inv" else sparql(arg)

    def pairs(self, ctx: Context, foci: Iterable[str], dicts: list[dict[str, list[str]]] | None = None) -> Pairs:
        """(focus, value nodes) for each focus node (``dicts``: the foci's spo entries, if known)."""
        if self.path is None:
            return [(f, (f,)) for f in foci]  # type: ignore[misc]
        kind, pred = self.path
        if kind == "path":  # a complex path, followed node by node
            index = ctx.index
            return [(f, values(index, pred, f)) for f in foci]  # type: ignore[arg-type]
        if kind == "pred":
            if dicts is not None:
                return [(f, d.get(pred, ())) for f, d in zip(foci, dicts)]  # type: ignore[misc]
            get = ctx.index.spo.get
            return [(f, (get(f) or _EMPTY).get(pred, ())) for f in foci]  # type: ignore[misc]
        inv = ctx.index.inverse(pred)
        return [(f, inv.get(f, ())) for f in foci]  # type: ignore[misc]

    def validate(
        self, ctx: Context, foci: Iterable[str], out: list[Hit], dicts: list[dict[str, list[str]]] | None = None
    ) -> None:
        """Append the results for the focus nodes ``foci`` (nothing when deactivated)."""
        if self.deactivated or not self.constraints:
            return
        if self.path is not None:
            pairs = self.pairs(ctx, foci, dicts)
            for c in self.constraints:
                c.check(ctx, pairs, out)
            return
        # a node shape: its property shapes share one lookup of each focus node's triples
        foci = foci if isinstance(foci, list) else list(foci)
        props = [c for c in self.constraints if c.prop is not None]
        others = [c for c in self.constraints if c.prop is None]
        if props:
            get = ctx.index.spo.get
            node_dicts = [get(f) or _EMPTY for f in foci]
            for pc in props:
                pc.prop.validate(ctx, foci, out, node_dicts)  # type: ignore[union-attr]
        if others:
            pairs = self.pairs(ctx, foci)
            for c in others:
                c.check(ctx, pairs, out)

    def failing(self, ctx: Context, nodes: list[str]) -> set[str]:
        """The nodes among ``nodes`` that do not conform to this shape (evaluated in bulk)."""
        if self.deactivated or not nodes:
            return set()
        if self.path is None and all(c.per_value for c in self.constraints):
            checks = [c.ok for c in self.constraints]  # type: ignore[attr-defined]  # no result tuples: just test each node
            return {n for n in nodes if not all(ok(ctx, n) for ok in checks)}
        if self._focus_preserving():
            out: list[Hit] = []
            self.validate(ctx, nodes, out)
            return {h[0] for h in out}
        return {n for n in nodes if not self.conforms(ctx, n)}

    def _focus_preserving(self) -> bool:
        """Do all results of this shape name the focus node they were produced for?

        True unless a property shape reached through sh:property has sh:property of its own
        (its results are about the values of the values)."""
        if self.path is not None:
            return all(c.prop is None for c in self.constraints)
        return all(c.prop._focus_preserving() for c in self.constraints if c.prop is not None)

    def conforms(self, ctx: Context, node: str) -> bool:
        """True when ``node`` as focus produces no result (used by sh:node, sh:or, ...)."""
        out: list[Hit] = []
        self.validate(ctx, (node,), out)
        return not out
