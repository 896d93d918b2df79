"""The bad-input campaign: broken files given to every command that reads files.

The engine is ``benchmarks/bench_bad_input.py`` (seeds, mutations, commands, the check of an
outcome); here hypothesis draws each mutation's parameters, so a failure shrinks to a small one.
Every outcome must be exit 0, 1 or 2 with one error line — never a traceback nor exit 3 —, every
input file and the pre-existing database byte-identical afterwards, and no temporary file left.
"""

from __future__ import annotations

import importlib.util
import random
import re
import sqlite3
import sys
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from shared_data import NIST_DIR

BENCH = Path(__file__).resolve().parent.parent / "benchmarks" / "bench_bad_input.py"
_spec = importlib.util.spec_from_file_location("bench_bad_input", BENCH)
bench = importlib.util.module_from_spec(_spec)
sys.modules["bench_bad_input"] = bench
_spec.loader.exec_module(bench)

pytestmark = [pytest.mark.usefixtures("own_directory"),
              pytest.mark.skipif(not (NIST_DIR / "commands1.xml").exists(), reason="NIST files not present")]

#: hypothesis examples per command in the default run (planners and runs cost a second each)
EXAMPLES = {"plan init": 3, "plan goal": 3, "plan domain.pddl": 4, "plan problem.pddl": 4, "plan nist problem": 2,
            "run init": 2, "validate ofn": 5, "predicates ofn": 4, "generate pddl ofn": 5, "db load ofn": 5,
            "scenario transform ofn": 6, "convert ofn": 6}
DEFAULT_EXAMPLES = 6
HEALTH = [HealthCheck.too_slow, HealthCheck.data_too_large, HealthCheck.large_base_example,
          HealthCheck.function_scoped_fixture]


@pytest.fixture(scope="module")
def seeds(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    return bench.make_seeds(tmp_path_factory.mktemp("seeds"))


@pytest.fixture(scope="module")
def seed_data(seeds: dict[str, Path]) -> dict[str, bytes]:
    return {role: path.read_bytes() for role, path in seeds.items()}


@pytest.fixture(scope="module")
def work(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return tmp_path_factory.mktemp("work")


def _drawn_mutant(data: st.DataObject, case: bench.Case, seed_data: dict[str, bytes]) -> tuple[str, bytes]:
    kind = data.draw(st.sampled_from(bench.kinds_for(case.role)), label="mutation")
    pick = lambda n: data.draw(st.integers(0, max(n - 1, 0)))  # noqa: E731
    return kind, bench.mutate(seed_data[case.role], kind, pick, bench.family(case.role))


def _campaign(name: str, examples: int, seeds, seed_data, work, derandomize: bool) -> None:
    case = bench.CASE_BY_NAME[name]

    @settings(max_examples=examples, deadline=None, derandomize=derandomize, suppress_health_check=HEALTH,
              database=None if derandomize else settings.default.database)
    @given(data=st.data())
    def check(data: st.DataObject) -> None:
        kind, mutant = _drawn_mutant(data, case, seed_data)
        outcome = bench.run_case(case, mutant, kind, seeds, work)
        assert not outcome.problems, (outcome.code, outcome.stderr[-1000:])

    check()


@pytest.mark.parametrize("name", [c.name for c in bench.CASES])
def test_bad_input(name: str, seeds, seed_data, work) -> None:
    """A few drawn mutants per command (reproducible: derandomized)."""
    _campaign(name, EXAMPLES.get(name, DEFAULT_EXAMPLES), seeds, seed_data, work, derandomize=True)


@pytest.mark.slow
@pytest.mark.parametrize("name", [c.name for c in bench.CASES])
def test_bad_input_campaign(name: str, seeds, seed_data, work) -> None:
    """The bigger campaign, reproducible as every other test (derandomized: CI fails only on
    what a rerun shows again); new random mutants are benchmarks/bench_bad_input.py's job."""
    _campaign(name, 2 * EXAMPLES.get(name, DEFAULT_EXAMPLES), seeds, seed_data, work, derandomize=True)


# --- every mutation on every syntax, once, with fixed parameters ---------------------------

#: the command each seed syntax is tried with for every mutation kind
BY_SYNTAX = {"ttl_init": "validate ttl", "rdf_init": "convert rdfxml", "ofn_init": "scenario transform ofn",
             "crcl_text": "crcl convert text", "crcl_xml": "crcl convert xml", "pddl_problem": "plan problem.pddl",
             "db": "db dump"}
EVERY = [(name, kind) for role, name in BY_SYNTAX.items() for kind in bench.kinds_for(role)]


@pytest.mark.parametrize(("name", "kind"), EVERY, ids=[f"{n}-{k}" for n, k in EVERY])
def test_every_mutation_of_every_syntax(name: str, kind: str, seeds, seed_data, work) -> None:
    case = bench.CASE_BY_NAME[name]
    mutant = bench.mutate(seed_data[case.role], kind, random.Random(f"{name} {kind}").randrange,
                          bench.family(case.role))
    assert mutant != seed_data[case.role] or kind in ("cycle", "numbers")
    outcome = bench.run_case(case, mutant, kind, seeds, work)
    assert not outcome.problems, (outcome.code, outcome.stderr[-1000:])


def test_the_suite_covers_every_command_and_mutation() -> None:
    """The campaign's own size cannot shrink silently: every command that reads files, every
    mutation kind of the issue."""
    commands = {" ".join(c.name.split()[:2]) if c.name.split()[0] in ("db", "crcl", "scenario", "generate")
                else c.name.split()[0] for c in bench.CASES}
    assert commands == {"validate", "convert", "scenario transform", "generate pddl", "plan", "db load",
                        "db dump", "run", "crcl convert", "predicates"}
    assert len(bench.CASES) == 26 and len(bench.MUTATIONS) == 16 and len(EVERY) == 6 * 15 + 7


# --- targeted cases: cycles, numbers, encodings ----------------------------------------------

def _retarget(text: str, pose: str, target: str) -> str:
    """``text`` with the ref object of ``:pose`` set to ``:target``."""
    new = re.sub(rf"(\n:{pose} a [^.]*?hasPhysicalLocation_RefObject ):\w+", rf"\1:{target}", text, flags=re.S)
    assert new != text, pose
    return new


TREE_CYCLES = {
    "own object": lambda t: _retarget(t, "part_a_1_pose", "part_a_1"),
    "two objects": lambda t: _retarget(t, "part_a_tray_pose", "part_a_1"),
    "three objects": lambda t: _retarget(_retarget(t, "work_table_1_pose", "part_a_1"), "part_a_tray_pose",
                                         "work_table_1"),
    "workstation below a part": lambda t: _retarget(t, "kitting_workstation_1_pose", "part_b_1"),
}
TREE_COMMANDS = ["validate ttl", "predicates ttl", "scenario transform ttl", "generate pddl init", "db load new",
                 "convert ttl"]


@pytest.mark.parametrize("cycle", sorted(TREE_CYCLES))
@pytest.mark.parametrize("name", TREE_COMMANDS)
def test_cycles_in_the_transformation_tree(name: str, cycle: str, seeds, seed_data, work) -> None:
    case = bench.CASE_BY_NAME[name]
    mutant = TREE_CYCLES[cycle](seed_data["ttl_init"].decode()).encode()
    outcome = bench.run_case(case, mutant, "cycle", seeds, work)
    assert not outcome.problems, (outcome.code, outcome.stderr[-1000:])
    if name == "predicates ttl" and cycle != "own object":  # a pose cannot be computed: said at its line
        assert outcome.code == 2 and re.search(r"init\.ttl:\d+: error: .*refers back to itself", outcome.stderr)


@pytest.mark.parametrize("name", ["run init", "plan init"])
def test_a_cycle_in_the_tree_stops_a_run(name: str, seeds, seed_data, work) -> None:
    mutant = TREE_CYCLES["two objects"](seed_data["ttl_init"].decode()).encode()
    outcome = bench.run_case(bench.CASE_BY_NAME[name], mutant, "cycle", seeds, work)
    assert not outcome.problems, (outcome.code, outcome.stderr[-1000:])


NUMBERS = ['"NaN"^^xsd:decimal', '"NaN"^^xsd:double', '"INF"^^xsd:double', '"-INF"^^xsd:double', "1e308", "-1e308", "1e309", "9" * 400]


@pytest.mark.parametrize("number", NUMBERS, ids=lambda n: n[:12])
@pytest.mark.parametrize("name", ["validate ttl", "predicates ttl", "scenario transform ttl", "db load new",
                                  "generate pddl init"])
def test_nan_and_infinite_coordinates(name: str, number: str, seeds, seed_data, work) -> None:
    text = seed_data["ttl_init"].decode()
    mutant = re.sub(r"(:part_a_1_point a [^.]*?hasPoint_X )[-\d.eE]+", rf"\g<1>{number}", text, flags=re.S)
    assert mutant != text
    outcome = bench.run_case(bench.CASE_BY_NAME[name], mutant.encode(), "numbers", seeds, work)
    assert not outcome.problems, (outcome.code, outcome.stderr[-1000:])


@pytest.mark.parametrize("number", ["9" * 400, '"abc"', '"NaN"^^xsd:double', '"-INF"^^xsd:double'], ids=lambda n: n[:8])
@pytest.mark.parametrize("name", ["predicates ttl", "validate ttl", "generate pddl init"])
def test_unusable_numbers_in_a_kit_design(name: str, number: str, seeds, seed_data, work) -> None:
    """A slot of the kit design (a PartRefAndPose's point) whose coordinate is no usable number."""
    text = seed_data["ttl_init"].decode()
    mutant = re.sub(r"(:kit_design_1_prp_a_1_point a [^.]*?hasPoint_X )[-\d.eE]+", rf"\g<1>{number}", text, flags=re.S)
    assert mutant != text
    outcome = bench.run_case(bench.CASE_BY_NAME[name], mutant.encode(), "numbers", seeds, work)
    assert not outcome.problems, (outcome.code, outcome.stderr[-1000:])


@pytest.mark.parametrize("number", ["nan", "inf", "-inf", "1e309", "1e308", "9" * 400], ids=lambda n: n[:8])
def test_nan_and_infinite_crcl(number: str, seeds, seed_data, work) -> None:
    for name, role in (("crcl convert text", "crcl_text"), ("crcl convert xml", "crcl_xml")):
        mutant = re.sub(rb"(?<=[{>])1\.5(?=[,<])", number.encode(), seed_data[role], count=3)
        assert mutant != seed_data[role]
        outcome = bench.run_case(bench.CASE_BY_NAME[name], mutant, "numbers", seeds, work)
        assert not outcome.problems, (outcome.code, outcome.stderr[-1000:])


@pytest.mark.parametrize("encoding", ["utf-16", "utf-32", "latin-1", "cp1252"])
@pytest.mark.parametrize("name", ["validate ofn", "crcl convert text", "plan domain.pddl", "db load new"])
def test_wrong_encodings(name: str, encoding: str, seeds, seed_data, work) -> None:
    case = bench.CASE_BY_NAME[name]
    text = seed_data[case.role].decode()
    word = {"ofn_init": "part_a_1", "crcl_text": "OpenGripper", "pddl_domain": "define", "ttl_init": "part_a_1"}
    text = text.replace(word[case.role], word[case.role].replace("a", "ä").replace("e", "é").replace("O", "Ö"), 3) \
        if encoding in ("latin-1", "cp1252") else text
    outcome = bench.run_case(case, text.encode(encoding), "encoding", seeds, work)
    assert not outcome.problems, (outcome.code, outcome.stderr[-1000:])
    if encoding in ("latin-1", "cp1252"):
        assert outcome.code == 2 and "UTF-8" in outcome.stderr, outcome.stderr


def test_a_database_that_is_not_one_is_left_alone(seeds, work) -> None:
    """db dump of a Turtle file, a picture, an empty file, a garbled page: one line, unchanged."""
    case = bench.CASE_BY_NAME["db dump"]
    data = seeds["db"].read_bytes()
    for mutant in (seeds["ttl_init"].read_bytes(), b"\x89PNG\r\n\x1a\n" + bytes(500), b"", data[:100],
                   data[:4096] + bytes(len(data) - 4096)):
        outcome = bench.run_case(case, mutant, "db", seeds, work)
        assert not outcome.problems and outcome.code == 2, (outcome.code, outcome.stderr[-1000:])


def test_the_seed_database_is_sound(seeds) -> None:
    with sqlite3.connect(seeds["db"]) as con:
        assert con.execute("PRAGMA integrity_check").fetchone()[0] == "ok"


# --- a sample in real processes --------------------------------------------------------------

SUBPROCESS_SAMPLE = [("validate ttl", "truncate"), ("convert ofn", "binary"), ("crcl convert xml", "deep-nesting"),
                     ("plan problem.pddl", "utf16"), ("db dump", "sqlite-page"), ("predicates ttl", "cycle"),
                     ("db load --replace", "huge-literal"), ("generate pddl goal", "shuffle-lines")]


@pytest.mark.parametrize(("name", "kind"), SUBPROCESS_SAMPLE, ids=[f"{n}-{k}" for n, k in SUBPROCESS_SAMPLE])
def test_in_a_real_process(name: str, kind: str, seeds, seed_data, work) -> None:
    case = bench.CASE_BY_NAME[name]
    mutant = bench.mutate(seed_data[case.role], kind, random.Random(kind).randrange, bench.family(case.role))
    outcome = bench.run_case(case, mutant, kind, seeds, work, real_process=True)
    assert not outcome.problems, (outcome.code, outcome.stderr[-1000:])


@pytest.mark.slow
def test_the_benchmark_campaign_runs(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """benchmarks/bench_bad_input.py end to end at a small size: counts, no problem, its section."""
    import json

    monkeypatch.chdir(tmp_path)
    out = tmp_path / "bad_input.json"
    assert bench.main(["--inputs", "40", "--subprocess", "4", "--seed", "3", "--no-doc", "--json", str(out)]) == 0
    result = json.loads(out.read_text())
    assert result["inputs"] == 40 and result["subprocesses"] == 4 and result["tracebacks"] == 0
    assert sum(result["by_exit"].values()) == 40 and set(result["by_exit"]) <= {"0", "1", "2"}
    section = bench.render(result, 3, 4, 1.0)
    assert section.startswith("## Bad-input campaign\n") and "**40 inputs tried**" in section
