"""When a change to a library's internals applies: the versions it was checked on."""

from __future__ import annotations

import functools
import os
import re
from dataclasses import dataclass
from importlib.metadata import PackageNotFoundError, version


def _version_tuple(text: str) -> tuple[int, ...]:
    """The leading numeric release of a version string (``"2.1.9"`` -> (2, 1, 9))."""
    parts = []
    for piece in text.split("."):
        m = re.match(r"\d+", piece)
        if m is None:
            break
        parts.append(int(m.group()))
        if m.end() != len(piece):
            break
    return tuple(parts)


@functools.lru_cache(maxsize=None)
def installed(distribution: str) -> str | None:
    """The installed version of ``distribution``, or None."""
    try:
        return version(distribution)
    except PackageNotFoundError:
        return None


@dataclass(frozen=True)
class Patch:
    """One change to a library's internals, applied only on the versions it was checked on.

    ``checked_from`` is the lowest version checked, ``checked_below`` the first version the
    range does not cover (``"2.1.9"``, ``"2.2"``: 2.1.9 and later 2.1 releases).
    """

    library: str
    checked_from: str
    checked_below: str
    what: str

    @property
    def range(self) -> str:
        """The version range in pip's notation."""
        return f">={self.checked_from},<{self.checked_below}"

    def active(self) -> bool:
        """Whether kitkb applies the change in this process."""
        if os.environ.get("KITKB_PATCHES", "").strip().lower() in ("0", "no", "off", "false"):
            return False
        found = installed(self.library)
        if found is None:
            return False
        have = _version_tuple(found)
        return _version_tuple(self.checked_from) <= have < _version_tuple(self.checked_below)
