"""The four test methods of the first paper (seed 000 §III) as seeded trials.

A campaign is a method, a seed and its options (:class:`Options`); trial ``i`` is a
:class:`Job` — everything a worker needs, and nothing else — made by :func:`jobs` from the
campaign alone, so the same campaign gives the same jobs wherever they run:

* **basic** (§III-B): one kit of a design known before the test (drawn from the campaign's seed:
  ``--parts`` parts of two or more types); its kit tray starts on the work table, and every trial
  places and turns the kit tray and the parts trays anew (:mod:`kb.scenario.placement`);
* **new-variety** (§III-C): as basic, but every trial's design is new (drawn from the trial's
  seed over the campaign's part types) and reaches the system as Turtle files: the trial records
  the time from their receipt to the first CRCL command sent to the cell;
* **multi** (§III-D): ``--kits`` kits of the designs of ``--parts`` (one size per design) in an
  order drawn from the trial's seed; kit trays come from the storage box and finished kits go to
  their boxes; the parts trays are placed and turned anew;
* **errors** (§III-E): basic with seeded faults and spare parts to recover with: by default each
  fault kind of the domain with a test-method rate (``soap:hasFaultKind_TestMethodRate``; the
  shipped ones are the paper's dropped and defective parts, missed grasps and moved parts:
  ``kitkb faults`` lists them), ``--faults`` sets others.

Any method's simulated sensor may err (``--sensor-noise``: every trial's cell has that noise and
its executor verifies with that accuracy). errors also sweeps a noise (``--noise-sweep
position=0mm:5mm:6``): every trial runs at every level, with the same seed, so the levels
differ only by the noise; row ``k`` of a sweep of ``L`` levels is trial ``k // L`` at level
``k % L`` (:meth:`Options.locate`).

Every trial's cell is opened by URL (:mod:`kb.cells`): by default ``sim:``, its own simulated
cell of its real placement; ``--cell URL`` (``Options.cell``) names one cell the campaign's
single trial runs on instead, its placement the cell's own (not the errors method: a real
cell's faults are its own). Fault mixes are checked by the simulated cell's opener, so this
package never imports ``kb.sim``.
"""

from __future__ import annotations

import dataclasses
import hashlib
import random
import re
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path
from typing import Any

from kb.cells.accuracy import KEYS, SensorAccuracy
from kb.cells.registry import DEFAULT_URL, CellRequest, check_cell, close_cell, open_cell, parse_cell_url
from kb.core.errors import InputError
from kb.core.limits import PARTS
from kb.model.faults import domain_fault_kinds
from kb.scenario.spec import DesignSpec, ScenarioSpec, method_spec, mixed_design, random_types, types_for

METHODS = ("basic", "new-variety", "multi", "errors")
#: parts of each type beyond what the kits need, per method (errors: see :func:`spare`)
SPARE = {"basic": 1, "new-variety": 1, "multi": 1, "errors": 3}
DEFAULT_PARTS = {"basic": (10,), "new-variety": (10,), "multi": (4, 6), "errors": (10,)}
DEFAULT_KITS = 3
#: trials of one campaign at most (each is a Dask task and a file)
MAX_TRIALS = 1_000_000


@dataclass(frozen=True)
class Options:
    """A campaign: its method, seed, number of trials and what its workstations hold."""

    method: str
    trials: int = 10
    seed: int = 0
    parts: tuple[int, ...] = ()  # parts per design (default per method: DEFAULT_PARTS)
    kits: int = DEFAULT_KITS  # multi: kits per trial
    faults: str | None = None  # errors: the fault mix (default: default_faults(domain))
    sensor_noise: str | None = None  # the sensor's accuracy, as --sensor-noise spells it
    noise_sweep: str | None = None  # errors: KEY=FROM:TO:N, the levels every trial runs at
    cell: str | None = None  # the cell's URL (None: every trial's own simulated cell, sim:)
    domain: tuple[str, ...] = ()  # --domain: extension files added to the shipped domain
    #: --partial-kits: a kit the parts cannot finish is delivered partial or left (None: the domain's policy)
    partial_kits: str | None = None

    def __post_init__(self) -> None:
        if self.method not in METHODS:
            raise InputError(f"unknown test method {self.method!r} (methods: {', '.join(METHODS)})")
        if not self.parts:
            object.__setattr__(self, "parts", DEFAULT_PARTS[self.method])
        if self.method == "errors" and self.faults is None:
            object.__setattr__(self, "faults", default_faults(self.domain))
        self._check()

    def _check(self) -> None:
        if not 1 <= self.trials <= MAX_TRIALS:
            raise InputError(f"--trials must be from 1 to {MAX_TRIALS:,} (got {self.trials:,})")
        for n in self.parts:
            if n < 2:
                raise InputError(f"--parts: a kit holds two or more parts (got {n})")
            PARTS.check(n, what=f"--parts {n:,}")
        if self.method != "multi" and len(self.parts) != 1:
            raise InputError(f"--parts: {self.method} builds one design, give one number (got {len(self.parts)})")
        if self.method == "multi":
            if len(self.parts) < 2:
                raise InputError("--parts: multi builds two or more designs, give one size each (e.g. 4,6)")
            if self.kits < len(self.parts):
                raise InputError(f"--kits ({self.kits}) must be at least the number of designs ({len(self.parts)})")
            PARTS.check(self.kits * max(self.parts), what=f"--kits {self.kits} of up to {max(self.parts)} parts")
        if self.faults is not None:
            if self.method != "errors":
                raise InputError(f"--faults is for the errors method, not {self.method}")
            _check_faults(self.faults, self.domain)
        base = _base_noise(self.sensor_noise)
        if self.noise_sweep is not None:
            _check_sweep(self, base)
        if self.cell is not None:
            _check_cell(self)
        if self.partial_kits is not None and self.partial_kits not in ("deliver", "leave"):
            raise InputError(f"--partial-kits must be deliver or leave (got {self.partial_kits!r})")

    def reach(self) -> None:
        """Refuse a ``--cell`` that does not answer before any trial runs (an InputError, exit
        2): the cell at its URL is opened once and closed (``sim:`` needs nothing)."""
        if self.cell is not None and not simulated(self.cell):
            close_cell(open_cell(self.cell, CellRequest()))

    @property
    def levels(self) -> int:
        """The noise levels each trial runs at (1 without a sweep)."""
        return len(sweep_levels(self.noise_sweep, self.sensor_noise)) if self.noise_sweep else 1

    @property
    def rows(self) -> int:
        """The campaign's rows (trial files): every trial at every level."""
        return self.trials * self.levels

    def locate(self, row: int) -> tuple[int, int | None]:
        """(trial, level) of row ``row`` (level None without a sweep)."""
        if self.noise_sweep is None:
            return row, None
        return divmod(row, self.levels)

    def noise_of(self, row: int) -> str | None:
        """The ``--sensor-noise`` text of row ``row``'s sensor (None: the state's own sensor):
        the campaign's, and for a sweep its level's value of the swept key, written exactly (SI)."""
        _trial, level = self.locate(row)
        if level is None:
            return self.sensor_noise
        name, kind = sweep_key(self.noise_sweep)
        item = f"{name}={sweep_values(self.noise_sweep)[level]!r}{KIND_UNIT[kind]}"
        return f"{self.sensor_noise},{item}" if self.sensor_noise else item

    def as_dict(self) -> dict[str, Any]:
        """What campaign.json keeps as ``options`` (what the trials depend on; the noise
        options only when given, so a campaign without them keeps the options it had)."""
        out: dict[str, Any] = {"parts": list(self.parts), "kits": self.kits if self.method == "multi" else None,
                               "faults": self.faults}
        if self.sensor_noise is not None:
            out["sensor_noise"] = self.sensor_noise
        if self.noise_sweep is not None:
            out["noise_sweep"] = self.noise_sweep
        if self.cell is not None:
            out["cell"] = self.cell
        if self.domain:
            out["domain"] = list(self.domain)
        if self.partial_kits is not None:
            out["partial_kits"] = self.partial_kits
        return out


#: the SI unit an exact value of each kind of noise key is written in
KIND_UNIT = {"length": "m", "angle": "rad", "rate": ""}


def _base_noise(text: str | None) -> Any:
    """The noise of ``--sensor-noise`` (None when not given); an InputError naming its item."""
    if text is None:
        return None
    try:
        return SensorAccuracy.parse(text)
    except ValueError as e:
        raise InputError(f"--sensor-noise: {e}") from None


def sweep_key(text: str) -> tuple[str, str]:
    """(field, kind) of the key a sweep ``KEY=FROM:TO:N`` varies (``misclass`` is
    ``misclassification``); an InputError for an unknown key."""
    key = text.partition("=")[0].strip().lower()
    if key not in KEYS:
        raise InputError(f"--noise-sweep {text}: {key!r} is not a noise key (keys: position, orientation, bias, "
                         "misdetection, misclass)")
    return KEYS[key]


@lru_cache(maxsize=16)
def sweep_levels(text: str, base: str | None = None) -> tuple[Any, ...]:
    """The :class:`~kb.cells.accuracy.SensorAccuracy` of each level of a sweep, over ``base``
    (the ``--sensor-noise`` text); an InputError for a malformed sweep."""
    try:
        return tuple(SensorAccuracy.sweep(text, _base_noise(base)))
    except ValueError as e:
        said = str(e)
        if repr(text) not in said:  # an end of the sweep read as its own item: say the sweep
            said = f"{text}: " + re.sub(r" \(item \d+ of '[^']*'\)$", "", said)
        raise InputError(f"--noise-sweep: {said}") from None


def sweep_values(text: str) -> list[float]:
    """The swept key's value at each level, in SI (metres, radians, a rate)."""
    name = sweep_key(text)[0]
    return [getattr(level, name) for level in sweep_levels(text)]


def _check_sweep(options: Options, base: Any) -> None:
    text = options.noise_sweep or ""
    if options.method != "errors":
        raise InputError(f"--noise-sweep is for the errors method, not {options.method}")
    name = sweep_key(text)[0]
    count = text.rpartition(":")[2].strip()
    if count.isdigit() and options.trials * int(count) > MAX_TRIALS:
        raise InputError(f"--noise-sweep {text}: {options.trials:,} trials at {int(count):,} levels are more than "
                         f"{MAX_TRIALS:,} runs")
    sweep_levels(text)
    if base is not None and options.sensor_noise is not None:
        given = {KEYS.get(item.partition("=")[0].strip().lower(), ("",))[0] for item in options.sensor_noise.split(",")}
        if name in given:
            raise InputError(f"--noise-sweep {text} and --sensor-noise {options.sensor_noise} both set {name}: "
                             "give it in one of them")


def simulated(url: str) -> bool:
    """True for a URL of the in-process simulator (``sim:``): every trial then has its own."""
    return parse_cell_url(url).scheme == "sim"


def _check_cell(options: Options) -> None:
    """``--cell``: ``sim:`` (no parameters: the options carry faults and noise, each trial its
    own seed and placement) or one cell every trial runs on, the real placement the cell's own:
    one trial (the cell keeps what the trial did), no injected faults, no noise sweep."""
    url = check_cell(options.cell)
    if url.scheme == "sim":
        if url.params:
            raise InputError(f"--cell {options.cell}: a campaign's simulated cells take no parameters (give "
                             "--faults or --sensor-noise; each trial has its own seed)")
        return
    if options.method == "errors":
        raise InputError(f"--cell {options.cell}: the errors method injects faults through its simulated cells; "
                         "a cell at a URL has its own faults (run basic, multi or new-variety against it)")
    if options.trials != 1:
        raise InputError(f"--cell {options.cell}: one trial per campaign on a cell at a URL (it keeps what a trial "
                         f"did: reset it, then run the next --seed), not {options.trials:,}")


def default_faults(domain: tuple[str, ...] = ()) -> str:
    """The errors method's faults unless ``--faults`` says otherwise: each fault kind of the
    domain (the shipped one with the extension files ``domain``) at its test-method rate, a
    chance per action it strikes (:meth:`kb.model.faults.FaultKinds.default_mix`)."""
    return domain_fault_kinds(domain).default_mix()


def _check_faults(text: str, domain: tuple[str, ...] = ()) -> None:
    """The simulated cell's own check of a fault mix, its kinds the domain's (through the
    registry: kb.sim not imported)."""
    try:
        check_cell(DEFAULT_URL, CellRequest(faults=text, fault_kinds=domain_fault_kinds(domain)))
    except InputError as e:
        raise InputError(f"--faults: {getattr(e, 'reason', e.message)}") from None


@dataclass(frozen=True)
class Job:
    """One trial, as a worker gets it: the nominal workstation (``spec``: what the system under
    test is told), the seed of the real placement and of the faults, and how to run it."""

    method: str
    index: int
    seed: int
    spec: ScenarioSpec
    faults: str | None = None
    deliver: bool = False  # new-variety: the design arrives as files, planned on receipt (never cached)
    order: tuple[str, ...] = field(default=())  # the designs of the kits, in the order asked
    noise: str | None = None  # the sensor's accuracy as --sensor-noise spells it (None: the state's sensor)
    sweep: tuple[int, int] | None = None  # in a noise sweep: (trial, level)
    cell: str | None = None  # the URL of the one cell the trial runs on (None: its own simulated cell)
    domain: tuple[str, ...] = ()  # extension files added to the shipped domain (--domain)
    partial_kits: str | None = None  # deliver | leave a kit the parts cannot finish (None: the domain's policy)

    def facts(self) -> dict[str, Any]:
        """The trial's facts known before it runs (its row's ``trial``): index, seed, method,
        designs, and the sensor noise (``noise``, spelled as --sensor-noise; ``sweep``: the
        trial and the level, in a sweep)."""
        out: dict[str, Any] = {"index": self.index, "seed": self.seed, "method": self.method,
                               "design": " ".join(self.order), "designs": list(self.order)}
        if self.noise is not None:
            out["noise"] = noise_label(self.noise)
        if self.sweep is not None:
            out["sweep"] = {"trial": self.sweep[0], "level": self.sweep[1]}
        return out


def noise_label(text: str) -> str:
    """A ``--sensor-noise`` text as :meth:`SensorAccuracy.text <kb.cells.accuracy.SensorAccuracy.text>`
    spells it (millimetres, degrees; "none" for an exact sensor), the label of a noise level."""
    return SensorAccuracy.parse(text).text()


def not_executed(job: Job, reason: str) -> dict[str, Any]:
    """The report of a trial whose run did not take place (as ``kitkb run``'s not executed)."""
    return {"scenario": job.spec.name, "seed": job.seed, "executed": False, "reason": reason, "goal_holds": False,
            "stopped": None, "injected": [], "failures": []}


def trial_seed(seed: int, index: int) -> int:
    """The seed of trial ``index`` of a campaign of ``seed`` (32 bits, from SHA-256)."""
    return int.from_bytes(hashlib.sha256(f"kitkb-testmethod/{seed}/{index}".encode()).digest()[:4], "big")


def design_seed(seed: int, design: int) -> int:
    """The seed of a campaign's design ``design`` (known before the test: not a trial's)."""
    return trial_seed(seed, -1 - design)


def jobs(options: Options, indices: list[int] | range | None = None) -> list[Job]:
    """The jobs of the campaign's rows (all, or ``indices``)."""
    indices = range(options.rows) if indices is None else indices
    return [job(options, i) for i in indices]


def job(options: Options, row: int) -> Job:
    """Row ``row`` of the campaign: its trial (``row`` itself without a sweep) at its noise."""
    trial, level = options.locate(row)
    extra: dict[str, Any] = {"noise": options.noise_of(row), "sweep": None if level is None else (trial, level),
                             "cell": options.cell if options.cell is not None and not simulated(options.cell) else None,
                             "domain": tuple(str(Path(d).resolve()) for d in options.domain),
                             "partial_kits": options.partial_kits}
    return dataclasses.replace(_job(options, trial), index=row, **extra)


def _job(options: Options, index: int) -> Job:
    """Trial ``index`` of the campaign (as if no noise)."""
    seed = trial_seed(options.seed, index)
    method = options.method
    types = random_types(types_for(max(options.parts)), options.seed)
    name = f"testmethod-{method}"
    if method in ("basic", "errors"):
        design = mixed_design(types, options.parts[0], design_seed(options.seed, 0), "kit_design_1")
        spec = method_spec(name, types, (design,), (0,), spare=spare(method, options.parts[0]),
                           kit_trays_on_table=True)
        return Job(method, index, seed, spec, options.faults, order=(design.name,))
    if method == "new-variety":
        design = mixed_design(types, options.parts[0], seed, f"kit_design_new_{index + 1}")
        spec = method_spec(f"{name}-{index + 1}", types, (design,), (0,), spare=SPARE[method],
                           kit_trays_on_table=True)
        return Job(method, index, seed, spec, deliver=True, order=(design.name,))
    designs = tuple(mixed_design(types, n, design_seed(options.seed, d), f"kit_design_{d + 1}")
                    for d, n in enumerate(options.parts))
    kits = _order(len(designs), options.kits, seed)
    spec = method_spec(name, types, designs, kits, spare=SPARE[method])
    return Job(method, index, seed, spec, order=tuple(designs[d].name for d in kits))


def spare(method: str, parts: int) -> int:
    """Spare parts of each type: :data:`SPARE`; for errors, at least half the kit's size, so that
    a trial's faults exhaust a parts tray seldom (the test is the recovery, not the supply)."""
    return max(SPARE[method], parts // 2) if method == "errors" else SPARE[method]


def _order(designs: int, kits: int, seed: int) -> tuple[int, ...]:
    """``kits`` design indices in a pseudo-random order, every design at least once."""
    rng = random.Random(seed)
    order = list(range(designs)) + [rng.randrange(designs) for _ in range(kits - designs)]
    rng.shuffle(order)
    return tuple(order)


def designs_of(spec: ScenarioSpec) -> list[DesignSpec]:
    """The designs of a job's workstation, in kit order."""
    return [spec.designs[d] for d in spec.kits]
