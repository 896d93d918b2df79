"""Classic PDDL as the IPC writes it: planned (and the plan validated by unified-planning),
or refused with one line naming the feature at its file:line (issue 26, point 8).

The domains in tests/data/pddl_classic/ are small, written for these tests in the shapes of
IPC domains: derived predicates (blocksworld with axioms, the promela domains), either types
(assembly), a predicate declared with one parameter name twice (logistics), a type and an
object with one name, IPC action costs with total-cost left uninitialised, and the
conventions of hand-written files.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from kb.core.errors import InputError, KitkbError
from kb.planning import read_pddl
from kb.planning.pddl.derived import MAX_SIZE

DATA = Path(__file__).parent / "data" / "pddl_classic"


def _downward() -> Path:
    import up_fast_downward

    return Path(up_fast_downward.__file__).parent / "downward" / "fast-downward.py"


def plan(name: str, tmp_path: Path, *extra: str, problem: str | None = None) -> tuple[int, list[str], str]:
    """``kitkb plan`` on ``NAME-domain.pddl`` and ``NAME-problem.pddl``: exit code, plan lines, stderr."""
    out = tmp_path / f"{name}.plan"
    domain = DATA / f"{name}-domain.pddl"
    prob = DATA / f"{problem or name}-problem.pddl"
    proc = subprocess.run([sys.executable, "-m", "kb.cli", "plan", str(domain), str(prob), "-o", str(out), *extra],
                          capture_output=True, text=True, timeout=300)
    lines = out.read_text().splitlines() if out.exists() else []
    return proc.returncode, lines, proc.stderr


def fd_optimal_length(domain: Path, problem: Path, tmp_path: Path) -> int:
    """The length of an optimal plan Fast Downward finds on the files as written (it reads
    derived predicates, either types and action costs itself): an independent reading."""
    work = tmp_path / "fd"
    work.mkdir(exist_ok=True)
    proc = subprocess.run([sys.executable, str(_downward()), "--plan-file", "sas_plan", str(domain), str(problem),
                           "--search", "astar(blind())"], cwd=work, capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stdout[-2000:]
    steps = [l for l in (work / "sas_plan").read_text().splitlines() if l.startswith("(")]
    return len(steps)


# --- derived predicates ----------------------------------------------------------------------

def test_derived_predicates_plan_and_validate(tmp_path: Path) -> None:
    code, lines, err = plan("blocks-axioms", tmp_path)
    assert code == 0, err
    assert "validated by unified-planning" in err
    # replay with the derived predicates computed from on/holding, as the domain defines them
    on, table, holding = {"c": "a", "d": "b"}, {"a", "b"}, None
    blocks = "abcd"

    def clear(x: str) -> bool:
        return holding != x and x not in on.values()

    for line in lines:
        name, *args = line[1:-1].split()
        if name == "pick-up":
            assert clear(args[0]) and args[0] in table and holding is None
            table.discard(args[0]); holding = args[0]
        elif name == "put-down":
            assert holding == args[0]
            table.add(args[0]); holding = None
        elif name == "stack":
            assert holding == args[0] and clear(args[1])
            on[args[0]] = args[1]; holding = None
        elif name == "unstack":
            assert on.get(args[0]) == args[1] and clear(args[0]) and holding is None
            del on[args[0]]; holding = args[0]
    assert on.get("a") == "b" and on.get("b") == "c" and not clear("c") and holding is None
    assert set(blocks) >= set(on)


def test_expansion_keeps_the_optimal_plan_length(tmp_path: Path) -> None:
    """Fast Downward, which reads derived predicates itself, finds optimal plans of one
    length on the files as written and on the text kitkb gives unified-planning."""
    for name in ("blocks-axioms", "telegraph"):
        domain, problem = DATA / f"{name}-domain.pddl", DATA / f"{name}-problem.pddl"
        task = read_pddl(domain, problem, warn=lambda m: None)
        assert ":derived" not in task.texts[0]
        (tmp_path / "d.pddl").write_text(task.texts[0])
        (tmp_path / "p.pddl").write_text(task.texts[1])
        assert fd_optimal_length(tmp_path / "d.pddl", tmp_path / "p.pddl", tmp_path) == \
            fd_optimal_length(domain, problem, tmp_path)


def test_stratified_derived_predicates_reach_a_deadlock(tmp_path: Path) -> None:
    code, lines, err = plan("telegraph", tmp_path)
    assert code == 0, err
    assert sorted(lines) == ["(read p1 s1 s2 c2)", "(read p2 t1 t2 c1)", "(write p1 s0 s1 c1)",
                             "(write p2 t0 t1 c2)"]


def test_recursive_derived_predicates_plan_with_fast_downward(tmp_path: Path) -> None:
    code, lines, err = plan("above", tmp_path)
    assert code == 0, err
    assert lines == ["(pick-up a)", "(stack a c)"]
    code, lines, err = plan("power", tmp_path)
    assert code == 0, err
    assert sorted(lines) == ["(close b1)", "(close s1)", "(close s2)", "(open s3)"]


def _check(task, text: str) -> bool:  # noqa: ANN001 - a PddlTask
    from unified_planning.io import PDDLReader

    from kb.planning import validate

    try:
        validate(task.problem, PDDLReader().parse_plan_string(task.problem, text))
    except KitkbError:
        return False
    return True


def test_validator_checks_plans_against_the_recursive_definition() -> None:
    """The fixpoint the validator evaluates is the derived predicates' meaning: a tower a on b
    on c puts a above c; a on b alone does not; leaving s3 closed feeds the faulty line."""
    above = read_pddl(DATA / "above-domain.pddl", DATA / "above-problem.pddl", warn=lambda m: None)
    assert _check(above, "(pick-up b)\n(stack b c)\n(pick-up a)\n(stack a b)")
    assert not _check(above, "(pick-up a)\n(stack a b)")
    assert not _check(above, "(pick-up c)\n(stack c a)")  # c above a, not a above c
    power = read_pddl(DATA / "power-domain.pddl", DATA / "power-problem.pddl", warn=lambda m: None)
    assert _check(power, "(open s3)\n(close b1)\n(close s1)\n(close s2)")
    assert not _check(power, "(close b1)\n(close s1)\n(close s2)")  # s3 closed: l3 fed
    assert not _check(power, "(open s3)\n(close s1)\n(close s2)")  # no breaker closed: nothing fed
    assert not _check(power, "(close s1)\n(open s3)\n(close s2)\n(open b1)")  # open b1 when it is open


def test_recursive_definitions_past_the_bound_are_refused(monkeypatch: pytest.MonkeyPatch) -> None:
    from kb.planning.pddl import axioms

    monkeypatch.setattr(axioms, "MAX_NODES", 200)
    with pytest.raises(InputError) as err:
        read_pddl(DATA / "above-domain.pddl", DATA / "above-problem.pddl", warn=lambda m: None)
    assert str(err.value).startswith(f"{DATA / 'above-domain.pddl'}:6: error: recursive derived predicates: "
                                     "checking plans against their definition takes more than 200 ground")


def test_recursive_derived_predicates_with_another_planner_are_refused(tmp_path: Path) -> None:
    code, lines, err = plan("above", tmp_path, "--planner", "enhsp")
    assert code == 2 and not lines
    assert err.strip() == (f"{DATA / 'above-domain.pddl'}:5: error: planner enhsp does not support this problem: "
                           "recursive derived predicates (planners that do: fast-downward, fast-downward-opt)")


def test_derived_predicate_changed_by_an_effect_is_refused(tmp_path: Path) -> None:
    domain = tmp_path / "d.pddl"
    text = (DATA / "blocks-axioms-domain.pddl").read_text()
    domain.write_text(text.replace("(and (not (ontable ?x)) (holding ?x))", "(and (not (ontable ?x)) (holding ?x)\n"
                                   "  (not (handempty)))", 1))
    line = next(i for i, l in enumerate(domain.read_text().splitlines(), 1) if l.startswith("  (not (handempty))"))
    with pytest.raises(InputError) as err:
        read_pddl(domain, DATA / "blocks-axioms-problem.pddl", warn=lambda m: None)
    assert str(err.value) == (f"{domain}:{line}: error: derived predicate handempty is changed by an effect "
                              "(a derived predicate is only defined by its :derived rules)")


def test_derived_predicate_in_init_is_refused(tmp_path: Path) -> None:
    problem = tmp_path / "p.pddl"
    problem.write_text((DATA / "blocks-axioms-problem.pddl").read_text().replace("(ontable b)", "(ontable b)\n(clear d)"))
    with pytest.raises(InputError, match=r"p\.pddl:5: error: derived predicate clear given in :init"):
        read_pddl(DATA / "blocks-axioms-domain.pddl", problem, warn=lambda m: None)


def test_expansion_size_is_bounded(tmp_path: Path) -> None:
    """Rules that each use the one below twice double per level: refused past the bound."""
    levels = 20
    rules = "\n".join(f"(:derived (d{i}) (and (d{i - 1}) (or (d{i - 1}) (p))))" for i in range(1, levels))
    domain = tmp_path / "d.pddl"
    domain.write_text(f"(define (domain blowup) (:predicates (p) {' '.join(f'(d{i})' for i in range(levels))})\n"
                      f"(:derived (d0) (p))\n{rules}\n(:action a :parameters () :precondition (d{levels - 1}) "
                      ":effect (p)))")
    problem = tmp_path / "p.pddl"
    problem.write_text("(define (problem b) (:domain blowup) (:init) (:goal (p)))")
    with pytest.raises(InputError, match=rf"expands to [\d,]+ symbols \(more than {MAX_SIZE:,}\): not supported"):
        read_pddl(domain, problem, warn=lambda m: None)


# --- types and names ---------------------------------------------------------------------------

def test_either_types_plan(tmp_path: Path) -> None:
    code, lines, err = plan("either", tmp_path)
    assert code == 0, err
    assert {"(fit g1 frame)", "(fit s1 frame)", "(polish-all)"} <= set(lines)
    assert {"(commit power frame)", "(commit wrench frame)"} <= set(lines)


def test_either_type_of_a_parameter_is_enforced(tmp_path: Path) -> None:
    """frame is an assembly, neither gear nor shaft: fit cannot take it as the part."""
    problem = tmp_path / "p.pddl"
    problem.write_text((DATA / "either-problem.pddl").read_text().replace(
        "(:goal (and (fitted g1 frame) (fitted s1 frame) (clean wrench) (clean g1)))", "(:goal (fitted frame g1))"))
    proc = subprocess.run([sys.executable, "-m", "kb.cli", "plan", str(DATA / "either-domain.pddl"), str(problem),
                           "-o", str(tmp_path / "x.plan")], capture_output=True, text=True, timeout=300)
    assert proc.returncode == 1, proc.stderr
    assert proc.stderr.startswith("no plan: fast-downward says UNSOLVABLE")


def test_repeated_parameter_name_in_a_predicate_plans(tmp_path: Path) -> None:
    code, lines, err = plan("logistics", tmp_path)
    assert code == 0, err
    assert lines == ["(load-truck obj11 tru1 pos1)", "(drive-truck tru1 pos1 apn1 cit1)",
                     "(unload-truck obj11 tru1 apn1)"]


def test_repeated_parameter_name_in_an_action_is_refused(tmp_path: Path) -> None:
    code, lines, err = plan("repeated-parameter", tmp_path)
    assert code == 2 and not lines
    assert err.splitlines() == [f"{DATA / 'repeated-parameter-domain.pddl'}:6: error: parameter ?x is declared "
                                "twice in action stack (first at line 6): which one the body means is ambiguous"]


def test_one_name_for_a_type_an_object_a_predicate_and_an_action(tmp_path: Path) -> None:
    code, lines, err = plan("names", tmp_path)
    assert code == 0, err
    # the plan names objects and actions as the files do
    assert "(load truck)" in lines and "(load load)" in lines
    assert lines[-1] == "(drive truck depot drive)"
    assert len(lines) == 5


def test_conventions_of_hand_written_files(tmp_path: Path) -> None:
    code, lines, err = plan("conventions", tmp_path)
    assert code == 0, err
    assert lines[:2] == ["(go r2d2 and not)", "(take r2d2 1st not)"]
    assert "(take r2d2 box.7 forall)" in lines and "(go r2d2 either object)" in lines
    assert lines[-1] == "(go r2d2 at either)" and len(lines) == 13


# --- action costs ----------------------------------------------------------------------------

def test_action_costs_with_total_cost_left_uninitialised(tmp_path: Path) -> None:
    code, lines, err = plan("costs", tmp_path, "--planner", "fast-downward-opt")
    assert code == 0, err
    assert lines == ["(pick-up truck-1 a package-1)", "(drive truck-1 a d)", "(drive truck-1 d c)",
                     "(drop truck-1 c package-1)"]
    assert "(PDDL, cost 9)" in err
    code, lines, err = plan("costs", tmp_path)  # the planner chosen by the problem's kind
    assert code == 0 and "by fast-downward (PDDL, cost " in err, err


def test_undefined_action_cost_makes_the_action_inapplicable(tmp_path: Path) -> None:
    """Without a length, the short road d -> c cannot be driven (as in Fast Downward and VAL)."""
    problem = tmp_path / "p.pddl"
    problem.write_text((DATA / "costs-problem.pddl").read_text().replace("(= (road-length d c) 4)", ""))
    proc = subprocess.run([sys.executable, "-m", "kb.cli", "plan", str(DATA / "costs-domain.pddl"), str(problem),
                           "-o", str(tmp_path / "x.plan"), "--planner", "fast-downward-opt", "--format", "json"],
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr
    report = json.loads(proc.stdout)
    assert report["cost"] == 22 and "(drive truck-1 d c)" not in report["plan"]


def test_unit_costs_and_initialised_total_cost(tmp_path: Path) -> None:
    code, lines, err = plan("costs-unit", tmp_path)
    assert code == 0, err
    assert len(lines) == 5 and "by fast-downward (PDDL, cost 5)" in err


def test_costs_without_a_metric_are_ignored(tmp_path: Path) -> None:
    code, lines, err = plan("costs-unit", tmp_path, problem="costs-nometric")
    assert code == 0, err
    assert len(lines) == 5 and "by fast-downward (PDDL)," in err


def test_total_cost_in_a_condition_stays_numeric(tmp_path: Path) -> None:
    """Not the IPC convention: a numeric problem, total-cost starting at 0 when not given."""
    domain = tmp_path / "d.pddl"
    domain.write_text((DATA / "costs-unit-domain.pddl").read_text().replace(
        ":precondition (and (room ?from)", ":precondition (and (< (total-cost) 100) (room ?from)"))
    task = read_pddl(domain, DATA / "costs-nometric-problem.pddl", warn=lambda m: None)
    total = task.problem.fluent("total-cost")
    assert task.problem.initial_value(total()).constant_value() == 0
    assert "INCREASE_EFFECTS" in task.problem.kind.features


# --- refused, one line, at the line -------------------------------------------------------------

BLOCKS = (DATA / "blocks-axioms-domain.pddl").read_text()
TIMED = BLOCKS.replace("(:action pick-up\n", "(:durative-action pick-up :duration (= ?duration 1)\n", 1).replace(
    ":precondition (and (clear ?x) (ontable ?x) (handempty))\n     :effect (and (not (ontable ?x)) (holding ?x))",
    ":condition (at start (and (clear ?x) (ontable ?x) (handempty)))\n"
    "     :effect (and (at end (not (ontable ?x))) (at end (holding ?x)))", 1)
PROBLEM = "(define (problem p) (:domain blocks-axioms) (:objects a b - block)\n(:init (ontable a))\n(:goal {}))"

#: (what, domain text (None: the blocks domain), problem text (None: its problem), the text
#: on the line of the error, the message). The domain is the file named unless a problem is given.
REFUSED = [
    ("a durative action", TIMED, None, "(:durative-action pick-up",
     "no installed planner supports this problem: durative actions (:durative-action)"),
    ("preferences", None, PROBLEM.format("(preference p1 (ontable a))"), "(:goal",
     "preferences (PDDL 3 :preferences) are not supported"),
    ("an object-valued function", BLOCKS.replace("(handempty))", "(handempty))\n(:functions (top ?x - block) - block)", 1),
     None, "(:functions", "function top has values of type block: object-valued functions (:object-fluents) are "
     "not supported"),
    ("either in :types", BLOCKS.replace("(:types block)", "(:types block - object\ntower - (either block object))", 1), None,
     "tower -", "type tower is declared with (either ...): not supported"),
    ("an object of an either type", None, "(define (problem p) (:domain blocks-axioms)\n"
     "(:objects a - (either block))(:init) (:goal (ontable a)))", "(:objects", "object a is of type (either ...): "
     "not supported"),
    ("PDDL 1.2 axioms", BLOCKS.replace("(:derived (handempty)", "(:axiom :vars () :context (p) :implies (q))\n"
                                       "(:derived (handempty)", 1), None, "(:axiom", ":axiom: not supported: PDDL 1.2 axioms"),
    ("HTN", BLOCKS.replace("(:action pick-up", "(:task deliver :parameters ())\n(:action pick-up", 1), None, "(:task",
     ":task: not supported: HTN tasks (HDDL)"),
    ("domain constraints", BLOCKS.replace("(:types block)", "(:types block)\n(:constraints (always (handempty)))", 1),
     None, "(:constraints", "domain :constraints (PDDL 3): not supported"),
    ("an unknown requirement", BLOCKS.replace(":strips :typing", ":strips :teleport :typing", 1), None, ":teleport",
     "unknown requirement :teleport"),
    ("a type cycle", BLOCKS.replace("(:types block)", "(:types block - brick brick - block)", 1), None, "(:types",
     "type block is its own ancestor (block - brick - block)"),
    ("an unknown predicate", None, PROBLEM.format("(ontabel a)"), "(:goal", "unknown predicate ontabel"),
    ("a wrong number of arguments", None, PROBLEM.format("(on a)"), "(:goal", "on takes 2 argument(s), given 1: (on a)"),
    ("an unknown object", None, PROBLEM.format("(ontable c)"), "(:goal", "unknown object c"),
    ("an object declared twice", None, "(define (problem p) (:domain blocks-axioms) (:objects a - block\n"
     "a - block) (:init) (:goal (ontable a)))", "a - block)", "object a is declared twice (first at line 1)"),
    ("an unknown variable", BLOCKS.replace("(holding ?x))", "(holding ?z))", 1), None, "(holding ?z)",
     "unknown variable ?z (not a parameter, nor bound by a quantifier around it)"),
    ("an unknown type", BLOCKS.replace("(?x - block ?y - block)", "(?x - block ?y - blok)", 1), None, "- blok",
     "unknown type blok"),
    ("an unbalanced parenthesis", BLOCKS + ")\n", None, ")", "')' closes nothing"),
    ("files in the wrong order", (DATA / "blocks-axioms-problem.pddl").read_text(), None, "(define",
     "this is a problem file, where a domain file was expected (kitkb plan DOMAIN PROBLEM)"),
]


def _line_of(text: str, marker: str) -> int:
    """The line of the last occurrence of ``marker`` at the start of a line, else of its first occurrence."""
    lines = text.splitlines()
    starts = [i for i, l in enumerate(lines, 1) if l.strip().startswith(marker)]
    return starts[-1] if marker == ")" else starts[0] if starts else next(i for i, l in enumerate(lines, 1) if marker in l)


@pytest.mark.parametrize(("what", "domain", "problem", "marker", "message"), REFUSED, ids=[r[0] for r in REFUSED])
def test_refused_with_the_feature_at_its_line(what: str, domain: str | None, problem: str | None, marker: str,
                                              message: str, tmp_path: Path) -> None:
    d, p = DATA / "blocks-axioms-domain.pddl", DATA / "blocks-axioms-problem.pddl"
    if domain is not None:
        d = tmp_path / "domain.pddl"
        d.write_text(domain)
    if problem is not None:
        p = tmp_path / "problem.pddl"
        p.write_text(problem)
    where = p if problem is not None else d
    line = _line_of(where.read_text(), marker)
    proc = subprocess.run([sys.executable, "-m", "kb.cli", "plan", str(d), str(p), "-o", str(tmp_path / "x.plan")],
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 2, proc.stderr
    assert len(proc.stderr.splitlines()) == 1 and "Traceback" not in proc.stderr
    assert proc.stderr.startswith(f"{where}:{line}: error: {message}"), proc.stderr
    assert not (tmp_path / "x.plan").exists()


def test_refused_list_covers_the_documented_features() -> None:
    """docs/pddl.md lists what is refused; the parametrized cases above cover it."""
    assert len(REFUSED) == 18
    doc = (Path(__file__).parent.parent / "docs" / "pddl.md").read_text()
    for phrase in ("durative", "preferences", ":object-fluents", "either", ":axiom", "HTN", ":constraints",
                   "recursive", "total-cost"):
        assert phrase in doc, phrase


def test_an_error_the_reader_finds_is_at_the_line_of_the_file(tmp_path: Path) -> None:
    """A type mismatch is unified-planning's reader's to find; its line is the file's."""
    problem = tmp_path / "p.pddl"
    problem.write_text("(define (problem t) (:domain transport-costs)\n"
                       "  (:objects a b - location truck-1 - vehicle package-1 - package)\n"
                       "  (:init (at truck-1 a)\n"
                       "         (in package-1 a))\n"
                       "  (:goal (at package-1 b)))\n")
    with pytest.raises(InputError) as err:
        read_pddl(DATA / "costs-domain.pddl", problem, warn=lambda m: None)
    assert err.value.file == str(problem) and err.value.line == 4, str(err.value)


def test_names_renamed_for_unified_planning_are_mapped_back() -> None:
    task = read_pddl(DATA / "conventions-domain.pddl", DATA / "conventions-problem.pddl", warn=lambda m: None)
    names = {o.name for o in task.problem.all_objects}
    assert {"o-1st", "o-box_7", "object-2"} <= names
    assert {task.original(n) for n in names} >= {"1st", "box.7", "object", "and", "not", "at", "home"}


def test_problem_for_another_domain_warns(tmp_path: Path) -> None:
    problem = tmp_path / "p.pddl"
    problem.write_text((DATA / "blocks-axioms-problem.pddl").read_text().replace("(:domain blocks-axioms)",
                                                                               "(:domain blocksworld)"))
    warnings: list[str] = []
    read_pddl(DATA / "blocks-axioms-domain.pddl", problem, warn=warnings.append)
    assert warnings == [f"{problem}:2: warning: the problem is for domain blocksworld, the domain file is "
                        "blocks-axioms"]


def test_forms_unified_planning_took_before_still_plan(tmp_path: Path) -> None:
    """'-type' glued to its dash, an empty quantifier, objects named like numbers PDDL does not
    have (nan, inf), an empty precondition and effect."""
    domain = tmp_path / "d.pddl"
    domain.write_text("(define (domain glued) (:types boat -object person -object)\n"
                      "(:predicates (saved ?p -person) (near ?b -boat ?p -person))\n"
                      "(:action rescue :parameters (?b -boat ?p -person)\n"
                      " :precondition (and (near ?b ?p) (forall () (near ?b ?p))) :effect (saved ?p))\n"
                      "(:action wait :parameters () :precondition () :effect ()))")
    problem = tmp_path / "p.pddl"
    problem.write_text("(define (problem g) (:domain glued) (:objects nan - boat inf - person)\n"
                       "(:init (near nan inf)) (:goal (saved inf)))")
    proc = subprocess.run([sys.executable, "-m", "kb.cli", "plan", str(domain), str(problem), "-o",
                           str(tmp_path / "x.plan")], capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr
    assert (tmp_path / "x.plan").read_text().splitlines() == ["(rescue nan inf)"]
    assert f"{domain}:5: warning: action wait changes nothing; left out" in proc.stderr


def test_numbers_past_the_bound_and_contingent_problems_are_refused(tmp_path: Path) -> None:
    problem = tmp_path / "p.pddl"
    problem.write_text((DATA / "costs-problem.pddl").read_text().replace("(= (road-length a b) 10)",
                                                                       f"(= (road-length a b) {'9' * 5000})"))
    with pytest.raises(InputError, match=r"p\.pddl:5: error: a number of 5,000 characters \(more than 100\)"):
        read_pddl(DATA / "costs-domain.pddl", problem, warn=lambda m: None)
    domain = tmp_path / "d.pddl"
    domain.write_text("(define (domain c)\n(:requirements :strips :contingent)\n(:predicates (p)))")
    with pytest.raises(InputError, match=r"d\.pddl:2: error: :contingent: not supported: contingent planning"):
        read_pddl(domain, DATA / "blocks-axioms-problem.pddl", warn=lambda m: None)


def test_data_files_count() -> None:
    """The shapes the tests plan or refuse (a case lost would shrink the suite silently)."""
    assert len(list(DATA.glob("*-domain.pddl"))) == 11
