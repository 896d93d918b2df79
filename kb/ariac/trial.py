"""An ARIAC trial file read into typed records, every field checked against ARIAC's format.

The format is the one ARIAC documents (docs-2023 ``trials.md``, ``orders.rst``,
``challenges.rst``) and its environment start-up reads: ``time_limit``, ``kitting_trays``
(``tray_ids`` on ``slots`` 1-6 of the two tray tables), ``parts`` (``bins`` 1-8 with slots
1-9, ``agvs`` 1-4 with parts in quadrants, ``conveyor_belt``), ``orders`` (kitting, assembly or
combined; announced on a time, a part placement or a submission; priority) and ``challenges``
(faulty_part, dropped_part, robot_malfunction, sensor_blackout, human), and 2024's
``assembly_inserts``. A key ARIAC does not define, a value of the wrong kind or out of range,
a slot used twice is an :class:`~kb.core.errors.InputError` at its ``file:line``.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Iterable

from kb.ariac.yamlfile import YList, YMap, line_of, load
from kb.core.errors import InputError

PART_TYPES = ("battery", "pump", "sensor", "regulator")
COLORS = ("red", "green", "blue", "orange", "purple")
#: ARIAC's destinations as its start-up maps them (KittingTask.msg): as1 and as3 are the
#: assembly stations' front, as2 and as4 their back; the scorer compares these values
DESTINATIONS = {"kitting": "kitting", "as1": "assembly_front", "as2": "assembly_back",
                "as3": "assembly_front", "as4": "assembly_back", "warehouse": "warehouse"}
ROBOTS = ("floor_robot", "ceiling_robot")
SENSOR_TYPES = ("break_beam", "proximity", "laser_profiler", "lidar", "camera", "logical_camera")
HUMAN_BEHAVIORS = ("indifferent", "antagonistic", "helpful")


@dataclass(frozen=True)
class Where:
    """A place in the trial file."""

    file: str
    line: int | None

    def __str__(self) -> str:
        return f"{self.file}:{self.line}" if self.line else self.file


@dataclass(frozen=True)
class BinPart:
    """One part in a bin slot."""

    bin: int
    slot: int
    type: str
    color: str
    rotation: float
    flipped: bool
    where: Where


@dataclass(frozen=True)
class KitTraySpawn:
    """A kit tray on a tray table slot (1-3 table 1, 4-6 table 2)."""

    tray_id: int
    slot: int
    where: Where


@dataclass(frozen=True)
class Product:
    """A part a kitting order asks for in a quadrant of its tray."""

    type: str
    color: str
    quadrant: int


@dataclass(frozen=True)
class Condition:
    """When an order or a challenge is announced: ``kind`` is ``time``, ``part_place`` or
    ``submission``; ``time`` seconds, ``agv``/``type``/``color`` or ``order_id``."""

    kind: str
    time: float | None = None
    agv: int | None = None
    type: str | None = None
    color: str | None = None
    order_id: str | None = None

    def as_dict(self) -> dict[str, Any]:
        return {k: v for k, v in self.__dict__.items() if v is not None}


@dataclass(frozen=True)
class KittingTask:
    agv: int
    tray_id: int
    destination: str  # as written (warehouse, kitting, as1..as4)
    products: tuple[Product, ...]

    @property
    def destination_value(self) -> str:
        """The destination as ARIAC's scorer compares it (as1 and as3 are both assembly_front)."""
        return DESTINATIONS[self.destination]


@dataclass(frozen=True)
class Order:
    id: str
    type: str  # kitting, assembly, combined
    priority: bool
    announcement: Condition
    kitting: KittingTask | None
    where: Where


@dataclass(frozen=True)
class Challenge:
    """An agility challenge: ``kind`` (faulty_part, dropped_part, robot_malfunction,
    sensor_blackout, human) and its fields as read (``condition`` for those announced)."""

    kind: str
    fields: dict[str, Any]
    condition: Condition | None
    where: Where


@dataclass
class Trial:
    """A trial file, read and checked."""

    path: str
    time_limit: float
    kit_trays: list[KitTraySpawn]
    bin_parts: list[BinPart]
    orders: list[Order]
    challenges: list[Challenge]
    agv_parts: dict[int, dict[str, Any]] = field(default_factory=dict)  # agv -> {tray_id, parts, where}
    conveyor: dict[str, Any] | None = None
    conveyor_where: Where | None = None
    assembly_inserts: dict[str, float] = field(default_factory=dict)

    @property
    def kitting_orders(self) -> list[Order]:
        return [o for o in self.orders if o.type == "kitting"]


# ------------------------------------------------------------------------------ reading


def read_trial(path: str | Path) -> Trial:
    """The trial file at ``path``, checked (an InputError at its ``file:line`` when it is not
    a trial ARIAC would run)."""
    return _Reader(str(path)).trial(load(path))


_PI = re.compile(r"^\s*([+-])?\s*(\d+(?:\.\d*)?|\.\d+)?\s*\*?\s*pi\s*(?:/\s*(\d+(?:\.\d*)?))?\s*$")


def angle(value: Any) -> float | None:
    """An ARIAC angle: a number, or ``pi`` with an optional sign, factor and divisor
    (``'pi'``, ``'-pi/2'``, ``'2*pi/3'``); None when it is neither."""
    if isinstance(value, bool):
        return None
    if isinstance(value, (int, float)):
        return float(value)
    if not isinstance(value, str):
        return None
    try:
        return float(value)
    except ValueError:
        pass
    m = _PI.match(value.lower())
    if m is None:
        return None
    sign, factor, divisor = m.groups()
    if divisor is not None and float(divisor) == 0:
        return None
    v = math.pi * (float(factor) if factor else 1.0) / (float(divisor) if divisor else 1.0)
    return -v if sign == "-" else v


class _Reader:
    def __init__(self, path: str) -> None:
        self.path = path
        self.taken_slots: dict[tuple[int, int], int | None] = {}

    # -- helpers
    def where(self, node: Any, key: Any = None) -> Where:
        return Where(self.path, line_of(node, key))

    def fail(self, node: Any, key: Any, message: str) -> InputError:
        return InputError(message, file=self.path, line=line_of(node, key))

    def mapping(self, node: Any, what: str, allowed: Iterable[str], parent: Any = None, key: Any = None,
                required: Iterable[str] = ()) -> YMap:
        if not isinstance(node, dict):
            raise self.fail(parent if parent is not None else node, key,
                            f"{what} must be a mapping of keys to values, not {_kind(node)}")
        allowed = tuple(allowed)
        for k in node:
            if k not in allowed:
                raise self.fail(node, k, f"{what}: unknown key {k!r} (ARIAC's keys here: {', '.join(allowed)})")
        for k in required:
            if k not in node:
                raise self.fail(node, None, f"{what}: missing {k!r}")
        return node

    def seq(self, node: Any, what: str, parent: Any, key: Any) -> YList:
        if not isinstance(node, list):
            raise self.fail(parent, key, f"{what} must be a list, not {_kind(node)}")
        return node

    def integer(self, node: Any, key: Any, what: str, lo: int, hi: int) -> int:
        v = node[key] if isinstance(node, (dict, list)) else node
        if isinstance(v, bool) or not isinstance(v, int) or not lo <= v <= hi:
            raise self.fail(node, key, f"{what} must be a whole number from {lo} to {hi}, not {v!r}")
        return v

    def number(self, node: Any, key: Any, what: str) -> float:
        v = node[key]
        if isinstance(v, bool) or not isinstance(v, (int, float)):
            try:
                return float(str(v))
            except ValueError:
                raise self.fail(node, key, f"{what} must be a number, not {v!r}") from None
        return float(v)

    def choice(self, node: Any, key: Any, what: str, options: Iterable[str]) -> str:
        v = node[key]
        options = tuple(options)
        if v not in options:
            raise self.fail(node, key, f"{what} {v!r} is not one of ARIAC's: {', '.join(options)}")
        return v

    def boolean(self, node: Any, key: str, what: str, default: bool = False) -> bool:
        if key not in node:
            return default
        v = node[key]
        if not isinstance(v, bool):
            raise self.fail(node, key, f"{what} must be true or false, not {v!r}")
        return v

    def angle_of(self, node: Any, key: str, what: str) -> float:
        if key not in node:
            return 0.0
        v = angle(node[key])
        if v is None:
            raise self.fail(node, key, f"{what} {node[key]!r} is not an angle (a number of radians, or pi "
                            "with a sign, factor and divisor: 'pi/2', '-pi/4', '2*pi/3')")
        return v

    def part_kind(self, node: YMap, what: str) -> tuple[str, str]:
        for k in ("type", "color"):
            if k not in node:
                raise self.fail(node, None, f"{what}: missing {k!r}")
        return (self.choice(node, "type", f"{what}: part type", PART_TYPES),
                self.choice(node, "color", f"{what}: part colour", COLORS))

    # -- sections
    def trial(self, doc: Any) -> Trial:
        if doc is None:
            raise InputError("empty file: not an ARIAC trial", file=self.path)
        top = self.mapping(doc, "trial", ("time_limit", "kitting_trays", "parts", "orders", "challenges",
                                          "assembly_inserts"))
        if "orders" not in top:
            raise InputError("no 'orders': an ARIAC trial has at least one order", file=self.path,
                             line=line_of(top))
        time_limit = self.number(top, "time_limit", "time_limit") if "time_limit" in top else -1.0
        trial = Trial(self.path, time_limit, self.kit_trays(top), [], [], [])
        if "parts" in top:
            self.parts(top, trial)
        trial.orders = self.orders(top)
        trial.challenges = self.challenges(top) if "challenges" in top else []
        if "assembly_inserts" in top:
            trial.assembly_inserts = self.inserts(top)
        self.cross_check(trial)
        return trial

    def kit_trays(self, top: YMap) -> list[KitTraySpawn]:
        if "kitting_trays" not in top or top["kitting_trays"] is None:
            return []
        node = self.mapping(top["kitting_trays"], "kitting_trays", ("tray_ids", "slots"), top, "kitting_trays",
                            required=("tray_ids", "slots"))
        ids = self.seq(node["tray_ids"], "kitting_trays.tray_ids", node, "tray_ids")
        slots = self.seq(node["slots"], "kitting_trays.slots", node, "slots")
        if len(ids) != len(slots):
            raise self.fail(node, "slots", f"kitting_trays: {len(ids)} tray_ids but {len(slots)} slots "
                            "(one slot per tray)")
        out, seen = [], {}
        for i in range(len(ids)):
            tray_id = self.integer(ids, i, "a kit tray id", 0, 9)
            slot = self.integer(slots, i, "a tray table slot", 1, 6)
            if slot in seen:
                raise self.fail(slots, i, f"kitting_trays: slot {slot} is given twice")
            seen[slot] = tray_id
            out.append(KitTraySpawn(tray_id, slot, self.where(slots, i)))
        return out

    def parts(self, top: YMap, trial: Trial) -> None:
        parts = top["parts"]
        if parts is None:
            return
        parts = self.mapping(parts, "parts", ("bins", "agvs", "conveyor_belt"), top, "parts")
        if parts.get("bins") is not None:
            bins = self.mapping(parts["bins"], "parts.bins", [f"bin{i}" for i in range(1, 9)], parts, "bins")
            for name, lots in bins.items():
                trial.bin_parts.extend(self.bin(int(name[3:]), lots, bins, name))
        if parts.get("agvs") is not None:
            agvs = self.mapping(parts["agvs"], "parts.agvs", [f"agv{i}" for i in range(1, 5)], parts, "agvs")
            for name, spec in agvs.items():
                trial.agv_parts[int(name[3:])] = self.agv(name, spec, agvs)
        if parts.get("conveyor_belt") is not None:
            trial.conveyor = self.conveyor(parts["conveyor_belt"], parts)
            trial.conveyor_where = self.where(parts, "conveyor_belt")

    def bin(self, number: int, lots: Any, parent: YMap, key: str) -> list[BinPart]:
        if lots is None:
            return []
        what = f"parts.bins.bin{number}"
        lots = self.seq(lots, what, parent, key)
        out = []
        for i, lot in enumerate(lots):
            lot = self.mapping(lot, f"{what}[{i + 1}]", ("type", "color", "slots", "rotation", "flipped"),
                               lots, i, required=("slots",))
            kind = self.part_kind(lot, f"{what}[{i + 1}]")
            rotation = self.angle_of(lot, "rotation", f"{what}: rotation")
            flipped = self.boolean(lot, "flipped", f"{what}: flipped")
            slots = self.seq(lot["slots"], f"{what}: slots", lot, "slots")
            for j in range(len(slots)):
                slot = self.integer(slots, j, f"{what}: a slot", 1, 9)
                first = self.taken_slots.get((number, slot), 0)
                if first != 0:
                    raise self.fail(slots, j, f"bin{number} slot {slot} already holds a part (line {first})")
                self.taken_slots[(number, slot)] = line_of(slots, j)
                out.append(BinPart(number, slot, *kind, rotation, flipped, self.where(slots, j)))
        return out

    def agv(self, name: str, spec: Any, parent: YMap) -> dict[str, Any]:
        spec = self.mapping(spec, f"parts.agvs.{name}", ("tray_id", "parts"), parent, name)
        tray = self.integer(spec, "tray_id", f"{name}: tray_id", 0, 9) if "tray_id" in spec else 0
        parts, quadrants, bad = [], set(), []
        for i, p in enumerate(self.seq(spec.get("parts") or YList(), f"{name}: parts", spec, "parts")):
            p = self.mapping(p, f"{name}: parts[{i + 1}]", ("type", "color", "quadrant", "rotation", "flipped"),
                             spec["parts"], i, required=("quadrant",))
            kind = self.part_kind(p, f"{name}: parts[{i + 1}]")
            q = self.integer(p, "quadrant", f"{name}: quadrant", 1, 4)
            if q in quadrants:
                raise self.fail(p, "quadrant", f"{name}: quadrant {q} is given twice")
            quadrants.add(q)
            if "rotation" in p and angle(p["rotation"]) is None:
                bad.append(f"rotation {p['rotation']!r} at line {line_of(p, 'rotation')}")
            parts.append({"type": kind[0], "color": kind[1], "quadrant": q,
                          "flipped": self.boolean(p, "flipped", f"{name}: flipped")})
        return {"tray_id": tray, "parts": parts, "where": self.where(parent, name), "bad": bad}

    def conveyor(self, node: Any, parent: YMap) -> dict[str, Any]:
        node = self.mapping(node, "parts.conveyor_belt", ("active", "spawn_rate", "order", "parts_to_spawn"),
                            parent, "conveyor_belt")
        active = self.boolean(node, "active", "conveyor_belt.active")
        if "order" in node:
            self.choice(node, "order", "conveyor_belt.order", ("random", "sequential"))
        if "spawn_rate" in node:
            self.number(node, "spawn_rate", "conveyor_belt.spawn_rate")
        lots = []
        for i, lot in enumerate(self.seq(node.get("parts_to_spawn") or YList(), "conveyor_belt.parts_to_spawn",
                                         node, "parts_to_spawn")):
            what = f"conveyor_belt.parts_to_spawn[{i + 1}]"
            lot = self.mapping(lot, what, ("type", "color", "number", "offset", "flipped", "rotation"),
                               node["parts_to_spawn"], i)
            kind = self.part_kind(lot, what)
            number = self.integer(lot, "number", f"{what}: number", 0, 10_000) if "number" in lot else 0
            if "offset" in lot:
                offset = self.number(lot, "offset", f"{what}: offset")
                if not -1 <= offset <= 1:
                    raise self.fail(lot, "offset", f"{what}: offset {offset} is not between -1 and 1")
            self.angle_of(lot, "rotation", f"{what}: rotation")
            self.boolean(lot, "flipped", f"{what}: flipped")
            lots.append({"type": kind[0], "color": kind[1], "number": number})
        return {"active": active, "parts": lots}

    def condition(self, node: YMap, what: str, keys: tuple[str, ...] = ("time_condition", "part_place_condition",
                                                                          "submission_condition")) -> Condition:
        given = [k for k in keys if k in node]
        if len(given) != 1:
            raise self.fail(node, None, f"{what}: one announcement condition is needed "
                            f"({', '.join(keys)}), {len(given)} given")
        key = given[0]
        if key == "time_condition":
            t = self.number(node, key, f"{what}: time_condition")
            if t < 0:
                raise self.fail(node, key, f"{what}: time_condition {t} is before the start")
            return Condition("time", time=t)
        if key == "part_place_condition":
            c = self.mapping(node[key], f"{what}: part_place_condition", ("agv", "type", "color"), node, key,
                             required=("agv", "type", "color"))
            return Condition("part_place", agv=self.integer(c, "agv", f"{what}: agv", 1, 4),
                             type=self.choice(c, "type", f"{what}: part type", PART_TYPES),
                             color=self.choice(c, "color", f"{what}: part colour", COLORS))
        c = self.mapping(node[key], f"{what}: submission_condition", ("order_id",), node, key,
                         required=("order_id",))
        return Condition("submission", order_id=str(c["order_id"]))

    def orders(self, top: YMap) -> list[Order]:
        orders = self.seq(top["orders"], "orders", top, "orders")
        if not orders:
            raise self.fail(top, "orders", "orders: the list is empty (an ARIAC trial has at least one order)")
        out: list[Order] = []
        seen: dict[str, int | None] = {}
        for i, o in enumerate(orders):
            o = self.mapping(o, f"orders[{i + 1}]", ("id", "type", "announcement", "priority", "kitting_task",
                                                     "assembly_task", "combined_task"), orders, i,
                             required=("id", "type", "announcement"))
            oid = str(o["id"])
            if oid in seen:
                raise self.fail(o, "id", f"order id {oid!r} is given twice (first at line {seen[oid]})")
            seen[oid] = line_of(o, "id")
            kind = self.choice(o, "type", f"order {oid}: type", ("kitting", "assembly", "combined"))
            task_key = f"{kind}_task"
            for other in ("kitting_task", "assembly_task", "combined_task"):
                if other in o and other != task_key:
                    raise self.fail(o, other, f"order {oid} of type {kind!r} has a {other} (its task is {task_key})")
            if task_key not in o:
                raise self.fail(o, None, f"order {oid}: missing {task_key!r}")
            ann = self.mapping(o["announcement"], f"order {oid}: announcement",
                               ("time_condition", "part_place_condition", "submission_condition"), o, "announcement")
            cond = self.condition(ann, f"order {oid}: announcement")
            priority = self.boolean(o, "priority", f"order {oid}: priority")
            kitting = self.kitting_task(oid, o) if kind == "kitting" else None
            if kind != "kitting":
                self.other_task(oid, o, task_key)
            out.append(Order(oid, kind, priority, cond, kitting, self.where(orders, i)))
        return out

    def kitting_task(self, oid: str, o: YMap) -> KittingTask:
        what = f"order {oid}: kitting_task"
        t = self.mapping(o["kitting_task"], what, ("agv_number", "tray_id", "destination", "products"), o,
                         "kitting_task", required=("agv_number", "tray_id", "destination", "products"))
        agv = self.integer(t, "agv_number", f"{what}: agv_number", 1, 4)
        tray = self.integer(t, "tray_id", f"{what}: tray_id", 0, 9)
        dest = self.choice(t, "destination", f"{what}: destination", tuple(DESTINATIONS))
        products, quadrants = [], {}
        for i, p in enumerate(self.seq(t["products"], f"{what}: products", t, "products")):
            p = self.mapping(p, f"{what}: products[{i + 1}]", ("type", "color", "quadrant"), t["products"], i,
                             required=("type", "color", "quadrant"))
            kind = self.part_kind(p, f"{what}: products[{i + 1}]")
            q = self.integer(p, "quadrant", f"{what}: quadrant", 1, 4)
            if q in quadrants:
                raise self.fail(p, "quadrant", f"{what}: quadrant {q} is asked for twice (line {quadrants[q]})")
            quadrants[q] = line_of(p, "quadrant")
            products.append(Product(*kind, q))
        if not products:
            raise self.fail(t, "products", f"{what}: no products")
        return KittingTask(agv, tray, dest, tuple(products))

    def other_task(self, oid: str, o: YMap, key: str) -> None:
        what = f"order {oid}: {key}"
        allowed = ("station", "products") + (("agv_number",) if key == "assembly_task" else ())
        t = self.mapping(o[key], what, allowed, o, key)
        if "station" in t:
            self.choice(t, "station", f"{what}: station", ("as1", "as2", "as3", "as4"))
        for i, p in enumerate(self.seq(t.get("products") or YList(), f"{what}: products", t, "products")):
            p = self.mapping(p, f"{what}: products[{i + 1}]", ("type", "color", "assembled_pose",
                                                               "assembly_direction"), t["products"], i)
            self.part_kind(p, f"{what}: products[{i + 1}]")

    def challenges(self, top: YMap) -> list[Challenge]:
        node = top["challenges"]
        if node is None:
            return []
        node = self.seq(node, "challenges", top, "challenges")
        kinds = {
            "faulty_part": ("order_id", "quadrant1", "quadrant2", "quadrant3", "quadrant4"),
            "dropped_part": ("robot", "type", "color", "drop_after", "delay"),
            "robot_malfunction": ("duration", "robots_to_disable"),
            "sensor_blackout": ("duration", "sensors_to_disable"),
            "human": ("behavior",),
        }
        conditions = ("time_condition", "part_place_condition", "submission_condition")
        out = []
        for i, c in enumerate(node):
            c = self.mapping(c, f"challenges[{i + 1}]", tuple(kinds), node, i)
            if len(c) != 1:
                raise self.fail(c, None, f"challenges[{i + 1}]: one challenge per list item ({len(c)} given)")
            kind, body = next(iter(c.items()))
            what = f"challenges[{i + 1}].{kind}"
            announced = kind in ("robot_malfunction", "sensor_blackout", "human")
            body = self.mapping(body, what, kinds[kind] + (conditions if announced else ()), c, kind)
            out.append(Challenge(kind, self.challenge_fields(kind, body, what),
                                 self.condition(body, what) if announced else None, self.where(c, kind)))
        return out

    def challenge_fields(self, kind: str, body: YMap, what: str) -> dict[str, Any]:
        if kind == "faulty_part":
            if "order_id" not in body:
                raise self.fail(body, None, f"{what}: missing 'order_id'")
            return {"order_id": str(body["order_id"]),
                    "quadrants": [q for q in range(1, 5) if self.boolean(body, f"quadrant{q}", f"{what}: quadrant{q}")]}
        if kind == "dropped_part":
            for k in kinds_required(kind):
                if k not in body:
                    raise self.fail(body, None, f"{what}: missing {k!r}")
            return {"robot": self.choice(body, "robot", f"{what}: robot", ROBOTS),
                    "type": self.choice(body, "type", f"{what}: part type", PART_TYPES),
                    "color": self.choice(body, "color", f"{what}: part colour", COLORS),
                    "drop_after": self.integer(body, "drop_after", f"{what}: drop_after", 1, 1_000_000),
                    "delay": self.number(body, "delay", f"{what}: delay")}
        if kind == "human":
            if "behavior" not in body:
                raise self.fail(body, None, f"{what}: missing 'behavior'")
            return {"behavior": self.choice(body, "behavior", f"{what}: behavior", HUMAN_BEHAVIORS)}
        listed, options = (("robots_to_disable", ROBOTS) if kind == "robot_malfunction"
                           else ("sensors_to_disable", SENSOR_TYPES))
        for k in ("duration", listed):
            if k not in body:
                raise self.fail(body, None, f"{what}: missing {k!r}")
        items = self.seq(body[listed], f"{what}: {listed}", body, listed)
        for j in range(len(items)):
            self.choice(items, j, f"{what}: {listed[:-len('s_to_disable')]}", options)
        return {"duration": self.number(body, "duration", f"{what}: duration"), listed: list(items)}

    def inserts(self, top: YMap) -> dict[str, float]:
        node = self.mapping(top["assembly_inserts"], "assembly_inserts", ("as1", "as2", "as3", "as4"), top,
                            "assembly_inserts")
        return {k: self.angle_of(node, k, f"assembly_inserts.{k}") for k in node}

    def cross_check(self, trial: Trial) -> None:
        ids = {o.id for o in trial.orders}
        for o in trial.orders:
            c = o.announcement
            if c.kind == "submission" and c.order_id not in ids:
                raise InputError(f"order {o.id} is announced on the submission of {c.order_id!r}, "
                                 "which no order of the trial has as its id", file=self.path, line=o.where.line)
        for ch in trial.challenges:
            oid = ch.fields.get("order_id") if ch.kind == "faulty_part" else (
                ch.condition.order_id if ch.condition else None)
            if oid is not None and oid not in ids:
                raise InputError(f"{ch.kind} names order {oid!r}, which the trial does not have",
                                 file=self.path, line=ch.where.line)


def kinds_required(kind: str) -> tuple[str, ...]:
    return {"dropped_part": ("robot", "type", "color", "drop_after", "delay")}.get(kind, ())


def _kind(value: Any) -> str:
    if value is None:
        return "nothing"
    if isinstance(value, dict):
        return "a mapping"
    if isinstance(value, list):
        return "a list"
    return repr(value)
