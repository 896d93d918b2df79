"""Looking again: how the executor senses with a sensor that is not exact.

The accuracy the executor assumes (a :class:`~kb.sim.noise.SensorNoise`: the sensor individual
of the state file, or ``--sensor-noise``) decides how many looks it takes and how wide its
checks' tolerances are. With an exact sensor none of this happens: one look, the 1 mm
tolerance of :mod:`kb.spatial.rcc8`, as before.

* **Poses** (position, orientation, bias sigmas): the belief averages still objects' looks
  (:mod:`kb.execution.belief`), so an object seen ``n`` times since it last moved is known to
  ``sigma(n) = sqrt(position² / n + bias²)`` per coordinate. Before an action's motion
  targets are computed, the objects they are computed from get looks until
  :data:`K_CAPTURE` sigmas fit in what a gripper or a tool changer captures (:data:`CAPTURE`,
  2 mm: :data:`kb.sim.robot.GRASP_TOLERANCE`): ``n >= (K_CAPTURE * position / CAPTURE)²``,
  7 looks at 1 mm. A check's tolerance is the exact one plus :data:`K_CHECK` sigmas of the
  difference of two objects' positions (``tol + K_CHECK * sqrt(2) * max sigma`` over the
  objects the check is decided on): 6.7 mm at 1 mm after one look; the objects get more
  looks while it is wider than :data:`WIDEST` (8 mm: kitkb's scenarios keep solids that do not
  touch at least 2 cm apart, so a tolerance below half of that cannot make them touch).
  A part is released :data:`RELEASE` (2 mm) above its place, not pressed into it.
* **Misdetections**: an object asked for and not reported is looked for again, up to the
  number of looks that all miss it with a chance below :data:`SURE` (3 at 1 %), before it is
  believed gone.
* **Misclassifications**: a SKU other than the believed one is believed when that many
  further looks all report it (:meth:`Looks.confirm`).
"""

from __future__ import annotations

import math
from typing import Any, Iterable, Sequence

import numpy as np

from kb.crcl.cell import CellInterface, Observation, sense_names
from kb.execution.belief import Belief
from kb.spatial.rcc8 import DEFAULT_TOLERANCE

#: what a gripper or a tool changer captures (m): the simulated cell's GRASP_TOLERANCE
CAPTURE = 2 * DEFAULT_TOLERANCE
#: sigmas of a target's error that must fit within :data:`CAPTURE`
K_CAPTURE = 5.0
#: sigmas of the difference of two positions a check's tolerance adds to the exact one
K_CHECK = 4.0
#: the widest tolerance a check is decided with (m); more looks beyond
WIDEST = 8 * DEFAULT_TOLERANCE
#: with noise, a placed object is released this far above where it goes (m), so that a place
#: that errs downwards does not push it into its support: it drops onto it
RELEASE = CAPTURE
#: at most this many looks of an object since it last moved
MAX_LOOKS = 64
#: the chance of being wrong accepted for "not there" and for "of another SKU"
SURE = 1e-6
#: further looks of a failed check's objects before the failure is declared
RECHECK = 3


class Looks:
    """Sensing for the executor with a sensor of accuracy ``noise`` (None or exact: one look)."""

    def __init__(self, cell: CellInterface, belief: Belief, noise: Any = None,
                 tolerance: float = DEFAULT_TOLERANCE) -> None:
        self.cell, self.belief, self.tolerance = cell, belief, tolerance
        self.noise = noise if noise is not None and not noise.zero else None
        self.poses = bool(self.noise is not None and self.noise.poses)
        p = self.noise.misdetection if self.noise is not None else 0.0
        q = self.noise.misclassification if self.noise is not None else 0.0
        self.relooks = _repeats(p)  # looks for an object not seen, before it is believed gone
        self.confirmations = _repeats(q) if q else 0
        self.capture_looks = self._looks_for(CAPTURE / K_CAPTURE)
        #: looks to narrow one check's tolerance to :data:`WIDEST`
        self.check_looks = self._looks_for((WIDEST - tolerance) / (K_CHECK * math.sqrt(2)))
        self.count = 0  # sensor queries made (for the benchmark's cost per action)

    @property
    def active(self) -> bool:
        return self.noise is not None

    def _looks_for(self, sigma: float) -> int:
        """Looks that bring an object's position sigma to ``sigma`` (at most :data:`MAX_LOOKS`)."""
        if not self.poses:
            return 1
        nz = self.noise
        room = sigma ** 2 - nz.bias ** 2
        if room <= 0:
            return MAX_LOOKS
        return max(1, min(MAX_LOOKS, math.ceil(nz.position ** 2 / room - 1e-9)))

    # --- sensing ----------------------------------------------------------------------
    def sense(self, names: Sequence[str]) -> list[Observation]:
        """The named objects as sensed now (:func:`kb.crcl.cell.sense_names`); with
        misdetections, those believed placed and not reported are looked for again."""
        self.count += 1
        obs = sense_names(self.cell, names)
        if self.relooks <= 1:
            return obs
        return obs + self._again([n for n in names if self.belief.placed(n)], obs)

    def sense_class(self, cls: str, expected: Iterable[str]) -> list[Observation]:
        """The objects of class ``cls`` (local name) as sensed now; with misdetections, the
        ``expected`` ones not reported are looked for again by name."""
        self.count += 1
        obs = self.cell.sense(cls, by="class")
        if self.relooks <= 1:
            return obs
        return obs + self._again(list(expected), obs)

    def _again(self, expected: list[str], obs: list[Observation]) -> list[Observation]:
        seen = {o.name for o in obs}
        missing = [n for n in expected if n not in seen]
        out: list[Observation] = []
        for _ in range(self.relooks - 1):
            if not missing:
                break
            self.count += 1
            found = sense_names(self.cell, missing)
            out.extend(found)
            got = {o.name for o in found}
            missing = [n for n in missing if n not in got]
        return out

    def until(self, indices: Iterable[int], looks: int) -> list[str]:
        """Look at the placed objects ``indices`` until each has ``looks`` looks since it last
        moved (one that moves meanwhile starts again; at most ``looks`` rounds); the names
        whose belief changed."""
        b = self.belief
        todo = [int(i) for i in indices if b.placed(b.names[int(i)])]
        changed: dict[str, None] = {}
        for _ in range(looks):
            short = [b.names[i] for i in todo if b.looks[i] < looks and b.placed(b.names[i])]
            if not short:
                break
            changed.update(dict.fromkeys(b.observe(self.sense(short), asked=short)))
        return list(changed)

    # --- tolerances -------------------------------------------------------------------
    def sigma(self, indices: Iterable[int]) -> float:
        """The largest position sigma among the placed objects ``indices``."""
        b = self.belief
        return max((b.sigma(int(i)) for i in indices if not np.isnan(b.poses[int(i), 0, 0])), default=0.0)

    def tolerance_of(self, indices: Iterable[int]) -> float:
        """The tolerance a check on objects ``indices`` is decided with (module docstring)."""
        if not self.poses:
            return self.tolerance
        return self.tolerance + K_CHECK * math.sqrt(2) * self.sigma(indices)

    def narrow(self, indices: Sequence[int]) -> float:
        """More looks of the objects ``indices`` while their check's tolerance is wider than
        :data:`WIDEST`; the tolerance then (wider still when :data:`MAX_LOOKS` or the bias do
        not allow it: the check may then find objects touching that do not)."""
        tol = self.tolerance_of(indices)
        if tol > WIDEST:
            self.until(indices, self.check_looks)
            tol = self.tolerance_of(indices)
        return tol

    def wide(self, tolerance: float) -> float:
        """A tolerance with twice the noise margin of ``tolerance`` (how sure a violation is:
        one that holds at both cannot be the noise of a contact)."""
        return tolerance + (tolerance - self.tolerance)

    # --- SKUs -------------------------------------------------------------------------
    def confirm(self) -> None:
        """Settle the belief's SKU claims by further looks at the object: the SKU that
        :attr:`confirmations` looks in a row report is believed (the claimed one, the believed
        one, or a third: the claim was a misclassification of a part whose SKU did change);
        misdetected looks do not count; no agreement within a few more looks: the belief stays."""
        b = self.belief
        for name in list(b.claims):
            last, run = None, 0
            for _ in range(4 * self.confirmations + self.relooks):
                self.count += 1
                found = [o for o in sense_names(self.cell, [name]) if o.name == name]
                if not found:
                    continue
                sku = found[0].sku
                last, run = sku, (run + 1 if sku == last else 1)
                if run >= self.confirmations:
                    break
            b.confirm_sku(name, last if run >= self.confirmations and last else None)


def _repeats(rate: float) -> int:
    """Looks that all go wrong with a chance below :data:`SURE` at ``rate`` per look (1 for 0)."""
    if rate <= 0:
        return 1
    return max(1, math.ceil(math.log(SURE) / math.log(rate) - 1e-9))
