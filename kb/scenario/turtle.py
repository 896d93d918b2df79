"""Scenario data as Turtle statements, and the same data as an rdflib Graph.

Scenario files are written as a stream of *blocks*, one per individual::

    (subject, classes, props)

``subject`` is a local name in the scenario namespace, ``classes`` are local names in the
kitting model namespace (``ktw:``), ``props`` a list of ``(property local name, value)``.
A value is a ``str`` (a reference to another individual of the scenario), a ``float``
(written as an ``xsd:decimal``), a ``bool``, a :class:`Typed` literal or a :class:`Text`
(an ``xsd:string``). A block whose subject is ``None`` is a comment line.

:func:`write_turtle` spells the blocks for kitkb's Turtle writer (:mod:`kb.io.turtle`), so
that files of millions of triples are written in seconds; :func:`blocks_to_graph` builds
the same triples with rdflib so that tests can check the text against it.
"""

from __future__ import annotations

from typing import IO, Iterable, NamedTuple, Union

from rdflib import OWL, RDF, XSD, Graph, Literal, URIRef

from kb.core.namespaces import KITTING_ONTOLOGY, KTW
from kb.io.turtle import TurtleWriter, decimal, string

XSD_NS = str(XSD)


class Typed(NamedTuple):
    """A literal with an explicit XML Schema datatype (local name, e.g. ``"NMTOKEN"``)."""

    lexical: str
    datatype: str


class Text(NamedTuple):
    """An ``xsd:string`` literal."""

    value: str


class Geometry(NamedTuple):
    """A pose bundle: the pose individual ``<owner>_pose`` (unless ``cls`` is None) with its
    point ``<owner>_point`` and axes ``<owner>_x_axis`` / ``<owner>_z_axis``.

    ``p`` is ``(x, y, z, x axis i, j, k, z axis i, j, k)``. Bundles are written from one
    template: they are most of a large scenario.
    """

    owner: str
    cls: str | None
    ref: str | None
    p: tuple


Value = Union[str, float, bool, Typed, Text]
Block = Union[tuple, Geometry]  # (subject | None, classes | comment, [(property, value)]) or Geometry

_TERMS = {
    str: lambda v: ":" + v,
    bool: lambda v: "true" if v else "false",
    float: decimal,
    Typed: lambda v: f"{string(v.lexical)}^^xsd:{v.datatype}",
    Text: lambda v: string(v.value),
}


def _term(v: Value) -> str:
    try:
        return _TERMS[type(v)](v)
    except KeyError:
        raise TypeError(f"cannot write value {v!r}") from None


def expand(g: Geometry) -> list[tuple]:
    """The plain blocks of a :class:`Geometry` bundle."""
    o, p = g.owner, g.p
    out: list[tuple] = []
    if g.cls is not None:
        out.append((f"{o}_pose", (g.cls,), [
            ("hasPhysicalLocation_RefObject", g.ref),
            ("hasPoseLocation_Point", f"{o}_point"),
            ("hasPoseLocation_XAxis", f"{o}_x_axis"),
            ("hasPoseLocation_ZAxis", f"{o}_z_axis"),
        ]))
    out.append((f"{o}_point", ("Point",), [("hasPoint_X", p[0]), ("hasPoint_Y", p[1]), ("hasPoint_Z", p[2])]))
    out.append((f"{o}_x_axis", ("Vector",), [("hasVector_I", p[3]), ("hasVector_J", p[4]), ("hasVector_K", p[5])]))
    out.append((f"{o}_z_axis", ("Vector",), [("hasVector_I", p[6]), ("hasVector_J", p[7]), ("hasVector_K", p[8])]))
    return out


def header(namespace: str, ontology_iri: str, comment: str) -> str:
    """Prefixes and the ontology declaration of a scenario file."""
    lines = [f"# {line}".rstrip() for line in comment.splitlines()]
    lines += [
        "",
        f"@prefix : <{namespace}> .",
        f"@prefix ktw: <{KTW}> .",
        "@prefix owl: <http://www.w3.org/2002/07/owl#> .",
        "@prefix rdfs: <http://www.w3.org/2000/01/rdf-schema#> .",
        f"@prefix xsd: <{XSD_NS}> .",
        "",
        f"<{ontology_iri}> a owl:Ontology ;",
        f"    owl:imports <{KITTING_ONTOLOGY}> .",
        "",
    ]
    return "\n".join(lines) + "\n"


def _statements(block: Block) -> Iterable[tuple]:
    return expand(block) if type(block) is Geometry else (block,)


def write_turtle(out: IO[str], head: str, blocks: Iterable[Block]) -> None:
    """Stream ``head`` and ``blocks`` to ``out`` as Turtle."""
    writer = TurtleWriter(out)
    writer.text(head)
    for block in blocks:
        for subject, classes, props in _statements(block):
            if subject is None:
                writer.text(f"\n# {classes}\n")
                continue
            types = "owl:NamedIndividual, " + ", ".join("ktw:" + c for c in classes)
            writer.statement(":" + subject, [("a", types), *((f"ktw:{p}", _term(v)) for p, v in props)])
    writer.flush()


def _literal(v: Value) -> Literal | URIRef:
    if isinstance(v, bool):
        return Literal(v)
    if isinstance(v, float):
        return Literal(decimal(v), datatype=XSD.decimal)
    if isinstance(v, Typed):
        return Literal(v.lexical, datatype=URIRef(XSD_NS + v.datatype))
    if isinstance(v, Text):
        return Literal(v.value)
    raise TypeError(f"cannot convert value {v!r}")


def blocks_to_graph(namespace: str, ontology_iri: str, blocks: Iterable[Block]) -> Graph:
    """The triples :func:`write_turtle` writes, built with rdflib (for tests and small files)."""
    g = Graph()
    onto = URIRef(ontology_iri)
    g.add((onto, RDF.type, OWL.Ontology))
    g.add((onto, OWL.imports, URIRef(KITTING_ONTOLOGY)))
    for block in blocks:
        for subject, classes, props in _statements(block):
            if subject is None:
                continue
            _add(g, namespace, subject, classes, props)
    return g


def _add(g: Graph, namespace: str, subject: str, classes, props) -> None:
    s = URIRef(namespace + subject)
    g.add((s, RDF.type, OWL.NamedIndividual))
    for c in classes:
        g.add((s, RDF.type, KTW[c]))
    for p, v in props:
        o = URIRef(namespace + v) if type(v) is str else _literal(v)
        g.add((s, KTW[p], o))


