"""Literals in the world-model database: parse into column values, check, print back.

A literal is stored as a Python value of its column's kind (``decimal`` columns hold floats).
:func:`canonical` is the literal written back for a stored value; :mod:`kb.world.database` keeps the
original spelling of any literal that is not canonical.
"""

from __future__ import annotations

import datetime as _dt
import math
from decimal import Decimal, InvalidOperation
from typing import Any, Callable

from rdflib import XSD, Literal, URIRef

Check = tuple[Callable[[Any], bool], str]


class ValueProblem(ValueError):
    """A literal that the column cannot hold (bad lexical form, outside the datatype)."""


def to_sql(lit: Literal, info: dict[str, Any],
           checks: tuple[Check, ...] = ()) -> Any:
    """The value a literal is stored as in a column described by ``info`` (``checks``: its CHECKs)."""
    value = parse_lexical(info.get("value", "text"), str(lit))
    check_value(value, checks)
    return value


def parse_lexical(kind: str, lex: str) -> Any:
    """The column value of lexical form ``lex`` for a column of value kind ``kind``."""
    try:
        return _PARSE[kind](lex)
    except (ValueError, InvalidOperation, TypeError, ArithmeticError):
        raise ValueProblem(f"{lex!r} is not a valid {kind} value") from None


def check_value(value: Any, checks: tuple[Check, ...]) -> None:
    """ValueProblem if ``value`` breaks one of the column's CHECKs."""
    for ok, text in checks:
        if not ok(value):
            raise ValueProblem(f"{value!r} violates {text}")


def _parse_bool(lex: str) -> bool:
    text = lex.strip()
    if text in ("true", "1"):
        return True
    if text in ("false", "0"):
        return False
    raise ValueError(lex)


def _parse_decimal(lex: str) -> float:
    try:
        value = float(lex)  # the same float as float(Decimal(lex)): both round correctly
    except ValueError:
        value = float(Decimal(lex.strip()))
    if not math.isfinite(value):
        raise ValueError(lex)
    return value


def _parse_datetime(lex: str) -> _dt.datetime:
    value = Literal(lex.strip(), datatype=XSD.dateTime).value
    if not isinstance(value, _dt.datetime):
        raise ValueError(lex)
    return _naive_utc(value)


def _naive_utc(value: _dt.datetime) -> _dt.datetime:
    if value.tzinfo is not None:
        value = value.astimezone(_dt.timezone.utc).replace(tzinfo=None)
    return value


def _parse_date(lex: str) -> _dt.date:
    value = Literal(lex.strip(), datatype=XSD.date).value
    if not isinstance(value, _dt.date):
        raise ValueError(lex)
    return value


_PARSE: dict[str, Callable[[str], Any]] = {
    "text": str, "iri": str, "boolean": _parse_bool, "integer": lambda s: int(s.strip()),
    "decimal": _parse_decimal, "float": lambda s: float(s.strip().replace("INF", "inf")),
    "datetime": _parse_datetime, "date": _parse_date,
}


def check_spec(ck: Any) -> tuple[str, str, Any, str] | tuple[()]:
    """``(column, operator, bound, text)`` of a CHECK constraint kitkb can test in Python
    (``>``, ``>=``, ``<``, ``<=`` a number, ``in`` an enumeration), else ``()``."""
    from sqlalchemy.sql import operators
    from sqlalchemy.sql.elements import BinaryExpression

    expr = getattr(ck, "sqltext", None)
    if not isinstance(expr, BinaryExpression):
        return ()
    name = getattr(expr.left, "name", None)
    right = getattr(expr.right, "value", None)
    if name is None:
        return ()
    if expr.operator is operators.in_op:
        allowed = set(getattr(expr.right, "value", None) or [v.value for v in getattr(expr.right, "clauses", [])])
        return name, "in", frozenset(allowed), f"the enumeration {sorted(allowed)}"
    ops = {operators.gt: ">", operators.ge: ">=", operators.lt: "<", operators.le: "<="}
    if expr.operator in ops and right is not None:
        return name, ops[expr.operator], right, f"{name} {ops[expr.operator]} {right}"
    return ()


_TESTS: dict[str, Callable[[Any, Any], bool]] = {
    "in": lambda v, b: v in b, ">": lambda v, b: v > b, ">=": lambda v, b: v >= b,
    "<": lambda v, b: v < b, "<=": lambda v, b: v <= b,
}


def make_check(op: str, bound: Any, text: str) -> Check:
    """The :data:`Check` of a :func:`check_spec`."""
    test = _TESTS[op]
    return (lambda v: test(v, bound)), text


_DEFAULT_TYPE = {"boolean": str(XSD.boolean), "integer": str(XSD.integer), "decimal": str(XSD.decimal),
                 "float": str(XSD.double), "datetime": str(XSD.dateTime), "date": str(XSD.date)}


def datatype_of(info: dict[str, Any]) -> str | None:
    """The datatype IRI of the canonical literals of a column (None: plain strings)."""
    return info.get("datatype") or _DEFAULT_TYPE.get(info.get("value", "text"))


def canonical(value: Any, info: dict[str, Any]) -> tuple[str, str | None]:
    """(lexical form, datatype IRI) of the canonical literal of a stored value."""
    kind = info.get("value", "text")
    dt = datatype_of(info)
    if kind == "boolean":
        return ("true" if value else "false"), dt
    if kind == "integer":
        return str(int(value)), dt
    if kind == "decimal":
        return decimal_text(value), dt
    if kind == "float":
        return repr(float(value)), dt
    if kind == "datetime":
        if isinstance(value, str):
            value = _dt.datetime.fromisoformat(value)
        return _naive_utc(value).isoformat() + "Z", dt
    if kind == "date":
        return value.isoformat(), dt
    return str(value), dt


def decimal_text(value: float) -> str:
    """The canonical ``xsd:decimal`` form of a stored float: its shortest repr, in fixed point."""
    text = repr(float(value))
    if "e" in text or "n" in text:  # exponent (or inf/nan, which are never stored)
        text = format(Decimal(text), "f")
        if "." not in text:
            text += ".0"
    return text


def is_canonical_parts(lex: str, datatype: str | None, lang: str | None, value: Any, info: dict[str, Any]) -> bool:
    """:func:`is_canonical` of a literal given by its parts (datatype None for plain strings)."""
    if lang is not None:
        return False
    text, dt = canonical(value, info)
    return lex == text and datatype == dt


def is_canonical(lit: Literal, value: Any, info: dict[str, Any]) -> bool:
    """True when ``lit`` is exactly the literal :func:`to_rdf` writes for ``value``."""
    if lit.language is not None:
        return False
    lex, dt = canonical(value, info)
    return str(lit) == lex and (str(lit.datatype) if lit.datatype is not None else None) == dt


def to_rdf(value: Any, info: dict[str, Any]) -> Literal:
    """The canonical literal of a stored value (what :func:`dump` writes by default)."""
    lex, dt = canonical(value, info)
    return Literal(lex, datatype=URIRef(dt) if dt else None)


def from_db(value: Any, info: dict[str, Any]) -> Any:
    """A value as read from the database, in the form :func:`to_sql` produces."""
    kind = info.get("value", "text")
    if value is None:
        return None
    if kind == "decimal":
        return float(value)
    if kind == "datetime":
        if isinstance(value, str):
            value = _dt.datetime.fromisoformat(value)
        return _naive_utc(value)
    if kind == "date" and isinstance(value, str):
        return _dt.date.fromisoformat(value)
    if kind == "boolean":
        return bool(value)
    return value
