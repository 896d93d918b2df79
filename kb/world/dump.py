"""Writing the world-model database back as Turtle, graph-isomorphic to what was loaded.

Streamed from the rows, without a graph: the individuals are read in id ranges
(:data:`CHUNK` ids at a time, one query per table that has rows), each written as one Turtle
statement (``subject a Class ; p o ; ...``) through :class:`kb.io.turtle.TurtleWriter`; then
the statements outside the model tables (``kitkb_triple``), grouped by subject. Memory holds
one range of rows and the spelling of each individual's name. One read transaction (a
snapshot: SQLite's WAL, PostgreSQL ``REPEATABLE READ``) sees one state of the database.
"""

from __future__ import annotations

import io
import json
import shutil
import sqlite3
import tempfile
from pathlib import Path
from typing import IO, TYPE_CHECKING, Any, Callable, Iterator

from rdflib import BNode, Graph, Literal, URIRef

from kb.core.errors import InputError
from kb.core.files import atomic_paths
from kb.core.progress import SILENT, Progress
from kb.io.parsing import new_graph, parse_text
from kb.io.turtle import Names, TurtleWriter, string
from kb.world.bulk import quoted
from kb.world.database import DEFAULT_DB, check_version, normalize_url, open_engine, read_meta
from kb.world.plan import TablePlan, load_plan
from kb.world.values import ValueProblem, canonical, datatype_of, decimal_text, from_db, parse_lexical

if TYPE_CHECKING:
    from sqlalchemy.engine import Connection

Table = TablePlan

#: Individuals read per range.
CHUNK = 20_000
_XSD = "http://www.w3.org/2001/XMLSchema#"
_BARE = {_XSD + "decimal", _XSD + "integer", _XSD + "boolean"}  # canonical forms Turtle writes bare
_RDF_TYPE = "http://www.w3.org/1999/02/22-rdf-syntax-ns#type"

Spelling = tuple[str, "str | None", "str | None"]  # lexical, datatype, language


def dump(url: str | Path, out: str | Path, progress: Progress = SILENT) -> Path:
    """Write database ``url`` to ``out`` as Turtle (atomically: complete or not at all);
    ``progress``: where the individuals written report (:mod:`kb.core.progress`)."""
    with _reading(url) as conn, atomic_paths([out]) as (tmp,):
        with open(tmp, "w", encoding="utf-8", newline="\n") as f:
            write_turtle(conn, f, progress)
    return Path(out)


def read_graph(url: str | Path = DEFAULT_DB) -> Graph:
    """The content of database ``url`` as an rdflib graph (the statements :func:`dump` writes)."""
    buf = io.StringIO()
    with _reading(url) as conn:
        prefixes = write_turtle(conn, buf)
    triples = parse_text(buf.getvalue(), "turtle", Path("dump.ttl"))
    return new_graph(triples, prefixes)


class _reading:
    """A read transaction on database ``url`` (version checked), as a context manager."""

    def __init__(self, url: str | Path):
        self.url = normalize_url(url)

    def __enter__(self) -> Connection:
        self.engine = open_engine(self.url, must_exist=True)
        conn = None
        try:
            conn = self.engine.connect()
            if conn.dialect.name == "postgresql":
                conn = conn.execution_options(isolation_level="REPEATABLE READ")
            self.conn, self.tx = conn, conn.begin()
            check_version(conn, self.url)
        except BaseException:
            if conn is not None:
                conn.close()  # ends the transaction: nothing is left holding a lock
            self.engine.dispose()
            raise
        return conn

    def __exit__(self, kind: object, exc: object, tb: object) -> None:
        try:
            self.tx.rollback()
            self.conn.close()
        finally:
            self.engine.dispose()
        cause = getattr(exc, "orig", exc)  # SQLite's own error, or SQLAlchemy's wrapping of it
        if type(cause) is sqlite3.DatabaseError:  # exactly: a damaged file (not locked, not a bug's SQL)
            raise InputError(f"database {self.url} is damaged (SQLite: {cause}); restore it or load it again") \
                from None


def write_turtle(conn: Connection, out: IO[str], progress: Progress = SILENT) -> dict[str, str]:
    """Write the database open on ``conn`` to ``out`` as Turtle; the prefixes it declares."""
    prefixes = json.loads(read_meta(conn).get("prefixes", "{}"))
    names = Names(prefixes)
    with tempfile.TemporaryFile("w+", encoding="utf-8", newline="\n") as body:
        writer = TurtleWriter(body)
        dump = _Dump(conn, names, writer)
        dump.progress = progress
        dump.run()
        writer.flush()
        used = names.used() | dump.used
        declared = {p: ns for p, ns in sorted(prefixes.items()) if p in used}
        head = TurtleWriter(out)
        head.prefixes(declared.items())
        head.text("\n")
        head.flush()
        body.seek(0)
        shutil.copyfileobj(body, out)
    return declared


class _Dump:
    """One dump: spellings of the individuals, then the rows range by range."""

    progress: Progress = SILENT

    def __init__(self, conn: Connection, names: Names, writer: TurtleWriter):
        self.conn, self.names, self.writer, self.m = conn, names, writer, load_plan()
        self.dbapi = conn.connection.driver_connection
        self.pg = conn.dialect.name == "postgresql"
        self.param = "%s" if self.pg else "?"
        #: prefixes the individuals' names use (their spellings are not kept in ``names``' cache)
        self.used: set[str] = set()

    def cursor(self) -> Any:
        cur = self.dbapi.cursor()  # type: ignore[union-attr]
        if self.pg:  # NUMERIC as float (the stored value), not Decimal
            import psycopg2.extensions as ext

            ext.register_type(ext.new_type((1700,), "KITKB_NUMERIC", _pg_float), cur)
        return cur

    def run(self) -> None:
        tables = self._filled()
        spelled, kinds = self._individuals()
        self.spelled = spelled
        columns = [(t, self._columns(t)) for t in tables if "parent" in t.info and t.name != "kitkb_thing"]
        links = [(t, self._link(t)) for t in tables if t.info.get("link")]
        top = len(kinds) - 1
        with self.progress.task("writing the individuals", total=top, unit="individuals") as task:
            for lo in range(1, top + 1, CHUNK):
                self._chunk(lo, min(lo + CHUNK, top + 1), kinds, columns, links, tables)
                task.advance(min(CHUNK, top + 1 - lo))
        self._triples()

    def _filled(self) -> list[Table]:
        """The tables that have rows (one query)."""
        tables = list(self.m.tables.values())
        cur = self.cursor()
        cur.execute(" UNION ALL ".join(f"SELECT {i} FROM (SELECT 1 AS x FROM {quoted(t.name)} LIMIT 1) q{i}"
                                       for i, t in enumerate(tables)))
        found = {r[0] for r in cur.fetchall()}
        return [t for i, t in enumerate(tables) if i in found]

    def _individuals(self) -> tuple[list[str | None], list[str | None]]:
        """Each individual's spelled name and spelled class (``kind``; None: no type statement),
        indexed by id (one entry per id: lists, not dictionaries, as there are many)."""
        names = self.names
        spelled: list[str | None] = [None]
        kinds: list[str | None] = [None]
        spelled_kind: dict[str, str | None] = {"": None}
        cache, used = names.cache, self.used
        cur = self.cursor()
        cur.execute("SELECT id, iri, kind FROM kitkb_thing ORDER BY id")
        for id_, key, kind in cur:
            if id_ >= len(spelled):
                spelled.extend([None] * (id_ + 1 - len(spelled)))
                kinds.extend([None] * (id_ + 1 - len(kinds)))
            if key.startswith("_:"):
                text = names.term(BNode(key[2:]))
            else:
                text = names.iri(key)
                del cache[key]  # spelled once: no need to keep it in the shared cache
                if not text.startswith("<"):
                    used.add(text.split(":", 1)[0])
            spelled[id_] = text
            k = spelled_kind.get(kind, "")
            if k == "":
                k = spelled_kind[kind] = names.iri(kind)
            kinds[id_] = k
        return spelled, kinds

    def _columns(self, table: Table) -> list[tuple[str, str, Callable[[Any], str], dict[str, Any]]]:
        """(column, spelled property, formatter, info) of the columns that hold statements."""
        return [(c.name, self.names.iri(c.info["iri"]), self._formatter(c.info), c.info)
                for c in table.columns if "iri" in c.info]

    def _link(self, table: Table) -> tuple[str, str, Callable[[Any], str]]:
        info = table.info
        column = "value_id" if info["kind"] == "object" else "value"
        return column, self.names.iri(info["iri"]), self._formatter(info)

    def _formatter(self, info: dict[str, Any]) -> Callable[[Any], str]:
        kind = info["kind"]
        if kind == "object":
            return self._individual
        if kind == "iri":
            return self.names.iri
        return self._data_formatter(info)

    def _individual(self, id_: int) -> str:
        return self.spelled[id_]

    def _data_formatter(self, info: dict[str, Any]) -> Callable[[Any], str]:
        """The Turtle of a stored value's canonical literal (bare where Turtle has a short form)."""
        kind, dt = info.get("value", "text"), datatype_of(info)
        if dt is None:
            return string if kind == "text" else lambda v: string(canonical(from_db(v, info), info)[0])
        if kind == "decimal" and dt == _XSD + "decimal":
            return decimal_text
        if dt in _BARE:
            return lambda v: canonical(from_db(v, info), info)[0]
        suffix = "^^" + self.names.iri(dt)
        return lambda v: string(canonical(from_db(v, info), info)[0]) + suffix

    def _spelling(self, spelling: Spelling, value: Any, info: dict[str, Any]) -> str | None:
        """The stored spelling of a literal, while it still denotes the stored value."""
        lex, dt, lang = spelling
        try:
            if parse_lexical(info.get("value", "text"), lex) != from_db(value, info):
                return None
        except ValueProblem:
            return None
        return self.names.term(Literal(lex, datatype=URIRef(dt) if dt else None, lang=lang))

    # --- one range of individuals ----------------------------------------------------------------
    def _chunk(self, lo: int, hi: int, kinds: list[str | None], columns: list, links: list,
               tables: list[Table]) -> None:
        pairs: dict[int, list[tuple[str, str]]] = {}
        types: dict[int, list[str]] = {}
        names = self.names
        for id_ in range(lo, hi):
            kind = kinds[id_]
            if kind:
                types[id_] = [kind]
        filled = {t.name for t in tables}
        if "kitkb_type" in filled:
            for thing, cls in self._range("SELECT thing_id, class_iri FROM kitkb_type WHERE thing_id >= {p} AND "
                                          "thing_id < {p} ORDER BY thing_id, class_iri", lo, hi):
                types.setdefault(thing, []).append(names.iri(cls))
        originals = self._originals(lo, hi) if "kitkb_literal" in filled else {}
        for table, cols in columns:
            if cols:
                self._class_rows(table, cols, lo, hi, pairs, originals)
        for table, (column, prop, fmt) in links:
            for subject, value in self._range(f"SELECT subject_id, {quoted(column)} FROM {quoted(table.name)} WHERE "
                                              f"subject_id >= {{p}} AND subject_id < {{p}} ORDER BY subject_id, "
                                              f"{quoted(column)}", lo, hi):
                pairs.setdefault(subject, []).append((prop, fmt(value)))
        write, spelled = self.writer.statement, self.spelled
        for id_ in sorted(types.keys() | pairs.keys()):
            line = [("a", ", ".join(types[id_]))] if id_ in types else []
            line += pairs.get(id_, [])
            if line:  # an individual of a model only referred to (a row of its class, no statement of its own)
                write(spelled[id_], line)

    def _range(self, sql: str, lo: int, hi: int) -> Iterator[tuple[Any, ...]]:
        cur = self.cursor()
        cur.execute(sql.format(p=self.param), (lo, hi))
        return iter(cur.fetchall())

    def _originals(self, lo: int, hi: int) -> dict[tuple[int, str], Spelling]:
        rows = self._range("SELECT thing_id, property_iri, lexical, datatype, lang FROM kitkb_literal "
                           "WHERE thing_id >= {p} AND thing_id < {p}", lo, hi)
        return {(t, p): (lex, dt, lang) for t, p, lex, dt, lang in rows}

    def _class_rows(self, table: Table, cols: list, lo: int, hi: int, pairs: dict[int, list[tuple[str, str]]],
                    originals: dict[tuple[int, str], Spelling]) -> None:
        sql = (f"SELECT id, {quoted(*(c[0] for c in cols))} FROM {quoted(table.name)} "
               f"WHERE id >= {{p}} AND id < {{p}} ORDER BY id")
        spellable = {c[3]["iri"] for c in cols if c[3]["kind"] == "data"}
        check = any(p in spellable for _, p in originals)
        for row in self._range(sql, lo, hi):
            mine = pairs.get(row[0])
            if mine is None:
                mine = pairs[row[0]] = []
            for (_, prop, fmt, info), value in zip(cols, row[1:]):
                if value is None:
                    continue
                text = None
                if check and (row[0], info["iri"]) in originals:
                    text = self._spelling(originals[(row[0], info["iri"])], value, info)
                mine.append((prop, text or fmt(value)))

    # --- statements outside the model tables -----------------------------------------------------
    def _triples(self) -> None:
        term, writer = self.names.term, self.writer
        cur = self.dbapi.cursor("kitkb_dump_triples") if self.pg else self.cursor()  # type: ignore[union-attr]
        cur.execute("SELECT subject, predicate, object, object_kind, datatype, lang FROM kitkb_triple "
                    "ORDER BY subject, id")
        subject, pairs = None, []
        for s, p, o, kind, dt, lang in cur:
            if s != subject:
                if pairs:
                    writer.statement(_node(term, subject), pairs)  # type: ignore[arg-type]
                subject, pairs = s, []
            if kind == "literal":
                obj = term(Literal(o, datatype=URIRef(dt) if dt else None, lang=lang))
            else:
                obj = _node(term, o)
            pairs.append(("a" if p == _RDF_TYPE else term(URIRef(p)), obj))
        if pairs:
            writer.statement(_node(term, subject), pairs)  # type: ignore[arg-type]
        cur.close()


def _node(term: Callable[[Any], str], key: str) -> str:
    return term(BNode(key[2:]) if key.startswith("_:") else URIRef(key))


def _pg_float(value: str | None, _cur: Any) -> float | None:
    return None if value is None else float(value)
