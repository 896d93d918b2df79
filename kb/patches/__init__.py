"""Changes kitkb makes to other libraries' internals for speed, one module per library.

Each change is a :class:`kb.patches.gate.Patch`: the library, the versions it was checked
on, and what it does. It applies only while the installed version is in that range and
``KITKB_PATCHES=0`` is not set; otherwise kitkb runs the library's stock code, slower but
with the same results. Differential tests (``tests/test_patches.py`` and those named in each
module) compare both paths on the versions locked in ``constraints.txt``.

- :mod:`kb.patches.unified_planning`: a lean import (no ConfigSpace/scipy), plan-validator
  fast paths, a problem class that keeps its kind and an object index;
- :mod:`kb.patches.sqlalchemy`: DDL that leaves the shared metadata as it found it;
- :mod:`kb.patches.rdflib`: an in-memory store that counts its triples once.
"""
