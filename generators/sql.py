"""SQL schema generator: the relational model as SQLAlchemy metadata and as DDL for a dialect.

``SqlGenerator(dialect="postgresql").serialize()`` is the ``CREATE TABLE`` script of the
kitting and SOAP ontologies. No SQL text is assembled by hand: tables, CHECK constraints and
foreign keys are SQLAlchemy objects, compiled with ``CreateTable(...).compile(dialect=...)``.
"""

from __future__ import annotations

import re
from typing import Any, ClassVar

from sqlalchemy import (Boolean, CheckConstraint, Column, Date, DateTime, Float, ForeignKey,
                        Integer, MetaData, Numeric, String, Table, Text, column, literal)
from sqlalchemy.dialects import mysql, postgresql, sqlite
from sqlalchemy.engine import Dialect
from sqlalchemy.schema import AddConstraint, CreateIndex, CreateTable
from sqlalchemy.types import TypeEngine

from kb.core.errors import InputError
from kb.core.generators import Generator
from kb.patches.sqlalchemy import ddl_scope

from generators.sql_model import (THING_TABLE, ColumnSpec, LinkSpec, Schema, ValueType, column_info,
                                  shipped_schema)

#: Length of IRI columns (indexable as VARCHAR on every dialect, MySQL included).
IRI_LENGTH = 760

#: Names of constraints, so that the DDL is the same on every run and every dialect.
NAMING_CONVENTION = {
    "pk": "pk_%(table_name)s",
    "fk": "fk_%(table_name)s_%(column_0_name)s",
    "uq": "uq_%(table_name)s_%(column_0_name)s",
    "ck": "ck_%(table_name)s_%(constraint_name)s",
    "ix": "ix_%(table_name)s_%(column_0_name)s",
}

DIALECTS: dict[str, Any] = {
    "sqlite": sqlite.dialect,
    "postgresql": postgresql.dialect,
    "mysql": mysql.dialect,
}

#: Tables kitkb keeps next to the class tables (version stamp, triples outside the model).
META_TABLE = "kitkb_meta"
TYPE_TABLE = "kitkb_type"
TRIPLE_TABLE = "kitkb_triple"
LITERAL_TABLE = "kitkb_literal"


def sql_type(value: ValueType) -> TypeEngine[Any]:
    """The SQLAlchemy type of a stored value."""
    if value.kind == "boolean":
        return Boolean()
    if value.kind == "integer":
        return Integer()
    if value.kind == "decimal":
        exact = mysql.DECIMAL(precision=38, scale=12, asdecimal=False)
        return Numeric(asdecimal=False).with_variant(exact, "mysql")
    if value.kind == "float":
        return Float()
    if value.kind == "datetime":
        return DateTime(timezone=True)
    if value.kind == "date":
        return Date()
    if value.kind == "iri" or value.enum:
        return String(IRI_LENGTH)
    return Text()


def _checks(name: str, value: ValueType) -> list[CheckConstraint]:
    col = column(name)
    out = []
    if value.enum:
        out.append(CheckConstraint(col.in_(list(value.enum)), name=f"{name}_in"))
    ops = {"gt": col.__gt__, "ge": col.__ge__, "lt": col.__lt__, "le": col.__le__}
    for op, bound in value.checks:
        number = int(bound) if value.kind == "integer" else float(bound)
        label = re.sub(r"\W", "_", bound).strip("_")
        out.append(CheckConstraint(ops[op](literal(number)), name=f"{name}_{op}_{label}"))
    return out


_DEFERRABLE = True  # switched off while building MySQL metadata (MySQL has no deferrable keys)


def _fk(target: str, alter: bool = True) -> ForeignKey:
    # Deferred: objects refer to each other in cycles (an object and its location), so a
    # load inserts all rows first and the database checks references at commit. Such keys
    # are added by ALTER TABLE after all tables exist (inline on SQLite, which cannot alter).
    if not _DEFERRABLE:
        return ForeignKey(f"{target}.id", use_alter=alter)
    return ForeignKey(f"{target}.id", deferrable=True, initially="DEFERRED", use_alter=alter)


def _column(spec: ColumnSpec) -> Column[Any]:
    info = column_info(spec)
    if spec.kind == "object":
        return Column(spec.name, Integer, _fk(spec.target or THING_TABLE), nullable=spec.nullable,
                      unique=spec.unique or None, index=not spec.unique, info=info)
    return Column(spec.name, sql_type(spec.value), nullable=spec.nullable, info=info)


def _link_table(meta: MetaData, link: LinkSpec) -> Table:
    if link.kind == "object":
        value = Column("value_id", Integer, _fk(link.target or THING_TABLE), primary_key=True)
    else:
        value = Column("value", sql_type(link.value), primary_key=True, autoincrement=False)
        if isinstance(value.type, Text):  # text cannot be a key on every dialect
            value.type = String(IRI_LENGTH)
    return Table(link.name, meta,
                 Column("subject_id", Integer, _fk(link.domain), primary_key=True, autoincrement=False),
                 value, *(_checks(value.name, link.value) if link.kind == "data" else []),
                 info={**column_info(link), "link": True})


def build_metadata(schema: Schema, deferrable: bool = True) -> MetaData:
    """SQLAlchemy metadata of ``schema``: class tables, link tables and kitkb's own tables.

    ``deferrable=False`` leaves out DEFERRABLE on foreign keys (for MySQL, which lacks it).
    """
    global _DEFERRABLE
    _DEFERRABLE = deferrable
    try:
        return _build_metadata(schema)
    finally:
        _DEFERRABLE = True


def _build_metadata(schema: Schema) -> MetaData:
    meta = MetaData(naming_convention=NAMING_CONVENTION, info={"version": schema.fingerprint()})
    for spec in schema.tables:
        cols: list[Any] = [Column("id", Integer, primary_key=True, autoincrement=spec.name == THING_TABLE)
                           if spec.name == THING_TABLE else
                           Column("id", Integer, _fk(spec.parent, alter=False), primary_key=True, autoincrement=False)]
        if spec.name == THING_TABLE:
            cols += [Column("iri", String(IRI_LENGTH), nullable=False, unique=True),
                     Column("name", String(IRI_LENGTH), nullable=False, index=True),
                     Column("kind", String(IRI_LENGTH), nullable=False, index=True)]
        for c in spec.columns:
            cols.append(_column(c))
            if c.kind == "data":
                cols += _checks(c.name, c.value)
        Table(spec.name, meta, *cols, comment=spec.comment or None,
              info={"iri": spec.class_iri, "parent": spec.parent})
    for link in schema.links:
        _link_table(meta, link)
    _kitkb_tables(meta)
    return meta


def _kitkb_tables(meta: MetaData) -> None:
    iri = lambda name, **kw: Column(name, String(IRI_LENGTH), **kw)  # noqa: E731
    Table(META_TABLE, meta, Column("key", String(100), primary_key=True), Column("value", Text, nullable=False),
          comment="Version stamp of the schema and other facts about the database.")
    Table(TYPE_TABLE, meta, Column("thing_id", Integer, _fk(THING_TABLE), primary_key=True, autoincrement=False),
          iri("class_iri", primary_key=True),
          comment="Asserted types of an individual other than its most specific model class.")
    Table(LITERAL_TABLE, meta,
          Column("thing_id", Integer, _fk(THING_TABLE), primary_key=True, autoincrement=False),
          iri("property_iri", primary_key=True), Column("lexical", Text, nullable=False),
          iri("datatype"), Column("lang", String(40)),
          comment="Original spelling of literals whose stored value prints differently.")
    Table(TRIPLE_TABLE, meta, Column("id", Integer, primary_key=True),
          iri("subject", nullable=False, index=True), iri("predicate", nullable=False),
          Column("object", Text, nullable=False), Column("object_kind", String(8), nullable=False),
          iri("datatype"), Column("lang", String(40)),
          CheckConstraint(Column("object_kind").in_(["iri", "bnode", "literal"]), name="kind_in"),
          comment="Statements outside the model's tables (ontology header, annotations, foreign terms).")


def ddl(meta: MetaData, dialect_name: str) -> str:
    """The ``CREATE TABLE`` / ``CREATE INDEX`` script of ``meta`` for one dialect, leaving
    ``meta`` usable for other dialects (:func:`kb.patches.sqlalchemy.ddl_scope`)."""
    with ddl_scope(meta) as scoped:
        return _ddl(scoped, _dialect(dialect_name))


def _ddl(meta: MetaData, dialect: Dialect) -> str:
    parts = []
    for table in meta.sorted_tables:
        parts.append(str(CreateTable(table).compile(dialect=dialect)).strip() + ";")
        for index in sorted(table.indexes, key=lambda i: i.name or ""):
            parts.append(str(CreateIndex(index).compile(dialect=dialect)).strip() + ";")
    if dialect.supports_alter:
        for table in meta.sorted_tables:
            for fk in sorted(table.foreign_key_constraints, key=lambda c: str(c.name)):
                if fk.use_alter:
                    parts.append(str(AddConstraint(fk).compile(dialect=dialect)).strip() + ";")
    return "\n\n".join(parts) + "\n"


def _dialect(name: str) -> Dialect:
    try:
        return DIALECTS[name]()
    except KeyError:
        raise InputError(f"unknown SQL dialect {name!r} (known: {', '.join(sorted(DIALECTS))})") from None


class SqlGenerator(Generator):
    """``CREATE TABLE`` script of the shipped kitting and SOAP ontologies for one SQL dialect."""

    name: ClassVar[str] = "sql"
    file_extension: ClassVar[str] = ".sql"

    def __init__(self, dialect: str = "sqlite", schema: Schema | None = None):
        _dialect(dialect)  # fail early on an unknown name
        self.dialect = dialect
        self.schema = schema or shipped_schema()

    def serialize(self) -> str:
        """The DDL script (deterministic)."""
        header = (f"-- kitkb schema {self.schema.fingerprint()} for {self.dialect}, generated from "
                  + ", ".join(f"{iri} {ver}".strip() for iri, ver in self.schema.ontologies) + "\n\n")
        # a metadata of its own: nothing else sees what DDL compilation does to it
        meta = build_metadata(self.schema, deferrable=self.dialect != "mysql")
        return header + _ddl(meta, _dialect(self.dialect))
