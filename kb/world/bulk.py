"""Rows into tables in bulk, through the driver: ``executemany`` on SQLite, ``COPY`` on PostgreSQL.

Values arrive as the loader builds them (ints, floats, bools, str, naive UTC datetimes, dates);
each driver gets them in the form SQLAlchemy's column types would have bound (the same
storage, so SQLAlchemy reads them back as before: ``tests/test_db_load.py`` compares the
SQLite date and time forms with SQLAlchemy's own). No SQLAlchemy import here.
"""

from __future__ import annotations

import datetime as _dt
from typing import Any, Callable, Iterable, Iterator, Sequence

from kb.world.plan import load_plan

Rows = Sequence[tuple[Any, ...]]

#: Rows per COPY buffer (bounded memory; one COPY statement per buffer).
COPY_ROWS = 50_000


def quoted(*names: str) -> str:
    """Identifiers quoted for SQL (a SOAP column is called ``limit``), comma-separated."""
    return ", ".join(f'"{n}"' for n in names)


def sqlite_datetime(v: _dt.datetime) -> str:
    """A datetime as SQLAlchemy's SQLite ``DATETIME`` stores it (its default storage format)."""
    return (f"{v.year:04d}-{v.month:02d}-{v.day:02d} {v.hour:02d}:{v.minute:02d}:{v.second:02d}."
            f"{v.microsecond:06d}")


def sqlite_date(v: _dt.date) -> str:
    """A date as SQLAlchemy's SQLite ``DATE`` stores it."""
    return f"{v.year:04d}-{v.month:02d}-{v.day:02d}"


_SQLITE_FORMS: dict[str, Callable[[Any], Any]] = {"datetime": sqlite_datetime, "date": sqlite_date}


def _sqlite_processors(table: str, columns: list[str]) -> list[tuple[int, Callable[[Any], Any]]]:
    """The columns that SQLite gets as text in SQLAlchemy's forms (dates and times)."""
    t = load_plan().tables[table]
    out = []
    for i, name in enumerate(columns):
        form = _SQLITE_FORMS.get(t.column(name).info.get("value", ""))
        if form is not None:
            out.append((i, form))
    return out


def insert_sqlite(cur: Any, tables: Iterable[tuple[str, list[str], Rows]]) -> None:
    """``INSERT`` every row with ``executemany`` (SQLite's C loop over one prepared statement)."""
    for name, columns, rows in tables:
        procs = _sqlite_processors(name, columns)
        if procs:
            rows = [_processed(row, procs) for row in rows]
        marks = ", ".join("?" * len(columns))
        cur.executemany(f"INSERT INTO {quoted(name)} ({quoted(*columns)}) VALUES ({marks})", rows)


def _processed(row: tuple[Any, ...], procs: list[tuple[int, Callable[[Any], Any]]]) -> tuple[Any, ...]:
    out = list(row)
    for i, proc in procs:
        if out[i] is not None:
            out[i] = proc(out[i])
    return tuple(out)


# --- PostgreSQL COPY (text format) ------------------------------------------------------------------

_ESCAPES = str.maketrans({"\\": "\\\\", "\t": "\\t", "\n": "\\n", "\r": "\\r"})


def _text(v: Any) -> str:
    if v is None:
        return "\\N"
    if v.__class__ is str:
        return v.translate(_ESCAPES)
    if v is True:
        return "t"
    if v is False:
        return "f"
    if isinstance(v, _dt.datetime):  # naive UTC (kb.world.values), said so: the session's zone is not used
        return (v if v.tzinfo else v.replace(tzinfo=_dt.timezone.utc)).isoformat()
    if isinstance(v, _dt.date):
        return v.isoformat()
    return repr(v) if isinstance(v, float) else str(v)


def _formatter(table: str, columns: list[str]) -> Callable[[tuple[Any, ...]], str]:
    t = load_plan().tables[table]
    plain = all(t.column(c).number for c in columns)
    if plain:  # ids and numbers only
        return lambda row: "\t".join(["\\N" if v is None else str(v) for v in row])
    return lambda row: "\t".join([_text(v) for v in row])


def copy_buffers(tables: Iterable[tuple[str, list[str], Rows]]) -> Iterator[tuple[str, bytes]]:
    """``(COPY ... FROM STDIN statement, its data)`` for every table, in buffers of
    :data:`COPY_ROWS` rows (PostgreSQL's text format)."""
    for name, columns, rows in tables:
        line = _formatter(name, columns)
        sql = f"COPY {quoted(name)} ({quoted(*columns)}) FROM STDIN"
        for start in range(0, len(rows), COPY_ROWS):
            text = "\n".join([line(row) for row in rows[start:start + COPY_ROWS]]) + "\n"
            yield sql, text.encode("utf-8")
