"""Names as unified-planning can take them, and back.

unified-planning keeps one namespace for types, predicates, functions, actions and objects,
and its reader takes only names of a letter then letters, digits, ``-`` and ``_``; PDDL has a
namespace per kind and FD-style planners take any symbol. kitkb renames what would clash or
not be read: a type (types never appear in a plan) before anything else, then a predicate
or function (neither do they), then an action named like an object, and any name the reader
refuses. Objects and actions keep their names in the plan: :attr:`Names.back` maps a renamed
one to the name in the file.
"""

from __future__ import annotations

import re
from itertools import count

from kb.planning.pddl.symbols import OBJECT, Symbols

_SAFE = re.compile(r"[a-z][a-z0-9_-]*\Z")
#: Words unified-planning's expression reader takes as its own before a predicate name.
RESERVED = frozenset({"and", "or", "not", "imply", "exists", "forall", "always", "sometime",
                      "sometime-before", "sometime-after", "at-most-once", "number", "either"})


def safe(name: str) -> bool:
    """True if unified-planning's reader takes ``name`` as a name."""
    return bool(_SAFE.match(name))


class Names:
    """The name each declared thing gets in the text unified-planning reads."""

    def __init__(self, s: Symbols) -> None:
        self.taken: set[str] = {OBJECT, *map(str, [*s.parents, *s.objects, *s.predicates, *s.functions, *s.operators])}
        self.types: dict[str, str] = {}
        self.predicates: dict[str, str] = {}
        self.functions: dict[str, str] = {}
        self.operators: dict[str, str] = {}
        self.objects: dict[str, str] = {}
        plan_names = set(s.objects) | set(s.operators)
        for name in s.objects:  # objects first: they keep their names unless unreadable
            self.objects[name] = str(name) if safe(name) and name != OBJECT else self._fresh(name, "o")
        for name in s.operators:
            clash = name in s.objects
            self.operators[name] = str(name) if safe(name) and not clash else self._fresh(name, "a")
        for table, mine in ((s.predicates, self.predicates), (s.functions, self.functions)):
            for name in table:
                bad = not safe(name) or name in RESERVED or name in plan_names
                mine[name] = self._fresh(name, "p") if bad else str(name)
        for name in s.parents:
            bad = not safe(name) or name in RESERVED or name in plan_names or name in s.predicates \
                or name in s.functions
            self.types[name] = self._fresh(name, "t") if bad else str(name)
        self.types[OBJECT] = OBJECT
        self.back = {new: old for table in (self.objects, self.operators) for old, new in table.items() if new != old}

    def _fresh(self, base: str, prefix: str) -> str:
        return self.fresh(base if safe(base) else f"{prefix}-{re.sub(r'[^a-z0-9_-]', '_', base)}")

    def fresh(self, base: str) -> str:
        """A new name from ``base`` that nothing else has (and remember it)."""
        base = base if safe(base) else "k-" + re.sub(r"[^a-z0-9_-]", "_", base)
        candidates = (base if i == 1 else f"{base}-{i}" for i in count(1))
        name = next(c for c in candidates if c not in self.taken and c not in RESERVED)
        self.taken.add(name)
        return name

    def variable(self, name: str, used: set[str]) -> str:
        """The name of variable ``?name`` (without ``?``) in a scope that already uses ``used``."""
        if safe(name) and name not in used:
            return name
        base = name if safe(name) else "v-" + re.sub(r"[^a-z0-9_-]", "_", name)
        return next(c for c in (f"{base}-{i}" for i in count(1)) if c not in used)
