"""Units: a state file and its copies in millimetres and inches are the same workstation.

Metamorphic: the predicates decided from geometry, the plan, and a seeded run with faults are
the same whatever length unit the file is written in; the database keeps the file's unit; a
unit kitkb cannot convert is an input error at its line. Also: ``kitkb run`` says why it did
not execute.
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pytest

from kb import planning
from kb.cli import main
from kb.core.errors import InputError
from kb.core.resources import scenario_dirs
from kb.execution import run_plan
from kb.execution.records import without_timings
from kb.scenario import write_scenario
from kb.scenario.variants import write_variant
from kb.spatial import Scene, true_predicates
from kb.world import WorldModel

SMALL = next(d for d in scenario_dirs() if d.name == "small-kit")
UNITS = ("millimeter", "inch")


def _variant(src: Path, out: Path, unit: str) -> Path:
    write_variant(src, out, unit=unit)
    return out


def _pair(d: Path, tmp: Path, unit: str) -> tuple[Path, Path]:
    tmp.mkdir(parents=True, exist_ok=True)
    return _variant(d / "init.ttl", tmp / "init.ttl", unit), _variant(d / "goal.ttl", tmp / "goal.ttl", unit)


@pytest.fixture(scope="module")
def generated(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("gen")
    write_scenario(out, parts=14, kits=1, seed=11)
    return out


@pytest.mark.parametrize("unit", UNITS)
def test_predicates_do_not_depend_on_the_unit(unit: str, tmp_path: Path, generated: Path) -> None:
    for d in (*scenario_dirs(), generated):
        init, goal = _pair(d, tmp_path / d.name, unit)
        assert true_predicates([init], goal) == true_predicates([d / "init.ttl"], d / "goal.ttl"), d.name
        assert true_predicates([goal]) == true_predicates([d / "goal.ttl"]), d.name


def test_a_scene_is_in_metres_and_knows_the_file_unit(tmp_path: Path) -> None:
    metres = Scene.from_files([SMALL / "init.ttl"])
    for unit, per in (("millimeter", 1000.0), ("inch", 1 / 0.0254)):
        scene = Scene.from_files([_variant(SMALL / "init.ttl", tmp_path / f"{unit}.ttl", unit)])
        assert scene.units.length == unit and scene.units.metres * per == pytest.approx(1.0)
        ok = metres.placed
        np.testing.assert_allclose(scene.lo[ok], metres.lo[ok], atol=1e-9)
        np.testing.assert_allclose(scene.hi[ok], metres.hi[ok], atol=1e-9)
    assert metres.units.length == "meter"


def test_tolerance_is_a_millimetre_in_a_millimetre_file(tmp_path: Path) -> None:
    """A kit tray resting 0.5 mm low in a millimetre file is still in its box (the tolerance is
    1 mm, not 0.001 file units); 5 mm low is through its floor."""
    mm = _variant(SMALL / "init.ttl", tmp_path / "mm.ttl", "millimeter")
    text = mm.read_text()
    base = true_predicates([mm])
    for drop, same in ((0.5, True), (5.0, False)):
        shifted = tmp_path / f"low{drop}.ttl"
        shifted.write_text(_lower(text, "kit_tray_1_point", drop))
        assert (true_predicates([shifted]) == base) is same, drop


def _lower(text: str, point: str, by: float) -> str:
    """``text`` with the z of the point ``point`` lowered by ``by`` (Turtle as kitkb writes it)."""
    head, _, rest = text.partition(f"\n:{point} ")
    block, sep, tail = rest.partition(" .\n")
    key = "ktw:hasPoint_Z "
    before, _, value = block.partition(key)
    z = value.split()[0].rstrip(";")
    number = float(z.split("^^")[0].strip('"'))
    return head + f"\n:{point} " + before + key + repr(number - by) + value[len(z):] + sep + tail


@pytest.mark.slow
@pytest.mark.parametrize("unit", UNITS)
def test_same_plan_and_same_seeded_run_in_any_unit(unit: str, tmp_path: Path) -> None:
    reports = {}
    for name, (init, goal) in (("meter", (SMALL / "init.ttl", SMALL / "goal.ttl")),
                               (unit, _pair(SMALL, tmp_path / unit, unit))):
        out = tmp_path / f"out-{name}"
        report = tmp_path / f"{name}.json"
        code = main(["run", str(init), str(goal), "-o", str(out), "--seed", "3", "--faults",
                     "missed-grasp@6,part-missing@9", "--report", str(report), "-q"])
        assert code == 0
        reports[name] = json.loads(report.read_text())
        reports[name]["plan"] = (out / init.parent.name / "plan.txt").read_text()
    a, b = reports["meter"], reports[unit]
    assert b["units"]["length"] == unit and a["units"]["length"] == "meter"
    a, b = without_timings(a), without_timings(b)
    for r in (a, b):
        for key in ("units", "scenario"):
            r.pop(key)
        r.pop("scene")  # the same objects and poses, to the float rounding of a unit conversion
    assert a == b
    assert a["injected"] and a["failures"]


def test_database_keeps_the_file_unit(tmp_path: Path) -> None:
    """Stable states are written back in the file's unit: after a run, the millimetre
    database's poses are the metre database's times 1000."""
    dbs = {}
    for unit in ("meter", "millimeter"):
        init, goal = ((SMALL / "init.ttl", SMALL / "goal.ttl") if unit == "meter"
                      else _pair(SMALL, tmp_path / unit, unit))
        model = planning.kitting_model([init], [goal], "strips")
        dbs[unit] = tmp_path / f"{unit}.sqlite"
        run = run_plan(planning.run(model.up_problem, None).lines, init, goal, db=dbs[unit])
        assert run.goal_holds
    with WorldModel(dbs["meter"]) as m, WorldModel(dbs["millimeter"]) as mm:
        moved = 0
        for obj in m.objects():
            local = obj.iri.rsplit("#", 1)[-1]
            other = next(o.iri for o in mm.objects() if o.iri.rsplit("#", 1)[-1] == local)
            try:
                a, b = m.global_pose(obj.iri), mm.global_pose(other)
            except Exception:  # noqa: BLE001 - objects with no pose
                continue
            np.testing.assert_allclose(a[:3, 3] * 1000.0, b[:3, 3], atol=1e-3)
            np.testing.assert_allclose(a[:3, :3], b[:3, :3], atol=1e-6)
            moved += 1
        assert moved > 10


def test_a_unit_kitkb_cannot_convert_is_an_error_at_its_line(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    text = (SMALL / "init.ttl").read_text()
    bad = tmp_path / "cm.ttl"
    bad.write_text(text.replace('LengthUnit "meter"', 'LengthUnit "centimeter"'))
    line = next(i for i, s in enumerate(bad.read_text().splitlines(), 1) if "centimeter" in s)
    with pytest.raises(InputError) as e:
        Scene.from_files([bad])
    assert e.value.line == line and "centimeter" in e.value.message
    assert main(["predicates", str(bad)]) == 2
    assert f"cm.ttl:{line}: error:" in capsys.readouterr().err


def test_scenario_generate_and_transform_write_other_units(tmp_path: Path, generated: Path) -> None:
    assert main(["scenario", "generate", "--parts", "14", "--kits", "1", "--seed", "11", "--unit", "inch",
                 "-o", str(tmp_path / "in"), "-q"]) == 0
    assert Scene.from_files([tmp_path / "in" / "init.ttl"]).units.length == "inch"
    assert true_predicates([tmp_path / "in" / "init.ttl"]) == true_predicates([generated / "init.ttl"])
    out = tmp_path / "t.ttl"
    assert main(["scenario", "transform", str(generated / "init.ttl"), "-o", str(out), "--unit", "millimeter",
                 "--yaw", "33", "-q"]) == 0
    assert true_predicates([out]) == true_predicates([generated / "init.ttl"])
    assert main(["scenario", "transform", str(generated / "init.ttl"), "-o", str(out), "--turn", "nosuch",
                 "--yaw", "3"]) == 2


def test_run_says_why_it_did_not_execute(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    """A part posed 30 cm above its tray: the geometry disagrees with the file's facts; the run
    is refused with exit 1, the atom, its likely cause (the implausible pose) and a report with
    executed: false and the reason."""
    init = tmp_path / "init.ttl"
    text = (SMALL / "init.ttl").read_text()
    init.write_text(_lower(text, "part_a_1_point", -0.3))
    report = tmp_path / "r.json"
    assert main(["run", str(init), str(SMALL / "goal.ttl"), "-o", str(tmp_path / "out"), "--report",
                 str(report)]) == 1
    data = json.loads(report.read_text())
    assert data["executed"] is False
    assert "part-location-partstray part_a_1 part_a_tray" in data["reason"]
    assert "likely cause: part_a_1 floats 0.3 m above the floor of part_a_tray" in data["reason"]
    assert "not executed" in capsys.readouterr().out


def test_run_reason_names_a_unit_the_sizes_do_not_fit(tmp_path: Path) -> None:
    """Millimetre numbers declared as inches, with a part resting low: the disagreement's
    likely cause names the unit."""
    mm = _variant(SMALL / "init.ttl", tmp_path / "mm.ttl", "millimeter").read_text()
    init = tmp_path / "init.ttl"
    init.write_text(_lower(mm.replace('LengthUnit "millimeter"', 'LengthUnit "inch"'), "part_a_1_point", -300.0))
    goal = _variant(SMALL / "goal.ttl", tmp_path / "goal.ttl", "millimeter")
    goal.write_text(goal.read_text().replace('LengthUnit "millimeter"', 'LengthUnit "inch"'))
    report = tmp_path / "r.json"
    assert main(["run", str(init), str(goal), "-o", str(tmp_path / "out"), "--report", str(report), "-q"]) == 1
    reason = json.loads(report.read_text())["reason"]
    assert "likely cause" in reason and "millimeters" in reason


def test_turning_a_location_without_axes_turns_it(tmp_path: Path) -> None:
    """A pose location that leaves its axes to the model's defaults (x along x, z up) is
    given turned axes: the turned object's world box is turned too."""
    from rdflib import Graph

    from kb.core.namespaces import KTW
    from kb.io.turtle import turtle
    from kb.scenario.variants import turn

    g = Graph()
    g.parse(SMALL / "init.ttl")
    tray = next(s for s in g.subjects(KTW.hasSkuObject_Sku) if str(s).endswith("part_b_tray"))
    loc = g.value(tray, KTW.hasSolidObject_PrimaryLocation)
    g.remove((loc, KTW.hasPoseLocation_XAxis, None))
    plain = tmp_path / "plain.ttl"
    plain.write_text(turtle(g))
    turned = tmp_path / "turned.ttl"
    turned.write_text(turtle(turn(g, 90.0, ["part_b_tray"])))
    a, b = Scene.from_files([plain]), Scene.from_files([turned])
    i = a.index[str(tray)]
    np.testing.assert_allclose(b.poses[i][:3, 0], [0.0, 1.0, 0.0], atol=1e-9)
    np.testing.assert_allclose(b.hi[i] - b.lo[i], (a.hi[i] - a.lo[i])[[1, 0, 2]], atol=1e-9)


def test_the_simulated_robot_takes_crcl_in_any_length_unit() -> None:
    """CRCL after SetLengthUnits(millimeter) or (inch) moves the robot where the same program
    in metres does, at the same speed."""
    from kb import crcl
    from kb.sim import SimulatedCell

    def flange_after(unit: str, per_metre: float) -> tuple[np.ndarray, float]:
        cell = SimulatedCell(SMALL / "init.ttl")
        start = cell.robot.tip()
        target = crcl.Pose.from_matrix(start)
        point = (np.asarray(target.point) + (0.1, -0.05, 0.2)) * per_metre
        program = [crcl.SetLengthUnits(unit), crcl.SetAbsoluteSpeed(0.5 * per_metre),
                   crcl.MoveTo(crcl.Pose(tuple(point), target.x_axis, target.z_axis))]
        assert all(cell.execute(c).ok for c in program)
        return cell.robot.flange.copy(), cell.time

    metres, t = flange_after("meter", 1.0)
    for unit, per in (("millimeter", 1000.0), ("inch", 1 / 0.0254)):
        flange, t2 = flange_after(unit, per)
        np.testing.assert_allclose(flange, metres, atol=1e-9)
        assert t2 == pytest.approx(t)


def test_turning_an_axis_that_is_no_number_is_one_line(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    """An ill-typed coordinate ("0x10"^^xsd:decimal) met while turning is an input error naming
    it (the random bad-input campaign found exit 3 here)."""
    init = scenario_dirs()[0] / "init.ttl"
    text = init.read_text()
    bad = tmp_path / "bad.ttl"
    bad.write_text(re.sub(r"hasVector_I\s+[-+0-9.eE]+", 'hasVector_I "0x10"^^xsd:decimal', text))
    assert main(["scenario", "transform", str(bad), "-o", str(tmp_path / "out.ttl"), "--yaw", "23"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "is not a number" in err[0] and "0x10" in err[0], err
    assert not (tmp_path / "out.ttl").exists()
