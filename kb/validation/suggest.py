"""Did-you-mean suggestions for misspelt names (properties, classes, individuals)."""

from __future__ import annotations

import difflib
from typing import Iterable

#: Characters that look alike in most fonts; a name equal up to these is a likely typo.
_CONFUSABLE = str.maketrans({"l": "1", "I": "1", "i": "1", "|": "1", "O": "0", "o": "0"})


def _shape(name: str) -> str:
    return name.casefold().translate(_CONFUSABLE)


def closest(name: str, candidates: Iterable[str], cutoff: float = 0.6) -> str | None:
    """The candidate closest to ``name``, or None when nothing is close enough.

    In order: a candidate equal to ``name`` up to letter case (``hasPoint_x`` ->
    ``hasPoint_X``); one equal up to look-alike characters (``part_a_l`` -> ``part_a_1``);
    else the best difflib ratio of at least ``cutoff``, ties broken alphabetically.
    """
    pool = sorted(set(candidates) - {name})
    for same in (lambda c: c.casefold() == name.casefold(), lambda c: _shape(c) == _shape(name)):
        hits = [c for c in pool if same(c)]
        if hits:
            return hits[0]
    best, best_score = None, cutoff
    matcher = difflib.SequenceMatcher(b=name)
    for c in pool:
        matcher.set_seq1(c)
        if matcher.real_quick_ratio() < best_score or matcher.quick_ratio() < best_score:
            continue
        score = matcher.ratio()
        if score > best_score or (score == best_score and best is None):
            best, best_score = c, score
    return best


def did_you_mean(name: str, candidates: Iterable[str], cutoff: float = 0.6) -> str:
    """``", did you mean X?"`` for the closest candidate, or ``""``."""
    best = closest(name, candidates, cutoff)
    return f", did you mean {best}?" if best else ""
