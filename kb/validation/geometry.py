"""Physical plausibility of a state file's poses, as warnings of ``kitkb validate``.

A data file that places solid objects (``hasSolidObject_PrimaryLocation``) is read as a scene
(:class:`kb.spatial.scene.Scene`, metres) and checked by :func:`kb.spatial.plausibility.check`:
``interpenetration`` (two solids in one space, a solid through the floor or a wall of its open
container or below the ground) and ``floating-object`` (resting on nothing), each reported at
the line of the object's pose location with both objects named and the depth in the file's
length unit. Warnings: they do not change the exit code. Files that place nothing (models, the
SOAP domain) are not read again.
"""

from __future__ import annotations

from typing import Any, Collection

from rdflib import URIRef

from kb.core.diagnostics import Diagnostic
from kb.core.errors import InputError
from kb.core.namespaces import KTW
from kb.validation.rules import RuleContext, graph_of

#: the rule of a state file whose geometry could not be read (so was not checked)
UNCHECKED = "geometry-unchecked"
_PRIMARY = KTW.hasSolidObject_PrimaryLocation
_POSE = (KTW.hasPoseLocation_Point, KTW.hasPoseLocation_XAxis, KTW.hasPoseLocation_ZAxis)


def locations(src: Any) -> dict[str, str]:
    """Object IRI -> the IRI of its pose location, for the objects ``src`` places."""
    return {str(s): str(o) for s, o in graph_of(src).subject_objects(_PRIMARY) if isinstance(o, URIRef)}


def check_geometry(ctx: RuleContext, src: Any, ignore: Collection[str] = ()) -> None:
    """Warnings for the implausible poses of data file ``src`` (nothing when it places no
    objects, or when both geometry rules are in ``ignore``)."""
    where = locations(src)
    if not where:
        return
    from kb.spatial.plausibility import RULES, check, describe  # numpy and the scene: only for state files
    from kb.spatial.rcc8 import DEFAULT_TOLERANCE
    from kb.spatial.scene import Scene
    wanted = tuple(r for r in RULES if r not in ignore)
    if not wanted:
        return
    try:
        scene = Scene.from_sources([src])
    except InputError as exc:
        if UNCHECKED not in ignore:
            ctx.out.append(Diagnostic(str(src.path), exc.line, "warning",
                                      f"physical plausibility not checked: {exc.message}", UNCHECKED, ""))
        return
    for f in check(scene, DEFAULT_TOLERANCE, where, wanted):
        focus = URIRef(f.obj)
        line = ctx.locate(src, URIRef(f.pose) if f.pose else focus, None, None)
        message = describe(f, lambda iri: ctx.name(URIRef(iri), src), scene.units)
        ctx.report(src, line, "warning", message, f.rule, focus)
        nodes = [n for obj in (f.obj, f.other) if obj for n in _pose_nodes(src, URIRef(obj))]
        key = (str(src.path), f.rule, ctx.name(focus, src), message)
        ctx.follows[key] = frozenset(ctx.name(n, src) for n in nodes)


def _pose_nodes(src: Any, obj: URIRef) -> list[Any]:
    """What ``obj``'s place and size are read from: it, its shape (its SKU's or its own), its
    pose location's point and axes, and the same for each reference object up the tree."""
    g = graph_of(src)
    out: list[Any] = []
    while obj is not None and obj not in out:
        sku = g.value(obj, KTW.hasSkuObject_Sku)
        shapes = [g.value(sku, KTW.hasStockKeepingUnit_InternalShape) if sku is not None else None,
                  g.value(obj, KTW.hasNoSkuObject_InternalShape)]
        loc = g.value(obj, _PRIMARY)
        out += [n for n in (obj, sku, *shapes, loc) if n is not None]
        if loc is None:
            break
        out += [n for n in (g.value(loc, p) for p in _POSE) if n is not None]
        obj = g.value(loc, KTW.hasPhysicalLocation_RefObject)
    return out
