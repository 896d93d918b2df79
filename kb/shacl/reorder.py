"""Order the triple patterns of simple SPARQL queries so that pyoxigraph joins cheaply.

pyoxigraph joins a basic graph pattern largely in the order it is written. A key-uniqueness
query written as ``$this sku ?k0 . ?other sku ?k0 . $this serial ?k1 . ?other serial ?k1``
pairs every two parts of the same SKU before it looks at the serial numbers: quadratic,
minutes at 10,000 parts, where the order ``serial, serial, sku, sku`` takes milliseconds.

Only a WHERE group made of plain triple patterns (``s p o .``, no ``;``/``,`` lists) and
FILTER clauses is reordered: a group's FILTERs apply to the whole group and its triples form
one join, so the order changes nothing but speed. Anything else is left as written. The
order is greedy: next comes the pattern, connected to the variables bound so far, with the
fewest expected rows (from per-predicate counts of triples, subjects and objects).
"""

from __future__ import annotations

import re
from collections.abc import Callable

RDF_TYPE = "<http://www.w3.org/1999/02/22-rdf-syntax-ns#type>"
_PREFIX = re.compile(r"PREFIX\s+([\w\-.]*):\s*<([^>]*)>", re.I)
_KEYWORDS = ("BIND", "OPTIONAL", "VALUES", "MINUS", "SERVICE", "GRAPH", "UNION", "SELECT")
Stats = Callable[[str], tuple[int, int, int] | None]


def _statements(body: str) -> list[str] | None:
    """Split a group body at top-level ``.``; None when it has nested groups or odd syntax."""
    out, cur, depth, i, n = [], [], 0, 0, len(body)
    while i < n:
        c = body[i]
        if c in "{}":
            return None
        if c in "\"'":
            j = i + 1
            while j < n and body[j] != c:
                j += 2 if body[j] == "\\" else 1
            if j >= n:
                return None
            cur.append(body[i : j + 1])
            i = j + 1
            continue
        if c == "<" and depth == 0:
            j = body.find(">", i)
            if j < 0:
                return None
            cur.append(body[i : j + 1])
            i = j + 1
            continue
        if c == "(":
            depth += 1
        elif c == ")":
            depth -= 1
        elif c == "." and depth == 0 and (i + 1 == n or body[i + 1].isspace()):
            out.append("".join(cur).strip())
            cur = []
            i += 1
            continue
        cur.append(c)
        i += 1
    if depth != 0:
        return None
    out.append("".join(cur).strip())
    return [s for s in out if s]


def _tokens(stmt: str) -> list[str]:
    return re.findall(r'(?:"(?:[^"\\]|\\.)*"|\'(?:[^\'\\]|\\.)*\'|[^\s"\'])+', stmt)


def _is_filter(stmt: str) -> bool:
    if not stmt[:6].upper() == "FILTER":
        return False
    rest = stmt[6:].lstrip()
    if not rest.startswith("("):
        return False
    depth = 0
    for i, c in enumerate(rest):  # the parenthesis opened first must close at the very end
        depth += c == "("
        depth -= c == ")"
        if depth == 0:
            return i == len(rest) - 1
    return False


def _expand(term: str, prefixes: dict[str, str]) -> str | None:
    if term == "a":
        return RDF_TYPE
    if re.fullmatch(r"<[^<>\s]*>", term):
        return term
    if ":" in term:
        pre, local = term.split(":", 1)
        if pre in prefixes and re.fullmatch(r"[\w\-.]*", local):
            return f"<{prefixes[pre]}{local}>"
    return None


def predicates_in(text: str) -> set[str]:
    """Predicate keys of the plain triple patterns of a query (for statistics)."""
    parsed = _parse(text)
    if parsed is None:
        return set()
    _, triples, _, _, _ = parsed
    return {p for _, p, _, _ in triples if p is not None}


def _parse(text: str):
    prefixes = dict(_PREFIX.findall(text))
    try:
        start = text.index("{")
        end = text.rindex("}")
    except ValueError:
        return None
    stmts = _statements(text[start + 1 : end])
    if not stmts:
        return None
    triples, filters = [], []
    for s in stmts:
        if _is_filter(s):
            filters.append(s)
            continue
        if s.split(None, 1)[0].upper() in _KEYWORDS or s.startswith("FILTER"):
            return None
        toks = _tokens(s)
        if len(toks) != 3 or any(t in (";", ",") or t.endswith((";", ",")) for t in toks):
            return None
        triples.append((toks[0], _expand(toks[1], prefixes), toks[2], s))
    return start, triples, filters, end, prefixes


def _var(term: str) -> str | None:
    return term[1:] if term[0] in "?$" else None


def reorder(text: str, stats: Stats, bound: frozenset[str] = frozenset()) -> str:
    """The query with its triple patterns in a cheap join order (unchanged when not simple)."""
    parsed = _parse(text)
    if parsed is None:
        return text
    start, triples, filters, end, _ = parsed
    if len(triples) < 2:
        return text
    big = 10**12
    have = set(bound)
    left = list(range(len(triples)))
    order: list[int] = []

    def cost(i: int) -> tuple[int, float, int]:
        s, p, o, _ = triples[i]
        sv, ov = _var(s), _var(o)
        s_bound = sv is None or sv in have
        o_bound = ov is None or ov in have
        connected = (sv in have if sv else False) or (ov in have if ov else False) or not have
        st = stats(p) if p is not None else None
        if st is None:
            est: float = big
        else:
            count, subjects, objects = st
            if s_bound and o_bound:
                est = 1
            elif s_bound:
                est = count / max(subjects, 1)
            elif o_bound:
                est = count / max(objects, 1)
            else:
                est = count
        return (0 if connected else 1, est, i)

    while left:
        best = min(left, key=cost)
        left.remove(best)
        order.append(best)
        s, _, o, _ = triples[best]
        have.update(v for v in (_var(s), _var(o)) if v)
    if order == sorted(order):
        return text
    body = " .\n    ".join(triples[i][3] for i in order) + " .\n    " + "\n    ".join(filters)
    return f"{text[: start + 1]}\n    {body}\n{text[end:]}"
