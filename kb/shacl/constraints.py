"""Constraint components: each checks the value nodes of one focus node and yields results.

Each constraint sees all (focus, value nodes) pairs of a shape at once and appends its
results to a list, as the tuple ``(focus, path, value, source_shape, component, severity,
message)`` with focus/value as keys; :mod:`kb.shacl.engine` turns them into
:class:`~kb.shacl.result.ShaclResult`. Each component follows pySHACL 0.40's reading of the
SHACL spec (one result per value node and per rule value, sh:minCount/sh:hasValue without a
value, sh:closed with the offending predicate as path).
"""

from __future__ import annotations

import re
from functools import lru_cache
from datetime import date, datetime, time
from decimal import Decimal
from typing import Any

from rdflib import Literal, URIRef
from rdflib.term import Node

from kb.core.namespaces import SH
from kb.shacl.index import RDF_TYPE
from kb.shacl.shape import Constraint, Context, Hit, Pairs, PerValue, Shape
from kb.shacl.terms import XSD_NS, XSD_STRING, key_of, literal_datatype, split_literal, to_node


RDF_LANGSTRING = "http://www.w3.org/1999/02/22-rdf-syntax-ns#langString"
RDFS_LITERAL = "http://www.w3.org/2000/01/rdf-schema#Literal"
RDFS_DATATYPE = "http://www.w3.org/2000/01/rdf-schema#Datatype"
_DECIMAL = re.compile(r"[+-]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)")
_INTEGER = re.compile(r"[+-]?[0-9]+")
_NUMBER_KEY = re.compile(
    r'"([+-]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+))"\^\^<http://www\.w3\.org/2001/XMLSchema#decimal>'
    r'|"([+-]?[0-9]+)"\^\^<http://www\.w3\.org/2001/XMLSchema#integer>'
)
_VALUE_TYPES: dict[str, type | tuple[type, ...]] = {
    XSD_STRING: (str, bytes),
    RDF_LANGSTRING: (str, bytes),
    XSD_NS + "integer": int,
    XSD_NS + "float": float,
    XSD_NS + "decimal": Decimal,
    XSD_NS + "boolean": bool,
    XSD_NS + "date": date,
    XSD_NS + "time": time,
    XSD_NS + "dateTime": datetime,
}


class ClassC(PerValue):
    component = SH.ClassConstraintComponent

    def __init__(self, shape: Shape, cls: str) -> None:
        super().__init__(shape)
        self.cls = cls
        self._accepted: dict[str, bool] = {}  # rdf:type value -> is it cls or a subclass (one run)

    def check(self, ctx: Context, pairs: Pairs, out: list[Hit]) -> None:
        get, cls, supers = ctx.index.spo.get, self.cls, ctx.index.superclasses
        accepted: dict[str, bool] = {}  # rdf:type value -> is it cls or a subclass of cls
        for focus, values in pairs:
            for v in values:
                if v[0] != '"':
                    preds = get(v)
                    found = False
                    for t in (preds.get(RDF_TYPE, ()) if preds else ()):
                        yes = accepted.get(t)
                        if yes is None:
                            yes = accepted[t] = t == cls or cls in supers(t)
                        if yes:
                            found = True
                            break
                    if found:
                        continue
                out.append(self.hit(focus, v))

    def ok(self, ctx: Context, value: str) -> bool:
        if value[0] == '"':
            return False
        accepted = self._accepted
        for t in ctx.index.objects(value, RDF_TYPE):
            yes = accepted.get(t)
            if yes is None:
                yes = accepted[t] = t == self.cls or self.cls in ctx.index.superclasses(t)
            if yes:
                return True
        return False

    def generic(self, value: str | None) -> str:
        return f"Value does not have class {self.cls[1:-1]}"


def datatype_matches(key: str, rule: str, rdf11_strings: bool) -> bool:
    """pySHACL's sh:datatype test on a value key (ill-typed literals do not match)."""
    if key[0] != '"':
        return False
    end = key.rindex('"')
    rest = key[end + 1 :]
    if rest.startswith("^^<"):
        dt: str | None = rest[3:-1]
        lang = None
    elif rest.startswith("@"):
        dt, lang = None, rest[1:]
    else:  # a plain literal, as rdflib's parsers read "abc"
        dt, lang = None, None
    if dt == rule:
        lex = key[1:end]
        if rule == XSD_STRING:
            return True
        if rule == XSD_NS + "decimal" and _DECIMAL.fullmatch(lex):
            return True
        if rule == XSD_NS + "integer" and _INTEGER.fullmatch(lex):
            return True
        lit = to_node(key)
        assert isinstance(lit, Literal)
        if lit.ill_typed is True:
            return False
        wanted = _VALUE_TYPES.get(rule)
        return True if wanted is None else isinstance(lit.value, wanted)
    if rule == RDFS_LITERAL:
        return True
    if rule == RDFS_DATATYPE and dt:
        return True
    if dt is None and lang is None and rule == XSD_STRING:
        return True
    if rule == RDF_LANGSTRING and lang:
        return True
    return False


_FAST_KEYS = {
    XSD_NS + "decimal": r'"[+-]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)"\^\^<http://www\.w3\.org/2001/XMLSchema#decimal>',
    XSD_NS + "integer": r'"[+-]?[0-9]+"\^\^<http://www\.w3\.org/2001/XMLSchema#integer>',
    XSD_STRING: r'"(?:[^"\\]|\\.)*"(?:\^\^<http://www\.w3\.org/2001/XMLSchema#string>)?',
}


def as_base(key: str, read_as: dict[str, str]) -> str:
    """The key of a literal of a datatype the shapes graph reads as another (``D
    kitkbsh:readAs xsd:decimal``: ``"7"^^D`` -> ``"7"^^xsd:decimal``); other keys unchanged."""
    if not read_as or key[0] != '"':
        return key
    dt = literal_datatype(key)
    base = read_as.get(dt) if dt is not None else None
    if base is None:
        return key
    return key[: key.rindex('"') + 1] + f"^^<{base}>"


class DatatypeC(PerValue):
    component = SH.DatatypeConstraintComponent

    def __init__(self, shape: Shape, datatype: str, read_as: dict[str, str] | None = None) -> None:
        super().__init__(shape)
        self.datatype = datatype[1:-1]
        fast = _FAST_KEYS.get(self.datatype)
        self.fast = re.compile(fast).fullmatch if fast else None
        #: Datatypes read as XSD ones (``kitkbsh:readAs``): ``"7"^^D`` is ``"7"^^xsd:decimal``,
        #: so sh:datatype xsd:decimal accepts it and ``"abc"^^D`` is ill-formed.
        self.read_as = read_as or {}
        #: The datatype whose lexical space a literal of ``self.datatype`` must be in, else None.
        self.base = self.read_as.get(self.datatype)

    def check(self, ctx: Context, pairs: Pairs, out: list[Hit]) -> None:
        fast, ok = self.fast, self.ok
        for focus, values in pairs:
            for v in values:
                if fast is not None and fast(v):
                    continue
                if not ok(ctx, v):
                    out.append(self.hit(focus, v))

    def ok(self, ctx: Context, value: str) -> bool:
        if datatype_matches(value, self.datatype, ctx.rdf11_strings):
            if self.base is None:
                return True
            return datatype_matches(as_base(value, self.read_as), self.base, ctx.rdf11_strings)
        if self.read_as:
            read = as_base(value, self.read_as)
            return read != value and datatype_matches(read, self.datatype, ctx.rdf11_strings)
        return False

    def generic(self, value: str | None) -> str:
        return f"Value is not Literal with datatype {self.datatype}"


_KINDS = {
    "_": {SH.BlankNode, SH.BlankNodeOrLiteral, SH.BlankNodeOrIRI},
    '"': {SH.Literal, SH.BlankNodeOrLiteral, SH.IRIOrLiteral},
    "<": {SH.IRI, SH.IRIOrLiteral, SH.BlankNodeOrIRI},
}


class NodeKindC(PerValue):
    component = SH.NodeKindConstraintComponent

    def __init__(self, shape: Shape, kind: Node) -> None:
        super().__init__(shape)
        self.kind = kind

    def ok(self, ctx: Context, value: str) -> bool:
        return self.kind in _KINDS[value[0]]

    def generic(self, value: str | None) -> str:
        return f"Value is not of Node Kind {self.kind}"


@lru_cache(maxsize=100_000)
def normalized(key: str) -> str:
    """The key of a literal as rdflib reads it (rdflib normalises ``"01"^^xsd:integer`` to
    ``"1"``); pyoxigraph keeps the lexical form, so sh:in/sh:hasValue compare both spellings."""
    if key[0] != '"':
        return key
    return key_of(to_node(key))


class InC(PerValue):
    component = SH.InConstraintComponent

    def __init__(self, shape: Shape, members: list[str]) -> None:
        super().__init__(shape)
        self.members = set(members)

    def ok(self, ctx: Context, value: str) -> bool:
        return value in self.members or (ctx.rdf11_strings and normalized(value) in self.members)

    def generic(self, value: str | None) -> str:
        return f"Value {value} not in list {sorted(self.members)}"


class RangeC(PerValue):
    """sh:minExclusive, sh:minInclusive, sh:maxExclusive, sh:maxInclusive (pySHACL comparison)."""

    TESTS = {
        "minExclusive": lambda c: c > 0,
        "minInclusive": lambda c: c >= 0,
        "maxExclusive": lambda c: c < 0,
        "maxInclusive": lambda c: c <= 0,
    }

    def __init__(self, shape: Shape, which: str, bound: Node, read_as: dict[str, str] | None = None) -> None:
        super().__init__(shape)
        self.component = SH[which[0].upper() + which[1:] + "ConstraintComponent"]
        self.which = which
        self.bound = bound
        self.test = self.TESTS[which]
        self._memo: dict[str, bool] = {}
        #: Datatypes read as others (``kitkbsh:readAs``): compared by the other's value.
        self.read_as = read_as or {}

    def ok(self, ctx: Context, value: str) -> bool:
        if value[0] != '"':
            return False
        known = self._memo.get(value)
        if known is None:
            known = self._memo[value] = self._compare(value)
        return known

    def _compare(self, value: str) -> bool:
        bound = self.bound
        if not isinstance(bound, Literal):
            return False
        bv = bound.value
        value = as_base(value, self.read_as)
        if isinstance(bv, (int, Decimal)) and not isinstance(bv, bool) and not bound.ill_typed:
            m = _NUMBER_KEY.fullmatch(value)
            if m:  # a well-formed xsd:decimal/xsd:integer: rdflib compares the Python values
                d = Decimal(m.group(1) or m.group(2))
                return bool(self.test((d > bv) - (d < bv)))
        v = to_node(value)
        assert isinstance(v, Literal)
        if v.value is None and v.datatype is not None and not str(v.datatype).startswith(XSD_NS) \
                and str(v.datatype) != RDF_LANGSTRING:
            # a datatype neither XSD's nor read as one: SPARQL's < is a type error, so the
            # value is not within the bound (rdflib would order it by its datatype's IRI)
            return False
        if isinstance(bound.value, str) != isinstance(v.value, str):
            return False
        try:
            return bool(self.test(compare_literal(v, bound)))
        except (TypeError, NotImplementedError, ArithmeticError):  # "NaN"^^xsd:decimal: decimal.InvalidOperation
            return False

    def generic(self, value: str | None) -> str:
        return f"Value is not within {self.which} {self.bound}"


def compare_literal(l1: Literal, l2: Literal) -> int:
    """pySHACL's ``pyshacl.rdfutil.compare_literal`` (0.40), spelt here: 0 when ``l1`` equals
    ``l2``, 1 when it is greater, else -1; rdflib's comparisons raise where they do (importing
    pySHACL for it imports rdflib's SPARQL engine too, 0.1 s of a run whose shapes pySHACL never
    runs). tests/test_shacl_compare.py checks it against pySHACL's on every pair of a sample."""
    if l1.eq(l2):
        return 0
    if l1.value.__class__ in (datetime, time):  # not rdflib's total order of the unorderable
        if l1.value == l2.value:
            return 0
        if l1.value > l2.value:
            return 1
    elif l1 > l2:
        return 1
    return -1


def value_string(key: str) -> str | None:
    """pySHACL's string form of a value node (None for blank nodes)."""
    if key[0] == "<":
        return key[1:-1]
    if key[0] == "_":
        return None
    return split_literal(key)[0]


class LengthC(PerValue):
    def __init__(self, shape: Shape, which: str, limit: int) -> None:
        super().__init__(shape)
        self.which = which
        self.limit = limit
        self.component = SH.MinLengthConstraintComponent if which == "min" else SH.MaxLengthConstraintComponent

    def ok(self, ctx: Context, value: str) -> bool:
        if self.which == "min" and self.limit == 0:
            return True
        text = value_string(value)
        if text is None:
            return False
        return len(text) >= self.limit if self.which == "min" else len(text) <= self.limit

    def generic(self, value: str | None) -> str:
        sign = ">=" if self.which == "min" else "<="
        return f"String length not {sign} {self.limit}"


class PatternC(PerValue):
    component = SH.PatternConstraintComponent

    def __init__(self, shape: Shape, pattern: str, flags: str | None) -> None:
        super().__init__(shape)
        f = 0
        if flags:
            f |= re.I if "i" in flags.lower() else 0
            f |= re.M if "m" in flags.lower() else 0
        self.pattern = pattern
        self.regex = re.compile(pattern, f)

    def ok(self, ctx: Context, value: str) -> bool:
        text = value_string(value)
        return text is not None and self.regex.search(text) is not None

    def generic(self, value: str | None) -> str:
        return f"Value does not match pattern '{self.pattern}'"


class CountC(Constraint):
    def __init__(self, shape: Shape, which: str, limit: int) -> None:
        super().__init__(shape)
        self.which = which
        self.limit = limit
        self.component = SH.MinCountConstraintComponent if which == "min" else SH.MaxCountConstraintComponent

    def check(self, ctx: Context, pairs: Pairs, out: list[Hit]) -> None:
        limit = self.limit
        if self.which == "min":
            out.extend(self.hit(f, None) for f, values in pairs if len(values) < limit)
        else:
            out.extend(self.hit(f, None) for f, values in pairs if len(values) > limit)

    def generic(self, value: str | None) -> str:
        word = "Less" if self.which == "min" else "More"
        return f"{word} than {self.limit} values on {self.shape.path_text}"


class HasValueC(Constraint):
    component = SH.HasValueConstraintComponent

    def __init__(self, shape: Shape, wanted: str) -> None:
        super().__init__(shape)
        self.wanted = wanted

    def check(self, ctx: Context, pairs: Pairs, out: list[Hit]) -> None:
        wanted = self.wanted
        for f, values in pairs:
            if wanted in values:
                continue
            if ctx.rdf11_strings and any(normalized(v) == wanted for v in values if v[0] == '"'):
                continue
            out.append(self.hit(f, None))

    def generic(self, value: str | None) -> str:
        return f"Value node does not have value {self.wanted}"


class ClosedC(Constraint):
    component = SH.ClosedConstraintComponent
    _ALWAYS_IGNORE = ("<http://www.w3.org/1999/02/22-rdf-syntax-ns#type>",
                      "<http://www.w3.org/2000/01/rdf-schema#Resource>")

    def __init__(self, shape: Shape, allowed: set[str]) -> None:
        super().__init__(shape)
        self.allowed = allowed

    def check(self, ctx: Context, pairs: Pairs, out: list[Hit]) -> None:
        spo, allowed = ctx.index.spo, self.allowed
        for focus, values in pairs:
            for v in values:
                preds = spo.get(v)
                if not preds or allowed.issuperset(preds):
                    continue
                for p, objs in preds.items():
                    if p in allowed:
                        continue
                    for o in objs:
                        if (p, o) != self._ALWAYS_IGNORE:
                            out.append(self.hit(focus, o, path=to_node(p)))

    def generic(self, value: str | None) -> str:
        return f"Node is closed. It cannot have value: {value}"


class PropertyC(Constraint):
    """sh:property: the property shape is validated with each value node as focus."""

    component = SH.PropertyConstraintComponent

    def __init__(self, shape: Shape, prop: Shape) -> None:
        super().__init__(shape)
        self.prop = prop

    def check(self, ctx: Context, pairs: Pairs, out: list[Hit]) -> None:
        self.prop.validate(ctx, [v for _, values in pairs for v in values], out)


def _distinct_values(pairs: Pairs) -> list[str]:
    return list(dict.fromkeys(v for _, values in pairs for v in values))


class NodeC(PerValue):
    component = SH.NodeConstraintComponent

    def __init__(self, shape: Shape, other: Shape) -> None:
        super().__init__(shape)
        self.other = other

    def check(self, ctx: Context, pairs: Pairs, out: list[Hit]) -> None:
        failing = self.other.failing(ctx, _distinct_values(pairs))
        out.extend(self.hit(f, v) for f, values in pairs for v in values if v in failing)

    def ok(self, ctx: Context, value: str) -> bool:
        return self.other.conforms(ctx, value)

    def generic(self, value: str | None) -> str:
        return f"Value does not conform to Shape {self.other.node}"


class NotC(PerValue):
    component = SH.NotConstraintComponent

    def __init__(self, shape: Shape, other: Shape) -> None:
        super().__init__(shape)
        self.other = other

    def check(self, ctx: Context, pairs: Pairs, out: list[Hit]) -> None:
        failing = self.other.failing(ctx, _distinct_values(pairs))
        out.extend(self.hit(f, v) for f, values in pairs for v in values if v not in failing)

    def ok(self, ctx: Context, value: str) -> bool:
        return not self.other.conforms(ctx, value)

    def generic(self, value: str | None) -> str:
        return f"Node {value} conforms to shape {self.other.node}"


class ListC(PerValue):
    """sh:and, sh:or, sh:xone over a list of shapes."""

    def __init__(self, shape: Shape, which: str, members: list[Shape]) -> None:
        super().__init__(shape)
        self.which = which
        self.members = members
        self.component = SH[which[0].upper() + which[1:] + "ConstraintComponent"]

    def check(self, ctx: Context, pairs: Pairs, out: list[Hit]) -> None:
        values = _distinct_values(pairs)
        if self.which == "xone":
            fails = [m.failing(ctx, values) for m in self.members]
            bad = {v for v in values if sum(1 for f in fails if v not in f) != 1}
        elif self.which == "or":  # each member judges only the values no earlier one passed
            rest = values
            for m in self.members:
                if not rest:
                    break
                failed = m.failing(ctx, rest)
                rest = [v for v in rest if v in failed]
            bad = set(rest)
        else:  # and: each member judges only the values every earlier one passed
            bad = set()
            rest = values
            for m in self.members:
                if not rest:
                    break
                failed = m.failing(ctx, rest)
                bad |= failed
                rest = [v for v in rest if v not in failed]
        out.extend(self.hit(f, v) for f, vals in pairs for v in vals if v in bad)

    def ok(self, ctx: Context, value: str) -> bool:
        if self.which == "and":
            return all(m.conforms(ctx, value) for m in self.members)
        if self.which == "or":
            return any(m.conforms(ctx, value) for m in self.members)
        return sum(1 for m in self.members if m.conforms(ctx, value)) == 1

    def generic(self, value: str | None) -> str:
        return f"Node {value} does not conform to sh:{self.which} of its shapes"


def literal_int(node: Any) -> int | None:
    """The integer value of a count/length parameter (None when it is not an integer literal)."""
    if isinstance(node, Literal) and isinstance(node.value, int) and not isinstance(node.value, bool):
        return int(node.value)
    return None
