"""``--domain FILE...``: extension files added to the shipped kitting domain, read by the one
mechanism that reads kitkb's own domain (kb.io.loader.domain_knowledge), on every command that
reads the domain; errors in an extension at its file:line, exit 2."""

from __future__ import annotations

from pathlib import Path

import pytest

from kb.cli import build_parser, main
from kb.core.errors import InputError
from kb.core.resources import ontology_path
from kb.execution.inputs import DomainInputs
from kb.io.loader import domain_knowledge, domain_paths
from kb.model.definitions import load_definitions

SHIPPED = ontology_path("kitting-domain.ttl")
SMALL = SHIPPED.parent / "scenarios" / "small-kit"

HEAD = """@prefix kd: <https://w3id.org/kitkb/kitting-domain#> .
@prefix soap: <https://w3id.org/kitkb/soap#> .
@prefix ktw: <https://w3id.org/kitkb/kitting#> .
@prefix owl: <http://www.w3.org/2002/07/owl#> .
@prefix x: <https://example.org/ext#> .

<https://example.org/ext> a owl:Ontology ; owl:imports <https://w3id.org/kitkb/kitting-domain> .
"""

#: a predicate defined only here: a part partly in a parts tray, by one RCC8-derived relation
PART_IN_TRAY = HEAD + """
x:part-in-tray a owl:NamedIndividual , soap:Predicate ;
    soap:hasPredicate_Name "part-in-tray" ;
    soap:hasPredicate_ReferenceType ktw:Part ;
    soap:hasPredicate_TargetType ktw:PartsTray ;
    soap:hasPredicate_Definition x:part-in-tray_f1 .
x:part-in-tray_f1 a owl:NamedIndividual , soap:RelationAtom ;
    soap:hasRelationAtom_Relation soap:Partially-In ;
    soap:hasRelationAtom_Subject soap:Reference ;
    soap:hasRelationAtom_Object soap:Target ;
    soap:hasAtom_IsNegated false .
"""


def _write(tmp_path: Path, text: str, name: str = "ext.ttl") -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


def _line(path: Path, needle: str) -> int:
    return next(i for i, line in enumerate(path.read_text().splitlines(), 1) if needle in line)


def test_the_shipped_domain_is_the_first_entry_and_an_extension_adds_to_it(tmp_path: Path) -> None:
    ext = _write(tmp_path, PART_IN_TRAY)
    assert domain_paths() == [SHIPPED]
    assert [p.resolve() for p in domain_paths([ext])] == [SHIPPED.resolve(), ext.resolve()]
    defs = load_definitions([ext])
    shipped = load_definitions()
    assert set(defs.predicates) == set(shipped.predicates) | {"part-in-tray"}
    inputs = DomainInputs([ext])
    assert [p.resolve() for p in inputs.files] == [SHIPPED.resolve(), ext.resolve()]
    assert {a.name for a in inputs.domain.actions} == {a.name for a in DomainInputs().domain.actions}


def test_a_modified_copy_of_the_shipped_domain_takes_its_place(tmp_path: Path) -> None:
    text = SHIPPED.read_text()
    old = 'soap:hasPredicate_Name "worktable-empty" ;'
    assert text.count(old) == 1
    copy = _write(tmp_path, text.replace(old, 'soap:hasPredicate_Name "table-is-bare" ;'), "kitting-domain.ttl")
    kb = domain_knowledge([copy])
    assert SHIPPED.resolve() not in {s.path.resolve() for s in kb.sources}
    names = set(load_definitions([copy]).predicates)
    assert "table-is-bare" in names and "worktable-empty" not in names


@pytest.mark.parametrize("old, new, needle, message", [
    ("soap:hasPredicate_Definition x:part-in-tray_f1", "soap:hasPredicate_Defintion x:part-in-tray_f1",
     "hasPredicate_Defintion", "unknown property soap:hasPredicate_Defintion"),
    ("soap:Partially-In ;", "soap:Partialy-In ;", "Partialy-In", "unknown term soap:Partialy-In"),
    ("soap:hasPredicate_ReferenceType ktw:Part ;", "soap:hasPredicate_ReferenceType ktw:Prat ;", "ktw:Prat",
     "unknown term ktw:Prat"),
])
def test_an_unknown_term_in_an_extension_is_an_error_at_its_line(tmp_path: Path, capsys, old: str, new: str,
                                                                 needle: str, message: str) -> None:
    ext = _write(tmp_path, PART_IN_TRAY.replace(old, new))
    with pytest.raises(InputError) as err:
        domain_knowledge([ext])
    assert (err.value.file, err.value.line) == (str(ext), _line(ext, needle))
    assert err.value.message.startswith(message)
    for argv in (["generate", "pddl", str(SMALL / "init.ttl"), str(SMALL / "goal.ttl"), "-o", str(tmp_path / "p")],
                 ["predicates", str(SMALL / "init.ttl")]):
        assert main([*argv, "--domain", str(ext)]) == 2
        err_text = capsys.readouterr().err
        assert err_text.startswith(f"{ext}:{_line(ext, needle)}: error: {message}")
        assert len(err_text.splitlines()) == 1
    assert not (tmp_path / "p").exists()


def test_a_syntax_error_in_an_extension_is_exit_2_at_its_line(tmp_path: Path, capsys) -> None:
    ext = _write(tmp_path, PART_IN_TRAY + "x:a x:b .\nx:c x:d\n")
    out = tmp_path / "plan.txt"
    assert main(["plan", str(SMALL / "init.ttl"), str(SMALL / "goal.ttl"), "-o", str(out), "--domain", str(ext)]) == 2
    assert capsys.readouterr().err.startswith(f"{ext}:")
    assert not out.exists()


def test_a_reference_to_an_undefined_action_is_an_error(tmp_path: Path) -> None:
    ext = _write(tmp_path, HEAD + """
x:slip a owl:NamedIndividual , soap:FailureMode ;
    soap:hasFailureMode_Name "slip" ;
    soap:hasFailureMode_Action kd:take-the-part .
""")
    with pytest.raises(InputError) as err:
        domain_knowledge([ext])
    assert (err.value.file, err.value.line) == (str(ext), _line(ext, "kd:take-the-part"))


def test_every_command_that_reads_the_domain_takes_domain() -> None:
    parser = build_parser()
    for argv in (["generate", "pddl", "I", "G", "-o", "D"], ["plan", "I", "G", "-o", "P"], ["predicates", "S"],
                 ["run", "I", "G"], ["testmethod", "basic"]):
        args = parser.parse_args([*argv, "--domain", "a.ttl", "--domain", "b.ttl"])
        assert args.domain == ["a.ttl", "b.ttl"], argv


def test_pddl_files_take_no_domain_extension(tmp_path: Path, capsys) -> None:
    ext = _write(tmp_path, PART_IN_TRAY)
    d, p = _write(tmp_path, "(define (domain d))", "d.pddl"), _write(tmp_path, "(define (problem p))", "p.pddl")
    assert main(["plan", str(d), str(p), "-o", str(tmp_path / "plan.txt"), "--domain", str(ext)]) == 2
    assert "--domain extends the ontology's domain" in capsys.readouterr().err


#: the extension's predicate made a precondition of take-part (so the planning domain uses it)
USED = PART_IN_TRAY + """
x:take-part_pre_part-in-tray a owl:NamedIndividual , soap:PredicateAtom ;
    soap:hasPredicateAtom_Predicate x:part-in-tray ;
    soap:hasPredicateAtom_ReferenceParameter kd:take-part_part ;
    soap:hasPredicateAtom_TargetParameter kd:take-part_partstray ;
    soap:hasAtom_IsNegated false .
kd:take-part_pre soap:hasPrecondition_PredicateAtom x:take-part_pre_part-in-tray .
"""


def test_a_predicate_defined_only_in_an_extension_is_in_the_initial_state(tmp_path: Path) -> None:
    from kb.planning.model import read_specs
    ext = _write(tmp_path, USED)
    _domain, spec = read_specs([SMALL / "init.ttl"], [SMALL / "goal.ttl"], "numeric", domain_files=[ext])
    got = sorted(f for f in spec.facts if f[0] == "part-in-tray")
    parts = sorted(f[1:] for f in spec.facts if f[0] == "part-location-partstray")
    assert [f[1:] for f in got] == parts and len(parts) == 7
    _domain, shipped = read_specs([SMALL / "init.ttl"], [SMALL / "goal.ttl"], "numeric")
    assert spec.facts - shipped.facts == set(got)


def test_a_broken_definition_of_an_extension_predicate_is_exit_2_at_its_line(tmp_path: Path, capsys) -> None:
    ext = _write(tmp_path, USED.replace("    soap:hasRelationAtom_Object soap:Target ;\n", ""))
    out = tmp_path / "pddl"
    assert main(["generate", "pddl", str(SMALL / "init.ttl"), str(SMALL / "goal.ttl"), "-o", str(out),
                 "--domain", str(ext)]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"{ext}:{_line(ext, 'x:part-in-tray_f1 a owl:NamedIndividual')}: error: predicate part-in-tray")
    assert not out.exists()
