"""Line index of OWL functional syntax and OWL/XML: each axiom's first line, mapped to
the RDF statements it becomes (see :mod:`kb.io.lines`)."""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from urllib.parse import urljoin

from rdflib import Literal, URIRef
from rdflib.namespace import OWL, RDF, RDFS

from kb.io.parsing import expat_parser, make_literal, map_iri, run_expat
from kb.io.lines.index import LineIndex


def index_owl(text: str, fmt: str, base: str, index: LineIndex) -> None:
    """Record the axioms of ``text`` (``fmt`` "ofn" or "owlxml") in ``index``."""
    nodes = _ofn_axioms(text) if fmt == "ofn" else _owx_axioms(text, base)
    for node in nodes:
        _index_axiom(node, index)


@dataclass
class _Node:
    """One parenthesised construct: ``head(args...)`` written at ``line``."""

    head: str
    line: int
    args: list = field(default_factory=list)


_OFN_TOKEN = re.compile(r'''
   (?P<ws>\s+|\#[^\n]*)
  |(?P<iri><[^<>\s]*>)
  |(?P<str>"(?:[^"\\]|\\.)*")
  |(?P<lang>@[A-Za-z]+(?:-[A-Za-z0-9]+)*)
  |(?P<dt>\^\^)
  |(?P<open>\()
  |(?P<close>\))
  |(?P<eq>=)
  |(?P<name>[^\s()<>"=^@]+)
  |(?P<other>.)
''', re.VERBOSE | re.DOTALL)


def _ofn_axioms(text: str) -> list[_Node]:
    """The ontology header and axioms of an OFN document, IRIs expanded."""
    prefixes: dict[str, str] = {}
    stack: list[_Node] = [_Node("", 1)]
    line = 1
    pending: str | None = None
    for m in _OFN_TOKEN.finditer(text):
        kind, value = m.lastgroup, m.group()
        if kind == "ws":
            line += value.count("\n")
            continue
        args = stack[-1].args
        if kind not in ("name", "open"):
            pending = None
        if kind == "open":
            node = _Node(pending or "", line)
            if pending is not None and args and args[-1] == ("kw", pending):
                args.pop()
            pending = None
            args.append(node)
            stack.append(node)
        elif kind == "close":
            if len(stack) > 1:
                done = stack.pop()
                if done.head == "Prefix":
                    _ofn_prefix(done, prefixes)
        elif kind == "name" and (":" not in value or stack[-1].head == "Prefix"):
            pending = value
            args.append(("kw", value))
        elif kind == "name":
            prefix, _, local = value.partition(":")
            args.append(URIRef(map_iri(prefixes.get(prefix, prefix + ":") + local)) if prefix in prefixes else ("kw", value))
        elif kind == "iri":
            args.append(URIRef(map_iri(value[1:-1])))
        elif kind == "str":
            args.append(("lit", _unescape_ofn(value[1:-1]), None, None))
        elif kind == "lang" and args and isinstance(args[-1], tuple) and args[-1][0] == "lit":
            args[-1] = ("lit", args[-1][1], value[1:], None)
        elif kind == "dt":
            args.append(("dt",))
        line += value.count("\n")
    return _flatten_ontology(stack[0])


def _unescape_ofn(s: str) -> str:
    return re.sub(r'\\(["\\])', r"\1", s) if "\\" in s else s


def _ofn_prefix(node: _Node, prefixes: dict[str, str]) -> None:
    # Prefix(name:=<iri>) tokenises as kw "name:" (or IRI-looking junk), eq, IRI
    iri = next((a for a in node.args if isinstance(a, URIRef)), None)
    first = node.args[0] if node.args else None
    name = first[1] if isinstance(first, tuple) and first[0] == "kw" else ""
    if iri is not None:
        prefixes[name.rstrip(":")] = str(iri)


def _flatten_ontology(root: _Node) -> list[_Node]:
    out: list[_Node] = []
    for node in root.args:
        if isinstance(node, _Node) and node.head == "Ontology":
            onto = next((a for a in node.args if isinstance(a, URIRef)), None)
            out.append(_Node("_Ontology", node.line, [onto]))
            for item in node.args:
                if isinstance(item, _Node):
                    item.args = _fold_literals(item.args)
                    if item.head in ("Import", "Annotation"):
                        out.append(_Node("_Onto" + item.head, item.line, [onto] + item.args))
                    else:
                        out.append(item)
    return out


def _fold_literals(args: list) -> list:
    """Turn ("lit", text, lang, None) ("dt",) IRI into rdflib literals, recursively."""
    out: list = []
    i = 0
    while i < len(args):
        a = args[i]
        if isinstance(a, _Node):
            a.args = _fold_literals(a.args)
            out.append(a)
        elif isinstance(a, tuple) and a[0] == "lit":
            dt = None
            if i + 2 < len(args) and args[i + 1] == ("dt",) and isinstance(args[i + 2], URIRef):
                dt = str(args[i + 2])
                i += 2
            out.append(make_literal(a[1], a[2], dt))
        elif not (isinstance(a, tuple) and a[0] in ("kw", "dt")):
            out.append(a)
        i += 1
    return out


# --- OWL/XML -------------------------------------------------------------------------------

def _owx_axioms(text: str, base: str) -> list[_Node]:
    """The axioms of an OWL/XML document as the same node trees as OFN."""
    parser = expat_parser(" ")
    stack: list[_Node] = [_Node("", 1)]
    state = {"base": base, "onto": None}
    prefixes: dict[str, str] = {}
    texts: list[str] = []

    def iri_of(attrs: dict) -> URIRef | None:
        if "IRI" in attrs:
            return URIRef(map_iri(urljoin(state["base"], attrs["IRI"])))
        if "abbreviatedIRI" in attrs:
            p, _, local = attrs["abbreviatedIRI"].partition(":")
            return URIRef(map_iri(prefixes.get(p, p + ":") + local))
        return None

    def start(name: str, attrs: dict) -> None:
        local = name.split(" ")[-1]
        line = parser.CurrentLineNumber
        if local == "Ontology":
            state["base"] = attrs.get("http://www.w3.org/XML/1998/namespace base", state["base"])
            state["onto"] = URIRef(map_iri(attrs["ontologyIRI"])) if "ontologyIRI" in attrs else None
            stack[0].args.append(_Node("_Ontology", line, [state["onto"]]))
            stack.append(_Node("Ontology", line))
            return
        if local == "Prefix":
            prefixes[attrs.get("name", "")] = attrs.get("IRI", "")
        node = _Node(local, line)
        node.args.append(attrs)
        stack.append(node)
        texts.clear()

    def end(name: str) -> None:
        if len(stack) < 2:
            return
        node = stack.pop()
        attrs = node.args.pop(0) if node.args and isinstance(node.args[0], dict) else {}
        parent = stack[-1]
        if node.head == "Ontology":
            return
        if node.head == "Literal":
            lang = attrs.get("http://www.w3.org/XML/1998/namespace lang")
            dt = attrs.get("datatypeIRI")
            parent.args.append(make_literal("".join(texts), lang, dt))
        elif node.head in ("IRI", "AbbreviatedIRI"):
            parent.args.append(URIRef(map_iri(urljoin(state["base"], "".join(texts).strip()))))
        elif (iri := iri_of(attrs)) is not None and not node.args and node.head not in ("Import",):
            parent.args.append(_Node(node.head, node.line, [iri]) if parent.head == "Declaration" else iri)
        elif node.head == "Import":
            stack[0].args.append(_Node("_OntoImport", node.line,
                                       [state["onto"], URIRef(map_iri("".join(texts).strip()))]))
        elif parent.head == "Ontology":
            if node.head == "Annotation":
                stack[0].args.append(_Node("_OntoAnnotation", node.line, [state["onto"]] + node.args))
            elif node.head != "Prefix":
                stack[0].args.append(node)
        else:
            parent.args.append(node)
        texts.clear()

    run_expat(parser, text, start, end, texts.append)
    return [n for n in stack[0].args if isinstance(n, _Node)]


# --- axiom -> statement mapping (shared by OFN and OWL/XML) --------------------------------

_DECLARED_TYPE = {
    "Class": OWL.Class, "NamedIndividual": OWL.NamedIndividual, "ObjectProperty": OWL.ObjectProperty,
    "DataProperty": OWL.DatatypeProperty, "AnnotationProperty": OWL.AnnotationProperty,
    "Datatype": RDFS.Datatype,
}
_CHARACTERISTIC = {
    "FunctionalObjectProperty": OWL.FunctionalProperty, "FunctionalDataProperty": OWL.FunctionalProperty,
    "InverseFunctionalObjectProperty": OWL.InverseFunctionalProperty,
    "TransitiveObjectProperty": OWL.TransitiveProperty, "SymmetricObjectProperty": OWL.SymmetricProperty,
    "AsymmetricObjectProperty": OWL.AsymmetricProperty, "ReflexiveObjectProperty": OWL.ReflexiveProperty,
    "IrreflexiveObjectProperty": OWL.IrreflexiveProperty,
}
_BINARY = {
    "SubClassOf": RDFS.subClassOf, "EquivalentClasses": OWL.equivalentClass, "DisjointClasses": OWL.disjointWith,
    "SubObjectPropertyOf": RDFS.subPropertyOf, "SubDataPropertyOf": RDFS.subPropertyOf,
    "SubAnnotationPropertyOf": RDFS.subPropertyOf,
    "ObjectPropertyDomain": RDFS.domain, "DataPropertyDomain": RDFS.domain, "AnnotationPropertyDomain": RDFS.domain,
    "ObjectPropertyRange": RDFS.range, "DataPropertyRange": RDFS.range, "AnnotationPropertyRange": RDFS.range,
    "InverseObjectProperties": OWL.inverseOf, "EquivalentObjectProperties": OWL.equivalentProperty,
    "EquivalentDataProperties": OWL.equivalentProperty, "DisjointUnion": OWL.disjointUnionOf,
    "DatatypeDefinition": OWL.equivalentClass, "HasKey": OWL.hasKey,
    "SameIndividual": OWL.sameAs, "DifferentIndividuals": OWL.differentFrom,
}
_ASSERTION = ("ObjectPropertyAssertion", "DataPropertyAssertion", "AnnotationAssertion")


def _mentioned(args: list) -> frozenset:
    found: set = set()
    stack = list(args)
    while stack:
        a = stack.pop()
        if isinstance(a, URIRef):
            found.add(a)
        elif isinstance(a, _Node) and a.head != "Annotation":
            stack.extend(a.args)
    return frozenset(found)


def _index_axiom(node: _Node, index: LineIndex) -> None:
    args = [a for a in node.args if not (isinstance(a, _Node) and a.head == "Annotation")]
    if not node.head.startswith("_"):
        index.axioms.append((_mentioned(args), node.line))
    named = [a if isinstance(a, (URIRef, Literal)) else None for a in args]
    head, line = node.head, node.line
    if head == "_Ontology":
        index.add(line, named[0], RDF.type, OWL.Ontology)
    elif head == "_OntoImport" and len(named) >= 2:
        index.add(line, named[0], OWL.imports, named[1])
    elif head == "_OntoAnnotation" and len(named) >= 3:
        index.add(line, named[0], named[1], named[2])
    elif head == "Declaration" and args and isinstance(args[0], _Node):
        inner = args[0]
        target = next((a for a in inner.args if isinstance(a, URIRef)), None)
        index.add(line, target, RDF.type, _DECLARED_TYPE.get(inner.head))
    elif head == "ClassAssertion" and len(args) >= 2:
        index.add(line, named[1], RDF.type, named[0])
    elif head in _ASSERTION and len(args) >= 3:
        index.add(line, named[1], named[0], named[2])
    elif head in _CHARACTERISTIC and args:
        index.add(line, named[0], RDF.type, _CHARACTERISTIC[head])
    elif head in _BINARY and args:
        index.add(line, named[0], _BINARY[head], named[1] if len(args) == 2 else None)
    else:
        first = next((a for a in args if isinstance(a, URIRef)), None)
        index.add(line, first)
