"""The world-model tables as lookups: which table holds a class, which column a property.

Built once from the metadata of the generated accessors (:mod:`kb.world.generated.accessors`,
one table per ontology class, see docs/database.md), which is kept in the cache of
:mod:`kb.world.cache` (SQLAlchemy documents ``MetaData`` as picklable): reading it from there
takes 40 ms where importing the module's 200 declarative classes takes 0.6 s.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import lru_cache
from typing import Any

from sqlalchemy import Column, MetaData, Table

from kb.world.cache import cached
from kb.world.values import Check, check_spec, make_check


@dataclass
class Model:
    """Lookup tables over the generated metadata: class -> table, property -> column."""

    metadata: Any
    version: str
    ontologies: tuple[tuple[str, str], ...] = ()
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


def check_specs(table: Table, column: str) -> tuple[tuple[str, Any, str], ...]:
    """``(operator, bound, text)`` of the CHECK constraints of ``table`` on ``column``."""
    return tuple(spec[1:] for ck in table.constraints if (spec := check_spec(ck)) and spec[0] == column)


def _plans(m: Model) -> dict[str, Plan]:
    plans = {}
    for iri, (table, col) in m.columns.items():
        checks = tuple(make_check(*spec) for spec in check_specs(table, col.name))
        plans[iri] = Plan(table.name, col.name, table.name, _target(col), dict(col.info), checks, False)
    for iri, table in m.links.items():
        value = table.c.value_id if table.info["kind"] == "object" else table.c.value
        checks = tuple(make_check(*spec) for spec in check_specs(table, value.name))
        plans[iri] = Plan(table.name, value.name, _target(table.c.subject_id) or "", _target(value),
                          dict(table.info), checks, True)
    return plans


def target_of(col: Column[Any]) -> str | None:
    """The table a foreign-key column points at (None for other columns)."""
    return _target(col)


@lru_cache(maxsize=1)
def model() -> Model:
    """The model of the generated accessors module (built once)."""
    metadata, version, ontologies = _metadata()
    m = Model(metadata, version, ontologies)
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


# --- the cached tables ----------------------------------------------------------------------

def _metadata() -> tuple[MetaData, str, tuple[tuple[str, str], ...]]:
    """The generated tables, schema version and ontology versions: from the cache
    (:mod:`kb.world.cache`), else from the module."""
    found = cached("tables", _from_module)
    if not (isinstance(found, tuple) and isinstance(found[0], MetaData) and isinstance(found[1], str)):
        found = _from_module()
    return found  # type: ignore[no-any-return]


def _from_module() -> tuple[MetaData, str, tuple[tuple[str, str], ...]]:
    from kb.world.generated import accessors as gen

    return gen.Base.metadata, gen.SCHEMA_VERSION, tuple(gen.ONTOLOGIES)
