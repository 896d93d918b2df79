"""The data graph indexed once: subject -> predicate -> objects, plus class membership.

Terms are keys (N-Triples spellings, see :mod:`kb.shacl.terms`). The index is the union of
everything added (data and model triples), which is what pySHACL validates when it is given
an ontology graph: it mixes the ontology into a copy of the data graph.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping

from rdflib import Graph, Literal

from kb.shacl.terms import ILL_TYPED, key_of

RDF_TYPE = "<http://www.w3.org/1999/02/22-rdf-syntax-ns#type>"
SUBCLASS_OF = "<http://www.w3.org/2000/01/rdf-schema#subClassOf>"


class DataIndex:
    """Subject-predicate-object dictionaries with lazily built inverse and class indexes."""

    def __init__(self) -> None:
        self.spo: dict[str, dict[str, list[str]]] = {}
        self._inverse: dict[str, dict[str, list[str]]] = {}
        self._supers: dict[str, frozenset[str]] = {}
        self._instances: dict[str, list[str]] | None = None
        self._subclasses: dict[str, list[str]] | None = None
        self.triples = 0

    # ------------------------------------------------------------------ building
    def add(self, s: str, p: str, o: str) -> None:
        """Add one triple (duplicates are ignored)."""
        preds = self.spo.get(s)
        if preds is None:
            self.spo[s] = {p: [o]}
            self.triples += 1
            return
        objs = preds.get(p)
        if objs is None:
            preds[p] = [o]
            self.triples += 1
        elif o not in objs:
            objs.append(o)
            self.triples += 1

    def add_ntriples(self, text: str) -> None:
        """Add N-Triples text as written by pyoxigraph (one triple per line, single spaces)."""
        spo = self.spo
        count = 0
        for line in text.splitlines():
            if not line or line[0] == "#":
                continue
            s, p, o = line.split(" ", 2)
            o = o[:-2] if o.endswith(" .") else o.rstrip(" .")
            preds = spo.get(s)
            if preds is None:
                spo[s] = {p: [o]}
                count += 1
                continue
            objs = preds.get(p)
            if objs is None:
                preds[p] = [o]
                count += 1
            elif o not in objs:
                objs.append(o)
                count += 1
        self.triples += count
        self._reset()

    def add_graph(self, graph: Graph) -> None:
        """Add an rdflib graph; literal keys keep rdflib's idea of term identity."""
        cache: dict[object, str] = {}

        def k(term: object) -> str:
            key = cache.get(term)
            if key is None:
                key = key_of(term)  # type: ignore[arg-type]
                if ILL_TYPED not in key:  # an ill-typed literal equals its well-typed twin
                    cache[term] = key
            elif type(term) is Literal and term.ill_typed:  # its well-typed twin was cached
                key = key_of(term)
            return key

        for s, p, o in graph.triples((None, None, None)):
            self.add(k(s), k(p), k(o))
        self._reset()

    def add_triples(self, triples: Iterable[tuple[object, object, object]]) -> None:
        """Add rdflib-term triples (a :class:`kb.io.views.TripleView`, the loader's lists);
        each distinct term is spelled once, as :meth:`add_graph` spells it."""
        cache: dict[object, str] = {}
        get = cache.get
        add = self.add
        for s, p, o in triples:
            if type(o) is Literal and o.ill_typed:  # equal to its well-typed twin: spelled apart
                add(key_of(s), key_of(p), key_of(o))  # type: ignore[arg-type]
                continue
            ks = get(s)
            if ks is None:
                ks = cache[s] = key_of(s)  # type: ignore[arg-type]
            kp = get(p)
            if kp is None:
                kp = cache[p] = key_of(p)  # type: ignore[arg-type]
            ko = get(o)
            if ko is None:
                ko = cache[o] = key_of(o)  # type: ignore[arg-type]
            add(ks, kp, ko)
        self._reset()

    def add_nested(self, spo: Mapping[object, Mapping[object, Iterable[object]]]) -> None:
        """Add rdflib-term triples given as subject -> predicate -> objects (without
        duplicates, as :meth:`kb.io.views.TripleView.by_subject` gives them).

        Keys are cached by object identity (the terms live in ``spo`` while this runs):
        hashing an rdflib literal is a Python-level call, hashing its ``id`` is not."""
        cache: dict[int, str] = {}
        get = cache.get
        mine = self.spo
        count = 0
        for s, preds in spo.items():
            ks = get(id(s))
            if ks is None:
                ks = cache[id(s)] = key_of(s)  # type: ignore[arg-type]
            have = mine.get(ks)
            for p, objs in preds.items():
                kp = get(id(p))
                if kp is None:
                    kp = cache[id(p)] = key_of(p)  # type: ignore[arg-type]
                keys = []
                for o in objs:
                    ko = get(id(o))
                    if ko is None:
                        ko = cache[id(o)] = key_of(o)  # type: ignore[arg-type]
                    keys.append(ko)
                if have is None:
                    mine[ks] = have = {kp: keys}
                    count += len(keys)
                elif kp not in have and len(set(keys)) == len(keys):
                    have[kp] = keys
                    count += len(keys)
                else:
                    before = self.triples
                    for ko in keys:
                        self.add(ks, kp, ko)
                    count += self.triples - before
                    self.triples = before
        self.triples += count
        self._reset()

    def _reset(self) -> None:
        self._inverse.clear()
        self._supers.clear()
        self._instances = None
        self._subclasses = None

    # ------------------------------------------------------------------ lookups
    def objects(self, s: str, p: str) -> list[str]:
        """Objects of (s, p, ?)."""
        preds = self.spo.get(s)
        if preds is None:
            return []
        return preds.get(p) or []

    def subjects(self, p: str, o: str) -> list[str]:
        """Subjects of (?, p, o), through an inverse index built once per predicate."""
        return self.inverse(p).get(o) or []

    def inverse(self, p: str) -> dict[str, list[str]]:
        """object -> subjects for predicate ``p``."""
        inv = self._inverse.get(p)
        if inv is None:
            inv = {}
            for s, preds in self.spo.items():
                for o in preds.get(p, ()):
                    subs = inv.get(o)
                    if subs is None:
                        inv[o] = [s]
                    else:
                        subs.append(s)
            self._inverse[p] = inv
        return inv

    def prepare_inverse(self, predicates: Iterable[str]) -> None:
        """Build the inverse indexes of several predicates in one pass over the data."""
        wanted = {p for p in predicates if p not in self._inverse}
        if not wanted:
            return
        invs: dict[str, dict[str, list[str]]] = {p: {} for p in wanted}
        for s, preds in self.spo.items():
            for p in wanted.intersection(preds):
                inv = invs[p]
                for o in preds[p]:
                    subs = inv.get(o)
                    if subs is None:
                        inv[o] = [s]
                    else:
                        subs.append(s)
        self._inverse.update(invs)

    def subjects_with(self, p: str) -> list[str]:
        """Subjects that have a value for ``p``."""
        return [s for s, preds in self.spo.items() if p in preds]

    def objects_of(self, p: str) -> set[str]:
        """Objects of all triples with predicate ``p``."""
        return set(self.inverse(p))

    def superclasses(self, cls: str) -> frozenset[str]:
        """``cls`` and everything reachable from it by rdfs:subClassOf."""
        found = self._supers.get(cls)
        if found is None:
            seen = {cls}
            todo = [cls]
            while todo:
                for sup in self.objects(todo.pop(), SUBCLASS_OF):
                    if sup not in seen:
                        seen.add(sup)
                        todo.append(sup)
            found = self._supers[cls] = frozenset(seen)
        return found

    def is_instance(self, node: str, cls: str) -> bool:
        """SHACL instance test: some rdf:type of ``node`` is ``cls`` or a subclass of it."""
        for t in self.objects(node, RDF_TYPE):
            if t == cls or cls in self.superclasses(t):
                return True
        return False

    def instances(self, cls: str) -> set[str]:
        """Instances of ``cls`` and of its transitive subclasses (the sh:targetClass set)."""
        if self._instances is None:
            inst: dict[str, list[str]] = {}
            subs: dict[str, list[str]] = {}
            for s, preds in self.spo.items():
                for t in preds.get(RDF_TYPE, ()):
                    inst.setdefault(t, []).append(s)
                for sup in preds.get(SUBCLASS_OF, ()):
                    subs.setdefault(sup, []).append(s)
            self._instances, self._subclasses = inst, subs
        assert self._subclasses is not None
        found: set[str] = set(self._instances.get(cls, ()))
        seen = {cls}
        todo = [cls]
        while todo:
            for sub in self._subclasses.get(todo.pop(), ()):
                if sub not in seen:
                    seen.add(sub)
                    todo.append(sub)
                    found.update(self._instances.get(sub, ()))
        return found

    def ntriples_split(
        self, predicates: Iterable[str] | None = None
    ) -> tuple[str, list[tuple[str, str, str]]]:
        """N-Triples text of the triples without blank nodes, and the triples with them."""
        lines: list[str] = []
        bnodes: list[tuple[str, str, str]] = []
        wanted = None if predicates is None else set(predicates)
        for s, preds in self.spo.items():
            sb = s[0] == "_"
            for p, objs in preds.items():
                if wanted is not None and p not in wanted:
                    continue
                for o in objs:
                    if sb or o[0] == "_":
                        bnodes.append((s, p, o))
                    else:
                        lines.append(f"{s} {p} {o} .")
        return "\n".join(lines) + "\n", bnodes

    def predicate_stats(self, predicates: Iterable[str]) -> dict[str, tuple[int, int, int]]:
        """(triples, distinct subjects, distinct objects) for each predicate asked for."""
        wanted = set(predicates)
        count = dict.fromkeys(wanted, 0)
        subs = dict.fromkeys(wanted, 0)
        objs: dict[str, set[str]] = {p: set() for p in wanted}
        for preds in self.spo.values():
            for p in wanted.intersection(preds):
                vals = preds[p]
                count[p] += len(vals)
                subs[p] += 1
                objs[p].update(vals)
        return {p: (count[p], subs[p], len(objs[p])) for p in wanted}

    def ntriples(self, predicates: Iterable[str] | None = None) -> str:
        """N-Triples text of the triples with the given predicates (all when None)."""
        lines: list[str] = []
        wanted = None if predicates is None else set(predicates)
        for s, preds in self.spo.items():
            for p, objs in preds.items():
                if wanted is not None and p not in wanted:
                    continue
                for o in objs:
                    lines.append(f"{s} {p} {o} .")
        return "\n".join(lines) + "\n"
