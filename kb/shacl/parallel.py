"""Share one validation between two processes: a forked child evaluates part of the shapes.

The data index is built once, in the parent; ``os.fork`` gives the child the same index
(copy-on-write) without copying or pickling it. The child evaluates the shapes that reach
SHACL-SPARQL constraints (loading the pyoxigraph store in its own background thread) plus a
share of the plain shapes, and sends its results back through a pipe; the parent evaluates
the remaining shapes meanwhile (and the caller may do other work between :meth:`Split.start`
and :meth:`Split.finish`). Results are merged per shape in the program's order, so they are
the same, in the same order, as those of one sequential pass.

Forking is used only where it is safe and worth it: where :class:`kb.core.jobs.Forked` may
fork (a POSIX system, no other thread running), at least two usable cores, and an index of
at least :data:`MIN_TRIPLES` triples. ``KITKB_SHACL_PARALLEL=0`` turns it off. If the child fails for any reason (killed,
out of memory, an exception), the parent evaluates the child's shapes itself.
"""

from __future__ import annotations

import os
from collections.abc import Callable

from kb.core.jobs import Forked, fork_is_safe, usable_cores
from kb.shacl.shape import Hit, Shape

#: Smallest index (triples, data and model) validated by two processes.
MIN_TRIPLES = 100_000

#: Share of the plain shapes' estimated cost the child takes on top of the SPARQL shapes
#: (the parent also runs the caller's work between start and finish).
CHILD_SHARE = 0.45

#: The same share when the parent has nothing else to do (a helper process that only
#: validates: the SPARQL shapes, with their store, are about as much work as the rest).
HELPER_SHARE = 0.08

Result = tuple  # a hit with its message spelled out (see :func:`_spelled`)


def can_fork(triples: int, *, min_triples: int | None = None) -> bool:
    """Is splitting a validation of ``triples`` triples between two processes safe and useful?"""
    setting = os.environ.get("KITKB_SHACL_PARALLEL", "").strip().lower()
    if setting in ("0", "no", "false", "off"):
        return False
    forced = setting in ("1", "yes", "true", "on", "force")
    if not fork_is_safe():
        return False
    if forced:
        return True
    limit = MIN_TRIPLES if min_triples is None else min_triples
    return triples >= limit and usable_cores() >= 2


def spelled(hit: Hit) -> Result:
    """A hit with its generic message made (what crosses the pipe; constraints stay home)."""
    f, path, v, src, comp, sev, msg = hit
    return f, path, v, src, comp, sev, msg if isinstance(msg, str) else msg.generic(v)


def shape_weight(shape: Shape, seen: set[int] | None = None) -> int:
    """Constraints evaluated per focus node by ``shape`` (property shapes included)."""
    seen = set() if seen is None else seen
    if id(shape) in seen:
        return 0
    seen.add(id(shape))
    w = 0
    for c in shape.constraints:
        w += 1
        if c.prop is not None:
            w += shape_weight(c.prop, seen)
    return w


def plan(costs: list[float], sparql: list[bool], share: float = CHILD_SHARE) -> set[int]:
    """Indexes of the shapes the child evaluates: all SPARQL ones, then the costliest plain
    ones until they reach ``share`` of the plain shapes' total cost."""
    child = {i for i, s in enumerate(sparql) if s}
    plain = sorted((i for i, s in enumerate(sparql) if not s), key=lambda i: -costs[i])
    budget = share * sum(costs[i] for i in plain)
    taken = 0.0
    for i in plain:
        if taken + costs[i] > budget:
            continue
        child.add(i)
        taken += costs[i]
    return child


class Split:
    """Shapes ``0..n-1``, evaluated by ``run(indexes) -> {index: hits}``, those in ``child`` by a
    forked child process."""

    def __init__(self, n: int, run: Callable[[list[int]], dict[int, list[Hit]]], child: set[int]) -> None:
        self.n = n
        self.run = run
        self.child = sorted(i for i in child if 0 <= i < n)
        self.job: Forked | None = None

    @property
    def pid(self) -> int | None:
        """The child's process id while it runs (None: no child)."""
        return self.job.pid if self.job is not None else None

    def start(self) -> None:
        """Fork the child (when there is something for it to do)."""
        if self.child:
            job = Forked(lambda: {i: [spelled(h) for h in hits] for i, hits in self.run(self.child).items()})
            self.job = job if job.started else None

    def finish(self, meanwhile: Callable[[], None] | None = None) -> list[list[Result]]:
        """Every shape's results, in shape order. The parent's shapes are evaluated now, then
        ``meanwhile`` runs (work of the caller's that fits while the child is still busy)."""
        job, self.job = self.job, None
        mine = [i for i in range(self.n) if not (job is not None and i in self.child)]
        try:
            found = {i: [spelled(h) for h in hits] for i, hits in self.run(mine).items()} if mine else {}
            if meanwhile is not None:
                meanwhile()
            ok, theirs = job.result() if job is not None else (True, {})
        finally:
            if job is not None:
                job.cancel()
        if job is not None and not (ok and isinstance(theirs, dict) and all(i in theirs for i in self.child)):
            theirs = {i: [spelled(h) for h in hits] for i, hits in self.run(self.child).items()}
        found.update(theirs)  # type: ignore[arg-type]
        return [found.get(i, []) for i in range(self.n)]
