"""The DDL of a bulk load, compiled by SQLAlchemy for the database's dialect.

A load creates the tables bare, fills them, then builds the indexes and checks the foreign
keys once, all in its one transaction (:mod:`kb.world.load`):

* PostgreSQL: ``CREATE TABLE`` without foreign keys or secondary indexes; after the data,
  ``CREATE INDEX`` and ``ALTER TABLE ... ADD CONSTRAINT ... FOREIGN KEY`` (each checks the
  rows already there in one pass; the keys stay ``DEFERRABLE INITIALLY DEFERRED``).
* SQLite cannot add a foreign key to a table, so they are written in ``CREATE TABLE`` as
  before; the load runs with ``PRAGMA foreign_keys = OFF`` and ends with
  ``PRAGMA foreign_key_check`` (every key, one pass), indexes built after the data.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from typing import Any

from kb.world.cache import cached

#: Table name prefixes of kitkb's tables (what ``--replace`` drops, whatever the schema version).
PREFIXES = ("kitkb_", "ktw_", "soap_")


@dataclass(frozen=True)
class LoadDDL:
    """Statements of a load, in order: ``create`` before the data, ``index`` and ``keys`` after."""

    create: tuple[str, ...]
    index: tuple[str, ...]
    keys: tuple[str, ...]


def _dialect(name: str) -> Any:
    if name == "postgresql":
        from sqlalchemy.dialects import postgresql

        return postgresql.dialect()  # type: ignore[no-any-return]
    from sqlalchemy.dialects import sqlite

    return sqlite.dialect()  # type: ignore[no-any-return]


@lru_cache(maxsize=None)
def load_ddl(dialect_name: str) -> LoadDDL:
    """The statements for ``sqlite`` or ``postgresql`` (compiled once, kept in :mod:`kb.world.cache`)."""
    found = cached(f"ddl-{dialect_name}", lambda: _compile(dialect_name))
    return found if isinstance(found, LoadDDL) else _compile(dialect_name)


def _compile(dialect_name: str) -> LoadDDL:
    from sqlalchemy.schema import AddConstraint, CreateIndex, CreateTable

    from kb.patches.sqlalchemy import ddl_scope
    from kb.world.schema import model

    dialect = _dialect(dialect_name)
    inline = not dialect.supports_alter
    with ddl_scope(model().metadata) as meta:
        tables = meta.sorted_tables
        create = tuple(str(CreateTable(t, include_foreign_key_constraints=t.foreign_key_constraints if inline else [])
                           .compile(dialect=dialect)).strip() for t in tables)
        index = tuple(str(CreateIndex(i).compile(dialect=dialect)).strip()
                      for t in tables for i in sorted(t.indexes, key=lambda i: i.name or ""))
        keys = () if inline else tuple(
            str(AddConstraint(fk).compile(dialect=dialect)).strip()
            for t in tables for fk in sorted(t.foreign_key_constraints, key=lambda c: str(c.name)))
    return LoadDDL(create, index, keys)


def kitkb_tables(names: list[str]) -> list[str]:
    """The names among ``names`` that are kitkb's tables (by prefix)."""
    return [n for n in names if n.startswith(PREFIXES)]
