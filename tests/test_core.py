"""kb.core: atomic files with the user's permissions, forked jobs, the generator registry."""

from __future__ import annotations

import os
import stat
import subprocess
import sys
from pathlib import Path

import pytest

from kb.cli import main
from kb.core.errors import InputError
from kb.core.files import atomic_paths, write_atomic
from kb.core.generators import BUILTIN, Generator, generator_names, get_generator
from kb.core.resources import scenario_dirs

SMALL = next(d for d in scenario_dirs() if d.name == "small-kit")


@pytest.fixture
def umask_022():
    old = os.umask(0o022)
    yield
    os.umask(old)


def _mode(path: Path) -> int:
    return stat.S_IMODE(path.stat().st_mode)


def test_new_file_gets_the_umask_mode(tmp_path: Path) -> None:
    old = os.umask(0o027)
    try:
        assert _mode(write_atomic(tmp_path / "a.txt", "x")) == 0o640
        os.umask(0o002)
        assert _mode(write_atomic(tmp_path / "b.txt", b"y")) == 0o664
    finally:
        os.umask(old)


def test_existing_file_keeps_its_mode_and_a_failure_keeps_its_content(tmp_path: Path) -> None:
    target = tmp_path / "keep.txt"
    target.write_text("old")
    target.chmod(0o600)
    write_atomic(target, "new")
    assert target.read_text() == "new" and _mode(target) == 0o600
    with pytest.raises(RuntimeError):
        with atomic_paths([target]) as (tmp,):
            tmp.write_text("half")
            raise RuntimeError("killed half way")
    assert target.read_text() == "new"
    assert [p.name for p in tmp_path.iterdir()] == ["keep.txt"]  # no temporary file left


def test_unwritable_target_is_an_input_error(tmp_path: Path) -> None:
    (tmp_path / "file").write_text("")
    with pytest.raises(InputError, match="is a file, not a folder"):
        write_atomic(tmp_path / "file" / "x.txt", "x")


def test_every_written_output_is_readable_by_others(tmp_path: Path, umask_022, capsys) -> None:
    """convert, generate pddl|sql, plan, db dump and scenario files are -rw-r--r-- under umask 022."""
    init, goal = SMALL / "init.ttl", SMALL / "goal.ttl"
    db = tmp_path / "w.sqlite"
    commands = [
        ["convert", str(init), "-o", str(tmp_path / "c.owl")],
        ["generate", "pddl", str(init), str(goal), "-o", str(tmp_path / "pddl")],
        ["generate", "sql", "-o", str(tmp_path / "s.sql")],
        ["plan", str(init), str(goal), "-o", str(tmp_path / "plan.txt")],
        ["scenario", "generate", "--parts", "3", "-o", str(tmp_path / "sc")],
        ["db", "load", str(init), "--db", str(db)],
        ["db", "dump", "--db", str(db), "-o", str(tmp_path / "d.ttl")],
    ]
    for argv in commands:
        assert main(argv) == 0, argv
    written = ["c.owl", "pddl/domain.pddl", "pddl/problem.pddl", "s.sql", "plan.txt", "sc/init.ttl",
               "sc/goal.ttl", "d.ttl"]
    assert {name: oct(_mode(tmp_path / name)) for name in written} == {name: oct(0o644) for name in written}
    err = capsys.readouterr().err.splitlines()
    assert len(err) == len(commands) and all(line.startswith("kitkb: ") for line in err)


# Forked refuses to fork while another thread runs; a test that leaves threads behind in this
# process (a Dask client's event loop) would make these two fail, so they run in a fresh interpreter.
_FORKED = """
import threading
from kb.core.jobs import Forked

def case_answers():
    assert Forked(lambda: {"answer": 42}).result() == (True, {"answer": 42})
    def boom():
        raise ValueError("in the child")
    assert Forked(boom).result() == (False, None)

def case_no_fork_while_another_thread_runs():
    release = threading.Event()
    other = threading.Thread(target=release.wait)
    other.start()
    try:
        job = Forked(lambda: 1)
        assert not job.started and job.result() == (False, None)
    finally:
        release.set()
        other.join()
    assert Forked(lambda: 1).result() == (True, 1)

globals()["case_" + CASE]()
print("ok")
"""


def _fresh(case: str) -> None:
    proc = subprocess.run([sys.executable, "-c", f"CASE = {case!r}\n" + _FORKED], capture_output=True, text=True,
                          timeout=120, cwd=Path(__file__).resolve().parents[1])
    assert proc.returncode == 0 and proc.stdout.strip() == "ok", proc.stdout + proc.stderr


def test_forked_job_answers_or_reports_failure() -> None:
    _fresh("answers")


def test_no_fork_while_another_thread_runs() -> None:
    _fresh("no_fork_while_another_thread_runs")


def test_registry_imports_generators_on_first_use(monkeypatch) -> None:
    class Fake(Generator):
        name = "fake"
        file_extension = ".txt"

        def serialize(self) -> str:
            return "fake"

    monkeypatch.setitem(BUILTIN, "fake", (__name__, "_FakeHolder"))
    monkeypatch.setitem(globals(), "_FakeHolder", Fake)
    assert get_generator("fake") is Fake and "fake" in generator_names()
    monkeypatch.setitem(BUILTIN, "notone", (__name__, "test_forked_job_answers_or_reports_failure"))
    with pytest.raises(InputError, match="is not a kitkb Generator"):
        get_generator("notone")
