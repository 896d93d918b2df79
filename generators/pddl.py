"""PDDL generator: a :class:`~kb.planning.KittingModel` as PDDL, with unified-planning's writer.

The PDDL text is entirely unified-planning's ``PDDLWriter`` output. PDDLWriter has no
notion of comments, so the only post-processing is inserting ``;`` comment lines: a
``; source: <IRI>`` line before each predicate, function and action naming the ontology
individual it was generated from, one per type naming its class, and in the problem one
per object naming its individual.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, ClassVar, Sequence

from kb.core.generators import Generator
from kb.core.namespaces import local_name
from kb.patches.unified_planning import environment
from kb.planning import KittingModel, domain_model, kitting_model


class PddlGenerator(Generator):
    """The PDDL domain (``domain.pddl``) and, when the model has one, problem (``problem.pddl``)."""

    name: ClassVar[str] = "pddl"
    file_extension: ClassVar[str] = ".pddl"

    def __init__(self, model: KittingModel):
        self.model = model
        self._texts: tuple[str, str | None] | None = None

    @classmethod
    def from_files(cls, init: Sequence[str | Path], goal: Sequence[str | Path], encoding: str = "strips",
                   match_names: bool = False) -> PddlGenerator:
        """The domain and the problem of going from the ``init`` state files to the ``goal`` ones."""
        return cls(kitting_model(init, goal, encoding, match_names=match_names))

    @classmethod
    def domain_only(cls, encoding: str = "strips", domain_files: Sequence[str | Path] | None = None) -> PddlGenerator:
        """The domain of ``kitting-domain.ttl`` (or ``domain_files``) alone."""
        return cls(domain_model(encoding, domain_files))

    def texts(self) -> tuple[str, str | None]:
        """Domain and problem text (problem None when the model has no objects); built once."""
        if self._texts is None:
            self._texts = pddl_texts(self.model)
        return self._texts

    def serialize(self) -> str:
        """The domain text."""
        return self.texts()[0]

    def outputs(self) -> dict[str, str]:
        """``domain.pddl`` and, with a problem, ``problem.pddl``."""
        domain, problem = self.texts()
        return {"domain.pddl": domain} | ({"problem.pddl": problem} if problem is not None else {})


def _writer(model: KittingModel) -> Any:
    environment()
    from unified_planning.io import PDDLWriter

    return PDDLWriter(model.up_problem)


def pddl_texts(model: KittingModel) -> tuple[str, str | None]:
    """Domain and problem text (problem None when the model has no objects)."""
    writer = _writer(model)
    domain = annotate_domain(writer.get_domain(), model, writer)
    problem = annotate_problem(writer.get_problem(), model, writer) if model.problem else None
    return domain, problem


def _sources(model: KittingModel, writer: Any) -> dict[str, str]:
    """PDDL name (as written) -> source IRI, for predicates, functions and actions."""
    up = model.up_problem
    out: dict[str, str] = {}
    for sig in list(model.domain.predicates.values()) + list(model.domain.functions.values()):
        out[writer.get_pddl_name(up.fluent(sig.name))] = sig.source
    for action in model.domain.actions:
        out[writer.get_pddl_name(up.action(action.name))] = action.source
    return out


def annotate_domain(text: str, model: KittingModel, writer: Any) -> str:
    """Insert source comments into the domain text written by PDDLWriter."""
    sources = _sources(model, writer)
    types = {writer.get_pddl_name(t): iri for iri, t in _user_types(model).items()}
    out = [f"; kitkb PDDL domain ({model.encoding} encoding), generated from the SOAP instances",
           f"; of <{model.domain.source}> with unified-planning's PDDLWriter."]
    if model.encoding == "strips":
        out.append("; Counts are compiled into token objects (see kb/planning/strips.py).")
    for line in text.splitlines():
        stripped = line.strip()
        if stripped.startswith("(:types"):
            out += [f"; type {name}: <{iri}>" for name, iri in sorted(types.items())]
        elif stripped.startswith("(:action "):
            name = stripped.split()[1]
            if name in sources:
                out.append(f" ; source: <{sources[name]}>")
        elif stripped.startswith("(") and not stripped.startswith("(:") and not stripped.startswith("(define"):
            name = stripped[1:].split()[0].rstrip(")")
            if name in sources:
                out.append(f"             ; source: <{sources[name]}>")
        out.append(line)
    return "\n".join(out) + "\n"


def _user_types(model: KittingModel) -> dict[str, Any]:
    by_name = {t.name: t for t in model.up_problem.user_types}
    return {iri: by_name[local_name(iri)] for iri in model.domain.types if local_name(iri) in by_name}


def annotate_problem(text: str, model: KittingModel, writer: Any) -> str:
    """Insert a header and one ``; object name: <IRI>`` line per object."""
    assert model.problem is not None
    out = [f"; kitkb PDDL problem ({model.encoding} encoding), generated with unified-planning's PDDLWriter",
           "; from the initial state " + ", ".join(map(_short, model.init_paths)),
           "; and the goal state " + ", ".join(map(_short, model.goal_paths)) + "."]
    for line in text.splitlines():
        if line.strip().startswith("(:objects"):
            for name, (_cls, iri) in sorted(model.problem.objects.items()):
                obj = model.up_problem.object(name)
                out.append(f" ; object {writer.get_pddl_name(obj)}: <{iri}>")
        out.append(line)
    return "\n".join(out) + "\n"


def _short(path: str) -> str:
    """The file name with its folder (stable whatever the working directory)."""
    p = Path(path)
    return f"{p.parent.name}/{p.name}" if p.parent.name else p.name
