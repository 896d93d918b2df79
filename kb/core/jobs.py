"""Work done in a forked child process, its answer sent back through a pipe.

:class:`Forked` is the one place kitkb forks: the SHACL engine shares a validation between
two processes, ``kitkb plan`` reads the ontology files while unified-planning imports, and a
big scenario writes its goal state while the parent writes the initial one. The child
shares the parent's memory copy-on-write, so nothing is copied or pickled on the way in,
only the answer on the way out.

A fork is refused (the caller then does the work itself) where it is not safe: on systems
without ``os.fork``, and while any other thread runs in this process, since a lock held by
that thread would stay locked for ever in the child.
"""

from __future__ import annotations

import os
import pickle
import signal
import threading
from collections.abc import Callable

from kb.core.progress import pausable_threads, threads_paused


def usable_cores() -> int:
    """Cores this process may run on."""
    try:
        return len(os.sched_getaffinity(0))
    except (AttributeError, OSError):
        return os.cpu_count() or 1


def fork_is_safe() -> bool:
    """True on a POSIX system with no thread but this one running (a progress display's
    refresh thread does not count: :class:`Forked` pauses it for the fork)."""
    return hasattr(os, "fork") and threading.active_count() - pausable_threads() == 1


class Forked:
    """``fn()`` computed in a forked child process; :meth:`result` collects it.

    The child sends the pickled value through a pipe and ends with ``os._exit`` (it never
    returns into the caller's code). :meth:`result` gives ``(True, value)``, or
    ``(False, None)`` when there was no child (the fork was refused or failed) or the child
    failed in any way (an exception, killed, a garbled answer); the caller then computes
    the value itself. A child is never left behind.
    """

    def __init__(self, fn: Callable[[], object]) -> None:
        self.pid: int | None = None
        self.fd: int | None = None
        if not fork_is_safe():
            return
        r, w = os.pipe()
        try:
            with threads_paused():
                pid = os.fork()
        except OSError:
            os.close(r)
            os.close(w)
            return
        if pid == 0:  # the child
            code = 1
            try:
                os.close(r)
                data = pickle.dumps(fn(), protocol=pickle.HIGHEST_PROTOCOL)
                with os.fdopen(w, "wb") as out:
                    out.write(data)
                code = 0
            except BaseException:  # noqa: BLE001 - the parent does the work again
                pass
            finally:
                os._exit(code)
        os.close(w)
        self.pid, self.fd = pid, r

    @property
    def started(self) -> bool:
        """True when a child is at work (or has answered and not been collected yet)."""
        return self.pid is not None

    def result(self) -> tuple[bool, object]:
        """(True, the child's value) or (False, None) if there is none."""
        if self.pid is None or self.fd is None:
            return False, None
        try:
            chunks = []
            with os.fdopen(self.fd, "rb") as inp:
                self.fd = None
                while chunk := inp.read(1 << 20):
                    chunks.append(chunk)
            _, status = os.waitpid(self.pid, 0)
            self.pid = None
            if os.waitstatus_to_exitcode(status) != 0:
                return False, None
            try:
                return True, pickle.loads(b"".join(chunks))
            except Exception:  # noqa: BLE001 - a garbled answer: the caller does it
                return False, None
        finally:
            self.cancel()

    def cancel(self) -> None:
        """Stop and reap the child if it is still there (the caller gave up on it)."""
        if self.fd is not None:
            os.close(self.fd)
            self.fd = None
        if self.pid is not None:
            try:
                os.kill(self.pid, signal.SIGKILL)
                os.waitpid(self.pid, 0)
            except OSError:
                pass
            self.pid = None
