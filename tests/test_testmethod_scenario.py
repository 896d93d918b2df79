"""The test methods' workstations (kb.scenario: kit trays on the work table, tables with room
for trays at any yaw, seeded placements) are valid state files whose geometry says what their
facts say, nominal and placed alike."""

from __future__ import annotations

from pathlib import Path

import pytest

from kb.planning.geometry import check_geometry
from kb.scenario import layout, write_spec
from kb.scenario.placement import place_trays, placements
from kb.scenario.spec import method_spec, mixed_design, random_types
from kb.validation import validate

TYPES = random_types(3, seed=4)


def _basic():
    design = mixed_design(TYPES, 5, seed=2, name="kit_design_1")
    return layout(method_spec("tm-basic", TYPES, (design,), (0,), kit_trays_on_table=True))


def _multi():
    designs = (mixed_design(TYPES, 3, seed=1, name="kit_design_1"), mixed_design(TYPES, 4, seed=2, name="kit_design_2"))
    return layout(method_spec("tm-multi", TYPES, designs, (1, 0, 1)))


@pytest.mark.parametrize("make", [_basic, _multi], ids=["basic", "multi"])
def test_nominal_and_placed_workstations_are_valid_and_agree_with_their_facts(make, tmp_path: Path):
    sc = make()
    real, placed = place_trays(sc, seed=11)
    assert placed != placements(sc)
    for name, scenario in (("nominal", sc), ("placed", real)):
        init, goal = write_spec(scenario, tmp_path / name)
        report = validate([str(init), str(goal)])
        assert report.conforms, [d.format() for d in report.diagnostics]
        geo = check_geometry([init], [goal])
        assert geo.initial_agrees, (name, geo.only_geometry, geo.only_symbolic)
        assert not geo.goal_not_holding, geo.goal_not_holding


def test_kit_trays_start_on_the_work_table_only_when_asked():
    basic, multi = _basic(), _multi()
    assert [k.on_table for k in basic.kits] == [True]
    assert [p.table for p in placements(basic)].count("work_table_1") == 1
    assert not any(k.on_table for k in multi.kits)
    assert {p.table for p in placements(multi)} == {"parts_table_1"}


def test_designs_hold_two_or_more_part_types():
    for seed in range(30):
        design = mixed_design(TYPES, 2 + seed % 5, seed, "d")
        assert len(design.counts) >= 2 and design.size == 2 + seed % 5
