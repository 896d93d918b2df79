"""The world-model tables as lookups: which table holds a class, which column a property.

Built once from the metadata of the generated accessors (:mod:`kb.world.generated.accessors`,
one table per ontology class, see docs/database.md).

Importing the accessors module builds some 200 declarative classes (0.6 s, half of a whole
``kitkb db load`` of 10,000 parts); the database code only needs their tables. So the
tables (SQLAlchemy ``MetaData``, which SQLAlchemy documents as picklable) are kept in a cache
file keyed by the accessors module's content and the SQLAlchemy and Python versions, and read
from there (40 ms) when the key matches; anything wrong with the cache means the module is
imported as before. The cache lives in ``$KITKB_CACHE_DIR``, else ``$XDG_CACHE_HOME/kitkb``
or ``~/.cache/kitkb``; ``KITKB_CACHE_DIR=off`` turns it off.
"""

from __future__ import annotations

import hashlib
import importlib.util
import os
import pickle
import sys
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path
from typing import Any, Callable

import sqlalchemy
from sqlalchemy import Column, MetaData, Table

from kb import __version__
from kb.world.values import Check, check_spec

_ACCESSORS = "kb.world.generated.accessors"


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

def cache_dir() -> Path | None:
    """Where kitkb keeps its caches (None when turned off)."""
    env = os.environ.get("KITKB_CACHE_DIR")
    if env is not None:
        return None if env.strip().lower() in ("", "0", "off", "no") else Path(env)
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "kitkb"


@lru_cache(maxsize=1)
def _cache_key() -> str | None:
    """What the cached files depend on: the accessors module's text, SQLAlchemy, Python, kitkb."""
    spec = importlib.util.find_spec(_ACCESSORS)
    if cache_dir() is None or spec is None or not spec.origin:
        return None
    try:
        source = Path(spec.origin).read_bytes()
    except OSError:
        return None
    return hashlib.sha256(b"\0".join([source, sqlalchemy.__version__.encode(), sys.version.encode(),
                                      __version__.encode()])).hexdigest()[:24]


def cached(name: str, make: Callable[[], Any]) -> Any:
    """``make()``, kept in the cache file ``name`` for the current generated schema (pickled)."""
    key, folder = _cache_key(), cache_dir()
    path = folder / f"{name}-{key}.pickle" if key is not None and folder is not None else None
    if path is not None:
        try:
            return pickle.loads(path.read_bytes())
        except Exception:  # noqa: BLE001 - a missing, stale or broken cache: make it again
            pass
    value = make()
    if path is not None:
        _write_cache(path, pickle.dumps(value, protocol=pickle.HIGHEST_PROTOCOL))
    return value


def _metadata() -> tuple[MetaData, str, tuple[tuple[str, str], ...]]:
    """The generated tables, schema version and ontology versions: from the cache file, else
    from the module."""
    found = cached("tables", _from_module)
    if not (isinstance(found, tuple) and isinstance(found[0], MetaData) and isinstance(found[1], str)):
        found = _from_module()
    return found  # type: ignore[no-any-return]


def _from_module() -> tuple[MetaData, str, tuple[tuple[str, str], ...]]:
    from kb.world.generated import accessors as gen

    return gen.Base.metadata, gen.SCHEMA_VERSION, tuple(gen.ONTOLOGIES)


def _write_cache(path: Path, data: bytes) -> None:
    """Write the cache file atomically; a cache that cannot be written is simply not kept."""
    try:
        path.parent.mkdir(mode=0o700, parents=True, exist_ok=True)
        tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
        tmp.write_bytes(data)
        os.replace(tmp, path)
    except OSError:
        pass
