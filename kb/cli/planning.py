"""``kitkb generate pddl`` and ``kitkb plan``."""

from __future__ import annotations

import os
import sys
import time
from pathlib import Path

from kb import planning
from kb.cli.output import Output
from kb.core.errors import InputError
from kb.core.generators import get_generator


def generate_pddl(init: str, goal: str, output: str, encoding: str, match_names: bool, out: Output,
                  domain: list[str] | None = None) -> int:
    """Write ``domain.pddl`` and ``problem.pddl`` for INIT -> GOAL into the folder ``output``
    (``domain``: extension files added to the shipped domain)."""
    with out.progress(f"generating PDDL from {Path(init).name} and {Path(goal).name}"):
        model = planning.kitting_model([init], [goal], encoding, domain_files=domain, match_names=match_names)
        for note in model.problem.notes:  # what the state files hold that is not read
            out.warn(note)
        written = get_generator("pddl")(model).write_outputs(Path(output))
    out.done(f"wrote {' and '.join(map(str, written))} ({encoding} encoding)", written=[str(w) for w in written],
             encoding=encoding)
    return 0


def plan(first: str, second: str, output: str, planner: str | None, encoding: str, timeout: float | None,
         engine_defaults: bool, match_names: bool, out: Output, domain: list[str] | None = None) -> int:
    """Plan from INIT GOAL ontology files, or from DOMAIN PROBLEM PDDL files; write the plan
    (``domain``: extension files added to the shipped domain; not with PDDL files)."""
    start = time.perf_counter()
    with out.progress(f"planning {Path(first).name} -> {Path(second).name}"):
        files = None
        if planning.is_pddl(first) and planning.is_pddl(second):
            if domain:
                raise InputError("--domain extends the ontology's domain; it does not apply to PDDL files "
                                 f"({Path(first).name}, {Path(second).name})")
            with out.progress("reading the PDDL files"):
                files = planning.read_pddl(first, second, warn=out.warn)
            problem = files.problem
            source = "PDDL"
        else:
            with out.progress("building the planning problem from the ontology files"):
                model = planning.kitting_model([first], [second], encoding, domain_files=domain, overlap=True,
                                               match_names=match_names)
            for note in model.problem.notes:  # what the state files hold that is not read
                out.warn(note)
            problem = model.up_problem
            source = f"ontology, {encoding} encoding"
        built = time.perf_counter() - start
        result = planning.run(problem, output, planner, timeout, engine_defaults, progress=out.tracker,
                              source=files)
    total = time.perf_counter() - start
    cost = f", cost {result.cost:g}" if result.cost is not None else ""
    out.done(f"wrote {output}: {len(result.lines)} actions by {result.planner} ({source}{cost}), validated by "
             f"unified-planning, in {total:.2f} s", output=output, actions=len(result.lines),
             planner=result.planner, source=source, validated=True, seconds=round(total, 3),
             times={"model": round(built, 3), "solve": round(result.times["solve"], 3),
                    "validate": round(result.times["validate"], 3)}, plan=result.lines,
             **({"cost": result.cost} if result.cost is not None else {}))
    if os.environ.get("KITKB_TIMING"):
        cpu = os.times()
        print(f"timing: model {built:.2f} s, solve {result.times['solve']:.2f} s, validate "
              f"{result.times['validate']:.2f} s; cpu {cpu.user + cpu.system:.2f} s + child processes "
              f"{cpu.children_user + cpu.children_system:.2f} s", file=sys.stderr)
    return 0
