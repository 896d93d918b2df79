"""Focus of attention (kb.execution.focus): the executor senses an action's neighbourhood, not
the whole cell, and decides its checks on it; every check's answer is the one the whole cell,
sensed at that moment, gives (fault-free runs and runs with every fault kind)."""

from __future__ import annotations

import copy
from typing import Any

import numpy as np
import pytest

from kb.core.errors import KitkbError
from kb.execution import Executor
from kb.execution.executor import SOLID
from kb.execution.focus import Focus, contact_only
from kb.model.definitions import load_definitions
from kb.model.soap import ActionSpec
from kb.planning.model import read_specs
from kb.scenario import write_scenario
from kb.sim import SimulatedCell
from kb.spatial.predicates import Evaluator
from test_execution import SHIPPED, SMALL, assert_built, execute, files

SOAP = "https://w3id.org/kitkb/soap#"


pytestmark = pytest.mark.usefixtures("own_directory")


@pytest.fixture
def compared(monkeypatch: pytest.MonkeyPatch) -> list[tuple[str, str, bool]]:
    """Every check decided on a neighbourhood is decided again on a copy of the belief that has
    sensed the whole cell at that moment (the simulated sensor has no noise: sensing changes
    nothing); the answers must agree. The list gets (action, predicate, holds) per atom."""
    out: list[tuple[str, str, bool]] = []
    check = Executor._check

    def _check(self: Executor, i: int, step: Any, phase: str) -> Any:
        result = check(self, i, step, phase)
        if self._near is None:
            return result
        whole = copy.deepcopy(self.belief)
        whole.observe(self.cell.sense("SolidObject", by="class"),
                      asked=[n for n in whole.of_class(SOLID) if whole.placed(n)])
        ev = Evaluator(self.defs, whole.scene(), self.tolerance)
        for atom in result.atoms:
            try:
                holds = ev.holds(atom.predicate, *atom.args)
            except KitkbError:
                holds = False
            assert holds == atom.holds, (i, step.line(), phase, atom.text(), atom.holds)
            out.append((step.action, atom.predicate, holds))
        return result

    monkeypatch.setattr(Executor, "_check", _check)
    return out


def test_the_kitting_relations_hold_only_between_touching_boxes() -> None:
    defs = load_definitions()
    for name in ("In-Contact-With", "In-Or-Against", "On-Top-With-Contact", "Partially-In"):
        assert contact_only(defs, SOAP + name), name
    # a relation that holds at a distance (above, anywhere) is not one
    cardinal = [iri for iri in defs.relations if iri.endswith("#Z-Plus")]
    assert cardinal and not contact_only(defs, cardinal[0])


def test_every_kitting_action_is_local() -> None:
    init, goal = files(SMALL)
    domain, _spec = read_specs([init], [goal], "numeric")
    focus = Focus(load_definitions(), {a.name: a for a in domain.actions}, [], 0.001)
    assert sorted(a.name for a in domain.actions if focus.plan(a.name) is None) == []
    # robot-empty: an effector touching the robot, something touching that effector
    ties = [(t.var.name, t.to if isinstance(t.to, str) else t.to.name) for t in focus.ties("robot-empty")]
    assert ties == [("ee", "reference"), ("held", "ee"), ("mounted", "reference")]


def test_an_untied_variable_makes_an_action_sense_the_whole_cell() -> None:
    from dataclasses import replace
    from kb.model.definitions import Exists, Not, Relation, Variable
    defs = load_definitions()
    p = defs.predicates["worktable-empty"]
    far = Variable("far", "far", p.formula.operand.variable.cls)
    above = Not("n", Exists("e", far, Relation("r", SOAP + "Z-Plus", far, "reference")))  # at any distance
    defs.predicates["worktable-empty"] = replace(p, formula=above)
    init, goal = files(SMALL)
    domain, _spec = read_specs([init], [goal], "numeric")
    actions: dict[str, ActionSpec] = {a.name: a for a in domain.actions}
    focus = Focus(defs, actions, [], 0.001)
    assert focus.ties("worktable-empty") is None
    assert focus.plan("put-kittray") is None and focus.plan("take-part") is not None


@pytest.mark.parametrize("name", SHIPPED)
def test_neighbourhood_checks_agree_with_the_whole_cell(name: str, compared: list) -> None:
    init, goal = files(name)
    run, cell = execute(name)
    assert_built(run, cell, init, goal)
    assert len(compared) == sum(len(c.atoms) for c in run.record.checks)  # every check was local
    assert {a for a, _p, _h in compared} >= {"take-part", "put-part", "attach-endeffector", "create-kit"}


MIXED = "missed-grasp=0.1,dropped-part=0.1,part-moved=0.1,part-missing=0.05,defective-part=0.05,wrong-sku=0.1," \
        "kit-tray-moved=0.3"


@pytest.mark.parametrize("seed", range(6))
def test_with_every_fault_kind_the_neighbourhood_checks_still_agree(seed: int, compared: list) -> None:
    run, _cell = execute("kit-a2b3c3d1e1", MIXED, seed)
    assert compared
    assert run.report()["injected"]  # faults happened; every check agreed (in the fixture)


def test_a_generated_kit_senses_neighbourhoods_not_the_cell(tmp_path: Any, monkeypatch: pytest.MonkeyPatch) -> None:
    init, goal = (str(p) for p in write_scenario(tmp_path, parts=40, kits=1, seed=0))
    asked: list[tuple[str, int]] = []
    sense, names = SimulatedCell.sense, SimulatedCell.sense_names
    monkeypatch.setattr(SimulatedCell, "sense", lambda self, q, by="class": asked.append((by, len(
        out := sense(self, q, by=by)))) or out)
    monkeypatch.setattr(SimulatedCell, "sense_names", lambda self, ns: asked.append(("names", len(
        out := names(self, ns)))) or out)
    run, cell = execute("generated", init=init, goal=goal)
    assert_built(run, cell, init, goal)
    by_class = [n for by, n in asked if by == "class"]
    solids = len(cell.sense("SolidObject"))
    assert by_class == [solids]  # once: the goal checked at the end
    seen = [n for by, n in asked if by == "names"]
    assert np.median(seen) < solids / 4, (np.median(seen), solids)
