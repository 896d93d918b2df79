"""Validation shared with a forked child process (kb.shacl.parallel): same results, same
order, and the parent still answers when the child fails."""

from __future__ import annotations

import importlib.util
import os
import sys
import threading
from collections import Counter
from pathlib import Path

import pytest

from kb.core.jobs import Forked
from kb.shacl import parallel
from kb.shacl.engine import Evaluation, evaluate
from kb.validation import validate

# every test here may assert that kitkb forks: threads that other tests left behind are not counted
pytestmark = [pytest.mark.skipif(not hasattr(os, "fork"), reason="needs os.fork"), pytest.mark.usefixtures("fork_ready")]

_BENCH = Path(__file__).resolve().parent.parent / "benchmarks" / "bench_validate.py"


def _bench():
    spec = importlib.util.spec_from_file_location("bench_validate_for_tests", _BENCH)
    assert spec and spec.loader
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


KINDS = ("missing", "closed", "datatype", "class", "maxcount", "axis", "weight")  # bench_validate.inject's turn


@pytest.fixture(scope="module")
def injected(tmp_path_factory) -> tuple[Path, dict[str, int]]:
    """A generated workstation (300 parts) with about 5% injected violations of every kind
    the benchmark injects (SPARQL rules included), as N-Triples; and how many of each kind."""
    from rdflib import RDF, Graph, URIRef

    out = tmp_path_factory.mktemp("parallel")
    spec = _bench().make_e2e(300, out, seed=4, rate=0.05)
    # 5% of the scenario's parts (counted with rdflib), the kinds in turn, and the length unit
    part = URIRef("https://w3id.org/kitkb/kitting#Part")
    parts = set(Graph().parse(out / "scenario" / "init.ttl").subjects(RDF.type, part))
    chosen = round(len(parts) * 0.05)
    expected = {kind: len(range(i, chosen, len(KINDS))) for i, kind in enumerate(KINDS)}
    assert spec["injected"] == {**expected, "in": 1}
    assert sum(expected.values()) == chosen == 16  # 318 parts
    return Path(spec["data"]), spec["injected"]


@pytest.fixture(scope="module")
def broken_workstation(injected) -> Path:
    return injected[0]


def _index_and_program(path: Path):
    """The engine's inputs for ``path`` as ``kitkb validate`` builds them."""
    from kb.io.loader import load
    from kb.validation import validator as v
    from kb.shacl.engine import prefixes_of
    from kb.shacl.index import DataIndex
    from kb.shacl.compiler import compile_program
    from kb.model.owl import OwlModel

    kb = load([path])
    data, model = kb.sources[0], kb.sources[1:]
    model_graph = v._merge(*(s.graph for s in model))
    shapes = v._shapes(OwlModel(model_graph), None)
    program = compile_program(shapes, rdf11_strings=False, prefixes=prefixes_of(shapes))

    def index() -> DataIndex:
        ix = DataIndex()
        ix.add_graph(model_graph)
        ix.add_nested(data.view().by_subject())
        return ix

    return index, program


def test_forked_evaluation_equals_one_pass_hit_for_hit(broken_workstation, monkeypatch):
    index, program = _index_and_program(broken_workstation)
    forks: list[int] = []
    real_start = parallel.Split.start

    def start(self):  # noqa: ANN001, ANN202
        real_start(self)
        forks.append(self.pid)

    monkeypatch.setattr(parallel.Split, "start", start)
    one_pass = evaluate(index(), program, rdf11_strings=False, parallel=False)
    assert forks == [None]
    shared = evaluate(index(), program, rdf11_strings=False, parallel=True)
    assert forks[-1] is not None, "a child process should have been forked"
    assert shared == one_pass
    # the comparison covers the shapes every injected kind violates
    assert {str(r.source_shape).rsplit("#", 1)[1] for r in one_pass} == {
        "ktw-SkuObject-hasSkuObject_Sku",  # missing SKU, SKU pointing at a pose
        "ktw-Part", "ktw-SkuObject", "ktw-SolidObject",  # extra property (closed shapes)
        "ktw-Part-hasPart_SerialNumber",  # serial number datatype, second serial number
        "AxisUnitLength", "VesselPartSku",  # SPARQL rules: axis length, the pose-typed SKU
        "ktw-StockKeepingUnit-hasStockKeepingUnit_Weight",  # zero weight
        "ktw-KittingWorkstation-hasKittingWorkstation_LengthUnit",  # unit outside sh:in
    }


def test_child_gets_the_sparql_shapes_and_a_share_of_the_rest(broken_workstation):
    index, program = _index_and_program(broken_workstation)
    ev = Evaluation(index(), program, rdf11_strings=False, parallel=True)
    try:
        sparql = {i for i, uses in enumerate(ev.uses_sparql) if uses}
        # the shapes of shapes/*.ttl that have sh:sparql constraints (8), read with rdflib
        from rdflib import Graph, URIRef

        from kb.core.resources import shapes_path

        shipped = Graph()
        for name in ("kitting-shapes.ttl", "kitting-rules.ttl"):
            shipped.parse(shapes_path(name), format="turtle")
        with_sparql = set(shipped.subjects(URIRef("http://www.w3.org/ns/shacl#sparql"), None))
        assert {ev.active[i][0].node for i in sparql} == with_sparql
        assert sparql <= set(ev.split.child)
        plain = set(range(len(ev.active))) - sparql
        assert plain - set(ev.split.child), "the parent keeps plain shapes"
        assert plain & set(ev.split.child), "the child takes some plain shapes too"
    finally:
        ev.finish()


@pytest.mark.parametrize("failure", ["raise", "exit", "kill"])
def test_parent_redoes_the_work_of_a_failed_child(broken_workstation, monkeypatch, failure):
    index, program = _index_and_program(broken_workstation)
    expected = evaluate(index(), program, rdf11_strings=False, parallel=False)
    parent = os.getpid()
    real_run = Evaluation._run

    def run(self, which):  # noqa: ANN001, ANN202
        if os.getpid() != parent:
            if failure == "raise":
                raise RuntimeError("child failed")
            if failure == "exit":
                os._exit(0)  # a clean exit without an answer
            os.kill(os.getpid(), 9)
        return real_run(self, which)

    monkeypatch.setattr(Evaluation, "_run", run)
    forks = _record_forks(monkeypatch)
    assert evaluate(index(), program, rdf11_strings=False, parallel=True) == expected
    assert forks and forks[-1] is not None, "a child process should have been forked"
    for pid in forks:  # no child left behind (other tests' processes, Dask's, are not ours to count)
        with pytest.raises(ChildProcessError):
            os.waitpid(pid, os.WNOHANG)


def _record_forks(monkeypatch) -> list[int | None]:  # noqa: ANN001
    """Process ids of the Forked jobs this process starts."""
    forks: list[int | None] = []
    real_init = Forked.__init__

    def init(self, fn):  # noqa: ANN001, ANN202
        real_init(self, fn)
        forks.append(self.pid)

    monkeypatch.setattr(Forked, "__init__", init)
    return forks


def test_kitkb_validate_reports_the_same_with_and_without_a_child(injected, monkeypatch):
    broken_workstation, kinds = injected
    monkeypatch.setenv("KITKB_SHACL_PARALLEL", "0")
    alone = validate([broken_workstation])
    monkeypatch.setenv("KITKB_SHACL_PARALLEL", "force")
    forks = _record_forks(monkeypatch)
    shared = validate([broken_workstation])
    assert forks and forks[0] is not None, "SHACL should have run in a helper process"
    assert shared.diagnostics == alone.diagnostics
    # one line per injected mistake, under its rule (a SKU that is a pose also breaks the
    # parts tray's SKU rule)
    assert Counter(d.rule for d in alone.diagnostics) == Counter({
        "min-count": kinds["missing"], "unknown-property": kinds["closed"], "datatype": kinds["datatype"],
        "class": kinds["class"], "vessel-part-sku": kinds["class"], "max-count": kinds["maxcount"],
        "axis-unit-length": kinds["axis"], "value-range": kinds["weight"], "enumeration": kinds["in"]})
    for pid in forks:  # reaped (other tests' processes, Dask's, are not ours to count)
        with pytest.raises(ChildProcessError):
            os.waitpid(pid, os.WNOHANG)


def test_kitkb_validate_survives_a_failed_helper(broken_workstation, monkeypatch):
    import kb.shacl as engine_api

    monkeypatch.setenv("KITKB_SHACL_PARALLEL", "0")
    expected = validate([broken_workstation]).diagnostics
    monkeypatch.setenv("KITKB_SHACL_PARALLEL", "force")
    parent = os.getpid()
    real = engine_api._start_here

    def dying(*args, **kwargs):  # noqa: ANN002, ANN003, ANN202
        if os.getpid() != parent:
            os._exit(3)
        return real(*args, **kwargs)

    monkeypatch.setattr(engine_api, "_start_here", dying)
    forks = _record_forks(monkeypatch)
    assert validate([broken_workstation]).diagnostics == expected
    assert forks and forks[0] is not None


def test_no_fork_with_another_thread_running_or_when_turned_off(monkeypatch):
    monkeypatch.delenv("KITKB_SHACL_PARALLEL", raising=False)
    monkeypatch.setattr(parallel, "usable_cores", lambda: 2)
    assert parallel.can_fork(10**6)
    assert not parallel.can_fork(parallel.MIN_TRIPLES - 1)
    monkeypatch.setattr(parallel, "usable_cores", lambda: 1)
    assert not parallel.can_fork(10**6)
    monkeypatch.setenv("KITKB_SHACL_PARALLEL", "force")
    assert parallel.can_fork(10)
    stop = threading.Event()
    worker = threading.Thread(target=stop.wait)
    worker.start()
    try:
        assert not parallel.can_fork(10**6), "a fork with another thread alive could deadlock the child"
    finally:
        stop.set()
        worker.join()
    monkeypatch.setenv("KITKB_SHACL_PARALLEL", "0")
    assert not parallel.can_fork(10**6)


def test_split_merges_in_shape_order_and_plans_by_cost():
    def run(which):  # noqa: ANN001, ANN202
        return {i: [(f"f{i}", None, None, "s", "c", "v", f"m{i}")] for i in which}

    split = parallel.Split(5, run, {1, 3})
    split.start()
    assert split.pid is not None or not parallel.can_fork(0, min_triples=0)
    got = split.finish()
    assert [hits[0][0] for hits in got] == ["f0", "f1", "f2", "f3", "f4"]
    child = parallel.plan([10.0, 1.0, 5.0, 4.0], [False, True, False, False], share=0.4)
    # SPARQL always; then the costliest plain ones that fit in 40% of the plain cost (7.6):
    # not 0 (10), 2 (5), then not 3 (5 + 4 > 7.6)
    assert child == {1, 2}
