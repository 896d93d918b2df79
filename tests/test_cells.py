"""Cells by URL (kb.cells): the registry's schemes (sim:, kitkb://, crcl://, the old HOST:PORT),
other packages' schemes through the ``kitkb.cells`` entry-point group (a dist-info on sys.path),
one-line refusals naming the URL and the known schemes, capabilities as protocols (a cell that
cannot inspect is refused for a plan that inspects, before anything is sent or stored), the
sensor-accuracy model owned outside kb.sim, and ``--cell`` on ``kitkb run`` and ``kitkb
testmethod``."""

from __future__ import annotations

import socket
import subprocess
import sys
import textwrap
from functools import lru_cache
from pathlib import Path

import pytest

from kb import planning
from kb.cells import (CAPTURE_TOLERANCE, CellRequest, SensorAccuracy, cell_accuracy, cell_schemes, check_cell,
                      open_cell, parse_cell_url)
from kb.cells.remote import CrclCell
from kb.core.errors import InputError
from kb.core.resources import ontology_path
from kb.crcl import InitCanon, RemoteCell
from kb.crcl.cell import CAPABILITIES, CellInterface, capabilities, execute_program, has, missing, require, sense_names
from kb.execution import run_plan
from kb.execution.api import PlanInputs, execute_plan
from kb.execution.records import RunRecord
from kb.model.definitions import load_definitions
from kb.model.failures import load_failure_model
from kb.planning.model import read_specs
from kb.sim import CellServer, SimulatedCell
from kb.spatial.scene import Scene
from kb.testmethod import Options, jobs
from kb.testmethod.trial import WatchedCell

REPO = Path(__file__).resolve().parents[1]
INIT, GOAL = str(ontology_path("scenarios/small-kit/init.ttl")), str(ontology_path("scenarios/small-kit/goal.ttl"))
KNOWN = "(known schemes: crcl, kitkb, mujoco, sim)"


@lru_cache(maxsize=None)
def scene() -> Scene:
    return Scene.from_files([INIT], declared=[GOAL])


@lru_cache(maxsize=None)
def plan() -> tuple[str, ...]:
    return tuple(planning.run(planning.kitting_model([INIT], [GOAL], "strips").up_problem, None).lines)


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _quiet(who: str, text: str) -> None:
    pass


# --- URLs ----------------------------------------------------------------------------------------

@pytest.mark.parametrize("text, scheme, host, port, params", [
    ("sim:", "sim", None, None, {}),
    ("sim:?faults=missed-grasp@6,part-missing=0.1&seed=3&noise=position=1mm,orientation=0.5deg", "sim", None, None,
     {"faults": "missed-grasp@6,part-missing=0.1", "seed": "3", "noise": "position=1mm,orientation=0.5deg"}),
    ("127.0.0.1:3989", "kitkb", "127.0.0.1", 3989, {}),
    ("localhost:4000,4100", "kitkb", "localhost", 4000, {"command": "4100"}),
    ("[::1]:3989", "kitkb", "::1", 3989, {}),
    ("kitkb://cell.lab:5000?command=6000&timeout=2.5", "kitkb", "cell.lab", 5000, {"command": "6000", "timeout": "2.5"}),
    ("KITKB://cell.lab", "kitkb", "cell.lab", None, {}),
    ("crcl://robot:64444?sensor=camera:3989", "crcl", "robot", 64444, {"sensor": "camera:3989"}),
    ("ros2://bridge/kitting", "ros2", "bridge", None, {}),
])
def test_a_cell_url_parses_to_its_scheme_host_port_and_parameters(text, scheme, host, port, params) -> None:
    url = parse_cell_url(text)
    assert (url.scheme, url.host, url.port, dict(url.params)) == (scheme, host, port, params)
    assert url.text == text


@pytest.mark.parametrize("text, why", [
    ("", "not a cell URL"),
    ("just-a-name", "not a cell URL"),
    ("kitkb://h:99999", "not a cell URL"),
    ("sim:?seed=1&seed=2", "parameter 'seed' given twice"),
    ("foo://x", "unknown scheme 'foo'"),
    ("sim:?bogus=1", "unknown parameter 'bogus' for sim:"),
    ("sim:?seed=x", "seed='x' is not a whole number"),
    ("sim:?faults=nothing=0.1", "unknown fault kind 'nothing'"),
    ("sim:?noise=position=1", "a bare length is ambiguous"),
    ("kitkb://127.0.0.1:3989?protocol=old", "unknown parameter 'protocol' for kitkb:"),
    ("kitkb://127.0.0.1:3989?timeout=-1", "must not be negative"),
    ("crcl://127.0.0.1:64444", "needs the sensor that sees its cell"),
    ("crcl://127.0.0.1:64444?sensor=cam:port", "sensor='cam:port': expected HOST:PORT"),
])
def test_a_bad_url_is_one_line_naming_it_and_the_known_schemes(text: str, why: str) -> None:
    with pytest.raises(InputError) as info:
        open_cell(text, CellRequest(scene=scene()))
    message = str(info.value)
    assert "\n" not in message and why in message and KNOWN in message
    assert f"cell {text.strip()!r}" in message


def test_an_unreachable_cell_is_refused_before_the_run_naming_the_address() -> None:
    port = _free_port()
    for text in (f"kitkb://127.0.0.1:{port}?command={port}", f"127.0.0.1:{port},{port}",
                 f"crcl://127.0.0.1:{port}?sensor=127.0.0.1:{port}"):
        with pytest.raises(InputError, match=rf"cell '.*{port}.*': nothing answers at 127.0.0.1:{port} .*known schemes"):
            open_cell(text, CellRequest(timeout=2))


def test_kitkb_run_with_a_bad_cell_exits_2_with_one_line(tmp_path: Path) -> None:
    done = subprocess.run([sys.executable, "-m", "kb.cli", "run", INIT, GOAL, "-o", str(tmp_path / "out"),
                           "--cell", "ros2://bridge"], capture_output=True, text=True, cwd=tmp_path,
                          env={"PYTHONPATH": str(REPO), "PATH": "/usr/bin:/bin"})
    assert done.returncode == 2, done.stderr
    lines = [line for line in done.stderr.splitlines() if line.strip()]
    assert len(lines) == 1 and "ros2://bridge" in lines[0] and "unknown scheme 'ros2'" in lines[0] \
        and KNOWN in lines[0], done.stderr
    assert "Traceback" not in done.stderr


# --- sim: ----------------------------------------------------------------------------------------

def test_sim_is_the_default_and_its_parameters_stand_for_the_request() -> None:
    by_url = open_cell("sim:?faults=missed-grasp@6&seed=4&noise=position=1mm", CellRequest(scene=scene()))
    by_request = open_cell(None, CellRequest(scene=scene(), faults="missed-grasp@6", seed=4,
                                             accuracy=SensorAccuracy(position=0.001)))
    for cell in (by_url, by_request):
        assert isinstance(cell, SimulatedCell)
        assert dict(cell.faults.spec.at) == {6: ("missed-grasp",)} and cell.faults.spec.seed == 4
        assert cell.accuracy == SensorAccuracy(position=0.001)
        assert cell_accuracy(cell, None) == SensorAccuracy(position=0.001)
    assert by_url.url.startswith("sim:?") and by_request.url == "sim:"
    # the URL's noise is over the request's accuracy: its keys replace, the others stay
    over = open_cell("sim:?noise=orientation=1deg", CellRequest(scene=scene(), accuracy=SensorAccuracy(position=0.002)))
    assert over.accuracy.position == 0.002 and over.accuracy.orientation == pytest.approx(0.017453292519943295)


@pytest.mark.parametrize("url, request_kw, why", [
    ("sim:?seed=3", {"seed": 4}, "seed=3 and a seed of 4 given besides"),
    ("sim:?faults=missed-grasp@6", {"faults": "part-missing@2"}, "given besides"),
    ("sim:", {"scene": None}, "needs the initial state it holds"),
])
def test_sim_refuses_what_cannot_work(url: str, request_kw: dict, why: str) -> None:
    kw = {"scene": scene(), **request_kw}
    with pytest.raises(InputError, match=why):
        open_cell(url, CellRequest(**kw))


def test_the_same_run_by_url_as_with_the_cell_given() -> None:
    by_url = run_plan(list(plan()), INIT, GOAL, cell="sim:?faults=missed-grasp@6,part-missing@9&seed=1",
                      notifier=_quiet)
    given = run_plan(list(plan()), INIT, GOAL, faults="missed-grasp@6,part-missing@9", seed=1, notifier=_quiet)
    assert by_url.goal_holds and given.goal_holds
    assert by_url.report()["injected"] == given.report()["injected"] != []
    assert [(f.mode, f.action_index) for f in by_url.failures()] == [(f.mode, f.action_index) for f in given.failures()]


# --- other packages' schemes ---------------------------------------------------------------------

PLUGIN = '''
"""A cell of another package: it moves and senses (a simulated cell behind it), and hears
which action starts, but cannot inspect."""
from kb.sim import SimulatedCell

OPENED = []


class Partial:
    def __init__(self, cell, url):
        self.cell, self.url = cell, url

    def execute(self, command):
        return self.cell.execute(command)

    def sense(self, query, *, by="class"):
        return self.cell.sense(query, by=by)

    def begin_action(self, index, action, args):
        self.cell.begin_action(index, action, args)


def open_partial(url, request):
    OPENED.append((url.text, url.host, dict(url.params), request.seed))
    return Partial(SimulatedCell(request.scene, seed=request.seed or 0), url.text)
'''


@pytest.fixture
def plugin(tmp_path: Path, monkeypatch: pytest.MonkeyPatch):
    """A distribution installed on sys.path (its dist-info declares the entry point)."""
    (tmp_path / "kitkb_partial_cell.py").write_text(textwrap.dedent(PLUGIN))
    info = tmp_path / "kitkb_partial_cell-0.1.dist-info"
    info.mkdir()
    (info / "METADATA").write_text("Metadata-Version: 2.1\nName: kitkb-partial-cell\nVersion: 0.1\n")
    (info / "entry_points.txt").write_text("[kitkb.cells]\npartial = kitkb_partial_cell:open_partial\n"
                                           "sim = kitkb_partial_cell:open_partial\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    yield
    sys.modules.pop("kitkb_partial_cell", None)


@pytest.mark.usefixtures("plugin")
def test_another_package_adds_a_scheme_through_the_entry_point_group() -> None:
    assert cell_schemes() == ["crcl", "kitkb", "mujoco", "partial", "sim"]
    cell = open_cell("partial://somewhere?x=1", CellRequest(scene=scene(), seed=7))
    import kitkb_partial_cell  # type: ignore[import-not-found]
    assert kitkb_partial_cell.OPENED == [("partial://somewhere?x=1", "somewhere", {"x": "1"}, 7)]
    assert capabilities(cell) == {"move", "sense", "begin-action"}
    assert not isinstance(cell, CellInterface)
    # a built-in scheme cannot be taken over
    assert isinstance(open_cell("sim:", CellRequest(scene=scene())), SimulatedCell)
    # unknown schemes name the plugin's too
    with pytest.raises(InputError, match=r"known schemes: crcl, kitkb, mujoco, partial, sim"):
        open_cell("nope:", CellRequest())


@pytest.mark.usefixtures("plugin")
def test_a_cell_that_cannot_inspect_runs_a_plan_without_look_for_part_and_refuses_one_with_it() -> None:
    run = run_plan(list(plan()), INIT, GOAL, cell="partial://here", notifier=_quiet)
    assert run.stopped is None and run.report()["injected"] == []
    # nothing inspected: no part is found good (its point lost), every other point is kept
    lost = [lost for k in run.kit_scores for lost in k.lost]
    assert lost and {x.predicate for x in lost} == {"part-quality-ok"}
    inspecting = [f"(look-for-part {_robot()} {part} {tray})" for part, tray in _parts()[:1]] + list(plan())
    store = _Store()
    cell = open_cell("partial://here", CellRequest(scene=scene()))
    with pytest.raises(InputError, match=r"^error: the cell partial://here cannot inspect parts, which the plan needs$"):
        execute_plan(inspecting, cell, _inputs(), RunRecord("x", 0), store=store)
    assert store.calls == [] and cell.cell.commands == 0  # refused before the store or the cell heard of it


def _robot() -> str:
    return next(line.split()[1] for line in plan() if line.startswith("(take-part"))


def _parts() -> list[tuple[str, str]]:
    return [(line.split()[2], line.split()[3]) for line in plan() if line.startswith("(take-part")]


@lru_cache(maxsize=None)
def _inputs() -> PlanInputs:
    domain, problem = read_specs([INIT], [GOAL], encoding="numeric")
    return PlanInputs(domain, problem, scene(), load_definitions(None), load_failure_model(None))


class _Store:
    def __init__(self) -> None:
        self.calls: list[str] = []

    def __getattr__(self, name: str):
        return lambda *a, **k: self.calls.append(name)


# --- capabilities --------------------------------------------------------------------------------

def test_capabilities_of_the_built_in_cells() -> None:
    sim = SimulatedCell(scene())
    assert capabilities(sim) == set(CAPABILITIES) - {"move-program"}  # command by command, in process
    remote = RemoteCell("127.0.0.1", 1, 2)  # connects on first use: nothing reached here
    assert capabilities(remote) == {"move", "move-program", "sense", "inspect", "begin-action"}
    crcl = CrclCell(RemoteCell("127.0.0.1", 1, 2), RemoteCell("127.0.0.1", 1, 2))
    assert capabilities(crcl) == {"move", "move-program", "sense", "begin-action"}
    assert missing(crcl, ["move", "inspect", "ground-truth"]) == ["inspect", "ground-truth"]
    with pytest.raises(InputError, match="cannot inspect parts, tell its ground truth, which the run needs"):
        require(crcl, ["move", "inspect", "ground-truth"])
    # a wrapper declares what it forwards: the watched cell's own, programs and names on top
    assert capabilities(WatchedCell(crcl)) == {"move", "move-program", "sense", "sense-names", "begin-action"}
    assert capabilities(WatchedCell(sim)) == set(CAPABILITIES)
    assert not has(WatchedCell(crcl), "inspect") and has(WatchedCell(sim), "ground-truth")


def test_execute_program_and_sense_names_on_a_cell_that_moves_and_senses_only() -> None:
    class Minimal:
        def __init__(self) -> None:
            self.cell = SimulatedCell(scene())

        def execute(self, command):  # noqa: ANN001, ANN202
            return self.cell.execute(command)

        def sense(self, query, *, by="class"):  # noqa: ANN001, ANN202
            return self.cell.sense(query, by=by)

    cell = Minimal()
    assert capabilities(cell) == {"move", "sense"}
    assert [s.done for s in execute_program(cell, [InitCanon()])] == [True]
    names = [n for n in scene().names[:3]]
    assert [o.name for o in sense_names(cell, names)] == [o.name for o in cell.cell.sense_names(names)]


# --- cells behind sockets ------------------------------------------------------------------------

def test_kitkb_url_drives_a_cell_server_as_the_old_address_did() -> None:
    served = SimulatedCell(scene(), seed=0)
    with CellServer(served, sensor_port=0, command_port=0) as server:
        url = f"kitkb://127.0.0.1:{server.sensor_port}?command={server.command_port}&timeout=20"
        cell = open_cell(url, CellRequest())
        try:
            assert isinstance(cell, RemoteCell) and cell.url == url
            run = run_plan(list(plan()), INIT, GOAL, cell=cell, notifier=_quiet)
        finally:
            cell.close()
    assert run.goal_holds and run.stopped is None
    assert served.commands > 0 and served.world.passed  # the server's cell moved and inspected


def test_crcl_url_pairs_a_controller_with_a_sensor() -> None:
    served = SimulatedCell(scene(), seed=0)
    with CellServer(served, sensor_port=0, command_port=0) as server:
        url = f"crcl://127.0.0.1:{server.command_port}?sensor=127.0.0.1:{server.sensor_port}&timeout=20"
        cell = open_cell(url, CellRequest())
        try:
            assert isinstance(cell, CrclCell) and repr(cell) == f"CrclCell({url})"
            assert capabilities(cell) == {"move", "move-program", "sense", "begin-action"}
            robot = cell.sense("Robot", by="class")
            assert [o.cls for o in robot] == ["Robot"]
            assert [s.done for s in cell.execute_program([InitCanon()])] == [True]
            assert served.commands >= 1
        finally:
            cell.close()


def test_a_run_on_a_crcl_controller_and_a_sensor_builds_the_kit_uninspected() -> None:
    served = SimulatedCell(scene(), seed=0)
    with CellServer(served, sensor_port=0, command_port=0) as server:
        url = f"crcl://127.0.0.1:{server.command_port}?sensor=127.0.0.1:{server.sensor_port}&timeout=20"
        run = run_plan(list(plan()), INIT, GOAL, cell=url, notifier=_quiet)
    assert run.goal_holds and run.stopped is None and run.failures() == []
    assert served.world.passed == set()  # nothing was inspected
    [kit] = run.kit_scores
    assert kit.score == kit.max_score - len(kit.lost) and {x.predicate for x in kit.lost} == {"part-quality-ok"}
    assert run.report()["injected"] == [] and served.action is not None  # the actions were announced


# --- the accuracy model and the capture tolerance, outside kb.sim --------------------------------

def test_the_accuracy_model_is_owned_by_kb_cells_and_kept_under_its_old_name() -> None:
    from kb.sim.noise import SensorNoise
    from kb.sim.robot import GRASP_TOLERANCE
    from kb.execution.looks import CAPTURE
    assert SensorNoise is SensorAccuracy
    assert CAPTURE == CAPTURE_TOLERANCE == GRASP_TOLERANCE == 0.002
    assert SensorAccuracy.parse("position=1mm,misclass=1%").text() == "position=1mm,misclass=0.01"


def test_execution_and_testmethod_never_import_the_simulator() -> None:
    """The forbidden contract is in pyproject.toml; run it (import-linter sees deferred imports)."""
    done = subprocess.run([str(Path(sys.executable).parent / "lint-imports"), "--no-cache", "--no-logo",
                           "--contract", _contract_id()], capture_output=True, text=True, cwd=REPO)
    assert done.returncode == 0 and "KEPT" in done.stdout, done.stdout + done.stderr


def _contract_id() -> str:
    import tomllib
    contracts = tomllib.loads((REPO / "pyproject.toml").read_text())["tool"]["importlinter"]["contracts"]
    found = [c for c in contracts if c.get("forbidden_modules") == ["kb.sim"]]
    assert found and set(found[0]["source_modules"]) == {"kb.execution", "kb.testmethod"}
    return found[0].get("id", "")


# --- kitkb testmethod --cell -------------------------------------------------------------------------

@pytest.mark.parametrize("kw, why", [
    ({"method": "errors", "trials": 1, "cell": "kitkb://127.0.0.1:3989"}, "the errors method injects faults"),
    ({"method": "basic", "trials": 2, "cell": "kitkb://127.0.0.1:3989"}, "one trial per campaign"),
    ({"method": "basic", "cell": "sim:?seed=3"}, "take no parameters"),
    ({"method": "basic", "cell": "nope://x"}, "unknown scheme 'nope'"),
])
def test_testmethod_refuses_cells_it_cannot_use(kw: dict, why: str) -> None:
    with pytest.raises(InputError, match=why):
        Options(**kw)


def test_testmethod_sim_cell_is_every_trial_its_own() -> None:
    plain, with_sim = jobs(Options("basic", trials=2)), jobs(Options("basic", trials=2, cell="sim:"))
    assert [j.cell for j in with_sim] == [None, None] and plain == with_sim
    assert jobs(Options("basic", trials=1, cell="kitkb://127.0.0.1:1"))[0].cell == "kitkb://127.0.0.1:1"
    assert Options("basic", trials=1, cell="kitkb://h:1").as_dict()["cell"] == "kitkb://h:1"
    assert "cell" not in Options("basic").as_dict()


def test_faults_are_checked_by_the_simulated_cell_without_a_scene() -> None:
    assert check_cell("sim:?faults=missed-grasp@6").scheme == "sim"
    with pytest.raises(InputError, match="--faults: unknown fault kind 'nothing'"):
        Options("errors", faults="nothing=0.1")


def test_a_trial_on_one_cell_at_a_url_runs_there_with_the_cells_own_placement() -> None:
    from kb.testmethod.trial import prepared, run_trial
    options = Options("basic", trials=1, parts=(3,), cell="kitkb://127.0.0.1:1")
    [job] = jobs(options)
    served = SimulatedCell(prepared(job.spec).scene)  # the cell holds the design as laid out
    with CellServer(served, sensor_port=0, command_port=0) as server:
        url = f"kitkb://127.0.0.1:{server.sensor_port}?command={server.command_port}&timeout=20"
        from dataclasses import replace
        row = run_trial(replace(job, cell=url))
    assert row["trial"]["error"] is None and row["executed"] and row["goal_holds"], row["trial"]
    assert row["trial"]["layout"]["placed"] is None and row["trial"]["layout"]["cell"] == url
    assert row["trial"]["built"] == list(job.order) and served.commands > 0
    assert row["injected"] == []  # the cell's own faults are its secret


def test_testmethod_refuses_a_cell_that_does_not_answer_before_any_trial() -> None:
    port = _free_port()
    options = Options("basic", trials=1, cell=f"kitkb://127.0.0.1:{port}?command={port}&timeout=2")
    with pytest.raises(InputError, match=f"nothing answers at 127.0.0.1:{port}"):
        options.reach()
    Options("basic", cell="sim:").reach()  # the simulator needs nothing


def test_the_entry_point_group_in_pyproject_declares_the_built_in_schemes() -> None:
    import tomllib
    from kb.cells.registry import BUILTIN, ENTRY_POINT_GROUP
    declared = tomllib.loads((REPO / "pyproject.toml").read_text())["project"]["entry-points"][ENTRY_POINT_GROUP]
    assert declared == {scheme: f"{module}:{fn}" for scheme, (module, fn) in BUILTIN.items()}
