"""Units of measure: the names the kitting model allows and their factors to SI.

A kitting workstation declares the units its data file is written in
(``hasKittingWorkstation_LengthUnit``, ``_AngleUnit``, ``_WeightUnit``; the kitting model's
datatypes ``ktw:lengthUnit``, ``ktw:angleUnit``, ``ktw:weightUnit``). kitkb computes in SI —
metres, radians, kilograms — whatever the file's units: a file's quantities are converted on
reading (:mod:`kb.spatial.scene`), every tolerance and threshold is a number of metres (1 mm
is 1 mm in any file), and what goes back into the file's world (database poses, reports) is
converted back with :class:`Units`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

#: Length unit name -> metres per unit.
LENGTH: dict[str, float] = {"meter": 1.0, "millimeter": 0.001, "inch": 0.0254}
#: Angle unit name -> radians per unit.
ANGLE: dict[str, float] = {"radian": 1.0, "degree": math.pi / 180.0}
#: Weight unit name -> kilograms per unit.
WEIGHT: dict[str, float] = {"kilogram": 1.0, "gram": 0.001, "milligram": 1e-6,
                            "ounce": 0.028349523125, "pound": 0.45359237}
#: Quantity kind (the model's ``ktw:quantityKind`` annotation) -> its table.
KINDS: dict[str, dict[str, float]] = {"length": LENGTH, "angle": ANGLE, "weight": WEIGHT}
#: Short symbols for reports.
SYMBOL: dict[str, str] = {"meter": "m", "millimeter": "mm", "inch": "in", "radian": "rad", "degree": "deg",
                          "kilogram": "kg", "gram": "g", "milligram": "mg", "ounce": "oz", "pound": "lb"}


@dataclass(frozen=True)
class Units:
    """The units a data file is written in (SI when the file declares none)."""

    length: str = "meter"
    angle: str = "radian"
    weight: str = "kilogram"

    def factor(self, kind: str) -> float:
        """SI units per file unit of quantity ``kind`` ("length", "angle", "weight")."""
        return KINDS[kind][getattr(self, kind)]

    @property
    def metres(self) -> float:
        """Metres per file length unit."""
        return LENGTH[self.length]

    def to_si(self, kind: str, value: float) -> float:
        """``value`` in the file's unit of ``kind`` -> SI."""
        return value * self.factor(kind)

    def from_si(self, kind: str, value: float) -> float:
        """``value`` in SI -> the file's unit of ``kind``."""
        return value / self.factor(kind)

    def length_text(self, metres: float, digits: int = 3) -> str:
        """A length given in metres, written in the file's unit with its symbol (``"12.5 mm"``)."""
        return f"{round(metres / self.metres, digits):g} {SYMBOL[self.length]}"

    def as_dict(self) -> dict[str, str]:
        """The three unit names (for JSON reports)."""
        return {"length": self.length, "angle": self.angle, "weight": self.weight}


#: What kitkb computes in.
SI = Units()


def unit_factor(kind: str, name: str) -> float | None:
    """SI units per ``name`` of quantity ``kind``; None when kitkb cannot convert ``name``."""
    return KINDS[kind].get(str(name).strip().lower())
