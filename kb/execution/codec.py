"""One dict form per record: what a run record is as JSON data, and back, losslessly.

Every record of a run (:mod:`kb.execution.records`: the run, its actions, checks and their
atoms, failures and their sightings, each kit's score) is a dataclass; its **dict form** is
built from the dataclass's own fields and their annotations, never from a second hand-written
list of keys:

* a nested record is its dict form, a tuple and a list are JSON lists (read back as the tuple
  or list the field declares, fixed-length tuples checked), ``None`` is ``null``, and every
  field is present (a missing one is its default when it has one);
* the free-form fields (``dict[str, Any]``, ``list[dict[str, Any]]``: injected faults,
  violations, the sensor, its errors, the scene) hold **JSON data**: objects with string keys,
  lists, strings, integers, floats, booleans and null (a tuple in them is kept as a list).

What is legal, checked when a record is made or a field is set (a :class:`ValueError` naming
the field), and again when it is encoded and decoded:

* strings: any Unicode text except NUL (U+0000) and lone surrogates, which neither a
  PostgreSQL text column nor UTF-8 can hold;
* integers: signed 64 bits (not booleans); floats: finite (no NaN, no infinity: JSON has
  neither) — an integer given for a float field is that float, NumPy scalars are Python's.

Floats come back exact (JSON keeps ``repr``'s shortest exact digits), so a record equals its
:func:`decode` of :func:`encode`, and of that through :func:`dumps`/:func:`loads`.
"""

from __future__ import annotations

import dataclasses
import json
import math
import types
import typing
from typing import Any, Callable, Union

import numpy as np

_INT_MIN, _INT_MAX = -(2 ** 63), 2 ** 63 - 1


class Codec:
    """Converts one annotated type: ``norm`` (a value given to a record: checked, made
    canonical, the same object when it already is), ``enc`` (to JSON data), ``dec`` (back)."""

    def norm(self, value: Any, path: str) -> Any:
        raise NotImplementedError

    def enc(self, value: Any, path: str) -> Any:
        return self.norm(value, path)

    def dec(self, data: Any, path: str) -> Any:
        return self.norm(data, path)


def _bad(path: str, what: str, value: Any) -> ValueError:
    shown = repr(value)
    return ValueError(f"{path}: {what}, not {shown[:60] + '...' if len(shown) > 60 else shown}")


def legal_text(value: str, path: str) -> str:
    """``value`` if a database and UTF-8 can hold it (no NUL, no lone surrogate)."""
    if "\x00" in value:
        raise _bad(path, "text without NUL characters", value)
    if not value.isascii():
        try:
            value.encode("utf-8")
        except UnicodeEncodeError:
            raise _bad(path, "text without lone surrogates", value) from None
    return value


class _Str(Codec):
    def norm(self, value: Any, path: str) -> str:
        if type(value) is not str:
            if not isinstance(value, str):
                raise _bad(path, "a string", value)
            value = str(value)
        return legal_text(value, path)


class _Int(Codec):
    def norm(self, value: Any, path: str) -> int:
        if type(value) is not int:
            if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
                raise _bad(path, "an integer", value)
            value = int(value)
        if not _INT_MIN <= value <= _INT_MAX:
            raise _bad(path, "a 64-bit integer", value)
        return value


class _Float(Codec):
    def norm(self, value: Any, path: str) -> float:
        if type(value) is not float:
            if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, float, np.integer, np.floating)):
                raise _bad(path, "a number", value)
            value = float(value)
        if not math.isfinite(value):
            raise _bad(path, "a finite number", value)
        return value


class _Bool(Codec):
    def norm(self, value: Any, path: str) -> bool:
        if type(value) is not bool:
            if not isinstance(value, np.bool_):
                raise _bad(path, "true or false", value)
            value = bool(value)
        return value


class _Optional(Codec):
    def __init__(self, inner: Codec):
        self.inner = inner

    def norm(self, value: Any, path: str) -> Any:
        return None if value is None else self.inner.norm(value, path)

    def enc(self, value: Any, path: str) -> Any:
        return None if value is None else self.inner.enc(value, path)

    def dec(self, data: Any, path: str) -> Any:
        return None if data is None else self.inner.dec(data, path)


class _List(Codec):
    def __init__(self, item: Codec):
        self.item = item

    def norm(self, value: Any, path: str) -> list[Any]:
        if not isinstance(value, (list, tuple)):
            raise _bad(path, "a list", value)
        out = [self.item.norm(x, f"{path}[{i}]") for i, x in enumerate(value)]
        if type(value) is list and all(a is b for a, b in zip(out, value)):
            return value  # the caller's list, so what it appends later is the record's
        return out

    def enc(self, value: Any, path: str) -> list[Any]:
        if not isinstance(value, (list, tuple)):
            raise _bad(path, "a list", value)
        return [self.item.enc(x, f"{path}[{i}]") for i, x in enumerate(value)]

    def dec(self, data: Any, path: str) -> list[Any]:
        if not isinstance(data, list):
            raise _bad(path, "a list", data)
        return [self.item.dec(x, f"{path}[{i}]") for i, x in enumerate(data)]


class _Tuple(Codec):
    """``tuple[X, ...]`` (``items`` one codec, ``fixed`` False) or ``tuple[X, Y, Z]``."""

    def __init__(self, items: list[Codec], fixed: bool):
        self.items, self.fixed = items, fixed

    def _each(self, value: Any, path: str, how: str, kinds: tuple[type, ...]) -> tuple[Any, ...]:
        if not isinstance(value, kinds):
            raise _bad(path, "a list", value)
        if self.fixed and len(value) != len(self.items):
            raise _bad(path, f"{len(self.items)} items", value)
        codecs = self.items if self.fixed else self.items * len(value)
        return tuple(getattr(c, how)(x, f"{path}[{i}]") for i, (c, x) in enumerate(zip(codecs, value)))

    def norm(self, value: Any, path: str) -> tuple[Any, ...]:
        out = self._each(value, path, "norm", (list, tuple))
        return value if type(value) is tuple and all(a is b for a, b in zip(out, value)) else out

    def enc(self, value: Any, path: str) -> list[Any]:
        return list(self._each(value, path, "enc", (list, tuple)))

    def dec(self, data: Any, path: str) -> tuple[Any, ...]:
        return self._each(data, path, "dec", (list,))


class _Json(Codec):
    """JSON data (``Any``): a tuple becomes a list, NumPy scalars Python's."""

    def norm(self, value: Any, path: str) -> Any:
        t = type(value)
        if value is None or t is bool:
            return value
        if t is str:
            return legal_text(value, path)
        if t is int:
            return _INT.norm(value, path)
        if t is float:
            return _FLOAT.norm(value, path)
        if t is dict:
            out = {}
            for k, v in value.items():
                if type(k) is not str:
                    raise _bad(f"{path}", "an object with string keys", k)
                out[legal_text(k, path)] = self.norm(v, f"{path}.{k}")
            return value if all(out[k] is value[k] for k in value) else out
        if t is list:
            items = [self.norm(x, f"{path}[{i}]") for i, x in enumerate(value)]
            return value if all(a is b for a, b in zip(items, value)) else items
        if t is tuple:
            return [self.norm(x, f"{path}[{i}]") for i, x in enumerate(value)]
        if isinstance(value, (bool, np.bool_)):
            return bool(value)
        if isinstance(value, (int, np.integer)):
            return _INT.norm(value, path)
        if isinstance(value, (float, np.floating)):
            return _FLOAT.norm(value, path)
        if isinstance(value, str):
            return legal_text(str(value), path)
        raise _bad(path, "JSON data (object, list, string, number, true, false, null)", value)

    def enc(self, value: Any, path: str) -> Any:
        return self.norm(value, path)

    def dec(self, data: Any, path: str) -> Any:
        return self.norm(data, path)


class _Dict(Codec):
    """``dict[str, X]``."""

    def __init__(self, value: Codec):
        self.value = value

    def _each(self, value: Any, path: str, how: str) -> dict[str, Any]:
        if not isinstance(value, dict):
            raise _bad(path, "an object", value)
        out = {}
        for k, v in value.items():
            if not isinstance(k, str):
                raise _bad(path, "an object with string keys", k)
            out[legal_text(str(k), path)] = getattr(self.value, how)(v, f"{path}.{k}")
        return out

    def norm(self, value: Any, path: str) -> dict[str, Any]:
        out = self._each(value, path, "norm")
        return value if type(value) is dict and all(out[k] is value[k] for k in value) else out

    def enc(self, value: Any, path: str) -> dict[str, Any]:
        return self._each(value, path, "enc")

    def dec(self, data: Any, path: str) -> dict[str, Any]:
        return self._each(data, path, "dec")


class _Record(Codec):
    """A dataclass: its dict form, one key per field."""

    def __init__(self, cls: type):
        self.cls = cls
        self._fields: dict[str, Codec] | None = None

    @property
    def fields(self) -> dict[str, Codec]:
        if self._fields is None:  # resolved on first use: a record's annotations may name later classes
            hints = typing.get_type_hints(self.cls)
            self._fields = {f.name: codec_of(hints[f.name]) for f in dataclasses.fields(self.cls)}
        return self._fields

    def norm(self, value: Any, path: str) -> Any:
        if not isinstance(value, self.cls):
            raise _bad(path, f"a {self.cls.__name__}", value)
        return value

    def enc(self, value: Any, path: str, skip: tuple[str, ...] = ()) -> dict[str, Any]:
        self.norm(value, path)
        return {name: c.enc(getattr(value, name), f"{path}.{name}") for name, c in self.fields.items()
                if name not in skip}

    def dec(self, data: Any, path: str) -> Any:
        if not isinstance(data, dict):
            raise _bad(path, f"a {self.cls.__name__} (an object)", data)
        unknown = [k for k in data if k not in self.fields]
        if unknown:
            raise ValueError(f"{path}: a {self.cls.__name__} has no field {unknown[0]!r} "
                             f"(written by another version of kitkb?)")
        # made as the dataclass's __init__ would, without checking each value again (dec did)
        out = object.__new__(self.cls)
        for f in dataclasses.fields(self.cls):
            if f.name in data:
                value = self.fields[f.name].dec(data[f.name], f"{path}.{f.name}")
            elif f.default is not dataclasses.MISSING:
                value = f.default
            elif f.default_factory is not dataclasses.MISSING:
                value = f.default_factory()
            else:
                raise ValueError(f"{path}: a {self.cls.__name__} needs its field {f.name!r}")
            object.__setattr__(out, f.name, value)
        post = getattr(out, "__post_init__", None)
        if post is not None:
            post()
        return out


_STR, _INT, _FLOAT, _BOOL, _JSON = _Str(), _Int(), _Float(), _Bool(), _Json()
_SCALARS: dict[Any, Codec] = {str: _STR, int: _INT, float: _FLOAT, bool: _BOOL, Any: _JSON}
_CODECS: dict[Any, Codec] = {}


def codec_of(tp: Any) -> Codec:
    """The codec of an annotated type (made once per type)."""
    try:
        return _CODECS[tp]
    except (KeyError, TypeError):
        pass
    codec = _make(tp)
    try:
        _CODECS[tp] = codec
    except TypeError:
        pass
    return codec


def _make(tp: Any) -> Codec:
    if tp in _SCALARS:
        return _SCALARS[tp]
    if dataclasses.is_dataclass(tp):
        return _Record(tp)
    origin, args = typing.get_origin(tp), typing.get_args(tp)
    if origin in (Union, types.UnionType):
        rest = [a for a in args if a is not type(None)]
        if len(rest) == 1 and len(args) == 2:
            return _Optional(codec_of(rest[0]))
    elif origin is list and len(args) == 1:
        return _List(codec_of(args[0]))
    elif origin is tuple and len(args) == 2 and args[1] is Ellipsis:
        return _Tuple([codec_of(args[0])], fixed=False)
    elif origin is tuple and args:
        return _Tuple([codec_of(a) for a in args], fixed=True)
    elif origin is dict and len(args) == 2 and args[0] is str:
        return _Dict(codec_of(args[1]))
    raise TypeError(f"no dict form for the type {tp!r}")


def encode(record: Any, skip: tuple[str, ...] = ()) -> dict[str, Any]:
    """The dict form of a record (a dataclass instance): JSON data (without the fields in
    ``skip``)."""
    return _record_codec(type(record)).enc(record, type(record).__name__, skip)


def decode(cls: type, data: Any, where: str | None = None) -> Any:
    """The record of class ``cls`` from its dict form (a :class:`ValueError` naming the field
    — prefixed by ``where`` — for data that is not one)."""
    return codec_of(cls).dec(data, where or cls.__name__)


def dumps(data: Any) -> str:
    """JSON text of a dict form (ASCII, so any legal string survives any database's text)."""
    return json.dumps(data, allow_nan=False, separators=(",", ":"))


def loads(text: str) -> Any:
    """JSON data back from :func:`dumps`'s text."""
    return json.loads(text)


class Record:
    """The base of kitkb's run records: every field checked and made canonical when it is set
    (:func:`codec_of` its annotation), ``to_dict``/``from_dict`` its dict form."""

    __slots__ = ()

    def __setattr__(self, name: str, value: Any) -> None:
        c = _record_codec(type(self)).fields.get(name)
        object.__setattr__(self, name, value if c is None else c.norm(value, f"{type(self).__name__}.{name}"))

    def to_dict(self) -> dict[str, Any]:
        """The record's dict form (:mod:`kb.execution.codec`): JSON data, every field."""
        return encode(self)

    @classmethod
    def from_dict(cls, data: Any, where: str | None = None) -> Any:
        """The record back from :meth:`to_dict`'s data (a ValueError for data that is not one)."""
        return decode(cls, data, where)


def _record_codec(cls: type) -> _Record:
    codec = codec_of(cls)
    assert isinstance(codec, _Record)
    return codec


def field_codec(cls: type, name: str) -> Callable[[Any, str], Any]:
    """The encoder of one field of record class ``cls``."""
    return _record_codec(cls).fields[name].enc
