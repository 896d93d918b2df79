"""Mutation suite: one realistic authoring mistake at a time in a real scenario file.

Each case edits the shipped small-kit initial state (found by pattern, so the suite follows
the file when it is regenerated), validates the mutated copy, and expects one diagnostic with
the given rule, focus, line and message text. The unmutated file must validate clean, so
every diagnostic comes from the mutation.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

import pytest

from kb.validation.validator import validate

from shared_data import NIST_DIR

ROOT = Path(__file__).resolve().parents[1]
BASE = ROOT / "ontologies" / "scenarios" / "small-kit" / "init.ttl"
NIST_INIT = NIST_DIR / "kittingInstancesInit1.owl"

pytestmark = pytest.mark.skipif(not BASE.exists(), reason="shipped scenario not present")


@dataclass
class Edit:
    """A mutated text, the 1-based line the mistake is on, and the subject it belongs to."""

    text: str
    line: int
    subject: str


def _subject_above(lines: list[str], i: int) -> str:
    """The subject (``:name``) of the Turtle statement that line ``i`` (0-based) belongs to."""
    for j in range(i, -1, -1):
        m = re.match(r"^(:[\w-]+)\s", lines[j])
        if m:
            return m.group(1)
    raise AssertionError(f"no subject above line {i + 1}")


def _edit_line(text: str, pattern: str, replace: Callable[[re.Match], str],
               where: Callable[[list[str], int], bool] = lambda ls, i: True) -> Edit:
    """Apply ``replace`` to the first line matching ``pattern`` (and ``where``)."""
    lines = text.splitlines()
    for i, line in enumerate(lines):
        m = re.search(pattern, line)
        if m and where(lines, i):
            lines[i] = line[: m.start()] + replace(m) + line[m.end():]
            return Edit("\n".join(lines) + "\n", i + 1, _subject_above(lines, i))
    raise AssertionError(f"pattern {pattern!r} not found in {BASE.name}")


def _in_block_of(suffix: str) -> Callable[[list[str], int], bool]:
    return lambda lines, i: _subject_above(lines, i).endswith(suffix)


def misspelled_property(t: str) -> Edit:
    return _edit_line(t, r"ktw:hasPoint_X\b", lambda m: "ktw:hasPoint_x")


def misspelled_reference(t: str) -> Edit:
    return _edit_line(t, r"(ktw:hasPartsVessel_Part\s+:part_a_)1\b", lambda m: m.group(1) + "l")


def missing_required(t: str) -> Edit:
    lines = t.splitlines()
    i = next(n for n, ln in enumerate(lines) if re.match(r"^\s+ktw:hasPart_SerialNumber ", ln))
    subject = _subject_above(lines, i)
    if lines[i].rstrip().endswith("."):  # last statement of the block: close the one above
        lines[i - 1] = re.sub(r";\s*$", ".", lines[i - 1])
    del lines[i]
    start = next(n for n, ln in enumerate(lines) if ln.startswith(subject + " "))
    return Edit("\n".join(lines) + "\n", start + 1, subject)


def wrong_datatype(t: str) -> Edit:
    return _edit_line(t, r"(ktw:hasPoint_Y )[-0-9.]+", lambda m: m.group(1) + '"abc"')


def unit_outside_enumeration(t: str) -> Edit:
    return _edit_line(t, r'(ktw:hasKittingWorkstation_LengthUnit )"meter"', lambda m: m.group(1) + '"furlong"')


def second_functional_value(t: str) -> Edit:
    return _edit_line(t, r"(ktw:hasPoint_Z )([-0-9.]+)", lambda m: m.group(1) + m.group(2) + ", 7.5")


def non_unit_axis(t: str) -> Edit:
    e = _edit_line(t, r"(ktw:hasVector_I )1\.0\b", lambda m: m.group(1) + "2.0", _in_block_of("_x_axis"))
    # a rule about the whole vector points at the vector's first line
    start = next(n for n, ln in enumerate(e.text.splitlines()) if ln.startswith(e.subject + " "))
    return Edit(e.text, start + 1, e.subject)


def data_declares_class(t: str) -> Edit:
    lines = t.splitlines() + [":Widget a owl:Class ."]
    return Edit("\n".join(lines) + "\n", len(lines), ":Widget")


def misspelled_class(t: str) -> Edit:
    return _edit_line(t, r"ktw:Point\b", lambda m: "ktw:Pont", lambda ls, i: ls[i].startswith(":"))


def wrong_class_reference(t: str) -> Edit:
    # the pose of an object points at a Point individual instead of a location
    return _edit_line(t, r"(ktw:hasSolidObject_PrimaryLocation :)([\w]+)_pose\b",
                      lambda m: m.group(1) + m.group(2) + "_point",
                      lambda ls, i: _subject_above(ls, i) != ":kitting_workstation_1")


def wrong_part_quantity(t: str) -> Edit:
    # reported at the statement that carries the wrong quantity, not at the tray's first line
    return _edit_line(t, r'(ktw:hasPartsVessel_PartQuantity ")(\d+)"', lambda m: f'{m.group(1)}{int(m.group(2)) + 1}"')


#: (name, mutation, rule, message text expected, where the line is)
CASES = [
    ("misspelled property", misspelled_property, "unknown-property",
     "unknown property ktw:hasPoint_x on {subject}, did you mean ktw:hasPoint_X?"),
    ("misspelled individual reference", misspelled_reference, "unknown-individual",
     "unknown individual :part_a_l (object of ktw:hasPartsVessel_Part on {subject}), did you mean :part_a_1?"),
    ("missing required attribute", missing_required, "min-count",
     "{subject} lacks ktw:hasPart_SerialNumber"),
    ("wrong datatype", wrong_datatype, "datatype",
     'ktw:hasPoint_Y of {subject} is "abc", expected xsd:decimal'),
    ("unit outside its enumeration", unit_outside_enumeration, "enumeration",
     'ktw:hasKittingWorkstation_LengthUnit of {subject} is "furlong", expected one of meter, millimeter, inch'),
    ("second value of a functional property", second_functional_value, "max-count",
     "{subject} has 2 values of ktw:hasPoint_Z, at most 1 allowed"),
    ("non-unit axis vector", non_unit_axis, "axis-unit-length",
     "axis vector {subject} is not of unit length (i²+j²+k² = 4.0)"),
    ("data file declaring a class", data_declares_class, "data-declares-term",
     "data file declares owl:Class {subject}"),
    ("misspelled class", misspelled_class, "unknown-class",
     "{subject} is typed ktw:Pont, which is not a declared class, did you mean ktw:Point?"),
    ("reference to an individual of the wrong class", wrong_class_reference, "class",
     "ktw:hasSolidObject_PrimaryLocation of {subject} is"),
    ("part quantity that does not match the parts listed", wrong_part_quantity, "part-quantity",
     "of {subject} differs from the number of parts it lists"),
]


def test_case_count() -> None:
    """The suite must not shrink silently."""
    assert len(CASES) == 11
    assert len({name for name, *_ in CASES}) == len(CASES)


def test_base_file_is_clean() -> None:
    report = validate([str(BASE)])
    assert report.diagnostics == [], [d.format() for d in report.diagnostics]


@pytest.mark.parametrize("name,mutate,rule,message", CASES, ids=[c[0] for c in CASES])
def test_mutation_is_caught(tmp_path: Path, name: str, mutate: Callable[[str], Edit], rule: str,
                            message: str) -> None:
    edit = mutate(BASE.read_text(encoding="utf-8"))
    target = tmp_path / "init.ttl"
    target.write_text(edit.text, encoding="utf-8")
    report = validate([str(target)])
    expected = message.format(subject=edit.subject)
    # one mistake, one line: no follow-on findings, never repeated by several shapes
    assert len(report.diagnostics) == 1, f"{name}:\n" + "\n".join(d.format() for d in report.diagnostics)
    (d,) = report.diagnostics
    assert d.rule == rule and expected in d.message, f"{name}: no [{rule}] '{expected}' in {d.format()}"
    assert d.focus == edit.subject
    assert d.line == edit.line, d.format()
    assert d.file == str(target)
    assert d.severity == "error"
    assert not report.conforms


@pytest.mark.skipif(not NIST_INIT.exists(), reason="NIST files not present")
def test_mutation_in_nist_functional_syntax(tmp_path: Path) -> None:
    """The same typo in a NIST OWL functional-syntax file, found at its line."""
    text = NIST_INIT.read_text(encoding="utf-8")
    lines = text.splitlines()
    i = next(n for n, ln in enumerate(lines) if "ktw:hasPoint_X" in ln)
    lines[i] = lines[i].replace("ktw:hasPoint_X", "ktw:hasPoint_x")
    target = tmp_path / NIST_INIT.name
    target.write_text("\n".join(lines) + "\n", encoding="utf-8")
    report = validate([str(target)])
    hits = [d for d in report.diagnostics if d.rule == "unknown-property"]
    assert len(hits) == 1, [d.format() for d in report.diagnostics]
    assert hits[0].line == i + 1
    assert "did you mean ktw:hasPoint_X?" in hits[0].message
    assert hits[0].focus.startswith(":")


@pytest.mark.slow
@pytest.mark.parametrize("name,mutate", [(c[0], c[1]) for c in CASES], ids=[c[0] for c in CASES])
def test_engines_agree_on_mutation(tmp_path: Path, monkeypatch: pytest.MonkeyPatch, name: str,
                                   mutate: Callable[[str], Edit]) -> None:
    """The fast SHACL engine reports what pySHACL reports on every mutated file."""
    target = tmp_path / "init.ttl"
    target.write_text(mutate(BASE.read_text(encoding="utf-8")).text, encoding="utf-8")
    found = {}
    for engine in ("pyshacl", "fast"):
        monkeypatch.setenv("KITKB_SHACL_ENGINE", engine)
        found[engine] = {(d.rule, d.focus, d.line, d.message) for d in validate([str(target)]).diagnostics}
    assert found["pyshacl"] == found["fast"]
