"""The static metrics of a CRCL program (kb.metrics, ``kitkb metrics``): the first paper's own
statements about its Fig. 11, each metric on a small program written for it (expected values
computed by hand), text and XML alike, the fast text reader against kb.crcl, the CLI."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

from kb.cli import main
from kb.crcl import read_file, read_text, write_xml
from kb.metrics import (DEFAULT_WEIGHTS, METRICS, Robot, move_time, program_metrics, read_steps, read_weights,
                        score, static_metrics, steps_of, text_steps)
from kb.core.errors import InputError

DATA = Path(__file__).parent / "data"
FIG11 = DATA / "fig11.crcl"
DOWN = "{0, 0, -1}, {1, 0, 0}"


def run(text: str, robot: Robot | None = None, rows: bool = True):
    """The metrics of CRCL text (read by the metrics' own reader)."""
    return static_metrics(text_steps(text.split("\n")), robot, rows=rows)


def program(*body: str) -> str:
    return "\n".join(["InitCanon()", *body, "EndCanon()"])


def move(x: float, y: float, z: float, kind: str = "MoveTo") -> str:
    return f"{kind}({{{{{x}, {y}, {z}}}, {DOWN}}})"


def by_line(result, line: int):
    return next(r for r in result.rows if r.line == line)


def delta(result, line: int, metric: str) -> float:
    """How much the command at ``line`` added to ``metric``."""
    i = METRICS.index(metric)
    row = by_line(result, line)
    before = result.rows[row.index - 1].values[i] if row.index else 0
    return row.values[i] - before


# --- the paper's Fig. 11 --------------------------------------------------------------------------

def test_fig11_is_the_paper_program_as_test_crcl_has_it() -> None:
    from test_crcl import FIG11 as PRINTED
    assert FIG11.read_text() == PRINTED
    assert read_steps(FIG11) == steps_of(read_text(PRINTED))


def test_fig11_parse_error_is_the_one_unreadable_line() -> None:
    result = program_metrics(FIG11, rows=True)
    assert result.totals["PE"] == 1
    assert [r.line for r in result.rows if r.values[METRICS.index("PE")] - _before(result, r, "PE")] == [25]
    assert by_line(result, 25).command == "MoveStraightTo(87)"
    # evaluation goes on: EndCanon after it is executed
    assert delta(result, 26, "OCE") == 1


def _before(result, row, metric: str) -> float:
    return result.rows[row.index - 1].values[METRICS.index(metric)] if row.index else 0


def test_fig11_set_relative_acceleration_minus_110_is_two_range_errors() -> None:
    result = program_metrics(FIG11, rows=True)
    row = by_line(result, 24)
    assert row.command == "SetRelativeAcceleration(-110)"
    assert delta(result, 24, "RE") == 2
    assert "negative" in row.notes[0] and "more than 100 %" in row.notes[1]


def test_fig11_first_close_gripper_and_close_tool_changer_are_useless() -> None:
    result = program_metrics(FIG11, rows=True)
    assert [by_line(result, n).command for n in (3, 4)] == ["CloseGripper()", "CloseToolChanger()"]
    assert delta(result, 3, "UCE") == 1 and delta(result, 4, "UCE") == 1
    assert delta(result, 14, "UCE") == 0 and delta(result, 15, "UCE") == 0  # OpenGripper, OpenToolChanger
    # kitkb's choice (docs/metrics.md): SetAngleUnits("degree") sets the default unit again
    assert delta(result, 17, "UCE") == 1
    assert result.totals["UCE"] == 3


def test_fig11_has_no_sequence_errors_and_its_totals() -> None:
    result = program_metrics(FIG11)
    tdm = math.sqrt(29) + 8 + 2 + 3 + 5  # from the origin through (5,0,2) (5,8,2) (7,8,2), to (4,8,2), (9,8,2)
    # MoveThroughTo at 50 % of 1 m/s and 10 % of 10 m/s² (the start); MoveStraightTo 3 m and MoveTo 5 m
    # too (3.8 m/s is refused)
    tet = 0.2 + 0.2 + 1.7 + move_time(math.sqrt(29) + 10, 0.5, 1) + move_time(3, 0.5, 1) \
        + move_time(5, 0.5, 1) + 0.2 + 0.2
    assert tet == pytest.approx(0.4 + 1.7 + (math.sqrt(29) + 10) / 0.5 + 0.5 + 6.5 + 10.5 + 0.4)
    assert result.totals == pytest.approx({
        "ACE": 8, "OCE": 13, "TCE": 21, "TDM": tdm, "CCE": 0.0, "TET": tet,
        "RE": 3, "PE": 1, "CSE": 0, "TE": 4, "UCE": 3})
    # SetAbsoluteSpeed(3.8) m/s is a range error only because the default robot's maximum is 1 m/s
    faster = program_metrics(FIG11, Robot(max_speed=4.0))
    assert faster.totals["RE"] == 2 and faster.totals["TE"] == 3
    assert faster.totals["TET"] == pytest.approx(0.2 + 0.2 + 1.7 + move_time(math.sqrt(29) + 10, 3.8, 1)
                                                 + move_time(3, 3.8, 1) + move_time(5, 3.8, 1) + 0.4)


def test_the_robot_starts_at_ten_percent_and_closed() -> None:
    result = run(program('SetLengthUnits("meter")', move(0, 0, 1), "SetRelativeSpeed(10)",
                         "SetAbsoluteAcceleration(1)", "SetEndPointTolerance(0)", "CloseGripper()"),
                 Robot(max_speed=2.0, max_acceleration=10.0))
    assert by_line(result, 3).values[METRICS.index("CCE")] == pytest.approx(move_time(1, 0.2, 1.0))
    assert [delta(result, n, "UCE") for n in (4, 5, 6, 7)] == [1, 1, 1, 1]
    assert by_line(result, 1).settings["relative_speed"] == pytest.approx(10)


def test_rows_show_the_settings_in_the_units_in_force() -> None:
    result = program_metrics(FIG11, rows=True)
    before, after = by_line(result, 20).settings, by_line(result, 21).settings  # SetLengthUnits("mm") at 21
    assert before["length_unit"] == "meter" and after["length_unit"] == "millimeter"
    assert before["end_point_tolerance"] == pytest.approx(0.4) and after["end_point_tolerance"] == pytest.approx(400)
    assert before["speed"] == pytest.approx(0.5) and after["speed"] == pytest.approx(500)
    assert after["position"] == pytest.approx([9000, 8000, 2000])
    assert after["gripper"] == after["tool_changer"] == "open"
    assert by_line(result, 3).settings["gripper"] == "closed"
    assert by_line(result, 24).settings["relative_acceleration"] == pytest.approx(0.8)  # -110 refused


# --- each metric on a program written for it ------------------------------------------------------

def test_move_time_is_a_trapezoid_or_a_triangle() -> None:
    assert move_time(1.0, 0.5, 1.0) == pytest.approx(2.5)  # 0.5 s up, 1.5 s cruising, 0.5 s down
    assert move_time(0.1, 1.0, 10.0) == pytest.approx(0.2)  # just reaches 1 m/s
    assert move_time(0.05, 1.0, 10.0) == pytest.approx(2 * math.sqrt(0.005))  # never reaches it
    assert move_time(0.0, 1.0, 10.0) == 0.0


def test_action_other_and_total_commands() -> None:
    result = run(program("Message(\"hi\")", "Dwell(0.5)", "OpenGripper()", move(0, 0, 1),
                         "SetRelativeSpeed(20)"))
    assert (result.totals["ACE"], result.totals["OCE"], result.totals["TCE"]) == (3, 4, 7)


def test_total_distance_moved_from_the_start_through_every_point() -> None:
    result = run(program('SetLengthUnits("meter")',
                         f"MoveThroughTo({{{{3, 4, 0}}, {DOWN}}}, {{{{3, 4, 2}}, {DOWN}}}, 2)",
                         move(3, 0, 2, "MoveStraightTo")), Robot(start=(0, 0, 0)))
    assert result.totals["TDM"] == pytest.approx(5 + 2 + 4)
    assert by_line(result, 3).values[METRICS.index("TDM")] == pytest.approx(7)
    shifted = run(program('SetLengthUnits("meter")', move(1, 0, 0)), Robot(start=(1, 0, 0)))
    assert shifted.totals["TDM"] == 0 and shifted.totals["UCE"] == 1


def test_execution_times_honour_speed_acceleration_and_units() -> None:
    robot = Robot(max_speed=2.0, max_acceleration=4.0)
    result = run(program('SetLengthUnits("meter")', "SetAbsoluteSpeed(0.5)", "SetAbsoluteAcceleration(1)",
                         'SetLengthUnits("mm")', move(1000, 0, 0),  # 1 m at 0.5 m/s, 1 m/s²: 2.5 s
                         "SetRelativeSpeed(50)", "SetRelativeAcceleration(25)",  # 1 m/s, 1 m/s²
                         move(1000, 0, 100),  # 0.1 m: a triangle, 2 sqrt(0.1) s
                         "Dwell(0.25)", "CloseGripper()", "OpenGripper()"), robot)
    cce = METRICS.index("CCE")
    assert by_line(result, 6).values[cce] == pytest.approx(2.5)
    assert by_line(result, 9).values[cce] == pytest.approx(2 * math.sqrt(0.1))
    assert by_line(result, 10).values[cce] == pytest.approx(0.25)
    assert by_line(result, 7).values[cce] == 0.0  # a setting takes no time
    assert result.totals["TET"] == pytest.approx(2.5 + 2 * math.sqrt(0.1) + 0.25 + 0.2 + 0.2)


def test_range_errors_one_per_bound_broken_and_the_command_is_not_executed() -> None:
    robot = Robot(max_speed=1.0, max_acceleration=10.0)
    result = run(program('SetLengthUnits("meter")',
                         "SetRelativeSpeed(150)",        # 3: more than 100 %
                         "SetRelativeSpeed(-5)",         # 4: negative
                         "SetAbsoluteSpeed(-2)",         # 5: negative, more than 1 m/s
                         "SetAbsoluteAcceleration(11)",  # 6: more than 10 m/s²
                         "Dwell(-1)",                    # 7
                         "SetEndPointTolerance(-0.1)",   # 8
                         "SetEndAngleTolerance(-1)",     # 9
                         "MoveTo({{1, 0, 0}, {0, 0, -2}, {0, 0, 1}})",  # 10: Z not unit, axes not perpendicular
                         "SetRelativeSpeed(0)", "SetRelativeSpeed(100)"), robot)  # 11, 12: in range
    assert [delta(result, n, "RE") for n in range(3, 13)] == [1, 1, 2, 1, 1, 1, 1, 2, 0, 0]
    assert result.totals["RE"] == 10
    assert [delta(result, n, "TCE") for n in range(3, 11)] == [0] * 8  # refused commands are not executed
    assert result.totals["TDM"] == 0  # the bad move did not happen
    ended = run(program("EndCanon(-1)"))
    assert ended.totals["RE"] == 1


def test_a_range_error_leaves_the_setting_as_it_was() -> None:
    result = run(program('SetLengthUnits("meter")', "SetRelativeSpeed(50)", "SetRelativeSpeed(500)",
                         move(1, 0, 0)), Robot(max_speed=1.0, max_acceleration=1.0))
    # the acceleration was never set: 10 % of the maximum, the kittingViewer's start
    assert by_line(result, 5).values[METRICS.index("CCE")] == pytest.approx(move_time(1, 0.5, 0.1))


def test_a_move_at_zero_speed_is_refused() -> None:
    result = run(program('SetLengthUnits("meter")', "SetRelativeSpeed(0)", move(1, 0, 0), move(0, 0, 0)))
    assert delta(result, 4, "RE") == 1 and delta(result, 4, "ACE") == 0
    assert delta(result, 5, "RE") == 0 and delta(result, 5, "UCE") == 1  # nowhere to go: no time needed


def test_parse_errors_and_evaluation_goes_on() -> None:
    result = run(program("MoveTo(87)", "Dwel(1)", "Dwell(1)", "SetLengthUnits(\"furlong\")", "Dwell(2)"))
    assert result.totals["PE"] == 3
    assert result.totals["ACE"] == 2 and result.totals["TET"] == pytest.approx(3)
    assert result.totals["CSE"] == 0 and result.totals["TE"] == 3


def test_command_sequence_errors() -> None:
    result = run("\n".join(["Dwell(1)", "InitCanon()", "Message(\"a\")", "InitCanon()", "EndCanon()",
                            "Dwell(1)", "EndCanon()"]))
    # Dwell before InitCanon; InitCanon not first; the second InitCanon; EndCanon not last; Dwell after it
    assert [delta(result, n, "CSE") for n in range(1, 8)] == [1, 1, 0, 1, 1, 1, 0]
    assert result.totals["CSE"] == 5 and result.totals["ACE"] == 0  # neither Dwell was executed
    assert result.totals["TE"] == 5
    # an unreadable first line is a parse error only: InitCanon is still the first command
    garbled = run("garbage\n" + program("Dwell(1)"))
    assert (garbled.totals["PE"], garbled.totals["CSE"], garbled.totals["ACE"]) == (1, 0, 1)


def test_total_errors_is_the_sum() -> None:
    result = run("Dwell(1)\n" + program("SetRelativeSpeed(-101)", "oops"))
    assert (result.totals["RE"], result.totals["PE"], result.totals["CSE"]) == (2, 1, 2)
    assert result.totals["TE"] == 5
    for row in result.rows:
        re, pe, cse, te = (row.values[METRICS.index(m)] for m in ("RE", "PE", "CSE", "TE"))
        assert te == re + pe + cse


def test_useless_commands_change_nothing() -> None:
    result = run(program('SetLengthUnits("meter")',   # 2: useful (mm before)
                         "OpenGripper()", "OpenGripper()",  # 3 useful, 4 useless
                         'SetLengthUnits("meter")',   # 5 useless
                         "SetAbsoluteSpeed(0.5)", "SetRelativeSpeed(50)",  # 6 useful, 7 useless (same 0.5 m/s)
                         'SetLengthUnits("mm")', "SetAbsoluteSpeed(500)",  # 8 useful, 9 useless (same speed)
                         "SetEndAngleTolerance(180)", 'SetAngleUnits("radian")',
                         f"SetEndAngleTolerance({math.pi})",  # 12 useless: the same angle in radians
                         move(0, 0, 0), move(0, 0, 0, "MoveStraightTo"),  # 13, 14: already there
                         "MoveTo({{0, 0, 0}, {0, 0, -1}, {0, 1, 0}})",  # 15: turns, useful
                         "Dwell(0)", "Dwell(0.1)", "StopMotion(0)", 'Message("m")'),
                 Robot(max_speed=1.0))
    useless = [r.line for r in result.rows if delta(result, r.line, "UCE")] if result.rows else []
    assert useless == [4, 5, 7, 9, 12, 13, 14, 16, 18]
    assert result.totals["UCE"] == 9


# --- text and XML, the fast reader and kb.crcl ----------------------------------------------------

def test_text_and_xml_give_the_same_metrics(tmp_path: Path) -> None:
    text = program('SetLengthUnits("meter")', "SetRelativeSpeed(40)", "CloseGripper()", "OpenGripper()",
                   f"MoveThroughTo({{{{1, 2, 3}}, {DOWN}}}, {{{{1, 2, 0.5}}, {DOWN}}}, 2)",
                   "SetRelativeAcceleration(-110)", "Dwell(0.5)", 'SetAngleUnits("radian")',
                   "SetEndAngleTolerance(0.1)", move(0.5, 0.5, 0.5, "MoveStraightTo"), 'Message("done")')
    crcl, xml = tmp_path / "p.crcl", tmp_path / "p.xml"
    crcl.write_text(text)
    xml.write_bytes(write_xml(read_text(text)))
    from_text, from_xml = program_metrics(crcl, rows=True), program_metrics(xml, rows=True)
    assert from_text.totals == from_xml.totals
    assert [(r.command, r.values, r.notes) for r in from_text.rows] == \
        [(r.command, r.values, r.notes) for r in from_xml.rows]
    assert from_text.totals["RE"] == 2 and from_text.totals["UCE"] == 1


def test_nist_commands1_has_no_errors_and_nothing_useless(tmp_path: Path) -> None:
    from shared_data import NIST_DIR
    commands1 = NIST_DIR / "commands1.xml"
    if not commands1.exists():
        pytest.skip("NIST CRCL files not present")
    result = program_metrics(commands1)
    assert {m: result.totals[m] for m in ("ACE", "OCE", "TCE", "RE", "PE", "CSE", "UCE")} == {
        "ACE": 34, "OCE": 7, "TCE": 41, "RE": 0, "PE": 0, "CSE": 0, "UCE": 0}
    from kb.crcl import write_text
    text = tmp_path / "commands1.crcl"
    text.write_text(write_text(read_file(commands1)))
    assert program_metrics(text).totals == result.totals


TRICKY = """\ufeff# a comment
InitCanon ( )
  SetLengthUnits("mm")
Message("a \\"quoted\\" word")
Message(\u201ctypographic\u201d)
Message("with (parentheses), and commas")
MoveThroughTo({{5,0,2}, {0,0,1}, {1,0,0}},
  {{5,8,2}, {0,0,1}, {1,0,0}},
  {{7,8,2}, {0,0,1}, {1,0,0}}, 3)
MoveThroughTo({{5,0,2}, {0,0,1}, {1,0,0}}, {{7,8,2}, {0,0,1}, {1,0,0}}, 2)
MoveThroughTo({{5,0,2}, {0,0,1}, {1,0,0}}, 3)
MoveTo({{1e999, 0, 0}, {0,0,1}, {1,0,0}})
MoveTo({{1.5e3, -.5, +2.}, {0,0,1}, {1,0,0}})  // trailing comment
Dwell(1e999)
Dwell(2)\r
SetRelativeSpeed(50)
EndCanon(2.0)
EndCanon(2)
StopMotion()
StopMotion(1)
SetCoordinateFrame("RobotBase")
SetAngleUnits("grad")
MoveTo({{1, 2
// a comment ends the statement
, 3}, {0,0,1}, {1,0,0}})
initCannon()
InitCanon(5)
Dwell()
StopMotion()
Message()
Dwell("x")
SetLengthUnits(5)
SetLengthUnits("inch")
EndCanon( )
CloseGripper ( )
  OpenGripper()\t
StartObjectScan("part_a")
StopObjectScan()
EndCanon(+3)
SetRelativeSpeed(1e999)
Message("a\\\\b")
EndCanon()"""


def test_fast_reader_reads_what_kb_crcl_reads(tmp_path: Path) -> None:
    path = tmp_path / "tricky.crcl"
    path.write_bytes(TRICKY.encode())
    steps = read_steps(path)
    assert steps == steps_of(read_file(path))
    assert [s[1] for s in steps] == [s[1] for s in steps_of(read_file(path))]
    assert sum(1 for s in steps if s[0] == "Unreadable") >= 8


def test_fast_reader_knows_kb_crcl_names() -> None:
    from kb.crcl import ANGLE_UNITS, COORDINATE_FRAMES, LENGTH_UNITS
    from kb.metrics import steps
    assert steps.ANGLE_UNITS == ANGLE_UNITS and steps.COORDINATE_FRAMES == COORDINATE_FRAMES
    assert steps.TEXT_LENGTH_UNITS == {*LENGTH_UNITS, "mm"}


def test_a_plain_program_is_measured_without_importing_kb_crcl(tmp_path: Path) -> None:
    import subprocess
    import sys
    path = tmp_path / "plain.crcl"
    path.write_text(program('SetLengthUnits("meter")', move(1, 0, 0), "Dwell(1)", 'Message("m")'))
    code = ("import sys; from kb.metrics import program_metrics; "
            f"m = program_metrics({str(path)!r}); print(m.totals['ACE'], 'kb.crcl' in sys.modules)")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert done.stdout.split() == ["2", "False"]


def test_fast_reader_on_a_generated_program(tmp_path: Path) -> None:
    import random
    rng = random.Random(7)
    lines = ["InitCanon()", 'SetLengthUnits("meter")']
    for _ in range(2000):
        x, y, z = (round(rng.uniform(-2, 2), 4) for _ in range(3))
        lines.append(rng.choice([move(x, y, z), move(x, y, z, "MoveStraightTo"), "CloseGripper()",
                                 "OpenGripper()", f"Dwell({rng.random():.3f})", f"SetRelativeSpeed({rng.randint(-5, 120)})",
                                 'Message("take part part_b_1")', "Garbage(", "  ", "// c"]))
    lines.append("EndCanon()")
    path = tmp_path / "gen.crcl"
    path.write_text("\n".join(lines))
    assert read_steps(path) == steps_of(read_file(path))


def test_more_commands_than_kb_crcl_allows_is_an_input_error(tmp_path: Path,
                                                              monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("KITKB_MAX_CRCL_COMMANDS", "3")
    path = tmp_path / "long.crcl"
    path.write_text(program("Dwell(1)", "oops") + "\n")
    with pytest.raises(InputError, match="too many commands") as info:
        read_steps(path)
    assert info.value.line == 4


def test_not_utf8_is_an_input_error_at_its_line(tmp_path: Path) -> None:
    path = tmp_path / "bad.crcl"
    path.write_bytes(b"InitCanon()\nDwell(\xff1)\nEndCanon()\n")
    with pytest.raises(InputError, match="not UTF-8") as info:
        read_steps(path)
    assert info.value.line == 2


# --- the score ------------------------------------------------------------------------------------

def test_score_from_default_and_user_weights(tmp_path: Path) -> None:
    totals = program_metrics(FIG11).totals
    default = score(totals)
    assert default.total == pytest.approx(-totals["TET"] - 10 * 3 - 10 * 1 - 3)
    assert set(default.contributions) == set(METRICS) == set(DEFAULT_WEIGHTS)
    config = tmp_path / "w.toml"
    config.write_text("[weights]\nTET = 0\nRE = -1\nUCE = -2.5\n")
    weights = read_weights(config)
    assert weights == {"TET": 0.0, "RE": -1.0, "UCE": -2.5}
    mine = score(totals, weights)
    assert mine.total == pytest.approx(-3 - 10 - 7.5)
    assert mine.contributions["UCE"] == pytest.approx(-7.5)


@pytest.mark.parametrize("text,message", [
    ("[weights]\nXYZ = 1\n", "unknown metric 'XYZ'"),
    ("[weights]\nRE = \"a lot\"\n", "finite number"),
    ("weights = 3\n", "one \\[weights\\] table"),
    ("[weights\n", "not TOML"),
])
def test_bad_weights_files(tmp_path: Path, text: str, message: str) -> None:
    config = tmp_path / "w.toml"
    config.write_text(text)
    with pytest.raises(InputError, match=message):
        read_weights(config)


# --- the command line -----------------------------------------------------------------------------

def test_cli_json(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["metrics", str(FIG11), "--format", "json", "--per-command", "--max-speed", "4"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["command"] == "metrics" and data["commands"] == 24
    assert data["metrics"]["RE"] == 2 and data["metrics"]["PE"] == 1 and data["metrics"]["UCE"] == 3
    assert data["robot"]["max_speed"] == 4.0 and data["robot"]["max_acceleration"] == 10.0
    assert len(data["rows"]) == 24
    row = next(r for r in data["rows"] if r["line"] == 24)
    assert row["command"] == "SetRelativeAcceleration(-110)" and row["RE"] == 2
    assert data["score"]["total"] == pytest.approx(sum(data["score"]["contributions"].values()))
    assert set(data["names"]) == set(METRICS)


def test_cli_text(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    config = tmp_path / "w.toml"
    config.write_text("[weights]\nTET = 0\n")
    assert main(["metrics", str(FIG11), "--per-command", "--config", str(config)]) == 0
    out = capsys.readouterr().out
    assert "useless: the gripper is already closed" in out
    assert "UCE  Useless Commands Executed" in out and "score -43.000" in out


@pytest.mark.parametrize("name,content,args", [
    ("missing.crcl", None, []),
    ("p.txt", "InitCanon()\n", []),
    ("bad.xml", "<CRCLProgram><InitCanon/>", []),
    ("p.crcl", "InitCanon()\n", ["--max-acceleration", "0"]),
    ("p.crcl", "InitCanon()\n", ["--config", "missing.toml"]),
])
def test_cli_bad_input_is_exit_2_one_line(tmp_path: Path, capsys: pytest.CaptureFixture[str], name: str,
                                          content: str | None, args: list[str]) -> None:
    path = tmp_path / name
    if content is not None:
        path.write_text(content)
    args = [a if a != "missing.toml" else str(tmp_path / a) for a in args]
    assert main(["metrics", str(path), *args]) == 2
    captured = capsys.readouterr()
    assert captured.out == "" and len(captured.err.strip().splitlines()) == 1
