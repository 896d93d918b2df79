"""How each kitting predicate and function is read off a workstation state.

One small rule per SOAP predicate name (the SOAP definitions say what a predicate means in
geometric terms; in a data file the same facts are explicit: primary locations, SKUs, kit
designs). A rule takes the initial-state :class:`World` and the goal-state one (for facts
about objects that first appear in the goal, such as NIST's kits) and yields argument tuples.
"""

from __future__ import annotations

from collections import Counter
from typing import Callable, Iterable

from rdflib import URIRef

from kb.core.namespaces import KTW
from kb.planning.state import World

Args = tuple[URIRef, ...]
Rule = Callable[[World, World], Iterable[Args]]

PART, TRAY, KIT, KITTRAY = str(KTW.Part), str(KTW.PartsTray), str(KTW.Kit), str(KTW.KitTray)
ROBOT, EE, HOLDER, STATION = str(KTW.Robot), str(KTW.EndEffector), str(KTW.EndEffectorHolder), \
    str(KTW.EndEffectorChangingStation)
TABLE, LBWK, LBWEKT, SKU = str(KTW.WorkTable), str(KTW.LargeBoxWithKits), \
    str(KTW.LargeBoxWithEmptyKitTrays), str(KTW.StockKeepingUnit)


def _located(child: str, parent: str) -> Rule:
    return lambda w, _g: w.located(child, parent)


def _swap(rule: Rule) -> Rule:
    return lambda w, g: [(b, a) for a, b in rule(w, g)]


def _held(child: str) -> Rule:
    return lambda w, _g: w.held_by(child, ROBOT, EE)


def _both(w: World, g: World, s: URIRef, prop: URIRef):  # noqa: ANN202
    """A property value from the initial state, else from the goal state."""
    value = w.value(s, prop)
    return value if value is not None else g.value(s, prop)


def kits(w: World, g: World) -> list[URIRef]:
    """Kits of either state (NIST's kits exist only in the goal)."""
    return sorted(set(w.of(KIT)) | set(g.of(KIT)), key=str)


def _effector_for(thing_sku: Callable[[World, World, URIRef], URIRef | None], things) -> Rule:  # noqa: ANN001
    def rule(w: World, g: World) -> Iterable[Args]:
        for x in things(w, g):
            sku = thing_sku(w, g, x)
            for ee in (w.values(sku, KTW.hasStockKeepingUnit_EndEffector) if sku is not None else []):
                yield (ee, x)
    return rule


def _sku(w: World, g: World, x: URIRef) -> URIRef | None:
    return _both(w, g, x, KTW.hasSkuObject_Sku)


def _kit_tray_sku(w: World, g: World, kit: URIRef) -> URIRef | None:
    tray = _both(w, g, kit, KTW.hasKit_KitTray)
    return _sku(w, g, tray) if tray is not None else None


def _not_holding(w: World, robot: URIRef) -> bool:
    return not any(r == robot for t in (PART, KIT, KITTRAY) for _x, r in w.held_by(t, ROBOT, EE))


def _robot_effectors(w: World) -> list[tuple[URIRef, URIRef]]:
    return w.located(EE, ROBOT)


def _lbwk_not_full(w: World, _g: World) -> Iterable[Args]:
    for box in w.of(LBWK):
        cap = w.value(box, KTW.hasLargeBoxWithKits_Capacity)
        inside = sum(1 for k in w.contents(box) if w.is_a(k, KIT))
        if cap is None or inside < int(cap):
            yield (box,)


PREDICATES: dict[str, Rule] = {
    "endeffector-location-endeffectorholder": _located(EE, HOLDER),
    "endeffectorholder-location-changingstation": _located(HOLDER, STATION),
    "endeffector-location-robot": _located(EE, ROBOT),
    "robot-with-endeffector": _swap(_located(EE, ROBOT)),
    "robot-with-no-endeffector": lambda w, g: [(r,) for r in w.of(ROBOT)
                                               if not any(rr == r for _e, rr in _robot_effectors(w))],
    "robot-empty": lambda w, g: [(r,) for r in w.of(ROBOT)
                                 if any(rr == r for _e, rr in _robot_effectors(w)) and _not_holding(w, r)],
    "endeffectorholder-empty": lambda w, g: [(h,) for h in w.of(HOLDER)
                                             if not any(w.is_a(x, EE) for x in w.contents(h))],
    "kit-kittray": lambda w, g: [(k, t) for k in kits(w, g)
                                 for t in [_both(w, g, k, KTW.hasKit_KitTray)] if t is not None],
    "kittray-location-worktable": _located(KITTRAY, TABLE),
    "kittray-location-lbwekt": _located(KITTRAY, LBWEKT),
    "kittray-location-robot": _held(KITTRAY),
    "robot-holds-kittray": _swap(_held(KITTRAY)),
    "kit-location-worktable": _located(KIT, TABLE),
    "kit-location-lbwk": _located(KIT, LBWK),
    "kit-location-robot": _held(KIT),
    "robot-holds-kit": _swap(_held(KIT)),
    "part-location-partstray": _located(PART, TRAY),
    "part-location-kit": _located(PART, KIT),
    "part-location-robot": _held(PART),
    "robot-holds-part": _swap(_held(PART)),
    "partstray-not-empty": lambda w, g: [(t,) for t in w.of(TRAY)
                                         if any(w.is_a(x, PART) for x in w.contents(t))],
    "worktable-empty": lambda w, g: [(t,) for t in w.of(TABLE) if not w.contents(t)],
    "lbwk-not-full": _lbwk_not_full,
    "part-sku": lambda w, g: [(p, s) for p in w.of(PART) for s in [_sku(w, g, p)] if s is not None],
    "endeffector-type-part": _effector_for(_sku, lambda w, g: w.of(PART)),
    "endeffector-type-kittray": _effector_for(_sku, lambda w, g: w.of(KITTRAY)),
    "endeffector-type-kit": _effector_for(_kit_tray_sku, kits),
    # a sensor check (quality inspection): never known before look-for-part runs
    "part-quality-ok": lambda w, g: [],
}


def design_counts(w: World, g: World, kit: URIRef) -> Counter:
    """SKU -> number of parts the kit's design asks for."""
    design = _both(w, g, kit, KTW.hasKit_Design)
    if design is None:
        return Counter()
    for state in (w, g):
        prps = state.values(design, KTW.hasKitDesign_PartRefAndPose)
        if prps:
            return Counter(state.value(p, KTW.hasPartRefAndPose_Sku) for p in prps)
    return Counter()


def parts_in(w: World, container: URIRef, sku: URIRef | None = None) -> list[URIRef]:
    """Parts placed in ``container`` (of ``sku`` if given)."""
    return [p for p in w.contents(container) if w.is_a(p, PART)
            and (sku is None or w.value(p, KTW.hasSkuObject_Sku) == sku)]


def _quantity_kit(w: World, g: World) -> Iterable[tuple[Args, int]]:
    for kit in kits(w, g):
        for sku in design_counts(w, g, kit):
            yield (kit, sku), len(parts_in(w, kit, sku))


def _capacity_kit(w: World, g: World) -> Iterable[tuple[Args, int]]:
    for kit in kits(w, g):
        for sku, n in design_counts(w, g, kit).items():
            yield (kit, sku), n


FUNCTIONS: dict[str, Callable[[World, World], Iterable[tuple[Args, int]]]] = {
    "quantity-partstray": lambda w, g: [((t,), len(parts_in(w, t))) for t in w.of(TRAY)],
    "quantity-kit": _quantity_kit,
    "capacity-kit": _capacity_kit,
}
