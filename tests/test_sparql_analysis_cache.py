"""kb.shacl.sparql keeps what its analysis of a SPARQL constraint decided between runs
(kb.core.cache): the same results with the cache cold, warm, broken or off; a query SHACL
refuses is refused every time; a warm cache parses nothing."""

from __future__ import annotations

import json

import pytest
from rdflib import Graph

import kb.shacl.sparql as sparql
from kb.core.cache import JsonCache
from kb.shacl import ShapeError, validate_graph

SHAPES = """
@prefix sh: <http://www.w3.org/ns/shacl#> . @prefix t: <urn:t:> .
t:S a sh:NodeShape ; sh:targetClass t:C ;
    sh:sparql [ sh:select "SELECT $this ?value WHERE { $this t:p ?value . FILTER (?value > 5) }" ] ;
    sh:property [ sh:path t:q ;
        sh:sparql [ sh:select "SELECT $this ?value WHERE { $this $PATH ?value . FILTER NOT EXISTS { ?value t:ok true } }" ] ] .
"""
DATA = """@prefix t: <urn:t:> .
t:a a t:C ; t:p 7 ; t:q t:x . t:b a t:C ; t:p 3 ; t:q t:y . t:y t:ok true ."""
REFUSED = """
@prefix sh: <http://www.w3.org/ns/shacl#> . @prefix t: <urn:t:> .
t:S a sh:NodeShape ; sh:targetClass t:C ;
    sh:sparql [ sh:select "SELECT $this WHERE { $this t:p ?v . MINUS { $this t:q ?w } }" ] .
"""


def _results(shapes: str = SHAPES) -> list[tuple[str, str, str]]:
    found = validate_graph(Graph().parse(data=DATA, format="turtle"), Graph().parse(data=shapes, format="turtle"))
    return sorted((str(r.focus), str(r.value), str(r.component)) for r in found)


@pytest.fixture
def cache(tmp_path, monkeypatch):
    monkeypatch.setenv("KITKB_CACHE_DIR", str(tmp_path))
    monkeypatch.setattr(sparql, "_ANALYSES", JsonCache("sparql-analysis", ["test"]))
    return tmp_path


def _no_parsing(monkeypatch) -> None:
    import rdflib.plugins.sparql.parser as parser

    def refuse(text: str):
        raise AssertionError("parsed although the analysis is cached")
    monkeypatch.setattr(parser, "parseQuery", refuse)


def test_warm_cache_same_results_without_parsing(cache, monkeypatch) -> None:
    cold = _results()
    assert len(cold) == 2  # t:a's value 7, t:a's q t:x
    files = list(cache.glob("sparql-analysis-*.json"))
    assert len(files) == 1 and len(json.loads(files[0].read_text())) == 2
    monkeypatch.setattr(sparql, "_ANALYSES", JsonCache("sparql-analysis", ["test"]))  # a new process: from the file
    _no_parsing(monkeypatch)
    assert _results() == cold


def test_broken_or_stale_cache_made_again(cache, monkeypatch) -> None:
    cold = _results()
    (file,) = cache.glob("sparql-analysis-*.json")
    file.write_text("{not json")
    monkeypatch.setattr(sparql, "_ANALYSES", JsonCache("sparql-analysis", ["test"]))
    assert _results() == cold
    monkeypatch.setattr(sparql, "_ANALYSES", JsonCache("sparql-analysis", ["other code"]))  # another key: its own file
    assert _results() == cold
    assert len(list(cache.glob("sparql-analysis-*.json"))) == 2


def test_cache_off(tmp_path, monkeypatch) -> None:
    monkeypatch.setenv("KITKB_CACHE_DIR", "off")
    monkeypatch.setattr(sparql, "_ANALYSES", JsonCache("sparql-analysis", ["test"]))
    assert len(_results()) == 2
    assert not list(tmp_path.iterdir())


def test_refused_query_refused_every_time(cache, monkeypatch) -> None:
    for _ in range(2):
        with pytest.raises(ShapeError, match="MINUS"):
            _results(REFUSED)
    assert not any(json.loads(f.read_text()) for f in cache.glob("sparql-analysis-*.json"))


def test_a_run_with_its_analyses_cached_imports_no_sparql_parser(cache) -> None:
    """rdflib's SPARQL grammar (80 ms to import) and pySHACL stay unimported when every query's
    analysis is cached (a fresh interpreter, the cache filled by a first one)."""
    import subprocess
    import sys
    from pathlib import Path

    root = Path(__file__).resolve().parents[1]
    code = ("import sys\nfrom rdflib import Graph\nfrom kb.shacl import validate_graph\n"
            f"validate_graph(Graph().parse(data={DATA!r}, format='turtle'), Graph().parse(data={SHAPES!r}, format='turtle'))\n"
            "print(sorted(m for m in sys.modules if m.startswith(('rdflib.plugins.sparql', 'pyshacl'))))")
    env = {"PYTHONPATH": str(root), "KITKB_CACHE_DIR": str(cache), "PATH": "/usr/bin:/bin"}
    runs = [subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, cwd=root)
            for _ in range(2)]
    assert all(r.returncode == 0 for r in runs), runs[-1].stderr
    assert runs[0].stdout.strip() != "[]"  # the first parses
    assert runs[1].stdout.strip() == "[]"
