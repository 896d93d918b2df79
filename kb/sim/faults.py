"""Seeded fault injection: what goes wrong in the simulated cell, and when.

Seven kinds (:data:`FAULT_KINDS`), each eligible on one plan action (as announced through
``begin_action(index, action, args)``; parameters in the order of ``kitting-domain.ttl``):

=================  ============  ==========================================================
kind               on            effect
=================  ============  ==========================================================
missed-grasp       take-part     the action's ``CloseGripper`` grasps nothing
dropped-part       take-part     the held part falls during the first move that carries it
                                 sideways (``kb.sim.robot.TRANSIT``): in transit
part-moved         take-part     the part (args[1]) shifts within its tray (args[2]), or out
                                 of it onto the table the tray stands on (with no room
                                 there: onto the floor beside the table)
part-missing       take-part     the part is taken out of the cell
defective-part     take-part     the part is flagged defective: only ``inspect`` shows it;
                                 its geometry is unchanged
wrong-sku          take-part     the part is replaced by one of another part SKU of the cell:
                                 its ``hasSkuObject_Sku`` fact and its shape change
kit-tray-moved     put-part      the kit (args[2]) — its tray with what is in it — shifts on
                                 the work table
=================  ============  ==========================================================

A :class:`FaultSpec` says which kinds and when: at given action indices (``at``; a fault
named for an action it is not eligible on waits for the next action it is eligible on), or
with a probability per eligible action (``rates``; one uniform draw per action partitions
[0, 1) among the kinds eligible there, in :data:`FAULT_KINDS` order, so at most one drawn fault
per action and each with exactly its probability). All randomness (the draws and where a part
or tray moves to) comes from one ``numpy`` generator seeded by ``FaultSpec.seed``: the same
spec and the same command stream give the same faults.

Faults acting before the action (part-moved, part-missing, defective-part, wrong-sku,
kit-tray-moved) are applied in ``begin_action``; missed-grasp and dropped-part arm the robot
and are recorded when they take effect. Every fault that took effect is an :class:`Injected`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable, Mapping

import numpy as np

from kb.sim.robot import Robot
from kb.sim.world import KIT_TRAY, SKU, TOLERANCE, World

FAULT_KINDS: tuple[str, ...] = ("missed-grasp", "dropped-part", "part-moved", "part-missing",
                                "defective-part", "wrong-sku", "kit-tray-moved")
#: action name -> fault kinds eligible on it
ELIGIBLE: dict[str, tuple[str, ...]] = {
    "take-part": ("missed-grasp", "dropped-part", "part-moved", "part-missing", "defective-part", "wrong-sku"),
    "put-part": ("kit-tray-moved",),
}
#: a moved kit shifts by a distance drawn in this range (m)
KIT_SHIFT = (0.02, 0.06)
#: a moved part lands at least this far (m) from where it was
MIN_SHIFT = 0.01
#: a part knocked off a table lands on the floor within this distance (m) of the table
BESIDE = 0.3
_TRIES = 200


@dataclass(frozen=True)
class Injected:
    """One fault that took effect: its kind, the plan action it belongs to, the objects it
    changed and what happened."""

    kind: str
    action_index: int
    objects: tuple[str, ...]
    detail: str


@dataclass(frozen=True)
class FaultSpec:
    """Which faults, when: ``rates`` (kind -> probability per eligible action), ``at`` (action
    index -> kind or kinds), and the ``seed`` of all fault randomness."""

    rates: Mapping[str, float] = field(default_factory=dict)
    at: Mapping[int, str | tuple[str, ...]] = field(default_factory=dict)
    seed: int = 0

    def __post_init__(self) -> None:
        for kind, p in self.rates.items():
            _check_kind(kind)
            if not 0.0 <= float(p) <= 1.0:
                raise ValueError(f"probability of {kind} must be in [0, 1], not {p}")
        for action, kinds in ELIGIBLE.items():
            total = sum(float(self.rates.get(k, 0.0)) for k in kinds)
            if total > 1.0 + 1e-12:
                raise ValueError(f"the probabilities of faults on {action} add up to {total} > 1")
        for index, kinds in self.at.items():
            for kind in _kinds(kinds):
                _check_kind(kind)
            if int(index) < 0:
                raise ValueError(f"action index must be >= 0, not {index}")

    @classmethod
    def parse(cls, text: str, seed: int = 0) -> "FaultSpec":
        """From ``"kind=probability,kind@action_index,..."`` (e.g. ``"missed-grasp=0.2,part-missing@3"``)."""
        rates: dict[str, float] = {}
        at: dict[int, tuple[str, ...]] = {}
        for item in filter(None, (s.strip() for s in text.split(","))):
            if "=" in item:
                kind, _, p = item.partition("=")
                try:
                    rates[kind.strip()] = float(p)
                except ValueError:
                    raise ValueError(f"fault {item!r}: {p!r} is not a probability") from None
            elif "@" in item:
                kind, _, i = item.partition("@")
                try:
                    at[int(i)] = at.get(int(i), ()) + (kind.strip(),)
                except ValueError:
                    raise ValueError(f"fault {item!r}: {i!r} is not an action index") from None
            else:
                raise ValueError(f"fault {item!r}: expected kind=probability or kind@action_index")
        return cls(rates, at, seed)


def _check_kind(kind: str) -> None:
    if kind not in FAULT_KINDS:
        raise ValueError(f"unknown fault kind {kind!r}; known: {', '.join(FAULT_KINDS)}")


def _kinds(kinds: str | tuple[str, ...]) -> tuple[str, ...]:
    return (kinds,) if isinstance(kinds, str) else tuple(kinds)


class Injector:
    """Applies a :class:`FaultSpec` to a world and its robot, action by action."""

    def __init__(self, spec: FaultSpec, world: World, robot: Robot, record: Callable[[Injected], None]) -> None:
        self.spec, self.world, self.robot, self.record = spec, world, robot, record
        self.rng = np.random.default_rng(spec.seed)
        self.pending: list[str] = []
        self.armed: dict[str, int] = {}  # armed kind -> the action index that armed it
        robot.on_fault = self._took_effect

    def _took_effect(self, kind: str, objects: tuple[str, ...], detail: str) -> None:
        self.record(Injected(kind, self.armed.pop(kind, -1), objects, detail))

    def begin_action(self, index: int, action: str, args: tuple[str, ...]) -> None:
        """Choose and apply (or arm) the faults of action ``index``."""
        self.robot.miss_grasp = False  # a missed grasp belongs to the action that armed it
        self.armed.pop("missed-grasp", None)
        self.pending.extend(_kinds(self.spec.at.get(index, ())))
        eligible = ELIGIBLE.get(action, ())
        chosen = [k for k in self.pending if k in eligible]
        self.pending = [k for k in self.pending if k not in eligible]
        drawn = self._draw(eligible)
        if drawn is not None and drawn not in chosen:
            chosen.append(drawn)
        for kind in sorted(chosen, key=FAULT_KINDS.index):
            _APPLY[kind](self, index, args)

    def _draw(self, eligible: tuple[str, ...]) -> str | None:
        rates = [(k, float(self.spec.rates.get(k, 0.0))) for k in FAULT_KINDS if k in eligible]
        if not any(p for _, p in rates):
            return None
        u, acc = float(self.rng.random()), 0.0
        for kind, p in rates:
            acc += p
            if u < acc:
                return kind
        return None

    # --- the kinds ----------------------------------------------------------------------
    def _part(self, args: tuple[str, ...]) -> int | None:
        """The part a take-part names (args[1]): a placed part the robot does not hold, else None
        (an announced action's arguments are whatever a client sent)."""
        i = self.world.index.get(args[1]) if len(args) > 1 else None
        return i if i is not None and self.world.is_a(i, "Part") and self._free(i) else None

    def _free(self, i: int) -> bool:
        """``i`` is placed and not carried by the robot."""
        return self.world.placed(i) and i not in self.world.subtree(self.robot.index)

    def missed_grasp(self, index: int, args: tuple[str, ...]) -> None:
        self.robot.miss_grasp = True
        self.armed["missed-grasp"] = index

    def dropped_part(self, index: int, args: tuple[str, ...]) -> None:
        self.robot.drop_in_transit = True
        self.armed["dropped-part"] = index

    def part_missing(self, index: int, args: tuple[str, ...]) -> None:
        i = self._part(args)
        if i is None:
            return
        w = self.world
        where = w.names[int(w.parent[i])] if w.parent[i] >= 0 else "the floor"
        w.remove(i)
        self.record(Injected("part-missing", index, (w.names[i],), f"taken out of the cell from {where}"))

    def defective_part(self, index: int, args: tuple[str, ...]) -> None:
        i = self._part(args)
        if i is None:
            return
        self.world.defective.add(self.world.names[i])
        self.record(Injected("defective-part", index, (self.world.names[i],), "flagged defective"))

    def wrong_sku(self, index: int, args: tuple[str, ...]) -> None:
        i = self._part(args)
        if i is None:
            return
        w, name = self.world, self.world.names[i]
        old = w.sku(i)
        boxes: dict[str, tuple[np.ndarray, np.ndarray]] = {}
        for j in range(len(w)):
            s = w.sku(j)
            if w.is_a(j, "Part") and s and s != old and not np.isnan(w.local_lo[j, 0]):
                boxes.setdefault(s, (w.local_lo[j].copy(), w.local_hi[j].copy()))
        if not boxes:
            return
        new = sorted(boxes)[int(self.rng.integers(len(boxes)))]
        w.facts[SKU] = {(s, o) for s, o in w.facts.get(SKU, set()) if s != name} | {(name, new)}
        w.local_lo[i], w.local_hi[i] = boxes[new]
        self.record(Injected("wrong-sku", index, (name, new), f"replaced by a part of {_local(new)} "
                                                               f"(was {_local(old or '')})"))

    def part_moved(self, index: int, args: tuple[str, ...]) -> None:
        i = self._part(args)
        if i is None:
            return
        w = self.world
        tray = int(w.parent[i])
        table = int(w.parent[tray]) if tray >= 0 else -1
        # within the tray, or out of it: onto the table it stands on, else (no room there)
        # onto the floor beside the table, as if knocked off
        options = [("within", tray), ("onto", table), ("floor", table)]
        if self.rng.random() >= 0.5:
            options = options[1:] + options[:1]
        for how, base in options:
            if base < 0:
                continue
            spot = self._free_spot(i, base, floor=how == "floor")
            if spot is not None:
                break
        else:
            return
        self._place(i, spot, -1 if how == "floor" else base)
        origin = _local(w.names[tray]) if tray >= 0 else "its place"
        what = {"within": f"shifted within {origin}", "onto": f"moved out of {origin} onto {_local(w.names[base])}",
                "floor": f"knocked out of {origin} onto the floor beside {_local(w.names[base])}"}[how]
        self.record(Injected("part-moved", index, (w.names[i],), f"{what} to ({spot[0]:.3f}, {spot[1]:.3f})"))

    def kit_tray_moved(self, index: int, args: tuple[str, ...]) -> None:
        w = self.world
        kit = w.index.get(args[2]) if len(args) > 2 else None
        if kit is None or not w.is_a(kit, "Kit") or not self._free(kit):
            return
        support = int(w.parent[kit])
        lo, hi = w.box(kit)
        d = self.rng.uniform(*KIT_SHIFT)
        a = self.rng.uniform(0, 2 * np.pi)
        dx, dy = d * np.cos(a), d * np.sin(a)
        if support >= 0:  # stay on the table
            slo, shi = w.box(support)
            dx = float(np.clip(dx, slo[0] - lo[0], shi[0] - hi[0]))
            dy = float(np.clip(dy, slo[1] - lo[1], shi[1] - hi[1]))
        w.shift(kit, dx, dy, 0.0)
        trays = w.objects(KIT_TRAY, w.names[kit])
        self.record(Injected("kit-tray-moved", index, (w.names[kit],) + tuple(trays),
                             f"shifted by ({dx:.3f}, {dy:.3f}) on "
                             f"{_local(w.names[support]) if support >= 0 else 'the floor'}"))

    # --- helpers ------------------------------------------------------------------------
    def _free_spot(self, i: int, base: int, floor: bool = False) -> tuple[float, float, float] | None:
        """A random (x, y, z of the bottom) where ``i`` fits on / in ``base`` (``floor``: on the
        floor within :data:`BESIDE` of ``base``'s footprint) without touching anything there, at
        least :data:`MIN_SHIFT` from where it is."""
        w = self.world
        lo, hi = w.box(i)
        half = (hi - lo) / 2
        blo, bhi = w.box(base)
        if floor:
            blo, bhi = blo - BESIDE, bhi + BESIDE
            z0 = 0.0
        else:
            z0 = float(blo[2] if w.open_top[base] else bhi[2])  # a container's floor, a table's top
        if np.any(bhi[:2] - blo[:2] < 2 * half[:2]):
            return None
        z1 = z0 + float(hi[2] - lo[2])
        others = []
        for j in w.solids(set(w.subtree(i)) | ({base} if not floor else set())):
            olo, ohi = w.box(j)
            if ohi[2] > z0 + TOLERANCE and olo[2] < z1 - TOLERANCE:
                others.append((olo[:2], ohi[:2]))
        for _ in range(_TRIES):
            c = self.rng.uniform(blo[:2] + half[:2], bhi[:2] - half[:2])
            if np.linalg.norm(c - (lo[:2] + half[:2])) < MIN_SHIFT:
                continue
            if all(np.any(c + half[:2] <= olo) or np.any(c - half[:2] >= ohi) for olo, ohi in others):
                return float(c[0]), float(c[1]), z0
        return None

    def _place(self, i: int, spot: tuple[float, float, float], base: int) -> None:
        """Put ``i`` with its footprint centred at ``spot`` (x, y, bottom z), resting on ``base``."""
        w = self.world
        lo, hi = w.box(i)
        center = (lo + hi) / 2
        w.shift(i, spot[0] - float(center[0]), spot[1] - float(center[1]), spot[2] - float(lo[2]))
        w.parent[i] = base


def _local(iri: str) -> str:
    return iri.rsplit("#", 1)[-1].rsplit("/", 1)[-1]

_APPLY: dict[str, Callable[[Injector, int, tuple[str, ...]], None]] = {
    "missed-grasp": Injector.missed_grasp,
    "dropped-part": Injector.dropped_part,
    "part-moved": Injector.part_moved,
    "part-missing": Injector.part_missing,
    "defective-part": Injector.defective_part,
    "wrong-sku": Injector.wrong_sku,
    "kit-tray-moved": Injector.kit_tray_moved,
}
