"""Play a CRCL program on a simulated cell of a state, and score where the objects ended up.

The first paper (§VI) plans the kittingViewer's metrics "related to the positions of objects"
((1) the objects that should have been moved, (2) moved, (3) moved to the correct place, (4)
moved to the wrong place) and "related to constraint violations"; kitkb's simulator owns
executing a program, so they are decided here (:mod:`kb.metrics` sits below :mod:`kb.sim`).

:func:`play` executes a program (a :class:`kb.crcl.Program`, commands, or :mod:`kb.metrics`
steps) command by command on a :class:`~kb.sim.SimulatedCell` of the initial state, with no
faults: every command the cell executes (``executed``: only those a static evaluation did not
refuse), ``kitkb-action`` messages beginning plan actions as on a cell server. Lengths and
angles are in the units of the program's form (its ``units``: the paper's millimetre and
degree for text and 2014 XML, CRCL 1.x's metre and radian; ``length_unit`` overrides the
length) until the program sets others, and ``InitCanon`` sets them back (CRCL: "units ...
back to their defaults"), as :mod:`kb.metrics` reads them. The result (:class:`Playback`)
holds each command's status, the cell's constraint violations (:class:`~kb.sim.Violation`)
and, with a goal state, the object metrics (:class:`ObjectMetrics`).

Object metrics (:func:`object_metrics`), decided by the ontology's predicates on three scenes
— the initial state, the goal state's own geometry, the cell's ground truth at the end:

* the *objects*: the objects of the task placed in the initial or final scene — SKU objects
  (parts, trays, boxes), not the cell's equipment (the robot, effectors, holders, tables: a
  plan may well end with an effector on the robot); an object that lends its box to a
  stand-in (a kit's tray, a large box's container) counts as that stand-in (the kit), which
  is where its lender is when it has no pose of its own;
* an object's *goal facts*: the atoms of the domain's two-argument spatial predicates (a
  definition with a relation atom: part-location-kit, kit-location-lbwk,
  endeffector-location-endeffectorholder ...) that hold in the goal state with the object as
  their first argument. Parts of one SKU are interchangeable, as kb.planning reads a goal:
  their goal facts are *places* of the SKU (part-location-kit(·, kit_1) twice ...), filled by
  whichever parts of the SKU are there (a matching that prefers the part the goal file names);
* **OSM** should have moved: objects with a goal fact that does not hold initially, and for
  each SKU, its places no part fills initially (counted as the parts that must come);
* **OM** moved: objects some point of whose box is more than the tolerance from where it was
  (an effector mounted and put back where it was has not moved);
* **OMR** moved to the right place: moved, with goal facts, all holding at the end (a part: it
  fills a place of its SKU at the end);
* **OMW** moved to a wrong place: moved and not to the right place (a goal fact fails at the
  end, or it has none: nothing asked it to move). OM = OMR + OMW.

Constraint metrics: the cell's violations by kind — **OVW** overweight grasps, **WVE** moves out
of the work volume, **WEE** wrong-effector grasps, **CTE** contact errors (:mod:`kb.sim.robot`
says what the robot does in each case). A kit the goal names that the program never created
(no ``create-kit`` action message) is created where its tray is before the end is judged: a
kit is its tray with what is in it.
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass, fields
from pathlib import Path
from typing import Any, Iterable, Sequence

import numpy as np

from kb import crcl
from kb.core.errors import InputError
from kb.core.namespaces import KTW, local_name
from kb.crcl.cell import Status
from kb.crcl.wire import parse_action
from kb.metrics.score import CONSTRAINT_METRICS, CONSTRAINT_OF_KIND
from kb.model.definitions import Definitions, Relation, load_definitions
from kb.sim.cell import SimulatedCell, Violation
from kb.spatial.predicates import Evaluator
from kb.spatial.rcc8 import DEFAULT_TOLERANCE
from kb.spatial.scene import STAND_INS, Scene

__all__ = ["ObjectMetrics", "Playback", "commands_of", "object_metrics", "play"]

_SKU = str(KTW.hasSkuObject_Sku)
_PART = str(KTW.Part)
_SOLID = str(KTW.SolidObject)
_ROBOT = str(KTW.Robot)
_MOVES = ("MoveTo", "MoveStraightTo", "MoveThroughTo")


# ---------------------------------------------------------------------------------------------
# Playing
# ---------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class ObjectMetrics:
    """Where the objects ended up: the objects (IRIs) that ``should_move`` (None without a
    goal), ``moved``, moved to the ``right`` place and to a ``wrong`` one (None without a
    goal), and each judged object's ``goal`` facts, (predicate, other object)."""

    should_move: tuple[str, ...] | None
    moved: tuple[str, ...]
    right: tuple[str, ...] | None
    wrong: tuple[str, ...] | None
    goal: dict[str, tuple[tuple[str, str], ...]]

    def counts(self) -> dict[str, int | None]:
        """OSM, OM, OMR, OMW (None where there is no goal)."""
        return {"OSM": None if self.should_move is None else len(self.should_move), "OM": len(self.moved),
                "OMR": None if self.right is None else len(self.right),
                "OMW": None if self.wrong is None else len(self.wrong)}

    def as_dict(self) -> dict[str, Any]:
        """JSON data (objects by local name)."""
        def names(xs: Iterable[str] | None) -> list[str] | None:
            return None if xs is None else [local_name(x) for x in xs]
        return {"should_move": names(self.should_move), "moved": names(self.moved), "right": names(self.right),
                "wrong": names(self.wrong),
                "goal": {local_name(k): [[p, local_name(o)] for p, o in v] for k, v in sorted(self.goal.items())}}


@dataclass
class Playback:
    """A program played on a cell: each command's ``statuses`` (None: not played, refused by
    the static evaluation), the cell's ``violations``, the ``objects`` metrics, the
    ``initial`` and ``final`` scenes (ground truth)."""

    statuses: list[Status | None]
    violations: list[Violation]
    objects: ObjectMetrics
    initial: Scene
    final: Scene

    def totals(self) -> dict[str, int | None]:
        """The object and constraint metrics (:data:`~kb.metrics.score.OBJECT_METRICS`,
        :data:`~kb.metrics.score.CONSTRAINT_METRICS`; object metrics None without a goal)."""
        kinds = Counter(CONSTRAINT_OF_KIND[v.kind] for v in self.violations)
        return {**self.objects.counts(), **{m: kinds.get(m, 0) for m in CONSTRAINT_METRICS}}

    def rows(self) -> list[dict[str, Any]]:
        """Per command: the constraint metrics after it (cumulative), its violations and, when
        the cell refused it, why."""
        by_command: dict[int, list[Violation]] = {}
        for v in self.violations:
            by_command.setdefault(v.command, []).append(v)
        running = dict.fromkeys(CONSTRAINT_METRICS, 0)
        out = []
        for i, status in enumerate(self.statuses):
            here = by_command.get(i, [])
            for v in here:
                running[CONSTRAINT_OF_KIND[v.kind]] += 1
            notes = [f"{v.kind}: {v.detail}" for v in here]
            if status is not None and not status.done:
                notes.append(f"cell: {status.message}")
            out.append({"index": i, "played": status is not None, **running, "notes": notes})
        return out

    def as_dict(self) -> dict[str, Any]:
        """JSON data: the totals, the object lists, the violations."""
        return {"metrics": self.totals(), "objects": self.objects.as_dict(),
                "violations": [v.as_dict() for v in self.violations]}


def play(program: Iterable[Any], init: str | Path | Scene, goal: str | Path | None = None, *,
         executed: Sequence[bool] | None = None, length_unit: str | None = None, match_names: bool = False,
         domain_files: Sequence[str | Path] | None = None, tolerance: float = DEFAULT_TOLERANCE) -> Playback:
    """Play ``program`` (commands or :mod:`kb.metrics` steps) on a simulated cell of ``init``
    (a state file, or its scene) and judge it against ``goal`` (a state file; None: the object
    metrics that need one are None). ``executed``: per command, whether to play it (default
    all). A state file that cannot be read is an :class:`~kb.core.errors.InputError`."""
    units = getattr(program, "units", None) or crcl.PAPER_UNITS
    commands = commands_of(program)
    if executed is not None and len(executed) != len(commands):
        raise ValueError(f"executed has {len(executed)} entries for {len(commands)} commands")
    declared = [goal] if goal is not None else []
    initial = init if isinstance(init, Scene) else Scene.from_files([init], declared, match_names=match_names)
    try:
        cell = SimulatedCell(initial)
    except ValueError as exc:  # no robot to play the program
        raise InputError(f"cannot play a program on it: {exc}", initial.path) from None
    robot = cell.robot
    length_unit = length_unit or units[0]
    if length_unit not in crcl.LENGTH_UNITS:
        raise ValueError(f"length_unit must be one of {', '.join(crcl.LENGTH_UNITS)}, not {length_unit!r}")
    robot.length_unit, robot.angle_unit = length_unit, units[1]
    robot.init_canon()
    statuses: list[Status | None] = []
    for i, command in enumerate(commands):
        if executed is not None and not executed[i]:
            statuses.append(None)
            cell.commands += 1  # keeps violations' command index the program's
            continue
        statuses.append(_execute(cell, command))
    goal_scene = None
    if goal is not None:
        goal_scene = Scene.from_files([goal], [init] if not isinstance(init, Scene) and init else [],
                                      match_names=match_names)
        _create_goal_kits(cell)
    final = cell.scene()
    defs = load_definitions(domain_files)
    objects = object_metrics(initial, final, goal_scene, defs, tolerance)
    return Playback(statuses, list(cell.violations), objects, initial, final)


def _execute(cell: SimulatedCell, command: crcl.Command) -> Status:
    """One command on the cell; a ``kitkb-action`` message begins a plan action (as
    :class:`~kb.sim.CellServer` does)."""
    try:
        action = parse_action(command.message) if isinstance(command, crcl.Message) else None
    except ValueError as exc:
        cell.commands += 1
        return Status.error(str(exc))
    if action is None:
        return cell.execute(command)
    index, name, args = action
    cell.commands += 1
    cell.begin_action(index, name, tuple(_resolve(cell, a) for a in args))
    return Status.ok(f"action {index} {name} begun")


def _resolve(cell: SimulatedCell, name: str) -> str:
    """The IRI of an object named by IRI or by a local name only it has; ``name`` otherwise."""
    w = cell.world
    if name in w.index:
        return name
    found = [n for n in w.names if local_name(n) == name]
    return found[0] if len(found) == 1 else name


def _create_goal_kits(cell: SimulatedCell) -> None:
    """Create, where their trays are, the goal's kits (declared in the initial scene) the
    program did not create."""
    w = cell.world
    for kit, tray in sorted(w.facts.get(str(KTW.hasKit_KitTray), ())):
        k = w.index.get(kit)
        if (k is None or not w.placed(k)) and tray in w.index:
            cell.create_kit(kit, tray)


def commands_of(program: Iterable[Any]) -> list[crcl.Command]:
    """The :mod:`kb.crcl` commands of a program: a :class:`~kb.crcl.Program`, commands, or
    :mod:`kb.metrics` steps ``(kind, line, value)``."""
    out = []
    for item in program:
        out.append(item if isinstance(item, crcl.Command) else _command_of_step(item))
    return out


def _command_of_step(step: tuple[str, int | None, Any]) -> crcl.Command:
    kind, line, value = step
    if kind == "Unreadable":
        text, reason = value if isinstance(value, tuple) else (str(value), "")
        return crcl.Unreadable(text, reason, line=line)
    cls = crcl.COMMANDS.get(kind) or crcl.CRCL1_COMMANDS[kind]
    if kind == "SetEndEffector":
        return crcl.SetEndEffector(value, line=line)
    if kind in crcl.CRCL1_COMMANDS:  # kept whole by kb.metrics.steps (its value is the command)
        return value
    if kind in _MOVES:
        poses = tuple(crcl.Pose(p[0:3], p[6:9], p[3:6]) for p in value)
        return crcl.MoveThroughTo(poses, line=line) if kind == "MoveThroughTo" else cls(poses[0], line=line)
    own = [f for f in fields(cls) if f.name != "line"]
    return cls(value, line=line) if own else cls(line=line)


# ---------------------------------------------------------------------------------------------
# Object metrics
# ---------------------------------------------------------------------------------------------

def spatial_predicates(defs: Definitions) -> list[str]:
    """The domain's two-argument predicates whose definition holds a relation atom (where
    an object is), by name."""
    return sorted(n for n, p in defs.predicates.items() if p.arity == 2 and _spatial(p.formula))


def _spatial(f: Any) -> bool:
    if isinstance(f, Relation):
        return True
    for name in ("operands",):
        if hasattr(f, name):
            return any(_spatial(x) for x in getattr(f, name))
    return any(_spatial(getattr(f, name)) for name in ("operand", "body", "condition") if hasattr(f, name))


def object_metrics(initial: Scene, final: Scene, goal: Scene | None, defs: Definitions,
                   tolerance: float = DEFAULT_TOLERANCE) -> ObjectMetrics:
    """The object metrics of a program that took ``initial`` to ``final`` (the same objects,
    the same names), against ``goal`` (module docstring)."""
    objects = _objects(initial, final)
    moved = tuple(x for x in objects if _moved(initial, final, x, tolerance))
    if goal is None:
        return ObjectMetrics(None, moved, None, None, {})
    facts = _goal_facts(goal, initial, defs, tolerance, set(objects))
    skus = {x: _sku(initial, x) or _sku(final, x) for x in objects}
    parts = {x for x in objects if _PART in _classes(initial, final, x) and skus[x] is not None}
    places: dict[str, list[tuple[str, str, str]]] = {}  # SKU -> (predicate, other, part the goal names)
    fixed: dict[str, tuple[tuple[str, str], ...]] = {}
    for x in objects:
        if x in parts:
            for p, o in facts.get(x, ()):
                places.setdefault(skus[x], []).append((p, o, x))  # type: ignore[index]
        elif facts.get(x):
            fixed[x] = facts[x]
    before = _Judge(initial, defs, tolerance)
    after = _Judge(final, defs, tolerance)
    should = {x for x, fs in fixed.items() if not all(before.holds(p, x, o) for p, o in fs)}
    filled_after: dict[str, tuple[str, str]] = {}
    for sku, roles in places.items():
        of_sku = sorted(x for x in parts if skus[x] == sku)
        unfilled, _ = _match(before, roles, of_sku)
        should.update(unfilled)
        _, filled = _match(after, roles, of_sku)
        filled_after.update(filled)
    right = tuple(x for x in moved if (x in fixed and all(after.holds(p, x, o) for p, o in fixed[x]))
                  or x in filled_after)
    wrong = tuple(x for x in moved if x not in right)
    goal_of = {**fixed, **{x: (pl,) for x, pl in filled_after.items()}}
    return ObjectMetrics(tuple(sorted(should)), moved, right, wrong, goal_of)


def _match(judge: "_Judge", roles: list[tuple[str, str, str]], parts: list[str]) -> tuple[set[str], dict[str, tuple[str, str]]]:
    """Parts of one SKU matched to its places (predicate, other): a place takes a part for
    which its atom holds, the part the goal file names there first. Returns (for each place no
    part fills: the part the goal names if it is free, else another free part; part -> the
    place it fills)."""
    filled: dict[str, tuple[str, str]] = {}
    empty: list[tuple[str, str, str]] = []
    for p, o, named in sorted(roles, key=lambda r: (r[0], r[1], r[2])):
        candidates = [x for x in [named] + parts if x not in filled and judge.holds(p, x, o)]
        if candidates:
            filled[candidates[0]] = (p, o)
        else:
            empty.append((p, o, named))
    free = [x for x in parts if x not in filled]
    unfilled: set[str] = set()
    for _p, _o, named in empty:
        pick = named if named in free else next((x for x in free if x not in unfilled), None)
        if pick is not None and pick in free:
            free.remove(pick)
            unfilled.add(pick)
    return unfilled, filled


class _Judge:
    """Atoms of one scene, each evaluated once."""

    def __init__(self, scene: Scene, defs: Definitions, tolerance: float) -> None:
        self.scene, self.ev, self.known = scene, Evaluator(defs, scene, tolerance), {}

    def holds(self, predicate: str, a: str, b: str) -> bool:
        key = (predicate, a, b)
        if key not in self.known:
            index = self.scene.index
            self.known[key] = (a in index and b in index and bool(self.scene.placed[index[a]])
                               and self.ev.holds(predicate, a, b))
        return self.known[key]


def _goal_facts(goal: Scene, initial: Scene, defs: Definitions, tolerance: float,
                objects: set[str]) -> dict[str, tuple[tuple[str, str], ...]]:
    """Object -> its goal facts (predicate, other object), in the initial scene's names (a goal
    individual named otherwise, as NIST's, by its local name)."""
    ev = Evaluator(defs, goal, tolerance)
    local = {}
    for n in initial.names:
        local.setdefault(local_name(n), n)

    def name(x: str) -> str:
        return x if x in initial.index else local.get(local_name(x), x)
    out: dict[str, list[tuple[str, str]]] = {}
    for p in spatial_predicates(defs):
        refs, tgts, truth = ev.table(p)
        for i, j in zip(*np.nonzero(truth)):
            x = name(refs[i])
            if x in objects:
                out.setdefault(x, []).append((p, name(tgts[j])))
    return {x: tuple(sorted(v)) for x, v in out.items()}


def _objects(initial: Scene, final: Scene) -> list[str]:
    """The objects of the task, placed in either scene: SKU objects (parts, trays, boxes) and
    the stand-ins that lend an SKU object's box (a kit), which count for their lender; not the
    cell's equipment (robots, effectors, holders, tables)."""
    lenders: dict[str, str] = {}
    for scene in (initial, final):
        for prop in STAND_INS.values():
            lenders.update({o: s for s, o in scene.facts.get(str(prop), ())})
    out = set()
    for scene in (initial, final):
        for i, n in enumerate(scene.names):
            if not scene.placed[i] or _SOLID not in scene.classes[i] or _ROBOT in scene.classes[i]:
                continue
            if _sku(initial, n) is None and _sku(final, n) is None:
                continue
            out.add(lenders.get(n, n))  # a kit tray is its kit
    return sorted(out)


def _classes(initial: Scene, final: Scene, x: str) -> frozenset[str]:
    for scene in (initial, final):
        if x in scene.index:
            return scene.classes[scene.index[x]]
    return frozenset()


def _sku(scene: Scene, x: str) -> str | None:
    skus = sorted(scene.related(_SKU).get(x, ()))
    return skus[0] if skus else None


def _box(scene: Scene, x: str) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
    """(pose, local lo, local hi) of ``x``; a stand-in with none of its own: its lender's."""
    i = scene.index.get(x)
    if i is None:
        return None
    assert scene.poses is not None and scene.local_lo is not None and scene.local_hi is not None
    if scene.placed[i]:
        return scene.poses[i], scene.local_lo[i], scene.local_hi[i]
    for cls, prop in STAND_INS.items():
        if cls in scene.classes[i]:
            for lender in sorted(scene.related(str(prop)).get(x, ())):
                j = scene.index.get(lender)
                if j is not None and scene.placed[j]:
                    return scene.poses[j], scene.local_lo[j], scene.local_hi[j]
    return None


def _moved(initial: Scene, final: Scene, x: str, tolerance: float) -> bool:
    """Some corner of x's box is more than ``tolerance`` from where it was (or x appeared,
    or went)."""
    a, b = _box(initial, x), _box(final, x)
    if a is None or b is None:
        return (a is None) != (b is None)
    lo, hi = a[1], a[2]
    corners = np.array([[u, v, w, 1.0] for u in (lo[0], hi[0]) for v in (lo[1], hi[1]) for w in (lo[2], hi[2])])
    return bool(np.max(np.linalg.norm((corners @ a[0].T - corners @ b[0].T)[:, :3], axis=1)) > tolerance)
