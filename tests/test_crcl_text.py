"""CRCL's two text forms (issue 26, point 3): NIST's kittingViewer form (``MoveThroughTo({ pose,``
newline ``pose }, n)``) and the first paper's Fig. 11 form (``MoveThroughTo(pose, pose, n)``) read
alike, kitkb writes NIST's by default and NIST's parser (emulated from its source in
``nist_crcl_parser``) reads it as kitkb does, the same program as NIST text, paper text and XML
gives the same metrics through both of kitkb's readers, and a file of which nothing is understood
is refused."""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import nist_crcl_parser as nist
from kb.cli import build_parser, main
from kb.core.errors import InputError
from kb.crcl import (ANGLE_UNITS, LENGTH_UNITS, CloseGripper, CloseToolChanger, Dwell, EndCanon, InitCanon, Message,
                     MoveStraightTo, MoveThroughTo, MoveTo, OpenGripper, OpenToolChanger, Pose, Program,
                     SetAbsoluteAcceleration, SetAbsoluteSpeed, SetAngleUnits, SetCoordinateFrame,
                     SetEndAngleTolerance, SetEndPointTolerance, SetIntermediatePointTolerance, SetLengthUnits,
                     SetRelativeAcceleration, SetRelativeSpeed, StartObjectScan, StopMotion, StopObjectScan,
                     Unreadable, read_file, read_text, read_xml, write_text)
from kb.crcl.text import NIST_LINE_BYTES, TEXT_STYLES, nist_unwritable
from kb.execution.scoring import crcl_lines
from kb.metrics import read_steps, static_metrics, steps_of, text_steps
from shared_data import NIST_DIR

DATA = Path(__file__).parent / "data" / "crcl_text"
NIST_FORM, PAPER_FORM, XML_FORM = DATA / "nist-form.crcl", DATA / "paper-form.crcl", DATA / "program.xml"
FIG11 = Path(__file__).parent / "data" / "fig11.crcl"
KITTINGVIEWER = NIST_DIR / "kittingViewer-commands1.crcl"
COMMANDS1 = NIST_DIR / "commands1.xml"
needs_nist = pytest.mark.skipif(not KITTINGVIEWER.exists() or not COMMANDS1.exists(),
                                reason="NIST's CRCL files not present")

#: The tool tip's points in the data files' program, in metres (the robot starts at the origin).
POINTS = [(0, 0, 0), (0.8, 0.4, 0.6), (0.8, 0.4, 0.1525), (0.8, 0.4, 0.6), (1.35, -0.2, 0.6), (1.35, -0.2, 0.2075),
          (1.35, -0.2, 0.6), (0.9, 0.35, 0.6), (0.9, 0.35, 0.1525), (0.9, 0.35, 0.6), (1.4, -0.15, 0.6),
          (1.4, -0.15, 0.2075), (0.5, 0, 1.0)]
#: Where each command of nist-form.crcl starts (a MoveThroughTo at its first line).
NIST_FORM_LINES = [1, 2, 3, 4, 5, 6, 8, 10, 11, 12, 15, 16, 17, 18, 19, 20, 21, 22, 25, 26, 27]


def _pose(x: float, y: float, z: float, k: float = -1) -> Pose:
    return Pose(point=(x, y, z), z_axis=(0, 0, k), x_axis=(1, 0, 0))


def _metrics(path: Path) -> dict:
    return static_metrics(read_steps(path)).totals


def _nist_reads(text: str) -> tuple[list, int]:
    return nist.parse(text.encode())


def _as_nist(program: Program) -> list[tuple]:
    """What NIST's parser should read for ``program`` (nist.parse's shape)."""
    out: list[tuple] = []
    for c in program:
        name = type(c).__name__
        if isinstance(c, MoveThroughTo):
            out.append((name, tuple((*p.point, *p.z_axis, *p.x_axis) for p in c.waypoints)))
        elif isinstance(c, (MoveTo, MoveStraightTo)):
            p = c.end_position
            out.append((name, (*p.point, *p.z_axis, *p.x_axis)))
        elif isinstance(c, Message):
            out.append((name, c.message))
        elif isinstance(c, (SetLengthUnits, SetAngleUnits)):
            out.append((name, c.unit_name))
        elif isinstance(c, EndCanon):
            out.append((name, c.reason))
        elif isinstance(c, (InitCanon, OpenGripper, CloseGripper, OpenToolChanger, CloseToolChanger)):
            out.append((name,))
        else:
            out.append((name, next(v for k, v in vars(c).items() if k != "line")))
    return out


# --- reading both forms -------------------------------------------------------------------------

def test_nist_form_paper_form_and_xml_are_one_program() -> None:
    nist_form, paper_form, xml = read_text(NIST_FORM), read_text(PAPER_FORM), read_xml(XML_FORM)
    assert nist_form == paper_form == xml and not nist_form.unreadable and len(nist_form) == 21
    assert [c.line for c in nist_form] == NIST_FORM_LINES
    assert nist_form[6] == MoveThroughTo([_pose(0.8, 0.4, 0.6), _pose(0.8, 0.4, 0.1525)])
    assert nist_form[14] == MoveThroughTo([_pose(900, 350, 600)])  # one pose in braces on one line
    assert nist_form[13] == SetLengthUnits("millimeter")  # "millimeter" in NIST's form, "mm" in the paper's
    turned = nist_form[17].waypoints[1]
    assert turned.z_axis == (0.0, -0.7071067811865476, -0.7071067811865476)


def test_the_same_program_gives_the_same_metrics_in_all_three_forms_and_both_readers() -> None:
    tdm = sum(math.dist(a, b) for a, b in zip(POINTS, POINTS[1:]))
    totals = []
    for path in (NIST_FORM, PAPER_FORM, XML_FORM):
        steps = read_steps(path)  # the fast reader for .crcl
        assert steps == steps_of(read_file(path)), path  # ... which does not diverge from kb.crcl
        totals.append(static_metrics(steps).totals)
    assert totals[0] == totals[1] == totals[2]
    assert totals[0]["TDM"] == pytest.approx(tdm, rel=1e-12)
    assert (totals[0]["PE"], totals[0]["TE"], totals[0]["ACE"], totals[0]["TCE"]) == (0, 0, 13, 21)


@needs_nist
def test_nists_kittingviewer_file_is_read_whole_and_measured_as_its_xml() -> None:
    program = read_text(KITTINGVIEWER)
    xml = read_xml(COMMANDS1)
    assert not program.unreadable and len(program) == len(xml) == 41
    # CRCL.xsd's EndCanon has no reason; the kittingViewer's file ends EndCanon(2)
    assert program[:-1] == xml[:-1] and program[-1] == EndCanon(2) and xml[-1] == EndCanon(0)
    moves = [c.line for c in program if isinstance(c, MoveThroughTo)]
    assert len(moves) == 17 and moves[:3] == [9, 12, 16]
    paper_steps = list(text_steps(write_text(program, style="paper").split("\n")))  # the paper's form
    fast = read_steps(KITTINGVIEWER)
    assert fast == steps_of(program)
    by_form = [static_metrics(s).totals for s in (fast, paper_steps, read_steps(COMMANDS1))]
    assert by_form[0] == by_form[1] == by_form[2]
    assert round(by_form[0]["TDM"], 2) == 60.53 and by_form[0]["PE"] == 0


@needs_nist
def test_kitkb_metrics_on_nists_text_file(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["metrics", str(KITTINGVIEWER), "--format", "json", "--per-command"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert round(data["metrics"]["TDM"], 2) == 60.53 and data["metrics"]["PE"] == 0
    assert [r["line"] for r in data["rows"]][6:10] == [7, 9, 11, 12]  # a MoveThroughTo at its first line


def test_a_command_over_several_lines_keeps_its_first_line(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["metrics", str(NIST_FORM), "--format", "json", "--per-command"]) == 0
    rows = json.loads(capsys.readouterr().out)["rows"]
    assert [r["line"] for r in rows] == NIST_FORM_LINES
    assert rows[6]["command"] == "MoveThroughTo(2 poses to 0.8, 0.4, 0.1525)"
    # an unreadable statement over three lines: one parse error, at its first line, in the rows
    # and in the error of a command that cannot take it
    text = NIST_FORM.read_text().replace("{1,0,0}} }, 3)", "{1,0,0}} }, 4)", 1)
    bad = tmp_path / "bad.crcl"
    bad.write_text(text)
    program = read_text(bad)
    assert program.unreadable == (Unreadable(text.split("\n", 11)[11].split("\nOpenGripper")[0]),)
    assert program.unreadable[0].line == 12 and program.unreadable[0].reason == "4 poses announced, 3 given"
    assert read_steps(bad) == steps_of(program)
    assert main(["metrics", str(bad), "--format", "json", "--per-command"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["metrics"]["PE"] == 1
    assert [(r["line"], r["notes"]) for r in data["rows"] if r["PE"] == 1][0] == (
        12, ["parse error: 4 poses announced, 3 given"])
    assert main(["crcl", "convert", str(bad), "-o", str(tmp_path / "bad.xml")]) == 2
    assert capsys.readouterr().err.startswith(f"{bad}:12: error: unreadable line 'MoveThroughTo({{ {{{{0.8,0.4,0.6}}")


def test_other_layouts_nists_parser_documents_and_c_numbers() -> None:
    # the layout of NIST's parser's own comment and of its commandsWithErrors file: {{{ and }}}
    text = ("MoveThroughTo({{{7,0,0},{0,0,1},{1,0,0}},\n"
            "               {{7,8,0},{0,0,1},{1,0,0}}},2)\n"
            "Dwell(0x1.8p1)\nSetAbsoluteSpeed(.5)\nSetRelativeSpeed(5.)\nSetEndPointTolerance(+1E-3)\n")
    program = read_text(text)
    assert program == Program([MoveThroughTo([_pose(7, 0, 0, 1), _pose(7, 8, 0, 1)]), Dwell(3.0),
                               SetAbsoluteSpeed(0.5), SetRelativeSpeed(5.0), SetEndPointTolerance(0.001)])
    assert list(text_steps(text.split("\n"))) == steps_of(program)
    assert _nist_reads(text) == (_as_nist(program), 0)


# --- NIST's parser, emulated --------------------------------------------------------------------

@needs_nist
def test_the_emulated_nist_parser_reads_nists_file_and_refuses_the_papers_form() -> None:
    """Anchors of the emulation: NIST's parser, compiled from its source, reported 0 parse
    errors on its own file and 5 on Fig. 11 (the three lines of its paper-form MoveThroughTo,
    ``"mm"`` and ``MoveStraightTo(87)``)."""
    commands, errors = nist.parse(KITTINGVIEWER.read_bytes())
    assert errors == 0 and commands == _as_nist(read_text(KITTINGVIEWER))
    commands, errors = nist.parse(FIG11.read_bytes())
    assert errors == 5
    assert [c[0] for c in commands].count("Unreadable") == 5
    assert [i for i, c in enumerate(commands) if c[0] == "Unreadable"] == [8, 9, 10, 20, 24]
    assert nist.parse(PAPER_FORM.read_bytes())[1] == 10  # the paper's form: NIST's parser refuses it
    assert nist.parse(write_text(read_text(FIG11), style="paper").encode())[1] == 3


def test_kitkbs_nist_form_is_what_nists_parser_reads() -> None:
    program = read_text(NIST_FORM)
    text = write_text(program)
    assert text == write_text(program, style="nist")
    assert _nist_reads(text) == (_as_nist(program), 0)
    assert read_text(text) == program
    assert text.split("\n")[6:9] == ["MoveThroughTo({ {{0.8,0.4,0.6}, {0,0,-1}, {1,0,0}},",
                                     "  {{0.8,0.4,0.1525}, {0,0,-1}, {1,0,0}} }, 2)", "CloseGripper()"]
    assert 'SetLengthUnits("millimeter")' in text and "MoveThroughTo({ {{900,350,600}, {0,0,-1}, {1,0,0}} }, 1)" in text
    # the paper's form of the same program: NIST's parser refuses its MoveThroughTo and "mm"
    assert _nist_reads(write_text(program, style="paper"))[1] == 5


@needs_nist
def test_kitkb_writes_nists_file_as_the_kittingviewer_does() -> None:
    written = write_text(read_xml(COMMANDS1)).split("\n")
    original = KITTINGVIEWER.read_text().split("\n")
    starts = [i for i, line in enumerate(original) if line.startswith("MoveThroughTo")]
    mine = [i for i, line in enumerate(written) if line.startswith("MoveThroughTo")]
    assert len(starts) == len(mine) == 17
    for a, b in zip(starts, mine):  # every MoveThroughTo line for line
        end = original.index(next(l for l in original[a:] if l.endswith(")")), a)
        assert written[b:b + end - a + 1] == original[a:end + 1]


_num = st.floats(allow_nan=False, allow_infinity=False)
_vec = st.tuples(_num, _num, _num)
_pose_st = st.builds(Pose, point=_vec, x_axis=_vec, z_axis=_vec)
_message = st.text(st.characters(codec="utf-8", exclude_characters='"\n\r\x00\\'), min_size=1, max_size=30)
_NIST_COMMAND = st.one_of(
    st.builds(Message, _message), st.builds(Dwell, _num), st.builds(MoveTo, _pose_st),
    st.builds(MoveStraightTo, _pose_st), st.builds(MoveThroughTo, st.lists(_pose_st, min_size=1, max_size=4)),
    st.sampled_from([InitCanon(), OpenGripper(), CloseGripper(), OpenToolChanger(), CloseToolChanger()]),
    st.builds(EndCanon, st.integers(-2 ** 31, 2 ** 31 - 1)),
    st.builds(SetLengthUnits, st.sampled_from(LENGTH_UNITS)), st.builds(SetAngleUnits, st.sampled_from(ANGLE_UNITS)),
    *(st.builds(cls, _num) for cls in (SetAbsoluteSpeed, SetRelativeSpeed, SetAbsoluteAcceleration,
                                       SetRelativeAcceleration, SetEndAngleTolerance, SetEndPointTolerance,
                                       SetIntermediatePointTolerance)))


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(_NIST_COMMAND, min_size=1, max_size=8))
def test_any_program_nists_form_holds_is_read_by_nists_parser_as_kitkb_reads_it(commands: list) -> None:
    program = Program(commands)
    try:
        text = write_text(program)
    except InputError as err:  # only a line too long for NIST's buffer, even spelt compactly
        assert f"more than the {NIST_LINE_BYTES} NIST's parser reads on a line" in str(err)
        assert any(nist_unwritable(c) for c in commands)
        return
    assert max(len(line.encode()) for line in text.split("\n")) <= NIST_LINE_BYTES
    assert _nist_reads(text) == (_as_nist(program), 0)
    back = read_text(text)
    assert back == program
    assert list(text_steps(text.split("\n"))) == steps_of(back)


def test_a_long_pose_is_spelt_compactly_to_fit_nists_line_and_refused_when_it_cannot() -> None:
    third = 0.30000000000000004  # 19 characters, as computed targets often are
    long = MoveStraightTo(Pose(point=(third, -third, third), z_axis=(third, third, -third),
                               x_axis=(-0.7071067811865476, 0.7071067811865476, third)))
    assert len(write_text(Program([long]), style="paper").rstrip("\n")) > NIST_LINE_BYTES
    text = write_text(Program([long]))
    assert text == ("MoveStraightTo({{.30000000000000004,-.30000000000000004,.30000000000000004},"
                    "{.30000000000000004,.30000000000000004,-.30000000000000004},"
                    "{-.7071067811865476,.7071067811865476,.30000000000000004}})\n")
    assert _nist_reads(text) == (_as_nist(Program([long])), 0) and read_text(text) == Program([long])
    tiny = -1.2345678901234567e-100
    too_long = MoveTo(Pose(point=(tiny,) * 3, z_axis=(tiny,) * 3, x_axis=(tiny,) * 3), line=7)
    with pytest.raises(InputError) as err:
        write_text(Program([too_long], source="p.crcl"))
    assert str(err.value) == (
        "p.crcl:7: error: MoveTo needs a line of 240 bytes, more than the 198 NIST's parser reads on a line "
        "(its 200-byte line buffer); NIST's CRCL text form cannot hold it (the paper's form can: --text-style paper)")
    assert read_text(write_text(Program([too_long]), style="paper")) == Program([too_long])


@pytest.mark.parametrize("command, why", [
    (SetCoordinateFrame("ToolTip"), "SetCoordinateFrame is not a command of NIST's CRCL text form"),
    (StartObjectScan("part_a_1"), "StartObjectScan is not a command of NIST's CRCL text form"),
    (StopObjectScan(), "StopObjectScan is not a command of NIST's CRCL text form"),
    (StopMotion(1), "StopMotion is not a command of NIST's CRCL text form"),
    (Message(""), "an empty Message"),
    (Message('say "hi"'), "a Message holding a double quote"),
    (Message("two\nlines"), "a Message holding a line break"),
    (Message("C:\\new"), "a Message holding a backslash that kitkb reads as an escape"),
    (Message("ends in \\"), "a Message holding a backslash that kitkb reads as an escape"),
    (EndCanon(2 ** 31), "EndCanon(2147483648): NIST's parser reads the reason as a C int"),
])
def test_what_nists_form_cannot_hold_is_refused_at_its_line(command, why: str, tmp_path: Path,
                                                            capsys: pytest.CaptureFixture[str]) -> None:
    program = Program([InitCanon(line=1), type(command)(*[v for k, v in vars(command).items() if k != "line"],
                                                        line=3), EndCanon(line=4)], source="p.crcl")
    with pytest.raises(InputError) as err:
        write_text(program)
    message = str(err.value)
    assert message.startswith(f"p.crcl:3: error: {why}") and "\n" not in message
    assert message.endswith("NIST's CRCL text form cannot hold it (the paper's form can: --text-style paper)")
    assert read_text(write_text(program, style="paper")) == program  # the paper's form holds it
    # the command line: exit 2, one line, nothing written; --text-style paper writes it
    source = tmp_path / "p.crcl"
    source.write_text(write_text(program, style="paper"))
    out = tmp_path / "out.crcl"
    assert main(["crcl", "convert", str(source), "-o", str(out)]) == 2
    err_line = capsys.readouterr().err
    assert err_line.startswith(f"{source}:2: error: {why}") and err_line.count("\n") == 1 and not out.exists()
    assert main(["-q", "crcl", "convert", str(source), "-o", str(out), "--text-style", "paper"]) == 0
    assert read_text(out) == program


def test_a_message_nists_parser_reads_as_it_stands() -> None:
    program = Program([Message("take part_a_1 from C:\\data (tray 2) {left}, then wait  ")])
    text = write_text(program)
    assert text == 'Message("take part_a_1 from C:\\data (tray 2) {left}, then wait  ")\n'
    assert _nist_reads(text) == (_as_nist(program), 0) and read_text(text) == program


def test_unreadable_lines_are_written_back_in_either_form() -> None:
    program = read_text(FIG11)
    for style in TEXT_STYLES:
        text = write_text(program, style=style)
        assert "MoveStraightTo(87)\n" in text and read_text(text) == program


# --- kb.metrics' fast reader against kb.crcl ----------------------------------------------------

TRICKY = [
    "MoveThroughTo({ {{1,2,3}, {0,0,1}, {1,0,0}},\n\n  {{1,2,4}, {0,0,1}, {1,0,0}} }, 2)\nCloseGripper()\n",
    "MoveThroughTo({ {{1,2,3}, {0,0,1}, {1,0,0}},\n# a comment\n  {{1,2,4}, {0,0,1}, {1,0,0}} }, 2)\n",
    "MoveThroughTo({ {{1,2,3}, {0,0,1}, {1,0,0}},\n  {{1,2,4}, {0,0,1}, {1,0,0}} }, 3)\nOpenGripper()\n",
    "MoveThroughTo({ {{1,2,3}, {0,0,1}, {1,0,0}},\nOpenGripper()\n  {{1,2,4}, {0,0,1}, {1,0,0}} }, 2)\n",
    "MoveThroughTo({ {{1,2,3}, {0,0,1}, {1,0,0}},\n  {{1,2,4}, {0,0,1}, {1,0,0}},",
    "MoveThroughTo({ {{1,2,3}, {0,0,1}, {1,0,0}},\n  {{1,2,4}, {0,0,1}, {1,0,0}} }, 2) junk\nDwell(1)\n",
    "MoveThroughTo({ {{1,2,3}, {0,0,1}, {1,0,0}},\r\n\t{{1,2,4},{0,0,1},{1,0,0}}\t}\t,\t2\t)\r\n",
    "MoveThroughTo({ {{1e999,2,3}, {0,0,1}, {1,0,0}},\n  {{1,2,4}, {0,0,1}, {1,0,0}} }, 2)\n",
    "MoveThroughTo({ {{1,2,3}, {0,0,1}, {1,0,0}},\n  {{1e308,2,4}, {0,0,1}, {1e308,0,0}} }, 2)\n",
    "MoveThroughTo({ {{1,2,3}, {0,0,1}, {1,0,0}}, {{1,2,4}, {0,0,1}, {1,0,0}} }, 2)\n",
    "MoveThroughTo({{1e308,2,3}, {0,0,1}, {1e308,0,0}}, {{1,2,4}, {0,0,1}, {1,0,0}}, 2)\n",
    "Dwell(1)\nMoveThroughTo({ {{1,2,3}, {0,0,1}, {1,0,0}},\n  {{1,2,4}, {0,0,1}, {1,0,0}} }, 2)\n",
    "Message(\"open\nMoveThroughTo({ {{1,2,3}, {0,0,1}, {1,0,0}},\n  {{1,2,4}, {0,0,1}, {1,0,0}} }, 2)\n",
    "MoveThroughTo({ {{1,2,3}, {0,0,1}, {1,0,0}},\n  {{1,2,4}, {0,0,1}, {1,0,0}},\n  {{1,2,5}, {0,0,1}, {1,0,0}},\n",
    "MoveThroughTo ( { {{1,2,3}, {0,0,1}, {1,0,0}} ,\n  {{1,2,4}, {0,0,1}, {1,0,0}} } , 2 )\n",
]


@pytest.mark.parametrize("text", TRICKY)
def test_fast_reader_reads_tricky_nist_text_as_kb_crcl(text: str, tmp_path: Path) -> None:
    path = tmp_path / "p.crcl"
    path.write_bytes(text.encode())
    assert read_steps(path) == steps_of(read_text(path))


def test_nists_form_is_measured_by_the_fast_reader_alone() -> None:
    import subprocess
    import sys
    code = ("import sys; from kb.metrics import program_metrics; "
            f"m = program_metrics({str(NIST_FORM)!r}); print(m.totals['PE'], 'kb.crcl' in sys.modules)")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert done.stdout.split() == ["0", "False"]  # no line of it went to kb.crcl


def test_fast_reader_gives_a_long_statement_to_kb_crcl(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("KITKB_MAX_LITERAL", "120")
    path = tmp_path / "p.crcl"
    path.write_text("InitCanon()\nMoveThroughTo({ {{1,2,3}, {0,0,1}, {1,0,0}},\n" + "  {{1,2,4}, {0,0,1}, {1,0,0}},\n" * 3
                    + "  {{1,2,5}, {0,0,1}, {1,0,0}} }, 5)\n")
    for read in (read_steps, read_text):
        with pytest.raises(InputError, match=r"p\.crcl:2: error: .*a statement of more than 120"):
            read(path)


_LINE_EDITS = st.lists(st.tuples(st.sampled_from(["delete", "duplicate", "blank", "comment", "truncate", "join",
                                                  "split"]), st.integers(0, 40), st.integers(0, 60)), max_size=4)


@settings(max_examples=120, deadline=None, suppress_health_check=[HealthCheck.too_slow,
                                                                  HealthCheck.function_scoped_fixture])
@given(_LINE_EDITS)
def test_fast_reader_and_kb_crcl_agree_on_mangled_nist_text(tmp_path: Path, edits: list) -> None:
    lines = NIST_FORM.read_text().split("\n")
    for what, at, cut in edits:
        at %= len(lines)
        if what == "delete":
            del lines[at]
        elif what == "duplicate":
            lines.insert(at, lines[at])
        elif what == "blank":
            lines.insert(at, "")
        elif what == "comment":
            lines.insert(at, "// a comment")
        elif what == "truncate":
            lines[at] = lines[at][:cut]
        elif what == "join" and at + 1 < len(lines):
            lines[at:at + 2] = [lines[at] + " " + lines[at + 1]]
        elif what == "split":
            lines[at:at + 1] = [lines[at][:cut], lines[at][cut:]]
        if not lines:
            lines = [""]
    path = tmp_path / "mangled.crcl"
    path.write_text("\n".join(lines))
    assert read_steps(path) == steps_of(read_text(path))


# --- nothing understood -------------------------------------------------------------------------

@pytest.mark.parametrize("content, line, start", [
    ("move to the tray\nthen grasp it\n", 1, "none of its 2 statement(s) is a CRCL command kitkb reads (the first "
                                             "at this line: expected Name(arguments)); looked for CRCL commands"),
    ("\n# only comments\n// and blank lines\n\n", None, "no CRCL command in it: looked for CRCL commands"),
    ("", None, "no CRCL command in it: looked for CRCL commands"),
    ("initCannon()\nMoveTo({{1, 2, 3}})\n", 1, "none of its 2 statement(s) is a CRCL command kitkb reads (the first "
                                               "at this line: unknown command initCannon)"),
])
def test_a_file_of_which_nothing_is_understood_is_refused(content: str, line: int | None, start: str, tmp_path: Path,
                                                          capsys: pytest.CaptureFixture[str]) -> None:
    path = tmp_path / "p.crcl"
    path.write_text(content)
    where = f"{path}:{line}" if line else f"{path}"
    for argv in (["metrics", str(path)], ["metrics", str(path), "--format", "json"],
                 ["crcl", "convert", str(path), "-o", str(tmp_path / "out.xml")],
                 ["crcl", "convert", str(path), "-o", str(tmp_path / "out.crcl")]):
        assert main(argv) == 2
        captured = capsys.readouterr()
        assert captured.err.startswith(f"{where}: error: {start}") and captured.err.count("\n") == 1, argv
        assert "NIST's kittingViewer form or the first paper's Fig. 11" in captured.err
        assert captured.out == ""
    assert not (tmp_path / "out.xml").exists() and not (tmp_path / "out.crcl").exists()


def test_a_file_with_some_unreadable_lines_is_measured_with_its_parse_errors(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["metrics", str(FIG11), "--format", "json"]) == 0
    assert json.loads(capsys.readouterr().out)["metrics"]["PE"] == 1


# --- the option, and the text a run reports -----------------------------------------------------

def test_text_style_option(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    action = next(a for a in build_parser()._subparsers._group_actions[0].choices["crcl"]._subparsers
                  ._group_actions[0].choices["convert"]._actions if a.dest == "text_style")
    assert tuple(action.choices) == TEXT_STYLES and action.default is None
    nist_out, paper_out = tmp_path / "nist.crcl", tmp_path / "paper.crcl"
    assert main(["crcl", "convert", str(XML_FORM), "-o", str(nist_out), "--format", "json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["text_style"] == "nist" and "NIST's kittingViewer form" in data["message"]
    assert nist_out.read_text() == write_text(read_xml(XML_FORM))
    assert main(["-q", "crcl", "convert", str(NIST_FORM), "-o", str(paper_out), "--text-style", "paper"]) == 0
    assert paper_out.read_text() == write_text(read_text(NIST_FORM), style="paper")
    assert read_text(paper_out) == read_text(nist_out) == read_xml(XML_FORM)
    assert main(["crcl", "convert", str(NIST_FORM), "-o", str(tmp_path / "x.xml"), "--text-style", "nist"]) == 2
    assert capsys.readouterr().err.endswith("error: --text-style chooses the layout of CRCL text (.crcl); "
                                            f"{tmp_path / 'x.xml'} is CRCL XML\n")
    assert not (tmp_path / "x.xml").exists()
    with pytest.raises(ValueError, match="unknown CRCL text style 'fig11'"):
        write_text(Program([InitCanon()]), style="fig11")


def test_a_runs_crcl_text_stays_one_line_per_command() -> None:
    program = read_text(NIST_FORM)
    lines = crcl_lines(program)
    assert len(lines) == len(program) and all("\n" not in line for line in lines)
    assert lines[6] == "MoveThroughTo({{0.8, 0.4, 0.6}, {0, 0, -1}, {1, 0, 0}}, {{0.8, 0.4, 0.1525}, {0, 0, -1}, {1, 0, 0}}, 2)"
    assert read_text("\n".join(lines)) == program
    assert re.fullmatch(r"MoveThroughTo\(\{\{.*\}\}, 1\)", lines[14])
