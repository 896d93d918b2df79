"""Seeded fault injection: what goes wrong in the simulated cell, and when.

The fault kinds are data: ``soap:FaultKind`` individuals of the domain (the shipped ones at
the end of ``kitting-domain.ttl``, read by :mod:`kb.model.faults`; ``kitkb faults`` lists
them). A kind strikes actions (as announced through ``begin_action(index, action, args)``) and
is carried out by one of the simulator's mechanisms (``soap:FaultMechanism``, soap.ttl section
7); this module has code per mechanism (:data:`MECHANISMS`, the one place their IRIs appear),
none per kind:

=================  ==============================================================================
mechanism          effect
=================  ==============================================================================
GraspNothing       the struck action's ``CloseGripper`` grasps nothing (armed until the next
                   action begins)
ReleaseInTransit   the held part falls during the first move that carries it sideways
                   (``kb.sim.robot.TRANSIT``): in transit
RemoveObject       the object (the kind's target argument) is taken out of the cell
MarkDefective      the object is flagged defective: only ``inspect`` shows it; its geometry is
                   unchanged
SwapSku            the object is replaced by one of another SKU among the cell's objects of the
                   target's type: its ``hasSkuObject_Sku`` fact and its shape change
DisplaceObject     the object shifts within what holds it, or out of it onto that holder's
                   support (with no room there: onto the floor beside the support)
ShiftInPlane       the object, with what it carries, shifts on its support
=================  ==============================================================================

A mechanism acting on an object acts on the struck action's argument the kind names
(``soap:hasFaultKind_Target``), when that object is of the parameter's type, placed, and not
held by the robot; otherwise the fault does nothing there. Distances are the mechanism's data.

A :class:`FaultSpec` says which kinds and when: at given action indices (``at``; a fault
named for an action it does not strike waits for the next action it strikes), or with a
probability per struck action (``rates``; one uniform draw per action partitions [0, 1) among
the kinds striking it, in the order of kinds, so at most one drawn fault per action and each
with exactly its probability). Its ``kinds`` are the run's domain's (default: the shipped
domain's); a kind not among them is refused, naming the known ones. All randomness (the draws
and where an object moves to) comes from one ``numpy`` generator seeded by ``FaultSpec.seed``:
the same spec and the same command stream give the same faults.

Mechanisms acting on an object apply in ``begin_action``; the others arm the robot, which
reports the fault by its own primitive's name when it takes effect, mapped back here to the
kind that armed it. Every fault that took effect is an :class:`Injected`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable, Mapping

import numpy as np

from kb.core.namespaces import SOAP
from kb.model.faults import FaultKind, FaultKinds, Strike, shipped_fault_kinds
from kb.sim.robot import Robot
from kb.sim.world import SKU, TOLERANCE, World

#: a displaced object lands at least this far (m) from where it was, unless its mechanism says
MIN_SHIFT = 0.01
#: an object knocked off its support lands on the floor within this distance (m) of it, unless its
#: mechanism says
BESIDE = 0.3
_TRIES = 200
#: the robot's armed primitives (its attributes), each reported by that name when it takes effect
GRASP_NOTHING, DROP_IN_TRANSIT = "miss_grasp", "drop_in_transit"


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
    """Which faults, when: ``rates`` (kind -> probability per struck action), ``at`` (action
    index -> kind or kinds), the ``seed`` of all fault randomness, and the ``kinds`` they are
    of (None: the shipped domain's, read when a fault is named)."""

    rates: Mapping[str, float] = field(default_factory=dict)
    at: Mapping[int, str | tuple[str, ...]] = field(default_factory=dict)
    seed: int = 0
    kinds: FaultKinds | None = field(default=None, compare=False, repr=False)

    def __post_init__(self) -> None:
        if not self.rates and not self.at:
            return
        catalog = self.catalog
        for kind, p in self.rates.items():
            _check_kind(catalog, kind)
            if not 0.0 <= float(p) <= 1.0:
                raise ValueError(f"probability of {kind} must be in [0, 1], not {p}")
        for action in catalog.actions:
            total = sum(float(self.rates.get(k.name, 0.0)) for k in catalog.eligible(action))
            if total > 1.0 + 1e-12:
                raise ValueError(f"the probabilities of faults on {action} add up to {total} > 1")
        for index, kinds in self.at.items():
            for kind in _kinds(kinds):
                _check_kind(catalog, kind)
            if int(index) < 0:
                raise ValueError(f"action index must be >= 0, not {index}")

    @property
    def catalog(self) -> FaultKinds:
        """The kinds this spec's names are of."""
        return self.kinds if self.kinds is not None else shipped_fault_kinds()

    @classmethod
    def parse(cls, text: str, seed: int = 0, kinds: FaultKinds | None = None) -> "FaultSpec":
        """From ``"kind=probability,kind@action_index,..."`` (e.g. ``"K=0.2,L@3"``); ``kinds``:
        the domain's (None: the shipped domain's)."""
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
        return cls(rates, at, seed, kinds)


def _check_kind(catalog: FaultKinds, name: str) -> None:
    kind = catalog.check(name)
    if kind.mechanism.iri not in MECHANISMS:
        raise ValueError(f"fault kind {name!r}: the simulated cell has no mechanism {kind.mechanism.name} "
                         f"(it has {', '.join(_local(m) for m in MECHANISMS)})")


def _kinds(kinds: str | tuple[str, ...]) -> tuple[str, ...]:
    return (kinds,) if isinstance(kinds, str) else tuple(kinds)


class Injector:
    """Applies a :class:`FaultSpec` to a world and its robot, action by action."""

    def __init__(self, spec: FaultSpec, world: World, robot: Robot, record: Callable[[Injected], None]) -> None:
        self.spec, self.world, self.robot, self.record = spec, world, robot, record
        self.active = bool(spec.rates or spec.at)
        self.catalog = spec.catalog if self.active else FaultKinds()
        self.rng = np.random.default_rng(spec.seed)
        self.pending: list[str] = []
        self.armed: dict[str, tuple[str, int]] = {}  # robot primitive -> (the kind, the action index) that armed it
        robot.on_fault = self._took_effect

    def _took_effect(self, primitive: str, objects: tuple[str, ...], detail: str) -> None:
        kind, index = self.armed.pop(primitive, (primitive, -1))
        self.record(Injected(kind, index, objects, detail))

    def begin_action(self, index: int, action: str, args: tuple[str, ...]) -> None:
        """Choose and apply (or arm) the faults of action ``index``."""
        self.robot.miss_grasp = False  # a grasp armed to miss belongs to the action that armed it
        self.armed.pop(GRASP_NOTHING, None)
        if not self.active:
            return
        self.pending.extend(_kinds(self.spec.at.get(index, ())))
        eligible = self.catalog.eligible(action)
        names = {k.name for k in eligible}
        chosen = [k for k in self.pending if k in names]
        self.pending = [k for k in self.pending if k not in names]
        drawn = self._draw(eligible)
        if drawn is not None and drawn not in chosen:
            chosen.append(drawn)
        for name in sorted(chosen, key=self.catalog.order):
            kind = self.catalog.check(name)
            MECHANISMS[kind.mechanism.iri](self, kind, kind.strike(action), index, args)  # type: ignore[arg-type]

    def _draw(self, eligible: tuple[FaultKind, ...]) -> str | None:
        rates = [(k.name, float(self.spec.rates.get(k.name, 0.0))) for k in eligible]
        if not any(p for _, p in rates):
            return None
        u, acc = float(self.rng.random()), 0.0
        for kind, p in rates:
            acc += p
            if u < acc:
                return kind
        return None

    # --- the mechanisms -----------------------------------------------------------------
    def _target(self, strike: Strike, args: tuple[str, ...]) -> int | None:
        """The object a strike names (its argument): one of the parameter's type, placed and not
        held by the robot, else None (an announced action's arguments are whatever a client sent)."""
        n = strike.argument
        i = self.world.index.get(args[n]) if n is not None and len(args) > n else None
        if i is None or (strike.type is not None and not self.world.is_a(i, strike.type)):
            return None
        return i if self._free(i) else None

    def _free(self, i: int) -> bool:
        """``i`` is placed and not carried by the robot."""
        return self.world.placed(i) and i not in self.world.subtree(self.robot.index)

    def grasp_nothing(self, kind: FaultKind, strike: Strike, index: int, args: tuple[str, ...]) -> None:
        self.robot.miss_grasp = True
        self.armed[GRASP_NOTHING] = (kind.name, index)

    def release_in_transit(self, kind: FaultKind, strike: Strike, index: int, args: tuple[str, ...]) -> None:
        self.robot.drop_in_transit = True
        self.armed[DROP_IN_TRANSIT] = (kind.name, index)

    def remove_object(self, kind: FaultKind, strike: Strike, index: int, args: tuple[str, ...]) -> None:
        i = self._target(strike, args)
        if i is None:
            return
        w = self.world
        where = w.names[int(w.parent[i])] if w.parent[i] >= 0 else "the floor"
        w.remove(i)
        self.record(Injected(kind.name, index, (w.names[i],), f"taken out of the cell from {where}"))

    def mark_defective(self, kind: FaultKind, strike: Strike, index: int, args: tuple[str, ...]) -> None:
        i = self._target(strike, args)
        if i is None:
            return
        self.world.defective.add(self.world.names[i])
        self.record(Injected(kind.name, index, (self.world.names[i],), "flagged defective"))

    def swap_sku(self, kind: FaultKind, strike: Strike, index: int, args: tuple[str, ...]) -> None:
        i = self._target(strike, args)
        if i is None:
            return
        w, name = self.world, self.world.names[i]
        old = w.sku(i)
        boxes: dict[str, tuple[np.ndarray, np.ndarray]] = {}
        for j in range(len(w)):
            s = w.sku(j)
            if (strike.type is None or w.is_a(j, strike.type)) and s and s != old and not np.isnan(w.local_lo[j, 0]):
                boxes.setdefault(s, (w.local_lo[j].copy(), w.local_hi[j].copy()))
        if not boxes:
            return
        new = sorted(boxes)[int(self.rng.integers(len(boxes)))]
        w.facts[SKU] = {(s, o) for s, o in w.facts.get(SKU, set()) if s != name} | {(name, new)}
        w.local_lo[i], w.local_hi[i] = boxes[new]
        self.record(Injected(kind.name, index, (name, new), f"replaced by a part of {_local(new)} "
                                                             f"(was {_local(old or '')})"))

    def displace_object(self, kind: FaultKind, strike: Strike, index: int, args: tuple[str, ...]) -> None:
        i = self._target(strike, args)
        if i is None:
            return
        w, m = self.world, kind.mechanism
        tray = int(w.parent[i])
        table = int(w.parent[tray]) if tray >= 0 else -1
        # within the tray, or out of it: onto the table it stands on, else (no room there)
        # onto the floor beside the table, as if knocked off
        options = [("within", tray), ("onto", table), ("floor", table)]
        if self.rng.random() >= 0.5:
            options = options[1:] + options[:1]
        least = m.min_shift if m.min_shift is not None else MIN_SHIFT
        beside = m.beside if m.beside is not None else BESIDE
        for how, base in options:
            if base < 0:
                continue
            spot = self._free_spot(i, base, least, beside if how == "floor" else None)
            if spot is not None:
                break
        else:
            return
        self._place(i, spot, -1 if how == "floor" else base)
        origin = _local(w.names[tray]) if tray >= 0 else "its place"
        what = {"within": f"shifted within {origin}", "onto": f"moved out of {origin} onto {_local(w.names[base])}",
                "floor": f"knocked out of {origin} onto the floor beside {_local(w.names[base])}"}[how]
        self.record(Injected(kind.name, index, (w.names[i],), f"{what} to ({spot[0]:.3f}, {spot[1]:.3f})"))

    def shift_in_plane(self, kind: FaultKind, strike: Strike, index: int, args: tuple[str, ...]) -> None:
        obj = self._target(strike, args)
        if obj is None:
            return
        w, m = self.world, kind.mechanism
        support = int(w.parent[obj])
        lo, hi = w.box(obj)
        d = self.rng.uniform(m.min_shift or 0.0, m.max_shift if m.max_shift is not None else (m.min_shift or 0.0))
        a = self.rng.uniform(0, 2 * np.pi)
        dx, dy = d * np.cos(a), d * np.sin(a)
        if support >= 0:  # stay on the support
            slo, shi = w.box(support)
            dx = float(np.clip(dx, slo[0] - lo[0], shi[0] - hi[0]))
            dy = float(np.clip(dy, slo[1] - lo[1], shi[1] - hi[1]))
        w.shift(obj, dx, dy, 0.0)
        related = tuple(o for prop in kind.also_names for o in w.objects(prop, w.names[obj]))
        self.record(Injected(kind.name, index, (w.names[obj],) + related,
                             f"shifted by ({dx:.3f}, {dy:.3f}) on "
                             f"{_local(w.names[support]) if support >= 0 else 'the floor'}"))

    # --- helpers ------------------------------------------------------------------------
    def _free_spot(self, i: int, base: int, least: float = MIN_SHIFT,
                   beside: float | None = None) -> tuple[float, float, float] | None:
        """A random (x, y, z of the bottom) where ``i`` fits on / in ``base`` (with ``beside``:
        on the floor within that distance of ``base``'s footprint) without touching anything
        there, at least ``least`` from where it is."""
        w = self.world
        lo, hi = w.box(i)
        half = (hi - lo) / 2
        blo, bhi = w.box(base)
        floor = beside is not None
        if floor:
            blo, bhi = blo - beside, bhi + beside
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
            if np.linalg.norm(c - (lo[:2] + half[:2])) < least:
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


#: The simulator's fault mechanisms by IRI (``soap:FaultMechanism`` individuals of soap.ttl):
#: the only place they are named in code.
MECHANISMS: dict[str, Callable[[Injector, FaultKind, Strike, int, tuple[str, ...]], None]] = {
    str(SOAP) + "GraspNothing": Injector.grasp_nothing,
    str(SOAP) + "ReleaseInTransit": Injector.release_in_transit,
    str(SOAP) + "RemoveObject": Injector.remove_object,
    str(SOAP) + "MarkDefective": Injector.mark_defective,
    str(SOAP) + "SwapSku": Injector.swap_sku,
    str(SOAP) + "DisplaceObject": Injector.displace_object,
    str(SOAP) + "ShiftInPlane": Injector.shift_in_plane,
}
