"""Cells by URL: which cell a run drives, and what the executor assumes of any cell.

* :mod:`.registry`: :func:`open_cell` (``url``, :class:`CellRequest`) -> a cell, by the URL's
  scheme: ``sim:`` (the in-process simulator, the default), ``kitkb://HOST:PORT`` (a kitkb cell
  server), ``crcl://HOST:PORT?sensor=HOST:PORT`` (a CRCL 1.x controller and a USARTruth-style
  sensor), and any scheme another distribution registers in the ``kitkb.cells`` entry-point
  group. Built-in schemes are found by module name, so nothing here imports ``kb.sim``.
* :mod:`.accuracy`: :class:`SensorAccuracy` (what a pose sensor's errors are: sigmas and rates,
  read from the state's ``ktw:PoseSensor`` or ``--sensor-noise``) and
  :data:`CAPTURE_TOLERANCE` (what a gripper captures): what the executor assumes of a cell,
  owned here, below both the executor and the simulator.
* :mod:`.remote`: the openers of cells behind sockets (:class:`kb.crcl.RemoteCell`).

What a cell can do is a set of capabilities, the protocols of :mod:`kb.crcl.cell`.
``kb.cells`` sits below ``kb.sim`` and above ``kb.spatial`` and ``kb.crcl`` (pyproject.toml's
import contracts).
"""

from kb.cells.accuracy import CAPTURE_TOLERANCE, SensorAccuracy, assumed_accuracy
from kb.cells.registry import (DEFAULT_URL, ENTRY_POINT_GROUP, CellRequest, CellURL, cell_accuracy, cell_schemes,
                               check_cell, close_cell, open_cell, parse_cell_url)

__all__ = ["CAPTURE_TOLERANCE", "DEFAULT_URL", "ENTRY_POINT_GROUP", "CellRequest", "CellURL", "SensorAccuracy",
           "assumed_accuracy", "cell_accuracy", "cell_schemes", "check_cell", "close_cell", "open_cell", "parse_cell_url"]
