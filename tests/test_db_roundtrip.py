"""kitkb db load / dump: graph-isomorphic round trips, odd names, one-line errors, atomic loads.

Every test runs on SQLite; the ``postgresql`` variants run when KITKB_PG_URL is set.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest
from rdflib import OWL, RDF, RDFS, BNode, Graph, Literal, Namespace, URIRef
from rdflib.compare import isomorphic
from sqlalchemy import Column, Integer, MetaData, Table, create_engine, insert

from generators.sql import build_metadata
from generators.sql_model import build_schema, model_files
from kb import world
from kb.cli import main
from kb.core.errors import InputError
from kb.io.loader import load_file
from kb.core.resources import ontology_path, scenario_dirs

from shared_data import NIST_DIR

KTW = Namespace("https://w3id.org/kitkb/kitting#")
SOAP = Namespace("https://w3id.org/kitkb/soap#")
NIST = NIST_DIR
PG_URL = os.environ.get("KITKB_PG_URL")


def _data_files() -> list[Path]:
    files = [d / f for d in scenario_dirs() for f in ("init.ttl", "goal.ttl") if (d / f).is_file()]
    files += [NIST / f for f in ("kittingInstancesInit1.owl", "kittingInstancesGoal1.owl") if (NIST / f).is_file()]
    domain = ontology_path("kitting-domain.ttl")  # SOAP instances: exercises the SOAP tables
    return files + ([domain] if domain.is_file() else [])


DATA_FILES = _data_files()


def test_case_count():
    assert len([f for f in DATA_FILES if f.parent.parent.name == "scenarios"]) == 6  # 3 scenarios x 2 states
    assert len([f for f in DATA_FILES if f.suffix == ".owl"]) == 2
    assert any(f.name == "kitting-domain.ttl" for f in DATA_FILES)


@pytest.fixture(scope="module")
def model_graph() -> Graph:
    g = Graph()
    for f in model_files():
        g.parse(f, format="turtle")
    return g


def _expected_rows(data: Graph, model: Graph) -> tuple[int, int, int]:
    """(individuals, points, SOAP actions) ``data`` holds, counted with rdflib: the nodes typed
    with a model class, plus the model's own individuals ``data`` refers to (soap:Target...)."""
    classes = {c for c in model.subjects(RDF.type, OWL.Class) if isinstance(c, URIRef)}
    typed = {s for s, c in data.subject_objects(RDF.type) if c in classes}
    model_individuals = {s for s, c in model.subject_objects(RDF.type) if c in classes}
    referred = {o for o in data.objects() if o in model_individuals and o not in typed}
    actions, todo = set(), [SOAP.Action]
    while todo:  # soap:Action and its subclasses
        c = todo.pop()
        actions.add(c)
        todo += [s for s in model.subjects(RDFS.subClassOf, c) if s not in actions]
    return (len(typed | referred), len(set(data.subjects(RDF.type, KTW.Point))),
            len({s for s, c in data.subject_objects(RDF.type) if c in actions}))


@pytest.mark.parametrize("path", DATA_FILES, ids=lambda p: f"{p.parent.name}/{p.name}")
def test_round_trip_is_isomorphic(path, url, tmp_path, model_graph):
    report = world.load(path, url)
    individuals, points, actions = _expected_rows(load_file(path).graph, model_graph)
    assert report.individuals == individuals
    # the values went into the model's tables, not only into the table of other statements
    assert (report.tables.get("ktw_point", 0), report.tables.get("soap_action", 0)) == (points, actions)
    out = world.dump(url, tmp_path / "dump.ttl")
    original = load_file(path).graph
    dumped = Graph().parse(out, format="turtle")
    assert len(dumped) == len(original)
    assert isomorphic(original, dumped)


def _odd_graph() -> Graph:
    from rdflib.namespace import XSD

    g = Graph()
    ex = Namespace("https://example.org/odd'name;x/")
    sku, shape = ex["sku_o'brien"], ex["shäpe(1)"]
    g.add((sku, RDF.type, KTW.StockKeepingUnit))
    g.add((sku, KTW.hasStockKeepingUnit_Description,
           Literal("O'Brien \"quoted\"\nRobert'); DROP TABLE kitkb_thing;-- é ✓")))
    g.add((sku, KTW.hasStockKeepingUnit_Weight, Literal("0.25", datatype=XSD.decimal)))
    g.add((sku, KTW.hasStockKeepingUnit_InternalShape, shape))
    g.add((shape, RDF.type, KTW.BoxyShape))
    g.add((shape, KTW.hasShapeDesign_Description, Literal("it's a box", lang="en")))
    for p, v in (("Length", "0.1"), ("Width", "0.20"), ("Height", "3E-1")):
        g.add((shape, KTW["hasBoxyShape_" + p], Literal(v, datatype=XSD.decimal if "E" not in v else XSD.double)))
    g.add((shape, KTW.hasBoxyShape_HasTop, Literal("1", datatype=XSD.boolean)))
    blank = BNode()
    g.add((blank, RDF.type, KTW.Point))
    for axis, v in (("X", "1"), ("Y", "-2.50"), ("Z", "+0.000")):
        g.add((blank, KTW["hasPoint_" + axis], Literal(v, datatype=XSD.decimal)))
    g.add((sku, URIRef("https://example.org/note'"), Literal("outside the model")))
    return g


def test_odd_names_and_values_round_trip(url, tmp_path):
    src = tmp_path / "odd.ttl"
    _odd_graph().serialize(src, format="turtle")
    world.load(src, url)
    dumped = Graph().parse(world.dump(url, tmp_path / "back.ttl"))
    assert isomorphic(load_file(src).graph, dumped)
    from kb.world.worldmodel import WorldModel

    with WorldModel(url) as wm:
        assert wm.object("sku_o'brien").iri == "https://example.org/odd'name;x/sku_o'brien"
        assert [o.name for o in wm.objects("BoxyShape")] == ["shäpe(1)"]


def _bad_weight(tmp_path: Path) -> Path:
    bad = tmp_path / "bad.ttl"
    bad.write_text(
        "@prefix ktw: <https://w3id.org/kitkb/kitting#> .\n"
        "@prefix : <https://example.org/bad#> .\n"
        ":sku a ktw:StockKeepingUnit ;\n"
        "    ktw:hasStockKeepingUnit_Description \"a part\" ;\n"
        "    ktw:hasStockKeepingUnit_Weight -1.5 .\n", encoding="utf-8")
    return bad


def test_value_outside_datatype_names_the_line_and_changes_nothing(url, tmp_path):
    good = DATA_FILES[0]
    world.load(good, url)
    before = world.read_graph(url)
    with pytest.raises(InputError) as err:
        world.load(_bad_weight(tmp_path), url, replace=True)
    assert str(err.value).startswith(f"{tmp_path / 'bad.ttl'}:5: error:")
    assert "> 0" in str(err.value)
    assert isomorphic(before, world.read_graph(url))


def test_missing_required_value_is_refused(url, tmp_path):
    f = tmp_path / "p.ttl"
    f.write_text("@prefix ktw: <https://w3id.org/kitkb/kitting#> .\n"
                 "<https://example.org/p> a ktw:Point ;\n  ktw:hasPoint_X 1.0 ;\n  ktw:hasPoint_Y 2.0 .\n")
    with pytest.raises(InputError, match=r"p.ttl:2: error: p \(Point\) has no value for hasPoint_Z"):
        world.load(f, url)


def test_cli_errors_are_one_line_exit_2(tmp_path, capsys):
    target = tmp_path / "w.sqlite"
    syntax = tmp_path / "broken.ttl"
    syntax.write_text("@prefix ktw: <https://w3id.org/kitkb/kitting#> .\n<a> ktw:x [ .\n")
    (tmp_path / "a_file").write_text("")
    cases = [
        ["db", "load", str(tmp_path / "missing.ttl"), "--db", str(target)],
        ["db", "load", str(syntax), "--db", str(target)],
        ["db", "load", str(_bad_weight(tmp_path)), "--db", str(target)],
        ["db", "load", str(DATA_FILES[0]), "--db", "nosuchdialect://x/y"],
        ["db", "load", str(DATA_FILES[0]), "--db", "postgresql+psycopg2://nobody@127.0.0.1:9/none"],
        ["db", "load", str(DATA_FILES[0]), "--db", str(tmp_path / "a_file" / "under" / "w.sqlite")],
        ["db", "dump", "--db", str(tmp_path / "absent.sqlite"), "-o", str(tmp_path / "o.ttl")],
    ]
    for argv in cases:
        assert main(argv) == 2, argv
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and "Traceback" not in err and "error" in err, (argv, err)
    assert not target.exists()  # nothing half-written
    assert not (tmp_path / "absent.sqlite").exists() and not (tmp_path / "o.ttl").exists()


def test_cli_load_and_dump(tmp_path, capsys):
    target, out = tmp_path / "new" / "folder" / "w.sqlite", tmp_path / "out.ttl"  # folders are made
    assert main(["db", "load", str(DATA_FILES[0]), "--db", str(target)]) == 0
    assert "individuals" in capsys.readouterr().err
    assert main(["db", "dump", "--db", str(target), "-o", str(out)]) == 0
    assert isomorphic(Graph().parse(out), load_file(DATA_FILES[0]).graph)


def test_database_of_another_ontology_version_is_refused(url, tmp_path, capsys):
    g = Graph()
    for f in model_files():
        g.parse(f)
    g.add((KTW.hasPoint_W, RDF.type, URIRef("http://www.w3.org/2002/07/owl#DatatypeProperty")))
    g.add((KTW.hasPoint_W, URIRef("http://www.w3.org/2000/01/rdf-schema#domain"), KTW.Point))
    other = build_schema(g)
    engine = world.open_engine(url)
    meta = build_metadata(other)
    meta.create_all(engine)
    with engine.begin() as conn:
        conn.execute(insert(meta.tables["kitkb_meta"]), [
            {"key": "schema_version", "value": other.fingerprint()},
            {"key": "ontologies", "value": json.dumps([["https://w3id.org/kitkb/kitting", "0.0.9"]])}])
    engine.dispose()
    with pytest.raises(world.SchemaVersionError, match="another ontology version"):
        world.read_graph(url)
    assert main(["db", "dump", "--db", url, "-o", str(tmp_path / "x.ttl")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "kitting 0.0.9" in err
    assert main(["db", "load", str(DATA_FILES[0]), "--db", url]) == 2  # not silently overwritten


def test_not_a_kitkb_database(tmp_path):
    path = tmp_path / "other.sqlite"
    engine = create_engine(world.normalize_url(path))
    meta = MetaData()
    Table("t", meta, Column("a", Integer))
    meta.create_all(engine)
    engine.dispose()
    with pytest.raises(world.SchemaVersionError, match="not a kitkb database"):
        world.read_graph(path)
