"""What a pose sensor's accuracy is: the errors the executor assumes of a cell's sensor, look by look.

Seed 004 assumes perfect poses from USARTruth and names its future work: a model of the noise
of each pose-estimation step. :class:`SensorAccuracy` is kitkb's model of it. The executor
(:mod:`kb.execution.looks`, :mod:`kb.execution.belief`) decides from it how many looks to take
and how wide its checks are; the simulated sensor (:mod:`kb.sim.sensor`, :mod:`kb.sim.noise`)
draws its errors from the same values. It lives here, below both, because it is what a
sensor is assumed to achieve, not how a simulator adds noise:

* ``position``: the standard deviation (m) of a Gaussian error of each coordinate of an
  object's location, drawn anew at every look;
* ``orientation``: the same for each of roll, pitch and yaw (rad);
* ``bias``: the standard deviation (m) of a per-object offset of the location, the same at
  every look, as a miscalibrated camera has: more looks do not average it out;
* ``misdetection``: the chance that an object is not reported at all in a look;
* ``misclassification``: the chance that an object with a SKU is reported with another SKU of
  the cell (one of the same kind of object: a part as another part SKU).

The accuracy of a sensor is data in the ontology: a ``ktw:PoseSensor`` individual of the
workstation (``hasKittingWorkstation_Sensor``) with ``hasPoseSensor_PositionAccuracy``,
``_OrientationAccuracy`` (in the file's length and angle units), ``_PositionBias``,
``_MisdetectionRate`` and ``_MisclassificationRate`` (:meth:`SensorAccuracy.from_scene`). The
option ``--sensor-noise position=1mm,orientation=0.5deg,misdetection=0.01,misclass=0.005``
(:meth:`SensorAccuracy.parse`) overrides it: a value carries its unit (m, cm, mm, in; deg,
rad), a rate is ``0.01`` or ``1%``.

:data:`CAPTURE_TOLERANCE` is the other thing an executor assumes of a cell: how far from its
tip a gripper or a tool changer still captures what it closes on (the simulated robot grasps
within it, :data:`kb.sim.robot.GRASP_TOLERANCE`; the executor takes looks until its targets
are known well within it, :mod:`kb.execution.looks`).
"""

from __future__ import annotations

import math
import re
from dataclasses import asdict, dataclass, fields, replace
from typing import Any

from kb.core.errors import InputError
from kb.core.namespaces import KTW, local_name
from kb.spatial.rcc8 import DEFAULT_TOLERANCE

#: what a gripper or a tool changer captures (m): an object whose grasp point is within this
#: distance of the tip is held (twice kb.spatial.rcc8's contact tolerance, 2 mm)
CAPTURE_TOLERANCE = 2 * DEFAULT_TOLERANCE

#: length unit symbol -> metres
LENGTHS: dict[str, float] = {"m": 1.0, "cm": 0.01, "mm": 0.001, "in": 0.0254}
#: angle unit symbol -> radians
ANGLES: dict[str, float] = {"deg": math.pi / 180.0, "rad": 1.0}
#: option key -> (field, kind: "length", "angle" or "rate")
KEYS: dict[str, tuple[str, str]] = {
    "position": ("position", "length"), "orientation": ("orientation", "angle"), "bias": ("bias", "length"),
    "misdetection": ("misdetection", "rate"), "misclass": ("misclassification", "rate"),
    "misclassification": ("misclassification", "rate"),
}
#: the sensor's properties in the kitting model -> field
PROPERTIES: dict[str, str] = {
    str(KTW.hasPoseSensor_PositionAccuracy): "position", str(KTW.hasPoseSensor_OrientationAccuracy): "orientation",
    str(KTW.hasPoseSensor_PositionBias): "bias", str(KTW.hasPoseSensor_MisdetectionRate): "misdetection",
    str(KTW.hasPoseSensor_MisclassificationRate): "misclassification",
}
SENSOR_OF = str(KTW.hasKittingWorkstation_Sensor)
_NUMBER = re.compile(r"^\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*([a-z%]*)\s*$")


@dataclass(frozen=True)
class SensorAccuracy:
    """A pose sensor's errors per look (SI: metres, radians; rates in [0, 1))."""

    position: float = 0.0
    orientation: float = 0.0
    misdetection: float = 0.0
    misclassification: float = 0.0
    bias: float = 0.0

    def __post_init__(self) -> None:
        for f in fields(self):
            v = getattr(self, f.name)
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v >= 0):
                raise ValueError(f"{f.name} must be a finite number >= 0, not {v!r}")
            if f.name in ("misdetection", "misclassification") and v >= 1:
                raise ValueError(f"{f.name} must be a rate below 1, not {v!r}")
            object.__setattr__(self, f.name, float(v))

    @property
    def zero(self) -> bool:
        """True for a perfect sensor (seed 004's USARTruth)."""
        return not any(getattr(self, f.name) for f in fields(self))

    @property
    def poses(self) -> bool:
        """True when the poses it reports are off (position, orientation or bias)."""
        return bool(self.position or self.orientation or self.bias)

    @classmethod
    def of(cls, value: "SensorAccuracy | tuple[float, float] | str | None") -> "SensorAccuracy":
        """A noise from itself, a (position sigma, orientation sigma) pair (the cell's former
        ``noise=``), the option's text, or None (none)."""
        if value is None:
            return cls()
        if isinstance(value, SensorAccuracy):
            return value
        if isinstance(value, str):
            return cls.parse(value)
        pos, ang = value
        return cls(position=float(pos), orientation=float(ang))

    @classmethod
    def parse(cls, text: str, base: "SensorAccuracy | None" = None) -> "SensorAccuracy":
        """From ``"position=1mm,orientation=0.5deg,misdetection=0.01,misclass=0.5%,bias=0.5mm"``;
        the keys given replace ``base``'s (the ontology's sensor), the others are kept. A length
        or an angle without its unit, an unknown key or unit, a negative value or a rate of 1 or
        more is a ValueError naming the item and its place in the text."""
        items = [s.strip() for s in text.split(",")]
        values: dict[str, float] = {}
        for k, item in enumerate(items, 1):
            where = f"item {k} of {text!r}"
            if not item:
                raise ValueError(f"an empty item ({where})")
            key, eq, raw = item.partition("=")
            key = key.strip().lower()
            if not eq or key not in KEYS:
                raise ValueError(f"{item!r}: expected KEY=VALUE with KEY one of position, orientation, bias, "
                                 f"misdetection, misclass ({where})")
            name, kind = KEYS[key]
            values[name] = _value(raw, kind, item, where)
        try:
            return replace(base or cls(), **values)
        except ValueError as exc:
            raise ValueError(f"{exc} ({text!r})") from None

    @classmethod
    def sweep(cls, text: str, base: "SensorAccuracy | None" = None) -> list["SensorAccuracy"]:
        """The levels of ``"KEY=FROM:TO:N"`` (``position=0mm:5mm:6``: 0, 1, ... 5 mm), each
        ``base`` with that key replaced; FROM and TO carry their units as in :meth:`parse`, N
        is the number of levels (at least 2). A ValueError names what is wrong."""
        key, eq, spec = text.partition("=")
        parts = spec.split(":")
        if not eq or len(parts) != 3:
            raise ValueError(f"{text!r}: expected KEY=FROM:TO:N, e.g. position=0mm:5mm:6")
        try:
            n = int(parts[2])
        except ValueError:
            raise ValueError(f"{text!r}: the number of levels {parts[2]!r} is not a whole number") from None
        if n < 2:
            raise ValueError(f"{text!r}: a sweep needs at least 2 levels, not {n}")
        lo = cls.parse(f"{key}={parts[0]}")
        hi = cls.parse(f"{key}={parts[1]}")
        name = KEYS.get(key.strip().lower(), (key, ""))[0]
        a, b = getattr(lo, name), getattr(hi, name)
        return [replace(base or cls(), **{name: a + (b - a) * k / (n - 1)}) for k in range(n)]

    @classmethod
    def from_scene(cls, scene: Any) -> "SensorAccuracy | None":
        """The accuracy of the workstation's pose sensor in a :class:`~kb.spatial.scene.Scene`
        (its values already in SI): the sensor its workstation names, else the only one; None
        when the state has none."""
        sensors = sorted({o for _s, o in scene.facts.get(SENSOR_OF, ())})
        if not sensors:
            sensors = sorted(n for n, c in zip(scene.names, scene.classes) if str(KTW.PoseSensor) in c)
        if not sensors:
            return None
        found = {}
        for prop, name in PROPERTIES.items():
            v = scene.values.get(prop, {}).get(sensors[0])
            if v is not None:
                try:
                    found[name] = float(v)  # type: ignore[arg-type]
                except (TypeError, ValueError):
                    raise ValueError(f"sensor {local_name(sensors[0])}: {local_name(prop)} {v!r} is not a number") from None
        try:
            return cls(**found)
        except ValueError as exc:
            raise ValueError(f"sensor {local_name(sensors[0])}: {exc}") from None

    def text(self) -> str:
        """The option's spelling (millimetres and degrees), the zero values left out ("none"
        for a perfect sensor)."""
        out = []
        for name, value in (("position", self.position), ("orientation", self.orientation), ("bias", self.bias)):
            if value:
                unit, f = ("deg", ANGLES["deg"]) if name == "orientation" else ("mm", LENGTHS["mm"])
                out.append(f"{name}={value / f:g}{unit}")
        if self.misdetection:
            out.append(f"misdetection={self.misdetection:g}")
        if self.misclassification:
            out.append(f"misclass={self.misclassification:g}")
        return ",".join(out) or "none"

    def as_dict(self) -> dict[str, float]:
        """The five values in SI (for JSON reports)."""
        return asdict(self)


def assumed_accuracy(scene: Any, given: "SensorAccuracy | str | None" = None) -> SensorAccuracy | None:
    """The accuracy the executor assumes of the sensor of the state ``scene`` (a
    :class:`~kb.spatial.scene.Scene`): ``given`` (an accuracy, or the ``--sensor-noise`` text
    over the state's own sensor) or the state's ``ktw:PoseSensor``; None when neither says
    anything (an exact sensor). A value the state or the text gets wrong is an
    :class:`~kb.core.errors.InputError` naming it (the state file's)."""
    if given is None and SENSOR_OF not in scene.facts and not any(
            "PoseSensor" in str(c) for cs in scene.classes for c in cs):
        return None
    try:
        base = SensorAccuracy.from_scene(scene)
    except ValueError as exc:
        raise InputError(str(exc), getattr(scene, "path", None)) from None
    if isinstance(given, str):
        try:
            return SensorAccuracy.parse(given, base)
        except ValueError as exc:
            raise InputError(f"sensor noise: {exc}") from None
    return given if given is not None else base


def _value(raw: str, kind: str, item: str, where: str) -> float:
    m = _NUMBER.match(raw)
    if m is None:
        raise ValueError(f"{item!r}: {raw.strip()!r} is not a number with a unit ({where})")
    number, unit = float(m.group(1)), m.group(2)
    if kind == "rate":
        if unit not in ("", "%"):
            raise ValueError(f"{item!r}: a rate is a number (0.01) or a percentage (1%), not {raw.strip()!r} ({where})")
        return number / 100.0 if unit == "%" else number
    table = LENGTHS if kind == "length" else ANGLES
    if not unit:
        raise ValueError(f"{item!r}: a bare {kind} is ambiguous; write its unit "
                         f"({', '.join(table)}: e.g. {m.group(1)}{next(iter(table)) if kind == 'angle' else 'mm'}) ({where})")
    if unit not in table:
        raise ValueError(f"{item!r}: unknown {kind} unit {unit!r}; known: {', '.join(table)} ({where})")
    return number * table[unit]


__all__ = ["ANGLES", "CAPTURE_TOLERANCE", "KEYS", "LENGTHS", "PROPERTIES", "SENSOR_OF", "SensorAccuracy",
           "assumed_accuracy"]
