"""Files kitkb writes: complete or not at all, with the permissions a user expects.

Every output (converted ontologies, PDDL, plans, SQL, dumps, scenarios) is written to a
temporary file beside its target and renamed over it, so a failure or a kill never leaves half
a file behind nor clobbers the old one. A new file gets the mode the process's umask gives
(``-rw-r--r--`` under the usual 022), an existing file keeps its mode.
"""

from __future__ import annotations

import os
import tempfile
from contextlib import contextmanager
from pathlib import Path
from typing import Iterator, Sequence

from kb.core.errors import InputError


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


@contextmanager
def atomic_paths(paths: Sequence[str | Path]) -> Iterator[list[Path]]:
    """Temporary paths to write ``paths`` through: when the block ends normally each is renamed
    over its target (parents created as needed); on any error none of the targets changes.

    Several targets are replaced together at the end (a scenario's ``init.ttl`` and
    ``goal.ttl``), one rename each.
    """
    targets = [Path(p) for p in paths]
    temps: list[Path] = []
    try:
        for target in targets:
            folder = target.parent
            if folder.exists() and not folder.is_dir():
                raise InputError("output folder is a file", folder)
            folder.mkdir(parents=True, exist_ok=True)
            fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".tmp", dir=folder)
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
