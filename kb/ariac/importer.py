"""``kitkb ariac import TRIAL.yaml -o DIR``: a trial as kitkb's initial and goal states.

Writes ``DIR/init.ttl`` and ``DIR/goal.ttl`` (complete Turtle data files importing the kitting
model, :mod:`kb.ariac.states` lays them out) and ``DIR/ariac.json``, the trial as kitkb
modelled it (its orders, challenges, which object stands for which of ARIAC's: what the ARIAC
scorer reads beside a run's report, :mod:`kb.ariac.scoring`). What kitkb does not model is
named in a warning and skipped: assembly and combined orders, the conveyor belt, parts placed
on AGVs at the start (assembly's input), the human, the time limit, orders over time.
"""

from __future__ import annotations

import json
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from kb.ariac import states
from kb.ariac.trial import Trial, read_trial
from kb.core.errors import InputError
from kb.core.files import atomic_paths
from kb.core.namespaces import SCENARIO
from kb.scenario.turtle import header, write_turtle

MANIFEST = "ariac.json"
FORMAT = "kitkb-ariac-1"


@dataclass
class Imported:
    """What an import wrote and said."""

    trial: Trial
    init: Path
    goal: Path
    manifest: Path
    warnings: list[str] = field(default_factory=list)
    data: dict[str, Any] = field(default_factory=dict)


def import_trial(path: str | Path, out_dir: str | Path, *, name: str | None = None) -> Imported:
    """Read the trial at ``path`` and write its states and manifest into ``out_dir`` (all three
    files or none)."""
    trial = read_trial(path)
    warnings = skipped(trial)
    scenario = _name(name or Path(path).stem)
    lay = states.lay_out(trial, f"{SCENARIO}ariac-{scenario}#", warnings)
    out = Path(out_dir)
    if out.exists() and not out.is_dir():
        raise InputError("output path exists and is not a folder", file=out)
    targets = [out / "init.ttl", out / "goal.ttl", out / MANIFEST]
    data = manifest(lay, scenario, warnings)
    with atomic_paths(targets) as temps:
        for state, temp in zip(("init", "goal"), temps):
            with open(temp, "w", encoding="utf-8", newline="\n") as f:
                write_turtle(f, header(lay.namespace, f"{SCENARIO}ariac-{scenario}/{state}", _comment(lay, state)),
                             states.state_blocks(lay, goal=state == "goal"))
        Path(temps[2]).write_text(json.dumps(data, indent=1) + "\n", encoding="utf-8")
    return Imported(trial, targets[0], targets[1], targets[2], warnings, data)


def _name(stem: str) -> str:
    return re.sub(r"[^A-Za-z0-9_.-]", "_", stem) or "trial"


def _comment(lay: states.Layout, state: str) -> str:
    what = "initial state" if state == "init" else "goal state (every kitting order's kit in its shipment)"
    return (f"NIST ARIAC trial {lay.trial.path}: {what}.\n"
            f"{len(lay.parts)} part(s) in bins, {len(lay.trays)} kit tray(s), {len(lay.kits)} kitting order(s).\n"
            "Written by kitkb ariac import (kb.ariac); ARIAC's world frame, metres, radians, kilograms.")


def skipped(trial: Trial) -> list[str]:
    """A warning for each part of ``trial`` kitkb does not model."""
    out = []
    for o in trial.orders:
        if o.type != "kitting":
            article = "an" if o.type == "assembly" else "a"
            out.append(f"{o.where}: order {o.id} is {article} {o.type} order: kitkb models kitting only, skipped")
    if trial.conveyor is not None and trial.conveyor.get("active", False):
        n = sum(lot["number"] for lot in trial.conveyor["parts"])
        out.append(f"{trial.conveyor_where}: the conveyor belt ({n} part(s)) is not modelled (kitkb's cell has no "
                   "moving parts): its parts are not available")
    for agv, spec in sorted(trial.agv_parts.items()):
        bad = f" ({'; '.join(spec['bad'])} is not an angle)" if spec["bad"] else ""
        out.append(f"{spec['where']}: parts on AGV {agv} at the start ({len(spec['parts'])} on tray "
                   f"{spec['tray_id']}, assembly's input) are not modelled, skipped{bad}")
    for c in trial.challenges:
        if c.kind == "human":
            out.append(f"{c.where}: the human challenge is not modelled (kitkb's cell has one robot and no people), "
                       "skipped")
    flipped = [p for p in trial.bin_parts if p.flipped]
    if flipped:
        out.append(f"{flipped[0].where}: {len(flipped)} flipped part(s) lie upside down; kitkb's domain has no "
                   "action that turns a part over, so the import puts them in kits only when no upright part "
                   "of their type and colour is left")
    if trial.time_limit > 0:
        out.append(f"{trial.path}: time_limit {trial.time_limit:g} s is not enforced")
    timed = [o for o in trial.kitting_orders if o.announcement.kind != "time" or o.announcement.time]
    if timed:
        out.append(f"{timed[0].where}: kitting orders announced later ({', '.join(o.id for o in timed)}) are "
                   "planned from the start with the others (orders over time are not modelled)")
    return out


def manifest(lay: states.Layout, scenario: str, warnings: list[str]) -> dict[str, Any]:
    """The trial as modelled: orders, challenges, and ARIAC's names of kitkb's objects."""
    trial = lay.trial
    return {
        "format": FORMAT,
        "trial": str(trial.path),
        "scenario": scenario,
        "time_limit": trial.time_limit,
        "orders": [{
            "id": o.id, "type": o.type, "priority": o.priority, "announcement": o.announcement.as_dict(),
            **({"agv": o.kitting.agv, "tray_id": o.kitting.tray_id, "destination": o.kitting.destination,
                "destination_value": o.kitting.destination_value,
                "products": [{"type": p.type, "color": p.color, "quadrant": p.quadrant} for p in o.kitting.products]}
               if o.kitting else {}),
        } for o in trial.orders],
        "kits": [{"order": k.order.id, "kit": k.name, "design": k.design, "tray": k.tray, "shipment": k.shipment,
                  "slots": {str(q): part for q, _, _, part in k.slots}} for k in lay.kits],
        "shipments": {k.shipment: {"order": k.order.id, "agv": k.order.kitting.agv,  # type: ignore[union-attr]
                                   "destination": k.order.kitting.destination,  # type: ignore[union-attr]
                                   "destination_value": k.order.kitting.destination_value,  # type: ignore[union-attr]
                                   "container": f"{k.shipment}_box"} for k in lay.kits},
        "parts": {p.name: {"type": p.part.type, "color": p.part.color, "bin": p.part.bin, "slot": p.part.slot,
                           "flipped": p.part.flipped} for p in lay.parts},
        "trays": {n: {"tray_id": t.tray_id, "slot": t.slot} for n, t in lay.trays},
        "challenges": [{"kind": c.kind, **c.fields, **({"condition": c.condition.as_dict()} if c.condition else {}),
                        "line": c.where.line} for c in trial.challenges],
        "warnings": warnings,
    }


def read_manifest(path: str | Path) -> dict[str, Any]:
    """An import's ``ariac.json`` (``path``: the file, or the folder or a state file beside it)."""
    p = Path(path)
    if p.is_dir():
        p = p / MANIFEST
    elif p.name != MANIFEST:
        p = p.parent / MANIFEST
    try:
        data = json.loads(p.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise InputError(f"no {MANIFEST} here: ARIAC scoring needs the states kitkb ariac import wrote "
                         "(their ariac.json beside init.ttl)", file=p) from None
    except (OSError, ValueError) as e:
        raise InputError(f"cannot read the ARIAC manifest: {e}", file=p) from None
    if not isinstance(data, dict) or data.get("format") != FORMAT:
        raise InputError(f"not a kitkb ARIAC manifest (format {FORMAT!r} expected)", file=p)
    return data
