"""Library side of ``kitkb generate pddl`` and ``kitkb plan`` (the CLI only parses arguments)."""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path


def generate_pddl(args: argparse.Namespace) -> int:
    """Write ``domain.pddl`` and ``problem.pddl`` for INIT -> GOAL into ``args.output``."""
    from generators.pddl_problem import PddlProblemGenerator

    gen = PddlProblemGenerator([args.init], [args.goal], args.encoding)
    domain, problem = gen.write_both(Path(args.output))
    print(f"wrote {domain} and {problem} ({args.encoding} encoding)", file=sys.stderr)
    return 0


def is_pddl(path: str) -> bool:
    """True if ``path`` looks like a PDDL file (extension, else first non-comment character)."""
    p = Path(path)
    if p.suffix.lower() == ".pddl":
        return True
    try:
        head = p.read_text(encoding="utf-8", errors="replace")[:4096]
    except OSError:
        return False
    body = "\n".join(line.split(";", 1)[0] for line in head.splitlines()).lstrip()
    return body.startswith("(define")


def plan(args: argparse.Namespace) -> int:
    """Plan from INIT GOAL ontology files, or from DOMAIN PROBLEM PDDL files; write the plan."""
    from kb import planning

    start = time.perf_counter()
    first, second = args.first, args.second
    if is_pddl(first) and is_pddl(second):
        problem = planning.read_pddl(first, second)
        source = "PDDL"
    else:
        from generators.pddl.model import kitting_model

        problem = kitting_model([first], [second], args.encoding, overlap=True).up_problem
        source = f"ontology, {args.encoding} encoding"
    built = time.perf_counter() - start
    result = planning.run(problem, args.output, args.planner, args.timeout, args.engine_defaults)
    total = time.perf_counter() - start
    print(f"plan: {len(result.lines)} actions by {result.planner} ({source}), validated by "
          f"unified-planning; written to {args.output} in {total:.2f} s", file=sys.stderr)
    if os.environ.get("KITKB_TIMING"):
        cpu = os.times()
        print(f"timing: model {built:.2f} s, solve {result.times['solve']:.2f} s, validate "
              f"{result.times['validate']:.2f} s; cpu {cpu.user + cpu.system:.2f} s + child processes "
              f"{cpu.children_user + cpu.children_system:.2f} s", file=sys.stderr)
    return 0
