"""Messages that mislead (issue 26 follow-ups from NIST's real files, points 4, 5 and 7).

Files shaped like NIST's: a state of the first 2012 form with NIST's own typing slips and a
2012-model excerpt beside it (``tests/data/validate_messages/nist2012``, hand-written in NIST's
syntax and names), NIST-2012-shaped state pairs (``tests/data/foreign/nist2012``) and NIST's
second 2013 state pair (``tests/data/kit_design_fit``, design ``a3b6c4``).

- ``plan`` says what helps given the options used (``--match-names`` only where it would);
- NIST's 2012 ``kittingClasses.owl`` beside the importing file is named in one note: kitkb's
  model stands in for it;
- a NIST 2012 term is reported once by ``validate``: at each statement, not again in the
  ``nist-2012-term`` warning (which ``predicates`` and ``plan`` keep whole);
- terms are named as the file writes them (its prefixes, the full IRI where it has none,
  never a prefix it does not declare; a renamed 2012 term with kitkb's name after it);
- "did you mean" only for plausible misspellings;
- a rule's finding at the statement that carries the offending value.
"""

from __future__ import annotations

import re
import shutil
from pathlib import Path

import pytest

from kb.cli import main
from kb.io import load
from kb.validation import validate
from kb.validation.suggest import allowed_slips, closest, did_you_mean, slips

DATA = Path(__file__).parent / "data"
NIST2012 = DATA / "validate_messages" / "nist2012"
INIT_2012 = NIST2012 / "kittingInstancesInit.owl"
MODEL_2012 = NIST2012 / "kittingClasses.owl"
PAIR_2012 = DATA / "foreign" / "nist2012"
A3B6C4 = DATA / "kit_design_fit" / "kittingInstancesInit-a3b6c4.owl"
A3B6C4_GOAL = DATA / "kit_design_fit" / "kittingInstancesGoal-a3b6c4.owl"
NS_2012 = "http://www.nist.gov/el/ontologies/kittingClasses.owl#"


def line_of(path: Path, text: str, nth: int = 1) -> int:
    """The line number of the ``nth`` line of ``path`` holding ``text``."""
    found = [i for i, line in enumerate(path.read_text("utf-8").splitlines(), 1) if text in line]
    return found[nth - 1]


def kitkb(capsys: pytest.CaptureFixture, *argv: str) -> tuple[int, str, str]:
    code = main(list(argv))
    out = capsys.readouterr()
    return code, out.out, out.err


def edited(tmp_path: Path, source: Path, old: str, new: str, name: str | None = None) -> Path:
    text = source.read_text("utf-8")
    assert old in text, old
    path = tmp_path / (name or source.name)
    path.write_text(text.replace(old, new, 1), "utf-8")
    return path


# --- 1. plan says what helps given the options used ------------------------------------------

def _goal_with_a_stranger(tmp_path: Path) -> Path:
    """NIST's second goal state naming a part the initial state has under no name (as NIST's
    Grasp state names a SKU its Init2 lacks)."""
    return edited(tmp_path, A3B6C4_GOAL, "Declaration(NamedIndividual(:kitting_workstation_1))",
                  "Declaration(NamedIndividual(:kitting_workstation_1))\n"
                  "ClassAssertion(ktw:Part :part_z_9)", "goal.owl")


def test_plan_with_match_names_does_not_suggest_match_names(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    goal = _goal_with_a_stranger(tmp_path)
    code, _, err = kitkb(capsys, "plan", str(A3B6C4), str(goal), "--match-names", "-o", str(tmp_path / "p.txt"))
    assert code == 2
    line = line_of(goal, "ClassAssertion(ktw:Part :part_z_9)")
    assert err == (f"{goal}:{line}: error: part_z_9 is in the goal state but not in the initial state "
                   "(--match-names found no individual called part_z_9 there either); only kits may be new in the "
                   "goal state (a kit is built during the plan): describe part_z_9 in the initial state, or leave "
                   "it out of the goal state (are the two files states of one workstation?)\n")
    assert not (tmp_path / "p.txt").exists()


def test_plan_without_match_names_suggests_it_only_where_it_helps(tmp_path: Path,
                                                                  capsys: pytest.CaptureFixture) -> None:
    # NIST's two states in two namespaces: the initial state has the goal's individual by name
    code, _, err = kitkb(capsys, "plan", str(A3B6C4), str(A3B6C4_GOAL), "-o", str(tmp_path / "p.txt"))
    assert code == 2
    assert "which calls it <http://www.nist.gov/el/ontologies/kittingInstancesInit1.owl#" in err
    assert err.rstrip().endswith("match individuals by local name (--match-names)")
    # a goal in the initial state's namespace naming an individual it has under no name
    init_ns = "Prefix(:=<http://www.nist.gov/el/ontologies/kittingInstancesInit1.owl#>)"
    goal = edited(tmp_path, _goal_with_a_stranger(tmp_path), "Prefix(:=<http://www.nist.gov/el/ontologies/"
                  "kittingInstancesGoal1.owl#>)", init_ns, "same-namespace.owl")
    code, _, err = kitkb(capsys, "plan", str(A3B6C4), str(goal), "-o", str(tmp_path / "p.txt"))
    assert code == 2
    assert ("part_z_9 is in the goal state but not in the initial state (no individual called part_z_9 there, "
            "in any namespace); only kits may be new") in err
    assert "--match-names" not in err


# --- 2. NIST's 2012 model beside the state: one note --------------------------------------------

def _pair_beside_the_model(tmp_path: Path) -> tuple[Path, Path]:
    for name in ("kittingInstancesInit.owl", "kittingInstancesGoal.owl"):
        shutil.copy(PAIR_2012 / name, tmp_path / name)
    shutil.copy(MODEL_2012, tmp_path / "kittingClasses.owl")
    return tmp_path / "kittingInstancesInit.owl", tmp_path / "kittingInstancesGoal.owl"


def _note(importer: Path) -> str:
    return (f"{importer}:{line_of(importer, 'Import(<file:kittingClasses.owl>)')}: info: kittingClasses.owl beside "
            f"{importer.name} is not read: kitkb's model stands in for NIST's 2012 model (the import of "
            "<file:kittingClasses.owl> is read as kitkb's kitting.ttl, the 2012 terms mapped onto it); name "
            "kittingClasses.owl on the command line to check it as a model file [model-stand-in]")


def test_the_2012_model_beside_the_state_is_named_once(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    init, goal = _pair_beside_the_model(tmp_path)
    code, out, _ = kitkb(capsys, "validate", str(init), str(goal))
    notes = [line for line in out.splitlines() if "[model-stand-in]" in line]
    assert notes == [_note(init)]  # once, at the first importer's import
    assert code == 1 and out.rstrip().endswith(", 1 note")
    # kitkb's model is what is read: the same findings as without the file beside
    alone = validate([PAIR_2012 / "kittingInstancesInit.owl"])
    beside = validate([init])
    assert [(d.rule, d.line, d.message) for d in beside.diagnostics if d.rule != "model-stand-in"] == \
        [(d.rule, d.line, d.message) for d in alone.diagnostics]
    assert [s.path.name for s in load([init]).sources] == ["kittingInstancesInit.owl", "kitting.ttl"]


def test_predicates_plan_and_generate_say_it_once(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    init, goal = _pair_beside_the_model(tmp_path)
    code, out, err = kitkb(capsys, "predicates", str(init), "--goal", str(goal))
    assert code == 0 and "part-location-partstray(part_a_1, part_a_tray)" in out
    assert err.splitlines() == [_note(init)]
    code, _, err = kitkb(capsys, "plan", str(init), str(goal), "-o", str(tmp_path / "plan.txt"))
    assert code == 0, err
    assert [line for line in err.splitlines() if "model-stand-in" in line] == [_note(init)]
    code, _, err = kitkb(capsys, "generate", "pddl", str(init), str(goal), "-o", str(tmp_path / "pddl"))
    assert code == 0 and [line for line in err.splitlines() if "model-stand-in" in line] == [_note(init)]


def test_no_note_without_the_model_beside_or_with_it_named(tmp_path: Path) -> None:
    assert not [w for w in load([PAIR_2012 / "kittingInstancesInit.owl"]).warnings if w.rule == "model-stand-in"]
    init, _ = _pair_beside_the_model(tmp_path)
    kb = load([init, tmp_path / "kittingClasses.owl"])
    assert not [w for w in kb.warnings if w.rule == "model-stand-in"]
    assert "kittingClasses.owl" in [s.path.name for s in kb.sources]


# --- 3. one defect, one report ---------------------------------------------------------------

def test_validate_reports_a_2012_term_at_its_statements_not_again_in_the_warning() -> None:
    report = validate([INIT_2012])
    assert not [d for d in report.diagnostics if d.rule == "nist-2012-term"]
    unknown = {(d.line, d.message) for d in report.diagnostics if d.rule == "unknown-property"}
    assert (line_of(INIT_2012, "DataPropertyAssertion(:hasBox_Height"),
            "unknown property :hasBox_Height on :PartATray") in unknown
    classes = [d for d in report.diagnostics if d.rule == "unknown-class"]
    assert {d.message for d in classes} >= {":RpyA1 is typed :RollPitchYaw, which is not a declared class"}


def test_a_term_validate_does_not_report_stays_in_the_warning() -> None:
    # --ignore unknown-property: the properties are reported nowhere else, the classes are
    report = validate([INIT_2012], ignore={"unknown-property"})
    (warning,) = [d for d in report.diagnostics if d.rule == "nist-2012-term"]
    assert warning.line == line_of(INIT_2012, "ObjectPropertyAssertion(:hasSolidObject_PhysicalLocation")
    assert warning.message.startswith("10 term(s) of NIST's 2012 kitting vocabulary")
    assert "hasSolidObject_PhysicalLocation (line 24), hasBox_Height (line 33), hasPose_Point" in warning.message
    assert "RollPitchYaw" not in warning.message and "Pose (line" not in warning.message
    # the 2012 model named: its terms are declared, so no statement reports them
    both = validate([INIT_2012, MODEL_2012])
    (warning,) = [d for d in both.diagnostics if d.rule == "nist-2012-term" and d.file == str(INIT_2012)]
    assert "RollPitchYaw" in warning.message and "hasPoint_Yaw" not in warning.message
    assert [d.line for d in both.diagnostics if "hasPoint_Yaw" in d.message] == \
        [line_of(INIT_2012, "DataPropertyAssertion(:hasPoint_Yaw")]


def test_predicates_keep_the_whole_warning(capsys: pytest.CaptureFixture) -> None:
    code, _, err = kitkb(capsys, "predicates", str(INIT_2012))
    assert code == 2
    (warning,) = [line for line in err.splitlines() if "[nist-2012-term]" in line]
    assert "12 term(s) of NIST's 2012 kitting vocabulary" in warning
    assert "hasSolidObject_PhysicalLocation (line 24), hasBox_Height (line 33)" in warning


# --- 4. 5. terms named as the file writes them ---------------------------------------------

def test_no_made_up_prefix_a_2012_class_in_the_files_prefix(tmp_path: Path) -> None:
    # a pose without its roll-pitch-yaw, validated against NIST's 2012 model named beside it
    init = edited(tmp_path, INIT_2012, "ObjectPropertyAssertion(:hasPose_Rpy :PartATrayPose :RpyA1)\n", "")
    shutil.copy(MODEL_2012, tmp_path / MODEL_2012.name)
    report = validate([init, tmp_path / MODEL_2012.name])
    text = "\n".join(d.format() for d in report.diagnostics)
    assert not re.search(r"\bns\d+:", text), text
    (found,) = [d for d in report.diagnostics if d.rule == "min-count" and d.focus == ":PartATrayPose"]
    assert found.message == (":PartATrayPose lacks :hasPose_Rpy: at least 1 value(s) required (an individual "
                             "of :RollPitchYaw)")
    assert found.line == line_of(init, "Declaration(NamedIndividual(:PartATrayPose))")


def test_full_iri_where_the_file_has_no_prefix(tmp_path: Path) -> None:
    model = tmp_path / "model.ttl"
    model.write_text("@prefix owl: <http://www.w3.org/2002/07/owl#> .\n"
                     "@prefix rdfs: <http://www.w3.org/2000/01/rdf-schema#> .\n"
                     "<http://e.org/m> a owl:Ontology .\n"
                     "<http://e.org/m#Widget> a owl:Class .\n<http://e.org/m#Gadget> a owl:Class .\n"
                     "<http://e.org/m#hasWidget_Gadget> a owl:ObjectProperty ;\n"
                     "    rdfs:domain <http://e.org/m#Widget> ; rdfs:range <http://e.org/m#Gadget> .\n"
                     "<http://e.org/m#Widget> rdfs:subClassOf [ a owl:Restriction ;\n"
                     "    owl:onProperty <http://e.org/m#hasWidget_Gadget> ; owl:someValuesFrom "
                     "<http://e.org/m#Gadget> ] .\n")
    data = tmp_path / "data.ttl"
    data.write_text("<http://e.org/d> a <http://www.w3.org/2002/07/owl#Ontology> ;\n"
                    "    <http://www.w3.org/2002/07/owl#imports> <http://e.org/m> .\n"
                    "<http://e.org/d#w1> a <http://e.org/m#Widget> .\n")
    report = validate([data, model])
    (found,) = [d for d in report.diagnostics if d.rule == "min-count"]
    assert found.message == ("<http://e.org/d#w1> lacks <http://e.org/m#hasWidget_Gadget>: at least 1 value(s) "
                             "required (an individual of <http://e.org/m#Gadget>)")


def test_a_renamed_2012_term_is_named_as_written_with_kitkbs_name() -> None:
    report = validate([INIT_2012])
    (found,) = [d for d in report.diagnostics if d.rule == "class"]
    assert found.message == (":hasSku_Shape (kitkb's hasStockKeepingUnit_InternalShape) of :StockKeepingUnitPartA "
                             "is :ShapePartA (it is :ShapeDesign), expected an individual of ktw:InternalShape")
    assert found.line == line_of(INIT_2012, "ObjectPropertyAssertion(:hasSku_Shape")
    (abstract,) = [d for d in report.diagnostics if d.rule == "abstract-class"]
    assert abstract.message == ":ShapePartA is typed :ShapeDesign, an abstract class: use one of its subclasses"


def test_two_2012_names_of_one_kitkb_term_each_named_at_its_statement(tmp_path: Path) -> None:
    # hasPart_Sku and hasPartsTray_Sku are both kitkb's hasSkuObject_Sku; each wrong at its line
    text = (PAIR_2012 / "kittingInstancesInit.owl").read_text("utf-8")
    part = re.search(r"ObjectPropertyAssertion\(:hasPart_Sku\s+:part_a_1\s+:(\w+)\)", text)
    tray = re.search(r"ObjectPropertyAssertion\(:hasPartsTray_Sku\s+:part_a_tray\s+:(\w+)\)", text)
    assert part and tray, "the 2012-shaped state names its SKUs so"
    text = text.replace(part.group(0), part.group(0).replace(part.group(1), "part_a_1_point"))
    text = text.replace(tray.group(0), tray.group(0).replace(tray.group(1), "part_a_tray_point"))
    path = tmp_path / "kittingInstancesInit.owl"
    path.write_text(text, "utf-8")
    found = {(d.line, d.message.split(" is ")[0]) for d in validate([path]).diagnostics if d.rule == "class"}
    assert found == {(line_of(path, "ObjectPropertyAssertion(:hasPart_Sku :part_a_1"),
                      ":hasPart_Sku (kitkb's hasSkuObject_Sku) of :part_a_1"),
                     (line_of(path, "ObjectPropertyAssertion(:hasPartsTray_Sku :part_a_tray"),
                      ":hasPartsTray_Sku (kitkb's hasSkuObject_Sku) of :part_a_tray")}


def test_the_2012_models_names_are_checked_as_written() -> None:
    report = validate([MODEL_2012])
    naming = {d.message for d in report.diagnostics if d.rule == "naming-convention"}
    # hasPartsTray_SerialNumber has the domain its name says (kitkb's name would not)
    assert not [m for m in naming if "SerialNumber" in m]
    assert (":hasWorkstation_LengthUnit (kitkb's hasKittingWorkstation_LengthUnit) is named for domain "
            "Workstation but its domain is :KittingWorkstation") in naming
    assert ":hasBox_Height is named for domain Box but its domain is :BoxyObject" in naming


# --- 6. did you mean: plausible misspellings only ----------------------------------------------

@pytest.mark.parametrize("written, candidates, meant", [
    ("PartGipperPose", ["PartGripperPose", "PartGripperPoint", "PartGripperRPY", "PartGripperHolderPose"],
     "PartGripperPose"),                                                  # NIST's 2012 states
    (":PartGipperPose", [":PartGripperPose", ":PartGripper"], ":PartGripperPose"),
    ("hasSprocket_Teth", ["hasSprocket_Teeth", "hasSprocket_Width"], "hasSprocket_Teeth"),
    ("Widgte", ["Widget", "Gadget"], "Widget"),                             # two letters swapped
    ("xsd:decmal", ["xsd:decimal", "xsd:double"], "xsd:decimal"),
    ("ktw:Pont", ["ktw:Point", "ktw:Part", "ktw:Robot"], "ktw:Point"),
    ("hasPoint_x", ["hasPoint_X", "hasPoint_Y"], "hasPoint_X"),            # letter case
    (":part_a_l", [":part_a_1", ":part_a_4"], ":part_a_1"),                # look-alikes
    (":hasPoint_x", ["ktw:hasPoint_X"], "ktw:hasPoint_X"),                 # compared without prefixes
    ("hasKittingWorkstaton_LenghtUnit", ["hasKittingWorkstation_LengthUnit"], "hasKittingWorkstation_LengthUnit"),
])
def test_a_plausible_misspelling_is_suggested(written: str, candidates: list[str], meant: str) -> None:
    assert closest(written, candidates) == meant


@pytest.mark.parametrize("written, candidates", [
    ("hasPoint_Yaw", ["hasPose_Point", "hasPoint_Y", "hasPoint_X"]),        # NIST's RollPitchYaw slip
    ("hasPoint_Roll", ["hasPoint_X", "hasRpy_Roll"]),
    ("hasRobot_Id", ["hasRobot_EndEffector", "hasRobot_Description"]),
    ("hasKitDesign_Id", ["hasKit_Design", "hasKitDesign_KitTraySku"]),
    ("hasLargeBoxWithKits_Box", ["hasLargeBoxWithKits_Kit"]),
    ("hasSku_EndEffectorRefs", ["hasRobot_EndEffector"]),
    ("hasSku_Weight", ["hasBoxyShape_Height"]),
    ("hasPart_Colour", ["hadByPart_Slot"]),
    ("hasSolidObject_PhysicalLocation", ["hasSolidObject_PrimaryLocation"]),
    (":sku_b", [":sku_a"]),
    (":table_1", [":tray_1"]),
    ("zzzz", ["ktw:Point"]),
    ("Id", ["Ix"]),
])
def test_an_unrelated_name_gets_no_suggestion(written: str, candidates: list[str]) -> None:
    assert closest(written, candidates) is None
    assert did_you_mean(written, candidates) == ""


def test_slips_count_typing_slips() -> None:
    assert slips("PartGipperPose", "PartGripperPose", 1) == 1
    assert slips("Widgte", "Widget", 1) == 1
    assert slips("abc", "abc", 0) == 0
    assert slips("hasPoint_Yaw", "hasPoint_Y", 5) == 2
    assert slips("hasPoint_Yaw", "hasPoint_Y", 1) == 2  # more than 1: told as most + 1
    assert allowed_slips("ktw:Pont") == 1 and allowed_slips("hasKittingWorkstation_LengthUnit") == 3
    assert allowed_slips("Id") == 0


def test_validate_suggests_nists_misspelt_pose_and_nothing_for_its_rpy_slips() -> None:
    report = validate([INIT_2012, MODEL_2012])
    line = line_of(INIT_2012, "ObjectPropertyAssertion(:hasPose_Rpy :PartGipperPose")
    (typo,) = [d for d in report.diagnostics if d.rule == "unknown-individual"]
    assert (typo.line, typo.message, typo.focus) == (
        line, "unknown individual :PartGipperPose (subject of :hasPose_Rpy, typed nowhere), did you mean "
              ":PartGripperPose?", ":PartGipperPose")
    # the pose it was meant for is not said to lack its roll-pitch-yaw as well
    assert not [d for d in report.diagnostics if d.focus == ":PartGripperPose"]
    slipped = [d for d in report.diagnostics if "hasPoint_Yaw" in d.message or "hasPoint_Roll" in d.message]
    assert len(slipped) == 2 and not [d for d in slipped if "did you mean" in d.message]


def test_a_subject_typed_nowhere_in_turtle(tmp_path: Path) -> None:
    small = next(p for p in (Path(__file__).parent.parent / "ontologies" / "scenarios").rglob("init.ttl")
                 if p.parent.name == "small-kit")
    text = small.read_text("utf-8") + '\n:part_a_l ktw:hasPart_SerialNumber "9"^^xsd:NMTOKEN .\n'
    path = tmp_path / "init.ttl"
    path.write_text(text, "utf-8")
    (found,) = validate([path]).diagnostics
    assert (found.rule, found.line) == ("unknown-individual", len(text.splitlines()))
    assert found.message == ("unknown individual :part_a_l (subject of ktw:hasPart_SerialNumber, typed nowhere), "
                             "did you mean :part_a_1?")


# --- 7. at the statement that carries the offending value ------------------------------------

def test_part_quantity_at_its_quantity_statement(tmp_path: Path) -> None:
    init = edited(tmp_path, A3B6C4, 'DataPropertyAssertion(ktw:hasPartsVessel_PartQuantity :part_a_tray\n'
                  '                      "2"^^xsd:nonNegativeInteger)',
                  'DataPropertyAssertion(ktw:hasPartsVessel_PartQuantity :part_a_tray\n'
                  '                      "12"^^xsd:nonNegativeInteger)')
    (found,) = [d for d in validate([init]).diagnostics if d.rule == "part-quantity"]
    assert found.line == line_of(init, "DataPropertyAssertion(ktw:hasPartsVessel_PartQuantity :part_a_tray")
    assert found.message == ("part quantity 12 of :part_a_tray differs from the number of parts it lists "
                             "(ktw:hasPartsVessel_Part)")


def test_vessel_part_sku_at_the_part_listed(tmp_path: Path) -> None:
    # part_b_1 listed in part_a_tray too: its SKU is not the tray's part SKU
    init = edited(tmp_path, A3B6C4, "ObjectPropertyAssertion(ktw:hasPartsVessel_Part\n"
                  "                        :part_a_tray :part_a_1)",
                  "ObjectPropertyAssertion(ktw:hasPartsVessel_Part\n"
                  "                        :part_a_tray :part_a_1)\n"
                  "ObjectPropertyAssertion(ktw:hasPartsVessel_Part :part_a_tray :part_b_1)")
    (found,) = [d for d in validate([init]).diagnostics if d.rule == "vessel-part-sku"]
    assert found.line == line_of(init, "ObjectPropertyAssertion(ktw:hasPartsVessel_Part :part_a_tray :part_b_1)")
