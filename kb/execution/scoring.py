"""What a run's metrics and report need from the executor's belief: the goal's kits as
:mod:`kb.metrics.kits` scores them, the objects as a report draws them, and the CRCL text of a
program sent (kept per action: :attr:`kb.execution.records.ActionRecord.programs`); and what
the oracle of what was buildable (:mod:`kb.metrics.oracle`) is fed at the end of a run: the
cell's part fates, the goal's kits from the initial state, never the belief
(:func:`note_buildable`)."""

from __future__ import annotations

import logging
from typing import Any, Iterable, Sequence

import numpy as np

from kb.core.namespaces import KTW
from kb.crcl import Command, Program, write_text
from kb.crcl.cell import has
from kb.execution.belief import SKU_OF, Belief
from kb.execution.records import RunRecord, local
from kb.metrics.kits import KitGoal, Slot
from kb.metrics.oracle import buildable
from kb.model.soap import DomainSpec
from kb.planning.problem import ProblemSpec
from kb.planning.state import pddl_name
from kb.spatial.scene import Scene

#: the class a report names an object by: the first of these it is of (else its first class)
SHOWN_CLASSES = ("Kit", "KitTray", "Part", "PartsTray", "EndEffector", "EndEffectorHolder", "EndEffectorChangingStation",
                 "Robot", "LargeBoxWithKits", "LargeBoxWithEmptyKitTrays", "LargeContainer", "WorkTable", "PartsBin")


def crcl_lines(commands: Iterable[Command]) -> list[str]:
    """A program's statements in the first paper's CRCL text form, one line per command (NIST's
    form puts a MoveThroughTo on several lines and refuses what its parser cannot read)."""
    return write_text(Program(list(commands)), style="paper").splitlines()


def kit_goals(belief: Belief, spec: ProblemSpec, by_name: dict[str, str]) -> list[KitGoal]:
    """The kits the goal names (an argument of a goal atom, of class Kit), each with its design's
    kit tray SKU and slots and the box the goal puts it in (``kit-location-lbwk``)."""
    kits: dict[str, str | None] = {}
    kit_class = str(KTW.Kit)
    for atom in spec.goal:
        for name in atom[1:]:
            iri = by_name.get(name, name)
            if iri in belief.index and kit_class in belief.classes[belief.index[iri]]:
                kits.setdefault(iri, None)
        if atom[0] == "kit-location-lbwk" and len(atom) == 3:
            kits[by_name.get(atom[1], atom[1])] = by_name.get(atom[2], atom[2])
    out = []
    for kit, box in kits.items():
        designs = belief.related(str(KTW.hasKit_Design), kit)
        design = designs[0] if designs else None
        slots: list[Slot] = []
        tray_sku = None
        if design is not None:
            skus = belief.related(str(KTW.hasKitDesign_KitTraySku), design)
            tray_sku = skus[0] if skus else None
            for prp in belief.related(str(KTW.hasKitDesign_PartRefAndPose), design):
                sku = belief.related(str(KTW.hasPartRefAndPose_Sku), prp)
                pose = belief.slots.get(prp)
                if sku and pose is not None:
                    slots.append(Slot(prp, sku[0], np.asarray(pose, float)))
        out.append(KitGoal(kit, design, tray_sku, tuple(slots), box))
    return out


def scene_data(belief: Belief) -> dict[str, Any]:
    """Every object with a box: its name, class, box in its own frame, global pose at the start
    and now (None: not placed), in metres."""
    objects = []
    for i, name in enumerate(belief.names):
        lo, hi = belief.local_lo[i], belief.local_hi[i]
        if np.isnan(lo[0]):
            continue
        classes = {local(c) for c in belief.classes[i]}
        shown = next((c for c in SHOWN_CLASSES if c in classes), min(classes) if classes else "Thing")
        initial, final = belief.initial[i], belief.poses[i]
        objects.append({"name": local(name), "class": shown, "lo": _r(lo), "hi": _r(hi),
                        "initial": None if np.isnan(initial[0, 0]) else [_r(row) for row in initial],
                        "final": None if np.isnan(final[0, 0]) else [_r(row) for row in final]})
    return {"objects": objects}


def _r(values: Iterable[float]) -> list[float]:
    return [round(float(v), 6) for v in values]


def delivered_kits(actions: Iterable[tuple[str, Sequence[str]]], domain: DomainSpec,
                   spec: ProblemSpec) -> list[str]:
    """The goal's kits the done ``actions`` (each its name and arguments: IRIs or local names)
    brought where the goal wants them, one entry per delivering action, in order. An action
    delivers a kit when one of its effects, read from the domain, makes true a goal atom whose
    first argument is that kit (kitkb's domain: put-kit's ``kit-location-lbwk``; an extension's
    own delivering action the same way). What ``kitkb run`` lists as the kits of a run and a
    test method's trial as the kits built."""
    goal = {tuple(g) for g in spec.goal}
    kits = {name for name, (kind, _iri) in spec.objects.items() if kind == str(KTW.Kit)}
    specs = {a.name: a for a in domain.actions}
    out: list[str] = []
    for name, args in actions:
        action = specs.get(name)
        if action is None:
            continue
        bound = dict(zip((p for p, _ in action.params), (pddl_name(a) for a in args)))
        for atom in action.effects:
            ground = (atom.predicate, *(bound.get(a, "") for a in atom.args))
            if not atom.negated and len(ground) > 1 and ground[1] in kits and ground in goal:
                out.append(ground[1])
                break
    return out


log = logging.getLogger("kitkb.execution")

#: what a run's ``oracle`` says when its cell tells no part fates (a real cell, a served one)
NO_FATES = "the cell tells no ground truth of its parts: what was buildable is unknown"


def note_buildable(record: RunRecord, cell: Any, scene: Scene, spec: ProblemSpec) -> None:
    """``record.oracle``: what was buildable (:func:`kb.metrics.oracle.buildable`) from the
    fates ``cell`` tells (its ``part-fates`` capability, :class:`kb.crcl.cell.PartFates`), the
    goal's kits and the SKUs of the run's initial state ``scene`` (read anew, not the belief),
    the kits ``record.kits`` scores with every point; a cell without part fates: the oracle
    says why it is unknown (``kits_buildable`` and ``completion`` null)."""
    if not has(cell, "part-fates"):
        record.oracle = {"unknown": NO_FATES}
        return
    initial = Belief(scene)
    goals = kit_goals(initial, spec, {name: iri for name, (_kind, iri) in spec.objects.items()})
    recorded: dict[str, str] = {}
    for s, o in sorted(scene.facts.get(SKU_OF, ())):
        recorded.setdefault(s, o)
    built = [k.kit for k in record.kits if k.score == k.max_score]
    try:
        fates = cell.part_fates()
    except Exception as exc:  # noqa: BLE001 - a cell that cannot tell them: unknown, the run stands
        log.exception("the cell's part fates could not be read")
        record.oracle = {"unknown": f"the cell's part fates could not be read: {type(exc).__name__}: {exc}"}
        return
    record.oracle = buildable(fates, goals, recorded, built).as_dict()
