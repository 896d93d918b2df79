"""PDDL generation from the ontologies: golden files, round trips through UP's reader, errors.

Golden files live in tests/golden/pddl/; ``KITKB_REGENERATE=1 pytest tests/test_pddl_generation.py``
rewrites them (then review the diff).
"""

from __future__ import annotations

import os
from functools import lru_cache
from pathlib import Path

import pytest

from kb.core.errors import InputError, NotSolvableError
from kb.core.resources import scenario_dirs

from shared_data import NIST_DIR

GOLDEN = Path(__file__).parent / "golden" / "pddl"
SCENARIOS = {d.name: d for d in scenario_dirs()}
NIST = NIST_DIR
ENCODINGS = ("strips", "numeric")


def test_shipped_scenarios_are_the_expected_ones() -> None:
    assert sorted(SCENARIOS) == ["kit-a2b3c3d1e1", "small-kit", "two-designs"]


@lru_cache(maxsize=None)
def generator(scenario: str, encoding: str):  # noqa: ANN201
    from generators.pddl import PddlGenerator

    d = SCENARIOS[scenario]
    return PddlGenerator.from_files([d / "init.ttl"], [d / "goal.ttl"], encoding)


def texts(scenario: str, encoding: str) -> tuple[str, str]:
    domain, problem = generator(scenario, encoding).texts()
    assert problem is not None
    return domain, problem


def check_golden(name: str, text: str) -> None:
    path = GOLDEN / name
    if os.environ.get("KITKB_REGENERATE"):
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text, encoding="utf-8")
    assert path.is_file(), f"missing golden file {path}; run with KITKB_REGENERATE=1"
    assert text == path.read_text(encoding="utf-8"), f"{name} differs from its golden file"


@pytest.mark.parametrize("encoding", ENCODINGS)
def test_domain_matches_golden(encoding: str) -> None:
    from generators.pddl import PddlGenerator

    gen = PddlGenerator.domain_only(encoding)
    domain = gen.serialize()
    assert gen.outputs() == {"domain.pddl": domain}  # no problem without state files
    check_golden(f"domain-{encoding}.pddl", domain)
    # the domain written with a problem is the same domain (only the requirements line
    # reflects the problem too: a numeric goal adds :equality)
    def body(text: str) -> list[str]:
        return [line for line in text.splitlines() if ":requirements" not in line]

    assert body(texts("small-kit", encoding)[0]) == body(domain)


@pytest.mark.parametrize("scenario", sorted(SCENARIOS))
@pytest.mark.parametrize("encoding", ENCODINGS)
def test_problem_matches_golden_and_rereads(scenario: str, encoding: str) -> None:
    from kb.patches.unified_planning import environment

    environment()
    from unified_planning.io import PDDLReader

    domain, problem = texts(scenario, encoding)
    check_golden(f"{scenario}-{encoding}.pddl", problem)
    reread = PDDLReader().parse_problem_string(domain, problem)
    assert len(reread.actions) == 13  # with take-part-from-worktable, look-at-part-on-worktable and reject-part-from-worktable (issue 29)
    # UP reads back every object of kitkb's model and every goal atom written (as one conjunction)
    assert sorted(o.name for o in reread.all_objects) == sorted(generator(scenario, encoding).model.problem.objects)
    written = [line.strip() for line in problem.split("(:goal (and", 1)[1].splitlines() if line.strip().startswith("(")]
    (goal,) = reread.goals
    assert len(goal.args) == len(written)


def test_domain_has_every_element_with_its_source() -> None:
    domain = texts("small-kit", "numeric")[0]
    for action in ("take-kittray", "put-kittray", "create-kit", "take-part", "put-part", "take-kit",
                   "put-kit", "attach-endeffector", "remove-endeffector", "look-for-part"):
        i = domain.index(f"(:action {action}\n")
        assert f"source: <https://w3id.org/kitkb/kitting-domain#{action}>" in domain[i - 200:i]
    assert "(:functions" in domain and "(increase (quantity-kit ?kit ?sku) 1)" in domain
    assert "(< (quantity-kit ?kit ?sku) (capacity-kit ?kit ?sku))" in domain
    assert "; type part: <https://w3id.org/kitkb/kitting#Part>" in domain
    strips = texts("small-kit", "strips")[0]
    assert "(:functions" not in strips and "quantity-kit-pending" in strips


def test_take_part_parameters_follow_the_seed_order() -> None:
    domain = texts("small-kit", "strips")[0]
    assert ":parameters ( ?robot - robot ?part - part ?partstray - partstray ?endeffector - endeffector)" in domain


def test_problem_facts_follow_the_workstation_state() -> None:
    problem = texts("kit-a2b3c3d1e1", "numeric")[1]
    assert "(part-location-partstray part_e_1 part_e_tray)" in problem
    assert "(endeffector-location-endeffectorholder part_gripper part_gripper_holder)" in problem
    assert "(robot-with-no-endeffector robot_1)" in problem
    assert "(= (capacity-kit kit_1 sku_part_b) 3)" in problem
    assert "(kit-location-lbwk kit_1 finished_kit_receiver_1)" in problem
    assert "(= (quantity-kit kit_1 sku_part_b) (capacity-kit kit_1 sku_part_b))" in problem


def test_strips_tokens_take_the_goal_files_parts() -> None:
    problem = texts("two-designs", "strips")[1]
    # two-designs' goal puts part_b_2 and part_b_3 in kit_2: those are kit_2's tokens
    assert "(quantity-kit-counted kit_2 sku_part_b part_b_2)" in problem
    assert "(quantity-kit-counted kit_2 sku_part_b part_b_3)" in problem
    assert problem.count("quantity-kit-counted") == 9


@pytest.mark.skipif(not NIST.is_dir(), reason="NIST corpus not present")
def test_nist_state_files_give_a_problem() -> None:
    from kb.planning.model import kitting_model

    m = kitting_model([NIST / "kittingInstancesInit1.owl"], [NIST / "kittingInstancesGoal1.owl"], match_names=True)
    assert m.problem is not None
    assert ("kit-location-lbwk", "kit_1", "finished_kit_receiver") in m.problem.goal
    assert len([g for g in m.problem.goal if g[0] == "quantity-kit-counted"]) == 4
    assert m.problem.objects["kit_1"][0].endswith("#Kit")


def _scenario_copy(tmp_path: Path, name: str, edit) -> tuple[Path, Path]:  # noqa: ANN001
    src = SCENARIOS[name]
    init, goal = tmp_path / "init.ttl", tmp_path / "goal.ttl"
    init.write_text(src.joinpath("init.ttl").read_text(encoding="utf-8"), encoding="utf-8")
    goal.write_text(edit(src.joinpath("goal.ttl").read_text(encoding="utf-8")), encoding="utf-8")
    return init, goal


def test_unknown_class_names_file_and_line(tmp_path: Path) -> None:
    from kb.planning.model import kitting_model

    init, goal = _scenario_copy(tmp_path, "small-kit",
                                lambda t: t.replace("owl:NamedIndividual, ktw:Robot", "owl:NamedIndividual, ktw:Robott"))
    with pytest.raises(InputError) as err:
        kitting_model([init], [goal])
    line = next(i for i, l in enumerate(goal.read_text().splitlines(), 1) if "ktw:Robott" in l)
    assert str(err.value).startswith(f"{goal}:{line}: error:") and "Robott" in str(err.value)


def test_goal_object_missing_from_init_names_file_and_line(tmp_path: Path) -> None:
    from kb.planning.model import kitting_model

    init, goal = _scenario_copy(tmp_path, "small-kit", lambda t: t.replace(":part_b_1 ", ":part_z_9 "))
    with pytest.raises(InputError) as err:
        kitting_model([init], [goal])
    assert "part_z_9 is in the goal state but not in the initial state" in str(err.value)
    assert str(err.value).startswith(f"{goal}:")


def test_not_enough_parts_is_no_plan(tmp_path: Path) -> None:
    from kb.planning.model import kitting_model

    def remove_b_parts(text: str) -> str:
        return text.replace("ktw:hasPartsVessel_Part :part_b_", "ktw:hasPartsVessel_Part :gone_b_")

    src = SCENARIOS["small-kit"]
    init, goal = tmp_path / "init.ttl", tmp_path / "goal.ttl"
    text = src.joinpath("init.ttl").read_text(encoding="utf-8")
    # move every B part out of its tray: its primary location now refers to the robot's table
    text = text.replace("ktw:hasPhysicalLocation_RefObject :part_b_tray", "ktw:hasPhysicalLocation_RefObject :parts_table_1")
    init.write_text(remove_b_parts(text), encoding="utf-8")
    goal.write_text(src.joinpath("goal.ttl").read_text(encoding="utf-8"), encoding="utf-8")
    with pytest.raises(NotSolvableError, match="^no plan: kit kit_1 needs"):
        kitting_model([init], [goal], "strips")


def test_unknown_encoding_is_an_input_error() -> None:
    from kb.planning.model import domain_model

    with pytest.raises(InputError, match="unknown encoding"):
        domain_model("fluent")


def test_non_quota_comparison_cannot_be_compiled() -> None:
    from dataclasses import replace

    from kb.model.soap import load_domain
    from kb.model.soap import Comparison, FTerm
    from kb.planning.strips import compile_domain

    domain, _ = load_domain()
    put = next(a for a in domain.actions if a.name == "put-part")
    odd = replace(put, comparisons=[Comparison(">", FTerm("quantity-kit", ("kit", "sku")), 2.0, "x#odd")])
    with pytest.raises(InputError, match="not a quota"):
        compile_domain(replace(domain, actions=[odd]))


def test_pddl_generator_is_found_by_name() -> None:
    from generators.pddl import PddlGenerator
    from kb.core.generators import get_generator

    assert get_generator("pddl") is PddlGenerator


def test_kit_without_design_names_file_and_line(tmp_path: Path) -> None:
    from kb.planning.model import kitting_model

    init, goal = _scenario_copy(tmp_path, "small-kit", lambda t: t.replace("ktw:hasKit_Design", "rdfs:seeAlso"))
    with pytest.raises(InputError, match="kit kit_1 has no kit design") as err:
        kitting_model([init], [goal])
    assert str(err.value).startswith(f"{goal}:")


def test_count_changed_outside_a_quota_cannot_be_compiled() -> None:
    from dataclasses import replace

    from kb.model.soap import load_domain
    from kb.model.soap import FTerm, NumericEffect
    from kb.planning.strips import compile_domain

    domain, _ = load_domain()
    take = next(a for a in domain.actions if a.name == "take-kit")
    sneaky = replace(take, numeric=[NumericEffect("increase", FTerm("quantity-kit", ("kit", "kit")), 1.0, "x#sneaky")])
    others = [a for a in domain.actions if a.name != "take-kit"]
    with pytest.raises(InputError, match="take-kit: numeric effect sneaky cannot be compiled"):
        compile_domain(replace(domain, actions=others + [sneaky]))
