"""``kitkb db load`` and ``kitkb db dump``."""

from __future__ import annotations

import time
from pathlib import Path

from kb.cli.output import Output
from kb.io.loader import domain_knowledge
from kb.world import dump as dump_db
from kb.world import load as load_db


def load(datafile: str, db: str, out: Output, replace: bool = False, domain: list[str] | None = None) -> int:
    """Load ``datafile`` into database ``db`` (``replace``: the world model it already holds;
    ``domain``: extension files whose classes of objects the file uses)."""
    start = time.perf_counter()
    if domain:
        domain_knowledge(domain)  # read (a broken one refused at its line) and its classes known
    with out.progress(f"loading {Path(datafile).name}"):
        report = load_db(datafile, db, replace=replace, progress=out.tracker)
    out.done(f"loaded {datafile} into {db}: {report.summary()}", datafile=datafile, db=db,
             statements=report.statements, individuals=report.individuals, tables=report.tables,
             outside_model=report.outside_model, replaced=report.replaced,
             seconds=round(time.perf_counter() - start, 3))
    return 0


def dump(db: str, output: str, out: Output) -> int:
    """Write database ``db`` to ``output`` as Turtle."""
    start = time.perf_counter()
    with out.progress(f"writing {Path(output).name} from the database"):
        dump_db(db, output, progress=out.tracker)
    out.done(f"wrote {output} (the content of {db})", output=output, db=db, bytes=Path(output).stat().st_size,
             seconds=round(time.perf_counter() - start, 3))
    return 0
