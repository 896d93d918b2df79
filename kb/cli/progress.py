"""Progress on a terminal: :class:`kb.core.progress.Progress` shown with rich.

One transient display on standard error: a line per open task with what is being done, a
bar, the counts (sizes for ``unit="bytes"``), the rate, the time elapsed and the time left
(a spinner and the time elapsed where the size is unknown: a planner at work). It is made
only where standard error is a terminal and ``--quiet`` is not given (:func:`tracker`);
anywhere else :data:`kb.core.progress.SILENT` stands in, which costs nothing. rich is
imported only when a display is made.

The display refreshes from its own thread, registered with :mod:`kb.core.progress` so that
:class:`kb.core.jobs.Forked` pauses it for the instant of a fork rather than refusing the fork.
"""

from __future__ import annotations

import os
import sys
import threading
import time
from contextlib import contextmanager
from typing import Any, Iterator, TextIO

from kb.core import progress as core
from kb.core.progress import SILENT, Progress

#: Seconds between two refreshes of the display (each costs about 3 ms of the work's CPU).
REFRESH = 0.2
#: Seconds a task's counts may wait before rich sees them (an advance then costs a clock reading).
PUSH = 0.05


def tracker(stream: TextIO | None = None, *, quiet: bool = False, force: bool | None = None) -> Progress:
    """The progress of a command: a :class:`Display` on ``stream`` (standard error) when it is a
    terminal and not ``quiet``, else :data:`~kb.core.progress.SILENT`. ``force`` True shows it on
    any stream (tests), False never; ``KITKB_PROGRESS=0`` turns it off, ``=1`` on."""
    stream = stream or sys.stderr
    if force is None:
        setting = os.environ.get("KITKB_PROGRESS", "").strip().lower()
        force = True if setting in ("1", "on", "yes", "force") else False if setting in ("0", "off", "no") else None
    if quiet or force is False:
        return SILENT
    if force is None and not _is_terminal(stream):
        return SILENT
    return Display(stream, force_terminal=bool(force))


def _is_terminal(stream: TextIO) -> bool:
    try:
        return stream.isatty() and os.environ.get("TERM", "") != "dumb"
    except (AttributeError, ValueError):
        return False


class Display:
    """A rich progress display on ``stream``: tasks may nest (each a line of one display)."""

    enabled = True

    def __init__(self, stream: TextIO, force_terminal: bool = False) -> None:
        self.stream, self.force_terminal = stream, force_terminal
        self._rich: Any = None
        self._open = 0
        self._pid = os.getpid()
        self._refresher: _Refresher | None = None

    @contextmanager
    def task(self, description: str, total: float | None = None, unit: str = "") -> Iterator[core.Task]:
        """A line of the display for the block."""
        if os.getpid() != self._pid:  # a forked child does not draw on its parent's terminal
            with SILENT.task(description) as t:
                yield t
            return
        if self._open == 0:
            self._start()
        self._open += 1
        rich = self._rich
        task_id = rich.add_task(description, total=total, unit=unit)
        rich.refresh()  # shown at once (the thread refreshes it from then on)
        task = _Task(rich, task_id)
        try:
            yield task
        finally:
            task.update()  # its last counts, drawn once before the line goes (a short task
            rich.refresh()  # may end between two of the thread's refreshes: ~3 ms a task)
            rich.remove_task(task_id)
            self._open -= 1
            if self._open == 0:
                self._stop()

    def _start(self) -> None:
        from rich.console import Console
        from rich.progress import BarColumn, Progress as RichProgress, SpinnerColumn, TextColumn, TimeElapsedColumn

        console = Console(file=self.stream, force_terminal=self.force_terminal or None, highlight=False)
        out_is_terminal = _is_terminal(sys.stdout)
        self._rich = RichProgress(SpinnerColumn(), TextColumn("{task.description}", markup=False), BarColumn(bar_width=30),
                                  _Counts(), TimeElapsedColumn(), _Left(), console=console, transient=True,
                                  auto_refresh=False, redirect_stdout=out_is_terminal, redirect_stderr=True)
        self._rich.start()
        self._refresher = _Refresher(self._rich)
        core.register(self._refresher)
        self._refresher.resume()

    def _stop(self) -> None:
        if self._refresher is not None:
            self._refresher.pause()
            core.unregister(self._refresher)
            self._refresher = None
        self._rich.stop()
        self._rich = None


class _Task:
    """One line of the display; advances are summed here and handed to rich every :data:`PUSH` s."""

    def __init__(self, rich: Any, task_id: Any) -> None:
        self._rich, self._id = rich, task_id
        self._pending = 0.0
        self._pushed = 0.0  # the first advance is shown at once

    def advance(self, amount: float = 1) -> None:
        self._pending += amount
        now = time.monotonic()
        if now - self._pushed >= PUSH:
            self._push(now)

    def _push(self, now: float) -> None:
        self._rich.advance(self._id, self._pending)
        self._pending, self._pushed = 0.0, now

    def update(self, *, completed: float | None = None, total: float | None = None,
               description: str | None = None) -> None:
        if self._pending:
            self._push(time.monotonic())
        fields: dict[str, Any] = {}
        if completed is not None:
            fields["completed"] = completed
        if total is not None:
            fields["total"] = total
        if description is not None:
            fields["description"] = description
        self._rich.update(self._id, **fields)
        if description is not None:  # a new step is shown at once, however short (as a new task is)
            self._rich.refresh()


class _Refresher:
    """The display's refresh thread (see :mod:`kb.core.progress`: paused around forks)."""

    def __init__(self, rich: Any) -> None:
        self.rich = rich
        self._thread: threading.Thread | None = None
        self._stop = threading.Event()

    @property
    def running(self) -> bool:
        return self._thread is not None and self._thread.is_alive()

    def resume(self) -> None:
        self._stop.clear()
        self._thread = threading.Thread(target=self._run, name="kitkb-progress", daemon=True)
        self._thread.start()

    def pause(self) -> None:
        if self._thread is not None:
            self._stop.set()
            self._thread.join()
            self._thread = None

    def _run(self) -> None:
        while not self._stop.wait(REFRESH):
            self.rich.refresh()


class _Counts:
    """``done/total unit`` and the rate (sizes for bytes), as a rich column."""

    def __call__(self, task: Any) -> Any:
        from rich.filesize import decimal
        from rich.text import Text

        unit = task.fields.get("unit", "")
        speed = task.finished_speed or task.speed
        if unit == "bytes":
            done = decimal(int(task.completed)) + (f"/{decimal(int(task.total))}" if task.total else "")
            rate = f"{decimal(int(speed))}/s" if speed else ""
        else:
            done = f"{int(task.completed):,}" + (f"/{int(task.total):,}" if task.total else "") + (
                f" {unit}" if unit else "")
            rate = (f"{speed:,.0f}/s" if speed >= 10 else f"{speed:.1f}/s") if speed else ""
        if not task.completed and not task.total:
            return Text("")
        return Text(f"{done}  {rate}".rstrip(), style="progress.download")

    def get_table_column(self) -> Any:
        from rich.table import Column

        return Column(no_wrap=True)


class _Left:
    """The time left (blank for work of unknown size), as a rich column."""

    def __call__(self, task: Any) -> Any:
        from rich.text import Text

        if not task.total:
            return Text("")
        left = task.time_remaining
        if left is None:
            return Text("-:--:-- left", style="progress.remaining")
        m, s = divmod(int(left), 60)
        h, m = divmod(m, 60)
        return Text(f"{h}:{m:02d}:{s:02d} left", style="progress.remaining")

    def get_table_column(self) -> Any:
        from rich.table import Column

        return Column(no_wrap=True)
