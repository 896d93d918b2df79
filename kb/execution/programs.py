"""A domain's action programs checked against what the executor can send, before a run.

An action program (``soap:ActionProgram``, docs/soap.md "Extending the domain in Turtle") is
data: each ``soap:CommandStep`` names a CRCL command and, for a motion, a target function of the
action's parameters. The executor turns a step into a command when the action runs
(:meth:`kb.execution.executor.Executor._commands`); a step it could not turn into one would stop
the run half way. :func:`check_programs` refuses such a domain first, with an
:class:`~kb.core.errors.InputError` at the file and line of the step's statement:

* ``Message`` (its ``hasCommandStep_Text``) and ``Dwell`` (its ``hasCommandStep_Duration``);
* a command with a target: a CRCL command whose one required field is a pose (``MoveTo``,
  ``MoveStraightTo``), the target one of the executor's target functions
  (:data:`kb.execution.targets.FUNCTIONS`) with as many arguments as it takes, each a parameter
  name of the action where it names an object and a number where it is a distance;
* a command without a target: a CRCL command with no required field (``CloseGripper``,
  ``OpenToolChanger`` ...).
"""

from __future__ import annotations

import dataclasses
import inspect

from rdflib.namespace import RDF

from kb.core.errors import InputError
from kb.core.namespaces import SOAP
from kb.crcl import COMMANDS
from kb.crcl.pose import Pose
from kb.execution.targets import FUNCTIONS, parse
from kb.io.loader import KnowledgeBase
from kb.model.soap import DomainSpec

#: the commands the executor makes from a step's own data rather than from CRCL's fields
DATA_COMMANDS = {"Message": "hasCommandStep_Text", "Dwell": "hasCommandStep_Duration"}


def _required(command: str) -> list[dataclasses.Field]:
    return [f for f in dataclasses.fields(COMMANDS[command]) if f.default is dataclasses.MISSING
            and f.default_factory is dataclasses.MISSING]


def pose_commands() -> list[str]:
    """The CRCL commands a step with a target can be: one required field, a pose."""
    return sorted(n for n in COMMANDS if n not in DATA_COMMANDS and
                  [str(f.type) for f in _required(n)] in (["Pose"], [Pose.__name__]))


def plain_commands() -> list[str]:
    """The CRCL commands a step without a target can be: no required field."""
    return sorted(n for n in COMMANDS if n not in DATA_COMMANDS and not _required(n))


def _signature(function: str) -> list[str]:
    """The annotations of a target function's arguments: 'str' (an object), 'float' (metres)."""
    params = list(inspect.signature(FUNCTIONS[function]).parameters.values())[1:]  # without self
    return [str(p.annotation) for p in params if p.default is inspect.Parameter.empty]


def check_programs(kb: KnowledgeBase, domain: DomainSpec) -> None:
    """Every command step of every action program in ``kb`` is one the executor can send
    (module docstring); InputError at the first that is not."""
    g = kb.graph
    params = {a.name: {n for n, _ in a.params} for a in domain.actions}
    pose, plain = pose_commands(), plain_commands()
    for program in sorted(g.subjects(RDF.type, SOAP.ActionProgram), key=str):
        action = g.value(program, SOAP.hasActionProgram_Action)
        name = g.value(action, SOAP.hasAction_Name) if action is not None else None
        if name is None or str(name) not in params:
            continue  # the failure model's reader reports a program of no action
        for step in sorted(g.objects(program, SOAP.hasActionProgram_Step), key=str):
            _check_step(kb, step, str(name), params[str(name)], pose, plain)


def _check_step(kb: KnowledgeBase, step, action: str, names: set[str], pose: list[str],  # noqa: ANN001
                plain: list[str]) -> None:
    g = kb.graph
    command = g.value(step, SOAP.hasCommandStep_Command)
    target = g.value(step, SOAP.hasCommandStep_Target)
    if command is None:
        return  # the failure model's reader reports it

    def fail(message: str, prop=SOAP.hasCommandStep_Command, value=command) -> None:  # noqa: ANN001
        found = kb.source_of(step, prop, value) or kb.source_of(step)
        path, line = (str(found[0].path), found[1]) if found else (None, None)
        raise InputError(f"action program of {action}: {message}", path, line)

    text = str(command)
    if text in DATA_COMMANDS:
        if target is not None:
            fail(f"{text} takes no target (it was given {str(target)!r})", SOAP.hasCommandStep_Target, target)
        return
    if text not in COMMANDS:
        fail(f"command {text!r} is not a CRCL command kitkb sends (with a target: {', '.join(pose)}; without: "
             f"{', '.join(plain)}; or {', '.join(DATA_COMMANDS)})")
    if target is None:
        if text not in plain:
            fail(f"command {text} needs a target (hasCommandStep_Target)" if text in pose else
                 f"command {text} takes values an action program cannot give (kitkb sends {', '.join(plain)} "
                 "without a target)")
        return
    if text not in pose:
        fail(f"command {text} takes no target pose (with a target: {', '.join(pose)})")
    _check_target(str(target), names, lambda m: fail(m, SOAP.hasCommandStep_Target, target))


def _check_target(expr: str, names: set[str], fail) -> None:  # noqa: ANN001
    try:
        function, args = parse(expr)
    except ValueError as e:
        fail(str(e))
        return
    wanted = _signature(function)
    if len(args) != len(wanted):
        fail(f"target {expr!r}: {function} takes {len(wanted)} argument(s), not {len(args)}")
    for arg, kind in zip(args, wanted):
        if kind == "float":
            try:
                float(arg)
            except ValueError:
                fail(f"target {expr!r}: {arg!r} is not a number (metres)")
        elif arg not in names:
            fail(f"target {expr!r}: {arg!r} is not a parameter of the action ({', '.join(sorted(names))})")

