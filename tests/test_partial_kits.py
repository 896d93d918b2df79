"""Kits in the best order, partial kits by decision (issue 29, point 3).

When the usable parts cannot finish every kit, the executor finishes as many kits as they allow
(:func:`kb.planning.achievable.choose_kits`: whole kits, never two halves) and follows the
partial-kit policy for each other kit: the domain's (``soap:hasExecutionPolicy_PartialKits``,
kitting-domain.ttl: deliver) or the run's (``kitkb run --partial-kits deliver|leave``). The run's
goal is still the whole goal: ``goal_holds`` false, the report's ``partial_kits`` saying what each
kit lacks, exit 1. Checked against the simulator's ground truth, not only the executor's belief.

The scenario is generated (8 parts, 2 kits, seed 1): kit_1 needs sku_part_b 2 and sku_part_c 2,
kit_2 needs sku_part_a 2, sku_part_b 1 and sku_part_c 1; sku_part_a has 3 parts. Taking two
parts of sku_part_a out of the cell leaves one too few for kit_2.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest
from rdflib import XSD, Graph, Literal

from kb import planning
from kb.cli import main
from kb.core.errors import InputError
from kb.core.namespaces import KTW
from kb.core.resources import ontology_path
from kb.execution import run_plan
from kb.execution.events import KitsChosen
from kb.model.policy import delivers_partial_kits
from kb.planning.achievable import achievable, choose_kits, delivered, replan_achievable
from kb.planning.model import read_specs
from kb.scenario import write_scenario
from kb.sim import FaultSpec, SimulatedCell
from kb.spatial.scene import Scene
from test_execution import goal_in_ground_truth, kit_contents


pytestmark = pytest.mark.usefixtures("own_directory")


@pytest.fixture(scope="module")
def two_kits(tmp_path_factory: pytest.TempPathFactory) -> tuple[str, str, tuple[str, ...]]:
    init, goal = write_scenario(tmp_path_factory.mktemp("two-kits"), parts=8, kits=2, seed=1)
    model = planning.kitting_model([str(init)], [str(goal)], "strips")
    return str(init), str(goal), tuple(planning.run(model.up_problem, None).lines)


def needs_of(init: str, goal: str) -> dict[str, dict[str, int]]:
    _domain, spec = read_specs([init], [goal], "numeric")
    out: dict[str, dict[str, int]] = {}
    for left, right in spec.goal_equal:
        out.setdefault(left[1], {})[left[2]] = int(spec.values[right])
    return out


def run_without(scenario: tuple, parts: list[str], **kw: Any):  # noqa: ANN201
    """The plan on a simulated cell from which ``parts`` were taken out before the run (the
    executor finds out at its take-part)."""
    init, goal, plan = scenario

    class Short(SimulatedCell):
        def __init__(self, *a: Any, **k: Any) -> None:
            super().__init__(*a, **k)
            for name in parts:
                self.world.remove(self.world.index[next(n for n in self.world.index if n.endswith("#" + name))])

    cell = Short(Scene.from_files([init], declared=[goal]), faults=FaultSpec.parse("", seed=0), seed=0)
    events: list = []
    run = run_plan(list(plan), init, goal, cell=cell, notifier=lambda who, text: None, on_event=events.append, **kw)
    return run, cell, events


# --- which kits: as many whole kits as the parts allow ------------------------------------------

def test_parts_for_one_of_two_kits_make_one_whole_kit_not_two_halves() -> None:
    needs = {"kit_1": {"a": 2, "b": 1}, "kit_2": {"a": 2, "b": 1}}
    assert choose_kits(needs, {"a": 2, "b": 2}) == ["kit_1"]
    assert choose_kits(needs, {"a": 4, "b": 2}) == ["kit_1", "kit_2"]
    assert choose_kits(needs, {"a": 1, "b": 2}) == []


def test_the_most_kits_win_over_the_plan_order() -> None:
    """Greedy in kit order would give the 2 parts of sku a to kit_1 and finish one kit; two can be finished."""
    assert choose_kits({"kit_1": {"a": 2}, "kit_2": {"a": 1}, "kit_3": {"a": 1}}, {"a": 2}) == ["kit_2", "kit_3"]


def test_ties_go_to_the_kit_with_more_parts_in_it_then_by_name() -> None:
    needs = {"kit_1": {"a": 1}, "kit_2": {"a": 1}}
    assert choose_kits(needs, {"a": 1}) == ["kit_1"]
    assert choose_kits(needs, {"a": 1}, placed={"kit_2": 2}) == ["kit_2"]
    assert choose_kits({"kit_1": {"a": 0}, "kit_2": {"a": 1}}, {"a": 0}) == ["kit_1"]  # nothing left to put in


def test_a_kit_left_on_the_work_table_blocks_the_others() -> None:
    """With leave, kit_1 standing on the work table stays there unless it is finished: kit_2 cannot be built after it."""
    needs = {"kit_1": {"a": 2}, "kit_2": {"a": 1}}
    assert choose_kits(needs, {"a": 1}, standing=["kit_1"], policy="deliver") == ["kit_2"]
    assert choose_kits(needs, {"a": 1}, standing=["kit_1"], policy="leave") == []
    assert choose_kits(needs, {"a": 2}, standing=["kit_1"], policy="leave") == ["kit_1"]


def test_the_achievable_goal_gives_the_finished_kit_all_its_parts(two_kits: tuple) -> None:
    """From the initial state with all but one part of sku_part_b unusable: kit_2 (needs one)
    is finished, kit_1 (needs two) is not: delivered partial it gets the parts left of the
    other SKUs; left, none, and the goal does not deliver it."""
    init, goal, _plan = two_kits
    assert needs_of(init, goal) == {"kit_1": {"sku_part_b": 2, "sku_part_c": 2},
                                    "kit_2": {"sku_part_a": 2, "sku_part_b": 1, "sku_part_c": 1}}
    domain, spec = read_specs([init], [goal], "numeric")
    out = {"part_b_2", "part_b_3", "part_b_4"}
    state, choice = achievable(domain, spec, spec.facts, dict(spec.values), out, "deliver")
    assert (choice.finished, choice.lacking) == (["kit_2"], {"kit_1": {"sku_part_b": 2}})
    assert state.shortage == []
    assert {k[1:]: v for k, v in state.quota.items()} == {
        ("kit_2", "sku_part_a"): ["part_a_1", "part_a_2"], ("kit_2", "sku_part_b"): ["part_b_1"],
        ("kit_2", "sku_part_c"): ["part_c_1"], ("kit_1", "sku_part_b"): [],
        ("kit_1", "sku_part_c"): ["part_c_2", "part_c_3"]}
    assert ("kit-location-lbwk", "kit_1", "finished_kit_receiver_1") in state.goal
    state, choice = achievable(domain, spec, spec.facts, dict(spec.values), out, "leave")
    assert (choice.finished, choice.lacking) == (["kit_2"], {"kit_1": {"sku_part_b": 2, "sku_part_c": 2}})
    assert state.quota[("quantity-kit", "kit_1", "sku_part_c")] == []
    assert not any("kit_1" in g for g in state.goal)
    assert choice.as_list() == [{"kit": "kit_1", "outcome": "left", "lacks": {"sku_part_b": 2, "sku_part_c": 2}}]
    result, _choice = replan_achievable(domain, spec, spec.facts, dict(spec.values), out, "deliver")
    assert not any("part_b_2" in line or "part_b_3" in line for line in result.lines)
    assert sum(line.startswith("(put-part ") for line in result.lines) == 4 + 2  # kit_2 whole, kit_1 its two c


def test_a_kit_already_in_its_box_takes_no_more_parts(two_kits: tuple) -> None:
    """A kit delivered partial earlier (its goal facts hold: it is in its box) is closed: no
    part is planned into it again, whatever the policy, and what it lacks stays lacking. (A
    campaign run planned the parts left into a kit already delivered and the planner proved the
    goal unreachable: the run stopped with "no plan".)"""
    init, goal, _plan = two_kits
    domain, spec = read_specs([init], [goal], "numeric")
    in_box = ("kit-location-lbwk", "kit_1", "finished_kit_receiver_1")
    assert in_box in spec.goal
    facts = set(spec.facts) | {in_box}
    out = {"part_b_2", "part_b_3", "part_b_4"}
    for policy in ("deliver", "leave"):
        state, choice = achievable(domain, spec, facts, dict(spec.values), out, policy)
        assert choice.finished == ["kit_2"], policy
        assert choice.lacking["kit_1"] == {"sku_part_b": 2, "sku_part_c": 2}, policy
        assert all(v == [] for k, v in state.quota.items() if k[1] == "kit_1"), policy
    assert delivered(spec.goal, facts, ["kit_1", "kit_2"]) == {"kit_1"}
    assert delivered(spec.goal, set(spec.facts), ["kit_1", "kit_2"]) == set()


def test_an_unknown_policy_is_refused(two_kits: tuple) -> None:
    init, goal, _plan = two_kits
    domain, spec = read_specs([init], [goal], "numeric")
    with pytest.raises(InputError, match="partial-kit policy 'keep' is not one of: deliver, leave"):
        achievable(domain, spec, spec.facts, dict(spec.values), (), "keep")


# --- the run: one kit finished, the other delivered partial or left -----------------------------

def test_one_part_too_few_delivers_the_other_kit_partial(two_kits: tuple) -> None:
    init, goal, _plan = two_kits
    run, cell, events = run_without(two_kits, ["part_a_2", "part_a_3"])
    report = run.report()
    assert run.stopped is None and run.goal_holds is False
    assert report["partial_kits"] == [{"kit": "kit_2", "outcome": "delivered partial", "lacks": {"sku_part_a": 1}}]
    assert report["goal_unmet"] == ["quantity-kit(kit_2, sku_part_a) = capacity-kit(kit_2, sku_part_a) (1, not 2)"]
    chosen = [e for e in events if isinstance(e, KitsChosen)]
    assert [e.text() for e in chosen] == ["  kits the parts allow: kit_1 finished; kit_2 delivered partial "
                                          "(lacks sku_part_a 1)"]
    # the ground truth: kit_1 whole and delivered, kit_2 delivered with all but the missing part
    assert goal_in_ground_truth(cell, init, goal) == ["quantity-kit kit_2 sku_part_a != capacity-kit kit_2 sku_part_a"]
    contents = kit_contents(cell)
    assert [s for _p, s in contents["kit_1"]] == ["sku_part_b", "sku_part_b", "sku_part_c", "sku_part_c"]
    assert [s for _p, s in contents["kit_2"]] == ["sku_part_a", "sku_part_b", "sku_part_c"]


def test_one_part_too_few_with_leave_leaves_the_other_kit_on_the_table(two_kits: tuple) -> None:
    init, goal, _plan = two_kits
    run, cell, _events = run_without(two_kits, ["part_a_2", "part_a_3"], partial_kits="leave")
    report = run.report()
    assert run.stopped is None and run.goal_holds is False
    assert report["partial_kits"] == [{"kit": "kit_2", "outcome": "left",
                                       "lacks": {"sku_part_a": 1, "sku_part_b": 1, "sku_part_c": 1}}]
    wrong = goal_in_ground_truth(cell, init, goal)
    assert "kit-location-lbwk kit_2 finished_kit_receiver_2" in wrong  # not delivered
    assert "kit-location-lbwk kit_1 finished_kit_receiver_1" not in wrong  # kit_1 is
    assert not any("kit_1" in w for w in wrong)
    assert kit_contents(cell)["kit_2"] == [("part_a_1", "sku_part_a")]  # what it had when it was left


def test_kitkb_run_says_the_partial_kits_and_exits_1(two_kits: tuple, tmp_path: Path,
                                                     capsys: pytest.CaptureFixture) -> None:
    init, goal, _plan = two_kits
    report = tmp_path / "report.json"
    page = tmp_path / "report.html"
    assert main(["run", init, goal, "-o", str(tmp_path / "out"), "--faults", "part-missing@23,part-missing@24,"
                 "part-missing@25", "--partial-kits", "leave", "--report", str(report),
                 "--report-html", str(page)]) == 1
    out = capsys.readouterr().out
    assert "kits the parts allow: kit_1 finished; kit_2 left (lacks sku_part_a 2, sku_part_b 1, sku_part_c 1)" in out
    assert "; partial kits kit_2 left (lacks sku_part_a 2, sku_part_b 1, sku_part_c 1)" in out
    data = json.loads(report.read_text())
    assert data["goal_holds"] is False and data["stopped"] is None
    assert data["partial_kits"] == [{"kit": "kit_2", "outcome": "left",
                                     "lacks": {"sku_part_a": 2, "sku_part_b": 1, "sku_part_c": 1}}]
    assert "partial kits: kit_2 left (lacks sku_part_a 2, sku_part_b 1, sku_part_c 1)" in page.read_text()


def test_a_bad_partial_kits_option_is_refused(two_kits: tuple, tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    init, goal, _plan = two_kits
    with pytest.raises(SystemExit) as e:
        main(["run", init, goal, "-o", str(tmp_path / "out"), "--partial-kits", "keep"])
    assert e.value.code == 2
    assert "--partial-kits: invalid choice: 'keep'" in capsys.readouterr().err


# --- the policy in the ontology -----------------------------------------------------------------

def test_the_shipped_domain_delivers_partial_kits() -> None:
    graph = Graph()
    for name in ("soap.ttl", "kitting-domain.ttl"):
        graph.parse(ontology_path(name), format="turtle")
    assert delivers_partial_kits(graph) is True


POLICY = """@prefix soap: <https://w3id.org/kitkb/soap#> .
@prefix owl: <http://www.w3.org/2002/07/owl#> .
@prefix ex: <https://example.org/x#> .
ex:policy a owl:NamedIndividual , soap:ExecutionPolicy ;
    soap:hasExecutionPolicy_PartialKits {policy} .
{extra}
"""


def test_a_domain_without_a_policy_has_none_and_one_that_leaves_leaves() -> None:
    graph = Graph()
    graph.parse(ontology_path("soap.ttl"), format="turtle")
    assert delivers_partial_kits(graph) is None
    graph.parse(data=POLICY.format(policy="soap:LeaveKit", extra=""), format="turtle")
    assert delivers_partial_kits(graph) is False


def test_two_policies_that_disagree_or_a_policy_without_its_boolean_are_refused() -> None:
    graph = Graph()
    for name in ("soap.ttl", "kitting-domain.ttl"):
        graph.parse(ontology_path(name), format="turtle")
    leave = Graph()
    leave.parse(data=POLICY.format(policy="soap:LeaveKit", extra=""), format="turtle")
    with pytest.raises(InputError, match="the domain declares two partial-kit policies"):
        delivers_partial_kits(graph + leave)
    odd = Graph()
    odd.parse(data=POLICY.format(policy="ex:odd", extra="ex:odd a soap:PartialKitPolicy ."), format="turtle")
    with pytest.raises(InputError, match="partial-kit policy x:odd needs one boolean|needs one boolean"):
        delivers_partial_kits(odd)


# --- the test methods ---------------------------------------------------------------------------

def test_a_campaign_passes_its_partial_kit_policy_to_every_trial() -> None:
    from kb.testmethod.methods import Options, job
    options = Options("errors", trials=2, seed=3, parts=(4,), faults="part-missing=1.0", partial_kits="leave")
    assert options.as_dict()["partial_kits"] == "leave"
    assert "partial_kits" not in Options("errors", trials=2, seed=3, parts=(4,)).as_dict()  # old campaigns resume
    assert [job(options, i).partial_kits for i in range(2)] == ["leave", "leave"]
    with pytest.raises(InputError, match="--partial-kits must be deliver or leave"):
        Options("errors", trials=1, parts=(4,), partial_kits="keep")


def test_a_trial_whose_parts_run_out_leaves_its_kit() -> None:
    from kb.testmethod.methods import Options, job
    from kb.testmethod.trial import run_trial
    row = run_trial(job(Options("errors", trials=1, seed=3, parts=(4,), faults="part-missing=1.0",
                                partial_kits="leave"), 0))
    assert row["executed"] and row["goal_holds"] is False and row["stopped"] is None, row.get("stopped")
    [kit] = row["partial_kits"]
    assert kit["outcome"] == "left" and sum(kit["lacks"].values()) > 0


def test_a_state_short_of_parts_before_the_run_builds_the_kits_they_allow(two_kits: tuple, tmp_path: Path,
                                                                           capsys: pytest.CaptureFixture) -> None:
    """Two of sku_part_a's three parts are not in the state at all: the first plan cannot reach
    the whole goal, so (by the domain's policy, deliver) it is made for the kits the parts allow
    — kit_1 finished, kit_2 delivered partial lacking one A — instead of "no plan"; the report
    says so and the ground truth agrees."""
    init, goal, _plan = two_kits
    def without(path: str, out: Path) -> Path:  # part_a_2 and part_a_3 left out of a state file
        g = Graph()
        g.parse(path)
        gone = [s for s in set(g.subjects()) if str(s).rsplit("#", 1)[-1].split("_pose")[0].split("_point")[0]
                .split("_x_axis")[0].split("_z_axis")[0] in ("part_a_2", "part_a_3")]
        for s in gone:
            g.remove((s, None, None))
            g.remove((None, None, s))
        for tray in [s for s in g.subjects() if str(s).endswith("#part_a_tray")]:
            n = len(set(g.objects(tray, KTW.hasPartsVessel_Part)))
            g.set((tray, KTW.hasPartsVessel_PartQuantity, Literal(n, datatype=XSD.nonNegativeInteger)))
        g.serialize(out, format="turtle")
        return out

    short = without(init, tmp_path / "init.ttl")
    report = tmp_path / "r.json"
    code = main(["run", str(short), str(without(goal, tmp_path / "goal.ttl")), "--report", str(report),
                 "-o", str(tmp_path / "out")])
    cap = capsys.readouterr()
    out = cap.out
    assert code == 1, out + cap.err
    data = json.loads(report.read_text())
    assert data.get("executed", True) and not data["goal_holds"], out
    assert data["partial_kits"] == [{"kit": "kit_2", "outcome": "delivered partial", "lacks": {"sku_part_a": 1}}]
    assert "kits the parts allow: kit_1 finished; kit_2 delivered partial (lacks sku_part_a 1)" in out
    assert data["kits_buildable"] == 1 and data["completion"] == 1.0
