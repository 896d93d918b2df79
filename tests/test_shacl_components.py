"""A constraint ignored is not "conforms" (issue 26, point 12).

A SPARQL-based constraint component typed with a class two ``rdfs:subClassOf`` steps below
``sh:ConstraintComponent`` is a SHACL instance of it (``rdf:type/rdfs:subClassOf*``); pySHACL,
to which kitkb handed it, ignored it and ``kitkb shacl`` said "conforms". kitkb now evaluates
SPARQL-based components itself (SELECT and ASK validators, node and property shapes, optional
parameters), and refuses at ``file:line`` (exit 2) what would otherwise be skipped: a component
without a validator for the shape's kind, a validator that is not SPARQL, a parameter of a node
that is no component, a ``sh:`` term that is no SHACL term or one of the advanced features,
a SPARQL constraint without sh:select, a malformed list, path, count, pattern or node kind, a
property shape without sh:path, a literal target.
"""

from __future__ import annotations

import logging
from pathlib import Path

import pytest
from rdflib import Graph, Literal, URIRef

from kb.cli import main
from kb.core.errors import InputError
from kb.core.namespaces import SH
from kb.shacl import unsupported_shapes, validate_graph
from kb.validation import validate
from kb.validation.plain import validate_files

PRE = """@prefix sh: <http://www.w3.org/ns/shacl#> .
@prefix rdfs: <http://www.w3.org/2000/01/rdf-schema#> .
@prefix xsd: <http://www.w3.org/2001/XMLSchema#> .
@prefix ex: <http://example.org/ex#> .
"""
EX = "http://example.org/ex#"

#: The component of the issue: its type two rdfs:subClassOf steps below sh:ConstraintComponent.
MAX_LENGTH = """
ex:Sub rdfs:subClassOf sh:ConstraintComponent .
ex:SubSub rdfs:subClassOf ex:Sub .
ex:MaxLength a ex:SubSub ;
    sh:parameter [ sh:path ex:maxLength ] ;
    sh:propertyValidator [ a sh:SPARQLSelectValidator ;
        sh:message "longer than {$maxLength} characters" ;
        sh:select \"\"\"SELECT $this ?value WHERE { $this $PATH ?value .
                                                    FILTER (STRLEN(STR(?value)) > $maxLength) }\"\"\" ] .
"""
PERSON = """
ex:PersonShape a sh:NodeShape ;
    sh:targetClass ex:Person ;
    sh:property [ sh:path ex:name ; ex:maxLength 4 ] .
"""
DATA = PRE + """
ex:bob a ex:Person ;
    ex:name "Robert" .
ex:ann a ex:Person ;
    ex:name "Ann" .
"""


def _files(tmp_path: Path, shapes: str, data: str = DATA) -> tuple[Path, Path]:
    (tmp_path / "data.ttl").write_text(data, encoding="utf-8")
    (tmp_path / "shapes.ttl").write_text(PRE + shapes, encoding="utf-8")
    return tmp_path / "data.ttl", tmp_path / "shapes.ttl"


def _rows(report) -> set[tuple[str, str, str, str]]:
    return {(str(p.result.focus).removeprefix(EX), str(p.result.component).removeprefix(EX),
             str(p.result.value), p.result.message) for p in report.results}


@pytest.mark.parametrize("steps", [0, 1, 2, 3])
def test_component_any_number_of_subclass_steps_down(tmp_path: Path, steps: int,
                                                     capsys: pytest.CaptureFixture[str]) -> None:
    chain = ["sh:ConstraintComponent"] + [f"ex:Kind{i}" for i in range(steps)]
    types = "".join(f"{chain[i + 1]} rdfs:subClassOf {chain[i]} .\n" for i in range(steps))
    shapes = MAX_LENGTH.replace("ex:Sub rdfs:subClassOf sh:ConstraintComponent .\n", "") \
        .replace("ex:SubSub rdfs:subClassOf ex:Sub .\n", types).replace("a ex:SubSub", f"a {chain[-1]}")
    data, shapes_file = _files(tmp_path, shapes + PERSON)
    report = validate_files([data], [shapes_file])
    assert _rows(report) == {("bob", "MaxLength", "Robert", "longer than 4 characters")}
    assert report.fallback == {}, "evaluated by kitkb's engine, not handed to pySHACL"
    assert main(["shacl", str(data), "-s", str(shapes_file)]) == 1
    assert "conforms" not in capsys.readouterr().out.replace("does not conform", "")


def test_the_issue_case_is_not_conforms(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    data, shapes = _files(tmp_path, MAX_LENGTH + PERSON)
    assert main(["shacl", str(data), "-s", str(shapes)]) == 1
    out = capsys.readouterr().out
    line = DATA.splitlines().index('    ex:name "Robert" .') + 1
    assert f'{data}:{line}: error: ex:bob ex:name = "Robert": longer than 4 characters [MaxLength]' in out


ASK_COMPONENT = """
ex:Kind rdfs:subClassOf ex:Kind0 . ex:Kind0 rdfs:subClassOf sh:ConstraintComponent .
ex:Prefix a ex:Kind ;
    sh:parameter [ sh:path ex:prefix ] ;
    sh:parameter [ sh:path ex:caseless ; sh:optional true ] ;
    sh:validator [ a sh:SPARQLAskValidator ;
        sh:message "{$value} does not start with {$prefix}" ;
        sh:ask \"\"\"ASK { FILTER (IF(COALESCE(?caseless, false), STRSTARTS(LCASE(STR($value)), LCASE($prefix)),
                                   STRSTARTS(STR($value), $prefix))) }\"\"\" ] .
"""


def test_ask_validator_on_property_and_node_shapes(tmp_path: Path) -> None:
    shapes = ASK_COMPONENT + """
ex:Names a sh:NodeShape ; sh:targetClass ex:Person ; sh:property [ sh:path ex:name ; ex:prefix "R" ] .
ex:Caseless a sh:NodeShape ; sh:targetClass ex:Person ;
    sh:property [ sh:path ex:name ; ex:prefix "a" ; ex:caseless true ] .
ex:Iris a sh:NodeShape ; sh:targetNode ex:bob , ex:ann ; ex:prefix "http://example.org/ex#b" .
"""
    report = validate_files(*[[f] for f in _files(tmp_path, shapes)])
    assert _rows(report) == {
        ("ann", "Prefix", "Ann", "Ann does not start with R"),        # property shape, case matters
        ("bob", "Prefix", "Robert", "Robert does not start with a"),  # the optional parameter given
        ("ann", "Prefix", EX + "ann", f"{EX}ann does not start with http://example.org/ex#b"),  # node shape
    }
    assert report.fallback == {}


def test_select_node_validator_and_several_parameter_values(tmp_path: Path) -> None:
    shapes = """
ex:Needs a ex:Kind . ex:Kind rdfs:subClassOf ex:Kind1 . ex:Kind1 rdfs:subClassOf sh:ConstraintComponent .
ex:Needs sh:parameter [ sh:path ex:needs ] ;
    sh:nodeValidator [ sh:message "lacks {$needs}" ;
        sh:select "SELECT $this WHERE { FILTER NOT EXISTS { $this $needs ?any } }" ] ;
    sh:validator [ sh:ask "ASK { FILTER (false) }" ] .
ex:S a sh:NodeShape ; sh:targetClass ex:Person ; ex:needs ex:name , ex:age .
"""
    report = validate_files(*[[f] for f in _files(tmp_path, shapes)])
    # the node validator wins over sh:validator; one constraint per value of the parameter
    assert _rows(report) == {("bob", "Needs", EX + "bob", f"lacks {EX}age"),
                             ("ann", "Needs", EX + "ann", f"lacks {EX}age")}


def test_only_optional_parameters_is_no_constraint_and_says_so(tmp_path: Path,
                                                               caplog: pytest.LogCaptureFixture) -> None:
    shapes = ASK_COMPONENT + "ex:S a sh:NodeShape ; sh:targetClass ex:Person ; " \
                             "sh:property [ sh:path ex:name ; ex:caseless true ] ."
    with caplog.at_level(logging.WARNING, logger="kb.shacl"):
        report = validate_files(*[[f] for f in _files(tmp_path, shapes)])
    assert report.conforms  # SHACL 6.2.3: the component does not apply
    assert any("without its mandatory ex:prefix" in r.message for r in caplog.records)


@pytest.mark.parametrize("params, said", [
    ('sh:flags "i"', "sh:flags without sh:pattern"),
    ("sh:qualifiedMinCount 1", "sh:qualifiedMinCount without sh:qualifiedValueShape"),
])
def test_a_core_component_given_in_part_is_warned_of(tmp_path: Path, caplog: pytest.LogCaptureFixture,
                                                     params: str, said: str) -> None:
    """By SHACL (and the W3C suite's core/node/qualified-001) the component does not apply and
    the rest of the shape counts: kitkb says so on the kb.shacl logger."""
    shapes = f"ex:S a sh:NodeShape ; sh:targetClass ex:Person ; sh:property [ sh:path ex:name ; {params} ] ."
    with caplog.at_level(logging.WARNING, logger="kb.shacl"):
        assert validate_files(*[[f] for f in _files(tmp_path, shapes)]).conforms
    assert any(said in r.message for r in caplog.records)


def test_blank_focus_nodes_and_rdflib_sparql(tmp_path: Path) -> None:
    data = PRE + 'ex:bob ex:pet [ ex:name "Rex" ] , [ ex:name "Ruffles" ] .'
    shapes = MAX_LENGTH + ASK_COMPONENT + """
ex:S a sh:NodeShape ; sh:targetObjectsOf ex:pet ;
    sh:property [ sh:path ex:name ; ex:maxLength 4 ; ex:prefix "Rex" ] ."""
    g, s = Graph().parse(data=data, format="turtle"), Graph().parse(data=PRE + shapes, format="turtle")
    for engine in ("oxigraph", "rdflib"):
        got = {(str(r.component).removeprefix(EX), str(r.value)) for r in validate_graph(g, s, sparql=engine)}
        assert got == {("MaxLength", "Ruffles"), ("Prefix", "Ruffles")}, engine


def test_same_results_as_pyshacl_for_a_directly_typed_component() -> None:
    import pyshacl
    from kb.shacl.fallback import results_from_report

    shapes = Graph().parse(data=PRE + MAX_LENGTH.replace("a ex:SubSub", "a sh:ConstraintComponent") + PERSON
                           + ASK_COMPONENT.replace("a ex:Kind ;", "a sh:ConstraintComponent ;")
                           + "ex:T a sh:NodeShape ; sh:targetClass ex:Person ; "
                             "sh:property [ sh:path ex:name ; ex:prefix \"A\" ] .", format="turtle")
    data = Graph().parse(data=DATA, format="turtle")
    ours = validate_graph(data, shapes)
    _, report, _ = pyshacl.validate(data, shacl_graph=shapes, allow_warnings=True)
    theirs = results_from_report(report)
    # pySHACL leaves sh:value out of an ASK validator's result on a property shape; SHACL
    # (and the W3C suite's sparql/component/validator-001) gives the value node
    assert sorted(r.key()[:4] for r in ours) == sorted(r.key()[:4] for r in theirs) and len(ours) == 2
    assert all(r.value == Literal("Robert") for r in ours)


def test_shape_left_to_pyshacl_still_runs_a_component_two_steps_down(tmp_path: Path) -> None:
    """sh:equals sends the shape to pySHACL, which is given the component's type spelt out."""
    shapes = MAX_LENGTH + """
ex:S a sh:NodeShape ; sh:targetClass ex:Person ;
    sh:property [ sh:path ex:name ; ex:maxLength 4 ; sh:equals ex:name ] ."""
    report = validate_files(*[[f] for f in _files(tmp_path, shapes)])
    assert report.fallback, "sh:equals is pySHACL's"
    assert {(f, c, v) for f, c, v, _ in _rows(report)} == {("bob", "MaxLength", "Robert")}


def test_users_shapes_in_kitkb_validate(tmp_path: Path) -> None:
    root = Path(__file__).resolve().parent.parent
    (tmp_path / "plant.ttl").write_text(PRE + MAX_LENGTH + """
@prefix ktw: <https://w3id.org/kitkb/kitting#> .
ex:Serials a sh:NodeShape ; sh:targetClass ktw:Part ;
    sh:property [ sh:path ktw:hasPart_SerialNumber ; ex:maxLength 2 ] .""", encoding="utf-8")
    diags = validate([str(root / "ontologies/scenarios/small-kit/init.ttl")],
                     extra_shapes=[str(tmp_path / "plant.ttl")]).diagnostics
    found = [d for d in diags if d.rule == "maxlength"]  # rules are named after their component
    assert found and all("longer than 2 characters" in d.message for d in found)


# ------------------------------------------------------------------ refused, never skipped

REFUSED = {
    "no validator for the kind": (
        """ex:C a ex:Sub . ex:Sub rdfs:subClassOf ex:Sub2 . ex:Sub2 rdfs:subClassOf sh:ConstraintComponent .
ex:C sh:parameter [ sh:path ex:p ] ; sh:nodeValidator [ sh:select "SELECT $this WHERE { }" ] .
ex:S a sh:NodeShape ; sh:targetClass ex:Person ;
    sh:property [ sh:path ex:name ; ex:p 1 ] .""",
        "constraint component ex:C has no validator for a property shape"),
    "a validator that is not SPARQL": (
        """ex:C a sh:ConstraintComponent ; sh:parameter [ sh:path ex:p ] ;
    sh:validator [ a sh:JSValidator ; sh:jsFunctionName "check" ] .
ex:S a sh:NodeShape ; sh:targetClass ex:Person ; ex:p 1 .""",
        "has 0 sh:select and 0 sh:ask"),
    "a component whose type chain is broken": (
        """ex:Sub rdfs:subClassOf sh:ConstraintComponnet .
ex:C a ex:Sub ; sh:parameter [ sh:path ex:p ] ; sh:validator [ sh:ask "ASK { }" ] .
ex:S a sh:NodeShape ; sh:targetClass ex:Person ; ex:p 1 .""",
        "ex:p is a parameter of ex:C, which is no SHACL instance of sh:ConstraintComponent"),
    "a parameter without an IRI path": (
        """ex:C a sh:ConstraintComponent ; sh:parameter [ sh:path "p" ] ; sh:validator [ sh:ask "ASK { }" ] .
ex:S a sh:NodeShape ; sh:targetClass ex:Person ; ex:p 1 .""",
        "constraint component ex:C has a parameter without exactly one IRI sh:path"),
    "a misspelt parameter of a component": (
        MAX_LENGTH + "ex:S a sh:NodeShape ; sh:targetClass ex:Person ; sh:property [ sh:path ex:name ; ex:maxLenght 4 ] .",
        "ex:maxLenght is no parameter of a constraint component here, did you mean ex:maxLength?"),
    "a misspelt constraint": (
        "ex:S a sh:NodeShape ; sh:targetClass ex:Person ; sh:property [ sh:path ex:name ; sh:minCont 2 ] .",
        "sh:minCont is not a SHACL term, did you mean sh:minCount?"),
    "a misspelt target": (
        "ex:S a sh:NodeShape ; sh:targetClas ex:Person ; sh:property [ sh:path ex:name ; sh:minCount 2 ] .\n"
        "ex:T a sh:NodeShape ; sh:targetClass ex:Person .",
        "sh:targetClas is not a SHACL term, did you mean sh:targetClass?"),
    "a SPARQL-based target": (
        'ex:S a sh:NodeShape ; sh:target [ a sh:SPARQLTarget ; sh:select "SELECT ?this WHERE { ?this a ex:Person }" ] ;'
        " sh:property [ sh:path ex:name ; sh:minCount 2 ] .\nex:T a sh:NodeShape ; sh:targetClass ex:Person .",
        "sh:target is of SHACL Advanced Features"),
    "a rule": (
        "ex:S a sh:NodeShape ; sh:targetClass ex:Person ; sh:rule [ a sh:TripleRule ; sh:subject sh:this ;"
        " sh:predicate ex:p ; sh:object 1 ] .",
        "sh:rule is of SHACL Advanced Features"),
    "a SPARQL constraint that asks": (
        'ex:S a sh:NodeShape ; sh:targetClass ex:Person ; sh:sparql [ sh:ask "ASK { FILTER (false) }" ] .',
        "a SPARQL-based constraint needs exactly one sh:select"),
    "a query in the wrong place": (
        'ex:S a sh:NodeShape ; sh:targetClass ex:Person ; sh:select "SELECT $this WHERE { }" .',
        "sh:select does not belong on a shape"),
    "$PATH in a node shape's query": (
        'ex:S a sh:NodeShape ; sh:targetClass ex:Person ; sh:sparql [ sh:select "SELECT $this WHERE { $this $PATH ?v }" ] .',
        "uses $PATH, which only a property shape has"),
    "a list that is not one": (
        "ex:S a sh:NodeShape ; sh:targetClass ex:Person ; sh:and ex:notAList .",
        "the value of sh:and is not a well-formed RDF list"),
    "a pattern that is not one": (
        'ex:S a sh:NodeShape ; sh:targetClass ex:Person ; sh:property [ sh:path ex:name ; sh:pattern "a(" ] .',
        "sh:pattern 'a(' is not a regular expression"),
    "an unknown node kind": (
        "ex:S a sh:NodeShape ; sh:targetClass ex:Person ; sh:nodeKind sh:IRIorLiteral .",
        "sh:nodeKind sh:IRIorLiteral is none of SHACL's six node kinds"),
    "a count that is not an integer": (
        'ex:S a sh:NodeShape ; sh:targetClass ex:Person ; sh:property [ sh:path ex:name ; sh:minCount "one" ] .',
        'sh:minCount "one" is not an integer'),
    "a property shape without a path": (
        "ex:S a sh:NodeShape ; sh:targetClass ex:Person ; sh:property [ sh:minCount 3 ] .",
        "of its sh:property has no sh:path"),
    "a malformed path": (
        'ex:S a sh:NodeShape ; sh:targetClass ex:Person ; sh:property [ sh:path "name" ; sh:minCount 1 ] .',
        'sh:path "name" is not a well-formed SHACL property path'),
    "one mandatory parameter without the other": (
        """ex:C a sh:ConstraintComponent ; sh:parameter [ sh:path ex:low ] , [ sh:path ex:high ] ;
    sh:validator [ sh:ask "ASK { FILTER ($value >= $low && $value <= $high) }" ] .
ex:S a sh:NodeShape ; sh:targetClass ex:Person ; sh:property [ sh:path ex:age ; ex:low 1 ] .""",
        "it gives ex:low of constraint component ex:C without its mandatory ex:high"),
    "a literal target class": (
        'ex:S a sh:NodeShape ; sh:targetClass "Person" ; sh:property [ sh:path ex:name ; sh:minCount 1 ] .\n'
        "ex:T a sh:NodeShape ; sh:targetClass ex:Person .",
        'sh:targetClass "Person" is a literal'),
}


@pytest.mark.parametrize("case", sorted(REFUSED))
def test_refused_with_the_reason_at_its_line(tmp_path: Path, case: str, capsys: pytest.CaptureFixture[str]) -> None:
    shapes, why = REFUSED[case]
    data, shapes_file = _files(tmp_path, shapes)
    with pytest.raises(InputError) as refused:
        validate_files([data], [shapes_file])
    assert why in refused.value.message
    assert refused.value.file == str(shapes_file) and refused.value.line, "named at its file:line"
    assert main(["shacl", str(data), "-s", str(shapes_file)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and why in err[0] and "Traceback" not in err[0]


def test_sparql_on_a_property_shape_runs_natively() -> None:
    shapes = Graph().parse(data=PRE + """
ex:S a sh:NodeShape ; sh:targetClass ex:Person ;
    sh:property [ sh:path ex:name ;
        sh:sparql [ sh:select "SELECT $this ?value WHERE { $this $PATH ?value . FILTER (STRLEN(?value) < 4) }" ] ] .""",
                           format="turtle")
    assert unsupported_shapes(shapes) == {}
    got = {(r.focus, r.path, r.value) for r in validate_graph(Graph().parse(data=DATA, format="turtle"), shapes)}
    assert got == {(URIRef(EX + "ann"), URIRef(EX + "name"), Literal("Ann"))}


def test_implicit_class_targets_through_subclass_steps() -> None:
    """A shape that is a class, both by rdf:type/rdfs:subClassOf*: an implicit class target."""
    shapes = Graph().parse(data=PRE + """
ex:Meta rdfs:subClassOf ex:Meta0 . ex:Meta0 rdfs:subClassOf rdfs:Class .
ex:ShapeKind rdfs:subClassOf ex:ShapeKind0 . ex:ShapeKind0 rdfs:subClassOf sh:NodeShape .
ex:Person a ex:Meta , ex:ShapeKind ; sh:property [ sh:path ex:name ; sh:maxLength 4 ] .""", format="turtle")
    got = {(r.focus, r.component) for r in validate_graph(Graph().parse(data=DATA, format="turtle"), shapes)}
    assert got == {(URIRef(EX + "bob"), SH.MaxLengthConstraintComponent)}


def test_the_shipped_shapes_compile_without_refusal() -> None:
    root = Path(__file__).resolve().parent.parent
    for name in ("kitting-shapes.ttl", "kitting-rules.ttl"):
        assert unsupported_shapes(Graph().parse(root / "shapes" / name)) == {}


RECURSIVE = """
ex:S a sh:NodeShape ; sh:targetNode ex:n1 ;
    sh:property [ sh:path ex:knows ; sh:node ex:S ] ;
    sh:property [ sh:path ex:name ; sh:minCount 1 ] ."""


def test_recursive_shape_evaluated_while_pyshacl_reaches_the_data(tmp_path: Path) -> None:
    data = PRE + 'ex:n1 ex:name "a" ; ex:knows ex:n2 . ex:n2 ex:knows ex:n3 .'
    report = validate_files(*[[f] for f in _files(tmp_path, RECURSIVE, data)])
    assert report.fallback and {(f, c) for f, c, _, _ in _rows(report)} == {("n1", str(SH.NodeConstraintComponent))}


def test_recursive_shape_refused_where_pyshacl_stops_short(tmp_path: Path) -> None:
    """pySHACL backs out three levels down and counts the rest as conforming: a chain whose
    20th node lacks its name conformed. kitkb refuses that answer."""
    nodes = [f'ex:n{i} ex:knows ex:n{i + 1}' + ("" if i == 20 else f' ; ex:name "n{i}"') + " ." for i in range(1, 21)]
    data, shapes = _files(tmp_path, RECURSIVE, PRE + "\n".join(nodes))
    with pytest.raises(InputError) as refused:
        validate_files([data], [shapes])
    assert "recursive and pySHACL, which evaluates it, stopped short" in refused.value.message
    assert refused.value.line == (PRE + RECURSIVE).splitlines().index("ex:S a sh:NodeShape ; sh:targetNode ex:n1 ;") + 1


def test_kitkb_shacl_json_lists_the_engine_warnings(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    import json

    shapes = ASK_COMPONENT + "ex:S a sh:NodeShape ; sh:targetClass ex:Person ; " \
                             "sh:property [ sh:path ex:name ; ex:caseless true ] ."
    data, shapes_file = _files(tmp_path, shapes)
    assert main(["shacl", str(data), "-s", str(shapes_file), "--format", "json"]) == 0
    captured = capsys.readouterr()
    warned = json.loads(captured.out)["warnings"]
    assert len(warned) == 1 and "does not apply" in warned[0] and warned[0] in captured.err
