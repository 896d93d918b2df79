"""Failure analysis: from the predicates a check found violated to the ontology's failure mode.

After a check of action A in phase P (precondition or effect) finds atoms violated, the
candidate modes are A's modes for P (:meth:`kb.model.failures.FailureModel.candidates`, most
likely first) whose every ``hasFailureMode_ViolatedPredicate`` is among the violated atoms'
predicates; the first whose condition holds where the objects really are (the condition is a
formula over A's parameters, evaluated on the sensed scene) is the diagnosis. No candidate
left: the failure is *unexplained* — recorded as such, never guessed.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Iterable

from kb.model.failures import FailureModel, FailureModeDef
from kb.spatial.predicates import Evaluator


@dataclass
class Diagnosis:
    """The failure mode found (None: unexplained) and the modes that were considered."""

    mode: FailureModeDef | None
    considered: list[str] = field(default_factory=list)
    rejected: dict[str, str] = field(default_factory=dict)  # mode -> why it was not taken

    @property
    def name(self) -> str:
        return self.mode.name if self.mode is not None else "unexplained"


def diagnose(model: FailureModel, evaluator: Evaluator, action: str, phase: str, violated: Iterable[str],
             args: dict[str, str]) -> Diagnosis:
    """The failure mode of ``action`` whose signal and condition match.

    ``violated``: predicate names of the violated atoms; ``args``: parameter name -> object
    IRI of the plan step as executed.
    """
    seen = set(violated)
    params = model.parameters.get(action, {})
    bindings = {iri: args[name] for iri, name in params.items() if name in args}
    out = Diagnosis(None)
    for mode in model.candidates(action, phase):
        out.considered.append(mode.name)
        if not mode.violated <= seen:
            out.rejected[mode.name] = "signal: needs " + ", ".join(sorted(mode.violated - seen)) + " violated"
            continue
        if mode.condition is not None and not evaluator.holds_formula(mode.condition, bindings):
            out.rejected[mode.name] = "condition does not hold"
            continue
        out.mode = mode
        break
    return out


__all__ = ["Diagnosis", "diagnose"]
