"""Scenario layout: sizes, poses and names of everything a :class:`ScenarioSpec` holds.

Conventions (NIST kitting model): a BoxyShape has its origin in the middle of the bottom,
z up into the box and x along the length (length >= width). Every solid object has a pose
relative to its container; lengths in meters, weights in kilograms. Floor plan: robot, work
table (where kits are built; empty in both states unless the spec starts its kit trays there)
and changing station in one row, the parts
table with the parts trays behind it, the large boxes in front. Parts trays may have a small
seeded yaw; parts lie on the tray floor and stick out of it (Partially-In, seed paper 004).
"""

from __future__ import annotations

import math
import random
from dataclasses import dataclass, field

from kb.core.namespaces import SCENARIO
from kb.scenario.spec import ScenarioSpec

Pose = tuple[float, float, float, float, float, float, float, float, float]
Axes = tuple[float, float, float, float, float, float]
IDENTITY: Axes = (1.0, 0.0, 0.0, 0.0, 0.0, 1.0)
POINTING_DOWN: Axes = (1.0, 0.0, 0.0, 0.0, 0.0, -1.0)  # end effectors: tool z axis down

PARTS_TRAY_H = 0.04  # lower than every part, so parts stick out of their trays
KIT_TRAY_H = 0.04
CELL_GAP = 0.02  # between neighbouring parts
TRAY_MARGIN = 0.02  # between the outer parts and a tray's rim
TABLE_H = 0.75
FLOOR_GAP = 0.5
BASE = (0.6, 0.3, 0.8)  # changing station base
HOLDER = (0.12, 0.12, 0.10)
EFFECTORS = {"part_gripper": (0.08, 0.06, 0.08), "tray_gripper": (0.10, 0.10, 0.09)}
ROBOT_BASE = (0.4, 0.4, 0.6)  # floor space the robot takes (its base is not modelled)
ROBOT_FLANGE = (0.1, 0.1, 0.02)  # the robot's shape: its tool flange (z axis along the tool, down)
ROBOT_HOME_Z = 1.2  # height of the tool flange at the robot's home pose


def pose(x: float, y: float, z: float, axes: Axes = IDENTITY) -> Pose:
    """A pose from a point and (x axis, z axis)."""
    return (float(x), float(y), float(z)) + axes


def yaw_axes(deg: float) -> Axes:
    """Axes of a rotation by ``deg`` degrees about z (unit, orthogonal)."""
    if deg == 0:
        return IDENTITY
    a = math.radians(deg)
    c, s = math.cos(a), math.sin(a)
    n = math.hypot(c, s)
    return (c / n, s / n, 0.0, 0.0, 0.0, 1.0)


@dataclass
class Sku:
    """A stock keeping unit with a box shape."""

    name: str
    description: str
    dims: tuple[float, float, float]
    has_top: bool
    weight: float
    effector: str | None


@dataclass
class PartsTrayLayout:
    """A parts tray on the parts table, its parts and their places in it."""

    name: str
    type_key: str
    serial: str
    pose: Pose
    parts: list[tuple[str, str, tuple[float, float, float]]]  # (part, serial, point in tray)


@dataclass
class KitLayout:
    """A kit to build: its design, kit tray, places in the two large boxes, and slots."""

    name: str
    design: int
    tray: str
    tray_serial: str
    tray_pose: Pose  # in the empty kit tray box (init)
    box: int  # index of its large box with kits
    pose: Pose  # in that box (goal)
    slots: list[tuple[str, str, str]] = field(default_factory=list)  # (slot, prp, part)
    on_table: bool = False  # the tray starts on the work table (``tray_pose`` on it), not in the box


@dataclass
class Scenario:
    """A laid-out scenario: everything the two state files say, with geometry."""

    spec: ScenarioSpec
    skus: dict[str, Sku]
    prps: list[list[tuple[str, str, tuple[float, float, float]]]]  # per design: (prp, type, point)
    trays: list[PartsTrayLayout]
    kits: list[KitLayout]
    floor: dict[str, tuple[Pose, tuple[float, float, float]]]  # object -> (pose, box dims)
    box_capacity: int
    work_volume: tuple[tuple[float, float, float], tuple[float, float, float]]
    weights: dict[str, float]

    @property
    def name(self) -> str:
        """Scenario name (the last segment of its namespace)."""
        return self.spec.name

    @property
    def namespace(self) -> str:
        """Namespace of the scenario's individuals."""
        return f"{SCENARIO}{self.spec.name}#"

    def ontology_iri(self, state: str) -> str:
        """IRI of the ``init`` or ``goal`` file."""
        return f"{SCENARIO}{self.spec.name}/{state}"


# ------------------------------------------------------------------------------ layout


def _grid(n: int) -> tuple[int, int]:
    cols = max(1, math.ceil(math.sqrt(n)))
    return cols, max(1, math.ceil(n / cols))


def _size(cols: int, rows: int, cl: float, cw: float, margin: float) -> tuple[float, float]:
    """Length and width of a box holding ``cols`` x ``rows`` cells of ``cl`` x ``cw``."""
    return round(cols * cl + 2 * margin, 9), round(rows * cw + 2 * margin, 9)


def _cells(cols: int, rows: int, cl: float, cw: float, margin: float) -> tuple[float, float, list]:
    """:func:`_size` and the cell centers, row by row, in the box frame (origin in the middle)."""
    length, width = cols * cl + 2 * margin, rows * cw + 2 * margin
    xs = [round(-length / 2 + margin + cl * (c + 0.5), 9) for c in range(cols)]
    ys = [round(-width / 2 + margin + cw * (r + 0.5), 9) for r in range(rows)]
    return round(length, 9), round(width, 9), [(x, y) for y in ys for x in xs]


def layout(spec: ScenarioSpec) -> Scenario:
    """Place every object of ``spec``: sizes, poses, names."""
    cl = max(t.length for t in spec.part_types) + CELL_GAP
    cw = max(t.width for t in spec.part_types) + CELL_GAP
    skus = _skus(spec, cl, cw)
    prps = _design_places(spec, cl, cw)
    trays, queues = _parts_trays(spec, cl, cw, skus["sku_parts_tray"].dims)
    n_boxes = len(spec.designs)
    per_design = [spec.kits.count(d) for d in range(n_boxes)]
    kt = skus["sku_kit_tray"].dims
    _, _, ekt_cells = _cells(*_grid(len(spec.kits)), kt[0] + 0.05, kt[1] + 0.05, 0.05)
    fk_cols, fk_rows = _grid(max(per_design))
    _, _, fk_cells = _cells(fk_cols, fk_rows, kt[0] + 0.05, kt[1] + 0.05, 0.05)
    kits: list[KitLayout] = []
    used = [0] * n_boxes
    taken = {key: 0 for key in queues}
    table_dims, table_cells = _work_table(spec, kt)
    for k, d in enumerate(spec.kits):
        x, y = ekt_cells[k]
        bx, by = fk_cells[used[d]]
        used[d] += 1
        kit = KitLayout(f"kit_{k + 1}", d, f"kit_tray_{k + 1}", f"kt_{k + 1}", pose(x, y, 0.0), d, pose(bx, by, 0.0))
        if spec.kit_trays_on_table:
            kit.tray_pose, kit.on_table = pose(*table_cells[k], TABLE_H), True
        skip = len(spec.designs[d].name) + len("_prp")
        for prp, key, _ in prps[d]:
            part = queues[key][taken[key]]
            taken[key] += 1
            kit.slots.append((f"{kit.name}_slot{prp[skip:]}", prp, part))
        kits.append(kit)
    floor = _floor(spec, skus, trays, table_dims)
    xs = [p[0] for p, _ in floor.values()]
    ys = [p[1] for p, _ in floor.values()]
    reach = max(max(d[0], d[1]) for _, d in floor.values())
    volume = (
        (round(min(xs) - reach, 6), round(min(ys) - reach, 6), 0.0),
        (round(max(xs) + reach, 6), round(max(ys) + reach, 6), 2.5),
    )
    return Scenario(spec, skus, prps, trays, kits, floor, fk_cols * fk_rows, volume, _weights(spec, skus))


def _weights(spec: ScenarioSpec, skus: dict[str, Sku]) -> dict[str, float]:
    """Maximum loads: the part gripper lifts any part, the tray gripper any finished kit."""
    types = {t.key: t for t in spec.part_types}
    max_part = max(t.weight for t in spec.part_types)
    kit_weight = max(
        skus["sku_kit_tray"].weight + sum(types[k].weight * n for k, n in spec.designs[d].counts) for d in spec.kits
    )
    weights = {
        "part_gripper": math.ceil(max_part * 20) / 10,
        "tray_gripper": math.ceil(kit_weight * 15) / 10,
    }
    weights["robot"] = float(math.ceil(weights["tray_gripper"] + 2.0))
    return weights


def _skus(spec: ScenarioSpec, cl: float, cw: float) -> dict[str, Sku]:
    skus: dict[str, Sku] = {}
    for t in spec.part_types:
        skus[f"sku_part_{t.key}"] = Sku(
            f"sku_part_{t.key}", f"SKU of part {t.key.upper()}", (t.length, t.width, t.height), True, t.weight,
            "part_gripper",
        )
    cols, rows = spec.tray_grid
    length, width = _size(cols, rows, cl, cw, TRAY_MARGIN)
    skus["sku_parts_tray"] = Sku("sku_parts_tray", "SKU of parts trays", (length, width, PARTS_TRAY_H), False,
                                 0.3, "tray_gripper")
    length, width = _size(*_grid(max(d.size for d in spec.designs)), cl, cw, TRAY_MARGIN)
    skus["sku_kit_tray"] = Sku("sku_kit_tray", "SKU of kit trays", (length, width, KIT_TRAY_H), False, 0.25,
                               "tray_gripper")
    kt = skus["sku_kit_tray"].dims
    high = KIT_TRAY_H + max(t.height for t in spec.part_types) + 0.05
    for name, n, h, text in (
        ("sku_empty_kit_tray_box", len(spec.kits), KIT_TRAY_H + 0.1, "large boxes of empty kit trays"),
        ("sku_finished_kit_box", max(spec.kits.count(d) for d in range(len(spec.designs))), high,
         "large boxes of finished kits"),
    ):
        length, width = _size(*_grid(n), kt[0] + 0.05, kt[1] + 0.05, 0.05)
        skus[name] = Sku(name, f"SKU of {text}", (length, width, round(h, 6)), False, 2.0, None)
    return skus


def _design_places(spec: ScenarioSpec, cl: float, cw: float) -> list:
    cols, rows = _grid(max(d.size for d in spec.designs))
    _, _, centers = _cells(cols, rows, cl, cw, TRAY_MARGIN)
    out = []
    for d in spec.designs:
        places = []
        for key, n in d.counts:
            for i in range(1, n + 1):
                x, y = centers[len(places)]
                places.append((f"{d.name}_prp_{key}_{i}", key, (x, y, 0.0)))
        out.append(places)
    return out


def _parts_trays(spec: ScenarioSpec, cl: float, cw: float, tray_dims) -> tuple[list, dict]:
    cols, rows = spec.tray_grid
    _, _, centers = _cells(cols, rows, cl, cw, TRAY_MARGIN)
    cap = cols * rows
    rng = random.Random(spec.seed)
    trays: list[PartsTrayLayout] = []
    queues: dict[str, list[str]] = {}
    for t, need in zip(spec.part_types, spec.needed().values()):
        total = need + spec.spare
        count = math.ceil(total / cap)
        names = []
        for j in range(count):
            name = f"part_{t.key}_tray" if count == 1 else f"part_{t.key}_tray_{j + 1}"
            yaw = round(rng.uniform(-spec.max_yaw_deg, spec.max_yaw_deg), 3) if spec.max_yaw_deg else 0.0
            tray = PartsTrayLayout(name, t.key, f"pt_{t.key}_{j + 1}", pose(0, 0, 0, yaw_axes(yaw)), [])
            for i in range(j * cap + 1, min(total, (j + 1) * cap) + 1):
                x, y = centers[(i - 1) % cap]
                tray.parts.append((f"part_{t.key}_{i}", f"{t.key}_{i}", (x, y, 0.0)))
                names.append(f"part_{t.key}_{i}")
            trays.append(tray)
        queues[t.key] = names[:need]
    return trays, queues


def _turnable_cell(length: float, width: float, room: float) -> tuple[float, float]:
    """A square cell in which a ``length`` x ``width`` tray fits at any yaw, ``room`` around it."""
    side = round(math.hypot(length, width) + 2 * room, 6)
    return side, side


def _work_table(spec: ScenarioSpec, kit_tray: tuple[float, float, float]) -> tuple[tuple, list]:
    """The work table's box dims, and the centres of the kit trays that start on it (in its
    frame; none unless ``spec.kit_trays_on_table``)."""
    kl, kw, _ = kit_tray
    length, width = max(1.0, round(kl + 0.3, 6)), max(0.6, round(kw + 0.3, 6))
    if not spec.kit_trays_on_table:
        return (length, width, TABLE_H), []
    cx, cy = _turnable_cell(kl, kw, spec.room) if spec.room > 0 else (kl + 0.05, kw + 0.05)
    tl, tw, centers = _cells(*_grid(len(spec.kits)), cx, cy, 0.05)
    return (max(length, tl), max(width, tw), TABLE_H), centers


def _floor(spec: ScenarioSpec, skus: dict[str, Sku], trays: list[PartsTrayLayout], table: tuple) -> dict:
    """Objects standing on the floor, each with its pose in the workstation and box dims."""
    pl, pw, _ = skus["sku_parts_tray"].dims
    if spec.room > 0:
        cx, cy = _turnable_cell(pl, pw, spec.room)
    else:
        a = math.radians(spec.max_yaw_deg)
        cx = pl * math.cos(a) + pw * math.sin(a) + 0.05
        cy = pl * math.sin(a) + pw * math.cos(a) + 0.05
    cols, rows = _grid(len(trays))
    length, width, centers = _cells(cols, rows, round(cx, 6), round(cy, 6), 0.05)
    for tray, (x, y) in zip(trays, centers):
        tray.pose = (x, y, TABLE_H) + tray.pose[3:]
    rows_of = [
        [("robot_1", ROBOT_BASE), ("work_table_1", table), ("changing_station_1", BASE)],
        [("parts_table_1", (length, width, TABLE_H))],
        [("empty_kit_tray_supply", skus["sku_empty_kit_tray_box"].dims)]
        + [(f"finished_kit_receiver_{d + 1}", skus["sku_finished_kit_box"].dims) for d in range(len(spec.designs))],
    ]
    widths = [max(d[1] for _, d in row) for row in rows_of]
    row_y = [0.0, widths[0] / 2 + FLOOR_GAP + widths[1] / 2, -(widths[0] / 2 + FLOOR_GAP + widths[2] / 2)]
    floor = {}
    for row, y in zip(rows_of, row_y):
        cursor = 0.0
        for name, dims in row:
            floor[name] = (pose(round(cursor + dims[0] / 2, 6), round(y, 6), 0.0), dims)
            cursor += dims[0] + FLOOR_GAP
    return floor


# ------------------------------------------------------------------------------ blocks
