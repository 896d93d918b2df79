"""``kitkb validate`` and ``kitkb convert``."""

from __future__ import annotations

import json
from pathlib import Path

from kb.cli.output import Output
from kb.io.convert import OUTPUT_FORMATS, convert as convert_file
from kb.validation import default_files, validate as validate_files

_SYNTAX = {"turtle": "Turtle", "xml": "RDF/XML", "nt": "N-Triples"}


def validate(files: list[str], format: str, out: Output, ignore: list[str] | None = None,
             shapes: list[str] | None = None, domain: list[str] | None = None) -> int:
    """Print the report (text: a ``file:line`` line per problem and a summary; JSON: an
    object with ``conforms``, ``files``, ``counts`` and ``diagnostics``); 0 conforms, 1 not.
    ``ignore``: rule names (each may list several, comma-separated) left out of the report;
    ``shapes``: users' shapes files applied besides the shipped shapes; ``domain``: domain
    extensions, validated too and known to the files (their classes of objects)."""
    rules = {r.strip() for item in ignore or () for r in item.split(",") if r.strip()}
    files = files or default_files()
    with out.progress(f"validating {_files([*(domain or ()), *files])}"):
        report = validate_files(files, extra_shapes=shapes or (), ignore=rules, progress=out.tracker,
                                domain=domain or ())
    if format == "json":
        print(json.dumps(report.as_dict(), indent=2), file=out.results)
    else:
        for d in report.diagnostics:
            print(d.format(), file=out.results)
        print(f"{len(report.files)} file(s): {report.summary()}", file=out.results)
    return 0 if report.conforms else 1


def convert(input: str, output: str, out: Output) -> int:
    """Write ``input`` to ``output`` in the syntax of its extension."""
    with out.progress(f"converting {Path(input).name} to {Path(output).name}"):
        n = convert_file(Path(input), Path(output))
    syntax = _SYNTAX[OUTPUT_FORMATS[Path(output).suffix.lower()]]
    out.done(f"wrote {output} ({syntax}, {n} statements)", output=output, input=input, syntax=syntax, statements=n)
    return 0


def _files(files: list[str]) -> str:
    """``a.ttl, b.ttl (12.3 MB)`` (the first three names, and the total size)."""
    size = sum(Path(f).stat().st_size for f in files if Path(f).is_file())
    names = ", ".join(Path(f).name for f in files[:3]) + (f" and {len(files) - 3} more" if len(files) > 3 else "")
    return f"{names} ({size / 1e6:.1f} MB)"
