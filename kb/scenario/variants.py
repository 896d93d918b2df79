"""Variants of a state file: the same workstation written in another unit, or turned.

What the first paper's test methods vary between runs (the location and yaw of kit trays and
parts trays) and what other people's files differ in (millimetres, inches), made from any
state file kitkb reads (Turtle, OWL functional syntax, RDF/XML):

* :func:`rescale` rewrites every quantity in another unit of its kind — the values of the
  data properties the kitting model annotates with ``ktw:quantityKind`` — and the
  workstation's unit declaration: the same workstation, other numbers;
* :func:`turn` turns the whole workstation about the world's z axis (every location given in
  the workstation's frame), or named objects about their own z axis (their own pose
  location; what they hold follows, its poses being relative to them).

``kitkb scenario transform IN -o OUT --unit U --yaw DEG [--turn OBJ,...]`` is the command.
"""

from __future__ import annotations

import math
from decimal import Decimal
from pathlib import Path
from typing import Iterable

import numpy as np
from rdflib import BNode, Graph, Literal, URIRef
from rdflib.namespace import RDF, XSD

from kb.core.errors import InputError
from kb.core.files import command_scope, write_atomic
from kb.core.namespaces import KTW, local_name
from kb.core.units import KINDS
from kb.io import load_file
from kb.io.turtle import decimal, turtle
from kb.model.units import UNIT_PROPS, quantity_kinds, read_units

_POINT, _XAXIS, _ZAXIS = KTW.hasPoseLocation_Point, KTW.hasPoseLocation_XAxis, KTW.hasPoseLocation_ZAxis
_XYZ = (KTW.hasPoint_X, KTW.hasPoint_Y, KTW.hasPoint_Z)
_IJK = (KTW.hasVector_I, KTW.hasVector_J, KTW.hasVector_K)


def number(v: float) -> Literal:
    """``v`` as an ``xsd:decimal`` literal (12 decimals at most, as kitkb writes numbers); NaN
    and the infinities, which ``xsd:decimal`` cannot hold, as ``xsd:double``."""
    v = float(v)
    if not math.isfinite(v):
        lexical = "NaN" if math.isnan(v) else "INF" if v > 0 else "-INF"
        return Literal(lexical, datatype=XSD.double, normalize=False)
    return Literal(decimal(v), datatype=XSD.decimal)


def rescale(graph: Graph, kind: str, unit: str) -> Graph:
    """``graph`` with every quantity of ``kind`` ("length", "angle", "weight") written in
    ``unit``, and the workstation declaring it. The graph is changed in place and returned."""
    if unit not in KINDS[kind]:
        raise InputError(f"unknown {kind} unit {unit!r} (kitkb knows {', '.join(KINDS[kind])})")
    prop = UNIT_PROPS[kind]
    table = KINDS[kind]
    workstations = list(graph.subject_objects(prop))
    if not workstations:
        raise InputError(f"no workstation declares its {kind} unit: nothing says what the numbers are")
    old = {str(u).strip().lower() for _, u in workstations}
    if len(old) > 1 or next(iter(old)) not in table:
        raise InputError(f"{kind} unit {', '.join(sorted(old))} cannot be converted (kitkb knows {', '.join(table)})")
    factor = table[old.pop()] / table[unit]
    props = {URIRef(p) for p, k in quantity_kinds().items() if k == kind}
    for s, p, o in list(graph):
        if p in props and isinstance(o, Literal) and isinstance(o.toPython(), (int, float, Decimal)):
            try:
                value = float(o.toPython()) * factor
            except OverflowError:  # an xsd:integer of hundreds of digits
                raise InputError(f"{local_name(s)}: {local_name(p)} is too large ({len(o)} digits)") from None
            graph.remove((s, p, o))
            graph.add((s, p, number(value)))
    for ws, u in workstations:
        graph.remove((ws, prop, u))
        graph.add((ws, prop, Literal(unit)))
    return graph


def turn(graph: Graph, yaw_deg: float, objects: Iterable[str] | None = None) -> Graph:
    """``graph`` turned by ``yaw_deg`` degrees about z: with no ``objects``, the whole
    workstation about the world's z axis (every location whose reference object is the
    workstation); else each named object (local name or IRI) about its own z axis. Changed in
    place and returned."""
    r = _yaw(yaw_deg)
    if objects is None:
        ws = set(graph.subjects(RDF.type, KTW.KittingWorkstation))
        if not ws:
            raise InputError("no KittingWorkstation: nothing to turn the state about")
        locations = [loc for loc, ref in graph.subject_objects(KTW.hasPhysicalLocation_RefObject)
                     if ref in ws and not any((w, KTW.hasSolidObject_PrimaryLocation, loc) in graph for w in ws)]
        for loc in _unique(locations):
            _turn_location(graph, loc, r, move_point=True)
        return graph
    for name in objects:
        obj = _find(graph, name)
        loc = graph.value(obj, KTW.hasSolidObject_PrimaryLocation)
        if loc is None:
            raise InputError(f"{name} has no location to turn")
        _turn_location(graph, loc, r, move_point=False)
    return graph


def write_variant(in_path: str | Path, out_path: str | Path, *, unit: str | None = None, yaw: float = 0.0,
                  objects: Iterable[str] | None = None) -> int:
    """Read a state file, turn it (``yaw`` degrees; the whole workstation or ``objects``) and
    write it in ``unit``; the number of statements written (Turtle, atomically).

    ``out_path`` may be ``in_path`` itself (``scenario generate --unit`` rewrites its own
    output): the file is then read in a scope of its own, so only a file the running command
    was given as an input stays protected from being written over."""
    if Path(in_path).resolve() == Path(out_path).resolve():
        with command_scope():
            source = load_file(in_path)
    else:
        source = load_file(in_path)
    graph = Graph()
    for prefix, iri in source.graph.namespaces():
        graph.bind(prefix, iri, override=False)
    graph += source.graph
    read_units([source.view()], str(in_path), source.line_of)  # a unit kitkb cannot convert: error at its line
    try:
        if yaw:
            turn(graph, yaw, objects)
        if unit is not None:
            rescale(graph, "length", unit)
    except InputError as e:
        raise InputError(e.message, in_path) from None
    write_atomic(Path(out_path), turtle(graph).encode("utf-8"))
    return len(graph)


def _yaw(deg: float) -> np.ndarray:
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def _unique(nodes: list) -> list:
    seen: set = set()
    return [n for n in nodes if not (n in seen or seen.add(n))]


def _find(graph: Graph, name: str) -> URIRef:
    if name.startswith(("http:", "https:", "urn:", "file:")):
        return URIRef(name)
    hits = {s for s in graph.subjects(KTW.hasSolidObject_PrimaryLocation) if local_name(s) == name}
    if len(hits) != 1:
        raise InputError(f"{'no' if not hits else 'more than one'} placed object named {name!r}")
    return hits.pop()


def _turn_location(graph: Graph, loc, r: np.ndarray, move_point: bool) -> None:  # noqa: ANN001
    """Rotate a pose location's axes by ``r`` (and its point about the origin of its frame)."""
    nodes = [(graph.value(loc, _POINT), _XYZ, move_point), (_axis(graph, loc, _XAXIS, "x", (1.0, 0.0, 0.0)), _IJK, True),
             (_axis(graph, loc, _ZAXIS, "z", (0.0, 0.0, 1.0)), _IJK, True)]
    for node, props, rotate in nodes:
        if node is None or not rotate:
            continue
        v = np.array([_coordinate(graph, node, p) for p in props])
        for p, x in zip(props, r @ v):
            for o in list(graph.objects(node, p)):
                graph.remove((node, p, o))
            graph.add((node, p, number(0.0 if abs(x) < 1e-12 else x)))


def _coordinate(graph: Graph, node, prop) -> float:  # noqa: ANN001
    """The number ``node`` has for ``prop`` (0 where it has none); an InputError naming both
    where it is no number ("0x10"^^xsd:decimal, a string) or too large for a float."""
    o = graph.value(node, prop)
    if o is None:
        return 0.0
    v = o.toPython() if isinstance(o, Literal) else None
    if isinstance(v, bool) or not isinstance(v, (int, float, Decimal)):
        raise InputError(f"{local_name(node)}: {local_name(prop)} is not a number ({str(o)[:40]!r})")
    try:
        return float(v)
    except OverflowError:  # an xsd:integer of hundreds of digits
        raise InputError(f"{local_name(node)}: {local_name(prop)} is too large ({len(o)} digits)") from None


def _axis(graph: Graph, loc, prop, name: str, default: tuple[float, float, float]):  # noqa: ANN001, ANN202
    """The vector of a pose location's axis; one made with the model's default (x along x, z up)
    where the location gives none, so that a turn turns it."""
    node = graph.value(loc, prop)
    if node is None:
        node = URIRef(f"{loc}_{name}_axis") if isinstance(loc, URIRef) else BNode()
        graph.add((loc, prop, node))
        graph.add((node, RDF.type, KTW.Vector))
        for p, v in zip(_IJK, default):
            graph.add((node, p, number(v)))
    return node
