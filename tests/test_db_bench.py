"""The database benchmark runs end to end at a small size (the real run is 10,000 parts)."""

from __future__ import annotations

import importlib.util
import json
from pathlib import Path

import pytest

BENCH = Path(__file__).resolve().parent.parent / "benchmarks" / "bench_db.py"


@pytest.mark.slow
def test_bench_db_small(tmp_path, capsys, monkeypatch):
    monkeypatch.delenv("KITKB_PG_URL", raising=False)
    spec = importlib.util.spec_from_file_location("bench_db", BENCH)
    bench = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(bench)
    out = tmp_path / "figures.json"
    assert bench.main(["--parts", "40", "--kits", "1", "--updates", "5", "--batch", "5", "--json", str(out)]) == 0
    figures = json.loads(out.read_text())["results"]["sqlite"]
    # the same scenario (the benchmark writes it with seed 0), counted with rdflib: its parts
    # (40 in the kit plus spares) and every solid object, whose global poses were computed
    from rdflib import OWL, RDF, RDFS, Graph, Namespace

    from kb.core.resources import ontology_path
    from kb.scenario import write_scenario
    from kb.scenario.spec import random_spec

    ktw = Namespace("https://w3id.org/kitkb/kitting#")
    init, _ = write_scenario(tmp_path / "same", parts=40, kits=1, seed=0)
    data, model = Graph().parse(init), Graph().parse(ontology_path("kitting.ttl"))
    solid, todo = set(), [ktw.SolidObject]
    while todo:
        c = todo.pop()
        solid.add(c)
        todo += [s for s in model.subjects(RDFS.subClassOf, c) if s not in solid]
    parts = set(data.subjects(RDF.type, ktw.Part))
    spec = random_spec(40, 1, 0)
    assert len(parts) == 40 + spec.spare * len(spec.part_types)  # the spares of each part type
    assert figures["parts"] == len(parts)
    assert figures["objects"] == len({s for s, c in data.subject_objects(RDF.type) if c in solid})
    assert figures["individuals"] == len(set(data.subjects(RDF.type, OWL.NamedIndividual)))
    # timings: measured, so only known to be positive
    assert figures["updates_per_s"] > 0 and figures["global_all_s"] > 0
    assert "| sensed pose updates" in capsys.readouterr().out
