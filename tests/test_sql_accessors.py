"""The generated typed accessors module: no drift, same schema as the SQL generator, usable ORM."""

from __future__ import annotations

import difflib
from pathlib import Path

import pytest
from sqlalchemy import select
from sqlalchemy.orm import Session, configure_mappers

import kb.world.generated.accessors as gen
from generators.accessors import AccessorsGenerator
from generators.sql import build_metadata, ddl
from generators.sql_model import shipped_schema
from kb import world
from kb.core.resources import scenario_dirs

MODULE = Path(gen.__file__)


def test_checked_in_module_is_up_to_date():
    fresh = AccessorsGenerator().serialize()
    current = MODULE.read_text(encoding="utf-8")
    if fresh != current:
        diff = "".join(list(difflib.unified_diff(current.splitlines(True), fresh.splitlines(True),
                                                 "checked in", "regenerated"))[:40])
        pytest.fail("kb/accessors_generated.py is stale; run python -m generators.accessors\n" + diff)


def test_generation_is_deterministic():
    assert AccessorsGenerator().serialize() == AccessorsGenerator(shipped_schema()).serialize()


@pytest.mark.parametrize("dialect", ["sqlite", "postgresql"])
def test_module_metadata_is_the_generated_schema(dialect):
    schema = shipped_schema()
    assert gen.SCHEMA_VERSION == schema.fingerprint()
    assert ddl(gen.Base.metadata, dialect) == ddl(build_metadata(schema), dialect)


def test_mappers_configure_and_types():
    configure_mappers()
    assert issubclass(gen.Part, gen.SkuObject) and issubclass(gen.SkuObject, gen.SolidObject)
    assert issubclass(gen.PoseLocationIn, gen.PoseLocation)
    hints = gen.Point.__annotations__
    assert hints["x"] == "Mapped[float]"
    assert gen.EndEffector.__annotations__["held_object"] == "Mapped[SolidObject | None]"
    assert gen.Kit.__annotations__["part"] == "Mapped[list[Part]]"


def test_orm_reads_a_loaded_scenario(tmp_path):
    from rdflib import RDF, Graph, Namespace, URIRef

    ktw = Namespace("https://w3id.org/kitkb/kitting#")
    scen = next(d for d in scenario_dirs() if (d / "init.ttl").is_file())
    url = world.normalize_url(tmp_path / "w.sqlite")
    world.load(scen / "init.ttl", url)
    data = Graph().parse(scen / "init.ttl", format="turtle")  # what the ORM must give back
    (ws_node,) = data.subjects(RDF.type, ktw.KittingWorkstation)
    engine = world.open_engine(url)
    try:
        with Session(engine) as session:
            parts = session.scalars(select(gen.Part)).all()
            assert sorted(p.iri for p in parts) == sorted(str(s) for s in data.subjects(RDF.type, ktw.Part))
            assert all(isinstance(p, gen.Part) for p in parts)
            part = parts[0]
            loc = part.primary_location
            assert loc.iri == str(data.value(URIRef(part.iri), ktw.hasSolidObject_PrimaryLocation))
            assert isinstance(loc, gen.PhysicalLocation) and isinstance(loc.ref_object, gen.SolidObject)
            assert loc.ref_object.iri == str(data.value(URIRef(loc.iri), ktw.hasPhysicalLocation_RefObject))
            assert isinstance(loc, gen.PoseLocation) and isinstance(loc.point.x, float)
            point = data.value(URIRef(loc.iri), ktw.hasPoseLocation_Point)
            assert loc.point.x == float(data.value(point, ktw.hasPoint_X))
            ws = session.scalars(select(gen.KittingWorkstation)).one()
            assert ws.iri == str(ws_node)
            assert ws.length_unit == str(data.value(ws_node, ktw.hasKittingWorkstation_LengthUnit))  # "meter"
            # a link table
            objects = sorted(str(o) for o in data.objects(ws_node, ktw.hasKittingWorkstation_Object))
            assert sorted(o.iri for o in ws.object) == objects
            assert all(isinstance(o, gen.SolidObject) for o in ws.object)
    finally:
        engine.dispose()


def test_orm_writes_are_dumped_and_checks_enforced(tmp_path):
    from rdflib import Literal, URIRef
    from sqlalchemy.exc import IntegrityError

    scen = next(d for d in scenario_dirs() if (d / "init.ttl").is_file())
    url = world.normalize_url(tmp_path / "w.sqlite")
    world.load(scen / "init.ttl", url)
    engine = world.open_engine(url)
    try:
        with Session(engine) as session:
            session.add(gen.Point(iri="https://example.org/new#p1", name="p1", x=1.0, y=2.0, z=3.5))
            session.commit()
        with Session(engine) as session:  # CHECK (weight > 0.0) in the real database
            session.add(gen.StockKeepingUnit(iri="https://example.org/new#s", name="s", description="x", weight=-1.0))
            with pytest.raises(IntegrityError):
                session.commit()
    finally:
        engine.dispose()
    g = world.read_graph(url)
    p1 = URIRef("https://example.org/new#p1")
    assert g.value(p1, URIRef("https://w3id.org/kitkb/kitting#hasPoint_Z")).eq(Literal(3.5))
    assert (URIRef("https://example.org/new#s"), None, None) not in g


def test_ddl_of_one_dialect_leaves_the_metadata_as_it_was():
    """SQLAlchemy's AddConstraint marks foreign keys for good; DDL for PostgreSQL (ALTER TABLE ...
    ADD CONSTRAINT) must not drop them from a later SQLite CREATE TABLE in the same process."""
    sqlite_before = ddl(gen.Base.metadata, "sqlite")
    assert "ADD CONSTRAINT" in ddl(gen.Base.metadata, "postgresql")
    assert ddl(gen.Base.metadata, "sqlite") == sqlite_before
    assert "fk_kitkb_literal_thing_id" in sqlite_before
