"""Code generated from the ontologies, checked in and kept apart from hand-written modules.

:mod:`.accessors` (written by the ``accessors`` generator) is the typed SQLAlchemy model of
the world-model database; a drift test regenerates it and compares.
"""
