"""Kit scores come from what is sensed and inspected at the end of a run (issue 26, point 11):
the executor inspects, through the cell, every part lying in a goal kit after it checks the
goal, so a second run against a cell that already holds the finished kit scores it whole (it
once said "holds part_a_1, not found good" while the cell's inspection answered {Quality ok}),
and a part found defective at the end loses its point even though it passed when it was taken."""

from __future__ import annotations

import json
from functools import lru_cache
from pathlib import Path
from typing import Any

import pytest

from kb import planning
from kb.cli import main
from kb.core.resources import ontology_path
from kb.crcl import RemoteCell
from kb.execution import Run, run_plan
from kb.sim import CellServer, SimulatedCell
from kb.spatial.scene import Scene

INIT, GOAL = str(ontology_path("scenarios/small-kit/init.ttl")), str(ontology_path("scenarios/small-kit/goal.ttl"))
NS = "https://w3id.org/kitkb/scenario/small-kit#"
IN_KIT = [NS + "part_a_1", NS + "part_a_2", NS + "part_b_1"]

pytestmark = pytest.mark.usefixtures("own_directory")


@lru_cache(maxsize=None)
def plan() -> tuple[str, ...]:
    return tuple(planning.run(planning.kitting_model([INIT], [GOAL], "strips").up_problem, None).lines)


class Watched(SimulatedCell):
    """The small kit's simulated cell, keeping the parts it was asked to inspect; ``spoil``:
    a part the cell finds defective from plan action ``at`` on (after it was taken)."""

    def __init__(self, spoil: str | None = None, at: int | None = None) -> None:
        super().__init__(Scene.from_files([INIT], declared=[GOAL]))
        self.inspected: list[str] = []
        self.spoil, self.at = spoil, at

    def inspect(self, name: str) -> bool:
        self.inspected.append(name)
        return super().inspect(name)

    def begin_action(self, index: int, action: str, args: tuple[str, ...]) -> None:
        super().begin_action(index, action, args)
        if self.spoil is not None and index == self.at:
            self.world.defective.add(self.spoil)


def execute(cell: Any) -> Run:
    return run_plan(list(plan()), INIT, GOAL, cell=cell, notifier=lambda who, text: None)


def kit(run: Run) -> dict:
    [score] = run.report()["kits"]
    return score


def test_a_second_run_against_the_finished_kit_scores_it_from_the_cell() -> None:
    cell = Watched()
    first = execute(cell)
    assert first.goal_holds and kit(first)["score"] == 6
    cell.inspected.clear()
    second = execute(cell)  # the cell holds the finished kit; the executor believes the initial state
    assert second.goal_holds is True
    assert kit(second) == {"kit": "kit_1", "design": "kit_design_a2b1", "score": 6, "max_score": 6, "lost": []}
    assert sorted(cell.inspected) == IN_KIT  # asked of the cell at the end, not remembered


def test_a_part_found_defective_at_the_end_loses_its_point_though_it_passed_when_taken() -> None:
    put_kit = next(i for i, line in enumerate(plan()) if line.startswith("(put-kit "))
    cell = Watched(spoil=NS + "part_a_1", at=put_kit)
    run = execute(cell)
    assert NS + "part_a_1" in cell.inspected[:-3]  # inspected when taken: it passed then
    assert run.goal_holds is True
    score = kit(run)
    assert score["score"] == 5 and [(x["predicate"], x["objects"]) for x in score["lost"]] == \
        [("part-quality-ok", ["part_a_1"])]
    assert "holds part_a_1, not found good" in score["lost"][0]["reason"]


def test_over_the_wire_the_second_run_scores_what_the_cell_inspects() -> None:
    served = Watched()
    with CellServer(served, sensor_port=0, command_port=0) as server:
        with RemoteCell("127.0.0.1", server.sensor_port, server.command_port, timeout=10) as remote:
            assert kit(execute(remote))["score"] == 6
            served.inspected.clear()
            assert kit(execute(remote))["score"] == 6
            assert sorted(served.inspected) == IN_KIT  # {Inspect ...} queries on the sensor port
            served.world.defective.add(NS + "part_b_1")
            third = execute(remote)
    assert third.goal_holds is True and kit(third)["score"] == 5
    assert [x["objects"] for x in kit(third)["lost"]] == [["part_b_1"]]


def test_kitkb_run_twice_against_a_served_cell(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    with CellServer(SimulatedCell(Scene.from_files([INIT], declared=[GOAL])), sensor_port=0,
                    command_port=0) as server:
        address = f"127.0.0.1:{server.sensor_port},{server.command_port}"
        for n in (1, 2):
            report = tmp_path / f"run{n}.json"
            assert main(["run", INIT, GOAL, "--cell", address, "-o", str(tmp_path / f"out{n}"), "--report",
                         str(report)]) == 0
            data = json.loads(report.read_text())
            assert data["goal_holds"] is True
            assert [(k["kit"], k["score"], k["max_score"], k["lost"]) for k in data["kits"]] == \
                [("kit_1", 6, 6, [])]
    out = capsys.readouterr().out
    assert out.count("kit kit_1: 6 of 6 points") == 2 and "not found good" not in out
