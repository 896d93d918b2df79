"""The closed-world SHACL shapes of an OWL model, derived from it so that model and shapes
cannot drift.

Validation derives them at run time for a model that is not the shipped one; the shipped
kitting model's shapes are checked in (``shapes/kitting-shapes.ttl``, written by the
``shapes`` generator) and read instead.

Scheme (see docs/validation.md):

* One node shape per named class ``C``: ``sh:targetClass C``, ``sh:closed true``. A shape
  carries the constraints whose source is ``C`` itself -- the value type (``sh:class`` /
  ``sh:datatype`` / ``sh:in`` / facets) and functionality of the properties whose domain is
  ``C``, and the cardinality restrictions axiomatised on ``C`` (only where they are stricter
  than what an ancestor's shape already checks). Because ``sh:targetClass`` follows
  ``rdfs:subClassOf`` in the data graph, an individual of ``C`` is also a focus of every
  ancestor's shape, so inherited constraints are checked once, by the ancestor.
* Closedness: ``sh:closed`` ignores ``rdfs:subClassOf``, so each shape lists as allowed
  (``sh:ignoredProperties``) the properties of its ancestors *and descendants*, plus the
  properties without a domain and the RDF/RDFS/OWL bookkeeping properties. The descendants
  must be allowed because an individual of a subclass is a focus of the superclass's shape;
  the shape of an individual's most specific asserted class still rejects a property of a
  sibling class. A stray property is reported by several shapes; the report deduplicates.
* Inverse-functional properties: a node shape targeting the objects of the property with
  ``sh:inversePath`` ``sh:maxCount 1``. ``owl:hasKey``: a SPARQL constraint (two individuals
  of the class with equal key values). Disjoint classes: ``sh:not [ sh:class D ]``.
* Datatypes: an ``owl:oneOf`` enumeration becomes ``sh:in`` listing each value both as a plain
  string and typed ``xsd:NMTOKEN`` (NIST writes ``"degree"^^xsd:NMTOKEN``; NMTOKEN values are
  strings, so it is the same value in OWL 2 -- accepted on purpose). ``xsd:decimal`` (and
  facet restrictions of it such as ``positiveDecimal`` = decimal > 0) accepts ``xsd:decimal``
  or ``xsd:integer`` literals (a Turtle ``1`` is an integer, which is a decimal in XSD);
  ``xsd:nonNegativeInteger`` / ``xsd:positiveInteger`` also accept an ``xsd:integer`` >= 0 / >= 1.

The output is deterministic Turtle (sorted, named property shapes, no blank-node ordering).
"""

from __future__ import annotations

from dataclasses import dataclass, field

from rdflib import OWL, RDF, RDFS, XSD, Graph, Literal, URIRef
from rdflib.term import Node

from kb.core.namespaces import NIST_SOAP, PREFIXES, SH
from kb.model.owl import UNBOUNDED, OwlModel, Restriction

#: Namespace of generated shapes.
SHAPES_NS = "https://w3id.org/kitkb/shapes#"
#: Annotation on generated property shapes: the property's value type in words (for messages).
EXPECTS = URIRef(SHAPES_NS + "expects")

#: Properties every individual may carry whatever its class.
META_PROPERTIES = [RDF.type, RDFS.label, RDFS.comment, RDFS.seeAlso, RDFS.isDefinedBy,
                   OWL.sameAs, OWL.differentFrom, OWL.versionInfo]

_BASE_PREFIXES = {
    "rdf": str(RDF), "rdfs": str(RDFS), "owl": str(OWL), "xsd": str(XSD), "sh": str(SH),
    "kitkbsh": SHAPES_NS,
}


#: Integer types a plain xsd:integer literal may stand for, with their lower bound.
_INTEGER_MIN = {XSD.nonNegativeInteger: 0, XSD.positiveInteger: 1}
#: The facets of a datatype restriction that become SHACL constraints of the same name.
_FACETS = ("minExclusive", "minInclusive", "maxExclusive", "maxInclusive", "pattern", "minLength",
           "maxLength", "length")
_FACET_WORDS = {"minExclusive": ">", "minInclusive": ">=", "maxExclusive": "<", "maxInclusive": "<=",
                "pattern": "matching", "minLength": "of length >=", "maxLength": "of length <=",
                "length": "of length"}
#: Where generated shapes say that a literal typed with a datatype is read as another.
READ_AS = URIRef(SHAPES_NS + "readAs")


@dataclass
class _PropShape:
    path: URIRef
    min: int = 0
    max: int = UNBOUNDED
    value: list[str] = field(default_factory=list)   # Turtle constraint lines
    expects: str = ""


class DerivedShapes:
    """Closed SHACL node shapes for every class of an OWL model graph."""

    def __init__(self, model: Graph | OwlModel, prefixes: dict[str, str] | None = None,
                 header: str = ""):
        self.model = model if isinstance(model, OwlModel) else OwlModel(model)
        self.prefixes = {**_BASE_PREFIXES, **PREFIXES, "nistsoap": NIST_SOAP, **(prefixes or {})}
        self._add_model_prefixes()
        self.header = header

    # --- naming ---------------------------------------------------------------------

    def _add_model_prefixes(self) -> None:
        known = set(self.prefixes.values())
        spaces = sorted({_split(str(t))[0] for t in [*self.model.classes, *self.model.properties]})
        n = 0
        for ns in spaces:
            if ns not in known:
                n += 1
                self.prefixes[f"ns{n}"] = ns
                known.add(ns)

    def qname(self, term: Node) -> str:
        """Turtle spelling of an IRI or literal."""
        if isinstance(term, Literal):
            return _literal(term)
        ns, local = _split(str(term))
        for prefix, space in self.prefixes.items():
            if space == ns and _safe_local(local):
                return f"{prefix}:{local}"
        return f"<{term}>"

    def _shape_name(self, term: URIRef, *suffix: str) -> str:
        prefix, local = self.qname(term).split(":", 1) if not self.qname(term).startswith("<") \
            else ("x", _split(str(term))[1])
        return "kitkbsh:" + "-".join([prefix, local, *suffix])

    # --- constraints ----------------------------------------------------------------

    def _value_constraints(self, ranges: list[Node], kind: str) -> tuple[list[str], str]:
        """Turtle constraint lines for the value type, and the type in words."""
        if kind == "object":
            classes = [r for r in ranges if isinstance(r, URIRef) and r != OWL.Thing]
            if not classes:
                return ["sh:nodeKind sh:BlankNodeOrIRI"], "an individual"
            if len(classes) == 1:
                return [f"sh:class {self.qname(classes[0])}"], f"an individual of {self.qname(classes[0])}"
            alts = " ".join(f"[ sh:class {self.qname(c)} ]" for c in classes)
            words = " or ".join(self.qname(c) for c in classes)
            return [f"sh:or ( {alts} )"], f"an individual of {words}"
        if len(ranges) != 1 or ranges[0] == RDFS.Literal:
            return ["sh:nodeKind sh:Literal"], "a literal"
        return self._datatype_constraints(ranges[0])

    def _datatype_constraints(self, dt: Node) -> tuple[list[str], str]:
        info = self.model.datatype_info(dt)
        if info is not None and info.values is not None:
            values: list[str] = []
            for v in info.values:
                values += [_literal(Literal(str(v))), _literal(Literal(str(v), datatype=XSD.NMTOKEN))]
            words = ", ".join(str(v) for v in info.values)
            return [f"sh:in ( {' '.join(values)} )"], f"one of {words}"
        base, names, facets = self._definition(dt)
        alts, lines, words = self._base_type(base)
        if alts and names:  # a literal typed with the defined datatype is read as its base
            alts += [self.qname(n) for n in names]
        out = ([_alternatives(alts)] if alts else []) + lines
        shown = []
        for facet, value in sorted(facets, key=lambda fv: _facet_order(fv[0])):
            name = _split(str(facet))[1]
            if name in _FACETS:
                out.append(f"sh:{name} {_literal(value)}")
                shown.append(f"{_FACET_WORDS[name]} {value}")
        if shown:  # "xsd:decimal > 0"; the report adds the datatype's name, in the file's prefixes
            words += (" " if words.startswith("xsd:") else ", ") + ", ".join(shown)
        return out, words

    def _definition(self, dt: Node) -> tuple[Node, list[URIRef], list[tuple[Node, Literal]]]:
        """The datatype a definition (``DatatypeDefinition(D DatatypeRestriction(B ...))``,
        possibly of another defined datatype) restricts in the end, the named datatypes on the
        way (``D``, ...) and all their facets."""
        names: list[URIRef] = []
        facets: list[tuple[Node, Literal]] = []
        seen: set[Node] = set()
        info = self.model.datatype_info(dt)
        while info is not None and info.values is None and info.base is not None and dt not in seen:
            seen.add(dt)
            if isinstance(dt, URIRef):
                names.append(dt)
            facets += sorted(info.facets.items())
            dt = info.base
            info = self.model.datatype_info(dt)
        return dt, names, facets

    def _base_type(self, dt: Node) -> tuple[list[str], list[str], str]:
        """(sh:datatype alternatives, other constraint lines, the type in words) of a datatype
        that is not a definition."""
        if dt == XSD.decimal:  # a Turtle 1 is an xsd:integer, which XSD counts as a decimal
            return ["xsd:decimal", "xsd:integer"], [], "xsd:decimal"
        if dt in _INTEGER_MIN:  # a Turtle 3 is an xsd:integer: accept it with the type's bound
            return [self.qname(dt), "xsd:integer"], [f"sh:minInclusive {_INTEGER_MIN[dt]}"], self.qname(dt)
        if _is_xsd(dt):
            return [self.qname(dt)], [], self.qname(dt)
        return [], ["sh:nodeKind sh:Literal"], "a literal"

    def read_as(self) -> dict[URIRef, URIRef]:
        """The model's named datatype definitions whose base is an XSD datatype: a literal typed
        with one is read as that datatype (``kitkbsh:readAs``, see :mod:`kb.shacl.compiler`)."""
        out = {}
        for d in self.model.datatypes:
            base, names, _ = self._definition(d)
            if names and isinstance(base, URIRef) and _is_xsd(base) and base != RDF.langString:
                out[d] = base
        return out

    # --- shapes per class ---------------------------------------------------------------

    def _inherited_bounds(self, c: URIRef, p: URIRef) -> tuple[int, int]:
        """Strongest (min, max) that the shapes of ``c``'s ancestors already check for ``p``."""
        lo, hi = 0, UNBOUNDED
        for a in self.model.ancestors(c):
            for r in self.model.classes[a].restrictions if a in self.model.classes else []:
                if r.prop == p and _plain(self.model, r):
                    lo, hi = max(lo, r.min), min(hi, r.max)
            info = self.model.properties.get(p)
            if info is not None and info.functional and a in info.domains:
                hi = min(hi, 1)
        return lo, hi

    def _property_shapes(self, c: URIRef) -> dict[URIRef, _PropShape]:
        shapes: dict[URIRef, _PropShape] = {}
        for p in self.model.properties_of(c):
            info = self.model.properties[p]
            value, words = self._value_constraints(info.ranges, info.kind)
            shapes[p] = _PropShape(p, max=1 if info.functional else UNBOUNDED, value=value, expects=words)
        lo_hi: dict[URIRef, list[int]] = {}
        for r in self.model.classes[c].restrictions:
            ps = shapes.setdefault(r.prop, _PropShape(r.prop))
            single = r.max <= 1 or (r.prop in self.model.properties and self.model.properties[r.prop].functional)
            if _plain(self.model, r) or (single and r.on is not None and r.min > 0):
                # at most one value, at least one of it qualified: that value is qualified
                b = lo_hi.setdefault(r.prop, [0, UNBOUNDED])
                b[0], b[1] = max(b[0], r.min), min(b[1], r.max)
                if not _plain(self.model, r):
                    lines, words = self._value_constraints([r.on], self._kind(r.prop))  # type: ignore[list-item]
                    ps.value += [line for line in lines if line not in ps.value]  # one check each
                    ps.expects = words
            elif r.on is not None and (r.min > 0 or r.max < UNBOUNDED):
                ps.value.append(self._qualified(r))
            if r.all_values is not None and r.all_values not in self._ranges(r.prop):
                lines = self._value_constraints([r.all_values], self._kind(r.prop))[0]
                ps.value += [line for line in lines if line not in ps.value]
        for p, (lo, hi) in lo_hi.items():
            ilo, ihi = self._inherited_bounds(c, p)
            ps = shapes[p]
            ps.min = lo if lo > ilo else 0
            ps.max = min(ps.max, hi if hi < ihi else UNBOUNDED)
        return shapes

    def _kind(self, p: URIRef) -> str:
        info = self.model.properties.get(p)
        return info.kind if info else "object"

    def _ranges(self, p: URIRef) -> list[Node]:
        info = self.model.properties.get(p)
        return info.ranges if info else []

    def _qualified(self, r: Restriction) -> str:
        inner = " ; ".join(self._value_constraints([r.on], self._kind(r.prop))[0])  # type: ignore[list-item]
        parts = [f"sh:qualifiedValueShape [ {inner} ]"]
        if r.min > 0:
            parts.append(f"sh:qualifiedMinCount {r.min}")
        if r.max < UNBOUNDED:
            parts.append(f"sh:qualifiedMaxCount {r.max}")
        return " ;\n    ".join(parts)

    def _allowed(self, c: URIRef, own: set[URIRef]) -> list[URIRef]:
        allowed = set(META_PROPERTIES) | set(self.model.global_properties()) | self.model.annotation_properties
        for other in [*self.model.ancestors(c), *self.model.descendants(c)]:
            allowed.update(self.model.properties_of(other))
        return sorted(allowed - own)

    def _class_block(self, c: URIRef) -> list[str]:
        name = self._shape_name(c)
        props = self._property_shapes(c)
        info = self.model.classes[c]
        lines = [f"{name} a sh:NodeShape ;", f"    sh:targetClass {self.qname(c)} ;", "    sh:closed true ;"]
        ignored = " ".join(self.qname(p) for p in self._allowed(c, set(props)))
        lines.append(f"    sh:ignoredProperties ( {ignored} ) ;")
        for d in sorted(x for x in info.disjoint if str(x) > str(c)):
            lines.append(f"    sh:not [ sh:class {self.qname(d)} ] ;")
        names = [self._shape_name(c, _split(str(p))[1]) for p in sorted(props)]
        if names:
            lines.append("    sh:property " + " ,\n        ".join(names) + " ;")
        lines[-1] = lines[-1][:-2] + " ."
        blocks = ["\n".join(lines)]
        for p, n in zip(sorted(props), names):
            blocks.append(self._prop_block(n, props[p]))
        for i, key in enumerate(info.keys):
            blocks.append(self._key_block(c, key, i))
        return blocks

    def _prop_block(self, name: str, ps: _PropShape) -> str:
        lines = [f"{name} a sh:PropertyShape ;", f"    sh:path {self.qname(ps.path)} ;"]
        if ps.min > 0:
            lines.append(f"    sh:minCount {ps.min} ;")
        if ps.max < UNBOUNDED:
            lines.append(f"    sh:maxCount {ps.max} ;")
        lines += [f"    {v} ;" for v in ps.value]
        if ps.expects:
            lines.append(f"    kitkbsh:expects {_literal(Literal(ps.expects))} ;")
        lines[-1] = lines[-1][:-2] + " ."
        return "\n".join(lines)

    def _key_block(self, c: URIRef, key: list[URIRef], i: int) -> str:
        # literal-valued key parts first (a serial number singles out one or two individuals;
        # a SKU is shared by thousands): pySHACL joins in the order written, quadratic otherwise
        order = sorted(range(len(key)), key=lambda j: self._is_object_property(key[j]))
        pats = " ".join(f"$this <{key[j]}> ?k{j} . ?other <{key[j]}> ?k{j} ." for j in order)
        query = (f"SELECT $this (?other AS ?value) WHERE {{ {pats} "
                 f"?other <{RDF.type}>/<{RDFS.subClassOf}>* <{c}> . "
                 f"FILTER (?other != $this && STR(?other) < STR($this)) }}")
        names = ", ".join(_split(str(k))[1] for k in key)
        msg = f"same key ({names}) as {{?value}}: owl:hasKey of {_split(str(c))[1]} says they are one individual"
        return "\n".join([
            f"{self._shape_name(c, 'key', str(i))} a sh:NodeShape ;",
            f"    sh:targetClass {self.qname(c)} ;",
            '    kitkbsh:rule "unique-key" ;',
            "    sh:sparql [",
            f"        sh:message {_literal(Literal(msg))} ;",
            f"        sh:select {_literal(Literal(query))} ] ."])

    def _is_object_property(self, p: URIRef) -> bool:
        info = self.model.properties.get(p)
        return info is not None and info.kind == "object"

    def _inverse_functional_block(self, p: URIRef) -> str:
        name = self._shape_name(p, "inverse")
        return "\n".join([
            f"{name} a sh:NodeShape ;",
            f"    sh:targetObjectsOf {self.qname(p)} ;",
            f"    sh:property {name}-path .",
            f"{name}-path a sh:PropertyShape ;",
            f"    sh:path [ sh:inversePath {self.qname(p)} ] ;",
            "    sh:maxCount 1 ."])

    # --- output ---------------------------------------------------------------------

    def turtle(self) -> str:
        """The shapes as Turtle text (same model, same text)."""
        out = [f"@prefix {p}: <{ns}> ." for p, ns in sorted(self.prefixes.items())]
        out.append("")
        if self.header:
            out += [f"# {line}".rstrip() for line in self.header.splitlines()] + [""]
        read_as = self.read_as()
        if read_as:
            out += [f"{self.qname(d)} kitkbsh:readAs {self.qname(b)} ." for d, b in sorted(read_as.items())]
            out.append("")
        for c in sorted(self.model.classes):
            out += [b + "\n" for b in self._class_block(c)]
        for p in sorted(self.model.properties):
            info = self.model.properties[p]
            if info.inverse_functional and info.kind == "object":
                out.append(self._inverse_functional_block(p) + "\n")
        return "\n".join(out)

    def graph(self) -> Graph:
        """The shapes as an rdflib graph."""
        return Graph().parse(data=self.turtle(), format="turtle")


def _plain(model: OwlModel, r: Restriction) -> bool:
    """True when a restriction is a plain count (unqualified, or qualified by the range)."""
    if r.on is None or r.on in (OWL.Thing, RDFS.Literal):
        return True
    info = model.properties.get(r.prop)
    return info is not None and r.on in info.ranges


def _alternatives(datatypes: list[str]) -> str:
    """``sh:datatype D``, or ``sh:or`` of one ``sh:datatype`` each (the commonest first)."""
    if len(datatypes) == 1:
        return f"sh:datatype {datatypes[0]}"
    return "sh:or ( " + " ".join(f"[ sh:datatype {d} ]" for d in datatypes) + " )"


def _facet_order(facet: Node) -> int:
    name = _split(str(facet))[1]
    return _FACETS.index(name) if name in _FACETS else len(_FACETS)


def _is_xsd(dt: Node) -> bool:
    return isinstance(dt, URIRef) and (str(dt).startswith(str(XSD)) or dt == RDF.langString)


def _split(iri: str) -> tuple[str, str]:
    for sep in ("#", "/"):
        if sep in iri:
            head, _, tail = iri.rpartition(sep)
            return head + sep, tail
    return "", iri


def _safe_local(local: str) -> bool:
    return bool(local) and all(ch.isalnum() or ch in "_-" for ch in local) and not local[0].isdigit()


def _literal(lit: Literal) -> str:
    text = str(lit).replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n")
    if lit.datatype is not None and lit.datatype != XSD.string:
        dt = lit.datatype
        dtq = f"xsd:{_split(str(dt))[1]}" if str(dt).startswith(str(XSD)) else f"<{dt}>"
        return f'"{text}"^^{dtq}'
    if lit.language:
        return f'"{text}"@{lit.language}'
    return f'"{text}"'


KITTING_HEADER = """Generated by generators/shapes.py from ontologies/kitting.ttl -- do not edit by hand.
Regenerate: python -m generators.shapes (or KITKB_REGENERATE=1 pytest tests/test_validate_shapes.py)."""

