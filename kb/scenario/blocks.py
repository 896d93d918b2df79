"""The individuals of a laid-out scenario, as writer blocks (see :mod:`kb.scenario.turtle`).

:func:`state_blocks` yields the init or the goal state (:func:`state_graph`: as a graph).
Both are complete data files: the workstation, SKUs, kit designs, changing station, robot
and tables appear in both; the parts trays, the large boxes and their contents differ.
"""

from __future__ import annotations

from typing import Iterator

from rdflib import Graph

from kb.scenario.layout import (BASE, EFFECTORS, HOLDER, POINTING_DOWN, ROBOT_FLANGE, ROBOT_HOME_Z, KitLayout, Pose,
                                Scenario, pose)
from kb.scenario.turtle import Block, Geometry, Text, Typed, blocks_to_graph

def _shape_block(name: str, description: str, dims, has_top: bool) -> Block:
    return (name, ("BoxyShape",), [
        ("hasShapeDesign_Description", Text(description)),
        ("hasBoxyShape_Length", float(dims[0])),
        ("hasBoxyShape_Width", float(dims[1])),
        ("hasBoxyShape_Height", float(dims[2])),
        ("hasBoxyShape_HasTop", has_top),
    ])


def _solid(name: str, classes: tuple[str, ...], props: list, cls: str, ref: str, p: Pose) -> Iterator[Block]:
    yield (name, classes, [("hasSolidObject_PrimaryLocation", f"{name}_pose")] + props)
    yield Geometry(name, cls, ref, p)


STATES = ("init", "goal")


def state_graph(sc: Scenario, state: str) -> Graph:
    """The ``init`` or ``goal`` state as an rdflib Graph (built without the Turtle writer)."""
    return blocks_to_graph(sc.namespace, sc.ontology_iri(state), state_blocks(sc, state))


def state_blocks(sc: Scenario, state: str) -> Iterator[Block]:
    """The individuals of the ``init`` or ``goal`` state, as writer blocks."""
    if state not in STATES:
        raise ValueError(state)
    goal = state == "goal"
    yield from _workstation_blocks(sc)
    yield from _sku_blocks(sc)
    yield from _design_blocks(sc)
    yield from _station_blocks(sc)
    yield from _robot_blocks(sc)
    yield from _table_blocks(sc, goal)
    yield from _parts_blocks(sc, goal)
    yield from _box_blocks(sc, goal)


def _workstation_blocks(sc: Scenario) -> Iterator[Block]:
    ws = "kitting_workstation_1"
    objects = ["work_table_1", "parts_table_1", "empty_kit_tray_supply"]
    objects += [f"finished_kit_receiver_{d + 1}" for d in range(len(sc.spec.designs))]
    objects += [t.name for t in sc.trays]
    props = [
        ("hasKittingWorkstation_AngleUnit", Text("degree")),
        ("hasKittingWorkstation_LengthUnit", Text("meter")),
        ("hasKittingWorkstation_WeightUnit", Text("kilogram")),
        ("hasKittingWorkstation_ChangingStation", "changing_station_1"),
        ("hasKittingWorkstation_Robot", "robot_1"),
    ]
    props += [("hasKittingWorkstation_Object", o) for o in objects]
    props += [("hasKittingWorkstation_Sku", s) for s in sc.skus]
    props += [("hasKittingWorkstation_KitDesign", d.name) for d in sc.spec.designs]
    yield (None, "workstation (its location is given relative to itself)", [])
    yield from _solid(ws, ("KittingWorkstation",), props, "PoseOnlyLocation", ws, pose(0, 0, 0))


def _sku_blocks(sc: Scenario) -> Iterator[Block]:
    yield (None, "stock keeping units and their shapes", [])
    for sku in sc.skus.values():
        props = [
            ("hasStockKeepingUnit_Description", Text(sku.description)),
            ("hasStockKeepingUnit_InternalShape", f"shape_{sku.name[4:]}"),
            ("hasStockKeepingUnit_Weight", float(sku.weight)),
        ]
        if sku.effector:
            props.append(("hasStockKeepingUnit_EndEffector", sku.effector))
        yield (sku.name, ("StockKeepingUnit",), props)
        yield _shape_block(f"shape_{sku.name[4:]}", f"shape of {sku.description[7:]}", sku.dims, sku.has_top)


def _design_blocks(sc: Scenario) -> Iterator[Block]:
    for design, places in zip(sc.spec.designs, sc.prps):
        yield (None, f"kit design {design.name}: part places in the kit tray frame", [])
        yield (design.name, ("KitDesign",), [("hasKitDesign_KitTraySku", "sku_kit_tray")]
               + [("hasKitDesign_PartRefAndPose", prp) for prp, _, _ in places])
        for prp, key, (x, y, z) in places:
            yield (prp, ("PartRefAndPose",), [
                ("hasPartRefAndPose_Sku", f"sku_part_{key}"),
                ("hasPartRefAndPose_Point", f"{prp}_point"),
                ("hasPartRefAndPose_XAxis", f"{prp}_x_axis"),
                ("hasPartRefAndPose_ZAxis", f"{prp}_z_axis"),
            ])
            yield Geometry(prp, None, None, pose(x, y, z))


def _station_blocks(sc: Scenario) -> Iterator[Block]:
    station = "changing_station_1"
    yield (None, "end effector changing station: base, holders, end effectors in their holders", [])
    holders = ["part_gripper_holder", "tray_gripper_holder"]
    p, _ = sc.floor[station]
    yield from _solid(station, ("EndEffectorChangingStation",),
                      [("hasEndEffectorChangingStation_Base", "changing_station_base")]
                      + [("hasEndEffectorChangingStation_EndEffectorHolder", h) for h in holders],
                      "PoseOnlyLocation", "kitting_workstation_1", p)
    yield from _solid("changing_station_base", ("MechanicalComponent",),
                      [("hasNoSkuObject_InternalShape", "shape_changing_station_base")],
                      "PoseOnlyLocation", station, pose(0, 0, 0))
    yield _shape_block("shape_changing_station_base", "base of the changing station", BASE, True)
    for holder, x in zip(holders, (0.15, -0.15)):
        effector = holder[: -len("_holder")]
        yield from _solid(holder, ("EndEffectorHolder",), [
            ("hasNoSkuObject_InternalShape", f"shape_{holder}"),
            ("hasEndEffectorHolder_EndEffector", effector),
        ], "PoseLocationIn", station, pose(x, 0.0, BASE[2] - HOLDER[2]))
        yield _shape_block(f"shape_{holder}", f"{holder.replace('_', ' ')}", HOLDER, False)
        yield from _effector_blocks(sc, effector, holder)


def _effector_blocks(sc: Scenario, name: str, holder: str) -> Iterator[Block]:
    if name == "part_gripper":
        classes, extra = ("GripperEffector",), []
        text, weight = "two-finger gripper for parts", 0.2
    else:
        classes = ("VacuumEffectorSingleCup",)
        extra = [("hasVacuumEffector_CupDiameter", 0.08), ("hasVacuumEffector_Length", 0.09)]
        text, weight = "single cup vacuum effector for trays and kits", 0.4
    yield from _solid(name, classes, [
        ("hasNoSkuObject_InternalShape", f"shape_{name}"),
        ("hasEndEffector_Description", Text(text)),
        ("hasEndEffector_Weight", weight),
        ("hasEndEffector_MaximumLoadWeight", float(sc.weights[name])),
    ] + extra, "PoseLocationIn", holder, pose(0.0, 0.0, HOLDER[2], POINTING_DOWN))
    yield _shape_block(f"shape_{name}", f"{name.replace('_', ' ')} (z axis along the tool)", EFFECTORS[name], True)


def _robot_blocks(sc: Scenario) -> Iterator[Block]:
    yield (None, "robot (holding no end effector); its pose is its tool flange at the home pose, z down", [])
    p, _floor_space = sc.floor["robot_1"]
    p = pose(p[0], p[1], ROBOT_HOME_Z, POINTING_DOWN)
    yield from _solid("robot_1", ("Robot",), [
        ("hasNoSkuObject_InternalShape", "shape_robot_1"),
        ("hasRobot_Description", Text("kitting robot")),
        ("hasRobot_MaximumLoadWeight", float(sc.weights["robot"])),
        ("hasRobot_WorkVolume", "robot_1_work_volume"),
    ], "PoseOnlyLocation", "kitting_workstation_1", p)
    yield _shape_block("shape_robot_1", "robot tool flange (z axis along the tool)", ROBOT_FLANGE, True)
    yield ("robot_1_work_volume", ("BoxVolume",), [
        ("hasBoxVolume_MinimumPoint", "robot_1_work_volume_min"),
        ("hasBoxVolume_MaximumPoint", "robot_1_work_volume_max"),
    ])
    for end, point in zip(("min", "max"), sc.work_volume):
        yield (f"robot_1_work_volume_{end}", ("Point",),
               [("hasPoint_X", point[0]), ("hasPoint_Y", point[1]), ("hasPoint_Z", point[2])])


def _table_blocks(sc: Scenario, goal: bool) -> Iterator[Block]:
    on_table = [] if goal else [k for k in sc.kits if k.on_table]
    yield (None, "work table where kits are built" + (" (empty)" if not on_table else " with empty kit trays"), [])
    p, dims = sc.floor["work_table_1"]
    yield from _solid("work_table_1", ("WorkTable",), [("hasNoSkuObject_InternalShape", "shape_work_table_1")]
                      + [("hasWorkTable_ObjectOnTable", k.tray) for k in on_table],
                      "PoseOnlyLocation", "kitting_workstation_1", p)
    yield _shape_block("shape_work_table_1", "work table", dims, True)
    for kit in on_table:
        yield from _kit_tray(kit, "PoseLocationOn", "work_table_1", kit.tray_pose)


def _parts_blocks(sc: Scenario, goal: bool) -> Iterator[Block]:
    used = {part for kit in sc.kits for _, _, part in kit.slots} if goal else set()
    yield (None, "parts table with the parts trays on it", [])
    p, dims = sc.floor["parts_table_1"]
    yield from _solid("parts_table_1", ("WorkTable",), [("hasNoSkuObject_InternalShape", "shape_parts_table_1")]
                      + [("hasWorkTable_ObjectOnTable", t.name) for t in sc.trays],
                      "PoseOnlyLocation", "kitting_workstation_1", p)
    yield _shape_block("shape_parts_table_1", "parts table", dims, True)
    for tray in sc.trays:
        parts = [part for part in tray.parts if part[0] not in used]
        count = f"{len(parts)} part" + ("" if len(parts) == 1 else "s")
        yield (None, f"parts tray {tray.name} ({count} of type {tray.type_key.upper()})", [])
        yield from _solid(tray.name, ("PartsTray",), [
            ("hasSkuObject_Sku", "sku_parts_tray"),
            ("hasPartsVessel_SerialNumber", Typed(tray.serial, "NMTOKEN")),
            ("hasPartsVessel_PartSku", f"sku_part_{tray.type_key}"),
            ("hasPartsVessel_PartQuantity", Typed(str(len(parts)), "nonNegativeInteger")),
        ] + [("hasPartsVessel_Part", name) for name, _, _ in parts],
            "PoseLocationOn", "parts_table_1", tray.pose)
        sku = f"sku_part_{tray.type_key}"
        for name, serial, (x, y, z) in parts:
            yield from _part(name, sku, serial, tray.name, pose(x, y, z))


def _part(name: str, sku: str, serial: str, ref: str, p: Pose) -> Iterator[Block]:
    yield from _solid(name, ("Part",), [
        ("hasSkuObject_Sku", sku),
        ("hasPart_SerialNumber", Typed(serial, "NMTOKEN")),
    ], "PoseLocationIn", ref, p)


def _box_blocks(sc: Scenario, goal: bool) -> Iterator[Block]:
    ws = "kitting_workstation_1"
    stored = [k for k in sc.kits if not k.on_table]
    yield (None, "large box with empty kit trays" + (" (emptied)" if goal or not stored else ""), [])
    p, _ = sc.floor["empty_kit_tray_supply"]
    yield from _solid("empty_kit_tray_supply", ("LargeBoxWithEmptyKitTrays",),
                      [("hasLargeBoxWithEmptyKitTrays_LargeContainer", "empty_kit_tray_box")]
                      + ([] if goal else [("hasLargeBoxWithEmptyKitTrays_KitTray", k.tray) for k in stored]),
                      "PoseOnlyLocation", ws, p)
    yield from _container("empty_kit_tray_box", "sku_empty_kit_tray_box", "ektb_1", "empty_kit_tray_supply")
    if not goal:
        for kit in stored:
            yield from _kit_tray(kit, "PoseLocationIn", "empty_kit_tray_box", kit.tray_pose)
    prps = {prp: key for places in sc.prps for prp, key, _ in places}
    points = {prp: pt for places in sc.prps for prp, _, pt in places}
    for d, design in enumerate(sc.spec.designs):
        box = f"finished_kit_receiver_{d + 1}"
        container = f"finished_kit_box_{d + 1}"
        kits = [k for k in sc.kits if k.box == d] if goal else []
        yield (None, f"large box for finished kits of {design.name}", [])
        p, _ = sc.floor[box]
        yield from _solid(box, ("LargeBoxWithKits",), [
            ("hasLargeBoxWithKits_LargeContainer", container),
            ("hasLargeBoxWithKits_KitDesign", design.name),
            ("hasLargeBoxWithKits_Capacity", Typed(str(sc.box_capacity), "positiveInteger")),
        ] + [("hasLargeBoxWithKits_Kit", k.name) for k in kits], "PoseOnlyLocation", ws, p)
        yield from _container(container, "sku_finished_kit_box", f"fkb_{d + 1}", box)
        for kit in kits:
            yield (None, f"finished kit {kit.name}", [])
            yield from _solid(kit.name, ("Kit",), [
                ("hasKit_Design", design.name),
                ("hasKit_KitTray", kit.tray),
                ("hasKit_Finished", True),
            ] + [("hasKit_Part", part) for _, _, part in kit.slots]
              + [("hasKit_Slot", slot) for slot, _, _ in kit.slots], "PoseLocationIn", container, kit.pose)
            yield from _kit_tray(kit, "PoseOnlyLocation", kit.name, pose(0, 0, 0))
            for slot, prp, part in kit.slots:
                yield (slot, ("Slot",), [("hasSlot_PartRefAndPose", prp), ("hasSlot_Part", part)])
            for slot, prp, part in kit.slots:
                key = prps[prp]
                yield from _part(part, f"sku_part_{key}", part[len("part_"):], kit.tray, pose(*points[prp]))


def _container(name: str, sku: str, serial: str, box: str) -> Iterator[Block]:
    yield from _solid(name, ("LargeContainer",), [
        ("hasSkuObject_Sku", sku),
        ("hasLargeContainer_SerialNumber", Typed(serial, "NMTOKEN")),
    ], "PoseOnlyLocation", box, pose(0, 0, 0))


def _kit_tray(kit: KitLayout, cls: str, ref: str, p: Pose) -> Iterator[Block]:
    yield from _solid(kit.tray, ("KitTray",), [
        ("hasSkuObject_Sku", "sku_kit_tray"),
        ("hasKitTray_SerialNumber", Typed(kit.tray_serial, "NMTOKEN")),
    ], cls, ref, p)


# ------------------------------------------------------------------------------ public API
