"""The units a CRCL program's numbers are in, by the form it is written in (docs/crcl.md).

A controller resets its length and angle units at ``InitCanon`` to the defaults of the language
it speaks: the first paper's (its text forms and NIST's 2014 CRCL.xsd XML) are millimetre and
degree, CRCL 1.x's (doc/Reference.md) metre and radian. A :class:`~kb.crcl.commands.Program`
carries the defaults of the form it was read from (``units``); :func:`restate` makes it mean
the same in a form with other defaults, by saying its units right after each ``InitCanon``.
"""

from __future__ import annotations

from kb.core.errors import InputError
from kb.crcl import commands as c
from kb.crcl.commands import (CRCL1_UNITS, PAPER_UNITS, Command, InitCanon, Program, SetAngleUnits,
                              SetLengthUnits)

#: Commands whose meaning does not depend on the length or angle unit in force.
UNIT_FREE = (c.InitCanon, c.EndCanon, c.Message, c.Dwell, c.OpenGripper, c.CloseGripper, c.OpenToolChanger,
             c.CloseToolChanger, c.SetLengthUnits, c.SetAngleUnits, c.GetStatus, c.SetEndEffector,
             c.SetRelativeSpeed, c.SetRelativeAcceleration, c.StopMotion, c.SetForceUnits, c.SetTorqueUnits,
             c.SetMotionCoordination, c.RunProgram, c.SetEndEffectorParameters, c.SetRobotParameters,
             c.ConfigureJointReports, c.Unreadable, c.StartObjectScan, c.StopObjectScan, c.SetCoordinateFrame)

#: Form -> the (length, angle) units its InitCanon sets.
FORM_UNITS: dict[str, tuple[str, str]] = {
    "text": PAPER_UNITS,   # the first paper's §V-C (and the kittingViewer that reads it)
    "xml": PAPER_UNITS,    # NIST's 2014 CRCL.xsd: the paper's language; its documentation names no default
    "1.x": CRCL1_UNITS,    # CRCL 1.x: doc/Reference.md §VI
}


def restate(program: Program, units: tuple[str, str]) -> Program:
    """``program`` for a controller that resets to ``units`` at InitCanon: after each
    InitCanon, a SetLengthUnits / SetAngleUnits naming the program's own default where it
    differs and the commands right after that InitCanon do not set it themselves. A program
    whose units are not known (None) or already ``units`` is returned as it is; the result
    carries ``units``. Commands before the first InitCanon are left as they are
    (:func:`check_lone` says whether their units would be lost)."""
    own = program.units
    if own is None or tuple(own) == tuple(units):
        return Program(program.commands, source=program.source, units=units if own is not None else None)
    out: list[Command] = []
    commands = program.commands
    for i, command in enumerate(commands):
        out.append(command)
        if isinstance(command, InitCanon):
            out.extend(_said(commands, i + 1, own, units))
    return Program(tuple(out), source=program.source, units=tuple(units))  # type: ignore[arg-type]


def check_lone(program: Program, units: tuple[str, str]) -> None:
    """InputError at the first command before any InitCanon whose numbers are lengths or angles
    when ``program``'s units differ from ``units``: written in a form that resets to ``units``
    (a file of its own), nothing could say its units."""
    own = program.units
    if own is None or tuple(own) == tuple(units):
        return
    for command in program.commands:
        if isinstance(command, InitCanon):
            return
        if not isinstance(command, UNIT_FREE):
            raise InputError(f"{type(command).__name__} before any InitCanon is in {' and '.join(own)}, which the "
                             f"form written resets to {' and '.join(units)}: give the program an InitCanon, after "
                             "which its units are said", program.source, command.line)


def _said(commands: tuple[Command, ...], start: int, own: tuple[str, str], units: tuple[str, str]) -> list[Command]:
    """The unit commands to add after the InitCanon before ``start``."""
    following = set()
    for command in commands[start:]:
        if not isinstance(command, (SetLengthUnits, SetAngleUnits)):
            break
        following.add(type(command))
    added: list[Command] = []
    if own[0] != units[0] and SetLengthUnits not in following:
        added.append(SetLengthUnits(own[0]))
    if own[1] != units[1] and SetAngleUnits not in following:
        added.append(SetAngleUnits(own[1]))
    return added


def said_units(units: tuple[str, str] = CRCL1_UNITS) -> list[Command]:
    """The commands that say ``units`` (default SI: metre and radian, in which kitkb's executor
    computes), for right after an InitCanon: every program kitkb sends says its units."""
    return [SetLengthUnits(units[0]), SetAngleUnits(units[1])]


def units_after(commands: tuple[Command, ...] | list[Command], defaults: tuple[str, str]) -> tuple[str, str]:
    """The (length, angle) units in force after ``commands`` on a controller with ``defaults``."""
    length, angle = defaults
    for command in commands:
        if isinstance(command, InitCanon):
            length, angle = defaults
        elif isinstance(command, SetLengthUnits):
            length = command.unit_name
        elif isinstance(command, SetAngleUnits):
            angle = command.unit_name
    return length, angle
