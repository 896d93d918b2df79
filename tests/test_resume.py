"""kitkb run --resume: a run stopped for the operator goes on as the same run (issue 29, point 5).

The seeded run: small-kit with every take-part's part taken out of the cell (part-missing=1.0)
and a domain without a partial-kit policy, so it stops for the operator when no part of sku_part_a
is left ("parts-tray-empty ... the remediation asks for an operator"). The operator puts two
parts back in their tray (a truth file: the cell as the run left it, written by the resume,
with the two parts placed as in the initial state); the resume goes on from the last stable
state in the database, senses the cell, replans and builds the kit: one run, all its actions.
"""

from __future__ import annotations

import json
import logging
from pathlib import Path

import numpy as np
import pytest
from rdflib import Graph

from kb.cli import main
from kb.core.errors import InputError
from kb.core.resources import ontologies_dir
from kb.execution import run_scenario
from kb.execution.resume import resume_run
from kb.execution.store import read_run
from kb.scenario.partial import Placement, with_locations, write_state
from kb.spatial.scene import Scene
from kb.world import WorldModel

pytestmark = pytest.mark.usefixtures("own_directory")

SMALL = ontologies_dir() / "scenarios" / "small-kit"
NS = "https://w3id.org/kitkb/scenario/small-kit#"
FAULTS = "part-missing=1.0"
BACK = ("part_a_3", "part_a_4")  # what the operator puts back in part_a_tray


@pytest.fixture(scope="module")
def no_policy(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The shipped domain without its partial-kit policy: a shortage stops for the operator."""
    text = (ontologies_dir() / "kitting-domain.ttl").read_text(encoding="utf-8")
    start = text.index("kd:execution-policy a owl:NamedIndividual")
    end = text.index(".\n", start) + 2
    path = tmp_path_factory.mktemp("domain") / "no-policy.ttl"
    path.write_text(text[:start] + text[end:], encoding="utf-8")
    return path


def _stopped(url: str, no_policy: Path) -> object:
    logging.disable(logging.WARNING)
    try:
        run = run_scenario(SMALL / "init.ttl", SMALL / "goal.ttl", faults=FAULTS, seed=3, db=url, replace=True,
                           domain_files=[no_policy])
    finally:
        logging.disable(logging.NOTSET)
    assert run.stopped and "operator" in run.stopped, run.stopped
    return run


def _operator_truth(stopped_state: Path, out: Path) -> Path:
    """The cell as the run left it, with the parts of :data:`BACK` put back where the initial
    state has them (in part_a_tray)."""
    init = Scene.from_files([SMALL / "init.ttl"])
    tray = init.index[NS + "part_a_tray"]
    places = [Placement(NS + p, NS + "part_a_tray", np.linalg.inv(init.poses[tray]) @ init.poses[init.index[NS + p]],
                        init.poses[init.index[NS + p]]) for p in BACK]
    graph = Graph()
    graph.parse(stopped_state, format="turtle")
    return write_state(with_locations(graph, places), out)


def test_a_run_stopped_for_the_operator_resumes_as_the_same_run(url: str, no_policy: Path, tmp_path: Path) -> None:
    first = _stopped(url, no_policy)
    before = first.record
    n_actions, n_failures = len(before.actions), len(before.failures)
    with WorldModel(url) as wm:
        stable_before = wm.stable_state()
    # the cell as the run left it: the parts taken out are not in it, so no plan
    out = tmp_path / "resume"
    again = resume_run(url, before.run_id, out_dir=out)
    assert again.stopped.startswith("no plan: ") and "sku_part_a" in again.stopped
    stopped_state = out / f"resume-{before.run_id}-stopped.ttl"
    assert stopped_state.is_file() and (out / f"resume-{before.run_id}-stable.ttl").is_file()
    # the operator puts two parts back: the goal holds
    truth = _operator_truth(stopped_state, tmp_path / "operator.ttl")
    done = resume_run(url, before.run_id, truth=truth, out_dir=tmp_path / "resume2")
    rec = done.record
    assert done.stopped is None and done.goal_holds, (done.stopped, rec.goal_unmet)
    assert rec.run_id == before.run_id
    # one run in the database, with all its actions: the first run's, then the resumed ones
    back = read_run(url)
    assert back.run_id == before.run_id and back.to_dict() == rec.to_dict()
    indices = [a.index for a in back.actions]
    assert indices == list(range(len(indices))) and len(indices) > n_actions
    untimed = lambda a: {k: v for k, v in a.to_dict().items() if k not in ("started", "ended")}  # noqa: E731
    assert [untimed(a) for a in back.actions[:n_actions]] == [untimed(a) for a in before.actions]
    assert len(back.failures) >= n_failures
    taken = [a.args[1].rsplit("#", 1)[-1] for a in back.actions[n_actions:] if a.action == "take-part" and a.status == "done"]
    assert sorted(taken)[:2] == sorted(BACK)[:2] and set(BACK) <= set(taken)
    with WorldModel(url) as wm:  # the stable-state counter went on
        assert wm.stable_state() > stable_before
    # the report's timeline: the two stops and resumes, in order, the actions after each resume
    report = done.report()
    assert [r["truth"] for r in report["resumes"]] == [None, str(truth.resolve())]
    kinds = [(e["kind"], e.get("index")) for e in report["timeline"] if e["kind"] in ("stop", "resume")]
    assert kinds == [("stop", n_actions - 1), ("resume", n_actions)] * 2
    times = [e["t"] for e in report["timeline"]]
    assert times == sorted(times)
    resume_at = next(e["t"] for e in reversed(report["timeline"]) if e["kind"] == "resume")
    assert any(e["kind"] == "action" and e["t"] >= resume_at and e["status"] == "done" for e in report["timeline"])
    assert report["resumes"][-1]["brought_back"] == sorted(BACK)


def test_kitkb_run_resume_on_the_command_line(tmp_path: Path, no_policy: Path, capsys: pytest.CaptureFixture) -> None:
    db = tmp_path / "world.sqlite"
    out = tmp_path / "out"
    code = main(["run", str(SMALL / "init.ttl"), str(SMALL / "goal.ttl"), "--faults", FAULTS, "--seed", "3",
                 "--domain", str(no_policy), "--db", str(db), "-o", str(out)])
    assert code == 1
    capsys.readouterr()
    code = main(["run", "--resume", "1", "--db", str(db), "-o", str(out), "--report", str(tmp_path / "r.json")])
    assert code == 1  # the cell as left: no part of sku_part_a
    text = capsys.readouterr().out
    assert "resume: run 1 after action" in text and "stopped: no plan" in text
    truth = _operator_truth(out / "resume-1" / "resume-1-stopped.ttl", tmp_path / "operator.ttl")
    code = main(["run", "--resume", "1", "--db", str(db), "--truth", str(truth), "-o", str(out),
                 "--report", str(tmp_path / "r.json")])
    assert code == 0, capsys.readouterr()
    data = json.loads((tmp_path / "r.json").read_text())
    assert data["goal_holds"] and data["stopped"] is None and len(data["resumes"]) == 2
    # a run that finished cannot be resumed
    code = main(["run", "--resume", "1", "--db", str(db)])
    assert code == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "finished (its goal holds)" in err[0]


def test_refusals_are_one_line_exit_2(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    db = tmp_path / "world.sqlite"
    # no database at all, then a database with no run
    assert main(["run", "--resume", "1", "--db", str(db)]) == 2
    assert main(["db", "load", str(SMALL / "init.ttl"), "--db", str(db)]) == 0
    capsys.readouterr()
    assert main(["run", "--resume", "1", "--db", str(db)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "no run is recorded" in err[0]
    # no --db; files beside --resume; the run's own options given again
    for argv in (["run", "--resume", "1"], ["run", str(SMALL / "init.ttl"), str(SMALL / "goal.ttl"), "--resume", "1",
                                            "--db", str(db)],
                 ["run", "--resume", "1", "--db", str(db), "--partial-kits", "leave"]):
        assert main(argv) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and "--resume" in err[0], err


def test_an_unknown_run_and_a_changed_file_are_refused(tmp_path: Path, no_policy: Path) -> None:
    db = tmp_path / "world.sqlite"
    domain = tmp_path / "domain.ttl"
    domain.write_bytes(no_policy.read_bytes())
    run = _stopped(str(db), domain)
    with pytest.raises(InputError, match="no run 7 in"):
        resume_run(db, 7)
    domain.write_text(domain.read_text() + "\n# changed\n")
    with pytest.raises(InputError, match="which has changed since: it cannot be resumed"):
        resume_run(db, run.record.run_id)
