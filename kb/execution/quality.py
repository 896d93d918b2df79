"""Detection quality: how well a campaign's runs caught the faults injected into them.

A verification system is judged by two numbers, the faults it catches and the false alarms it
raises. Scored from run reports alone (:meth:`RunRecord.report
<kb.execution.records.RunRecord.report>`: ``injected`` is the simulator's ground truth,
``failures`` the executor's diagnoses), against the fault kinds of the domain
(:class:`kb.model.faults.FaultKinds`, default the shipped domain's): the failure modes a fault
of each kind may be diagnosed as (``soap:hasFaultKind_DiagnosedBy``), whether every injection
of it must be detected, and whether its right diagnosis rejects the object:

* :func:`score` matches every failure of one report to an injected fault (an object named in
  both, the failure at or after the injection: the latest such injection) and judges its mode
  (correct, wrong, or unmatched: no fault behind it);
* :func:`score_detection` adds up reports per fault kind: injected, detected, diagnosed right,
  diagnosed wrong, missed, absorbed (a fault of a kind that need not be detected, e.g. a moved
  object late binding found where it now is) and moot (a fault on an object already rejected),
  and the false alarms (diagnoses with no fault behind them) per failure mode, over the actions
  checked;
* :func:`by_noise` does it per sensor accuracy (the report's ``sensor``), for a sweep.

A report naming a kind the domain does not declare is an :class:`~kb.core.errors.InputError`
(score it with the domain it ran in). ``benchmarks/bench_execution.py`` (the fault campaign) and
``benchmarks/bench_noise.py`` (the same under sensor noise) score with these.
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass, field
from typing import Any, Iterable

from kb.cells.accuracy import SensorAccuracy
from kb.core.errors import InputError
from kb.model.faults import FaultKind, FaultKinds, shipped_fault_kinds


def _kind(kinds: FaultKinds, name: str) -> FaultKind:
    kind = kinds.get(name)
    if kind is None:
        raise InputError(f"a run report names fault kind {name!r}, which the domain does not declare "
                         f"(known: {', '.join(kinds.names) or 'none'}); score it with the domain it ran in")
    return kind


def score(rep: dict, kinds: FaultKinds | None = None) -> dict:
    """Match every failure of a run's report to an injected fault (an object named in both, and
    the failure at or after the injection: the latest such injection) and judge its mode against
    the right diagnoses of its kind (``kinds``: the domain's; None: the shipped domain's).

    Returns ``verdicts`` (per failure: correct, wrong, unmatched), ``matched_to`` (per failure:
    the injection's index or None), ``detected`` and ``moot`` (per injection)."""
    kinds = kinds if kinds is not None else shipped_fault_kinds()
    injected = rep.get("injected", [])
    matched_to: list[int | None] = []
    verdicts = []
    for f in rep.get("failures", []):
        objs = set(f["objects"])
        cands = [j for j, x in enumerate(injected) if objs & set(x["objects"]) and f["action_index"] >= x["action_index"]]
        j = max(cands, key=lambda j: (injected[j]["action_index"], j)) if cands else None
        matched_to.append(j)
        if j is None:
            verdicts.append("unmatched")
        else:
            verdicts.append("correct" if f["mode"] in _kind(kinds, injected[j]["kind"]).diagnosed_by else "wrong")
    detected = [any(m == j for m in matched_to) for j in range(len(injected))]
    # a fault on an object the run had already rejected (the right diagnosis of a rejecting kind)
    # needs no detection: the executor never takes that object again (it rebinds without a new check)
    rejecting = kinds.rejecting_modes()
    rejected = [(f["action_index"], o) for f in rep.get("failures", []) if f["mode"] in rejecting
                for o in f["objects"][:1]]
    moot = [any(i < x["action_index"] and o == x["objects"][0] for i, o in rejected) for x in injected]
    return {"verdicts": verdicts, "matched_to": matched_to, "detected": detected, "moot": moot}


@dataclass
class KindQuality:
    """The injections of one fault kind: how many were caught and diagnosed how."""

    injected: int = 0
    detected: int = 0
    right: int = 0  # detected, and a failure matched to it has an allowed mode
    wrong: int = 0  # detected, every failure matched to it has a mode not allowed
    missed: int = 0  # not detected, though its kind must be
    absorbed: int = 0  # not detected, and its kind need not be (late binding found the object)
    moot: int = 0  # on a part already rejected: nothing to detect

    @property
    def needing(self) -> int:
        """Injections that needed a diagnosis: detected ones and missed ones."""
        return self.detected + self.missed

    def as_dict(self) -> dict[str, int]:
        return {"injected": self.injected, "detected": self.detected, "diagnosed_right": self.right,
                "diagnosed_wrong": self.wrong, "missed": self.missed, "absorbed": self.absorbed, "moot": self.moot}


@dataclass
class DetectionQuality:
    """A campaign's detection quality: per fault kind, false alarms, and what they were out of."""

    kinds: dict[str, KindQuality] = field(default_factory=dict)
    false_alarms: Counter = field(default_factory=Counter)  # failure mode -> diagnoses with no fault behind
    runs: int = 0
    actions: int = 0  # actions attempted (each checked), over all runs
    failures: int = 0
    uncertain: int = 0  # failures that said they were not certain (a noisy sensor's)
    undecidable: int = 0  # atoms noise made undecidable (reports with a sensor)

    @property
    def total(self) -> KindQuality:
        out = KindQuality()
        for q in self.kinds.values():
            for name in ("injected", "detected", "right", "wrong", "missed", "absorbed", "moot"):
                setattr(out, name, getattr(out, name) + getattr(q, name))
        return out

    @property
    def false_alarm_count(self) -> int:
        return sum(self.false_alarms.values())

    def rates(self) -> dict[str, float | None]:
        """Detection rate (detected / needing detection), right-diagnosis rate (right /
        injected that needed a diagnosis) and false alarms per 10,000 actions."""
        t = self.total
        return {"detection": t.detected / t.needing if t.needing else None,
                "diagnosed_right": t.right / t.needing if t.needing else None,
                "false_alarms_per_10k_actions": 1e4 * self.false_alarm_count / self.actions if self.actions else None}

    def as_dict(self) -> dict[str, Any]:
        return {"runs": self.runs, "actions": self.actions, "failures": self.failures, "uncertain": self.uncertain,
                "undecidable": self.undecidable, "kinds": {k: q.as_dict() for k, q in self.kinds.items()},
                "total": self.total.as_dict(), "false_alarms": dict(self.false_alarms), **self.rates()}


def score_detection(reports: Iterable[dict], kinds: FaultKinds | None = None) -> DetectionQuality:
    """Detection quality of run reports (each a :meth:`RunRecord.report
    <kb.execution.records.RunRecord.report>`, or the same keys: ``injected``, ``failures``,
    and ``attempts`` or ``timeline`` or ``actions`` for the actions checked), against the fault
    kinds ``kinds`` (None: the shipped domain's)."""
    kinds = kinds if kinds is not None else shipped_fault_kinds()
    out = DetectionQuality()
    for rep in reports:
        out.runs += 1
        out.actions += _attempts(rep)
        sc = score(rep, kinds)
        failures = rep.get("failures", [])
        out.failures += len(failures)
        out.uncertain += sum(1 for f in failures if f.get("certainty") == "uncertain")
        out.undecidable += int((rep.get("sensor") or {}).get("undecidable", 0))
        for f, verdict in zip(failures, sc["verdicts"]):
            if verdict == "unmatched":
                out.false_alarms[f["mode"]] += 1
        for j, x in enumerate(rep.get("injected", [])):
            q = out.kinds.setdefault(x["kind"], KindQuality())
            q.injected += 1
            verdicts = [v for m, v in zip(sc["matched_to"], sc["verdicts"]) if m == j]
            if sc["detected"][j]:
                q.detected += 1
                if "correct" in verdicts:
                    q.right += 1
                else:
                    q.wrong += 1
            elif sc["moot"][j]:
                q.moot += 1
            elif _kind(kinds, x["kind"]).must_detect:
                q.missed += 1
            else:
                q.absorbed += 1
    return out


def by_noise(reports: Iterable[dict], kinds: FaultKinds | None = None) -> dict[str, DetectionQuality]:
    """:func:`score_detection` per sensor accuracy (the report's ``sensor.accuracy``, written
    as ``--sensor-noise`` spells it; "none" for an exact sensor), in the order first met."""
    groups: dict[str, list[dict]] = {}
    for rep in reports:
        groups.setdefault(noise_key(rep), []).append(rep)
    return {k: score_detection(v, kinds) for k, v in groups.items()}


def noise_key(rep: dict) -> str:
    """The sensor accuracy of a report as ``--sensor-noise`` spells it ("none": exact)."""
    acc = (rep.get("sensor") or {}).get("accuracy")
    if not acc:
        return "none"
    return SensorAccuracy(**acc).text()


def _attempts(rep: dict) -> int:
    if "attempts" in rep:
        return int(rep["attempts"])
    timeline = rep.get("timeline")
    if timeline is not None:
        return sum(1 for e in timeline if e.get("kind") == "action")
    return int(rep.get("actions", 0))
