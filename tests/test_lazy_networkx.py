"""kb.patches.unified_planning.LEAN_NETWORKX: networkx is imported on first use only, and then
works as the real one (unified-planning's partial-order plans, submodule imports)."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def _python(code: str, **env: str) -> str:
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT,
                          env={**os.environ, "PYTHONPATH": str(ROOT), **env}, timeout=120)
    assert done.returncode == 0, done.stderr
    return done.stdout.strip()


_PLAN = """
import sys
from kb.patches.unified_planning import environment
environment()
from unified_planning.shortcuts import BoolType, Fluent, InstantaneousAction, Problem, PlanKind
from unified_planning.plans import ActionInstance, SequentialPlan
print(type(sys.modules["networkx"]).__name__, sum(m.startswith("networkx.") for m in sys.modules))
x = Fluent("x", BoolType()); y = Fluent("y", BoolType())
a = InstantaneousAction("a"); a.add_effect(x, True)
b = InstantaneousAction("b"); b.add_precondition(x); b.add_effect(y, True)
p = Problem("p"); p.add_fluent(x, default_initial_value=False); p.add_fluent(y, default_initial_value=False)
p.add_actions([a, b]); p.add_goal(y)
pop = SequentialPlan([ActionInstance(a), ActionInstance(b)]).convert_to(PlanKind.PARTIAL_ORDER_PLAN, p)
print([str(ai) for ai in pop.all_sequential_plans().__next__().actions])
import networkx
print(type(networkx).__name__, type(networkx.DiGraph()).__module__)
"""


def test_networkx_not_imported_until_used_then_real() -> None:
    lines = _python(_PLAN).splitlines()
    assert lines[0] == "_LazyNetworkx 0"  # unified-planning imported, networkx not
    assert lines[1] == "['a', 'b']"  # a partial-order plan (networkx's DiGraph) works
    assert lines[2] == "module networkx.classes.digraph"


def test_stock_import_when_patches_are_off() -> None:
    assert _python(_PLAN, KITKB_PATCHES="0").splitlines()[0].startswith("module ")


def test_submodule_import_first() -> None:
    out = _python("from kb.patches.unified_planning import environment\nenvironment()\n"
                  "import unified_planning.model.problem\nimport networkx.algorithms.dag as d\nimport networkx as nx\n"
                  "g = nx.DiGraph(); g.add_edge(1, 2); print(d.is_directed_acyclic_graph(g), type(nx).__name__)")
    assert out == "True module"
