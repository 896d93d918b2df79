"""Write NIST-shaped state files with a defect that stops kitkb's commands (run by hand; the
output is committed).

NIST's later state files (el-robotics-core: ``kittingInstancesInit3.owl``, the grasp and
external-shape states, ``soapInstances.owl``) place the end effector holders without any shape,
and describe some SKUs by an ``ExternalShape`` (a model file) only. This script rewrites NIST's
first initial state, ``../shared/nist/kittingInstancesInit1.owl`` (public domain), into those
shapes::

    python tests/data/one_verdict/make_one_verdict.py ../shared/nist tests/data/one_verdict

* ``kittingInstancesHolders.owl``: the two holders lose their ``hasNoSkuObject_InternalShape``;
* ``kittingInstancesExternalShape.owl``: the SKU of part A has an ``ExternalShape`` (NIST's
  three properties) instead of its internal shape.
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

EXTERNAL = """ObjectPropertyAssertion(ktw:hasStockKeepingUnit_ExternalShape
                        :stock_keeping_unit_part_a :external_shape_part_a)

//*****************************************
// 3 start ktw:ExternalShape external_shape_part_a
Declaration(NamedIndividual(:external_shape_part_a))
ClassAssertion(ktw:ExternalShape :external_shape_part_a)
DataPropertyAssertion(ktw:hasShapeDesign_Description :external_shape_part_a
                      "Shape of part A"^^xsd:string)
DataPropertyAssertion(ktw:hasExternalShape_ModelFormatName :external_shape_part_a
                      "STL"^^xsd:string)
DataPropertyAssertion(ktw:hasExternalShape_ModelFileName :external_shape_part_a
                      "partA.stl"^^xsd:string)
DataPropertyAssertion(ktw:hasExternalShape_ModelName :external_shape_part_a
                      "partA"^^xsd:string)
// 3 end ktw:ExternalShape
//*****************************************
"""


def holders(text: str) -> str:
    text, n = re.subn(r"ObjectPropertyAssertion\(ktw:hasNoSkuObject_InternalShape\n\s+:(part|tray)_gripper_holder "
                      r":\w+\)\n", "", text)
    assert n == 2
    return text


def external(text: str) -> str:
    text, n = re.subn(r"ObjectPropertyAssertion\(ktw:hasStockKeepingUnit_InternalShape\n\s+:stock_keeping_unit_part_a "
                      r":shape_part_a\)\n", EXTERNAL, text)
    assert n == 1
    return text


def main(src: str, out: str) -> None:
    text = Path(src, "kittingInstancesInit1.owl").read_text()
    Path(out, "kittingInstancesHolders.owl").write_text(holders(text))
    Path(out, "kittingInstancesExternalShape.owl").write_text(external(text))


if __name__ == "__main__":
    main(*sys.argv[1:3])
