"""The execution world model in a real database: open, load a data file, dump it back.

The tables are those of the generated module :mod:`kb.accessors_generated` (one per ontology
class, see docs/database.md). :func:`load` fills them from a data file in one transaction;
:func:`dump` writes the database back as Turtle, graph-isomorphic to what was loaded.

Every statement of a data file is kept. Statements the class tables can hold go there;
the rest (the ontology header, ``owl:NamedIndividual`` declarations, annotations, a
property used on an individual outside its domain) go to ``kitkb_triple``; asserted types
beyond the most specific model class go to ``kitkb_type``; a literal whose stored value
would print differently (``"8.500000"`` stored as 8.5, ``"degree"^^xsd:NMTOKEN`` in a
string column) keeps its spelling in ``kitkb_literal``.

A database carries the fingerprint of the schema it was made with (``kitkb_meta``); one
made from another ontology version is refused with :class:`SchemaVersionError`.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path
from typing import Any, Callable, Iterator

from rdflib import RDF, BNode, Graph, Literal, URIRef
from rdflib.term import Node
from sqlalchemy import Column, Engine, Table, create_engine, delete, event, func, insert, inspect, select
from sqlalchemy.engine import Connection, make_url
from sqlalchemy.exc import ArgumentError, DBAPIError, NoSuchModuleError, SQLAlchemyError

from kb.db_values import Check, ValueProblem, check_spec, from_db, is_canonical, to_rdf, to_sql
from kb.errors import InputError

#: Rows per INSERT statement batch.
_BATCH = 5000
#: Name of the SQLite file used when no database is given.
DEFAULT_DB = "kitkb.sqlite"


class SchemaVersionError(InputError):
    """The database was made from another version of the ontology (or is not kitkb's)."""


# --- the model as the generated metadata describes it ----------------------------------------

@dataclass
class Model:
    """Lookup tables over the generated metadata: class -> table, property -> column."""

    metadata: Any
    version: str
    class_table: dict[str, Table] = field(default_factory=dict)
    parent: dict[str, str] = field(default_factory=dict)
    depth: dict[str, int] = field(default_factory=dict)
    columns: dict[str, tuple[Table, Column[Any]]] = field(default_factory=dict)
    links: dict[str, Table] = field(default_factory=dict)

    plans: dict[str, "Plan"] = field(default_factory=dict)

    def table(self, name: str) -> Table:
        """The table named ``name``."""
        return self.metadata.tables[name]

    def chain(self, table: str) -> list[str]:
        """``table`` and the tables of all its ancestor classes, nearest first."""
        out = []
        while table:
            out.append(table)
            table = self.parent.get(table, "")
        return out


@dataclass(frozen=True)
class Plan:
    """Where the values of one property go: a column of a class table, or a link table."""

    table: str  # class table (columns) or link table
    column: str  # column name (value column of a link table)
    domain: str  # class table the subject must have a row in
    target: str | None  # class table the object must have a row in (object properties)
    info: dict[str, Any]
    checks: tuple[Check, ...]
    link: bool


def _target(col: Column[Any]) -> str | None:
    return next(iter(col.foreign_keys)).column.table.name if col.foreign_keys else None


def _plans(m: Model) -> dict[str, Plan]:
    plans = {}
    for iri, (table, col) in m.columns.items():
        checks = tuple((fn, text) for ck in table.constraints
                       if (spec := check_spec(ck)) and spec[0] == col.name for fn, text in [spec[1:]])
        plans[iri] = Plan(table.name, col.name, table.name, _target(col), dict(col.info), checks, False)
    for iri, table in m.links.items():
        value = table.c.value_id if table.info["kind"] == "object" else table.c.value
        checks = tuple((fn, text) for ck in table.constraints
                       if (spec := check_spec(ck)) and spec[0] == value.name for fn, text in [spec[1:]])
        plans[iri] = Plan(table.name, value.name, _target(table.c.subject_id) or "", _target(value),
                          dict(table.info), checks, True)
    return plans


@lru_cache(maxsize=1)
def model() -> Model:
    """The model of the generated accessors module (built once)."""
    from kb import accessors_generated as gen

    m = Model(gen.Base.metadata, gen.SCHEMA_VERSION)
    for table in m.metadata.tables.values():
        info = table.info
        if info.get("link"):
            m.links[info["iri"]] = table
        elif "parent" in info:
            m.parent[table.name] = info["parent"]
            if info["iri"]:
                m.class_table[info["iri"]] = table
            for col in table.columns:
                if "iri" in col.info:
                    m.columns[col.info["iri"]] = (table, col)
    for iri, table in m.class_table.items():
        m.depth[iri] = len(m.chain(table.name))
    m.plans = _plans(m)
    return m


# --- opening a database -------------------------------------------------------------------------

def normalize_url(url: str | Path) -> str:
    """An SQLAlchemy URL; a plain path means an SQLite file."""
    text = str(url)
    if "://" in text or text.startswith("sqlite:"):
        return text
    return f"sqlite:///{Path(text).resolve()}"


def safe_url(url: str) -> str:
    """``url`` with any password hidden, for messages."""
    try:
        return make_url(url).render_as_string(hide_password=True)
    except ArgumentError:
        return url


def open_engine(url: str | Path, must_exist: bool = False) -> Engine:
    """An engine on ``url`` (SQLAlchemy URL or SQLite path); one-line :class:`InputError` if unusable.

    ``must_exist``: refuse an SQLite file that does not exist (instead of creating it).
    """
    url = normalize_url(url)
    sqlite_file = _sqlite_file(url) if "://" in url else None
    if must_exist and sqlite_file is not None and not sqlite_file.is_file():
        raise InputError(f"no such database file: {sqlite_file}")
    try:
        parsed = make_url(url)
        if parsed.get_backend_name() == "sqlite":
            engine = create_engine(url, connect_args={"timeout": 60})
            _sqlite_transactions(engine, parsed.database or "")
        else:
            engine = create_engine(url, pool_pre_ping=True)
        with engine.connect():
            pass
    except (ArgumentError, NoSuchModuleError, ValueError) as exc:
        raise InputError(f"bad database URL {safe_url(url)!r}: {_first_line(exc)}") from None
    except (DBAPIError, SQLAlchemyError) as exc:
        raise InputError(f"cannot open database {safe_url(url)}: {_first_line(exc)}") from None
    except ImportError as exc:
        raise InputError(f"cannot open database {safe_url(url)}: missing driver ({exc.name})") from None
    return engine


def _first_line(exc: BaseException) -> str:
    orig = getattr(exc, "orig", None) or exc
    text = str(orig).strip().splitlines()
    return text[0] if text else type(orig).__name__


def _sqlite_transactions(engine: Engine, database: str) -> None:
    """Real transactions on SQLite: BEGIN before DDL too, foreign keys on, WAL for files."""

    @event.listens_for(engine, "connect")
    def _connect(dbapi_conn: Any, _record: Any) -> None:
        dbapi_conn.isolation_level = None  # we issue BEGIN ourselves (below)
        cur = dbapi_conn.cursor()
        cur.execute("PRAGMA foreign_keys = ON")
        cur.execute("PRAGMA busy_timeout = 60000")
        if database and database != ":memory:":
            cur.execute("PRAGMA journal_mode = WAL")
            cur.execute("PRAGMA synchronous = NORMAL")
        cur.close()

    @event.listens_for(engine, "begin")
    def _begin(conn: Connection) -> None:
        # A writer takes the write lock at BEGIN, so two writers queue instead of deadlocking.
        conn.exec_driver_sql("BEGIN IMMEDIATE" if conn.get_execution_options().get("kitkb_write") else "BEGIN")


def writing(conn: Connection) -> Connection:
    """``conn`` marked as a writer (SQLite takes the write lock when it begins)."""
    return conn.execution_options(kitkb_write=True)


# --- version stamp ------------------------------------------------------------------------------

def stamp(conn: Connection, **extra: str) -> None:
    """Write the schema fingerprint and ontology versions into ``kitkb_meta``."""
    from kb import __version__
    from kb import accessors_generated as gen

    values = {"schema_version": gen.SCHEMA_VERSION, "ontologies": json.dumps(gen.ONTOLOGIES),
              "kitkb_version": __version__, "stable_state": "0", **extra}
    meta = model().table("kitkb_meta")
    conn.execute(delete(meta))
    conn.execute(insert(meta), [{"key": k, "value": v} for k, v in sorted(values.items())])


def read_meta(conn: Connection) -> dict[str, str]:
    """The ``kitkb_meta`` entries."""
    meta = model().table("kitkb_meta")
    return {k: v for k, v in conn.execute(select(meta.c.key, meta.c.value))}


def check_version(conn: Connection, url: str) -> None:
    """Refuse a database that is not kitkb's or was made from another ontology version."""
    names = set(inspect(conn).get_table_names())
    if "kitkb_meta" not in names:
        what = "is empty (load a data file first: kitkb db load FILE --db URL)" if not names else \
            "is not a kitkb database (it has no kitkb_meta table)"
        raise SchemaVersionError(f"database {safe_url(url)} {what}")
    meta = read_meta(conn)
    m = model()
    if meta.get("schema_version") != m.version:
        from kb import accessors_generated as gen

        made = _versions(meta.get("ontologies", "[]"))
        now = ", ".join(f"{i.rsplit('/', 1)[-1]} {v}" for i, v in gen.ONTOLOGIES)
        raise SchemaVersionError(
            f"database {safe_url(url)} was made from another ontology version ({made}, schema "
            f"{meta.get('schema_version', '?')}); this kitkb uses {now} (schema {m.version}): "
            f"load the data again into a new database")


def _versions(text: str) -> str:
    try:
        return ", ".join(f"{i.rsplit('/', 1)[-1]} {v}" for i, v in json.loads(text)) or "unknown ontologies"
    except (ValueError, TypeError):
        return "unknown ontologies"


# --- terms ------------------------------------------------------------------------------------

def term_key(node: Node) -> str:
    """How a node is written in IRI columns: the IRI, or ``_:label`` for a blank node."""
    return f"_:{node}" if isinstance(node, BNode) else str(node)


def key_term(key: str) -> URIRef | BNode:
    """The node of a :func:`term_key` string."""
    return BNode(key[2:]) if key.startswith("_:") else URIRef(key)


def local_name(key: str) -> str:
    """The part of an IRI after its last ``#`` or ``/`` (the whole key if there is none)."""
    cut = max(key.rfind("#"), key.rfind("/"))
    return key[cut + 1:] if cut >= 0 and cut < len(key) - 1 else key


# --- reading data files ----------------------------------------------------------------------------

LineOf = Callable[[Node, Node, Node], "int | None"]


def read_data(path: str | Path) -> tuple[Graph, LineOf]:
    """The statements of one data file (NIST namespace mapped onto ours) and a line finder.

    Any format :mod:`kb.loader` reads (Turtle, RDF/XML, OWL/XML, OWL functional syntax);
    imports are not followed: the database holds what this file says.
    """
    from kb.loader import load_file

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
    from generators.sql_model import model_files

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
    sqlite_file = _sqlite_file(url)
    existed = sqlite_file is None or sqlite_file.exists()
    engine = open_engine(url)
    try:
        with writing(engine.connect()) as conn, conn.begin():
            _prepare(conn, url)
            report = _write(conn, b)
            prefixes = _prefixes(graph)
            stamp(conn, source=Path(datafile).name, prefixes=json.dumps(prefixes, sort_keys=True))
    except SQLAlchemyError as exc:
        _discard(engine, sqlite_file, existed)
        raise InputError(f"database refused the data: {_first_line(exc)}", file=str(datafile)) from None
    except BaseException:
        _discard(engine, sqlite_file, existed)
        raise
    if engine.dialect.name == "postgresql":
        with engine.connect() as conn:  # fresh statistics, or the planner scans whole tables
            conn.execution_options(isolation_level="AUTOCOMMIT").exec_driver_sql("ANALYZE")
    engine.dispose()
    report.statements = len(graph)
    return report


def drop_all(url: str | Path) -> None:
    """Drop every table of database ``url`` (kitkb's and any other): a clean slate for tests."""
    from sqlalchemy import MetaData

    engine = open_engine(url)
    meta = MetaData()
    meta.reflect(engine)
    meta.drop_all(engine)
    engine.dispose()


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


def _sqlite_file(url: str) -> Path | None:
    try:
        parsed = make_url(url)
    except ArgumentError:
        return None
    if parsed.get_backend_name() == "sqlite" and parsed.database not in (None, "", ":memory:"):
        return Path(parsed.database)
    return None


def _discard(engine: Engine, sqlite_file: Path | None, existed: bool) -> None:
    engine.dispose()
    if sqlite_file is not None and not existed:
        for suffix in ("", "-wal", "-shm", "-journal"):
            Path(str(sqlite_file) + suffix).unlink(missing_ok=True)


def _prepare(conn: Connection, url: str) -> None:
    """Create the tables in an empty database, or empty the tables of a kitkb database."""
    m = model()
    if not inspect(conn).get_table_names():
        from generators.sql import ddl_scope

        with ddl_scope(m.metadata):
            m.metadata.create_all(conn)
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


# --- dump -----------------------------------------------------------------------------------------

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
    from generators.base import write_text_atomic

    from kb.turtle_writer import turtle

    text = turtle(read_graph(url))
    try:
        return write_text_atomic(Path(out), text)
    except OSError as exc:
        raise InputError(f"cannot write: {exc.strerror or exc}", file=out) from None
