"""OWL reasoning: load files into owlready2 and check consistency with HermiT (Java).

owlready2 reads neither Turtle nor functional syntax, and would try to fetch ``owl:imports``
from the network. So the files go through :func:`kb.io.loader.load` (every format, imports
resolved through the catalog), and the union graph — without its ``owl:imports`` — is handed
to owlready2 as N-Triples.
"""

from __future__ import annotations

import shutil
import tempfile
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Sequence

import owlready2
from rdflib.namespace import OWL

from kb.core.errors import ConfigurationError
from kb.io.loader import load


@dataclass(frozen=True)
class ConsistencyReport:
    """What HermiT concluded: consistency, unsatisfiable classes, and counts."""

    consistent: bool
    unsatisfiable: tuple[str, ...]
    classes: int
    individuals: int
    explanation: str = ""


def to_owlready(paths: Sequence[str | Path]) -> tuple[Any, Any]:
    """Load ``paths`` (and their imports) into a fresh owlready2 World.

    Returns ``(world, ontology)``.
    """
    kb = load(paths)
    graph = kb.graph
    graph.remove((None, OWL.imports, None))
    world = owlready2.World()
    with tempfile.TemporaryDirectory(prefix="kitkb-owl-") as tmp:
        nt = Path(tmp) / "union.nt"
        graph.serialize(nt, format="nt", encoding="utf-8")
        onto = world.get_ontology(nt.as_uri()).load()
    return world, onto


def check_consistency(paths: Sequence[str | Path]) -> ConsistencyReport:
    """Run HermiT over ``paths``; needs a Java runtime (installed by ``scripts/setup.sh``)."""

    if shutil.which("java") is None:
        raise ConfigurationError("HermiT needs a Java runtime: install one (Debian: default-jre-headless)")
    world, onto = to_owlready(paths)
    try:
        with onto:
            owlready2.sync_reasoner_hermit(world, infer_property_values=False, debug=0)
    except owlready2.OwlReadyInconsistentOntologyError as exc:
        return ConsistencyReport(False, (), len(list(world.classes())), len(list(world.individuals())), str(exc))
    bad = tuple(sorted(c.iri for c in world.inconsistent_classes()))
    return ConsistencyReport(not bad, bad, len(list(world.classes())), len(list(world.individuals())))
