"""Progress of long work (shown on a terminal only, never with --quiet) and ``--format json``
on every subcommand (one JSON object on standard output with the facts of the text line)."""

from __future__ import annotations

import io
import json
import os
import pty
import re
import select
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

from kb.cli import HANDLERS, main
from kb.cli.progress import Display, tracker
from kb.core.jobs import Forked, fork_is_safe
from kb.core.progress import SILENT, counted
from kb.core.resources import scenario_dirs
from kb.crcl import EndCanon, InitCanon, Message, Program, write_text

REPO = Path(__file__).resolve().parents[1]
SMALL = {d.name: d for d in scenario_dirs()}["small-kit"]
INIT, GOAL = SMALL / "init.ttl", SMALL / "goal.ttl"
KITKB = [sys.executable, "-m", "kb.cli"]


# --- the facade --------------------------------------------------------------------------------

def test_no_display_where_standard_error_is_not_a_terminal_or_with_quiet(monkeypatch) -> None:
    monkeypatch.delenv("KITKB_PROGRESS", raising=False)
    assert tracker(io.StringIO()) is SILENT
    assert tracker(io.StringIO(), force=True, quiet=True) is SILENT
    assert isinstance(tracker(io.StringIO(), force=True), Display)
    monkeypatch.setenv("KITKB_PROGRESS", "0")
    assert tracker(io.StringIO(), force=None) is SILENT


def test_silent_progress_leaves_a_loop_alone() -> None:
    items = [1, 2, 3]
    with SILENT.task("x", total=3) as task:
        assert counted(items, task) is items  # not even a generator in between
        task.advance(3)
        task.update(total=4, description="y")


def test_a_display_shows_what_is_done_counts_and_time_left() -> None:
    stream = io.StringIO()
    display = tracker(stream, force=True)
    before = threading.active_count()
    with display.task("reading i.ttl", total=2_000_000, unit="bytes") as task:
        task.advance(1_000_000)
        with display.task("writing 3 tables", total=30, unit="rows") as inner:
            inner.advance(10)
            time.sleep(0.35)
    text = stream.getvalue()
    assert "reading i.ttl" in text and "1.0 MB/2.0 MB" in text
    assert "writing 3 tables" in text and "10/30 rows" in text and "left" in text
    assert threading.active_count() == before  # its refresh thread ended with the last task


def test_work_of_unknown_size_shows_a_spinner_and_the_time_elapsed() -> None:
    stream = io.StringIO()
    with tracker(stream, force=True).task("solving with fast-downward"):
        time.sleep(0.25)
    assert "solving with fast-downward" in stream.getvalue() and "0:00:00" in stream.getvalue()


def test_a_fork_pauses_the_refresh_thread_instead_of_being_refused() -> None:
    display = tracker(io.StringIO(), force=True)
    with display.task("validating"):
        assert threading.active_count() >= 2
        assert fork_is_safe()
        job = Forked(lambda: 6 * 7)
        assert job.started
        assert job.result() == (True, 42)
        assert display._refresher is not None and display._refresher.running  # resumed after the fork


# --- on a terminal, piped, quiet ------------------------------------------------------------------

def _on_a_terminal(args: list[str]) -> tuple[int, str]:
    """Exit code and what ``kitkb args`` wrote on its standard error, a pseudo-terminal."""
    master, slave = pty.openpty()
    env = dict(os.environ, PYTHONPATH=str(REPO), TERM="xterm", COLUMNS="160")
    env.pop("KITKB_PROGRESS", None)
    proc = subprocess.Popen(KITKB + args, stdout=subprocess.DEVNULL, stderr=slave, stdin=subprocess.DEVNULL, env=env)
    os.close(slave)
    data = b""
    while True:
        ready, _, _ = select.select([master], [], [], 0.2)
        if ready:
            try:
                chunk = os.read(master, 65536)
            except OSError:  # the other end closed
                chunk = b""
            if not chunk and proc.poll() is not None:
                break
            data += chunk
        elif proc.poll() is not None:
            break
    os.close(master)
    return proc.wait(), data.decode("utf-8", "replace")


@pytest.fixture(scope="module")
def scenario(tmp_path_factory: pytest.TempPathFactory) -> Path:
    folder = tmp_path_factory.mktemp("progress") / "sc"
    assert main(["scenario", "generate", "--parts", "300", "-o", str(folder), "-q"]) == 0
    return folder


def test_db_load_shows_progress_on_a_terminal(scenario: Path, tmp_path: Path) -> None:
    code, err = _on_a_terminal(["db", "load", str(scenario / "init.ttl"), "--db", str(tmp_path / "w.sqlite")])
    assert code == 0, err
    plain = re.sub(r"\x1b\[[0-9;?]*[A-Za-z]", "", err)
    assert "loading init.ttl" in plain and "reading init.ttl" in plain and "writing" in plain
    assert re.search(r"[\d.]+ [kM]B/[\d.]+ [kM]B", plain)  # bytes read of the file's
    assert "kitkb: loaded" in plain


def test_db_dump_shows_the_individuals_written_on_a_terminal(scenario: Path, tmp_path: Path) -> None:
    assert main(["db", "load", str(scenario / "init.ttl"), "--db", str(tmp_path / "w.sqlite"), "-q"]) == 0
    code, err = _on_a_terminal(["db", "dump", "--db", str(tmp_path / "w.sqlite"), "-o", str(tmp_path / "d.ttl")])
    assert code == 0, err
    assert re.search(r"writing the individuals .*\d+/[\d,]+ individuals", re.sub(r"\x1b\[[0-9;?]*[A-Za-z]", "", err))


def test_validate_says_which_step_it_is_at_on_a_terminal(scenario: Path) -> None:
    code, err = _on_a_terminal(["validate", str(scenario / "init.ttl")])
    assert code == 0, err
    assert "validating init.ttl (" in err and "reading 1 file(s)" in err and "the Python rules" in err


def test_no_progress_with_quiet_on_a_terminal(scenario: Path, tmp_path: Path) -> None:
    code, err = _on_a_terminal(["db", "load", str(scenario / "init.ttl"), "--db", str(tmp_path / "w.sqlite"), "-q"])
    assert code == 0 and err == ""


def test_no_progress_when_piped(scenario: Path, tmp_path: Path) -> None:
    env = dict(os.environ, PYTHONPATH=str(REPO))
    env.pop("KITKB_PROGRESS", None)
    proc = subprocess.run(KITKB + ["db", "load", str(scenario / "init.ttl"), "--db", str(tmp_path / "w.sqlite")],
                          capture_output=True, text=True, env=env, timeout=300)
    assert proc.returncode == 0
    assert proc.stdout == ""
    assert proc.stderr.startswith("kitkb: loaded ") and proc.stderr.count("\n") == 1


def test_plan_shows_the_planner_at_work_on_a_terminal(tmp_path: Path) -> None:
    code, err = _on_a_terminal(["plan", str(INIT), str(GOAL), "-o", str(tmp_path / "plan.txt")])
    assert code == 0, err
    assert "solving with " in err and "planning init.ttl -> goal.ttl" in err


# --- --format json everywhere -------------------------------------------------------------------

def _crcl(tmp_path: Path) -> Path:
    path = tmp_path / "p.crcl"
    path.write_text(write_text(Program([InitCanon(), Message("hello"), EndCanon()])))
    return path


ARIAC_TRIAL = REPO / "tests" / "data" / "ariac" / "one_kit.yaml"


def _cases(tmp: Path) -> dict[str, list[str]]:
    """A cheap command line of every subcommand (``sim serve`` and ``crcl send``, which need a
    peer, are tested apart: tests/test_sim_server.py, tests/test_crcl_wire.py)."""
    return {
        "validate": ["validate", str(INIT)],
        "shacl": ["shacl", str(INIT), "-s", str(REPO / "shapes" / "kitting-rules.ttl")],
        "convert": ["convert", str(INIT), "-o", str(tmp / "a.nt")],
        "scenario generate": ["scenario", "generate", "--parts", "3", "-o", str(tmp / "sc")],
        "scenario transform": ["scenario", "transform", str(INIT), "-o", str(tmp / "mm.ttl"), "--unit", "millimeter"],
        "generate pddl": ["generate", "pddl", str(INIT), str(GOAL), "-o", str(tmp / "pddl")],
        "generate sql": ["generate", "sql", "-o", str(tmp / "s.sql")],
        "generate shapes": ["generate", "shapes", "-o", str(tmp / "shapes.ttl")],
        "generate accessors": ["generate", "accessors", "-o", str(tmp / "accessors.py")],
        "plan": ["plan", str(INIT), str(GOAL), "-o", str(tmp / "plan.txt")],
        "db load": ["db", "load", str(INIT), "--db", str(tmp / "w.sqlite")],
        "db dump": ["db", "dump", "--db", str(tmp / "w.sqlite"), "-o", str(tmp / "d.ttl")],
        "run": ["run", str(INIT), str(GOAL), "-o", str(tmp / "out"), "--report", str(tmp / "report.json")],
        "report": ["report", str(tmp / "report.json"), "-o", str(tmp / "report.html")],  # the run's report
        "crcl convert": ["crcl", "convert", str(_crcl(tmp)), "-o", str(tmp / "p2.crcl")],
        "predicates": ["predicates", str(INIT), "-p", "part-location-partstray"],
        "faults": ["faults"],
        "sim export-mjcf": ["sim", "export-mjcf", str(INIT), "-o", str(tmp / "scene.xml")],
        "metrics": ["metrics", str(_crcl(tmp))],
        "testmethod": ["testmethod", "basic", "--trials", "1", "--parts", "2", "--workers", "1", "--out", str(tmp / "tm")],
        "ariac import": ["ariac", "import", str(ARIAC_TRIAL), "-o", str(tmp / "ariac")],
        "ariac run": ["ariac", "run", str(ARIAC_TRIAL), "-o", str(tmp / "ariac-run"), "--report", str(tmp / "ariac.json")],
        "ariac score": ["ariac", "score", str(tmp / "ariac.json"), "--scoring", "ariac-2023"],  # ariac run's report
    }


#: the facts each command's JSON object holds besides ``command``, ``message`` and ``warnings``
FACTS = {
    "convert": {"output", "input", "syntax", "statements"},
    "scenario generate": {"init", "goal", "parts", "kits", "seed", "unit", "unlocated"},
    "scenario transform": {"output", "input", "statements", "unit", "yaw", "turned", "unlocated"},
    "generate pddl": {"written", "encoding"},
    "generate sql": {"output", "dialect"},
    "generate shapes": {"output", "generator"},
    "generate accessors": {"output", "generator"},
    "plan": {"output", "actions", "planner", "source", "validated", "seconds", "times", "plan"},
    "db load": {"datafile", "db", "statements", "individuals", "tables", "outside_model", "replaced", "seconds"},
    "db dump": {"output", "db", "bytes", "seconds"},
    "crcl convert": {"output", "input", "form", "text_style", "xml_form", "commands", "unreadable", "xsd", "xml_not_validated"},
    "report": {"kind", "output", "bytes", "runs", "scene", "failures"},
    "sim export-mjcf": {"output", "bodies", "free", "fixed", "mocap"},
    "ariac import": {"init", "goal", "manifest", "kits"},
}


def test_every_subcommand_is_covered(tmp_path: Path) -> None:
    assert set(_cases(tmp_path)) | {"sim serve", "crcl send"} == set(HANDLERS)  # a new command needs a case


def test_every_subcommand_prints_one_json_object_with_the_facts_of_its_text(tmp_path: Path, capsys) -> None:
    text_dir, json_dir = tmp_path / "text", tmp_path / "json"
    text_dir.mkdir(), json_dir.mkdir()
    checked = 0
    for (command, text_args), json_args in zip(_cases(text_dir).items(), _cases(json_dir).values()):
        text_code = main(text_args)
        text = capsys.readouterr()
        json_code = main(json_args + ["--format", "json"])
        out = capsys.readouterr()
        assert json_code == text_code, (command, out.err)
        data = json.loads(out.out)  # the whole of standard output is one JSON document
        if command in FACTS:
            assert text.out == "" and out.err == "", command
            assert set(data) == {"command", "message", "warnings"} | FACTS[command], command
            assert data["command"] == command and data["warnings"] == []
            line = text.err.strip().removeprefix("kitkb: ").replace(str(text_dir), str(json_dir))
            assert _steady(data["message"]) == _steady(line), command
            for key, value in data.items():  # every number and path of the object is in the text line
                if isinstance(value, (int, float, str)) and not isinstance(value, bool) and value not in (0, "") \
                        and key not in ("command", "message", "seconds", "bytes", "input", "xsd", "db"):
                    assert str(value) in data["message"], (command, key, value)
        checked += 1
        if command == "validate":
            assert data["conforms"] is True and text.out.splitlines()[-1].startswith(f"{len(data['files'])} file(s)")
        if command == "predicates":
            assert [f"{d['predicate']}({', '.join(d['args'])})" for d in data] == text.out.splitlines()
        if command == "faults":  # a line per kind, the kinds in the object in the same order
            assert [k["name"] for k in data["kinds"]] == [line.split(":")[0] for line in text.out.splitlines()]
            mix = {part.split("=")[0] for part in data["default_mix"].split(",")}  # the errors method's default
            assert data["kinds"] and mix <= {k["name"] for k in data["kinds"] if k["test_rate"]}
        if command == "metrics":
            assert data["command"] == "metrics" and "score" in data
            assert text.out.splitlines()[-1] == f"score {data['score']['total']:.3f}"
        if command == "run":
            assert data == json.loads((json_dir / "report.json").read_text())  # the report, on stdout too
            assert data["goal_holds"] is True and data["executed"] is True
            assert "execute: goal holds" in text.out
    assert checked == len(HANDLERS) - 2  # all but sim serve and crcl send


def _steady(message: str) -> str:
    """A message without its timing (``in 1.23 s``)."""
    return re.sub(r"in \d+\.\d+ s", "in - s", message)


def test_generate_sql_to_standard_output_as_json(capsys) -> None:
    assert main(["generate", "sql", "-o", "-"]) == 0
    ddl = capsys.readouterr().out
    assert main(["generate", "sql", "-o", "-", "--format", "json"]) == 0
    assert json.loads(capsys.readouterr().out)["ddl"] == ddl


def test_an_error_stays_one_line_on_standard_error_with_json(tmp_path: Path, capsys) -> None:
    code = main(["db", "load", str(tmp_path / "missing.ttl"), "--db", str(tmp_path / "w.sqlite"), "--format", "json"])
    out = capsys.readouterr()
    assert code == 2 and out.out == "" and out.err.count("\n") == 1


def test_warnings_are_in_the_json_object(tmp_path: Path, capsys) -> None:
    from kb.cli.output import Output

    stdout, stderr = io.StringIO(), io.StringIO()
    out = Output(stdout=stdout, stderr=stderr, format="json", command="plan")
    out.warn("a.pddl:3: warning: something")
    out.done("wrote plan.txt", output="plan.txt")
    assert json.loads(stdout.getvalue()) == {"command": "plan", "message": "wrote plan.txt", "output": "plan.txt",
                                             "warnings": ["a.pddl:3: warning: something"]}
    assert stderr.getvalue() == "a.pddl:3: warning: something\n"


def test_sim_serve_prints_its_ports_as_one_json_line() -> None:
    env = dict(os.environ, PYTHONPATH=str(REPO))
    proc = subprocess.Popen(KITKB + ["sim", "serve", str(INIT), "--sensor-port", "0", "--command-port", "0",
                                     "--format", "json"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            env=env)
    try:
        assert proc.stdout is not None
        ready, _, _ = select.select([proc.stdout], [], [], 60)
        assert ready
        data = json.loads(proc.stdout.readline())
        assert data["command"] == "sim serve" and data["host"] == "127.0.0.1"
        assert data["cell"] == f"127.0.0.1:{data['sensor_port']},{data['command_port']}"
        assert str(data["sensor_port"]) in data["message"]
        proc.send_signal(signal.SIGINT)
        assert proc.wait(timeout=30) == 0
        assert proc.stdout.read() == ""
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()


def test_quiet_keeps_the_json_object_it_was_asked_for(tmp_path: Path, capsys) -> None:
    assert main(["convert", str(INIT), "-o", str(tmp_path / "a.nt"), "--format", "json", "-q"]) == 0
    out = capsys.readouterr()
    assert json.loads(out.out)["statements"] > 0 and out.err == ""


def test_a_file_name_is_shown_as_written_not_read_as_markup() -> None:
    stream = io.StringIO()
    with tracker(stream, force=True).task("reading [bold]x[/b].ttl", total=3) as task:
        task.advance()
    assert "reading [bold]x[/b].ttl" in stream.getvalue()
