"""Existing PDDL files (classic IPC domains, NIST's hand-written one) as planning problems.

:func:`read_task` reads a domain and a problem, checks them (errors at ``file:line``),
rewrites what unified-planning's reader cannot take into what it can — derived predicates
expanded, ``either`` types, clashing or unreadable names, IPC action costs — and reads the
result with unified-planning's own reader. docs/pddl.md lists what is supported.
"""

from kb.planning.pddl.task import PddlTask, read_task

__all__ = ["PddlTask", "read_task"]
