"""Looking again: how the executor senses with a sensor that is not exact.

The accuracy the executor assumes (a :class:`~kb.cells.accuracy.SensorAccuracy`: the sensor individual
of the state file, or ``--sensor-noise``) decides how many looks it takes and how wide its
checks' tolerances are. With an exact sensor none of this happens: one look, the 1 mm
tolerance of :mod:`kb.spatial.rcc8`, as before.

* **Poses** (position, orientation, bias sigmas): the belief averages still objects' looks
  (:mod:`kb.execution.belief`), so an object seen ``n`` times since it last moved is known to
  ``sigma(n) = sqrt(position² / n + bias²)`` per coordinate. Before an action's motion
  targets are computed, the objects they are computed from get looks until
  :data:`K_CAPTURE` sigmas fit in what a gripper or a tool changer captures (:data:`CAPTURE`,
  2 mm: :data:`kb.cells.accuracy.CAPTURE_TOLERANCE`, what a cell's gripper is assumed to capture): ``n >= (K_CAPTURE * position / CAPTURE)²``,
  7 looks at 1 mm. A check's tolerance is the exact one plus :data:`K_CHECK` sigmas of the
  difference of two objects' positions (``tol + K_CHECK * sqrt(2) * max sigma`` over the
  objects the check is decided on; an object's sigma counts its orientation's too, as the
  yaw error times half its diagonal: 4.4 mm for a 1 m table at 0.5 degrees): 6.7 mm for
  small objects at 1 mm after one look; the objects get more looks while it is wider than
  :data:`WIDEST` (8 mm: kitkb's scenarios keep solids that do not touch at least 2 cm apart,
  so a tolerance below half of that cannot make them touch). A still object's looks add up
  over the run, so a large table pays its looks once.
  A part is released :data:`RELEASE` (1 mm) above its place, not pressed into it.
* **Misdetections**: an object asked for and not reported is looked for again, up to the
  number of looks that all miss it with a chance below :data:`SURE` (3 at 1 %), before it is
  believed gone.
* **Misclassifications**: a SKU other than the believed one is believed when that many
  further looks all report it (:meth:`Looks.confirm`).
"""

from __future__ import annotations

import math
import statistics
from typing import Any, Iterable, Sequence

import numpy as np

from kb.cells.accuracy import CAPTURE_TOLERANCE, SensorAccuracy
from kb.core.namespaces import KTW
from kb.crcl.cell import Observation, Senses, sense_names
from kb.execution.belief import Belief
from kb.model.definitions import Definitions
from kb.spatial.frames import HEADING_MERGE, heading_groups, headings
from kb.spatial.predicates import Evaluator
from kb.spatial.rcc8 import DEFAULT_TOLERANCE
from kb.spatial.scene import Scene

SOLID = str(KTW.SolidObject)
#: what a gripper or a tool changer captures (m): kb.cells.accuracy's, the simulated robot's too
CAPTURE = CAPTURE_TOLERANCE
#: sigmas of a target's error that must fit within :data:`CAPTURE`
K_CAPTURE = 5.0
#: sigmas of the difference of two positions a check's tolerance adds to the exact one
K_CHECK = 4.0
#: the widest tolerance a check is decided with (m); more looks beyond
WIDEST = 8 * DEFAULT_TOLERANCE
#: with noise, a placed object is released this far above where it goes (m), so that a place
#: that errs downwards does not push it into its support: it drops onto it (with the 1 mm a
#: support allows, 2 mm: 5 sigma of a place whose two poses had their capture looks)
RELEASE = DEFAULT_TOLERANCE
#: at most this many looks of an object since it last moved, to narrow a tolerance
MAX_LOOKS = 256
#: the chance of being wrong accepted for "not there" and for "of another SKU"
SURE = 1e-6
#: headings (rad) closer than this at most share a frame under noise (0.5 degrees)
MERGE = math.radians(0.5)
#: further looks of a failed check's objects before the failure is declared
RECHECK = 3


class Looks:
    """Sensing for the executor with a sensor of accuracy ``noise`` (None or exact: one look)."""

    def __init__(self, cell: Senses, belief: Belief, noise: SensorAccuracy | None = None,
                 tolerance: float = DEFAULT_TOLERANCE) -> None:
        self.cell, self.belief, self.tolerance = cell, belief, tolerance
        self.noise = noise if noise is not None and not noise.zero else None
        self.poses = bool(self.noise is not None and self.noise.poses)
        p = self.noise.misdetection if self.noise is not None else 0.0
        q = self.noise.misclassification if self.noise is not None else 0.0
        self.relooks = _repeats(p)  # looks for an object not seen, before it is believed gone
        self.confirmations = _repeats(q) if q else 0
        self.capture_looks = self._looks_for(CAPTURE / K_CAPTURE)
        self.count = 0  # sensor queries made (the report's sensor.queries)

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
        misdetections, those not reported are looked for again (one believed gone, or not there
        yet, may be there now: a kit just made)."""
        self.count += 1
        obs = sense_names(self.cell, names)
        if self.relooks <= 1:
            return obs
        return obs + self._again(names, obs, placed=False)

    def sense_class(self, cls: str, expected: Iterable[str]) -> list[Observation]:
        """The objects of class ``cls`` (local name) as sensed now; with misdetections, the
        ``expected`` ones not reported are looked for again by name."""
        self.count += 1
        obs = self.cell.sense(cls, by="class")
        if self.relooks <= 1:
            return obs
        return obs + self._again(list(expected), obs)

    def _again(self, expected: Sequence[str], obs: list[Observation], placed: bool = True) -> list[Observation]:
        """Looks for the ``expected`` objects that ``obs`` lacks: those believed placed, or
        (``placed`` false) any solid object (never a SKU or a design, which no look shows)."""
        seen = {o.name for o in obs}
        b = self.belief
        missing = list(dict.fromkeys(n for n in expected if n not in seen and (
            b.placed(n) or not placed and n in b.index and SOLID in b.classes[b.index[n]])))
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

    def until(self, indices: Iterable[int], looks: int | dict[int, int]) -> list[str]:
        """Look at the placed objects ``indices`` until each has ``looks`` looks since it last
        moved (or ``looks[i]`` for object i): each round one query that names every object as
        many times as it lacks looks (simultaneous frames), again for what was missed or moved
        meanwhile; the names whose belief changed."""
        b = self.belief
        want = looks if isinstance(looks, dict) else {int(i): looks for i in indices}
        todo = {i: n for i, n in want.items() if b.placed(b.names[i])}
        changed: dict[str, None] = {}
        for _ in range(max(todo.values(), default=0)):  # all the looks missing in one query a round
            short = {b.names[i]: n - int(b.looks[i]) for i, n in todo.items() if b.looks[i] < n and b.placed(b.names[i])}
            if not short:
                break
            asked = [name for name, k in short.items() for _ in range(k)]
            changed.update(dict.fromkeys(b.observe(self.sense(asked), asked=list(short))))
        return list(changed)

    def needed(self, i: int, sigma: float) -> int:
        """Looks object ``i`` needs for its sigma to be at most ``sigma`` (at most :data:`MAX_LOOKS`)."""
        b = self.belief
        n = max(int(b.looks[i]), 1)
        if b.sigma(i, n) <= sigma:
            return n
        hi = n
        while hi < MAX_LOOKS and b.sigma(i, hi) > sigma:
            hi = min(MAX_LOOKS, hi * 2)
        lo = hi // 2
        while lo + 1 < hi:  # the fewest looks in (lo, hi] that do
            mid = (lo + hi) // 2
            lo, hi = (lo, mid) if b.sigma(i, mid) <= sigma else (mid, hi)
        return hi

    # --- tolerances -------------------------------------------------------------------
    def sigma(self, indices: Iterable[int]) -> float:
        """The largest position sigma among the placed objects ``indices``."""
        b = self.belief
        idx = np.asarray(list(indices) if not isinstance(indices, np.ndarray) else indices, np.int64)
        idx = idx[~np.isnan(b.poses[idx, 0, 0])] if len(idx) else idx
        return float(b.sigmas(idx).max()) if len(idx) else 0.0

    def tolerance_of(self, indices: Iterable[int]) -> float:
        """The tolerance a check on objects ``indices`` is decided with (module docstring)."""
        if not self.poses:
            return self.tolerance
        return self.tolerance + K_CHECK * math.sqrt(2) * self.sigma(indices)

    def narrow(self, indices: Sequence[int]) -> float:
        """More looks of the objects ``indices`` whose sigma makes their check's tolerance wider
        than :data:`WIDEST`; the tolerance then (wider still when :data:`MAX_LOOKS` or the bias
        do not allow it: the check may then find objects touching that do not)."""
        tol = self.tolerance_of(indices)
        if tol > WIDEST:
            target = (WIDEST - self.tolerance) / (K_CHECK * math.sqrt(2))
            b = self.belief
            idx = np.asarray(indices, np.int64)
            idx = idx[~np.isnan(b.poses[idx, 0, 0])]
            want = {int(i): self.needed(int(i), target) for i in idx[b.sigmas(idx) > target]}
            self.until(want, want)
            tol = self.tolerance_of(indices)
        return tol

    def evaluator(self, defs: Definitions, scene: Scene, tolerance: float) -> Evaluator:
        """An evaluator of ``scene`` (the belief's, or a part of it) at ``tolerance`` whose
        objects' frames allow for the noise of their headings (:meth:`frames`)."""
        return _Noisy(defs, scene, tolerance, self.frames)

    def frames(self, scene: Scene) -> np.ndarray:
        """(K,) the yaw of each object's frame, as :func:`kb.spatial.relations.object_frames`
        gives it, except that an object whose believed heading is within :data:`K_CHECK` sigmas
        of its looks' yaw error from axis-aligned is taken as axis-aligned, and headings within
        that of the scene's typical object (at most :data:`MERGE`) share a frame: a turned tray
        and the parts in it, whose believed headings differ by noise. A box is then decided as
        the hull of a box turned by at most that, which the check's tolerance allows for; the
        relation kernel runs once per frame, as for an exact sensor."""
        if scene.poses is None or scene.local_lo is None or not len(scene.names):
            return np.zeros(len(scene.names))
        h = headings(scene.poses)
        h[~scene.placed] = np.nan
        b = self.belief
        n = np.array([b.looks[b.index[x]] for x in scene.names], float)
        allowed = np.where(n > 0, K_CHECK * self.noise.orientation / np.sqrt(np.maximum(n, 1.0)), 0.0)
        h[np.abs(h) <= allowed] = 0.0
        seen = n[scene.placed & (n > 0)]
        # the median as np.median gives it (the middle one, or the mean of the middle two), without
        # its overhead on a few numbers
        merge = K_CHECK * self.noise.orientation / math.sqrt(statistics.median(seen.tolist())) if len(seen) else 0.0
        labels, yaws = heading_groups(h, min(max(merge, HEADING_MERGE), MERGE))
        return yaws[labels]

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


class _Noisy(Evaluator):
    """An :class:`~kb.spatial.predicates.Evaluator` with the object frames of :meth:`Looks.frames`."""

    def __init__(self, defs: Definitions, scene: Scene, tolerance: float, frames: Any) -> None:
        super().__init__(defs, scene, tolerance)
        self._frames = frames


def _repeats(rate: float) -> int:
    """Looks that all go wrong with a chance below :data:`SURE` at ``rate`` per look (1 for 0)."""
    if rate <= 0:
        return 1
    return max(1, math.ceil(math.log(SURE) / math.log(rate) - 1e-9))
