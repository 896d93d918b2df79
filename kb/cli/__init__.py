"""The ``kitkb`` command: argument parsing only.

Each subcommand names its handler as ``module:function`` in :data:`HANDLERS`, imported when
that subcommand runs, so ``kitkb validate`` never imports SQLAlchemy or unified-planning.
A handler takes the parsed options as keyword arguments plus a :class:`kb.cli.output.Output`
and returns the exit code. Errors derived from :class:`kb.core.errors.KitkbError` print as
one line and exit with their ``exit_code``; nothing prints a traceback unless
``--traceback`` is given.
"""

from __future__ import annotations

import argparse
import gc
import importlib
import inspect
import os
import sys
from typing import Any, Callable, Sequence

from kb.cli.output import Output
from kb.core.errors import KitkbError
from kb.core.files import command_scope
from kb.core.units import LENGTH

DESCRIPTION = ("kitkb: a knowledge base for robotic kit building (NIST / IEEE ORA kitting). "
               "Validate ontology files, generate PDDL, SQL and scenarios from the ontologies, "
               "plan with a real planner, and keep the world model in a database. Long work shows its progress "
               "on standard error when that is a terminal (not with --quiet); every command takes --format json "
               "for its facts as JSON on standard output (one object; predicates: a list).")
EXIT_CODES = ("exit codes: 0 success (validate: the files conform); 1 violations found, or no plan "
              "exists; 2 unusable input (one line naming the file and line); 3 internal error; "
              "130 interrupted")

#: Subcommand -> ``module:function`` of its handler (imported when the subcommand runs).
HANDLERS = {
    "validate": "kb.cli.validation:validate",
    "shacl": "kb.cli.shacl:shacl",
    "convert": "kb.cli.validation:convert",
    "scenario generate": "kb.cli.scenario:generate",
    "scenario transform": "kb.cli.scenario:transform",
    "generate pddl": "kb.cli.planning:generate_pddl",
    "generate sql": "kb.cli.generate:generate_sql",
    "generate shapes": "kb.cli.generate:generate_file",
    "generate accessors": "kb.cli.generate:generate_file",
    "plan": "kb.cli.planning:plan",
    "db load": "kb.cli.world:load",
    "db dump": "kb.cli.world:dump",
    "run": "kb.cli.ariac:scored_run",  # kb.cli.pipeline:run, with --scoring ariac-YEAR (kb.ariac)
    "crcl convert": "kb.cli.crcl:convert",
    "crcl send": "kb.cli.crcl:send",
    "metrics": "kb.cli.metrics:metrics",
    "predicates": "kb.cli.predicates:predicates",
    "faults": "kb.cli.faults:faults",
    "sim serve": "kb.cli.sim:serve",
    "sim export-mjcf": "kb.cli.sim:export_mjcf",
    "testmethod": "kb.cli.testmethod:testmethod",
    "report": "kb.cli.report:report",
    "ariac import": "kb.cli.ariac:import_command",
    "ariac run": "kb.cli.ariac:run_command",
    "ariac score": "kb.cli.ariac:score_command",
}
DIALECTS = ["sqlite", "postgresql", "mysql"]
SENSOR_NOISE_HELP = ("the pose sensor's errors per look, over the state file's sensor (ktw:PoseSensor): "
                     "position=1mm,orientation=0.5deg (Gaussian sigmas, with units m, cm, mm, in, deg, rad), "
                     "bias=0.5mm (a per-object offset), misdetection=0.01 and misclass=0.5%% (chances per object "
                     "and look); docs/execution.md")
#: the fault kinds are the domain's (soap:FaultKind individuals), listed by a command of their own
FAULT_KINDS_HELP = "kinds: the domain's, with --domain an extension's too; kitkb faults lists them"
DB_HELP = "SQLite file or SQLAlchemy URL such as postgresql://user@host/db (default kitkb.sqlite)"
DEFAULT_DB = "kitkb.sqlite"


def _common() -> argparse.ArgumentParser:
    """Options every subcommand takes (also accepted before the subcommand)."""
    common = argparse.ArgumentParser(add_help=False)
    common.add_argument("-q", "--quiet", action="store_true", default=argparse.SUPPRESS,
                        help="print no line on success and no progress (errors are still printed)")
    common.add_argument("--traceback", action="store_true", default=argparse.SUPPRESS,
                        help="show the Python traceback of an error (for debugging kitkb)")
    return common


FORMAT_HELP = ("text: the line(s) kitkb prints; json: one JSON object on standard output with the same facts "
               "(paths written, counts, timings, warnings) and the text line as 'message' (default text)")


def _sub(sub: Any, name: str, command: str, help: str, format_help: str = FORMAT_HELP,
         **kw: Any) -> argparse.ArgumentParser:
    formats = list(kw.pop("formats", ("text", "json")))
    p = sub.add_parser(name, help=help, description=kw.pop("description", help[:1].upper() + help[1:] + "."),
                       epilog=EXIT_CODES, parents=[_common()], **kw)
    p.set_defaults(command=command)
    p.add_argument("--format", choices=formats, default="text", help=format_help)
    return p


def _add_files(sub: Any) -> None:
    p = _sub(sub, "validate", "validate", "closed-world validation of ontology files (SHACL), with file:line reports",
             format_help="text: one file:line line per problem and a summary; json: an object with "
                         "conforms, files, counts and diagnostics (default text)")
    p.add_argument("files", nargs="*", metavar="FILE",
                   help="Turtle, RDF/XML, OWL/XML or OWL functional syntax files, with their imports "
                        "(default: the shipped model and scenarios)")
    p.add_argument("--ignore", action="append", default=[], metavar="RULE[,RULE...]",
                   help="leave the findings of these rules (the names in brackets, e.g. floating-object) out "
                        "of the report and the exit code; may be repeated")
    p.add_argument("--shapes", action="extend", nargs="+", default=[], metavar="SHAPES",
                   help="SHACL shapes files applied to the data files besides the shipped shapes (their "
                        "results at file:line like the rest; put them after the files, or repeat --shapes)")
    p.add_argument("--domain", action="append", metavar="FILE",
                   help="a domain extension (as the other commands' --domain, repeatable): validated too, and the "
                        "classes of objects it declares (rdfs:subClassOf a class of the model), with its domain "
                        "individuals, known to the FILEs (docs/validation.md, \"A domain extension's classes\")")
    p = _sub(sub, "shacl", "shacl", "plain SHACL validation: data files against shapes files, no kitting model",
             formats=("text", "json", "turtle"),
             format_help="text: one file:line line per result and a summary; turtle: the W3C validation "
                         "report (sh:ValidationReport); json: one object with conforms, counts and results "
                         "(default text)",
             description="kitkb shacl DATA... -s SHAPES...: validate the data files (one data graph) against "
                         "the shapes files (one shapes graph) with kitkb's SHACL engine (pySHACL for what it "
                         "does not implement): no kitting model, no closed-world rules, no imports. Exit 0 "
                         "when the data conforms (no result of any severity), 1 when not, 2 for unusable "
                         "input (a broken file, shapes files without shapes, a shape SHACL forbids).")
    p.add_argument("files", nargs="+", metavar="DATA", help="data files in any syntax kitkb reads")
    p.add_argument("-s", "--shapes", action="extend", nargs="+", required=True, metavar="SHAPES",
                   help="SHACL shapes files (repeatable)")
    p.add_argument("-o", "--output", metavar="FILE", help="write the report to FILE instead of standard output")
    p = _sub(sub, "convert", "convert", "write an ontology file in another syntax")
    p.add_argument("input", metavar="IN", help="a file in any syntax kitkb reads")
    p.add_argument("-o", "--output", required=True, metavar="OUT",
                   help="output file; the extension chooses the syntax: .ttl Turtle, .owl/.rdf RDF/XML "
                        "(opens in Protege), .nt N-Triples")


def _add_scenario(sub: Any) -> None:
    p = sub.add_parser("scenario", help="scenario files (initial and goal states of a workstation)",
                       description="Scenario files: initial and goal states of a kitting workstation.")
    ssub = p.add_subparsers(dest="scenario_command", required=True, metavar="SUBCOMMAND")
    g = _sub(ssub, "generate", "scenario generate", "write a valid init/goal pair of any size")
    g.add_argument("--parts", type=int, required=True, help="number of parts in the kits")
    g.add_argument("--kits", type=int, default=1, help="number of kits to build (default 1)")
    g.add_argument("--seed", type=int, default=0, help="random seed: the same seed gives the same files (default 0)")
    g.add_argument("-o", "--output", required=True, metavar="DIR", help="output folder (init.ttl, goal.ttl)")
    g.add_argument("--unit", choices=list(LENGTH), default="meter",
                   help="length unit the files are written in (default meter)")
    g.add_argument("--unlocated", type=int, default=0, metavar="N",
                   help="a partial initial state: N parts (chosen with --seed) without a location, which "
                        "kitkb run senses before it plans (docs/validation.md, 'Partial data')")
    g.add_argument("--mark-unlocated", action="store_true",
                   help="with --unlocated: give those parts a ktw:RelativeLocationIn to their tray (pose to be "
                        "sensed) instead of no location")
    t = _sub(ssub, "transform", "scenario transform",
             "write a state file in another length unit, or turned about z (the same workstation)")
    t.add_argument("file", metavar="FILE", help="a state file (Turtle, OWL functional syntax, RDF/XML)")
    t.add_argument("-o", "--output", required=True, metavar="OUT", help="the Turtle file to write")
    t.add_argument("--unit", choices=list(LENGTH), help="rewrite every length in this unit")
    t.add_argument("--yaw", type=float, default=0.0, metavar="DEG",
                   help="turn by DEG degrees about z: the whole workstation about the world's z axis, or "
                        "with --turn each named object about its own")
    t.add_argument("--turn", metavar="OBJ,...", help="objects (local names) to turn about their own z axis")
    t.add_argument("--unlocate", metavar="OBJ,...",
                   help="objects (local names) written without their location: a partial state kitkb run "
                        "senses (with --mark-unlocated: a ktw:RelativeLocationIn to what held them)")
    t.add_argument("--mark-unlocated", action="store_true", help="with --unlocate: see there")


def _add_generate(sub: Any) -> None:
    p = sub.add_parser("generate", help="files derived from the ontologies (PDDL, SQL, shapes, accessors)",
                       description="Files derived from the ontologies.")
    gsub = p.add_subparsers(dest="generate_command", required=True, metavar="TARGET")
    g = _sub(gsub, "pddl", "generate pddl", "PDDL domain and problem of an initial and a goal state file")
    g.add_argument("init", metavar="INIT", help="initial state file (Turtle, RDF/XML, OWL functional syntax)")
    g.add_argument("goal", metavar="GOAL", help="goal state file")
    _state_files(g)
    g.add_argument("-o", "--output", required=True, metavar="DIR", help="output folder (domain.pddl, problem.pddl)")
    g = _sub(gsub, "sql", "generate sql", "SQL schema (DDL) of the world-model database")
    g.add_argument("--dialect", choices=DIALECTS, default="sqlite", help="SQL dialect (default sqlite)")
    g.add_argument("-o", "--output", default="-", metavar="FILE", help="output file ('-', the default: standard output)")
    for name, what, default in (("shapes", "SHACL shapes of the shipped kitting model", "shapes/kitting-shapes.ttl"),
                                ("accessors", "typed SQLAlchemy module of the world-model database",
                                 "kb/world/generated/accessors.py")):
        g = _sub(gsub, name, f"generate {name}", what)
        g.add_argument("-o", "--output", required=True, metavar="FILE", help=f"output file (checked in as {default})")
        g.set_defaults(generator=name)


#: The help of ``--domain`` on every command that reads the planning domain.
DOMAIN_HELP = ("a domain extension (Turtle or any syntax kitkb reads) added to the shipped kitting-domain.ttl: "
               "actions with their programs, predicates and functions with their definitions, failure modes, "
               "fault kinds (repeatable; it may import kitkb's ontologies by IRI; a file that declares "
               "<https://w3id.org/kitkb/kitting-domain> itself replaces the shipped domain; docs/soap.md)")


def _domain_option(p: argparse.ArgumentParser) -> None:
    p.add_argument("--domain", action="append", metavar="FILE", help=DOMAIN_HELP)


def _state_files(p: argparse.ArgumentParser) -> None:
    _domain_option(p)
    p.add_argument("--encoding", choices=["strips", "numeric"], default="strips",
                   help="strips: counts compiled into objects (Fast Downward, pyperplan); "
                        "numeric: PDDL 2.1 fluents (ENHSP) (default strips)")
    p.add_argument("--match-names", action="store_true",
                   help="match the goal's individuals to the initial state's by local name, for files "
                        "that name one workstation in two namespaces (as NIST's do); default: by IRI")


def _add_plan(sub: Any) -> None:
    p = _sub(sub, "plan", "plan", "plan with a real planner and write the validated plan",
             description="kitkb plan INIT GOAL -o PLAN plans from ontology state files; kitkb plan "
                         "DOMAIN.pddl PROBLEM.pddl -o PLAN from existing PDDL. The plan is written only "
                         "after unified-planning's plan validator accepted it.")
    p.add_argument("first", metavar="INIT|DOMAIN", help="initial state file, or a PDDL domain")
    p.add_argument("second", metavar="GOAL|PROBLEM", help="goal state file, or a PDDL problem")
    p.add_argument("-o", "--output", required=True, metavar="PLAN", help="plan file (one action per line)")
    p.add_argument("--planner", help="planner name (fast-downward, enhsp, pyperplan, ...); "
                                     "default: the first installed one that supports the problem")
    _state_files(p)
    p.add_argument("--timeout", type=float, metavar="SECONDS", help="planner time limit (default none)")
    p.add_argument("--engine-defaults", action="store_true",
                   help="run the planner with its own default settings instead of kitkb's")


def _add_db(sub: Any) -> None:
    p = sub.add_parser("db", help="the world-model database (SQLite file or PostgreSQL)",
                       description="The world-model database (an SQLite file, or a PostgreSQL server).")
    dsub = p.add_subparsers(dest="db_command", required=True, metavar="SUBCOMMAND")
    g = _sub(dsub, "load", "db load", "load a data file into a new database (one transaction)")
    g.add_argument("datafile", metavar="DATAFILE", help="a workstation state file in any syntax kitkb reads")
    g.add_argument("--db", default=DEFAULT_DB, metavar="URL", help=DB_HELP)
    g.add_argument("--replace", action="store_true",
                   help="replace the world model (and run history) the database already holds")
    g.add_argument("--domain", action="append", metavar="FILE",
                   help="a domain extension whose classes of objects DATAFILE uses (their individuals get the rows "
                        "of the model class each descends from, the class itself kept as a type); may be repeated")
    g = _sub(dsub, "dump", "db dump", "write the database content as Turtle")
    g.add_argument("--db", default=DEFAULT_DB, metavar="URL", help=DB_HELP)
    g.add_argument("-o", "--output", required=True, metavar="FILE", help="output .ttl file")


def _add_run(sub: Any) -> None:
    p = _sub(sub, "run", "run", "the closed loop: validate, plan, execute with every action checked from geometry",
             format_help="text: a line per stage and per action; json: the run's report (what --report writes) "
                         "on standard output instead (default text)",
             description="kitkb run [INIT GOAL]: validate the state files, plan with a real planner, and execute "
                         "the plan in the simulated cell (or --cell), every action's preconditions and effects "
                         "checked from geometry, failures diagnosed by the ontology's failure modes and "
                         "recovered. With no files: every shipped scenario (the main job).")
    p.add_argument("files", nargs="*", metavar="INIT GOAL", help="initial and goal state files (default: every "
                                                                   "shipped scenario)")
    p.add_argument("-o", "--output", default="out", metavar="DIR", help="output folder (default out/)")
    p.add_argument("--faults", metavar="KIND=RATE,...",
                   help="faults to inject in the simulated cell: KIND=RATE (chance per eligible action) or "
                        "KIND@ACTION (at that action), comma separated; " + FAULT_KINDS_HELP)
    p.add_argument("--seed", type=int, default=0, help="seed of the simulated cell's faults (default 0)")
    p.add_argument("--db", metavar="URL", help="world-model database that gets the initial state, the domain, "
                                               "the stable states and the run's records (with INIT GOAL; default: "
                                               "a new out/<scenario>/world.sqlite); a postgresql:// URL works too")
    p.add_argument("--replace", action="store_true",
                   help="with --db: replace the world model and run history the database already holds")
    _domain_option(p)
    p.add_argument("--report", metavar="FILE", help="write the JSON report (goal_holds, injected, failures, ...); "
                                                   "--format json prints the same report on standard output")
    p.add_argument("--report-html", metavar="FILE",
                   help="write the report as one self-contained HTML page (3-D view of the cell, the tool's path, "
                        "failures, metrics, kit scores, timeline; docs/report.md)")
    p.add_argument("--cell", metavar="URL", help="the cell to drive: sim: (the in-process simulator, the default; "
                                                  "sim:?faults=...&seed=N&noise=... as the options), "
                                                  "kitkb://HOST:PORT (a cell server: kitkb sim serve; the old "
                                                  "HOST:PORT[,PORT] too), crcl://HOST:PORT?sensor=HOST:PORT (a CRCL "
                                                  "1.x controller and a USARTruth-style sensor: no inspection), or a "
                                                  "scheme another package registers (docs/execution.md, 'Cells by URL')")
    p.add_argument("--sensor-noise", metavar="KEY=VALUE,...", help=SENSOR_NOISE_HELP + "; the simulated cell's "
                   "sensor has it and the checks allow for it (with --cell: what the executor assumes of the cell's "
                   "sensor)")
    p.add_argument("--match-names", action="store_true",
                   help="match the goal's individuals to the initial state's by local name (NIST's files)")
    p.add_argument("--partial-kits", choices=["deliver", "leave"], metavar="deliver|leave",
                   help="when the usable parts cannot finish every kit, the kits they can finish are built (as "
                        "many as possible) and each other kit is delivered partial or left, not delivered "
                        "(default: the domain's soap:hasExecutionPolicy_PartialKits, kitkb's: deliver; docs/execution.md)")
    p.add_argument("--scoring", choices=["ariac-2023", "ariac-2024"], metavar="ariac-2023|ariac-2024",
                   help="also score the run by NIST ARIAC's kitting score of that year, per quadrant with the reason "
                        "for every point (states written by kitkb ariac import; docs/ariac.md)")
    p.add_argument("--resume", metavar="RUN_ID", type=int,
                   help="instead of INIT GOAL: go on with run RUN_ID of --db, which stopped (its report's stopped), "
                        "as the same run: from its last stable state, the cell sensed again, a new plan to the same "
                        "goal (its files, domain and options as recorded; --faults, --seed and --cell for the cell "
                        "now; docs/execution.md, 'Resuming a stopped run')")
    p.add_argument("--truth", metavar="FILE",
                   help="a state file the simulated cell holds instead of the initial state (the same objects "
                        "placed otherwise); with --resume: the cell as the operator left it (default: as the run "
                        "left it, written to OUT/<scenario>/resume-RUN_ID-stopped.ttl); an object it does not "
                        "locate is not in the cell")


def _add_crcl(sub: Any) -> None:
    p = sub.add_parser("crcl", help="CRCL robot command files (text form and CRCL XML)",
                       description="CRCL robot command files: the text form (.crcl) and CRCL.xsd XML (.xml).")
    csub = p.add_subparsers(dest="crcl_command", required=True, metavar="SUBCOMMAND")
    g = _sub(csub, "convert", "crcl convert", "convert a CRCL program between text (.crcl) and XML (.xml: "
             "2014 CRCL.xsd, CRCL 1.x program or command instance)")
    g.add_argument("input", metavar="IN", help="a .crcl (text form) or .xml (CRCL XML: 2014 or 1.x) file")
    g.add_argument("-o", "--output", required=True, metavar="OUT",
                   help="output file; the extension chooses the form: .crcl text, .xml CRCL XML")
    g.add_argument("--xsd", metavar="PATH",
                   help="CRCL.xsd to check XML against (default: $KITKB_NIST_DIR/CRCL.xsd, else "
                        "../shared/nist/CRCL.xsd beside the checkout; without one, XML is checked by "
                        "kitkb's own reader only)")
    g.add_argument("--text-style", choices=["nist", "paper"], metavar="nist|paper",
                   help="the layout of CRCL text written (.crcl): nist, NIST's kittingViewer form, which its "
                        "parser reads (MoveThroughTo({ pose,<newline> pose }, n); the default), or paper, the "
                        "first paper's Fig. 11 form (MoveThroughTo(pose, pose, n)); both are read")
    g.add_argument("--xml-form", choices=["2014", "1.x", "command"], metavar="2014|1.x|command",
                   help="the CRCL XML written (.xml): 2014, NIST's early CRCL.xsd program; 1.x, a CRCL 1.x "
                        "program (CRCLProgramInstance.xsd, CommandIDs 1, 2, ...); command, a CRCL 1.x command "
                        "instance of the program's one command (default: 1.x for a CRCL 1.x input, else 2014). "
                        "All are read; units are said after InitCanon where the forms' defaults differ "
                        "(docs/crcl.md)")
    _add_crcl_send(csub)


def _add_crcl_send(csub: Any) -> None:
    g = _sub(csub, "send", "crcl send", "stream a CRCL program to a CRCL 1.x controller, one command at a time",
             format_help="text: one line (all done, or the command that was not); json: one object with each "
                         "command's outcome (id, command, state, seconds) and the last status (pose, gripper) "
                         "(default text)",
             description="Send the commands of FILE (a CRCL 1.x program or command instance, a 2014 CRCL.xsd "
                         "program, or the text form, with its units said) to the CRCL 1.x controller at "
                         "HOST:PORT as CRCLCommandInstance documents on one TCP connection, CommandIDs 1, 2, ..., "
                         "each waited for until a CRCLStatus names it CRCL_Done or CRCL_Error (GetStatus sent "
                         "while the controller is silent). Exit 0 when every command is done, 1 when one ends in "
                         "CRCL_Error or is not acknowledged within --timeout (named), 2 for bad input, a "
                         "controller that cannot be reached or breaks the protocol.")
    g.add_argument("file", metavar="FILE", help="a .xml (CRCL 1.x or 2014 CRCL.xsd) or .crcl (text) file")
    g.add_argument("--to", required=True, metavar="HOST:PORT", help="the CRCL 1.x controller")
    g.add_argument("--timeout", type=float, default=30.0, metavar="S",
                   help="seconds to wait for each command's Done or Error (default 30)")


def _add_metrics(sub: Any) -> None:
    p = _sub(sub, "metrics", "metrics", "the static metrics of a CRCL program (the kittingViewer's ACE ... UCE)",
             format_help="text: a table of the metrics and the score; json: one object with metrics, names, "
                         "units, robot, score and (with --per-command) rows, then on one line (default text)",
             description="Evaluate a CRCL program (.crcl text or .xml CRCL XML) command by command on a "
                         "simulated robot and print the first paper's static metrics with cumulative values: "
                         "ACE, OCE, TCE, TDM, CCE, TET, RE, PE, CSE, TE, UCE (docs/metrics.md defines them), "
                         "and a weighted total score.")
    p.add_argument("program", metavar="PROGRAM", nargs="?",
                   help="a .crcl (text form) or .xml (CRCL XML) program (or --run RUN_ID --db URL)")
    p.add_argument("--run", metavar="RUN_ID", type=int,
                   help="instead of a program: the execution metrics and kit scores of a run recorded in --db "
                        "(and the static metrics of the CRCL it sent), from its records, without running it again")
    p.add_argument("--db", metavar="URL",
                   help="with --run: the world-model database (SQLite file or PostgreSQL URL) the run was recorded in")
    p.add_argument("--per-command", action="store_true",
                   help="also print the metrics after every command, one row each, as NIST's kittingViewer "
                        "showed them")
    p.add_argument("--max-speed", type=float, metavar="M/S",
                   help="the robot's maximum speed of the controlled point in m/s (default 1, the kittingViewer's)")
    p.add_argument("--max-acceleration", type=float, metavar="M/S2",
                   help="the robot's maximum acceleration in m/s² (default 10, the kittingViewer's)")
    p.add_argument("--config", metavar="WEIGHTS.toml",
                   help="TOML file with a [weights] table, metric = weight, for the total score (default "
                        "weights: docs/metrics.md)")
    p.add_argument("--init", metavar="STATE",
                   help="also play the program on a simulated cell of this initial state file: objects moved "
                        "(OM) and constraint violations (OVW overweight grasps, WVE moves out of the work volume, "
                        "WEE wrong effectors, CTE contacts along every move; docs/metrics.md)")
    p.add_argument("--goal", metavar="STATE",
                   help="with --init: the goal state file, for the objects that should have moved (OSM) and those "
                        "moved to the right (OMR) or a wrong place (OMW), decided by the ontology's predicates")
    p.add_argument("--match-names", action="store_true",
                   help="with --goal: match its individuals to the initial state's by local name (NIST's files)")
    p.add_argument("--length-unit", choices=list(LENGTH),
                   help="the unit of the program's lengths until it sets one, set again by InitCanon (default "
                        "millimeter, the paper's; kitkb's executor sends meter)")


def _add_predicates(sub: Any) -> None:
    p = _sub(sub, "predicates", "predicates", "the predicates that hold in a state file, computed from its geometry",
             format_help="text: name(arg1, arg2) a line; json: a list of {predicate, args} (default text)",
             description="Print every predicate atom that holds in a workstation state file, one "
                         "name(arg1, arg2) a line, evaluated from the definitions in the domain "
                         "ontology (3-D RCC8 relations of the objects' boxes, SKU and model facts).")
    p.add_argument("state", nargs="+", metavar="STATE", help="state file(s) of one workstation state")
    p.add_argument("--goal", metavar="FILE",
                   help="also take the individuals that only this file (the goal state) names, with their "
                        "model facts but no geometry, as the PDDL generator does (NIST's kits)")
    p.add_argument("--match-names", action="store_true",
                   help="with --goal: match its individuals to the state's by local name (NIST's files)")
    _domain_option(p)
    p.add_argument("-p", "--predicate", action="append", metavar="NAME", help="only this predicate (repeatable)")
    p.add_argument("--tolerance", type=float, metavar="METRES",
                   help="contact and equality tolerance in metres (default 0.001)")


def _add_faults(sub: Any) -> None:
    p = _sub(sub, "faults", "faults", "the fault kinds a simulated cell can inject, as the domain declares them",
             format_help="text: a line per kind; json: one object with kinds and default_mix (default text)",
             description="List the fault kinds (soap:FaultKind individuals of the shipped kitting-domain.ttl and "
                         "of --domain extensions) that --faults names: the actions each strikes, the simulator "
                         "mechanism that carries it out, the failure modes that diagnose it right, whether it must "
                         "be detected or may be absorbed, whether its diagnosis rejects the object, and its rate "
                         "in the errors test method's default mix. docs/soap.md explains how to declare one.")
    _domain_option(p)


def _add_sim(sub: Any) -> None:
    p = sub.add_parser("sim", help="the simulated workcell", description="The simulated workcell.")
    ssub = p.add_subparsers(dest="sim_command", required=True, metavar="SUBCOMMAND")
    g = _sub(ssub, "serve", "sim serve", "serve a simulated workcell on 127.0.0.1 until SIGINT or SIGTERM",
             format_help="text: one line with the bound ports; json: one object with init, host, sensor_port, "
                         "command_port and cell (the --cell address) (default text)",
             description="Serve a simulated workcell of a state file on 127.0.0.1: a sensor port speaking "
                         "USARTruth key-value lines ({Class C}, {Name N}, {Inspect N}) and a command port "
                         "that is a CRCL 1.x controller (CRCLCommandInstance documents in, CRCLStatus documents "
                         "out; several clients at once, e.g. a robot and a gripper, drive the same robot), which "
                         "also takes kitkb's earlier {Length N} programs, as kb.crcl.wire documents. "
                         "Prints one line with the bound ports; runs until SIGINT or SIGTERM (exit 0).")
    g.add_argument("init", metavar="INIT", help="initial state file of the cell")
    g.add_argument("--goal", metavar="GOAL",
                   help="goal state file: its individuals that INIT lacks (a kit to create) exist, unplaced")
    g.add_argument("--faults", metavar="KIND=RATE,...",
                   help="faults to inject: kind=probability per eligible action or kind@action_index, "
                        f"comma-separated ({FAULT_KINDS_HELP})")
    _domain_option(g)
    g.add_argument("--seed", type=int, default=0, help="seed of the faults and the sensor noise (default 0)")
    g.add_argument("--sensor-noise", metavar="KEY=VALUE,...", help=SENSOR_NOISE_HELP)
    g.add_argument("--noise", metavar="POS_SIGMA,ANGLE_SIGMA",
                   help="the old spelling of --sensor-noise (bare sigmas in metres and radians): refused, with the "
                        "new spelling of the same values")
    g.add_argument("--sensor-port", type=int, default=3989, metavar="P",
                   help="sensor port (default 3989, USARTruth's; 0: any free port)")
    g.add_argument("--command-port", type=int, default=3990, metavar="P",
                   help="command port, the CRCL 1.x controller (default 3990; 0: any free port)")
    g.add_argument("--status-period", type=float, default=1.0, metavar="S",
                   help="a CRCL 1.x connection sent no status for S seconds is sent one (a heartbeat; "
                        "default 1; 0: statuses only when a command ends and on GetStatus)")
    g.add_argument("--engine", choices=["kinematic", "mujoco"], default="kinematic", metavar="kinematic|mujoco",
                   help="the simulator behind the ports: kitkb's kinematic cell (default) or the physics-based "
                        "cell on MuJoCo (docs/physics.md)")
    g = _sub(ssub, "export-mjcf", "sim export-mjcf", "write a state's MuJoCo scene (MJCF) as the physics cell builds it",
             format_help="text: one line with the file and its bodies; json: one object with output, bodies, free, "
                         "fixed and mocap (default text)",
             description="Write the MJCF scene the MuJoCo cell (--cell mujoco:) builds from a state file: its "
                         "solids as MuJoCo bodies (boxes, cylinders, open containers as floor and walls), parts "
                         "and trays free, the rest fixed, the flange and effectors mocap bodies; MuJoCo's viewer "
                         "opens it (python -m mujoco.viewer --mjcf FILE). docs/physics.md.")
    g.add_argument("init", metavar="INIT", help="state file")
    g.add_argument("-o", "--output", required=True, metavar="OUT", help="the MJCF file to write (.xml)")
    g.add_argument("--goal", metavar="GOAL", help="goal state file: its individuals that INIT lacks exist, unplaced")


def _add_testmethod(sub: Any) -> None:
    p = _sub(sub, "testmethod", "testmethod", "run one of the first paper's test methods as a seeded campaign on Dask",
             format_help="text: a line per trial and the summary (kits built, mean / median / p95 of each metric, "
                         "failures by mode, recoveries); json: one object with the summary and the rows (default text)",
             description="Run one of the first paper's four test methods (§III) as a campaign of seeded trials on "
                         "Dask distributed: basic (one kit, kit tray and parts trays placed and turned anew each "
                         "trial), new-variety (a design never seen, delivered as Turtle files: the time from receipt "
                         "to the first CRCL command), multi (several designs in a seeded order, kit trays from "
                         "storage), errors (dropped and defective parts to recover from). Each trial's report goes "
                         "to DIR/trials/NNNNN.json and the summary to DIR/campaign.json; a campaign run again into "
                         "the same DIR resumes. docs/testmethods.md describes the methods.")
    p.add_argument("method", choices=["basic", "new-variety", "multi", "errors"], metavar="METHOD",
                   help="basic, new-variety, multi or errors")
    p.add_argument("--trials", type=int, default=10, help="number of trials (default 10)")
    p.add_argument("--seed", type=int, default=0, help="campaign seed: the same seed gives the same trials (default 0)")
    p.add_argument("--parts", metavar="N[,N...]", help="parts of the kit design (multi: one size per design; "
                                                        "default 10, multi 4,6)")
    p.add_argument("--kits", type=int, help="multi: kits built in a trial, of the designs in a seeded order (default 3)")
    p.add_argument("--faults", metavar="KIND=RATE,...",
                   help="errors: the faults injected (default: each fault kind at its test-method rate, as "
                        "kitkb faults lists them; " + FAULT_KINDS_HELP + ")")
    p.add_argument("--sensor-noise", metavar="KEY=VALUE,...",
                   help=SENSOR_NOISE_HELP + "; every trial's simulated sensor has it and its checks allow for it")
    p.add_argument("--noise-sweep", metavar="KEY=FROM:TO:N",
                   help="errors: run every trial at N levels of one noise key from FROM to TO (e.g. "
                        "position=0mm:5mm:6 or orientation=0deg:1deg:5; over --sensor-noise for the other keys), "
                        "with the same seed, and score detection quality per level")
    p.add_argument("--cell", metavar="URL",
                   help="sim: (default: every trial its own simulated cell of its real placement), or one cell at a "
                        "URL as kitkb run --cell takes it that the trial runs on, its placement the cell's own: "
                        "one trial, not the errors method")
    p.add_argument("--partial-kits", choices=["deliver", "leave"], metavar="deliver|leave",
                   help="a kit a trial's usable parts cannot finish is delivered partial or left, after the kits they "
                        "can finish (default: the domain's policy, kitkb's: deliver; as kitkb run --partial-kits)")
    _domain_option(p)
    where = p.add_mutually_exclusive_group()
    where.add_argument("--workers", type=int, metavar="N",
                       help="Dask worker processes of a local cluster on this machine (default: one per core)")
    where.add_argument("--scheduler", metavar="ADDR", help="a running Dask scheduler (tcp://host:8786) instead")
    p.add_argument("--out", dest="output", metavar="DIR",
                   help="campaign folder (default out/testmethod-METHOD); the trials already in it are not run again")


def _add_report(sub: Any) -> None:
    p = _sub(sub, "report", "report", "one HTML page of a run report or a campaign (3-D view, metrics, kit scores, "
                                      "timeline)",
             description="Draw a run's JSON report (kitkb run --report) or a campaign folder (kitkb testmethod "
                         "--out DIR) as one self-contained HTML page that opens with no network: the workstation "
                         "in 3-D with the tool tip's path and the failures, the metrics, the kit scores with every "
                         "lost point, a timeline of actions, failures and recoveries; for a campaign the metrics "
                         "across the trials and the failed trials, each with a page of its own in DIR/report/. "
                         "docs/report.md shows what a page holds.")
    p.add_argument("input", metavar="RUN.json|CAMPAIGN_DIR", help="a run report, or a campaign folder")
    p.add_argument("-o", "--output", required=True, metavar="OUT.html", help="the HTML page to write")


def _add_ariac(sub: Any) -> None:
    p = sub.add_parser("ariac", help="NIST ARIAC's kitting trials (YAML files) as kitkb states, run and scored",
                       description="NIST ARIAC's kitting trials: import a trial file as kitkb states, run it end to "
                                   "end, score a run by ARIAC's kitting score of a year (docs/ariac.md).")
    asub = p.add_subparsers(dest="ariac_command", required=True, metavar="SUBCOMMAND")
    i = _sub(asub, "import", "ariac import", "write a trial's initial and goal states (and ariac.json)")
    i.add_argument("trial", metavar="TRIAL.yaml", help="an ARIAC trial file (2023 or 2024 format)")
    i.add_argument("-o", "--output", required=True, metavar="DIR", help="output folder (init.ttl, goal.ttl, ariac.json)")
    r = _sub(asub, "run", "ariac run", "import a trial, run its kitting orders in a cell and score them")
    r.add_argument("trial", metavar="TRIAL.yaml", help="an ARIAC trial file")
    r.add_argument("-o", "--output", default="out/ariac", metavar="DIR", help="folder of the states and run outputs "
                                                                            "(default out/ariac)")
    r.add_argument("--report", metavar="FILE", help="write the run's report with its ARIAC scores (JSON)")
    r.add_argument("--cell", metavar="URL", help="the cell to drive (as kitkb run --cell; default the simulated cell)")
    r.add_argument("--faults", metavar="KIND=RATE,...", help="faults to inject (as kitkb run --faults)")
    r.add_argument("--seed", type=int, default=0, help="seed of the cell's faults (default 0)")
    r.add_argument("--partial-kits", choices=["deliver", "leave"], default="deliver", metavar="deliver|leave",
                   help="a kit the parts cannot finish is submitted partial (ARIAC's rule, the default) or left")
    s = _sub(asub, "score", "ariac score", "ARIAC's kitting score of a recorded run, per quadrant with reasons")
    s.add_argument("report", metavar="REPORT.json", help="the report of kitkb run on an imported trial's states")
    s.add_argument("--scoring", choices=["ariac-2023", "ariac-2024"], required=True, metavar="ariac-2023|ariac-2024",
                   help="the year whose scoring code to follow (docs/metrics.md, \"ARIAC's kitting score\")")
    s.add_argument("--trial", metavar="DIR", help="the import's folder (its ariac.json; default: where the report "
                                                  "says, else beside the report)")


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of the ``kitkb`` command."""
    parser = argparse.ArgumentParser(prog="kitkb", description=DESCRIPTION, epilog=EXIT_CODES)
    parser.add_argument("-q", "--quiet", action="store_true", help="print no line on success")
    parser.add_argument("--traceback", action="store_true", help="show the Python traceback of an error")
    sub = parser.add_subparsers(dest="subcommand", required=True, metavar="COMMAND")
    for add in (_add_files, _add_scenario, _add_generate, _add_plan, _add_db, _add_run, _add_crcl, _add_metrics,
                _add_predicates, _add_faults, _add_sim, _add_testmethod, _add_report, _add_ariac):
        add(sub)
    return parser


def handler(command: str) -> Callable[..., int]:
    """The handler function of a subcommand (its module imported now)."""
    module, _, function = HANDLERS[command].partition(":")
    return getattr(importlib.import_module(module), function)


#: Options that name files a command reads (noted before it runs, so that no output replaces
#: them even where a forked child does the reading), and the option naming its database.
_INPUT_OPTIONS = ("files", "input", "init", "goal", "first", "second", "datafile", "state", "domain", "file",
                  "xsd", "program", "config", "shapes", "truth")


def _guard(options: dict[str, Any]) -> Any:
    """The command's :func:`~kb.core.files.command_scope` with its input files and database."""
    inputs: list[str] = []
    for name in _INPUT_OPTIONS:
        value = options.get(name)
        if isinstance(value, str):
            inputs.append(value)
        elif isinstance(value, (list, tuple)):
            inputs.extend(v for v in value if isinstance(v, str))
    db = options.get("db")
    databases = [db] if isinstance(db, str) and "://" not in db else []
    return command_scope(inputs=inputs, databases=databases,
                         outputs=[v for v in (options.get("output"), options.get("report"), options.get("report_html"))
                                  if isinstance(v, str)])


_PARSER_ONLY = {"subcommand", "scenario_command", "generate_command", "db_command", "crcl_command",
                "sim_command", "command", "quiet", "traceback"}


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``kitkb`` command; the exit code."""
    return _dispatch(build_parser().parse_args(argv))


def _dispatch(args: argparse.Namespace) -> int:
    out = Output(quiet=args.quiet, format=getattr(args, "format", "text"), command=args.command)
    try:
        fn = handler(args.command)
        accepted = inspect.signature(fn).parameters
        options = {k: v for k, v in vars(args).items() if k not in _PARSER_ONLY and k in accepted}
        with _guard(options):  # no output of this command may replace a file it reads
            return int(fn(out=out, **options) or 0)
    except KitkbError as exc:
        if args.traceback:
            raise
        print(str(exc), file=sys.stderr)
        return exc.exit_code
    except KeyboardInterrupt:
        print("kitkb: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:  # the reader went away (``kitkb validate ... | head``)
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 1
    except Exception as exc:  # a bug of ours: still one line, never a traceback by default
        if args.traceback:
            raise
        print(f"kitkb: internal error: {type(exc).__name__}: {exc} (run with --traceback)", file=sys.stderr)
        return 3


def run() -> None:
    """The console script: :func:`main`, then exit.

    A one-shot process: for ``validate`` (and ``db load`` / ``db dump``, which stream a big file
    through hundreds of thousands of rows) the cyclic garbage collector would only walk the
    millions of objects of a big file again (0.4 s at 10,000 parts), and freeing them one by
    one at exit only costs time, so it runs without the collector and the process ends with
    ``os._exit`` once the output is flushed (the database is committed and closed by then).
    ``run`` runs without the collector too (what it reads and makes lives to its end, frozen
    stage by stage; its passes over the imports, the reading and the world-model load were
    0.1-0.2 s of a 160-part run, and the peak RSS is no higher) and ends with the objects frozen.
    """
    args = build_parser().parse_args()
    fast = args.command in ("validate", "shacl", "db load", "db dump")
    if fast or args.command == "run":
        gc.disable()
    code = _dispatch(args)
    if fast:
        try:
            sys.stdout.flush()
            sys.stderr.flush()
        except BrokenPipeError:
            code = code or 1
        except OSError:
            pass
        os._exit(code)
    if args.command == "run":  # its objects live to the end: not walked by a last collection at exit
        gc.freeze()  # (0.4 s of a 160-part run; atexit handlers and flushes still run)
    sys.exit(code)


if __name__ == "__main__":  # pragma: no cover
    run()
