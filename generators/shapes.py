"""Shapes generator: the SHACL shapes of an OWL model as a Turtle file.

The shapes are derived by :mod:`kb.validation.shapes` (validation needs them at run time);
this generator writes them, by default those of the shipped kitting model to
``shapes/kitting-shapes.ttl``: ``python -m generators.shapes [FILE]`` or
``kitkb generate shapes -o FILE``.
"""

from __future__ import annotations

import sys
from typing import ClassVar

from rdflib import Graph

from kb.core.generators import Generator
from kb.core.resources import ontology_path, shapes_path
from kb.model.owl import OwlModel
from kb.validation.shapes import KITTING_HEADER, DerivedShapes


class ShapesGenerator(Generator):
    """Closed SHACL node shapes for every class of an OWL model (default: the shipped kitting model)."""

    name: ClassVar[str] = "shapes"
    file_extension: ClassVar[str] = ".ttl"

    def __init__(self, model: Graph | OwlModel | None = None, prefixes: dict[str, str] | None = None,
                 header: str | None = None):
        if model is None:
            model = Graph().parse(ontology_path("kitting.ttl"), format="turtle")
            header = KITTING_HEADER if header is None else header
        self.shapes = DerivedShapes(model, prefixes, header or "")

    def serialize(self) -> str:
        """The shapes as Turtle text (same model, same text)."""
        return self.shapes.turtle()

    def graph(self) -> Graph:
        """The shapes as an rdflib graph."""
        return self.shapes.graph()


def main(argv: list[str] | None = None) -> int:
    """Write shapes/kitting-shapes.ttl (or the file named as the first argument)."""
    args = sys.argv[1:] if argv is None else argv
    target = ShapesGenerator().write(args[0] if args else shapes_path("kitting-shapes.ttl"))
    print(f"wrote {target}")
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
