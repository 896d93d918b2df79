"""One dict form per record (kb.execution.codec): run, action and failure records round-trip
losslessly through their dict form, JSON, and the run tables of SQLite and PostgreSQL; what a
record cannot hold is refused when it is made; a real run read back equals the run in memory."""

from __future__ import annotations

import dataclasses
import json
import math
import os
from pathlib import Path
from typing import Any, Iterator

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from kb import planning, world
from kb.core.errors import InputError
from kb.core.resources import ontology_path
from kb.execution import open_run, run_plan
from kb.execution.codec import dumps, loads
from kb.execution.records import ActionRecord, AtomCheck, Check, FailureRecord, RunRecord, Sighting
from kb.execution.store import RunStore, _PREPARED, prepare, read_run
from kb.metrics.kits import KitScore, LostPoint

SMALL = Path(ontology_path("kitting-domain.ttl")).parent / "scenarios" / "small-kit"
INIT, GOAL = str(SMALL / "init.ttl"), str(SMALL / "goal.ttl")
FAULTS = "missed-grasp@6,part-missing@9,wrong-sku@12"
NOISE = "position=1mm,orientation=0.5deg,misdetection=1%,misclass=0.5%"
PG_URL = os.environ.get("KITKB_PG_URL")


# --- what a record may hold ----------------------------------------------------------------------

def texts(max_size: int = 12) -> st.SearchStrategy[str]:
    """Any Unicode text a database holds: no NUL, no lone surrogate (emoji, RTL, combining...)."""
    return st.text(st.characters(blacklist_categories=("Cs",), blacklist_characters="\x00"), max_size=max_size)


FLOATS = st.floats(allow_nan=False, allow_infinity=False)  # -0.0, subnormals, 1.7e308 included
INTS = st.integers(-2 ** 63, 2 ** 63 - 1)
POINTS = st.none() | st.tuples(FLOATS, FLOATS, FLOATS)
NAMES = st.lists(texts(), max_size=3)
JSON = st.recursive(st.none() | st.booleans() | INTS | FLOATS | texts(),
                    lambda inner: st.lists(inner, max_size=3) | st.dictionaries(texts(6), inner, max_size=3),
                    max_leaves=6)
OBJECTS = st.dictionaries(texts(6), JSON, max_size=3)

atoms = st.builds(AtomCheck, texts(), NAMES.map(tuple), st.booleans(), st.booleans())
checks = st.builds(Check, INTS, texts(), st.lists(atoms, max_size=3), FLOATS, st.lists(atoms, max_size=2))
sightings = st.builds(Sighting, texts(), POINTS, POINTS)
failures = st.builds(FailureRecord, INTS, texts(), NAMES.map(tuple), texts(), st.lists(atoms, max_size=2),
                     st.lists(sightings, max_size=2), texts(), texts(), INTS, texts(), texts(), FLOATS, NAMES,
                     st.none() | texts(), st.none() | texts(), NAMES)
actions = st.builds(ActionRecord, INTS, texts(), NAMES.map(tuple), texts(), NAMES, FLOATS, FLOATS,
                    st.lists(NAMES, max_size=2))
kits = st.builds(KitScore, texts(), st.none() | texts(), INTS, INTS,
                 st.lists(st.builds(LostPoint, INTS, texts(), texts(), NAMES.map(tuple), st.booleans()),
                          max_size=2).map(tuple))


@st.composite
def runs(draw: st.DrawFn) -> RunRecord:
    """A run with every field drawn; its actions' indexes unique and in order (as an executor
    numbers its attempts: the index is an action's key in its run)."""
    acts = sorted(draw(st.lists(actions, max_size=4, unique_by=lambda a: a.index)), key=lambda a: a.index)
    return RunRecord(
        draw(texts()), draw(st.none() | INTS), acts, draw(st.lists(checks, max_size=3)),
        draw(st.lists(failures, max_size=3)), draw(INTS), draw(st.none() | st.booleans()), draw(st.none() | texts()),
        draw(st.lists(OBJECTS, max_size=2)), draw(FLOATS), draw(FLOATS), None, draw(st.none() | FLOATS),
        draw(FLOATS), violations=draw(st.none() | st.lists(OBJECTS, max_size=2)), kits=draw(st.lists(kits, max_size=2)),
        tip_start=draw(POINTS), scene=draw(st.none() | OBJECTS), sensor=draw(st.none() | OBJECTS),
        sensor_errors=draw(st.none() | st.lists(OBJECTS, max_size=2)), goal_unmet=draw(NAMES),
        repeated_diagnoses=draw(st.lists(OBJECTS, max_size=2)), oracle=draw(st.none() | OBJECTS))


def same(a: Any, b: Any, path: str = "") -> None:
    """``a`` and ``b`` identical: types (tuple is not list, None is not missing, int is not
    float) and floats to the bit (-0.0 is not 0.0), recursively."""
    assert type(a) is type(b), f"{path}: {type(a).__name__} != {type(b).__name__}"
    if dataclasses.is_dataclass(a):
        for f in dataclasses.fields(a):
            same(getattr(a, f.name), getattr(b, f.name), f"{path}.{f.name}")
    elif isinstance(a, (list, tuple)):
        assert len(a) == len(b), path
        for i, (x, y) in enumerate(zip(a, b)):
            same(x, y, f"{path}[{i}]")
    elif isinstance(a, dict):
        assert list(a) == list(b), path
        for k in a:
            same(a[k], b[k], f"{path}.{k}")
    elif isinstance(a, float):
        assert a.hex() == b.hex(), f"{path}: {a!r} != {b!r}"
    else:
        assert a == b, f"{path}: {a!r} != {b!r}"


# --- the dict form, and JSON ---------------------------------------------------------------------

@settings(max_examples=150, deadline=None)
@given(runs())
def test_a_run_round_trips_through_its_dict_form_and_json(run: RunRecord) -> None:
    data = run.to_dict()
    same(RunRecord.from_dict(data), run)
    same(RunRecord.from_dict(loads(dumps(data))), run)
    assert loads(dumps(data)) == data and dumps(data).isascii()


@settings(max_examples=100, deadline=None)
@given(failures, actions, checks)
def test_each_record_round_trips_on_its_own(failure: FailureRecord, action: ActionRecord, check: Check) -> None:
    for record in (failure, action, check, *check.atoms):
        same(type(record).from_dict(loads(dumps(record.to_dict()))), record)


def test_every_field_is_in_the_dict_form_and_only_the_fields() -> None:
    for cls in (RunRecord, ActionRecord, FailureRecord, Check, AtomCheck, Sighting):
        assert set(_example(cls).to_dict()) == {f.name for f in dataclasses.fields(cls)}
    data = FailureRecord(1, "take-part", ("r", "p"), "effect", [], [], "m").to_dict()
    assert data["certainty"] is None and data["args"] == ["r", "p"]  # null, not missing; a list in JSON
    del data["certainty"], data["witnesses"]  # missing with a default: the default
    assert FailureRecord.from_dict(data).certainty is None


def _example(cls: type) -> Any:
    return {RunRecord: RunRecord("s"), ActionRecord: ActionRecord(0, "a", ()), Check: Check(0, "effect", [], 0.0),
            FailureRecord: FailureRecord(0, "a", (), "effect", [], [], "m"), AtomCheck: AtomCheck("p", (), False, True),
            Sighting: Sighting("o", None, None)}[cls]


@pytest.mark.parametrize(("make", "says"), [
    (lambda: Sighting("o", (0.0, math.nan, 0.0), None), "Sighting.expected[1]: a finite number, not nan"),
    (lambda: Check(0, "effect", [], math.inf), "Check.time: a finite number, not inf"),
    (lambda: ActionRecord(0, "take\x00part", ()), "ActionRecord.action: text without NUL characters"),
    (lambda: RunRecord("s\ud800"), "RunRecord.scenario: text without lone surrogates"),
    (lambda: RunRecord("s", seed=2 ** 63), "RunRecord.seed: a 64-bit integer"),
    (lambda: RunRecord("s", seed=True), "RunRecord.seed: an integer, not True"),
    (lambda: RunRecord("s", tip_start=(1.0, 2.0)), "RunRecord.tip_start: 3 items"),
    (lambda: AtomCheck("p", ("a",), False, "yes"), "AtomCheck.holds: true or false"),
    (lambda: RunRecord("s", injected=[{"detail": math.nan}]), "RunRecord.injected[0].detail: a finite number"),
    (lambda: RunRecord("s", sensor={1: "x"}), "RunRecord.sensor: an object with string keys"),
    (lambda: RunRecord("s", scene={"o": {1, 2}}), "RunRecord.scene.o: JSON data"),
])
def test_what_a_record_cannot_hold_is_refused_when_it_is_made(make: Any, says: str) -> None:
    with pytest.raises(ValueError, match=r"^" + __import__("re").escape(says)):
        make()


def test_a_field_set_later_is_checked_and_made_canonical() -> None:
    import numpy as np
    run = RunRecord("s")
    with pytest.raises(ValueError, match="RunRecord.ended: a finite number"):
        run.ended = math.nan
    run.replans = np.int64(3)
    run.tip_start = [np.float64(0.5), 1, 2.0]  # a list of numbers: the tuple of floats the field is
    run.violations = [{"objects": ("a", "b"), "detail": np.float32(0.25)}]  # JSON data: a tuple is a list
    same(run.replans, 3)
    same(run.tip_start, (0.5, 1.0, 2.0))
    same(run.violations, [{"objects": ["a", "b"], "detail": 0.25}])
    same(RunRecord.from_dict(loads(dumps(run.to_dict()))), run)
    kept: list[ActionRecord] = []
    run.actions = kept
    kept.append(ActionRecord(0, "a", ()))  # the list given is the record's, not a copy
    assert run.actions is kept and len(run.to_dict()["actions"]) == 1


@pytest.mark.parametrize(("data", "says"), [
    ({"scenario": "s", "colour": "red"}, "RunRecord: a RunRecord has no field 'colour'"),
    ({"seed": 1}, "RunRecord: a RunRecord needs its field 'scenario'"),
    ({"scenario": "s", "tip_start": [1, 2, "x"]}, "RunRecord.tip_start[2]: a number"),
    ({"scenario": "s", "actions": [{"index": 0, "action": "a", "args": "r"}]}, "RunRecord.actions[0].args: a list"),
    ({"scenario": "s", "failures": [{"mode": "m"}]}, "RunRecord.failures[0]: a FailureRecord needs its field"),
])
def test_data_that_is_not_a_dict_form_is_refused_naming_the_field(data: dict, says: str) -> None:
    with pytest.raises(ValueError, match=r"^" + __import__("re").escape(says)):
        RunRecord.from_dict(data)


# --- the run tables: SQLite and PostgreSQL -------------------------------------------------------

@pytest.fixture(scope="module", params=["sqlite", pytest.param("postgresql", marks=pytest.mark.postgres)])
def prepared(request: pytest.FixtureRequest, tmp_path_factory: pytest.TempPathFactory) -> Iterator[str]:
    """A world-model database with small-kit's initial state and the domain (run tables next)."""
    if request.param == "sqlite":
        url = world.normalize_url(tmp_path_factory.mktemp("codec") / "world.sqlite")
    elif not PG_URL:
        pytest.skip("KITKB_PG_URL is not set")
    else:
        url = PG_URL
        world.drop_all(url)
    prepare(url, INIT)
    _PREPARED.pop(world.normalize_url(url)).release()  # each run below takes the database's lock itself
    yield url
    if request.param == "postgresql":
        world.drop_all(url)


def store_run(url: str, run: RunRecord) -> int:
    """``run`` recorded as an executor records it: begun, each action and failure as it ends, ended."""
    store = RunStore(url)
    try:
        store.begin_run(run)
        for action in run.actions:
            store.record_action(action)
        for failure in run.failures:
            store.record_failure(failure)
        store.end_run(run)
    finally:
        store.close()
    assert run.run_id is not None
    return run.run_id


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(runs())
def test_a_run_round_trips_through_the_run_tables(prepared: str, run: RunRecord) -> None:
    run_id = store_run(prepared, run)
    back = read_run(prepared, run_id)
    same(back, run)
    same(open_run(prepared, run_id).record, run)


def test_long_and_unusual_text_and_extreme_numbers_round_trip_through_the_tables(prepared: str) -> None:
    text = "kit ✓ 工具 \u202e\u0301 " + "x" * 5000  # beyond any column length PostgreSQL had before
    failure = FailureRecord(2 ** 62, text, (text,), "effect", [AtomCheck(text, (text,), True, True)],
                            [Sighting(text, (5e-324, -0.0, 1.7976931348623157e308), None)], "mode ✓",
                            text, -2 ** 63, "retry", text, -1e308, [text], None, "certain", [])
    run = RunRecord(text, 2 ** 63 - 1, [ActionRecord(-2 ** 63, text, (text,), text, [text], 1e308, -1e308, [[text]])],
                    failures=[failure], replans=2 ** 62, plan_time=0.1 + 0.2, sensor={"é": [1, 2.5, None, True]})
    same(read_run(prepared, store_run(prepared, run)), run)


def test_what_changes_after_a_record_is_stored_is_stored_at_the_run_end(prepared: str) -> None:
    run = RunRecord("later", actions=[ActionRecord(0, "take-part", ("r", "p"))],
                    failures=[FailureRecord(0, "take-part", ("r", "p"), "effect", [], [], "missed-grasp")])
    store = RunStore(prepared)
    try:
        store.begin_run(run)
        store.record_action(run.actions[0])
        store.record_failure(run.failures[0])
        run.actions[0].status, run.failures[0].outcome = "done", "recovered: retry 1 of 3"  # decided afterwards
        run.failures.append(FailureRecord(1, "put-part", (), "effect", [], [], "unexplained"))  # never recorded
        store.record_failure(run.failures[0])  # recorded again: one row, updated
        store.end_run(run)
    finally:
        store.close()
    same(read_run(prepared, run.run_id), run)


def test_run_tables_of_an_older_version_are_widened_and_given_their_record_column(prepared: str) -> None:
    from sqlalchemy import create_engine, text
    old = RunRecord("before", 1, [ActionRecord(0, "a", ("x",), "done")],
                    failures=[FailureRecord(0, "a", ("x",), "effect", [], [], "m", outcome="gave up")])
    store_run(prepared, old)
    engine = create_engine(prepared)
    with engine.begin() as c:  # the tables as 472f1d7 made them: no record column, 32-bit integers, short text
        for table in ("kitkb_run", "kitkb_run_action", "kitkb_run_failure"):
            c.execute(text(f"ALTER TABLE {table} DROP COLUMN record"))
        if engine.dialect.name == "postgresql":  # rows other tests stored (this database is the worker's)
            c.execute(text("UPDATE kitkb_run SET seed = 0 WHERE seed NOT BETWEEN -2147483648 AND 2147483647"))
            c.execute(text("UPDATE kitkb_run SET scenario = left(scenario, 200)"))
            c.execute(text("UPDATE kitkb_run_failure SET mode = left(mode, 200)"))
            c.execute(text("ALTER TABLE kitkb_run ALTER COLUMN seed TYPE INTEGER, "
                           "ALTER COLUMN scenario TYPE VARCHAR(200)"))
            c.execute(text("ALTER TABLE kitkb_run_failure ALTER COLUMN mode TYPE VARCHAR(200)"))
    engine.dispose()
    back = read_run(prepared, old.run_id)  # from the old columns
    assert (back.scenario, back.seed, back.actions[0].status, back.failures[0].outcome) == ("before", 1, "done", "gave up")
    new = RunRecord("n" * 300, 2 ** 40, failures=[FailureRecord(0, "a", (), "effect", [], [], "m" * 300)])
    same(read_run(prepared, store_run(prepared, new)), new)  # the store widened the tables and added record


# --- a real run, and older databases -------------------------------------------------------------

@pytest.fixture(scope="module")
def small_plan() -> list[str]:
    return planning.run(planning.kitting_model([INIT], [GOAL], "strips").up_problem, None, None).lines


def _noisy_run(plan: list[str], db: str | Path) -> Any:
    return run_plan(plan, INIT, GOAL, faults=FAULTS, seed=1, notifier=lambda *a: None, sensor_noise=NOISE, db=db)


def _assert_read_back_equal(run: Any, url: str | Path) -> None:
    back = open_run(url)
    same(back.record, run.record)
    rec = run.record
    # what earlier versions lost: each failure's certainty and the modes it considered, the sensor, its errors
    assert [f.certainty for f in rec.failures] == ["certain"] * 3 and all(f.considered for f in rec.failures)
    assert rec.sensor["accuracy"]["position"] == 0.001 and rec.sensor["queries"] > 0 and rec.sensor_errors
    assert rec.checks and back.history() == run.history() and back.why(6) == run.why(6)
    assert back.report() == run.report() and back.metrics == run.metrics


def test_a_real_noisy_run_with_faults_reads_back_equal_to_the_run_in_memory(small_plan: list[str],
                                                                             tmp_path: Path) -> None:
    db = tmp_path / "w.sqlite"
    _assert_read_back_equal(_noisy_run(small_plan, db), db)


@pytest.mark.postgres
def test_a_real_noisy_run_with_faults_reads_back_equal_on_postgresql(small_plan: list[str]) -> None:
    if not PG_URL:
        pytest.skip("KITKB_PG_URL is not set")
    world.drop_all(PG_URL)
    try:
        _assert_read_back_equal(_noisy_run(small_plan, PG_URL), PG_URL)
    finally:
        world.drop_all(PG_URL)


def test_a_database_of_an_older_version_opens_and_records_new_runs(small_plan: list[str], tmp_path: Path) -> None:
    import sqlite3
    db = tmp_path / "w.sqlite"
    old = _noisy_run(small_plan, db)
    with sqlite3.connect(db) as c:  # the run tables as kitkb made them before records had a dict form
        for table in ("kitkb_run", "kitkb_run_action", "kitkb_run_failure"):
            c.execute(f"ALTER TABLE {table} DROP COLUMN record")
    back = open_run(db).record  # what the old columns and the report hold
    assert [(f.mode, f.recovery, f.outcome, f.certainty, f.witnesses) for f in back.failures] == \
        [(f.mode, f.recovery, f.outcome, f.certainty, f.witnesses) for f in old.record.failures]
    assert back.sensor == old.record.sensor and back.sensor_errors == old.record.sensor_errors
    assert back.kits == old.record.kits and back.actions[3].programs == old.record.actions[3].programs
    new = RunRecord("new", 7, [ActionRecord(0, "a", ("x",), "done")], plan_time=0.5)
    store_run(str(db), new)  # the store adds the record columns
    same(read_run(db, new.run_id), new)
    assert open_run(db, old.record.run_id).record.failures[0].certainty == "certain"


def test_a_row_that_is_not_a_record_is_refused_in_one_line(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    import sqlite3

    from kb.cli import main
    db = _prepared_sqlite(tmp_path)
    run = store_run(str(db), RunRecord("s", failures=[FailureRecord(0, "a", (), "effect", [], [], "m")]))
    with sqlite3.connect(db) as c:
        (text,), = c.execute("SELECT record FROM kitkb_run_failure").fetchall()
        c.execute("UPDATE kitkb_run_failure SET record = ?", (json.dumps(dict(json.loads(text), colour="red")),))
    with pytest.raises(InputError, match=r"run 1: failure row 1: a FailureRecord has no field 'colour'"):
        read_run(db, run)
    capsys.readouterr()
    assert main(["metrics", "--run", str(run), "--db", str(db)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "has no field 'colour'" in err[0] and "Traceback" not in err[0]


def _prepared_sqlite(tmp_path: Path) -> Path:
    db = tmp_path / "p.sqlite"
    prepare(db, INIT)
    _PREPARED.pop(world.normalize_url(db)).release()
    return db
