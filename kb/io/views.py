"""Read-only views of triples that validation queries instead of rdflib graphs.

:class:`TripleView` holds one file's triples in plain dictionaries with the read-only query
methods of an rdflib graph (much cheaper to build than an rdflib store for a data file of a
million triples); :class:`UnionView` is a union of such views and graphs, without copying.
"""

from __future__ import annotations

from typing import Iterable, Iterator

#: An rdflib term (or anything hashable standing for one) used as an index key.
Key = object


class TripleView:
    """A read-only, dictionary-indexed set of triples with the query methods of an rdflib
    graph that validation uses (``triples``, ``subjects``, ``objects``, ``in`` ...).

    Filling it costs a fraction of an rdflib store (one subject -> predicate -> objects index;
    the predicate and object indexes are built on first use), which matters for data files
    of a million triples. Results come in the order the triples were added.
    """

    def __init__(self, triples: Iterable[tuple] = ()) -> None:
        spo: dict[Key, dict[Key, dict[Key, None]]] = {}
        count = 0
        for s, p, o in triples:
            preds = spo.get(s)
            if preds is None:
                spo[s] = {p: {o: None}}
                count += 1
                continue
            objs = preds.get(p)
            if objs is None:
                preds[p] = {o: None}
                count += 1
            elif o not in objs:
                objs[o] = None
                count += 1
        self._spo = spo
        self._len = count
        self._pos: dict[Key, dict[Key, list[Key]]] | None = None
        self._single: dict[Key, dict[Key, list[Key]]] = {}
        self._osp: dict[Key, dict[Key, list[Key]]] | None = None

    # --- indexes ---------------------------------------------------------------------
    #: Predicates indexed one at a time before the whole predicate index is built at once.
    SINGLE_PREDICATES = 2

    def _by_predicate(self) -> dict[Key, dict[Key, list[Key]]]:
        """predicate -> object -> subjects, for every predicate."""
        if self._pos is None:
            pos: dict[Key, dict[Key, list[Key]]] = {}
            for s, preds in self._spo.items():
                for p, objs in preds.items():
                    inv = pos.get(p)
                    if inv is None:
                        inv = pos[p] = {}
                    for o in objs:
                        subs = inv.get(o)
                        if subs is None:
                            inv[o] = [s]
                        else:
                            subs.append(s)
            self._pos = pos
        return self._pos

    def _predicate(self, p: Key) -> dict[Key, list[Key]]:
        """object -> subjects for one predicate: a pass over the subjects for the first few
        predicates asked about (validation asks about rdf:type and the odd unknown
        predicate), the whole predicate index once more are asked about."""
        if self._pos is not None:
            return self._pos.get(p) or {}
        one = self._single.get(p)
        if one is None:
            if len(self._single) >= self.SINGLE_PREDICATES:
                self._single.clear()
                return self._by_predicate().get(p) or {}
            one = self._single[p] = {}
            for s, preds in self._spo.items():
                objs = preds.get(p)
                if objs is not None:
                    for o in objs:
                        subs = one.get(o)
                        if subs is None:
                            one[o] = [s]
                        else:
                            subs.append(s)
        return one

    def _by_object(self) -> dict[Key, dict[Key, list[Key]]]:
        if self._osp is None:
            osp: dict[Key, dict[Key, list[Key]]] = {}
            for s, preds in self._spo.items():
                for p, objs in preds.items():
                    for o in objs:
                        subs = osp.get(o)
                        if subs is None:
                            osp[o] = {s: [p]}
                        else:
                            subs.setdefault(s, []).append(p)
            self._osp = osp
        return self._osp

    def by_subject(self) -> dict[Key, dict[Key, dict[Key, None]]]:
        """The subject -> predicate -> objects index itself (do not modify it)."""
        return self._spo

    # --- rdflib-like queries -----------------------------------------------------------
    def __len__(self) -> int:
        return self._len

    def __iter__(self) -> Iterator[tuple]:
        for s, preds in self._spo.items():
            for p, objs in preds.items():
                for o in objs:
                    yield s, p, o

    def __contains__(self, triple: tuple) -> bool:
        return next(self.triples(triple), None) is not None

    def triples(self, pattern: tuple) -> Iterator[tuple]:
        """Triples matching ``(s, p, o)``, None standing for anything."""
        s, p, o = pattern
        if s is not None:
            preds = self._spo.get(s)
            if not preds:
                return
            for pp, objs in ([(p, preds[p])] if p in preds else []) if p is not None else preds.items():
                if o is None:
                    for oo in objs:
                        yield s, pp, oo
                elif o in objs:
                    yield s, pp, o
        elif p is not None:
            inv = self._predicate(p)
            if not inv:
                return
            if o is not None:
                for ss in inv.get(o, ()):
                    yield ss, p, o
            else:
                for oo, subs in inv.items():
                    for ss in subs:
                        yield ss, p, oo
        elif o is not None:
            for ss, preds in self._by_object().get(o, {}).items():
                for pp in preds:
                    yield ss, pp, o
        else:
            yield from self

    def subjects(self, predicate: Key | None = None, obj: Key | None = None) -> Iterator[Key]:
        """Subjects of (?, p, o); with duplicates when p or o is None, like rdflib."""
        if predicate is not None and obj is not None:
            yield from self._predicate(predicate).get(obj, ())
            return
        for s, _, _ in self.triples((None, predicate, obj)):
            yield s

    def objects(self, subject: Key | None = None, predicate: Key | None = None) -> Iterator[Key]:
        """Objects of (s, p, ?)."""
        if subject is not None and predicate is not None:
            yield from self._spo.get(subject, {}).get(predicate, ())
            return
        for _, _, o in self.triples((subject, predicate, None)):
            yield o

    def predicates(self, subject: Key | None = None, obj: Key | None = None) -> Iterator[Key]:
        """Predicates of (s, ?, o)."""
        if subject is None and obj is None:
            yield from self._by_predicate()
            return
        for _, p, _ in self.triples((subject, None, obj)):
            yield p

    def subject_objects(self, predicate: Key | None = None) -> Iterator[tuple]:
        """(s, o) of (?, p, ?)."""
        for s, _, o in self.triples((None, predicate, None)):
            yield s, o

    def subject_predicates(self, obj: Key | None = None) -> Iterator[tuple]:
        """(s, p) of (?, ?, o)."""
        for s, p, _ in self.triples((None, None, obj)):
            yield s, p

    def predicate_objects(self, subject: Key | None = None) -> Iterator[tuple]:
        """(p, o) of (s, ?, ?)."""
        for _, p, o in self.triples((subject, None, None)):
            yield p, o

    def value(self, subject: Key | None = None, predicate: Key | None = None, obj: Key | None = None) -> Key | None:
        """One object of (s, p, ?) (or subject of (?, p, o)), else None."""
        if obj is None:
            return next(self.objects(subject, predicate), None)
        return next(self.subjects(predicate, obj), None)


class UnionView:
    """A read-only union of graphs or :class:`TripleView` objects (no copy; duplicates are
    kept, as in rdflib's ``ReadOnlyGraphAggregate``)."""

    def __init__(self, graphs: list) -> None:
        self.graphs = list(graphs)

    def __len__(self) -> int:
        return sum(len(g) for g in self.graphs)

    def __iter__(self) -> Iterator[tuple]:
        for g in self.graphs:
            yield from g.triples((None, None, None))

    def __contains__(self, triple: tuple) -> bool:
        return any(triple in g for g in self.graphs)

    def triples(self, pattern: tuple) -> Iterator[tuple]:
        for g in self.graphs:
            yield from g.triples(pattern)

    def subjects(self, predicate=None, obj=None):  # noqa: ANN001, ANN201
        for g in self.graphs:
            yield from g.subjects(predicate, obj)

    def objects(self, subject=None, predicate=None):  # noqa: ANN001, ANN201
        for g in self.graphs:
            yield from g.objects(subject, predicate)

    def predicates(self, subject=None, obj=None):  # noqa: ANN001, ANN201
        for g in self.graphs:
            yield from g.predicates(subject, obj)

    def subject_objects(self, predicate=None):  # noqa: ANN001, ANN201
        for g in self.graphs:
            yield from g.subject_objects(predicate)

    def subject_predicates(self, obj=None):  # noqa: ANN001, ANN201
        for g in self.graphs:
            yield from g.subject_predicates(obj)

    def predicate_objects(self, subject=None):  # noqa: ANN001, ANN201
        for g in self.graphs:
            yield from g.predicate_objects(subject)

    def value(self, subject=None, predicate=None, obj=None):  # noqa: ANN001, ANN201
        for g in self.graphs:
            v = g.value(subject, predicate, obj)
            if v is not None:
                return v
        return None
