"""Recovery as data (issue 28, point 3): the executor does what the failure mode's Turtle says.

A remediation's strategy is a ``soap:RecoveryStrategy`` individual dispatched by its IRI
(retry, replan, rebind, reject, a recovery plan, abort), never by the mode's name: a mode of a
new name behaves as its strategy says. A recovery plan's steps are domain actions with their
parameters bound from the failure (``soap:ParameterBinding``, by name, or by the step action's
preconditions), executed and checked like plan actions, then the run goes on (the failed action
again when its precondition failed) or replans. What a mode implies about its objects
(``soap:hasFailureMode_ObjectConsequence``) is read from the data and kept by the belief. A
notification carries the failure's data, in the record, the report and the database.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from kb.core.errors import InputError
from kb.core.namespaces import SOAP
from kb.execution import open_run, run_plan, run_scenario
from kb.execution.belief import Belief
from kb.model.failures import load_failure_model
from kb.spatial.scene import Scene
from test_execution import SMALL, files, plan_of

pytestmark = pytest.mark.usefixtures("own_directory")

HEAD = """
@prefix kd: <https://w3id.org/kitkb/kitting-domain#> .
@prefix soap: <https://w3id.org/kitkb/soap#> .
@prefix owl: <http://www.w3.org/2002/07/owl#> .
@prefix xsd: <http://www.w3.org/2001/XMLSchema#> .
@prefix x: <urn:recovery#> .

<urn:recovery> a owl:Ontology ; owl:imports <https://w3id.org/kitkb/kitting-domain> .
"""

#: a mode of a new name, more likely than part-missing-from-tray for the same signal: rebind
#: the part, which is kept out until an inspection passes it
PART_GONE = HEAD + """
x:part-gone a owl:NamedIndividual , soap:FailureMode ;
    soap:hasFailureMode_Name "part-gone" ;
    soap:hasFailureMode_Action kd:take-part ;
    soap:hasFailureMode_Phase soap:PreconditionCheck ;
    soap:hasFailureMode_ViolatedPredicate kd:part-location-partstray ;
    soap:hasFailureMode_Condition x:part-gone_f1 ;
    soap:hasFailureMode_Consequence "The part is gone; another of its SKU will do."^^xsd:string ;
    soap:hasFailureMode_Severity "3"^^xsd:integer ;
    soap:hasFailureMode_Likelihood "0.9"^^xsd:decimal ;
    soap:hasFailureMode_ObjectConsequence x:part-gone_c1 ;
    soap:hasFailureMode_Remediation x:part-gone_remediation .

x:part-gone_f1 a owl:NamedIndividual , soap:PredicateAtom ;
    soap:hasPredicateAtom_Predicate kd:partstray-not-empty ;
    soap:hasPredicateAtom_ReferenceParameter kd:take-part_partstray ;
    soap:hasAtom_IsNegated false .

x:part-gone_c1 a owl:NamedIndividual , soap:ObjectConsequence ;
    soap:hasObjectConsequence_Parameter kd:take-part_part ;
    soap:hasObjectConsequence_Kind soap:ReusableAfterInspection .

x:part-gone_notify a owl:NamedIndividual , soap:Notification ;
    soap:hasNotification_Recipient "stores" ;
    soap:hasNotification_Message "{part} gone from {partstray}." .

x:part-gone_remediation a owl:NamedIndividual , soap:FailureRemediation ;
    soap:hasFailureRemediation_Notification x:part-gone_notify ;
    soap:hasFailureRemediation_Recovery soap:RebindObject ;
    soap:hasFailureRemediation_Object kd:take-part_part ;
    soap:hasFailureRemediation_OperatorIntervention false .
"""

#: a mode of a new name for a robot without its effector: a recovery plan with explicit
#: bindings, then a replan
NO_TOOL = HEAD + """
x:no-tool a owl:NamedIndividual , soap:FailureMode ;
    soap:hasFailureMode_Name "no-tool" ;
    soap:hasFailureMode_Action kd:take-part ;
    soap:hasFailureMode_Phase soap:PreconditionCheck ;
    soap:hasFailureMode_ViolatedPredicate kd:endeffector-location-robot ;
    soap:hasFailureMode_Consequence "No tool on the robot."^^xsd:string ;
    soap:hasFailureMode_Severity "3"^^xsd:integer ;
    soap:hasFailureMode_Likelihood "0.9"^^xsd:decimal ;
    soap:hasFailureMode_Remediation x:no-tool_remediation .

x:no-tool_step1 a owl:NamedIndividual , soap:RecoveryStep ;
    soap:hasRecoveryStep_Action kd:attach-endeffector ;
    soap:hasRecoveryStep_Position "1"^^xsd:positiveInteger ;
    soap:hasRecoveryStep_Binding x:no-tool_b1 .

x:no-tool_b1 a owl:NamedIndividual , soap:ParameterBinding ;
    soap:hasParameterBinding_Parameter kd:attach-endeffector_endeffector ;
    soap:hasParameterBinding_FailedParameter kd:take-part_endeffector .

x:no-tool_plan a owl:NamedIndividual , soap:RecoveryPlan ;
    soap:hasRecoveryPlan_Step x:no-tool_step1 .

x:no-tool_remediation a owl:NamedIndividual , soap:FailureRemediation ;
    soap:hasFailureRemediation_Recovery soap:ExecuteRecoveryPlan ;
    soap:hasFailureRemediation_RecoveryPlan x:no-tool_plan ;
    soap:hasFailureRemediation_ThenReplan true ;
    soap:hasFailureRemediation_OperatorIntervention false .
"""


def _extension(tmp_path: Path, text: str) -> str:
    path = tmp_path / "extension.ttl"
    path.write_text(text, encoding="utf-8")
    return str(path)


def _without(plan: tuple[str, ...], prefix: str) -> list[str]:
    """The plan without its first line starting with ``prefix``."""
    k = next(i for i, line in enumerate(plan) if line.startswith(prefix))
    return list(plan[:k] + plan[k + 1:])


def test_a_recovery_plan_runs_its_bound_steps_checked_and_the_run_goes_on() -> None:
    """No part gripper attached before the first take-part: endeffector-not-attached's plan
    attaches it (robot and effector bound from take-part, holder and station chosen by
    attach-endeffector's preconditions), checked like a plan action, then take-part again."""
    init, goal = files(SMALL)
    plan = _without(plan_of(init, goal), "(attach-endeffector robot_1 part_gripper")
    run = run_plan(plan, init, goal, seed=0, notifier=lambda who, text: None)
    [f] = run.failures()
    assert (f.mode, f.phase, f.recovery) == ("endeffector-not-attached", "precondition", "recovery-plan")
    line = "(attach-endeffector robot_1 part_gripper part_gripper_holder changing_station_1)"
    assert f.outcome == f"recovered: recovery plan {line}"
    after = [(a.action, a.status) for a in run.record.actions if a.index > f.action_index][:2]
    assert after == [("attach-endeffector", "done"), ("take-part", "done")]
    checked = {c.phase for c in run.record.checks if c.action_index == f.action_index + 1}
    assert checked == {"precondition", "effect"}  # the recovery step was checked like any action
    assert run.record.replans == 0 and run.stopped is None and run.goal_holds


def test_a_recovery_plan_that_replans_after_it(tmp_path: Path) -> None:
    init, goal = files(SMALL)
    plan = _without(plan_of(init, goal), "(attach-endeffector robot_1 part_gripper")
    run = run_plan(plan, init, goal, seed=0, domain_files=[_extension(tmp_path, NO_TOOL)],
                   notifier=lambda who, text: None)
    [f] = run.failures()
    assert (f.mode, f.recovery) == ("no-tool", "recovery-plan")
    assert f.outcome.endswith(", then a replan")
    assert run.record.actions[f.action_index + 1].action == "attach-endeffector"
    assert run.record.replans == 1 and run.stopped is None and run.goal_holds


def test_a_failing_recovery_plan_is_bounded(tmp_path: Path) -> None:
    """A plan whose step keeps failing (its effector cannot be attached: it is not in its
    holder) is not run forever: at most max_replans plans, then replans, then a stop."""
    init, goal = files(SMALL)
    plan = _without(plan_of(init, goal), "(attach-endeffector robot_1 part_gripper")
    plan = [line.replace("part_gripper part_gripper_holder", "part_gripper tray_gripper_holder") for line in plan]
    run = run_plan(plan, init, goal, seed=0, notifier=lambda who, text: None)
    plans = [f for f in run.failures() if f.recovery == "recovery-plan"]
    assert 1 <= len(plans) <= 10 and len(run.failures()) <= 3 * 10 + 2  # max_replans each, no loop


def test_rebind_is_dispatched_by_strategy_and_the_consequence_read_from_data(tmp_path: Path) -> None:
    init, goal = files(SMALL)
    ext = _extension(tmp_path, PART_GONE)
    mode = load_failure_model([ext]).modes["part-gone"]
    assert mode.remediation.strategy == str(SOAP.RebindObject) and mode.remediation.obj == "part"
    assert [(c.parameter, c.kind, c.reason) for c in mode.consequences] == [
        ("part", str(SOAP.ReusableAfterInspection), "reusableafterinspection")]
    run = run_scenario(init, goal, faults="part-missing@6", seed=0, domain_files=[ext],
                       notifier=lambda who, text: None)
    [f] = run.failures()
    assert (f.mode, f.recovery, f.outcome) == ("part-gone", "rebind", "recovered: bound part_a_3 from part_a_tray")
    assert [(n.recipient, n.message) for n in f.notifications] == [("stores", "part_a_1 gone from part_a_tray.")]
    assert run.goal_holds


def test_the_belief_keeps_an_object_to_inspect_out_until_an_inspection_passes_it() -> None:
    init, goal = files(SMALL)
    b = Belief(Scene.from_files([init], declared=[goal]))
    part = next(n for n in b.names if n.endswith("part_a_1"))
    b.learn(part, "to inspect", until_inspected=True)
    assert not b.usable(part) and b.awaits_inspection(part)
    b.passed_inspection(part, True)
    assert b.usable(part) and not b.awaits_inspection(part)
    b.learn(part, "to inspect", until_inspected=True)
    b.passed_inspection(part, False)  # failed: defective for good
    b.passed_inspection(part, True)
    assert not b.usable(part) and b.unusable[part] == "to inspect"


def test_a_notification_carries_its_attachments_through_the_report_and_the_database(tmp_path: Path) -> None:
    init, goal = files(SMALL)
    db = tmp_path / "w.sqlite"
    run = run_scenario(init, goal, faults="missed-grasp@6", seed=0, db=db, notifier=lambda who, text: None)
    [f] = run.failures()
    [n] = f.notifications
    assert n.recipient == "engineering" and n.message.startswith("Missed grasp of part_a_1 in part_a_tray")
    a = n.attachments
    assert a["action"] == "take-part" and a["args"]["part"] == "part_a_1" and a["phase"] == "effect"
    assert "robot-holds-part(robot_1, part_a_1)" in a["violated"]
    assert {s["object"] for s in a["sightings"]} >= {"part_a_1", "robot_1"}
    assert len(a["grasps"]["part_a_1"]) == 4  # the grasp pose the message speaks of (4x4, m)
    assert run.report()["failures"][0]["notifications"] == [n.to_dict()]
    back = open_run(db)
    assert back.failures()[0].notifications == f.notifications


@pytest.mark.parametrize("old, new, message", [
    (" ;\n    soap:hasParameterBinding_FailedParameter kd:take-part_endeffector .", " .",
     "needs one of hasParameterBinding_FailedParameter, hasParameterBinding_Object"),
    ("FailedParameter kd:take-part_endeffector", "FailedParameter kd:put-part_kit",
     "failed parameter put-part_kit is not a parameter of take-part"),
])
def test_a_malformed_binding_is_an_error_at_its_line(tmp_path: Path, old: str, new: str, message: str) -> None:
    assert NO_TOOL.count(old) == 1
    ext = _extension(tmp_path, NO_TOOL.replace(old, new))
    with pytest.raises(InputError) as e:
        load_failure_model([ext])
    assert message in str(e.value) and "extension.ttl" in str(e.value)


def test_the_report_page_shows_the_notifications_and_their_attachments() -> None:
    from kb.report.tables import failures_table
    init, goal = files(SMALL)
    run = run_scenario(init, goal, faults="missed-grasp@6", seed=0, notifier=lambda who, text: None)
    page = failures_table(run.report())
    assert 'id="notifications-table"' in page and "engineering" in page and "Missed grasp of part_a_1" in page
    assert "grasps" in page and "sightings" in page
    assert "notifications-table" not in failures_table(run_scenario(init, goal, seed=0).report())


def test_a_recovery_that_is_no_strategy_is_an_error_at_its_line(tmp_path: Path) -> None:
    ext = _extension(tmp_path, NO_TOOL.replace("soap:hasFailureRemediation_Recovery soap:ExecuteRecoveryPlan",
                                               "soap:hasFailureRemediation_Recovery x:Teleport"))
    with pytest.raises(InputError, match="recovery Teleport is not a soap:RecoveryStrategy individual") as e:
        load_failure_model([ext])
    assert "extension.ttl:" in str(e.value)


def test_a_strategy_kitkb_has_no_handler_for_stops_the_run_saying_so(tmp_path: Path) -> None:
    text = NO_TOOL.replace("soap:hasFailureRemediation_Recovery soap:ExecuteRecoveryPlan",
                           "soap:hasFailureRemediation_Recovery x:Teleport") + \
        "\nx:Teleport a owl:NamedIndividual , soap:RecoveryStrategy .\n"
    init, goal = files(SMALL)
    plan = _without(plan_of(init, goal), "(attach-endeffector robot_1 part_gripper")
    run = run_plan(plan, init, goal, seed=0, domain_files=[_extension(tmp_path, text)], notifier=lambda who, text: None)
    assert run.stopped.startswith("recovery strategy Teleport has no handler in kitkb (known: Abort, ")
    [f] = run.failures()
    assert (f.recovery, f.outcome) == ("stop", f"stopped: {run.stopped}")


def test_a_moved_object_is_expected_where_it_was_sensed_and_stays_usable() -> None:
    from kb.execution.recovery import CONSEQUENCES, Recovery

    init, goal = files(SMALL)

    class Half(Recovery):  # the recovery half alone, with a belief and a stable state
        def __init__(self) -> None:
            self.belief = Belief(Scene.from_files([init], declared=[goal]))
            self.stable = self.belief.poses.copy()

    r = Half()
    part = next(n for n in r.belief.names if n.endswith("part_a_1"))
    j = r.belief.index[part]
    r.belief.poses[j, 0, 3] += 0.05  # sensed 5 cm along x
    getattr(r, CONSEQUENCES[str(SOAP.Moved)])(part, "moved")
    assert r.stable[j, 0, 3] == r.belief.poses[j, 0, 3] and r.belief.usable(part)
    getattr(r, CONSEQUENCES[str(SOAP.Condemned)])(part, "dropped")
    assert r.belief.unusable == {part: "dropped"}
