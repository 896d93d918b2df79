"""Where each statement of a data file goes: triples in, rows of the world-model tables out.

:class:`RowBuilder` reads the statements once, in file order, and fills the rows as it goes:
a statement about a subject whose type is already known goes straight to its column or link
table; the few whose subject is not typed yet wait until the end. An object property's value
is taken on trust (its type may come later in the file) and checked when all types are
known: a value outside the property's range becomes a plain statement, as before. Every
statement is kept: what the class tables cannot hold goes to ``kitkb_triple``, other asserted
types to ``kitkb_type``, unusual spellings of literals to ``kitkb_literal`` (docs/database.md).

Each node (IRI or blank node) gets the next id when the file first names it; individuals keep
it as their database id (so rows never need renumbering; ids of nodes that turn out not to
be individuals are simply not used). Memory is that of the rows (one list per table row,
values shared), not of the triples.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import lru_cache, partial
from typing import Any, Callable, Iterable

import pyoxigraph as ox

from kb.core.errors import InputError
from kb.core.namespaces import local_name
from kb.core.resources import model_files
from kb.io.loader import extension_classes
from kb.spatial.scene import class_ancestors
from kb.world.plan import PropertyPlan, load_plan
from kb.world.values import ValueProblem, check_value, is_canonical_parts, parse_lexical

RDF_TYPE = "http://www.w3.org/1999/02/22-rdf-syntax-ns#type"
THING = "kitkb_thing"
#: Longest IRI an IRI column (and an individual's name) holds.
MAX_IRI = 760

# what a property is, for the loop
_OBJECT, _IRI, _DATA = 0, 1, 2
_UNKNOWN = object()  # not seen yet

Row = list[Any]
Table = tuple[str, list[str], "list[Any]"]


@dataclass
class TableRows:
    """The rows of one class table being built: id -> ``[id, value, ...]`` in column order."""

    name: str
    columns: list[str]  # "id" first
    required: list[int]  # positions of NOT NULL columns
    rows: dict[int, Row] = field(default_factory=dict)

    def new_row(self, node: int) -> None:
        """An empty row for ``node``."""
        row = [None] * len(self.columns)
        row[0] = node
        self.rows[node] = row


class _Prop:
    """A model property as the loop uses it."""

    __slots__ = ("plan", "iri", "kind", "link", "rows", "pos", "domain", "target", "checks", "vtype", "values")

    def __init__(self, plan: PropertyPlan, iri: str, tables: dict[str, TableRows], vtypes: dict[tuple, dict]):
        self.plan, self.iri, self.link = plan, iri, plan.link
        self.kind = {"object": _OBJECT, "iri": _IRI}.get(plan.info["kind"], _DATA)
        self.domain, self.target, self.checks = plan.domain, plan.target, plan.checks
        self.values: dict[tuple[int, Any], None] = {}  # link rows (subject id, value), in order
        table = None if plan.link else tables[plan.table]
        self.rows = table.rows if table is not None else None
        self.pos = table.columns.index(plan.column) if table is not None else -1
        key = (plan.info.get("value"), plan.info.get("datatype"))
        #: parsed literals of this value type, shared by the properties of the same type
        self.vtype = vtypes.setdefault(key, {}) if self.kind == _DATA else None


@dataclass
class Built:
    """What :class:`RowBuilder` made: rows per table as ``(table, columns, rows)``, and counts."""

    tables: list[Table]
    individuals: int
    statements: int
    outside: int
    prefixes: dict[str, str]


@lru_cache(maxsize=1)
def model_individuals() -> dict[str, tuple[str, ...]]:
    """Individuals the shipped ontologies define (``soap:EffectCheck``...) with their model classes."""
    m = load_plan()
    out: dict[str, list[str]] = {}
    for path in model_files():
        for s, p, o, _ in ox.parse(path=path, format=ox.RdfFormat.TURTLE):
            if p.value == RDF_TYPE and type(s) is ox.NamedNode and o.value in m.class_table:
                out.setdefault(s.value, []).append(o.value)
    return {k: tuple(v) for k, v in out.items()}


class _Named:
    """Stands for an IRI the file names only as a plain value: the node of an individual of the
    model ontologies that gets a row (:meth:`RowBuilder._external`)."""

    def __init__(self, iri: str):
        self.iri = iri


class RowBuilder:
    """Turns the statements of one data file into rows of the model's tables.

    ``terms`` reads the file's terms (:mod:`kb.world.triples`); ``line_of(subject key,
    predicate, object term)`` finds lines for error messages; ``file`` names the file in them.
    Feed it the statements (:meth:`feed`), then :meth:`finish`.
    """

    def __init__(self, terms: Any, line_of: Callable[..., int | None], file: str):
        self.terms, self.line_of, self.file, self.m = terms, line_of, file, load_plan()
        m = self.m
        self.tables: dict[str, TableRows] = {}
        for table in m.tables.values():
            if "parent" in table.info and table.name != THING:
                cols = list(table.columns)
                self.tables[table.name] = TableRows(
                    table.name, [c.name for c in cols],
                    [i for i, c in enumerate(cols) if not c.nullable and not c.primary_key])
        self._vtypes: dict[tuple, dict] = {}
        self._chains = {iri: tuple(m.chain(t)) for iri, t in m.class_table.items()}
        self._tablesets: dict[str, tuple[frozenset[str], list[TableRows]]] = {}
        self.nodes: dict[Any, int] = {}  # term -> id
        # id -> IRI or _:label; -> model classes stated; -> tables it has rows in (id 0 unused)
        self.keys: list[str] = [""]
        self.classes: list[list[str] | None] = [None]
        self.in_tables: list[frozenset[str] | None] = [None]
        self.handlers: dict[Any, Callable[[int, Any, Any], None]] = {}  # predicate term -> its handler
        self.props: dict[Any, _Prop] = {}  # predicate term -> model property
        self.class_of: dict[Any, str | None] = {}  # type term -> model class IRI or None
        self.pending: list[Any] = []  # statements whose subject was not typed (yet)
        self.out_of_range: dict[tuple[int, str], int] = {}  # (node, property) -> a value outside its range
        self.other_types: list[tuple[int, Any]] = []  # (node, type term) of non-model types
        self.extended: set[Any] = set()  # type terms of extension classes (rows of a model class)
        self.literals: dict[tuple[int, str], tuple[str, str | None, str | None]] = {}
        self.outside: dict[tuple[str, str, str, str, str | None, str | None], None] = {}
        self.statements = 0
        self.duplicates = 0

    # --- errors ---------------------------------------------------------------------------------
    def fail(self, node: int, predicate: str | None, obj: Any, message: str) -> InputError:
        """An input error at the line of the statement about ``node``."""
        return InputError(message, file=self.file, line=self.line_of(self.keys[node], predicate, obj))

    # --- the loop -------------------------------------------------------------------------------
    def feed(self, quads: Iterable[Any]) -> None:
        """Read the statements (``(s, p, o, graph)`` tuples); may raise :class:`InputError`.

        Each predicate gets a handler made for it (:meth:`_handler`): the loop itself only finds
        the subject's id and calls the handler with ``(subject id, object, statement)``."""
        nodes, handlers, node, handler = self.nodes.get, self.handlers.get, self._node, self._handler
        count = 0
        for q in quads:
            count += 1
            s = q[0]  # indexing a quad is cheaper than unpacking it
            si = nodes(s)
            if si is None:
                si = node(s)
            fn = handlers(q[1])
            if fn is None:
                fn = handler(q[1])
            fn(si, q[2], q)
        self.statements += count

    def _node(self, term: Any, key: str | None = None) -> int:
        key = key or self.terms.resource(term)
        if key is None:
            raise AssertionError("a literal as subject")  # parsers never give one
        node = len(self.keys)
        self.nodes[term] = node
        self.keys.append(key)
        self.classes.append(None)
        self.in_tables.append(None)
        return node

    def _handler(self, p: Any) -> Callable[[int, Any, Any], None]:
        """The handler of predicate ``p``: rdf:type, a model property (by kind), or another property."""
        iri = self.terms.resource(p) or ""
        if iri == RDF_TYPE:
            fn = self._type_handler()
        else:
            plan = self.m.properties.get(iri)
            if plan is None:
                fn = partial(_outside_handler, self._outside, iri)
            else:
                prop = self.props[p] = _Prop(plan, iri, self.tables, self._vtypes)
                fn = self._column_handler(prop) if not prop.link and prop.kind != _IRI else \
                    partial(_general_handler, self.in_tables, self.pending.append, self._store, prop)
        self.handlers[p] = fn
        return fn

    def _column_handler(self, prop: _Prop) -> Callable[[int, Any, Any], None]:
        """The handler of a property held in a column: the common case (the subject is typed, the
        column still empty, the value usual) on the spot, anything else by :meth:`_store`."""
        in_tables, pending, store = self.in_tables, self.pending.append, self._store
        rows, pos, domain = prop.rows, prop.pos, prop.domain
        if prop.kind == _OBJECT:
            nodes, node, resource = self.nodes.get, self._node, self.terms.resource

            def on_object(si: int, o: Any, q: Any) -> None:
                tables = in_tables[si]
                if tables is None or domain not in tables:
                    pending(q)  # its subject's type may come later
                    return
                value = nodes(o)
                if value is None:
                    key = resource(o)
                    if key is None:  # a literal: kept as written (by _store)
                        store(si, prop, o)
                        return
                    value = node(o, key)
                row = rows[si]  # type: ignore[index]
                if row[pos] is not None:
                    store(si, prop, o)
                else:
                    row[pos] = value
            return on_object
        parsed_of, parse, checks = prop.vtype.get, self._literal, prop.checks  # type: ignore[union-attr]

        def on_data(si: int, o: Any, q: Any) -> None:
            tables = in_tables[si]
            if tables is None or domain not in tables:
                pending(q)
                return
            parsed = parsed_of(o)
            row = rows[si]  # type: ignore[index]
            if parsed is None or checks or not parsed[1] or row[pos] is not None:
                store(si, prop, o)
            else:
                row[pos] = parsed[0]
        return on_data

    def _type_handler(self) -> Callable[[int, Any, Any], None]:
        """The handler of ``rdf:type``: a model class gives the node its rows, another type is
        kept for ``kitkb_type`` (or as written, if the node turns out not to be an individual)."""
        class_get, class_of, other = self.class_of.get, self._class_of, self.other_types.append
        classes, in_tables, more, rows_of = self.classes, self.in_tables, self._more_class, self._class_rows

        extended = self.extended

        def on_type(si: int, o: Any, q: Any) -> None:
            cls = class_get(o, _UNKNOWN)
            if cls is _UNKNOWN:
                cls = class_of(o)
            if cls is None:
                other((si, o))
                return
            if o in extended:  # a domain extension's class: rows of its model class, the type kept
                other((si, o))
            if classes[si] is None:  # typed for the first time: rows in its class's tables
                classes[si] = [cls]
                tables, rows = rows_of(cls)
                for table, width in rows:
                    row = [None] * width
                    row[0] = si
                    table[si] = row
                in_tables[si] = tables
            else:
                more(si, cls)
        return on_type

    # --- types ----------------------------------------------------------------------------------
    def _class_of(self, o: Any) -> str | None:
        """The model class a type term names (None: another class, or not a class); for a class
        a domain extension declares under model classes (:func:`kb.io.loader.declare_classes`),
        the deepest of those, its individuals' rows (the class itself kept in ``kitkb_type``)."""
        key = self.terms.resource(o) if self.terms.is_iri(o) else None
        cls = key if key in self.m.class_table else None
        if cls is None and key is not None and key in extension_classes():
            above = [c for c in class_ancestors().get(key, ()) if c in self.m.class_table]
            if above:
                cls = min(above, key=lambda c: (-self.m.depth[c], c))
                self.extended.add(o)
        self.class_of[o] = cls
        return cls

    def _class_rows(self, cls: str) -> tuple[frozenset[str], list[tuple[dict[int, Row], int]]]:
        """The tables an individual of ``cls`` has rows in (``kitkb_thing`` included), and the
        rows and row width of those that :class:`TableRows` builds."""
        found = self._tablesets.get(cls)
        if found is None:
            names = frozenset(self._chains[cls])
            found = self._tablesets[cls] = (names, [(self.tables[t].rows, len(self.tables[t].columns))
                                                    for t in sorted(names) if t != THING])
        return found

    def _more_class(self, node: int, cls: str) -> None:
        """Another model class for a typed node: rows in the tables it adds."""
        mine = self.classes[node]
        if cls in mine:  # type: ignore[operator]
            self.duplicates += 1
            return
        mine.append(cls)  # type: ignore[union-attr]
        tables, _ = self._class_rows(cls)
        old = self.in_tables[node] or frozenset()
        for name in tables - old:
            if name != THING:
                self.tables[name].new_row(node)
        self.in_tables[node] = old | tables

    def primary(self, node: int) -> str:
        """The most specific model class of a node ("" for an individual only referred to)."""
        classes = self.classes[node]
        if not classes:
            return ""
        if len(classes) == 1:
            return classes[0]
        depth = self.m.depth
        return min(classes, key=lambda c: (-depth[c], c))

    # --- statements -----------------------------------------------------------------------------
    def _outside(self, node: int, p: str, o: Any) -> None:
        """A statement kept as written (``kitkb_triple``): predicate IRI, object term."""
        key = self.terms.resource(o)
        if key is None:
            lex, dt, lang = self.terms.literal(o)
            self._keep((self.keys[node], p, lex, "literal", dt, lang))
        else:
            self._keep_resource(node, p, key)

    def _keep_resource(self, node: int, p: str, key: str) -> None:
        self._keep((self.keys[node], p, key, "bnode" if key.startswith("_:") else "iri", None, None))

    def _keep(self, row: tuple[str, str, str, str, str | None, str | None]) -> None:
        if row in self.outside:
            self.duplicates += 1
        self.outside[row] = None

    def _store(self, node: int, prop: _Prop, o: Any) -> None:
        """Put one statement in its column or link table (its subject has the domain's rows),
        or keep it as a plain statement when its value does not fit there."""
        kind = prop.kind
        canonical = True
        if kind == _OBJECT:
            value = self.nodes.get(o)
            if value is None:
                key = self.terms.resource(o)
                if key is None:  # a literal where the model expects an individual
                    return self._outside(node, prop.iri, o)
                value = self._node(o, key)
        elif kind == _IRI:
            value = self.terms.resource(o) if self.terms.is_iri(o) else None
            if value is None or len(value) > MAX_IRI:
                return self._outside(node, prop.iri, o)
        else:
            parsed = prop.vtype.get(o)  # type: ignore[union-attr]
            if parsed is None:
                parsed = self._literal(node, prop, o)
            value, canonical = parsed
            if prop.checks:
                try:
                    check_value(value, prop.checks)
                except ValueProblem as exc:
                    raise self._value_error(node, prop, o, exc) from None
        if prop.link:
            if not canonical:  # a literal spelled unusually stays a plain statement (lossless)
                return self._outside(node, prop.iri, o)
            pair = (node, value)
            if pair in prop.values:
                self.duplicates += 1
            prop.values[pair] = None
            return None
        row = prop.rows[node]  # type: ignore[index]
        old = row[prop.pos]
        if old is not None:
            if old == value and (kind != _DATA or self._same_spelling(node, prop, o, canonical)):
                self.duplicates += 1  # the same statement twice
                return None
            raise self.fail(node, prop.iri, o, f"{local_name(self.keys[node])} has a second value for the "
                                               f"functional property {local_name(prop.iri)}")
        row[prop.pos] = value
        if not canonical:
            self.literals[(node, prop.iri)] = self.terms.literal(o)
        return None

    def _literal(self, node: int, prop: _Prop, o: Any) -> tuple[Any, bool]:
        terms = self.terms
        key = terms.resource(o)
        if key is not None:
            spelled = key if key.startswith("_:") else f"<{key}>"
            raise self.fail(node, prop.iri, o, f"{local_name(prop.iri)} expects a literal value, not {spelled}")
        lex, dt, lang = terms.literal(o)
        info = prop.plan.info
        try:
            value = parse_lexical(info.get("value", "text"), lex)
        except ValueProblem as exc:
            raise self._value_error(node, prop, o, exc) from None
        parsed = value, is_canonical_parts(lex, dt, lang, value, info)
        prop.vtype[o] = parsed  # type: ignore[index]
        return parsed

    def _value_error(self, node: int, prop: _Prop, o: Any, exc: ValueProblem) -> InputError:
        return self.fail(node, prop.iri, o, f"{local_name(prop.iri)} of {local_name(self.keys[node])}: {exc}")

    def _same_spelling(self, node: int, prop: _Prop, o: Any, canonical: bool) -> bool:
        spelled = self.literals.get((node, prop.iri))
        if spelled is None:
            return canonical
        return not canonical and spelled == self.terms.literal(o)

    # --- the end --------------------------------------------------------------------------------
    def finish(self, prefixes: dict[str, str]) -> Built:
        """Place the statements that waited, check ranges and required values; the rows."""
        for q in self.pending:
            node, prop, o = self.nodes[q[0]], self.props[q[1]], q[2]
            tables = self.in_tables[node]
            if tables is not None and prop.domain in tables:
                self._store(node, prop, o)
            else:
                self._outside(node, prop.iri, o)
        self.pending.clear()
        self._external()
        things = self._things()
        self._ranges()
        self._required()
        types = self._types()
        tables = self._emit(things, types)
        return Built(tables, len(things), self.statements - self.duplicates, len(self.outside) + len(types),
                     prefixes)

    def _external(self) -> None:
        """Rows for the individuals of the model ontologies the file refers to without defining them.

        They get rows (so that foreign keys can point at them) but no type statements on dump.
        Only those whose tables require no values are taken: their values are not in the file.
        """
        candidates = [i for i, c in enumerate(self.classes) if i and c is None and not self.keys[i].startswith("_:")]
        referred = {row[2] for row in self.outside if row[3] == "iri"}
        for prop in self.props.values():
            if isinstance(prop, _Prop) and prop.kind == _IRI:
                referred.update(v for _, v in prop.values) if prop.link else referred.update(
                    row[prop.pos] for row in prop.rows.values() if row[prop.pos] is not None)  # type: ignore[union-attr]
        referred.difference_update(self.keys)
        if not candidates and not referred:
            return
        known = model_individuals()
        candidates += [self._node(_Named(iri), iri) for iri in sorted(referred) if iri in known]
        for node in candidates:
            classes = known.get(self.keys[node])
            if classes is None:
                continue
            tables = frozenset(t for c in classes for t in self._chains[c])
            if not any(c.info.get("iri") and not c.nullable for t in tables for c in self.m.tables[t].columns):
                self.in_tables[node] = tables
                for t in tables:
                    if t != THING:
                        self.tables[t].new_row(node)

    def _things(self) -> list[tuple[int, str, str, str]]:
        """``kitkb_thing`` rows: the individuals (typed with a model class, or external)."""
        out = []
        keys, classes, in_tables, primary = self.keys, self.classes, self.in_tables, self.primary
        for node in range(1, len(keys)):
            if in_tables[node] is None:
                continue
            key, mine = keys[node], classes[node]
            if len(key) > MAX_IRI:
                raise self.fail(node, RDF_TYPE, None, f"name longer than {MAX_IRI} characters: {key[:40]}...")
            out.append((node, key, local_name(key), (mine[0] if len(mine) == 1 else primary(node)) if mine else ""))
        return out

    def _ranges(self) -> None:
        """Object values outside the property's range become plain statements."""
        in_tables, keys = self.in_tables, self.keys
        for prop in list(self.props.values()):
            if not isinstance(prop, _Prop) or prop.kind != _OBJECT:
                continue
            target = prop.target
            if prop.link:
                bad = [pair for pair in prop.values if not _fits(in_tables[pair[1]], target)]
                for node, value in bad:
                    del prop.values[(node, value)]
                    self._keep_resource(node, prop.iri, keys[value])
                continue
            pos = prop.pos
            for node, row in prop.rows.items():  # type: ignore[union-attr]
                value = row[pos]
                if value is not None and not _fits(in_tables[value], target):
                    row[pos] = None
                    self._keep_resource(node, prop.iri, keys[value])
                    self.out_of_range[(node, prop.iri)] = value

    def _required(self) -> None:
        """Every NOT NULL column of every row is filled, or the file is refused."""
        for table in self.tables.values():
            for pos in table.required:
                for node, row in table.rows.items():
                    if row[pos] is None:
                        cls = self.primary(node)
                        col = self.m.tables[table.name].column(table.columns[pos])
                        iri = col.info.get("iri", col.name)
                        if (node, iri) in self.out_of_range:  # given, but not an individual it may be
                            raise self._out_of_range(node, iri, self.out_of_range[(node, iri)])
                        raise self.fail(node, RDF_TYPE, None,
                                        f"{local_name(self.keys[node])} ({local_name(cls)}) has no value for "
                                        f"{local_name(col.info.get('iri', col.name))}, which the model requires")

    def _out_of_range(self, node: int, iri: str, value: int) -> InputError:
        """The required value ``value`` of ``node``'s ``iri`` that the model's range does not admit,
        at its statement, in the words of validate's unknown-individual and class rules."""
        subject, obj = local_name(self.keys[node]), local_name(self.keys[value])
        if self.in_tables[value] is None:
            return self.fail(node, iri, None, f"unknown individual {obj} (object of {local_name(iri)} on {subject}), "
                                              "which the model requires")
        return self.fail(node, iri, None, f"{local_name(iri)} of {subject} is {obj} (it is "
                                          f"{local_name(self.primary(value))}), not an individual of the property's "
                                          "range, which the model requires")

    def _types(self) -> dict[tuple[int, str], None]:
        """``kitkb_type`` rows: asserted types of individuals other than their primary class."""
        types: dict[tuple[int, str], None] = {}
        for node, classes in enumerate(self.classes):
            if classes is not None and len(classes) > 1:
                primary = self.primary(node)
                types.update(((node, c), None) for c in classes if c != primary)
        other = dict.fromkeys(self.other_types)
        self.duplicates += len(self.other_types) - len(other)
        iris = {t: self.terms.resource(t) if self.terms.is_iri(t) else None for t in {t for _, t in other}}
        in_tables = self.in_tables
        for node, term in other:
            iri = iris[term]
            if in_tables[node] is not None and iri is not None:
                types[(node, iri)] = None
            else:
                self._outside(node, RDF_TYPE, term)
        return types

    def _emit(self, things: list[tuple[int, str, str, str]], types: dict[tuple[int, str], None]) -> list[Table]:
        out: list[Table] = [(THING, ["id", "iri", "name", "kind"], things)]
        for table in self.tables.values():
            if table.rows:
                out.append((table.name, table.columns, list(table.rows.values())))
                table.rows = {}
        for prop in self.props.values():
            if isinstance(prop, _Prop) and prop.link and prop.values:
                out.append((prop.plan.table, ["subject_id", prop.plan.column], list(prop.values)))
        if types:
            out.append(("kitkb_type", ["thing_id", "class_iri"], list(types)))
        if self.literals:
            out.append(("kitkb_literal", ["thing_id", "property_iri", "lexical", "datatype", "lang"],
                        [(node, p, *parts) for (node, p), parts in self.literals.items()]))
        if self.outside:
            out.append(("kitkb_triple", ["subject", "predicate", "object", "object_kind", "datatype", "lang"],
                        list(self.outside)))
        return out


def _outside_handler(outside: Callable[[int, str, Any], None], iri: str, si: int, o: Any, q: Any) -> None:
    outside(si, iri, o)


def _general_handler(in_tables: list[Any], pending: Callable[[Any], None], store: Callable[..., None],
                     prop: _Prop, si: int, o: Any, q: Any) -> None:
    tables = in_tables[si]
    if tables is None or prop.domain not in tables:
        pending(q)
    else:
        store(si, prop, o)


def _fits(tables: frozenset[str] | None, target: str | None) -> bool:
    return tables is not None and target is not None and target in tables
