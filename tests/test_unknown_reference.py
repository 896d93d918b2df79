"""A location's reference object that the state does not place is refused, never read as the
world frame (issue 26, points 2 and 5).

A pose is given in the frame of its location's ``hasPhysicalLocation_RefObject``. Before, a
reference object that was no object the state places (a misspelt name, an individual of another
file, a SKU, a tray located by a relative location with no point) was taken for the world frame:
the pose was read as global and the parts of a tray lay at the origin, in or out of whatever is
there. Now the commands stop at the location's statement of its reference (exit 2, one line:
the location, the reference, why), and ``kitkb validate`` reports the same defect at the same
line as an ``unknown-reference`` error, or, where another error already says it (a misspelt
name is an ``unknown-individual``, a SKU a ``class`` error), that error. What worked reads as
before: the workstation whose location refers to itself (NIST's), a workstation with no
location, objects with no pose (NIST's relative locations).

NIST-shaped files: tests/data/unknown_reference, made from NIST's first state by
make_unknown_reference.py; kitkb's Turtle: the small kit, edited here.
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pytest

from kb.cli import main
from kb.core.errors import InputError
from kb.core.resources import scenario_dirs
from kb.io.loader import load
from kb.spatial.scene import Scene
from kb.spatial.survey import UNKNOWN_REFERENCE, survey
from kb.validation import validate
from tests.shared_data import NIST_DIR
from tests.test_one_verdict import _refusal, _same_verdict

DATA = Path(__file__).parent / "data" / "unknown_reference"
SMALL_KIT = next(d for d in scenario_dirs() if d.name == "small-kit")


def _ref(obj: str, ref: str):  # noqa: ANN202
    """An edit of the small kit: ``obj``'s pose refers to ``ref``."""
    def edit(text: str) -> str:
        out, n = re.subn(rf"(:{obj}_pose a .*?ktw:hasPhysicalLocation_RefObject) :\w+", rf"\g<1> :{ref}", text,
                         count=1, flags=re.S)
        assert n == 1
        return out
    return edit


def _relative_tray(text: str) -> str:
    """part_a_tray located on the parts table by a RelativeLocationOn (no point), as NIST's
    InitNoLoc locates its parts; its parts keep their poses in its frame."""
    out, n = re.subn(r"(:part_a_tray_pose a owl:NamedIndividual, ktw:)PoseLocationOn ;(\s*ktw:hasPhysicalLocation_RefObject"
                     r" :\w+) ;.*?\.\n", r'\1RelativeLocationOn ;\2 ;\n    ktw:hasRelativeLocation_Description '
                     r'"on the parts table" .\n', text, count=1, flags=re.S)
    assert n == 1
    return out


def _no_location(obj: str):  # noqa: ANN202
    def edit(text: str) -> str:
        out, n = re.subn(rf"(:{obj} a .*?)ktw:hasSolidObject_PrimaryLocation :\w+ ;\s*", r"\1", text, count=1,
                         flags=re.S)
        assert n == 1
        return out
    return edit


def _write(tmp_path: Path, edit) -> Path:  # noqa: ANN001
    path = tmp_path / "init.ttl"
    path.write_text(edit((SMALL_KIT / "init.ttl").read_text()))
    return path


def _line_of_reference(path: Path, location: str) -> int:
    """The line of ``location``'s hasPhysicalLocation_RefObject statement (Turtle)."""
    lines = path.read_text().splitlines()
    start = next(n for n, t in enumerate(lines) if t.startswith(f":{location} a "))
    return next(n for n in range(start, len(lines)) if "hasPhysicalLocation_RefObject" in lines[n]) + 1


#: an edit of the small kit -> (the command's message after "file:line: error: ", the rule validate reports)
CASES = {
    "a misspelt reference": (
        _ref("part_a_1", "part_a_tary"),
        "part_a_1_pose: its reference object part_a_tary is not an object of the state: none of its files declares it "
        "with a class of the kitting model (a misspelt name, or an individual of another file)", "unknown-individual"),
    "a SKU as reference": (
        _ref("part_a_1", "sku_part_a"),
        "part_a_1_pose: its reference object sku_part_a is not a solid object: it is a StockKeepingUnit", "class"),
    "a point as reference": (
        _ref("part_a_1", "part_a_2_point"),
        "part_a_1_pose: its reference object part_a_2_point is not a solid object: it is a Point", "class"),
    "a tray with no location": (
        _no_location("part_a_tray"),
        "part_a_1_pose: its reference object part_a_tray is not placed by the state: it has no location", "min-count"),
    "a tray located by a relative location": (
        _relative_tray,
        "part_a_1_pose: its reference object part_a_tray is not placed by the state: its location part_a_tray_pose "
        "has no point", UNKNOWN_REFERENCE),
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_the_commands_refuse_a_reference_the_state_does_not_place(case: str, tmp_path: Path,
                                                                   capsys: pytest.CaptureFixture[str]) -> None:
    edit, message, rule = CASES[case]
    path = _write(tmp_path, edit)
    line = _line_of_reference(path, "part_a_1_pose")
    assert main(["predicates", str(path)]) == 2
    assert capsys.readouterr().err.strip().splitlines() == [f"{path}:{line}: error: {message}"]
    refusal, errors = _same_verdict(path)  # validate has it: as this error, or another that says why
    assert refusal is not None and refusal.line == line
    assert rule in {e.rule for e in errors}, [e.format() for e in errors]
    assert len({e.line for e in errors}) == len(errors), [e.format() for e in errors]  # one verdict a line


def test_validate_reports_each_location_that_has_no_frame(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """The tray located by a relative location: each of its four parts' poses is an
    ``unknown-reference`` error at its line (nothing else says it: a relative location has no
    point by right), exit 1; the JSON report names the rule."""
    path = _write(tmp_path, _relative_tray)
    assert main(["validate", str(path)]) == 1
    out = capsys.readouterr().out.splitlines()
    parts = [f"part_a_{k}" for k in range(1, 5)]
    assert out == [f"{path}:{_line_of_reference(path, p + '_pose')}: error: {p}_pose: its reference object part_a_tray "
                   f"is not placed by the state: its location part_a_tray_pose has no point [unknown-reference]"
                   for p in parts] + ["1 file(s): 4 errors"]
    assert main(["validate", "--format", "json", str(path)]) == 1
    got = json.loads(capsys.readouterr().out)
    assert {d["rule"] for d in got["diagnostics"]} == {UNKNOWN_REFERENCE}


def test_an_individual_of_the_goal_is_no_frame_of_the_initial_state(tmp_path: Path,
                                                                     capsys: pytest.CaptureFixture[str]) -> None:
    """kit_1 first appears in the goal: a pose of the initial state in its frame is refused by
    `predicates --goal` (the goal's individuals have no geometry in the initial state), and
    validate says so (a class error: nothing in the initial state makes kit_1 a solid object)."""
    init = _write(tmp_path, _ref("part_a_1", "kit_1"))
    goal = SMALL_KIT / "goal.ttl"
    line = _line_of_reference(init, "part_a_1_pose")
    assert main(["predicates", str(init), "--goal", str(goal)]) == 2
    assert capsys.readouterr().err.strip() == (
        f"{init}:{line}: error: part_a_1_pose: its reference object kit_1 is not an object of the state: none of its "
        "files declares it with a class of the kitting model (a misspelt name, or an individual of another file)")
    report = validate([init, goal])
    assert [(e.line, e.rule) for e in report.errors] == [(line, "class")]


# --- NIST-shaped files -----------------------------------------------------------------------------

def test_nist_tray_located_by_a_relative_location(capsys: pytest.CaptureFixture[str]) -> None:
    path = DATA / "kittingInstancesRelativeTray.owl"
    refusal, errors = _same_verdict(path)
    assert refusal is not None and str(refusal).endswith(
        "error: part_a_1_pose: its reference object part_a_tray is not placed by the state: its location "
        "part_a_tray_location has no point")
    assert [(e.rule, e.focus) for e in errors] == [(UNKNOWN_REFERENCE, ":part_a_1_pose"),
                                                   (UNKNOWN_REFERENCE, ":part_a_2_pose")]
    assert "ObjectPropertyAssertion(ktw:hasPhysicalLocation_RefObject" in \
        path.read_text().splitlines()[refusal.line - 1]  # the statement of the reference
    assert main(["validate", str(path)]) == 1
    assert f"{refusal} [unknown-reference]" in capsys.readouterr().out.splitlines()


def test_nist_misspelt_reference(capsys: pytest.CaptureFixture[str]) -> None:
    path = DATA / "kittingInstancesMisspelt.owl"
    refusal, errors = _same_verdict(path)
    assert refusal is not None and "its reference object part_b_tary is not an object of the state" in refusal.message
    assert [(e.line, e.rule) for e in errors] == [(refusal.line, "unknown-individual")]
    assert "did you mean :part_b_tray?" in errors[0].message


@pytest.mark.parametrize("ref, words", [
    ("part_b_tary", "unknown individual part_b_tary (object of hasPhysicalLocation_RefObject on part_b_1_pose)"),
    ("stock_keeping_unit_part_b", "hasPhysicalLocation_RefObject of part_b_1_pose is stock_keeping_unit_part_b (it is "
                                  "StockKeepingUnit), not an individual of the property's range"),
])
def test_db_load_names_the_reference_the_model_requires_at_its_statement(ref: str, words: str, tmp_path: Path,
                                                                          capsys: pytest.CaptureFixture[str]) -> None:
    """A required object value that is no individual of its range is refused by db load at the
    statement that gives it, saying so (not "has no value", at the subject's declaration)."""
    text = (DATA / "kittingInstancesMisspelt.owl").read_text().replace(":part_b_tary)", f":{ref})")
    path = tmp_path / "state.owl"
    path.write_text(text)
    line = text[:text.index(f":part_b_1_pose :{ref})")].count("\n")  # the statement's first line, before it
    assert main(["db", "load", str(path), "--db", str(tmp_path / "w.sqlite")]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith(f"{path}:{line}: error: {words}"), err
    assert not (tmp_path / "w.sqlite").exists() or main(["db", "dump", "--db", str(tmp_path / "w.sqlite"),
                                                         "-o", str(tmp_path / "d.ttl")]) != 0


def test_nist_parts_with_relative_locations_are_read_as_before() -> None:
    """Parts located by a relative location in their tray (NIST's InitNoLoc): not placed,
    nothing refers to them; the state is read and conforms."""
    path = DATA / "kittingInstancesRelativeParts.owl"
    scene = Scene.from_files([path])
    placed = {n.rsplit("#", 1)[-1] for i, n in enumerate(scene.names) if scene.placed[i]}
    assert "part_a_tray" in placed and not {"part_a_1", "part_a_2"} & placed
    assert validate([path]).conforms


def test_the_data_files_are_the_makers(tmp_path: Path) -> None:
    if not NIST_DIR.is_dir():
        pytest.skip("NIST files not found")
    import importlib.util
    spec = importlib.util.spec_from_file_location("make_unknown_reference", DATA / "make_unknown_reference.py")
    maker = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(maker)
    maker.main(str(NIST_DIR), str(tmp_path))
    for made in sorted(tmp_path.glob("*.owl")):
        assert made.read_text() == (DATA / made.name).read_text(), made.name
    assert len(list(tmp_path.glob("*.owl"))) == 3


# --- what worked reads as before -------------------------------------------------------------------

def test_a_workstation_with_no_location_is_the_world_frame(tmp_path: Path) -> None:
    """The workstation is the world frame whether its location refers to itself (NIST's and
    kitkb's files) or it has none (validate then says it lacks one, as before)."""
    path = _write(tmp_path, _no_location("kitting_workstation_1"))
    assert _refusal(path) is None
    mine, shipped = Scene.from_files([path]), Scene.from_files([SMALL_KIT / "init.ttl"])
    assert mine.names == shipped.names and np.array_equal(mine.lo, shipped.lo, equal_nan=True)
    assert [e.rule for e in validate([path]).errors] == ["min-count"]


STATES = sorted(p for d in scenario_dirs() for p in d.glob("*.ttl")) + sorted(
    p for d in ("thin", "one_verdict", "kit_design_fit", "foreign/nist2012") for p in (DATA.parent / d).glob("*.*")
    if p.suffix in (".ttl", ".owl")) + (sorted(NIST_DIR.glob("kittingInstances*.owl")) if NIST_DIR.is_dir() else [])


@pytest.mark.parametrize("path", STATES, ids=lambda p: f"{p.parent.name}/{p.name}")
def test_no_state_file_of_ours_or_nists_refers_to_what_it_does_not_place(path: Path) -> None:
    refusal = _refusal(path)
    assert refusal is None or "its reference object" not in refusal.message
    src = load([path], resolve_imports=False).sources[0]
    assert not [d for d in survey(src).defects if d.rule == UNKNOWN_REFERENCE]


def test_the_builder_and_the_survey_agree_on_every_reference(tmp_path: Path) -> None:
    """Every reference of the small kit made each kind of wrong in turn: the survey lists the
    builder's refusal, word for word at its line, and one defect per location."""
    for case, (edit, _message, _rule) in CASES.items():
        path = _write(tmp_path, edit)
        with pytest.raises(InputError) as got:
            Scene.from_files([path])
        src = load([path], resolve_imports=False).sources[0]
        mine = [d for d in survey(src).defects if d.rule == UNKNOWN_REFERENCE]
        assert [(src.line_of(*d.at), d.message) for d in mine][:1] == [(got.value.line, got.value.message)], case
        assert len({d.node for d in mine}) == len(mine)


def test_an_ignored_error_does_not_hide_what_follows_from_it() -> None:
    """validate --ignore unknown-individual: the misspelt reference is still reported, as the
    unknown-reference that predicates refuses (an ignored rule stands for nothing)."""
    path = DATA / "kittingInstancesMisspelt.owl"
    report = validate([path], ignore={"unknown-individual"})
    assert not report.conforms
    assert [(d.rule, d.line) for d in report.diagnostics if d.severity == "error"] == [("unknown-reference", 1386)]
    assert "unknown-reference" not in {d.rule for d in validate([path]).diagnostics}
