"""ARIAC's kitting score by year: reference cases from docs-2023/scoring.rst and from each
year's task_manager_plugin.cpp (ScoreQuadrant, ScoreKittingTask, HandleFaultyParts)."""

from __future__ import annotations

import pytest

from kb.ariac.scoring import Shipment, Task, TrayPart, faulty_quadrants, quadrant_points, score_kitting
from kb.ariac.trial import DESTINATIONS
from kb.core.errors import InputError

TASK = Task(3, "warehouse", (("battery", "blue", 3), ("pump", "purple", 1)))


def ship(*parts: TrayPart, tray: int | None = 3, at: str = "warehouse", checked: bool = False) -> Shipment:
    return Shipment(tray, parts, at, checked)


def part(q: int, type_: str, color: str, flipped: bool = False, faulty: bool = False, name: str = "") -> TrayPart:
    return TrayPart(name or f"{type_}_{color}_{q}", type_, color, q, flipped, faulty)


GOOD = (part(3, "battery", "blue"), part(1, "pump", "purple"))


@pytest.mark.parametrize("year,tray,maximum", [("ariac-2023", 3, 11), ("ariac-2024", 1, 9)])
def test_a_perfect_kit_scores_tray_quadrants_and_bonus(year: str, tray: int, maximum: int) -> None:
    s = score_kitting("O", TASK, ship(*GOOD), year)
    assert (s.score, s.max_score, s.tray, s.bonus, s.penalty, s.destination) == (maximum, maximum, tray, 2, 0, 1)
    assert [q.score for q in s.quadrants] == [3, 3]
    assert any("bonus 2" in r.reason for r in s.reasons)


# (type right, colour right, flipped, faulty) -> points: 2023 as documented and coded, 2024 as coded
@pytest.mark.parametrize("b,c,d,e,p2023,p2024", [
    (True, True, False, False, 3, 3),
    (True, False, False, False, 2, 2),
    (True, True, True, False, 2, 0),
    (True, False, True, False, 1, 0),
    (True, True, False, True, 0, 0),
    (False, True, False, False, 0, 0),
    (False, False, True, True, 0, 0),
])
def test_quadrant_points_by_year(b: bool, c: bool, d: bool, e: bool, p2023: int, p2024: int) -> None:
    assert quadrant_points("ariac-2023", b, c, d, e) == p2023
    assert quadrant_points("ariac-2024", b, c, d, e) == p2024


def test_a_flipped_part_costs_the_bonus_and_in_2024_its_points() -> None:
    kit = ship(part(3, "battery", "blue", flipped=True), part(1, "pump", "purple"))
    assert score_kitting("O", TASK, kit, "ariac-2023").score == 3 + 2 + 3  # no bonus
    s = score_kitting("O", TASK, kit, "ariac-2024")
    assert s.score == 1 + 0 + 3
    assert "flipped: 0 in 2024" in s.quadrants[1].reasons[0].reason


def test_extra_parts_cost_one_point_each_and_the_wrong_tray_its_points() -> None:
    kit = ship(*GOOD, part(2, "sensor", "red"), part(4, "sensor", "red"), tray=5)
    s = score_kitting("O", TASK, kit, "ariac-2023")
    assert (s.tray, s.penalty, s.score) == (0, 2, 0 + 6 + 2 - 2)
    assert any("kit tray 5, not 3" in r.reason for r in s.reasons)


def test_the_wrong_destination_multiplies_by_zero() -> None:
    s = score_kitting("O", TASK, ship(*GOOD, at="kitting"), "ariac-2024")
    assert s.score == 0 and s.destination == 0
    assert any("not warehouse: score x0" in r.reason for r in s.reasons)


def test_2023_floors_a_kit_at_zero_2024_does_not() -> None:
    task = Task(3, "warehouse", (("pump", "red", 1),))
    kit = ship(part(1, "sensor", "red"), part(2, "sensor", "red"), part(3, "sensor", "red"), tray=7)
    assert score_kitting("O", task, kit, "ariac-2023").score == 0
    assert score_kitting("O", task, kit, "ariac-2024").score == -2


def test_as1_and_as3_are_the_same_destination_for_the_scorer() -> None:
    task = Task(3, DESTINATIONS["as1"], TASK.products)
    assert score_kitting("O", task, ship(*GOOD, at=DESTINATIONS["as3"]), "ariac-2023").destination == 1
    assert score_kitting("O", task, ship(*GOOD, at=DESTINATIONS["as2"]), "ariac-2023").destination == 0


def test_faulty_quadrant_without_a_quality_check_is_whatever_right_part_lies_there() -> None:
    kit = ship(*GOOD)
    assert faulty_quadrants([3], TASK, kit) == {3}
    s = score_kitting("O", TASK, kit, "ariac-2023", faulty=[3])
    assert s.score == 3 + 0 + 3 and "is faulty: 0" in s.quadrants[1].reasons[0].reason
    # a part of the wrong colour in a faulty quadrant is not the faulty one: it scores 2
    wrong = ship(part(3, "battery", "red"), part(1, "pump", "purple"))
    assert faulty_quadrants([3], TASK, wrong) == set()


def test_after_a_quality_check_only_the_part_found_faulty_is() -> None:
    replaced = ship(*GOOD, checked=True)
    assert faulty_quadrants([3], TASK, replaced) == set()
    assert score_kitting("O", TASK, replaced, "ariac-2023", faulty=[3]).score == 11
    kept = ship(part(3, "battery", "blue", faulty=True), part(1, "pump", "purple"), checked=True)
    assert faulty_quadrants([3], TASK, kept) == {3}


def test_the_last_part_listed_in_a_quadrant_counts_and_the_others_are_extra() -> None:
    kit = ship(part(3, "battery", "red", name="first"), part(3, "battery", "blue", name="last"),
               part(1, "pump", "purple"))
    s = score_kitting("O", TASK, kit, "ariac-2023")
    assert s.quadrants[1].part == "last" and s.quadrants[1].score == 3 and s.penalty == 1
    assert s.score == 3 + 6 + 2 - 1


def test_an_empty_quadrant_no_tray_and_no_submission() -> None:
    s = score_kitting("O", TASK, ship(part(1, "pump", "purple")), "ariac-2023")
    assert s.score == 3 + 3 and "empty" in s.quadrants[1].reasons[0].reason
    assert score_kitting("O", TASK, ship(*GOOD, tray=None), "ariac-2023").score == 0
    s = score_kitting("O", TASK, None, "ariac-2024")
    assert s.score == 0 and s.max_score == 9 and "not submitted" in s.reasons[0].reason


def test_an_unknown_year_is_refused() -> None:
    with pytest.raises(InputError, match="unknown ARIAC scoring"):
        score_kitting("O", TASK, ship(*GOOD), "ariac-2022")
