"""Predicate, function and spatial-relation definitions of a SOAP domain, as typed values.

What the ontology says a predicate *means*, read once from its Turtle:

* a predicate's ``soap:hasPredicate_Definition`` is a formula tree (:class:`And`, :class:`Or`,
  :class:`Not`, :class:`Exists`) over atoms: spatial :class:`Relation` atoms, and the
  non-spatial kinds :class:`Sku`, :class:`Model`, :class:`Count` and :class:`Sensor`; a failure
  condition may also use a predicate as a leaf (:class:`PredicateLeaf`);
* a function's ``soap:hasFunction_Definition`` is a :class:`CountOf` or the kit design's count;
* an intermediate state relation (``soap:In-Contact-With``, ...) is the ``owl:equivalentClass``
  expression of its class, read into :class:`RelationExpr` down to the 24 RCC8 and 6 cardinal
  primitives of ``kb.spatial.rcc8``.

Nothing here computes geometry (``kb.spatial.predicates`` evaluates these trees on a scene).
A definition that cannot be evaluated — a missing operand, a variable used outside its
quantifier, an unknown relation, a cycle — is an :class:`~kb.core.errors.InputError` at the
file and line of the offending node (:func:`check_definitions` lists them all for validation).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Iterable, Sequence, Union

from rdflib import BNode, Graph, Literal, URIRef
from rdflib.collection import Collection
from rdflib.namespace import OWL, RDF

from kb.core.errors import InputError
from kb.core.namespaces import SOAP
from kb.io import KnowledgeBase
from kb.io.loader import domain_knowledge

#: The 30 primitive relations, per axis: RCC8 then cardinal directions.
RCC8_NAMES = ("DC", "EC", "PO", "EQ", "TPP", "NTPP", "TPPi", "NTPPi")
PRIMITIVES: tuple[str, ...] = tuple(f"{a}-{r}" for a in "XYZ" for r in RCC8_NAMES) + tuple(
    f"{a}-{d}" for a in "XYZ" for d in ("Plus", "Minus"))

#: Where a node was written: ``(file, line)``; ``(None, None)`` when unknown.
Locator = Callable[[URIRef | BNode], tuple[str | None, int | None]]


# ------------------------------------------------------------------------------ terms

@dataclass(frozen=True)
class Variable:
    """A quantified object: its name and the class its candidates are drawn from."""

    node: str
    name: str
    cls: str


#: A term: "reference" (1st argument), "target" (2nd), a parameter IRI (failure conditions),
#: or a :class:`Variable`.
Term = Union[str, Variable]
REFERENCE, TARGET = "reference", "target"


# ------------------------------------------------------------------------------ formulas

@dataclass(frozen=True)
class Relation:
    """``relation(subject, object)``: a spatial atom; ``relation`` is a relation IRI."""

    node: str
    relation: str
    subject: Term
    object: Term
    negated: bool = False


@dataclass(frozen=True)
class Sku:
    """The subject end effector is listed by the object's SKU (a kit: its tray's SKU)."""

    node: str
    subject: Term
    object: Term
    negated: bool = False


@dataclass(frozen=True)
class Model:
    """The model states ``subject <property> object``."""

    node: str
    property: str
    subject: Term
    object: Term
    negated: bool = False


@dataclass(frozen=True)
class Count:
    """The number of ``variable``s satisfying ``condition`` compares by ``operator`` with
    ``limit`` or with the value of ``limit_property`` of ``limit_subject``."""

    node: str
    variable: Variable
    condition: "Formula"
    operator: str
    limit: float | None = None
    limit_property: str | None = None
    limit_subject: Term | None = None
    negated: bool = False


@dataclass(frozen=True)
class Sensor:
    """The inspection ``check`` passes for ``subject``."""

    node: str
    check: str
    subject: Term
    negated: bool = False


@dataclass(frozen=True)
class PredicateLeaf:
    """Another predicate on two terms (used in failure conditions)."""

    node: str
    predicate: str
    reference: Term | None
    target: Term | None
    negated: bool = False


@dataclass(frozen=True)
class And:
    node: str
    operands: tuple["Formula", ...]


@dataclass(frozen=True)
class Or:
    node: str
    operands: tuple["Formula", ...]


@dataclass(frozen=True)
class Not:
    node: str
    operand: "Formula"


@dataclass(frozen=True)
class Exists:
    """Some candidate of ``variable`` other than the objects already bound makes ``body`` hold."""

    node: str
    variable: Variable
    body: "Formula"


Formula = Union[And, Or, Not, Exists, Relation, Sku, Model, Count, Sensor, PredicateLeaf]


# ------------------------------------------------------------------------------ relations

@dataclass(frozen=True)
class RelationExpr:
    """A Boolean expression over the primitive relations: ``op`` is "prim" (``name``),
    "any" (owl:unionOf), "all" (owl:intersectionOf), "not" (owl:complementOf) or "true"
    (``soap:SpatialRelation``, every pair)."""

    op: str
    name: str = ""
    args: tuple["RelationExpr", ...] = ()


# ------------------------------------------------------------------------------ definitions

@dataclass(frozen=True)
class PredicateDef:
    """A predicate: name, argument classes (``None`` when absent) and definition."""

    iri: str
    name: str
    reference_type: str | None
    target_type: str | None
    formula: Formula

    @property
    def arity(self) -> int:
        return (self.reference_type is not None) + (self.target_type is not None)


@dataclass(frozen=True)
class CountOf:
    """Function definition: the number of ``variable``s satisfying ``condition``."""

    node: str
    variable: Variable
    condition: Formula


@dataclass(frozen=True)
class DesignCount:
    """Function definition: the number of slots of the kit's design with the SKU."""

    node: str


@dataclass(frozen=True)
class FunctionDef:
    iri: str
    name: str
    reference_type: str | None
    target_type: str | None
    definition: CountOf | DesignCount


@dataclass
class Definitions:
    """Every predicate, function and intermediate relation a domain defines."""

    predicates: dict[str, PredicateDef]
    functions: dict[str, FunctionDef]
    relations: dict[str, RelationExpr]  # relation IRI -> expression (primitives included)

    def relation(self, iri: str) -> RelationExpr:
        return self.relations[iri]


def load_definitions(domain_files: Sequence[str | Path] | None = None) -> Definitions:
    """The definitions of the domain in ``domain_files`` (default: the shipped
    ``kitting-domain.ttl``) with their imports; errors name the file and line of the node."""
    kb = domain_knowledge(domain_files)
    return read_definitions(kb.graph, locator(kb))


def locator(kb: KnowledgeBase) -> Locator:
    """Where a node is stated in ``kb``'s files: ``(file, line)``."""
    def locate(node) -> tuple[str | None, int | None]:  # noqa: ANN001
        found = kb.source_of(node)
        return (str(found[0].path), found[1]) if found else (None, None)
    return locate


def read_definitions(graph: Graph, locate: Locator | None = None) -> Definitions:
    """The definitions of every ``soap:Predicate`` and ``soap:Function`` in ``graph``.

    Raises :class:`InputError` at the first malformed node (see :func:`check_definitions`).
    """
    problems = []
    defs = _Reader(graph, locate or (lambda n: (None, None)), problems).read()
    if problems:
        raise problems[0]
    return defs


def check_definitions(graph: Graph, locate: Locator | None = None) -> list[InputError]:
    """Every malformed predicate or function definition in ``graph`` (empty when all are sound)."""
    problems: list[InputError] = []
    _Reader(graph, locate or (lambda n: (None, None)), problems).read()
    return problems


class _Malformed(Exception):
    def __init__(self, node, message: str):  # noqa: ANN001
        super().__init__(message)
        self.node, self.message = node, message


def _short(node) -> str:  # noqa: ANN001
    text = str(node)
    return text.rsplit("#", 1)[-1].rsplit("/", 1)[-1] if isinstance(node, URIRef) else "a blank node"


class _Reader:
    def __init__(self, g: Graph, locate: Locator, problems: list[InputError]):
        self.g, self.locate, self.problems = g, locate, problems
        self.relations: dict[str, RelationExpr] = {f"{SOAP}{p}": RelationExpr("prim", p) for p in PRIMITIVES}
        self.relations[str(SOAP.SpatialRelation)] = RelationExpr("true")
        self._relating: set[str] = set()

    def error(self, node, message: str) -> None:  # noqa: ANN001
        file, line = self.locate(node)
        self.problems.append(InputError(message, file, line))

    def read(self) -> Definitions:
        predicates, functions = {}, {}
        for node in sorted(self.g.subjects(RDF.type, SOAP.Predicate), key=str):
            try:
                p = self.predicate(node)
                predicates[p.name] = p
            except _Malformed as e:
                self.error(e.node, f"predicate {_short(node)}: {e.message}")
        for node in sorted(self.g.subjects(RDF.type, SOAP.Function), key=str):
            try:
                f = self.function(node)
                functions[f.name] = f
            except _Malformed as e:
                self.error(e.node, f"function {_short(node)}: {e.message}")
        return Definitions(predicates, functions, self.relations)

    # --- helpers ------------------------------------------------------------------
    def values(self, node, prop) -> list:  # noqa: ANN001
        return sorted(self.g.objects(node, prop), key=str)

    def one(self, node, prop, what: str, owner=None):  # noqa: ANN001, ANN201
        vals = self.values(node, prop)
        if len(vals) != 1:
            local = str(prop).rsplit("#", 1)[-1]
            raise _Malformed(node, f"{what} {_short(owner or node)} needs exactly one {local} "
                                   f"(has {len(vals)})")
        return vals[0]

    def optional(self, node, prop):  # noqa: ANN001, ANN201
        vals = self.values(node, prop)
        return vals[0] if vals else None

    def negated(self, node) -> bool:  # noqa: ANN001
        v = self.optional(node, SOAP.hasAtom_IsNegated)
        if v is None:
            return False
        if not isinstance(v, Literal) or not isinstance(v.toPython(), bool):
            raise _Malformed(node, f"hasAtom_IsNegated of {_short(node)} must be a boolean, not {v}")
        return bool(v.toPython())

    # --- predicates and functions ------------------------------------------------------
    def predicate(self, node) -> PredicateDef:  # noqa: ANN001
        name = str(self.one(node, SOAP.hasPredicate_Name, "predicate"))
        ref = self.optional(node, SOAP.hasPredicate_ReferenceType)
        tgt = self.optional(node, SOAP.hasPredicate_TargetType)
        scope = ([REFERENCE] if ref is not None else []) + ([TARGET] if tgt is not None else [])
        body = self.one(node, SOAP.hasPredicate_Definition, "predicate")
        formula = self.formula(body, tuple(scope), (), owner=node)
        return PredicateDef(str(node), name, str(ref) if ref is not None else None,
                            str(tgt) if tgt is not None else None, formula)

    def function(self, node) -> FunctionDef:  # noqa: ANN001
        name = str(self.one(node, SOAP.hasFunction_Name, "function"))
        ref = self.optional(node, SOAP.hasFunction_ReferenceType)
        tgt = self.optional(node, SOAP.hasFunction_TargetType)
        scope = ([REFERENCE] if ref is not None else []) + ([TARGET] if tgt is not None else [])
        body = self.one(node, SOAP.hasFunction_Definition, "function")
        types = set(self.g.objects(body, RDF.type))
        if SOAP.DesignCountExpression in types:
            definition: CountOf | DesignCount = DesignCount(str(body))
        elif SOAP.CountExpression in types:
            var = self.variable(self.one(body, SOAP.hasCountExpression_Variable, "count expression"))
            cond = self.formula(self.one(body, SOAP.hasCountExpression_Condition, "count expression"),
                                tuple(scope), (), bound=(var,))
            definition = CountOf(str(body), var, cond)
        else:
            raise _Malformed(body, f"definition {_short(body)} of function {name} is neither a "
                                   "soap:CountExpression nor a soap:DesignCountExpression")
        return FunctionDef(str(node), name, str(ref) if ref is not None else None,
                           str(tgt) if tgt is not None else None, definition)

    # --- formulas -----------------------------------------------------------------
    def formula(self, node, scope: tuple, path: tuple, owner=None, bound: tuple = ()) -> Formula:  # noqa: ANN001
        """The formula at ``node``; ``scope``: "reference"/"target"/parameter IRIs usable as
        terms; ``bound``: the variables of enclosing quantifiers."""
        if node in path:
            raise _Malformed(node, f"formula {_short(node)} contains itself")
        path = path + (node,)
        types = set(self.g.objects(node, RDF.type))
        n = str(node)
        if SOAP.Conjunction in types or SOAP.Disjunction in types:
            prop = SOAP.hasConjunction_Operand if SOAP.Conjunction in types else SOAP.hasDisjunction_Operand
            ops = self.values(node, prop)
            if not ops:
                raise _Malformed(node, f"{_short(node)} has no operands ({str(prop).rsplit('#', 1)[-1]})")
            parts = tuple(self.formula(o, scope, path, bound=bound) for o in ops)
            return And(n, parts) if SOAP.Conjunction in types else Or(n, parts)
        if SOAP.Negation in types:
            return Not(n, self.formula(self.one(node, SOAP.hasNegation_Operand, "negation"), scope, path,
                                       bound=bound))
        if SOAP.Existential in types:
            var = self.variable(self.one(node, SOAP.hasExistential_Variable, "existential"))
            body = self.one(node, SOAP.hasExistential_Body, "existential")
            return Exists(n, var, self.formula(body, scope, path, bound=bound + (var,)))
        if SOAP.RelationAtom in types:
            rel = self.one(node, SOAP.hasRelationAtom_Relation, "relation atom")
            self.relation(rel, node)
            return Relation(n, str(rel), self.term(self.one(node, SOAP.hasRelationAtom_Subject, "relation atom"),
                                                   scope, bound, node),
                            self.term(self.one(node, SOAP.hasRelationAtom_Object, "relation atom"), scope, bound, node),
                            self.negated(node))
        if SOAP.SkuAtom in types:
            return Sku(n, self.term(self.one(node, SOAP.hasSkuAtom_Subject, "SKU atom"), scope, bound, node),
                       self.term(self.one(node, SOAP.hasSkuAtom_Object, "SKU atom"), scope, bound, node),
                       self.negated(node))
        if SOAP.ModelAtom in types:
            prop = self.one(node, SOAP.hasModelAtom_Property, "model atom")
            return Model(n, str(prop), self.term(self.one(node, SOAP.hasModelAtom_Subject, "model atom"), scope,
                                                 bound, node),
                         self.term(self.one(node, SOAP.hasModelAtom_Object, "model atom"), scope, bound, node),
                         self.negated(node))
        if SOAP.CountAtom in types:
            return self.count(node, scope, path, bound)
        if SOAP.SensorAtom in types:
            return Sensor(n, str(self.one(node, SOAP.hasSensorAtom_Check, "sensor atom")),
                          self.term(self.one(node, SOAP.hasSensorAtom_Subject, "sensor atom"), scope, bound, node),
                          self.negated(node))
        if SOAP.PredicateAtom in types:
            pred = self.one(node, SOAP.hasPredicateAtom_Predicate, "predicate atom")
            ref = self.optional(node, SOAP.hasPredicateAtom_ReferenceParameter)
            tgt = self.optional(node, SOAP.hasPredicateAtom_TargetParameter)
            return PredicateLeaf(n, str(pred), self.term(ref, scope, bound, node) if ref is not None else None,
                                 self.term(tgt, scope, bound, node) if tgt is not None else None, self.negated(node))
        where = f" (in {_short(owner)})" if owner is not None else ""
        raise _Malformed(node, f"{_short(node)}{where} is not a formula: expected a soap:Conjunction, "
                               "Disjunction, Negation, Existential or an atom")

    def count(self, node, scope: tuple, path: tuple, bound: tuple) -> Count:  # noqa: ANN001
        var = self.variable(self.one(node, SOAP.hasCountAtom_Variable, "count atom"))
        cond = self.formula(self.one(node, SOAP.hasCountAtom_Condition, "count atom"), scope, path,
                            bound=bound + (var,))
        op = str(self.one(node, SOAP.hasCountAtom_Operator, "count atom"))
        if op not in ("<", "<=", "=", ">=", ">"):
            raise _Malformed(node, f"count atom {_short(node)} has operator {op!r} (one of < <= = >= >)")
        limit = self.optional(node, SOAP.hasCountAtom_Limit)
        prop = self.optional(node, SOAP.hasCountAtom_LimitProperty)
        if (limit is None) == (prop is None):
            raise _Malformed(node, f"count atom {_short(node)} needs either hasCountAtom_Limit or "
                                   "hasCountAtom_LimitProperty")
        subject = None
        if prop is not None:
            subject = self.term(self.one(node, SOAP.hasCountAtom_LimitSubject, "count atom"), scope, bound, node)
        return Count(str(node), var, cond, op, float(limit.toPython()) if limit is not None else None,
                     str(prop) if prop is not None else None, subject, self.negated(node))

    def variable(self, node) -> Variable:  # noqa: ANN001
        if SOAP.Variable not in set(self.g.objects(node, RDF.type)):
            raise _Malformed(node, f"{_short(node)} is quantified but is not a soap:Variable")
        name = self.optional(node, SOAP.hasVariable_Name)
        cls = self.one(node, SOAP.hasVariable_Class, "variable")
        return Variable(str(node), str(name) if name is not None else _short(node), str(cls))

    def term(self, node, scope: tuple, bound: tuple, atom) -> Term:  # noqa: ANN001
        if node == SOAP.Reference or node == SOAP.Target:
            key = REFERENCE if node == SOAP.Reference else TARGET
            if key not in scope:
                raise _Malformed(atom, f"atom {_short(atom)} uses soap:{_short(node)} but its predicate has no "
                                       f"{'reference' if key == REFERENCE else 'target'} type")
            return key
        for var in bound:
            if var.node == str(node):
                return var
        if SOAP.Variable in set(self.g.objects(node, RDF.type)):
            raise _Malformed(atom, f"atom {_short(atom)} uses variable {_short(node)} outside the "
                                   "quantifier that introduces it")
        if SOAP.Parameter in set(self.g.objects(node, RDF.type)):
            return str(node)
        raise _Malformed(atom, f"atom {_short(atom)} has term {_short(node)}: expected soap:Reference, "
                               "soap:Target, a quantified soap:Variable or an action's soap:Parameter")

    # --- relations ----------------------------------------------------------------
    def relation(self, iri, atom) -> RelationExpr:  # noqa: ANN001
        key = str(iri)
        if key in self.relations:
            return self.relations[key]
        if key in self._relating:
            raise _Malformed(atom, f"relation {_short(iri)} is defined through itself")
        eq = [e for e in self.g.objects(iri, OWL.equivalentClass)]
        if not isinstance(iri, URIRef) or not eq:
            raise _Malformed(atom, f"relation {_short(iri)} is neither one of the 30 RCC8/cardinal relations "
                                   "nor a class with an owl:equivalentClass definition")
        self._relating.add(key)
        try:
            expr = self.class_expr(eq[0], atom)
        finally:
            self._relating.discard(key)
        self.relations[key] = expr
        return expr

    def class_expr(self, node, atom) -> RelationExpr:  # noqa: ANN001
        if isinstance(node, URIRef):
            return self.relation(node, atom)
        for prop, op in ((OWL.unionOf, "any"), (OWL.intersectionOf, "all")):
            head = self.g.value(node, prop)
            if head is not None:
                return RelationExpr(op, args=tuple(self.class_expr(m, atom) for m in Collection(self.g, head)))
        other = self.g.value(node, OWL.complementOf)
        if other is not None:
            return RelationExpr("not", args=(self.class_expr(other, atom),))
        raise _Malformed(atom, "a relation's owl:equivalentClass uses a class expression other than "
                               "unionOf, intersectionOf, complementOf or a named class")


def subformulas(formula: Formula) -> Iterable[Formula]:
    """``formula`` and every formula inside it (operands, bodies, count conditions)."""
    stack = [formula]
    while stack:
        f = stack.pop()
        yield f
        stack.extend(getattr(f, "operands", ()))
        stack.extend(getattr(f, attr) for attr in ("operand", "body", "condition") if hasattr(f, attr))


def variable_classes(formula: Formula) -> set[str]:
    """Classes the quantified variables of ``formula`` range over (what it searches)."""
    return {f.variable.cls for f in subformulas(formula) if isinstance(f, (Exists, Count))}
