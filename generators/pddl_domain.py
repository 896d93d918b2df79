"""PDDL domain generator: the SOAP kitting actions as a PDDL domain (via unified-planning)."""

from __future__ import annotations

from pathlib import Path
from typing import ClassVar, Sequence

from generators.base import Generator


class PddlDomainGenerator(Generator):
    """The planning domain of ``kitting-domain.ttl`` in the ``strips`` or ``numeric`` encoding."""

    name: ClassVar[str] = "pddl-domain"
    file_extension: ClassVar[str] = ".pddl"

    def __init__(self, encoding: str = "strips", domain_files: Sequence[str | Path] | None = None):
        self.encoding = encoding
        self.domain_files = domain_files

    def serialize(self) -> str:
        """The domain as PDDL text with source comments."""
        from generators.pddl.model import domain_model
        from generators.pddl.writer import pddl_texts

        return pddl_texts(domain_model(self.encoding, self.domain_files))[0]
