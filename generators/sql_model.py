"""The relational model of the ontologies: which tables and columns hold which classes and properties.

This is the typed layer between the ontology and the writers (:mod:`generators.sql`
renders it as SQLAlchemy metadata and DDL, :mod:`generators.accessors` as a Python module);
it reads the ontology through :class:`kb.model.owl.OwlModel`.
The mapping (see docs/database.md):

* one table per named class (joined-table inheritance): a class table holds the class's
  own properties, and its ``id`` is a foreign key to the table of its parent class; root
  classes point at the table ``kitkb_thing`` that gives every individual its IRI;
* a functional property (or one restricted to at most one value on its domain class) is
  a column of its domain's table: a foreign key to the range class's table for an object
  property whose range is a model class, an IRI column for any other object property, a
  typed column for a datatype property (CHECK constraints from the datatype's facets or
  enumeration);
* any other property is a link table ``(subject_id, value)``;
* a column is NOT NULL when the domain class requires at least one value.
"""

from __future__ import annotations

import hashlib
import json
import keyword
import re
from dataclasses import asdict, dataclass, field, replace
from functools import lru_cache
from pathlib import Path
from typing import Iterable, Sequence

from rdflib import RDFS, XSD, Graph, URIRef
from rdflib.term import Node

from kb.core.errors import InputError
from kb.core.namespaces import KTW, SOAP
from kb.core.resources import model_files
from kb.model.owl import UNBOUNDED, OwlModel

#: Namespaces whose classes and properties become tables and columns, with the table prefix.
MODEL_NAMESPACES: dict[str, str] = {str(KTW): "ktw", str(SOAP): "soap"}

#: Name of the table every individual has a row in.
THING_TABLE = "kitkb_thing"

#: Longest identifier the generated schema uses (PostgreSQL allows 63, MySQL 64).
MAX_IDENTIFIER = 60

_TEXT_TYPES = {"string", "normalizedString", "token", "NMTOKEN", "Name", "NCName", "language",
               "anyURI", "NMTOKENS", "ID", "IDREF", "ENTITY"}
_INTEGER_CHECKS: dict[str, tuple[str, str] | None] = {
    "integer": None, "int": None, "long": None, "short": None, "byte": None,
    "nonNegativeInteger": ("ge", "0"), "positiveInteger": ("gt", "0"),
    "nonPositiveInteger": ("le", "0"), "negativeInteger": ("lt", "0"),
    "unsignedLong": ("ge", "0"), "unsignedInt": ("ge", "0"), "unsignedShort": ("ge", "0"),
    "unsignedByte": ("ge", "0"),
}
_FACETS = {"minExclusive": "gt", "minInclusive": "ge", "maxExclusive": "lt", "maxInclusive": "le"}


@dataclass(frozen=True)
class ValueType:
    """The SQL side of a datatype: a storage kind, CHECK facets and the RDF datatype to write."""

    kind: str  # text | boolean | integer | decimal | float | datetime | date | iri
    checks: tuple[tuple[str, str], ...] = ()  # ("gt", "0"), ("ge", "0"), ...
    enum: tuple[str, ...] = ()  # allowed values of an enumeration
    datatype: str | None = None  # datatype IRI of canonical literals (None: plain string)
    range_iri: str | None = None  # the declared range (datatype or class IRI)


@dataclass(frozen=True)
class ColumnSpec:
    """A single-valued property stored as a column of its domain class's table."""

    name: str
    attr: str  # Python attribute name in the accessors module
    property_iri: str
    kind: str  # "data" | "object" (foreign key) | "iri" (object value outside the model)
    value: ValueType
    target: str | None = None  # referenced table of an object column
    nullable: bool = True
    unique: bool = False
    rel: str = ""  # attribute of the related object (object columns)


@dataclass(frozen=True)
class LinkSpec:
    """A property with several values: a link table ``(subject_id, value)``."""

    name: str
    attr: str
    property_iri: str
    kind: str  # "data" | "object" | "iri"
    domain: str  # table of the subjects
    value: ValueType
    target: str | None = None  # table of the objects (kind "object")
    required: bool = False  # the domain class requires at least one value (not enforced in SQL)


@dataclass(frozen=True)
class TableSpec:
    """One class and its table."""

    name: str
    class_iri: str
    class_name: str  # Python class name
    parent: str  # table of the parent class (THING_TABLE for roots)
    columns: tuple[ColumnSpec, ...] = ()
    comment: str = ""


@dataclass(frozen=True)
class Schema:
    """The whole relational model, in a deterministic order (parents before children)."""

    tables: tuple[TableSpec, ...]
    links: tuple[LinkSpec, ...]
    ontologies: tuple[tuple[str, str], ...] = ()  # (ontology IRI, owl:versionInfo)
    version: str = field(default="")

    def table(self, name: str) -> TableSpec:
        """The table named ``name``."""
        for t in self.tables:
            if t.name == name:
                return t
        raise KeyError(name)

    def fingerprint(self) -> str:
        """A short hash of the structure (comments left out): equal fingerprints mean compatible databases."""
        tables = [{k: v for k, v in asdict(t).items() if k != "comment"} for t in self.tables]
        body = json.dumps([tables, [asdict(link) for link in self.links]], sort_keys=True)
        return hashlib.sha256(body.encode()).hexdigest()[:16]


# --- names -------------------------------------------------------------------------------

def snake(name: str) -> str:
    """``EndEffectorChangingStation`` -> ``end_effector_changing_station``."""
    s = re.sub(r"(?<=[a-z0-9])(?=[A-Z])|(?<=[A-Z])(?=[A-Z][a-z])", "_", name)
    s = re.sub(r"[^0-9a-zA-Z]+", "_", s).strip("_").lower()
    return s or "x"


def shorten(name: str, limit: int = MAX_IDENTIFIER) -> str:
    """``name`` cut to ``limit`` characters with a stable hash suffix when too long."""
    if len(name) <= limit:
        return name
    digest = hashlib.sha1(name.encode()).hexdigest()[:8]
    return f"{name[: limit - 9].rstrip('_')}_{digest}"


def split_iri(iri: str) -> tuple[str, str]:
    """(namespace, local name) of an IRI, split after the last ``#`` or ``/``."""
    cut = max(iri.rfind("#"), iri.rfind("/"))
    return iri[: cut + 1], iri[cut + 1:]


def _attribute(prop_local: str, domain_local: str | None) -> str:
    """The attribute part of ``has<Domain>_<Attribute>``, else the whole local name."""
    if domain_local and prop_local.startswith(f"has{domain_local}_"):
        return prop_local[len(domain_local) + 4:]
    return prop_local


def column_info(spec: ColumnSpec | LinkSpec) -> dict[str, object]:
    """What kb.world.database needs to know about a column: property IRI, kind and value type."""
    info: dict[str, object] = {"iri": spec.property_iri, "kind": spec.kind}
    if spec.kind == "data":
        info["value"] = spec.value.kind
        if spec.value.datatype:
            info["datatype"] = spec.value.datatype
    return info


# --- reading the ontology (through kb.model.owl) ------------------------------------------

def _in_model(term: object) -> bool:
    return isinstance(term, URIRef) and split_iri(str(term))[0] in MODEL_NAMESPACES


def _model_classes(model: OwlModel) -> list[URIRef]:
    return sorted(c for c in model.classes if _in_model(c))


def _parent(model: OwlModel, cls: URIRef) -> URIRef | None:
    """The first (sorted) model class ``cls`` is stated a subclass of."""
    parents = sorted(p for p in model.classes[cls].parents if _in_model(p) and p in model.classes)
    return parents[0] if parents else None


def _properties(model: OwlModel) -> list[tuple[URIRef, str]]:
    """(property, "object" | "data") of the model's properties, sorted."""
    return sorted((p, "object" if info.kind == "object" else "data")
                  for p, info in model.properties.items() if _in_model(p))


def _single(values: Sequence[Node]) -> URIRef | None:
    return values[0] if len(values) == 1 and isinstance(values[0], URIRef) else None


def _bounds(model: OwlModel, cls: URIRef, prop: URIRef) -> tuple[int, int | None]:
    """(min, max) number of values ``cls`` allows for ``prop`` (from its own rdfs:subClassOf restrictions)."""
    lo, hi = 0, UNBOUNDED
    for r in model.classes[cls].restrictions:
        if r.prop == prop and r.via == RDFS.subClassOf:
            lo, hi = max(lo, r.min), min(hi, r.max)
    return lo, hi if hi < UNBOUNDED else None


def _value_type(model: OwlModel, rng: URIRef | None) -> ValueType:
    """Storage kind, checks and canonical datatype of a datatype property's range."""
    if rng is None or rng == RDFS.Literal:
        return ValueType("text", range_iri=str(rng) if rng else None)
    if str(rng).startswith(str(XSD)):
        return _xsd_value_type(rng)
    info = model.datatype_info(rng)
    if info is not None and info.values is not None:
        items = info.values
        base = items[0].datatype if items and items[0].datatype else None
        vt = _xsd_value_type(base) if base else ValueType("text")
        return ValueType(vt.kind, vt.checks, tuple(str(v) for v in items), vt.datatype, str(rng))
    if info is not None and info.base is not None:
        vt = _value_type(model, info.base)
        checks = list(vt.checks)
        for pred, value in info.facets.items():
            op = _FACETS.get(split_iri(str(pred))[1])
            if op and pred.startswith(str(XSD)):
                checks.append((op, str(value)))
        return ValueType(vt.kind, tuple(checks), vt.enum, vt.datatype, str(rng))
    return ValueType("text", datatype=str(rng), range_iri=str(rng))


def _xsd_value_type(dt: URIRef) -> ValueType:
    local = split_iri(str(dt))[1]
    canonical = None if local == "string" else str(dt)
    if local in _INTEGER_CHECKS:
        check = _INTEGER_CHECKS[local]
        return ValueType("integer", (check,) if check else (), (), canonical, str(dt))
    kind = {"boolean": "boolean", "decimal": "decimal", "float": "float", "double": "float",
            "dateTime": "datetime", "dateTimeStamp": "datetime", "date": "date"}.get(local)
    if kind is None:
        kind = "text"  # strings and anything else are kept as their lexical form
    return ValueType(kind, (), (), canonical, str(dt))


# --- building the schema -----------------------------------------------------------------------

def _table_names(classes: list[URIRef]) -> dict[URIRef, str]:
    names: dict[URIRef, str] = {}
    for c in classes:
        ns, local = split_iri(str(c))
        names[c] = shorten(f"{MODEL_NAMESPACES[ns]}_{snake(local)}")
    return names


def _class_names(classes: list[URIRef]) -> dict[URIRef, str]:
    locals_ = [split_iri(str(c))[1] for c in classes]
    out = {}
    for c, local in zip(classes, locals_):
        ns = split_iri(str(c))[0]
        name = re.sub(r"\W", "_", local)
        if locals_.count(local) > 1 or name in {"Thing", "Base"}:
            name = MODEL_NAMESPACES[ns].capitalize() + name
        out[c] = name
    return out


def _unique_name(name: str, taken: set[str]) -> str:
    base, n = name, 2
    while name in taken:
        name, n = f"{base}_{n}", n + 1
    taken.add(name)
    return name


def build_schema(graph: Graph) -> Schema:
    """The relational model of the model classes and properties in ``graph``."""
    model = OwlModel(graph)
    model_classes = _model_classes(model)
    tables = _table_names(model_classes)
    classes = _class_names(model_classes)
    columns: dict[str, list[ColumnSpec]] = {t: [] for t in tables.values()}
    taken: dict[str, set[str]] = {t: {"id"} for t in tables.values()}
    taken[THING_TABLE] = {"id", "iri", "name", "kind"}
    columns[THING_TABLE] = []
    links: list[LinkSpec] = []
    all_names = set(tables.values()) | {THING_TABLE}
    for prop, kind in _properties(model):
        info = model.properties[prop]
        domain = _single(info.domains)
        domain = domain if domain in tables else None
        dom_table = tables[domain] if domain is not None else THING_TABLE
        rng = _single(info.ranges)
        dom_local = split_iri(str(domain))[1] if domain is not None else None
        attr = snake(_attribute(split_iri(str(prop))[1], dom_local))
        lo, hi = _bounds(model, domain, prop) if domain is not None else (0, None)
        functional = info.functional or hi == 1
        if kind == "object":
            ckind, target = ("object", tables[rng]) if rng in tables else ("iri", None)
            value = ValueType("iri", range_iri=str(rng) if rng else None)
        else:
            ckind, target, value = "data", None, _value_type(model, rng)
        if functional:
            suffix = "_id" if ckind == "object" else ""
            name = _unique_name(shorten(attr + suffix), taken[dom_table])
            columns[dom_table].append(ColumnSpec(
                name, name, str(prop), ckind, value, target, nullable=lo < 1,
                unique=info.inverse_functional and ckind == "object"))
        else:
            prefix = MODEL_NAMESPACES[split_iri(str(prop))[0]]
            name = _unique_name(shorten(f"{prefix}_{snake(split_iri(str(prop))[1])}"), all_names)
            links.append(LinkSpec(name, _unique_name(attr, taken[dom_table]), str(prop), ckind,
                                  dom_table, value, target, required=lo >= 1))
    specs = [TableSpec(tables[c], str(c), classes[c],
                       tables[p] if (p := _parent(model, c)) is not None else THING_TABLE,
                       tuple(columns[tables[c]]), " ".join(model.comment(c).split()))
             for c in model_classes]
    thing = TableSpec(THING_TABLE, "", "Thing", "", tuple(columns[THING_TABLE]),
                      "Every individual: its IRI, local name and most specific class.")
    ordered, links = _assign_attributes([thing, *_parents_first(specs)], links)
    ontologies = tuple(sorted((str(o), version) for o, version in model.ontologies()))
    return Schema(tuple(ordered), tuple(sorted(links, key=lambda l: l.name)), ontologies)


def _py_name(name: str) -> str:
    name = re.sub(r"\W", "_", name)
    if name[:1].isdigit():
        name = "_" + name
    return name + "_" if keyword.iskeyword(name) or name in _RESERVED else name


_RESERVED = {"metadata", "registry", "query", "id", "iri", "name", "kind"}


def _assign_attributes(tables: list[TableSpec], links: list[LinkSpec]) -> tuple[list[TableSpec], list[LinkSpec]]:
    """Python attribute names unique along each inheritance chain (parents come first)."""
    inherited: dict[str, set[str]] = {"": set()}
    out, new_links = [], []
    by_domain: dict[str, list[LinkSpec]] = {}
    for link in links:
        by_domain.setdefault(link.domain, []).append(link)
    for t in tables:
        taken = set(inherited[t.parent]) | ({"id", "iri", "name", "kind"} if t.name == THING_TABLE else set())
        prefix = snake(t.class_name)
        def pick(base: str) -> str:
            name = _py_name(base)
            if name in taken or name.rstrip("_") in taken:
                name = _py_name(f"{prefix}_{base}")
            return _unique_name(name, taken)
        cols = []
        for c in t.columns:
            attr = pick(c.name)
            rel = pick(c.name[:-3]) if c.kind == "object" else ""
            cols.append(replace(c, attr=attr, rel=rel))
        for link in by_domain.get(t.name, []):
            new_links.append(replace(link, attr=pick(link.attr)))
        inherited[t.name] = taken
        out.append(replace(t, columns=tuple(cols)))
    return out, new_links


def _parents_first(specs: list[TableSpec]) -> list[TableSpec]:
    by_parent: dict[str, list[TableSpec]] = {}
    for s in specs:
        by_parent.setdefault(s.parent, []).append(s)
    out: list[TableSpec] = []
    frontier = [THING_TABLE]
    while frontier:
        nxt = []
        for parent in frontier:
            kids = sorted(by_parent.get(parent, []), key=lambda s: s.name)
            out += kids
            nxt += [k.name for k in kids]
        frontier = nxt
    return out


def shipped_schema(files: Iterable[Path] | None = None) -> Schema:
    """The schema of the shipped kitting and SOAP ontologies (or of ``files``)."""
    paths = tuple(files) if files is not None else tuple(model_files())
    stamps = tuple((str(p), p.stat().st_mtime_ns if p.is_file() else 0) for p in paths)
    return _schema_of(stamps)


@lru_cache(maxsize=4)
def _schema_of(stamps: tuple[tuple[str, int], ...]) -> Schema:
    graph = Graph()
    for path in (Path(p) for p, _ in stamps):
        try:
            graph.parse(path, format="turtle")
        except FileNotFoundError:
            raise InputError("no such file", file=path) from None
        except Exception as exc:  # rdflib raises many kinds of syntax errors
            raise InputError(f"cannot read ontology: {str(exc).splitlines()[0]}", file=path) from None
    return build_schema(graph)
