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


def read_specs(init: Sequence[str | Path], goal: Sequence[str | Path], encoding: str = "strips",
               domain_files: Sequence[str | Path] | None = None) -> tuple[DomainSpec, ProblemSpec]:
    """Domain and problem specs (no unified-planning yet) for ``init`` -> ``goal``."""
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
    return domain, spec


def kitting_model(init: Sequence[str | Path], goal: Sequence[str | Path], encoding: str = "strips",
                  domain_files: Sequence[str | Path] | None = None, overlap: bool = False) -> KittingModel:
    """Domain and problem for going from the ``init`` state files to the ``goal`` ones.

    ``overlap``: read the files in a forked child process while this one imports
    unified-planning (two cores: start-up and reading then take the time of the longer one).
    The result is the same; any failure in the child falls back to reading here, so errors
    are reported exactly as without ``overlap``.
    """
    from generators.pddl.build import build_problem

    specs = _read_specs_forked(init, goal, encoding, domain_files) if overlap else None
    domain, spec = specs or read_specs(init, goal, encoding, domain_files)
    return KittingModel(encoding, domain, spec, build_problem(domain, spec),
                        tuple(map(str, init)), tuple(map(str, goal)))


def _read_specs_forked(init: Sequence[str | Path], goal: Sequence[str | Path], encoding: str,
                       domain_files: Sequence[str | Path] | None) -> tuple[DomainSpec, ProblemSpec] | None:
    """:func:`read_specs` in a forked child while unified-planning is imported here; None on failure."""
    import os
    import pickle
    import sys

    if not hasattr(os, "fork") or "unified_planning.model" in sys.modules:
        return None
    read_fd, write_fd = os.pipe()
    pid = os.fork()
    if pid == 0:  # child: read, send the specs, leave without running any clean-up
        status = 1
        try:
            os.close(read_fd)
            data = pickle.dumps(read_specs(init, goal, encoding, domain_files), pickle.HIGHEST_PROTOCOL)
            with os.fdopen(write_fd, "wb") as out:
                out.write(data)
            status = 0
        except BaseException:  # noqa: BLE001 - the parent reads again and reports the error
            pass
        finally:
            os._exit(status)
    os.close(write_fd)
    try:
        from generators.pddl.up_env import environment

        environment()
        import unified_planning.model  # noqa: F401 - the import the child's time hides
        import unified_planning.shortcuts  # noqa: F401
    finally:
        with os.fdopen(read_fd, "rb") as pipe:
            data = pipe.read()
        _pid, status = os.waitpid(pid, 0)
    if status != 0 or not data:
        return None
    try:
        return pickle.loads(data)
    except Exception:  # noqa: BLE001 - fall back to reading in this process
        return None


def _check(encoding: str) -> None:
    from kb.errors import InputError

    if encoding not in ENCODINGS:
        raise InputError(f"unknown encoding {encoding!r} (known: {', '.join(ENCODINGS)})")
