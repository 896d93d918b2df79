"""A synthetic kitting workstation, its model and its shapes, for the SHACL engine.

Used by ``benchmarks/bench_validate.py`` (``--synthetic``) and by ``tests/test_shacl_engine.py``
until the generated shapes and scenarios exist. The data follows the kitting model's naming
(``has<Domain>_<Attribute>``); about 1% of the parts carry an injected violation, one kind after
the other: missing property, extra property on a closed shape, wrong datatype, ill-typed literal,
value outside ``sh:in``, non-positive decimal, wrong class, non-unit axis vector (found by the
SHACL-SPARQL rule), maximum count exceeded and a serial number that breaks the pattern.

Per part: 21 triples (part 4, pose 5, point 4, two axis vectors 4 each); one stock keeping
unit per 10 parts (6 triples). Axis vectors are written as decimals with zeros
(``1.0 0.0 0.0``), the case where some engines lose SPARQL rows.
"""

from __future__ import annotations

import random
from pathlib import Path

PREFIXES = """@prefix ktw: <https://w3id.org/kitkb/kitting#> .
@prefix rdf: <http://www.w3.org/1999/02/22-rdf-syntax-ns#> .
@prefix rdfs: <http://www.w3.org/2000/01/rdf-schema#> .
@prefix owl: <http://www.w3.org/2002/07/owl#> .
@prefix xsd: <http://www.w3.org/2001/XMLSchema#> .
@prefix sh: <http://www.w3.org/ns/shacl#> .
@prefix ex: <https://w3id.org/kitkb/scenario/synthetic#> .
@prefix kss: <https://w3id.org/kitkb/shapes/synthetic#> .
"""

VIOLATION_KINDS = (
    "missing",
    "closed",
    "datatype",
    "illtyped",
    "in",
    "nonpositive",
    "class",
    "axis",
    "maxcount",
    "pattern",
)

MODEL = PREFIXES + """
ktw:SolidObject a owl:Class .
ktw:Part a owl:Class ; rdfs:subClassOf ktw:SolidObject .
ktw:WorkTable a owl:Class ; rdfs:subClassOf ktw:SolidObject .
ktw:KittingWorkstation a owl:Class ; rdfs:subClassOf ktw:SolidObject .
ktw:DataThing a owl:Class .
ktw:StockKeepingUnit a owl:Class ; rdfs:subClassOf ktw:DataThing .
ktw:ShapeDesign a owl:Class ; rdfs:subClassOf ktw:DataThing .
ktw:ExternalShape a owl:Class ; rdfs:subClassOf ktw:ShapeDesign .
ktw:PhysicalLocation a owl:Class ; rdfs:subClassOf ktw:DataThing .
ktw:PoseLocation a owl:Class ; rdfs:subClassOf ktw:PhysicalLocation .
ktw:PoseLocationIn a owl:Class ; rdfs:subClassOf ktw:PoseLocation .
ktw:PoseLocationOn a owl:Class ; rdfs:subClassOf ktw:PoseLocation .
ktw:Point a owl:Class ; rdfs:subClassOf ktw:DataThing .
ktw:Vector a owl:Class ; rdfs:subClassOf ktw:DataThing .
"""

SHAPES = PREFIXES + """
kss:PartShape a sh:NodeShape ; sh:targetClass ktw:Part ;
    sh:closed true ; sh:ignoredProperties ( rdf:type ) ;
    sh:property [ sh:path ktw:hasPart_SerialNumber ; sh:minCount 1 ; sh:maxCount 1 ;
                  sh:datatype xsd:string ; sh:pattern "^sn-[0-9]+$" ] ,
                [ sh:path ktw:hasSkuObject_Sku ; sh:minCount 1 ; sh:maxCount 1 ;
                  sh:class ktw:StockKeepingUnit ] ,
                [ sh:path ktw:hasSolidObject_PrimaryLocation ; sh:minCount 1 ; sh:maxCount 1 ;
                  sh:class ktw:PhysicalLocation ] .

kss:PoseShape a sh:NodeShape ; sh:targetClass ktw:PoseLocation ;
    sh:closed true ; sh:ignoredProperties ( rdf:type ) ;
    sh:property [ sh:path ktw:hasPhysicalLocation_RefObject ; sh:minCount 1 ; sh:maxCount 1 ;
                  sh:class ktw:SolidObject ; sh:nodeKind sh:IRI ] ,
                [ sh:path ktw:hasPoseLocation_Point ; sh:minCount 1 ; sh:maxCount 1 ; sh:class ktw:Point ] ,
                [ sh:path ktw:hasPoseLocation_XAxis ; sh:minCount 1 ; sh:maxCount 1 ; sh:class ktw:Vector ] ,
                [ sh:path ktw:hasPoseLocation_ZAxis ; sh:minCount 1 ; sh:maxCount 1 ; sh:class ktw:Vector ] .

kss:PointShape a sh:NodeShape ; sh:targetClass ktw:Point ;
    sh:closed true ; sh:ignoredProperties ( rdf:type ) ;
    sh:property kss:PointX , kss:PointY , kss:PointZ .
kss:PointX sh:path ktw:hasPoint_X ; sh:minCount 1 ; sh:maxCount 1 ; sh:datatype xsd:decimal .
kss:PointY sh:path ktw:hasPoint_Y ; sh:minCount 1 ; sh:maxCount 1 ; sh:datatype xsd:decimal .
kss:PointZ sh:path ktw:hasPoint_Z ; sh:minCount 1 ; sh:maxCount 1 ; sh:datatype xsd:decimal .

kss:VectorShape a sh:NodeShape ; sh:targetClass ktw:Vector ;
    sh:closed true ; sh:ignoredProperties ( rdf:type ) ;
    sh:property [ sh:path ktw:hasVector_I ; sh:minCount 1 ; sh:maxCount 1 ; sh:datatype xsd:decimal ] ,
                [ sh:path ktw:hasVector_J ; sh:minCount 1 ; sh:maxCount 1 ; sh:datatype xsd:decimal ] ,
                [ sh:path ktw:hasVector_K ; sh:minCount 1 ; sh:maxCount 1 ; sh:datatype xsd:decimal ] ;
    sh:sparql [ a sh:SPARQLConstraint ;
        sh:message "axis vector {$this} is not of unit length" ;
        sh:prefixes kss: ;
        sh:select \"\"\"SELECT $this WHERE {
            $this ktw:hasVector_I ?i ; ktw:hasVector_J ?j ; ktw:hasVector_K ?k .
            FILTER (ABS(?i * ?i + ?j * ?j + ?k * ?k - 1.0) > 0.000001)
        }\"\"\" ] .

kss: a owl:Ontology ; sh:declare [ sh:prefix "ktw" ; sh:namespace "https://w3id.org/kitkb/kitting#"^^xsd:anyURI ] .

kss:SkuShape a sh:NodeShape ; sh:targetClass ktw:StockKeepingUnit ;
    sh:closed true ; sh:ignoredProperties ( rdf:type ) ;
    sh:property [ sh:path ktw:hasStockKeepingUnit_Weight ; sh:minCount 1 ; sh:maxCount 1 ;
                  sh:datatype xsd:decimal ; sh:minExclusive 0 ] ,
                [ sh:path ktw:hasStockKeepingUnit_WeightUnit ; sh:minCount 1 ; sh:maxCount 1 ;
                  sh:in ( "kilogram"^^xsd:NMTOKEN "gram"^^xsd:NMTOKEN "pound"^^xsd:NMTOKEN "ounce"^^xsd:NMTOKEN ) ] ,
                [ sh:path ktw:hasStockKeepingUnit_Description ; sh:maxCount 1 ; sh:datatype xsd:string ;
                  sh:minLength 3 ; sh:maxLength 80 ] ,
                [ sh:path ktw:hasStockKeepingUnit_Shape ; sh:minCount 1 ; sh:maxCount 1 ; sh:class ktw:ShapeDesign ] .

kss:ShapeDesignShape a sh:NodeShape ; sh:targetClass ktw:ShapeDesign ;
    sh:closed true ; sh:ignoredProperties ( rdf:type ) ;
    sh:property [ sh:path ktw:hasShapeDesign_Description ; sh:maxCount 1 ; sh:datatype xsd:string ] ,
                [ sh:path ktw:hasExternalShape_ModelName ; sh:maxCount 1 ;
                  sh:or ( [ sh:datatype xsd:string ] [ sh:datatype xsd:NMTOKEN ] ) ] .

kss:WorkTableShape a sh:NodeShape ; sh:targetClass ktw:WorkTable ;
    sh:closed true ; sh:ignoredProperties ( rdf:type ) ;
    sh:property [ sh:path ktw:hasSolidObject_PrimaryLocation ; sh:minCount 1 ; sh:maxCount 1 ;
                  sh:node kss:PoseShape ] .

kss:WorkstationShape a sh:NodeShape ; sh:targetNode ex:workstation ;
    sh:property [ sh:path ktw:hasWorkstation_LengthUnit ; sh:minCount 1 ; sh:maxCount 1 ;
                  sh:in ( "meter"^^xsd:NMTOKEN "millimeter"^^xsd:NMTOKEN "inch"^^xsd:NMTOKEN ) ] ,
                [ sh:path ktw:hasWorkstation_WeightUnit ; sh:hasValue "kilogram"^^xsd:NMTOKEN ] ,
                [ sh:path ktw:hasWorkstation_Name ; sh:maxCount 1 ;
                  sh:not [ sh:datatype xsd:integer ] ] .

kss:RefTargetShape a sh:NodeShape ; sh:targetObjectsOf ktw:hasPhysicalLocation_RefObject ;
    sh:nodeKind sh:IRI .

kss:OldPartShape a sh:NodeShape ; sh:targetClass ktw:Part ; sh:deactivated true ;
    sh:property [ sh:path ktw:hasPart_SerialNumber ; sh:maxCount 0 ] .
"""


def _vec(name: str, ijk: tuple[str, str, str]) -> list[str]:
    return [
        f"ex:{name} a ktw:Vector ;",
        f'  ktw:hasVector_I "{ijk[0]}"^^xsd:decimal ; ktw:hasVector_J "{ijk[1]}"^^xsd:decimal ;'
        f' ktw:hasVector_K "{ijk[2]}"^^xsd:decimal .',
    ]


def data_text(parts: int, seed: int = 1, rate: float = 0.01) -> tuple[str, int]:
    """Turtle text of a workstation with ``parts`` parts; returns (text, injected violations)."""
    rnd = random.Random(seed)
    out: list[str] = [PREFIXES]
    out += [
        'ex:workstation a ktw:KittingWorkstation ; ktw:hasWorkstation_LengthUnit "meter"^^xsd:NMTOKEN ;',
        '  ktw:hasWorkstation_WeightUnit "kilogram"^^xsd:NMTOKEN ; ktw:hasWorkstation_Name "cell 1" .',
        "ex:table a ktw:WorkTable ; ktw:hasSolidObject_PrimaryLocation ex:table_pose .",
        "ex:table_pose a ktw:PoseLocationOn ; ktw:hasPhysicalLocation_RefObject ex:workstation ;",
        "  ktw:hasPoseLocation_Point ex:table_pt ; ktw:hasPoseLocation_XAxis ex:table_x ;"
        " ktw:hasPoseLocation_ZAxis ex:table_z .",
        'ex:table_pt a ktw:Point ; ktw:hasPoint_X "0.0"^^xsd:decimal ; ktw:hasPoint_Y "0.0"^^xsd:decimal ;'
        ' ktw:hasPoint_Z "0.0"^^xsd:decimal .',
        'ex:shape_box a ktw:ExternalShape ; ktw:hasExternalShape_ModelName "box"^^xsd:NMTOKEN .',
    ]
    out += _vec("table_x", ("1.0", "0.0", "0.0")) + _vec("table_z", ("0.0", "0.0", "1.0"))
    units = ("kilogram", "gram", "pound", "ounce")
    skus = max(1, parts // 10)
    step = max(1, round(1 / rate)) if rate > 0 else 0
    kinds = {}
    if step:
        for n, i in enumerate(range(step // 2, parts, step)):
            kinds[i] = VIOLATION_KINDS[n % len(VIOLATION_KINDS)]
    bad_skus = {f"bad_{i}": k for i, k in kinds.items() if k in ("in", "nonpositive")}
    for s in [*range(skus), *bad_skus]:
        kind = bad_skus.get(str(s))
        weight = "0.0" if kind == "nonpositive" else f"{rnd.uniform(0.01, 5):.3f}"
        unit = "furlong" if kind == "in" else units[0 if kind else int(s) % 4]
        out.append(
            f'ex:sku_{s} a ktw:StockKeepingUnit ; ktw:hasStockKeepingUnit_Weight "{weight}"^^xsd:decimal ;'
            f' ktw:hasStockKeepingUnit_WeightUnit "{unit}"^^xsd:NMTOKEN ;'
            f' ktw:hasStockKeepingUnit_Description "sku number {s}" ; ktw:hasStockKeepingUnit_Shape ex:shape_box .'
        )
    for i in range(parts):
        kind = kinds.get(i)
        serial = f'"sn-{i}"'
        if kind == "pattern":
            serial = f'"SN {i}"'
        part = [f"ex:part_{i} a ktw:Part ;"]
        if kind != "missing":
            part.append(f"  ktw:hasPart_SerialNumber {serial} ;")
        if kind == "maxcount":
            part.append(f'  ktw:hasPart_SerialNumber "sn-{i}0" ;')
        if kind == "closed":
            part.append('  ktw:hasPart_Color "red" ;')
        loc = f"ex:part_{i}_pt" if kind == "class" else f"ex:part_{i}_pose"
        sku = f"bad_{i}" if kind in ("in", "nonpositive") else i % skus
        part.append(f"  ktw:hasSkuObject_Sku ex:sku_{sku} ; ktw:hasSolidObject_PrimaryLocation {loc} .")
        out += part
        out.append(
            f"ex:part_{i}_pose a ktw:PoseLocationIn ; ktw:hasPhysicalLocation_RefObject ex:table ;"
            f" ktw:hasPoseLocation_Point ex:part_{i}_pt ; ktw:hasPoseLocation_XAxis ex:part_{i}_x ;"
            f" ktw:hasPoseLocation_ZAxis ex:part_{i}_z ."
        )
        x = f'"{rnd.uniform(-1, 1):.4f}"^^xsd:decimal'
        if kind == "datatype":
            x = f'"{rnd.uniform(-1, 1):.4f}"'
        elif kind == "illtyped":
            x = '"1,5"^^xsd:decimal'
        out.append(
            f"ex:part_{i}_pt a ktw:Point ; ktw:hasPoint_X {x} ;"
            f' ktw:hasPoint_Y "{rnd.uniform(-1, 1):.4f}"^^xsd:decimal ; ktw:hasPoint_Z "0.0"^^xsd:decimal .'
        )
        xaxis = ("1.0", "1.0", "0.0") if kind == "axis" else ("1.0", "0.0", "0.0")
        out += _vec(f"part_{i}_x", xaxis) + _vec(f"part_{i}_z", ("0.0", "0.0", "1.0"))
    return "\n".join(out) + "\n", len(kinds)


def write_synthetic(out_dir: str | Path, parts: int, seed: int = 1, rate: float = 0.01) -> dict[str, Path]:
    """Write ``data.ttl``, ``model.ttl`` and ``shapes.ttl`` into ``out_dir``; return their paths."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    text, _ = data_text(parts, seed, rate)
    paths = {"data": out / "data.ttl", "model": out / "model.ttl", "shapes": out / "shapes.ttl"}
    paths["data"].write_text(text)
    paths["model"].write_text(MODEL)
    paths["shapes"].write_text(SHAPES)
    return paths
