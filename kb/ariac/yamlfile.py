"""A YAML file read with the line of every value, so that a bad trial is reported at ``file:line``.

PyYAML composes the file into nodes (libyaml's C parser when PyYAML was built with it); the
nodes are turned into :class:`YMap` / :class:`YList` (a ``dict`` / ``list`` that also knows its
own line and each member's line) and plain scalars (PyYAML's safe constructor: ``true``, numbers,
strings). A syntax error, an alias bomb or a duplicate key is an :class:`~kb.core.errors.InputError`
naming the file and line.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import yaml

from kb.core import limits
from kb.core.errors import InputError

try:  # the C parser (libyaml) when PyYAML has it: 5-10x faster
    from yaml import CSafeLoader as _Loader
except ImportError:  # pragma: no cover - PyYAML built without libyaml
    from yaml import SafeLoader as _Loader  # type: ignore[assignment]

MAX_NODES = 200_000  # a trial file has hundreds; aliases could multiply them (a "billion laughs")


class YMap(dict):
    """A YAML mapping: a dict with ``line`` (its own, 1-based) and ``lines`` (each key's)."""

    line: int
    lines: dict[Any, int]


class YList(list):
    """A YAML sequence: a list with ``line`` and ``lines`` (each item's, by index)."""

    line: int
    lines: list[int]


def line_of(value: Any, key: Any = None, default: int | None = None) -> int | None:
    """The line of ``value`` (a YMap or YList), or of its member ``key`` when given."""
    if key is not None and isinstance(value, (YMap, YList)):
        try:
            return value.lines[key]
        except (KeyError, IndexError, TypeError):
            pass
    return getattr(value, "line", default)


def load(path: str | Path) -> Any:
    """The document of the YAML file ``path`` (one document; empty file: None)."""
    path = Path(path)
    try:
        limits.check_file_size(path)
        text = path.read_text(encoding="utf-8")
    except UnicodeDecodeError as e:
        raise InputError(f"not UTF-8 text ({e.reason} at byte {e.start})", file=path) from None
    except OSError as e:
        raise InputError(f"cannot read: {e.strerror}", file=path) from None
    return loads(text, path)


def loads(text: str, path: str | Path = "<string>") -> Any:
    """The document of YAML ``text`` (``path`` names it in errors)."""
    loader = _Loader(text)
    try:
        node = loader.get_single_node()
    except yaml.MarkedYAMLError as e:
        mark = e.problem_mark or e.context_mark
        line = mark.line + 1 if mark is not None else None
        raise InputError(f"not YAML: {e.problem or e.context}", file=path, line=line) from None
    except yaml.YAMLError as e:
        raise InputError(f"not YAML: {e}", file=path) from None
    finally:
        loader.dispose()
    if node is None:
        return None
    return _Builder(path).build(node)


class _Builder:
    def __init__(self, path: str | Path) -> None:
        self.path = path
        self.count = 0
        self.scalars = yaml.SafeLoader("")

    def fail(self, node: yaml.Node, message: str) -> InputError:
        return InputError(message, file=self.path, line=node.start_mark.line + 1)

    def build(self, node: yaml.Node) -> Any:
        self.count += 1
        if self.count > MAX_NODES:
            raise self.fail(node, f"more than {MAX_NODES:,} YAML values (aliases repeated?): not a trial file")
        if isinstance(node, yaml.MappingNode):
            return self._mapping(node)
        if isinstance(node, yaml.SequenceNode):
            out = YList(self.build(item) for item in node.value)
            out.line, out.lines = node.start_mark.line + 1, [item.start_mark.line + 1 for item in node.value]
            return out
        try:
            return self.scalars.construct_object(node, deep=True)
        except yaml.YAMLError as e:
            raise self.fail(node, f"bad YAML value: {getattr(e, 'problem', e)}") from None

    def _mapping(self, node: yaml.MappingNode) -> YMap:
        out = YMap()
        out.line, out.lines = node.start_mark.line + 1, {}
        for key_node, value_node in node.value:
            if key_node.tag == "tag:yaml.org,2002:merge":
                raise self.fail(key_node, "YAML merge keys (<<) are not used in trial files")
            key = self.build(key_node)
            if isinstance(key, (dict, list)):
                raise self.fail(key_node, "a mapping key must be a plain value")
            if key in out:
                raise self.fail(key_node, f"key {key!r} given twice (first at line {out.lines[key]})")
            out[key] = self.build(value_node)
            out.lines[key] = key_node.start_mark.line + 1
        return out
