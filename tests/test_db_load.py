"""kitkb db load: no silent wipe (--replace), atomic loads (a file breaking half way, a database
error half way, SIGKILL during the load), on SQLite and PostgreSQL (KITKB_PG_URL).

The round trips themselves are in test_db_roundtrip.py.
"""

from __future__ import annotations

import os
import signal
import sqlite3
import subprocess
import sys
import time
from pathlib import Path

import pytest
from rdflib.compare import isomorphic

from kb import world
from kb.cli import main
from kb.core.errors import InputError
from kb.core.resources import scenario_dirs
from kb.io.loader import load_file
from kb.scenario import write_scenario

PG_URL = os.environ.get("KITKB_PG_URL")
REPO = Path(__file__).resolve().parent.parent
SCENARIOS = {d.name: d for d in scenario_dirs()}
SMALL = SCENARIOS["small-kit"] / "init.ttl"
OTHER = SCENARIOS["two-designs"] / "init.ttl"


def _same_as(url: str, path: Path) -> bool:
    return isomorphic(world.read_graph(url), load_file(path).graph)


# --- no silent wipe -------------------------------------------------------------------------------

def test_loading_over_a_world_model_needs_replace(url):
    world.load(SMALL, url)
    with pytest.raises(InputError) as err:
        world.load(OTHER, url)
    message = str(err.value)
    assert "already holds the world model from init.ttl" in message and "--replace" in message
    assert "individuals" in message
    assert _same_as(url, SMALL)
    report = world.load(OTHER, url, replace=True)
    assert report.replaced is not None and report.replaced.startswith("the world model from init.ttl")
    assert "replaced the world model from init.ttl" in report.summary()
    assert _same_as(url, OTHER)


def test_a_file_without_individuals_is_an_input_error_and_wipes_nothing(url, tmp_path, capsys):
    world.load(SMALL, url)
    empty = tmp_path / "empty.ttl"
    empty.write_text("@prefix owl: <http://www.w3.org/2002/07/owl#> .\n<https://example.org/x> a owl:Ontology .\n")
    for extra, said in (([], "already holds"), (["--replace"], "empty.ttl: error: no individual")):
        assert main(["db", "load", str(empty), "--db", url, *extra]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and said in err, err
    assert _same_as(url, SMALL)


def test_empty_file_into_a_new_database_leaves_no_file(tmp_path, capsys):
    empty, target = tmp_path / "empty.ttl", tmp_path / "new.sqlite"
    empty.write_text("")
    assert main(["db", "load", str(empty), "--db", str(target)]) == 2
    assert "no individual" in capsys.readouterr().err
    assert not target.exists()


def test_cli_says_what_it_replaces(tmp_path, capsys):
    target = tmp_path / "w.sqlite"
    assert main(["db", "load", str(SMALL), "--db", str(target)]) == 0
    capsys.readouterr()
    assert main(["db", "load", str(OTHER), "--db", str(target)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "already holds" in err and "--replace" in err
    with world.WorldModel(target) as wm:
        wm.commit_stable_state({}, True)  # one stable state committed: the message counts it
    assert main(["db", "load", str(OTHER), "--db", str(target), "--replace"]) == 0
    err = capsys.readouterr().err
    assert "replaced the world model from init.ttl" in err and "1 stable states committed" in err


def test_run_history_counts_as_content(url):
    """Tables of a run's history beside the world model (kitkb_ prefix) are named and replaced."""
    world.load(SMALL, url)
    engine = world.open_engine(url)
    with engine.begin() as conn:
        conn.exec_driver_sql("CREATE TABLE kitkb_run_event (id INTEGER PRIMARY KEY, what TEXT)")
        conn.exec_driver_sql("INSERT INTO kitkb_run_event VALUES (1, 'part dropped')")
    engine.dispose()
    with pytest.raises(InputError, match="run history: 1 rows in 1 tables"):
        world.load(OTHER, url)
    report = world.load(OTHER, url, replace=True)
    assert "run history: 1 rows in 1 tables" in (report.replaced or "")
    engine = world.open_engine(url)
    from sqlalchemy import inspect

    assert "kitkb_run_event" not in inspect(engine).get_table_names()
    engine.dispose()


def test_a_database_that_is_not_kitkb_s_is_never_replaced(tmp_path):
    path = tmp_path / "other.sqlite"
    with sqlite3.connect(path) as conn:
        conn.execute("CREATE TABLE t (a INTEGER)")
        conn.execute("INSERT INTO t VALUES (1)")
    for replace in (False, True):
        with pytest.raises(world.SchemaVersionError, match="not a kitkb database"):
            world.load(SMALL, path, replace=replace)
    with sqlite3.connect(path) as conn:
        assert conn.execute("SELECT a FROM t").fetchall() == [(1,)]


def test_another_ontology_version_is_replaced_only_when_asked(url):
    world.load(SMALL, url)
    engine = world.open_engine(url)
    with engine.begin() as conn:
        conn.exec_driver_sql("UPDATE kitkb_meta SET value = 'f00' WHERE key = 'schema_version'")
    engine.dispose()
    with pytest.raises(InputError, match="another ontology version.*--replace"):
        world.load(OTHER, url)
    report = world.load(OTHER, url, replace=True)
    assert report.replaced == "a world model made from another ontology version"
    assert _same_as(url, OTHER)


# --- atomicity ---------------------------------------------------------------------------------------

def _broken_half_way(tmp_path: Path, how: str) -> tuple[Path, int]:
    """OTHER's text with a syntax error, or a value outside its datatype, half way down."""
    lines = OTHER.read_text(encoding="utf-8").splitlines(keepends=True)
    at = next(i for i in range(len(lines) // 2, len(lines)) if "ktw:hasPoint_X" in lines[i])
    if how == "syntax":
        lines[at] = lines[at].replace("ktw:hasPoint_X", "ktw:hasPoint_X [ ; ,")
    else:
        lines[at] = "    ktw:hasPoint_X \"abc\"^^xsd:decimal ;\n"
    bad = tmp_path / f"broken-{how}.ttl"
    bad.write_text("".join(lines), encoding="utf-8")
    return bad, at + 1


@pytest.mark.parametrize("how", ["syntax", "value"])
def test_a_file_that_breaks_half_way_changes_nothing(url, tmp_path, how):
    world.load(SMALL, url)
    bad, line = _broken_half_way(tmp_path, how)
    with pytest.raises(InputError) as err:
        world.load(bad, url, replace=True)
    assert str(err.value).startswith(f"{bad}:{line}: error:"), str(err.value)
    assert _same_as(url, SMALL)


def test_a_database_error_half_way_changes_nothing(url, monkeypatch):
    """The database fails after half the tables are written (a full disk, say): rolled back."""
    world.load(SMALL, url)
    load_module = sys.modules["kb.world.load"]
    if url.startswith("sqlite"):
        real = load_module.insert_sqlite

        def half_then_fail(cur, tables):
            tables = list(tables)
            real(cur, tables[: len(tables) // 2])
            cur.execute("SELECT no_such_column FROM kitkb_meta")  # the driver's own error

        monkeypatch.setattr(load_module, "insert_sqlite", half_then_fail)
    else:
        real_buffers = load_module.copy_buffers

        def half_then_fail(tables):
            buffers = list(real_buffers(tables))
            yield from buffers[: len(buffers) // 2]
            yield "COPY no_such_table FROM STDIN", b"1\n"  # the server's own error

        monkeypatch.setattr(load_module, "copy_buffers", half_then_fail)
    with pytest.raises(InputError, match="database refused the data"):
        world.load(OTHER, url, replace=True)
    monkeypatch.undo()
    assert _same_as(url, SMALL)
    with world.WorldModel(url) as wm:
        assert len(wm.global_poses()) == len(wm.objects("SolidObject"))


def test_a_failed_load_into_a_new_file_leaves_no_file(tmp_path, monkeypatch):
    target = tmp_path / "new.sqlite"
    load_module = sys.modules["kb.world.load"]
    monkeypatch.setattr(load_module, "insert_sqlite", lambda cur, tables: cur.execute("SELECT nothing FROM x"))
    with pytest.raises(InputError, match="database refused the data"):
        world.load(SMALL, target)
    assert not any(tmp_path.glob("new.sqlite*"))


# --- SIGKILL during the load --------------------------------------------------------------------------

_LOADER = [sys.executable, "-m", "kb.cli", "db", "load"]


@pytest.fixture(scope="module")
def big(tmp_path_factory) -> Path:
    """A workstation big enough that writing it takes a while (5,000 parts)."""
    init, _ = write_scenario(tmp_path_factory.mktemp("big"), parts=5000, kits=10, seed=3)
    return init


def _kill_when(proc: subprocess.Popen, ready, timeout: float = 120) -> bool:
    """SIGKILL ``proc`` as soon as ``ready()``; False if it ended first."""
    deadline = time.monotonic() + timeout
    while proc.poll() is None and time.monotonic() < deadline:
        if ready():
            proc.send_signal(signal.SIGKILL)
            proc.wait()
            return True
        time.sleep(0.0005)
    proc.wait()
    return False


def _outcome(url: str, before: Path, after: Path) -> str:
    """Which of the two files the database now holds ("before" or "after"; else it fails)."""
    graph = world.read_graph(url)
    if isomorphic(graph, load_file(before).graph):
        return "before"
    assert isomorphic(graph, load_file(after).graph), "the database holds half a load"
    return "after"


@pytest.mark.slow
def test_sigkill_during_a_sqlite_load_leaves_the_last_stable_state(tmp_path, big):
    db = tmp_path / "world.sqlite"
    world.load(SMALL, db)
    with world.WorldModel(db) as wm:  # a stable state after the load: it must survive too
        part = wm.objects("Part")[0].name
        moved = wm.global_pose(part)
        moved[0, 3] += 0.25
        assert wm.commit_stable_state({part: moved}, True).committed
    before = tmp_path / "before.ttl"
    world.dump(db, before)
    wal = Path(str(db) + "-wal")
    env = {**os.environ, "PYTHONPATH": str(REPO)}
    killed_mid_way = 0
    for _ in range(5):
        start = wal.stat().st_size if wal.exists() else 0
        proc = subprocess.Popen([*_LOADER, str(big), "--db", str(db), "--replace"], env=env,
                                stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        # the transaction has written pages once the write-ahead log grows
        if _kill_when(proc, lambda: wal.exists() and wal.stat().st_size > start):
            outcome = _outcome(world.normalize_url(db), before, big)
            if outcome == "before":
                killed_mid_way += 1
                with world.WorldModel(db) as wm:
                    assert wm.stable_state() == 1 and abs(wm.global_pose(part)[0, 3] - moved[0, 3]) < 1e-9
                break
            world.load(before, db, replace=True)  # it committed first: start again from the old state
    assert killed_mid_way, "the load was never caught in its transaction"
    with pytest.raises(InputError, match="already holds"):  # the old world model is still there
        world.load(big, db)


@pytest.mark.slow
def test_sigkill_during_the_load_of_a_new_sqlite_file(tmp_path, big):
    db = tmp_path / "new.sqlite"
    journal = Path(str(db) + "-journal")  # a new file is filled with a rollback journal
    env = {**os.environ, "PYTHONPATH": str(REPO)}
    proc = subprocess.Popen([*_LOADER, str(big), "--db", str(db)], env=env,
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    if not _kill_when(proc, lambda: journal.exists() and db.exists() and db.stat().st_size > 1 << 20):
        pytest.skip("the load ended before it could be killed")
    assert journal.exists()  # killed inside its transaction
    with pytest.raises(world.SchemaVersionError, match="is empty"):  # no half world model
        world.read_graph(db)
    world.load(SMALL, db)  # and the next load needs no --replace
    assert _same_as(world.normalize_url(db), SMALL)


@pytest.mark.slow
@pytest.mark.postgres
def test_sigkill_during_a_postgresql_load_leaves_the_last_stable_state(tmp_path, big):
    if not PG_URL:
        pytest.skip("KITKB_PG_URL is not set")
    import psycopg2
    from sqlalchemy.engine import make_url

    world.drop_all(PG_URL)
    try:
        world.load(SMALL, PG_URL)
        before = tmp_path / "before.ttl"
        world.dump(PG_URL, before)
        u = make_url(PG_URL)
        watch = psycopg2.connect(host=u.host, port=u.port, user=u.username, dbname=u.database)
        watch.autocommit = True
        cur = watch.cursor()

        def copying() -> bool:  # the load's transaction is writing rows
            cur.execute("SELECT count(*) FROM pg_stat_activity WHERE query LIKE 'COPY %%' AND state = 'active' "
                        "AND pid <> pg_backend_pid()")
            return cur.fetchone()[0] > 0

        env = {**os.environ, "PYTHONPATH": str(REPO)}
        killed_mid_way = 0
        for _ in range(5):
            proc = subprocess.Popen([*_LOADER, str(big), "--db", PG_URL, "--replace"], env=env,
                                    stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            if _kill_when(proc, copying):
                deadline = time.monotonic() + 30  # the server notices the lost client and rolls back
                while time.monotonic() < deadline:
                    cur.execute("SELECT count(*) FROM pg_stat_activity WHERE state <> 'idle' AND "
                                "pid <> pg_backend_pid() AND datname = current_database()")
                    if cur.fetchone()[0] == 0:
                        break
                    time.sleep(0.05)
                if _outcome(PG_URL, before, big) == "before":
                    killed_mid_way += 1
                    break
                world.load(before, PG_URL, replace=True)
        watch.close()
        assert killed_mid_way, "the load was never caught in its transaction"
    finally:
        world.drop_all(PG_URL)


# --- a reload seen by an open WorldModel ----------------------------------------------------------------

def test_an_open_world_model_sees_a_reload(url):
    world.load(SMALL, url)
    with world.WorldModel(url) as wm:
        poses = wm.global_poses()
        world.load(OTHER, url, replace=True)  # another process could do this
        after = wm.global_poses()
        with world.WorldModel(url) as fresh:
            assert set(after) == set(fresh.global_poses()) != set(poses)
        name = next(iter(set(after) - set(poses)))
        assert wm.global_pose(name).shape == (4, 4)


# --- what a load into an SQLite file does without ----------------------------------------------------

def test_an_sqlite_load_imports_neither_sqlalchemy_nor_the_accessors(tmp_path):
    """The cached load plan and DDL stand in for them (kb.world.cache); a fresh process shows it."""
    code = ("import sys; from kb.world import load; load(sys.argv[1], sys.argv[2]); "
            "print(sorted(m for m in sys.modules if m.startswith('sqlalchemy') or m.endswith('accessors')))")
    env = {**os.environ, "PYTHONPATH": str(REPO), "KITKB_CACHE_DIR": str(tmp_path / "cache")}
    runs = [subprocess.run([sys.executable, "-c", code, str(SMALL), str(tmp_path / f"w{i}.sqlite")], env=env,
                           capture_output=True, text=True, timeout=300) for i in range(2)]
    assert all(r.returncode == 0 for r in runs), runs[0].stderr + runs[1].stderr
    assert runs[1].stdout.strip() == "[]"  # the first run made the cache
    assert _same_as(world.normalize_url(tmp_path / "w1.sqlite"), SMALL)


def test_sqlite_dates_and_times_are_stored_as_sqlalchemy_stores_them():
    import datetime as dt

    from sqlalchemy import Date, DateTime
    from sqlalchemy.dialects import sqlite as sqlite_dialect

    from kb.world.bulk import sqlite_date, sqlite_datetime

    dialect = sqlite_dialect.dialect()
    stamp = dt.datetime(2024, 2, 29, 23, 59, 58, 123456)
    day = dt.date(1999, 12, 31)
    assert sqlite_datetime(stamp) == DateTime(timezone=True).dialect_impl(dialect).bind_processor(dialect)(stamp)
    assert sqlite_date(day) == Date().dialect_impl(dialect).bind_processor(dialect)(day)


def test_a_new_file_ignores_what_a_deleted_database_left_beside_it(tmp_path):
    """A database deleted by hand while a writer was killed leaves a hot journal behind; the
    load that makes a new file of that name must not be rolled back with it (SQLite drops a
    journal, or a write-ahead log, found beside an empty database file)."""
    target = tmp_path / "w.sqlite"
    writer = ("import sqlite3, os, sys; c = sqlite3.connect(sys.argv[1], isolation_level=None); "
              "c.execute('CREATE TABLE kitkb_meta (key TEXT, value TEXT)'); "
              "c.executemany('INSERT INTO kitkb_meta VALUES (?, ?)', [(str(i), 'x' * 500) for i in range(2000)]); "
              "c.execute('BEGIN'); c.execute('UPDATE kitkb_meta SET value = ?', ('y' * 600,)); os._exit(0)")
    subprocess.run([sys.executable, "-c", writer, str(target)], check=True, timeout=120)
    assert Path(str(target) + "-journal").stat().st_size > 0  # a hot journal
    target.unlink()
    world.load(SMALL, target)
    assert _same_as(world.normalize_url(target), SMALL)
