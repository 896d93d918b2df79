"""A domain extension's classes of objects in ``kitkb validate`` (docs/validation.md, "A domain
extension's classes").

A domain file (one holding SOAP domain individuals, or importing the kitting domain) may declare a
class ``rdfs:subClassOf`` a class of the model: ``tests/data/extension/buffer/extension.ttl``
declares ``xp:BufferBox`` under ``ktw:LargeContainer``, names it as a parameter's and a predicate's
type, and its state files type their buffer box with it. The class joins the model for every file
of the validation (given as a FILE or with ``--domain``): the state files may use it, and the shapes
of its ancestors apply to its individuals. A state file still declares no class, a domain file
no class under nothing of the model, no property, and changes no model term.
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

from kb.cli import main
from kb.validation import validate

BUFFER = Path(__file__).parent / "data" / "extension" / "buffer"
EXT, INIT, GOAL = BUFFER / "extension.ttl", BUFFER / "init.ttl", BUFFER / "goal.ttl"


def _line(path: Path, pattern: str) -> int:
    """The 1-based line of ``path`` matching ``pattern`` (a regular expression), the first."""
    for n, text in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
        if re.search(pattern, text):
            return n
    raise AssertionError(f"{pattern!r} not in {path}")


def _found(report) -> list[tuple[str, int | None, str, str]]:  # noqa: ANN001
    return [(Path(d.file).name, d.line, d.rule, d.message) for d in report.diagnostics]


# --- the buffer extension validates ---------------------------------------------------------

def test_all_files_as_arguments(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["validate", str(EXT), str(INIT), str(GOAL)]) == 0
    assert capsys.readouterr().out.strip().splitlines()[-1] == "3 file(s): conforms"


def test_extension_with_domain_option(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["validate", "--domain", str(EXT), str(INIT), str(GOAL)]) == 0
    # the extension is validated too: three files
    assert capsys.readouterr().out.strip().splitlines()[-1] == "3 file(s): conforms"


def test_domain_option_json(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["validate", "--format", "json", "--domain", str(EXT), str(INIT)]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["conforms"] is True
    assert sorted(Path(f).name for f in out["files"]) == ["extension.ttl", "init.ttl"]


def test_state_file_alone_still_unknown_class() -> None:
    report = validate([str(INIT)])
    line = _line(INIT, r"^:buffer_box a .*xp:BufferBox")
    assert [(f, n, r) for f, n, r, _ in _found(report)] == [("init.ttl", line, "unknown-class")]
    assert "xp:BufferBox, which is not a declared class" in report.diagnostics[0].message


def test_extension_findings_at_their_lines(tmp_path: Path) -> None:
    """With --domain the extension is validated: a misspelt property of it at its line."""
    ext = tmp_path / "extension.ttl"
    ext.write_text(EXT.read_text(encoding="utf-8").replace(
        'soap:hasPredicate_Name "part-location-buffer"', 'soap:hasPredicate_Nme "part-location-buffer"'),
        encoding="utf-8")
    report = validate([str(INIT)], domain=[str(ext)])
    line = _line(ext, r"hasPredicate_Nme")
    assert ("extension.ttl", line, "unknown-property") in [(f, n, r) for f, n, r, _ in _found(report)]


# --- the ancestors' shapes apply to the new class's individuals -----------------------------

@pytest.mark.parametrize("domain", [True, False], ids=["--domain", "argument"])
def test_large_container_min_count_on_buffer_box(tmp_path: Path, domain: bool) -> None:
    """ktw:LargeContainer's own shape (one serial number) and SkuObject's (a SKU) target the
    buffer box through xp:BufferBox rdfs:subClassOf ktw:LargeContainer."""
    init = tmp_path / "init.ttl"
    text = INIT.read_text(encoding="utf-8")
    box = '    ktw:hasSkuObject_Sku :sku_buffer_box ;\n    ktw:hasLargeContainer_SerialNumber "bb_1"^^xsd:NMTOKEN .\n'
    assert box in text
    init.write_text(text.replace(box, "    ktw:hasSkuObject_Sku :sku_buffer_box .\n"), encoding="utf-8")
    report = validate([str(init)], domain=[str(EXT)]) if domain else validate([str(EXT), str(init)])
    line = _line(init, r"^:buffer_box a ")
    assert [(f, n, r) for f, n, r, _ in _found(report)] == [("init.ttl", line, "min-count")]
    assert ":buffer_box lacks ktw:hasLargeContainer_SerialNumber" in report.diagnostics[0].message


def test_sku_object_min_count_and_closed_on_buffer_box(tmp_path: Path) -> None:
    init = tmp_path / "init.ttl"
    text = INIT.read_text(encoding="utf-8")
    box = '    ktw:hasSkuObject_Sku :sku_buffer_box ;\n    ktw:hasLargeContainer_SerialNumber "bb_1"^^xsd:NMTOKEN .\n'
    init.write_text(text.replace(box, '    ktw:hasLargeContainer_SerialNumber "bb_1"^^xsd:NMTOKEN ;\n'
                                      '    ktw:hasKitTray_SerialNumber "kt_9"^^xsd:NMTOKEN .\n'), encoding="utf-8")
    report = validate([str(init)], domain=[str(EXT)])
    found = {(n, r, m) for _f, n, r, m in _found(report)}
    at = _line(init, r"^:buffer_box a ")
    assert (at, "min-count", ":buffer_box lacks ktw:hasSkuObject_Sku: at least 1 value(s) required "
                             "(an individual of ktw:StockKeepingUnit)") in found
    closed = [(n, m) for n, r, m in found if r == "closed"]
    assert closed == [(_line(init, r"hasKitTray_SerialNumber"), ":buffer_box may not have ktw:hasKitTray_SerialNumber: "
                       "not a property of ktw:LargeContainer (nor of its superclasses or subclasses)")]
    assert not report.conforms


def test_buffer_box_geometry(tmp_path: Path) -> None:
    """The geometry survey sees the buffer box as an object (a large container): lifted off
    its table it floats, at its pose's line."""
    init = tmp_path / "init.ttl"
    text = INIT.read_text(encoding="utf-8")
    point = ":buffer_box_point a owl:NamedIndividual, ktw:Point ;\n    ktw:hasPoint_X 0.7 ;\n    ktw:hasPoint_Y 0.0 ;\n" \
            "    ktw:hasPoint_Z 0.75 ."
    assert point in text
    init.write_text(text.replace(point, point.replace("0.75", "0.85")), encoding="utf-8")
    report = validate([str(init)], domain=[str(EXT)])
    assert [(f, n, r, m) for f, n, r, m in _found(report)] == [
        ("init.ttl", _line(init, r"^:buffer_box_pose a "), "floating-object",
         ":buffer_box floats 0.1 m above :parts_table_1")]
    assert report.conforms


# --- what is still refused ------------------------------------------------------------------

def _extended(tmp_path: Path, extra: str) -> Path:
    ext = tmp_path / "extension.ttl"
    ext.write_text(EXT.read_text(encoding="utf-8") + "\n" + extra, encoding="utf-8")
    return ext


def _declares(report, name: str = "extension.ttl") -> list[tuple[int | None, str]]:  # noqa: ANN001
    return [(n, m) for f, n, r, m in _found(report) if f == name and r == "data-declares-term"]


def test_state_file_may_not_declare_a_class(tmp_path: Path) -> None:
    """A state file (no SOAP individuals) declaring a class under the model's is refused, with
    the extension or without."""
    init = tmp_path / "init.ttl"
    init.write_text(INIT.read_text(encoding="utf-8") + "\nxp:SmallBox a owl:Class ;\n"
                    "    rdfs:subClassOf ktw:LargeContainer .\n", encoding="utf-8")
    report = validate([str(init)], domain=[str(EXT)])
    line = _line(init, r"^xp:SmallBox a owl:Class")
    assert _declares(report, "init.ttl") == [
        (line, "data file declares owl:Class xp:SmallBox: classes and properties belong in a model file"),
        (line + 1, "data file states xp:SmallBox rdfs:subClassOf ktw:LargeContainer: axioms belong in a model file")]
    assert _declares(report) == []


def test_domain_class_under_nothing_of_the_model(tmp_path: Path) -> None:
    ext = _extended(tmp_path, "xp:Gadget a owl:Class ;\n    rdfs:subClassOf xp:Widget .\n"
                              "xp:Lone a owl:Class ;\n    rdfs:label \"lone\"@en .\n"
                              "xp:Looped a owl:Class ;\n    rdfs:subClassOf xp:Looped2 .\n"
                              "xp:Looped2 a owl:Class ;\n    rdfs:subClassOf xp:Looped .\n"
                              "xp:p9 a owl:NamedIndividual , soap:Parameter ;\n    soap:hasParameter_Name \"g\" ;\n"
                              "    soap:hasParameter_Type xp:Gadget ;\n"
                              "    soap:hasParameter_Position \"1\"^^xsd:positiveInteger .\n")
    report = validate([str(INIT), str(GOAL)], domain=[str(ext)])
    rule = ("a domain file may declare only a class of objects rdfs:subClassOf a class of the model, directly "
            "or through another class it declares")
    assert _declares(report) == [
        (_line(ext, r"^xp:Gadget a"), "domain file declares owl:Class xp:Gadget under no class of the model "
         f"(rdfs:subClassOf xp:Widget: xp:Widget is neither a class of the model nor one a domain file declares): {rule}"),
        (_line(ext, r"^xp:Lone a"), "domain file declares owl:Class xp:Lone under no class of the model "
         f"(it has no named rdfs:subClassOf): {rule}"),
        (_line(ext, r"^xp:Looped a"), "domain file declares owl:Class xp:Looped under no class of the model "
         f"(rdfs:subClassOf xp:Looped2: xp:Looped2 is itself under no class of the model): {rule}"),
        (_line(ext, r"^xp:Looped2 a"), "domain file declares owl:Class xp:Looped2 under no class of the model "
         f"(rdfs:subClassOf xp:Looped: xp:Looped is itself under no class of the model): {rule}")]
    # one defect, one report: the refused class named as a type is not also an unknown individual
    assert [r for _f, _n, r, _m in _found(report)] == ["data-declares-term"] * 4
    # and the buffer box, under a class of the model, is still known to the states
    assert not any(f != "extension.ttl" for f, *_ in _found(report))
    # an ignored error stands for nothing: what follows from it comes back
    ignored = validate([str(INIT)], domain=[str(ext)], ignore={"data-declares-term"})
    assert [(n, r, m) for _f, n, r, m in _found(ignored)] == [
        (_line(ext, r"soap:hasParameter_Type xp:Gadget"), "unknown-individual",
         "unknown individual xp:Gadget (object of soap:hasParameter_Type on xp:p9)")]


def test_domain_class_through_another_it_declares(tmp_path: Path) -> None:
    ext = _extended(tmp_path, "xp:SmallBufferBox a owl:Class ;\n    rdfs:subClassOf xp:BufferBox ;\n"
                              "    rdfs:label \"small buffer box\"@en ;\n    rdfs:comment \"A smaller one.\"@en .\n")
    init = tmp_path / "init.ttl"
    init.write_text(INIT.read_text(encoding="utf-8").replace(":buffer_box a owl:NamedIndividual, xp:BufferBox",
                                                            ":buffer_box a owl:NamedIndividual, xp:SmallBufferBox"),
                    encoding="utf-8")
    report = validate([str(init)], domain=[str(ext)])
    assert _found(report) == []


def test_domain_file_may_not_change_a_model_term(tmp_path: Path) -> None:
    ext = _extended(tmp_path, "ktw:Part rdfs:subClassOf ktw:KitTray .\n")
    report = validate([str(INIT)], domain=[str(ext)])
    assert _declares(report) == [(_line(ext, r"^ktw:Part rdfs:subClassOf"),
                                  "data file changes ktw:Part rdfs:subClassOf ktw:KitTray: axioms belong in a model file")]


def test_domain_file_may_not_declare_a_property(tmp_path: Path) -> None:
    ext = _extended(tmp_path, "xp:hasBufferBox_Colour a owl:DatatypeProperty ;\n    rdfs:domain xp:BufferBox ;\n"
                              "    rdfs:range xsd:string .\n")
    report = validate([str(INIT)], domain=[str(ext)])
    line = _line(ext, r"^xp:hasBufferBox_Colour a")
    assert _declares(report) == [
        (line, "data file declares owl:DatatypeProperty xp:hasBufferBox_Colour: classes and properties belong "
               "in a model file"),
        (line + 1, "data file states xp:hasBufferBox_Colour rdfs:domain xp:BufferBox: axioms belong in a model file"),
        (line + 2, "data file states xp:hasBufferBox_Colour rdfs:range xsd:string: axioms belong in a model file")]


def test_domain_class_other_axioms(tmp_path: Path) -> None:
    ext = _extended(tmp_path, "xp:BufferBox owl:disjointWith ktw:KitTray .\n")
    report = validate([str(INIT)], domain=[str(ext)])
    assert _declares(report) == [
        (_line(ext, r"^xp:BufferBox owl:disjointWith"),
         "domain file states xp:BufferBox owl:disjointWith ktw:KitTray: a domain file's class of objects has only "
         "named superclasses (rdfs:subClassOf), rdfs:label and rdfs:comment; other axioms belong in a model file")]


def test_no_domain_unchanged(tmp_path: Path) -> None:
    """A file that declares a class under the model's but holds no SOAP individual and imports
    no domain is a state file: refused as before."""
    f = tmp_path / "state.ttl"
    f.write_text(INIT.read_text(encoding="utf-8") + "\nxp:BufferBox a owl:Class ;\n"
                 "    rdfs:subClassOf ktw:LargeContainer .\n", encoding="utf-8")
    report = validate([str(f)])
    assert sorted(r for _f, _n, r, _m in _found(report)) == ["data-declares-term", "data-declares-term",
                                                             "unknown-class"]
