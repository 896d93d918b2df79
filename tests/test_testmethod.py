"""kitkb testmethod: seeded test method campaigns on Dask (kb.testmethod, kb.scenario.placement).

A handful of trials of a small kit: the same rows with 1 and 2 workers, a campaign resumed
from its folder, a worker killed in the middle of a trial (its trial run again elsewhere), the
real placement against the nominal one, and bad options. The errors method's noise sweep: the
same rows with 1 and 2 workers, detection quality per level, its zero level the rows of a
campaign without noise, resumed; a trial with sensor noise is run_plan's with that noise.
"""

from __future__ import annotations

import json
import os
import shutil
import signal
import threading
import time
from pathlib import Path

import numpy as np
import pytest

from kb.cli import main
from kb.crcl.cell import execute_program
from kb.execution import Executor, run_plan
from kb.scenario import write_spec
from kb.execution.belief import Belief
from kb.scenario.placement import GAP, Placement, place_trays, placements
from kb.sim import SimulatedCell
from kb.testmethod import Options, comparable, done_rows, jobs, run_campaign, trial_path
from kb.testmethod.trial import WatchedCell, file_scene, knowledge, placed_scene, prepared, run_trial

SMALL = Options("basic", trials=4, seed=5, parts=(3,))
#: a small noise sweep: 2 trials of the errors method, each at 0 and 2 mm of position noise
SWEEP_ARGS = ["errors", "--trials", "2", "--seed", "5", "--parts", "4", "--noise-sweep", "position=0mm:2mm:2"]
SWEEP = Options("errors", trials=2, seed=5, parts=(4,), noise_sweep="position=0mm:2mm:2")


def _rows(folder: Path, n: int) -> list[dict]:
    return [json.loads(trial_path(folder, i).read_text()) for i in range(n)]


@pytest.fixture(scope="module")
def client():
    """One LocalCluster of two single-threaded worker processes for the module."""
    from distributed import Client, LocalCluster
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address="127.0.0.1:0",
                      silence_logs=50) as cluster, Client(cluster) as c:
        yield c


@pytest.fixture(scope="module")
def one_worker(tmp_path_factory) -> Path:
    """SMALL run on a LocalCluster of one worker (the command's own cluster)."""
    folder = tmp_path_factory.mktemp("one") / "campaign"
    run_campaign(SMALL, folder, workers=1)
    return folder


@pytest.fixture(scope="module")
def two_workers(tmp_path_factory, client) -> Path:
    folder = tmp_path_factory.mktemp("two") / "campaign"
    run_campaign(SMALL, folder, client=client)
    return folder


@pytest.fixture(scope="module")
def sweep_one(tmp_path_factory) -> Path:
    """SWEEP on a LocalCluster of one worker."""
    folder = tmp_path_factory.mktemp("sweep-one") / "campaign"
    run_campaign(SWEEP, folder, workers=1)
    return folder


@pytest.fixture(scope="module")
def sweep_two(tmp_path_factory, client) -> Path:
    folder = tmp_path_factory.mktemp("sweep-two") / "campaign"
    run_campaign(SWEEP, folder, client=client)
    return folder


# ------------------------------------------------------------------ placement


def test_placements_vary_stay_on_their_tables_and_do_not_overlap():
    prep = prepared(jobs(SMALL, [0])[0].spec)
    sc = prep.scenario
    nominal = {p.obj: p for p in placements(sc)}
    assert {p.table for p in nominal.values()} == {"parts_table_1", "work_table_1"}
    yaws = []
    for seed in range(20):
        _, placed = place_trays(sc, seed)
        assert [p.obj for p in placed] == list(nominal)
        assert place_trays(sc, seed)[1] == placed  # the same seed, the same placement
        for p in placed:
            dims = sc.skus["sku_parts_tray" if p.table == "parts_table_1" else "sku_kit_tray"].dims[:2]
            table = sc.floor[p.table][1]
            corners = _corners(p, dims)
            assert np.all(np.abs(corners[:, 0]) <= table[0] / 2 + 1e-9)
            assert np.all(np.abs(corners[:, 1]) <= table[1] / 2 + 1e-9)
            yaws.append(p.yaw)
        parts = [p for p in placed if p.table == "parts_table_1"]
        dims = sc.skus["sku_parts_tray"].dims[:2]
        for i, a in enumerate(parts):
            for b in parts[i + 1:]:
                assert _apart(a, b, dims) >= GAP - 1e-6, (seed, a, b)
    assert max(yaws) - min(yaws) > 300  # over the full circle


def _rounded(data):  # noqa: ANN001, ANN202
    """``data`` with its floats to 9 decimals (the placed scene is the placed file's to 1e-9 m)."""
    if isinstance(data, dict):
        return {k: _rounded(v) for k, v in data.items()}
    if isinstance(data, list):
        return [_rounded(v) for v in data]
    return round(data, 9) if isinstance(data, float) else data


def _corners(p: Placement, dims) -> np.ndarray:
    a = np.radians(p.yaw)
    r = np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])
    half = np.array([[1, 1], [-1, 1], [-1, -1], [1, -1]]) * np.array(dims) / 2
    return half @ r.T + [p.x, p.y]


def _apart(a: Placement, b: Placement, dims) -> float:
    """A lower bound of the distance between two turned rectangles (separating axes)."""
    ca, cb = _corners(a, dims), _corners(b, dims)
    best = -np.inf
    for poly in (ca, cb):
        for i in range(2):
            edge = poly[i + 1] - poly[i]
            axis = np.array([-edge[1], edge[0]]) / np.linalg.norm(edge)
            pa, pb = ca @ axis, cb @ axis
            best = max(best, pb.min() - pa.max(), pa.min() - pb.max())
    return best


def test_placed_scene_is_the_scene_of_the_placed_file():
    for job in jobs(SMALL, [1, 2]):
        prep = prepared(job.spec)
        real, placed = place_trays(prep.scenario, job.seed)
        from_file = file_scene(real, prep.goal)
        fast = placed_scene(prep.scene, prep.scenario.namespace, placed)
        assert fast.names == from_file.names
        assert np.allclose(np.nan_to_num(fast.poses, nan=7.0), np.nan_to_num(from_file.poses, nan=7.0), atol=1e-9)


@pytest.mark.parametrize("noise", [None, "position=1mm,orientation=0.5deg,misdetection=1%"])
def test_a_trial_is_run_plan_on_the_placed_file(tmp_path, noise):
    """The trial's own loop gives the report of ``run_plan(..., truth=FILE)`` on the same files,
    with the same sensor noise."""
    options = Options("errors", trials=2, seed=5, parts=(3,), faults="dropped-part@2,defective-part@4",
                      sensor_noise=noise)
    job = jobs(options, [1])[0]
    row = run_trial(job)
    prep = prepared(job.spec)
    real, _ = place_trays(prep.scenario, job.seed)
    truth, _goal = write_spec(real, tmp_path)
    run = run_plan(prep.plan, prep.init, prep.goal, truth=truth, faults=job.faults, seed=job.seed,
                   name=job.spec.name, notifier=lambda *a: None, sensor_noise=noise)
    assert row["injected"] and row["failures"]
    expected = _rounded(comparable(run.report()))  # (a sensor error's time in the cell's clock: to 1e-9 s)
    assert {k: v for k, v in _rounded(comparable(row)).items() if k in expected} == expected
    if noise:
        assert row["trial"]["noise"] == "position=1mm,orientation=0.5deg,misdetection=0.01"
        assert row["sensor"]["accuracy"]["position"] == pytest.approx(0.001) and "sensor_errors" in row
    else:
        assert "noise" not in row["trial"] and "sensor" not in row


# ------------------------------------------------------------------ the system moves to the real placement


class _Recorder(WatchedCell):
    """A cell that keeps every action begun and every command sent, to play them again."""

    def __init__(self, cell) -> None:  # noqa: ANN001
        super().__init__(cell)
        self.log: list = []

    def begin_action(self, index, action, args):  # noqa: ANN001, ANN201
        self.log.append(("begin", (index, action, args)))
        return self.cell.begin_action(index, action, args)

    def execute_program(self, commands):  # noqa: ANN001, ANN201
        self.log.append(("program", list(commands)))
        return super().execute_program(commands)


def _run(prep, scene) -> tuple[bool, _Recorder]:  # noqa: ANN001
    defs, failures = knowledge()
    cell = _Recorder(SimulatedCell(scene))
    ex = Executor(cell, prep.domain, prep.problem, defs, failures, Belief(prep.scene), notifier=lambda *a: None)
    return bool(ex.run(prep.plan).goal_holds), cell


def _replayed(prep, scene, log) -> bool:  # noqa: ANN001
    """The goal after playing ``log``'s commands open loop on a cell of ``scene``."""
    cell = SimulatedCell(scene)
    for kind, data in log:
        if kind == "begin":
            cell.begin_action(*data)
        else:
            execute_program(cell, data)
    defs, failures = knowledge()
    return Executor(cell, prep.domain, prep.problem, defs, failures, Belief(prep.scene)).goal_holds()


def test_the_real_placement_differs_from_the_nominal_one():
    job = jobs(SMALL, [2])[0]
    prep = prepared(job.spec)
    nominal = prep.scene
    _, placed = place_trays(prep.scenario, job.seed)
    real = placed_scene(nominal, prep.scenario.namespace, placed)
    built, nominal_run = _run(prep, nominal)  # the executor told the truth
    assert built and _replayed(prep, nominal, nominal_run.log)  # the commands alone build the kit there
    # a system that moved to the nominal poses (the same commands) does not build it in the real cell
    assert not _replayed(prep, real, nominal_run.log)
    built, real_run = _run(prep, real)  # kitkb's executor senses where the trays are and builds it
    assert built
    assert [d for k, d in real_run.log if k == "begin"] == [d for k, d in nominal_run.log if k == "begin"]


def test_a_trial_that_cannot_run_is_a_row_saying_why(monkeypatch):
    from kb.core.errors import NotSolvableError
    from kb.report.source import is_run_report
    from kb.testmethod import trial

    def no_plan(spec, *args, **kwargs):  # noqa: ANN001, ANN002, ANN003, ANN202
        raise NotSolvableError("no plan: the goal cannot be reached")
    monkeypatch.setattr(trial, "prepared", no_plan)
    row = trial.run_trial(jobs(SMALL, [0])[0])
    assert row["trial"]["error"] == "no plan: the goal cannot be reached" and row["executed"] is False
    assert is_run_report(row)  # kitkb report draws it among the failed trials


# ------------------------------------------------------------------ campaigns on Dask


def test_one_and_two_workers_give_the_same_rows(one_worker, two_workers):
    meta = json.loads((two_workers / "campaign.json").read_text())
    assert {"method", "seed", "trials", "options", "summary"} <= set(meta)
    assert (meta["method"], meta["seed"], meta["trials"]) == ("basic", 5, 4)
    assert meta["summary"]["kits_built"] == 4 and meta["summary"]["run"]["workers"] == 2
    one, two = _rows(one_worker, 4), _rows(two_workers, 4)
    for a, b in zip(one, two):
        assert comparable(a) == comparable(b)
        assert {"index", "seed", "method", "design", "layout", "time_s", "error"} <= set(a["trial"])
        assert a["goal_holds"] and a["trial"]["error"] is None
    layouts = [json.dumps(r["trial"]["layout"]["placed"]) for r in one]
    assert len(set(layouts)) == 4  # every trial placed and turned the trays anew
    assert one[0]["trial"]["layout"]["nominal"] == one[1]["trial"]["layout"]["nominal"]


def test_one_and_two_workers_give_the_same_sweep(sweep_one, sweep_two):
    one, two = _rows(sweep_one, 4), _rows(sweep_two, 4)
    assert [comparable(r) for r in one] == [comparable(r) for r in two]
    a, b = (json.loads((f / "campaign.json").read_text())["summary"] for f in (sweep_one, sweep_two))
    assert comparable(a["sweep"]) == comparable(b["sweep"]) and a["detection"] == b["detection"]


# ------------------------------------------------------------------ sensor noise and the noise sweep


def test_a_sweep_over_sensor_noise_keeps_its_other_keys():
    from kb.sim.noise import SensorNoise
    options = Options("errors", trials=3, seed=1, parts=(3,), sensor_noise="position=1mm,misdetection=1%",
                      noise_sweep="orientation=0deg:1deg:5")
    assert (options.levels, options.rows, options.locate(7)) == (5, 15, (1, 2))
    batch = jobs(options)
    assert [j.facts()["noise"] for j in batch[:5]] == [
        "position=1mm,misdetection=0.01", "position=1mm,orientation=0.25deg,misdetection=0.01",
        "position=1mm,orientation=0.5deg,misdetection=0.01", "position=1mm,orientation=0.75deg,misdetection=0.01",
        "position=1mm,orientation=1deg,misdetection=0.01"]
    level = SensorNoise.parse(batch[8].noise)  # the exact value of the level, not its rounded spelling
    assert level == SensorNoise(position=0.001, orientation=np.radians(0.75), misdetection=0.01)
    assert {j.seed for j in batch[5:10]} == {jobs(Options("errors", trials=3, seed=1, parts=(3,)))[1].seed}
    assert Options("errors", trials=2, sensor_noise="position=1mm").as_dict()["sensor_noise"] == "position=1mm"


def test_a_sweep_runs_every_trial_at_every_level(sweep_two):
    rows = _rows(sweep_two, 4)
    facts = [(r["trial"]["index"], r["trial"]["sweep"], r["trial"]["noise"]) for r in rows]
    assert facts == [(0, {"trial": 0, "level": 0}, "none"), (1, {"trial": 0, "level": 1}, "position=2mm"),
                     (2, {"trial": 1, "level": 0}, "none"), (3, {"trial": 1, "level": 1}, "position=2mm")]
    # each trial's seed, layout and faults the same at every level: the levels differ only by noise
    for a, b in (rows[0:2], rows[2:4]):
        assert a["trial"]["seed"] == b["trial"]["seed"] and a["trial"]["layout"] == b["trial"]["layout"]
        assert [(x["kind"], x["action_index"]) for x in a["injected"]] == \
            [(x["kind"], x["action_index"]) for x in b["injected"]]
    assert "sensor" not in rows[0] and rows[1]["sensor"]["accuracy"]["position"] == pytest.approx(0.002)
    assert rows[0]["trial"]["seed"] != rows[2]["trial"]["seed"]


def test_a_sweep_scores_detection_quality_per_level(sweep_two):
    from kb.execution.quality import by_noise, score_detection
    meta = json.loads((sweep_two / "campaign.json").read_text())
    assert meta["options"]["noise_sweep"] == "position=0mm:2mm:2" and meta["trials"] == 2
    summary = meta["summary"]
    rows = _rows(sweep_two, 4)
    sweep = summary["sweep"]
    assert (sweep["key"], sweep["unit"], [lv["value"] for lv in sweep["levels"]]) == ("position", "mm", [0.0, 2.0])
    scored = by_noise(rows)  # the quality scorer's own grouping, by the sensor each report names
    assert list(scored) == [lv["noise"] for lv in sweep["levels"]] == ["none", "position=2mm"]
    for lv in sweep["levels"]:
        quality = scored[lv["noise"]].as_dict()
        assert {k: lv[k] for k in quality} == quality and lv["runs"] == 2 and lv["kits"] == 2
        for key in ("injected", "detected", "diagnosed_right", "diagnosed_wrong", "missed"):
            assert key in lv["total"]
        assert {"false_alarms", "false_alarms_per_10k_actions", "detection"} <= set(lv)
    assert sweep["levels"][0]["total"]["injected"] > 0  # the errors method's faults were there to detect
    assert summary["detection"] == score_detection(rows).as_dict()


def test_zero_noise_gives_the_rows_of_a_campaign_without_noise(sweep_two, tmp_path, client):
    plain = Options("errors", trials=2, seed=5, parts=(4,))
    run_campaign(plain, tmp_path / "plain", client=client)
    for index, row in enumerate(_rows(tmp_path / "plain", 2)):
        level0 = comparable(_rows(sweep_two, 4)[2 * index])
        trial = level0["trial"]
        assert trial.pop("sweep") == {"trial": index, "level": 0} and trial.pop("noise") == "none"
        assert trial.pop("index") == 2 * index
        row = comparable(row)
        assert row["trial"].pop("index") == index
        assert level0 == row
    summary = json.loads((tmp_path / "plain" / "campaign.json").read_text())["summary"]
    assert "sweep" not in summary and summary["detection"]["total"]["injected"] > 0  # quality without a sweep too
    assert json.loads((tmp_path / "plain" / "campaign.json").read_text())["options"] == \
        {"parts": [4], "kits": None, "faults": plain.faults}  # the options a campaign without noise always had


def test_a_sweep_resumes(sweep_two, tmp_path, client, capsys):
    folder = tmp_path / "campaign"
    shutil.copytree(sweep_two, folder)
    trial_path(folder, 1).unlink()
    trial_path(folder, 2).write_text('{"trial": ')
    assert sorted(done_rows(SWEEP, folder)) == [0, 3]
    assert sorted(done_rows(Options("errors", trials=1, seed=5, parts=(4,), noise_sweep="position=0mm:2mm:2"),
                            folder)) == [0]
    code = main(["testmethod", *SWEEP_ARGS, "--out", str(folder), "--scheduler", client.scheduler.address, "-q"])
    out = capsys.readouterr().out
    assert code == 0
    assert [comparable(r) for r in _rows(folder, 4)] == [comparable(r) for r in _rows(sweep_two, 4)]
    assert "detection quality by position noise (position=0mm:2mm:2):" in out
    table = out.split("detection quality by position noise")[1].splitlines()
    assert table[1].split()[:3] == ["position", "mm", "noise"] and len(table) == 4
    assert table[2].split()[:2] == ["0.0", "none"] and table[3].split()[:2] == ["2.0", "position=2mm"]
    # all resumed: nothing run, the same summary as JSON
    code, data = _command(client, [*SWEEP_ARGS, "--out", str(folder)], capsys)
    assert code == 0 and data["summary"]["run"] == {**data["summary"]["run"], "ran": 0, "resumed": 4}
    assert [r["level"] for r in data["rows"]] == [0, 1, 0, 1] and data["rows"][1]["noise"] == "position=2mm"
    assert comparable(data["summary"]["sweep"]) == \
        comparable(json.loads((sweep_two / "campaign.json").read_text())["summary"]["sweep"])
    assert "2 trials at 2 noise levels, 4 runs" in data["message"]
    # the same folder with another sweep, or none, is another campaign
    for args in (["errors", "--trials", "2", "--seed", "5", "--parts", "4"],
                 [*SWEEP_ARGS[:-1], "position=0mm:3mm:2"]):
        assert main(["testmethod", *args, "--out", str(folder)]) == 2
        assert "give another --out" in capsys.readouterr().err


def test_an_interrupted_campaign_resumes(two_workers, tmp_path, client):
    folder = tmp_path / "campaign"
    shutil.copytree(two_workers, folder)
    trial_path(folder, 1).unlink()
    trial_path(folder, 3).write_text('{"trial": ')  # a file cut short: run again
    assert sorted(done_rows(SMALL, folder)) == [0, 2]
    campaign = run_campaign(SMALL, folder, client=client)
    assert (campaign.ran, campaign.resumed) == (2, 2)
    assert [comparable(r) for r in _rows(folder, 4)] == [comparable(r) for r in _rows(two_workers, 4)]
    more = Options("basic", trials=5, seed=5, parts=(3,))  # more trials extend the campaign
    assert run_campaign(more, folder, client=client).ran == 1


def test_a_killed_worker_loses_only_its_trial(two_workers, tmp_path, client):
    pids = client.run(os.getpid)
    folder = tmp_path / "campaign"
    done: dict = {}
    runner = threading.Thread(target=lambda: done.setdefault("c", run_campaign(SMALL, folder, client=client)))
    runner.start()
    killed = None
    deadline = time.monotonic() + 60
    while killed is None and runner.is_alive() and time.monotonic() < deadline:
        busy = [w for w, keys in client.processing().items() if any("kitkb-trial" in str(k) for k in keys)]
        if busy:
            killed = pids[busy[0]]
            os.kill(killed, signal.SIGKILL)  # the worker dies in the middle of its trial
        time.sleep(0.02)
    runner.join(120)
    assert killed is not None, "no trial was seen running"
    campaign = done["c"]
    assert campaign.lost == [] and campaign.ran == 4
    assert [comparable(r) for r in _rows(folder, 4)] == [comparable(r) for r in _rows(two_workers, 4)]
    assert killed not in client.run(os.getpid).values()  # that worker was replaced


# ------------------------------------------------------------------ the command


def _command(client, args: list[str], capsys) -> tuple[int, dict]:  # noqa: ANN001
    """``kitkb testmethod ARGS --scheduler (the module's cluster) --format json``."""
    code = main(["testmethod", *args, "--scheduler", client.scheduler.address, "--format", "json", "-q"])
    return code, json.loads(capsys.readouterr().out)


@pytest.mark.slow
def test_new_variety_times_a_design_never_seen(tmp_path, capsys, client):
    code, data = _command(client, ["new-variety", "--trials", "2", "--parts", "2", "--out", str(tmp_path / "c")],
                          capsys)
    assert code == 0, data
    assert data["summary"]["kits_built"] == 2 and len(data["rows"]) == 2
    rows = _rows(tmp_path / "c", 2)
    assert rows[0]["trial"]["design"] != rows[1]["trial"]["design"]  # a design never seen, each trial
    assert all(r["trial"]["receipt_to_first_command_s"] > 0 for r in rows)
    assert "trial.receipt_to_first_command_s" in data["summary"]["metrics"]


@pytest.mark.slow
def test_multi_builds_designs_in_a_seeded_order_from_storage(tmp_path, capsys, client):
    code, data = _command(client, ["multi", "--trials", "2", "--parts", "2,3", "--kits", "3", "--seed", "2",
                                   "--out", str(tmp_path / "c")], capsys)
    assert code == 0, data
    rows = _rows(tmp_path / "c", 2)
    orders = [r["trial"]["designs"] for r in rows]
    assert all(sorted(set(o)) == ["kit_design_1", "kit_design_2"] and len(o) == 3 for o in orders)
    for row in rows:
        taken = [e["args"][1] for e in row["timeline"] if e["kind"] == "action" and e["action"] == "take-kittray"]
        assert len(taken) == 3  # every kit tray fetched from storage
        assert [k["design"] for k in row["kits"]] == row["trial"]["designs"] == row["trial"]["built"]
    assert data["summary"]["kits_built"] == 6


@pytest.mark.slow
def test_errors_recovers_from_a_dropped_and_a_defective_part(tmp_path, capsys, client):
    code, data = _command(client, ["errors", "--trials", "1", "--parts", "3", "--faults",
                                   "dropped-part@2,defective-part@4", "--out", str(tmp_path / "c")], capsys)
    assert code == 0, data
    s = data["summary"]
    assert s["injected_by_kind"] == {"defective-part": 1, "dropped-part": 1}
    assert set(s["failures_by_mode"]) and s["recoveries"]["failures"] >= 2 and s["kits_built"] == 1


@pytest.mark.parametrize("args, message", [
    (["basic", "--trials", "0"], "--trials must be from 1 to"),
    (["basic", "--trials", "2000000"], "--trials must be from 1 to"),
    (["basic", "--parts", "1"], "two or more parts"),
    (["basic", "--parts", "x"], "--parts takes whole numbers"),
    (["basic", "--parts", "3,4"], "give one number"),
    (["multi", "--parts", "3"], "two or more designs"),
    (["multi", "--parts", "3,4", "--kits", "1"], "--kits (1) must be at least"),
    (["basic", "--faults", "missed-grasp=0.1"], "--faults is for the errors method"),
    (["errors", "--faults", "nothing=0.1"], "--faults:"),
    (["basic", "--kits", "2"], "--kits is for the multi method"),
    (["basic", "--workers", "0"], "--workers must be at least 1"),
    (["basic", "--sensor-noise", "position=1"], "--sensor-noise: 'position=1': a bare length is ambiguous"),
    (["errors", "--sensor-noise", "position=1mm,orientation=0.5"], "'orientation=0.5': a bare angle"),
    (["errors", "--sensor-noise", "position=1mm,loud=2"], "--sensor-noise: 'loud=2': expected KEY=VALUE"),
    (["basic", "--noise-sweep", "position=0mm:1mm:2"], "--noise-sweep is for the errors method, not basic"),
    (["multi", "--noise-sweep", "position=0mm:1mm:2"], "--noise-sweep is for the errors method, not multi"),
    (["errors", "--noise-sweep", "position=0mm:1mm"], "expected KEY=FROM:TO:N"),
    (["errors", "--noise-sweep", "position=0:1mm:2"], "'position=0': a bare length is ambiguous"),
    (["errors", "--noise-sweep", "position=0mm:1mm:1"], "a sweep needs at least 2 levels"),
    (["errors", "--noise-sweep", "loudness=0mm:1mm:2"], "'loudness' is not a noise key"),
    (["errors", "--noise-sweep", "orientation=0deg:1deg:3", "--sensor-noise", "position=1mm,orientation=0.1deg"],
     "both set orientation: give it in one of them"),
    (["errors", "--noise-sweep", "misclass=0:1%:2", "--sensor-noise", "misclassification=0.01"],
     "both set misclassification"),
    (["errors", "--trials", "1000", "--noise-sweep", "position=0mm:1mm:1001"], "more than 1,000,000 runs"),
])
def test_bad_options_exit_2_with_one_line(tmp_path, capsys, args, message):
    code = main(["testmethod", *args, "--out", str(tmp_path / "c")])
    err = capsys.readouterr().err
    assert code == 2 and message in err and err.count("\n") == 1, err
    assert not (tmp_path / "c").exists()


def test_another_campaign_in_the_folder_is_refused(two_workers, tmp_path, capsys):
    folder = tmp_path / "campaign"
    shutil.copytree(two_workers, folder)
    before = (folder / "campaign.json").read_bytes()
    code = main(["testmethod", "basic", "--trials", "4", "--seed", "6", "--parts", "3", "--out", str(folder)])
    err = capsys.readouterr().err
    assert code == 2 and "give another --out" in err and err.count("\n") == 1, err
    assert (folder / "campaign.json").read_bytes() == before
    (tmp_path / "file").write_text("x")
    for out in (tmp_path / "file", tmp_path / "file" / "campaign"):
        assert main(["testmethod", "basic", "--out", str(out)]) == 2
        assert capsys.readouterr().err.count("\n") == 1


def test_the_page_of_a_sweep_draws_its_levels(sweep_two):
    """kitkb report DIR of a sweep: the sweep's section from the summary (the browser test draws
    it); a summary whose sweep is of another shape is left out, never a failure."""
    from kb.report.campaign import campaign_body
    from kb.report.source import read_campaign
    campaign = read_campaign(sweep_two)
    body = campaign_body(campaign)
    assert 'id="sweep-detection"' in body and 'id="sweep-false-alarms"' in body and 'id="sweep-table"' in body
    assert body.index('id="sweep"') < body.index('id="summary"') and "kit_design_1 @ position=2mm" in body
    for sweep in ("x", {"levels": "x"}, {"levels": [{"value": "a"}, 3]}, {"levels": [{"value": 1, "total": 2}]}):
        campaign.meta["summary"] = {**campaign.meta["summary"], "sweep": sweep}
        assert "Campaign" in campaign_body(campaign)
