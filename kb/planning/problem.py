"""Read a planning problem (:class:`ProblemSpec`) from an initial and a goal state file.

Objects are the individuals whose class falls under a domain type; the initial facts and
function values come from :mod:`kb.planning.facts`; the goal puts every kit of the goal
file where the goal file puts it, with the parts its kit design asks for
(``quantity = capacity`` for every SKU of the design).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from itertools import product
from pathlib import Path
from typing import Sequence

from rdflib import Graph, URIRef
from rdflib.namespace import RDF

from kb.core.errors import InputError
from kb.core.namespaces import KTW, local_name
from kb.io.loader import MODEL_STAND_IN, NOT_READ_RULES, KnowledgeBase, Source, load
from kb.io.vocabulary import not_understood
from kb.model.definitions import Definitions, Locator, load_definitions
from kb.model.soap import DomainSpec
from kb.planning import facts
from kb.planning import goal as goals
from kb.planning.state import KIT, PART, TRAY, ClassTree, World, design_counts, parts_in, pddl_name
from kb.spatial.scene import Scene


@dataclass
class ProblemSpec:
    """Objects, initial state and goal read from a workstation's init and goal files.

    ``objects`` maps a PDDL object name to (domain type IRI, individual IRI).
    ``facts`` are ground atoms true initially, ``values`` ground function values,
    ``goal`` ground atoms, ``goal_equal`` pairs of ground terms that must be equal.
    ``quota`` lists, per (function, args), the objects that may fill it (STRIPS tokens).
    """

    name: str
    objects: dict[str, tuple[str, str]] = field(default_factory=dict)
    facts: set[tuple[str, ...]] = field(default_factory=set)
    values: dict[tuple[str, ...], float] = field(default_factory=dict)
    goal: list[tuple[str, ...]] = field(default_factory=list)
    goal_equal: list[tuple[tuple[str, ...], tuple[str, ...]]] = field(default_factory=list)
    quota: dict[tuple[str, ...], list[str]] = field(default_factory=dict)
    shortage: list[str] = field(default_factory=list)  # quotas that cannot be filled
    sources: dict[str, str] = field(default_factory=dict)  # what -> file:line it came from
    #: the state files' warnings about what in them is not read (``file:line: warning: ...``)
    notes: list[str] = field(default_factory=list)
    #: the domain's predicates, whose true atoms ``facts`` holds (the others' atoms are false)
    predicates: list[str] = field(default_factory=list)



def load_world(paths: Sequence[str | Path], tree: ClassTree, like: World | None = None) -> World:
    """The :class:`World` of one state given as one or more files.

    With ``like`` (the initial state), individuals are renamed to the IRIs ``like`` uses for
    the same local names: for state files that describe one workstation in two namespaces,
    as NIST's initial and goal files do.
    """
    return world_of(load(list(paths), resolve_imports=False).sources, tree, like)


def world_of(sources: Sequence[Source], tree: ClassTree, like: World | None = None) -> World:
    """:func:`load_world` of files already loaded (e.g. by the closed loop, which reads each
    file once: :class:`kb.execution.inputs.LoopInputs`)."""
    kb = KnowledgeBase(list(sources))
    first = kb.sources[0]
    graph = kb.graph if like is None else _aligned(kb.graph, like)
    world = World(graph, first.path, tree, first.line_of)
    world.reading = [w for w in kb.warnings if w.rule in NOT_READ_RULES]
    world.notes = [w.format() for w in world.reading]
    world.matched_names = like is not None
    world.sources = list(sources)  # the goal's scene is read from them (kb.planning.goal)
    return world


def _aligned(graph: Graph, like: World) -> Graph:
    """``graph`` with subjects renamed to ``like``'s IRIs of the same local name, if any differ."""
    typed = {s for s in graph.subjects(RDF.type) if isinstance(s, URIRef)}
    known_subjects = set(like.g.subjects(RDF.type))
    strangers = typed - known_subjects
    if not strangers:
        return graph
    known = {pddl_name(s): s for s in known_subjects if isinstance(s, URIRef)}
    alias = {s: known[pddl_name(s)] for s in strangers if pddl_name(s) in known}
    if not alias:
        return graph
    out = Graph()
    for s, p, o in graph:
        out.add((alias.get(s, s), p, alias.get(o, o)))
    return out


def _notes(init: World, goal: World) -> list[str]:
    """The two states' warnings about what they hold that is not read; a note about one
    model file that kitkb's model stands in for once, though both files import it."""
    said: set[tuple[str, str]] = set()
    out = []
    for world in (init, goal):
        reading = getattr(world, "reading", None)
        if reading is None:
            out += world.notes
            continue
        for d in reading:
            if d.rule == MODEL_STAND_IN:
                if (d.rule, d.focus) in said:
                    continue
                said.add((d.rule, d.focus))
            out.append(d.format())
    return out


def used_types(domain: DomainSpec) -> set[str]:
    """Types that appear in parameters, predicates or functions (objects are typed with these)."""
    out = {t for a in domain.actions for _n, t in a.params}
    out |= {t for s in domain.predicates.values() for t in s.arg_types}
    out |= {t for s in domain.functions.values() for t in s.arg_types}
    return out


def read_problem(domain: DomainSpec, init: World, goal: World, name: str = "kitting",
                 definitions: Definitions | None = None, goal_scene: "Scene | None" = None,
                 scene: Scene | None = None, locate: Locator | None = None) -> ProblemSpec:
    """The problem of going from ``init`` to ``goal`` in ``domain`` (numeric form).

    The initial facts and function values are those that hold by ``definitions`` on ``scene``,
    the initial state's (default: :func:`initial_scene`; :mod:`kb.planning.facts`); ``locate``:
    where a domain node is written (the error of a predicate without a definition).

    ``definitions``: the domain's predicate definitions (default: the shipped domain's), by
    which the goal state's atoms are decided on ``goal_scene`` (default: read from ``goal``'s
    files); see :mod:`kb.planning.goal`."""
    spec = ProblemSpec(name, notes=_notes(init, goal))
    if not init.kind:
        raise not_understood("the initial state has no object kitkb reads (no individual of a class of "
                             "the kitting model that the planning domain uses)", init.g, init.path)
    names = _objects(spec, init, goal)
    _initial(spec, domain, init, goal, names, definitions, scene, locate)
    _goal(spec, domain, init, goal, names)
    _goal_facts(spec, domain, goal, definitions, goal_scene)
    return spec


def _goal_facts(spec: ProblemSpec, domain: DomainSpec, goal: World, definitions: Definitions | None,
                scene: "Scene | None") -> None:
    """Every goal fact of the goal state (:mod:`kb.planning.goal`) into ``spec.goal``; an
    InputError at the goal file's line when one cannot be brought about."""
    defs = definitions if definitions is not None else load_definitions()
    scene = scene if scene is not None else goals.goal_scene(goal)
    found = goals.decide(domain, defs, scene, [t for pair in spec.goal_equal for t in pair], spec.objects)
    line_of = scene.source.line_of if scene.source is not None else goal.line_of
    goals.check_reachable(domain, spec.objects, spec.facts, found, scene, goal.path, line_of)
    spec.goal[:] = sorted(set(spec.goal) | set(found.atoms))


def initial_scene(init: World, goal: World) -> Scene:
    """The scene of the initial state, the goal state's individuals declared (with their model
    facts, no geometry; matched by local name when ``goal`` was read so): what its facts are
    decided on."""
    sources = getattr(init, "sources", None)
    declared = getattr(goal, "sources", None) or [goal.path]
    matched = bool(getattr(goal, "matched_names", False))
    if sources:
        return Scene.from_sources(sources, declared=declared, match_names=matched)
    return Scene.from_files([init.path], declared=declared, match_names=matched)


def _initial(spec: ProblemSpec, domain: DomainSpec, init: World, goal: World, names: dict[URIRef, str],
             definitions: Definitions | None, scene: Scene | None, locate: Locator | None) -> None:
    """The initial facts and function values (:func:`kb.planning.facts.initial_state`: by the
    definitions, on the initial state's scene), every other grounding of a function 0."""
    defs = definitions if definitions is not None else load_definitions()
    state = facts.initial_state(domain, defs, scene if scene is not None else initial_scene(init, goal), locate)
    spec.predicates = sorted(domain.predicates)
    for pred, args in state.atoms:
        spec.facts.add((pred, *(_named(names, URIRef(a), goal, pred) for a in args)))
    for (fn, *args), value in state.values.items():
        if all(URIRef(a) in names for a in args):  # (an object of the function's class the problem lacks)
            spec.values[(fn, *(names[URIRef(a)] for a in args))] = value
    for f in domain.functions.values():
        _zero_fill(spec, domain, f.name, f.arg_types)


def _named(names: dict[URIRef, str], node: URIRef, goal: World, used_by: str) -> str:
    """The object name of ``node``; InputError if it is not an object of either state."""
    try:
        return names[node]
    except KeyError:
        raise InputError(f"{pddl_name(node)} (needed for {used_by}) is not an object of the initial "
                         "state", goal.path, goal.line_of(node)) from None


def _zero_fill(spec: ProblemSpec, domain: DomainSpec, function: str, arg_types: tuple[str, ...]) -> None:
    """Give every other grounding of a numeric function the value 0.

    PDDL leaves unset numeric fluents undefined, and unified-planning's simulator (hence its
    plan validator) refuses problems with undefined numeric values; the functions of the
    kitting domain range over kits, SKUs and trays, so this adds few values.
    """
    def is_a(cls: str | None, target: str) -> bool:
        while cls is not None and cls != target:
            cls = domain.types.get(cls)
        return cls == target

    pools = [[n for n, (cls, _iri) in spec.objects.items() if is_a(cls, t)] for t in arg_types]
    for args in product(*pools):
        spec.values.setdefault((function, *args), 0)


def _objects(spec: ProblemSpec, init: World, goal: World) -> dict[URIRef, str]:
    """Object names for the individuals of both states.

    An individual of the goal file is the object of the initial state with the same IRI;
    only kits may be new in the goal (a kit is made from a kit tray during the plan).
    """
    names: dict[URIRef, str] = {}
    taken: set[str] = set()

    def add(s: URIRef, kind: str, state: World) -> None:
        name = pddl_name(s)
        if name.lower() in taken:
            raise InputError(f"two individuals are both called {name}", state.path, state.line_of(s))
        taken.add(name.lower())
        names[s] = name
        spec.objects[name] = (kind, str(s))

    for s, kind in sorted(init.kind.items(), key=lambda kv: str(kv[0])):
        add(s, kind, init)
    for s, kind in sorted(goal.kind.items(), key=lambda kv: str(kv[0])):
        if s in names:
            known = spec.objects[names[s]][0]
            if known != kind:
                raise InputError(f"{names[s]} is a {local_name(kind)} in the goal state but a "
                                 f"{local_name(known)} in the initial state", goal.path, goal.line_of(s))
        elif kind == KIT:
            add(s, kind, goal)
        else:
            raise InputError(f"{pddl_name(s)} is in the goal state but not in the initial state{_what_helps(s, init, goal)}",
                             goal.path, goal.line_of(s))
    return names


def _what_helps(s: URIRef, init: World, goal: World) -> str:
    """The rest of the message about the goal's individual ``s`` that the initial state lacks:
    what would help, given how the states were read. ``--match-names`` only where it was not
    used and the initial state has an individual of that name in another namespace (NIST
    writes its two states so); otherwise the goal names an object the initial state lacks."""
    name = pddl_name(s)
    namesakes = sorted(str(x) for x in init.g.subjects(RDF.type) if isinstance(x, URIRef) and pddl_name(x) == name)
    only_kits = ("; only kits may be new in the goal state (a kit is built during the plan): describe "
                 f"{name} in the initial state, or leave it out of the goal state (are the two files states "
                 "of one workstation?)")
    if getattr(goal, "matched_names", False):
        return f" (--match-names found no individual called {name} there either){only_kits}"
    if namesakes:
        return (f", which calls it <{namesakes[0]}> (the goal state <{s}>): if both files describe one "
                "workstation in two namespaces, as NIST's do, match individuals by local name (--match-names)")
    return f" (no individual called {name} there, in any namespace){only_kits}"


def _goal(spec: ProblemSpec, domain: DomainSpec, init: World, goal: World,
          names: dict[URIRef, str]) -> None:
    kits = goal.of(KIT)
    if not kits:
        raise not_understood("the goal state has no kit kitkb reads (nothing to build: no individual of "
                             "ktw:Kit)", goal.g, goal.path)
    counted = [f for f in domain.functions.values() if f.kind == "CountExpression"]
    designs = [f for f in domain.functions.values() if f.kind == "DesignCountExpression"]
    free, used = _free_parts(init, names, movable(spec.facts, domain)), set()
    for f in counted:
        for cap in (d for d in designs if d.arg_types == f.arg_types):
            for kit in kits:
                need = design_counts(init, goal, kit)
                if not need:
                    raise InputError(f"kit {names[kit]} has no kit design with parts (hasKit_Design)",
                                     goal.path, goal.line_of(kit))
                for sku in sorted(need, key=str):
                    args = (names[kit], names[sku])
                    spec.goal_equal.append(((f.name, *args), (cap.name, *args)))
                    tokens = _tokens(init, goal, kit, sku, need[sku], names, free, used)
                    spec.quota[(f.name, *args)] = tokens
                    if len(tokens) < need[sku] - len(_already(init, kit, sku)):
                        spec.shortage.append(f"kit {args[0]} needs {need[sku]} part(s) of {args[1]}; "
                                             f"only {len(tokens)} more can be found in parts trays")


def _already(init: World, kit: URIRef, sku: URIRef) -> list[URIRef]:
    return parts_in(init, kit, sku) if kit in init.kind else []


def _tokens(init: World, goal: World, kit: URIRef, sku: URIRef, need: int, names: dict[URIRef, str],
            free: dict[URIRef, list[URIRef]], used: set[URIRef]) -> list[str]:
    """The parts that will fill (kit, sku): the goal file's choice first, then other parts.

    Only parts lying in a parts tray in the initial state can be taken, so only those are
    candidates; a part the goal file names but that is elsewhere is replaced by another of
    the same SKU (parts of one SKU are interchangeable).
    """
    already = _already(init, kit, sku)
    wanted = [p for p in _goal_parts(goal, kit).get(sku, []) if p not in already]
    missing = need - len(already)
    available = free.get(sku, [])
    in_trays = set(available)
    out: list[str] = []
    for p in [p for p in wanted if p in in_trays] + available:
        if len(out) >= missing:
            break
        if p in names and p not in used:
            out.append(names[p])
            used.add(p)
    return out


def _goal_parts(goal: World, kit: URIRef) -> dict[URIRef, list[URIRef]]:
    """SKU -> parts the goal state puts in ``kit`` (placed in it, or listed by hasKit_Part)."""
    cache = goal.memo.setdefault("goal_parts", {})
    if kit not in cache:
        by_sku: dict[URIRef, list[URIRef]] = {}
        seen: set[URIRef] = set()
        for p in parts_in(goal, kit) + goal.values(kit, KTW.hasKit_Part):
            if p not in seen:
                seen.add(p)
                by_sku.setdefault(goal.value(p, KTW.hasSkuObject_Sku), []).append(p)
        cache[kit] = by_sku
    return cache[kit]


def _free_parts(init: World, names: dict[URIRef, str], movable: set[str]) -> dict[URIRef, list[URIRef]]:
    """SKU -> the parts the plan may put in a kit: those lying in parts trays in the initial
    state first (in tray and name order), then every other part in no kit or kit tray that an
    action can take from where it lies (:func:`movable`: a part in a bin, on a table, in a box,
    which a domain extension's action takes from), in name order."""
    free: dict[URIRef, list[URIRef]] = {}
    for tray in init.of(TRAY):
        for p in parts_in(init, tray):
            free.setdefault(init.value(p, KTW.hasSkuObject_Sku), []).append(p)
    taken = {p for parts in free.values() for p in parts}
    taken.update(p for holder in (*init.of(KIT), *init.of(str(KTW.KitTray))) for p in parts_in(init, holder))
    for p in sorted(init.of(PART), key=str):
        if p not in taken and names.get(p) in movable:
            free.setdefault(init.value(p, KTW.hasSkuObject_Sku), []).append(p)
    return free


def movable(facts: "set[tuple[str, ...]] | list[tuple[str, ...]]", domain: DomainSpec) -> set[str]:
    """The objects some action can take from where they lie: the first argument of a fact that
    an action needs (a precondition atom on one of its parameters) and undoes (deletes the same
    atom): a part in a parts tray for kitkb's take-part, in a bin for an extension's action;
    not a part lying where no action takes from."""
    preds = set()
    for action in domain.actions:
        deleted = {(e.predicate, e.args) for e in action.effects if e.negated}
        preds.update(p.predicate for p in action.pre if not p.negated and p.args and (p.predicate, p.args) in deleted)
    return {f[1] for f in facts if len(f) > 1 and f[0] in preds}
