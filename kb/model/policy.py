"""The domain's execution policy (soap.ttl section 8): what the executor does with a kit the
usable parts cannot finish, read from the soap:ExecutionPolicy individual of the domain files."""

from __future__ import annotations

from rdflib import Graph, Literal
from rdflib.namespace import RDF

from kb.core.errors import InputError
from kb.core.namespaces import SOAP
from kb.model.definitions import Locator, _short


def delivers_partial_kits(graph: Graph, locate: Locator | None = None) -> bool | None:
    """True: a kit that cannot be finished is delivered partial; False: it is left; None: the
    domain declares no partial-kit policy. Two policies that disagree, or a policy without
    its one soap:hasPartialKitPolicy_Delivers boolean, are an InputError at the line."""
    where = locate or (lambda n: (None, None))
    found: dict[bool, object] = {}
    for holder in sorted(graph.subjects(RDF.type, SOAP.ExecutionPolicy), key=str):
        for policy in sorted(graph.objects(holder, SOAP.hasExecutionPolicy_PartialKits), key=str):
            values = list(graph.objects(policy, SOAP.hasPartialKitPolicy_Delivers))
            if len(values) != 1 or not isinstance(values[0], Literal) or not isinstance(values[0].toPython(), bool):
                path, line = where(policy)
                raise InputError(f"partial-kit policy {_short(policy)} needs one boolean "
                                 "soap:hasPartialKitPolicy_Delivers", path, line)
            found.setdefault(bool(values[0].toPython()), holder)
    if len(found) > 1:
        path, line = where(found[False])
        raise InputError(f"the domain declares two partial-kit policies ({_short(found[True])} delivers, "
                         f"{_short(found[False])} leaves): give one", path, line)
    return next(iter(found), None)
