"""Where each statement of a file is written: first line of each subject, (subject,
predicate) and (subject, predicate, object), and of each OWL axiom."""

from __future__ import annotations

from dataclasses import dataclass, field

#: An rdflib term (or anything hashable standing for one) used as an index key.
Key = object


@dataclass
class LineIndex:
    """First line of each subject, (subject, predicate) and (subject, predicate, object)."""

    subj: dict[Key, int] = field(default_factory=dict)
    sp: dict[tuple, int] = field(default_factory=dict)
    spo: dict[tuple, int] = field(default_factory=dict)
    #: OWL axioms (functional syntax, OWL/XML): the named entities each mentions, and its line;
    #: locates the blank nodes an axiom turns into (owl:AllDifferent, restrictions, lists).
    axioms: list[tuple[frozenset, int]] = field(default_factory=list)

    def add(self, line: int, s: Key | None, p: Key | None = None, o: Key | None = None) -> None:
        """Record that ``line`` states (s, p, o); missing parts are left out."""
        if s is None:
            return
        self.subj.setdefault(s, line)
        if p is not None:
            self.sp.setdefault((s, p), line)
            if o is not None:
                self.spo.setdefault((s, p, o), line)

    def axiom_line(self, names: set) -> int | None:
        """Line of the first axiom mentioning exactly ``names``, else of the first mentioning
        them all (None if there is none, or ``names`` is empty)."""
        if not names:
            return None
        for mentioned, line in self.axioms:
            if mentioned == names:
                return line
        return next((line for mentioned, line in self.axioms if names <= mentioned), None)

    def lookup(self, s: Key, p: Key | None = None, o: Key | None = None) -> int | None:
        """Line of (s,p,o), falling back to (s,p), then to s."""
        if p is not None and o is not None and (s, p, o) in self.spo:
            return self.spo[(s, p, o)]
        if p is not None and (s, p) in self.sp:
            return self.sp[(s, p)]
        return self.subj.get(s)
