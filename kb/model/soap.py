"""The SOAP model: the typed view of the actions, predicates and functions of SOAP instances.

The SOAP vocabulary is described in ``docs/soap.md``: a ``soap:Action`` has ordered
``soap:Parameter`` s (``hasParameter_Position``) typed by a kitting class (punned IRI), a
``soap:Precondition`` with predicate atoms (possibly negated) and function comparisons, and a
``soap:Effect`` with predicate atoms (negated = delete) and numeric effects.
:func:`read_domain` reads them into a :class:`DomainSpec`, which the planner
(:mod:`kb.planning`) turns into a planning problem. Every element keeps the IRI of the
individual it comes from (``source``), so written PDDL and plans lead back to the ontology.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable, Sequence

from rdflib import Graph, URIRef
from rdflib.namespace import OWL, RDF, RDFS

from kb.core.errors import InputError
from kb.core.namespaces import KITTING_DOMAIN_ONTOLOGY, SOAP, local_name
from kb.io.loader import KnowledgeBase, domain_knowledge

_OPS = {"Equal": "=", "Less": "<", "Greater": ">", "LessOrEqual": "<=", "GreaterOrEqual": ">="}
_NUMERIC_KINDS = {SOAP.IncreaseEffect: "increase", SOAP.DecreaseEffect: "decrease", SOAP.AssignEffect: "assign"}


@dataclass(frozen=True)
class Signature:
    """A predicate or function: name, argument types (class IRIs), source IRI."""

    name: str
    arg_types: tuple[str, ...]
    source: str


@dataclass(frozen=True)
class Atom:
    """A predicate applied to action parameters (by name); ``negated`` for not / delete."""

    predicate: str
    args: tuple[str, ...]
    negated: bool = False
    source: str = ""


@dataclass(frozen=True)
class FTerm:
    """A function applied to action parameters (by name)."""

    function: str
    args: tuple[str, ...]


@dataclass(frozen=True)
class Comparison:
    """``left op right`` with op one of < <= = >= >; right is a term or a number."""

    op: str
    left: FTerm
    right: FTerm | float
    source: str = ""


@dataclass(frozen=True)
class NumericEffect:
    """``increase``/``decrease``/``assign`` of a term by a number or another term."""

    kind: str
    term: FTerm
    amount: FTerm | float
    source: str = ""


@dataclass
class ActionSpec:
    """One SOAP action: ordered typed parameters, precondition and effect."""

    name: str
    source: str
    params: list[tuple[str, str]]  # (name, class IRI) in declared order
    pre: list[Atom] = field(default_factory=list)
    comparisons: list[Comparison] = field(default_factory=list)
    effects: list[Atom] = field(default_factory=list)
    numeric: list[NumericEffect] = field(default_factory=list)

    def param_type(self, name: str) -> str:
        """Class IRI of the parameter called ``name``."""
        return dict(self.params)[name]


@dataclass(frozen=True)
class FunctionSpec(Signature):
    """A numeric function plus how the ontology defines it.

    ``kind`` is the local name of the definition's class (``CountExpression``,
    ``DesignCountExpression``); ``counted`` the class IRI a count expression counts.
    """

    kind: str = ""
    counted: str = ""


@dataclass
class DomainSpec:
    """A planning domain read from the SOAP instances."""

    name: str
    source: str
    types: dict[str, str | None]  # class IRI -> parent class IRI (None for a root)
    predicates: dict[str, Signature]
    functions: dict[str, FunctionSpec]
    actions: list[ActionSpec]


def load_domain(domain_files: Sequence[str | Path] | None = None) -> tuple[DomainSpec, Graph]:
    """The domain of the SOAP instances in ``domain_files`` (default: the shipped
    ``kitting-domain.ttl``, with its imports), and the graph it was read from."""
    kb = domain_knowledge(domain_files)
    return read_domain(kb.graph, locate=statements(kb)), kb.graph


#: where a statement (subject, property, value; the last two may be None) is written: (file, line)
StatementLocator = Callable[..., "tuple[str | None, int | None]"]


def statements(kb: KnowledgeBase) -> StatementLocator:
    """Where a statement is written in ``kb``'s files: ``(file, line)``, else ``(None, None)``."""
    def locate(s, p=None, o=None) -> tuple[str | None, int | None]:  # noqa: ANN001
        found = kb.source_of(s, p, o) or (kb.source_of(s) if p is not None else None)
        return (str(found[0].path), found[1]) if found else (None, None)
    return locate


def read_domain(graph: Graph, name: str = "kitting-domain", locate: StatementLocator | None = None) -> DomainSpec:
    """The domain stated by the ``soap:Action`` individuals of ``graph``; a malformed one is an
    InputError at its file and line when ``locate`` (:func:`statements`) says where it is."""
    reader = _Reader(graph, locate)
    actions = sorted(graph.subjects(RDF.type, SOAP.Action), key=str)
    if not actions:
        raise InputError("no soap:Action individuals found: is kitting-domain.ttl loaded?")
    specs = [reader.action(a) for a in actions]
    specs.sort(key=lambda a: a.name)
    return DomainSpec(name, KITTING_DOMAIN_ONTOLOGY, reader.type_tree(), reader.predicates,
                      reader.functions, specs)


class _Reader:
    def __init__(self, graph: Graph, locate: StatementLocator | None = None):
        self.g = graph
        self.locate = locate or (lambda s, p=None, o=None: (None, None))
        self.predicates: dict[str, Signature] = {}
        self.functions: dict[str, FunctionSpec] = {}
        self.used_types: set[str] = set()

    # --- helpers --------------------------------------------------------------------
    def one(self, s, p, what: str):  # noqa: ANN001, ANN201
        value = self.g.value(s, p)
        if value is None:
            raise InputError(f"{local_name(s)}: missing {local_name(p)} ({what})", *self.locate(s))
        return value

    def named(self, atom, prop, cls, name_prop, what: str, action: str):  # noqa: ANN001, ANN201
        """The ``cls`` individual an atom or term names by ``prop``: an InputError at that
        statement when it names something that is not one (no ``name_prop``: undefined)."""
        node = self.one(atom, prop, what)
        if self.g.value(node, name_prop) is None:
            raise InputError(f"action {action}: {local_name(atom)} names {local_name(node)}, which is not a "
                             f"soap:{local_name(cls)} of the domain (no {local_name(name_prop)}: undefined or "
                             "misspelt?)", *self.locate(atom, prop, node))
        return node

    def types_of(self, node) -> set:  # noqa: ANN001
        return set(self.g.objects(node, RDF.type))

    # --- signatures -----------------------------------------------------------------
    def signature_types(self, node, ref, target) -> tuple[str, ...]:  # noqa: ANN001
        types = tuple(str(t) for t in (self.g.value(node, ref), self.g.value(node, target)) if t is not None)
        self.used_types.update(types)
        return types

    def predicate(self, node) -> str:  # noqa: ANN001
        name = str(self.one(node, SOAP.hasPredicate_Name, "predicate name"))
        if name not in self.predicates:
            types = self.signature_types(node, SOAP.hasPredicate_ReferenceType, SOAP.hasPredicate_TargetType)
            self.predicates[name] = Signature(name, types, str(node))
        return name

    def function(self, node) -> str:  # noqa: ANN001
        name = str(self.one(node, SOAP.hasFunction_Name, "function name"))
        if name not in self.functions:
            types = self.signature_types(node, SOAP.hasFunction_ReferenceType, SOAP.hasFunction_TargetType)
            definition = self.g.value(node, SOAP.hasFunction_Definition)
            kind, counted = "", ""
            if definition is not None:
                kinds = sorted(local_name(t) for t in self.types_of(definition) if t != OWL.NamedIndividual)
                kind = kinds[0] if kinds else ""
                var = self.g.value(definition, SOAP.hasCountExpression_Variable)
                cls = self.g.value(var, SOAP.hasVariable_Class) if var is not None else None
                counted = str(cls) if cls is not None else ""
            self.functions[name] = FunctionSpec(name, types, str(node), kind=kind, counted=counted)
        return name

    # --- actions --------------------------------------------------------------------
    def action(self, node) -> ActionSpec:  # noqa: ANN001
        name = str(self.one(node, SOAP.hasAction_Name, "action name"))
        params = sorted(self.g.objects(node, SOAP.hasAction_Parameter),
                        key=lambda p: int(self.one(p, SOAP.hasParameter_Position, "parameter position")))
        names = {p: str(self.one(p, SOAP.hasParameter_Name, "parameter name")) for p in params}
        typed = []
        for p in params:
            cls = str(self.one(p, SOAP.hasParameter_Type, "parameter type"))
            self.used_types.add(cls)
            typed.append((names[p], cls))
        spec = ActionSpec(name, str(node), typed)
        pre = self.g.value(node, SOAP.hasAction_Precondition)
        eff = self.g.value(node, SOAP.hasAction_Effect)
        if pre is not None:
            spec.pre = self.atoms(pre, SOAP.hasPrecondition_PredicateAtom, names, name)
            spec.comparisons = [self.comparison(c, names, name)
                                for c in sorted(self.g.objects(pre, SOAP.hasPrecondition_FunctionComparison), key=str)]
        if eff is not None:
            spec.effects = self.atoms(eff, SOAP.hasEffect_PredicateAtom, names, name)
            spec.numeric = [self.numeric(n, names, name)
                            for n in sorted(self.g.objects(eff, SOAP.hasEffect_NumericEffect), key=str)]
        return spec

    def args(self, node, ref, target, names: dict, action: str) -> tuple[str, ...]:  # noqa: ANN001
        out = []
        for prop in (ref, target):
            term = self.g.value(node, prop)
            if term is None:
                continue
            if term not in names:
                raise InputError(f"action {action}: {local_name(node)} refers to {local_name(term)}, "
                                 "which is not one of the action's parameters", *self.locate(node, prop, term))
            out.append(names[term])
        return tuple(out)

    def atoms(self, holder, prop, names: dict, action: str) -> list[Atom]:  # noqa: ANN001
        out = []
        for atom in sorted(self.g.objects(holder, prop), key=str):
            pred = self.predicate(self.named(atom, SOAP.hasPredicateAtom_Predicate, SOAP.Predicate,
                                             SOAP.hasPredicate_Name, "predicate", action))
            args = self.args(atom, SOAP.hasPredicateAtom_ReferenceParameter,
                             SOAP.hasPredicateAtom_TargetParameter, names, action)
            negated = bool(self.g.value(atom, SOAP.hasAtom_IsNegated, default=False).toPython()) \
                if self.g.value(atom, SOAP.hasAtom_IsNegated) is not None else False
            out.append(Atom(pred, args, negated, str(atom)))
        return out

    def term(self, node, names: dict, action: str) -> FTerm:  # noqa: ANN001
        fn = self.function(self.named(node, SOAP.hasFunctionTerm_Function, SOAP.Function, SOAP.hasFunction_Name,
                                      "function", action))
        return FTerm(fn, self.args(node, SOAP.hasFunctionTerm_ReferenceParameter,
                                   SOAP.hasFunctionTerm_TargetParameter, names, action))

    def comparison(self, node, names: dict, action: str) -> Comparison:  # noqa: ANN001
        kinds = [local_name(t) for t in self.types_of(node)]
        op = next((_OPS[k.removeprefix("FunctionToFunction").removeprefix("FunctionToDecimal")]
                   for k in kinds if k.removeprefix("FunctionToFunction").removeprefix("FunctionToDecimal") in _OPS
                   and k.startswith("FunctionTo")), None)
        if op is None:
            raise InputError(f"action {action}: comparison {local_name(node)} has no operator class", *self.locate(node))
        left = self.term(self.one(node, SOAP.hasFunctionComparison_FirstOperand, "first operand"), names, action)
        second = self.g.value(node, SOAP.hasFunctionToFunction_SecondOperand)
        if second is not None:
            right: FTerm | float = self.term(second, names, action)
        else:
            right = float(self.one(node, SOAP.hasFunctionToDecimal_SecondOperand, "second operand").toPython())
        return Comparison(op, left, right, str(node))

    def numeric(self, node, names: dict, action: str) -> NumericEffect:  # noqa: ANN001
        kind = next((k for t, k in _NUMERIC_KINDS.items() if t in self.types_of(node)), None)
        if kind is None:
            raise InputError(f"action {action}: numeric effect {local_name(node)} is not an "
                             "Increase/Decrease/AssignEffect", *self.locate(node))
        term = self.term(self.one(node, SOAP.hasNumericEffect_Function, "function term"), names, action)
        amount_fn = self.g.value(node, SOAP.hasNumericEffect_AmountFunction)
        amount: FTerm | float = (self.term(amount_fn, names, action) if amount_fn is not None
                                 else float(self.one(node, SOAP.hasNumericEffect_Amount, "amount").toPython()))
        return NumericEffect(kind, term, amount, str(node))

    # --- types ----------------------------------------------------------------------
    def parent(self, cls: str) -> str | None:
        parents = sorted(str(p) for p in self.g.objects(URIRef(cls), RDFS.subClassOf)
                         if isinstance(p, URIRef) and p != OWL.Thing)
        return parents[0] if parents else None

    def type_tree(self) -> dict[str, str | None]:
        """The used classes and all their named ancestors, child -> parent."""
        tree: dict[str, str | None] = {}
        todo = sorted(self.used_types)
        while todo:
            cls = todo.pop()
            if cls in tree:
                continue
            tree[cls] = self.parent(cls)
            if tree[cls] is not None:
                todo.append(tree[cls])
        return dict(sorted(tree.items()))
