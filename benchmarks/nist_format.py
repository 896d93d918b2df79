"""Write a kitkb workstation (init + goal state files) as a problem in NIST's own PDDL format.

The baseline of ``bench_plan.py``: NIST's hand-written numeric domain
(``/work/shared/nist/domain-fluents.pddl``) with a problem of the same size as a kitkb
scenario, written the way NIST's ``problem-fluents-*.pddl`` files are (same predicates,
``part-not-searched`` flag, ``origin-part``, ``capacity-kit``/``quantity-kit`` per parts
tray, ``quantity = capacity`` goals). Parts go to kits exactly as in kitkb's STRIPS problem
(:attr:`ProblemSpec.quota`), so both planners build the same kits from the same trays.

    .venv/bin/python benchmarks/nist_format.py INIT GOAL -o problem.pddl
"""

from __future__ import annotations

import argparse
from collections import Counter, defaultdict
from pathlib import Path

KTW = "https://w3id.org/kitkb/kitting#"
NIST_TYPES = {
    "Robot": "Robot", "EndEffectorChangingStation": "EndEffectorChangingStation", "KitTray": "KitTray",
    "Kit": "Kit", "LargeBoxWithEmptyKitTrays": "LargeBoxWithEmptyKitTrays",
    "LargeBoxWithKits": "LargeBoxWithKits", "WorkTable": "WorkTable", "PartsTray": "PartsTray",
    "Part": "Part", "EndEffector": "EndEffector", "EndEffectorHolder": "EndEffectorHolder",
}


def nist_problem(init: Path, goal: Path) -> tuple[str, int, int]:
    """NIST-format problem text, number of kit parts, number of kits."""
    from kb.planning.model import kitting_model

    spec = kitting_model([init], [goal], "numeric").problem
    assert spec is not None
    kind = {name: cls.removeprefix(KTW) for name, (cls, _iri) in spec.objects.items()}
    facts = defaultdict(list)
    for fact in sorted(spec.facts):
        facts[fact[0]].append(fact[1:])
    tray_of = {part: tray for part, tray in facts["part-location-partstray"]}
    capacity: Counter = Counter()
    for (_f, kit, _sku), parts in spec.quota.items():
        for part in parts:
            capacity[(kit, tray_of[part])] += 1
    tray_count = Counter(tray_of.values())
    init_lines = []
    add = init_lines.append
    for holder, station in facts["endeffectorholder-location-changingstation"]:
        add(f"(endeffectorholder-location {holder} {station})")
        add(f"(endeffectorchangingstation-contains-endeffectorholder {station} {holder})")
    for (robot,) in facts["robot-with-no-endeffector"]:
        add(f"(robot-with-no-endeffector {robot})")
    for ee, robot in facts["endeffector-location-robot"]:
        add(f"(endeffector-location-robot {ee} {robot})")
        add(f"(robot-with-endeffector {robot} {ee})")
    for (robot,) in facts["robot-empty"]:
        add(f"(robot-empty {robot})")
    for (holder,) in facts["endeffectorholder-empty"]:
        add(f"(endeffectorholder-empty {holder})")
    add("(part-not-searched)")
    for box in sorted({b for _t, b in facts["kittray-location-lbwekt"]}):
        add(f"(lbwekt-not-empty {box})")
    for (box,) in facts["lbwk-not-full"]:
        add(f"(lbwk-not-full {box})")
    for (tray,) in facts["partstray-not-empty"]:
        add(f"(partstray-not-empty {tray})")
    for ee, holder in facts["endeffector-location-endeffectorholder"]:
        add(f"(endeffector-location-endeffectorholder {ee} {holder})")
        add(f"(endeffectorholder-holds-endeffector {holder} {ee})")
    for (table,) in facts["worktable-empty"]:
        add(f"(worktable-empty {table})")
    for tray, box in facts["kittray-location-lbwekt"]:
        add(f"(kittray-location-lbwekt {tray} {box})")
    for part, tray in facts["part-location-partstray"]:
        add(f"(part-location-partstray {part} {tray})")
        add(f"(origin-part {part} {tray})")
    for pred in ("endeffector-type-part", "endeffector-type-kittray", "endeffector-type-kit"):
        for ee, thing in facts[pred]:
            add(f"({pred} {ee} {thing})")
    kits = sorted(n for n, k in kind.items() if k == "Kit")
    trays = sorted(n for n, k in kind.items() if k == "PartsTray")
    goals = []
    for kit in kits:
        for tray in trays:
            add(f"(= (capacity-kit {kit} {tray}) {capacity[(kit, tray)]})")
            add(f"(= (quantity-kit {kit} {tray}) 0)")
            if capacity[(kit, tray)]:
                goals.append(f"(= (quantity-kit {kit} {tray}) (capacity-kit {kit} {tray}))")
    for tray in trays:
        add(f"(= (quantity-partstray {tray}) {tray_count[tray]})")
    goals += [f"(kit-location-lbwk {kit} {box})" for _p, kit, box in spec.goal if _p == "kit-location-lbwk"]
    by_type = defaultdict(list)
    for name, k in kind.items():
        if k in NIST_TYPES:
            by_type[NIST_TYPES[k]].append(name)
    objects = "\n".join(f"\t\t{' '.join(sorted(v))} - {t}" for t, v in sorted(by_type.items()))
    text = ("(define (problem kitting-problem)\n\t(:domain kitting-domain)\n\t(:objects\n"
            f"{objects}\n\t)\n\t(:init\n\t\t" + "\n\t\t".join(init_lines) + "\n\t)\n"
            "\t(:goal (and\n\t\t" + "\n\t\t".join(goals) + "\n\t))\n)\n")
    return text, sum(capacity.values()), len(kits)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("init")
    parser.add_argument("goal")
    parser.add_argument("-o", "--output", required=True)
    args = parser.parse_args()
    text, parts, kits = nist_problem(Path(args.init), Path(args.goal))
    Path(args.output).write_text(text, encoding="utf-8")
    print(f"wrote {args.output}: {parts} kit parts, {kits} kit(s)")


if __name__ == "__main__":
    main()
