"""``kitkb predicates``: the predicates that hold in a state file, computed from its geometry."""

from __future__ import annotations

import json
from pathlib import Path

from kb.cli.output import Output
from kb.spatial import true_predicates


def predicates(state: list[str], goal: str | None, match_names: bool, domain: list[str] | None,
               predicate: list[str] | None, tolerance: float | None, format: str, out: Output) -> int:
    """Print every true atom ``name(arg1, arg2)`` (JSON: objects with ``predicate`` and ``args``)."""
    with out.progress(f"deciding the predicates of {', '.join(Path(s).name for s in state)} from geometry"):
        facts = true_predicates(state, goal=goal, match_names=match_names, domain_files=domain,
                                names=predicate, tolerance=tolerance)
    if format == "json":
        items = [{"predicate": name, "args": [_local(a) for a in args]} for name, args in facts]
        print(json.dumps(items, indent=1), file=out.results)
    else:
        for name, args in facts:
            print(f"{name}({', '.join(_local(a) for a in args)})", file=out.results)
    return 0


def _local(iri: str) -> str:
    return iri.rsplit("#", 1)[-1].rsplit("/", 1)[-1]
