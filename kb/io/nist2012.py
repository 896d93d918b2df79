"""NIST's 2012 kitting vocabulary (``kittingClasses.owl#``) read as kitkb's model.

Terms are mapped one by one as they are parsed (:func:`kb.io.parsing.map_iri`: the same local
name, or the 2013 renaming of :data:`kb.core.namespaces.NIST_2012_RENAMES`). One 2012 structure
has no term to map to and is read here, after parsing: a ``PartsTrayWithParts`` group, which
holds a parts tray (``hasPartsTrayWithParts_Tray``) and lists its parts
(``hasPartsTrayWithParts_Parts``), the parts located in the group. The 2012 model puts the
tray at the group's origin ("the coordinate system of a PartsTrayWithParts is in the same
place as the coordinate system of its PartsTray"), so the group is read as its tray: the tray
takes the group's location, what is located in the group is located in the tray, and the
parts are the tray's (``hasPartsVessel_Part``), as kitkb's (and NIST's 2013) model has it.
A tray that is not at its group's origin is an InputError at its line (nothing is guessed).
"""

from __future__ import annotations

from pathlib import Path
from typing import Callable

from rdflib import Literal, URIRef
from rdflib.namespace import RDF

from kb.core.errors import InputError
from kb.core.namespaces import KTW, NIST_KTW_2012
from kb.io.parsing import Triple

_GROUP = URIRef(NIST_KTW_2012 + "PartsTrayWithParts")
_TRAY = URIRef(NIST_KTW_2012 + "hasPartsTrayWithParts_Tray")
_PARTS = URIRef(NIST_KTW_2012 + "hasPartsTrayWithParts_Parts")
_PART_IN = URIRef(NIST_KTW_2012 + "hadByPart_PartsTrayWithParts")
_TRAY_IN = URIRef(NIST_KTW_2012 + "hadByPartsTray_PartsTrayWithParts")
_IDENTITY = {KTW.hasPoseLocation_Point: (0.0, 0.0, 0.0), KTW.hasPoseLocation_XAxis: (1.0, 0.0, 0.0),
             KTW.hasPoseLocation_ZAxis: (0.0, 0.0, 1.0)}
_COMPONENTS = {KTW.hasPoseLocation_Point: (KTW.hasPoint_X, KTW.hasPoint_Y, KTW.hasPoint_Z),
               KTW.hasPoseLocation_XAxis: (KTW.hasVector_I, KTW.hasVector_J, KTW.hasVector_K),
               KTW.hasPoseLocation_ZAxis: (KTW.hasVector_I, KTW.hasVector_J, KTW.hasVector_K)}


def read_groups(triples: list[Triple], path: Path,
                line_of: Callable[[str], int | None]) -> list[Triple]:
    """``triples`` with each 2012 ``PartsTrayWithParts`` group read as its tray (see the module
    docstring); ``line_of(local_name)``: the line where an individual is first written."""
    trays = {g: t for g, p, t in triples if p == _TRAY}
    if not trays:
        return triples
    index: dict[tuple, list] = {}
    for s, p, o in triples:
        index.setdefault((s, p), []).append(o)

    def one(s, p):  # noqa: ANN001, ANN202
        found = index.get((s, p))
        return found[0] if found else None

    dropped: set[tuple] = set()
    for group, tray in trays.items():
        own = one(tray, KTW.hasSolidObject_PrimaryLocation)
        if own is not None and one(own, KTW.hasPhysicalLocation_RefObject) == group:
            _require_origin(own, tray, group, one, path, line_of)
            dropped.add((tray, KTW.hasSolidObject_PrimaryLocation, own))
            dropped.update((own, p, o) for (s, p), objs in index.items() if s == own for o in objs)
    out: list[Triple] = []
    for s, p, o in triples:
        if (s, p, o) in dropped or p in (_TRAY, _TRAY_IN) or (p == RDF.type and o == _GROUP):
            continue
        if p == _PARTS:
            out.append((trays[s], KTW.hasPartsVessel_Part, o))
        elif p == _PART_IN:
            out.append((s, KTW.hadByPart_PartsVessel, trays.get(o, o)))
        else:
            out.append((trays.get(s, s), p, trays.get(o, o)))
    return out


def _require_origin(location, tray, group, one, path: Path, line_of) -> None:  # noqa: ANN001
    """InputError unless ``location`` (the tray's, in its group) is the group's origin."""
    for prop, expected in _IDENTITY.items():
        node = one(location, prop)
        values = tuple(_number(one(node, c)) for c in _COMPONENTS[prop]) if node is not None else expected
        if any(v is None or abs(v - e) > 1e-9 for v, e in zip(values, expected)):
            raise InputError(f"{_local(tray)} is not at the origin of its NIST 2012 PartsTrayWithParts "
                             f"{_local(group)} (the 2012 model puts it there; kitkb reads the group as its "
                             "tray and cannot place it otherwise)", path, line_of(_local(location)))


def _number(value: object) -> float | None:
    try:
        return float(value) if isinstance(value, Literal) else None
    except (TypeError, ValueError):
        return None


def _local(node: object) -> str:
    return str(node).rsplit("#", 1)[-1]
