"""Small derived values kept in a file between runs (like Python's ``.pyc``): a JSON table per
kind of value, keyed by what the values depend on.

A :class:`JsonCache` is one file, ``NAME-KEY.json`` in kitkb's cache folder, where KEY is a
digest of what every value in it was derived with (the source of the modules that derive them,
the versions of the libraries they use); each entry is keyed by a digest of its own inputs. A
missing, stale or unreadable file just means the values are made again; the file is written
atomically, so a reader never sees half of it (two processes writing at once: the last one's
entries are kept, the other's are made again later).

The folder is ``$KITKB_CACHE_DIR``, else ``$XDG_CACHE_HOME/kitkb`` or ``~/.cache/kitkb``
(made with mode 0700); ``KITKB_CACHE_DIR=off`` turns the caches off (as for
:mod:`kb.world.cache`).
"""

from __future__ import annotations

import hashlib
import json
import os
import sys
from pathlib import Path
from typing import Any, Iterable

from kb import __version__


def cache_dir() -> Path | None:
    """Where kitkb keeps its caches (None when turned off)."""
    env = os.environ.get("KITKB_CACHE_DIR")
    if env is not None:
        return None if env.strip().lower() in ("", "0", "off", "no") else Path(env)
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "kitkb"


def digest(parts: Iterable[str | bytes]) -> str:
    """A short digest of ``parts`` (in order)."""
    h = hashlib.sha256()
    for part in parts:
        h.update(part if isinstance(part, bytes) else part.encode())
        h.update(b"\0")
    return h.hexdigest()[:24]


def write_atomically(path: Path, data: bytes) -> None:
    """Write a cache file atomically; one that cannot be written is simply not kept."""
    try:
        path.parent.mkdir(mode=0o700, parents=True, exist_ok=True)
        tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
        tmp.write_bytes(data)
        os.replace(tmp, path)
    except OSError:
        pass


class JsonCache:
    """Entries (JSON values) of one kind, for one ``key`` of what derives them: read from the
    cache file on first use, written back when an entry was added."""

    def __init__(self, name: str, key: Iterable[str | bytes]) -> None:
        self.name = name
        self._key = list(key)
        self._entries: dict[str, Any] | None = None
        self._path: Path | None = None

    def _load(self) -> dict[str, Any]:
        if self._entries is None:
            folder = cache_dir()
            self._entries = {}
            if folder is not None:
                self._path = folder / f"{self.name}-{digest([*self._key, sys.version, __version__])}.json"
                try:
                    found = json.loads(self._path.read_bytes())
                    if isinstance(found, dict):
                        self._entries = found
                except (OSError, ValueError):  # missing or broken: made again
                    pass
        return self._entries

    def get(self, key: str) -> Any:
        """The entry ``key`` (None when there is none)."""
        return self._load().get(key)

    def put(self, key: str, value: Any) -> None:
        """Keep ``value`` (JSON) as entry ``key``, in the file too."""
        entries = self._load()
        entries[key] = value
        if self._path is not None:
            write_atomically(self._path, json.dumps(entries, sort_keys=True).encode())
