"""ARIAC's kitting score, by year, as that year's scoring code computes it.

A small pure function of what ARIAC's tray sensor sees on an order's AGV when the order is
submitted (:class:`Shipment`: the tray's id, each part's type, colour, quadrant, whether it is
upside down or faulty, and where the AGV is) and the order's kitting task. Each piece is kept
with the reason for every point gained or lost (:class:`KittingScore`). The rules follow the
``ScoreKittingTask`` / ``ScoreQuadrant`` / ``HandleFaultyParts`` of ARIAC's task manager of the
year (``ariac-2023``, ``ariac-2024``); where they differ from ARIAC's documentation
(``docs-2023/scoring.rst``), docs/metrics.md ("ARIAC's kitting score") lists how.

:func:`observe` reads a kitkb run's report (its scene's final poses) with the import's
``ariac.json`` into the shipments; :func:`score_run` scores every order of the trial.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, field
from typing import Any, Iterable

import numpy as np

from kb.ariac import workcell as W
from kb.core.errors import InputError

YEARS = ("ariac-2023", "ariac-2024")


@dataclass(frozen=True)
class TrayPart:
    """A part ARIAC's tray sensor sees on the tray."""

    name: str
    type: str
    color: str
    quadrant: int
    flipped: bool = False
    faulty: bool = False  # the part is a faulty one (what a quality check finds)


@dataclass(frozen=True)
class Shipment:
    """What is on an order's AGV when it is submitted, and where that AGV is
    (``kitting``, ``assembly_front``, ``assembly_back``, ``warehouse``)."""

    tray_id: int | None  # None: no kit tray on the AGV
    parts: tuple[TrayPart, ...]
    location: str
    quality_checked: bool = False  # a quality check was asked for the order before submission


@dataclass(frozen=True)
class Task:
    """An order's kitting task: tray id, destination (as ARIAC compares it) and products
    (``(type, colour, quadrant)``)."""

    tray_id: int
    destination: str
    products: tuple[tuple[str, str, int], ...]


@dataclass
class Point:
    points: int
    reason: str


@dataclass
class QuadrantScore:
    quadrant: int
    score: int
    correct_type: bool | None = None  # None: no part in the quadrant
    correct_color: bool | None = None
    flipped: bool | None = None
    faulty: bool | None = None
    part: str | None = None
    reasons: list[Point] = field(default_factory=list)


@dataclass
class KittingScore:
    """One order's score and its pieces, ARIAC's names: tray, quadrants, bonus, penalty,
    destination multiplier."""

    order: str
    year: str
    score: int
    max_score: int
    tray: int
    quadrants: list[QuadrantScore]
    bonus: int
    penalty: int
    destination: int
    reasons: list[Point]

    def as_dict(self) -> dict[str, Any]:
        return asdict(self)


def _check_year(year: str) -> None:
    if year not in YEARS:
        raise InputError(f"unknown ARIAC scoring {year!r} (known: {', '.join(YEARS)})")


def quadrant_points(year: str, correct_type: bool, correct_color: bool, flipped: bool, faulty: bool) -> int:
    """ScoreQuadrant of the year: B type, C colour, D flipped, E faulty."""
    _check_year(year)
    if not correct_type or faulty:
        return 0
    if year == "ariac-2024":
        if flipped:
            return 0
        return 3 if correct_color else 2
    if correct_color:
        return 2 if flipped else 3
    return 1 if flipped else 2


def faulty_quadrants(faulty: Iterable[int], task: Task, shipment: Shipment) -> set[int]:
    """HandleFaultyParts (the same in both years): in a quadrant the faulty-part challenge
    names, a part of the ordered type and colour is faulty when no quality check was asked
    for the order (whichever part it is); after a check, the part found faulty is."""
    out: set[int] = set()
    wanted = {q: (t, c) for t, c, q in task.products}
    for q in faulty:
        here = [p for p in shipment.parts if p.quadrant == q]
        if not shipment.quality_checked:
            if q in wanted and any((p.type, p.color) == wanted[q] for p in here):
                out.add(q)
        elif here and here[-1].faulty:
            out.add(q)
    return out


def score_kitting(order: str, task: Task, shipment: Shipment | None, year: str,
                  faulty: Iterable[int] = ()) -> KittingScore:
    """The kitting score of ``order`` submitted as ``shipment`` (None: never submitted),
    ``faulty`` the quadrants its faulty-part challenge names."""
    _check_year(year)
    n = len(task.products)
    tray_points = 3 if year == "ariac-2023" else 1
    max_score = tray_points + 3 * n + n
    if shipment is None:
        quads = [QuadrantScore(q, 0, reasons=[Point(0, "order not submitted")]) for _, _, q in task.products]
        return KittingScore(order, year, 0, max_score, 0, quads, 0, 0, 0,
                            [Point(0, "order not submitted: its kit never reached its AGV's destination")])
    reasons: list[Point] = []
    seen = shipment.parts if shipment.tray_id is not None else ()
    bad = faulty_quadrants(faulty, task, shipment) if shipment.tray_id is not None else set()
    quads = [_quadrant(year, t, c, q, seen, q in bad) for t, c, q in sorted(task.products, key=lambda p: p[2])]
    if shipment.tray_id is None:
        tray = 0
        reasons.append(Point(0, "no kit tray on the AGV (the sensor sees no parts without a tray)"))
    elif shipment.tray_id == task.tray_id:
        tray = tray_points
        reasons.append(Point(tray, f"kit tray {shipment.tray_id} is the one ordered"))
    else:
        tray = 0
        reasons.append(Point(0, f"kit tray {shipment.tray_id}, not {task.tray_id}: no tray points"))
    total_q = sum(qs.score for qs in quads)
    bonus = n if total_q == 3 * n else 0
    reasons.append(Point(bonus, f"bonus {n} (every quadrant 3 points)" if bonus else
                         f"no bonus: quadrants {total_q} of {3 * n}"))
    penalty = max(0, len(seen) - n)
    if penalty:
        reasons.append(Point(-penalty, f"{len(seen)} parts on the tray, {n} ordered: -{penalty}"))
    destination = 1 if shipment.location == task.destination else 0
    reasons.append(Point(0, f"AGV at {shipment.location}" + (" as ordered (x1)" if destination else
                                                             f", not {task.destination}: score x0")))
    raw = tray + total_q + bonus - penalty
    if year == "ariac-2023":
        score = max(raw, 0) * destination
        if raw < 0 and destination:
            reasons.append(Point(-raw, "2023: a kit's score is not below 0"))
    else:
        score = raw * destination
    return KittingScore(order, year, score, max_score, tray, quads, bonus, penalty, destination, reasons)


def _quadrant(year: str, type_: str, color: str, q: int, parts: Iterable[TrayPart], faulty: bool) -> QuadrantScore:
    here = [p for p in parts if p.quadrant == q]
    if not here:
        return QuadrantScore(q, 0, reasons=[Point(0, f"quadrant {q}: empty ({color} {type_} ordered)")])
    p = here[-1]  # the code scores each part of the quadrant in turn: the last one seen counts
    ct, cc, fl = p.type == type_, p.color == color, p.flipped
    pts = quadrant_points(year, ct, cc, fl, faulty)
    what = f"quadrant {q}: {p.color} {p.type} ({p.name})"
    if not ct:
        why = f"{what}, a {type_} was ordered: 0"
    elif faulty:
        why = f"{what} is faulty: 0"
    elif fl and year == "ariac-2024":
        why = f"{what} is flipped: 0 in 2024"
    else:
        why = f"{what}: right type" + (" and colour" if cc else f", wrong colour ({color} ordered)") + (
            ", flipped" if fl else "") + f": {pts}"
    reasons = [Point(pts, why)]
    if len(here) > 1:
        reasons.append(Point(0, f"quadrant {q} holds {len(here)} parts; the last the sensor lists counts"))
    return QuadrantScore(q, pts, ct, cc, fl, faulty, p.name, reasons)


# ------------------------------------------------------------------------------ a kitkb run


def observe(report: dict[str, Any], manifest: dict[str, Any]) -> dict[str, Shipment | None]:
    """Each kitting order's shipment as its AGV's sensor would see it at the end of a kitkb
    run: the kit trays and parts inside the order's shipment box (final poses of the report's
    scene), or None when nothing was shipped (the order was never submitted)."""
    objects = {o["name"]: o for o in report.get("scene", {}).get("objects", [])}
    faulty = _faulty_parts(report)
    out: dict[str, Shipment | None] = {}
    trays = manifest.get("trays", {})
    for ship_name, ship in manifest.get("shipments", {}).items():
        box = objects.get(ship["container"])
        if box is None:
            raise InputError(f"the run's scene has no {ship['container']}: the report is not a run of this import")
        inside = [name for name in trays if name in objects and _inside(objects[name], box)]
        if not inside:
            out[ship["order"]] = None
            continue
        tray = objects[inside[0]]
        parts = tuple(_tray_parts(tray, objects, manifest, faulty))
        out[ship["order"]] = Shipment(trays[inside[0]]["tray_id"], parts, ship["destination_value"])
    return out


def _faulty_parts(report: dict[str, Any]) -> set[str]:
    """Parts a run's cell made defective (its ground truth of injected faults)."""
    out = set()
    for f in report.get("injected", []) or []:
        if isinstance(f, dict) and "defective" in str(f.get("kind", "")):
            out.update(str(a).rsplit("#", 1)[-1] for a in f.get("objects", f.get("args", [])) or [])
    return out


def _pose(obj: dict[str, Any]) -> np.ndarray:
    return np.asarray(obj.get("final") or obj["initial"], dtype=float)


def _inside(obj: dict[str, Any], box: dict[str, Any]) -> bool:
    local = np.linalg.inv(_pose(box)) @ _pose(obj)[:, 3]
    lo, hi = np.asarray(box["lo"]), np.asarray(box["hi"])
    return bool(np.all(local[:3] >= lo - 1e-6) and np.all(local[:2] <= hi[:2] + 1e-6))


def _tray_parts(tray: dict[str, Any], objects: dict[str, Any], manifest: dict[str, Any],
                faulty: set[str]) -> Iterable[TrayPart]:
    inv = np.linalg.inv(_pose(tray))
    hx, hy = W.KIT_TRAY[0] / 2, W.KIT_TRAY[1] / 2
    for name, info in manifest.get("parts", {}).items():
        obj = objects.get(name)
        if obj is None:
            continue
        rel = inv @ _pose(obj)
        x, y, z = rel[:3, 3]
        if abs(x) <= hx + 1e-6 and abs(y) <= hy + 1e-6 and -0.01 <= z <= 0.25:
            # kitkb's cell puts a part down at its slot's pose, upright; but no action of the domain turns a
            # part over, so a part that started upside down is upside down still
            flipped = bool(rel[2, 2] < 0) or bool(info.get("flipped"))
            yield TrayPart(name, info["type"], info["color"], W.quadrant_of(x, y), flipped, name in faulty)


def score_run(report: dict[str, Any], manifest: dict[str, Any], year: str) -> dict[str, Any]:
    """Every order of the trial scored as ``year`` scored it, from a kitkb run's report."""
    _check_year(year)
    shipments = observe(report, manifest)
    challenges = [c for c in manifest.get("challenges", []) if c.get("kind") == "faulty_part"]
    orders = []
    for o in manifest.get("orders", []):
        if o["type"] != "kitting":
            orders.append({"order": o["id"], "type": o["type"], "score": None,
                           "reason": f"{'an' if o['type'] == 'assembly' else 'a'} {o['type']} order: kitkb models kitting only (not scored)"})
            continue
        if o["id"] not in shipments:
            orders.append({"order": o["id"], "type": "kitting", "score": None,
                           "reason": "not imported (no kit tray of its id): not scored"})
            continue
        task = Task(o["tray_id"], o["destination_value"],
                    tuple((p["type"], p["color"], p["quadrant"]) for p in o["products"]))
        bad = [q for c in challenges if c.get("order_id") == o["id"] for q in c.get("quadrants", [])]
        orders.append({"type": "kitting", **score_kitting(o["id"], task, shipments[o["id"]], year, bad).as_dict()})
    scored = [o for o in orders if o.get("score") is not None]
    out: dict[str, Any] = {"scoring": year, "orders": orders,
                           "max_score": sum(o["max_score"] for o in scored)}
    out["total"] = sum(o["score"] for o in scored)
    out["note"] = ("the trial score is the sum of the orders' scores (ComputeTrialScore)" if year == "ariac-2023" else
                   "2024's code prints each order's score and maximum and computes no trial total "
                   "(ComputeTrialScore is commented out): total is their sum")
    return out
