"""docs/architecture.md stays true where a test can tell: every module that keeps an import
inside a function (of kitkb, of generators, or of a library that costs a command's start-up) is
named, with its reason, in "Imports kept inside functions, on purpose"."""

from __future__ import annotations

import ast
import re
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
#: top-level packages whose import a module may keep inside a function only for a stated reason
WATCHED = {"kb", "generators", "unified_planning", "sqlalchemy", "psycopg2", "pyshacl", "pyhornedowl",
           "dask", "distributed", "rich", "rdflib", "owlready2", "plotly", "numpy", "lxml", "pyoxigraph"}


def _section() -> str:
    text = (REPO / "docs" / "architecture.md").read_text(encoding="utf-8")
    start = text.index("## Imports kept inside functions, on purpose")
    return text[start:text.index("\n## ", start + 1)]


def _deferring_modules() -> dict[str, set[str]]:
    """Module path -> the watched packages it imports inside a function (TYPE_CHECKING blocks aside)."""
    found: dict[str, set[str]] = {}
    for path in sorted((REPO / "kb").rglob("*.py")):
        rel = path.relative_to(REPO).as_posix()
        if "/generated/" in rel:
            continue
        tree = ast.parse(path.read_text(encoding="utf-8"))
        for func in ast.walk(tree):
            if not isinstance(func, (ast.FunctionDef, ast.AsyncFunctionDef)):
                continue
            for node in ast.walk(func):
                names = ([a.name for a in node.names] if isinstance(node, ast.Import)
                         else [node.module or ""] if isinstance(node, ast.ImportFrom) and node.level == 0 else [])
                if isinstance(node, ast.Call) and getattr(node.func, "attr", None) == "import_module":
                    names = ["kb (by name: importlib)"]  # a registry importing what it finds by name
                for name in names:
                    if name.split(".")[0].split(" ")[0] in WATCHED:
                        found.setdefault(rel, set()).add(name)
    return found


def _named(section: str) -> set[str]:
    """The module paths the section names: `kb/x/y.py`, and `y.py` after a `kb/x/...` of the same item."""
    named: set[str] = set()
    for item in re.split(r"\n- ", section):
        folder = None
        for token in re.findall(r"`([A-Za-z0-9_/.]+\.py)`", item):
            if "/" in token:
                folder = token.rsplit("/", 1)[0]
                named.add(token)
            elif folder:
                named.add(f"{folder}/{token}")
    for dotted in re.findall(r"`(kb(?:\.[a-z_0-9]+)+)", section):  # `kb.core.generators`, `kb.cells.registry`
        parts = dotted.split(".")
        for cut in range(len(parts), 1, -1):
            candidate = "/".join(parts[:cut]) + ".py"
            if (REPO / candidate).exists():
                named.add(candidate)
                break
    return named


def test_every_deferred_import_is_named_in_architecture_md() -> None:
    named = _named(_section())
    unnamed = {m: sorted(v) for m, v in _deferring_modules().items() if m not in named}
    assert not unnamed, f"defer these imports with a reason in docs/architecture.md, or move them up: {unnamed}"


def test_the_section_names_no_module_that_does_not_defer() -> None:
    """A module named there that no longer defers anything: the sentence has gone stale."""
    deferring = set(_deferring_modules())
    paths = set(re.findall(r"`(kb/[A-Za-z0-9_/]+\.py)`", _section()))
    stale = sorted(m for m in paths if m not in deferring)
    assert not stale, f"docs/architecture.md names modules that import nothing inside functions: {stale}"


def test_the_check_sees_a_deferred_import() -> None:
    """The walk finds a function-level import (so the first test can fail)."""
    assert "kb/core/generators.py" in _deferring_modules() or "kb/cells/registry.py" in _deferring_modules() \
        or any(m.startswith("kb/execution/") for m in _deferring_modules())
