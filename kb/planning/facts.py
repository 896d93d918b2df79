"""The initial state of a planning problem, decided by the predicates' and functions' own
definitions on the state's scene (no code per predicate name).

An atom ``p(a, b)`` is true initially when ``p``'s ``soap:hasPredicate_Definition`` holds for
``a`` and ``b`` on the initial state's geometry and facts: the evaluation ``kitkb predicates``
makes (:class:`kb.spatial.predicates.Evaluator`, every argument pair of a predicate at once on
the scene's world boxes). A function's value is its ``soap:hasFunction_Definition`` counted
the same way. Static facts (``part-sku``, ``endeffector-type-*``, ``kit-kittray``) are the same
kind of atoms, decided by their SKU and model atoms on the scene's facts; the scene of the
initial state declares the goal state's individuals (with their model facts, without geometry:
NIST's kits exist only in the goal), so an object named only in the goal contributes its
static facts.

Every predicate and function of the planning domain must have a definition; one that has none,
or whose definition cannot be evaluated, is an :class:`~kb.core.errors.InputError` at the file
and line of its node (the domain's reader reports malformed definitions the same way).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable

from rdflib import URIRef

from kb.core.errors import InputError
from kb.model.definitions import Definitions, Locator
from kb.model.soap import DomainSpec
from kb.spatial.predicates import Evaluator
from kb.spatial.scene import Scene

#: An atom's arguments: the scene's object IRIs.
Args = tuple[str, ...]


@dataclass
class InitialState:
    """The atoms true in a scene (``(predicate, args)``, sorted) and the function values
    (``(function, *args) -> value``; argument tuples of every object of the function's classes)."""

    atoms: list[tuple[str, Args]] = field(default_factory=list)
    values: dict[tuple[str, ...], int] = field(default_factory=dict)


def initial_state(domain: DomainSpec, defs: Definitions, scene: Scene, locate: Locator | None = None,
                  evaluator: Evaluator | None = None) -> InitialState:
    """The atoms of ``domain``'s predicates and the values of its functions that hold in
    ``scene`` by their definitions in ``defs`` (``locate``: where a domain node is written, for
    the error of one without a definition; ``evaluator``: one already made on ``scene``)."""
    _check_defined(domain, defs, locate or (lambda node: (None, None)))
    ev = evaluator or Evaluator(defs, scene)
    out = InitialState(ev.facts(sorted(domain.predicates)))
    for name in sorted(domain.functions):
        for args, value in ev.function_values(name).items():
            out.values[(name, *args)] = value
    return out


def _check_defined(domain: DomainSpec, defs: Definitions, locate: Callable) -> None:
    """InputError at its line for a predicate or function of the domain with no definition."""
    for kind, used, defined in (("predicate", domain.predicates, defs.predicates),
                                ("function", domain.functions, defs.functions)):
        for name in sorted(set(used) - set(defined)):
            file, line = locate(URIRef(used[name].source))
            raise InputError(f"{kind} {name} has no definition kitkb can evaluate (soap:has{kind.title()}_Definition): "
                             "its initial truth cannot be decided", file, line)
