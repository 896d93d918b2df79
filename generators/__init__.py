"""Emitters of the files kitkb derives from the ontologies: one module per target.

``pddl`` (PDDL domain and problem), ``sql`` (DDL per dialect), ``accessors`` (the typed ORM
module of the world-model database) and ``shapes`` (the SHACL shapes of the kitting model).
Each is a :class:`kb.core.generators.Generator`, found by name through kb's registry
(:func:`kb.core.generators.get_generator`); this package imports kb, and kb never imports it.
``sql_model`` is the relational model the ``sql`` and ``accessors`` targets share.
"""
