"""The database benchmark runs end to end at a small size (the real runs are 10,000 and 50,000 parts)."""

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
    assert bench.main(["--parts", "40", "--kits", "1", "--runs", "1", "--updates", "5", "--batch", "5",
                       "--batches", "1", "--json", str(out)]) == 0
    result = json.loads(out.read_text())["results"]["40"]
    figures = result["median"]
    # the same scenario (the benchmark writes it with seed 0), counted with rdflib: its parts
    # (40 in the kit plus spares) and every solid object, whose global poses were computed
    from rdflib import RDF, RDFS, Graph, Namespace

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
    assert figures["sqlite_parts"] == len(parts)
    assert figures["sqlite_objects"] == len({s for s, c in data.subject_objects(RDF.type) if c in solid})
    assert result["info"]["statements"] == len(data)
    # timings and memory: measured, so only known to be positive; the anchor ran beside kitkb
    assert all(figures[k] > 0 for k in ("anchor_load_s", "anchor_load_mb", "sqlite_load_s", "sqlite_load_mb",
                                        "sqlite_dump_s", "sqlite_batch_updates_per_s", "sqlite_update_one_ms"))
    text = capsys.readouterr().out
    assert "| load `init.ttl`, whole process |" in text and "anchor (pyoxigraph)" in text
