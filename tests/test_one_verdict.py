"""One verdict per defect (issue 26, point 5): a defect that stops a command is reported by
``kitkb validate`` as what it is — an error, at the same line, with the same message and a rule
naming it — so an author learns it there first.

The commands read a state's geometry with :meth:`kb.spatial.scene.Scene.from_files` and stop
at the first defect (exit 2); ``validate`` reads it with :func:`kb.spatial.survey.survey`,
which lists every defect. Each case below is a file shaped like a real one with one defect
(NIST's functional syntax in ``tests/data/one_verdict``, made from NIST's first state by
``make_one_verdict.py``; kitkb's Turtle, edited here); for each, the command's one line is one
of ``validate``'s errors (or the same defect is already an error of another rule at that node,
a misspelt coordinate being an ``unknown-property``), and where ``validate`` finds no error the
commands do not stop.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

from kb.cli import main
from kb.core.errors import InputError
from kb.core.resources import scenario_dirs
from kb.io.loader import load
from kb.scenario import write_scenario
from kb.spatial.scene import Scene
from kb.spatial.survey import survey
from kb.validation import validate
from tests.shared_data import NIST_DIR

DATA = Path(__file__).parent / "data" / "one_verdict"
SMALL_KIT = next(d for d in scenario_dirs() if d.name == "small-kit")
NIST_SHAPED = sorted(DATA.glob("*.owl"))


def _sub(pattern: str, repl: str, count: int = 1):  # noqa: ANN202
    def edit(text: str) -> str:
        out, n = re.subn(pattern, repl, text, count=count, flags=re.S | re.M)
        assert n >= 1, pattern
        return out
    return edit


#: an edit of the small kit's initial state -> the rule of the defect it makes
TURTLE = {
    "a part's SKU without a shape": (
        _sub(r"(:sku_part_a a .*?)ktw:hasStockKeepingUnit_InternalShape :\w+ ;\n\s*", r"\1"), "no-shape"),
    "a holder without a shape": (
        _sub(r"(:part_gripper_holder a .*?)ktw:hasNoSkuObject_InternalShape :\w+ ;\n\s*", r"\1"), "no-shape"),
    "a shape with no dimensions": (
        _sub(r"(:shape_part_a a owl:NamedIndividual, ktw:)BoxyShape( ;.*?) ;\s*ktw:hasBoxyShape_Length [0-9.]+ ;\s*"
             r"ktw:hasBoxyShape_Width [0-9.]+ ;\s*ktw:hasBoxyShape_Height [0-9.]+ ;\s*ktw:hasBoxyShape_HasTop true",
             r"\1InternalShape\2"), "no-shape"),
    "a misspelt shape name": (
        _sub(r"(:sku_part_a a .*?ktw:hasStockKeepingUnit_InternalShape) :shape_part_a", r"\1 :shape_prt_a"),
        "unknown-individual"),
    "a reference cycle": (
        _sub(r"(:part_a_tray_pose a .*?ktw:hasPhysicalLocation_RefObject) :\w+", r"\1 :part_a_1"), "reference-cycle"),
    "a coordinate left out": (
        _sub(r"(:part_a_1_point a .*?)ktw:hasPoint_Y [-0-9.eE]+ ;\s*", r"\1"), "min-count"),
    "a coordinate of hundreds of digits": (
        _sub(r"(:part_a_1_point a .*?ktw:hasPoint_X) [-0-9.eE]+", r"\1 " + "9" * 400), "unusable-number"),
    "a coordinate that is a word": (
        _sub(r"(:part_a_1_point a .*?ktw:hasPoint_X) [-0-9.eE]+", r'\1 "left"'), "datatype"),
    "an axis of length zero": (
        _sub(r"(:part_a_1_z_axis a .*?ktw:hasVector_K) [-0-9.]+", r"\1 0.0"), "axis-unit-length"),
    "parallel axes": (
        _sub(r"(:part_a_1_x_axis a .*?ktw:hasVector_I) [-0-9.]+( ;\s*ktw:hasVector_J [-0-9.]+ ;\s*ktw:hasVector_K)"
             r" [-0-9.]+", r"\1 0.0\2 1.0"), "axes-orthogonal"),
    "two length units": (
        _sub(r'(ktw:hasKittingWorkstation_LengthUnit) "meter"', r'\1 "meter", "millimeter"'), "max-count"),
    "a unit kitkb cannot convert": (
        _sub(r'(ktw:hasKittingWorkstation_LengthUnit) "meter"', r'\1 "furlong"'), "enumeration"),
    "a slot coordinate of hundreds of digits": (
        _sub(r"(:kit_design_a2b1_prp_a_1_point a .*?ktw:hasPoint_X) [-0-9.eE]+", r"\1 " + "9" * 400),
        "unusable-number"),
    "a slot axis of length zero": (
        _sub(r"(:kit_design_a2b1_prp_a_1_z_axis a .*?ktw:hasVector_K) [-0-9.]+", r"\1 0.0"), "axis-unit-length"),
    "a misspelt reference object": (
        _sub(r"(:part_a_1_pose a .*?ktw:hasPhysicalLocation_RefObject) :\w+", r"\1 :part_a_tary"), "unknown-individual"),
    "a reference object located with no point": (  # tests/test_unknown_reference.py has more
        _sub(r"(:part_a_tray_pose a owl:NamedIndividual, ktw:)PoseLocationOn ;(\s*ktw:hasPhysicalLocation_RefObject"
             r" :\w+) ;.*?\.\n", r'\1RelativeLocationOn ;\2 ;\n    ktw:hasRelativeLocation_Description "on a table" .\n'),
        "unknown-reference"),
}


def _refusal(path: Path) -> InputError | None:
    """What ``kitkb predicates`` stops with on ``path`` (None: it does not stop)."""
    try:
        Scene.from_files([path])
    except InputError as exc:
        return exc
    return None


def _same_verdict(path: Path) -> tuple[InputError | None, list]:
    """The command's refusal and validate's errors. The refusal is one of the defects the
    survey lists (its message and line), and validate reports that defect: as the same line
    under the defect's rule, or, where the defect follows from another error at its node (a
    misspelt or ill-typed coordinate), as that error."""
    refusal = _refusal(path)
    report = validate([path])
    if refusal is None:
        return None, report.errors
    src = load([path], resolve_imports=False).sources[0]
    defects = [d for d in survey(src).defects
               if d.message == refusal.message and src.line_of(*d.at) == refusal.line]
    assert defects, f"the survey misses what predicates refuses: {refusal}"
    defect = defects[0]
    found = [e for e in report.errors if (e.line, e.message, e.rule) == (refusal.line, refusal.message, defect.rule)]
    explained = [e for e in report.errors for n in defect.nodes if _explains(e, n)]
    assert found or explained, (str(refusal), [d.format() for d in report.errors])
    return refusal, report.errors


def _explains(error, node: object) -> bool:  # noqa: ANN001
    """Whether ``error`` is at ``node`` (a node, or (node, word): with the word in its message)."""
    node, word = node if isinstance(node, tuple) else (node, None)
    return node is not None and error.focus == ":" + str(node).rsplit("#", 1)[-1] and \
        (word is None or word in error.message.lower())


@pytest.mark.parametrize("case", sorted(TURTLE))
def test_a_defect_that_stops_predicates_is_an_error_of_validate(case: str, tmp_path: Path) -> None:
    edit, rule = TURTLE[case]
    path = tmp_path / "init.ttl"
    path.write_text(edit((SMALL_KIT / "init.ttl").read_text()))
    refusal, errors = _same_verdict(path)
    assert refusal is not None, case
    assert rule in {d.rule for d in errors}, [d.format() for d in errors]
    assert len({d.line for d in errors}) == len(errors), [d.format() for d in errors]  # one verdict a line


# --- NIST-shaped files ------------------------------------------------------------------------------

@pytest.mark.parametrize("path", NIST_SHAPED, ids=lambda p: p.name)
def test_nist_shaped_files_that_stop_predicates(path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """Holders placed with no shape (NIST's Init3, grasp, external-shape states,
    soapInstances.owl) and an SKU with an ExternalShape only: `predicates` stops with exit 2 at
    the first; `validate` has each as a `no-shape` error at its line (exit 1)."""
    assert len(NIST_SHAPED) == 2
    refusal, errors = _same_verdict(path)
    assert refusal is not None
    assert {d.rule for d in errors} == {"no-shape"} and len(errors) == 2
    assert main(["predicates", str(path)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [str(refusal)]
    assert main(["validate", str(path)]) == 1
    out = capsys.readouterr().out.splitlines()
    assert f"{refusal} [no-shape]" in out  # word for word, at the same line
    if "ExternalShape" in path.name:
        assert "(an ExternalShape is a model file kitkb does not read)" in refusal.message


@pytest.mark.skipif(not NIST_DIR.is_dir(), reason="NIST files not found")
def test_nist_soap_instances_holders() -> None:
    _, errors = _same_verdict(NIST_DIR / "soapInstances.owl")
    assert [d.focus for d in errors if d.rule == "no-shape"] == [":part_gripper_holder", ":tray_gripper_holder"]


# --- what db load and plan refuse ---------------------------------------------------------------------

def _command_error(argv: list[str], capsys: pytest.CaptureFixture[str]) -> str:
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    return err[0]


def test_a_name_too_long_for_the_world_model(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """`kitkb db load` refuses an individual's name longer than 760 characters: validate says
    so first, as `name-too-long` at the same line."""
    text = re.sub(r":part_a_1\b(?!_)", ":part_a_1" + "x" * 800, (SMALL_KIT / "init.ttl").read_text())
    path = tmp_path / "init.ttl"
    path.write_text(text)
    refusal = _command_error(["db", "load", str(path), "--db", str(tmp_path / "w.sqlite"), "-q"], capsys)
    assert main(["validate", str(path)]) == 1
    out = capsys.readouterr().out.splitlines()
    assert out == [f"{refusal} [name-too-long]", "1 file(s): 1 error"]


def test_two_individuals_plan_would_give_one_name(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """`kitkb plan` names objects by their local names, case aside: `Part_A_1` and `part_a_1`
    are one name, refused at the second; validate says so first, as `name-clash`."""
    path = tmp_path / "init.ttl"
    path.write_text(re.sub(r":part_a_2\b(?!_)", ":Part_A_1", (SMALL_KIT / "init.ttl").read_text()))
    refusal = _command_error(["plan", str(path), str(SMALL_KIT / "goal.ttl"), "-o", str(tmp_path / "p.txt")], capsys)
    assert main(["validate", str(path)]) == 1
    out = capsys.readouterr().out.splitlines()
    assert out == [f"{refusal} [name-clash]", "1 file(s): 1 error"]


def test_names_not_used_in_plans_may_meet(tmp_path: Path) -> None:
    """A point and a vector whose names differ only in case are no objects of a plan."""
    text = re.sub(r":part_a_1_x_axis\b", ":Part_A_1_Point", (SMALL_KIT / "init.ttl").read_text())
    path = tmp_path / "init.ttl"
    path.write_text(text)
    assert validate([path]).conforms


def test_validate_reads_names_and_limits_as_the_commands_do() -> None:
    from kb.planning.state import pddl_name as planning_name
    from kb.validation.rules import MAX_NAME, pddl_name
    from kb.world.rows import MAX_IRI

    assert MAX_NAME == MAX_IRI
    for iri in ("urn:x#part_a_1", "urn:x#Part-A.1", "urn:x/1st", "urn:x#é_part", "urn:x#", "urn:x#_x", "urn:x#a b"):
        assert pddl_name(iri) == planning_name(iri)


# --- what validate passes, the commands read -------------------------------------------------------

@pytest.mark.parametrize("path", sorted(p for d in scenario_dirs() for p in d.glob("*.ttl")) +
                         [DATA.parent / "thin" / "init.ttl", DATA.parent / "kit_design_fit" / "kittingInstancesGoal-a3b6c4.owl"],
                         ids=lambda p: f"{p.parent.name}/{p.name}")
def test_what_has_no_geometry_error_is_read_by_the_commands(path: Path) -> None:
    assert _refusal(path) is None
    assert not [d for d in validate([path]).errors if d.rule in ("no-shape", "reference-cycle", "missing-value",
                                                                 "unusable-number", "degenerate-pose", "unit",
                                                                 "unknown-reference")]


def test_the_survey_builds_the_builders_scene(tmp_path: Path) -> None:
    """Where nothing stops it, the survey's scene is the builder's, bit for bit (the geometry
    the plausibility check reads), in metres from a millimetre file too."""
    init, goal = write_scenario(tmp_path, parts=40, kits=2, seed=3)
    mm = tmp_path / "mm.ttl"
    from kb.scenario.variants import write_variant
    write_variant(init, mm, unit="millimeter", yaw=23.0)
    paths = [init, goal, mm, DATA.parent / "thin" / "init.ttl"] + ([NIST_DIR / "kittingInstancesInit1.owl"]
                                                                   if NIST_DIR.is_dir() else [])
    for path in paths:
        src = load([path], resolve_imports=False).sources[0]
        mine, theirs = survey(src).scene, Scene.from_sources([src])
        assert mine.names == theirs.names and mine.classes == theirs.classes, path
        for field in ("lo", "hi", "poses", "local_lo", "local_hi", "parents", "open_top"):
            assert np.array_equal(getattr(mine, field), getattr(theirs, field), equal_nan=True), (path, field)
        assert mine.units == theirs.units and mine.slots.keys() == theirs.slots.keys()
        assert all(np.array_equal(mine.slots[k], theirs.slots[k]) for k in mine.slots)
