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
    assert figures["parts"] >= 40 and figures["objects"] > figures["parts"]
    assert figures["updates_per_s"] > 0 and figures["global_all_s"] > 0
    assert "| sensed pose updates" in capsys.readouterr().out
