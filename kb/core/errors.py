"""One exception root for kitkb; the CLI prints any of them as one line."""

from __future__ import annotations

from pathlib import Path


class KitkbError(Exception):
    """Root of every error kitkb raises on purpose.

    ``exit_code`` is what the command line exits with when this error ends a command.
    """

    exit_code = 2


class InputError(KitkbError):
    """Unusable input: a missing file, a syntax error, an unknown name.

    Formats as ``file:line: error: message`` (or ``file: error: message`` with no line).
    """

    def __init__(self, message: str, file: str | Path | None = None, line: int | None = None):
        super().__init__(message)
        self.message = message
        self.file = str(file) if file is not None else None
        self.line = line

    def __str__(self) -> str:
        where = self.file or ""
        if where and self.line:
            where = f"{where}:{self.line}"
        return f"{where}: error: {self.message}" if where else f"error: {self.message}"


class ConfigurationError(KitkbError):
    """Something kitkb needs is missing from this machine (a planner, Java, a driver)."""


class NotSolvableError(KitkbError):
    """A well-formed problem with no answer (no plan); exit code 1."""

    exit_code = 1


class CellError(KitkbError):
    """A workcell that cannot be reached, or that answered outside the cell protocol
    (:mod:`kb.crcl.wire`); exit code 2, as an address that names no working cell is an
    unusable input, not a fault of kitkb.

    Formats as ``host:port: error: message`` (``error: message`` with no address).
    """

    def __init__(self, message: str, address: str | None = None):
        super().__init__(message)
        self.message = message
        self.address = address

    def __str__(self) -> str:
        return f"{self.address}: error: {self.message}" if self.address else f"error: {self.message}"
