"""Planning with real planners: every shipped scenario, NIST's files, plan shape, errors."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest
from rdflib import RDF, Graph, Namespace

from kb.core.errors import ConfigurationError, InputError
from kb.core.resources import scenario_dirs

from shared_data import NIST_DIR

SCENARIOS = {d.name: d for d in scenario_dirs()}
NIST = NIST_DIR
KTW = Namespace("https://w3id.org/kitkb/kitting#")
nist = pytest.mark.skipif(not NIST.is_dir(), reason="NIST corpus not present")


def plan_lines(init: Path, goal: Path, encoding: str = "strips", planner: str | None = None,
               match_names: bool = False) -> tuple[str, list[str]]:
    from kb import planning

    result = planning.plan_files(init, goal, None, planner, encoding, match_names=match_names)
    return result.planner, result.lines


def actions(lines: list[str], name: str) -> list[list[str]]:
    return [line[1:-1].split()[1:] for line in lines if line[1:].split()[0] == name]


@pytest.mark.parametrize("scenario", sorted(SCENARIOS))
def test_every_shipped_scenario_plans_and_validates(scenario: str) -> None:
    d = SCENARIOS[scenario]
    planner, lines = plan_lines(d / "init.ttl", d / "goal.ttl")
    assert planner == "fast-downward"  # chosen from the problem kind (classical)
    # the goal file's kits and the parts in them, counted with rdflib
    goal = Graph().parse(d / "goal.ttl", format="turtle")
    kits = len(set(goal.subjects(RDF.type, KTW.Kit)))
    parts = len(set(goal.subject_objects(KTW.hasKit_Part)))
    assert len(actions(lines, "take-part")) == len(actions(lines, "put-part")) == parts
    assert len(actions(lines, "put-kit")) == kits
    # the minimum length: 2 per part; per kit tray in, create, kit out (5) and the end-effector
    # swaps (tray gripper off, part gripper on, off, tray gripper on: 4); the first attach; the
    # last remove (every goal fact is a goal: the goal files put both effectors in their holders)
    assert len(lines) == 2 * parts + 5 * kits + 4 * kits + 1 + 1
    assert actions(lines, "remove-endeffector")[-1] == lines[-1][1:-1].split()[1:]


def test_shipped_scenario_count() -> None:
    assert len(SCENARIOS) == 3


def test_ten_part_five_type_plan_has_the_expected_shape() -> None:
    d = SCENARIOS["kit-a2b3c3d1e1"]
    _, lines = plan_lines(d / "init.ttl", d / "goal.ttl")
    names = [line[1:].split()[0] for line in lines]
    # tray from the supply box to the work table, kit made on it
    assert names.index("take-kittray") < names.index("put-kittray") < names.index("create-kit")
    assert actions(lines, "put-kittray")[0][2] == "work_table_1"
    # every part taken then put in the kit, ten parts of five SKUs
    taken = [a[1] for a in actions(lines, "take-part")]
    put = [a[1] for a in actions(lines, "put-part")]
    assert len(taken) == 10 and sorted(taken) == sorted(put)
    assert {a[4] for a in actions(lines, "put-part")} == {f"sku_part_{c}" for c in "abcde"}
    for part in taken:
        i = lines.index(next(l for l in lines if l.startswith(f"(take-part robot_1 {part} ")))
        assert lines[i + 1].startswith(f"(put-part robot_1 {part} kit_1 work_table_1 ")
    # the finished kit goes to the finished-kit box last, then the tray gripper back in its
    # holder (every goal fact is a goal: the goal file's robot has no effector)
    assert lines[-3].startswith("(take-kit robot_1 kit_1 ") and lines[-2] == "(put-kit robot_1 kit_1 finished_kit_receiver_1)"
    assert lines[-1] == "(remove-endeffector robot_1 tray_gripper tray_gripper_holder changing_station_1)"
    # end effectors change: tray gripper for trays and kits, part gripper for parts
    attached = [a[1] for a in actions(lines, "attach-endeffector")]
    assert attached == ["tray_gripper", "part_gripper", "tray_gripper"]
    assert len(actions(lines, "remove-endeffector")) == 3
    assert all(a[3] == "part_gripper" for a in actions(lines, "take-part"))
    assert len(lines) == 31  # the minimum: 2 x 10 parts + 11


def test_pyperplan_solves_the_strips_encoding() -> None:
    d = SCENARIOS["small-kit"]
    planner, lines = plan_lines(d / "init.ttl", d / "goal.ttl", planner="pyperplan")
    assert planner == "pyperplan" and len(actions(lines, "put-part")) == 3


@pytest.mark.slow
def test_enhsp_solves_the_numeric_encoding() -> None:
    d = SCENARIOS["kit-a2b3c3d1e1"]
    planner, lines = plan_lines(d / "init.ttl", d / "goal.ttl", encoding="numeric")
    assert planner == "enhsp"  # chosen from the problem kind (numeric fluents)
    assert len(actions(lines, "put-part")) == 10


def test_numeric_problem_is_given_to_a_numeric_planner() -> None:
    from kb.planning.model import kitting_model
    from kb import planning

    d = SCENARIOS["small-kit"]
    problem = kitting_model([d / "init.ttl"], [d / "goal.ttl"], "numeric").up_problem
    assert planning.choose_planner(problem) == "enhsp"
    with pytest.raises(ConfigurationError, match="does not support"):
        planning.choose_planner(problem, "fast-downward")


def test_missing_planner_names_its_package() -> None:
    from kb.planning.model import kitting_model
    from kb import planning

    d = SCENARIOS["small-kit"]
    problem = kitting_model([d / "init.ttl"], [d / "goal.ttl"]).up_problem
    with pytest.raises(ConfigurationError, match=r"planner tamer is not installed \(pip install up-tamer\)"):
        planning.choose_planner(problem, "tamer")


@nist
def test_nist_state_files_plan() -> None:
    # NIST writes its initial and goal states in two namespaces: by IRI they share nothing
    with pytest.raises(InputError, match="is in the goal state but not in the initial state"):
        plan_lines(NIST / "kittingInstancesInit1.owl", NIST / "kittingInstancesGoal1.owl")
    _, lines = plan_lines(NIST / "kittingInstancesInit1.owl", NIST / "kittingInstancesGoal1.owl", match_names=True)
    assert len(actions(lines, "put-part")) == 4  # NIST's kit design a2b1c1
    assert lines[-1] == "(put-kit robot_1 kit_1 finished_kit_receiver)"


def run_cli(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "kb.cli", *args], capture_output=True, text=True, timeout=600)


@nist
@pytest.mark.parametrize("problem", ["problem-fluents-a2b1c1.pddl",
                                     "problem-fluents-a2b3c3d1e1.pddl"])
def test_nist_pddl_plans_through_the_cli(problem: str, tmp_path: Path) -> None:
    out = tmp_path / "plan.txt"
    proc = run_cli("plan", str(NIST / "domain-fluents.pddl"), str(NIST / problem), "-o", str(out))
    assert proc.returncode == 0, proc.stderr
    assert "warning: requirement :derived-predicates is declared but never used" in proc.stderr
    lines = out.read_text().splitlines()
    assert lines[-1].startswith("(put-kit robot_1 ")
    assert all(line.startswith("(") and line.endswith(")") for line in lines)


def test_cli_generate_and_plan_from_ontology_files(tmp_path: Path) -> None:
    d = SCENARIOS["small-kit"]
    proc = run_cli("generate", "pddl", str(d / "init.ttl"), str(d / "goal.ttl"), "-o", str(tmp_path))
    assert proc.returncode == 0, proc.stderr
    assert (tmp_path / "domain.pddl").is_file() and (tmp_path / "problem.pddl").is_file()
    out = tmp_path / "plan.txt"
    proc = run_cli("plan", str(d / "init.ttl"), str(d / "goal.ttl"), "-o", str(out))
    assert proc.returncode == 0, proc.stderr
    assert "(take-part robot_1 part_a_1 part_a_tray part_gripper)" in out.read_text().splitlines()


@pytest.mark.slow
@pytest.mark.parametrize("encoding", ["strips", "numeric"])
def test_generated_pddl_plans_through_the_cli(encoding: str, tmp_path: Path) -> None:
    d = SCENARIOS["two-designs"]
    proc = run_cli("generate", "pddl", str(d / "init.ttl"), str(d / "goal.ttl"), "-o", str(tmp_path),
                   "--encoding", encoding)
    assert proc.returncode == 0, proc.stderr
    out = tmp_path / "plan.txt"
    proc = run_cli("plan", str(tmp_path / "domain.pddl"), str(tmp_path / "problem.pddl"), "-o", str(out))
    assert proc.returncode == 0, proc.stderr
    assert ("by fast-downward" if encoding == "strips" else "by enhsp") in proc.stderr
    assert len([l for l in out.read_text().splitlines() if l.startswith("(put-kit ")]) == 2


def test_unsolvable_goal_is_no_plan_exit_1(tmp_path: Path) -> None:
    from generators.pddl import PddlGenerator

    d = SCENARIOS["small-kit"]
    domain, problem = PddlGenerator.from_files([d / "init.ttl"], [d / "goal.ttl"]).texts()
    # the finished-kit box is full: put-kit can never run
    (tmp_path / "domain.pddl").write_text(domain)
    (tmp_path / "problem.pddl").write_text(problem.replace("(lbwk-not-full finished_kit_receiver_1)", ""))
    out = tmp_path / "plan.txt"
    proc = run_cli("plan", str(tmp_path / "domain.pddl"), str(tmp_path / "problem.pddl"), "-o", str(out))
    assert proc.returncode == 1
    assert proc.stderr.startswith("no plan: fast-downward says UNSOLVABLE"), proc.stderr
    assert not out.exists()


def test_unknown_object_in_pddl_names_file_and_line(tmp_path: Path) -> None:
    from kb import planning

    bad = tmp_path / "problem.pddl"
    text = (NIST / "problem-fluents-a2b1c1.pddl").read_text()
    bad.write_text(text.replace("- PartsTray", "- PartTray"))
    line = next(i for i, l in enumerate(bad.read_text().splitlines(), 1) if "PartTray" in l)
    with pytest.raises(InputError) as err:
        planning.read_pddl(NIST / "domain-fluents.pddl", bad, warn=lambda m: None)
    assert str(err.value) == f"{bad}:{line}: error: unknown type PartTray"


def test_help_does_not_import_unified_planning() -> None:
    code = ("import sys; from kb.cli import build_parser; build_parser().format_help(); "
            "print('unified_planning' in sys.modules)")
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert proc.stdout.strip() == "False"


def test_validator_speed_ups_reject_broken_plans() -> None:
    """kitkb's fast paths inside unified-planning's validator still reject wrong plans."""
    from unified_planning.plans import SequentialPlan

    from kb.planning.model import kitting_model
    from kb import planning
    from kb.core.errors import KitkbError

    d = SCENARIOS["small-kit"] if "small-kit" in SCENARIOS else next(iter(SCENARIOS.values()))
    problem = kitting_model([d / "init.ttl"], [d / "goal.ttl"]).up_problem
    plan = planning.solve(problem, planning.choose_planner(problem))
    planning.validate(problem, plan)  # the planner's plan is accepted
    steps = list(plan.actions)
    swapped = steps[:]
    swapped[0], swapped[1] = swapped[1], swapped[0]
    for broken in (steps[1:], steps[:-1], swapped):
        with pytest.raises(KitkbError, match="does not validate"):
            planning.validate(problem, SequentialPlan(broken))


def test_validator_fast_paths_match_unified_planning_walkers() -> None:
    """Substitution and state evaluation fast paths give UP's own walkers' results."""
    from unified_planning.model.walkers.state_evaluator import StateEvaluator
    from unified_planning.model.walkers.substituter import Substituter
    from unified_planning.engines.sequential_simulator import UPSequentialSimulator

    from kb.patches import unified_planning as up_patches
    from kb.planning.model import kitting_model

    d = next(iter(SCENARIOS.values()))
    problem = kitting_model([d / "init.ttl"], [d / "goal.ttl"]).up_problem
    env = problem.environment
    substituter = Substituter(env)
    evaluator = StateEvaluator(problem)
    state = UPSequentialSimulator(problem).get_initial_state()
    objects = {}
    for action in problem.actions:
        if any(not objects.setdefault(p.type, list(problem.objects(p.type))) for p in action.parameters):
            continue  # a type the scenario has no object of (a reject bin): nothing to ground
        subs = {}
        for p in action.parameters:
            subs[env.expression_manager.ParameterExp(p)] = env.expression_manager.ObjectExp(objects[p.type][0])
        promoted = up_patches.promote(substituter, subs)
        exprs = list(action.preconditions) + [e.fluent for e in action.effects] + [e.value for e in action.effects]
        exprs += [env.expression_manager.Not(x) for x in action.preconditions]
        for expr in exprs:
            ground = up_patches.substitute_fast(substituter, expr, promoted)
            assert ground is substituter.walk(expr, subs=promoted)
            fast = up_patches.evaluate_literal(ground, state, env.expression_manager)
            assert fast is not None and fast is StateEvaluator.evaluate(evaluator, ground, state)
