"""The world model in a real database (SQLite embedded, or PostgreSQL): what the executor
reads and writes.

:func:`load` fills the database from a data file in one transaction (:mod:`.load`: the file
read as a stream, :mod:`.triples`, into rows, :mod:`.rows`, written in bulk, :mod:`.bulk`,
into tables made by :mod:`.ddl`); :func:`dump` streams it back as Turtle (:mod:`.dump`);
:class:`WorldModel` (:mod:`.worldmodel`) reads objects, poses and the transformation tree and
stores sensed poses with eq. (1), alone or in stable-state batches (:mod:`.poses`: the batch
arithmetic and the kept tree). :mod:`.database` opens databases and checks their version
stamp (:mod:`.sqlite`: SQLite files as kitkb opens them), :mod:`.schema` maps classes and
properties to the tables of the generated accessors (:mod:`.generated.accessors`), :mod:`.plan`
is the same as plain data for loads, kept with the tables and DDL in :mod:`.cache`;
:mod:`.values` converts literals to column values and back.

The world model API is imported on first use (``kb.world.WorldModel``), so ``kitkb db load``
imports neither numpy nor, for an SQLite file, SQLAlchemy.
"""

from __future__ import annotations

import importlib
from typing import Any

from kb.world.database import DEFAULT_DB, SchemaVersionError, drop_all, normalize_url, open_engine
from kb.world.dump import dump, read_graph
from kb.world.load import LoadReport, load

_LAZY = {"StepResult", "WorldModel", "WorldObject"}

__all__ = ["DEFAULT_DB", "LoadReport", "SchemaVersionError", "StepResult", "WorldModel", "WorldObject",
           "drop_all", "dump", "load", "normalize_url", "open_engine", "read_graph"]


def __getattr__(name: str) -> Any:
    if name not in _LAZY:
        raise AttributeError(f"module 'kb.world' has no attribute {name!r}")
    value = getattr(importlib.import_module("kb.world.worldmodel"), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | _LAZY)
