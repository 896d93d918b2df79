"""Files kitkb writes: complete or not at all, never over what the command reads.

Every output (converted ontologies, PDDL, plans, SQL, dumps, scenarios, reports) is written to
a temporary file beside its target and renamed over it, so a failure or a kill never leaves half
a file behind nor clobbers the old one. A new file gets the mode the process's umask gives
(``-rw-r--r--`` under the usual 022), an existing file keeps its mode.

Inside :func:`command_scope` (one per ``kitkb`` command) every file a reader opens
(:func:`note_input`) and every SQLite database the command opens (:func:`note_database`) is
remembered by device and inode; writing over any of them is an :class:`InputError` naming both
paths, so ``-o i.ttl``, ``-o ./i.ttl``, a symlink or a hard link to an input are all caught.
Overwriting an earlier output that is not an input stays allowed, as Unix tools do.
"""

from __future__ import annotations

import glob
import os
import tempfile
from contextlib import contextmanager
from contextvars import ContextVar
from pathlib import Path
from typing import Any, Iterator, Sequence

from kb.core.errors import InputError


#: (device, inode) -> (what it is, the path the command named it by), for the running command.
_READ: ContextVar[dict[tuple[int, int], tuple[str, str]] | None] = ContextVar("kitkb_read", default=None)


@contextmanager
def command_scope(inputs: Sequence[str | Path] = (), databases: Sequence[str | Path] = (),
                  outputs: Sequence[str | Path] = ()) -> Iterator[None]:
    """One command's guard: ``inputs`` and ``databases`` (and whatever readers note while the
    block runs) may not be written over by :func:`atomic_paths` inside it. ``outputs`` are
    checked at once, so a command refuses before it works rather than after."""
    token = _READ.set({})
    try:
        for path in inputs:
            note_input(path)
        for path in databases:
            note_database(path)
        for path in outputs:
            check_output(path)
        yield
    finally:
        _READ.reset(token)


def _identity(path: str | Path) -> tuple[int, int] | None:
    try:
        st = os.stat(path)
    except (OSError, ValueError):
        return None
    return (st.st_dev, st.st_ino)


def note_input(path: str | Path, what: str = "input") -> None:
    """Remember ``path`` as read by the running command (nothing outside a command scope)."""
    read = _READ.get()
    if read is None:
        return
    key = _identity(path)
    if key is not None:
        read.setdefault(key, (what, str(path)))


def note_database(path: str | Path) -> None:
    """Remember the SQLite file ``path`` (and its ``-wal``/``-journal``) as a database the running
    command opens."""
    note_input(path, "database")
    for suffix in ("-wal", "-shm", "-journal"):
        note_input(f"{path}{suffix}", "database")


def check_output(path: str | Path) -> None:
    """InputError (exit 2) if writing ``path`` would replace a file the running command reads."""
    read = _READ.get()
    if not read:
        return
    key = _identity(path)
    if key is not None and key in read:
        what, original = read[key]
        raise InputError(f"refusing to write over {original}, the {what} this command reads "
                         f"(the same file); choose another output path", path)


def utf8_lines(f: Any, path: str | Path) -> Iterator[str]:
    """The lines of binary file ``f`` as text, without their ``\\n`` and the first without a
    byte order mark; bytes that are not UTF-8 are an InputError at their line of ``path``."""
    for number, raw in enumerate(f, 1):
        try:
            text = raw.decode("utf-8")
        except UnicodeDecodeError:
            raise InputError("not UTF-8 text", path, number) from None
        if number == 1:
            text = text.removeprefix("\ufeff")
        yield text.removesuffix("\n")


def _umask() -> int:
    """The process's umask, read without changing it where the system allows."""
    try:
        with open("/proc/self/status", encoding="ascii") as status:
            for line in status:
                if line.startswith("Umask:"):
                    return int(line.split()[1], 8)
    except (OSError, ValueError, IndexError):
        pass
    mask = os.umask(0o022)  # no other way: set and restore at once
    os.umask(mask)
    return mask


def _mode_for(path: Path) -> int:
    try:
        return path.stat().st_mode & 0o7777
    except OSError:
        return 0o666 & ~_umask()


def _sweep(folder: Path, name: str) -> None:
    """Remove the temporary files of ``name`` whose writer is gone (killed: SIGKILL leaves them).
    A temporary file is named ``.NAME.PID.XXXXXXXX.tmp`` by the process writing it."""
    for stale in folder.glob(f".{glob.escape(name)}.*.tmp"):
        pid = stale.name[len(name) + 2:].split(".", 1)[0]
        if pid.isdigit() and int(pid) != os.getpid():
            try:
                os.kill(int(pid), 0)
            except ProcessLookupError:
                stale.unlink(missing_ok=True)
            except OSError:
                pass  # alive, another user's


@contextmanager
def atomic_paths(paths: Sequence[str | Path]) -> Iterator[list[Path]]:
    """Temporary paths to write ``paths`` through: when the block ends normally each is renamed
    over its target (parents created as needed); on any error none of the targets changes.

    Several targets are replaced together at the end (a scenario's ``init.ttl`` and
    ``goal.ttl``), one rename each.
    """
    targets = [Path(p) for p in paths]
    temps: list[Path] = []
    for target in targets:
        check_output(target)
    try:
        for target in targets:
            if target.is_dir():
                raise InputError("is a folder; give a file path", target)
            folder = target.parent
            if folder.exists() and not folder.is_dir():
                raise InputError(f"cannot write {target}: {folder} is a file, not a folder", target)
            folder.mkdir(parents=True, exist_ok=True)
            check_output(target)  # again: "x/../i.ttl" names i.ttl only once x exists
            _sweep(folder, target.name)
            fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.{os.getpid()}.", suffix=".tmp", dir=folder)
            os.close(fd)
            temps.append(Path(tmp))
        yield temps
        for tmp, target in zip(temps, targets):
            os.chmod(tmp, _mode_for(target))
            os.replace(tmp, target)
    except OSError as exc:
        where = exc.filename if isinstance(exc.filename, str) else (targets[0] if targets else "")
        raise InputError(f"cannot write: {exc.strerror or exc}", where) from None
    finally:
        for tmp in temps:
            tmp.unlink(missing_ok=True)


def write_atomic(path: str | Path, data: str | bytes) -> Path:
    """Write ``data`` (text as UTF-8 with ``\\n`` line ends) to ``path`` atomically, flushed to disk.

    An unwritable target is an :class:`~kb.core.errors.InputError` naming it.
    """
    target = Path(path)
    with atomic_paths([target]) as (tmp,):
        with open(tmp, "wb") as out:
            out.write(data.encode("utf-8") if isinstance(data, str) else data)
            out.flush()
            os.fsync(out.fileno())
    return target
