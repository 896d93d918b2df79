"""Object and constraint metrics of a CRCL program played on a state (kb.sim.playback,
``kitkb metrics PROGRAM --init STATE --goal STATE``): a hand-written program on the shipped
small kit that moves one part to its kit slot, one to a wrong place, carries one through other
parts and a tray wall, tries a wrong effector and leaves the work volume; an overweight pick;
and the executor's own program for a correct plan, which makes no violation."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

from kb import crcl
from kb.cli import main
from kb.core.resources import ontology_path
from kb.crcl.wire import action_message
from kb.metrics.score import PLAYBACK_WEIGHTS, SCORED, score
from kb.sim import SimulatedCell
from kb.sim.playback import play
from kb.spatial.rcc8 import relate_pair

SMALL = ontology_path("scenarios/small-kit")
INIT, GOAL = SMALL / "init.ttl", SMALL / "goal.ttl"
NS = "https://w3id.org/kitkb/scenario/small-kit#"


def tip(x: float, y: float, z: float) -> str:
    return f"{{{{{x}, {y}, {z}}}, {{0, 0, -1}}, {{1, 0, 0}}}}"


#: small-kit's tool tip places: the part gripper's mount face in its holder, parts' top faces
#: in their trays, the kit tray in its box (its slot for part A 1 at -0.07, -0.05)
PROGRAM = "\n".join([
    "InitCanon()", 'SetLengthUnits("meter")', "SetAbsoluteSpeed(1.0)",
    f"MoveTo({tip(2.85, 0, 1.0)})", f"MoveTo({tip(2.85, 0, 0.8)})", "CloseToolChanger()",   # the part gripper
    f"MoveTo({tip(2.85, 0, 1.0)})",
    f"MoveTo({tip(0.235, -0.995, 0.04)})", "CloseGripper()",          # 9: the kit tray: a wrong effector
    f"MoveTo({tip(0.235, -0.995, 1.0)})",
    f"MoveTo({tip(0.165, 0.945, 0.81)})", "CloseGripper()",           # part_a_1 into its kit slot: right
    f"MoveTo({tip(0.165, -1.045, 0.06)})", "OpenGripper()",
    f"MoveTo({tip(0.305, 0.945, 0.81)})", "CloseGripper()",           # part_a_2 onto the work table: wrong
    f"MoveTo({tip(1.4, 0.1, 0.81)})", "OpenGripper()",
    f"MoveTo({tip(0.675, 0.945, 0.81)})", "CloseGripper()",           # part_b_1 ...
    f"MoveStraightTo({tip(0.675, 0.945, 0.86)})",
    f"MoveStraightTo({tip(1.2, 0.945, 0.86)})",                       # 22: 1 cm too low over part_b_2, _3
    f"MoveTo({tip(0.305, 1.045, 0.82)})",                             # into part_a_tray's free cell
    f"MoveStraightTo({tip(0.305, 1.40, 0.82)})",                      # 24: out through its back wall
    "OpenGripper()",                                                  # part_b_1 falls to the floor: wrong
    f"MoveTo({tip(0.305, 1.40, 2.6)})",                               # 26: above the work volume (2.5 m)
    f"MoveTo({tip(0.305, 1.40, 1.0)})",
    f"MoveTo({tip(2.85, 0, 0.72)})", "OpenToolChanger()",            # the part gripper back where it was
    f"MoveTo({tip(2.85, 0, 1.0)})", "EndCanon()",
]) + "\n"


@pytest.fixture(scope="module")
def program(tmp_path_factory: pytest.TempPathFactory) -> Path:
    path = tmp_path_factory.mktemp("programs") / "program.crcl"
    path.write_text(PROGRAM)
    return path


@pytest.fixture(scope="module")
def played(program: Path):  # noqa: ANN201
    return play(crcl.read_text(program), INIT, GOAL)


def local(names) -> list[str]:  # noqa: ANN001
    return sorted(n.rsplit("#", 1)[-1] for n in names)


def test_the_objects_that_should_have_moved_moved_and_where_they_went(played) -> None:  # noqa: ANN001
    o = played.objects
    assert local(o.should_move) == ["kit_1", "part_a_1", "part_a_2", "part_b_1"]
    assert local(o.moved) == ["part_a_1", "part_a_2", "part_b_1"]  # the gripper is back where it was
    assert local(o.right) == ["part_a_1"] and local(o.wrong) == ["part_a_2", "part_b_1"]
    assert o.goal[NS + "part_a_1"] == (("part-location-kit", NS + "kit_1"),)
    assert played.totals() == {"OSM": 4, "OM": 3, "OMR": 1, "OMW": 2, "OVW": 0, "WVE": 1, "WEE": 1, "CTE": 3}


def test_each_violation_names_its_command_and_objects(played) -> None:  # noqa: ANN001
    got = [(v.kind, v.command, tuple(local(v.objects))) for v in played.violations]
    assert got == [("wrong-effector", 8, ("kit_tray_1", "part_gripper")),
                   ("contact", 21, ("part_b_1", "part_b_2")), ("contact", 21, ("part_b_1", "part_b_3")),
                   ("contact", 23, ("part_a_tray", "part_b_1")),
                   ("work-volume", 25, ("robot_1",))]
    assert all(v.action is None for v in played.violations)  # no action announced: a bare program
    rows = played.rows()
    assert rows[21]["CTE"] == 2 and rows[-1]["CTE"] == 3 and rows[-1]["WVE"] == 1
    assert any("passes through part_b_2" in n for n in rows[21]["notes"])


def test_the_contact_is_between_two_free_end_poses(program: Path) -> None:
    """The carried part is clear of part_b_2 and part_b_3 before and after the move that
    passes through them."""
    commands = list(crcl.read_text(program))
    for upto in (21, 22):  # before and after command 21
        scene = play(commands[:upto], INIT).final
        i = scene.index[NS + "part_b_1"]
        for other in ("part_b_2", "part_b_3"):
            j = scene.index[NS + other]
            rel = relate_pair(scene.lo[i], scene.hi[i], scene.lo[j], scene.hi[j])
            assert rel & {"X-DC", "Y-DC", "Z-DC", "X-EC", "Y-EC", "Z-EC"}, (upto, other, rel)


def test_an_overweight_pick_in_a_state_written_in_grams(tmp_path: Path) -> None:
    text = INIT.read_text().replace('WeightUnit "kilogram"', 'WeightUnit "gram"')
    text = re.sub(r"(Weight) ([0-9.]+)", lambda m: f"{m.group(1)} {float(m.group(2)) * 1000:g}", text)
    text = text.replace("hasEndEffector_MaximumLoadWeight 1200", "hasEndEffector_MaximumLoadWeight 900")
    init = tmp_path / "init.ttl"
    init.write_text(text)
    steps = ["InitCanon()", 'SetLengthUnits("meter")', f"MoveTo({tip(2.55, 0, 1.0)})", f"MoveTo({tip(2.55, 0, 0.8)})",
             "CloseToolChanger()", f"MoveTo({tip(0.305, 0.995, 0.79)})", "CloseGripper()",  # part_a_tray, 1020 g
             f"MoveTo({tip(0.305, 0.995, 1.2)})", "EndCanon()"]
    result = play(crcl.read_text("\n".join(steps)), init, GOAL)
    assert result.totals()["OVW"] == 1 and result.totals()["OM"] == 0  # the tray gripper is equipment
    assert not result.statuses[6].done and "more than tray_gripper's maximum load 0.9 kg" in result.statuses[6].message


def test_a_correct_plans_program_makes_no_violation(tmp_path: Path) -> None:
    """The executor's CRCL for a correct plan of small-kit (recorded with its kitkb-action
    messages), played again from the initial state: every object that should move moves to its
    place, nothing else moves, no violation."""
    from kb.execution import run_plan

    plan = ["(attach-endeffector robot_1 tray_gripper tray_gripper_holder changing_station_1)",
            "(take-kittray robot_1 kit_tray_1 empty_kit_tray_supply tray_gripper)",
            "(put-kittray robot_1 kit_tray_1 work_table_1)", "(create-kit kit_1 kit_tray_1 work_table_1)",
            "(remove-endeffector robot_1 tray_gripper tray_gripper_holder changing_station_1)",
            "(attach-endeffector robot_1 part_gripper part_gripper_holder changing_station_1)"]
    for part, tray, sku in (("part_a_1", "part_a_tray", "a"), ("part_a_2", "part_a_tray", "a"),
                            ("part_b_1", "part_b_tray", "b")):
        plan += [f"(take-part robot_1 {part} {tray} part_gripper)",
                 f"(put-part robot_1 {part} kit_1 work_table_1 sku_part_{sku})"]
    plan += ["(remove-endeffector robot_1 part_gripper part_gripper_holder changing_station_1)",
             "(attach-endeffector robot_1 tray_gripper tray_gripper_holder changing_station_1)",
             "(take-kit robot_1 kit_1 work_table_1 tray_gripper)", "(put-kit robot_1 kit_1 finished_kit_receiver_1)",
             "(remove-endeffector robot_1 tray_gripper tray_gripper_holder changing_station_1)"]  # goal: back in its holder
    sent: list[crcl.Command] = []

    class Recording(SimulatedCell):
        def execute(self, command: crcl.Command):  # noqa: ANN202
            sent.append(command)
            return super().execute(command)

        def begin_action(self, index: int, action: str, args: tuple[str, ...]) -> None:
            sent.append(action_message(index, action, tuple(a.rsplit("#", 1)[-1] for a in args)))
            super().begin_action(index, action, args)

    cell = Recording(INIT)
    run = run_plan(plan, INIT, GOAL, cell=cell)
    assert run.goal_holds and cell.violations == []
    path = tmp_path / "run.crcl"
    path.write_text(crcl.write_text(crcl.Program(tuple(sent))))
    again = play(crcl.read_text(path), INIT, GOAL, length_unit="meter")
    assert again.violations == []
    assert again.totals() == {"OSM": 4, "OM": 4, "OMR": 4, "OMW": 0, "OVW": 0, "WVE": 0, "WEE": 0, "CTE": 0}
    assert local(again.objects.right) == ["kit_1", "part_a_1", "part_a_2", "part_b_1"]
    assert NS + "tray_gripper" not in again.objects.moved  # left on the robot: equipment, not an object


def test_every_metric_is_weighted() -> None:
    assert set(PLAYBACK_WEIGHTS) | {"ACE"} <= set(SCORED)
    totals = {"OMR": 2, "OMW": 1, "CTE": 3, "OSM": None}
    s = score(totals)
    assert s.contributions == {"OMR": 20.0, "OMW": -10.0, "CTE": -30.0} and s.total == pytest.approx(-20.0)


# --- the command line -----------------------------------------------------------------------------

def test_cli_json_and_text(program: Path, capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    assert main(["metrics", str(program), "--init", str(INIT), "--goal", str(GOAL), "--format", "json",
                 "--per-command"]) == 0
    data = json.loads(capsys.readouterr().out)
    m = data["metrics"]
    assert (m["OSM"], m["OM"], m["OMR"], m["OMW"], m["OVW"], m["WVE"], m["WEE"], m["CTE"]) == (4, 3, 1, 2, 0, 1, 1, 3)
    assert m["TCE"] == 31 and data["names"]["CTE"] == "ConTact Errors"
    assert data["score"]["contributions"]["CTE"] == -30.0
    assert data["objects"]["right"] == ["part_a_1"] and len(data["violations"]) == 5
    row = next(r for r in data["rows"] if r["index"] == 21)
    assert row["CTE"] == 2 and any("part_b_2" in n for n in row["notes"])
    config = tmp_path / "w.toml"
    config.write_text("[weights]\nCTE = -100\nTET = 0\n")
    assert main(["metrics", str(program), "--init", str(INIT), "--config", str(config)]) == 0
    out = capsys.readouterr().out
    assert "CTE  ConTact Errors" in out and "x -100 = -300.000" in out
    assert "OSM  Objects that Should have Moved" in out and "no --goal" in out
    assert "contact (line 22): part_b_1 passes through part_b_2" in out


@pytest.mark.parametrize("args,message", [
    (["--init", "missing.ttl"], "no such file"),
    (["--goal", str(GOAL)], "--goal needs --init"),
    (["--init", "bad.ttl"], "bad.ttl:1:"),
    (["--init", str(ontology_path("kitting.ttl"))], "no placed robot"),
])
def test_cli_bad_states_are_one_line_exit_2(program: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                             args: list[str], message: str) -> None:
    (tmp_path / "bad.ttl").write_text("this is not turtle\n")
    args = [str(tmp_path / a) if a in ("missing.ttl", "bad.ttl") else a for a in args]
    assert main(["metrics", str(program), *args]) == 2
    captured = capsys.readouterr()
    assert captured.out == "" and len(captured.err.strip().splitlines()) == 1 and message in captured.err
