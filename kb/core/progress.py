"""Progress of long work as the library reports it: a small protocol that the command line fills.

A library function that may run for seconds takes ``progress: Progress = SILENT`` and says what
it is doing through it::

    with progress.task("reading init.ttl", total=size, unit="bytes") as task:
        for chunk in chunks:
            task.advance(len(chunk))

:data:`SILENT` does nothing and says so (``enabled`` is False), so a hot loop can skip even the
counting (:func:`counted` returns its items untouched then). The library never imports a
display: ``kitkb`` passes one (:mod:`kb.cli.progress`, over rich) only when standard error is a
terminal.

A display may refresh itself from a thread. :class:`kb.core.jobs.Forked` forks only while no
other thread runs, so such a thread registers here (:func:`register`) and is paused for the
instant of a fork (:func:`threads_paused`) instead of turning the fork down.
"""

from __future__ import annotations

import os
from collections.abc import Iterable, Iterator
from contextlib import contextmanager
from typing import ContextManager, Protocol, TypeVar

T = TypeVar("T")


class Task(Protocol):
    """One piece of work being shown: advanced as it goes, renamed or resized on the way."""

    def advance(self, amount: float = 1) -> None:
        """``amount`` more of the work is done."""

    def update(self, *, completed: float | None = None, total: float | None = None,
               description: str | None = None) -> None:
        """Set how much is done, the total (None: unknown) or what is being done."""


class Progress(Protocol):
    """Where long work reports: :meth:`task` opens one task for the length of a ``with``.
    ``total`` None is work of unknown size (a spinner with the time elapsed); ``unit`` names
    what is counted (``"bytes"`` is shown as sizes)."""

    enabled: bool

    def task(self, description: str, total: float | None = None, unit: str = "") -> ContextManager[Task]:
        """A task shown until the ``with`` block ends."""


class _NullTask:
    """A task no one watches (its own context manager, so no object is made per use)."""

    def advance(self, amount: float = 1) -> None:
        pass

    def update(self, *, completed: float | None = None, total: float | None = None,
               description: str | None = None) -> None:
        pass

    def __enter__(self) -> "_NullTask":
        return self

    def __exit__(self, *exc: object) -> None:
        return None


_NULL_TASK = _NullTask()


class Silent:
    """No progress shown (not a terminal, ``--quiet``, a library caller): costs nothing."""

    enabled = False

    def task(self, description: str, total: float | None = None, unit: str = "") -> ContextManager[Task]:
        """A task that does nothing."""
        return _NULL_TASK


#: The default of every ``progress`` parameter.
SILENT: Progress = Silent()


def counted(items: Iterable[T], task: Task, every: int = 4096) -> Iterable[T]:
    """``items``, advancing ``task`` once per ``every`` items (the items themselves, untouched,
    when ``task`` is the silent one)."""
    if task is _NULL_TASK:
        return items
    return _counting(items, task, every)


def _counting(items: Iterable[T], task: Task, every: int) -> Iterator[T]:
    n = 0
    for item in items:
        yield item
        n += 1
        if n == every:
            task.advance(n)
            n = 0
    if n:
        task.advance(n)


# --- display threads and forks ----------------------------------------------------------------

class Pausable(Protocol):
    """A display's refresh thread, stopped and started again around a fork."""

    @property
    def running(self) -> bool:
        """True while its thread runs."""

    def pause(self) -> None:
        """Stop the thread (returns once it has ended)."""

    def resume(self) -> None:
        """Start the thread again."""


_pausable: list[Pausable] = []


def register(thread: Pausable) -> None:
    """Count ``thread`` as one that :func:`threads_paused` stops (until :func:`unregister`)."""
    _pausable.append(thread)


def unregister(thread: Pausable) -> None:
    """Forget ``thread``."""
    if thread in _pausable:
        _pausable.remove(thread)


def pausable_threads() -> int:
    """How many of the running threads are display threads that a fork may pause."""
    return sum(1 for t in _pausable if t.running)


@contextmanager
def threads_paused() -> Iterator[None]:
    """Display threads stopped for the block (a ``fork`` inside it); started again after it, in
    the process that entered it only (a forked child keeps no display thread)."""
    pid = os.getpid()
    stopped = [t for t in _pausable if t.running]
    for t in stopped:
        t.pause()
    try:
        yield
    finally:
        if os.getpid() == pid:
            for t in stopped:
                t.resume()
