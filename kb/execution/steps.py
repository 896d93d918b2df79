"""A plan as the executor carries it out: steps (an action and its argument IRIs), read from
PDDL action lines, and :class:`Stop`, raised when the run cannot go on."""

from __future__ import annotations

import re
from dataclasses import dataclass

from kb.core.errors import KitkbError
from kb.model.soap import ActionSpec
from kb.planning.state import pddl_name

_PLAN_LINE = re.compile(r"^\(\s*([^\s()]+)((?:\s+[^\s()]+)*)\s*\)$")


class Stop(KitkbError):
    """The run cannot go on (no plan left, a remediation that stops for an operator)."""

    exit_code = 1


@dataclass
class Step:
    action: str
    args: dict[str, str]  # parameter name -> IRI
    retries: int = 0
    #: a step of a failure mode's recovery plan: it may handle an object the run found unusable
    #: (clear a condemned part away), and what it takes is not inspected first
    recovery: bool = False

    def line(self) -> str:
        return f"({self.action} {' '.join(pddl_name(a) for a in self.args.values())})"


def parse_plan(lines: list[str], actions: dict[str, ActionSpec], by_name: dict[str, str]) -> list[Step]:
    """Steps of PDDL action lines; ``by_name`` maps PDDL object names to IRIs."""
    steps = []
    for line in lines:
        m = _PLAN_LINE.match(line.strip())
        if m is None:
            raise KitkbError(f"not a plan action: {line!r}")
        name, args = m.group(1), m.group(2).split()
        spec = actions.get(name)
        if spec is None:
            raise KitkbError(f"plan action {name} is not in the domain")
        if len(args) != len(spec.params):
            raise KitkbError(f"plan action {line.strip()}: {name} takes {len(spec.params)} arguments")
        steps.append(Step(name, {p: by_name.get(a, a) for (p, _t), a in zip(spec.params, args)}))
    return steps


class Fields(dict):
    """Arguments by parameter name for ``str.format_map``; an unknown field stays as written."""

    def __missing__(self, key: str) -> str:
        return "{" + key + "}"
