"""The world model in a real database (SQLite embedded, or PostgreSQL): what the executor
reads and writes.

:func:`load` fills the database from a data file in one transaction (:mod:`.load`);
:func:`dump` writes it back as Turtle (:mod:`.dump`); :class:`WorldModel` (:mod:`.worldmodel`)
reads objects, poses and the transformation tree and stores sensed poses with eq. (1) in
stable-state commits. :mod:`.database` opens databases and checks their version stamp,
:mod:`.schema` maps classes and properties to the tables of the generated accessors
(:mod:`.generated.accessors`), :mod:`.values` converts literals to column values and back.
"""

from kb.world.database import DEFAULT_DB, SchemaVersionError, drop_all, normalize_url, open_engine
from kb.world.dump import dump, read_graph
from kb.world.load import LoadReport, load
from kb.world.worldmodel import StepResult, WorldModel, WorldObject

__all__ = ["DEFAULT_DB", "LoadReport", "SchemaVersionError", "StepResult", "WorldModel", "WorldObject",
           "drop_all", "dump", "load", "normalize_url", "open_engine", "read_graph"]
