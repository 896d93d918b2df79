"""The oracle of what was buildable (kb.metrics.oracle): hand-built truths, the simulator's part
fates (kb.sim.fates), and seeded runs whose report is checked against a computation of its own
from the simulated cell's ground truth."""

from __future__ import annotations

import itertools
from collections import Counter
from pathlib import Path

import numpy as np
import pytest

from kb.crcl.cell import Fate, has
from kb.execution import run_scenario
from kb.metrics.kits import KitGoal, Slot
from kb.metrics.oracle import buildable, most_kits
from kb.sim import SimulatedCell
from kb.sim.faults import FaultSpec
from kb.sim.world import SKU
from kb.spatial.scene import Scene

ROOT = Path(__file__).resolve().parents[1]
SCENARIOS = ROOT / "ontologies" / "scenarios"
A, B, C, TRAY = "x#sku_a", "x#sku_b", "x#sku_c", "x#sku_tray"


def kit(name: str, tray: str | None = TRAY, **counts: int) -> KitGoal:
    slots = tuple(Slot(f"x#{name}_{s}_{i}", f"x#sku_{s}", np.eye(4)) for s, n in counts.items() for i in range(n))
    return KitGoal(f"x#{name}", f"x#design_{name}", tray, slots, "x#box")


def part(name: str, sku: str, place: str = "parts-tray", *, kit: str | None = None, defective: bool = False,
         reachable: bool | None = None) -> Fate:
    reach = place not in ("floor", "gone") if reachable is None else reachable
    return Fate(f"x#{name}", "part", sku, defective, place, None if place in ("floor", "gone") else "x#holder",
                kit, reach)


def tray(name: str, kit: str | None = None) -> Fate:
    return Fate(f"x#{name}", "kit-tray", TRAY, False, "kit" if kit else "on", "x#table", kit, True)


def parts(sku: str, n: int, prefix: str, **kw) -> list[Fate]:  # noqa: ANN003
    return [part(f"{prefix}{i}", sku, **kw) for i in range(n)]


def recorded(fates: list[Fate]) -> dict[str, str]:
    return {f.name: f.sku for f in fates if f.sku is not None}


GOALS = [kit("kit_1", a=2, b=1), kit("kit_2", a=2, b=1)]


def world(extra: list[Fate] = (), a: int = 4, b: int = 2) -> list[Fate]:  # type: ignore[assignment]
    return parts(A, a, "a") + parts(B, b, "b") + [tray("t1"), tray("t2")] + list(extra)


# --- hand-built truths ----------------------------------------------------------------------

def test_all_parts_fine_every_kit_buildable() -> None:
    fates = world()
    got = buildable(fates, GOALS, recorded(fates), built=[])
    assert (got.kits_buildable, got.kits_built, got.kits) == (2, 0, 2)
    assert got.completion == 0.0
    assert got.usable == {"sku_a": 4, "sku_b": 2, "sku_tray": 2}
    assert got.not_counted == []


def test_one_sku_short_by_one_is_one_kit_fewer() -> None:
    fates = world(b=1)
    assert buildable(fates, GOALS, recorded(fates), built=[]).kits_buildable == 1
    fates = world(a=3)
    assert buildable(fates, GOALS, recorded(fates), built=[]).kits_buildable == 1
    fates = parts(A, 4, "a") + parts(B, 2, "b") + [tray("t1")]  # one kit tray for two kits
    assert buildable(fates, GOALS, recorded(fates), built=[]).kits_buildable == 1


def test_a_part_on_the_floor_is_not_counted_one_on_the_table_is() -> None:
    fates = world(b=1, extra=[part("b_dropped", B, "floor")])
    got = buildable(fates, GOALS, recorded(fates), built=[])
    assert got.kits_buildable == 1
    assert got.not_counted == [{"name": "b_dropped", "kind": "part", "why": "floor", "place": "floor"}]
    fates = world(b=1, extra=[part("b_dropped", B, "on")])  # dropped onto the work table: usable from there
    assert buildable(fates, GOALS, recorded(fates), built=[]).kits_buildable == 2


def test_out_of_reach_not_counted_unless_in_a_kit() -> None:
    far = part("b_far", B, "on", reachable=False)
    fates = world(b=1, extra=[far])
    got = buildable(fates, GOALS, recorded(fates), built=[])
    assert got.kits_buildable == 1 and got.not_counted[0]["why"] == "out-of-reach"
    in_kit = part("b_far", B, "kit", kit="x#kit_2", reachable=False)  # put there by the robot: it counts
    fates = world(b=1, extra=[in_kit])
    assert buildable(fates, GOALS, recorded(fates), built=[]).kits_buildable == 2


def test_defective_and_wrong_sku_parts_not_counted() -> None:
    fates = world(b=1, extra=[part("b_bad", B, defective=True)])
    got = buildable(fates, GOALS, recorded(fates), built=[])
    assert got.kits_buildable == 1 and [x["why"] for x in got.not_counted] == ["defective"]
    swapped = part("b_swapped", C)  # the state records it as sku_b; it truly is sku_c now
    fates = world(b=1, extra=[swapped])
    rec = dict(recorded(fates), **{swapped.name: B})
    got = buildable(fates, GOALS, rec, built=[])
    assert got.kits_buildable == 1 and [x["why"] for x in got.not_counted] == ["other-sku"]
    gone = part("b_gone", B, "gone")
    fates = world(b=1, extra=[gone])
    assert buildable(fates, GOALS, recorded(fates), built=[]).not_counted[0]["why"] == "gone"


def test_parts_in_a_built_kit_count_for_it_and_nothing_else() -> None:
    # kit_1 delivered with its 2 a, 1 b and its tray; left: 1 a, 1 b, one tray: kit_2 is not buildable
    in_kit = [part(f"k{i}", s, "kit", kit="x#kit_1", reachable=False) for i, s in enumerate((A, A, B))]
    fates = in_kit + [tray("t1", kit="x#kit_1")] + parts(A, 1, "a") + parts(B, 1, "b") + [tray("t2")]
    got = buildable(fates, GOALS, recorded(fates), built=["x#kit_1"])
    assert (got.kits_buildable, got.kits_built, got.completion) == (1, 1, 1.0)
    assert got.usable == {"sku_a": 1, "sku_b": 1, "sku_tray": 1}
    # the same parts in kit_1 not finished (no score): they could have gone into either kit
    got = buildable(fates, GOALS, recorded(fates), built=[])
    assert (got.kits_buildable, got.completion) == (1, 0.0)
    # a built kit's parts count for it, by local name as a report names the kit
    got = buildable(fates + parts(A, 1, "a_more"), GOALS, recorded(fates), built=["kit_1"])
    assert (got.kits_buildable, got.kits_built) == (2, 1)


def test_nothing_buildable_nothing_built_is_complete() -> None:
    fates = parts(A, 1, "a")
    got = buildable(fates, GOALS, recorded(fates), built=[])
    assert (got.kits_buildable, got.kits_built, got.completion) == (0, 0, 1.0)
    got = buildable([], [], {}, built=[])  # a goal with no kit
    assert (got.kits_buildable, got.kits, got.completion) == (0, 0, 1.0)
    assert got.as_dict()["completion"] == 1.0


def test_most_kits_is_exact_where_fewest_parts_first_is_not() -> None:
    # taking the smallest kit (a, b) leaves neither of the two others; both others together fit
    kits = [{A: 1, B: 1}, {A: 1, C: 1, "d": 1}, {B: 1, C: 1, "e": 1}]
    assert most_kits(kits, {A: 1, B: 1, C: 2, "d": 1, "e": 1}) == 2
    assert most_kits(kits, {}) == 0
    assert most_kits([{}], {}) == 1  # a kit needing nothing
    assert most_kits([{A: 2}] * 5, {A: 7}) == 3


def brute_force(kits: list[dict[str, int]], pool: dict[str, int]) -> int:
    for n in range(len(kits), 0, -1):
        for chosen in itertools.combinations(kits, n):
            need = Counter()
            for k in chosen:
                need.update(k)
            if all(pool.get(s, 0) >= c for s, c in need.items()):
                return n
    return 0


def test_most_kits_agrees_with_every_subset() -> None:
    rng = np.random.default_rng(29)
    for _ in range(200):
        skus = ["s0", "s1", "s2", "s3"]
        kits = [{s: int(rng.integers(0, 3)) for s in skus} for _ in range(int(rng.integers(0, 7)))]
        pool = {s: int(rng.integers(0, 8)) for s in skus}
        assert most_kits(kits, pool) == brute_force(kits, pool), (kits, pool)


# --- the simulator's fates ------------------------------------------------------------------

def small_kit() -> Scene:
    return Scene.from_files([SCENARIOS / "small-kit" / "init.ttl"], [SCENARIOS / "small-kit" / "goal.ttl"])


def test_a_simulated_cell_tells_part_fates() -> None:
    cell = SimulatedCell(small_kit())
    assert has(cell, "part-fates") and has(cell, "ground-truth")
    fates = {f.name.rsplit("#", 1)[-1]: f for f in cell.part_fates()}
    assert {f.kind for f in fates.values()} == {"part", "kit-tray"}
    a1 = fates["part_a_1"]
    assert (a1.place, a1.reachable, a1.defective, a1.kit) == ("parts-tray", True, False, None)
    assert a1.sku.endswith("sku_part_a")
    w = cell.world
    i = w.index[a1.name]
    w.defective.add(a1.name)  # what the faults do, done by hand
    w.shift(i, 0.0, 0.0, 0.5)
    w.drop(i, {int(x) for x in np.flatnonzero(np.ones(len(w), bool))} - set(w.subtree(i)))  # onto the floor
    got = {f.name: f for f in cell.part_fates()}[a1.name]
    assert (got.place, got.reachable, got.defective, got.holder) == ("floor", False, True, None)
    w.remove(i)
    assert {f.name: f for f in cell.part_fates()}[a1.name].place == "gone"


def test_fates_follow_injected_faults() -> None:
    scene = small_kit()
    cell = SimulatedCell(scene, faults=FaultSpec.parse("wrong-sku@0", seed=3))
    name = next(n for n in scene.names if n.endswith("part_a_1"))
    tray_ = next(n for n in scene.names if n.endswith("part_a_tray"))
    effector = next(n for n in scene.names if n.endswith("part_gripper"))
    robot = next(n for n in scene.names if n.endswith("robot_1"))
    cell.begin_action(0, "take-part", (robot, name, tray_, effector))
    assert [x.kind for x in cell.injected] == ["wrong-sku"]
    got = {f.name: f for f in cell.part_fates()}[name]
    before = sorted(o for s, o in scene.facts[SKU] if s == name)
    assert [got.sku] != before and got.place == "parts-tray"


# --- seeded runs against the simulator's truth ------------------------------------------------

def truth_buildable(cell: SimulatedCell, scene: Scene, report: dict) -> int:
    """What was buildable, worked out here from the cell's world and the state's kit designs
    (not through kb.sim.fates nor kb.metrics.oracle)."""
    w = cell.world
    facts = scene.facts
    recorded_ = {s: o for s, o in sorted(facts[SKU], reverse=True)}
    design_of = dict(facts["https://w3id.org/kitkb/kitting#hasKit_Design"])
    slots = facts["https://w3id.org/kitkb/kitting#hasKitDesign_PartRefAndPose"]
    slot_sku = dict(facts["https://w3id.org/kitkb/kitting#hasPartRefAndPose_Sku"])
    tray_sku = dict(facts["https://w3id.org/kitkb/kitting#hasKitDesign_KitTraySku"])
    built = {k["kit"] for k in report["kits"] if k["score"] == k["max_score"]}
    held = set(w.subtree(cell.robot.index))

    def kit_of(i: int) -> str | None:
        j = int(w.parent[i])
        while j >= 0:
            if w.is_a(j, "Kit"):
                return w.names[j].rsplit("#", 1)[-1]
            j = int(w.parent[j])
        return None

    pool: Counter[str] = Counter()
    for i, name in enumerate(w.names):
        if not (w.is_a(i, "Part") or w.is_a(i, "KitTray")) or kit_of(i) in built:
            continue
        sku = w.sku(i)
        if not w.placed(i) or name in w.defective or sku != recorded_.get(name, sku):
            continue
        on_floor = int(w.parent[i]) < 0 and i not in held and w.box(i)[0][2] <= 1e-3
        if on_floor:
            continue
        pool[sku] += 1
    needs = []
    for k, design in design_of.items():
        if k.rsplit("#", 1)[-1] in built:
            continue
        need = Counter(slot_sku[p] for d, p in slots if d == design)
        need[tray_sku[design]] += 1
        needs.append(dict(need))
    return len(built) + brute_force(needs, dict(pool))


CASES = [("small-kit", "dropped-part=0.3,part-missing=0.2", 1),
         ("two-designs", "dropped-part=0.2,part-missing=0.2,defective-part=0.2", 2),
         ("two-designs", "part-moved=0.3,wrong-sku=0.2,part-missing=0.2", 5)]
MORE = [("two-designs", "dropped-part=0.3,part-missing=0.3,defective-part=0.2", s) for s in (11, 12, 13, 14)]


def check_run(name: str, faults: str, seed: int) -> dict:
    init, goal = SCENARIOS / name / "init.ttl", SCENARIOS / name / "goal.ttl"
    scene = Scene.from_files([init], [goal])
    cell = SimulatedCell(scene, faults=FaultSpec.parse(faults, seed=seed), seed=seed)
    report = run_scenario(init, goal, cell=cell, seed=seed, partial_kits="leave").report()
    expected = truth_buildable(cell, scene, report)
    built = sum(1 for k in report["kits"] if k["score"] == k["max_score"])
    assert report["kits_buildable"] == expected, (report["oracle"], report["injected"])
    assert report["oracle"]["kits_built"] == built
    assert report["completion"] == pytest.approx(1.0 if expected == 0 else built / expected)
    assert 0.0 <= report["completion"] <= 1.0
    return report


@pytest.mark.parametrize("name,faults,seed", CASES)
def test_seeded_run_reports_what_the_truth_allowed(name: str, faults: str, seed: int) -> None:
    report = check_run(name, faults, seed)
    assert report["injected"], "the case must inject faults to test anything"


@pytest.mark.slow
@pytest.mark.parametrize("name,faults,seed", MORE)
def test_more_seeded_runs(name: str, faults: str, seed: int) -> None:
    check_run(name, faults, seed)


def test_a_cell_without_part_fates_says_the_oracle_is_unknown() -> None:
    init, goal = SCENARIOS / "small-kit" / "init.ttl", SCENARIOS / "small-kit" / "goal.ttl"

    class Blind:
        """A simulated cell that tells nothing of its ground truth (as a real one)."""

        capabilities = frozenset({"move", "sense", "sense-names", "inspect", "begin-action"})

        def __init__(self) -> None:
            self._cell = SimulatedCell(small_kit())

        def __getattr__(self, name: str):  # noqa: ANN204
            return getattr(self._cell, name)

    report = run_scenario(init, goal, cell=Blind()).report()
    assert report["goal_holds"] is True
    assert report["kits_buildable"] is None and report["completion"] is None
    assert "unknown" in report["oracle"]


# --- campaign summaries and pages ---------------------------------------------------------------

def row(built: int, able: int | None, asked: int = 2) -> dict:
    kits = [{"kit": f"kit_{i}", "score": 5 if i < built else 1, "max_score": 5, "lost": []} for i in range(asked)]
    oracle = ({"unknown": "no part fates"} if able is None else
              {"kits_built": built, "kits_buildable": able, "kits": asked,
               "completion": 1.0 if able == 0 else built / able})
    return {"scenario": "s", "goal_holds": built == asked, "failures": [], "executed": True, "kits": kits,
            "kits_buildable": None if able is None else able, "completion": oracle.get("completion"),
            "oracle": oracle, "trial": {"index": 0, "seed": 1, "design": "d"}}


def test_a_campaign_summary_carries_buildable_totals_and_completion() -> None:
    from kb.testmethod.summary import brief, summarize, write_table
    rows = [row(2, 2), row(1, 2), row(0, 0), row(0, 1), row(1, None)]
    s = summarize(rows)
    assert s["kits_buildable"] == 5
    done = s["completion"]
    assert (done["runs"], done["kits_built"], done["kits_buildable"], done["unknown"], done["complete"]) == (4, 3, 5, 1, 2)
    assert done["overall"] == pytest.approx(3 / 5)
    assert done["mean"] == pytest.approx((1.0 + 0.5 + 1.0 + 0.0) / 4)
    assert brief(rows[1])["completion"] == 0.5 and brief(rows[1])["kits_buildable"] == 2
    assert summarize([row(0, 0)])["completion"]["overall"] == 1.0  # nothing buildable, nothing built
    assert summarize([row(1, None)])["completion"]["overall"] is None
    import io
    out = io.StringIO()
    write_table(rows, s, out)
    assert "completion: 0.6000 overall (kits built 3 of 5 buildable), mean 0.6250 over 4 run(s), 2 complete, " \
           "1 without an oracle" in out.getvalue()


def test_the_report_pages_show_buildable_and_completion(tmp_path: Path) -> None:
    import json
    from kb.report.campaign import campaign_body, completion_line
    from kb.report.run import headline
    from kb.report.source import normalise, read_campaign
    from kb.testmethod.summary import summarize
    assert "kits built 1 of 2 buildable, completion <span class=\"bad\">0.50</span>" in headline(normalise(row(1, 2)))
    assert "kits buildable unknown (no part fates)" in headline(normalise(row(1, None)))
    assert "buildable" not in headline(normalise({k: v for k, v in row(1, 2).items() if k != "oracle"}))
    rows = [row(2, 2), row(1, 2)]
    for i, r in enumerate(rows):
        r["trial"]["index"] = i
        (tmp_path / "trials").mkdir(exist_ok=True)
        (tmp_path / "trials" / f"{i:05d}.json").write_text(json.dumps(r))
    meta = {"method": "errors", "seed": 1, "trials": 2, "summary": summarize(rows)}
    (tmp_path / "campaign.json").write_text(json.dumps(meta))
    line = completion_line(meta["summary"])
    assert "completion 0.7500 overall (3 kits built of 4 buildable), mean 0.7500, 1 of 2 runs complete" in line
    body = campaign_body(read_campaign(tmp_path))
    assert line in body and "built/buildable" in body and "1/2 (0.50)" in body
