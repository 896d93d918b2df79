"""Loading a data file into the world-model database: one transaction, at the speed of a bulk loader.

Every statement of a data file is kept (:mod:`.rows` says where each goes). The file is read
once as a stream of statements straight into rows (:mod:`.triples`, no rdflib graph), which
are written in bulk in one transaction (:mod:`.bulk`: ``executemany`` on SQLite, ``COPY`` on
PostgreSQL) into tables created bare; indexes are built and foreign keys checked once, after
the data (:mod:`.ddl`). A load that fails, or is killed, leaves the database as it was.

A database that already holds a world model (or run history) is only replaced when asked
(``replace=True``, ``kitkb db load --replace``); the report says what was replaced. A file
that defines no individual of the model is an input error, not an empty world.
"""

from __future__ import annotations

import datetime as _dt
import io
import json
import queue
import sqlite3 as _sqlite3
import threading
import uuid
from dataclasses import dataclass, field
from functools import partial
from pathlib import Path
from typing import Any, Callable


from kb.core.errors import InputError
from kb.core.memory import gc_paused
from kb.core.progress import SILENT, Progress
from kb.core.namespaces import PREFIXES, local_name
from kb.world import sqlite
from kb.world.bulk import copy_buffers, insert_sqlite
from kb.world.database import (DEFAULT_DB, SchemaVersionError, first_line, normalize_url, open_engine,
                               other_version, safe_url, sqlite_file, stamp_values)
from kb.world.ddl import kitkb_tables, load_ddl
from kb.world.lock import hold
from kb.world.plan import load_plan
from kb.world.rows import Built, RowBuilder
from kb.world.triples import DataFile

_CORE_PREFIXES = {"owl": "http://www.w3.org/2002/07/owl#",
                  "rdf": "http://www.w3.org/1999/02/22-rdf-syntax-ns#",
                  "rdfs": "http://www.w3.org/2000/01/rdf-schema#",
                  "xsd": "http://www.w3.org/2001/XMLSchema#"}
#: Key of the PostgreSQL advisory lock loads take (two loads into one database queue).
_PG_LOCK = 0x6B69746B62  # "kitkb"


@dataclass
class LoadReport:
    """What :func:`load` stored, and what it replaced."""

    individuals: int = 0
    statements: int = 0
    outside_model: int = 0
    tables: dict[str, int] = field(default_factory=dict)
    #: the world model the load replaced (None: the database was new or empty)
    replaced: str | None = None

    def summary(self) -> str:
        """One line for the command line."""
        line = (f"{self.statements} statements: {self.individuals} individuals in "
                f"{len(self.tables)} tables, {self.outside_model} statements outside the model tables")
        return line + (f"; replaced {self.replaced}" if self.replaced else "")


def build(datafile: str | Path, progress: Progress = SILENT) -> Built:
    """The rows of ``datafile``: every statement placed, checked, numbered (nothing written)."""
    with progress.task(f"reading {Path(datafile).name}", total=_size(datafile), unit="bytes") as task:
        data = DataFile(datafile, task if progress.enabled else None)
        with gc_paused():
            built = _rows(data, datafile)
    if not built.individuals:
        raise InputError("no individual of the kitting or SOAP model in this file (nothing typed with a "
                         "model class): refusing to load an empty world", file=str(datafile))
    return built


def _size(datafile: str | Path) -> int | None:
    try:
        return Path(datafile).stat().st_size
    except OSError:
        return None


def _rows(data: DataFile, datafile: str | Path) -> Built:
    builder = RowBuilder(data.terms, data.line_of, str(datafile))
    try:
        builder.feed(data.quads())
    except DataFile.PARSE_ERRORS as exc:
        error = data.parse_error(exc)
        if error is None:
            raise
        raise error from None
    return builder.finish(data.prefixes)


def load(datafile: str | Path, url: str | Path = DEFAULT_DB, replace: bool = False,
         progress: Progress = SILENT) -> LoadReport:
    """Load the statements of ``datafile`` into database ``url``, in one transaction.

    A database that already holds a world model or run history is refused unless ``replace``;
    then its world model and history are dropped in the same transaction as the load. On any
    error nothing changes (a new SQLite file is removed again). ``progress``: where reading
    the file and writing the rows report (:mod:`kb.core.progress`).
    """
    url = normalize_url(url)
    with hold(url, "a load"):  # not while a run (or another load) writes this world model
        return _load(datafile, url, replace, progress)


def _load(datafile: str | Path, url: str, replace: bool, progress: Progress = SILENT) -> LoadReport:
    target = sqlite_file(url)
    existed = target is None or target.exists()
    writer = _writer(url, replace)
    writer.progress = progress
    try:
        writer.check()  # before reading the file: refuse at once
        writer.start()
        try:
            built = build(datafile, progress)
        except BaseException:
            writer.abort()
            raise
        report = writer.finish(built, Path(datafile).name)
    except _DriverError as exc:
        _discard(writer, target, existed)
        raise InputError(f"database refused the data: {first_line(exc)}", file=str(datafile)) from None
    except BaseException:
        _discard(writer, target, existed)
        raise
    writer.dispose()
    return report


class _DriverError(Exception):
    """A database driver's error (wrapped so that one ``except`` catches sqlite3's and psycopg2's)."""

    def __init__(self, orig: BaseException):
        super().__init__(str(orig))
        self.orig = orig


def _discard(writer: "_Writer", path: Path | None, existed: bool) -> None:
    writer.dispose()
    if path is not None and not existed:
        for suffix in ("", "-wal", "-shm", "-journal"):
            try:
                Path(str(path) + suffix).unlink(missing_ok=True)
            except OSError:  # its folder could not be made: nothing there to remove
                pass


def _prefixes(file_prefixes: dict[str, str], built: Built) -> dict[str, str]:
    """Prefixes for dumps: the usual ones, kitkb's, the file's, and ``:`` for the namespace
    most individuals are named in (when the file does not declare one)."""
    out = {**_CORE_PREFIXES, **PREFIXES}
    taken = set(out.values())
    for name, iri in file_prefixes.items():
        if name not in out and iri not in taken:
            out[name] = iri
            taken.add(iri)
    if "" not in out:
        counts: dict[str, int] = {}
        for _, iri, _name, _kind in built.tables[0][2]:
            if not iri.startswith("_:"):
                ns = iri[: len(iri) - len(local_name(iri))]
                counts[ns] = counts.get(ns, 0) + 1
        if counts:
            out[""] = max(sorted(counts), key=lambda k: counts[k])
    return out


def _meta(built: Built, source: str) -> list[tuple[str, str]]:
    values = stamp_values(source=source, prefixes=json.dumps(_prefixes(built.prefixes, built), sort_keys=True),
                          loaded_at=_dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds"),
                          load_id=uuid.uuid4().hex,
                          individuals=str(built.individuals), statements=str(built.statements))
    return sorted(values.items())


def _report(built: Built, replaced: str | None) -> LoadReport:
    return LoadReport(individuals=built.individuals, statements=built.statements, outside_model=built.outside,
                      tables={name: len(rows) for name, _, rows in built.tables if rows}, replaced=replaced)


# --- what the database holds -------------------------------------------------------------------

def _describe(url: str, names: list[str], meta: dict[str, str], things: int | None,
              history: tuple[int, int]) -> str:
    """The world model a database holds, in words (for ``--replace`` and its refusal);
    ``history``: (rows, tables) of kitkb's tables beside the model's (the runs' records)."""
    parts = []
    if meta.get("schema_version") != load_plan().version:
        return "a world model made from another ontology version"
    if meta.get("source"):
        parts.append(f"from {meta['source']}")
    if meta.get("loaded_at"):
        parts.append(f"loaded {meta['loaded_at']}")
    count = meta.get("individuals") or (str(things) if things is not None else None)
    if count:
        parts.append(f"{int(count):,} individuals")
    parts.append(f"{int(meta.get('stable_state', '0') or 0)} stable states committed")
    if history[0]:
        parts.append(f"run history: {history[0]:,} rows in {history[1]} tables")
    return "the world model " + " ".join(parts[:1]) + (" (" + ", ".join(parts[1:]) + ")" if parts[1:] else "")


class _Writer:
    """One load's transaction on one kind of database (raw driver connection):
    :meth:`check` refuses early, :meth:`start` may begin the work while the file is read,
    :meth:`finish` writes the rows and commits, :meth:`abort` rolls back."""

    progress: Progress = SILENT

    def __init__(self, url: str, replace: bool, connect: Callable[[], Any], errors: tuple[type[BaseException], ...],
                 dispose: Callable[[], None]):
        self.url, self.replace, self._connect, self.errors, self.dispose = url, replace, connect, errors, dispose

    def connect(self) -> Any:
        """A raw connection (``driver_connection``, ``commit``, ``rollback``, ``close``)."""
        try:
            return self._connect()
        except self.errors as exc:
            raise _DriverError(exc) from None

    def check(self) -> None:
        """Refuse now (before the file is read) what the load would refuse."""
        raw = self.connect()
        try:
            cur = raw.driver_connection.cursor()
            self._existing(cur)
        except self.errors as exc:
            raise _DriverError(exc) from None
        finally:
            raw.rollback()
            raw.close()

    def start(self) -> None:
        """Begin what can be done before the rows exist (nothing, by default)."""

    def abort(self) -> None:
        """The rows will not come: change nothing."""

    def finish(self, built: Built, source: str) -> LoadReport:
        """Replace the database's kitkb tables with ``built``; commit, or change nothing."""
        raise NotImplementedError

    def _existing(self, cur: Any) -> tuple[list[str], str | None]:
        """(kitkb tables to drop, what they hold in words); refuses what may not be replaced."""
        names = self._tables(cur)
        if not names:
            return [], None
        url = self.url
        if "kitkb_meta" not in names:
            raise SchemaVersionError(f"database {safe_url(url)} is not a kitkb database (it has tables of its "
                                     f"own and no kitkb_meta table); it is left as it is: load into a new database")
        cur.execute("SELECT key, value FROM kitkb_meta")
        meta = {k: v for k, v in cur.fetchall()}
        things = None
        if "individuals" not in meta and "kitkb_thing" in names:
            cur.execute("SELECT count(*) FROM kitkb_thing")
            things = cur.fetchone()[0]
        rows = 0
        extra = [n for n in kitkb_tables(names) if n not in load_plan().tables]
        for name in extra:
            cur.execute(f'SELECT count(*) FROM "{name}"')
            rows += cur.fetchone()[0]
        what = _describe(url, names, meta, things, (rows, len(extra)))
        if not self.replace:
            why = other_version(url, meta) if meta.get("schema_version") != load_plan().version else \
                f"database {safe_url(url)} already holds {what}"
            raise InputError(f"{why}; kitkb db load --replace replaces it (and its run history)")
        return kitkb_tables(names), what

    def _tables(self, cur: Any) -> list[str]:
        raise NotImplementedError


class _SQLite(_Writer):
    """SQLite: all in :meth:`finish` (the write lock is taken once the rows are ready).

    A new file is filled with a rollback journal (``journal_mode=DELETE``, ``synchronous=FULL``:
    the pages are written once, into the file, and synced at commit) and switched to WAL after
    the commit; an existing database keeps WAL, so that its readers go on reading the old world
    model until the new one commits. Killed half way, a new file's journal rolls it back to empty.
    """

    #: the database file did not exist when the load began
    new = False

    def _tables(self, cur: Any) -> list[str]:
        cur.execute("SELECT name FROM sqlite_master WHERE type IN ('table', 'view') AND name NOT LIKE 'sqlite_%'")
        return [r[0] for r in cur.fetchall()]

    def check(self) -> None:
        if not self.new:  # a new file holds nothing to refuse (and is not made before the rows are ready)
            super().check()

    def finish(self, built: Built, source: str) -> LoadReport:
        raw = self.connect()
        try:
            cur = raw.driver_connection.cursor()
            cur.execute("PRAGMA foreign_keys = OFF")  # checked once below; cannot change inside a transaction
            if self.new:
                cur.execute("PRAGMA journal_mode = DELETE")
                cur.execute("PRAGMA synchronous = FULL")
            try:
                cur.execute("BEGIN IMMEDIATE")
                try:
                    report = self._fill(cur, built, source)
                    cur.execute("COMMIT")
                except BaseException:
                    cur.execute("ROLLBACK")
                    raise
                cur.execute("PRAGMA journal_mode = WAL")  # as every kitkb SQLite database
                cur.execute("PRAGMA synchronous = NORMAL")
                return report
            finally:
                cur.execute("PRAGMA foreign_keys = ON")
        except self.errors as exc:
            raise _DriverError(exc) from None
        finally:
            raw.close()

    def _fill(self, cur: Any, built: Built, source: str) -> LoadReport:
        drop, replaced = self._existing(cur)
        for name in drop:
            cur.execute(f'DROP TABLE "{name}"')
        ddl = load_ddl("sqlite")
        for stmt in ddl.create:
            cur.execute(stmt)
        rows = sum(len(r) for _, _, r in built.tables)
        with self.progress.task(f"writing {len(built.tables)} tables", total=rows, unit="rows") as task:
            insert_sqlite(cur, _advancing(built.tables, task))
        with self.progress.task("indexing", total=len(ddl.index), unit="indexes") as task:
            for stmt in ddl.index:
                cur.execute(stmt)
                task.advance()
        cur.execute("PRAGMA foreign_key_check")
        broken = cur.fetchmany(3)
        if broken:
            raise InputError("database refused the data: foreign keys without their rows: " +
                             ", ".join(f"{t} row {r} -> {p}" for t, r, p, _ in broken))
        cur.executemany("INSERT INTO kitkb_meta (key, value) VALUES (?, ?)", _meta(built, source))
        return _report(built, replaced)


def _advancing(tables: list[Any], task: Any) -> Any:
    """``tables`` (name, columns, rows), ``task`` advanced by each one's rows once it was written."""
    for table in tables:
        yield table
        task.advance(len(table[2]))


class _PostgreSQL(_Writer):
    """PostgreSQL: a worker thread owns the connection and runs the transaction's steps in order
    while this thread reads the file and formats the rows: psycopg2 lets other threads run while
    it waits for the server, so creating the tables (mostly the server's disk) overlaps reading
    the file, and each table's ``COPY`` overlaps formatting the next."""

    def _tables(self, cur: Any) -> list[str]:
        cur.execute("SELECT tablename FROM pg_tables WHERE schemaname = current_schema()")
        return [r[0] for r in cur.fetchall()]

    def start(self) -> None:
        self.raw = self.connect()
        self.cur = self.raw.driver_connection.cursor()
        self.jobs: queue.Queue[Any] = queue.Queue(maxsize=4)
        self.error: BaseException | None = None
        self.replaced: str | None = None
        self.worker = threading.Thread(target=self._work, name="kitkb-load", daemon=True)
        self.worker.start()
        self.jobs.put(self._prepare)

    def _work(self) -> None:
        while True:
            job = self.jobs.get()
            if job is None:
                return
            if self.error is None:
                try:
                    job()
                except BaseException as exc:  # noqa: BLE001 - handed to the loading thread
                    self.error = exc

    def _prepare(self) -> None:
        cur = self.cur
        cur.execute("SELECT pg_advisory_xact_lock(%s)", (_PG_LOCK,))
        drop, self.replaced = self._existing(cur)
        if drop:
            # no CASCADE: a view or a key of another application on kitkb's tables refuses the load
            try:
                cur.execute("DROP TABLE " + ", ".join(f'"{n}"' for n in drop))
            except self.errors as exc:
                if getattr(exc, "pgcode", None) != "2BP01":  # dependent_objects_still_exist
                    raise
                detail = getattr(getattr(exc, "diag", None), "message_detail", None) or first_line(exc)
                raise InputError(f"database {safe_url(self.url)}: objects of another application depend on "
                                 f"kitkb's tables ({detail.splitlines()[0]}); --replace leaves them as they are: "
                                 f"drop them first, or load into a new database") from None
        cur.execute(";\n".join(load_ddl("postgresql").create))

    def _stop(self) -> None:
        self.jobs.put(None)
        self.worker.join()

    def abort(self) -> None:
        self._stop()
        try:
            self.raw.rollback()
        finally:
            self.raw.close()

    def finish(self, built: Built, source: str) -> LoadReport:
        try:
            for sql, data in copy_buffers(built.tables):
                if self.error is not None:
                    break
                self.jobs.put(partial(self.cur.copy_expert, sql, io.BytesIO(data), 1 << 20))
            self.jobs.put(partial(self._complete, built, source))
            self._stop()
            if self.error is not None:
                raise self.error
            self.raw.commit()
            return _report(built, self.replaced)
        except BaseException as exc:
            if self.worker.is_alive():
                self._stop()
            self.raw.rollback()
            if isinstance(exc, self.errors):
                raise _DriverError(exc) from None
            raise
        finally:
            self.raw.close()

    def _complete(self, built: Built, source: str) -> None:
        cur, ddl = self.cur, load_ddl("postgresql")
        cur.execute(";\n".join(ddl.index + ddl.keys))
        cur.execute("SELECT setval(pg_get_serial_sequence('kitkb_thing', 'id'), %s)",
                    (max(r[0] for r in built.tables[0][2]),))
        cur.executemany("INSERT INTO kitkb_meta (key, value) VALUES (%s, %s)", _meta(built, source))
        filled = sorted({name for name, _, rows in built.tables if rows} | {"kitkb_meta"})
        cur.execute("ANALYZE " + ", ".join(filled))  # fresh statistics, or the planner scans whole tables


class _Direct:
    """An sqlite3 connection opened without SQLAlchemy, with the face of SQLAlchemy's raw connections."""

    def __init__(self, conn: Any):
        self.driver_connection = conn

    def commit(self) -> None:
        self.driver_connection.commit()

    def rollback(self) -> None:
        self.driver_connection.rollback()

    def close(self) -> None:
        self.driver_connection.close()


def _writer(url: str, replace: bool) -> _Writer:
    """The writer for database ``url``: an SQLite file is opened by the driver itself (no
    SQLAlchemy import: 0.1 s of a load), anything else through an SQLAlchemy engine."""
    path = sqlite.plain_file(url)
    if path is not None:
        new = not sqlite.check_file(path, url)  # missing or 0 bytes: nothing in it to keep
        writer = _SQLite(url, replace, lambda: _Direct(sqlite.connect(path, url, wal=not new)), (_sqlite3.Error,),
                         lambda: None)
        writer.new = new
        return writer
    from sqlalchemy.exc import SQLAlchemyError

    engine = open_engine(url)
    errors = (engine.dialect.dbapi.Error, SQLAlchemyError)  # type: ignore[union-attr]
    if engine.dialect.name == "sqlite":
        return _SQLite(url, replace, engine.raw_connection, errors, engine.dispose)
    if engine.dialect.name == "postgresql" and engine.dialect.driver == "psycopg2":
        return _PostgreSQL(url, replace, engine.raw_connection, errors, engine.dispose)
    engine.dispose()
    raise InputError(f"kitkb loads SQLite files and PostgreSQL (psycopg2) databases, not "
                     f"{engine.dialect.name}+{engine.dialect.driver}")
