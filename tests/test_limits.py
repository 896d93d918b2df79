"""Bounded inputs (kb.core.limits): each limit refuses with exit code 2 and one line naming the
file, the line where there is one, and the variable that raises it; deep nesting in every
syntax is exit 2, never a RecursionError (exit 3); big CRCL programs are read and written in
bounded memory; the defaults are documented in docs/limits.md."""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

from kb.cli import main
from kb.core import limits
from kb.core.errors import InputError
from kb.crcl import read_text, read_xml, write_xml
from kb.crcl import xml as crcl_xml
from kb.crcl.xml import default_xsd, schema

ROOT = Path(__file__).resolve().parents[1]
EX = "@prefix ex: <http://ex.org/> .\n"
PROGRAM = ('InitCanon()\nDwell(1)\nMoveTo({{1, 2, 3}, {0, 0, 1}, {1, 0, 0}})\nMessage("hello")\n'
           'OpenGripper()\nCloseGripper()\nEndCanon()\n')


def _run(argv: list[str], capsys: pytest.CaptureFixture[str]) -> tuple[int, str]:
    code = main(argv)
    err = capsys.readouterr().err.strip()
    return code, err


def _refused(code: int, err: str, env: str, where: str) -> None:
    """Exit 2, one line, at ``where`` (``file`` or ``file:line``), naming ``env``."""
    assert code == 2, err
    assert len(err.splitlines()) == 1, err
    assert err.startswith(f"{where}: error: "), err
    assert env in err and "over the limit on" in err, err


# --- the limits' own rules -------------------------------------------------------------------

def test_every_limit_has_a_documented_variable_and_default() -> None:
    doc = (ROOT / "docs" / "limits.md").read_text(encoding="utf-8")
    names = [limit.env for limit in limits.ALL]
    assert len(limits.ALL) == 6 and len(set(names)) == len(names)
    for limit in limits.ALL:
        assert limit.env.startswith("KITKB_MAX_")
        row = next((line for line in doc.splitlines() if line.startswith("|") and f"`{limit.env}`" in line), None)
        assert row is not None, f"{limit.env} has no row in docs/limits.md"
        assert limit.default > 0


def test_amounts_and_a_bad_variable(monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str],
                                    tmp_path: Path) -> None:
    assert limits.parse_amount("2G") == 2 * 10**9
    assert limits.parse_amount("512Mi") == 512 * 2**20
    assert limits.parse_amount("1_000") == 1000
    assert limits.parse_amount("0") is None and limits.parse_amount("none") is None
    with pytest.raises(ValueError):
        limits.parse_amount("lots")
    monkeypatch.setenv("KITKB_MAX_STATEMENTS", "lots")
    path = tmp_path / "a.ttl"
    path.write_text(EX + "ex:a ex:p ex:b .\n")
    code, err = _run(["validate", str(path)], capsys)
    assert code == 2 and err == ("error: KITKB_MAX_STATEMENTS='lots' is not a whole number "
                                 "(like 5000000, 2G, 512Mi; 0 or none lifts the limit)")


def test_a_lifted_limit(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("KITKB_MAX_PARTS", "0")
    assert limits.PARTS.value() is None
    limits.PARTS.check(10**15)


# --- ontology and data files -------------------------------------------------------------------

def test_file_size(monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    path = tmp_path / "a.ttl"
    path.write_text(EX + "ex:a ex:p ex:b .\n")
    monkeypatch.setenv("KITKB_MAX_FILE_BYTES", "20")
    code, err = _run(["validate", str(path)], capsys)
    _refused(code, err, "KITKB_MAX_FILE_BYTES", str(path))
    assert "a file's size" in err


def test_file_size_of_a_sparse_2gb_file(capsys: pytest.CaptureFixture[str], tmp_path: Path,
                                        monkeypatch: pytest.MonkeyPatch) -> None:
    """A file past the default limit is refused before a byte of it is read."""
    path = tmp_path / "huge.ttl"
    with open(path, "wb") as f:
        f.truncate(limits.FILE_BYTES.default + 1)
    code, err = _run(["validate", str(path)], capsys)
    _refused(code, err, "KITKB_MAX_FILE_BYTES", str(path))


def test_statements(monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    path = tmp_path / "a.nt"
    path.write_text("".join(f"<http://ex.org/a{i}> <http://ex.org/p> <http://ex.org/b> .\n" for i in range(6)))
    monkeypatch.setenv("KITKB_MAX_STATEMENTS", "5")
    code, err = _run(["validate", str(path)], capsys)
    _refused(code, err, "KITKB_MAX_STATEMENTS", str(path))
    monkeypatch.setenv("KITKB_MAX_STATEMENTS", "6")
    assert main(["validate", str(path)]) in (0, 1)


def test_literal(monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    path = tmp_path / "a.ttl"
    path.write_text(EX + "ex:a ex:p ex:b .\n" + 'ex:a ex:q "' + "x" * 30 + '" .\n')
    monkeypatch.setenv("KITKB_MAX_LITERAL", "20")
    code, err = _run(["validate", str(path)], capsys)
    _refused(code, err, "KITKB_MAX_LITERAL", f"{path}:3")
    assert "a literal of 30 characters" in err


def _deep(syntax: str, n: int) -> tuple[str, str]:
    """A file nested ``n`` levels deep in ``syntax``: (suffix, text)."""
    if syntax == "turtle-blank-nodes":
        return ".ttl", EX + "ex:a ex:p " + "[ ex:p " * n + "ex:b" + " ]" * n + " .\n"
    if syntax == "turtle-collections":
        return ".ttl", EX + "ex:a ex:p " + "( " * n + "ex:b" + " )" * n + " .\n"
    if syntax == "ofn":
        return ".ofn", ("Ontology(<http://ex.org/o>\nSubClassOf(<http://ex.org/A> " + "ObjectComplementOf(" * n
                        + "<http://ex.org/B>" + ")" * n + ")\n)\n")
    if syntax == "rdfxml":
        return ".rdf", ('<?xml version="1.0"?>\n<rdf:RDF xmlns:rdf="http://www.w3.org/1999/02/22-rdf-syntax-ns#" '
                        'xmlns:ex="http://ex.org/">\n' + "<rdf:Description><ex:p>" * n
                        + "</ex:p></rdf:Description>" * n + "</rdf:RDF>\n")
    assert syntax == "owlxml"
    return ".owx", ('<?xml version="1.0"?>\n<Ontology xmlns="http://www.w3.org/2002/07/owl#" '
                    'ontologyIRI="http://ex.org/o">\n<SubClassOf><Class IRI="http://ex.org/A"/>'
                    + "<ObjectComplementOf>" * n + '<Class IRI="http://ex.org/B"/>' + "</ObjectComplementOf>" * n
                    + "</SubClassOf></Ontology>\n")


SYNTAXES = ["turtle-blank-nodes", "turtle-collections", "ofn", "rdfxml", "owlxml"]


@pytest.mark.parametrize("syntax", SYNTAXES)
def test_deep_nesting_is_exit_2(syntax: str, capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    """100,000 levels: refused at its line by validate and convert, never a RecursionError."""
    suffix, text = _deep(syntax, 100_000)
    path = tmp_path / f"deep{suffix}"
    path.write_text(text)
    for argv in (["validate", str(path)], ["convert", str(path), "-o", str(tmp_path / "out.ttl")]):
        code, err = _run(argv, capsys)
        _refused(code, err, "KITKB_MAX_NESTING", f"{path}:{2 if syntax != 'rdfxml' and syntax != 'owlxml' else 3}")
        assert "nested too deep" in err


@pytest.mark.parametrize("syntax", SYNTAXES)
def test_nesting_limit_override(syntax: str, monkeypatch: pytest.MonkeyPatch,
                                capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    suffix, text = _deep(syntax, 12)
    path = tmp_path / f"deep{suffix}"
    path.write_text(text)
    monkeypatch.setenv("KITKB_MAX_NESTING", "8")
    code, err = _run(["validate", str(path)], capsys)
    _refused(code, err, "KITKB_MAX_NESTING", f"{path}:{2 if 'xml' not in syntax else 3}")
    monkeypatch.setenv("KITKB_MAX_NESTING", "40")
    assert main(["validate", str(path)]) in (0, 1)


@pytest.mark.parametrize("syntax", SYNTAXES)
def test_nesting_just_under_the_limit_converts_to_turtle(syntax: str, capsys: pytest.CaptureFixture[str],
                                                         tmp_path: Path) -> None:
    """rdflib's Turtle writer recurses about five frames a level: kitkb makes room for it."""
    depth = limits.NESTING.default - 5
    suffix, text = _deep(syntax, depth // 2 if syntax == "rdfxml" else depth)
    path = tmp_path / f"deep{suffix}"
    path.write_text(text)
    code, err = _run(["convert", str(path), "-o", str(tmp_path / "out.ttl")], capsys)
    assert code == 0, err


def test_nesting_in_strings_and_comments_does_not_count(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    path = tmp_path / "a.ttl"
    path.write_text(EX + '# ((((((((((\nex:a ex:p "[[[[[[[[[[", """((((\n((((((""", <http://ex.org/x#((((((((((> .\n')
    monkeypatch.setenv("KITKB_MAX_NESTING", "2")
    assert main(["validate", str(path)]) in (0, 1)


# --- CRCL ----------------------------------------------------------------------------------------

def test_crcl_text_commands(monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str],
                            tmp_path: Path) -> None:
    path = tmp_path / "p.crcl"
    path.write_text("# a comment\n" + PROGRAM)
    monkeypatch.setenv("KITKB_MAX_CRCL_COMMANDS", "3")
    code, err = _run(["crcl", "convert", str(path), "-o", str(tmp_path / "p.xml")], capsys)
    _refused(code, err, "KITKB_MAX_CRCL_COMMANDS", f"{path}:5")
    assert not (tmp_path / "p.xml").exists()


def test_crcl_statement_length(monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str],
                               tmp_path: Path) -> None:
    path = tmp_path / "p.crcl"
    path.write_text(PROGRAM.replace('"hello"', '"' + "x" * 50 + '"'))
    monkeypatch.setenv("KITKB_MAX_LITERAL", "50")
    code, err = _run(["crcl", "convert", str(path), "-o", str(tmp_path / "p.xml")], capsys)
    _refused(code, err, "KITKB_MAX_LITERAL", f"{path}:4")
    # a statement over several lines is stopped while it is read
    path.write_text("InitCanon()\nMoveThroughTo(\n" + "{{1, 2, 3}, {0, 0, 1}, {1, 0, 0}},\n" * 10 + "10)\nEndCanon()\n")
    code, err = _run(["crcl", "convert", str(path), "-o", str(tmp_path / "p.xml")], capsys)
    _refused(code, err, "KITKB_MAX_LITERAL", f"{path}:2")


@pytest.mark.parametrize("stream", [False, True])
def test_crcl_xml_commands(stream: bool, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str],
                           tmp_path: Path) -> None:
    path = tmp_path / "p.xml"
    path.write_bytes(write_xml(read_text(PROGRAM)))
    if stream:
        monkeypatch.setattr(crcl_xml, "STREAM_FROM", 0)
    monkeypatch.setenv("KITKB_MAX_CRCL_COMMANDS", "3")
    code, err = _run(["crcl", "convert", str(path), "-o", str(tmp_path / "p.crcl")], capsys)
    line = next(i for i, text in enumerate(path.read_text().splitlines(), 1) if "<Message>" in text)
    _refused(code, err, "KITKB_MAX_CRCL_COMMANDS", f"{path}:{line}")


def test_crcl_xml_deep_nesting(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    path = tmp_path / "p.xml"
    path.write_text("<CRCLProgram>\n<InitCanon/>\n" + "<Dwell>" * 100_000 + "</Dwell>" * 100_000
                    + "\n<EndCanon/>\n</CRCLProgram>\n")
    code, err = _run(["crcl", "convert", str(path), "-o", str(tmp_path / "p.crcl")], capsys)
    assert code == 2 and len(err.splitlines()) == 1 and err.startswith(f"{path}:3: error: XML syntax error"), err


def _variants() -> list[str]:
    return ["InitCanon()\n" + "".join(f"Dwell({i})\nMoveTo({{{{{i}, 2, 3}}, {{0, 0, 1}}, {{1, 0, 0}}}})\n"
                                       for i in range(n)) + "EndCanon()\n" for n in (1, 2, 3, 7)]


@pytest.mark.parametrize("chunk", [1, 2, 3, 5])
def test_crcl_xml_in_chunks_is_the_same(chunk: int, monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    """Written and read a chunk at a time: the same bytes, the same program, the same errors."""
    xsd = schema(default_xsd()) if default_xsd() else None
    for text in _variants():
        program = read_text(text)
        whole = write_xml(program, xsd)
        path = tmp_path / "p.xml"
        path.write_bytes(whole)
        read_whole = read_xml(path, xsd)
        monkeypatch.setattr(crcl_xml, "CHUNK", chunk)
        monkeypatch.setattr(crcl_xml, "STREAM_FROM", 0)
        assert write_xml(program, xsd) == whole
        assert read_xml(path, xsd) == read_whole == program
        bad = whole.replace(b"<DwellTime>0.0</DwellTime>", b"<DwellTime>x</DwellTime>")
        path.write_bytes(bad)
        with pytest.raises(InputError) as streamed:
            read_xml(path, xsd)
        monkeypatch.setattr(crcl_xml, "STREAM_FROM", 10**12)
        with pytest.raises(InputError) as at_once:
            read_xml(path, xsd)
        assert streamed.value.line == at_once.value.line
        monkeypatch.setattr(crcl_xml, "CHUNK", 10_000)


@pytest.mark.slow
def test_a_long_crcl_program_converts_in_bounded_memory(tmp_path: Path) -> None:
    """Text -> XML -> text of a 250,000-line program in a child process, both ways under 0.6 GB
    peak (a million lines: 0.74 GB and 0.55 GB measured; it was 4.4 GB / 3.0 GB with the whole
    text and element tree in memory, about 1.1 GB at this size)."""
    lines = ["MoveTo({{9,8,2}, {0,0,1}, {1,0,0}})", "Dwell(1.7)", "OpenGripper()", "CloseGripper()"]  # NIST's layout
    text = tmp_path / "big.crcl"
    with open(text, "w") as f:
        f.write("InitCanon()\n")
        for i in range(250_000 - 2):
            f.write(lines[i % 4] + "\n")
        f.write("EndCanon(0)\n")
    # kitkb in a fresh parent that reports its one child's peak (this process's own children's
    # peak would count every child an earlier test of this worker started)
    measure = ("import resource, subprocess, sys; done = subprocess.run(sys.argv[1:], capture_output=True, text=True); "
               "print(done.returncode, resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss); "
               "print(done.stdout + done.stderr)")
    kitkb = [sys.executable, "-c", "from kb.cli import run; run()"]
    for source, target in ((text, tmp_path / "big.xml"), (tmp_path / "big.xml", tmp_path / "back.crcl")):
        done = subprocess.run([sys.executable, "-c", measure, *kitkb, "crcl", "convert", str(source), "-o", str(target)],
                              capture_output=True, text=True, env={**os.environ, "PYTHONPATH": str(ROOT)})
        code, peak_kib = map(int, done.stdout.split("\n", 1)[0].split())
        assert code == 0, done.stdout
        assert "250000 commands" in done.stdout
        assert peak_kib * 1024 < 0.6e9, f"{source.name} -> {target.name}: peak {peak_kib * 1024 / 1e9:.2f} GB"
    assert (tmp_path / "back.crcl").read_text() == text.read_text()


# --- scenarios -------------------------------------------------------------------------------

def test_parts(monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    monkeypatch.setenv("KITKB_MAX_PARTS", "10")
    code, err = _run(["scenario", "generate", "--parts", "11", "-o", str(tmp_path / "s")], capsys)
    assert code == 2 and len(err.splitlines()) == 1, err
    assert "KITKB_MAX_PARTS" in err and "--parts 11" in err
    assert not (tmp_path / "s").exists()


def test_parts_past_the_machine_refused_at_once(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    code, err = _run(["scenario", "generate", "--parts", str(10**12), "-o", str(tmp_path / "s")], capsys)
    assert code == 2 and re.fullmatch(r"error: --parts 1,000,000,000,000: over the limit on parts in a generated "
                                      r"scenario \([\d,]+ parts; set KITKB_MAX_PARTS to raise it\)", err), err
