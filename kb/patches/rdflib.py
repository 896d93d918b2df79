"""kitkb's change to rdflib's internals (checked on rdflib 7.6.0).

:data:`COUNTED_MEMORY`: rdflib's triple-only in-memory store (``SimpleMemory``, about twice as
fast to fill as ``Memory``) counts its triples on every ``len()``, which pySHACL and the
loader ask often; :class:`CountedMemory` caches the count between changes. That is only
right while every change goes through ``add``/``remove`` (``addN`` and the graph's methods
do, in the checked versions). Stock: ``SimpleMemory``.

Differential test: ``tests/test_patches.py`` (the same graphs and lengths with the patch off).
"""

from __future__ import annotations

from typing import Iterable

from rdflib import Graph
from rdflib.plugins.stores.memory import SimpleMemory

from kb.patches.gate import Patch

COUNTED_MEMORY = Patch("rdflib", "7.6.0", "7.7", "SimpleMemory with len() cached between changes")
PATCHES = [COUNTED_MEMORY]


class CountedMemory(SimpleMemory):
    """``SimpleMemory`` with ``len()`` cached between changes instead of counted on every call."""

    def __init__(self, *args, **kwargs):  # noqa: ANN002, ANN003
        super().__init__(*args, **kwargs)
        self._count: int | None = 0

    def add(self, triple, context, quoted=False):  # noqa: ANN001, ANN201
        self._count = None
        return super().add(triple, context, quoted)

    def remove(self, triple_pattern, context=None):  # noqa: ANN001, ANN201
        self._count = None
        return super().remove(triple_pattern, context)

    def __len__(self, context=None) -> int:  # noqa: ANN001
        if self._count is None:
            self._count = super().__len__(context)
        return self._count


def memory_graph(triples: Iterable[tuple] = ()) -> Graph:
    """An rdflib graph on a triple-only memory store, filled with ``triples`` (without the
    per-triple checks of ``Graph.add``)."""
    store = CountedMemory() if COUNTED_MEMORY.active() else SimpleMemory()
    graph = Graph(store=store)
    add = SimpleMemory.add.__get__(store)
    for triple in triples:
        add(triple, graph)
    if isinstance(store, CountedMemory):
        store._count = None
    return graph
