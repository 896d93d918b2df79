"""Loading a data file into the world-model database, in one transaction.

Every statement of a data file is kept. Statements the class tables can hold go there;
the rest (the ontology header, ``owl:NamedIndividual`` declarations, annotations, a
property used on an individual outside its domain) go to ``kitkb_triple``; asserted types
beyond the most specific model class go to ``kitkb_type``; a literal whose stored value
would print differently (``"8.500000"`` stored as 8.5, ``"degree"^^xsd:NMTOKEN`` in a
string column) keeps its spelling in ``kitkb_literal``.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path
from typing import Any, Callable, Iterator

from rdflib import RDF, BNode, Graph, Literal, URIRef
from rdflib.term import Node
from sqlalchemy import Engine, Table, delete, func, insert, inspect, select
from sqlalchemy.engine import Connection
from sqlalchemy.exc import SQLAlchemyError

from kb.core.errors import InputError
from kb.core.namespaces import local_name
from kb.core.resources import model_files
from kb.io.loader import load_file
from kb.patches.sqlalchemy import ddl_scope
from kb.world.database import (DEFAULT_DB, check_version, first_line, normalize_url, open_engine, sqlite_file,
                               stamp, term_key, writing)
from kb.world.schema import Plan, model
from kb.world.values import ValueProblem, is_canonical, to_sql

#: Rows per INSERT statement batch.
_BATCH = 5000

# --- reading data files ----------------------------------------------------------------------------

LineOf = Callable[[Node, Node, Node], "int | None"]


def read_data(path: str | Path) -> tuple[Graph, LineOf]:
    """The statements of one data file (NIST namespace mapped onto ours) and a line finder.

    Any format :mod:`kb.io.loader` reads (Turtle, RDF/XML, OWL/XML, OWL functional syntax);
    imports are not followed: the database holds what this file says.
    """
    src = load_file(Path(path))
    return src.graph, src.line_of


# --- load -----------------------------------------------------------------------------------------

@dataclass
class LoadReport:
    """What :func:`load` stored."""

    individuals: int = 0
    statements: int = 0
    outside_model: int = 0
    tables: dict[str, int] = field(default_factory=dict)

    def summary(self) -> str:
        """One line for the command line."""
        return (f"{self.statements} statements: {self.individuals} individuals in "
                f"{len(self.tables)} tables, {self.outside_model} statements outside the model tables")


@lru_cache(maxsize=1)
def _model_individuals() -> dict[str, tuple[str, ...]]:
    """Individuals the shipped ontologies define (``soap:EffectCheck``...) with their model classes."""
    g, m = Graph(), model()
    for path in model_files():
        g.parse(path, format="turtle")
    out: dict[str, list[str]] = {}
    for s, o in g.subject_objects(RDF.type):
        if isinstance(s, URIRef) and str(o) in m.class_table:
            out.setdefault(str(s), []).append(str(o))
    return {k: tuple(v) for k, v in out.items()}


def _external_individuals(g: Graph, typed: dict[Node, list[str]]) -> dict[Node, list[str]]:
    """Individuals of the model ontologies that ``g`` refers to without defining them.

    They get rows (so that foreign keys can point at them) but no type statements on dump.
    Only those whose tables require no values are taken: their values are not in ``g``.
    """
    known, m = _model_individuals(), model()
    out: dict[Node, list[str]] = {}
    for o in set(g.objects()):
        if isinstance(o, URIRef) and o not in typed and str(o) in known:
            tables = {t for c in known[str(o)] for t in m.chain(m.class_table[c].name)}
            if not any(not c.nullable and "iri" in c.info for t in tables for c in m.table(t).columns):
                out[o] = list(known[str(o)])
    return out


class _Builder:
    """Turns one graph into rows of the model's tables."""

    def __init__(self, graph: Graph, line_of: LineOf, file: str):
        self.g, self.line_of, self.file, self.m = graph, line_of, file, model()
        self.ids: dict[Node, int] = {}
        self.primary: dict[Node, str] = {}
        self.tables_of: dict[Node, set[str]] = {}
        self.rows: dict[str, dict[int, dict[str, Any]]] = {}
        self.link_rows: dict[str, list[dict[str, Any]]] = {}
        self.types: list[dict[str, Any]] = []
        self.literals: list[dict[str, Any]] = []
        self.triples: list[dict[str, Any]] = []

    def fail(self, s: Node, p: Node, o: Node, message: str) -> InputError:
        return InputError(message, file=self.file, line=self.line_of(s, p, o))

    def individuals(self) -> None:
        classes: dict[Node, list[str]] = {}
        for s, o in self.g.subject_objects(RDF.type):
            if isinstance(s, (URIRef, BNode)) and str(o) in self.m.class_table:
                classes.setdefault(s, []).append(str(o))
        external = _external_individuals(self.g, classes)
        for n, node in enumerate(sorted([*classes, *external], key=term_key), start=1):
            mine = sorted(classes.get(node) or external[node], key=lambda c: (-self.m.depth[c], c))
            self.ids[node], self.primary[node] = n, mine[0] if node in classes else ""
            tables = {t for c in mine for t in self.m.chain(self.m.class_table[c].name)}
            self.tables_of[node] = tables
            for t in tables:
                self.rows.setdefault(t, {})[n] = {"id": n}
            key = term_key(node)
            if len(key) > 760:
                raise self.fail(node, RDF.type, URIRef(mine[0]), f"name longer than 760 characters: {key[:40]}...")
            self.rows["kitkb_thing"][n].update(iri=key, name=local_name(key), kind=self.primary[node])

    def statement(self, s: Node, p: Node, o: Node) -> None:
        if s in self.ids:
            if p == RDF.type:
                if str(o) == self.primary[s]:
                    return
                if isinstance(o, URIRef):
                    self.types.append({"thing_id": self.ids[s], "class_iri": str(o)})
                    return
            else:
                plan = self.m.plans.get(str(p))
                if plan is not None and plan.domain in self.tables_of[s] and self._store(s, p, o, plan):
                    return
        self.outside(s, p, o)

    def outside(self, s: Node, p: Node, o: Node) -> None:
        kind = "literal" if isinstance(o, Literal) else "bnode" if isinstance(o, BNode) else "iri"
        self.triples.append({"subject": term_key(s), "predicate": str(p),
                             "object": str(o) if kind == "literal" else term_key(o), "object_kind": kind,
                             "datatype": str(o.datatype) if isinstance(o, Literal) and o.datatype else None,
                             "lang": o.language if isinstance(o, Literal) else None})

    def _value(self, s: Node, p: Node, o: Node, plan: Plan) -> tuple[bool, Any]:
        """(fits, value) of object ``o`` for the column or link of ``plan``."""
        kind = plan.info["kind"]
        if kind == "object":
            return o in self.ids and plan.target in self.tables_of[o], self.ids.get(o)
        if kind == "iri":
            return isinstance(o, URIRef) and len(str(o)) <= 760, str(o)
        if not isinstance(o, Literal):
            raise self.fail(s, p, o, f"{local_name(str(p))} expects a literal value, not {o.n3()}")
        try:
            return True, to_sql(o, plan.info, plan.checks)
        except ValueProblem as exc:
            raise self.fail(s, p, o, f"{local_name(str(p))} of {local_name(term_key(s))}: {exc}") from None

    def _store(self, s: Node, p: Node, o: Node, plan: Plan) -> bool:
        ok, value = self._value(s, p, o, plan)
        if not ok:
            return False
        data = plan.info["kind"] == "data"
        if plan.link:
            if data and not is_canonical(o, value, plan.info):
                return False  # a literal spelled unusually stays a plain statement (lossless)
            self.link_rows.setdefault(plan.table, []).append({"subject_id": self.ids[s], plan.column: value})
            return True
        row = self.rows[plan.table][self.ids[s]]
        if plan.column in row:
            raise self.fail(s, p, o, f"{local_name(term_key(s))} has a second value for the functional "
                                     f"property {local_name(str(p))}")
        row[plan.column] = value
        if data and not is_canonical(o, value, plan.info):
            self.literals.append({"thing_id": self.ids[s], "property_iri": str(p), "lexical": str(o),
                                  "datatype": str(o.datatype) if o.datatype else None, "lang": o.language})
        return True

    def required(self) -> None:
        """Every NOT NULL column of every row is filled, or the file is refused."""
        for tname, rows in self.rows.items():
            table = self.m.table(tname)
            needed = [c for c in table.columns if not c.nullable and not c.primary_key and c.name != "kind"]
            for row in rows.values():
                for c in needed:
                    if c.name not in row:
                        node = next(n for n, i in self.ids.items() if i == row["id"])
                        cls = URIRef(self.primary[node])
                        raise self.fail(node, RDF.type, cls,
                                        f"{local_name(term_key(node))} ({local_name(str(cls))}) has no value for "
                                        f"{local_name(c.info.get('iri', c.name))}, which the model requires")


def load(datafile: str | Path, url: str | Path = DEFAULT_DB) -> LoadReport:
    """Replace the content of database ``url`` with the statements of ``datafile``.

    One transaction: on any error nothing is written (a new SQLite file is removed again).
    """
    graph, line_of = read_data(datafile)
    b = _Builder(graph, line_of, str(datafile))
    b.individuals()
    for s, p, o in graph:
        b.statement(s, p, o)
    b.required()
    url = normalize_url(url)
    target = sqlite_file(url)
    existed = target is None or target.exists()
    engine = open_engine(url)
    try:
        with writing(engine.connect()) as conn, conn.begin():
            _prepare(conn, url)
            report = _write(conn, b)
            prefixes = _prefixes(graph)
            stamp(conn, source=Path(datafile).name, prefixes=json.dumps(prefixes, sort_keys=True))
    except SQLAlchemyError as exc:
        _discard(engine, target, existed)
        raise InputError(f"database refused the data: {first_line(exc)}", file=str(datafile)) from None
    except BaseException:
        _discard(engine, target, existed)
        raise
    if engine.dialect.name == "postgresql":
        with engine.connect() as conn:  # fresh statistics, or the planner scans whole tables
            conn.execution_options(isolation_level="AUTOCOMMIT").exec_driver_sql("ANALYZE")
    engine.dispose()
    report.statements = len(graph)
    return report


def _prefixes(graph: Graph) -> dict[str, str]:
    """The graph's prefixes, plus ``:`` for the namespace most individuals are named in."""
    out = {p: str(ns) for p, ns in graph.namespace_manager.namespaces()}
    if "" not in out:
        counts: dict[str, int] = {}
        for s in graph.subjects(RDF.type, None):
            if isinstance(s, URIRef):
                ns = str(s)[: len(str(s)) - len(local_name(str(s)))]
                counts[ns] = counts.get(ns, 0) + 1
        if counts:
            out[""] = max(sorted(counts), key=lambda k: counts[k])
    return out


def _discard(engine: Engine, path: Path | None, existed: bool) -> None:
    engine.dispose()
    if path is not None and not existed:
        for suffix in ("", "-wal", "-shm", "-journal"):
            Path(str(path) + suffix).unlink(missing_ok=True)


def _prepare(conn: Connection, url: str) -> None:
    """Create the tables in an empty database, or empty the tables of a kitkb database."""
    m = model()
    if not inspect(conn).get_table_names():
        with ddl_scope(m.metadata) as scoped:
            scoped.create_all(conn)
        return
    check_version(conn, url)
    for table in reversed(m.metadata.sorted_tables):
        conn.execute(delete(table))


def _write(conn: Connection, b: _Builder) -> LoadReport:
    m = model()
    report = LoadReport(individuals=len(b.ids), outside_model=len(b.triples) + len(b.types))
    for table in m.metadata.sorted_tables:
        rows = list(b.rows.get(table.name, {}).values()) or b.link_rows.get(table.name, [])
        rows = rows or {"kitkb_type": b.types, "kitkb_literal": b.literals,
                        "kitkb_triple": b.triples}.get(table.name, [])
        if rows:
            report.tables[table.name] = len(rows)
            for chunk in _chunks(_complete(table, rows)):
                conn.execute(insert(table), chunk)
    if conn.dialect.name == "postgresql" and b.ids:
        conn.execute(select(func.setval(func.pg_get_serial_sequence("kitkb_thing", "id"), len(b.ids))))
    return report


def _complete(table: Table, rows: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """Rows with every column present (executemany needs the same keys in each row)."""
    names = [c.name for c in table.columns if not (table.name == "kitkb_triple" and c.name == "id")]
    return [{n: r.get(n) for n in names} for r in rows]


def _chunks(rows: list[dict[str, Any]]) -> Iterator[list[dict[str, Any]]]:
    for i in range(0, len(rows), _BATCH):
        yield rows[i:i + _BATCH]
