"""The typed planning model between the ontology and unified-planning.

The SOAP reader (:mod:`generators.pddl.soap_reader`) fills a :class:`DomainSpec`; the
workstation reader (:mod:`generators.pddl.state`) fills a :class:`ProblemSpec`. The
builders (:mod:`generators.pddl.build`) turn both into a ``unified_planning`` problem.
Every element keeps the IRI of the ontology individual it comes from (``source``), so that
written PDDL and plans lead back to the ontology.
"""

from __future__ import annotations

from dataclasses import dataclass, field


@dataclass(frozen=True)
class Signature:
    """A predicate or function: name, argument types (class IRIs), source IRI."""

    name: str
    arg_types: tuple[str, ...]
    source: str


@dataclass(frozen=True)
class Atom:
    """A predicate applied to action parameters (by name); ``negated`` for not / delete."""

    predicate: str
    args: tuple[str, ...]
    negated: bool = False
    source: str = ""


@dataclass(frozen=True)
class FTerm:
    """A function applied to action parameters (by name)."""

    function: str
    args: tuple[str, ...]


@dataclass(frozen=True)
class Comparison:
    """``left op right`` with op one of < <= = >= >; right is a term or a number."""

    op: str
    left: FTerm
    right: FTerm | float
    source: str = ""


@dataclass(frozen=True)
class NumericEffect:
    """``increase``/``decrease``/``assign`` of a term by a number or another term."""

    kind: str
    term: FTerm
    amount: FTerm | float
    source: str = ""


@dataclass
class ActionSpec:
    """One SOAP action: ordered typed parameters, precondition and effect."""

    name: str
    source: str
    params: list[tuple[str, str]]  # (name, class IRI) in declared order
    pre: list[Atom] = field(default_factory=list)
    comparisons: list[Comparison] = field(default_factory=list)
    effects: list[Atom] = field(default_factory=list)
    numeric: list[NumericEffect] = field(default_factory=list)

    def param_type(self, name: str) -> str:
        """Class IRI of the parameter called ``name``."""
        return dict(self.params)[name]


@dataclass(frozen=True)
class FunctionSpec(Signature):
    """A numeric function plus how the ontology defines it.

    ``kind`` is the local name of the definition's class (``CountExpression``,
    ``DesignCountExpression``); ``counted`` the class IRI a count expression counts.
    """

    kind: str = ""
    counted: str = ""


@dataclass
class DomainSpec:
    """A planning domain read from the SOAP instances."""

    name: str
    source: str
    types: dict[str, str | None]  # class IRI -> parent class IRI (None for a root)
    predicates: dict[str, Signature]
    functions: dict[str, FunctionSpec]
    actions: list[ActionSpec]


@dataclass
class ProblemSpec:
    """Objects, initial state and goal read from a workstation's init and goal files.

    ``objects`` maps a PDDL object name to (domain type IRI, individual IRI).
    ``facts`` are ground atoms true initially, ``values`` ground function values,
    ``goal`` ground atoms, ``goal_equal`` pairs of ground terms that must be equal.
    ``quota`` lists, per (function, args), the objects that may fill it (STRIPS tokens).
    """

    name: str
    objects: dict[str, tuple[str, str]] = field(default_factory=dict)
    facts: set[tuple[str, ...]] = field(default_factory=set)
    values: dict[tuple[str, ...], float] = field(default_factory=dict)
    goal: list[tuple[str, ...]] = field(default_factory=list)
    goal_equal: list[tuple[tuple[str, ...], tuple[str, ...]]] = field(default_factory=list)
    quota: dict[tuple[str, ...], list[str]] = field(default_factory=dict)
    shortage: list[str] = field(default_factory=list)  # quotas that cannot be filled
    sources: dict[str, str] = field(default_factory=dict)  # what -> file:line it came from
