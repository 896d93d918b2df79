"""``kitkb generate sql|shapes|accessors``: files from the generators found by name."""

from __future__ import annotations

from kb.cli.output import Output
from kb.core.generators import get_generator


def generate_sql(dialect: str, output: str, out: Output) -> int:
    """The DDL script for ``dialect`` to ``output`` (``-``: standard output; with ``--format
    json`` the script is the object's ``ddl``)."""
    gen = get_generator("sql")(dialect=dialect)
    if output == "-":
        ddl = gen.serialize()
        if out.is_json:
            out.emit({"output": "-", "dialect": dialect, "ddl": ddl})
        else:
            out.results.write(ddl)
    else:
        gen.write(output)
        out.done(f"wrote {output} ({dialect} DDL)", output=output, dialect=dialect)
    return 0


def generate_file(generator: str, output: str, out: Output) -> int:
    """The single file of ``generator`` (built with its defaults) to ``output``."""
    with out.progress(f"generating {generator}"):
        get_generator(generator)().write(output)
    out.done(f"wrote {output} ({generator})", output=output, generator=generator)
    return 0
