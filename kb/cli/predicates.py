"""``kitkb predicates``: the predicates that hold in a state file, computed from its geometry."""

from __future__ import annotations

import json
from pathlib import Path

from kb.cli.output import Output
from kb.core.namespaces import SOAP
from kb.io.loader import Source, domain_knowledge, load, reading_notes
from kb.io.vocabulary import not_understood
from kb.model.definitions import Definitions, locator, read_definitions
from kb.spatial import DEFAULT_TOLERANCE, Evaluator, Scene


def predicates(state: list[str], goal: str | None, match_names: bool, domain: list[str] | None,
               predicate: list[str] | None, tolerance: float | None, format: str, out: Output) -> int:
    """Print every true atom ``name(arg1, arg2)`` (JSON: objects with ``predicate`` and ``args``).
    Input in which nothing is understood (no predicate definition in ``--domain``, no placed
    object in the state files) is an InputError saying what was looked for; the parts of the
    files that are not read are warnings."""
    with out.progress(f"deciding the predicates of {', '.join(Path(s).name for s in state)} from geometry"):
        with reading_notes() as notes:
            try:
                defs = _definitions(domain)
                scene = _scene(state, goal, match_names)
            finally:
                for note in notes:
                    out.warn(note.format())
        facts = Evaluator(defs, scene, DEFAULT_TOLERANCE if tolerance is None else tolerance).facts(predicate)
    if format == "json":
        items = [{"predicate": name, "args": [_local(a) for a in args]} for name, args in facts]
        print(json.dumps(items, indent=1), file=out.results)
    else:
        for name, args in facts:
            print(f"{name}({', '.join(_local(a) for a in args)})", file=out.results)
    return 0


def _definitions(domain: list[str] | None) -> Definitions:
    """The predicate definitions of the shipped kitting domain and the extension files ``domain``."""
    kb = domain_knowledge(domain)
    defs = read_definitions(kb.graph, locator(kb))
    given = {Path(d).resolve() for d in domain or ()}
    named = [s for s in kb.sources if s.path.resolve() in given]
    if named and not any(_defines_predicate(s) for s in named):
        raise not_understood(f"no predicate definition kitkb reads in {', '.join(Path(d).name for d in domain)} "
                             "(it looked for individuals of soap:Predicate with a soap:hasPredicate_Definition)",
                             (t for s in named for t in s.triples()), domain[0])
    return defs


def _defines_predicate(source: Source) -> bool:
    """Whether ``source`` says anything in kitkb's SOAP vocabulary (an extension may add only
    actions or failure modes; one that states nothing of it, such as NIST's own SOAP file,
    defines no predicate kitkb reads)."""
    soap = str(SOAP)
    return any(str(p).startswith(soap) or str(o).startswith(soap) for _s, p, o in source.triples())


def _scene(state: list[str], goal: str | None, match_names: bool) -> Scene:
    """The scene of the state files; InputError when no object in them is placed."""
    sources = load(list(state), resolve_imports=False).sources
    scene = Scene.from_sources(sources, declared=[goal] if goal else (), match_names=match_names)
    if not scene.placed.any():
        raise not_understood("no placed object kitkb reads (it looked for individuals of the kitting model's "
                             "solid objects with a ktw:hasSolidObject_PrimaryLocation pose)",
                             (t for s in sources for t in s.triples()), state[0])
    return scene


def _local(iri: str) -> str:
    return iri.rsplit("#", 1)[-1].rsplit("/", 1)[-1]
