"""Predicates computed from geometry (kb.spatial.predicates) agree with the symbolic state the
PDDL generator reads, are defined in Turtle only, and report bad definitions and shapes."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from kb.cli import main
from kb.core.errors import InputError
from kb.core.namespaces import KTW
from kb.core.resources import ontology_path
from kb.model.definitions import check_definitions, load_definitions, read_definitions
from kb.planning.model import read_specs
from kb.planning.state import pddl_name
from kb.spatial import Evaluator, Scene, true_predicates
from kb.spatial.transforms import from_xyz_rpy
from shared_data import NIST_DIR

SCENARIOS = Path(ontology_path("kitting-domain.ttl")).parent / "scenarios"
SHIPPED = ["kit-a2b3c3d1e1", "small-kit", "two-designs"]
NIST = NIST_DIR


@pytest.fixture(scope="module")
def defs():
    return load_definitions()


def _named(facts):
    return {(name, *map(pddl_name, args)) for name, args in facts}


def _agreement(defs, init: Path, goal: Path, match_names: bool = False):
    _domain, spec = read_specs([init], [goal], encoding="numeric", match_names=match_names)
    start = Evaluator(defs, Scene.from_files([init], declared=[goal], match_names=match_names))
    end = Evaluator(defs, Scene.from_files([goal]))
    return spec, start, end


@pytest.mark.parametrize("scenario", SHIPPED)
def test_init_predicates_from_geometry_equal_the_generated_pddl_facts(defs, scenario: str) -> None:
    spec, start, _ = _agreement(defs, SCENARIOS / scenario / "init.ttl", SCENARIOS / scenario / "goal.ttl")
    assert _named(start.facts()) == spec.facts


@pytest.mark.parametrize("scenario", SHIPPED)
def test_init_function_values_from_geometry_equal_the_generated_ones(defs, scenario: str) -> None:
    spec, start, _ = _agreement(defs, SCENARIOS / scenario / "init.ttl", SCENARIOS / scenario / "goal.ttl")
    for fn in ("quantity-partstray", "quantity-kit", "capacity-kit"):
        mine = {(fn, *map(pddl_name, args)): v for args, v in start.function_values(fn).items()}
        theirs = {k: v for k, v in spec.values.items() if k[0] == fn}
        assert theirs and {k: mine.get(k, 0) for k in theirs} == theirs, fn  # the generator zero-fills
        assert all(v == 0 for k, v in mine.items() if k not in theirs), fn


@pytest.mark.parametrize("scenario", SHIPPED)
def test_every_goal_fact_holds_in_the_goal_geometry(defs, scenario: str) -> None:
    spec, _, end = _agreement(defs, SCENARIOS / scenario / "init.ttl", SCENARIOS / scenario / "goal.ttl")
    true = _named(end.facts())
    assert spec.goal and all(tuple(g) in true for g in spec.goal)
    quantity = {(pddl_name(k), pddl_name(s)): v for (k, s), v in end.function_values("quantity-kit").items()}
    capacity = {(pddl_name(k), pddl_name(s)): v for (k, s), v in end.function_values("capacity-kit").items()}
    for (q, *args), (c, *args2) in spec.goal_equal:
        assert (q, c) == ("quantity-kit", "capacity-kit") and args == args2
        assert quantity[tuple(args)] == capacity[tuple(args)] > 0


def test_nist_init1_and_goal1_agree_with_the_generated_facts(defs) -> None:
    """NIST's holders sit against the ends of the changing-station base (a 1 mm plate with the
    gripper hanging below it) and its parts are exactly as tall as the kit tray: kitkb's
    In-Or-Against relation and Partially-In with EQ cover both (docs/soap.md)."""
    init, goal = NIST / "kittingInstancesInit1.owl", NIST / "kittingInstancesGoal1.owl"
    spec, start, end = _agreement(defs, init, goal, match_names=True)
    assert _named(start.facts()) == spec.facts
    true = _named(end.facts())
    assert all(tuple(g) in true for g in spec.goal)
    assert ("robot-with-endeffector", "robot_1", "tray_gripper") in spec.facts  # mounted on the robot point
    assert ("endeffector-location-endeffectorholder", "part_gripper", "part_gripper_holder") in spec.facts


# ------------------------------------------------------------------------------ hand-built scenes

R, EE, PART, TABLE, TRAY = "urn:x#robot", "urn:x#gripper", "urn:x#part", "urn:x#table", "urn:x#tray"


def _cell(part_z: float, tip_z: float | None = None, table_top: float = 0.75) -> Scene:
    """A robot flange (point) with a gripper (0.04 x 0.04 x 0.1, hanging down), a part of
    0.05 x 0.05 x 0.05 and a table."""
    down = from_xyz_rpy(0, 0, 0, np.pi, 0, 0)  # z axis down
    tip_z = part_z + 0.05 if tip_z is None else tip_z
    flange = down.copy()
    flange[:3, 3] = [0.0, 0.0, tip_z + 0.1]
    gripper = flange.copy()
    part = from_xyz_rpy(0.0, 0.0, part_z, 0, 0, 0)
    table = from_xyz_rpy(0.0, 0.0, 0.0, 0, 0, 0)
    names = [R, EE, PART, TABLE, "urn:x#sku", TRAY]
    classes = [[str(KTW.Robot)], [str(KTW.GripperEffector)], [str(KTW.Part)], [str(KTW.WorkTable)],
               [str(KTW.StockKeepingUnit)], [str(KTW.PartsTray)]]
    poses = np.stack([flange, gripper, part, table, np.full((4, 4), np.nan),
                      from_xyz_rpy(5.0, 0.0, table_top, 0, 0, 0)])
    lo = np.array([[0, 0, 0], [-0.02, -0.02, 0], [-0.025, -0.025, 0], [-0.5, -0.5, 0], [np.nan] * 3, [-.2, -.2, 0]])
    hi = np.array([[0, 0, 0], [0.02, 0.02, 0.1], [0.025, 0.025, 0.05], [0.5, 0.5, table_top], [np.nan] * 3,
                   [.2, .2, 0.04]])
    facts = {str(KTW.hasSkuObject_Sku): {(PART, "urn:x#sku")},
             str(KTW.hasStockKeepingUnit_EndEffector): {("urn:x#sku", EE)}}
    return Scene.from_parts(names, classes, poses, lo, hi, facts)


def test_a_part_touching_the_gripper_in_the_air_is_held(defs) -> None:
    ev = Evaluator(defs, _cell(part_z=1.0))
    assert ev.holds("robot-holds-part", R, PART) and ev.holds("part-location-robot", PART, R)
    assert ev.holds("robot-with-endeffector", R, EE) and not ev.holds("robot-empty", R)
    assert ev.holds("endeffector-type-part", EE, PART) and ev.holds("part-sku", PART, "urn:x#sku")


def test_a_part_resting_on_the_table_is_not_held_though_it_touches_the_gripper(defs) -> None:
    ev = Evaluator(defs, _cell(part_z=0.75))
    assert ev.holds("part-location-robot", PART, R)  # touches the gripper
    assert not ev.holds("robot-holds-part", R, PART)  # but the table supports it
    assert ev.holds("robot-empty", R) is False


def test_contact_tolerance_is_one_millimetre(defs) -> None:
    assert Evaluator(defs, _cell(part_z=0.7505, tip_z=1.5)).holds("robot-empty", R)
    on_table = Evaluator(defs, _cell(part_z=0.7505, tip_z=1.5))
    assert not on_table.holds("worktable-empty", TABLE)  # 0.5 mm above the table: resting on it
    assert Evaluator(defs, _cell(part_z=0.755, tip_z=1.5)).holds("worktable-empty", TABLE)  # 5 mm: apart
    assert Evaluator(defs, _cell(part_z=0.755, tip_z=1.5), tolerance=0.01).holds("worktable-empty", TABLE) is False


def test_existential_never_binds_an_argument_again(defs) -> None:
    """robot-empty looks for a held object other than the robot it is about: the flange
    touching the gripper must not count as something held."""
    ev = Evaluator(defs, _cell(part_z=0.2, tip_z=1.5))
    assert ev.holds("robot-empty", R)


# ------------------------------------------------------------------------------ Turtle only

EXTRA = """@prefix kd: <https://w3id.org/kitkb/kitting-domain#> .
@prefix soap: <https://w3id.org/kitkb/soap#> .
@prefix ktw: <https://w3id.org/kitkb/kitting#> .
@prefix owl: <http://www.w3.org/2002/07/owl#> .
@prefix xsd: <http://www.w3.org/2001/XMLSchema#> .
@prefix x: <urn:extra#> .

<urn:extra> a owl:Ontology ; owl:imports <https://w3id.org/kitkb/kitting-domain> .

x:partstray-crowded a owl:NamedIndividual , soap:Predicate ;
    soap:hasPredicate_Name "partstray-crowded" ;
    soap:hasPredicate_ReferenceType ktw:PartsTray ;
    soap:hasPredicate_Definition x:c1 .
x:part a owl:NamedIndividual , soap:Variable ; soap:hasVariable_Name "part" ; soap:hasVariable_Class ktw:Part .
x:c2 a owl:NamedIndividual , soap:RelationAtom ; soap:hasRelationAtom_Relation soap:Partially-In ;
    soap:hasRelationAtom_Subject x:part ; soap:hasRelationAtom_Object soap:Reference ; soap:hasAtom_IsNegated false .
x:c1 a owl:NamedIndividual , soap:CountAtom ; soap:hasCountAtom_Variable x:part ; soap:hasCountAtom_Condition x:c2 ;
    soap:hasCountAtom_Operator ">=" ; soap:hasCountAtom_Limit "4"^^xsd:decimal ; soap:hasAtom_IsNegated false .

x:holder-or-tray a owl:NamedIndividual , soap:Predicate ;
    soap:hasPredicate_Name "in-holder-or-tray" ;
    soap:hasPredicate_ReferenceType ktw:SolidObject ;
    soap:hasPredicate_Definition x:d1 .
x:d1 a owl:NamedIndividual , soap:Disjunction ; soap:hasDisjunction_Operand x:d3 , x:d5 .
x:h a owl:NamedIndividual , soap:Variable ; soap:hasVariable_Name "holder" ; soap:hasVariable_Class ktw:EndEffectorHolder .
x:t a owl:NamedIndividual , soap:Variable ; soap:hasVariable_Name "tray" ; soap:hasVariable_Class ktw:PartsTray .
x:d3 a owl:NamedIndividual , soap:Existential ; soap:hasExistential_Variable x:h ; soap:hasExistential_Body x:d2 .
x:d2 a owl:NamedIndividual , soap:RelationAtom ; soap:hasRelationAtom_Relation soap:In-Or-Against ;
    soap:hasRelationAtom_Subject soap:Reference ; soap:hasRelationAtom_Object x:h ; soap:hasAtom_IsNegated false .
x:d5 a owl:NamedIndividual , soap:Existential ; soap:hasExistential_Variable x:t ; soap:hasExistential_Body x:d4 .
x:d4 a owl:NamedIndividual , soap:RelationAtom ; soap:hasRelationAtom_Relation soap:Partially-In ;
    soap:hasRelationAtom_Subject soap:Reference ; soap:hasRelationAtom_Object x:t ; soap:hasAtom_IsNegated false .
"""


def test_a_predicate_added_in_turtle_alone_is_evaluated(tmp_path: Path, capsys) -> None:
    extra = tmp_path / "extra.ttl"
    extra.write_text(EXTRA)
    init = SCENARIOS / "small-kit" / "init.ttl"
    code = main(["predicates", str(init), "--domain", str(extra), "-p", "partstray-crowded", "-p",
                 "in-holder-or-tray"])
    assert code == 0
    assert capsys.readouterr().out.splitlines() == [
        "in-holder-or-tray(part_a_1)", "in-holder-or-tray(part_a_2)", "in-holder-or-tray(part_a_3)",
        "in-holder-or-tray(part_a_4)", "in-holder-or-tray(part_b_1)", "in-holder-or-tray(part_b_2)",
        "in-holder-or-tray(part_b_3)", "in-holder-or-tray(part_gripper)", "in-holder-or-tray(tray_gripper)",
        "partstray-crowded(part_a_tray)",  # 4 parts; part_b_tray has 3
    ]


def _broken(tmp_path: Path, old: str, new: str) -> Path:
    text = ontology_path("kitting-domain.ttl").read_text()
    assert old in text
    path = tmp_path / "kitting-domain.ttl"
    path.write_text(text.replace(old, new, 1))
    return path


def _line(path: Path, needle: str) -> int:
    return next(i for i, line in enumerate(path.read_text().splitlines(), 1) if needle in line)


def test_a_malformed_definition_is_an_error_at_its_file_and_line(tmp_path: Path, capsys) -> None:
    bad = _broken(tmp_path, "kd:worktable-empty_f2 a owl:NamedIndividual , soap:Existential ;\n"
                            "    soap:hasExistential_Variable kd:worktable-empty_tray ;\n",
                  "kd:worktable-empty_f2 a owl:NamedIndividual , soap:Existential ;\n")
    with pytest.raises(InputError) as err:
        load_definitions([bad])
    line = _line(bad, "kd:worktable-empty_f2 a owl:NamedIndividual")
    assert (err.value.file, err.value.line) == (str(bad), line)
    assert "worktable-empty" in err.value.message and "hasExistential_Variable" in err.value.message
    assert main(["validate", str(bad)]) == 1
    report = capsys.readouterr().out
    assert f"{bad}:{line}: error: predicate worktable-empty: existential worktable-empty_f2 needs exactly one " \
           f"hasExistential_Variable (has 0) [malformed-definition]" in report
    assert main(["predicates", str(SCENARIOS / "small-kit" / "init.ttl"), "--domain", str(bad)]) == 2
    assert capsys.readouterr().err.startswith(f"{bad}:{line}: error: predicate worktable-empty")


def test_a_variable_outside_its_quantifier_and_an_unknown_relation_are_reported(tmp_path: Path) -> None:
    bad = _broken(tmp_path, "soap:hasRelationAtom_Relation soap:On-Top-With-Contact ;\n"
                            "    soap:hasRelationAtom_Subject kd:worktable-empty_tray ;",
                  "soap:hasRelationAtom_Relation soap:On-Top-With-Contact ;\n"
                  "    soap:hasRelationAtom_Subject kd:robot-empty_held ;")
    text = bad.read_text()
    old = "kd:kit-location-worktable_f1 a owl:NamedIndividual , soap:RelationAtom ;\n" \
          "    soap:hasRelationAtom_Relation soap:On-Top-With-Contact ;"
    bad.write_text(text.replace(old, old.replace("On-Top-With-Contact", "On-Top-With-Contac")))
    from kb.io import load
    problems = check_definitions(load([bad]).graph)
    assert sorted(p.message for p in problems) == [
        "predicate kit-location-worktable: relation On-Top-With-Contac is neither one of the 30 RCC8/cardinal "
        "relations nor a class with an owl:equivalentClass definition",
        "predicate worktable-empty: atom worktable-empty_f3 uses variable robot-empty_held outside the "
        "quantifier that introduces it"]
    assert read_definitions(load([ontology_path("kitting-domain.ttl")]).graph).predicates  # the shipped file is sound


# ------------------------------------------------------------------------------ CLI and shapes

def test_cli_prints_one_atom_a_line_and_json(capsys) -> None:
    init = str(SCENARIOS / "small-kit" / "init.ttl")
    assert main(["predicates", init, "-p", "partstray-not-empty", "-p", "robot-with-no-endeffector"]) == 0
    assert capsys.readouterr().out.splitlines() == [
        "partstray-not-empty(part_a_tray)", "partstray-not-empty(part_b_tray)", "robot-with-no-endeffector(robot_1)"]
    assert main(["predicates", init, "-p", "kittray-location-lbwekt", "--format", "json"]) == 0
    assert json.loads(capsys.readouterr().out) == [
        {"predicate": "kittray-location-lbwekt", "args": ["kit_tray_1", "empty_kit_tray_supply"]}]


def test_goal_declared_objects_give_kit_facts_like_the_generator() -> None:
    init, goal = SCENARIOS / "small-kit" / "init.ttl", SCENARIOS / "small-kit" / "goal.ttl"
    alone = true_predicates([init], names=["kit-kittray"])
    assert alone == []  # the kit first appears in the goal
    with_goal = true_predicates([init], goal=goal, names=["kit-kittray", "kit-location-lbwk"])
    assert [(n, tuple(map(pddl_name, a))) for n, a in with_goal] == [("kit-kittray", ("kit_1", "kit_tray_1"))]


def test_an_object_placed_without_a_shape_is_an_error_naming_it(tmp_path: Path, capsys) -> None:
    text = (SCENARIOS / "small-kit" / "init.ttl").read_text()
    old = "    ktw:hasSolidObject_PrimaryLocation :work_table_1_pose ;\n    ktw:hasNoSkuObject_InternalShape :shape_work_table_1 ."
    assert old in text
    state = tmp_path / "init.ttl"
    state.write_text(text.replace(old, "    ktw:hasSolidObject_PrimaryLocation :work_table_1_pose ."))
    assert main(["predicates", str(state)]) == 2
    err = capsys.readouterr().err
    line = _line(state, ":work_table_1 a owl:NamedIndividual")
    assert err.startswith(f"{state}:{line}: error: work_table_1 is placed but has no shape")


def test_check_geometry_names_a_state_whose_boxes_contradict_its_stated_locations(tmp_path: Path) -> None:
    """part_a_1 says it is in part_a_tray, but its pose lifts it 0.5 m above the tray."""
    from kb.planning.geometry import check_geometry
    text = (SCENARIOS / "small-kit" / "init.ttl").read_text()
    old = ":part_a_1_point a owl:NamedIndividual, ktw:Point ;\n    ktw:hasPoint_X -0.14 ;\n" \
          "    ktw:hasPoint_Y -0.05 ;\n    ktw:hasPoint_Z 0.0 ."
    assert old in text
    init = tmp_path / "init.ttl"
    init.write_text(text.replace(old, old.replace("ktw:hasPoint_Z 0.0", "ktw:hasPoint_Z 0.5")))
    result = check_geometry([init], [SCENARIOS / "small-kit" / "goal.ttl"])
    assert not result.agrees
    assert result.only_symbolic == [("part-location-partstray", "part_a_1", "part_a_tray")]
    assert result.only_geometry == [] and result.goal_not_holding == []
    assert check_geometry([SCENARIOS / "small-kit" / "init.ttl"], [SCENARIOS / "small-kit" / "goal.ttl"]).agrees


def test_a_cylindrical_shape_counts_by_its_bounding_box(tmp_path: Path) -> None:
    """Part B as a cylinder 0.07 across and 0.06 high: its world box is 0.07 x 0.07 x 0.06 about
    the part's pose, and it is still in its tray."""
    text = (SCENARIOS / "small-kit" / "init.ttl").read_text()
    old = (":shape_part_b a owl:NamedIndividual, ktw:BoxyShape ;\n    ktw:hasShapeDesign_Description \"shape of part B\" ;\n"
           "    ktw:hasBoxyShape_Length 0.12 ;\n    ktw:hasBoxyShape_Width 0.08 ;\n    ktw:hasBoxyShape_Height 0.06 ;\n"
           "    ktw:hasBoxyShape_HasTop true .")
    assert old in text
    state = tmp_path / "init.ttl"
    state.write_text(text.replace(old, ":shape_part_b a owl:NamedIndividual, ktw:CylindricalShape ;\n"
                                       "    ktw:hasShapeDesign_Description \"part B, round\" ;\n"
                                       "    ktw:hasCylindricalShape_Diameter 0.07 ;\n"
                                       "    ktw:hasCylindricalShape_Height 0.06 ;\n"
                                       "    ktw:hasCylindricalShape_HasTop true ."))
    boxy, round_ = Scene.from_files([SCENARIOS / "small-kit" / "init.ttl"]), Scene.from_files([state])
    i = round_.index[next(n for n in round_.names if n.endswith("#part_b_1"))]
    centre = (boxy.lo[i] + boxy.hi[i]) / 2
    assert np.allclose(round_.hi[i] - round_.lo[i], [0.07, 0.07, 0.06])
    assert np.allclose((round_.lo[i] + round_.hi[i]) / 2, centre)
    facts = true_predicates([state], names=["part-location-partstray"])
    assert ("part-location-partstray", ("part_b_1", "part_b_tray")) in [(n, tuple(map(pddl_name, a))) for n, a in facts]
