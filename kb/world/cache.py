"""Values derived from the generated schema, kept in files between runs (like Python's ``.pyc``).

Importing the generated accessors module builds some 200 declarative classes (0.6 s, half of
a whole ``kitkb db load`` of 10,000 parts), and SQLAlchemy itself takes 0.1 s to import;
what the database code needs from them (the tables, their compiled DDL, the load plan of
:mod:`kb.world.plan`) is made once and pickled. A cached value is keyed by the accessors
module's text and the SQLAlchemy, Python and kitkb versions, so a regenerated schema or an
upgrade makes new ones; a missing, stale or unreadable file just means the value is made again.

The files live in ``$KITKB_CACHE_DIR``, else ``$XDG_CACHE_HOME/kitkb`` or ``~/.cache/kitkb``
(made with mode 0700); ``KITKB_CACHE_DIR=off`` turns the cache off. This module imports
neither SQLAlchemy nor the accessors.
"""

from __future__ import annotations

import hashlib
import importlib.util
import os
import pickle
import sys
from functools import lru_cache
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path
from typing import Any, Callable

from kb import __version__

ACCESSORS = "kb.world.generated.accessors"


def cache_dir() -> Path | None:
    """Where kitkb keeps its caches (None when turned off)."""
    env = os.environ.get("KITKB_CACHE_DIR")
    if env is not None:
        return None if env.strip().lower() in ("", "0", "off", "no") else Path(env)
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "kitkb"


@lru_cache(maxsize=1)
def _key() -> str | None:
    """What the cached values depend on: the accessors module's text, SQLAlchemy, Python, kitkb."""
    spec = importlib.util.find_spec(ACCESSORS)
    if spec is None or not spec.origin:
        return None
    try:
        source = Path(spec.origin).read_bytes()
        sqlalchemy = version("SQLAlchemy")
    except (OSError, PackageNotFoundError):
        return None
    return hashlib.sha256(b"\0".join([source, sqlalchemy.encode(), sys.version.encode(),
                                      __version__.encode()])).hexdigest()[:24]


def cached(name: str, make: Callable[[], Any]) -> Any:
    """``make()``, kept in the cache file ``name`` for the current generated schema (pickled)."""
    folder, key = cache_dir(), _key()
    path = folder / f"{name}-{key}.pickle" if folder is not None and key is not None else None
    if path is not None:
        try:
            return pickle.loads(path.read_bytes())
        except Exception:  # noqa: BLE001 - a missing, stale or broken cache: make it again
            pass
    value = make()
    if path is not None:
        _write(path, pickle.dumps(value, protocol=pickle.HIGHEST_PROTOCOL))
    return value


def _write(path: Path, data: bytes) -> None:
    """Write a cache file atomically; one that cannot be written is simply not kept."""
    try:
        path.parent.mkdir(mode=0o700, parents=True, exist_ok=True)
        tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
        tmp.write_bytes(data)
        os.replace(tmp, path)
    except OSError:
        pass
