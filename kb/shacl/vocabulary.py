"""The SHACL vocabulary, sorted by what kitkb does with each term on a shape.

A predicate of the ``sh:`` namespace that no engine evaluates is never skipped in silence (a
misspelt ``sh:minCont`` left every value conforming): :func:`on_shape` says why a shape that
carries one is refused. The property terms are those of the W3C SHACL vocabulary
(``http://www.w3.org/ns/shacl#``, core, SPARQL, advanced features and JavaScript extensions).
"""

from __future__ import annotations

import difflib

from rdflib import URIRef

from kb.core.namespaces import SH


def _terms(names: str) -> frozenset[URIRef]:
    return frozenset(SH[n] for n in names.split())


#: Every property of the SHACL vocabulary.
PROPERTIES = _terms("""
    alternativePath and annotationProperty annotationValue annotationVarName ask class closed condition
    conforms construct datatype deactivated declare defaultValue description detail disjoint entailment
    equals expression filterShape flags focusNode group hasValue ignoredProperties in intersection
    inversePath js jsFunctionName jsLibrary jsLibraryURL labelTemplate languageIn lessThan
    lessThanOrEquals maxCount maxExclusive maxInclusive maxLength message minCount minExclusive
    minInclusive minLength name namespace node nodeKind nodeValidator nodes not object oneOrMorePath
    optional or order parameter path pattern predicate prefix prefixes property propertyValidator
    qualifiedMaxCount qualifiedMinCount qualifiedValueShape qualifiedValueShapesDisjoint result
    resultAnnotation resultMessage resultPath resultSeverity returnType rule select severity shapesGraph
    shapesGraphWellFormed sourceConstraint sourceConstraintComponent sourceShape sparql subject
    suggestedShapesGraph target targetClass targetNode targetObjectsOf targetSubjectsOf union uniqueLang
    update validator value xone zeroOrMorePath zeroOrOnePath""")

#: Core constraint parameters kitkb's engine leaves to pySHACL, which evaluates them.
PYSHACL = _terms("""equals disjoint lessThan lessThanOrEquals uniqueLang languageIn qualifiedValueShape
    qualifiedMinCount qualifiedMaxCount qualifiedValueShapesDisjoint""")

#: Terms a shape may carry that are no constraint (descriptions, prefixes, SHACL-SPARQL's
#: parameter declarations: a sh:Parameter is a property shape).
ANNOTATIONS = _terms("""name description order group defaultValue declare prefixes labelTemplate entailment
    shapesGraph suggestedShapesGraph parameter optional""")

#: SHACL Advanced Features and SHACL-JS: neither kitkb nor pySHACL (as kitkb runs it) evaluates them.
ADVANCED = _terms("""condition construct expression filterShape intersection js jsFunctionName jsLibrary
    jsLibraryURL nodes object predicate returnType rule subject target union""")

#: The six node kinds (values of sh:nodeKind).
NODE_KINDS = _terms("BlankNode IRI Literal BlankNodeOrIRI BlankNodeOrLiteral IRIOrLiteral")


def unknown(term: URIRef) -> str:
    """Why ``term`` (of the ``sh:`` namespace, not of SHACL) is refused, with the nearest term."""
    local = str(term)[len(str(SH)):]
    names = [str(t)[len(str(SH)):] for t in PROPERTIES]
    near = difflib.get_close_matches(local, names, n=1, cutoff=0.75)
    hint = f", did you mean sh:{near[0]}?" if near else ""
    return f"sh:{local} is not a SHACL term{hint} (a constraint no engine knows would be skipped)"


def on_shape(term: URIRef, known: frozenset[URIRef] | set[URIRef]) -> str | None:
    """Why a shape carrying the ``sh:`` predicate ``term`` is refused (None: it is not; ``known``
    are the parameters the engine evaluates)."""
    if term in known or term in PYSHACL or term in ANNOTATIONS:
        return None
    local = str(term)[len(str(SH)):]
    if term in ADVANCED:
        return (f"sh:{local} is of SHACL Advanced Features or SHACL-JS, which kitkb does not evaluate "
                "(its constraints would be skipped)")
    if term in PROPERTIES:
        return f"sh:{local} does not belong on a shape (SHACL uses it elsewhere), so it constrains nothing"
    return unknown(term)
