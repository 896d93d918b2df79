"""Write a NIST-shaped state pair whose kit design does not fit its tray (run by hand; the
output is committed).

NIST's second state pair (el-robotics-core, design ``a3b6c4``) puts 13 slots at x -0.372 ..
0.35 m, y -0.306 .. 0.287 m of a kit tray 0.5 x 0.4 m: most of them outside it. This script
rewrites NIST's first pair, ``../shared/nist/kittingInstances{Init,Goal}1.owl`` (public domain),
into that shape: the design ``a2b1c1`` (4 slots) becomes ``a3b6c4`` (3 slots of part a, 6 of b,
4 of c, in NIST's own block layout), the kit tray's SKU 0.4 m wide, every name with ``a2b1c1``
renamed::

    python tests/data/kit_design_fit/make_a3b6c4.py ../shared/nist tests/data/kit_design_fit
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

XS = (-0.372, -0.13, 0.11, 0.35)
YS = (-0.306, -0.108, 0.09, 0.287)
#: (part letter, number, x, y): a 4 x 4 grid spanning NIST's extremes, 13 of its places
SLOTS = [(sku, n, XS[k % 4], YS[k // 4]) for k, (sku, n) in enumerate(
    [("a", 1), ("a", 2), ("a", 3), ("b", 1), ("b", 2), ("b", 3), ("b", 4), ("b", 5), ("b", 6),
     ("c", 1), ("c", 2), ("c", 3), ("c", 4)])]
SLOTS[-1] = ("c", 4, XS[1], YS[3])
BLOCK = re.compile(r"ObjectPropertyAssertion\(ktw:hasKitDesign_PartRefAndPose\n.*?// 3 end ktw:PartRefAndPose\n"
                   r"//\*+\n\n", re.S)


def rewrite(text: str) -> str:
    blocks = list(BLOCK.finditer(text))
    template = blocks[0].group(0)
    new = []
    for sku, n, x, y in SLOTS:
        block = template.replace("a2b1c1_a_1", f"a3b6c4_{sku}_{n}").replace("stock_keeping_unit_part_a",
                                                                           f"stock_keeping_unit_part_{sku}")
        block = re.sub(r'(hasPoint_X :point_kit_\w+\n\s+)"[-0-9.]+"', rf'\g<1>"{x:.6f}"', block)
        block = re.sub(r'(hasPoint_Y :point_kit_\w+\n\s+)"[-0-9.]+"', rf'\g<1>"{y:.6f}"', block)
        new.append(block)
    text = text[:blocks[0].start()] + "".join(new) + text[blocks[-1].end():]
    text, n = re.subn(r'(hasBoxyShape_Width :shape_kit_tray\n\s+)"0\.300000"', r'\g<1>"0.400000"', text)
    assert n == 1
    return text.replace("a2b1c1", "a3b6c4")


def main(src: str, out: str) -> None:
    for name in ("Init", "Goal"):
        text = Path(src, f"kittingInstances{name}1.owl").read_text()
        Path(out, f"kittingInstances{name}-a3b6c4.owl").write_text(rewrite(text))


if __name__ == "__main__":
    main(*sys.argv[1:3])
