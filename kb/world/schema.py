"""The world-model tables as lookups: which table holds a class, which column a property.

Built once from the metadata of the generated accessors (:mod:`kb.world.generated.accessors`,
one table per ontology class, see docs/database.md).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import lru_cache
from typing import Any

from sqlalchemy import Column, Table

from kb.world.generated import accessors as gen
from kb.world.values import Check, check_spec


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
