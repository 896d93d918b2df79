"""From ontology files to a unified-planning problem, in either encoding.

``numeric``: the SOAP actions as they are (PDDL 2.1 numeric fluents), for ENHSP.
``strips``: the same actions with counts compiled into token objects
(:mod:`generators.pddl.strips`), for Fast Downward and pyperplan.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any, Sequence

from generators.pddl.spec import DomainSpec, ProblemSpec

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


def load_domain(domain_files: Sequence[str | Path] | None = None) -> tuple[DomainSpec, Any]:
    """The numeric domain read from the SOAP instances, and the graph it was read from."""
    from generators.pddl.soap_reader import read_domain
    from kb.loader import load
    from kb.resources import ontology_path

    kb = load(list(domain_files) if domain_files else [ontology_path("kitting-domain.ttl")])
    return read_domain(kb.graph), kb.graph


def domain_model(encoding: str = "strips", domain_files: Sequence[str | Path] | None = None) -> KittingModel:
    """The domain alone (no objects), in ``encoding``."""
    from generators.pddl.build import build_problem
    from generators.pddl.strips import compile_domain

    _check(encoding)
    domain, _graph = load_domain(domain_files)
    if encoding == "strips":
        domain, _quotas = compile_domain(domain)
    return KittingModel(encoding, domain, None, build_problem(domain))


def kitting_model(init: Sequence[str | Path], goal: Sequence[str | Path], encoding: str = "strips",
                  domain_files: Sequence[str | Path] | None = None) -> KittingModel:
    """Domain and problem for going from the ``init`` state files to the ``goal`` ones."""
    from generators.pddl.build import build_problem
    from generators.pddl.problem import load_world, read_problem, used_types
    from generators.pddl.strips import compile_domain, compile_problem
    from generators.pddl.world import ClassTree

    _check(encoding)
    domain, graph = load_domain(domain_files)
    tree = ClassTree(graph, used_types(domain))
    start = load_world(init, tree)
    spec = read_problem(domain, start, load_world(goal, tree, like=start))
    if encoding == "strips":
        domain, quotas = compile_domain(domain)
        spec = compile_problem(spec, quotas)
    return KittingModel(encoding, domain, spec, build_problem(domain, spec),
                        tuple(map(str, init)), tuple(map(str, goal)))


def _check(encoding: str) -> None:
    from kb.errors import InputError

    if encoding not in ENCODINGS:
        raise InputError(f"unknown encoding {encoding!r} (known: {', '.join(ENCODINGS)})")
