"""The executor driving a cell over kitkb's cell protocol (loopback sockets): the same plan, faults
and seed give the same failures, recoveries and goal through ``kb.sim.CellServer`` +
``kb.crcl.RemoteCell`` as in process; ``kitkb run --cell`` against a ``kitkb sim serve``
process builds the kit, and the server's own faults (announced actions: ``begin_action`` over
the wire) are diagnosed and recovered."""

from __future__ import annotations

import json
import os
import re
import select
import signal
import socket
import subprocess
import sys
from contextlib import contextmanager
from functools import lru_cache
from pathlib import Path
from typing import Iterator

import numpy as np
import pytest

from kb import planning
from kb.core.resources import ontology_path
from kb.crcl import RemoteCell
from kb.execution import Run, run_plan
from kb.sim import CellServer, FaultSpec, SimulatedCell
from kb.spatial.scene import Scene

REPO = Path(__file__).resolve().parents[1]
INIT, GOAL = str(ontology_path("scenarios/small-kit/init.ttl")), str(ontology_path("scenarios/small-kit/goal.ttl"))
MIXED = "missed-grasp=0.1,dropped-part=0.1,part-moved=0.1,part-missing=0.1,defective-part=0.1,wrong-sku=0.1," \
        "kit-tray-moved=0.3"


pytestmark = pytest.mark.usefixtures("own_directory")


@lru_cache(maxsize=None)
def plan() -> tuple[str, ...]:
    return tuple(planning.run(planning.kitting_model([INIT], [GOAL], "strips").up_problem, None).lines)


def cell(faults: str, seed: int) -> SimulatedCell:
    return SimulatedCell(Scene.from_files([INIT], declared=[GOAL]), faults=FaultSpec.parse(faults, seed=seed),
                         seed=seed)


def execute(on: object, faults: str = "", seed: int = 0) -> Run:
    return run_plan(list(plan()), INIT, GOAL, cell=on, faults=faults, seed=seed,  # type: ignore[arg-type]
                    notifier=lambda who, text: None)


def diagnoses(run: Run) -> list[tuple]:
    return [(f.mode, f.action_index, f.action, f.phase, tuple(f.objects), tuple(a.text() for a in f.violated),
             f.recovery, f.outcome, f.kit) for f in run.failures()]


@pytest.mark.parametrize("faults, seed", [("missed-grasp@6,part-missing@9", 1), (MIXED, 5)])
def test_over_the_sockets_the_same_failures_recoveries_and_goal_as_in_process(faults: str, seed: int) -> None:
    here = cell(faults, seed)
    local = execute(here)
    served = cell(faults, seed)
    with CellServer(served, sensor_port=0, command_port=0) as server:
        with RemoteCell("127.0.0.1", server.sensor_port, server.command_port, timeout=10) as remote:
            over = execute(remote)
    assert local.goal_holds is True and over.goal_holds is True
    assert local.stopped is None and over.stopped is None
    assert local.failures() and diagnoses(over) == diagnoses(local)
    assert [f.why() for f in over.failures()] == [f.why() for f in local.failures()]
    assert [(a.index, a.action, a.args, a.status, a.commands) for a in over.actions()] == \
        [(a.index, a.action, a.args, a.status, a.commands) for a in local.actions()]
    # the server's cell saw the same actions announced (begin_action over the wire): same faults
    assert served.injected == here.injected and here.injected
    assert over.report()["injected"] == []  # a remote cell's faults are its own secret
    assert local.report()["injected"] == [{"kind": x.kind, "action_index": x.action_index,
                                           "objects": [o.rsplit("#", 1)[-1] for o in x.objects],
                                           "detail": x.detail} for x in here.injected]
    a, b = here.scene(), served.scene()
    assert a.names == b.names and a.facts == b.facts
    np.testing.assert_allclose(np.nan_to_num(a.poses, nan=-1.0), np.nan_to_num(b.poses, nan=-1.0), atol=1e-9)


def test_the_in_process_default_cell_is_the_same_simulated_cell() -> None:
    by_name = execute(None, "missed-grasp@6,part-missing@9", 1)
    given = execute(cell("missed-grasp@6,part-missing@9", 1))
    assert diagnoses(by_name) == diagnoses(given)
    assert by_name.report()["injected"] == given.report()["injected"]


# --- kitkb sim serve and kitkb run --cell, as processes ------------------------------------------

def _free_pair() -> int:
    """A port P with P and P + 1 free on loopback (``--cell HOST:PORT`` means command port PORT + 1)."""
    for _ in range(50):
        with socket.socket() as a:
            a.bind(("127.0.0.1", 0))
            port = a.getsockname()[1]
            if port >= 65535:
                continue
            with socket.socket() as b:
                try:
                    b.bind(("127.0.0.1", port + 1))
                except OSError:
                    continue
            return port
    raise RuntimeError("no two consecutive free ports")


def _env() -> dict[str, str]:
    return dict(os.environ, PYTHONPATH=str(REPO))


@contextmanager
def sim_serve(*options: str) -> Iterator[str]:
    """``kitkb sim serve`` of small-kit as a process; yields the ``--cell`` address it prints."""
    proc = subprocess.Popen([sys.executable, "-m", "kb.cli", "sim", "serve", INIT, "--goal", GOAL, *options],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=_env())
    try:
        assert proc.stdout is not None
        ready, _, _ = select.select([proc.stdout], [], [], 60)
        assert ready, "kitkb sim serve printed no line"
        line = proc.stdout.readline()
        m = re.search(r"\(--cell (\S+)\)", line)
        assert m, (line, proc.stderr.read() if proc.poll() is not None and proc.stderr else "")
        yield m.group(1)
        proc.send_signal(signal.SIGINT)
        assert proc.wait(timeout=30) == 0
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()


def kitkb_run(tmp_path: Path, *options: str) -> tuple[int, str, dict]:
    report = tmp_path / "report.json"
    done = subprocess.run([sys.executable, "-m", "kb.cli", "run", INIT, GOAL, "-o", str(tmp_path / "out"),
                           "--report", str(report), *options], capture_output=True, text=True, env=_env(),
                          cwd=tmp_path, timeout=300)
    return done.returncode, done.stdout + done.stderr, json.loads(report.read_text())


def test_kitkb_run_builds_the_kit_in_a_kitkb_sim_serve_process(tmp_path: Path) -> None:
    port = _free_pair()
    with sim_serve("--sensor-port", str(port), "--command-port", str(port + 1)) as address:
        assert address == f"127.0.0.1:{port},{port + 1}"
        code, out, report = kitkb_run(tmp_path, "--cell", f"127.0.0.1:{port}")  # command port: PORT + 1
    assert code == 0, out
    assert f"execute in the cell at 127.0.0.1:{port}:" in out
    assert "execute: goal holds (from geometry); kits kit_1;" in out
    assert (report["goal_holds"], report["stopped"], report["failures"], report["injected"]) == (True, None, [], [])
    assert report["actions"] == len(plan())


def test_the_servers_own_faults_are_diagnosed_and_recovered_over_the_wire(tmp_path: Path) -> None:
    """The faults are the server's (``kitkb sim serve --faults``): the executor announces each
    action (``kitkb-action`` messages), so they strike at the same actions as in process."""
    with sim_serve("--sensor-port", "0", "--command-port", "0", "--faults", "missed-grasp@6,part-missing@9",
                   "--seed", "1") as address:
        code, out, report = kitkb_run(tmp_path, "--cell", address)
    assert code == 0, out
    assert report["goal_holds"] is True and report["injected"] == []
    assert [(f["mode"], f["action_index"], f["objects"], f["recovery"], f["outcome"]) for f in report["failures"]] == [
        ("missed-grasp", 6, ["part_a_1", "part_a_tray", "robot_1"], "retry", "retry 1 of 3"),
        ("part-missing-from-tray", 9, ["part_a_2", "part_a_tray"], "rebind",
         "recovered: bound part_a_3 from part_a_tray")]
    local = execute(None, "missed-grasp@6,part-missing@9", 1).report()
    assert report["failures"] == local["failures"]
