"""Write NIST-shaped state files whose locations name reference objects the state does not place
(run by hand; the output is committed).

A pose is given in the frame of its location's ``hasPhysicalLocation_RefObject``. NIST's files
mix poses with relative locations, which have no point (``kittingInstancesInitNoLoc.owl``
gives its parts ``RelativeLocationIn`` locations), and a name may be misspelt. This script
rewrites NIST's first initial state, ``../shared/nist/kittingInstancesInit1.owl`` (public
domain)::

    python tests/data/unknown_reference/make_unknown_reference.py ../shared/nist tests/data/unknown_reference

* ``kittingInstancesRelativeTray.owl``: part_a_tray is located by a ``RelativeLocationIn`` (in
  the workstation, no point), as NIST's InitNoLoc locates its parts; part_a_1 and part_a_2 keep
  their poses in part_a_tray's frame, which the state no longer places;
* ``kittingInstancesMisspelt.owl``: part_b_1's pose refers to ``:part_b_tary``, declared nowhere;
* ``kittingInstancesRelativeParts.owl``: part_a_1 and part_a_2 are located by
  ``RelativeLocationIn`` in part_a_tray (as InitNoLoc's parts): they are not placed, and nothing
  refers to them (a state kitkb reads as before).
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

RELATIVE = """ObjectPropertyAssertion(ktw:hasSolidObject_PrimaryLocation
                        :{obj} :{obj}_location)

//*****************************************
// {depth} start ktw:RelativeLocationIn {obj}_location
Declaration(NamedIndividual(:{obj}_location))
ClassAssertion(ktw:RelativeLocationIn :{obj}_location)
ObjectPropertyAssertion(ktw:hasPhysicalLocation_RefObject
                        :{obj}_location :{ref})
DataPropertyAssertion(ktw:hasRelativeLocation_Description :{obj}_location
                      "The {kind} is in {ref}"^^xsd:string)
// {depth} end ktw:RelativeLocationIn
//*****************************************
"""


def relative(text: str, obj: str, ref: str, kind: str, depth: int) -> str:
    """``obj``'s pose location (with its point and axes) replaced by a RelativeLocationIn in ``ref``."""
    pattern = (rf"ObjectPropertyAssertion\(ktw:hasSolidObject_PrimaryLocation\n\s+:{obj} :{obj}_pose\)\n.*?"
               rf"// {depth} end ktw:Pose\w*Location\w*\n//\*+\n")
    text, n = re.subn(pattern, RELATIVE.format(obj=obj, ref=ref, kind=kind, depth=depth), text, count=1, flags=re.S)
    assert n == 1, obj
    return text


def misspelt(text: str) -> str:
    text, n = re.subn(r"(ObjectPropertyAssertion\(ktw:hasPhysicalLocation_RefObject\n\s+:part_b_1_pose) :part_b_tray\)",
                      r"\1 :part_b_tary)", text)
    assert n == 1
    return text


def main(src: str, out: str) -> None:
    text = Path(src, "kittingInstancesInit1.owl").read_text()
    Path(out, "kittingInstancesRelativeTray.owl").write_text(relative(text, "part_a_tray", "kitting_workstation_1",
                                                                      "PartsTray", 3))
    Path(out, "kittingInstancesMisspelt.owl").write_text(misspelt(text))
    parts = relative(relative(text, "part_a_1", "part_a_tray", "Part", 4), "part_a_2", "part_a_tray", "Part", 4)
    Path(out, "kittingInstancesRelativeParts.owl").write_text(parts)


if __name__ == "__main__":
    main(*sys.argv[1:3])
