"""The result type of the SHACL engine (the contract the validation layer reads)."""

from __future__ import annotations

from dataclasses import dataclass

import rdflib


@dataclass(frozen=True)
class ShaclResult:
    """One SHACL validation result, with the fields of ``sh:ValidationResult``.

    ``path`` is the ``sh:resultPath`` (None for node shapes), ``value`` the ``sh:value`` (None
    when the component reports none, e.g. sh:minCount), ``source_shape`` the shape that holds
    the constraint (a blank node of the shapes graph for inline property shapes).
    """

    focus: rdflib.term.Node
    path: rdflib.term.Node | None
    value: rdflib.term.Node | None
    source_shape: rdflib.term.Node
    component: rdflib.URIRef
    severity: rdflib.URIRef
    message: str

    def key(self) -> tuple[object, ...]:
        """(focus, component, source shape, path, value): what equivalence with pySHACL compares."""
        return (self.focus, self.component, self.source_shape, self.path, self.value)
