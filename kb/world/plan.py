"""What a load needs to know about the tables, as plain data (no SQLAlchemy objects).

:func:`load_plan` is derived once from :func:`kb.world.schema.model` and kept in the cache of
:mod:`kb.world.cache`, so ``kitkb db load`` into an SQLite file imports neither SQLAlchemy nor
the generated accessors (0.2 s of a 1.3 s load of 10,000 parts).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property, lru_cache
from typing import Any

from kb.world.cache import cached
from kb.world.values import Check, make_check


@dataclass(frozen=True)
class ColumnPlan:
    """One column: its name, whether it may be NULL or is (part of) the key, what it holds
    (``info`` of the generated column: property IRI, kind, value type), whether its values
    are numbers, and the table a foreign key points at."""

    name: str
    nullable: bool
    primary_key: bool
    info: dict[str, Any]
    number: bool
    target: str | None


@dataclass(frozen=True)
class TablePlan:
    """One table: its name, columns in order and ``info`` (class IRI and parent table, or the
    property of a link table)."""

    name: str
    columns: tuple[ColumnPlan, ...]
    info: dict[str, Any]

    def column(self, name: str) -> ColumnPlan:
        """The column called ``name``."""
        return next(c for c in self.columns if c.name == name)


@dataclass(frozen=True)
class PropertyPlan:
    """Where the values of one property go: a column of a class table, or a link table
    (as :class:`kb.world.schema.Plan`, with its CHECKs as data)."""

    table: str
    column: str
    domain: str
    target: str | None
    info: dict[str, Any]
    check_specs: tuple[tuple[str, Any, str], ...]
    link: bool

    @cached_property
    def checks(self) -> tuple[Check, ...]:
        """The CHECK constraints on the column, as tests."""
        return tuple(make_check(*spec) for spec in self.check_specs)


@dataclass(frozen=True)
class LoadPlan:
    """The tables (in the order they are created), classes and properties of the schema."""

    version: str
    ontologies: tuple[tuple[str, str], ...]
    tables: dict[str, TablePlan]
    class_table: dict[str, str]  # class IRI -> table
    parent: dict[str, str]  # table -> parent table
    depth: dict[str, int]  # class IRI -> depth of its table in the hierarchy
    properties: dict[str, PropertyPlan]  # property IRI -> where its values go

    def chain(self, table: str) -> list[str]:
        """``table`` and the tables of all its ancestor classes, nearest first."""
        out = []
        while table:
            out.append(table)
            table = self.parent.get(table, "")
        return out


def _make() -> LoadPlan:
    from kb.world.schema import check_specs, model, target_of

    m = model()
    tables = {}
    for t in m.metadata.sorted_tables:  # names as plain str (SQLAlchemy's are a subclass of its own)
        columns = tuple(ColumnPlan(str(c.name), bool(c.nullable), bool(c.primary_key), dict(c.info), _number(c),
                                   target_of(c)) for c in t.columns)
        tables[str(t.name)] = TablePlan(str(t.name), columns, dict(t.info))
    properties = {iri: PropertyPlan(p.table, p.column, p.domain, p.target, dict(p.info),
                                    check_specs(m.table(p.table), p.column), p.link) for iri, p in m.plans.items()}
    plan = LoadPlan(m.version, tuple(m.ontologies), tables, {iri: str(t.name) for iri, t in m.class_table.items()},
                    dict(m.parent), dict(m.depth), properties)
    return _plain(plan)  # type: ignore[no-any-return]


def _plain(value: Any) -> Any:
    """``value`` with every str subclass (SQLAlchemy's ``quoted_name``) made a plain str, so the
    pickled plan can be read without importing SQLAlchemy."""
    if isinstance(value, str):
        return str(value)
    if isinstance(value, dict):
        return {_plain(k): _plain(v) for k, v in value.items()}
    if isinstance(value, (tuple, list, frozenset)):
        return type(value)(_plain(v) for v in value)
    if hasattr(value, "__dataclass_fields__"):
        return type(value)(**{f: _plain(getattr(value, f)) for f in value.__dataclass_fields__})
    return value


def _number(col: Any) -> bool:
    try:
        return col.type.python_type in (int, float)
    except NotImplementedError:
        return False


@lru_cache(maxsize=1)
def load_plan() -> LoadPlan:
    """The plan of the current generated schema (from the cache when it can)."""
    found = cached("plan", _make)
    return found if isinstance(found, LoadPlan) else _make()
