"""Write NIST-2012-shaped state files from NIST's 2013 ones (run by hand; the output is committed).

NIST's 2012 state files (el-robotics-core, ``Ontology/kittingInstances*.owl`` before
``kittingWorkstationClasses.owl``) name the model ``kittingClasses.owl``: two default prefixes
(the instance namespace, then the model's, which wins, so individuals and terms share it), a
relative ``Import(<file:kittingClasses.owl>)``, the 2012 property names (``hasWorkstation_*``,
``hasSku_Shape``, ``hasPart_Sku``, ``hasKit_Tray``, ``isKit_Finished``...) and each parts tray
inside a ``PartsTrayWithParts`` group that lists the parts, the tray and the parts located
relative to the group. This script rewrites ``../shared/nist/kittingInstances{Init,Goal}1.owl``
(public domain) into that shape::

    python tests/data/foreign/make_nist2012.py ../shared/nist tests/data/foreign/nist2012
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

RENAMED = {  # 2013 name -> 2012 name (the ones a 2013 state file uses)
    "hasKittingWorkstation_AngleUnit": "hasWorkstation_AngleUnit",
    "hasKittingWorkstation_LengthUnit": "hasWorkstation_LengthUnit",
    "hasKittingWorkstation_WeightUnit": "hasWorkstation_WeightUnit",
    "hasKittingWorkstation_Robot": "hasWorkstation_Robot",
    "hasKittingWorkstation_ChangingStation": "hasWorkstation_ChangingStation",
    "hasKittingWorkstation_KitDesign": "hasWorkstation_KitDesigns",
    "hasKittingWorkstation_Sku": "hasWorkstation_Skus",
    "hasEndEffector_MaximumLoadWeight": "hasEffector_MaximumLoadWeight",
    "hasEndEffectorChangingStation_Base": "hasChangingStation_Base",
    "hasEndEffectorChangingStation_EndEffectorHolder": "hasChangingStation_EndEffectorHolders",
    "hasBoxyShape_HasTop": "hasBoxyShape_Top",
    "hasKit_Finished": "isKit_Finished",
    "hasKit_KitTray": "hasKit_Tray",
    "hasKit_Part": "hasKit_Parts",
    "hasKitDesign_PartRefAndPose": "hasKitDesign_PartRefAndPoses",
    "hasLargeBoxWithEmptyKitTrays_KitTray": "hasLargeBoxWithEmptyKitTrays_KitTrays",
    "hasLargeBoxWithKits_Kit": "hasLargeBoxWithKits_Kits",
    "hasPartsVessel_SerialNumber": "hasPartsTray_SerialNumber",
    "hasStockKeepingUnit_Description": "hasSku_Description",
    "hasStockKeepingUnit_Weight": "hasSku_Weight",
    "hasStockKeepingUnit_InternalShape": "hasSku_Shape",
    "hasStockKeepingUnit_EndEffector": "hasSku_EndEffectors",
    "hasNoSkuObject_InternalShape": "hasSolidObject_InternalShape",
}
SKU_OF = {"Part": "hasPart_Sku", "KitTray": "hasKitTray_Sku", "PartsTray": "hasPartsTray_Sku",
          "LargeContainer": "hasLargeContainer_Sku"}
DROPPED = ("hasPartsVessel_PartSku", "hasPartsVessel_PartQuantity")


def statements(text: str) -> list[str]:
    """The file's lines, a statement continued over several lines joined into one."""
    out, pending, depth = [], "", 0
    for line in text.splitlines():
        if not pending and (line.startswith("//") or not line.strip()):
            out.append(line)
            continue
        pending = f"{pending} {line.strip()}" if pending else line
        depth += line.count("(") - line.count(")")
        if depth <= 0 or line.startswith(("Prefix", "Ontology", "Import")):
            out.append(pending)
            pending, depth = "", 0
    return out


def convert(text: str, name: str) -> str:
    lines = statements(text)
    classes = {ind: cls for cls, ind in re.findall(r"ClassAssertion\(ktw:(\w+) :(\w+)\)", text)}
    trays = sorted({ind for ind, cls in classes.items() if cls == "PartsTray"})
    tray_parts = re.findall(r"hasPartsVessel_Part\s+:(\w+)\s+:(\w+)\)", text)
    out: list[str] = []
    for line in lines:
        if line.startswith("Prefix(ktw:="):
            out.append("Prefix(:=<http://www.nist.gov/el/ontologies/kittingClasses.owl#>)")
            continue
        if line.startswith("Import("):
            out.append("Import(<file:kittingClasses.owl>)")
            continue
        if line.startswith("Ontology("):
            out.append(f"Ontology(<http://www.nist.gov/el/ontologies/{name}>")
            continue
        if any(d in line for d in DROPPED) or "hasPartsVessel_Part " in line:
            continue
        if "hasKittingWorkstation_Object" in line:
            if "work_table" not in line:
                continue
            line = line.replace("hasKittingWorkstation_Object", "hasWorkstation_WorkTable")
        if "hasSkuObject_Sku" in line:
            subject = re.search(r"hasSkuObject_Sku :(\w+)", line).group(1)
            line = line.replace("hasSkuObject_Sku", SKU_OF[classes[subject]])
        for new, old in RENAMED.items():
            line = re.sub(rf"\bktw:{new}\b", f"ktw:{old}", line)
        for tray in trays:  # the tray and its parts are located in the group
            group = tray.replace("_tray", "_supply")
            if re.search(rf"hasPhysicalLocation_RefObject :\w+_pose :{tray}\)", line):
                line = line.replace(f":{tray})", f":{group})")
            if f"hasPhysicalLocation_RefObject :{tray}_pose " in line:
                line = re.sub(r":\w+\)$", f":{group})", line)
        if "hasPhysicalLocation_RefObject" in line and ":kit_1)" in line and "kit_tray_1" not in line:
            line = line.replace(":kit_1)", ":kit_tray_1)")  # 2012: parts in a kit relative to its tray
        line = line.replace("ktw:", ":")
        if line.startswith("ClassAssertion(:PartsTray "):
            tray = line.split()[-1].rstrip(")").lstrip(":")
            out.extend(group_lines(tray, text, [p for t, p in tray_parts if t == tray]))
        out.append(line)
    return "\n".join(out) + "\n"


def group_lines(tray: str, text: str, parts: list[str]) -> list[str]:
    """A PartsTrayWithParts group where the tray was, the tray at the group's origin."""
    group = tray.replace("_tray", "_supply")
    point = {axis: re.search(rf"hasPoint_{axis} :{tray}_point\s+\"([-0-9.]+)\"", text).group(1)
             for axis in "XYZ"}
    lines = ["// start PartsTrayWithParts " + group,
             f"Declaration(NamedIndividual(:{group}))",
             f"ClassAssertion(:PartsTrayWithParts :{group})",
             f"ObjectPropertyAssertion(:hasSolidObject_PrimaryLocation :{group} :{group}_pose)",
             f"Declaration(NamedIndividual(:{group}_pose))",
             f"ClassAssertion(:PoseOnlyLocation :{group}_pose)",
             f"ObjectPropertyAssertion(:hasPhysicalLocation_RefObject :{group}_pose :kitting_workstation_1)",
             f"ObjectPropertyAssertion(:hasPoseLocation_Point :{group}_pose :{group}_point)",
             f"ObjectPropertyAssertion(:hasPoseLocation_XAxis :{group}_pose :{group}_x_axis)",
             f"ObjectPropertyAssertion(:hasPoseLocation_ZAxis :{group}_pose :{group}_z_axis)",
             f"Declaration(NamedIndividual(:{group}_point))",
             f"ClassAssertion(:Point :{group}_point)"]
    lines += [f"DataPropertyAssertion(:hasPoint_{a} :{group}_point \"{v}\"^^xsd:decimal)" for a, v in point.items()]
    for axis, ijk in (("x", "100"), ("z", "001")):
        lines += [f"Declaration(NamedIndividual(:{group}_{axis}_axis))", f"ClassAssertion(:Vector :{group}_{axis}_axis)"]
        lines += [f"DataPropertyAssertion(:hasVector_{c} :{group}_{axis}_axis \"{d}.000000\"^^xsd:decimal)"
                  for c, d in zip("IJK", ijk)]
    lines.append(f"ObjectPropertyAssertion(:hasPartsTrayWithParts_Tray :{group} :{tray})")
    lines += [f"ObjectPropertyAssertion(:hasPartsTrayWithParts_Parts :{group} :{p})" for p in parts]
    return lines + ["// end PartsTrayWithParts"]


def at_origin(text: str) -> str:
    """Each parts tray at the origin of its group (2012: "the location point of the PartsTray
    should be (0,0,0)")."""
    return re.sub(r"(hasPoint_[XYZ] :part_[a-z]_tray_point )\"[-0-9.]+\"", r'\1"0.000000"', text)


def main(src: str, dst: str) -> None:
    out = Path(dst)
    out.mkdir(parents=True, exist_ok=True)
    for stage in ("Init", "Goal"):
        text = Path(src, f"kittingInstances{stage}1.owl").read_text("utf-8")
        name = f"kittingInstances{stage}.owl"
        (out / name).write_text(at_origin(convert(text, name)), "utf-8")


if __name__ == "__main__":
    main(*sys.argv[1:3])
