"""Generators: the base class of every file kitkb derives from the ontologies, and the
registry that finds them by name.

A generator turns the knowledge base into one artefact (SHACL shapes, PDDL, an SQL schema, a
Python module). The emitters live in the ``generators`` package, which imports kb; kb never
imports it. kb finds a generator by name here, the way rdflib finds its plugins: built-in
names map to ``(module, class)`` and are imported on first use, and other distributions can
add generators through the ``kitkb.generators`` entry point group (``name = "module:Class"``).
Adding a target means one module with one :class:`Generator` subclass and one registry line.
"""

from __future__ import annotations

import importlib
from abc import ABC, abstractmethod
from importlib.metadata import entry_points
from pathlib import Path
from typing import ClassVar

from kb.core.errors import InputError
from kb.core.files import write_atomic

#: Entry point group through which other distributions register generators.
ENTRY_POINT_GROUP = "kitkb.generators"

#: kitkb's own generators: name -> (module, class), imported when first asked for.
BUILTIN: dict[str, tuple[str, str]] = {
    "accessors": ("generators.accessors", "AccessorsGenerator"),
    "pddl": ("generators.pddl", "PddlGenerator"),
    "shapes": ("generators.shapes", "ShapesGenerator"),
    "sql": ("generators.sql", "SqlGenerator"),
}


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
        """Write :meth:`serialize` to ``path`` atomically."""
        return write_atomic(path, self.serialize())

    def outputs(self) -> dict[str, str]:
        """Every file of the artefact: default file name -> text (one file unless overridden)."""
        return {f"{self.name}{self.file_extension}": self.serialize()}

    def write_outputs(self, folder: str | Path) -> list[Path]:
        """Write :meth:`outputs` into ``folder`` (each file atomically)."""
        return [write_atomic(Path(folder) / name, text) for name, text in self.outputs().items()]


def _registered() -> dict[str, str]:
    """Every known generator name -> ``module:Class`` (built-in names win)."""
    found = {ep.name: ep.value for ep in entry_points(group=ENTRY_POINT_GROUP)}
    found.update({name: f"{module}:{cls}" for name, (module, cls) in BUILTIN.items()})
    return found


def generator_names() -> list[str]:
    """The names :func:`get_generator` knows."""
    return sorted(_registered())


def get_generator(name: str) -> type[Generator]:
    """The generator class registered under ``name`` (its module imported now)."""
    target = BUILTIN.get(name)
    spec = f"{target[0]}:{target[1]}" if target else _registered().get(name)
    if spec is None:
        raise InputError(f"unknown generator {name!r} (known: {', '.join(generator_names())})")
    module, _, cls = spec.partition(":")
    try:
        found = getattr(importlib.import_module(module), cls)
    except (ImportError, AttributeError) as exc:
        raise InputError(f"generator {name!r} cannot be loaded from {spec}: {exc}") from None
    if not (isinstance(found, type) and issubclass(found, Generator)):
        raise InputError(f"generator {name!r} ({spec}) is not a kitkb Generator")
    return found
