"""From ontology files to a unified-planning problem, in either encoding.

``numeric``: the SOAP actions as they are (PDDL 2.1 numeric fluents), for ENHSP.
``strips``: the same actions with counts compiled into token objects
(:mod:`kb.planning.strips`), for Fast Downward and pyperplan.
"""

from __future__ import annotations

import importlib
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Sequence

from kb.core.errors import InputError
from kb.core.jobs import Forked
from kb.io.loader import domain_knowledge
from kb.model.definitions import locator, read_definitions
from kb.model.soap import DomainSpec, load_domain, read_domain, statements
from kb.patches.unified_planning import environment
from kb.planning.build import build_problem
from kb.planning.problem import ProblemSpec, load_world, read_problem, used_types
from kb.planning.state import ClassTree
from kb.planning.strips import compile_domain, compile_problem
from kb.spatial.unlocated import refuse_unlocated

ENCODINGS = ("strips", "numeric")


@dataclass
class KittingModel:
    """A domain (and optionally a problem) in one encoding, with the UP problem built from it."""

    encoding: str
    domain: DomainSpec
    problem: ProblemSpec | None
    up_problem: Any
    init_paths: tuple[str, ...] = ()
    goal_paths: tuple[str, ...] = ()


def domain_model(encoding: str = "strips", domain_files: Sequence[str | Path] | None = None) -> KittingModel:
    """The domain alone (no objects), in ``encoding``."""
    _check(encoding)
    domain, _graph = load_domain(domain_files)
    if encoding == "strips":
        domain, _quotas = compile_domain(domain)
    return KittingModel(encoding, domain, None, build_problem(domain))


def read_specs(init: Sequence[str | Path], goal: Sequence[str | Path], encoding: str = "strips",
               domain_files: Sequence[str | Path] | None = None,
               match_names: bool = False) -> tuple[DomainSpec, ProblemSpec]:
    """Domain and problem specs (no unified-planning yet) for ``init`` -> ``goal``.

    ``match_names``: the goal's individuals are those of the initial state with the same local
    name (for state files that name one workstation in two namespaces, as NIST's do); by
    default they are matched by IRI.
    """
    _check(encoding)
    kb = domain_knowledge(domain_files)
    domain = read_domain(kb.graph, locate=statements(kb))
    tree = ClassTree(kb.graph, used_types(domain))
    start = load_world(init, tree)
    refuse_unlocated(start.sources, "planning", start.g)  # a partial state: kitkb run senses it first
    spec = read_problem(domain, start, load_world(goal, tree, like=start if match_names else None),
                        definitions=read_definitions(kb.graph, locator(kb)), locate=locator(kb))
    return encoded(domain, spec, encoding)


def encoded(domain: DomainSpec, spec: ProblemSpec, encoding: str) -> tuple[DomainSpec, ProblemSpec]:
    """A numeric domain and problem (:func:`read_problem`'s) in ``encoding`` (neither is changed)."""
    _check(encoding)
    if encoding == "strips":
        domain, quotas = compile_domain(domain)
        spec = compile_problem(spec, quotas)
    return domain, spec


def model_of(domain: DomainSpec, spec: ProblemSpec, encoding: str = "strips",
             paths: tuple[Sequence[str | Path], Sequence[str | Path]] = ((), ())) -> KittingModel:
    """:func:`kitting_model` of a numeric domain and problem already read (``paths``: the init
    and goal files they were read from)."""
    domain, spec = encoded(domain, spec, encoding)
    return KittingModel(encoding, domain, spec, build_problem(domain, spec),
                        tuple(map(str, paths[0])), tuple(map(str, paths[1])))


def kitting_model(init: Sequence[str | Path], goal: Sequence[str | Path], encoding: str = "strips",
                  domain_files: Sequence[str | Path] | None = None, overlap: bool = False,
                  match_names: bool = False) -> KittingModel:
    """Domain and problem for going from the ``init`` state files to the ``goal`` ones.

    ``overlap``: read the files in a forked child process while this one imports
    unified-planning (two cores: start-up and reading then take the time of the longer one).
    The result is the same; any failure in the child falls back to reading here, so errors
    are reported exactly as without ``overlap``. ``match_names``: see :func:`read_specs`.
    """
    args = (init, goal, encoding, domain_files, match_names)
    specs = _read_specs_overlapped(*args) if overlap else None
    domain, spec = specs or read_specs(*args)
    return KittingModel(encoding, domain, spec, build_problem(domain, spec),
                        tuple(map(str, init)), tuple(map(str, goal)))


def _read_specs_overlapped(*args: Any) -> tuple[DomainSpec, ProblemSpec] | None:
    """:func:`read_specs` in a forked child while unified-planning is imported here; None
    when there is no child or it failed (the caller reads the files itself)."""
    if "unified_planning.model" in sys.modules:
        return None  # nothing left to overlap with
    job = Forked(lambda: read_specs(*args))
    try:
        environment()
        for module in ("unified_planning.model", "unified_planning.shortcuts"):
            importlib.import_module(module)  # the work the child's reading hides
    finally:
        ok, value = job.result()
    return value if ok else None  # type: ignore[return-value]


def _check(encoding: str) -> None:
    if encoding not in ENCODINGS:
        raise InputError(f"unknown encoding {encoding!r} (known: {', '.join(ENCODINGS)})")
