"""ARIAC's workcell geometry: where a trial's names (bins and slots, tray table slots, AGVs,
quadrants) are in the world, and the sizes kitkb gives its objects.

Poses are ARIAC's world frame (metres, radians): the bins' and tray tables' frames from ARIAC's
``object_poses.yaml`` (the same in 2023 and 2024), the bin slots' and kit tray quadrants'
offsets from its environment start-up (``spawn_bin_parts``, ``spawn_parts_on_agvs``), the tray
table slots from ``spawn_kit_trays`` (x offsets -0.43, 0, 0.43 on each table) and the AGVs'
trays from ARIAC's robot description (track at x -2.27 and y 4.8, 1.2, -1.2, -4.8, turned a
quarter turn; tray 0.2 m along the track's -y and 0.75 m up). ARIAC publishes no boxes for its
meshes: the part and tray sizes below are kitkb's (the part heights are ARIAC's
``part_heights``), chosen so that a part fits its bin slot and its quadrant at any rotation.
"""

from __future__ import annotations

import math

#: bin frames: (x, y, z) and yaw (object_poses.yaml): the bin's floor is at z
BINS: dict[int, tuple[float, float, float, float]] = {
    1: (-1.9, 3.375, 0.72, math.pi), 2: (-1.9, 2.625, 0.72, math.pi),
    3: (-2.65, 2.625, 0.72, math.pi), 4: (-2.65, 3.375, 0.72, math.pi),
    5: (-1.9, -3.375, 0.72, math.pi), 6: (-1.9, -2.625, 0.72, math.pi),
    7: (-2.65, -2.625, 0.72, math.pi), 8: (-2.65, -3.375, 0.72, math.pi),
}
BIN_SIZE = 0.6  # a bin's square footprint (its nine slots 0.18 m apart)
#: a bin slot's offset in its bin's frame (environment start-up)
BIN_SLOTS: dict[int, tuple[float, float]] = {
    1: (0.18, 0.18), 2: (0.18, 0.0), 3: (0.18, -0.18),
    4: (0.0, 0.18), 5: (0.0, 0.0), 6: (0.0, -0.18),
    7: (-0.18, 0.18), 8: (-0.18, 0.0), 9: (-0.18, -0.18),
}
SLOT_CELL = (0.17, 0.17, 0.02)  # kitkb's parts tray standing for one bin slot (lower than every part)

#: kit tray stations' tables (kts1, kts2): (x, y, z) of the table top and yaw
TRAY_TABLES: dict[int, tuple[float, float, float, float]] = {
    1: (-1.3, -5.84, 0.725, math.pi), 2: (-1.3, 5.84, 0.725, 0.0),
}
TRAY_TABLE_SIZE = (1.4, 0.6, 0.06)  # the table top kitkb models as the box the trays lie in
#: tray table slot -> (table, x offset along the table)
TRAY_SLOTS: dict[int, tuple[int, float]] = {1: (1, -0.43), 2: (1, 0.0), 3: (1, 0.43),
                                            4: (2, -0.43), 5: (2, 0.0), 6: (2, 0.43)}
#: tool changers of kts1 (parts and trays), in its table's frame: kitkb's changing station
TOOL_CHANGERS = {"part_gripper": (-0.2, -0.46), "tray_gripper": (0.2, -0.46)}

#: AGV trays at their kitting stations: (x, y, z) and yaw
AGV_Y = {1: 4.8, 2: 1.2, 3: -1.2, 4: -4.8}
AGV_TRAY_X, AGV_TRAY_Z, AGV_YAW = -2.27 + 0.2, 0.75 + 0.01, math.pi / 2
AGV_DECK = (0.5, 0.7, AGV_TRAY_Z)  # kitkb's work table standing for an AGV's tray (x, y in its frame)
#: where kitkb puts the place a finished kit goes (an order's shipment on its AGV): beside the
#: AGV's kitting station, away from the robot, one per order on that AGV
SHIPMENT_X0, SHIPMENT_DX = -3.15, -0.85

#: a kit tray's quadrants: offsets of a part's place in the tray's frame (spawn_parts_on_agvs)
QUADRANTS: dict[int, tuple[float, float]] = {1: (-0.0925, 0.1275), 2: (0.0925, 0.1275),
                                             3: (-0.0925, -0.1275), 4: (0.0925, -0.1275)}
KIT_TRAY = (0.38, 0.52, 0.02)  # x, y (ARIAC's tray frame: quadrants 1-2 at +y), height

#: part sizes (x, y, height) in metres and weights in kg; heights are ARIAC's part_heights
PARTS: dict[str, tuple[float, float, float, float]] = {
    "battery": (0.13, 0.06, 0.04, 0.15),
    "pump": (0.10, 0.10, 0.12, 0.30),
    "sensor": (0.11, 0.08, 0.07, 0.20),
    "regulator": (0.11, 0.08, 0.07, 0.20),
}

ROBOT_HOME = (-1.3, 0.0, 1.4)  # the floor robot's tool flange at home (on its rail, over the bins' aisle)


def quadrant_of(x: float, y: float) -> int:
    """The quadrant of a point in a kit tray's frame (1: -x +y, 2: +x +y, 3: -x -y, 4: +x -y)."""
    return (1 if x < 0 else 2) if y >= 0 else (3 if x < 0 else 4)
