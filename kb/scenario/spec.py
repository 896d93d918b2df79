"""Declarative scenario specifications: part types, kit designs, kits.

A :class:`ScenarioSpec` says *what* a workstation holds; :mod:`kb.scenario` lays it out
(geometry, names) and writes the initial and goal states. The shipped scenarios under
``ontologies/scenarios/`` are written from the specs in :data:`SHIPPED`.
"""

from __future__ import annotations

import math
import random
import string
from dataclasses import dataclass


@dataclass(frozen=True)
class PartType:
    """A part SKU: ``key`` is its letter(s) (``"a"``), sizes in meters, weight in kilograms."""

    key: str
    length: float
    width: float
    height: float
    weight: float


@dataclass(frozen=True)
class DesignSpec:
    """A kit design: ``counts`` gives how many parts of each type key the kit holds."""

    name: str
    counts: tuple[tuple[str, int], ...]

    @property
    def size(self) -> int:
        """Number of parts in a kit of this design."""
        return sum(n for _, n in self.counts)


@dataclass(frozen=True)
class ScenarioSpec:
    """What a workstation holds; ``kits`` gives the design index of each kit to build."""

    name: str
    description: str
    part_types: tuple[PartType, ...]
    designs: tuple[DesignSpec, ...]
    kits: tuple[int, ...]
    spare: int = 1  # parts per type beyond what the kits need
    tray_grid: tuple[int, int] = (4, 3)  # parts tray cells (columns, rows)
    max_yaw_deg: float = 0.0  # parts trays on the parts table get a yaw in [-max, max]
    seed: int = 0  # draws the yaws
    #: kit trays start on the work table (the basic kit test method), not in the storage box
    kit_trays_on_table: bool = False
    #: > 0: the tables leave a tray this much room (m) on every side at any yaw, so that the test
    #: methods can place and turn trays anywhere on them (:mod:`kb.scenario.placement`)
    room: float = 0.0

    def needed(self) -> dict[str, int]:
        """Parts of each type the kits need together."""
        need = {t.key: 0 for t in self.part_types}
        for d in self.kits:
            for key, n in self.designs[d].counts:
                need[key] += n
        return need


def type_key(i: int) -> str:
    """Spreadsheet-style letters: 0 -> a, 25 -> z, 26 -> aa, ..."""
    letters = ""
    i += 1
    while i:
        i, r = divmod(i - 1, 26)
        letters = string.ascii_lowercase[r] + letters
    return letters


def _design_name(counts: tuple[tuple[str, int], ...]) -> str:
    return "kit_design_" + "".join(f"{k}{n}" for k, n in counts)


def _design(counts: list[tuple[str, int]]) -> DesignSpec:
    c = tuple(counts)
    return DesignSpec(_design_name(c), c)


_A = PartType("a", 0.10, 0.08, 0.06, 0.18)
_B = PartType("b", 0.12, 0.08, 0.06, 0.18)
_C = PartType("c", 0.15, 0.08, 0.06, 0.18)
_D = PartType("d", 0.08, 0.06, 0.05, 0.12)
_E = PartType("e", 0.09, 0.09, 0.07, 0.25)

SHIPPED: dict[str, ScenarioSpec] = {
    "small-kit": ScenarioSpec(
        name="small-kit",
        description="One kit of two part types (2 of A, 1 of B); one parts tray per type.",
        part_types=(_A, _B),
        designs=(_design([("a", 2), ("b", 1)]),),
        kits=(0,),
        spare=2,
        tray_grid=(3, 2),
    ),
    "kit-a2b3c3d1e1": ScenarioSpec(
        name="kit-a2b3c3d1e1",
        description="One 10-part kit of five part types (2 A, 3 B, 3 C, 1 D, 1 E).",
        part_types=(_A, _B, _C, _D, _E),
        designs=(_design([("a", 2), ("b", 3), ("c", 3), ("d", 1), ("e", 1)]),),
        kits=(0,),
        spare=1,
        tray_grid=(3, 2),
    ),
    "two-designs": ScenarioSpec(
        name="two-designs",
        description="Two kits of two different designs (a2b1c1 and b2c1d2), two kit trays.",
        part_types=(_A, _B, _C, _D),
        designs=(
            _design([("a", 2), ("b", 1), ("c", 1)]),
            _design([("b", 2), ("c", 1), ("d", 2)]),
        ),
        kits=(0, 1),
        spare=1,
        tray_grid=(3, 2),
    ),
}


def random_spec(parts: int, kits: int, seed: int) -> ScenarioSpec:
    """A generated specification: ``parts`` parts over ``kits`` kits, drawn from ``seed``."""
    rng = random.Random(seed)
    n_types = max(1, min(parts, math.ceil(math.sqrt(parts))))
    types = []
    for i in range(n_types):
        length = round(rng.uniform(0.04, 0.10), 3)
        width = round(rng.uniform(0.03, length), 3)
        height = round(rng.uniform(0.05, 0.09), 3)
        weight = round(rng.uniform(0.05, 0.30), 3)
        types.append(PartType(type_key(i), length, width, height, weight))
    sizes = [parts // kits + (1 if k < parts % kits else 0) for k in range(kits)]
    variants = min(kits, 3)
    designs: list[DesignSpec] = []
    index: dict[tuple[int, int], int] = {}
    kit_designs = []
    for k, size in enumerate(sizes):
        slot = (size, k % variants)
        if slot not in index:
            index[slot] = len(designs)
            designs.append(_random_design(rng, types, size, len(designs) + 1))
        kit_designs.append(index[slot])
    return ScenarioSpec(
        name=f"generated-p{parts}-k{kits}-s{seed}",
        description=f"Generated scenario: {parts} parts in {kits} kit(s), seed {seed}.",
        part_types=tuple(types),
        designs=tuple(designs),
        kits=tuple(kit_designs),
        spare=1 + rng.randrange(3),
        tray_grid=(6, 5),
        max_yaw_deg=4.0,
        seed=seed,
    )


def _random_design(rng: random.Random, types: list[PartType], size: int, number: int) -> DesignSpec:
    chosen = rng.sample(types, min(len(types), max(1, min(size, rng.randint(2, 6) if size > 1 else 1))))
    if size >= len(types) * 2:
        chosen = list(types)
    order = {t.key: i for i, t in enumerate(types)}
    counts = {t.key: 1 for t in sorted(chosen[:size], key=lambda t: order[t.key])}
    keys = list(counts)
    for _ in range(size - len(counts)):
        counts[rng.choice(keys)] += 1
    return DesignSpec(f"kit_design_{number}", tuple(counts.items()))


# --------------------------------------------------------------- test method workstations


def random_types(count: int, seed: int) -> tuple[PartType, ...]:
    """``count`` part types of sizes and weights drawn from ``seed`` (as :func:`random_spec` draws them)."""
    rng = random.Random(seed)
    types = []
    for i in range(count):
        length = round(rng.uniform(0.04, 0.10), 3)
        width = round(rng.uniform(0.03, length), 3)
        height = round(rng.uniform(0.05, 0.09), 3)
        weight = round(rng.uniform(0.05, 0.30), 3)
        types.append(PartType(type_key(i), length, width, height, weight))
    return tuple(types)


def types_for(parts: int) -> int:
    """How many part types a test method's supply holds for designs of up to ``parts`` parts:
    two or more (the first paper's basic kit holds "two or more different types of parts"),
    about the square root of the size, at most six."""
    return max(2, min(6, round(math.sqrt(parts))))


def mixed_design(types: tuple[PartType, ...], size: int, seed: int, name: str) -> DesignSpec:
    """A design of ``size`` parts of at least two of ``types`` (one when ``size`` is 1), the
    counts drawn from ``seed``."""
    rng = random.Random(seed)
    n = min(len(types), size, max(2, rng.randint(2, len(types))))
    chosen = sorted(rng.sample(range(len(types)), n))
    counts = {types[i].key: 1 for i in chosen}
    keys = list(counts)
    for _ in range(size - n):
        counts[rng.choice(keys)] += 1
    return DesignSpec(name, tuple(counts.items()))


def method_spec(name: str, types: tuple[PartType, ...], designs: tuple[DesignSpec, ...], kits: tuple[int, ...], *,
                spare: int = 1, kit_trays_on_table: bool = False, room: float = 0.05) -> ScenarioSpec:
    """A test method's workstation: ``designs`` built as ``kits`` (design indices, in order),
    every tray placeable at any yaw (``room``); kit trays on the work table or in storage."""
    used = sorted({k for d in designs for k, _ in d.counts})
    return ScenarioSpec(
        name=name,
        description=f"Test method workstation: {len(kits)} kit(s) of {len(designs)} design(s).",
        part_types=tuple(t for t in types if t.key in used),
        designs=designs,
        kits=kits,
        spare=spare,
        tray_grid=(3, 2),
        kit_trays_on_table=kit_trays_on_table,
        room=room,
    )
