"""kb.shacl.constraints.compare_literal is pySHACL's compare_literal (spelt in kitkb so that a
validation whose shapes pySHACL never runs does not import pySHACL and rdflib's SPARQL engine):
the same answer, or the same exception, on every ordered pair of a sample of literals."""

from __future__ import annotations

import itertools

from pyshacl.rdfutil import compare_literal as pyshacl_compare
from rdflib import Literal, URIRef
from rdflib.namespace import XSD

from kb.shacl.constraints import compare_literal

SAMPLE = [
    Literal(3), Literal(-2), Literal("3", datatype=XSD.integer), Literal("3.0", datatype=XSD.decimal),
    Literal("2.5", datatype=XSD.decimal), Literal("2.5E0", datatype=XSD.double), Literal("NaN", datatype=XSD.double),
    Literal("INF", datatype=XSD.float), Literal("1", datatype=XSD.float), Literal("abc"), Literal("abd"),
    Literal("abc", lang="en"), Literal("abc", datatype=XSD.string), Literal(True), Literal(False),
    Literal("2024-01-02", datatype=XSD.date), Literal("2024-01-03", datatype=XSD.date),
    Literal("2024-01-02T10:00:00", datatype=XSD.dateTime), Literal("2024-01-02T10:00:00Z", datatype=XSD.dateTime),
    Literal("2024-01-02T11:00:00+01:00", datatype=XSD.dateTime), Literal("10:00:00", datatype=XSD.time),
    Literal("09:00:00", datatype=XSD.time), Literal("x", datatype=XSD.integer), Literal("7", datatype=URIRef("urn:t:d")),
    Literal("8", datatype=URIRef("urn:t:d")), Literal("P1D", datatype=XSD.duration),
]


def _outcome(fn, a: Literal, b: Literal) -> object:
    try:
        return fn(a, b)
    except Exception as exc:  # noqa: BLE001 - the exception's type is the answer
        return type(exc).__name__


def test_same_as_pyshacl_on_every_pair() -> None:
    pairs = list(itertools.product(SAMPLE, repeat=2))
    assert len(pairs) == len(SAMPLE) ** 2 == 676
    differ = [(a, b) for a, b in pairs if _outcome(compare_literal, a, b) != _outcome(pyshacl_compare, a, b)]
    assert not differ
