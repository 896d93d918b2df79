"""Kill tests: a real ``kitkb`` process killed (SIGKILL) at seeded random points while it writes.

Each output must afterwards be either its old bytes or the complete new file (the bytes an
unkilled run writes), the SQLite database must pass ``PRAGMA integrity_check`` and hold either
its old content or the new one (for ``db load --replace``), or for a run the world model it had
before or one of the stable states the run commits — never half of one. A temporary file a
killed writer leaves (``.NAME.*.tmp``) is never taken for an output, and the next command writing
that output removes it.

Delays are drawn from ``random.Random(seed)`` between 0 and the unkilled run's duration, plus one
kill the moment the command's temporary file (or the database's journal) appears.
"""

from __future__ import annotations

import contextlib
import os
import random
import shutil
import signal
import sqlite3
import subprocess
import sys
import time
from pathlib import Path
from typing import Callable

import numpy as np
import pytest

from kb.cli import main

KITKB = Path(sys.executable).with_name("kitkb")
#: kills per command in the default run (the slow run multiplies them)
KILLS = 3
SLOW_KILLS = 4

pytestmark = pytest.mark.skipif(not hasattr(signal, "SIGKILL"), reason="POSIX only")


def _quiet(argv: list[str]) -> None:
    with contextlib.redirect_stderr(open(os.devnull, "w")):
        assert main(["-q", *argv]) == 0, argv


@pytest.fixture(scope="module")
def big(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    """A 400-part scenario, a 3-part one, and world models of both."""
    root = tmp_path_factory.mktemp("kill")
    _quiet(["scenario", "generate", "--parts", "400", "-o", str(root / "s400")])
    _quiet(["scenario", "generate", "--parts", "3", "-o", str(root / "s3")])
    _quiet(["db", "load", str(root / "s3" / "init.ttl"), "--db", str(root / "w3.sqlite")])
    _quiet(["db", "load", str(root / "s400" / "init.ttl"), "--db", str(root / "w400.sqlite")])
    return {"s400": root / "s400", "s3": root / "s3", "w3": root / "w3.sqlite", "w400": root / "w400.sqlite"}


# --- killing -------------------------------------------------------------------------------

def _temps(folder: Path) -> list[Path]:
    return sorted(folder.rglob(".*.tmp"))


def _kill(argv: list[str], cwd: Path, delay: float | None, watch: Callable[[], bool] | None = None) -> bool:
    """Start ``kitkb argv``; SIGKILL it after ``delay`` seconds, or (``delay`` None) the moment
    ``watch()`` is true. True if it was killed (False: it had finished)."""
    proc = subprocess.Popen([str(KITKB), "-q", *argv], cwd=cwd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    start = time.monotonic()
    try:
        while proc.poll() is None:
            elapsed = time.monotonic() - start
            if (delay is not None and elapsed >= delay) or (delay is None and watch is not None and watch()):
                proc.send_signal(signal.SIGKILL)
                proc.wait()
                return True
            if elapsed > 600:
                raise AssertionError(f"kitkb {argv} still running after 600 s")
            time.sleep(0.002)
        err = proc.stderr.read().decode(errors="replace")
        assert proc.returncode == 0, (argv, proc.returncode, err)
        return False
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
        proc.stderr.close()


def _timed(argv: list[str], cwd: Path) -> float:
    start = time.monotonic()
    _kill(argv, cwd, None)
    return time.monotonic() - start


def _delays(seed: str, duration: float, kills: int) -> list[float | None]:
    """``kills`` seeded delays in [0, duration], and one kill at the first sign of writing (None)."""
    rng = random.Random(seed)
    return [None] + sorted(rng.uniform(0.05, duration) for _ in range(kills))


def _kills(request: pytest.FixtureRequest) -> int:
    return SLOW_KILLS if request.node.get_closest_marker("slow") else KILLS


# --- files: old bytes or the complete new file -----------------------------------------------

def _lines(data: bytes | None) -> list[bytes] | None:
    """A file's lines in order (``kitkb convert`` writes its statements in no fixed order)."""
    return None if data is None else sorted(data.splitlines(keepends=True))


def _file_case(tmp: Path, argv: Callable[[Path], list[str]], outputs: list[str], old: Callable[[Path], None],
               kills: int, seed: str) -> None:
    """Reference run into ``tmp/new``; then per kill: a folder with the old outputs, the command
    killed, each output its old bytes or the new file complete (its lines, in any order),
    temporaries swept by the next run."""
    reference = tmp / "new"
    reference.mkdir()
    duration = _timed(argv(reference), tmp)
    new = {name: _lines((reference / name).read_bytes()) for name in outputs}
    assert not _temps(reference)
    for i, delay in enumerate(_delays(seed, duration, kills)):
        folder = tmp / f"kill{i}"
        folder.mkdir()
        old(folder)
        before = {name: (folder / name).read_bytes() if (folder / name).exists() else None for name in outputs}
        watch = (lambda f=folder: bool(_temps(f))) if delay is None else None
        _kill(argv(folder), tmp, delay, watch)
        for name in outputs:
            now = (folder / name).read_bytes() if (folder / name).exists() else None
            assert now == before[name] or _lines(now) == new[name], \
                f"{name} is neither old nor new after a kill at {delay}"
        left = _temps(folder)
        if left:  # a killed writer cannot remove its temporary file: the next writer does
            _kill(argv(folder), tmp, None)
            assert not _temps(folder), f"temporary files kept after the next run: {_temps(folder)}"
            assert all(_lines((folder / name).read_bytes()) == new[name] for name in outputs)


@pytest.mark.parametrize("kills", [pytest.param(KILLS, id="default"),
                                   pytest.param(SLOW_KILLS, id="slow", marks=pytest.mark.slow)])
def test_convert_killed(big, tmp_path: Path, kills: int) -> None:
    init = big["s400"] / "init.ttl"

    def old(folder: Path) -> None:  # an earlier output: the small scenario, converted
        _quiet(["convert", str(big["s3"] / "init.ttl"), "-o", str(folder / "big.nt")])

    _file_case(tmp_path, lambda f: ["convert", str(init), "-o", str(f / "big.nt")], ["big.nt"], old, kills,
               "convert")


@pytest.mark.parametrize("kills", [pytest.param(KILLS, id="default"),
                                   pytest.param(SLOW_KILLS, id="slow", marks=pytest.mark.slow)])
def test_scenario_generate_killed(big, tmp_path: Path, kills: int) -> None:
    def old(folder: Path) -> None:
        for name in ("init.ttl", "goal.ttl"):
            shutil.copyfile(big["s3"] / name, folder / name)

    _file_case(tmp_path, lambda f: ["scenario", "generate", "--parts", "400", "-o", str(f)],
               ["init.ttl", "goal.ttl"], old, kills, "scenario")


@pytest.mark.parametrize("kills", [pytest.param(KILLS, id="default"),
                                   pytest.param(SLOW_KILLS, id="slow", marks=pytest.mark.slow)])
def test_db_dump_killed(big, tmp_path: Path, kills: int) -> None:
    def old(folder: Path) -> None:  # an earlier dump, of the small world model
        _quiet(["db", "dump", "--db", str(big["w3"]), "-o", str(folder / "dump.ttl")])

    database = tmp_path / "w400.sqlite"
    shutil.copyfile(big["w400"], database)
    before = database.read_bytes()
    _file_case(tmp_path, lambda f: ["db", "dump", "--db", str(database), "-o", str(f / "dump.ttl")], ["dump.ttl"],
               old, kills, "dump")
    assert database.read_bytes() == before  # a dump only reads


# --- databases: old content or new, never half -----------------------------------------------

def _integrity(path: Path) -> None:
    with contextlib.closing(sqlite3.connect(path)) as con:
        assert con.execute("PRAGMA integrity_check").fetchone()[0] == "ok"


def _content(path: Path) -> dict[str, int]:
    """Rows per table, and kitkb's meta values: which world model the database holds."""
    with contextlib.closing(sqlite3.connect(path)) as con:
        tables = [r[0] for r in con.execute("SELECT name FROM sqlite_master WHERE type = 'table' ORDER BY name")]
        rows = {t: con.execute(f'SELECT count(*) FROM "{t}"').fetchone()[0] for t in tables}
        meta = dict(con.execute("SELECT key, value FROM kitkb_meta")) if "kitkb_meta" in tables else {}
    return {**rows, **{f"meta:{k}": v for k, v in meta.items() if k not in ("loaded_at", "load_id")}}


def _journal_appears(path: Path, since: float) -> Callable[[], bool]:
    def seen() -> bool:
        for suffix in ("-journal", "-wal"):
            other = Path(f"{path}{suffix}")
            if other.exists() and other.stat().st_mtime >= since:
                return True
        return path.stat().st_mtime > since
    return seen


@pytest.mark.parametrize("kills", [pytest.param(KILLS, id="default"),
                                   pytest.param(SLOW_KILLS, id="slow", marks=pytest.mark.slow)])
def test_db_load_replace_killed(big, tmp_path: Path, kills: int) -> None:
    """db load --replace of the 400-part world model over the 3-part one."""
    init = big["s400"] / "init.ttl"
    reference = tmp_path / "reference.sqlite"
    shutil.copyfile(big["w3"], reference)
    old = _content(reference)
    duration = _timed(["db", "load", str(init), "--db", str(reference), "--replace"], tmp_path)
    new = _content(reference)
    assert new != old
    for i, delay in enumerate(_delays("load", duration, kills)):
        database = tmp_path / f"kill{i}.sqlite"
        shutil.copyfile(big["w3"], database)
        since = time.time()
        _kill(["db", "load", str(init), "--db", str(database), "--replace"], tmp_path, delay,
              _journal_appears(database, since) if delay is None else None)
        _integrity(database)
        assert _content(database) in (old, new), f"database half loaded after a kill at {delay}"
    assert not list(tmp_path.glob(".*.tmp"))


# --- runs: the world model before, or a committed stable state -------------------------------

def _poses(url: Path) -> tuple[int, dict[str, np.ndarray]]:
    from kb.world import WorldModel

    world = WorldModel(url)
    try:
        return world.stable_state(), world.global_poses()
    finally:
        world.close()


def _reference_states(big, tmp: Path, monkeypatch: pytest.MonkeyPatch) -> dict[int, dict[str, np.ndarray]]:
    """The stable states an unkilled run commits, by number (0: the world model loaded), taken
    in process from :meth:`WorldModel.commit_stable_state`."""
    from kb.world import WorldModel

    states: dict[int, dict[str, np.ndarray]] = {}
    commit = WorldModel.commit_stable_state

    def recording(self, *args, **kwargs):  # noqa: ANN001, ANN202
        result = commit(self, *args, **kwargs)
        states[self.stable_state()] = self.global_poses()
        return result

    monkeypatch.setattr(WorldModel, "commit_stable_state", recording)
    database = tmp / "reference.sqlite"
    shutil.copyfile(big["w3"], database)
    states[0] = _poses(database)[1]
    s3 = big["s3"]
    _quiet(["run", str(s3 / "init.ttl"), str(s3 / "goal.ttl"), "-o", str(tmp / "reference"), "--db", str(database),
            "--replace"])
    monkeypatch.undo()
    assert len(states) > 10
    return states


def _same(a: dict[str, np.ndarray], b: dict[str, np.ndarray]) -> bool:
    return a.keys() == b.keys() and all(np.allclose(a[k], b[k], atol=1e-9, equal_nan=True) for k in a)


@pytest.mark.parametrize("kills", [pytest.param(KILLS, id="default"),
                                   pytest.param(SLOW_KILLS, id="slow", marks=pytest.mark.slow)])
def test_run_killed(big, tmp_path: Path, monkeypatch: pytest.MonkeyPatch, kills: int) -> None:
    monkeypatch.chdir(tmp_path)
    states = _reference_states(big, tmp_path, monkeypatch)
    s3 = big["s3"]
    argv = lambda db, out: ["run", str(s3 / "init.ttl"), str(s3 / "goal.ttl"), "-o", str(out), "--db", str(db),  # noqa: E731
                            "--replace"]
    timing = tmp_path / "timing.sqlite"
    shutil.copyfile(big["w3"], timing)
    duration = _timed(argv(timing, tmp_path / "timing"), tmp_path)
    for i, delay in enumerate(_delays("run", duration, kills)):
        database = tmp_path / f"kill{i}.sqlite"
        shutil.copyfile(big["w3"], database)
        since = time.time()
        _kill(argv(database, tmp_path / f"out{i}"), tmp_path, delay,
              _journal_appears(database, since) if delay is None else None)
        _integrity(database)
        number, poses = _poses(database)
        assert number in states, f"stable state {number} was never committed"
        assert _same(poses, states[number]), f"the database holds no stable state after a kill at {delay}"
    assert not list(tmp_path.glob(".*.tmp"))  # the database is written in place, never through one
