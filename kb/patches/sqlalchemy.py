"""kitkb's change to SQLAlchemy's internals (checked on SQLAlchemy 2.1.9).

:data:`DDL_SCOPE`: SQLAlchemy's ``AddConstraint`` (emitted by DDL compilation and by
``create_all`` on dialects with ALTER) marks a foreign key as "not part of CREATE TABLE" for
good, in the private ``ForeignKeyConstraint._create_rule``; a later CREATE TABLE on SQLite
from the same metadata then silently lacks that foreign key. :func:`ddl_scope` saves and
restores the mark, so one metadata serves every dialect in one process. Stock: the DDL is
run on a fresh copy of the metadata (the same tables; the shared one is never touched).

Differential test: ``tests/test_sql_schema.py`` (PostgreSQL DDL, then SQLite tables with
every foreign key) and ``tests/test_patches.py`` (same DDL with the patch off).
"""

from __future__ import annotations

from contextlib import contextmanager
from typing import Iterator

from sqlalchemy import MetaData

from kb.patches.gate import Patch

DDL_SCOPE = Patch("SQLAlchemy", "2.1.9", "2.2", "DDL leaves the shared metadata's foreign keys as they were")
PATCHES = [DDL_SCOPE]


@contextmanager
def ddl_scope(meta: MetaData) -> Iterator[MetaData]:
    """The metadata to emit DDL from: ``meta`` itself, restored afterwards (:data:`DDL_SCOPE`),
    or a copy of it where the patch does not apply."""
    if not DDL_SCOPE.active():
        copy = MetaData(naming_convention=dict(meta.naming_convention))
        for table in meta.sorted_tables:
            table.to_metadata(copy)
        yield copy
        return
    fks = [fk for table in meta.tables.values() for fk in table.foreign_key_constraints]
    saved = [fk._create_rule for fk in fks]
    try:
        yield meta
    finally:
        for fk, rule in zip(fks, saved):
            fk._create_rule = rule
