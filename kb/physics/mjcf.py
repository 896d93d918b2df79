"""The MJCF scene of a cell's ground truth: every solid object as MuJoCo bodies and geoms.

Built from a :class:`kb.sim.world.World` (the simulator's ground truth of a state file, the
same the kinematic cell holds), so both cells start from one state:

* **shapes**: an object's box (its SKU's ``BoxyShape``, or its own) is one ``box`` geom; a
  ``CylindricalShape`` (and a vacuum effector, a cylinder of its cup) a ``cylinder`` geom; an
  open-top container (a tray, a kit tray, a large box, an effector holder: ``HasTop`` false)
  is a floor plate and four walls of :data:`~kb.physics.params.PLATE` thickness, the walls
  inside its box, the floor plate just under its bottom face (the state puts what lies in a
  tray on the tray's bottom face: there it rests);
* **what moves**: parts, parts trays and kit trays are free bodies (a ``freejoint``); tables,
  stations, boxes, holders and every other solid are fixed (geoms of a body with no joint);
  the robot's flange and every end effector are mocap bodies, moved by the cell (an effector
  mounted on the flange is moved with it, one stowed stays where it is);
* **masses**: a free object's mass is its SKU's ``hasStockKeepingUnit_Weight`` (spread over its
  geoms by volume), else its geoms' volume at :data:`~kb.physics.params.DENSITY`;
* **contacts**: friction and softness of :mod:`kb.physics.params` on every geom; collision
  groups keep fixed objects from colliding with each other (a table and the box on it may
  touch by rounding), a free container's floor plate from the table under it (its walls stand
  on it), and the robot's geoms (flange, effectors) touching free bodies only;
* **grips**: one inactive ``weld`` per free body, from the flange to it, which the cell
  activates when a grasp holds it (:mod:`kb.physics.robot`).

Objects with no body: those not placed, stand-ins (a kit is its kit tray's body, a large box
with kits its container's, a changing station its base's), and a robot's zero-size point.
``kitkb sim export-mjcf INIT -o scene.xml`` writes the scene; MuJoCo's viewer opens it
(``python -m mujoco.viewer --mjcf scene.xml``).
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from xml.sax.saxutils import quoteattr

import mujoco
import numpy as np
from rdflib import URIRef

from kb.core.namespaces import KTW, local_name
from kb.physics import params as P
from kb.sim.world import SKU, SKU_WEIGHT, World
from kb.spatial.scene import Scene

#: collision bits (MuJoCo contype / conaffinity): two geoms collide when one's contype meets the
#: other's conaffinity. Fixed objects meet free ones only; free meet fixed, free and the robot; a
#: free container's floor plate meets free bodies only; the robot meets nothing itself (free
#: bodies meet it). A held body drops the robot bit, so the gripper does not push what it holds.
STATIC, FREE, FLOOR, ROBOT = (1, 2), (2, 7), (8, 2), (4, 0)
#: The robot's geoms sense, they do not push: MuJoCo's collision detection makes their contacts,
#: and their contact parameters win (priority) with a vanishing impedance and stiffness and no
#: friction, so a contact of theirs carries micronewtons. kitkb's effector shapes are bounding
#: boxes (a vacuum cup is a cylinder as wide as its cup, a gripper a box round its fingers),
#: which in the shipped scenarios reach over what lies next to what they grasp (a tray
#: gripper's cup over the kit's parts); as pushers they would wreck kits a real tool would not
#: touch. What the robot holds is a free body: it pushes.
SENSING = (' priority="1" solimp="0.0001 0.0001 0.001" solref="-0.001 -0.001" friction="0 0 0"'
           ' condim="1"')
#: the classes of the free bodies
FREE_CLASSES = ("Part", "PartsTray", "KitTray")
#: the flange's mocap body
FLANGE = "robot_flange"


@dataclass
class Body:
    """One object's MuJoCo body: its name, ``kind`` (``free``, ``static`` or ``mocap``) and
    geoms (names)."""

    index: int
    name: str
    kind: str
    geoms: list[str] = field(default_factory=list)


@dataclass
class Mjcf:
    """A scene as MJCF text, with the body of each object that has one (by world index)."""

    xml: str
    bodies: dict[int, Body]


def cylinders(scene: Scene | None) -> set[str]:
    """The objects of ``scene`` whose shape is a ``CylindricalShape`` (their SKU's, or their own),
    read from the state file the scene was read from; empty without one (all boxes then)."""
    source = getattr(scene, "source", None) if scene is not None else None
    if source is None:
        return set()
    view = source.view()
    out: set[str] = set()
    for name in scene.names:  # type: ignore[union-attr]
        node = _node(name)
        sku = view.value(node, KTW.hasSkuObject_Sku)
        shape = view.value(sku, KTW.hasStockKeepingUnit_InternalShape) if sku is not None else None
        shape = shape if shape is not None else view.value(node, KTW.hasNoSkuObject_InternalShape)
        if shape is not None and view.value(shape, KTW.hasCylindricalShape_Diameter) is not None:
            out.add(name)
    return out


def _node(name: str) -> URIRef:
    return URIRef(name)


def kind_of(world: World, i: int) -> str | None:
    """``free``, ``static``, ``mocap`` or None (no body) for object ``i`` of ``world`` (a robot
    and an end effector: mocap; a robot's point has no geom)."""
    if not world.placed(i) or world.stand_in(i):
        return None
    if world.is_a(i, "EndEffector") or world.is_a(i, "Robot"):
        return "mocap"
    if any(world.is_a(i, c) for c in FREE_CLASSES):
        return "free"
    return "static"


def build(world: World, cylinder_names: set[str] | frozenset[str] = frozenset(), title: str = "kitkb") -> Mjcf:
    """The MJCF scene of ``world`` (``cylinder_names``: objects drawn as cylinders)."""
    bodies: dict[int, Body] = {}
    parts: list[str] = []
    used: set[str] = {FLANGE}
    robots = [i for i in range(len(world)) if world.is_a(i, "Robot") and world.placed(i)]
    robot = robots[0] if robots else -1  # the robot kb.sim.robot.Robot drives: the first placed
    for i in range(len(world)):
        kind = kind_of(world, i)
        if kind is None:
            continue
        if i == robot:
            body = Body(i, FLANGE, "mocap")
        else:
            body = Body(i, _unique(local_name(world.names[i]), used), kind)
        cyl = world.names[i] in cylinder_names or world.is_a(i, "VacuumEffector")
        parts.append(_body(world, i, body, cyl))
        bodies[i] = body
    welds = [f'    <weld name="grip__{b.name}" body1="{FLANGE}" body2="{b.name}" active="false" '
             f'solref="{P.GRIPPER.timeconst:g} {P.GRIPPER.damping:g}"/>' for b in bodies.values() if b.kind == "free"]
    if not any(b.name == FLANGE for b in bodies.values()):
        parts.append(f'    <body name="{FLANGE}" mocap="true" pos="0 0 0"/>')
    fr = " ".join(f"{v:g}" for v in P.FRICTION)
    xml = "\n".join([
        f"<mujoco model={quoteattr(title)}>",
        '  <compiler angle="radian"/>',
        f'  <option timestep="{P.TIMESTEP:g}" gravity="0 0 -9.81" integrator="implicitfast" cone="pyramidal">',
        '    <flag sleep="enable"/>',
        "  </option>",
        "  <default>",
        f'    <geom friction="{fr}" solref="{P.CONTACT_SOLREF[0]:g} {P.CONTACT_SOLREF[1]:g}" condim="4"/>',
        "  </default>",
        "  <worldbody>",
        f'    <geom name="floor" type="plane" size="0 0 1" contype="{STATIC[0]}" conaffinity="{STATIC[1]}"/>',
        *parts,
        "  </worldbody>",
        *(["  <equality>", *welds, "  </equality>"] if welds else []),
        "</mujoco>", ""])
    return Mjcf(xml, bodies)


def _unique(name: str, used: set[str]) -> str:
    base = re.sub(r"[^A-Za-z0-9_.-]", "_", name) or "object"
    out, n = base, 1
    while out in used:
        n += 1
        out = f"{base}_{n}"
    used.add(out)
    return out


def _body(world: World, i: int, body: Body, cylinder: bool) -> str:
    pose = world.poses[i]
    quat = quaternion(pose[:3, :3])
    attrs = f'name="{body.name}" pos="{_v(pose[:3, 3])}" quat="{_v(quat)}"'
    lo, hi = world.local_lo[i], world.local_hi[i]
    groups = {"free": FREE, "static": STATIC, "mocap": ROBOT}[body.kind]
    geoms = _geoms(body, lo, hi, bool(world.open_top[i]), cylinder, groups)
    mass = _mass(world, i) if body.kind == "free" else None
    mocap = ' mocap="true"' if body.kind == "mocap" else ""
    lines = [f"    <body {attrs}{mocap}>"]
    if body.kind == "free":
        lines.append("      <freejoint/>")
    volumes = [g[1] for g in geoms]
    for (text, volume) in geoms:
        weight = f' mass="{mass * volume / sum(volumes):.6g}"' if mass is not None and sum(volumes) > 0 else \
            (f' density="{P.DENSITY:g}"' if body.kind == "free" else "")
        lines.append(f"      {text[:-2]}{weight}/>")
    lines.append("    </body>")
    return "\n".join(lines)


def _geoms(body: Body, lo: np.ndarray, hi: np.ndarray, open_top: bool, cylinder: bool,
           groups: tuple[int, int]) -> list[tuple[str, float]]:
    """(geom element, volume) of one object: a box or cylinder, or a container's plates."""
    size = (hi - lo) / 2
    centre = (hi + lo) / 2
    if not np.all(size > 0):
        return []  # a point (NIST's robot): no geom
    out: list[tuple[str, float]] = []

    def geom(kind: str, c: np.ndarray, s: np.ndarray | tuple[float, ...], g: tuple[int, int], volume: float) -> None:
        name = f"{body.name}__{len(out)}"
        body.geoms.append(name)
        sensing = SENSING if g == ROBOT else ""
        out.append((f'<geom name="{name}" type="{kind}" pos="{_v(c)}" size="{_v(s)}" '
                    f'contype="{g[0]}" conaffinity="{g[1]}"{sensing}/>', volume))
    if not open_top:
        if cylinder:
            r = float(min(size[0], size[1]))
            geom("cylinder", centre, (r, size[2]), groups, np.pi * r * r * 2 * size[2])
        else:
            geom("box", centre, size, groups, float(np.prod(2 * size)))
        return out
    t = P.PLATE / 2
    w = float(min(t, size[0] / 4, size[1] / 4))  # half thickness of a wall
    floor_groups = FLOOR if groups == FREE else groups
    geom("box", np.array([centre[0], centre[1], lo[2] - t]), (size[0], size[1], t), floor_groups,
         float(4 * size[0] * size[1] * 2 * t))
    for axis in (0, 1):
        for sign in (-1, 1):
            c = centre.copy()
            c[axis] = (hi if sign > 0 else lo)[axis] - sign * w
            s = size.copy()
            s[axis] = w
            if axis == 1:
                s[0] = size[0] - 2 * w  # the x walls run the whole length; the y walls between them
            geom("box", c, s, groups, float(np.prod(2 * s)))
    return out


def _mass(world: World, i: int) -> float | None:
    """The SKU weight (kg) of ``i`` itself (not what rests in it), None when none is given."""
    skus = world.objects(SKU, world.names[i])
    value = world.values.get(SKU_WEIGHT, {}).get(skus[0]) if skus else None
    try:  # a number as the state file writes it (xsd:decimal reads as a Decimal)
        w = float(value) if value is not None and not isinstance(value, bool) else None
    except (TypeError, ValueError):
        return None
    return w if w is not None and np.isfinite(w) and w > 0 else None


def quaternion(rotation: np.ndarray) -> np.ndarray:
    """The unit quaternion (w, x, y, z) of a 3x3 rotation matrix."""
    q = np.zeros(4)
    mujoco.mju_mat2Quat(q, np.ascontiguousarray(rotation, float).reshape(9))
    return q


def _v(values: np.ndarray | tuple[float, ...]) -> str:
    return " ".join(f"{float(v):.9g}" for v in values)
