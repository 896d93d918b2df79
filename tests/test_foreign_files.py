"""Other people's files (issue 26, points 4 and 6): read right, or refused with the reason.

Files shaped like the real ones (tests/data/foreign/): Protégé's OWL/XML and RDF/XML with their
internal DTD, RDF/XML in ISO-8859-1, NIST's 2012 state files (``kittingClasses.owl#``, a
relative import, PartsTrayWithParts groups; made from NIST's 2013 ones by make_nist2012.py) and
the first 2012 form, a Windows path import, a Protégé catalog, NIST's SOAP as a domain file, an
entity bomb. Every command whose input holds nothing it understands exits 2 saying what it
looked for.
"""

from __future__ import annotations

import codecs
from pathlib import Path

import pytest
from rdflib import Literal, URIRef
from rdflib.namespace import RDF, RDFS, XSD

from kb.cli import main
from kb.core.errors import InputError
from kb.core.namespaces import KITTING_ONTOLOGY, KTW, NIST_KTW_2012
from kb.io import load, load_file
from kb.io.parsing import _rust_message, expand_entities
from shared_data import NIST_DIR

DATA = Path(__file__).parent / "data" / "foreign"
NIST2012 = DATA / "nist2012"
EARLY = DATA / "nist2012-early" / "kittingInstancesGoal.owl"
CELL = "http://www.semanticweb.org/nist/workcell#"
needs_nist = pytest.mark.skipif(not (NIST_DIR / "kittingInstancesInit1.owl").is_file(),
                                reason="NIST's reference files are not beside the checkout")


def line_of(path: Path, text: str, nth: int = 1) -> int:
    """The line of the ``nth`` line of ``path`` that contains ``text``."""
    found = [i for i, line in enumerate(path.read_text("utf-8").splitlines(), 1) if text in line]
    return found[nth - 1]


def kitkb(capsys: pytest.CaptureFixture, *argv: str) -> tuple[int, str, str]:
    """``kitkb ARGV`` in this process: (exit code, standard output, standard error)."""
    code = main(list(argv))
    out = capsys.readouterr()
    return code, out.out, out.err


def one_error(err: str) -> str:
    """The one error line of a refused command (warnings may come before it)."""
    errors = [line for line in err.splitlines() if ": error: " in line or line.startswith("error: ")]
    assert len(errors) == 1, err
    assert "Traceback" not in err
    return errors[0]


# --- point 6: Protégé's output ---------------------------------------------------------------

def test_protege_owl_xml_with_its_dtd_is_read() -> None:
    graph = load_file(DATA / "protege" / "workcell.owx").graph
    part = URIRef(CELL + "part_a_1")
    assert (part, RDF.type, KTW.Part) in graph
    assert (part, KTW.hasPart_SerialNumber, Literal("a1", datatype=XSD.NMTOKEN)) in graph
    assert (part, RDFS.label, Literal("pièce A n° 1", lang="fr")) in graph


def test_protege_owl_xml_findings_keep_their_lines(capsys: pytest.CaptureFixture) -> None:
    """The DTD's lines are kept when its entities are expanded: a finding is at its own line."""
    path = DATA / "protege" / "workcell.owx"
    code, out, _ = kitkb(capsys, "validate", str(path))
    assert code == 1
    line = line_of(path, "<DataPropertyAssertion>", 2)
    assert f"{path}:{line}: error: unknown property <{CELL}hasColour>" in out


def test_protege_rdf_xml_with_single_quoted_entities_is_read() -> None:
    graph = load_file(DATA / "protege" / "workcell.owl").graph
    part = URIRef(CELL + "part_a_1")
    assert (part, RDF.type, KTW.Part) in graph
    assert (part, KTW.hasPart_SerialNumber, Literal("a1", datatype=XSD.NMTOKEN)) in graph
    assert (part, RDFS.label, Literal("Teil & Zubehör", lang="de")) in graph
    assert (part, URIRef(CELL + "hasColour"), Literal("red")) in graph


def test_iso_8859_1_rdf_xml_is_transcoded(capsys: pytest.CaptureFixture) -> None:
    path = DATA / "latin1.rdf"
    assert b"encoding='ISO-8859-1'" in path.read_bytes()[:60]
    graph = load_file(path).graph
    part = URIRef("http://www.example.org/atelier#pièce_a_1")
    assert (part, RDFS.label, Literal("Pièce « A » n° 1, 20 °C", lang="fr")) in graph
    assert (part, RDFS.label, Literal("Größe: groß", lang="de")) in graph
    code, out, _ = kitkb(capsys, "validate", str(path))
    assert code == 1
    assert f"{path}:{line_of_bytes(path, b'hasPart_Colour')}: error: unknown property ktw:hasPart_Colour" in out


def line_of_bytes(path: Path, text: bytes) -> int:
    data = path.read_bytes()
    return data[: data.index(text)].count(b"\n") + 1


@pytest.mark.parametrize("bom, codec", [(codecs.BOM_UTF16_LE, "utf-16-le"), (codecs.BOM_UTF16_BE, "utf-16-be")])
def test_utf16_xml_with_a_byte_order_mark_is_read(tmp_path: Path, bom: bytes, codec: str) -> None:
    text = (DATA / "latin1.rdf").read_bytes().decode("iso-8859-1").replace("ISO-8859-1", "UTF-16")
    path = tmp_path / "utf16.rdf"
    path.write_bytes(bom + text.encode(codec))
    labels = set(load_file(path).graph.objects(None, RDFS.label))
    assert Literal("Größe: groß", lang="de") in labels


def test_a_turtle_file_stays_utf8_only(tmp_path: Path) -> None:
    path = tmp_path / "state.ttl"
    path.write_bytes(codecs.BOM_UTF16_LE + "<http://a.org/a> <http://a.org/p> 1 .\n".encode("utf-16-le"))
    with pytest.raises(InputError, match="not UTF-8 text"):
        load_file(path)


@pytest.mark.parametrize("declared, body, message, line", [
    ("x-klingon", b"<r/>", "unknown character encoding 'x-klingon' in the XML declaration", 1),
    ("base64", b"<r/>", "unknown character encoding 'base64' in the XML declaration", 1),
    ("US-ASCII", b"<r>\n<a>caf\xe9</a></r>", "not ascii text (byte 0xe9)", 3),
])
def test_a_declared_encoding_that_cannot_be_read_is_exit_2_at_its_line(
        tmp_path: Path, capsys: pytest.CaptureFixture, declared: str, body: bytes, message: str, line: int) -> None:
    path = tmp_path / "odd.rdf"
    path.write_bytes(f'<?xml version="1.0" encoding="{declared}"?>\n'.encode() + body)
    code, _, err = kitkb(capsys, "convert", str(path), "-o", str(tmp_path / "out.ttl"))
    assert code == 2
    assert one_error(err) == f"{path}:{line}: error: {message}"


def test_an_entity_bomb_is_exit_2_in_one_line(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    path = DATA / "protege" / "bomb.owx"
    code, _, err = kitkb(capsys, "convert", str(path), "-o", str(tmp_path / "out.ttl"))
    assert code == 2
    assert one_error(err) == (f"{path}:{line_of(path, '<!ENTITY lol7 ')}: error: XML entity 'lol7' expands to "
                              "30,000,000 characters: over the limit on a literal's length (10,000,000 characters; "
                              "set KITKB_MAX_LITERAL to raise it)")
    assert not (tmp_path / "out.ttl").exists()


def test_an_entity_bomb_stays_refused_with_the_literal_limit_lifted(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("KITKB_MAX_LITERAL", "0")
    with pytest.raises(InputError, match=r"over the amplification limit \(100 times, an entity bomb\)") as info:
        load_file(DATA / "protege" / "bomb.owx")
    assert info.value.line == line_of(DATA / "protege" / "bomb.owx", "&lol9;</Literal>")


@pytest.mark.parametrize("subset, message", [
    ('<!ENTITY a "x&b;"> <!ENTITY b "y&a;">', "XML entity 'a' refers to itself"),
    ('<!ENTITY % p "x">', "XML parameter entity 'p' is not allowed"),
    ('<!ENTITY e SYSTEM "file:///etc/passwd">', "external XML entity 'e' is not allowed (nothing is fetched)"),
    ('<!ATTLIST r a CDATA "1">', "an XML attribute-list declaration (<!ATTLIST>) is not read"),
])
def test_entities_that_are_not_allowed(tmp_path: Path, subset: str, message: str) -> None:
    path = tmp_path / "x.rdf"
    path.write_text(f'<?xml version="1.0"?>\n<!DOCTYPE r [\n{subset}\n]>\n<r>&a;</r>\n')
    with pytest.raises(InputError, match=message.replace("(", r"\(").replace(")", r"\)")) as info:
        load_file(path)
    assert info.value.line == 3


def test_entities_refer_to_one_another_and_keep_lines(tmp_path: Path) -> None:
    text = ('<?xml version="1.0"?>\n<!DOCTYPE rdf:RDF [\n<!ENTITY base "http://ex.org/">\n'
            '<!ENTITY ex "&base;ns#">\n<!ENTITY two "line one\nline two">\n]>\n<rdf:RDF/>\n'
            '<a b="&ex;x" c=\'&two;\'>&ex;y &two; &lt;&unknown;</a>\n')
    out = expand_entities(text, tmp_path / "x.rdf")
    assert out.count("\n") == text.count("\n")
    assert '<a b="http://ex.org/ns#x" c=\'line one line two\'>http://ex.org/ns#y line one&#10;line two' in out
    assert out.endswith("&lt;&unknown;</a>\n")  # predefined and undeclared references left to the parser


def test_windows_path_import_reads_the_file(capsys: pytest.CaptureFixture) -> None:
    """NIST's state with the import of a Windows checkout: read, the path named at its line,
    the import resolved to kitkb's model by its file name."""
    path = DATA / "windows" / "kittingInstancesInit1.owl"
    kb = load([path])
    assert kb.sources[0].imports == ["file:C:/Documents%20and%20Settings/kootbally/ipmas/Ontology/Kitting/"
                                     "kittingWorkstationClasses.owl"]
    assert len(kb.sources) == 2 and kb.sources[1].path.name == "kitting.ttl"
    code, out, _ = kitkb(capsys, "validate", str(path))
    assert code == 0
    assert (f"{path}:{line_of(path, 'Import(')}: warning: <file:C:\\Documents and Settings\\kootbally\\ipmas"
            "\\Ontology\\Kitting\\kittingWorkstationClasses.owl> is a file path, not an IRI; read as "
            "<file:C:/Documents%20and%20Settings/kootbally/ipmas/Ontology/Kitting/kittingWorkstationClasses.owl> "
            "[file-iri]") in out


@pytest.mark.parametrize("name, line, text", [
    ("import.owx", 3, '<?xml version="1.0"?>\n<Ontology xmlns="http://www.w3.org/2002/07/owl#" '
                   'ontologyIRI="http://e.org/o">\n<Import>file:C:\\Models\\kittingWorkstationClasses.owl</Import>\n'
                   '</Ontology>\n'),
    ("import.rdf", 4, '<?xml version="1.0"?>\n<rdf:RDF xmlns:rdf="http://www.w3.org/1999/02/22-rdf-syntax-ns#" '
                   'xmlns:owl="http://www.w3.org/2002/07/owl#">\n<owl:Ontology rdf:about="http://e.org/o">\n'
                   '<owl:imports rdf:resource="file:C:\\Models\\kittingWorkstationClasses.owl"/>\n'
                   '</owl:Ontology>\n</rdf:RDF>\n'),
])
def test_windows_path_imports_in_xml(tmp_path: Path, name: str, line: int, text: str) -> None:
    path = tmp_path / name
    path.write_text(text)
    source = load_file(path)
    assert source.imports == ["file:C:/Models/kittingWorkstationClasses.owl"]
    assert [(w.rule, w.line) for w in source.warnings] == [("file-iri", line)]


def test_library_errors_are_one_line_at_a_line(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    path = tmp_path / "bad.owx"
    path.write_text('<?xml version="1.0"?>\n<Ontology xmlns="http://www.w3.org/2002/07/owl#" '
                    'ontologyIRI="http://e.org/o">\n<Declaration>\n<Klass IRI="#A"/>\n</Declaration>\n</Ontology>\n')
    code, _, err = kitkb(capsys, "convert", str(path), "-o", str(tmp_path / "out.ttl"))
    assert code == 2
    assert one_error(err) == (f"{path}:4: error: syntax error (OWL/XML): Unknown Entity: expected kind of "
                              "NamedOWLEntity, found Klass")
    path = tmp_path / "bad.rdf"
    path.write_text('<?xml version="1.0"?>\n<rdf:RDF xmlns:rdf="http://www.w3.org/1999/02/22-rdf-syntax-ns#">\n'
                    '<rdf:Description rdf:about="http://e.org/a"/>\n'
                    '<rdf:Description rdf:about="http://e.org/a b"/>\n</rdf:RDF>\n')
    code, _, err = kitkb(capsys, "convert", str(path), "-o", str(tmp_path / "out.ttl"))
    assert code == 2
    assert one_error(err).startswith(f"{path}:4: error: ")


@pytest.mark.parametrize("raw, sentence", [
    ('Failed to open ontology: ValidityError("Missing Element: expected IRI", BytePosition(162))',
     "Missing Element: expected IRI"),
    ('Failed to open ontology: ParserError(UnrecognizedEntity(1..4, "xsd"), Unknown)', "undeclared XML entity &xsd;"),
    ("Failed to open ontology: ParserError(UnexpectedEof, Unknown)", "unexpected eof"),
])
def test_rust_debug_strings_become_sentences(raw: str, sentence: str) -> None:
    assert _rust_message(raw) == sentence


# --- point 4: NIST's 2012 namespace, nothing understood --------------------------------------

def test_nist_2012_state_is_read_by_the_mapping() -> None:
    """2012 names (hasWorkstation_*, hasSku_Shape, hasPart_Sku...) read as kitkb's; the
    PartsTrayWithParts groups as their trays; nothing left unread; the relative import of
    kittingClasses.owl is kitkb's model, whether or not the file is beside the state."""
    kb = load([NIST2012 / "kittingInstancesInit.owl"])
    source = kb.sources[0]
    assert source.imports == ["file:kittingClasses.owl"]
    assert [s.path.name for s in kb.sources] == ["kittingInstancesInit.owl", "kitting.ttl"]
    assert [w.rule for w in source.warnings] == ["ofn-comment"]
    graph = source.graph
    ns = NIST_KTW_2012
    tray, part = URIRef(ns + "part_a_tray"), URIRef(ns + "part_a_1")
    assert (URIRef(ns + "kitting_workstation_1"), KTW.hasKittingWorkstation_LengthUnit, None) in graph
    assert (tray, KTW.hasPartsVessel_Part, part) in graph
    assert (part, KTW.hasSkuObject_Sku, URIRef(ns + "stock_keeping_unit_part_a")) in graph
    assert not [t for t in graph if any(str(x).startswith(ns) and str(x)[len(ns):][:1].isupper() or
                                        str(x).startswith(ns + "has") for x in t[1:])]


@needs_nist
def test_nist_2012_state_decides_the_predicates_of_its_2013_original(capsys: pytest.CaptureFixture) -> None:
    code, new, _ = kitkb(capsys, "predicates", str(NIST2012 / "kittingInstancesInit.owl"))
    assert code == 0
    code, old, _ = kitkb(capsys, "predicates", str(NIST_DIR / "kittingInstancesInit1.owl"))
    assert code == 0 and new == old and "part-location-partstray(part_a_1, part_a_tray)" in new


def test_nist_2012_goal_with_its_kit_generates_pddl(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    code, _, err = kitkb(capsys, "generate", "pddl", str(NIST2012 / "kittingInstancesInit.owl"),
                         str(NIST2012 / "kittingInstancesGoal.owl"), "-o", str(tmp_path))
    assert code == 0, err
    problem = (tmp_path / "problem.pddl").read_text()
    assert "kit_1" in problem and "part_a_1" in problem


def test_a_2012_tray_off_its_groups_origin_is_refused(tmp_path: Path) -> None:
    text = (NIST2012 / "kittingInstancesInit.owl").read_text("utf-8")
    moved = text.replace('hasPoint_X :part_b_tray_point "0.000000"', 'hasPoint_X :part_b_tray_point "0.100000"')
    assert moved != text
    path = tmp_path / "moved.owl"
    path.write_text(moved, "utf-8")
    with pytest.raises(InputError) as info:
        load_file(path)
    assert "part_b_tray is not at the origin of its NIST 2012 PartsTrayWithParts part_b_supply" in str(info.value)
    assert info.value.line == line_of(path, ":part_b_tray :part_b_tray_pose")


def test_first_2012_form_names_its_terms_and_predicates_refuses(capsys: pytest.CaptureFixture) -> None:
    code, out, err = kitkb(capsys, "predicates", str(EARLY))
    assert code == 2 and out == ""
    warning = f"{EARLY}:{line_of(EARLY, 'ClassAssertion(:KitInstance')}: warning: 14 term(s) of NIST's 2012"
    assert warning in err and "KitInstance (line 18), hasSolidObject_PhysicalLocation (line 19)" in err
    error = one_error(err)
    assert error.startswith(f"{EARLY}: error: no placed object kitkb reads")
    assert "without counterpart in kitkb's model are hasSolidObject_PhysicalLocation, KitInstance" in error


def test_a_goal_whose_kit_is_not_understood_is_exit_2(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    goal = tmp_path / "goal.owl"
    goal.write_text("Prefix(:=<http://www.nist.gov/el/ontologies/kittingClasses.owl#>)\n"
                    "Ontology(<http://www.nist.gov/el/ontologies/kittingInstancesGoal.owl>\n"
                    "Import(<file:kittingClasses.owl>)\nClassAssertion(:KitInstance :KitInstance1)\n)\n")
    code, _, err = kitkb(capsys, "generate", "pddl", str(NIST2012 / "kittingInstancesInit.owl"), str(goal),
                         "-o", str(tmp_path / "pddl"))
    assert code == 2
    assert one_error(err) == (f"{goal}: error: the goal state has no kit kitkb reads (nothing to build: no "
                              "individual of ktw:Kit): its terms of NIST's 2012 namespace without counterpart in "
                              "kitkb's model are KitInstance; kitkb reads <https://w3id.org/kitkb/kitting#> "
                              "(NIST's <http://www.nist.gov/el/ontologies/kittingWorkstationClasses.owl#> and "
                              "<http://www.nist.gov/el/ontologies/kittingClasses.owl#> mapped onto it), "
                              "<https://w3id.org/kitkb/soap#> and <https://w3id.org/kitkb/kitting-domain#>")


def test_an_initial_state_of_another_vocabulary_is_exit_2(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    code, _, err = kitkb(capsys, "plan", str(DATA / "catalog" / "kittingInstancesCell.owl"),
                         str(NIST2012 / "kittingInstancesGoal.owl"), "-o", str(tmp_path / "plan.txt"))
    assert code == 2
    assert one_error(err).startswith(f"{DATA / 'catalog' / 'kittingInstancesCell.owl'}: error: the initial state "
                                     "has no object kitkb reads (no individual of a class of the kitting model "
                                     "that the planning domain uses): its classes and properties are in "
                                     "<http://www.example.org/cellModel#>; kitkb reads")
    assert not (tmp_path / "plan.txt").exists()


@needs_nist
def test_nist_soap_as_a_domain_file_is_exit_2(capsys: pytest.CaptureFixture) -> None:
    domain = DATA / "nist-soap" / "soapInstances.owl"
    code, out, err = kitkb(capsys, "predicates", str(NIST_DIR / "kittingInstancesInit1.owl"), "--domain", str(domain))
    assert code == 2 and out == ""
    assert one_error(err).startswith(
        f"{domain}: error: no predicate definition kitkb reads in soapInstances.owl (it looked for individuals of "
        "soap:Predicate with a soap:hasPredicate_Definition): its classes and properties are in "
        "<http://www.nist.gov/el/ontologies/soapClasses.owl#> (NIST's SOAP, not kitkb's); kitkb reads")


def test_no_placed_object_of_kitkbs_own_classes_is_exit_2(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    path = tmp_path / "bare.ttl"
    path.write_text("@prefix ktw: <https://w3id.org/kitkb/kitting#> .\n<http://e.org/a#robot_1> a ktw:Robot .\n")
    code, out, err = kitkb(capsys, "predicates", str(path))
    assert code == 2 and out == ""
    assert one_error(err) == (f"{path}: error: no placed object kitkb reads (it looked for individuals of the "
                              "kitting model's solid objects with a ktw:hasSolidObject_PrimaryLocation pose): the "
                              "classes and properties it uses are all kitkb's")


def test_an_unresolved_relative_import_is_named_at_its_line(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    path = tmp_path / "cell.owl"
    path.write_text("Prefix(:=<http://e.org/cell#>)\nPrefix(m:=<http://e.org/model#>)\n"
                    "Ontology(<http://e.org/cell>\n\nImport(<file:cellModel.owl>)\n"
                    "ClassAssertion(m:Press :press_1)\n)\n")
    code, out, err = kitkb(capsys, "validate", str(path))
    assert code == 2 and out == ""
    assert one_error(err).startswith(
        f"{path}:5: error: no model to validate against: the files declare no classes, and their import of "
        f"<file:cellModel.owl> ({path}:5) did not resolve (name the model file on the command line, put it beside "
        f"the importing file, or import <{KITTING_ONTOLOGY}>); its classes and properties are in <http://e.org/model#>")
    warnings = load([path]).warnings
    assert [(w.rule, w.line) for w in warnings] == [("unresolved-import", 5)]
    assert "no cellModel.owl beside cell.owl, in a catalog-v001.xml there, or on the command line" in warnings[0].message


def test_a_protege_catalog_resolves_imports_inside_its_folder_only() -> None:
    path = DATA / "catalog" / "kittingInstancesCell.owl"
    kb = load([path])
    assert [s.path.name for s in kb.sources] == ["kittingInstancesCell.owl", "cellModel.ttl"]
    assert [(w.rule, w.line, w.focus) for w in kb.warnings] == [
        ("unresolved-import", line_of(path, "outside.owl"), "file:outside.owl")]


def test_plan_and_generate_name_what_they_do_not_read(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    goal = tmp_path / "goal.owl"
    text = (NIST2012 / "kittingInstancesGoal.owl").read_text("utf-8").rstrip()
    assert text.endswith(")")
    goal.write_text(text[:-1] + 'DataPropertyAssertion(:hasShapeDesign_Model :shape_work_table "table.stl")\n)\n',
                    "utf-8")
    code, _, err = kitkb(capsys, "generate", "pddl", str(NIST2012 / "kittingInstancesInit.owl"), str(goal),
                         "-o", str(tmp_path / "pddl"))
    assert code == 0
    assert err.startswith(f"{goal}:{line_of(goal, 'hasShapeDesign_Model')}: warning: 1 term(s) of NIST's 2012 "
                          "kitting vocabulary <http://www.nist.gov/el/ontologies/kittingClasses.owl#> have no "
                          "counterpart in kitkb's model and are not read: hasShapeDesign_Model")


@needs_nist
def test_nists_own_soap_instances_as_a_domain_file_is_exit_2(capsys: pytest.CaptureFixture) -> None:
    domain = NIST_DIR / "soapInstances.owl"
    code, out, err = kitkb(capsys, "predicates", str(NIST_DIR / "kittingInstancesInit1.owl"), "--domain", str(domain))
    assert code == 2 and out == ""
    assert "no predicate definition kitkb reads in soapInstances.owl" in one_error(err)
    assert "<http://www.nist.gov/el/ontologies/soapClasses.owl#> (NIST's SOAP, not kitkb's)" in one_error(err)
