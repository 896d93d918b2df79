"""kitkb: a knowledge base and reasoning framework for robotic kit building.

The library is organised by what each module owns; see docs/architecture.md.
Submodules are imported on use so that the ``kitkb`` command starts quickly.
"""

__version__ = "0.1.0"
