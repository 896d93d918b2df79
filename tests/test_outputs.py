"""One way to write a file (kb.core.files): no command writes over what it reads, outputs are
whole or absent, and an unwritable target is one line with exit 2 and nothing left behind."""

from __future__ import annotations

import errno
import hashlib
import os
from pathlib import Path

import pytest

from kb.cli import main
from kb.core import files
from kb.core.errors import InputError


@pytest.fixture(scope="module")
def scenario(tmp_path_factory: pytest.TempPathFactory) -> Path:
    folder = tmp_path_factory.mktemp("scenario")
    assert main(["-q", "scenario", "generate", "--parts", "3", "-o", str(folder)]) == 0
    return folder


@pytest.fixture
def work(scenario: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """A folder (the current directory) with i.ttl, g.ttl, a world model w.sqlite and links to i.ttl."""
    for name, source in (("i.ttl", "init.ttl"), ("g.ttl", "goal.ttl")):
        (tmp_path / name).write_bytes((scenario / source).read_bytes())
    (tmp_path / "sym.ttl").symlink_to("i.ttl")
    os.link(tmp_path / "i.ttl", tmp_path / "hard.ttl")
    monkeypatch.chdir(tmp_path)
    assert main(["-q", "db", "load", "i.ttl", "--db", "w.sqlite"]) == 0
    return tmp_path


def digest(folder: Path) -> dict[str, str]:
    """Every file of ``folder`` (recursively) -> its hash; symlinks by their target's name."""
    out = {}
    for p in sorted(folder.rglob("*")):
        if p.is_symlink():
            out[str(p.relative_to(folder))] = "->" + os.readlink(p)
        elif p.is_file():
            out[str(p.relative_to(folder))] = hashlib.sha256(p.read_bytes()).hexdigest()
    return out


#: Commands that would replace one of their own inputs; {out} is the path tried.
OVERWRITES = [
    ["convert", "i.ttl", "-o", "{out}"],
    ["plan", "i.ttl", "g.ttl", "-o", "{out}"],
    ["run", "i.ttl", "g.ttl", "-o", "runs", "--report", "{out}"],
    ["scenario", "transform", "i.ttl", "-o", "{out}", "--unit", "millimeter"],
    ["predicates", "i.ttl", "--goal", "g.ttl"],  # reads only: the control
]


@pytest.mark.parametrize("out", ["i.ttl", "./i.ttl", "sub/../i.ttl", "sym.ttl", "hard.ttl"])
@pytest.mark.parametrize("command", OVERWRITES[:4], ids=lambda c: c[0] if c[0] != "scenario" else "transform")
def test_no_command_writes_over_a_file_it_reads(work: Path, command: list[str], out: str,
                                                capsys: pytest.CaptureFixture[str]) -> None:
    (work / "sub").mkdir()
    before = digest(work)
    assert main([a.format(out=out) for a in command]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "refusing to write over" in err[0]
    assert out in err[0] and "i.ttl" in err[0]  # both paths named
    assert digest(work) == before  # nothing changed, nothing left behind


def test_the_goal_is_an_input_too(work: Path, capsys: pytest.CaptureFixture[str]) -> None:
    before = digest(work)
    assert main(["plan", "i.ttl", "g.ttl", "-o", "./g.ttl"]) == 2
    assert "g.ttl" in capsys.readouterr().err
    assert digest(work) == before


def test_a_dump_never_replaces_its_database(work: Path, capsys: pytest.CaptureFixture[str]) -> None:
    before = digest(work)
    assert main(["db", "dump", "--db", "w.sqlite", "-o", "w.sqlite"]) == 2
    assert main(["db", "dump", "--db", "w.sqlite", "-o", "./w.sqlite"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 2 and all("database" in line and "w.sqlite" in line for line in err)
    assert digest(work) == before


def test_an_earlier_output_may_be_overwritten(work: Path) -> None:
    assert main(["-q", "convert", "i.ttl", "-o", "copy.nt"]) == 0
    first = (work / "copy.nt").read_bytes()
    (work / "copy.nt").write_text("old")
    assert main(["-q", "convert", "i.ttl", "-o", "copy.nt"]) == 0
    assert (work / "copy.nt").read_bytes() == first
    assert main(["-q", "db", "dump", "--db", "w.sqlite", "-o", "dump.ttl"]) == 0
    assert main(["-q", "db", "dump", "--db", "w.sqlite", "-o", "dump.ttl"]) == 0


@pytest.mark.parametrize("target, message", [
    ("sub.nt", "is a folder"),  # a directory
    ("i.ttl/x.nt", "is a file, not a folder"),  # a path under a regular file
    ("/proc/kitkb-cannot-write.nt", "cannot write"),  # a place nobody may write, even root
])
def test_an_unwritable_target_is_one_line_and_nothing_is_left(work: Path, target: str, message: str,
                                                              capsys: pytest.CaptureFixture[str]) -> None:
    (work / "sub.nt").mkdir()
    before = digest(work)
    assert main(["convert", "i.ttl", "-o", target]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and message in err[0], err
    assert digest(work) == before


def test_a_full_disk_leaves_the_old_file(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    target = tmp_path / "out.txt"
    target.write_text("old")
    real_fsync = os.fsync

    def full(fd: int) -> None:
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(os, "fsync", full)
    with pytest.raises(InputError, match="No space left on device"):
        files.write_atomic(target, "new" * 1000)
    monkeypatch.setattr(os, "fsync", real_fsync)
    assert target.read_text() == "old"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.txt"]


def test_several_targets_replace_together_or_not_at_all(tmp_path: Path) -> None:
    a, b = tmp_path / "a", tmp_path / "b"
    a.write_text("old a")
    with pytest.raises(RuntimeError):
        with files.atomic_paths([a, b]) as (ta, tb):
            ta.write_text("new a")
            raise RuntimeError("killed half way")
    assert a.read_text() == "old a" and not b.exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a"]


def test_the_guard_holds_only_inside_a_command(tmp_path: Path) -> None:
    source = tmp_path / "i.ttl"
    source.write_text("x")
    files.note_input(source)  # outside a command: nothing remembered
    files.write_atomic(source, "library call")
    with files.command_scope(inputs=[source]):
        with pytest.raises(InputError, match="refusing"):
            files.write_atomic(tmp_path / "." / "i.ttl", "y")
        files.write_atomic(tmp_path / "other.ttl", "fine")
    files.write_atomic(source, "after the command")
    assert source.read_text() == "after the command"


def test_a_crcl_program_is_never_converted_over_itself(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    program = tmp_path / "p.crcl"
    program.write_text("InitCanon()\nMoveTo({1, 2, 3}, {1, 0, 0}, {0, 0, -1})\nEndCanon()\n")
    (tmp_path / "link.crcl").symlink_to("p.crcl")
    before = program.read_bytes()
    assert main(["crcl", "convert", str(program), "-o", str(tmp_path / "link.crcl")]) == 2
    assert "refusing to write over" in capsys.readouterr().err
    assert program.read_bytes() == before
