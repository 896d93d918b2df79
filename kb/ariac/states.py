"""A trial's workstation laid out in ARIAC's geometry, and its initial and goal states as blocks.

How ARIAC's workcell maps onto kitkb's kitting model (docs/ariac.md has the table):

* a part type and colour is a SKU (``sku_pump_red``); a bin is a work table (``bin2``) and each
  of its occupied slots a parts tray of one part (``bin2_slot3``), so that a bin may hold parts
  of several SKUs as ARIAC's do; a flipped part lies upside down (its z axis down);
* each kit tray id is a kit tray SKU (``sku_kit_tray_03``); the trays on the two tray tables are
  in two large boxes of empty kit trays (``kts1``, ``kts2``, the tables' tops);
* each AGV's tray is a work table (``agv1`` .. ``agv4``): kits are built on an AGV;
* a kitting order is a kit design (its tray id's SKU, one part reference per quadrant at the
  quadrant's offset) and a kit to build; the place its kit goes is a large box with kits of
  capacity 1 beside its AGV (``shipment_<order>``), standing for "its AGV sent to its
  destination": putting the kit there is submitting the order;
* the floor robot is kitkb's robot; its two tools (parts, trays) hang in a changing station at
  kts1's tool changers.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from typing import Iterator

from kb.ariac import workcell as W
from kb.ariac.trial import BinPart, KitTraySpawn, Order, Trial
from kb.scenario.turtle import Block, Geometry, Text, Typed

Pose = tuple[float, ...]
UP = (1.0, 0.0, 0.0, 0.0, 0.0, 1.0)
DOWN = (1.0, 0.0, 0.0, 0.0, 0.0, -1.0)
WS = "kitting_workstation_1"
ROBOT = "floor_robot"


def pose(x: float, y: float, z: float, yaw: float = 0.0, flipped: bool = False) -> Pose:
    """A pose from a point, a yaw and whether the object lies upside down (roll pi, as ARIAC
    spawns a flipped part: x axis kept, z axis down)."""
    c, s = round(math.cos(yaw), 12), round(math.sin(yaw), 12)
    return (float(round(x, 9)), float(round(y, 9)), float(round(z, 9)), float(c), float(s), 0.0, 0.0, 0.0,
            -1.0 if flipped else 1.0)


def name_of(text: str) -> str:
    """A local name from an ARIAC id (letters, digits and underscores)."""
    return re.sub(r"[^A-Za-z0-9_]", "_", text)


@dataclass
class PartIn:
    name: str
    part: BinPart


@dataclass
class Kit:
    """A kitting order's kit: its design, tray, shipment and a part for each quadrant (None:
    no part of that type and colour is left in the bins)."""

    order: Order
    name: str
    design: str
    tray: str
    shipment: str
    shipment_pose: Pose
    slots: list[tuple[int, str, str, str | None]] = field(default_factory=list)  # (quadrant, slot, prp, part)


@dataclass
class Layout:
    trial: Trial
    namespace: str
    parts: list[PartIn]
    trays: list[tuple[str, KitTraySpawn]]
    kits: list[Kit]
    skus: dict[str, tuple[str, tuple[float, float, float], bool, float, str | None]]
    warnings: list[str]

    @property
    def bins(self) -> list[int]:
        return sorted({p.part.bin for p in self.parts})


def lay_out(trial: Trial, namespace: str, warnings: list[str]) -> Layout:
    """Name and place everything of ``trial`` kitkb models (``warnings`` gets what it skips)."""
    parts = [PartIn(f"{p.type}_{p.color}_b{i:02d}", p) for i, p in enumerate(trial.bin_parts)]
    trays = [(f"kit_tray_{t.tray_id:02d}_{i}", t) for i, t in enumerate(trial.kit_trays)]
    skus: dict = {}
    kinds = {(p.part.type, p.part.color) for p in parts}
    kinds |= {(pr.type, pr.color) for o in trial.kitting_orders for pr in o.kitting.products}  # type: ignore[union-attr]
    for kind in sorted(kinds):
        x, y, h, weight = W.PARTS[kind[0]]
        skus[f"sku_{kind[0]}_{kind[1]}"] = (f"SKU of {kind[1]} {kind[0]}s", (x, y, h), True, weight, "part_gripper")
    for tray_id in sorted({t.tray_id for _, t in trays} | {o.kitting.tray_id for o in trial.kitting_orders}):  # type: ignore[union-attr]
        skus[f"sku_kit_tray_{tray_id:02d}"] = (f"SKU of kit trays with marker id {tray_id}", W.KIT_TRAY, False, 0.3,
                                               "tray_gripper")
    skus["sku_bin_slot"] = ("SKU of a bin slot (kitkb's parts tray for one slot of an ARIAC bin)", W.SLOT_CELL,
                            False, 0.1, None)
    skus["sku_tray_table_top"] = ("SKU of a kit tray table's top", W.TRAY_TABLE_SIZE, False, 20.0, None)
    skus["sku_shipment"] = ("SKU of an order's shipment (its AGV sent to its destination)",
                            (W.KIT_TRAY[0] + 0.1, W.KIT_TRAY[1] + 0.1, 0.2), False, 5.0, None)
    return Layout(trial, namespace, parts, trays, _kits(trial, parts, trays, warnings), skus, warnings)


def _kits(trial: Trial, parts: list[PartIn], trays: list[tuple[str, KitTraySpawn]], warnings: list[str]) -> list[Kit]:
    free_trays = list(trays)
    # upright parts first: a flipped part is the last resort (kitkb's domain has no action that turns it over)
    stock = sorted(parts, key=lambda p: p.part.flipped)
    kits: list[Kit] = []
    per_agv: dict[int, int] = {}
    for order in trial.kitting_orders:
        task = order.kitting
        assert task is not None
        tray = next((t for t in free_trays if t[1].tray_id == task.tray_id), None)
        if tray is None:
            warnings.append(f"{order.where}: order {order.id} asks for kit tray {task.tray_id}, which no tray table "
                            f"holds (or another order took it): skipped")
            continue
        free_trays.remove(tray)
        k = per_agv.get(task.agv, 0)
        per_agv[task.agv] = k + 1
        oid = name_of(order.id)
        kit = Kit(order, f"kit_{oid}", f"design_{oid}", tray[0], f"shipment_{oid}",
                  pose(W.SHIPMENT_X0 + k * W.SHIPMENT_DX, W.AGV_Y[task.agv], 0.0, W.AGV_YAW))
        for product in sorted(task.products, key=lambda p: p.quadrant):
            found = next((p for p in stock if (p.part.type, p.part.color) == (product.type, product.color)), None)
            if found is not None:
                stock.remove(found)
            kit.slots.append((product.quadrant, f"{kit.name}_q{product.quadrant}", f"{kit.design}_q{product.quadrant}",
                              found.name if found else None))
        short = [f"{p.color} {p.type} (quadrant {p.quadrant})" for p, (_, _, _, part) in
                 zip(sorted(task.products, key=lambda p: p.quadrant), kit.slots) if part is None]
        if short:
            warnings.append(f"{order.where}: order {order.id}: the bins hold no part left for "
                            f"{', '.join(short)} (insufficient parts): its kit can only be partial")
        kits.append(kit)
    return kits


# ------------------------------------------------------------------------------ blocks


def state_blocks(lay: Layout, goal: bool) -> Iterator[Block]:
    """The individuals of the initial (``goal`` False) or goal state."""
    yield from _workstation(lay)
    yield from _skus(lay)
    yield from _designs(lay)
    yield from _station()
    yield from _robot(lay)
    yield from _bins(lay, goal)
    yield from _tray_tables(lay, goal)
    yield from _agvs(lay)
    yield from _shipments(lay, goal)


def _solid(name: str, classes: tuple[str, ...], props: list, cls: str, ref: str, p: Pose) -> Iterator[Block]:
    yield (name, classes, [("hasSolidObject_PrimaryLocation", f"{name}_pose")] + props)
    yield Geometry(name, cls, ref, p)


def _shape(name: str, description: str, dims: tuple[float, float, float], has_top: bool) -> Block:
    return (name, ("BoxyShape",), [
        ("hasShapeDesign_Description", Text(description)),
        ("hasBoxyShape_Length", float(dims[0])), ("hasBoxyShape_Width", float(dims[1])),
        ("hasBoxyShape_Height", float(dims[2])), ("hasBoxyShape_HasTop", has_top),
    ])


def _objects(lay: Layout) -> list[str]:
    out = [f"bin{b}" for b in lay.bins] + [f"kts{t}{s}" for t in (1, 2) for s in ("_table", "")] + [f"agv{a}" for a in W.AGV_Y]
    out += [f"bin{p.part.bin}_slot{p.part.slot}" for p in lay.parts]
    return out + [k.shipment for k in lay.kits]


def _workstation(lay: Layout) -> Iterator[Block]:
    props = [
        ("hasKittingWorkstation_AngleUnit", Text("radian")),
        ("hasKittingWorkstation_LengthUnit", Text("meter")),
        ("hasKittingWorkstation_WeightUnit", Text("kilogram")),
        ("hasKittingWorkstation_ChangingStation", "changing_station_1"),
        ("hasKittingWorkstation_Robot", ROBOT),
    ]
    props += [("hasKittingWorkstation_Object", o) for o in _objects(lay)]
    props += [("hasKittingWorkstation_Sku", s) for s in lay.skus]
    props += [("hasKittingWorkstation_KitDesign", k.design) for k in lay.kits]
    yield (None, "ARIAC workcell (ARIAC's world frame; its location is given relative to itself)", [])
    yield from _solid(WS, ("KittingWorkstation",), props, "PoseOnlyLocation", WS, pose(0, 0, 0))


def _skus(lay: Layout) -> Iterator[Block]:
    yield (None, "stock keeping units: a part type and colour each, a kit tray id each, and the containers", [])
    for name, (text, dims, top, weight, effector) in lay.skus.items():
        props = [("hasStockKeepingUnit_Description", Text(text)),
                 ("hasStockKeepingUnit_InternalShape", f"shape_{name[4:]}"),
                 ("hasStockKeepingUnit_Weight", float(weight))]
        if effector:
            props.append(("hasStockKeepingUnit_EndEffector", effector))
        yield (name, ("StockKeepingUnit",), props)
        yield _shape(f"shape_{name[4:]}", f"shape of {text[7:]}", dims, top)


def _designs(lay: Layout) -> Iterator[Block]:
    for kit in lay.kits:
        task = kit.order.kitting
        assert task is not None
        yield (None, f"order {kit.order.id}: kit tray {task.tray_id} on AGV {task.agv} to {task.destination}, "
                     "a part reference per quadrant", [])
        yield (kit.design, ("KitDesign",), [("hasKitDesign_KitTraySku", f"sku_kit_tray_{task.tray_id:02d}")]
               + [("hasKitDesign_PartRefAndPose", prp) for _, _, prp, _ in kit.slots])
        for product in task.products:
            prp = f"{kit.design}_q{product.quadrant}"
            yield (prp, ("PartRefAndPose",), [
                ("hasPartRefAndPose_Sku", f"sku_{product.type}_{product.color}"),
                ("hasPartRefAndPose_Point", f"{prp}_point"),
                ("hasPartRefAndPose_XAxis", f"{prp}_x_axis"),
                ("hasPartRefAndPose_ZAxis", f"{prp}_z_axis"),
            ])
            yield Geometry(prp, None, None, pose(*W.QUADRANTS[product.quadrant], 0.0))


HOLDER = (0.12, 0.12, 0.10)
BASE = (0.6, 0.3, 0.7)
EFFECTORS = {"part_gripper": (0.08, 0.06, 0.08), "tray_gripper": (0.10, 0.10, 0.09)}


def _station() -> Iterator[Block]:
    x, y, _, yaw = W.TRAY_TABLES[1]
    c, s = math.cos(yaw), math.sin(yaw)
    ox, oy = (W.TOOL_CHANGERS["part_gripper"][0] + W.TOOL_CHANGERS["tray_gripper"][0]) / 2, W.TOOL_CHANGERS["part_gripper"][1]
    at = pose(x + c * ox - s * oy, y + s * ox + c * oy, 0.0, yaw)
    holders = ["part_gripper_holder", "tray_gripper_holder"]
    yield (None, "changing station at kts1's tool changers (parts, trays)", [])
    yield from _solid("changing_station_1", ("EndEffectorChangingStation",),
                      [("hasEndEffectorChangingStation_Base", "changing_station_base")]
                      + [("hasEndEffectorChangingStation_EndEffectorHolder", h) for h in holders],
                      "PoseOnlyLocation", WS, at)
    yield from _solid("changing_station_base", ("MechanicalComponent",),
                      [("hasNoSkuObject_InternalShape", "shape_changing_station_base")],
                      "PoseOnlyLocation", "changing_station_1", pose(0, 0, 0))
    yield _shape("shape_changing_station_base", "base of the tool changers", BASE, True)
    for holder in holders:
        effector = holder[: -len("_holder")]
        hx = W.TOOL_CHANGERS[effector][0] - ox
        yield from _solid(holder, ("EndEffectorHolder",), [
            ("hasNoSkuObject_InternalShape", f"shape_{holder}"),
            ("hasEndEffectorHolder_EndEffector", effector),
        ], "PoseLocationIn", "changing_station_1", pose(hx, 0.0, BASE[2] - HOLDER[2]))
        yield _shape(f"shape_{holder}", f"{effector.replace('_', ' ')} changer", HOLDER, False)
        yield from _effector(effector, holder)


def _effector(name: str, holder: str) -> Iterator[Block]:
    if name == "part_gripper":
        classes, extra, text, weight, load = ("GripperEffector",), [], "the floor robot's gripper for parts", 0.2, 1.0
    else:
        classes = ("VacuumEffectorSingleCup",)
        extra = [("hasVacuumEffector_CupDiameter", 0.08), ("hasVacuumEffector_Length", 0.09)]
        text, weight, load = "the floor robot's gripper for kit trays and kits", 0.4, 3.0
    p = (0.0, 0.0, HOLDER[2]) + DOWN
    yield from _solid(name, classes, [
        ("hasNoSkuObject_InternalShape", f"shape_{name}"),
        ("hasEndEffector_Description", Text(text)),
        ("hasEndEffector_Weight", weight),
        ("hasEndEffector_MaximumLoadWeight", load),
    ] + extra, "PoseLocationIn", holder, p)
    yield _shape(f"shape_{name}", f"{name.replace('_', ' ')} (z axis along the tool)", EFFECTORS[name], True)


def _robot(lay: Layout) -> Iterator[Block]:
    yield (None, "the floor robot (holding no tool); its pose is its tool flange at home, z down", [])
    yield from _solid(ROBOT, ("Robot",), [
        ("hasNoSkuObject_InternalShape", f"shape_{ROBOT}"),
        ("hasRobot_Description", Text("ARIAC's floor robot (a UR10e on a linear rail)")),
        ("hasRobot_MaximumLoadWeight", 5.0),
        ("hasRobot_WorkVolume", f"{ROBOT}_work_volume"),
    ], "PoseOnlyLocation", WS, W.ROBOT_HOME + DOWN)
    yield _shape(f"shape_{ROBOT}", "robot tool flange (z axis along the tool)", (0.1, 0.1, 0.02), True)
    yield (f"{ROBOT}_work_volume", ("BoxVolume",), [
        ("hasBoxVolume_MinimumPoint", f"{ROBOT}_work_volume_min"),
        ("hasBoxVolume_MaximumPoint", f"{ROBOT}_work_volume_max"),
    ])
    xs = [W.SHIPMENT_X0 + W.SHIPMENT_DX * max(1, len(lay.kits)) - 1.0, -0.3]
    for end, point in zip(("min", "max"), ((xs[0], -6.8, 0.0), (xs[1], 6.8, 2.5))):
        yield (f"{ROBOT}_work_volume_{end}", ("Point",),
               [("hasPoint_X", point[0]), ("hasPoint_Y", point[1]), ("hasPoint_Z", point[2])])


def _bins(lay: Layout, goal: bool) -> Iterator[Block]:
    used = {part for kit in lay.kits for *_, part in kit.slots if part} if goal else set()
    by_bin: dict[int, list[PartIn]] = {}
    for p in lay.parts:
        by_bin.setdefault(p.part.bin, []).append(p)
    for b in lay.bins:
        x, y, z, yaw = W.BINS[b]
        yield (None, f"bin{b}: a work table whose top is the bin's floor; a parts tray for each occupied slot", [])
        yield from _solid(f"bin{b}", ("WorkTable",), [("hasNoSkuObject_InternalShape", f"shape_bin{b}")]
                          + [("hasWorkTable_ObjectOnTable", f"bin{b}_slot{p.part.slot}") for p in by_bin[b]],
                          "PoseOnlyLocation", WS, pose(x, y, 0.0, yaw))
        yield _shape(f"shape_bin{b}", f"bin{b}", (W.BIN_SIZE, W.BIN_SIZE, z), True)
        for p in by_bin[b]:
            tray = f"bin{b}_slot{p.part.slot}"
            here = [] if p.name in used else [p]
            yield from _solid(tray, ("PartsTray",), [
                ("hasSkuObject_Sku", "sku_bin_slot"),
                ("hasPartsVessel_SerialNumber", Typed(tray, "NMTOKEN")),
                ("hasPartsVessel_PartSku", f"sku_{p.part.type}_{p.part.color}"),
                ("hasPartsVessel_PartQuantity", Typed(str(len(here)), "nonNegativeInteger")),
            ] + [("hasPartsVessel_Part", q.name) for q in here],
                "PoseLocationOn", f"bin{b}", pose(*W.BIN_SLOTS[p.part.slot], z))
            for q in here:
                h = W.PARTS[q.part.type][2]
                yield from _part(q.name, q.part, tray, pose(0.0, 0.0, h if q.part.flipped else 0.0,
                                                            q.part.rotation, q.part.flipped))


def _part(name: str, part: BinPart, ref: str, p: Pose) -> Iterator[Block]:
    yield from _solid(name, ("Part",), [
        ("hasSkuObject_Sku", f"sku_{part.type}_{part.color}"),
        ("hasPart_SerialNumber", Typed(name, "NMTOKEN")),
    ], "PoseLocationIn", ref, p)


def _tray_tables(lay: Layout, goal: bool) -> Iterator[Block]:
    used = {k.tray for k in lay.kits} if goal else set()
    for table in (1, 2):
        x, y, z, yaw = W.TRAY_TABLES[table]
        trays = [(n, t) for n, t in lay.trays if W.TRAY_SLOTS[t.slot][0] == table and n not in used]
        yield (None, f"kit tray station kts{table}: its table top holds the kit trays of slots "
                     f"{3 * table - 2}-{3 * table}", [])
        yield from _solid(f"kts{table}_table", ("MechanicalComponent",), [
            ("hasNoSkuObject_InternalShape", f"shape_kts{table}_table")], "PoseOnlyLocation", WS, pose(x, y, 0.0, yaw))
        yield _shape(f"shape_kts{table}_table", f"kit tray station {table}'s table",
                     W.TRAY_TABLE_SIZE[:2] + (z - 0.01,), True)
        yield from _solid(f"kts{table}", ("LargeBoxWithEmptyKitTrays",),
                          [("hasLargeBoxWithEmptyKitTrays_LargeContainer", f"kts{table}_top")]
                          + [("hasLargeBoxWithEmptyKitTrays_KitTray", n) for n, _ in trays],
                          "PoseOnlyLocation", WS, pose(x, y, z - 0.01, yaw))
        yield from _solid(f"kts{table}_top", ("LargeContainer",), [
            ("hasSkuObject_Sku", "sku_tray_table_top"),
            ("hasLargeContainer_SerialNumber", Typed(f"kts{table}_top", "NMTOKEN")),
        ], "PoseOnlyLocation", f"kts{table}", pose(0, 0, 0))
        for n, t in trays:
            yield from _kit_tray(n, t.tray_id, "PoseLocationIn", f"kts{table}_top",
                                 pose(W.TRAY_SLOTS[t.slot][1], 0.0, 0.0))


def _kit_tray(name: str, tray_id: int, cls: str, ref: str, p: Pose) -> Iterator[Block]:
    yield from _solid(name, ("KitTray",), [
        ("hasSkuObject_Sku", f"sku_kit_tray_{tray_id:02d}"),
        ("hasKitTray_SerialNumber", Typed(name, "NMTOKEN")),
    ], cls, ref, p)


def _agvs(lay: Layout) -> Iterator[Block]:
    used = {k.order.kitting.agv for k in lay.kits}  # type: ignore[union-attr]
    for agv, y in W.AGV_Y.items():
        if agv in used:
            text, cls = "its tray is a work table where kits are built", "WorkTable"
        else:
            text, cls = "no kitting order ships on it: an obstacle, not a work table", "MechanicalComponent"
        yield (None, f"AGV {agv} at its kitting station: {text}", [])
        yield from _solid(f"agv{agv}", (cls,), [("hasNoSkuObject_InternalShape", f"shape_agv{agv}")],
                          "PoseOnlyLocation", WS, pose(W.AGV_TRAY_X, y, 0.0, W.AGV_YAW))
        yield _shape(f"shape_agv{agv}", f"AGV {agv}'s tray", W.AGV_DECK, True)


def _shipments(lay: Layout, goal: bool) -> Iterator[Block]:
    for kit in lay.kits:
        task = kit.order.kitting
        assert task is not None
        yield (None, f"order {kit.order.id}'s shipment: AGV {task.agv} sent to {task.destination}", [])
        yield from _solid(kit.shipment, ("LargeBoxWithKits",), [
            ("hasLargeBoxWithKits_LargeContainer", f"{kit.shipment}_box"),
            ("hasLargeBoxWithKits_KitDesign", kit.design),
            ("hasLargeBoxWithKits_Capacity", Typed("1", "positiveInteger")),
        ] + ([("hasLargeBoxWithKits_Kit", kit.name)] if goal else []), "PoseOnlyLocation", WS, kit.shipment_pose)
        yield from _solid(f"{kit.shipment}_box", ("LargeContainer",), [
            ("hasSkuObject_Sku", "sku_shipment"),
            ("hasLargeContainer_SerialNumber", Typed(f"{kit.shipment}_box", "NMTOKEN")),
        ], "PoseOnlyLocation", kit.shipment, pose(0, 0, 0))
        if not goal:
            continue
        parts = {p.name: p.part for p in lay.parts}
        filled = [(q, slot, prp, part) for q, slot, prp, part in kit.slots if part]
        yield from _solid(kit.name, ("Kit",), [
            ("hasKit_Design", kit.design), ("hasKit_KitTray", kit.tray), ("hasKit_Finished", True),
        ] + [("hasKit_Part", part) for *_, part in filled]
          + [("hasKit_Slot", slot) for _, slot, _, _ in kit.slots], "PoseLocationIn", f"{kit.shipment}_box",
            pose(0, 0, 0))
        tray_id = next(t.tray_id for n, t in lay.trays if n == kit.tray)
        yield from _kit_tray(kit.tray, tray_id, "PoseOnlyLocation", kit.name, pose(0, 0, 0))
        for q, slot, prp, part in kit.slots:
            yield (slot, ("Slot",), [("hasSlot_PartRefAndPose", prp)] + ([("hasSlot_Part", part)] if part else []))
        for q, _, _, part in filled:
            yield from _part(part, parts[part], kit.tray, pose(*W.QUADRANTS[q], 0.0))
