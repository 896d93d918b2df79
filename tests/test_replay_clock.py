"""One clock (issue 31 point 3): a run's TET, its replay and the cell's clock agree.

The run's metrics time its CRCL on the robot of kitkb's cells (kb.metrics.motion.cell_robot:
the speed the programs command, 1 m/s until one does, no acceleration phases, a MoveTo up,
across and down); the simulated cell (kb.sim.robot) keeps its clock by the same rules. The
tolerance, 1 %, is for what the commands cannot say: a MoveTo that the cell raises higher than
the higher end to clear a wall it sees.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from kb.crcl.text import read_text
from kb.execution.loop import run_scenario
from kb.metrics import cell_robot, read_steps, static_metrics
from kb.metrics.clock import timed_commands
from kb.scenario import write_scenario
from kb.sim import FaultSpec
from kb.sim.cell import SimulatedCell

ROOT = Path(__file__).resolve().parent.parent
SMALL = ROOT / "ontologies" / "scenarios" / "small-kit"
#: how far a run's TET may be from the cell's clock (relative)
TOLERANCE = 0.01


def _tet(report: dict) -> float:
    return report["metrics"]["static"]["TET"]


def test_small_kit_tet_is_the_cell_clock() -> None:
    cell = SimulatedCell(SMALL / "init.ttl")
    run = run_scenario(SMALL / "init.ttl", SMALL / "goal.ttl", cell=cell)
    report = run.record.report()
    assert run.goal_holds and cell.time > 5.0
    assert _tet(report) == pytest.approx(cell.time, rel=TOLERANCE)
    # the replay's clock: its last command ends at TET, its commands never go back in time
    rows = report["commands"]["rows"]
    assert rows[-1][3] == pytest.approx(_tet(report), abs=1e-6)
    assert all(r[2] <= r[3] for r in rows) and all(a[3] <= b[2] + 1e-9 for a, b in zip(rows, rows[1:]))
    # not the kittingViewer's 10 % of 1 m/s any more: TDM / TET is about the cell's 1 m/s
    assert report["metrics"]["static"]["TDM"] / _tet(report) == pytest.approx(1.0, rel=0.05)


def test_a_run_with_faults_keeps_one_clock(tmp_path: Path) -> None:
    folder = tmp_path / "g"
    write_scenario(folder, parts=8, kits=2, seed=5)
    cell = SimulatedCell(folder / "init.ttl", faults=FaultSpec.parse("missed-grasp@3,dropped-part@9", seed=2), seed=2)
    run = run_scenario(folder / "init.ttl", folder / "goal.ttl", cell=cell)
    report = run.record.report()
    assert report["failures"], "the faults should have struck"
    assert _tet(report) == pytest.approx(cell.time, rel=TOLERANCE)


def test_commanded_speeds_are_the_one_source(tmp_path: Path) -> None:
    """A program that commands its speeds: the cell and the metrics both follow them."""
    program = tmp_path / "p.crcl"
    program.write_text("\n".join([
        "InitCanon()", "SetAbsoluteSpeed(0.25)",
        "MoveTo({{0.3, 0.2, 0.4}, {0, 0, -1}, {1, 0, 0}})",
        "MoveStraightTo({{0.3, 0.2, 0.1}, {0, 0, -1}, {1, 0, 0}})",
        "SetAbsoluteSpeed(0.5)", "Dwell(0.5)",
        "MoveTo({{0.6, 0.4, 0.2}, {0, 0, -1}, {1, 0, 0}})",
        "MoveThroughTo({{0.6, 0.4, 0.5}, {0, 0, -1}, {1, 0, 0}}, {{0.2, 0.4, 0.5}, {0, 0, -1}, {1, 0, 0}}, 2)",
        "EndCanon()"]) + "\n")
    cell = SimulatedCell(SMALL / "init.ttl")
    start = tuple(float(v) for v in cell.robot.tip()[:3, 3])
    for command in read_text(program).commands:
        assert cell.execute(command).done
    steps = read_steps(program)
    tet = static_metrics(steps, cell_robot(start)).totals["TET"]
    assert cell.time > 2.0
    assert tet == pytest.approx(cell.time, rel=1e-6)
    # the kittingViewer's robot (10 % of 1 m/s and of 10 m/s² at the start, trapezoids) does not
    assert static_metrics(read_steps(program)).totals["TET"] != pytest.approx(cell.time, rel=0.05)


def test_timed_commands_keep_each_action_s_commands_in_order() -> None:
    from types import SimpleNamespace as A
    actions = [A(index=0, programs=[["InitCanon()", "MoveTo({{1, 0, 0}, {0, 0, -1}, {1, 0, 0}})", "EndCanon()"]]),
               A(index=1, programs=[["InitCanon()", "CloseGripper()", "SetAbsoluteSpeed(0.5)",
                                     "MoveStraightTo({{1, 1, 0}, {0, 0, -1}, {1, 0, 0}})", "EndCanon()"]])]
    data = timed_commands(actions)
    rows = data["rows"]
    assert [r[0] for r in rows] == [0, 0, 0, 1, 1, 1, 1, 1]
    move, close, straight = rows[1], rows[4], rows[6]
    assert (move[2], move[3]) == (0.0, 1.0) and move[5] == [[1.0, 0.0, 0.0]]
    assert close[1] == "CloseGripper()" and data["settings"][close[7]]["gripper"] == "closed"
    assert straight[3] - straight[2] == pytest.approx(2.0)  # 1 m at the commanded 0.5 m/s
    assert data["settings"][straight[7]]["speed"] == 0.5
    tet = data["metrics"].index("TET")
    assert rows[-1][6][tet] == pytest.approx(3.0)
