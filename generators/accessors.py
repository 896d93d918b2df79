"""Typed accessors generator: the relational model as a SQLAlchemy 2.0 declarative module.

The output (checked in as ``kb/world/generated/accessors.py``) has one ``Mapped[...]`` class per
ontology class, joined-table inheritance following the class hierarchy, a typed column per
single-valued property, a relationship per object property and a ``list`` relationship per
link table. Its metadata is the same schema :mod:`generators.sql` emits (a test compares the
DDL). Output is deterministic: the same ontology gives the same text.

Regenerate with ``python -m generators.accessors -o kb/world/generated/accessors.py``.
"""

from __future__ import annotations

import argparse
import re
from typing import ClassVar

from kb.core.generators import Generator
from generators.sql_model import (THING_TABLE, ColumnSpec, LinkSpec, Schema, TableSpec, ValueType, column_info,
                                  shipped_schema)

_PY_TYPES = {"boolean": "bool", "integer": "int", "decimal": "float", "float": "float",
             "datetime": "datetime.datetime", "date": "datetime.date", "iri": "str", "text": "str"}
_SQL_TYPES = {"boolean": "Boolean()", "integer": "Integer()", "decimal": "_DECIMAL", "float": "Float()",
              "datetime": "DateTime(timezone=True)", "date": "Date()", "iri": "_IRI", "text": "Text()"}

_HEADER = '''\
"""Typed accessors of the kitkb world-model database. GENERATED: do not edit by hand.

Made by generators/accessors.py from {sources}.
Regenerate: python -m generators.accessors -o kb/world/generated/accessors.py
One class per ontology class (joined-table inheritance); see docs/database.md.
"""

from __future__ import annotations

import datetime

from sqlalchemy import (Boolean, CheckConstraint, Column, Date, DateTime, Float, ForeignKey, Integer,
                        MetaData, Numeric, String, Table, Text, column, literal)
from sqlalchemy.dialects import mysql
from sqlalchemy.orm import DeclarativeBase, Mapped, foreign, mapped_column, relationship, remote

#: Fingerprint of the schema; a database stamped with another one is refused.
SCHEMA_VERSION = {version!r}
#: (ontology IRI, owl:versionInfo) of the ontologies the schema was made from.
ONTOLOGIES = {ontologies!r}

_IRI = String(760)
_DECIMAL = Numeric(asdecimal=False).with_variant(mysql.DECIMAL(precision=38, scale=12, asdecimal=False), "mysql")


def _ref(table: str, alter: bool = True) -> ForeignKey:
    """A deferred foreign key to ``table.id`` (checked at commit; cycles are allowed)."""
    return ForeignKey(f"{{table}}.id", deferrable=True, initially="DEFERRED", use_alter=alter)


class Base(DeclarativeBase):
    """Declarative base of the generated classes."""

    metadata = MetaData(naming_convention={{
        "pk": "pk_%(table_name)s",
        "fk": "fk_%(table_name)s_%(column_0_name)s",
        "uq": "uq_%(table_name)s_%(column_0_name)s",
        "ck": "ck_%(table_name)s_%(constraint_name)s",
        "ix": "ix_%(table_name)s_%(column_0_name)s",
    }}, info={{"version": SCHEMA_VERSION}})


# --- kitkb's own tables ---------------------------------------------------------------------

Table("kitkb_meta", Base.metadata, Column("key", String(100), primary_key=True),
      Column("value", Text, nullable=False),
      comment="Version stamp of the schema and other facts about the database.")
Table("kitkb_type", Base.metadata,
      Column("thing_id", Integer, _ref("kitkb_thing"), primary_key=True, autoincrement=False),
      Column("class_iri", _IRI, primary_key=True),
      comment="Asserted types of an individual other than its most specific model class.")
Table("kitkb_literal", Base.metadata,
      Column("thing_id", Integer, _ref("kitkb_thing"), primary_key=True, autoincrement=False),
      Column("property_iri", _IRI, primary_key=True), Column("lexical", Text, nullable=False),
      Column("datatype", _IRI), Column("lang", String(40)),
      comment="Original spelling of literals whose stored value prints differently.")
Table("kitkb_triple", Base.metadata, Column("id", Integer, primary_key=True),
      Column("subject", _IRI, nullable=False, index=True), Column("predicate", _IRI, nullable=False),
      Column("object", Text, nullable=False), Column("object_kind", String(8), nullable=False),
      Column("datatype", _IRI), Column("lang", String(40)),
      CheckConstraint(column("object_kind").in_(["iri", "bnode", "literal"]), name="kind_in"),
      comment="Statements outside the model's tables (ontology header, annotations, foreign terms).")
'''

_THING = '''

class Thing(Base):
    """{comment}"""

    __tablename__ = "kitkb_thing"
    __table_args__ = {{"comment": {comment!r}, "info": {{"iri": "", "parent": ""}}}}
    __mapper_args__ = {{"polymorphic_on": "kind", "polymorphic_identity": ""}}

    id: Mapped[int] = mapped_column(Integer, primary_key=True, autoincrement=True)
    iri: Mapped[str] = mapped_column(_IRI, unique=True)
    name: Mapped[str] = mapped_column(_IRI, index=True)
    kind: Mapped[str] = mapped_column(_IRI, index=True)
'''


def _py_type(value: ValueType, nullable: bool) -> str:
    base = _PY_TYPES[value.kind]
    return f"{base} | None" if nullable else base


def _checks(name: str, value: ValueType) -> list[str]:
    out = []
    if value.enum:
        out.append(f"CheckConstraint(column({name!r}).in_({list(value.enum)!r}), name={name + '_in'!r})")
    ops = {"gt": ">", "ge": ">=", "lt": "<", "le": "<="}
    for op, bound in value.checks:
        number = repr(int(bound)) if value.kind == "integer" else repr(float(bound))
        label = re.sub(r"\W", "_", bound).strip("_")
        out.append(f"CheckConstraint(column({name!r}) {ops[op]} literal({number}), "
                   f"name={f'{name}_{op}_{label}'!r})")
    return out


class _Writer:
    """Renders the module text from the schema."""

    def __init__(self, schema: Schema):
        self.schema = schema
        self.classes = {t.name: t.class_name for t in schema.tables}
        self.links: dict[str, list[LinkSpec]] = {}
        for link in schema.links:
            self.links.setdefault(link.domain, []).append(link)

    def write(self) -> str:
        s = self.schema
        sources = ", ".join(f"{iri} {ver}".strip() for iri, ver in s.ontologies) or "no ontology"
        parts = [_HEADER.format(sources=sources, version=s.fingerprint(), ontologies=s.ontologies)]
        parts.append(_THING.format(comment=s.table(THING_TABLE).comment))
        parts += [self._link_table(link) for link in s.links]
        parts += [self._class(t) for t in s.tables if t.name != THING_TABLE]
        parts.append("\n\n#: Generated class of each table name.\nCLASSES: dict[str, type[Base]] = {\n"
                     + "".join(f"    {t.name!r}: {t.class_name},\n" for t in s.tables) + "}\n")
        return "".join(parts)

    def _link_table(self, link: LinkSpec) -> str:
        info = {**column_info(link), "link": True}
        if link.kind == "object":
            value = f'Column("value_id", Integer, _ref({(link.target or THING_TABLE)!r}), primary_key=True)'
        else:
            sql = _SQL_TYPES[link.value.kind]
            sql = "_IRI" if sql == "Text()" else sql
            value = f'Column("value", {sql}, primary_key=True, autoincrement=False)'
        checks = "".join(f",\n    {c}" for c in (_checks("value", link.value) if link.kind == "data" else []))
        return (f"\n{link.name} = Table(\n    {link.name!r}, Base.metadata,\n"
                f'    Column("subject_id", Integer, _ref({link.domain!r}), primary_key=True, autoincrement=False),\n'
                f"    {value}{checks},\n    info={info!r},\n)\n")

    def _class(self, t: TableSpec) -> str:
        parent = self.classes[t.parent]
        checks = [c for col in t.columns if col.kind == "data" for c in _checks(col.name, col.value)]
        table_kw = {"info": {"iri": t.class_iri, "parent": t.parent}}
        if t.comment:
            table_kw["comment"] = t.comment
        doc = (t.comment or t.class_name).replace('"""', "'''").replace("\\", "\\\\")
        lines = [f"\n\nclass {t.class_name}({parent}):", f'    """{doc}', "", f"    Class <{t.class_iri}>.",
                 '    """', "", f"    __tablename__ = {t.name!r}"]
        if checks:
            lines.append("    __table_args__ = (")
            lines += [f"        {c}," for c in checks]
            lines.append(f"        {table_kw!r},")
            lines.append("    )")
        else:
            lines.append(f"    __table_args__ = {table_kw!r}")
        lines += ["", f"    id: Mapped[int] = mapped_column(ForeignKey({t.parent + '.id'!r}, deferrable=True, "
                  f'initially="DEFERRED"), primary_key=True, autoincrement=False)']
        lines.append(f'    __mapper_args__ = {{"polymorphic_identity": {t.class_iri!r}, '
                     f'"inherit_condition": id.column == {parent}.__table__.c.id}}')
        for col in t.columns:
            lines += self._column(t, col)
        for link in self.links.get(t.name, []):
            lines += self._link_rel(t, link)
        return "\n".join(lines) + "\n"

    def _column(self, t: TableSpec, col: ColumnSpec) -> list[str]:
        info = column_info(col)
        name = "" if col.attr == col.name else f"{col.name!r}, "
        if col.kind == "object":
            target = self.classes[col.target or THING_TABLE]
            extra = ", unique=True" if col.unique else ", index=True"
            hint = "int | None" if col.nullable else "int"
            target_table = col.target or THING_TABLE
            out = [f"    {col.attr}: Mapped[{hint}] = mapped_column({name}Integer, _ref({target_table!r})"
                   f"{extra}, info={info!r})"]
            rel_hint = f"{target} | None" if col.nullable else target
            out.append(f"    {col.rel}: Mapped[{rel_hint}] = relationship({target!r}, primaryjoin=lambda: "
                       f"foreign({t.class_name}.__table__.c.{col.name}) == remote({target}.__table__.c.id), "
                       f"foreign_keys=lambda: [{t.class_name}.__table__.c.{col.name}])")
            return out
        sql = _SQL_TYPES[col.value.kind] if not col.value.enum else "_IRI"
        return [f"    {col.attr}: Mapped[{_py_type(col.value, col.nullable)}] = mapped_column({name}{sql}, "
                f"nullable={col.nullable}, info={info!r})"]

    def _link_rel(self, t: TableSpec, link: LinkSpec) -> list[str]:
        if link.kind != "object":
            return [f"    # {link.attr}: values of <{link.property_iri}> are rows of table {link.name}"]
        target = self.classes[link.target or THING_TABLE]
        return [f"    {link.attr}: Mapped[list[{target}]] = relationship({target!r}, secondary=lambda: {link.name}, "
                f"primaryjoin=lambda: {t.class_name}.__table__.c.id == {link.name}.c.subject_id, "
                f"secondaryjoin=lambda: {target}.__table__.c.id == {link.name}.c.value_id, "
                f"info={{'iri': {link.property_iri!r}}})"]


class AccessorsGenerator(Generator):
    """Python module of typed SQLAlchemy classes for the shipped kitting and SOAP ontologies."""

    name: ClassVar[str] = "accessors"
    file_extension: ClassVar[str] = ".py"

    def __init__(self, schema: Schema | None = None):
        self.schema = schema or shipped_schema()

    def serialize(self) -> str:
        """The module text (deterministic)."""
        return _Writer(self.schema).write()


def main(argv: list[str] | None = None) -> int:
    """Write the accessors module (``python -m generators.accessors -o FILE``)."""
    parser = argparse.ArgumentParser(prog="python -m generators.accessors", description=__doc__.splitlines()[0])
    parser.add_argument("-o", "--output", default="kb/world/generated/accessors.py")
    args = parser.parse_args(argv)
    AccessorsGenerator().write(args.output)
    return 0


if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(main())
