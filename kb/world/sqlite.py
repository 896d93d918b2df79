"""SQLite files as kitkb opens them: the file of an ``sqlite:///`` URL, and a connection with
kitkb's settings (used by the SQLAlchemy engines of :mod:`kb.world.database` and, without
SQLAlchemy, by the bulk load of :mod:`kb.world.load`).

Settings: transactions begun explicitly (``isolation_level=None``; writers ``BEGIN IMMEDIATE``),
foreign keys on, a busy timeout of 60 s, and for files WAL with ``synchronous=NORMAL`` (a
committed transaction survives a crash of the application; an OS crash may lose the last ones).

A file that is not kitkb's is never changed by being opened: a file that is not an SQLite
database at all is refused before SQLite sees it (:func:`check_file`), and WAL (which rewrites
the file's header) is only switched on in a database that holds a kitkb world model (a load
switches a new one on when it commits).
"""

from __future__ import annotations

import re
import sqlite3
from pathlib import Path
from typing import Any

from kb.core.errors import InputError

#: Seconds a connection waits for another writer's lock.
BUSY_TIMEOUT = 60
#: The first 16 bytes of every SQLite database file.
MAGIC = b"SQLite format 3\x00"
_PLAIN_FILE = re.compile(r"sqlite(?:\+pysqlite)?:///(/[^?#]*)\Z")


def plain_file(url: str) -> Path | None:
    """The file of an ``sqlite:///ABSOLUTE/PATH`` URL with no options (what a plain path
    becomes); None for anything else (other URLs are left to SQLAlchemy)."""
    m = _PLAIN_FILE.match(url)
    return Path(m.group(1)) if m else None


def settings(dbapi_conn: Any, database: str, wal: bool = True) -> None:
    """kitkb's settings on a new sqlite3 connection (``database``: its file, or "" / ":memory:";
    ``wal=False``: leave the journal mode alone, for a load that makes the file)."""
    dbapi_conn.isolation_level = None  # kitkb issues BEGIN itself
    cur = dbapi_conn.cursor()
    cur.execute("PRAGMA foreign_keys = ON")
    cur.execute(f"PRAGMA busy_timeout = {BUSY_TIMEOUT * 1000}")
    if wal and database and database != ":memory:":
        cur.execute("PRAGMA synchronous = NORMAL")
        if _kitkb(cur) and cur.execute("PRAGMA journal_mode").fetchone()[0] != "wal":
            cur.execute("PRAGMA journal_mode = WAL")
    cur.close()


def _kitkb(cur: Any) -> bool:
    """The database holds a kitkb world model (a ``kitkb_meta`` table)."""
    return cur.execute("SELECT 1 FROM sqlite_master WHERE type = 'table' AND name = 'kitkb_meta'").fetchone() \
        is not None


def check_file(path: Path, url: str) -> bool:
    """Refuse (one-line InputError) an existing file that is not an SQLite database (a Turtle
    file, a picture), before SQLite opens it; True if the file holds something (not missing,
    not 0 bytes)."""
    try:
        with open(path, "rb") as f:
            head = f.read(len(MAGIC))
    except FileNotFoundError:
        return False
    except IsADirectoryError:
        raise InputError(f"database {url} is a folder, not a kitkb world model") from None
    except OSError as exc:
        raise InputError(f"cannot open database {url}: {exc.strerror or exc}") from None
    if head and head != MAGIC and not (head.count(0) == len(head) and _hot_journal(path)):
        raise InputError(f"database {url} is not a kitkb world model (the file is not an SQLite database); "
                         f"it is left as it is: give a new file") from None
    return bool(head)


def _hot_journal(path: Path) -> bool:
    """A rollback journal beside ``path``: a new database whose writer was killed before its
    first commit wrote page 1 (zeros where the header goes); SQLite rolls it back on open."""
    try:
        with open(f"{path}-journal", "rb") as f:
            return f.read(8) == b"\xd9\xd5\x05\xf9\x20\xa1\x63\xd7"  # the journal's magic
    except OSError:
        return False


def make_folder(path: Path) -> None:
    """Create the folder of database file ``path`` if needed; one-line InputError if it cannot."""
    if not path.parent.exists():
        try:
            path.parent.mkdir(parents=True)
        except OSError as exc:
            raise InputError(f"cannot create the folder of {path}: {exc.strerror or exc}") from None


def connect(path: Path, url: str, wal: bool = True) -> sqlite3.Connection:
    """A connection to database file ``path`` (made if missing) with kitkb's settings."""
    make_folder(path)
    check_file(path, url)
    try:
        conn = sqlite3.connect(str(path), timeout=BUSY_TIMEOUT, isolation_level=None)
        settings(conn, str(path), wal)
    except sqlite3.Error as exc:
        raise InputError(f"cannot open database {url}: {str(exc).splitlines()[0] if str(exc) else exc}") from None
    return conn
