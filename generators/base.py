"""The small base class every generator derives from.

A generator turns the knowledge base (ontology graphs) into one artefact: SHACL shapes,
a PDDL domain or problem, an SQL schema, a Python module. Adding a target means one module
with one subclass and one line in :data:`generators.REGISTRY`.
"""

from __future__ import annotations

import os
import tempfile
from abc import ABC, abstractmethod
from pathlib import Path
from typing import ClassVar


class Generator(ABC):
    """Base of all generators: a name, a file extension, and :meth:`serialize`."""

    #: Short name used on the command line and in the registry.
    name: ClassVar[str] = ""
    #: Extension (with the dot) of the file :meth:`write` produces.
    file_extension: ClassVar[str] = ""

    @abstractmethod
    def serialize(self) -> str:
        """The generated artefact as text (deterministic for the same input)."""

    def write(self, path: str | Path) -> Path:
        """Write :meth:`serialize` to ``path`` atomically (temp file, then rename)."""
        return write_text_atomic(Path(path), self.serialize())


def write_text_atomic(path: Path, text: str) -> Path:
    """Write ``text`` to ``path`` so that a failure never leaves half a file behind."""
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", dir=path.parent)
    try:
        with os.fdopen(fd, "w", encoding="utf-8", newline="\n") as fh:
            fh.write(text)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return path
