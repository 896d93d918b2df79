"""Units said, not assumed (issue 27, point 4): each CRCL form's InitCanon defaults (the paper's
text and 2014 XML: millimetre and degree; CRCL 1.x: metre and radian) honoured by the converters,
the metrics and the simulated robot; every program kitkb sends says its units after InitCanon."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from kb import crcl
from kb.core.errors import InputError
from kb.crcl import commands as c
from kb.crcl import instance as inst
from kb.crcl.files import read_file, write_file
from kb.crcl.units import FORM_UNITS, restate, said_units, units_after
from kb.core.resources import ontology_path
from kb.metrics import program_metrics
from kb.metrics.motion import Robot as MetricsRobot
from kb.metrics.static import static_metrics
from kb.metrics.steps import read_steps
from kb.sim import SimulatedCell

from shared_data import NIST_DIR

SMALL = ontology_path("scenarios/small-kit")
INIT = SMALL / "init.ttl"
CRCL_SCHEMAS = NIST_DIR.parent / "crcl" / "schemas"
DOWN = ((0.0, 0.0, -1.0), (1.0, 0.0, 0.0))


def _move(x: float) -> c.MoveStraightTo:
    return c.MoveStraightTo(c.Pose((x, 0.0, 0.0), DOWN[1], DOWN[0]))


def test_each_form_has_its_defaults():
    assert FORM_UNITS == {"text": ("millimeter", "degree"), "xml": ("millimeter", "degree"),
                          "1.x": ("meter", "radian")}
    assert crcl.read_text("InitCanon()\n").units == c.PAPER_UNITS
    assert crcl.read_xml(NIST_DIR / "commands1.xml").units == c.PAPER_UNITS


def test_restating_says_the_programs_own_units_after_each_init_canon_once():
    paper = c.Program([c.InitCanon(), _move(1000), c.EndCanon(), c.InitCanon(), c.SetLengthUnits("meter"),
                       _move(1), c.EndCanon()], units=c.PAPER_UNITS)
    as_1x = restate(paper, c.CRCL1_UNITS)
    assert as_1x.units == c.CRCL1_UNITS
    assert as_1x.commands == (c.InitCanon(), c.SetLengthUnits("millimeter"), c.SetAngleUnits("degree"), _move(1000),
                              c.EndCanon(), c.InitCanon(), c.SetAngleUnits("degree"), c.SetLengthUnits("meter"),
                              _move(1), c.EndCanon())
    assert restate(as_1x, c.CRCL1_UNITS) == as_1x  # nothing to add in its own form
    back = restate(as_1x, c.PAPER_UNITS)  # said already: nothing added
    assert back.commands == as_1x.commands
    assert units_after(as_1x.commands[:4], c.CRCL1_UNITS) == ("millimeter", "degree")
    assert restate(c.Program([_move(1)]), c.CRCL1_UNITS).commands == (_move(1),)  # units not known: kept


def test_a_lone_length_command_cannot_change_form_silently(tmp_path):
    lone = c.Program([_move(1)], source="one.crcl", units=c.PAPER_UNITS)
    assert restate(lone, c.CRCL1_UNITS).commands == lone.commands  # a session's sender may say them first
    with pytest.raises(InputError, match="before any InitCanon") as err:
        write_file(lone, tmp_path / "one.xml", xml_form="1.x")
    assert err.value.file == "one.crcl" and not (tmp_path / "one.xml").exists()


def test_said_units_are_si():
    assert said_units() == [c.SetLengthUnits("meter"), c.SetAngleUnits("radian")]


# --- the metrics ----------------------------------------------------------------------------------

def _write(tmp_path: Path, name: str, program: c.Program, **kw) -> Path:
    path = tmp_path / name
    if path.suffix == ".crcl":
        path.write_text(crcl.write_text(program, style="paper"))
    else:
        path.write_bytes(inst.write_program_instance(program) if kw.get("xml_form") == "1.x" else crcl.write_xml(program))
    return path


def test_a_paper_program_without_units_moves_millimetres_and_a_1x_one_metres(tmp_path):
    program = c.Program([c.InitCanon(), _move(1000), c.EndCanon()])
    paper = program_metrics(_write(tmp_path, "p.crcl", program))
    early = program_metrics(_write(tmp_path, "p.xml", program))
    crcl1 = program_metrics(_write(tmp_path, "p1.xml", program, xml_form="1.x"))
    assert round(paper.totals["TDM"], 9) == 1.0 and round(early.totals["TDM"], 9) == 1.0
    assert round(crcl1.totals["TDM"], 6) == 1000.0
    assert read_steps(tmp_path / "p1.xml").units == c.CRCL1_UNITS
    # --length-unit overrides the form's default
    assert round(static_metrics(read_steps(tmp_path / "p.crcl"), MetricsRobot(length_unit="meter")).totals["TDM"]) == 1000


def test_nist_figures_stay_where_the_file_states_its_units(tmp_path):
    for name in ("kittingViewer-commands1.crcl", "commands1.xml"):
        assert round(program_metrics(NIST_DIR / name).totals["TDM"], 2) == 60.53
    if (CRCL_SCHEMAS / "CRCLProgramInstance.xsd").exists():
        write_file(read_file(NIST_DIR / "commands1.xml"), tmp_path / "c1x.xml", xml_form="1.x")
        assert round(program_metrics(tmp_path / "c1x.xml").totals["TDM"], 2) == 60.53  # same motion, its units said


def test_angle_units_act_on_the_end_angle_tolerance():
    steps = crcl.read_text("InitCanon()\nSetEndAngleTolerance(90)\nSetAngleUnits(\"radian\")\nEndCanon()\n")
    from kb.metrics.steps import steps_of
    rows = static_metrics(steps_of(steps), rows=True).rows
    assert math.isclose(rows[1].settings["end_angle_tolerance"], 90.0)  # degree by the paper's default
    assert math.isclose(rows[2].settings["end_angle_tolerance"], math.pi / 2)  # the same angle, in radians


def test_units_said_right_after_init_canon_are_not_useless_but_later_repeats_are():
    text = 'InitCanon()\nSetLengthUnits("mm")\nSetAngleUnits("degree")\nDwell(1)\nSetAngleUnits("degree")\nEndCanon()\n'
    from kb.metrics.steps import steps_of
    rows = static_metrics(steps_of(crcl.read_text(text)), rows=True).rows
    assert [bool(r.notes) for r in rows] == [False, False, False, False, True, False]
    assert rows[-1].values[-1] == 1  # UCE: the repeat only


# --- the simulated robot --------------------------------------------------------------------------

@pytest.fixture()
def cell() -> SimulatedCell:
    return SimulatedCell(INIT)


def test_the_robot_resets_to_metres_and_radians_at_init_canon(cell):
    robot = cell.robot
    start = robot.tip()[:3, 3].copy()
    target = c.Pose(tuple(start * 1000), DOWN[1], DOWN[0])
    assert cell.execute(c.SetLengthUnits("millimeter")).done
    assert cell.execute(c.MoveStraightTo(target)).done
    assert np.allclose(robot.tip()[:3, 3], start)  # millimetres said: the same place
    assert cell.execute(c.InitCanon()).done
    assert (robot.metres, robot.radians) == (1.0, 1.0)


def test_a_rotational_speed_in_degrees_times_a_turn(cell):
    robot = cell.robot
    tip = robot.tip()
    here = c.Pose(tuple(tip[:3, 3]), tuple(tip[:3, 0]), tuple(tip[:3, 2]))
    turned = c.Pose(here.point, tuple(-np.array(here.x_axis)), here.z_axis)  # half a turn about Z
    for command in (c.InitCanon(), c.SetAngleUnits("degree"), c.SetRotSpeed(90)):
        assert cell.execute(command).done
    before = robot.time
    assert cell.execute(c.MoveStraightTo(turned)).done
    assert math.isclose(robot.time - before, 2.0, rel_tol=1e-6)  # 180 degrees at 90 degrees a second
    assert cell.execute(c.SetEndAngleTolerance(1)).done
    assert math.isclose(robot.tolerances["end angle"], math.pi / 180)


def test_commands_the_robot_cannot_carry_out_are_error_statuses(cell):
    status = cell.execute(c.ActuateJoints([c.JointActuation(1, 0.5)]))
    assert not status.done and "no joint model" in status.message
    assert cell.execute(c.GetStatus()).done
    assert cell.execute(c.SetEndEffector(0.5)).done


def test_a_paper_program_played_moves_millimetres():
    from kb.sim.playback import play
    x, y, z = (SimulatedCell(INIT).robot.tip()[:3, 3] * 1000).tolist()
    text = f"InitCanon()\nMoveStraightTo({{{{{x}, {y}, {z + 100}}}, {{0, 0, -1}}, {{1, 0, 0}}}})\nEndCanon()\n"
    played = play(crcl.read_text(text), INIT)
    assert played.statuses[1].done, played.statuses[1].message
    robot = next(n for n in played.final.names if n.endswith("robot_1"))
    rise = played.final.lo[played.final.index[robot], 2] - played.initial.lo[played.initial.index[robot], 2]
    assert math.isclose(rise, 0.1, abs_tol=1e-9)  # 100 mm, not 100 m
