"""``kitkb faults``: the fault kinds a simulated cell can inject, as the domain declares them."""

from __future__ import annotations

from kb.cli.output import Output
from kb.core.namespaces import local_name
from kb.model.faults import FaultKind, domain_fault_kinds


def faults(domain: list[str] | None, format: str, out: Output) -> int:
    """List the fault kinds of the shipped domain and the extension files ``domain``, in their
    order: one line each (name, actions, mechanism, right diagnoses, must be detected, rejecting,
    test-method rate, what happens); with ``--format json`` one object with ``kinds`` and the
    errors method's ``default_mix``."""
    kinds = domain_fault_kinds(domain)
    for kind in kinds:
        for mode in kind.undeclared_modes:
            out.warn(f"warning: fault kind {kind.name}: {local_name(mode)} (hasFaultKind_DiagnosedBy) is no "
                     "failure mode of the domain; it counts as no right diagnosis")
    if format == "json":
        out.emit({"kinds": [k.as_dict() for k in kinds], "default_mix": kinds.default_mix()})
        return 0
    for kind in kinds:
        print(_line(kind), file=out.results)
    return 0


def _line(kind: FaultKind) -> str:
    flags = ["must be detected" if kind.must_detect else "may be absorbed"] + (["rejects"] if kind.rejecting else [])
    rate = f"; errors method rate {kind.test_rate:g}" if kind.test_rate else ""
    diagnosed = ", ".join(sorted(kind.diagnosed_by)) or "none"
    text = f" — {kind.comment}" if kind.comment else ""
    return (f"{kind.name}: on {', '.join(kind.actions)} by {kind.mechanism.name}; diagnosed as {diagnosed}; "
            f"{', '.join(flags)}{rate}{text}")
