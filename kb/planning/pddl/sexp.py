"""PDDL text as s-expressions that remember their lines, and back to text.

PDDL is case-insensitive: symbols are kept in lower case (:class:`Sym` keeps the spelling
of the file in ``written`` for messages). A comment runs from ``;`` to the end of its line.
:func:`parse` is iterative, so nesting is bounded by :data:`kb.core.limits.NESTING`, not by
Python's stack; :func:`render` writes a tree back as text with a map from each output line
to the source line it came from, so an error another reader finds in the text is reported
at the line of the file.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Iterable, Union

from kb.core.errors import InputError
from kb.core.limits import NESTING

_TOKEN = re.compile(r"[()]|[^\s();]+|;[^\n]*|\n")


class Sym(str):
    """A symbol (name, variable, number, keyword) in lower case, with its line (0: made by kitkb)."""

    line: int
    written: str

    def __new__(cls, text: str, line: int = 0, written: str | None = None) -> "Sym":
        sym = super().__new__(cls, text.lower())
        sym.line = line
        sym.written = written if written is not None else text
        return sym


class Expr(list):
    """A parenthesised list of :data:`Node`, with the line of its opening parenthesis."""

    line: int

    def __init__(self, items: Iterable["Node"] = (), line: int = 0) -> None:
        super().__init__(items)
        self.line = line

    @property
    def head(self) -> str:
        """The first symbol ("" for an empty list or one that starts with a list)."""
        return self[0] if self and isinstance(self[0], Sym) else ""


Node = Union[Sym, Expr]


def sym(text: str, like: Node | int = 0) -> Sym:
    """A symbol made by kitkb, placed at the line of ``like`` (a node or a line number)."""
    return Sym(text, like if isinstance(like, int) else like.line)


def expr(items: Iterable[Node | str], like: Node | int = 0) -> Expr:
    """A list made by kitkb (plain strings become symbols), at the line of ``like``."""
    line = like if isinstance(like, int) else like.line
    return Expr((sym(i, line) if not isinstance(i, (Sym, Expr)) else i for i in items), line)


def parse(text: str, path: str | Path) -> Expr:
    """The one top-level list of a PDDL file (``(define ...)``); InputError at the line of
    an unbalanced parenthesis, text outside it, or nesting past the limit."""
    line = 1
    stack: list[Expr] = []
    top: list[Node] = []
    limit = NESTING.value()
    for match in _TOKEN.finditer(text):
        token = match.group()
        if token == "\n":
            line += 1
        elif token[0] == ";":
            continue
        elif token == "(":
            stack.append(Expr(line=line))
            if limit is not None and len(stack) > limit:
                raise NESTING.error(len(stack), path, line, f"parentheses nested {len(stack):,} deep")
        elif token == ")":
            if not stack:
                raise InputError("')' closes nothing", path, line)
            done = stack.pop()
            (stack[-1] if stack else top).append(done)
        else:
            (stack[-1] if stack else top).append(Sym(token, line))
    if stack:
        raise InputError("'(' is never closed (the file ends first)", path, stack[-1].line)
    if not top:
        raise InputError("no PDDL here (expected '(define ...)')", path, None)
    if len(top) > 1:
        extra = top[1]
        raise InputError(f"text after the end of '(define ...)': {show(extra)}", path, extra.line)
    if not isinstance(top[0], Expr):
        raise InputError(f"expected '(define ...)', found {top[0].written!r}", path, top[0].line)
    return top[0]


def show(node: Node, limit: int = 60) -> str:
    """``node`` as PDDL text for a message, cut at ``limit`` characters."""
    text = node.written if isinstance(node, Sym) else _flat(node)
    return text if len(text) <= limit else text[: limit - 3] + "..."


def _flat(node: Node) -> str:
    if isinstance(node, Sym):
        return node.written
    return "(" + " ".join(_flat(n) for n in node) + ")"


class Rendered:
    """Text written from nodes, and the source line of each of its lines."""

    def __init__(self) -> None:
        self._lines: list[list[str]] = [[]]
        self.source: list[int] = [0]  # source line of output line i + 1

    def write(self, nodes: Iterable[Node]) -> "Rendered":
        """Append ``nodes``, each opening list or symbol starting a new output line when its
        source line differs from the current line's."""
        stack: list[tuple[Iterable[Node], bool]] = [(iter(nodes), False)]
        while stack:
            items, closing = stack[-1]
            node = next(items, None)  # type: ignore[call-overload]
            if node is None:
                stack.pop()
                if closing:
                    self._lines[-1].append(")")
                continue
            self._place(node.line)
            if isinstance(node, Sym):
                self._lines[-1].append(str(node))
            else:
                self._lines[-1].append("(")
                stack.append((iter(node), True))
        return self

    def _place(self, line: int) -> None:
        if line and line != self.source[-1]:
            if self._lines[-1]:
                self._lines.append([])
                self.source.append(line)
            else:
                self.source[-1] = line

    def text(self) -> str:
        """The text, one output line per source line reached."""
        return "\n".join(_join(parts) for parts in self._lines) + "\n"

    def line_of(self, output_line: int) -> int | None:
        """The source line of ``output_line`` (1-based), or None if it is not known."""
        if 1 <= output_line <= len(self.source):
            for i in range(output_line - 1, -1, -1):
                if self.source[i]:
                    return self.source[i]
        return None


def _join(parts: list[str]) -> str:
    out: list[str] = []
    for part in parts:
        if out and part != ")" and out[-1] != "(":
            out.append(" ")
        out.append(part)
    return "".join(out)
