"""What a report is drawn from: a run's JSON report, or a campaign folder.

A run report is what ``kitkb run --report FILE`` writes (:meth:`kb.execution.records.RunRecord.report`
and what the CLI adds): one run, or the main job's ``{"runs": [...]}`` of several. A campaign
folder is what ``kitkb testmethod ... --out DIR`` writes: ``DIR/campaign.json`` and one run
report per trial in ``DIR/trials/<index:05d>.json``. Anything else is an
:class:`~kb.core.errors.InputError` (exit 2) naming the file, and the line for bad JSON.
"""

from __future__ import annotations

import json
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from kb.core.errors import InputError
from kb.core.files import note_input
from kb.core.limits import check_file_size

#: The keys every kitkb run report has (older reports and not-executed runs included).
RUN_KEYS = ("scenario", "goal_holds", "failures")
_TRIAL_NAME = re.compile(r"^(\d+)\.json$")


@dataclass
class Campaign:
    """A campaign folder read: ``meta`` is ``campaign.json``, ``trials`` the trial reports in
    index order, each with the path it was read from."""

    directory: Path
    meta: dict[str, Any]
    trials: list[tuple[Path, dict[str, Any]]] = field(default_factory=list)


def read_json(path: str | Path) -> Any:
    """The JSON value in ``path``; a file that is missing, too big or not JSON is an InputError."""
    p = Path(path)
    check_file_size(p)
    note_input(p)
    try:
        text = p.read_bytes().decode("utf-8-sig")
    except FileNotFoundError:
        raise InputError("no such file", p) from None
    except UnicodeDecodeError:
        raise InputError("not UTF-8 text, so not a JSON report", p) from None
    except OSError as exc:
        raise InputError(f"cannot read: {exc.strerror or exc}", p) from None
    try:
        return json.loads(text)
    except json.JSONDecodeError as exc:
        raise InputError(f"not JSON: {exc.msg} (column {exc.colno})", p, exc.lineno) from None
    except RecursionError:
        raise InputError("not a kitkb report: JSON nested too deeply", p) from None


def is_run_report(data: Any) -> bool:
    """True for a kitkb run report: one run, or several under ``runs``."""
    if not isinstance(data, dict):
        return False
    if isinstance(data.get("runs"), list):
        return all(is_run_report(r) for r in data["runs"])
    return (all(k in data for k in RUN_KEYS) and isinstance(data["scenario"], str)
            and isinstance(data["failures"], list))


def read_run(path: str | Path) -> dict[str, Any]:
    """The run report in ``path`` (InputError if it is not one)."""
    data = read_json(path)
    if not is_run_report(data):
        raise InputError("not a kitkb run report (a JSON object with scenario, goal_holds and failures, "
                         "as kitkb run --report writes)", path)
    return normalise(data)


def read_campaign(directory: str | Path) -> Campaign:
    """The campaign in folder ``directory``: ``campaign.json`` and its trials' reports."""
    folder = Path(directory)
    meta_path = folder / "campaign.json"
    if not meta_path.is_file():
        raise InputError("not a campaign folder: it has no campaign.json (kitkb testmethod --out writes one)",
                         folder)
    meta = read_json(meta_path)
    if not isinstance(meta, dict) or "method" not in meta:
        raise InputError("not a kitkb campaign file (a JSON object with method, seed, trials, summary)", meta_path)
    trials = []
    for number, path in sorted(_trial_files(folder / "trials")):
        data = read_json(path)
        if not is_run_report(data):
            raise InputError("not a kitkb trial report (a run report with scenario, goal_holds and failures)",
                             path)
        data = normalise(data)
        data.setdefault("trial", {}).setdefault("index", number)
        trials.append((path, data))
    return Campaign(folder, meta, trials)


def _trial_files(folder: Path) -> list[tuple[int, Path]]:
    if not folder.is_dir():
        return []
    found = []
    for path in folder.iterdir():
        match = _TRIAL_NAME.match(path.name)
        if match and path.is_file():
            found.append((int(match.group(1)), path))
    return found


def read_source(source: str | Path) -> dict[str, Any] | Campaign:
    """A run report (file) or a campaign (folder)."""
    p = Path(source)
    if p.is_dir():
        return read_campaign(p)
    if not p.exists():
        raise InputError("no such file or folder", p)
    return read_run(p)


#: The sections of a run report that hold lists of objects, and the list fields of those objects.
_LISTS = {"failures": ("objects", "violated"), "injected": ("objects",), "kits": ("lost",), "path": ("points",),
          "timeline": ("args", "objects")}
#: The sections that hold one object.
_OBJECTS = ("metrics", "scene", "trial", "units", "oracle", "commands")


def _records(value: Any, lists: tuple[str, ...]) -> list[dict[str, Any]]:
    """The objects of a list (anything else left out), their list fields lists."""
    out = []
    for item in value if isinstance(value, list) else []:
        if isinstance(item, dict):
            out.append({**item, **{k: item[k] if isinstance(item.get(k), list) else [] for k in lists if k in item}})
    return out


def normalise(report: dict[str, Any]) -> dict[str, Any]:
    """``report`` with every section the page draws of the shape it expects: a section of
    another shape left out (it is then said to be missing), list items that are not objects
    dropped, list fields that are not lists emptied. The page never fails on a report that
    is well-formed JSON, whatever its values."""
    out = dict(report)
    for key, lists in _LISTS.items():
        if key in out:
            if isinstance(out[key], list):
                out[key] = _records(out[key], lists)
            else:
                del out[key]
    for kit in out.get("kits", []):
        kit["lost"] = _records(kit.get("lost"), ("objects",))
    for key in _OBJECTS:
        if key in out and not isinstance(out[key], dict):
            del out[key]
    if "scene" in out:
        out["scene"] = {**out["scene"], "objects": _records(out["scene"].get("objects"), ())}
    if isinstance(out.get("metrics", {}).get("static"), (list, str, int, float)):
        out["metrics"] = {k: v for k, v in out["metrics"].items() if k != "static"}
    if isinstance(out.get("runs"), list):
        out["runs"] = [normalise(r) for r in out["runs"] if isinstance(r, dict)]
    return out
