"""Generators: artefacts derived from the ontologies (shapes, PDDL, SQL, accessors).

:data:`REGISTRY` maps a generator's name to ``(module, class)``; the module is imported
only when that generator is used, so importing :mod:`generators` costs nothing.
"""

from __future__ import annotations

import importlib
from typing import Any

REGISTRY: dict[str, tuple[str, str]] = {
    "shapes": ("generators.shapes", "ShapesGenerator"),
    "sql": ("generators.sql", "SqlGenerator"),
    "accessors": ("generators.accessors", "AccessorsGenerator"),
    "pddl-domain": ("generators.pddl_domain", "PddlDomainGenerator"),
    "pddl-problem": ("generators.pddl_problem", "PddlProblemGenerator"),
}


def get_generator(name: str) -> Any:
    """The generator class registered under ``name`` (imported on first use)."""
    from kb.errors import InputError

    try:
        module, cls = REGISTRY[name]
    except KeyError:
        known = ", ".join(sorted(REGISTRY)) or "none"
        raise InputError(f"unknown generator {name!r} (known: {known})") from None
    return getattr(importlib.import_module(module), cls)
