"""Every shipped file loads in rdflib and owlready2; the model is consistent under HermiT,
alone and with each shipped scenario's data."""

from __future__ import annotations

from pathlib import Path

import pytest
from rdflib import Graph

from kb.validation.consistency import check_consistency, to_owlready
from kb.core.resources import ontologies_dir, scenario_dirs

MODEL = sorted(ontologies_dir().glob("*.ttl"))
SCENARIO_FILES = [f for d in scenario_dirs() for f in (d / "init.ttl", d / "goal.ttl")]


def test_shipped_file_counts() -> None:
    assert [p.name for p in MODEL] == ["kitting-domain.ttl", "kitting.ttl", "soap.ttl"]
    assert len(SCENARIO_FILES) >= 6


@pytest.mark.parametrize("path", MODEL + SCENARIO_FILES, ids=lambda p: f"{p.parent.name}/{p.name}")
def test_loads_in_rdflib(path: Path) -> None:
    assert len(Graph().parse(path, format="turtle")) > 100


@pytest.mark.parametrize("path", MODEL + SCENARIO_FILES, ids=lambda p: f"{p.parent.name}/{p.name}")
def test_loads_in_owlready2(path: Path) -> None:
    world, _ = to_owlready([path])
    assert len(list(world.classes())) >= 47  # the kitting model came in through the import


@pytest.mark.slow
def test_model_consistent_under_hermit() -> None:
    report = check_consistency(MODEL)
    assert report.consistent, report
    assert report.classes > 100


@pytest.mark.slow
@pytest.mark.parametrize("scenario", scenario_dirs(), ids=lambda d: d.name)
def test_scenario_consistent_under_hermit(scenario: Path) -> None:
    for state in ("init.ttl", "goal.ttl"):
        report = check_consistency([scenario / state])
        assert report.consistent, (state, report)
        assert report.individuals > 50


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
