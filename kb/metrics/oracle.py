"""The oracle of what was buildable: from the cell's ground truth at the end of a run, the most
kits of the goal that could have been finished with the usable parts that existed
(``kits_buildable``), and ``completion`` = kits built / kits buildable.

It reads no belief of the executor: each part's and kit tray's fate comes from the cell
(:class:`kb.crcl.cell.Fate`: where it truly is, what it truly is, whether the robot could take
it from there), the kits' designs from the goal, the SKUs the run was told from its initial
state. docs/metrics.md ("What was buildable") has the rules; in short:

* a **built** kit (every point of its score, :mod:`kb.metrics.kits`) counts as buildable, and
  the parts and the tray in it count for it and for nothing else (delivered, they are done);
* every other part or kit tray is **usable** when it is in the cell, not defective, of the SKU
  the run's state records for it (one the state does not record: of the SKU it truly is), and
  either lies in a kit (the robot put it there: it could have gone anywhere) or is
  **reachable** (not on the floor, within the robot's work volume, or held by the robot);
* the other kits of the goal each need their design's parts per SKU and a kit tray of the
  design's tray SKU; ``kits_buildable`` = built kits + the largest number of other kits whose
  needs the usable parts and trays cover together (exact: kits of the same needs are grouped
  and every count of each group tried, largest first, with a bound);
* ``completion`` = built / buildable; 1.0 when nothing was buildable and nothing was built
  (the run left nothing buildable undone). Built kits count in both, so it never exceeds 1.
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass, field
from typing import Any, Collection, Iterable, Mapping, Sequence

from kb.crcl.cell import Fate
from kb.metrics.kits import KitGoal

#: why a part or kit tray is not counted, in the order the reasons are decided
REASONS = ("gone", "defective", "other-sku", "no-sku", "floor", "out-of-reach")


def _local(iri: str | None) -> str:
    return "?" if iri is None else str(iri).rsplit("#", 1)[-1].rsplit("/", 1)[-1]


@dataclass(frozen=True)
class Buildable:
    """What the oracle found: ``kits_buildable``, ``kits_built`` (the goal's kits with every
    point of their score), ``completion``; ``kits`` the goal's kits; ``usable`` each SKU's
    usable parts and kit trays outside the built kits (local name -> count); ``not_counted``
    each part or tray left out and why (:data:`REASONS`)."""

    kits_buildable: int
    kits_built: int
    kits: int
    usable: dict[str, int] = field(default_factory=dict)
    not_counted: list[dict[str, str]] = field(default_factory=list)

    @property
    def completion(self) -> float:
        """Kits built / kits buildable; 1.0 when neither is any."""
        return 1.0 if self.kits_buildable == 0 else self.kits_built / self.kits_buildable

    def as_dict(self) -> dict[str, Any]:
        """As JSON data (the run record's ``oracle``)."""
        return {"kits_buildable": self.kits_buildable, "kits_built": self.kits_built, "kits": self.kits,
                "completion": round(self.completion, 6), "usable": dict(self.usable),
                "not_counted": [dict(x) for x in self.not_counted]}


def why_not(fate: Fate, recorded: str | None) -> str | None:
    """Why ``fate``'s object cannot go into a kit (one of :data:`REASONS`), None when it can
    (``recorded``: the SKU the run's state gives it, None: none)."""
    if fate.place == "gone":
        return "gone"
    if fate.defective:
        return "defective"
    if recorded is not None and fate.sku != recorded:
        return "other-sku"
    if fate.sku is None:
        return "no-sku"
    if fate.place == "floor":
        return "floor"
    if not fate.reachable and fate.kit is None:
        return "out-of-reach"
    return None


def needs(goal: KitGoal) -> Counter[str]:
    """What one kit of ``goal`` needs: its design's parts per SKU and one kit tray of its tray
    SKU (SKU IRI -> count)."""
    out: Counter[str] = Counter(slot.sku for slot in goal.slots)
    if goal.tray_sku is not None:
        out[goal.tray_sku] += 1
    return out


def buildable(fates: Iterable[Fate], goals: Sequence[KitGoal], recorded: Mapping[str, str],
              built: Collection[str]) -> Buildable:
    """The oracle over ``fates`` (the cell's ground truth at the end of the run) for the kits of
    ``goals``; ``recorded``: each object's SKU in the run's initial state (IRI -> SKU IRI);
    ``built``: the goal's kits built (every point of their score)."""
    named = {_local(k) for k in built}  # kits are matched by local name (a report's are local)
    done = {_local(g.kit) for g in goals if _local(g.kit) in named}
    pool: Counter[str] = Counter()
    left_out: list[dict[str, str]] = []
    for fate in fates:
        if fate.kit is not None and _local(fate.kit) in done:
            continue  # counts for its built kit
        reason = why_not(fate, recorded.get(fate.name))
        if reason is None:
            pool[fate.sku] += 1  # type: ignore[index]
        else:
            left_out.append({"name": _local(fate.name), "kind": fate.kind, "why": reason, "place": fate.place})
    others = [needs(g) for g in goals if _local(g.kit) not in done]
    more = most_kits(others, pool)
    return Buildable(len(done) + more, len(done), len(goals),
                     {_local(s): n for s, n in sorted(pool.items())}, left_out)


def most_kits(kits: Sequence[Mapping[str, int]], pool: Mapping[str, int]) -> int:
    """The largest number of ``kits`` (each its needs, SKU -> count) the ``pool`` (SKU ->
    count) covers together. Kits of equal needs are one group; each group's count is tried
    from the largest the pool allows down, groups with the fewest needs first, a branch cut
    when even every remaining kit could not beat the best found."""
    groups: Counter[tuple[tuple[str, int], ...]] = Counter(
        tuple(sorted((s, n) for s, n in k.items() if n > 0)) for k in kits)
    order = sorted(groups.items(), key=lambda g: (sum(n for _, n in g[0]), g[0]))
    have = dict(pool)
    best = 0

    def fits(need: tuple[tuple[str, int], ...], left: dict[str, int]) -> int:
        return min((left.get(s, 0) // n for s, n in need), default=len(kits))

    def search(i: int, count: int, left: dict[str, int]) -> None:
        nonlocal best
        if count > best:
            best = count
        if i == len(order):
            return
        if count + sum(c for _, c in order[i:]) <= best:
            return
        need, available = order[i]
        for take in range(min(available, fits(need, left)), -1, -1):
            rest = dict(left)
            for s, n in need:
                rest[s] = rest.get(s, 0) - n * take
            search(i + 1, count + take, rest)
            if best == len(kits):
                return
    search(0, 0, have)
    return best
