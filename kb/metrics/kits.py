"""Kit scores: how much of each kit the goal asks for was built, and for every point lost the
predicate that does not hold and its objects (ARIAC scores kits but cannot say why).

A kit's points, decided by the ontology's predicates (:class:`kb.spatial.predicates.Evaluator`)
on the cell as sensed at the end of a run:

* **1 — the right kit tray**: the kit is built (seen in the cell) on a kit tray
  (``kit-kittray``) of the SKU its design names (``hasKitDesign_KitTraySku``; the tray's
  ``hasSkuObject_Sku``);
* **1 per design slot** (``PartRefAndPose``) **filled with the right SKU**: a part lies in the
  kit (``part-location-kit``) at the slot — its centre within half its own smaller footprint
  side of the slot's point, in the kit's frame; each part fills at most one slot, nearest
  first — and is of the slot's SKU (``part-sku``) and not found defective (``part-quality-ok``:
  the executor has the cell inspect every part in a goal kit at the end of the run,
  :meth:`kb.execution.executor.Executor.inspect_kits`, and the scene carries those results);
* **1 — no extra parts**: no part lies in the kit outside its slots;
* **1 — delivered**: the kit is in the finished-kit box the goal names (``kit-location-lbwk``).

``score = max_score - points lost``; docs/metrics.md has the table and the choices made.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Iterable

import numpy as np

from kb.core.errors import KitkbError
from kb.spatial.predicates import Evaluator

_KTW = "https://w3id.org/kitkb/kitting#"
SKU_OF = _KTW + "hasSkuObject_Sku"


def _local(iri: str | None) -> str:
    return "?" if iri is None else str(iri).rsplit("#", 1)[-1].rsplit("/", 1)[-1]


@dataclass(frozen=True)
class Slot:
    """A design slot: its PartRefAndPose, SKU, and pose in the kit's (its tray's) frame (m)."""

    name: str
    sku: str
    pose: np.ndarray


@dataclass(frozen=True)
class KitGoal:
    """What the goal asks of one kit: its design's tray SKU and slots, the box it goes to."""

    kit: str
    design: str | None
    tray_sku: str | None
    slots: tuple[Slot, ...]
    box: str | None


@dataclass(frozen=True)
class LostPoint:
    """A point a kit lost: why, the predicate that does not hold as the goal wants (``holds``:
    what it is), its objects."""

    points: int
    reason: str
    predicate: str
    objects: tuple[str, ...]
    holds: bool = False

    def as_dict(self) -> dict[str, Any]:
        return {"points": self.points, "reason": self.reason, "predicate": self.predicate,
                "objects": [_local(o) for o in self.objects], "holds": self.holds}


@dataclass(frozen=True)
class KitScore:
    """One kit's score out of ``max_score``, with the points lost."""

    kit: str
    design: str | None
    score: int
    max_score: int
    lost: tuple[LostPoint, ...] = field(default=())

    def as_dict(self) -> dict[str, Any]:
        return {"kit": _local(self.kit), "design": _local(self.design) if self.design else None,
                "score": self.score, "max_score": self.max_score, "lost": [x.as_dict() for x in self.lost]}

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> "KitScore":
        """A score back from its JSON data (names as written: local names)."""
        lost = tuple(LostPoint(int(x["points"]), str(x["reason"]), str(x["predicate"]), tuple(x["objects"]),
                               bool(x.get("holds", False))) for x in data.get("lost", ()))
        return cls(str(data["kit"]), data.get("design"), int(data["score"]), int(data["max_score"]), lost)


def score_kits(goals: Iterable[KitGoal], ev: Evaluator) -> list[KitScore]:
    """Each goal kit's score on the scene of ``ev``."""
    return [_score(goal, ev) for goal in goals]


def _score(goal: KitGoal, ev: Evaluator) -> KitScore:
    scene = ev.scene
    kit = goal.kit
    lost: list[LostPoint] = []
    max_score = 3 + len(goal.slots)
    k = scene.index.get(kit)
    if goal.box is None:
        max_score -= 1
    if k is None or not scene.placed[k]:  # never built (or gone): nothing of it holds
        lost.append(LostPoint(2, f"{_local(kit)} was not built: it is not in the cell (the tray and the no-extra-"
                                 f"parts points)", "kit-kittray", (kit,)))
        lost.extend(LostPoint(1, f"slot {_local(s.name)} ({_local(s.sku)}) is empty: {_local(kit)} was not built",
                              "part-location-kit", (kit, s.name)) for s in goal.slots)
        if goal.box is not None:
            lost.append(LostPoint(1, f"{_local(kit)} was not delivered to {_local(goal.box)}", "kit-location-lbwk",
                                  (kit, goal.box)))
        return KitScore(kit, goal.design, 0, max_score, tuple(lost))
    lost.extend(_tray(goal, ev))
    lost.extend(_slots(goal, ev, scene.poses[k]))
    if goal.box is not None and not _holds(ev, "kit-location-lbwk", kit, goal.box):
        lost.append(LostPoint(1, f"{_local(kit)} is not in {_local(goal.box)}", "kit-location-lbwk", (kit, goal.box)))
    return KitScore(kit, goal.design, max_score - sum(x.points for x in lost), max_score, tuple(lost))


def _holds(ev: Evaluator, predicate: str, *args: str) -> bool:
    try:
        return ev.holds(predicate, *args)
    except KitkbError:  # an object the scene does not know: the atom does not hold
        return False


def _sku(ev: Evaluator, obj: str) -> str | None:
    skus = [o for s, o in ev.scene.facts.get(SKU_OF, ()) if s == obj]
    return skus[0] if len(skus) == 1 else None


def _tray(goal: KitGoal, ev: Evaluator) -> list[LostPoint]:
    """The kit-tray point: built on a tray of the design's tray SKU."""
    kit = goal.kit
    try:
        _refs, trays, truth = ev.table("kit-kittray", [kit])
    except KitkbError:
        trays, truth = [], np.zeros((1, 0), bool)
    on = [t for t, ok in zip(trays, np.asarray(truth).reshape(-1)) if ok]
    if not on:
        return [LostPoint(1, f"{_local(kit)} is on no kit tray", "kit-kittray", (kit,))]
    sku = _sku(ev, on[0])
    if goal.tray_sku is not None and sku != goal.tray_sku:
        return [LostPoint(1, f"{_local(kit)} is on {_local(on[0])} of SKU {_local(sku)}, the design asks for "
                             f"{_local(goal.tray_sku)}", "hasSkuObject_Sku", (on[0], goal.tray_sku))]
    return []


def _slots(goal: KitGoal, ev: Evaluator, kit_pose: np.ndarray) -> list[LostPoint]:
    """The slot points and the no-extra-parts point."""
    kit, scene = goal.kit, ev.scene
    try:
        parts, _kits, truth = ev.table("part-location-kit", None, [kit])
    except KitkbError:
        parts, truth = [], np.zeros((0, 1), bool)
    inside = [p for p, ok in zip(parts, np.asarray(truth).reshape(-1)) if ok]
    inv = np.linalg.inv(kit_pose)
    pairs = []  # (distance, part, slot index) of every part near enough to a slot
    for p in inside:
        i = scene.index[p]
        at = (inv @ scene.poses[i])[:3, 3]
        reach = 0.5 * float(np.min((scene.local_hi[i] - scene.local_lo[i])[:2]))
        for j, s in enumerate(goal.slots):
            d = float(np.linalg.norm(at[:2] - s.pose[:2, 3]))
            if d <= reach:
                pairs.append((d, p, j))
    filled: dict[int, str] = {}
    used: set[str] = set()
    for _d, p, j in sorted(pairs, key=lambda x: (x[0], x[1], x[2])):
        if j not in filled and p not in used:
            filled[j], used = p, used | {p}
    lost = []
    for j, s in enumerate(goal.slots):
        p = filled.get(j)
        if p is None:
            lost.append(LostPoint(1, f"slot {_local(s.name)} of {_local(kit)} ({_local(s.sku)}) is empty",
                                  "part-location-kit", (kit, s.name)))
        elif not _holds(ev, "part-sku", p, s.sku):
            lost.append(LostPoint(1, f"slot {_local(s.name)} of {_local(kit)} holds {_local(p)} of SKU "
                                     f"{_local(_sku(ev, p))}, not {_local(s.sku)}", "part-sku", (p, s.sku)))
        elif "part-quality-ok" in ev.defs.predicates and not _holds(ev, "part-quality-ok", p):
            lost.append(LostPoint(1, f"slot {_local(s.name)} of {_local(kit)} holds {_local(p)}, not found good",
                                  "part-quality-ok", (p,)))
    extra = [p for p in inside if p not in used]
    if extra:
        lost.append(LostPoint(1, f"{_local(kit)} holds part(s) in no slot: {', '.join(map(_local, extra))}",
                              "part-location-kit", (*extra, kit), holds=True))
    return lost
