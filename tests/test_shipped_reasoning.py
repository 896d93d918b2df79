"""Every shipped file loads in rdflib and owlready2; the model is consistent under HermiT,
alone and with each shipped scenario's data."""

from __future__ import annotations

from pathlib import Path

import pytest
from rdflib import Graph, Literal, URIRef
from rdflib.compare import isomorphic
from rdflib.namespace import OWL, RDF

from kb.io.loader import catalog, load_file
from kb.validation.consistency import check_consistency, to_owlready
from kb.core.resources import ontologies_dir, scenario_dirs

MODEL = sorted(ontologies_dir().glob("*.ttl"))
SCENARIO_FILES = [f for d in scenario_dirs() for f in (d / "init.ttl", d / "goal.ttl")]
XSD_STRING = URIRef("http://www.w3.org/2001/XMLSchema#string")  # not rdflib's XSD: pytest probes module globals


def _with_imports(paths: list[Path]) -> Graph:
    """rdflib's union of ``paths`` and the shipped files they import (through the catalog)."""
    shipped = catalog()
    union, todo, seen = Graph(), list(paths), set()
    while todo:
        path = todo.pop()
        if path in seen:
            continue
        seen.add(path)
        g = Graph().parse(path, format="turtle")
        union += g
        for iri in g.objects(None, OWL.imports):
            assert str(iri) in shipped, f"{path.name} imports {iri}, which is not a shipped ontology"
            todo.append(shipped[str(iri)])
    return union


def _declared(g: Graph, owl_type: URIRef) -> set[str]:
    return {str(s) for s in g.subjects(RDF.type, owl_type) if isinstance(s, URIRef)}


def _plain_strings(g: Graph) -> Graph:
    """``g`` with "x"^^xsd:string written "x" (the same literal in RDF 1.1; kitkb's loader
    writes the plain form, rdflib keeps the spelling)."""
    out = Graph()
    for s, p, o in g:
        out.add((s, p, Literal(str(o)) if isinstance(o, Literal) and o.datatype == XSD_STRING else o))
    return out


def test_shipped_file_counts() -> None:
    assert [p.name for p in MODEL] == ["kitting-domain.ttl", "kitting.ttl", "soap.ttl"]
    assert [f"{p.parent.name}/{p.name}" for p in SCENARIO_FILES] == [
        f"{name}/{state}.ttl" for name in ("kit-a2b3c3d1e1", "small-kit", "two-designs") for state in ("init", "goal")]


@pytest.mark.parametrize("path", MODEL + SCENARIO_FILES, ids=lambda p: f"{p.parent.name}/{p.name}")
def test_loads_in_rdflib(path: Path) -> None:
    """rdflib and kitkb's loader (pyoxigraph underneath) read the same graph."""
    theirs = _plain_strings(Graph().parse(path, format="turtle"))
    ours = load_file(path)
    assert ours.format == "turtle"
    assert len(ours.graph) == len(theirs)
    assert isomorphic(ours.graph, theirs)


@pytest.mark.parametrize("path", MODEL + SCENARIO_FILES, ids=lambda p: f"{p.parent.name}/{p.name}")
def test_loads_in_owlready2(path: Path) -> None:
    world, _ = to_owlready([path])
    union = _with_imports([path])  # the kitting model comes in through the import
    assert {c.iri for c in world.classes()} == _declared(union, OWL.Class)
    assert {i.iri for i in world.individuals()} == _declared(union, OWL.NamedIndividual)


@pytest.mark.slow
def test_model_consistent_under_hermit() -> None:
    report = check_consistency(MODEL)
    assert report.consistent, report
    union = _with_imports(MODEL)
    assert (report.classes, report.individuals) == (len(_declared(union, OWL.Class)),
                                                    len(_declared(union, OWL.NamedIndividual)))


@pytest.mark.slow
@pytest.mark.parametrize("scenario", scenario_dirs(), ids=lambda d: d.name)
def test_scenario_consistent_under_hermit(scenario: Path) -> None:
    for state in ("init.ttl", "goal.ttl"):
        report = check_consistency([scenario / state])
        assert report.consistent, (state, report)
        union = _with_imports([scenario / state])
        assert (report.classes, report.individuals) == (len(_declared(union, OWL.Class)),
                                                        len(_declared(union, OWL.NamedIndividual))), state


@pytest.mark.slow
def test_hermit_finds_an_inconsistency(tmp_path: Path) -> None:
    """The check can fail: a point with two X values (hasPoint_X is functional)."""
    bad = tmp_path / "bad.ttl"
    bad.write_text(
        "@prefix ktw: <https://w3id.org/kitkb/kitting#> .\n"
        "@prefix owl: <http://www.w3.org/2002/07/owl#> .\n"
        "<urn:bad> a owl:Ontology ; owl:imports <https://w3id.org/kitkb/kitting> .\n"
        "<urn:bad#p> a owl:NamedIndividual, ktw:Point ; ktw:hasPoint_X 1.0, 2.0 ; "
        "ktw:hasPoint_Y 0.0 ; ktw:hasPoint_Z 0.0 .\n"
    )
    assert not check_consistency([bad]).consistent
