"""CRCL 1.x XML is read beside the 2014 form (a status is refused for what it is), and a schema
given with --xsd finds the files it includes (CRCL 1.x's schemas include each other by relative paths)."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from kb.core.errors import InputError
from kb.crcl import xml as crcl_xml

from shared_data import NIST_DIR as NIST

CRCL = NIST.parent / "crcl"
pytestmark = pytest.mark.skipif(not (CRCL / "schemas" / "CRCLProgramInstance.xsd").exists(),
                                reason="NIST's CRCL 1.x schemas are not beside the checkout")


def test_a_schema_that_includes_files_beside_it_loads_from_any_working_directory(tmp_path, monkeypatch):
    folder = tmp_path / "schemas"
    shutil.copytree(CRCL / "schemas", folder)
    monkeypatch.chdir(tmp_path.parent)  # not the schema's folder: its includes are found from it
    xsd = crcl_xml.schema(folder / "CRCLProgramInstance.xsd")
    from lxml import etree
    assert xsd.validate(etree.parse(str(CRCL / "instances" / "programExample.xml")))


def test_a_schema_whose_include_is_missing_is_one_line_naming_it(tmp_path):
    (tmp_path / "CRCLProgramInstance.xsd").write_bytes((CRCL / "schemas" / "CRCLProgramInstance.xsd").read_bytes())
    with pytest.raises(InputError) as err:
        crcl_xml.schema(tmp_path / "CRCLProgramInstance.xsd")
    assert "\n" not in err.value.message and ".xsd" in err.value.message


@pytest.mark.parametrize("name, count, first", [
    ("programExample.xml", 41, "InitCanon"),
    ("commandMoveTo.xml", 1, "MoveTo"),
])
def test_crcl_1x_documents_are_read_as_programs_in_metres_and_radians(name, count, first):
    program = crcl_xml.read_xml(CRCL / "instances" / name)
    assert len(program) == count and type(program[0]).__name__ == first
    assert program.units == ("meter", "radian")


def test_a_crcl_1x_status_is_refused_for_what_it_is():
    with pytest.raises(InputError) as err:
        crcl_xml.read_xml(CRCL / "instances" / "statusExample.xml")
    assert "CRCL 1.x status" in err.value.message and err.value.line is not None


def test_a_big_crcl_1x_program_is_read_alike(monkeypatch):
    whole = crcl_xml.read_xml(CRCL / "instances" / "programExample.xml")
    monkeypatch.setattr(crcl_xml, "STREAM_FROM", 0)  # every file read as a stream
    assert crcl_xml.read_xml(CRCL / "instances" / "programExample.xml") == whole


def test_nist_early_program_still_reads_both_ways(monkeypatch):
    whole = crcl_xml.read_xml(NIST / "commands1.xml")
    monkeypatch.setattr(crcl_xml, "STREAM_FROM", 0)
    assert crcl_xml.read_xml(NIST / "commands1.xml").commands == whole.commands and whole.commands


def test_kitkb_metrics_on_a_crcl_1x_status_is_exit_2():
    import subprocess
    import sys
    done = subprocess.run([sys.executable, "-m", "kb.cli", "metrics", str(CRCL / "instances" / "statusExample.xml")],
                          capture_output=True, text=True)
    assert done.returncode == 2 and "CRCL 1.x status" in done.stderr and "Traceback" not in done.stderr
