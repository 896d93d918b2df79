"""Objects of a state whose location is unknown: sensed before planning (partial instance data).

The paper's cell does not know where its parts are until it senses them. A state file may
leave an object's place open, in one of two ways (docs/validation.md, "Partial data: objects
to be sensed"):

* no ``ktw:hasSolidObject_PrimaryLocation`` at all; or
* a primary location that is a ``ktw:RelativeLocation`` (``RelativeLocationIn`` /
  ``RelativeLocationOn``: a reference object and a description, no pose) — the mark "in this
  tray, pose to be sensed".

Only a stock-keeping-unit object (``ktw:SkuObject``: parts, trays, kit trays...) can be left
unlocated: a sensor recognises it by its class and SKU. Nor can an object that another
object's location refers to (a tray whose parts are posed in its frame: their poses would have
no frame until it is sensed). Any other solid object without a location stays what the shapes
say it is (a missing value). :func:`unlocated` lists them,
cheaply (one pass over the file's SKU objects: ``kitkb run`` and planning ask it of every state,
and a state with every object placed goes on as before); :func:`refuse_unlocated` is what a
command that needs every pose (``generate pddl``, ``plan``, ``predicates``...) says of one.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Sequence

from rdflib import URIRef
from rdflib.namespace import RDF

from kb.core.errors import InputError
from kb.core.namespaces import KTW, local_name
from kb.io.loader import Source
from kb.spatial.scene import class_ancestors

_KTW = str(KTW)
_SKU_OBJECT = str(KTW.SkuObject)
_SOLID = str(KTW.SolidObject)
_RELATIVE = str(KTW.RelativeLocation)
_PRIMARY, _REF = KTW.hasSolidObject_PrimaryLocation, KTW.hasPhysicalLocation_RefObject
_POINT = KTW.hasPoseLocation_Point
#: containment the kitting model states besides locations: container property, and the
#: property of the container whose value stands for it (a large box's container)
CONTAINMENT = ((KTW.hasPartsVessel_Part, None),
               (KTW.hasLargeBoxWithEmptyKitTrays_KitTray, KTW.hasLargeBoxWithEmptyKitTrays_LargeContainer),
               (KTW.hasLargeBoxWithKits_Kit, KTW.hasLargeBoxWithKits_LargeContainer))


@dataclass(frozen=True)
class Unlocated:
    """An object of a state whose pose is not known. ``name``: its IRI; ``cls``: the IRI of
    its most specific kitting class (what a sensor is asked for); ``sku``: its SKU's IRI
    (None when it has none); ``container``: the object the file says it is in (a parts tray
    that lists it, the reference object of its relative location), None when the file does
    not say; ``location``: its relative location (the mark) or None when it has no primary
    location; ``path``, ``line``: where the file declares it."""

    name: str
    cls: str
    sku: str | None
    container: str | None
    location: str | None
    path: str
    line: int | None

    @property
    def why(self) -> str:
        """What the file says of its place, in words."""
        if self.location is not None:
            return (f"its location {local_name(self.location)} is relative (a RelativeLocation, no pose)"
                    + (f" to {local_name(self.container)}" if self.container else ""))
        return "it has no ktw:hasSolidObject_PrimaryLocation"

    def as_dict(self) -> dict[str, object]:
        return {"object": local_name(self.name), "class": local_name(self.cls),
                "sku": local_name(self.sku) if self.sku else None,
                "container": local_name(self.container) if self.container else None,
                "line": self.line}


def unlocated(source: Source, graph: Any = None) -> list[Unlocated]:
    """The SKU objects ``source`` declares whose pose is unknown, in name order (empty for a
    state with every object placed: the common case, one pass over the objects with a SKU,
    without the model's class tree). ``graph``: the statements to look in when the caller
    holds them already (an rdflib graph; default the source's triple view)."""
    view = source.view() if graph is None else graph
    # the common case without the class tree: every object with a SKU has a primary location with a point
    open_ = []
    for s, _ in view.subject_objects(KTW.hasSkuObject_Sku):
        loc = view.value(s, _PRIMARY)
        if loc is None or view.value(loc, _POINT) is None:
            open_.append((s, loc))
    if not open_:
        return []
    anc = class_ancestors()
    out = []
    for s, loc in open_:
        cs = [str(c) for c in view.objects(s, RDF.type) if str(c) in anc and _SKU_OBJECT in anc[str(c)]]
        if not isinstance(s, URIRef) or not cs:
            continue
        relative = loc is not None and any(_RELATIVE in anc.get(str(t), ()) for t in view.objects(loc, RDF.type))
        if loc is not None and not relative:
            continue
        out.append((s, cs, loc))
    if not out:
        return []
    frames = set(view.objects(None, _REF))  # other objects' poses are given in their frame: not to be sensed
    out = [t for t in out if t[0] not in frames]
    if not out:
        return []
    held = _containers(view)
    found = []
    for s, cs, loc in sorted(out, key=lambda t: str(t[0])):
        ref = view.value(loc, _REF) if loc is not None else None
        container = ref if ref is not None else held.get(s)
        sku = view.value(s, KTW.hasSkuObject_Sku)
        cls = max(cs, key=lambda c: (len(anc.get(c, ())), c))
        found.append(Unlocated(str(s), cls, str(sku) if sku is not None else None,
                               str(container) if container is not None else None,
                               str(loc) if loc is not None else None, str(source.path),
                               source.line_of(s, RDF.type)))
    return found


def _containers(view) -> dict:  # noqa: ANN001
    """Object -> the container the file lists it in (a large box: its large container)."""
    held = {}
    for prop, stand_in in CONTAINMENT:
        for container, thing in view.subject_objects(prop):
            own = view.value(container, stand_in) if stand_in is not None else None
            held.setdefault(thing, own if own is not None else container)
    return held


def refuse_unlocated(sources: Sequence[Source], command: str, graph: Any = None) -> None:
    """An InputError (exit 2) at the first object of ``sources`` whose location is unknown:
    ``command`` needs every object placed; ``kitkb run`` senses them first. ``graph``: the
    statements of a single source, when the caller holds them."""
    for source in sources:
        found = unlocated(source, graph if len(sources) == 1 else None)
        if found:
            first = found[0]
            more = f" (and {len(found) - 1} more)" if len(found) > 1 else ""
            raise InputError(f"{local_name(first.name)}'s location is unknown: {first.why}{more}; {command} needs "
                             "every object placed (kitkb run senses such objects before it plans)",
                             first.path, first.line)
