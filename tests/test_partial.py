"""Partial instance data (issue 28, point 5): objects whose location is unknown validate with a
note, planning refuses them at their line, and the closed loop senses them before it plans."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from rdflib import URIRef

from kb.cli import main
from kb.core.errors import InputError
from kb.core.resources import ontology_path
from kb.execution.loop import ClosedLoop, LoopOptions
from kb.io import load_file
from kb.spatial.unlocated import unlocated
from kb.validation import validate

SMALL = ontology_path("scenarios/small-kit/init.ttl")
SMALL_GOAL = ontology_path("scenarios/small-kit/goal.ttl")


@pytest.fixture(scope="module")
def partial(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A generated scenario (6 parts, 2 kits) whose initial state leaves 2 parts unlocated."""
    out = tmp_path_factory.mktemp("partial") / "s6"
    assert main(["-q", "scenario", "generate", "--parts", "6", "--kits", "2", "--seed", "3", "--unlocated", "2",
                 "-o", str(out)]) == 0
    return out


def _without(tmp_path: Path, name: str, mark: bool = False) -> Path:
    out = tmp_path / f"{name}{'-marked' if mark else ''}.ttl"
    args = ["-q", "scenario", "transform", str(SMALL), "-o", str(out), "--unlocate", name]
    assert main(args + (["--mark-unlocated"] if mark else [])) == 0
    return out


def test_a_full_state_has_no_unlocated_object() -> None:
    assert unlocated(load_file(SMALL)) == []


@pytest.mark.parametrize("mark", [False, True])
def test_an_unlocated_part_is_found_with_its_tray(tmp_path: Path, mark: bool) -> None:
    found = unlocated(load_file(_without(tmp_path, "part_b_1", mark)))
    assert [(u.name.rsplit("#")[-1], u.cls.rsplit("#")[-1], u.container.rsplit("#")[-1]) for u in found] == [
        ("part_b_1", "Part", "part_b_tray")]
    assert (found[0].location is not None) is mark
    assert found[0].line is not None


def test_it_validates_with_a_note_at_its_line(tmp_path: Path) -> None:
    path = _without(tmp_path, "part_b_1")
    report = validate([str(path)])
    assert report.conforms, report.summary()
    notes = [d for d in report.diagnostics if d.rule == "location-unknown"]
    assert len(notes) == 1 and notes[0].severity == "info"
    assert notes[0].line == unlocated(load_file(path))[0].line
    assert "part_b_1" in notes[0].message and "min-count" not in {d.rule for d in report.diagnostics}


def test_other_rules_keep_applying_and_other_objects_still_need_a_location(tmp_path: Path) -> None:
    from rdflib import Graph, Literal
    from rdflib.namespace import XSD
    from kb.core.namespaces import KTW
    graph = Graph().parse(_without(tmp_path, "part_b_1"))
    ns = str(next(s for s in graph.subjects() if str(s).endswith("#robot_1"))).rsplit("#")[0] + "#"
    # the robot is no SKU object: without its location it is still an error; the part's serial
    # number written twice is still a max-count error
    graph.remove((URIRef(ns + "robot_1"), KTW.hasSolidObject_PrimaryLocation, None))
    graph.add((URIRef(ns + "part_b_1"), KTW.hasPart_SerialNumber, Literal("b_1_again", datatype=XSD.NMTOKEN)))
    bad = tmp_path / "bad.ttl"
    graph.serialize(bad, format="turtle")
    report = validate([str(bad)])
    rules = {(d.rule, d.focus) for d in report.diagnostics}
    assert ("min-count", ":robot_1") in rules
    assert ("max-count", ":part_b_1") in rules
    assert ("location-unknown", ":part_b_1") in rules


def test_planning_refuses_at_the_objects_line(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    path = _without(tmp_path, "part_b_1")
    line = unlocated(load_file(path))[0].line
    for command in (["generate", "pddl", str(path), str(SMALL_GOAL), "-o", str(tmp_path / "pddl")],
                    ["plan", str(path), str(SMALL_GOAL), "-o", str(tmp_path / "plan.txt")]):
        assert main(command) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and err[0].startswith(f"{path}:{line}: error: part_b_1's location is unknown")
    assert not (tmp_path / "plan.txt").exists()


def test_the_simulator_places_unlocated_parts_seeded_in_free_spots(tmp_path: Path) -> None:
    from kb.sim.cell import SimulatedCell
    path = _without(tmp_path, "part_b_1")
    a, b, c = (SimulatedCell(path, seed=s) for s in (1, 1, 2))
    assert [p.as_dict() for p in a.hidden] == [p.as_dict() for p in b.hidden]
    assert a.hidden[0].container.endswith("part_b_tray")
    truth = a.scene()
    i, tray = truth.index[a.hidden[0].name], truth.index[a.hidden[0].container]
    assert truth.placed[i]
    assert np.all(truth.lo[i, :2] >= truth.lo[tray, :2]) and np.all(truth.hi[i, :2] <= truth.hi[tray, :2])
    from kb.core.namespaces import KTW
    others = [j for j in truth.of_class(str(KTW.Part)) if truth.placed[j] and j != i]
    assert len(others) == 6  # small-kit: 4 parts A, 3 parts B
    for j in others:  # clear of every other part
        assert np.any(truth.hi[i, :2] <= truth.lo[j, :2]) or np.any(truth.lo[i, :2] >= truth.hi[j, :2])
    spots = {tuple(p.local[:3, 3].round(4)) for cell in (a, c, SimulatedCell(path, seed=3)) for p in cell.hidden}
    assert len(spots) >= 2  # other seeds, other spots


def test_a_run_senses_plans_and_builds_the_kits(partial: Path, tmp_path: Path) -> None:
    init, goal = partial / "init.ttl", partial / "goal.ttl"
    report = validate([str(init), str(goal)])
    assert report.conforms and sum(d.rule == "location-unknown" for d in report.diagnostics) == 2
    events = []
    result = ClosedLoop(init, goal, LoopOptions(seed=4, out_dir=tmp_path / "out"), on_event=events.append).run()
    assert result.ok, result.reason
    stages = [e.stage for e in events if type(e).__name__ == "StageEnded"]
    assert stages[:3] == ["validate", "locate", "pddl"]
    data = result.report()["located"]
    asked = [u["object"] for u in data["asked"]]
    assert len(asked) == 2 and [s["object"] for s in data["sensed"]] == asked
    assert [s["container"] for s in data["sensed"]] == [t["container"] for t in data["truth"]]
    for s, t in zip(data["sensed"], data["truth"]):  # an exact sensor: where the simulator put them
        assert np.allclose(s["position"], t["position"], atol=1e-6)
    sensed = tmp_path / "out" / "init-sensed.ttl"
    assert unlocated(load_file(sensed)) == [] and validate([str(sensed)]).conforms
    plan = (tmp_path / "out" / "plan.txt").read_text()
    assert all(f" {name} " in plan for name in asked)  # the sensed parts are planned with and built into kits
    json.dumps(result.report())


def test_sim_world_file_is_where_the_objects_truly_are(tmp_path: Path) -> None:
    path = _without(tmp_path, "part_b_1", mark=True)
    result = ClosedLoop(path, SMALL_GOAL, LoopOptions(cell=f"sim:?world={SMALL}", validate=False, geometry=False,
                                                      execute=False)).run()
    sensed = result.located.placements[0]
    assert sensed.container.endswith("part_b_tray")
    from kb.spatial.scene import Scene
    truth = Scene.from_files([SMALL])
    i = truth.index[sensed.name]
    assert np.allclose(sensed.pose, truth.poses[i], atol=1e-9)
    assert result.located.truth == []  # the cell was given the truth: it placed nothing itself


def test_an_object_the_sensor_does_not_find_is_refused(tmp_path: Path) -> None:
    from kb.cells import CellRequest, open_cell
    from kb.spatial.scene import Scene
    path = _without(tmp_path, "part_b_1")
    cell = open_cell("sim:", CellRequest(scene=Scene.from_files([path], [SMALL_GOAL]), state=path, goal=SMALL_GOAL))

    class Blind:  # the cell's sensor never reports part_b_1
        def __getattr__(self, name: str):  # noqa: ANN204
            return getattr(cell, name)

        def execute(self, command):  # noqa: ANN001, ANN201
            return cell.execute(command)

        def sense(self, query, *, by="class"):  # noqa: ANN001, ANN201
            return [o for o in cell.sense(query, by=by) if not o.name.endswith("part_b_1")]

        def inspect(self, name):  # noqa: ANN001, ANN201
            return cell.inspect(name)

        def begin_action(self, index, action, args):  # noqa: ANN001, ANN201
            return cell.begin_action(index, action, args)

    line = unlocated(load_file(path))[0].line
    with pytest.raises(InputError) as e:
        ClosedLoop(path, SMALL_GOAL, LoopOptions(cell=Blind(), validate=False)).run()
    assert e.value.line == line and "did not find it" in str(e.value)


@pytest.mark.parametrize("scheme", ["kitkb", "crcl"])
def test_a_cell_server_of_the_partial_state_is_sensed_by_url(partial: Path, tmp_path: Path, scheme: str) -> None:
    """``kitkb sim serve`` of the partial file: the served cell places the parts itself; the run
    senses them through the cell's URL (the USARTruth port) and builds the kits."""
    from kb.sim import CellServer, SimulatedCell
    init, goal = partial / "init.ttl", partial / "goal.ttl"
    cell = SimulatedCell(init, seed=9, declared=[goal])
    assert len(cell.hidden) == 2
    with CellServer(cell, sensor_port=0, command_port=0) as server:
        url = (f"kitkb://127.0.0.1:{server.sensor_port}?command={server.command_port}" if scheme == "kitkb" else
               f"crcl://127.0.0.1:{server.command_port}?sensor=127.0.0.1:{server.sensor_port}")
        result = ClosedLoop(init, goal, LoopOptions(cell=url, validate=False, out_dir=tmp_path)).run()
    assert result.goal_holds, result.reason
    data = result.report()["located"]
    assert [(s["object"], s["container"]) for s in data["sensed"]] == [
        (p.name.rsplit("#")[-1], p.container.rsplit("#")[-1]) for p in cell.hidden]
    for s, p in zip(data["sensed"], cell.hidden):
        assert np.allclose(s["position"], p.pose[:3, 3], atol=1e-6)
