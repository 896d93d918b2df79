"""``kitkb db load`` and ``kitkb db dump``."""

from __future__ import annotations

from kb.cli.output import Output
from kb.world import dump as dump_db
from kb.world import load as load_db


def load(datafile: str, db: str, out: Output, replace: bool = False) -> int:
    """Load ``datafile`` into database ``db`` (``replace``: the world model it already holds)."""
    report = load_db(datafile, db, replace=replace)
    out.done(f"loaded {datafile} into {db}: {report.summary()}")
    return 0


def dump(db: str, output: str, out: Output) -> int:
    """Write database ``db`` to ``output`` as Turtle."""
    dump_db(db, output)
    out.done(f"wrote {output} (the content of {db})")
    return 0
