"""Writing the world-model database back as Turtle, graph-isomorphic to what was loaded."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from rdflib import RDF, BNode, Graph, Literal, URIRef
from rdflib.term import Node
from sqlalchemy import Table, select
from sqlalchemy.engine import Connection

from kb.core.files import write_atomic
from kb.io.turtle import turtle
from kb.world.database import DEFAULT_DB, check_version, key_term, normalize_url, open_engine, read_meta
from kb.world.schema import model
from kb.world.values import ValueProblem, from_db, to_rdf, to_sql


def read_graph(url: str | Path = DEFAULT_DB) -> Graph:
    """The content of database ``url`` as an RDF graph (what :func:`dump` writes)."""
    url = normalize_url(url)
    engine = open_engine(url, must_exist=True)
    try:
        with engine.connect() as conn, conn.begin():
            check_version(conn, url)
            return _graph(conn)
    finally:
        engine.dispose()


def _graph(conn: Connection) -> Graph:
    m = model()
    g = Graph()
    meta = read_meta(conn)
    for prefix, ns in sorted(json.loads(meta.get("prefixes", "{}")).items()):
        g.bind(prefix, ns, override=True, replace=True)
    thing = m.table("kitkb_thing")
    nodes: dict[int, URIRef | BNode] = {}
    for id_, iri, kind in conn.execute(select(thing.c.id, thing.c.iri, thing.c.kind)):
        nodes[id_] = key_term(iri)
        if kind:  # "" marks an individual of the shipped ontologies the data only refers to
            g.add((nodes[id_], RDF.type, URIRef(kind)))
    spelled = _spellings(conn)
    for table in m.metadata.sorted_tables:
        if "parent" in table.info:
            _class_rows(conn, g, table, nodes, spelled)
        elif table.info.get("link"):
            _link_rows(conn, g, table, nodes)
    t = m.table("kitkb_type")
    for thing_id, cls in conn.execute(select(t.c.thing_id, t.c.class_iri)):
        g.add((nodes[thing_id], RDF.type, URIRef(cls)))
    tr = m.table("kitkb_triple")
    for s, p, o, kind, dt, lang in conn.execute(select(tr.c.subject, tr.c.predicate, tr.c.object,
                                                       tr.c.object_kind, tr.c.datatype, tr.c.lang)):
        obj = Literal(o, datatype=URIRef(dt) if dt else None, lang=lang) if kind == "literal" else key_term(o)
        g.add((key_term(s), URIRef(p), obj))
    return g


def _spellings(conn: Connection) -> dict[tuple[int, str], Literal]:
    lit = model().table("kitkb_literal")
    out = {}
    for thing_id, prop, lex, dt, lang in conn.execute(select(lit.c.thing_id, lit.c.property_iri, lit.c.lexical,
                                                             lit.c.datatype, lit.c.lang)):
        out[(thing_id, prop)] = Literal(lex, datatype=URIRef(dt) if dt else None, lang=lang)
    return out


def _class_rows(conn: Connection, g: Graph, table: Table, nodes: dict[int, Any],
                spelled: dict[tuple[int, str], Literal]) -> None:
    cols = [c for c in table.columns if "iri" in c.info]
    if not cols:
        return
    for row in conn.execute(select(table.c.id, *cols)):
        s = nodes[row[0]]
        for col, value in zip(cols, row[1:]):
            if value is None:
                continue
            info, p = col.info, URIRef(col.info["iri"])
            if info["kind"] == "object":
                g.add((s, p, nodes[value]))
            elif info["kind"] == "iri":
                g.add((s, p, URIRef(value)))
            else:
                g.add((s, p, _literal(value, info, spelled.get((row[0], info["iri"])))))


def _literal(value: Any, info: dict[str, Any], original: Literal | None) -> Literal:
    value = from_db(value, info)
    if original is not None:
        try:
            if to_sql(original, info) == value:
                return original
        except ValueProblem:
            pass
    return to_rdf(value, info)


def _link_rows(conn: Connection, g: Graph, table: Table, nodes: dict[int, Any]) -> None:
    info, p = table.info, URIRef(table.info["iri"])
    value_col = table.c.value_id if info["kind"] == "object" else table.c.value
    for subject_id, value in conn.execute(select(table.c.subject_id, value_col)):
        if info["kind"] == "object":
            obj: Node = nodes[value]
        elif info["kind"] == "iri":
            obj = URIRef(value)
        else:
            obj = to_rdf(from_db(value, info), info)
        g.add((nodes[subject_id], p, obj))


def dump(url: str | Path, out: str | Path) -> Path:
    """Write database ``url`` to ``out`` as Turtle (atomically)."""
    return write_atomic(out, turtle(read_graph(url)))
