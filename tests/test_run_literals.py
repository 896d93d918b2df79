"""kitkb run loads the initial state into its world model through an N-Triples file of its
own: every literal a state may hold reaches the database as written (NIST's GearBox names its
STL files in strings over several lines)."""

from __future__ import annotations

from pathlib import Path

from rdflib import Graph, Literal, URIRef
from rdflib.namespace import RDFS

from kb.core.resources import scenario_dirs
from kb.execution import store
from kb.execution.store import prepare
from kb.world import dump, normalize_url

SMALL_KIT = next(d for d in scenario_dirs() if d.name == "small-kit")
ROBOT = URIRef("https://w3id.org/kitkb/scenario/small-kit#robot_1")
TEXTS = ['two\nlines', 'a \\ backslash, "quotes", a tab\tand a\r\ncarriage return', 'ünïcödé \u2028 line separator']


def test_prepare_keeps_literals_with_line_breaks_quotes_and_backslashes(tmp_path: Path) -> None:
    init = tmp_path / "init.ttl"
    g = Graph()
    g.parse(SMALL_KIT / "init.ttl")
    for i, text in enumerate(TEXTS):
        g.add((ROBOT, RDFS.comment, Literal(text, lang="en" if i == 2 else None)))
    init.write_text(g.serialize(format="turtle"), encoding="utf-8")
    db = tmp_path / "w.sqlite"
    prepare(db, init)
    store._PREPARED.pop(normalize_url(db)).release()  # no run follows: the run's hold on the database ends here
    out = tmp_path / "dump.ttl"
    dump(db, out)
    back = Graph().parse(out)
    assert {str(o) for o in back.objects(ROBOT, RDFS.comment)} == set(TEXTS)


def test_a_statement_the_load_refuses_is_told_at_the_state_files_line(tmp_path: Path) -> None:
    """The load reads kitkb's own N-Triples copy of the state: what it refuses is told at the
    state file's line, never at a line of the temporary file (gone by then)."""
    import pytest

    from kb.core.errors import InputError
    state = Path(__file__).parent / "data" / "unknown_reference" / "kittingInstancesMisspelt.owl"
    with pytest.raises(InputError) as err:
        prepare(tmp_path / "w.sqlite", state)
    assert err.value.file == str(state) and err.value.line == 1386
    assert "unknown individual part_b_tary" in err.value.message
