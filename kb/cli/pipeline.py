"""The main job: everything kitkb does, end to end, on the shipped scenarios.

Each stage is a library call; this module only sequences them and prints one line per
stage, so that ``./main.sh`` shows a new user what the project does:

1. validate the shipped model (closed world, SHACL);
2. for each shipped scenario: validate its initial and goal state files, generate the PDDL
   domain and problem, plan with a real planner (validated plan), check that the predicates
   decided from the objects' boxes equal the PDDL facts (and the goal holds in the goal's
   boxes), and load the initial state into the world-model database and read every object's
   global pose back.

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
from kb.planning.geometry import check_geometry
from kb.validation import validate
from kb.world import WorldModel, load


def run(output: str, out: Output) -> int:
    """``kitkb run``: the main job, its progress on standard output (with ``--quiet`` only
    the problems it finds)."""
    return run_main_job(out.results, output, quiet=out.quiet)


class _Progress:
    """The main job's lines: stages (unless quiet) and problems (always)."""

    def __init__(self, out: TextIO, quiet: bool) -> None:
        self.out, self.quiet = out, quiet

    def say(self, text: str) -> None:
        if not self.quiet:
            print(text, file=self.out)

    def stage(self, label: str, started: float) -> None:
        self.say(f"  {label} ({time.perf_counter() - started:.2f} s)")

    def problem(self, text: str) -> None:
        print(text, file=self.out)


def run_main_job(out: TextIO, out_dir: str | Path = "out", quiet: bool = False) -> int:
    """Run every stage on the shipped scenarios; 0 when all succeeded, 1 otherwise."""
    progress = _Progress(out, quiet)
    status = 0
    model = sorted(ontologies_dir().glob("*.ttl"))
    scenarios = scenario_dirs()
    progress.say(f"kitkb: main job on {len(scenarios)} shipped scenarios, outputs in {out_dir}/")
    t = time.perf_counter()
    report = validate([str(p) for p in model])
    progress.stage(f"model: {len(model)} files, {report.summary()}", t)
    for diag in report.diagnostics:
        progress.problem("    " + diag.format())
    status |= 0 if report.conforms else 1
    for scenario in scenarios:
        progress.say(f"{scenario.name}:")
        status |= _scenario(scenario, Path(out_dir) / scenario.name, progress)
    if status:
        progress.problem("kitkb: main job found problems")
    else:
        progress.say("kitkb: main job succeeded")
    return status


def _scenario(scenario: Path, target: Path, progress: _Progress) -> int:
    init, goal = scenario / "init.ttl", scenario / "goal.ttl"
    t = time.perf_counter()
    report = validate([str(init), str(goal)])
    progress.stage(f"validate: {report.summary()}", t)
    for diag in report.diagnostics:
        progress.problem(f"    {scenario.name}: {diag.format()}")
    if not report.conforms:
        return 1
    t = time.perf_counter()
    model = planning.kitting_model([init], [goal], "strips")
    get_generator("pddl")(model).write_outputs(target)
    progress.stage(f"pddl: {target / 'domain.pddl'}, {target / 'problem.pddl'}", t)
    t = time.perf_counter()
    result = planning.run(model.up_problem, target / "plan.txt")
    progress.stage(f"plan: {len(result.lines)} actions by {result.planner}, validated -> {target / 'plan.txt'}", t)
    t = time.perf_counter()
    geo = check_geometry([init], [goal])
    progress.stage(f"geometry: {geo.atoms} atoms hold in the initial state's boxes, "
                   f"{'equal to the PDDL init facts; every goal fact holds in the goal' if geo.agrees else 'DISAGREE'}",
                   t)
    for what, atoms in (("only in geometry", geo.only_geometry), ("only in PDDL", geo.only_symbolic),
                        ("goal not holding", geo.goal_not_holding)):
        for atom in atoms:
            progress.problem(f"    {scenario.name}: {what}: ({' '.join(atom)})")
    if not geo.agrees:
        return 1
    t = time.perf_counter()
    db_file = target / "world.sqlite"
    db_file.unlink(missing_ok=True)
    loaded = load(init, db_file)
    with WorldModel(db_file) as world:
        poses = world.global_poses()
    progress.stage(f"world model: {loaded.individuals} individuals, {len(poses)} global poses -> {db_file}", t)
    return 0
