"""The world-model database: opening it (SQLite file or PostgreSQL URL), its version stamp,
and how terms are keyed in it.

A database carries the fingerprint of the schema it was made with (``kitkb_meta``); one made
from another ontology version is refused with :class:`SchemaVersionError`. SQLite runs with
real transactions (``BEGIN IMMEDIATE`` for writers), foreign keys on and WAL for files
(:mod:`kb.world.sqlite`).

SQLAlchemy is imported by the functions that use it, not with this module: ``kitkb db load``
into an SQLite file does without it (:mod:`kb.world.load`).
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import TYPE_CHECKING, Any

from kb import __version__
from kb.core.errors import InputError
from kb.core.files import note_database
from kb.world import sqlite
from kb.world.plan import load_plan

if TYPE_CHECKING:
    from sqlalchemy import Engine
    from sqlalchemy.engine import Connection

#: Name of the SQLite file used when no database is given.
DEFAULT_DB = "kitkb.sqlite"


class SchemaVersionError(InputError):
    """The database was made from another version of the ontology (or is not kitkb's)."""


# --- opening a database -------------------------------------------------------------------------

def normalize_url(url: str | Path) -> str:
    """An SQLAlchemy URL; a plain path means an SQLite file."""
    text = str(url)
    if "://" in text or text.startswith("sqlite:"):
        return text
    return f"sqlite:///{Path(text).resolve()}"


def safe_url(url: str) -> str:
    """``url`` with any password hidden, for messages."""
    if "@" not in url:  # no credentials (SQLite files)
        return url
    from sqlalchemy.engine import make_url
    from sqlalchemy.exc import ArgumentError

    try:
        return make_url(url).render_as_string(hide_password=True)
    except ArgumentError:
        return url


def open_engine(url: str | Path, must_exist: bool = False) -> Engine:
    """An engine on ``url`` (SQLAlchemy URL or SQLite path); one-line :class:`InputError` if unusable.

    ``must_exist``: refuse an SQLite file that does not exist (instead of creating it).
    """
    from sqlalchemy import create_engine
    from sqlalchemy.engine import make_url
    from sqlalchemy.exc import ArgumentError, DBAPIError, NoSuchModuleError, SQLAlchemyError

    url = normalize_url(url)
    path = sqlite_file(url) if "://" in url else None
    if must_exist and path is not None and not path.is_file():
        raise InputError(f"no such database file: {path}")
    if path is not None:
        note_database(path)  # an existing file; a new one is noted once created, below
        sqlite.check_file(path, url)  # not an SQLite file (a Turtle file): refused untouched
        sqlite.make_folder(path)
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
        raise InputError(f"bad database URL {safe_url(url)!r}: {first_line(exc)}") from None
    except (DBAPIError, SQLAlchemyError) as exc:
        raise InputError(f"cannot open database {safe_url(url)}: {first_line(exc)}") from None
    except ImportError as exc:
        raise InputError(f"cannot open database {safe_url(url)}: missing driver ({exc.name})") from None
    if path is not None:
        note_database(path)
    return engine


def first_line(exc: BaseException) -> str:
    """The first line of a driver error (what a one-line message shows)."""
    orig = getattr(exc, "orig", None) or exc
    text = str(orig).strip().splitlines()
    return text[0] if text else type(orig).__name__


def _sqlite_transactions(engine: Engine, database: str) -> None:
    """Real transactions on SQLite: BEGIN before DDL too, foreign keys on, WAL for files."""
    from sqlalchemy import event

    @event.listens_for(engine, "connect")
    def _connect(dbapi_conn: Any, _record: Any) -> None:
        sqlite.settings(dbapi_conn, database)

    @event.listens_for(engine, "begin")
    def _begin(conn: Connection) -> None:
        # A writer takes the write lock at BEGIN, so two writers queue instead of deadlocking.
        conn.exec_driver_sql("BEGIN IMMEDIATE" if conn.get_execution_options().get("kitkb_write") else "BEGIN")


def writing(conn: Connection) -> Connection:
    """``conn`` marked as a writer (SQLite takes the write lock when it begins)."""
    return conn.execution_options(kitkb_write=True)


# --- version stamp ------------------------------------------------------------------------------

def stamp_values(**extra: str) -> dict[str, str]:
    """The ``kitkb_meta`` entries of a new world model: schema fingerprint, ontology and kitkb
    versions, the stable-state counter at 0, and ``extra`` (source file, prefixes...)."""
    m = load_plan()
    return {"schema_version": m.version, "ontologies": json.dumps(m.ontologies),
            "kitkb_version": __version__, "stable_state": "0", **extra}


def read_meta(conn: Connection) -> dict[str, str]:
    """The ``kitkb_meta`` entries."""
    from sqlalchemy import select

    from kb.world.schema import model

    meta = model().table("kitkb_meta")
    return {k: v for k, v in conn.execute(select(meta.c.key, meta.c.value))}


def check_version(conn: Connection, url: str) -> None:
    """Refuse a database that is not kitkb's or was made from another ontology version."""
    from sqlalchemy import inspect

    names = set(inspect(conn).get_table_names())
    if "kitkb_meta" not in names:
        what = "is empty (load a data file first: kitkb db load FILE --db URL)" if not names else \
            "is not a kitkb database (it has no kitkb_meta table)"
        raise SchemaVersionError(f"database {safe_url(url)} {what}")
    meta = read_meta(conn)
    if meta.get("schema_version") != load_plan().version:
        raise SchemaVersionError(other_version(url, meta) + ": load the data again into a new database")


def other_version(url: str, meta: dict[str, str]) -> str:
    """What is wrong with a database made from another ontology version (no advice)."""
    m = load_plan()
    made = _versions(meta.get("ontologies", "[]"))
    now = ", ".join(f"{i.rsplit('/', 1)[-1]} {v}" for i, v in m.ontologies)
    return (f"database {safe_url(url)} was made from another ontology version ({made}, schema "
            f"{meta.get('schema_version', '?')}); this kitkb uses {now} (schema {m.version})")


def _versions(text: str) -> str:
    try:
        return ", ".join(f"{i.rsplit('/', 1)[-1]} {v}" for i, v in json.loads(text)) or "unknown ontologies"
    except (ValueError, TypeError):
        return "unknown ontologies"


def sqlite_file(url: str) -> Path | None:
    """The file of an SQLite URL (None for another database or an in-memory one)."""
    if not url.startswith("sqlite"):
        return None
    plain = sqlite.plain_file(url)
    if plain is not None:
        return plain
    from sqlalchemy.engine import make_url
    from sqlalchemy.exc import ArgumentError

    try:
        parsed = make_url(url)
    except ArgumentError:
        return None
    if parsed.get_backend_name() == "sqlite" and parsed.database not in (None, "", ":memory:"):
        return Path(parsed.database)
    return None


def drop_all(url: str | Path) -> None:
    """Drop every table of database ``url`` (kitkb's and any other): a clean slate for tests.

    One transaction; on PostgreSQL one ``DROP TABLE ... CASCADE`` of the tables of the current
    schema (reflecting them first took seconds)."""
    engine = open_engine(url)
    try:
        if engine.dialect.name == "sqlite":
            _drop_sqlite(engine)
            return
        with writing(engine.connect()) as conn, conn.begin():
            if engine.dialect.name == "postgresql":
                names = [r[0] for r in conn.exec_driver_sql(
                    "SELECT tablename FROM pg_tables WHERE schemaname = current_schema()")]
                if names:
                    conn.exec_driver_sql("DROP TABLE " + ", ".join(f'"{n}"' for n in names) + " CASCADE")
            else:
                from sqlalchemy import MetaData

                meta = MetaData()
                meta.reflect(conn)
                meta.drop_all(conn)
    finally:
        engine.dispose()


def _drop_sqlite(engine: Engine) -> None:
    """Drop every table of an SQLite database in one transaction, foreign keys off (a DROP
    would otherwise delete and check every row first)."""
    raw = engine.raw_connection()
    try:
        cur = raw.driver_connection.cursor()  # type: ignore[union-attr]
        cur.execute("PRAGMA foreign_keys = OFF")
        cur.execute("BEGIN IMMEDIATE")
        try:
            cur.execute("SELECT name FROM sqlite_master WHERE type = 'table' AND name NOT LIKE 'sqlite_%'")
            for (name,) in cur.fetchall():
                cur.execute(f'DROP TABLE "{name}"')
            cur.execute("COMMIT")
        except BaseException:
            cur.execute("ROLLBACK")
            raise
        finally:
            cur.execute("PRAGMA foreign_keys = ON")
    finally:
        raw.close()


def model() -> Any:
    """The SQLAlchemy model of the schema (:func:`kb.world.schema.model`; imported on use)."""
    from kb.world.schema import model as schema_model

    return schema_model()
