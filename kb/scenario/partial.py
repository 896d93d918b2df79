"""Partial state files: objects whose location is unknown, and the same states with them placed.

Three uses, one vocabulary (docs/validation.md, "Partial data: objects to be sensed"):

* :func:`unlocate` makes a partial file of a full one (``kitkb scenario generate
  --unlocated N``, ``kitkb scenario transform --unlocate OBJ,...``): the chosen objects lose their
  primary location (or, with ``mark=True``, keep only a ``ktw:RelativeLocationIn`` to the
  container they were in: "in this tray, pose to be sensed");
* a simulator's ground truth of a partial state when it is given none
  (:func:`kb.sim.hidden.place_unknown`) is written with :func:`with_locations` too;
* :func:`with_locations` writes what was sensed into the state: each object's primary location
  a pose in the frame of the object found to contain it (a relative location it had is kept as
  its secondary location).

Poses are SI 4x4 matrices (:class:`Placement`); they are written in the file's length unit.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Iterable, Sequence

import numpy as np
from rdflib import Graph, Literal, URIRef
from rdflib.namespace import OWL, RDF

from kb.core.errors import InputError
from kb.core.files import command_scope, write_atomic
from kb.core.namespaces import KTW, local_name
from kb.core.units import SI, Units
from kb.io.loader import Source, load_file
from kb.io.turtle import turtle
from kb.scenario.variants import number

_PRIMARY, _SECONDARY = KTW.hasSolidObject_PrimaryLocation, KTW.hasSolidObject_SecondaryLocation
_REF = KTW.hasPhysicalLocation_RefObject
_POINT, _XAXIS, _ZAXIS = KTW.hasPoseLocation_Point, KTW.hasPoseLocation_XAxis, KTW.hasPoseLocation_ZAxis
_XYZ = (KTW.hasPoint_X, KTW.hasPoint_Y, KTW.hasPoint_Z)
_IJK = (KTW.hasVector_I, KTW.hasVector_J, KTW.hasVector_K)


@dataclass(frozen=True)
class Placement:
    """Where an object is: ``container`` (IRI) and ``local``, its 4x4 pose in the container's
    frame, in SI; ``pose``: its global pose (SI)."""

    name: str
    container: str
    local: np.ndarray
    pose: np.ndarray

    def as_dict(self, units: Units = SI) -> dict[str, object]:
        """JSON data: the object, its container, its position in the container and in the world
        (in ``units``' length) and its yaw in the world (degrees)."""
        m = units.metres
        return {"object": local_name(self.name), "container": local_name(self.container),
                "in_container": [round(float(v) / m, 6) for v in self.local[:3, 3]],
                "position": [round(float(v) / m, 6) for v in self.pose[:3, 3]],
                "yaw_deg": round(float(np.degrees(np.arctan2(self.pose[1, 0], self.pose[0, 0]))), 3)}


def copy_graph(source: Source) -> Graph:
    """A new graph of ``source``'s statements and prefixes (the source's own is not changed)."""
    graph = Graph()
    for prefix, ns in source.graph.namespace_manager.namespaces():
        graph.bind(prefix, ns, override=True)
    for t in source.triples():
        graph.add(t)
    return graph


# --- placing: what was sensed, or a simulator's truth -------------------------------------------------

def with_locations(graph: Graph, placements: Iterable[Placement], units: Units = SI) -> Graph:
    """``graph`` (changed in place) with each placement its object's primary location: a
    ``ktw:PoseLocationIn`` named ``<object>_sensed_pose`` in the container's frame; a relative
    location the object had becomes its secondary location."""
    for p in placements:
        obj = URIRef(p.name)
        for old in list(graph.objects(obj, _PRIMARY)):
            graph.remove((obj, _PRIMARY, old))
            graph.add((obj, _SECONDARY, old))
        loc = _fresh(graph, f"{p.name}_sensed_pose")
        graph.add((obj, _PRIMARY, loc))
        graph.add((loc, RDF.type, OWL.NamedIndividual))
        graph.add((loc, RDF.type, KTW.PoseLocationIn))
        graph.add((loc, _REF, URIRef(p.container)))
        m = p.local
        for prop, cls, props, values in ((_POINT, KTW.Point, _XYZ, [units.from_si("length", v) for v in m[:3, 3]]),
                                         (_XAXIS, KTW.Vector, _IJK, m[:3, 0]), (_ZAXIS, KTW.Vector, _IJK, m[:3, 2])):
            node = _fresh(graph, f"{loc}_{local_name(prop).rsplit('_', 1)[-1].lower()}")
            graph.add((loc, prop, node))
            graph.add((node, RDF.type, OWL.NamedIndividual))
            graph.add((node, RDF.type, cls))
            for q, v in zip(props, values):
                v = float(v)
                graph.add((node, q, number(0.0 if abs(v) < 1e-12 else round(v, 9))))
    return graph


def _fresh(graph: Graph, iri: str) -> URIRef:
    """``iri``, or ``iri_2``, ``iri_3``... the first that names nothing in ``graph``."""
    node, n = URIRef(iri), 1
    while (node, None, None) in graph or (None, None, node) in graph:
        n += 1
        node = URIRef(f"{iri}_{n}")
    return node


def write_state(graph: Graph, path: str | Path) -> Path:
    """Write ``graph`` as Turtle to ``path`` (atomically)."""
    return write_atomic(path, turtle(graph))


def graph_source(graph: Graph, path: str | Path) -> Source:
    """A :class:`Source` over ``graph`` (for a scene of a state made in memory; ``path`` names it)."""
    return Source(Path(path), "turtle", graph=graph, prefixes={p: str(n) for p, n in graph.namespace_manager.namespaces()})


# --- partial files for tests and users ----------------------------------------------------------------

def unlocate(graph: Graph, names: Iterable[str], mark: bool = False) -> list[str]:
    """Take the location of each object of ``names`` (IRIs) out of ``graph`` (in place): its
    primary location and the pose's point and axes when nothing else uses them. ``mark``:
    leave a ``ktw:RelativeLocationIn`` to the object the location referred to (the mark "pose to
    be sensed"). The names done, in order; an object with no location is an InputError."""
    done = []
    for name in names:
        obj = URIRef(name)
        loc = graph.value(obj, _PRIMARY)
        if loc is None:
            raise InputError(f"{local_name(name)} has no location to take away")
        ref = graph.value(loc, _REF)
        graph.remove((obj, _PRIMARY, loc))
        if not any(True for _ in graph.subject_predicates(loc)):
            for node in (graph.value(loc, p) for p in (_POINT, _XAXIS, _ZAXIS)):
                if node is not None and sum(1 for _ in graph.subject_predicates(node)) == 1:
                    graph.remove((node, None, None))
            graph.remove((loc, None, None))
        if mark and ref is not None:
            rel = _fresh(graph, f"{name}_to_be_sensed")
            graph.add((obj, _PRIMARY, rel))
            graph.add((rel, RDF.type, OWL.NamedIndividual))
            graph.add((rel, RDF.type, KTW.RelativeLocationIn))
            graph.add((rel, _REF, ref))
            graph.add((rel, KTW.hasRelativeLocation_Description,
                       Literal(f"in {local_name(ref)}; pose to be sensed")))
        done.append(name)
    return done


def choose_unlocated(graph: Graph, count: int, seed: int) -> list[str]:
    """``count`` parts of ``graph`` (``ktw:Part`` individuals with a location), chosen with ``seed``."""
    parts = sorted(str(p) for p in graph.subjects(RDF.type, KTW.Part) if graph.value(p, _PRIMARY) is not None)
    if count > len(parts):
        raise InputError(f"--unlocated {count}: the state has {len(parts)} located part(s)")
    rng = np.random.default_rng(seed)
    return sorted((parts[k] for k in rng.choice(len(parts), size=count, replace=False)), key=str)


def write_partial(path: str | Path, output: str | Path | None = None, *, count: int | None = None,
                  names: Sequence[str] = (), seed: int = 0, mark: bool = False) -> list[str]:
    """Write the state file ``path`` to ``output`` (default: over itself, for a file kitkb just
    wrote) as a partial state: ``count`` parts chosen with ``seed`` and the objects ``names``
    (local names or IRIs) without their location (:func:`unlocate`; ``mark``: with a relative
    location instead). The IRIs taken, in order."""
    if output is None or Path(output).resolve() == Path(path).resolve():
        with command_scope():  # the command's own output, rewritten: only its given inputs stay protected
            source = load_file(path)
    else:
        source = load_file(path)
    graph = copy_graph(source)
    chosen = choose_unlocated(graph, count, seed) if count else []
    for name in names:
        hits = sorted({str(s) for s in graph.subjects(_PRIMARY, None) if str(s) == name or local_name(s) == name})
        if not hits:
            raise InputError(f"{name}: no object of that name has a location", file=path)
        chosen.extend(h for h in hits if h not in chosen)
    done = unlocate(graph, chosen, mark=mark)
    write_state(graph, output if output is not None else path)
    return done
