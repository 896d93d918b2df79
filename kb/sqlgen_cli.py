"""Library side of ``kitkb generate sql`` and ``kitkb db load/dump`` (the CLI only parses arguments)."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path


def generate_sql(args: argparse.Namespace) -> int:
    """Write the DDL script of the shipped ontologies for ``args.dialect`` to ``args.output`` ("-": stdout)."""
    from generators.sql import SqlGenerator

    gen = SqlGenerator(dialect=getattr(args, "dialect", None) or "sqlite")
    output = getattr(args, "output", None)
    if output in (None, "-"):
        sys.stdout.write(gen.serialize())
    else:
        _write(gen, Path(output))
    return 0


def generate_accessors(args: argparse.Namespace) -> int:
    """Write the typed accessors module to ``args.output``."""
    from generators.accessors import AccessorsGenerator

    _write(AccessorsGenerator(), Path(args.output))
    return 0


def _write(gen: object, path: Path) -> None:
    from kb.errors import InputError

    try:
        gen.write(path)  # type: ignore[attr-defined]
    except OSError as exc:
        raise InputError(f"cannot write: {exc.strerror or exc}", file=path) from None


def db_load(args: argparse.Namespace) -> int:
    """``kitkb db load DATAFILE --db URL``: replace the database content with the file's statements."""
    from kb.db import load

    report = load(args.datafile, args.db)
    print(f"kitkb: loaded {args.datafile}: {report.summary()}")
    return 0


def db_dump(args: argparse.Namespace) -> int:
    """``kitkb db dump --db URL -o FILE.ttl``: write the database as Turtle."""
    from kb.db import dump

    dump(args.db, args.output)
    return 0
