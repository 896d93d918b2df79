"""The planning-relevant view of one workstation data file (initial or goal state).

Individuals are typed with the nearest domain type among their classes' ancestors; an
object's place is the reference object of its ``hasSolidObject_PrimaryLocation`` (a large
container stands for the large box that owns it). Explicit containment properties
(``hasPartsVessel_Part``, ``hasEndEffectorHolder_EndEffector``, ...) are used only for
objects that have no primary location.
"""

from __future__ import annotations

import re
from collections import Counter, defaultdict
from functools import lru_cache
from pathlib import Path

from rdflib import Graph, URIRef
from rdflib.namespace import OWL, RDF, RDFS

from kb.core.errors import InputError
from kb.core.namespaces import KTW

# containment properties: (property, True if the subject contains the object)
_CONTAINS = [
    (KTW.hasPartsVessel_Part, True), (KTW.hasLargeBoxWithEmptyKitTrays_KitTray, True),
    (KTW.hasLargeBoxWithKits_Kit, True), (KTW.hasKit_Part, True),
    (KTW.hasEndEffectorHolder_EndEffector, True), (KTW.hasRobot_EndEffector, True),
    (KTW.hasEndEffector_HeldObject, True), (KTW.hasWorkTable_ObjectOnTable, True),
    (KTW.hasEndEffectorChangingStation_EndEffectorHolder, True),
]
_OWNERS = [KTW.hasLargeBoxWithEmptyKitTrays_LargeContainer, KTW.hasLargeBoxWithKits_LargeContainer]


@lru_cache(maxsize=65_536)
def pddl_name(iri: str) -> str:
    """A PDDL-safe object name from an individual's local name (remembered: the executor asks
    for the same few thousand names again and again)."""
    local = str(iri).rsplit("#", 1)[-1].rsplit("/", 1)[-1]
    name = re.sub(r"[^A-Za-z0-9_-]", "_", local)
    return name if name[:1].isalpha() else f"o_{name}"


class ClassTree:
    """The kitting class hierarchy and the domain types objects are mapped onto."""

    def __init__(self, model: Graph, domain_types: set[str]):
        self.parents: dict[str, list[str]] = defaultdict(list)
        self.known: set[str] = set()
        for cls in model.subjects(RDF.type, OWL.Class):
            if isinstance(cls, URIRef):
                self.known.add(str(cls))
        for child, parent in model.subject_objects(RDFS.subClassOf):
            if isinstance(child, URIRef) and isinstance(parent, URIRef):
                self.parents[str(child)].append(str(parent))
        self.domain_types = domain_types
        self._cache: dict[str, str | None] = {}

    def depth(self, cls: str) -> int:
        """Number of named ancestors of ``cls`` (on its first parent chain)."""
        n, seen = 0, {cls}
        while self.parents.get(cls):
            cls = sorted(self.parents[cls])[0]
            if cls in seen:
                break
            seen.add(cls)
            n += 1
        return n

    def domain_type(self, cls: str) -> str | None:
        """The nearest domain type at or above ``cls`` (breadth first), or None."""
        if cls not in self._cache:
            todo, seen, found = [cls], set(), None
            while todo and found is None:
                nxt = []
                for c in todo:
                    if c in self.domain_types:
                        found = c
                        break
                    seen.add(c)
                    nxt.extend(p for p in self.parents.get(c, ()) if p not in seen)
                todo = nxt
            self._cache[cls] = found
        return self._cache[cls]


class World:
    """Typed objects and their places in one state file."""

    def __init__(self, graph: Graph, path: str | Path, tree: ClassTree, line_of=None):  # noqa: ANN001
        self.g = graph
        self.path = str(path)
        self.line_of = line_of or (lambda *a: None)
        #: warnings about what the file holds that kitkb does not read (set by the loader)
        self.notes: list[str] = []
        #: the same, as the loader's diagnostics (``kb.planning.problem.load_world``)
        self.reading: list | None = None
        #: True when the individuals were matched to the initial state's by local name
        #: (``--match-names``): what a message about a missing individual can suggest
        self.matched_names = False
        self.kind: dict[URIRef, str] = {}
        for s, cls in graph.subject_objects(RDF.type):
            c = str(cls)
            if not isinstance(s, URIRef) or (c not in tree.known and not c.startswith(str(KTW))):
                continue  # a class of no model (owl:NamedIndividual, another vocabulary's)
            if c not in tree.known:
                raise InputError(f"{pddl_name(s)} has unknown class ktw:{c[len(str(KTW)):]} "
                                 "(not in the kitting model)", self.path, self.line_of(s, RDF.type, cls))
            t = tree.domain_type(c)
            if t is not None and (s not in self.kind or tree.depth(t) > tree.depth(self.kind[s])):
                self.kind[s] = t
        self.owner = {c: box for p in _OWNERS for box, c in graph.subject_objects(p)}
        self.place: dict[URIRef, URIRef] = {}
        self._inside: dict[URIRef, list[URIRef]] | None = None
        self._of: dict[str, list[URIRef]] = {}
        #: per-world cache for derived tables (readers store what they compute once)
        self.memo: dict[str, dict] = {}
        for s in self.kind:
            where = self._primary(s)
            if where is not None:
                self.place[s] = where
        for prop, _ in _CONTAINS:
            for container, thing in graph.subject_objects(prop):
                if thing in self.kind and thing not in self.place:
                    self.place[thing] = self.owner.get(container, container)

    def _primary(self, s: URIRef) -> URIRef | None:
        loc = self.g.value(s, KTW.hasSolidObject_PrimaryLocation)
        ref = self.g.value(loc, KTW.hasPhysicalLocation_RefObject) if loc is not None else None
        if ref is None or ref == s:
            return None
        return self.owner.get(ref, ref)

    # --- queries --------------------------------------------------------------------
    def of(self, type_iri: str) -> list[URIRef]:
        """Objects of the domain type, sorted by name."""
        if type_iri not in self._of:
            self._of[type_iri] = sorted((s for s, k in self.kind.items() if k == type_iri), key=_natural)
        return self._of[type_iri]

    def is_a(self, s: URIRef | None, type_iri: str) -> bool:
        return s is not None and self.kind.get(s) == type_iri

    def located(self, child: str, parent: str) -> list[tuple[URIRef, URIRef]]:
        """(x, y) for x of type child whose place is y of type parent."""
        return [(x, self.place[x]) for x in self.of(child) if self.is_a(self.place.get(x), parent)]

    def contents(self, container: URIRef) -> list[URIRef]:
        """Objects whose place is ``container``, sorted by name."""
        if self._inside is None:
            inside: dict[URIRef, list[URIRef]] = defaultdict(list)
            for x, y in self.place.items():
                inside[y].append(x)
            self._inside = {y: sorted(xs, key=_natural) for y, xs in inside.items()}
        return self._inside.get(container, [])

    def held_by(self, child: str, robot_type: str, effector_type: str) -> list[tuple[URIRef, URIRef]]:
        """(x, robot) for x of type child on a robot or on an end effector on a robot."""
        out = []
        for x in self.of(child):
            where = self.place.get(x)
            if self.is_a(where, effector_type):
                where = self.place.get(where)
            if self.is_a(where, robot_type):
                out.append((x, where))
        return out

    def value(self, s: URIRef, prop: URIRef):  # noqa: ANN201
        return self.g.value(s, prop)

    def values(self, s: URIRef, prop: URIRef) -> list:
        return sorted(self.g.objects(s, prop), key=_natural)


#: The kitting model's classes the goal's quotas read (a kit and its design, parts in trays).
PART, TRAY, KIT = str(KTW.Part), str(KTW.PartsTray), str(KTW.Kit)


def design_counts(w: World, g: World, kit: URIRef) -> Counter:
    """SKU -> number of parts the kit's design asks for (the kit and its design read in the
    initial state ``w``, else the goal state ``g``)."""
    design = w.value(kit, KTW.hasKit_Design)
    if design is None:
        design = g.value(kit, KTW.hasKit_Design)
    if design is None:
        return Counter()
    for state in (w, g):
        prps = state.values(design, KTW.hasKitDesign_PartRefAndPose)
        if prps:
            return Counter(state.value(p, KTW.hasPartRefAndPose_Sku) for p in prps)
    return Counter()


def parts_in(w: World, container: URIRef, sku: URIRef | None = None) -> list[URIRef]:
    """Parts placed in ``container`` (of ``sku`` if given)."""
    return [p for p in w.contents(container) if w.is_a(p, PART)
            and (sku is None or w.value(p, KTW.hasSkuObject_Sku) == sku)]


def _natural(x: object) -> list:
    return [int(t) if t.isdigit() else t for t in re.split(r"(\d+)", str(x))]
