"""The main job: everything kitkb does, end to end, on the shipped scenarios.

Each stage is a library call; this module only sequences them and prints one line per
stage, so that ``./main.sh`` shows a new user what the project does:

1. validate the shipped model (closed world, SHACL);
2. for each shipped scenario: validate its initial and goal state files, generate the PDDL
   domain and problem, plan with a real planner (validated plan), and load the initial state
   into the world-model database and read every object's global pose back.

Outputs go to ``out_dir`` (default ``out/``): ``<scenario>/domain.pddl``, ``problem.pddl``,
``plan.txt`` and ``world.sqlite``.
"""

from __future__ import annotations

import time
from pathlib import Path
from typing import TextIO

from kb import planning
from kb.cli.output import Output
from kb.core.generators import get_generator
from kb.core.resources import ontologies_dir, scenario_dirs
from kb.validation import validate
from kb.world import WorldModel, load


def run(output: str, out: Output) -> int:
    """``kitkb run``: the main job, its progress on standard output (nothing with ``--quiet``
    but the problems found)."""
    return run_main_job(out.results if not out.quiet else _Problems(out.results), output)


class _Problems:
    """A stream that passes on only the lines about problems."""

    def __init__(self, target: TextIO) -> None:
        self.target = target

    def write(self, text: str) -> None:
        if ": error:" in text or ": warning:" in text or "found problems" in text:
            self.target.write(text)

    def flush(self) -> None:
        self.target.flush()


def _stage(out: TextIO, label: str, started: float) -> None:
    print(f"  {label} ({time.perf_counter() - started:.2f} s)", file=out)


def run_main_job(out: TextIO, out_dir: str | Path = "out") -> int:
    """Run every stage on the shipped scenarios; 0 when all succeeded, 1 otherwise."""
    status = 0
    model = sorted(ontologies_dir().glob("*.ttl"))
    scenarios = scenario_dirs()
    print(f"kitkb: main job on {len(scenarios)} shipped scenarios, outputs in {out_dir}/", file=out)
    t = time.perf_counter()
    report = validate([str(p) for p in model])
    _stage(out, f"model: {len(model)} files, {report.summary()}", t)
    status |= 0 if report.conforms else 1
    for scenario in scenarios:
        print(f"{scenario.name}:", file=out)
        status |= _scenario(scenario, Path(out_dir) / scenario.name, out)
    print("kitkb: main job " + ("succeeded" if status == 0 else "found problems"), file=out)
    return status


def _scenario(scenario: Path, target: Path, out: TextIO) -> int:
    init, goal = scenario / "init.ttl", scenario / "goal.ttl"
    t = time.perf_counter()
    report = validate([str(init), str(goal)])
    _stage(out, f"validate: {report.summary()}", t)
    for diag in report.diagnostics:
        print("    " + diag.format(), file=out)
    if not report.conforms:
        return 1
    target.mkdir(parents=True, exist_ok=True)
    t = time.perf_counter()
    model = planning.kitting_model([init], [goal], "strips")
    get_generator("pddl")(model).write_outputs(target)
    _stage(out, f"pddl: {target / 'domain.pddl'}, {target / 'problem.pddl'}", t)
    t = time.perf_counter()
    result = planning.run(model.up_problem, target / "plan.txt")
    _stage(out, f"plan: {len(result.lines)} actions by {result.planner}, validated -> {target / 'plan.txt'}", t)
    t = time.perf_counter()
    db_file = target / "world.sqlite"
    db_file.unlink(missing_ok=True)
    loaded = load(init, db_file)
    with WorldModel(db_file) as world:
        poses = world.global_poses()
    _stage(out, f"world model: {loaded.individuals} individuals, {len(poses)} global poses -> {db_file}", t)
    return 0
