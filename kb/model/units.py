"""The units a data file is written in, and which of the kitting model's properties hold a
quantity (the model's ``ktw:quantityKind`` annotations): what :mod:`kb.spatial.scene` and
:mod:`kb.scenario.variants` convert. The unit tables are :mod:`kb.core.units`."""

from __future__ import annotations

from functools import lru_cache
from typing import Callable, Sequence

from kb.core.errors import InputError
from kb.core.namespaces import KTW, local_name
from kb.core.resources import ontology_path
from kb.core.units import KINDS, SI, Units, unit_factor
from kb.io import load_file
from kb.io.views import TripleView

#: workstation property -> the quantity kind whose unit it names
UNIT_PROPS = {"length": KTW.hasKittingWorkstation_LengthUnit, "angle": KTW.hasKittingWorkstation_AngleUnit,
              "weight": KTW.hasKittingWorkstation_WeightUnit}


@lru_cache(maxsize=1)
def quantity_kinds() -> dict[str, str]:
    """Data property IRI -> its quantity kind ("length", "angle", "weight"), from the kitting
    model's ``ktw:quantityKind`` annotations."""
    view = load_file(ontology_path("kitting.ttl")).view()
    return {str(p): str(k) for p, k in view.subject_objects(KTW.quantityKind) if str(k) in KINDS}


def read_units(views: Sequence[TripleView], path: str | None = None, locate: Callable | None = None) -> Units:
    """The units the workstation of ``views`` declares (SI for a kind it does not declare).

    A unit kitkb cannot convert, or two workstations declaring different units, is an
    :class:`InputError` at the workstation's line."""
    found: dict[str, str] = {}
    for kind, prop in UNIT_PROPS.items():
        for view in views:
            for ws, name in view.subject_objects(prop):
                text = str(name).strip().lower()
                # the line only for an error: finding it indexes the whole file (a second of a big one)
                where = (lambda: locate(ws, prop, name) if locate is not None else None)  # noqa: E731
                if unit_factor(kind, text) is None:
                    known = ", ".join(KINDS[kind])
                    raise InputError(f"{local_name(ws)}: {kind} unit {str(name)!r} cannot be converted "
                                     f"(kitkb knows {known})", path, where())
                if found.setdefault(kind, text) != text:
                    raise InputError(f"{local_name(ws)}: {kind} unit {text!r} differs from {found[kind]!r} "
                                     "declared by another workstation of the same state", path, where())
    return Units(**{k: found.get(k, getattr(SI, k)) for k in UNIT_PROPS})
