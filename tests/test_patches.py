"""kitkb's changes to library internals (kb.patches): each is gated by the versions it was
checked on, applies on the locked versions, and gives the same results as the stock code."""

from __future__ import annotations

import os
import re
import sqlite3
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest
from rdflib import Graph, Literal, URIRef

from kb.core.resources import scenario_dirs
from kb.patches import gate, rdflib as rdflib_patches, sqlalchemy as sqlalchemy_patches
from kb.patches import unified_planning as up_patches

ROOT = Path(__file__).resolve().parent.parent
PATCHES = [*up_patches.PATCHES, *sqlalchemy_patches.PATCHES, *rdflib_patches.PATCHES]
SCENARIOS = {d.name: d for d in scenario_dirs()}


def _locked() -> dict[str, str]:
    pins = {}
    for line in (ROOT / "constraints.txt").read_text().splitlines():
        if line and not line.startswith("#"):
            name, _, version = line.partition("==")
            pins[re.sub(r"[-_.]+", "-", name).lower()] = version
    return pins


def test_every_dependency_has_an_upper_bound_and_a_lock() -> None:
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    requirements = project["dependencies"] + [r for extra in project["optional-dependencies"].values() for r in extra]
    locked = _locked()
    for requirement in requirements:
        name = re.sub(r"[-_.]+", "-", re.split(r"[<>=!~ ]", requirement)[0]).lower()
        assert "<" in requirement, f"{requirement} has no upper bound"
        assert name in locked, f"{name} is not pinned in constraints.txt"
        assert gate.installed(name) == locked[name], f"{name}: installed {gate.installed(name)}, locked {locked[name]}"


@pytest.mark.parametrize("patch", PATCHES, ids=lambda p: f"{p.library}: {p.what}")
def test_patch_applies_on_the_locked_version(patch: gate.Patch) -> None:
    locked = _locked()[re.sub(r"[-_.]+", "-", patch.library).lower()]
    have = gate._version_tuple(locked)
    assert gate._version_tuple(patch.checked_from) <= have < gate._version_tuple(patch.checked_below), patch.range
    assert patch.active()


def test_patch_outside_its_range_or_turned_off_is_not_applied(monkeypatch) -> None:
    patch = gate.Patch("unified-planning", "1.3.0", "1.4", "test")
    monkeypatch.setattr(gate, "installed", lambda name: "1.4.0")
    assert not patch.active()
    monkeypatch.setattr(gate, "installed", lambda name: "1.2.9")
    assert not patch.active()
    monkeypatch.setattr(gate, "installed", lambda name: "1.3.7.dev2")
    assert patch.active()
    monkeypatch.setenv("KITKB_PATCHES", "0")
    assert not patch.active()


def test_stock_rdflib_store_holds_the_same_graph(monkeypatch) -> None:
    triples = [(URIRef(f"urn:s{i}"), URIRef("urn:p"), Literal(i)) for i in range(50)]
    patched = rdflib_patches.memory_graph(triples)
    patched.add((URIRef("urn:x"), URIRef("urn:p"), Literal("added")))
    monkeypatch.setenv("KITKB_PATCHES", "0")
    stock = rdflib_patches.memory_graph(triples)
    stock.add((URIRef("urn:x"), URIRef("urn:p"), Literal("added")))
    assert type(stock.store) is not type(patched.store)
    assert len(stock) == len(patched) == 51 and set(stock) == set(patched)
    patched.remove((URIRef("urn:x"), None, None))
    assert len(patched) == 50


@pytest.mark.parametrize("patches", ["", "0"], ids=["patched", "stock"])
def test_ddl_leaves_shared_metadata_whole(patches: str, tmp_path: Path, monkeypatch) -> None:
    """DDL from the world model's own metadata (PostgreSQL: foreign keys added by ALTER), then
    SQLite tables from the same metadata: every foreign key is still there."""
    from generators.sql import ddl
    from kb import world
    from kb.world.schema import model

    monkeypatch.setenv("KITKB_PATCHES", patches)
    text = ddl(model().metadata, "postgresql")
    assert "ALTER TABLE" in text and "FOREIGN KEY" in text
    world.load(SCENARIOS["small-kit"] / "init.ttl", tmp_path / "w.sqlite")
    with sqlite3.connect(tmp_path / "w.sqlite") as conn:
        fks = conn.execute("SELECT count(*) FROM pragma_foreign_key_list('ktw_part')").fetchone()[0]
        assert fks == len(model().table("ktw_part").foreign_keys) > 0


def test_stock_ddl_is_the_same_schema(monkeypatch) -> None:
    from generators.sql import ddl
    from kb.world.schema import model

    def statements(text: str) -> set[frozenset[str]]:
        return {frozenset(line.strip().rstrip(",") for line in s.splitlines()) for s in text.split(";\n")}

    patched = ddl(model().metadata, "postgresql")
    monkeypatch.setenv("KITKB_PATCHES", "0")
    stock = ddl(model().metadata, "postgresql")
    assert statements(stock) == statements(patched)  # constraint order within a table may differ


def _kitkb(*args: str, env: dict[str, str]) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "kb.cli", *args], capture_output=True, text=True,
                          env={**os.environ, **env}, timeout=600)


@pytest.mark.parametrize("scenario", ["small-kit", "two-designs"])
def test_planning_with_stock_unified_planning_gives_the_same_files(scenario: str, tmp_path: Path) -> None:
    init, goal = SCENARIOS[scenario] / "init.ttl", SCENARIOS[scenario] / "goal.ttl"
    outputs = {}
    for label, env in (("patched", {}), ("stock", {"KITKB_PATCHES": "0"})):
        out = tmp_path / label
        for args in (["generate", "pddl", str(init), str(goal), "-o", str(out)],
                     ["plan", str(init), str(goal), "-o", str(out / "plan.txt")]):
            proc = _kitkb(*args, env=env)
            assert proc.returncode == 0, proc.stderr
        outputs[label] = {p.name: p.read_text() for p in sorted(out.iterdir())}
    assert outputs["stock"] == outputs["patched"]
    assert set(outputs["stock"]) == {"domain.pddl", "problem.pddl", "plan.txt"}


def test_lean_import_does_not_load_scipy() -> None:
    code = ("import sys; from kb.patches.unified_planning import environment; environment(); "
            "import unified_planning.engines; print('scipy' in sys.modules)")
    for env, expected in (({}, "False"), ({"KITKB_PATCHES": "0"}, "True")):
        proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                              env={**os.environ, **env}, timeout=120)
        assert proc.stdout.strip() == expected, (env, proc.stderr)
