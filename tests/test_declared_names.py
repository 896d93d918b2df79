"""Issue 28: no failure-mode, recovery-strategy or fault-kind name is keyed on in ``kb/``.

Every such name is declared once, in Turtle (``ontologies/*.ttl``): the individuals of
``soap:FailureMode``, ``soap:RecoveryStrategy`` and ``soap:FaultKind`` (and their subclasses),
named by their IRI's local name and by each literal of their ``has<Class>_Name`` properties.
Python reads them through ``kb.model``; it never spells one out. The check reads each module of
``kb/`` with :mod:`ast` and looks at its string constants (docstrings left out: they document,
they do not key) and at the attribute names read from kitkb's namespaces (``SOAP.RetryAction``
keys on a strategy as surely as ``"RetryAction"`` does). A mention that must stay is listed in
:data:`ALLOWED` with the reason; an entry no longer needed fails too, so the list only shrinks.
"""

from __future__ import annotations

import ast
import re
from pathlib import Path

import pytest
from rdflib import RDF, RDFS, Graph, Literal, URIRef

ROOT = Path(__file__).resolve().parents[1]
ONTOLOGIES = ROOT / "ontologies"
SOAP = "https://w3id.org/kitkb/soap#"
#: the classes whose individuals' names Python must not key on
DECLARING = ("FailureMode", "RecoveryStrategy", "FaultKind")
#: namespace objects of kb.core.namespaces whose attributes are IRIs of declared individuals
NAMESPACES = {"SOAP", "KD"}

#: folders not read: ``kb/world/generated/`` is written from the Turtle itself by
#: ``kitkb generate accessors`` (its enumerations are the declarations' image, regenerated on a
#: change, never edited; tests/test_sql_accessors.py keeps it equal to what the ontology gives)
GENERATED = ("kb/world/generated/",)

#: (module path relative to the repository, name) -> why the mention stays. Keep it short.
_STRATEGY_TABLE = "the one table from strategy individual to its handler (recovery.STRATEGIES)"
ALLOWED: dict[tuple[str, str], str] = {
    ("kb/execution/recovery.py", "Abort"): _STRATEGY_TABLE,
    ("kb/execution/recovery.py", "ExecuteRecoveryPlan"): _STRATEGY_TABLE,
    ("kb/execution/recovery.py", "RebindObject"): _STRATEGY_TABLE,
    ("kb/execution/recovery.py", "RejectHeldObject"): _STRATEGY_TABLE,
    ("kb/execution/recovery.py", "Replan"): _STRATEGY_TABLE,
    ("kb/execution/recovery.py", "RetryAction"): _STRATEGY_TABLE,
}


def _local(iri: str) -> str:
    return re.split(r"[#/]", iri)[-1]


def declared_names() -> dict[str, set[str]]:
    """Each declaring class -> the names of its individuals in the shipped Turtle."""
    g = Graph()
    for path in sorted(ONTOLOGIES.glob("*.ttl")):
        g.parse(path, format="turtle")
    out: dict[str, set[str]] = {}
    for cls in DECLARING:
        classes = {URIRef(SOAP + cls)}
        todo = list(classes)
        while todo:  # its subclasses, declared in any of the files
            for sub in g.subjects(RDFS.subClassOf, todo.pop()):
                if isinstance(sub, URIRef) and sub not in classes:
                    classes.add(sub)
                    todo.append(sub)
        names: set[str] = set()
        for c in classes:
            for ind in g.subjects(RDF.type, c):
                if not isinstance(ind, URIRef):
                    continue
                names.add(_local(str(ind)))
                for p, o in g.predicate_objects(ind):
                    if isinstance(o, Literal) and _local(str(p)).endswith("_Name"):
                        names.add(str(o))
        out[cls] = names
    return out


def _docstrings(tree: ast.AST) -> set[int]:
    """ids of the constant nodes that are docstrings (module, class, function)."""
    out = set()
    for node in ast.walk(tree):
        if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)):
            body = getattr(node, "body", [])
            if body and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant) \
                    and isinstance(body[0].value.value, str):
                out.add(id(body[0].value))
    return out


def _pattern(names: set[str]) -> re.Pattern[str]:
    """A name as a whole token: not part of a longer name (letters, digits, '-', '_')."""
    alts = "|".join(re.escape(n) for n in sorted(names, key=len, reverse=True))
    return re.compile(rf"(?<![A-Za-z0-9_-])(?:{alts})(?![A-Za-z0-9_-])")


def mentions(path: Path, names: set[str]) -> set[str]:
    """The declared names a module spells out: in its string constants (f-strings' literal
    parts too), docstrings left out, and as attributes of kitkb's namespace objects."""
    tree = ast.parse(path.read_text(encoding="utf-8"), str(path))
    docs = _docstrings(tree)
    pattern = _pattern(names)
    found: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Constant) and isinstance(node.value, str) and id(node) not in docs:
            found.update(pattern.findall(node.value))
        elif isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name) \
                and node.value.id in NAMESPACES and node.attr in names:
            found.add(node.attr)
    return found


def test_the_shipped_turtle_declares_names_of_each_kind() -> None:
    """The check has something to check: failure modes, the recovery strategies and the fault
    kinds are declared in the shipped Turtle (fault kinds: issue 28, point 4)."""
    names = declared_names()
    assert len(names["FailureMode"]) >= 12
    assert {"RetryAction", "Replan", "ExecuteRecoveryPlan", "Abort"} <= names["RecoveryStrategy"]
    assert names["FaultKind"], "no soap:FaultKind individual in ontologies/*.ttl (issue 28, point 4)"


def test_the_scanner_reads_code_not_comments(tmp_path: Path) -> None:
    """A name in a string constant or a namespace attribute counts; in a comment, a docstring
    or inside a longer name it does not."""
    src = tmp_path / "m.py"
    src.write_text('"""missed-grasp in a docstring."""\n'
                   "# dropped-part in a comment\n"
                   'A = "not-missed-grasp-at-all"\n'
                   'B = f"{A} missed-grasp"\n'
                   "C = SOAP.Replan\n"
                   "def f():\n    '''Abort here is a docstring.'''\n    return 'Abort'\n", encoding="utf-8")
    assert mentions(src, {"missed-grasp", "dropped-part", "Replan", "Abort"}) == {"missed-grasp", "Replan", "Abort"}


def _modules() -> list[Path]:
    return sorted(p for p in (ROOT / "kb").rglob("*.py") if "__pycache__" not in p.parts
                  and not str(p.relative_to(ROOT)).startswith(GENERATED))


def test_no_declared_name_is_keyed_on_in_kb() -> None:
    names = set().union(*declared_names().values())
    modules = _modules()
    assert len(modules) > 150  # the whole package is read
    found = {(str(p.relative_to(ROOT)), n) for p in modules for n in mentions(p, names)}
    unexplained = sorted(found - set(ALLOWED))
    assert not unexplained, "declared names spelt out in kb/ (read them through kb.model):\n" + \
        "\n".join(f"  {path}: {name!r}" for path, name in unexplained)


@pytest.mark.parametrize("entry", sorted(ALLOWED) or [None])
def test_every_allowed_mention_is_still_there_and_justified(entry: tuple[str, str] | None) -> None:
    if entry is None:
        return
    path, name = entry
    assert ALLOWED[entry].strip(), f"{entry}: no justification"
    assert name in mentions(ROOT / path, {name}), f"{entry}: no longer mentioned: drop it from ALLOWED"
