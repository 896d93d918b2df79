"""kitkb: a knowledge base and reasoning framework for robotic kit building.

One package per concern, in layers that only import downwards (docs/architecture.md):
``core`` < ``patches`` < ``io`` < ``model`` < ``shacl``, ``scenario``, ``spatial`` <
``planning``, ``validation``, ``world`` < ``cli``. The emitters of derived files live in the
separate ``generators`` package, which kb finds by name and never imports.
"""

__version__ = "0.1.0"
