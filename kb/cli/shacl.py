"""``kitkb shacl DATA... -s SHAPES...``: plain SHACL validation (kb.validation.plain)."""

from __future__ import annotations

import contextlib
import json
import logging
from collections.abc import Iterator

from kb.cli.output import Output
from kb.core.files import write_atomic
from kb.validation.plain import ShaclReport, validate_files


def shacl(files: list[str], shapes: list[str], format: str, out: Output, output: str | None = None) -> int:
    """Validate the data files against the shapes files and print SHACL's report (text: a
    ``file:line`` line per result and a summary; turtle: the W3C ``sh:ValidationReport``;
    json: one object); with ``output`` the report goes to that file instead. 0 conforms, 1 not.
    The engine's warnings (shapes handed to pySHACL, a component that does not apply) are the
    command's warnings: on standard error, and in the JSON object."""
    with out.progress(f"validating {len(files)} data file(s) against {len(shapes)} shapes file(s)"), \
            _engine_warnings(out):
        report = validate_files(files, shapes, progress=out.tracker)
    text = _render(report, format, out)
    if output is None:
        print(text, end="", file=out.results)
    else:
        write_atomic(output, text)
        if format != "json":
            out.done(f"wrote {output} ({report.summary()})", output=output, conforms=report.conforms)
    return 0 if report.conforms else 1


class _ToOutput(logging.Handler):
    def __init__(self, out: Output) -> None:
        super().__init__(logging.WARNING)
        self.out = out

    def emit(self, record: logging.LogRecord) -> None:
        self.out.warn(record.getMessage())


@contextlib.contextmanager
def _engine_warnings(out: Output) -> Iterator[None]:
    """The ``kb.shacl`` logger's warnings, while the block runs, through ``out.warn``."""
    logger = logging.getLogger("kb.shacl")
    handler = _ToOutput(out)
    logger.addHandler(handler)
    propagate, logger.propagate = logger.propagate, False
    try:
        yield
    finally:
        logger.removeHandler(handler)
        logger.propagate = propagate


def _render(report: ShaclReport, format: str, out: Output) -> str:
    if format == "turtle":
        return report.turtle()
    if format == "json":
        head = {"command": out.command} if out.command else {}
        return json.dumps({**head, **report.as_dict(), "warnings": out.warnings}, indent=1) + "\n"
    lines = [d.format() for d in report.diagnostics()]
    n_data, n_shapes = len(report.data_files), len(report.shapes_files.sources)
    lines.append(f"{n_data} data file(s), {n_shapes} shapes file(s): {report.summary()}")
    if report.fallback:
        lines.append(f"(pySHACL evaluated {len(report.fallback)} shape(s) kitkb's engine does not implement)")
    return "\n".join(lines) + "\n"


__all__ = ["shacl"]
