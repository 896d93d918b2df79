"""SHACL property paths (SHACL 2.3.1): read from the shapes graph, followed over the data index.

A path is a tuple: ``("pred", key)``, ``("inv", path)``, ``("seq", (paths...))``,
``("alt", (paths...))``, ``("star", path)`` (sh:zeroOrMorePath), ``("plus", path)``
(sh:oneOrMorePath) or ``("opt", path)`` (sh:zeroOrOnePath). :func:`values` gives the value
nodes of a focus node (each once, in the order found), :func:`sparql` the same path in SPARQL's
syntax (for ``$PATH`` in SPARQL constraints).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from rdflib import RDF, BNode, Graph, URIRef
from rdflib.collection import Collection
from rdflib.term import Node

from kb.core.namespaces import SH
from kb.shacl.index import DataIndex

Path = tuple[Any, ...]

_UNARY = {SH.inversePath: "inv", SH.zeroOrMorePath: "star", SH.oneOrMorePath: "plus", SH.zeroOrOnePath: "opt"}


def read(g: Graph, node: Node, key: Callable[[Node], str], depth: int = 0) -> Path | None:
    """The path described at ``node`` of ``g`` (None when it is not a well-formed SHACL path)."""
    if isinstance(node, URIRef):
        return ("pred", key(node))
    if not isinstance(node, BNode) or depth > 50:
        return None
    preds = set(g.predicates(node))
    if RDF.first in preds:
        return _list_path("seq", g, node, key, depth)
    if len(preds) != 1:
        return None
    (pred,) = preds
    objs = list(g.objects(node, pred))
    if len(objs) != 1:
        return None
    if pred == SH.alternativePath:
        return _list_path("alt", g, objs[0], key, depth)
    kind = _UNARY.get(pred)  # type: ignore[call-overload]
    inner = read(g, objs[0], key, depth + 1) if kind else None
    return (kind, inner) if inner is not None else None


def _list_path(kind: str, g: Graph, head: Node, key: Callable[[Node], str], depth: int) -> Path | None:
    """A sequence or alternative path of the paths listed at ``head`` (two at least)."""
    try:
        members = list(Collection(g, head))
    except Exception:  # a malformed list
        return None
    steps = [read(g, m, key, depth + 1) for m in members]
    if len(steps) < 2 or any(s is None for s in steps):
        return None
    return (kind, tuple(steps))


def values(index: DataIndex, path: Path, node: str) -> list[str]:
    """The nodes reached from ``node`` by ``path`` (each once)."""
    return list(_follow(index, path, [node], forward=True))


def _follow(index: DataIndex, path: Path, nodes: list[str], forward: bool) -> dict[str, None]:
    kind, arg = path
    out: dict[str, None] = {}
    if kind == "pred":
        for n in nodes:
            out.update(dict.fromkeys(index.objects(n, arg) if forward else index.subjects(arg, n)))
    elif kind == "inv":
        out = _follow(index, arg, nodes, not forward)
    elif kind == "seq":
        current = dict.fromkeys(nodes)
        for step in (arg if forward else reversed(arg)):
            current = _follow(index, step, list(current), forward)
        out = current
    elif kind == "alt":
        for step in arg:
            out.update(_follow(index, step, nodes, forward))
    elif kind == "opt":
        out = dict.fromkeys(nodes)
        out.update(_follow(index, arg, nodes, forward))
    else:  # star, plus: the closure
        seen: dict[str, None] = dict.fromkeys(nodes) if kind == "star" else {}
        frontier = list(nodes)
        while frontier:
            found = [n for n in _follow(index, arg, frontier, forward) if n not in seen]
            seen.update(dict.fromkeys(found))
            frontier = found
        out = seen
    return out


def sparql(path: Path) -> str:
    """``path`` in SPARQL's property path syntax (keys are ``<iri>`` already)."""
    kind, arg = path
    if kind == "pred":
        return arg
    if kind == "seq":
        return "(" + "/".join(sparql(p) for p in arg) + ")"
    if kind == "alt":
        return "(" + "|".join(sparql(p) for p in arg) + ")"
    if kind == "inv":
        return f"^({sparql(arg)})"
    return f"({sparql(arg)}){_MODIFIERS[kind]}"


_MODIFIERS = {"star": "*", "plus": "+", "opt": "?"}
