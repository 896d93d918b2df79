"""Line index of RDF/XML: an expat walk in which node elements state subjects and
property elements statements (see :mod:`kb.io.lines`)."""

from __future__ import annotations

from urllib.parse import urljoin

from rdflib import URIRef
from rdflib.namespace import RDF

from kb.io.parsing import expat_parser, make_literal, map_iri, run_expat
from kb.io.lines.index import LineIndex

_RDF = str(RDF)
_XML = "http://www.w3.org/XML/1998/namespace"


def index_rdfxml(text: str, base: str, index: LineIndex) -> None:
    """Walk RDF/XML with expat: node elements state subjects, property elements statements."""
    parser = expat_parser("")
    # frames: ("root",) | ("node", subject) | ("prop", s, p, line, attrs, has_child) | ("skip",)
    stack: list[list] = []
    bases: list[str] = [base]
    langs: list[str | None] = [None]
    texts: list[str] = []

    def resolve(ref: str) -> URIRef:
        return URIRef(map_iri(urljoin(bases[-1], ref)))

    def node_subject(attrs: dict) -> URIRef | None:
        if _RDF + "about" in attrs:
            return resolve(attrs[_RDF + "about"])
        if _RDF + "ID" in attrs:
            return resolve("#" + attrs[_RDF + "ID"])
        return None

    def start(name: str, attrs: dict) -> None:
        line = parser.CurrentLineNumber
        bases.append(urljoin(bases[-1], attrs[_XML + "base"]) if _XML + "base" in attrs else bases[-1])
        langs.append(attrs.get(_XML + "lang", langs[-1]))
        top = stack[-1] if stack else None
        if top is not None and top[0] == "skip":
            stack.append(["skip"])
            return
        if top is None and name == _RDF + "RDF":
            stack.append(["root"])
            return
        if top is None or top[0] in ("root", "prop"):
            s = node_subject(attrs)
            if top is not None and top[0] == "prop":
                top[5] = True
                index.add(top[3], top[1], top[2], s)
            index.add(line, s)
            if name != _RDF + "Description":
                index.add(line, s, RDF.type, URIRef(map_iri(name)))
            for key, value in attrs.items():
                if key == _RDF + "type":
                    index.add(line, s, RDF.type, resolve(value))
                elif not key.startswith(_RDF) and not key.startswith(_XML):
                    index.add(line, s, URIRef(map_iri(key)), make_literal(value, langs[-1], None))
            stack.append(["node", s])
            return
        s = top[1]
        p = URIRef(map_iri(name))
        index.add(line, s, p)
        if _RDF + "resource" in attrs:
            index.add(line, s, p, resolve(attrs[_RDF + "resource"]))
        parse_type = attrs.get(_RDF + "parseType")
        if parse_type == "Resource":
            stack.append(["prop", s, p, line, attrs, True])
            stack.append(["node", None])
            return
        if parse_type is not None:
            stack.append(["prop", s, p, line, attrs, True])
            stack.append(["skip"])
            return
        texts.clear()
        stack.append(["prop", s, p, line, attrs, _RDF + "resource" in attrs or _RDF + "nodeID" in attrs])

    def end(name: str) -> None:
        bases.pop()
        lang = langs.pop()
        if not stack:
            return
        frame = stack.pop()
        if frame[0] == "node" and stack and stack[-1][0] == "prop" and stack[-1][4].get(_RDF + "parseType") == "Resource":
            stack.pop()
        if frame[0] == "skip" and stack and stack[-1][0] == "prop" and stack[-1][4].get(_RDF + "parseType"):
            stack.pop()
        if frame[0] == "prop" and not frame[5]:
            dt = frame[4].get(_RDF + "datatype")
            lit = make_literal("".join(texts), None if dt else lang, str(resolve(dt)) if dt else None)
            index.add(frame[3], frame[1], frame[2], lit)
        texts.clear()

    run_expat(parser, text, start, end, texts.append)
