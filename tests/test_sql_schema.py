"""SQL schema generated from the kitting and SOAP ontologies: tables, types, constraints, dialects."""

from __future__ import annotations

import os
import re
import sqlite3

import pytest
from rdflib import OWL, RDF, Graph, URIRef

from generators.sql import DIALECTS, SqlGenerator, build_metadata, ddl
from generators.sql_model import MODEL_NAMESPACES, build_schema, shipped_schema
from kb.core.generators import generator_names, get_generator
from kb.core.resources import model_files
from kb.core.namespaces import local_name
from kb.core.errors import InputError


@pytest.fixture(scope="module")
def schema():
    return shipped_schema()


@pytest.fixture(scope="module")
def scripts(schema):
    return {d: SqlGenerator(d, schema).serialize() for d in DIALECTS}


def _table(script: str, name: str) -> str:
    m = re.search(rf"CREATE TABLE {name} \((.*?)\n\);", script, re.S)
    assert m, f"no CREATE TABLE {name}"
    return m.group(1)


def test_one_table_per_model_class(schema, scripts):
    assert [f.name for f in model_files()] == ["kitting.ttl", "soap.ttl"]
    g = Graph()
    for f in model_files():
        g.parse(f)
    classes = {c for c in g.subjects(RDF.type, OWL.Class)
               if isinstance(c, URIRef) and any(str(c).startswith(ns) for ns in MODEL_NAMESPACES)}
    names = {local_name(c) for c in classes}
    # both models' classes, the kitting workstation's and SOAP's (its fault kinds, section 7, too)
    assert {"KitTray", "PartsTray", "PoseSensor", "FailureMode", "RecoveryStrategy", "FaultKind",
            "FaultMechanism"} <= names
    assert {t.class_iri for t in schema.tables if t.class_iri} == {str(c) for c in classes}
    for d, script in scripts.items():
        assert script.count("CREATE TABLE ") == len(build_metadata(schema).tables), d


def test_registry_knows_the_generators():
    assert get_generator("sql") is SqlGenerator
    assert get_generator("accessors").__name__ == "AccessorsGenerator"
    assert sorted(generator_names()) == ["accessors", "pddl", "shapes", "sql"]
    with pytest.raises(InputError, match="unknown generator 'owl2vec'"):
        get_generator("owl2vec")


def test_columns_types_and_checks(scripts):
    pg = scripts["postgresql"]
    point = _table(pg, "ktw_point")
    assert re.search(r"\bx NUMERIC NOT NULL", point)
    sku = _table(pg, "ktw_stock_keeping_unit")
    assert "CHECK (weight > 0.0)" in sku  # positiveDecimal: minExclusive 0
    ws = _table(pg, "ktw_kitting_workstation")
    assert "angle_unit IN ('degree', 'radian')" in ws  # enumeration
    assert "length_unit IN ('meter', 'millimeter', 'inch')" in ws
    vessel = _table(pg, "ktw_parts_vessel")
    assert "CHECK (part_quantity >= 0)" in vessel  # nonNegativeInteger
    kit = _table(pg, "ktw_kit")
    assert re.search(r"\bfinished BOOLEAN NOT NULL", kit)


def test_not_null_from_min_cardinality_only(scripts):
    pg = scripts["postgresql"]
    assert "primary_location_id INTEGER NOT NULL" in _table(pg, "ktw_solid_object")  # exactly 1
    held = re.search(r"held_object_id INTEGER(.*)", _table(pg, "ktw_end_effector")).group(1)
    assert "NOT NULL" not in held  # at most 1


def test_foreign_keys_and_link_tables(scripts):
    pg = scripts["postgresql"]
    assert re.search(r"ALTER TABLE ktw_solid_object ADD CONSTRAINT \S+ FOREIGN KEY\(primary_location_id\) "
                     r"REFERENCES ktw_physical_location \(id\)", pg)
    assert re.search(r"ALTER TABLE ktw_has_kit_part ADD CONSTRAINT \S+ FOREIGN KEY\(value_id\) "
                     r"REFERENCES ktw_part \(id\)", pg)  # hasKit_Part has several values
    assert "FOREIGN KEY(id) REFERENCES ktw_sku_object (id)" in _table(pg, "ktw_part")  # inheritance


def test_dialect_differences(scripts):
    assert "DEFERRABLE" in scripts["postgresql"] and "DEFERRABLE" not in scripts["mysql"]
    assert "SERIAL" in scripts["postgresql"] and "AUTO_INCREMENT" in scripts["mysql"]
    assert "DECIMAL(38, 12)" in scripts["mysql"]
    names = re.findall(r"(?:CONSTRAINT|TABLE|INDEX) (\w+)", scripts["mysql"] + scripts["postgresql"])
    assert names and max(len(n) for n in names) <= 64


def test_deterministic(schema):
    assert SqlGenerator("mysql", schema).serialize() == SqlGenerator("mysql", shipped_schema()).serialize()


def test_sqlite_script_runs(scripts):
    con = sqlite3.connect(":memory:")
    con.executescript("BEGIN;\n" + scripts["sqlite"] + "COMMIT;\n")
    n = con.execute("select count(*) from sqlite_master where type = 'table'").fetchone()[0]
    assert n == scripts["sqlite"].count("CREATE TABLE ")


@pytest.mark.postgres
def test_postgresql_script_runs(scripts):
    url = os.environ.get("KITKB_PG_URL")
    if not url:
        pytest.skip("KITKB_PG_URL is not set")
    from sqlalchemy import create_engine, inspect

    from kb.world.database import model

    engine = create_engine(url)
    model().metadata.drop_all(engine)
    try:
        with engine.begin() as conn:
            for stmt in scripts["postgresql"].split(";\n"):
                if stmt.strip():
                    conn.exec_driver_sql(stmt)  # the generated script, statement by statement
            assert len(inspect(conn).get_table_names()) == scripts["postgresql"].count("CREATE TABLE ")
    finally:
        model().metadata.drop_all(engine)
        engine.dispose()


def test_generate_sql_function(tmp_path):
    from kb.cli.generate import generate_sql
    from kb.cli.output import Output

    out = tmp_path / "schema.sql"
    assert generate_sql("postgresql", str(out), Output(quiet=True)) == 0
    assert out.read_text().startswith("-- kitkb schema ")
    with pytest.raises(InputError, match="unknown SQL dialect 'oracle'"):
        generate_sql("oracle", str(tmp_path / "x.sql"), Output(quiet=True))
    assert not (tmp_path / "x.sql").exists()


def test_schema_follows_the_ontology():
    g = Graph()
    for f in model_files():
        g.parse(f)
    before = build_schema(g)
    g.remove((URIRef("https://w3id.org/kitkb/kitting#hasKit_Part"), RDF.type, OWL.ObjectProperty))
    after = build_schema(g)
    assert before.fingerprint() != after.fingerprint()
    assert "ktw_has_kit_part" in {l.name for l in before.links} - {l.name for l in after.links}


def test_ddl_of_metadata_is_plain_text(schema):
    metadata = build_metadata(schema)
    text = ddl(metadata, "sqlite")
    assert "CREATE TABLE kitkb_thing" in text and text.endswith(";\n")
    assert text.count("CREATE TABLE ") == len(metadata.tables)


def test_cli_generate_sql(tmp_path):
    from kb.cli import main

    out = tmp_path / "pg.sql"
    assert main(["generate", "sql", "--dialect", "postgresql", "-o", str(out)]) == 0
    assert "CREATE TABLE ktw_kit_tray" in out.read_text()
    with pytest.raises(SystemExit) as exit_:  # argparse names the choices
        main(["generate", "sql", "--dialect", "db2", "-o", str(tmp_path / "x.sql")])
    assert exit_.value.code == 2
    assert not (tmp_path / "x.sql").exists()
