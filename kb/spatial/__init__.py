"""Geometry of the workstation and the predicates it decides.

* :mod:`.transforms`: 6-DoF poses as 4x4 transforms, equation (1) of the world model;
* :mod:`.rcc8`: the 24 RCC8 (per axis) and 6 cardinal-direction relations of world boxes,
  N x M pairs in one call;
* :mod:`.scene`: the objects of a state (file or simulator), their classes, model facts and
  world boxes;
* :mod:`.predicates`: the SOAP predicates and functions evaluated on a scene from their Turtle
  definitions (:mod:`kb.model.definitions`);
* :mod:`.sweep`: continuous contact: the solids oriented boxes pass through as they move along
  a path (:func:`sweep_contacts`; open containers as floor and walls).
"""

from __future__ import annotations

from pathlib import Path
from typing import Iterable, Sequence

from kb.model.definitions import load_definitions
from kb.spatial.predicates import Evaluator
from kb.spatial.rcc8 import DEFAULT_TOLERANCE
from kb.spatial.scene import Scene
from kb.spatial.sweep import sweep_contacts


def true_predicates(state: Sequence[str | Path], goal: str | Path | None = None, match_names: bool = False,
                    domain_files: Sequence[str | Path] | None = None, names: Iterable[str] | None = None,
                    tolerance: float | None = None) -> list[tuple[str, tuple[str, ...]]]:
    """Every atom ``(predicate, args)`` that holds in the state files, from their geometry.

    ``goal``: a goal state file whose own individuals (e.g. NIST's kits) are added without
    geometry, as the PDDL generator reads them; ``names``: only these predicates.
    """
    defs = load_definitions(domain_files)
    scene = Scene.from_files(list(state), declared=[goal] if goal else (), match_names=match_names)
    ev = Evaluator(defs, scene, DEFAULT_TOLERANCE if tolerance is None else tolerance)
    return ev.facts(names)


__all__ = ["DEFAULT_TOLERANCE", "Evaluator", "Scene", "sweep_contacts", "true_predicates"]
