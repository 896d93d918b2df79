"""The namespaces kitkb's ontologies live in, and the foreign ones it maps.

Every module takes its IRIs from here so that a namespace is spelled once.
"""

from __future__ import annotations

from rdflib import Namespace

BASE = "https://w3id.org/kitkb/"

#: The kitting workstation model (classes and properties of the IEEE/NIST model).
KTW = Namespace(BASE + "kitting#")
#: The SOAP model: actions, predicates, state relations, RCC8, failures.
SOAP = Namespace(BASE + "soap#")
#: The SOAP instances for kitting: the actions, predicates and failure modes.
KD = Namespace(BASE + "kitting-domain#")
#: Base for scenario data files (one namespace per scenario: SCENARIO + name + "#").
SCENARIO = BASE + "scenario/"

#: Ontology IRIs of the shipped files (what ``owl:imports`` names).
KITTING_ONTOLOGY = BASE + "kitting"
SOAP_ONTOLOGY = BASE + "soap"
KITTING_DOMAIN_ONTOLOGY = BASE + "kitting-domain"

#: The NIST kitting model namespace; the loader maps it onto :data:`KTW`
#: (same local names), so NIST data files are validated against our model.
NIST_KTW = "http://www.nist.gov/el/ontologies/kittingWorkstationClasses.owl#"
#: NIST's 2012 kitting namespace (``kittingClasses.owl``, the model before
#: ``kittingWorkstationClasses.owl``). The loader maps its terms onto :data:`KTW` by local
#: name, through :data:`NIST_2012_RENAMES` where the 2013 model renamed a term; the terms in
#: :data:`NIST_2012_UNMAPPED` and those kitkb's model lacks are kept as they are and named
#: in a warning (docs/validation.md, "NIST's 2012 vocabulary").
NIST_KTW_2012 = "http://www.nist.gov/el/ontologies/kittingClasses.owl#"
NIST_ONTOLOGY_2012 = "http://www.nist.gov/el/ontologies/kittingClasses.owl"

#: 2012 local name -> kitkb's (2013) local name, for terms the 2013 NIST model renamed. Each
#: pair has the same domain, range and comment in the two NIST models (``hasSku_Shape``: "a
#: StockKeepingUnit has a ShapeDesign", the 2013 InternalShape; the per-class ``..._Sku``
#: properties became the one ``hasSkuObject_Sku`` of SkuObject, their common superclass).
NIST_2012_RENAMES: dict[str, str] = {
    "hasWorkstation_AngleUnit": "hasKittingWorkstation_AngleUnit",
    "hasWorkstation_LengthUnit": "hasKittingWorkstation_LengthUnit",
    "hasWorkstation_WeightUnit": "hasKittingWorkstation_WeightUnit",
    "hasWorkstation_Robot": "hasKittingWorkstation_Robot",
    "hasWorkstation_ChangingStation": "hasKittingWorkstation_ChangingStation",
    "hasWorkstation_KitDesigns": "hasKittingWorkstation_KitDesign",
    "hasWorkstation_Skus": "hasKittingWorkstation_Sku",
    "hasWorkstation_OtherObstacles": "hasKittingWorkstation_OtherObstacle",
    "hasWorkstation_WorkTable": "hasKittingWorkstation_Object",
    "hasEffector_MaximumLoadWeight": "hasEndEffector_MaximumLoadWeight",
    "hasChangingStation_Base": "hasEndEffectorChangingStation_Base",
    "hasChangingStation_EndEffectorHolders": "hasEndEffectorChangingStation_EndEffectorHolder",
    "hasBoxyShape_Top": "hasBoxyShape_HasTop",
    "isKit_Finished": "hasKit_Finished",
    "hasKit_Tray": "hasKit_KitTray",
    "hasKit_Parts": "hasKit_Part",
    "hasKitDesign_PartRefAndPoses": "hasKitDesign_PartRefAndPose",
    "hasLargeBoxWithEmptyKitTrays_KitTrays": "hasLargeBoxWithEmptyKitTrays_KitTray",
    "hasLargeBoxWithKits_Kits": "hasLargeBoxWithKits_Kit",
    "hasKitTray_Sku": "hasSkuObject_Sku",
    "hasPartsTray_Sku": "hasSkuObject_Sku",
    "hasPartsBin_Sku": "hasSkuObject_Sku",
    "hasPart_Sku": "hasSkuObject_Sku",
    "hasLargeContainer_Sku": "hasSkuObject_Sku",
    "hasPartsTray_SerialNumber": "hasPartsVessel_SerialNumber",
    "hasPartsBin_SerialNumber": "hasPartsVessel_SerialNumber",
    "hasPartsBin_PartQuantity": "hasPartsVessel_PartQuantity",
    "hasPartsBin_PartSku": "hasPartsVessel_PartSku",
    "hasSku_Description": "hasStockKeepingUnit_Description",
    "hasSku_Weight": "hasStockKeepingUnit_Weight",
    "hasSku_Shape": "hasStockKeepingUnit_InternalShape",
    "hasSku_EndEffectors": "hasStockKeepingUnit_EndEffector",
    "hasMultiCup_ArrayNumber": "hasVacuumEffectorMultiCup_ArrayNumber",
    "hasMultiCup_ArrayRadius": "hasVacuumEffectorMultiCup_ArrayRadius",
    "hasWorkTable_SolidObjects": "hasWorkTable_ObjectOnTable",
    "hasSolidObject_InternalShape": "hasNoSkuObject_InternalShape",
    "hasSolidObject_ExternalShape": "hasNoSkuObject_ExternalShape",
    "hadByChangingStation_Workstation": "hadByChangingStation_KittingWorkstation",
    "hadByRobot_Workstation": "hadByRobot_KittingWorkstation",
    "hadByKitDesign_Workstation": "hadByKitDesign_KittingWorkstation",
    "hadBySku_Workstation": "hadBySku_KittingWorkstation",
    "hadByEndEffectorHolder_ChangingStation": "hadByEndEffectorHolder_EndEffectorChangingStation",
    "hadBySolidObject_WorkTable": "hadByObjectOnTable_WorkTable",
}
#: 2012 terms that kitkb's model spells the same but means otherwise, kept unmapped: the
#: 2012 PartsTrayWithParts is a group (a tray and its parts, hasPartsTrayWithParts_Tray and
#: _Parts), kitkb's is a parts tray that holds parts.
NIST_2012_UNMAPPED = frozenset({"PartsTrayWithParts"})
#: NIST's SOAP namespace is a different vocabulary from ours and is kept as is.
NIST_SOAP = "http://www.nist.gov/el/ontologies/soapClasses.owl#"
NIST_ONTOLOGY = "http://www.nist.gov/el/ontologies/kittingWorkstationClasses.owl"

#: The W3C SHACL vocabulary.
SH = Namespace("http://www.w3.org/ns/shacl#")

#: Namespace rewrites the loader applies to every term it reads (NIST's 2012 namespace is
#: mapped term by term, not here: see :data:`NIST_KTW_2012`).
NAMESPACE_MAP: dict[str, str] = {NIST_KTW: str(KTW)}

#: The vocabularies kitkb reads (what a message says when a file uses none of them).
READ_NAMESPACES: tuple[str, ...] = (str(KTW), str(SOAP), str(KD), NIST_KTW, NIST_KTW_2012)

PREFIXES: dict[str, str] = {
    "ktw": str(KTW),
    "soap": str(SOAP),
    "kd": str(KD),
}


def local_name(iri: object) -> str:
    """The local part of an IRI: its fragment if it has one, else its last path segment
    (the whole IRI when that part is empty)."""
    text = str(iri)
    for sep in ("#", "/"):
        if sep in text:
            local = text.rpartition(sep)[2]
            return local or text
    return text
