"""A bad ARIAC trial file is one line naming its file and line, exit 2, nothing written."""

from __future__ import annotations

from pathlib import Path

import pytest

from kb.cli import main

ORDER = """orders:
  - id: 'A1'
    type: 'kitting'
    announcement:
      time_condition: 0
    kitting_task:
      agv_number: 1
      tray_id: 1
      destination: 'warehouse'
      products:
        - type: 'pump'
          color: 'red'
          quadrant: 1
"""
TRAYS = "kitting_trays:\n  tray_ids: [1]\n  slots: [2]\n"
BINS = "parts:\n  bins:\n    bin1:\n      - type: 'pump'\n        color: 'red'\n        slots: [1, 2]\n"

CASES = {
    "unknown top key": (TRAYS + BINS + ORDER + "sensors: []\n", 23, "unknown key 'sensors'"),
    "unknown lot key": (TRAYS + BINS + "        colour: 'red'\n" + ORDER, 10, "unknown key 'colour'"),
    "slot out of range": (TRAYS + BINS.replace("[1, 2]", "[1, 10]") + ORDER, 9, "from 1 to 9"),
    "slot twice": (TRAYS + BINS + "      - type: 'battery'\n        color: 'blue'\n        slots: [2]\n" + ORDER, 12,
                   "bin1 slot 2 already holds a part (line 9)"),
    "bad part type": (TRAYS + BINS.replace("'pump'", "'gear'") + ORDER, 7, "part type 'gear'"),
    "bad rotation": (TRAYS + BINS + "        rotation: 'p1/2'\n" + ORDER, 10, "is not an angle"),
    "yaml syntax": (TRAYS + BINS + "      - type: [pump\n" + ORDER, 11, "not YAML"),
    "no orders": (TRAYS + BINS, 1, "no 'orders'"),
    "duplicate key": (TRAYS + "kitting_trays:\n  tray_ids: [2]\n  slots: [3]\n" + BINS + ORDER, 4, "given twice"),
    "ids and slots differ": ("kitting_trays:\n  tray_ids: [1, 2]\n  slots: [2]\n" + BINS + ORDER, 3,
                             "2 tray_ids but 1 slots"),
    "tray slot 7": (TRAYS.replace("[2]", "[7]") + BINS + ORDER, 3, "from 1 to 6"),
    "quadrant 5": (TRAYS + BINS + ORDER.replace("quadrant: 1", "quadrant: 5"), 22, "from 1 to 4"),
    "two conditions": (TRAYS + BINS + ORDER.replace("time_condition: 0", "time_condition: 0\n      submission_condition:"
                                                    "\n        order_id: 'A1'"), 14, "2 given"),
    "unknown destination": (TRAYS + BINS + ORDER.replace("'warehouse'", "'dock'"), 18, "destination 'dock'"),
    "order id twice": (TRAYS + BINS + ORDER + ORDER[len("orders:\n"):], 23, "order id 'A1' is given twice"),
    "submission of no order": (TRAYS + BINS + ORDER.replace("time_condition: 0", "submission_condition:\n"
                                                            "        order_id: 'Z9'"), 11, "'Z9'"),
    "challenge unknown": (TRAYS + BINS + ORDER + "challenges:\n  - earthquake:\n      duration: 3\n", 24,
                          "unknown key 'earthquake'"),
    "faulty part of no order": (TRAYS + BINS + ORDER + "challenges:\n  - faulty_part:\n      order_id: 'Q'\n"
                                "      quadrant1: true\n", 24, "names order 'Q'"),
    "not a mapping": ("- just\n- a list\n", 1, "trial must be a mapping"),
}


@pytest.mark.parametrize("name", sorted(CASES))
def test_a_bad_trial_is_one_line_at_its_file_and_line(name: str, tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    text, line, message = CASES[name]
    trial = tmp_path / "bad.yaml"
    trial.write_text(text)
    code = main(["ariac", "import", str(trial), "-o", str(tmp_path / "out")])
    err = capsys.readouterr().err.strip()
    assert code == 2, err
    assert len(err.splitlines()) == 1 and "Traceback" not in err, err
    assert err.startswith(f"{trial}:{line}: error: "), err
    assert message in err, err
    assert not (tmp_path / "out").exists()


def test_the_cases_are_all_here() -> None:
    assert len(CASES) == 19


def test_an_empty_file_and_a_missing_file(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    empty = tmp_path / "empty.yaml"
    empty.write_text("")
    assert main(["ariac", "import", str(empty), "-o", str(tmp_path / "o")]) == 2
    assert "empty file" in capsys.readouterr().err
    assert main(["ariac", "import", str(tmp_path / "none.yaml"), "-o", str(tmp_path / "o")]) == 2
    assert "cannot read" in capsys.readouterr().err


def test_scoring_states_that_were_not_imported_is_refused(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    small = Path(__file__).resolve().parents[1] / "ontologies" / "scenarios" / "small-kit"
    code = main(["run", str(small / "init.ttl"), str(small / "goal.ttl"), "--scoring", "ariac-2023",
                 "-o", str(tmp_path / "o")])
    err = capsys.readouterr().err
    assert code == 2 and "ariac.json" in err and "kitkb ariac import" in err
