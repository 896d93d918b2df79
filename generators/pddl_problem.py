"""PDDL problem generator: objects, initial facts and goal from init and goal state files."""

from __future__ import annotations

from pathlib import Path
from typing import ClassVar, Sequence

from generators.base import Generator, write_text_atomic


class PddlProblemGenerator(Generator):
    """The planning problem of going from ``init`` to ``goal`` (state files of one workstation)."""

    name: ClassVar[str] = "pddl-problem"
    file_extension: ClassVar[str] = ".pddl"

    def __init__(self, init: Sequence[str | Path], goal: Sequence[str | Path], encoding: str = "strips"):
        self.init = list(init)
        self.goal = list(goal)
        self.encoding = encoding
        self._texts: tuple[str, str | None] | None = None

    def texts(self) -> tuple[str, str]:
        """Domain and problem text (both are needed together; built once)."""
        if self._texts is None:
            from generators.pddl.model import kitting_model
            from generators.pddl.writer import pddl_texts

            self._texts = pddl_texts(kitting_model(self.init, self.goal, self.encoding))
        domain, problem = self._texts
        assert problem is not None
        return domain, problem

    def serialize(self) -> str:
        """The problem as PDDL text with a comment per object naming its individual."""
        return self.texts()[1]

    def write_both(self, out_dir: str | Path) -> tuple[Path, Path]:
        """Write ``domain.pddl`` and ``problem.pddl`` into ``out_dir``."""
        domain, problem = self.texts()
        out = Path(out_dir)
        return write_text_atomic(out / "domain.pddl", domain), write_text_atomic(out / "problem.pddl", problem)
