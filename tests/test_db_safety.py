"""Databases never lose data (issue 17): a load into a file that is not a kitkb world model is
refused without touching it; two writers of one world model at once (two runs, a load during a
run) either both finish or one is refused with one line, never a corrupt file nor a lost stable
state; a killed run leaves its last stable state and no lock behind. SQLite and PostgreSQL.
"""

from __future__ import annotations

import json
import os
import random
import signal
import sqlite3
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from kb import world
from kb.cli import main
from kb.world.database import safe_url, sqlite_file
from kb.world.lock import PG_KEY, DatabaseBusy, hold, lock_path

PG_URL = os.environ.get("KITKB_PG_URL")
KITKB = [sys.executable, "-m", "kb.cli"]
#: Each stable-state commit of a run slowed down by $KITKB_TEST_PAUSE seconds (so that a second
#: writer meets the run mid-way), the poses after each commit appended to $KITKB_TEST_POSES as
#: JSON lines (stable state, global poses).
_PATCH = """
import json, os, sys, time
from kb.execution import store
pause, record = float(os.environ.get("KITKB_TEST_PAUSE", "0")), os.environ.get("KITKB_TEST_POSES")
def note(self):
    if record:
        with open(record, "a") as out:
            poses = {n: m.tolist() for n, m in self.world.global_poses().items()}
            out.write(json.dumps([self.world.stable_state(), poses]) + "\\n")
begin, commit = store.RunStore.begin_run, store.RunStore.commit_stable
def begin_run(self, *a, **k):
    begin(self, *a, **k); note(self)
def commit_stable(self, *a):
    commit(self, *a); note(self); time.sleep(pause)
store.RunStore.begin_run, store.RunStore.commit_stable = begin_run, commit_stable
"""
#: ``kitkb`` with the patch.
SLOW_KITKB = [sys.executable, "-c", _PATCH + "from kb.cli import main\nsys.exit(main(sys.argv[1:]))\n"]
#: A run of a given plan (PLAN INIT GOAL URL) with the patch: what ``kitkb run --db URL
#: --replace`` does after validating and planning (kb.execution.run_plan), without those seconds.
SLOW_PLAN = [sys.executable, "-c", _PATCH + """
from kb.execution import run_plan
plan, init, goal, url = sys.argv[1:]
run_plan(open(plan).read().splitlines(), init, goal, db=url, replace=True)
"""]


@pytest.fixture(scope="module")
def scenario(tmp_path_factory) -> tuple[Path, Path]:
    out = tmp_path_factory.mktemp("scenario")
    assert main(["scenario", "generate", "--parts", "3", "-o", str(out), "-q"]) == 0
    return out / "init.ttl", out / "goal.ttl"


@pytest.fixture(scope="module")
def kitkb_db(scenario, tmp_path_factory) -> Path:
    """A kitkb world model (to copy)."""
    db = tmp_path_factory.mktemp("model") / "w.sqlite"
    world.load(scenario[0], db)
    return db


def _other_app(path: Path, view: bool = False) -> Path:
    conn = sqlite3.connect(path)
    conn.execute("CREATE TABLE users (id INTEGER PRIMARY KEY, name TEXT)")
    conn.executemany("INSERT INTO users VALUES (?, ?)", [(1, "ada"), (2, "bob")])
    if view:
        conn.execute("CREATE VIEW names AS SELECT name FROM users")
    conn.commit()
    conn.close()
    return path


def _foreign(kind: str, folder: Path, scenario: tuple[Path, Path]) -> Path:
    """A file that is not a kitkb world model."""
    path = folder / {"turtle": "state.ttl", "png": "picture.png", "garbage": "data.bin",
                     "other-sqlite": "app.sqlite", "other-sqlite-in-wal": "app.sqlite", "sqlite-view": "app.db",
                     "short": "x.sqlite"}[kind]
    if kind == "turtle":
        path.write_bytes(scenario[0].read_bytes())
    elif kind == "png":
        path.write_bytes(b"\x89PNG\r\n\x1a\n" + bytes(range(256)) * 8)
    elif kind == "garbage":
        path.write_bytes(random.Random(7).randbytes(5000))
    elif kind == "short":
        path.write_bytes(b"hi\n")
    elif kind == "sqlite-view":
        conn = sqlite3.connect(path)
        conn.execute("CREATE VIEW v AS SELECT 1 AS one")
        conn.close()
    else:
        _other_app(path)
        if kind == "other-sqlite-in-wal":
            conn = sqlite3.connect(path)
            conn.execute("PRAGMA journal_mode = WAL")
            conn.close()
    return path


def _one_line_error(err: str, names: str) -> str:
    """The command's error output is one line (no traceback) naming ``names``."""
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith("error:") and "Traceback" not in err, err
    assert names in lines[0], lines[0]
    return lines[0]


def _beside(path: Path) -> set[str]:
    return {p.name for p in path.parent.iterdir()} - {path.name}


FOREIGN = ["turtle", "png", "garbage", "short", "other-sqlite", "other-sqlite-in-wal", "sqlite-view"]


@pytest.mark.parametrize("kind", FOREIGN)
@pytest.mark.parametrize("command", ["load", "load --replace", "dump"])
def test_a_file_that_is_not_a_world_model_is_refused_untouched(kind, command, tmp_path, scenario, capsys):
    folder = tmp_path / "f"
    folder.mkdir()
    path = _foreign(kind, folder, scenario)
    before, around = path.read_bytes(), _beside(path)
    if command == "dump":
        argv = ["db", "dump", "--db", str(path), "-o", str(tmp_path / "out.ttl")]
    else:
        argv = ["db", "load", str(scenario[0]), "--db", str(path), *command.split()[1:]]
    assert main(argv) == 2
    line = _one_line_error(capsys.readouterr().err, str(path))
    assert "kitkb" in line
    assert path.read_bytes() == before
    assert _beside(path) == around  # no -wal, -shm, -journal or lock file left
    assert not (tmp_path / "out.ttl").exists()


def test_the_foreign_cases_are_all_there():
    assert len(FOREIGN) == 7


def test_a_run_into_someone_else_s_database_is_refused_untouched(tmp_path, scenario, capsys):
    path = _other_app(tmp_path / "app.sqlite")
    before = path.read_bytes()
    assert main(["run", *map(str, scenario), "--db", str(path), "--replace", "-o", str(tmp_path / "out"), "-q"]) == 2
    _one_line_error(capsys.readouterr().err, str(path))
    assert path.read_bytes() == before


def test_an_empty_file_holds_nothing_to_lose_and_is_loaded_into(tmp_path, scenario):
    """A 0-byte file is an empty SQLite database (``touch w.sqlite``): loaded into, no --replace."""
    path = tmp_path / "w.sqlite"
    path.touch()
    assert main(["db", "load", str(scenario[0]), "--db", str(path), "-q"]) == 0
    with world.WorldModel(path) as wm:
        assert wm.objects("Part")
    assert _integrity(path) == "ok"


def test_a_world_model_of_another_version_is_replaced_only_when_asked(tmp_path, scenario, kitkb_db, capsys):
    path = tmp_path / "w.sqlite"
    path.write_bytes(kitkb_db.read_bytes())
    conn = sqlite3.connect(path)
    conn.execute("UPDATE kitkb_meta SET value = 'older' WHERE key = 'schema_version'")
    conn.commit()
    conn.close()
    before = path.read_bytes()
    assert main(["db", "load", str(scenario[0]), "--db", str(path)]) == 2
    assert "another ontology version" in _one_line_error(capsys.readouterr().err, str(path))
    assert path.read_bytes() == before
    assert main(["db", "load", str(scenario[0]), "--db", str(path), "--replace", "-q"]) == 0
    assert _integrity(path) == "ok"


def test_replace_keeps_the_tables_of_others_beside_a_world_model(tmp_path, scenario, kitkb_db):
    path = tmp_path / "w.sqlite"
    path.write_bytes(kitkb_db.read_bytes())
    _other_app(path, view=True)
    assert main(["db", "load", str(scenario[0]), "--db", str(path), "--replace", "-q"]) == 0
    conn = sqlite3.connect(path)
    assert conn.execute("SELECT name FROM names ORDER BY name").fetchall() == [("ada",), ("bob",)]
    conn.close()


# --- one writer at a time -------------------------------------------------------------------------

def _integrity(path: Path | str) -> str:
    conn = sqlite3.connect(path)
    try:
        return "; ".join(r[0] for r in conn.execute("PRAGMA integrity_check"))
    finally:
        conn.close()


def _check_database(url: str) -> None:
    """SQLite: ``PRAGMA integrity_check`` is ok; both: the world model opens and dumps."""
    path = sqlite_file(url)
    if path is not None:
        assert _integrity(path) == "ok"
    world.read_graph(url)


def _state(url: str) -> tuple[int, dict[str, np.ndarray]]:
    with world.WorldModel(url) as wm:
        return wm.stable_state(), wm.global_poses()


def _run_args(scenario, url: str, out: Path, *extra: str) -> list[str]:
    return ["run", *map(str, scenario), "--db", url, "-o", str(out), "-q", *extra]


def _started(proc: subprocess.Popen, url: str, timeout: float = 60) -> None:
    """Wait until the run ``proc`` holds its database (it is past validation and planning)."""
    path = sqlite_file(url)
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline and proc.poll() is None:
        if path is not None and lock_path(path).exists():
            return
        if path is None and _pg_held(url):
            return
        time.sleep(0.01)
    raise AssertionError(f"the run never took its database: {proc.communicate()}")


def _pg_held(url: str) -> bool:
    from sqlalchemy import create_engine, text

    engine = create_engine(url)
    try:
        with engine.connect() as conn:
            return bool(conn.execute(text("SELECT count(*) FROM pg_locks WHERE locktype = 'advisory' "
                                          f"AND classid = {PG_KEY} AND granted")).scalar())
    finally:
        engine.dispose()


def _slow(env_pause: float, poses: Path | None = None) -> dict[str, str]:
    env = {**os.environ, "KITKB_TEST_PAUSE": str(env_pause)}
    if poses is not None:
        env["KITKB_TEST_POSES"] = str(poses)
    return env


def test_a_second_writer_is_refused_while_a_run_holds_the_database(url, scenario, tmp_path):
    """The lock as another process sees it: this process holds it as a run would (a real run
    meets a real one in test_a_second_run_during_a_run_is_refused)."""
    world.load(scenario[0], url)
    with hold(url, "a run"):
        done = subprocess.run([*KITKB, "db", "load", str(scenario[0]), "--db", url, "--replace"],
                              capture_output=True, text=True, timeout=300)
        assert done.returncode == 2, done.stderr
        line = _one_line_error(done.stderr, safe_url(url))
        assert f"in use by a run (pid {os.getpid()}" in line
    _check_database(url)
    assert _state(url)[0] == 0  # the world model loaded above, untouched
    assert main(["db", "load", str(scenario[0]), "--db", url, "--replace", "-q"]) == 0  # given back


def test_the_lock_is_reentrant_and_refuses_other_processes_only(tmp_path):
    url = world.normalize_url(tmp_path / "w.sqlite")
    with hold(url, "a run"), hold(url, "a load"):
        assert lock_path(tmp_path / "w.sqlite").exists()
        code = f"from kb.world.lock import hold\nwith hold({url!r}, 'x'): pass"
        done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
        assert DatabaseBusy.__name__ in done.stderr
    assert not lock_path(tmp_path / "w.sqlite").exists()


def test_a_load_during_a_run_is_refused_and_the_run_finishes(url, scenario, reference, actions, tmp_path):
    run = subprocess.Popen([*SLOW_PLAN, str(reference[0]), *map(str, scenario), url],
                           env=_slow(0.15), stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        _started(run, url)
        load = subprocess.run([*KITKB, "db", "load", str(scenario[0]), "--db", url, "--replace"],
                              capture_output=True, text=True, timeout=120)
        still_running = run.poll() is None
    finally:
        out, err = run.communicate(timeout=300)
    assert run.returncode == 0, err
    assert still_running, "the run ended before the load came: the test proves nothing"
    assert load.returncode == 2
    assert "in use by a run" in _one_line_error(load.stderr, safe_url(url))
    _check_database(url)
    assert _state(url)[0] == actions  # every stable state of the run, none lost


def test_two_runs_at_once_on_one_database(url, scenario, actions, tmp_path):
    """Both started together: the first to take the database runs, the second is refused (or,
    if the first was already done, replaces it): never both at once."""
    procs = [subprocess.Popen([*KITKB, *_run_args(scenario, url, tmp_path / f"out{i}", "--replace")],
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True) for i in range(2)]
    results = [(p.wait(timeout=300), p.communicate()[1]) for p in procs]
    codes = sorted(code for code, _ in results)
    assert codes in ([0, 0], [0, 2]), results
    for code, err in results:
        if code == 2:
            assert "in use by a run" in _one_line_error(err, safe_url(url))
    _check_database(url)
    assert _state(url)[0] == actions


def test_a_second_run_during_a_run_is_refused(url, scenario, reference, actions, tmp_path):
    first = subprocess.Popen([*SLOW_PLAN, str(reference[0]), *map(str, scenario), url],
                             env=_slow(0.6), stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        _started(first, url)
        second = subprocess.run([*KITKB, *_run_args(scenario, url, tmp_path / "b", "--replace")],
                                capture_output=True, text=True, timeout=300)
        still_running = first.poll() is None
    finally:
        _, err = first.communicate(timeout=300)
    assert first.returncode == 0, err
    assert still_running, "the first run ended before the second came: the test proves nothing"
    assert second.returncode == 2
    _one_line_error(second.stderr, safe_url(url))
    _check_database(url)
    assert _state(url)[0] == actions


def test_two_runs_into_one_output_folder(scenario, actions, tmp_path):
    """Without --db a run writes out/<scenario>/world.sqlite, its own output: a second run into
    the same folder is refused, never removes the database under the first."""
    out = tmp_path / "out"
    db = out / scenario[0].parent.name / "world.sqlite"
    url = world.normalize_url(db)
    first = subprocess.Popen([*SLOW_KITKB, "run", *map(str, scenario), "-o", str(out), "-q"],
                             env=_slow(0.6), stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        _started(first, url)
        second = subprocess.run([*KITKB, "run", *map(str, scenario), "-o", str(out), "-q"],
                                capture_output=True, text=True, timeout=300)
        still_running = first.poll() is None
    finally:
        _, err = first.communicate(timeout=300)
    assert first.returncode == 0, err
    assert still_running, "the first run ended before the second came: the test proves nothing"
    assert second.returncode == 2
    _one_line_error(second.stderr, str(db))
    _check_database(url)
    assert _state(url)[0] == actions


# --- a killed run --------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def reference(scenario, tmp_path_factory) -> tuple[Path, list[dict[str, np.ndarray]]]:
    """The plan of an undisturbed ``kitkb run`` and the global poses after each of its stable
    states (index: stable state)."""
    folder = tmp_path_factory.mktemp("reference")
    record = folder / "poses.jsonl"
    done = subprocess.run([*SLOW_KITKB, *_run_args(scenario, str(folder / "w.sqlite"), folder / "out")],
                          env=_slow(0, record), capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    states = [json.loads(line) for line in record.read_text().splitlines()]
    plan = folder / "out" / scenario[0].parent.name / "plan.txt"
    actions = sum(1 for line in plan.read_text().splitlines() if line.strip().startswith("("))
    assert actions > 3
    assert [k for k, _ in states] == list(range(actions + 1))  # one stable state per action
    return plan, [{n: np.array(m) for n, m in poses.items()} for _, poses in states]


@pytest.fixture(scope="module")
def actions(reference) -> int:
    """The generated scenario's plan length: one stable state per action."""
    return len(reference[1]) - 1


def _stable_state(url: str) -> int:
    """The stable-state counter as a reader sees it now (-1 while there is none to read)."""
    try:
        if sqlite_file(url) is not None:
            conn = sqlite3.connect(f"file:{sqlite_file(url)}?mode=ro", uri=True, timeout=5)
            try:
                row = conn.execute("SELECT value FROM kitkb_meta WHERE key = 'stable_state'").fetchone()
            finally:
                conn.close()
        else:
            row = _pg(url, "SELECT value FROM kitkb_meta WHERE key = 'stable_state'")[0]
        return int(row[0])
    except Exception:  # noqa: BLE001 - not there yet
        return -1


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_a_killed_run_leaves_its_last_stable_state_and_no_lock(url, scenario, reference, actions, tmp_path, seed):
    plan, poses_after = reference
    rng = random.Random(seed)
    run = subprocess.Popen([*SLOW_PLAN, str(plan), *map(str, scenario), url], env=_slow(0.08),
                           stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    try:
        _started(run, url)
        deadline = time.monotonic() + 120
        while _stable_state(url) < 1 and run.poll() is None and time.monotonic() < deadline:
            time.sleep(0.005)
        time.sleep(rng.uniform(0, 1.0))  # somewhere among the plan's stable states
        assert run.poll() is None, f"the run ended before it was killed: {run.communicate()[1]}"
        run.send_signal(signal.SIGKILL)
    finally:
        run.wait(timeout=60)
    _check_database(url)
    k, poses = _state(url)
    assert 0 < k < actions
    assert set(poses_after[0]) <= set(poses)
    for name, matrix in poses_after[k].items():
        assert np.allclose(poses[name], matrix, atol=1e-9), (k, name)
    # the killed run's lock went with it (PostgreSQL: once the server saw the session end)
    deadline = time.monotonic() + 10
    while True:
        try:
            with hold(url, "the next writer"):
                break
        except DatabaseBusy:
            assert time.monotonic() < deadline, "the killed run's lock was never given back"
            time.sleep(0.1)


# --- PostgreSQL: a database shared with other applications ---------------------------------------

@pytest.fixture
def pg_url():
    if not PG_URL:
        pytest.skip("KITKB_PG_URL is not set")
    world.drop_all(PG_URL)
    yield PG_URL
    world.drop_all(PG_URL)


def _pg(url: str, sql: str) -> list[tuple]:
    from sqlalchemy import create_engine, text

    engine = create_engine(url)
    try:
        with engine.begin() as conn:
            result = conn.execute(text(sql))
            return [tuple(r) for r in result] if result.returns_rows else []
    finally:
        engine.dispose()


@pytest.mark.postgres
@pytest.mark.parametrize("replace", [[], ["--replace"]])
def test_postgresql_tables_of_another_application_are_never_replaced(pg_url, scenario, replace, capsys):
    _pg(pg_url, "CREATE TABLE users (id integer PRIMARY KEY, name text); "
                "INSERT INTO users VALUES (1, 'ada'), (2, 'bob')")
    assert main(["db", "load", str(scenario[0]), "--db", pg_url, *replace]) == 2
    assert "not a kitkb database" in _one_line_error(capsys.readouterr().err, safe_url(pg_url))
    assert _pg(pg_url, "SELECT name FROM users ORDER BY id") == [("ada",), ("bob",)]
    assert _pg(pg_url, "SELECT tablename FROM pg_tables WHERE schemaname = current_schema()") == [("users",)]


@pytest.mark.postgres
def test_postgresql_replace_never_drops_what_another_application_built_on_it(pg_url, scenario, capsys):
    world.load(scenario[0], pg_url)
    _pg(pg_url, "CREATE VIEW parts AS SELECT id FROM ktw_part")
    before, parts = _state(pg_url), _pg(pg_url, "SELECT count(*) FROM parts")
    assert main(["db", "load", str(scenario[0]), "--db", pg_url, "--replace"]) == 2
    assert "view parts depends on table ktw_part" in _one_line_error(capsys.readouterr().err, safe_url(pg_url))
    assert _pg(pg_url, "SELECT count(*) FROM parts") == parts
    after = _state(pg_url)
    assert after[0] == before[0] and after[1].keys() == before[1].keys()
