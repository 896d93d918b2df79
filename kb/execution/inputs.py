"""A closed loop's inputs, each file parsed once and handed to every stage.

:class:`LoopInputs` holds the loaded state files (their :class:`~kb.io.loader.Source`, with the
imports validation reads) and the domain's knowledge base (the domain files and the model
ontologies they import); what the stages need is made from them on first use and kept: the
domain (:class:`~kb.model.soap.DomainSpec`), the predicate definitions, the failure modes, the
two states' symbolic worlds and the numeric problem (the planner's facts), the planning model
in either encoding, the initial state's scene (the geometry check's, the executor's first
belief, a simulated cell's ground truth, each copying it) and the goal state's. The world-model load gets the
loaded files too (:func:`kb.execution.store.prepare`), so no stage opens a file again.

What is parsed, once each: the initial and goal state files, the domain files (default
``kitting-domain.ttl``) and the model ontologies they import. Outside this object: the shipped
model's class tree and unit annotations (read once per process, :mod:`kb.spatial.scene`,
:mod:`kb.model.units`), validation's shapes, and the N-Triples file the world-model load
streams (the initial state and the domain written out once, by kitkb, for the bulk loader).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from pathlib import Path
from typing import Any, Sequence

from kb.core.memory import gc_paused
from kb.core.resources import ontology_path
from kb.execution.programs import check_programs
from kb.io.loader import KnowledgeBase, Source, domain_knowledge, load
from kb.model.definitions import Definitions, locator, read_definitions
from kb.model.failures import FailureModel, read_failure_model
from kb.model.soap import DomainSpec, read_domain, statements
from kb.planning.model import KittingModel, encoded, model_of
from kb.planning.problem import ProblemSpec, read_problem, used_types, world_of
from kb.planning.state import ClassTree, World
from kb.spatial.scene import Scene


def _model_files() -> set[Path]:
    return {ontology_path(name).resolve() for name in ("soap.ttl", "kitting.ttl")}


@dataclass(frozen=True)
class PlanInputs:
    """What the executor needs of its files: the domain and the problem (numeric encoding),
    the initial state's scene (its first belief), the predicate definitions and the failure
    modes. A caller that runs many plans of one design (``kb.testmethod``) makes them once."""

    domain: DomainSpec
    problem: ProblemSpec
    scene: Scene
    definitions: Definitions
    failures: FailureModel


class DomainInputs:
    """The domain: the shipped ``kitting-domain.ttl`` and the extension files ``domain_files``
    (``--domain FILE...``; None or empty: the shipped domain alone) read once with their imports
    by :func:`kb.io.loader.domain_knowledge`, and what is made of them on first use: the planning
    domain, the predicate and function definitions, the failure modes. One serves every loop of
    a process that plans in the same domain (``kb.testmethod``'s trials); every reader of the
    domain (planner, executor, diagnosis, the simulator's fault kinds, the test methods) takes
    its knowledge from :attr:`kb` (its ``graph``, and ``locator(kb)`` for lines), so all see
    the same extended domain. ``files`` is the list actually read (the shipped file first)."""

    def __init__(self, domain_files: Sequence[str | Path] | None = None) -> None:
        #: the extension files as given (None: none)
        self.domain_files = list(domain_files) if domain_files else None

    @cached_property
    def kb(self) -> KnowledgeBase:
        """The shipped domain and the extensions with their imports (the model ontologies)."""
        return domain_knowledge(self.domain_files)

    @property
    def files(self) -> list[Path]:
        """The domain's own files in reading order (the shipped ``kitting-domain.ttl`` first,
        unless an extension is a modified copy of it), without the model ontologies."""
        return [s.path for s in self.kb.sources if s.path.resolve() not in _model_files()]

    @cached_property
    def domain(self) -> DomainSpec:
        """The planning domain (numeric) of the SOAP actions; an action program step the
        executor could not send is an InputError at its line, before anything is planned
        (:func:`kb.execution.programs.check_programs`)."""
        domain = read_domain(self.kb.graph, locate=statements(self.kb))
        check_programs(self.kb, domain)
        return domain

    @cached_property
    def definitions(self) -> Definitions:
        return read_definitions(self.kb.graph, locator(self.kb))

    @cached_property
    def failures(self) -> FailureModel:
        return read_failure_model(self.kb.graph, locator(self.kb))

    @cached_property
    def tree(self) -> ClassTree:
        """The classes of the state files' individuals that the domain's types cover."""
        return ClassTree(self.kb.graph, used_types(self.domain))


class LoopInputs:
    """The files of one closed loop, each parsed once; the stages' inputs made from them.

    ``states``: the state files as loaded (by validation, with their imports; or without);
    ``knowledge``: the domain (read on first use; one may be shared by many loops)."""

    def __init__(self, init: str | Path, goal: str | Path, states: KnowledgeBase, *,
                 domain_files: Sequence[str | Path] | None = None, match_names: bool = False,
                 knowledge: DomainInputs | None = None) -> None:
        self.init_path, self.goal_path = Path(init), Path(goal)
        self.states = states
        self.knowledge = knowledge or DomainInputs(domain_files)
        self.match_names = match_names
        by_path = {s.path.resolve(): s for s in states.sources}
        self.init: Source = by_path[self.init_path.resolve()]
        self.goal: Source = by_path[self.goal_path.resolve()]

    @classmethod
    def read(cls, init: str | Path, goal: str | Path, *, domain_files: Sequence[str | Path] | None = None,
             match_names: bool = False, imports: bool = True, knowledge: DomainInputs | None = None) -> "LoopInputs":
        """Read ``init`` and ``goal`` (with the files they import, which validation reads,
        unless ``imports`` is False); the domain is read when a stage first needs it."""
        states = load([init, goal], resolve_imports=imports)
        return cls(init, goal, states, domain_files=domain_files, match_names=match_names, knowledge=knowledge)

    # --- the domain -------------------------------------------------------------------------
    @property
    def domain(self) -> DomainSpec:
        return self.knowledge.domain

    @property
    def definitions(self) -> Definitions:
        return self.knowledge.definitions

    @property
    def failures(self) -> FailureModel:
        return self.knowledge.failures

    # --- the problem ------------------------------------------------------------------------
    @cached_property
    def worlds(self) -> tuple[World, World]:
        """The symbolic views of the initial and the goal state."""
        tree = self.knowledge.tree
        with gc_paused():
            start = world_of([self.init], tree)
            return start, world_of([self.goal], tree, like=start if self.match_names else None)

    @cached_property
    def problem(self) -> ProblemSpec:
        """The numeric problem: objects, the facts the planner is given, the goal."""
        start, end = self.worlds
        with gc_paused():  # the initial facts decided on the initial scene, by the domain's definitions
            return read_problem(self.domain, start, end, definitions=self.definitions, goal_scene=self.goal_scene,
                                scene=self.scene, locate=locator(self.knowledge.kb))

    def model(self, encoding: str = "strips") -> KittingModel:
        """The planning model (domain, problem, unified-planning problem) in ``encoding``."""
        return model_of(self.domain, self.problem, encoding, ([self.init_path], [self.goal_path]))

    def specs(self, encoding: str = "numeric") -> tuple[DomainSpec, ProblemSpec]:
        return encoded(self.domain, self.problem, encoding)

    # --- geometry ---------------------------------------------------------------------------
    @cached_property
    def scene(self) -> Scene:
        """The initial state's scene, the goal's individuals declared (matched by name with
        ``match_names``)."""
        with gc_paused():  # many small objects built beside the loaded files' millions: no collector passes
            return Scene.from_sources([self.init], declared=[self.goal], match_names=self.match_names)

    @cached_property
    def goal_scene(self) -> Scene:
        with gc_paused():
            return Scene.from_sources([self.goal])

    def plan_inputs(self) -> PlanInputs:
        """What the executor needs (:class:`PlanInputs`)."""
        return PlanInputs(self.domain, self.problem, self.scene, self.definitions, self.failures)

    def loaded(self) -> dict[Path, Any]:
        """Resolved path -> Source of every file read so far (for the world-model load)."""
        out = {s.path.resolve(): s for s in self.states.sources}
        if "kb" in self.knowledge.__dict__:
            out.update({s.path.resolve(): s for s in self.knowledge.kb.sources})
        return out
