"""``kitkb generate sql|shapes|accessors``: files from the generators found by name."""

from __future__ import annotations

from kb.cli.output import Output
from kb.core.generators import get_generator


def generate_sql(dialect: str, output: str, out: Output) -> int:
    """The DDL script for ``dialect`` to ``output`` (``-``: standard output)."""
    gen = get_generator("sql")(dialect=dialect)
    if output == "-":
        out.results.write(gen.serialize())
    else:
        gen.write(output)
        out.done(f"wrote {output} ({dialect} DDL)")
    return 0


def generate_file(generator: str, output: str, out: Output) -> int:
    """The single file of ``generator`` (built with its defaults) to ``output``."""
    get_generator(generator)().write(output)
    out.done(f"wrote {output} ({generator})")
    return 0
