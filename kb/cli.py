"""The ``kitkb`` command: a thin shim over the library.

Each subcommand parses its arguments and calls one library function, imported when the
subcommand runs (start-up stays lean). Errors derived from :class:`kb.errors.KitkbError`
print as one line and exit with their ``exit_code``; nothing prints a traceback unless
``--traceback`` is given.

Exit codes: 0 success / conforms, 1 violations or no plan, 2 unusable input.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Callable, Sequence

Handler = Callable[[argparse.Namespace], int]


def _lazy(module: str, function: str) -> Handler:
    """A handler that imports ``module`` only when its subcommand runs and calls ``function(args)``."""

    def handler(args: argparse.Namespace) -> int:
        import importlib

        return getattr(importlib.import_module(module), function)(args)

    return handler


# --- validate / convert ------------------------------------------------------------

def _cmd_validate(args: argparse.Namespace) -> int:
    from kb.validate import run_validate

    if _console:
        # a one-shot process: the cyclic garbage collector would only walk the millions of
        # objects of a big file again (0.4 s at 10,000 parts); :func:`run` skips freeing them
        import gc

        gc.disable()
        _fast_exit.append(True)
    return run_validate(args.files, fmt=args.format, out=sys.stdout)


def _cmd_convert(args: argparse.Namespace) -> int:
    from kb.convert import convert

    convert(Path(args.input), Path(args.output))
    return 0


def _add_validate(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("validate", help="closed-world validation of ontology files (SHACL)")
    p.add_argument("files", nargs="*", help="files to validate (default: the shipped model and scenarios)")
    p.add_argument("--format", choices=["text", "json"], default="text")
    p.set_defaults(handler=_cmd_validate)

    p = sub.add_parser("convert", help="convert between Turtle, RDF/XML, OWL/XML and functional syntax inputs")
    p.add_argument("input")
    p.add_argument("-o", "--output", required=True,
                   help="output file; .ttl Turtle, .owl/.rdf RDF/XML, .nt N-Triples (written atomically)")
    p.set_defaults(handler=_cmd_convert)


# --- scenario ----------------------------------------------------------------------

def _cmd_scenario_generate(args: argparse.Namespace) -> int:
    from kb.scenario import write_scenario

    write_scenario(Path(args.output), parts=args.parts, kits=args.kits, seed=args.seed)
    return 0


def _add_scenario(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("scenario", help="scenario files (initial and goal states)")
    ssub = p.add_subparsers(dest="scenario_command", required=True)
    g = ssub.add_parser("generate", help="write a valid init/goal pair of any size")
    g.add_argument("--parts", type=int, required=True, help="number of parts in the kits")
    g.add_argument("--kits", type=int, default=1, help="number of kits to build")
    g.add_argument("--seed", type=int, default=0)
    g.add_argument("-o", "--output", required=True, help="output folder (init.ttl, goal.ttl)")
    g.set_defaults(handler=_cmd_scenario_generate)


# --- run (the main job) ---------------------------------------------------------------

def _cmd_run(args: argparse.Namespace) -> int:
    from kb.pipeline import run_main_job

    return run_main_job(out=sys.stdout, out_dir=args.output)


def _add_run(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("run", help="the main job on the shipped scenarios: validate, PDDL, plan, world model")
    p.add_argument("-o", "--output", default="out", help="output folder (default out/)")
    p.set_defaults(handler=_cmd_run)


# --- further subcommands are added below, one _add_* function each ---------------------

# --- db (world model database) ----------------------------------------------------------

def _add_db(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("db", help="the execution world model database (SQLite file or PostgreSQL)")
    dsub = p.add_subparsers(dest="db_command", required=True)
    g = dsub.add_parser("load", help="replace the database content with a data file (one transaction)")
    g.add_argument("datafile")
    g.add_argument("--db", default="kitkb.sqlite", help="SQLAlchemy URL or SQLite file (default kitkb.sqlite)")
    g.set_defaults(handler=_lazy("kb.sqlgen_cli", "db_load"))
    g = dsub.add_parser("dump", help="write the database as Turtle")
    g.add_argument("--db", default="kitkb.sqlite", help="SQLAlchemy URL or SQLite file (default kitkb.sqlite)")
    g.add_argument("-o", "--output", required=True, help="output .ttl file")
    g.set_defaults(handler=_lazy("kb.sqlgen_cli", "db_dump"))


# --- generate (pddl, sql) / plan ---------------------------------------------------------

def _add_generate(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("generate", help="generate artefacts from the ontologies (PDDL, SQL)")
    gsub = p.add_subparsers(dest="generate_command", required=True)
    g = gsub.add_parser("pddl", help="PDDL domain and problem from an initial and a goal state file")
    g.add_argument("init", help="initial state file (Turtle, RDF/XML, OWL functional syntax)")
    g.add_argument("goal", help="goal state file")
    g.add_argument("-o", "--output", required=True, help="output folder (domain.pddl, problem.pddl)")
    g.add_argument("--encoding", choices=["strips", "numeric"], default="strips",
                   help="strips: counts compiled into objects (Fast Downward, pyperplan); "
                        "numeric: PDDL 2.1 fluents (ENHSP)")
    g.set_defaults(handler=_lazy("kb.planning_cli", "generate_pddl"))
    g = gsub.add_parser("sql", help="SQL schema (DDL) of the shipped ontologies")
    g.add_argument("--dialect", default="sqlite", help="SQL dialect (default sqlite)")
    g.add_argument("-o", "--output", default="-", help="output file ('-' for standard output)")
    g.set_defaults(handler=_lazy("kb.sqlgen_cli", "generate_sql"))


def _add_plan(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("plan", help="plan with a real planner and write the validated plan",
                       description="kitkb plan INIT GOAL -o PLAN (ontology state files) or "
                                   "kitkb plan DOMAIN.pddl PROBLEM.pddl -o PLAN (existing PDDL). "
                                   "Exit 0: plan written; 1: no plan; 2: unusable input or planner.")
    p.add_argument("first", metavar="INIT|DOMAIN", help="initial state file, or a PDDL domain")
    p.add_argument("second", metavar="GOAL|PROBLEM", help="goal state file, or a PDDL problem")
    p.add_argument("-o", "--output", required=True, help="plan file (one action per line)")
    p.add_argument("--planner", help="planner name (fast-downward, enhsp, pyperplan, ...); "
                                     "default: chosen from the problem's kind")
    p.add_argument("--encoding", choices=["strips", "numeric"], default="strips",
                   help="encoding for ontology input (default strips)")
    p.add_argument("--timeout", type=float, help="planner time limit in seconds")
    p.add_argument("--engine-defaults", action="store_true",
                   help="run the planner with its own default settings instead of kitkb's")
    p.set_defaults(handler=_lazy("kb.planning_cli", "plan"))


def _add_planning(sub: argparse._SubParsersAction) -> None:
    _add_generate(sub)
    _add_plan(sub)


_ADDERS: list[Callable[[argparse._SubParsersAction], None]] = [
    _add_validate,
    _add_scenario,
    _add_run,
    _add_db,
    _add_planning,
]


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of the ``kitkb`` command."""
    parser = argparse.ArgumentParser(prog="kitkb", description=__doc__.splitlines()[0])
    parser.add_argument("--traceback", action="store_true", help="show Python tracebacks (debugging)")
    sub = parser.add_subparsers(dest="command", required=True)
    for add in _ADDERS:
        add(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``kitkb`` console script."""
    from kb.errors import KitkbError

    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return int(args.handler(args) or 0)
    except KitkbError as exc:
        if args.traceback:
            raise
        print(str(exc), file=sys.stderr)
        return exc.exit_code
    except KeyboardInterrupt:
        print("kitkb: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:  # the reader went away (``kitkb validate ... | head``)
        import os

        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 1
    except Exception as exc:  # a bug of ours: still one line, never a traceback by default
        if args.traceback:
            raise
        print(f"kitkb: internal error: {type(exc).__name__}: {exc} (run with --traceback)", file=sys.stderr)
        return 3


_console = False
_fast_exit: list[bool] = []


def run() -> None:
    """The console script: :func:`main`, then exit.

    After ``validate`` the process ends without tearing down its heap (``os._exit`` once the
    output is flushed): freeing the objects of a big file one by one only costs time.
    """
    global _console
    _console = True
    code = main()
    if _fast_exit:
        import os

        try:
            sys.stdout.flush()
            sys.stderr.flush()
        except BrokenPipeError:
            code = code or 1
        except OSError:
            pass
        os._exit(code)
    sys.exit(code)


if __name__ == "__main__":  # pragma: no cover
    run()
