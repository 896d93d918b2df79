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
