"""The kitkb command as a new user meets it: help texts, exit codes, one success line."""

from __future__ import annotations

import argparse
import re
from pathlib import Path

import pytest

from kb.cli import EXIT_CODES, HANDLERS, build_parser, handler, main
from kb.core.resources import scenario_dirs

SCENARIOS = {d.name: d for d in scenario_dirs()}


def _leaves(parser: argparse.ArgumentParser, path: tuple[str, ...] = ()):  # noqa: ANN202
    subs = [a for a in parser._actions if isinstance(a, argparse._SubParsersAction)]
    if not subs:
        yield path, parser
    for action in subs:
        for name, child in action.choices.items():
            yield from _leaves(child, (*path, name))


LEAVES = dict(_leaves(build_parser()))


def test_every_subcommand_has_a_handler() -> None:
    assert {" ".join(path) for path in LEAVES} == set(HANDLERS)
    for command in HANDLERS:
        assert callable(handler(command))


@pytest.mark.parametrize("path", sorted(LEAVES), ids=" ".join)
def test_every_option_has_help_and_the_exit_codes_are_shown(path: tuple[str, ...]) -> None:
    parser = LEAVES[path]
    for action in parser._actions:
        assert action.help and action.help != argparse.SUPPRESS, (path, action.dest)
    assert parser.epilog == EXIT_CODES
    assert "exit codes: 0 success" in parser.format_help()


def test_top_level_help_speaks_to_users() -> None:
    text = build_parser().format_help()
    assert "Validate ontology files" in text and "exit codes:" in text
    assert "shim" not in text and "handler" not in text and "import" not in text


def test_dialect_choices_are_listed() -> None:
    assert "{sqlite,postgresql,mysql}" in LEAVES[("generate", "sql")].format_help()


def test_quiet_before_or_after_the_subcommand(tmp_path: Path, capsys) -> None:
    from rdflib import Graph

    init = SCENARIOS["small-kit"] / "init.ttl"
    assert main(["convert", str(init), "-o", str(tmp_path / "a.nt")]) == 0
    statements = len(Graph().parse(init, format="turtle"))  # 877
    assert capsys.readouterr().err == f"kitkb: wrote {tmp_path / 'a.nt'} (N-Triples, {statements} statements)\n"
    assert main(["-q", "convert", str(init), "-o", str(tmp_path / "b.nt")]) == 0
    assert main(["convert", "--quiet", str(init), "-o", str(tmp_path / "c.nt")]) == 0
    assert capsys.readouterr() == ("", "")
    assert main(["-q", "convert", str(tmp_path / "missing.ttl"), "-o", str(tmp_path / "d.nt")]) == 2
    assert capsys.readouterr().err.endswith("missing.ttl: error: no such file\n")  # errors are never silenced


def test_goal_of_another_scenario_is_an_input_error_at_its_line(tmp_path: Path, capsys) -> None:
    """A goal naming individuals the initial state does not have is refused (by IRI), even when
    their local names coincide with the initial state's."""
    out = tmp_path / "s8"
    assert main(["-q", "scenario", "generate", "--parts", "8", "-o", str(out)]) == 0
    goal = SCENARIOS["small-kit"] / "goal.ttl"
    for command in (["plan", str(out / "init.ttl"), str(goal), "-o", str(tmp_path / "p.txt")],
                    ["generate", "pddl", str(out / "init.ttl"), str(goal), "-o", str(tmp_path / "pddl")]):
        assert main(command) == 2
        err = capsys.readouterr().err
        m = re.match(rf"{re.escape(str(goal))}:(\d+): error: (\S+) is in the goal state but not in the initial state", err)
        assert m, err
        assert f":{m.group(2)} " in goal.read_text().splitlines()[int(m.group(1)) - 1] + " "
    assert not (tmp_path / "p.txt").exists() and not (tmp_path / "pddl").exists()


def test_quiet_main_job_prints_only_problems(tmp_path: Path, monkeypatch) -> None:
    import io

    import kb.cli.pipeline as pipeline

    good = SCENARIOS["small-kit"]
    bad = tmp_path / "scenarios" / "broken"
    bad.mkdir(parents=True)
    (bad / "init.ttl").write_text((good / "init.ttl").read_text().replace("hasPoint_X", "hasPoint_x", 1))
    (bad / "goal.ttl").write_text((good / "goal.ttl").read_text())
    for dirs, code in (([good], 0), ([good, bad], 1)):
        monkeypatch.setattr(pipeline, "scenario_dirs", lambda dirs=dirs: dirs)
        out = io.StringIO()
        assert pipeline.run_main_job(out, tmp_path / "out", quiet=True) == code
        lines = out.getvalue().splitlines()
        if code == 0:
            assert lines == []
        else:  # the one misspelt property, then the verdict
            line = next(n for n, text in enumerate((bad / "init.ttl").read_text().splitlines(), 1) if "hasPoint_x" in text)
            error = (f"{bad / 'init.ttl'}:{line}: error: unknown property ktw:hasPoint_x on "
                     ":kitting_workstation_1_point, did you mean ktw:hasPoint_X? [unknown-property]")
            assert lines == [
                f"    broken: {error}",
                f"    broken: not executed: the state files do not validate (1 error(s): unknown-property); first: {error}",
                "kitkb: main job found problems"]
    assert (tmp_path / "out" / "small-kit" / "plan.txt").is_file()
