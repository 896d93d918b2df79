"""One kitkb writer of a world model at a time: a run or a load holds its database while it works.

A run (:mod:`kb.execution.store`, from loading its initial state to its last record) and a load
(:func:`kb.world.load`) take the database's writer lock; a second one is refused at once with
:class:`DatabaseBusy` (exit 2), one line naming the database and the holder, instead of
replacing a world model a run is writing stable states into.

* SQLite file ``w.sqlite``: an exclusive ``flock`` on ``w.sqlite-kitkb-lock`` beside it (SQLite
  itself uses ``fcntl`` locks on the database file, which ``flock`` does not touch); the file
  holds the holder's description and is removed when the lock is given back.
* PostgreSQL: a session advisory lock (keys ``'kitk'`` and a hash of the current schema) on a
  connection of its own, named ``kitkb <what> pid N`` for ``pg_stat_activity``.

Both are given back by the system when the holder dies (the kernel closes a killed process's
files; the server ends its session), so a killed run never leaves a lock that blocks. Within one
process the lock is re-entrant: the run's own load of its initial state passes.

Readers (``kitkb db dump``, :class:`kb.world.WorldModel`) take no lock: they read one committed
state in one transaction.
"""

from __future__ import annotations

import datetime as _dt
import os
import threading
import zlib
from contextlib import contextmanager
from pathlib import Path
from typing import Any, Callable, Iterator

from kb.core.errors import InputError

#: First key of kitkb's PostgreSQL advisory lock ("kitk"); the second is a hash of the schema.
PG_KEY = 0x6B69746B
#: Suffix of the lock file beside an SQLite database.
SUFFIX = "-kitkb-lock"

_HELD: dict[str, "Held"] = {}
_GUARD = threading.Lock()


class DatabaseBusy(InputError):
    """Another kitkb process is writing the world model (a run or a load)."""


class Held:
    """A writer lock this process holds (counted: re-entrant)."""

    def __init__(self, key: str, free: Callable[[], None]):
        self.key, self._free, self.count = key, free, 1

    def release(self) -> None:
        """Give back one hold; the lock itself when the last one goes."""
        with _GUARD:
            self.count -= 1
            if self.count:
                return
            _HELD.pop(self.key, None)
        self._free()


def acquire(url: str, what: str) -> Held:
    """The writer lock of database ``url`` (a normalized URL) for ``what`` ("a run", "a load of
    init.ttl"); :class:`DatabaseBusy` if another process holds it."""
    from kb.world.database import sqlite_file

    path = sqlite_file(url)
    if path is not None:
        path = path.resolve()  # one lock whichever symlink or relative name the file is given by
    key = str(path) if path is not None else url
    with _GUARD:
        held = _HELD.get(key)
        if held is not None:
            held.count += 1
            return held
    if path is None and url.startswith("sqlite"):  # in memory: one process by nature
        free: Callable[[], None] = lambda: None  # noqa: E731
    elif path is not None:
        free = _lock_file(path, url, what)
    else:
        free = _lock_server(url, what)
    held = Held(key, free)
    with _GUARD:
        _HELD[key] = held
    return held


@contextmanager
def hold(url: str, what: str) -> Iterator[Held]:
    """:func:`acquire` for the length of a block."""
    held = acquire(url, what)
    try:
        yield held
    finally:
        held.release()


def _holder(what: str) -> str:
    since = _dt.datetime.now(_dt.timezone.utc).strftime("%Y-%m-%d %H:%M:%S UTC")
    return f"{what} (pid {os.getpid()}, since {since})"


def _busy(url: str, holder: str) -> DatabaseBusy:
    from kb.world.database import safe_url

    return DatabaseBusy(f"database {safe_url(url)} is in use by {holder or 'another kitkb process'}: "
                        f"refusing to write it at the same time; try again when that ends")


# --- SQLite: a lock file beside the database ----------------------------------------------------

def lock_path(path: Path) -> Path:
    """The lock file of SQLite database file ``path``."""
    return Path(f"{path}{SUFFIX}")


def _lock_file(path: Path, url: str, what: str) -> Callable[[], None]:
    import fcntl

    from kb.world.sqlite import make_folder

    make_folder(path)
    target = lock_path(path)
    for _ in range(20):
        try:
            fd = os.open(target, os.O_RDWR | os.O_CREAT | os.O_CLOEXEC, 0o666)
        except OSError as exc:
            raise InputError(f"cannot lock database {url}: {exc.strerror or exc} ({target})") from None
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            holder = os.pread(fd, 400, 0).decode("utf-8", "replace").strip()
            os.close(fd)
            raise _busy(url, holder) from None
        if _same_file(fd, target):  # not a file its last holder removed as this one opened it
            break
        os.close(fd)
    else:  # pragma: no cover - twenty holders in a row removed the file under this one
        raise _busy(url, "")
    os.ftruncate(fd, 0)
    os.pwrite(fd, _holder(what).encode("utf-8"), 0)

    def free() -> None:
        try:
            target.unlink(missing_ok=True)  # still holding it: nobody else can have it yet
        except OSError:
            pass
        os.close(fd)
    return free


def _same_file(fd: int, path: Path) -> bool:
    try:
        on_disk = os.stat(path)
    except OSError:
        return False
    mine = os.fstat(fd)
    return (mine.st_dev, mine.st_ino) == (on_disk.st_dev, on_disk.st_ino)


# --- PostgreSQL: a session advisory lock --------------------------------------------------------

def _lock_server(url: str, what: str) -> Callable[[], None]:
    from sqlalchemy import create_engine
    from sqlalchemy.exc import SQLAlchemyError
    from sqlalchemy.pool import NullPool

    from kb.world.database import first_line, open_engine, safe_url

    engine = open_engine(url)  # the usual one-line errors for a bad URL or an unreachable server
    if engine.dialect.name != "postgresql":  # kitkb loads and runs on SQLite and PostgreSQL only
        engine.dispose()
        return lambda: None
    engine.dispose()
    engine = create_engine(url, poolclass=NullPool, connect_args={"application_name": _holder(what)[:63]})
    errors = (engine.dialect.dbapi.Error, SQLAlchemyError)  # type: ignore[union-attr]
    raw = None
    try:
        raw = engine.raw_connection()
        conn = raw.driver_connection
        conn.autocommit = True  # the lock outlives transactions; no transaction is left open
        cur = conn.cursor()
        cur.execute("SELECT current_schema()")
        key = zlib.crc32(str(cur.fetchone()[0]).encode("utf-8")) & 0x7FFFFFFF
        cur.execute("SELECT pg_try_advisory_lock(%s, %s)", (PG_KEY, key))
        if not cur.fetchone()[0]:
            cur.execute("SELECT a.application_name, a.pid FROM pg_locks l JOIN pg_stat_activity a"
                        " USING (pid) WHERE l.locktype = 'advisory' AND l.classid = %s AND l.objid = %s"
                        " AND l.objsubid = 2 AND l.granted", (PG_KEY, key))
            row = cur.fetchone()
            holder = (row[0] or f"a kitkb process (server pid {row[1]})") if row else ""
            raise _busy(url, holder)
    except errors as exc:
        _close(raw, engine)
        raise InputError(f"cannot lock database {safe_url(url)}: {first_line(exc)}") from None
    except BaseException:
        _close(raw, engine)
        raise

    def free() -> None:
        _close(raw, engine)  # ends the session: the server gives the lock back
    return free


def _close(raw: Any, engine: Any) -> None:
    try:
        if raw is not None:
            raw.close()
    finally:
        engine.dispose()
