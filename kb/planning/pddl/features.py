"""Where a PDDL file first uses each language feature, so that a feature no installed
planner (or unified-planning's validator) takes is refused at its ``file:line``.

unified-planning describes a problem by its kind (``problem.kind.features``: flags such as
``CONDITIONAL_EFFECTS``); :data:`KIND_FEATURES` says which PDDL construct sets each flag.
"""

from __future__ import annotations

from pathlib import Path

from kb.planning.pddl.sexp import Node

DURATIVE = "durative actions (:durative-action)"
NUMERIC = "numeric fluents (:functions)"
CONDITIONAL = "conditional effects (when)"
FORALL_EFFECT = "universal effects (forall in an effect)"
FORALL = "universal conditions (forall)"
EXISTS = "existential conditions (exists)"
DISJUNCTION = "disjunctive conditions (or, imply)"
NEGATION = "negative conditions (not)"
EQUALITY = "equality (=)"
TIMED_LITERALS = "timed initial literals ((at N ...) in :init)"
CONSTRAINTS = "trajectory constraints (:constraints)"
PROCESSES = "processes (:process)"
EVENTS = "events (:event)"
CONTINUOUS = "continuous effects (#t)"
COSTS = "action costs (total-cost)"
METRIC = "a metric (:metric)"
TYPES = "types (:types)"
UNDEFINED = "fluents without an initial value"
RECURSIVE = "recursive derived predicates"

#: unified-planning ProblemKind flag -> the PDDL feature that sets it.
KIND_FEATURES = {
    **dict.fromkeys(("CONTINUOUS_TIME", "DISCRETE_TIME", "INTERMEDIATE_CONDITIONS_AND_EFFECTS",
                     "EXTERNAL_CONDITIONS_AND_EFFECTS", "TIMED_GOALS", "DURATION_INEQUALITIES",
                     "SELF_OVERLAPPING", "STATIC_FLUENTS_IN_DURATIONS", "FLUENTS_IN_DURATIONS",
                     "REAL_TYPE_DURATIONS", "INT_TYPE_DURATIONS"), DURATIVE),
    "TIMED_EFFECTS": TIMED_LITERALS,
    **dict.fromkeys(("INT_FLUENTS", "REAL_FLUENTS", "SIMPLE_NUMERIC_PLANNING", "GENERAL_NUMERIC_PLANNING",
                     "INCREASE_EFFECTS", "DECREASE_EFFECTS", "FLUENTS_IN_NUMERIC_ASSIGNMENTS",
                     "STATIC_FLUENTS_IN_NUMERIC_ASSIGNMENTS", "NUMERIC_FLUENTS"), NUMERIC),
    "UNDEFINED_INITIAL_NUMERIC": UNDEFINED,
    "CONDITIONAL_EFFECTS": CONDITIONAL,
    "FORALL_EFFECTS": FORALL_EFFECT,
    "UNIVERSAL_CONDITIONS": FORALL,
    "EXISTENTIAL_CONDITIONS": EXISTS,
    "DISJUNCTIVE_CONDITIONS": DISJUNCTION,
    "NEGATIVE_CONDITIONS": NEGATION,
    "EQUALITIES": EQUALITY,
    "TRAJECTORY_CONSTRAINTS": CONSTRAINTS,
    "STATE_INVARIANTS": CONSTRAINTS,
    "PROCESSES": PROCESSES,
    "EVENTS": EVENTS,
    **dict.fromkeys(("INCREASE_CONTINUOUS_EFFECTS", "DECREASE_CONTINUOUS_EFFECTS",
                     "NON_LINEAR_CONTINUOUS_EFFECTS"), CONTINUOUS),
    **dict.fromkeys(("CONTINUOUS_NUMBERS", "DISCRETE_NUMBERS"), NUMERIC),
    "UNDEFINED_INITIAL_SYMBOLIC": UNDEFINED,
    **dict.fromkeys(("ACTIONS_COST", "STATIC_FLUENTS_IN_ACTIONS_COST", "FLUENTS_IN_ACTIONS_COST",
                     "INT_NUMBERS_IN_ACTIONS_COST", "REAL_NUMBERS_IN_ACTIONS_COST"), COSTS),
    **dict.fromkeys(("FINAL_VALUE", "MAKESPAN", "PLAN_LENGTH", "OVERSUBSCRIPTION",
                     "TEMPORAL_OVERSUBSCRIPTION"), METRIC),
    "RECURSIVE_DERIVED_PREDICATES": RECURSIVE,  # kitkb's flag: only some planners read axioms
    "FLAT_TYPING": TYPES,
    "HIERARCHICAL_TYPING": TYPES,
}


class Features:
    """The first place each feature is used: feature -> (file, line)."""

    def __init__(self) -> None:
        self.first: dict[str, tuple[Path, int]] = {}

    def note(self, feature: str, path: Path, where: Node | int) -> None:
        """Remember ``where`` (a node or a line) if ``feature`` was not seen before."""
        line = where if isinstance(where, int) else where.line
        if feature not in self.first and line:
            self.first[feature] = (path, line)

    def explain(self, kind_flags: list[str] | set[str]) -> tuple[str, tuple[Path, int] | None]:
        """The PDDL features behind unified-planning's ``kind_flags``, and the file and line
        of the first use of the first of them used in the files (None if none is)."""
        named: list[str] = []
        for flag in sorted(kind_flags):
            feature = KIND_FEATURES.get(flag, flag)
            if feature not in named:
                named.append(feature)
        named.sort(key=lambda f: f not in self.first)
        places = [self.first[f] for f in named if f in self.first]
        return ", ".join(named), (places[0] if places else None)
