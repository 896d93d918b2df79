"""Which vocabularies a file is written in: what a command says when it understood nothing.

A command whose input yields nothing it reads (no placed object, no predicate definition, no
kit, no model) exits 2 saying what it looked for (:func:`not_understood`): the namespaces the
file's classes and properties are in, the terms of NIST's 2012 namespace kitkb's model lacks,
and the namespaces kitkb reads.
"""

from __future__ import annotations

from collections import Counter
from pathlib import Path
from typing import Iterable

from rdflib import URIRef
from rdflib.namespace import OWL, RDF, RDFS, XSD

from kb.core import namespaces as ns
from kb.core.errors import InputError
from kb.io.loader import KnowledgeBase

_STANDARD = (str(RDF), str(RDFS), str(OWL), str(XSD), "http://www.w3.org/XML/1998/namespace")
_OURS = (str(ns.KTW), str(ns.SOAP), str(ns.KD))


def namespace_of(iri: str) -> str:
    """``iri`` up to its last ``#`` or ``/`` (the whole IRI if it has neither)."""
    for sep in ("#", "/"):
        if sep in iri:
            return iri.rpartition(sep)[0] + sep
    return iri


def terms_used(triples: Iterable[tuple]) -> Counter:
    """How often each class (object of ``rdf:type``) and property is used in ``triples``."""
    used: Counter = Counter()
    for _s, p, o in triples:
        if p == RDF.type:
            if isinstance(o, URIRef):
                used[str(o)] += 1
        else:
            used[str(p)] += 1
    return used


def foreign(triples: Iterable[tuple]) -> tuple[list[str], list[str]]:
    """(namespaces of the classes and properties kitkb does not read, most used first; local
    names of the terms of NIST's 2012 namespace that have no counterpart in kitkb's model)."""
    spaces: Counter = Counter()
    unmapped: list[str] = []
    for iri, n in terms_used(triples).most_common():
        if iri.startswith(ns.NIST_KTW_2012):
            unmapped.append(iri[len(ns.NIST_KTW_2012):])
        elif not iri.startswith(_STANDARD + _OURS):
            spaces[namespace_of(iri)] += n
    return [space for space, _ in spaces.most_common()], unmapped


def read_namespaces() -> str:
    """The namespaces kitkb reads, for a message."""
    return (f"kitkb reads <{ns.KTW}> (NIST's <{ns.NIST_KTW}> and <{ns.NIST_KTW_2012}> mapped onto it), "
            f"<{ns.SOAP}> and <{ns.KD}>")


def explain(triples: Iterable[tuple]) -> str:
    """What ``triples`` are written in, against what kitkb reads (one clause of a message)."""
    triples = list(triples)
    spaces, unmapped = foreign(triples)
    if not spaces and not unmapped:
        if any(iri.startswith(_OURS) for iri in terms_used(triples)):
            return "the classes and properties it uses are all kitkb's"
        return "it uses no class or property of a kitting vocabulary (" + read_namespaces() + ")"
    said = []
    if spaces:
        named = ", ".join(f"<{s}>" + (" (NIST's SOAP, not kitkb's)" if s == ns.NIST_SOAP else "")
                          for s in spaces[:4])
        more = f" and {len(spaces) - 4} more" if len(spaces) > 4 else ""
        said.append(f"its classes and properties are in {named}{more}")
    if unmapped:
        more = f" and {len(unmapped) - 5} more" if len(unmapped) > 5 else ""
        said.append(f"its terms of NIST's 2012 namespace without counterpart in kitkb's model are "
                    f"{', '.join(unmapped[:5])}{more}")
    return "; ".join(said) + "; " + read_namespaces()


def not_understood(what: str, triples: Iterable[tuple], path: str | Path | None = None,
                   line: int | None = None) -> InputError:
    """The InputError (exit 2) of an input in which nothing was understood: ``what`` (what was
    looked for and not found), then :func:`explain`."""
    return InputError(f"{what}: {explain(triples)}", None if path is None else str(path), line)


def no_model(kb: KnowledgeBase) -> InputError:
    """The InputError of files that declare no class and import no model kitkb found, at the
    first import that did not resolve (each named at its line), with what the files are
    written in."""
    unresolved = kb.unresolved_imports
    if unresolved:
        where = ", ".join(f"<{d.focus}> ({d.file}:{d.line})" if d.line else f"<{d.focus}> ({d.file})"
                          for d in unresolved[:3])
        said = (f"no model to validate against: the files declare no classes, and their import of {where} did "
                f"not resolve (name the model file on the command line, put it beside the importing file, or "
                f"import <{ns.KITTING_ONTOLOGY}>)")
    else:
        said = (f"no model to validate against: the files declare no classes and import no model (add "
                f"owl:imports <{ns.KITTING_ONTOLOGY}>)")
    triples = [t for s in kb.sources for t in s.triples()]
    spaces, unmapped = foreign(triples)
    if spaces or unmapped:
        said += f"; {explain(triples)}"
    first = unresolved[0] if unresolved else None
    return InputError(said, first.file if first else None, first.line if first else None)
