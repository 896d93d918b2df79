"""Kits that cannot be finished: the executor's half of :mod:`kb.planning.achievable`.

When the usable parts left cannot fill every kit (a replan's :func:`kb.planning.replan.restated`
finds a shortage, or a failure's remediation would stop the run because no usable part of a SKU
is left for its step), the executor does not stop: it plans for the achievable goal, the kits
the parts can finish (as many as possible, chosen by :func:`kb.planning.achievable.choose_kits`)
and each other kit as the partial-kit policy says: delivered partial or left. The policy is the
run's (``kitkb run --partial-kits``, :attr:`PartialKits.partial_kits`) over the domain's
(``soap:hasExecutionPolicy_PartialKits``: :attr:`kb.model.failures.FailureModel.delivers_partial_kits`);
with neither, a shortage stops the run as before.

Each decision is kept in the run record (``partial_kits``: each kit not finished, how it ends,
what it lacks, SKU -> count) and told as a :class:`~kb.execution.events.KitsChosen` event. The
goal the run is judged by is still the whole goal: a run with a partial or left kit does not
reach it (``goal_holds`` false).
"""

from __future__ import annotations

from typing import Iterable

from kb.execution.events import Event, KitsChosen
from kb.execution.records import RunRecord, local
from kb.model.failures import FailureModel
from kb.model.soap import DomainSpec
from kb.planning.achievable import check_policy, replan_achievable
from kb.planning.planners import PlanResult
from kb.planning.problem import ProblemSpec
from kb.planning.replan import replan, restated

Atom = tuple[str, ...]


class PartialKits:
    """The partial-kit policy and the replan to the achievable goal (a base of the executor)."""

    domain: DomainSpec
    spec: ProblemSpec
    failures: FailureModel
    planner: str | None
    record: RunRecord
    #: the run's partial-kit policy (``deliver`` | ``leave``); None: the domain's
    partial_kits: str | None = None

    def _emit(self, event: Event) -> None:
        raise NotImplementedError

    def kit_policy(self) -> str | None:
        """``deliver``, ``leave``, or None (no policy: a shortage stops the run)."""
        if self.partial_kits is not None:
            return check_policy(self.partial_kits)
        delivers = self.failures.delivers_partial_kits
        return None if delivers is None else ("deliver" if delivers else "leave")

    def plan_within_parts(self, facts: Iterable[Atom], values: dict[Atom, float],
                          excluded: Iterable[str]) -> PlanResult:
        """A plan from the state to the goal (:func:`kb.planning.replan.replan`), or, when the
        usable parts cannot fill every kit and a policy is given, to the achievable goal; the
        decision goes to the record and the events."""
        facts, excluded = set(facts), set(excluded)
        policy = self.kit_policy()
        if policy is None or not restated(self.spec, facts, values, excluded, self.domain).shortage:
            return replan(self.domain, self.spec, facts, values, excluded, self.planner)
        result, choice = replan_achievable(self.domain, self.spec, facts, values, excluded, policy, self.planner)
        self.record.partial_kits = choice.as_list()
        self._emit(KitsChosen([local(k) for k in choice.finished],
                              [(local(p["kit"]), p["outcome"], tuple(p["lacks"].items())) for p in self.record.partial_kits]))
        return result

    def short_and_decided(self, short: str) -> bool:
        """A failure that would stop the run for want of parts (``short``: :meth:`Recovery._shortage`'s
        reason) is replanned instead when a partial-kit policy is given."""
        return bool(short) and self.kit_policy() is not None
