"""Did-you-mean suggestions for misspelt names (properties, classes, individuals).

A suggestion is made only for a plausible misspelling: a name equal to the one written up to
letter case or look-alike characters, or a few typing slips away from it (letters left out,
added, changed or two neighbours swapped: one slip per ten characters of the name, at least
one), with the same words, each still recognisable (fewer slips in a word than half its
letters). Names are compared without their prefix. So ``PartGipperPose`` is
``PartGripperPose`` misspelt and ``hasSprocket_Teth`` ``hasSprocket_Teeth``, but
``hasPoint_Yaw`` is not ``hasPoint_Y`` (two slips in twelve characters, and ``Yaw`` is no
``Y``) nor ``hasPose_Point``, and ``hasLargeBoxWithKits_Box`` is not ``..._Kit``: another
name, not a typo of it.
"""

from __future__ import annotations

import difflib
import re
from typing import Iterable

#: Characters that look alike in most fonts; a name equal up to these is a likely typo.
_CONFUSABLE = str.maketrans({"l": "1", "I": "1", "i": "1", "|": "1", "O": "0", "o": "0"})
#: One typing slip is allowed per this many characters of the name written (at least one).
CHARACTERS_PER_SLIP = 10
#: Names shorter than this get a suggestion only up to letter case and look-alikes.
SHORTEST = 4


_WORDS = re.compile(r"[A-Z]+(?![a-z])|[A-Z]?[a-z]+|[0-9]+")


def _shape(name: str) -> str:
    return name.casefold().translate(_CONFUSABLE)


def _local(name: str) -> str:
    """``name`` without its prefix: ``ktw:Point`` -> ``Point``, ``<http://e.org/m#Point>`` ->
    ``Point``, ``:part_a_1`` -> ``part_a_1``."""
    if name.startswith("<") and name.endswith(">"):
        inner = name[1:-1]
        for sep in ("#", "/"):
            if sep in inner:
                return inner.rpartition(sep)[2] or inner
        return inner
    return name.partition(":")[2] if ":" in name else name


def slips(a: str, b: str, most: int) -> int:
    """The typing slips between ``a`` and ``b``: letters left out, added, changed or two
    neighbours swapped (optimal string alignment distance), counted up to ``most``: ``most +
    1`` stands for anything more (only the cells within ``most`` of the diagonal are filled)."""
    if a == b:
        return 0
    la, lb = len(a), len(b)
    if abs(la - lb) > most:
        return most + 1
    far = most + 1
    previous2: list[int] = []
    previous = [j if j <= most else far for j in range(lb + 1)]
    for i in range(1, la + 1):
        current = [far] * (lb + 1)
        if i <= most:
            current[0] = i
        lo, hi = max(1, i - most), min(lb, i + most)
        best = current[0] if lo == 1 else far
        ai = a[i - 1]
        for j in range(lo, hi + 1):
            value = previous[j - 1] + (ai != b[j - 1])
            if previous[j] + 1 < value:
                value = previous[j] + 1
            if current[j - 1] + 1 < value:
                value = current[j - 1] + 1
            if i > 1 and j > 1 and ai == b[j - 2] and a[i - 2] == b[j - 1] and previous2[j - 2] + 1 < value:
                value = previous2[j - 2] + 1
            current[j] = value if value <= most else far
            if current[j] < best:
                best = current[j]
        if best > most:
            return far
        previous2, previous = previous, current
    return min(previous[lb], far)


def allowed_slips(name: str) -> int:
    """How many slips a candidate may be from ``name`` (its local part) to be suggested."""
    local = _local(name)
    return 0 if len(local) < SHORTEST else max(1, len(local) // CHARACTERS_PER_SLIP)


def closest(name: str, candidates: Iterable[str]) -> str | None:
    """The candidate ``name`` is most plausibly a misspelling of, or None.

    In order: a candidate equal to ``name`` up to letter case (``hasPoint_x`` ->
    ``hasPoint_X``); one equal up to look-alike characters (``part_a_l`` -> ``part_a_1``);
    else the candidate fewest typing slips away, if within :func:`allowed_slips`
    (``PartGipperPose`` -> ``PartGripperPose``), ties broken by difflib's similarity, then
    alphabetically. Names are compared without their prefixes.
    """
    pool = sorted(set(candidates) - {name})
    local = _local(name)
    for same in (lambda c: _local(c).casefold() == local.casefold(), lambda c: _shape(_local(c)) == _shape(local)):
        hits = [c for c in pool if same(c)]
        if hits:
            return hits[0]
    most = allowed_slips(name)
    if most == 0:
        return None
    shape, size = _shape(local), len(local)
    found: list[tuple[int, float, str]] = []
    for c in pool:
        other = _local(c)
        if abs(len(other) - size) > most:
            continue
        n = slips(shape, _shape(other), most)
        if n <= most and _same_words(local, other):
            found.append((n, -difflib.SequenceMatcher(a=local, b=other).ratio(), c))
    return min(found)[2] if found else None


def _same_words(a: str, b: str) -> bool:
    """True when ``a`` and ``b`` have as many words (``PartGripperPose``: Part, Gripper, Pose;
    ``part_a_1``: part, a, 1) and each word of one is recognisable in the other's (fewer
    slips than half its letters: ``Gipper`` is ``Gripper``, ``Box`` is no ``Kit``)."""
    wa, wb = _WORDS.findall(a), _WORDS.findall(b)
    if len(wa) != len(wb):
        return False
    for x, y in zip(wa, wb):
        longest = max(len(x), len(y))
        if x.casefold() != y.casefold() and 2 * slips(_shape(x), _shape(y), longest) >= longest:
            return False
    return True


def resembles(name: str, candidate: str, cutoff: float = 0.6) -> bool:
    """True when ``candidate`` looks like ``name`` (equal up to case or look-alikes, or a
    difflib ratio of at least ``cutoff``): looser than :func:`closest`, for telling that a
    stray property was probably meant as a missing one (the missing one's report then only
    follows from the stray one's)."""
    if name.casefold() == candidate.casefold() or _shape(name) == _shape(candidate):
        return True
    return difflib.SequenceMatcher(a=candidate, b=name).ratio() >= cutoff


def did_you_mean(name: str, candidates: Iterable[str]) -> str:
    """``", did you mean X?"`` for the closest candidate, or ``""``."""
    best = closest(name, candidates)
    return f", did you mean {best}?" if best else ""
