"""A state file's geometry in ``kitkb validate``: what stops the commands that read it, kit
designs that do not fit their tray, and implausible poses.

Each data file is read by :func:`kb.spatial.survey.survey` (one pass, metres):

* every defect that keeps kitkb from building the file's scene — the commands (``predicates``,
  ``plan``, ``run``) stop at the first with exit 2 — is an **error** here, with the same
  message at the same line and a rule naming it (``no-shape``, ``reference-cycle``,
  ``missing-value``, ``unusable-number``, ``degenerate-pose``, ``unit``, ``unknown-reference``):
  one verdict per defect, so an author learns it from ``validate`` first;
* ``slot-outside-tray`` (**error**, at the slot's line): a kit design's slot whose part would
  not lie in (or on) the design's kit tray, by how much and on which side, in the file's
  length unit (:func:`kb.spatial.plausibility.slot_misfits`); ``kitkb run`` refuses such a
  state before executing;
* ``interpenetration`` and ``floating-object`` (**warnings**, at the line of the object's pose
  location, both objects named, the depth in the file's length unit):
  :func:`kb.spatial.plausibility.check`.

A finding that only follows from another error (a misspelt coordinate is an ``unknown-property``,
not also a ``missing-value``) is left out: each carries the nodes it is read from
(``RuleContext.follows``), and :func:`kb.validation.validator.validate` drops it when one of
them has an error.
"""

from __future__ import annotations

from typing import Any, Collection, Iterable

import numpy as np
from rdflib import URIRef

from kb.core.namespaces import KTW
from kb.spatial.plausibility import RULES as PLAUSIBILITY, SLOT_OUTSIDE, check, describe, describe_misfit, slot_misfits
from kb.spatial.rcc8 import DEFAULT_TOLERANCE
from kb.spatial.survey import RULES as DEFECTS, Survey, survey
from kb.validation.rules import RuleContext, graph_of

#: every rule of this module
RULES = (*DEFECTS, SLOT_OUTSIDE, *PLAUSIBILITY)
_PRIMARY = KTW.hasSolidObject_PrimaryLocation
_POSE = (KTW.hasPoseLocation_Point, KTW.hasPoseLocation_XAxis, KTW.hasPoseLocation_ZAxis)


def check_geometry(ctx: RuleContext, src: Any, ignore: Collection[str] = ()) -> None:
    """Errors and warnings of data file ``src``'s geometry (nothing when every rule of this
    module is in ``ignore``)."""
    if all(r in ignore for r in RULES):
        return
    found = survey(src)
    _defects(ctx, src, found)
    if SLOT_OUTSIDE not in ignore:
        _slots(ctx, src, found)
    wanted = tuple(r for r in PLAUSIBILITY if r not in ignore)
    if found.scene is None or not wanted or not found.locations:
        return
    scene = found.scene
    for f in check(scene, DEFAULT_TOLERANCE, found.locations, wanted):
        focus = URIRef(f.obj)
        line = ctx.locate(src, URIRef(f.pose) if f.pose else focus, None, None)
        message = describe(f, lambda iri: ctx.name(URIRef(iri), src), scene.units)
        ctx.report(src, line, "warning", message, f.rule, focus)
        nodes = [n for obj in (f.obj, f.other) if obj for n in _pose_nodes(src, URIRef(obj))]
        _follows(ctx, src, f.rule, focus, message, nodes)


def _defects(ctx: RuleContext, src: Any, found: Survey) -> None:
    """The defects that stop the commands, as errors (each once)."""
    seen = set()
    for d in found.defects:
        if (d.rule, d.message, d.at) in seen:
            continue
        seen.add((d.rule, d.message, d.at))
        ctx.report(src, ctx.locate(src, *d.at, *(None,) * (3 - len(d.at))), "error", d.message, d.rule, d.node)
        _follows(ctx, src, d.rule, d.node, d.message, d.nodes)


def _slots(ctx: RuleContext, src: Any, found: Survey) -> None:
    """``slot-outside-tray`` errors, at each slot's line."""
    s = found.slots
    misfit, by, side = slot_misfits(s.pose, s.part_lo, s.part_hi, s.tray_lo, s.tray_hi, DEFAULT_TOLERANCE)
    for n in np.flatnonzero(misfit):
        slot = URIRef(s.names[n])
        name = [ctx.name(URIRef(x), src) for x in (s.names[n], s.design[n], s.part_sku[n], s.tray_sku[n])]
        message = describe_misfit(*name, float(by[n]), int(side[n]), s.part_hi[n] - s.part_lo[n],
                                  s.tray_hi[n] - s.tray_lo[n], found.units)
        ctx.report(src, ctx.locate(src, slot, None, None), "error", message, SLOT_OUTSIDE, slot)
        prp, design, part_sku, tray_sku, part_shape, tray_shape = s.nodes[n]
        g = graph_of(src)
        axes = [g.value(prp, p) for p in (KTW.hasPartRefAndPose_Point, KTW.hasPartRefAndPose_XAxis,
                                          KTW.hasPartRefAndPose_ZAxis)]
        _follows(ctx, src, SLOT_OUTSIDE, slot, message, [prp, part_shape, tray_shape, *axes, (design, "sku"),
                                                          (part_sku, "shape"), (tray_sku, "shape")])


def _follows(ctx: RuleContext, src: Any, rule: str, focus: Any, message: str, nodes: Iterable[Any]) -> None:
    """Record what a finding is read from: a node (any error there explains it) or a pair
    (node, word) (an error there whose message has the word in it)."""
    named: set[Any] = set()
    for n in nodes:
        if isinstance(n, tuple):
            if n[0] is not None:
                named.add((ctx.name(n[0], src), n[1]))
        elif n is not None:
            named.add(ctx.name(n, src))
    key = (str(src.path), rule, ctx.name(focus, src), message)
    ctx.follows[key] = ctx.follows.get(key, frozenset()) | frozenset(named)


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
