"""Shipped scenarios and the scenario generator (kb.scenario)."""

from __future__ import annotations

import filecmp
import math
import subprocess
import sys
from collections import Counter
from pathlib import Path

import numpy as np
import pytest
from rdflib import OWL, RDF, RDFS, Graph, Literal, Namespace, URIRef
from rdflib.compare import isomorphic

import kb.scenario as scenario
from kb.core.errors import InputError
from kb.core.namespaces import KITTING_ONTOLOGY, KTW
from kb.core.resources import ontology_path, scenario_dirs
from kb.scenario import build_scenario, layout, state_graph, write_scenario, write_shipped, write_spec
from kb.scenario.spec import SHIPPED, ScenarioSpec, random_spec

XSD = Namespace("http://www.w3.org/2001/XMLSchema#")

REPO = Path(__file__).resolve().parent.parent
SHIPPED_NAMES = ["kit-a2b3c3d1e1", "small-kit", "two-designs"]
STATES = ["init", "goal"]
TOL = 1e-9


def _load(path: Path) -> Graph:
    return Graph().parse(path, format="turtle")


@pytest.fixture(scope="module")
def shipped() -> dict[tuple[str, str], Graph]:
    root = ontology_path("scenarios")
    return {(n, s): _load(root / n / f"{s}.ttl") for n in SHIPPED_NAMES for s in STATES}


GENERATED = dict(parts=60, kits=3, seed=11)


@pytest.fixture(scope="module")
def generated(tmp_path_factory) -> dict[str, Graph]:
    out = tmp_path_factory.mktemp("gen")
    write_scenario(out, **GENERATED)
    return {s: _load(out / f"{s}.ttl") for s in STATES}


def _spec(key: tuple[str, str]) -> ScenarioSpec:
    """The specification a graph of _all_graphs was written from."""
    return SHIPPED[key[0]] if key[0] in SHIPPED else random_spec(**GENERATED)


def _part_count(spec: ScenarioSpec) -> int:
    """Parts of a workstation: those its kits need, plus ``spare`` of every part type."""
    return sum(n for d in spec.kits for _, n in spec.designs[d].counts) + spec.spare * len(spec.part_types)


def _all_graphs(shipped, generated):
    yield from shipped.items()
    for s, g in generated.items():
        yield ("generated", s), g


# ------------------------------------------------------------------ files and drift


def test_shipped_folders_are_the_three_scenarios():
    names = sorted(p.name for p in scenario_dirs())
    assert names == SHIPPED_NAMES == sorted(SHIPPED)
    for d in scenario_dirs():
        assert sorted(p.name for p in d.iterdir()) == ["goal.ttl", "init.ttl"]


def test_shipped_files_match_their_specs(tmp_path):
    """Drift check: the shipped files are what write_shipped writes today."""
    write_shipped(tmp_path)
    root = ontology_path("scenarios")
    for name in SHIPPED_NAMES:
        for state in STATES:
            assert filecmp.cmp(root / name / f"{state}.ttl", tmp_path / name / f"{state}.ttl", shallow=False), (
                f"{name}/{state}.ttl differs from kb.scenario.spec.SHIPPED; run kb.scenario.write_shipped()"
            )


def test_ontology_header_and_import(shipped):
    for (name, state), g in shipped.items():
        onto = URIRef(f"https://w3id.org/kitkb/scenario/{name}/{state}")
        assert (onto, RDF.type, OWL.Ontology) in g
        assert (onto, OWL.imports, URIRef(KITTING_ONTOLOGY)) in g


def test_every_individual_is_declared_with_a_kitting_class(shipped, generated):
    for key, g in _all_graphs(shipped, generated):
        subjects = {s for s in g.subjects() if isinstance(s, URIRef) and "/scenario/" in str(s) and "#" in str(s)}
        assert subjects == set(g.subjects(RDF.type, OWL.NamedIndividual)), key
        for s in subjects:
            assert (s, RDF.type, OWL.NamedIndividual) in g, (key, s)
            assert any(str(c).startswith(str(KTW)) for c in g.objects(s, RDF.type)), (key, s)


def test_writer_output_is_isomorphic_to_rdflib_graph(tmp_path):
    cases = [layout(spec) for spec in SHIPPED.values()] + [build_scenario(40, 2, 5), build_scenario(7, 7, 1)]
    for sc in cases:
        write_spec(sc, tmp_path / sc.name)
        for state in STATES:
            parsed = _load(tmp_path / sc.name / f"{state}.ttl")
            built = state_graph(sc, state)
            assert len(parsed) == len(built)
            assert isomorphic(parsed, built), (sc.name, state)


# ------------------------------------------------------------------ counts


def _ind(g: Graph, cls: str) -> list:
    return sorted(g.subjects(RDF.type, KTW[cls]))


def _slot_skus(g: Graph, kit) -> Counter:
    return Counter(
        str(g.value(g.value(slot, KTW.hasSlot_PartRefAndPose), KTW.hasPartRefAndPose_Sku)).split("#")[1]
        for slot in g.objects(kit, KTW.hasKit_Slot)
    )


def test_small_kit_counts(shipped):
    init, goal = shipped["small-kit", "init"], shipped["small-kit", "goal"]
    part_skus = {g_.value(p, KTW.hasSkuObject_Sku) for g_ in (init,) for p in _ind(init, "Part")}
    assert len(part_skus) == 2
    assert len(_ind(init, "PartsTray")) == 2
    assert len(_ind(init, "Kit")) == 0 and len(_ind(goal, "Kit")) == 1
    (kit,) = _ind(goal, "Kit")
    assert _slot_skus(goal, kit) == Counter({"sku_part_a": 2, "sku_part_b": 1})
    for tray in _ind(init, "PartsTray"):  # the parts needed and two spares (the spec's spare=2)
        need = _slot_skus(goal, kit)[str(init.value(tray, KTW.hasPartsVessel_PartSku)).split("#")[1]]
        assert len(list(init.objects(tray, KTW.hasPartsVessel_Part))) == need + SHIPPED["small-kit"].spare == need + 2
    holders = _ind(init, "EndEffectorHolder")
    assert len(holders) == 2
    effectors = {init.value(h, KTW.hasEndEffectorHolder_EndEffector) for h in holders}
    sku_effectors = {
        str(s).split("#")[1]: init.value(s, KTW.hasStockKeepingUnit_EndEffector) for s in _ind(init, "StockKeepingUnit")
    }
    assert sku_effectors["sku_part_a"] != sku_effectors["sku_kit_tray"]
    assert {sku_effectors["sku_part_a"], sku_effectors["sku_kit_tray"]} == effectors


def test_a2b3c3d1e1_counts(shipped):
    goal = shipped["kit-a2b3c3d1e1", "goal"]
    (kit,) = _ind(goal, "Kit")
    assert len(list(goal.objects(kit, KTW.hasKit_Slot))) == 10
    assert len(list(goal.objects(kit, KTW.hasKit_Part))) == 10
    assert _slot_skus(goal, kit) == Counter(
        {"sku_part_a": 2, "sku_part_b": 3, "sku_part_c": 3, "sku_part_d": 1, "sku_part_e": 1}
    )
    assert goal.value(kit, KTW.hasKit_Finished).toPython() is True


def test_two_designs_counts(shipped):
    init, goal = shipped["two-designs", "init"], shipped["two-designs", "goal"]
    kits = _ind(goal, "Kit")
    assert len(kits) == 2
    designs = {goal.value(k, KTW.hasKit_Design) for k in kits}
    assert len(designs) == 2
    assert len({goal.value(k, KTW.hasKit_KitTray) for k in kits}) == 2
    assert len(_ind(init, "KitTray")) == 2
    assert _slot_skus(goal, kits[0]) != _slot_skus(goal, kits[1])
    # one large box with kits per design, holding the kits of that design
    for box in _ind(goal, "LargeBoxWithKits"):
        design = goal.value(box, KTW.hasLargeBoxWithKits_KitDesign)
        for kit in goal.objects(box, KTW.hasLargeBoxWithKits_Kit):
            assert goal.value(kit, KTW.hasKit_Design) == design


def test_goal_state_changes(shipped):
    for name in SHIPPED_NAMES:
        init, goal = shipped[name, "init"], shipped[name, "goal"]
        assert list(init.objects(None, KTW.hasLargeBoxWithEmptyKitTrays_KitTray))
        assert not list(goal.objects(None, KTW.hasLargeBoxWithEmptyKitTrays_KitTray))
        for g in (init, goal):
            (robot,) = _ind(g, "Robot")
            assert g.value(robot, KTW.hasRobot_EndEffector) is None
            for holder in _ind(g, "EndEffectorHolder"):
                assert g.value(holder, KTW.hasEndEffectorHolder_EndEffector) is not None
        for kit in _ind(goal, "Kit"):
            tray = goal.value(kit, KTW.hasKit_KitTray)
            for part in goal.objects(kit, KTW.hasKit_Part):
                loc = goal.value(part, KTW.hasSolidObject_PrimaryLocation)
                assert goal.value(loc, KTW.hasPhysicalLocation_RefObject) == tray
        # quantities agree with the listed parts
        for g in (init, goal):
            for tray in _ind(g, "PartsTray"):
                listed = len(list(g.objects(tray, KTW.hasPartsVessel_Part)))
                assert int(g.value(tray, KTW.hasPartsVessel_PartQuantity)) == listed


# ------------------------------------------------------------------ geometry


def _vec(g: Graph, v) -> np.ndarray:
    return np.array([float(g.value(v, KTW[f"hasVector_{c}"])) for c in "IJK"])


def _pt(g: Graph, p) -> np.ndarray:
    return np.array([float(g.value(p, KTW[f"hasPoint_{c}"])) for c in "XYZ"])


def _pose(g: Graph, obj):
    loc = g.value(obj, KTW.hasSolidObject_PrimaryLocation)
    x, z = _vec(g, g.value(loc, KTW.hasPoseLocation_XAxis)), _vec(g, g.value(loc, KTW.hasPoseLocation_ZAxis))
    rot = np.column_stack([x, np.cross(z, x), z])
    return g.value(loc, KTW.hasPhysicalLocation_RefObject), _pt(g, g.value(loc, KTW.hasPoseLocation_Point)), rot


def _dims(g: Graph, obj) -> np.ndarray | None:
    shape = g.value(obj, KTW.hasNoSkuObject_InternalShape)
    if shape is None:
        sku = g.value(obj, KTW.hasSkuObject_Sku)
        shape = g.value(sku, KTW.hasStockKeepingUnit_InternalShape) if sku is not None else None
    if shape is None:
        return None
    return np.array([float(g.value(shape, KTW[f"hasBoxyShape_{d}"])) for d in ("Length", "Width", "Height")])


def _corners_in_ref(g: Graph, obj) -> tuple:
    ref, p, rot = _pose(g, obj)
    L, W, H = _dims(g, obj)
    local = np.array([[sx * L / 2, sy * W / 2, z] for sx in (-1, 1) for sy in (-1, 1) for z in (0, H)])
    return ref, local @ rot.T + p


def _inside_xy(corners: np.ndarray, dims: np.ndarray) -> bool:
    return bool(np.all(np.abs(corners[:, :2]) <= dims[:2] / 2 + TOL))


def test_axes_unit_and_orthogonal(shipped, generated):
    for key, g in _all_graphs(shipped, generated):
        n = 0
        for owner_p, xp, zp in (
            (KTW.hasPoseLocation_Point, KTW.hasPoseLocation_XAxis, KTW.hasPoseLocation_ZAxis),
            (KTW.hasPartRefAndPose_Point, KTW.hasPartRefAndPose_XAxis, KTW.hasPartRefAndPose_ZAxis),
        ):
            for s in set(g.subjects(xp, None)):
                x, z = _vec(g, g.value(s, xp)), _vec(g, g.value(s, zp))
                assert abs(np.linalg.norm(x) - 1) < TOL and abs(np.linalg.norm(z) - 1) < TOL, (key, s)
                assert abs(float(x @ z)) < TOL, (key, s)
                n += 1
        # every pose location and every part reference and pose has its axes
        poses = {s for c in ("PoseLocation", "PoseLocationIn", "PoseLocationOn", "PoseOnlyLocation", "PartRefAndPose")
                 for s in _ind(g, c)}
        assert n == len(poses), key


def test_generated_trays_have_small_yaw(tmp_path):
    write_scenario(tmp_path, parts=150, kits=2, seed=3)
    g = _load(tmp_path / "init.ttl")
    yaws = [math.degrees(math.atan2(r[1, 0], r[0, 0])) for t in _ind(g, "PartsTray") for _, _, r in [_pose(g, t)]]
    assert any(abs(y) > 0.01 for y in yaws)
    assert all(abs(y) <= 4.0 + 1e-6 for y in yaws)


def test_parts_partially_in_their_trays(shipped, generated):
    """Formula (2) of the sensor paper: inside in x and y, partially in z (sticking out)."""
    for key, g in _all_graphs(shipped, generated):
        checked = 0
        for part in _ind(g, "Part"):
            ref, corners = _corners_in_ref(g, part)
            assert (ref, RDF.type, KTW.PartsTray) in g or (ref, RDF.type, KTW.KitTray) in g, (key, part)
            tray_dims = _dims(g, ref)
            assert _inside_xy(corners, tray_dims), (key, part)
            assert abs(corners[:, 2].min()) < TOL  # resting on the tray floor
            assert corners[:, 2].max() > tray_dims[2]  # sticking out of the tray
            checked += 1
        assert checked == _part_count(_spec(key)), key


def test_parts_in_a_tray_do_not_overlap(shipped, generated):
    for key, g in _all_graphs(shipped, generated):
        by_ref: dict = {}
        for part in _ind(g, "Part"):
            ref, corners = _corners_in_ref(g, part)
            by_ref.setdefault(ref, []).append((corners[:, :2].min(axis=0), corners[:, :2].max(axis=0)))
        for boxes in by_ref.values():
            for i, (lo1, hi1) in enumerate(boxes):
                for lo2, hi2 in boxes[i + 1:]:
                    assert np.any(hi1 <= lo2 + TOL) or np.any(hi2 <= lo1 + TOL), key


def test_design_places_fit_the_kit_tray(shipped, generated):
    for key, g in _all_graphs(shipped, generated):
        for design in _ind(g, "KitDesign"):
            sku = g.value(design, KTW.hasKitDesign_KitTraySku)
            shape = g.value(sku, KTW.hasStockKeepingUnit_InternalShape)
            tray_dims = np.array([float(g.value(shape, KTW[f"hasBoxyShape_{d}"])) for d in ("Length", "Width")])
            boxes = []
            for prp in g.objects(design, KTW.hasKitDesign_PartRefAndPose):
                p = _pt(g, g.value(prp, KTW.hasPartRefAndPose_Point))
                pshape = g.value(g.value(prp, KTW.hasPartRefAndPose_Sku), KTW.hasStockKeepingUnit_InternalShape)
                half = np.array([float(g.value(pshape, KTW[f"hasBoxyShape_{d}"])) for d in ("Length", "Width")]) / 2
                lo, hi = p[:2] - half, p[:2] + half
                assert np.all(np.abs(lo) <= tray_dims / 2 + TOL) and np.all(np.abs(hi) <= tray_dims / 2 + TOL)
                boxes.append((lo, hi))
            for i, (lo1, hi1) in enumerate(boxes):
                for lo2, hi2 in boxes[i + 1:]:
                    assert np.any(hi1 <= lo2 + TOL) or np.any(hi2 <= lo1 + TOL), key


def test_containers_hold_their_contents(shipped, generated):
    """Trays on tables (touching in z), holders in the station base, end effectors in holders,
    kit trays and kits inside their large containers."""
    for key, g in _all_graphs(shipped, generated):
        for tray in _ind(g, "PartsTray"):
            ref, corners = _corners_in_ref(g, tray)
            assert (ref, RDF.type, KTW.WorkTable) in g
            table = _dims(g, ref)
            assert _inside_xy(corners, table)
            assert abs(corners[:, 2].min() - table[2]) < TOL
            assert (ref, KTW.hasWorkTable_ObjectOnTable, tray) in g
        for holder in _ind(g, "EndEffectorHolder"):
            station, corners = _corners_in_ref(g, holder)
            base = g.value(station, KTW.hasEndEffectorChangingStation_Base)
            base_dims = _dims(g, base)
            assert _inside_xy(corners, base_dims) and corners[:, 2].max() <= base_dims[2] + TOL
            eff = g.value(holder, KTW.hasEndEffectorHolder_EndEffector)
            ref, corners = _corners_in_ref(g, eff)
            assert ref == holder
            hd = _dims(g, holder)
            assert _inside_xy(corners, hd) and corners[:, 2].min() >= -TOL and corners[:, 2].max() <= hd[2] + TOL
        for obj in _ind(g, "KitTray") + _ind(g, "Kit"):
            ref, p, _ = _pose(g, obj)
            if (ref, RDF.type, KTW.Kit) in g:
                assert np.allclose(p, 0)
                continue
            assert (ref, RDF.type, KTW.LargeContainer) in g
            tray = obj if (obj, RDF.type, KTW.KitTray) in g else g.value(obj, KTW.hasKit_KitTray)
            L, W, H = _dims(g, tray)
            box = _dims(g, ref)
            assert abs(p[0]) + L / 2 <= box[0] / 2 + TOL and abs(p[1]) + W / 2 <= box[1] / 2 + TOL
            assert p[2] >= -TOL and p[2] + H <= box[2] + TOL


# ------------------------------------------------------------------ the kitting model's restrictions


@pytest.fixture(scope="module")
def model() -> dict:
    path = ontology_path("kitting.ttl")
    if not path.exists():
        pytest.skip("ontologies/kitting.ttl not there yet")
    m = Graph().parse(path)
    supers: dict = {}
    for c in set(m.subjects(RDF.type, OWL.Class)):
        seen, todo = set(), [c]
        while todo:
            x = todo.pop()
            if x in seen:
                continue
            seen.add(x)
            todo.extend(o for o in m.objects(x, RDFS.subClassOf) if isinstance(o, URIRef))
        supers[c] = seen
    restrictions: dict = {}
    for c in supers:
        for r in m.objects(c, RDFS.subClassOf):
            p = m.value(r, OWL.onProperty)
            if p is None:
                continue
            lo = hi = None
            if (v := m.value(r, OWL.qualifiedCardinality) or m.value(r, OWL.cardinality)) is not None:
                lo = hi = int(v)
            if (v := m.value(r, OWL.minQualifiedCardinality) or m.value(r, OWL.minCardinality)) is not None:
                lo = int(v)
            if (v := m.value(r, OWL.maxQualifiedCardinality) or m.value(r, OWL.maxCardinality)) is not None:
                hi = int(v)
            restrictions.setdefault(c, []).append((p, lo, hi))
    domains = {p: d for p, d in m.subject_objects(RDFS.domain)}
    ranges = {p: r for p, r in m.subject_objects(RDFS.range)}
    return {"supers": supers, "restrictions": restrictions, "domains": domains, "ranges": ranges}


def _check_against_model(g: Graph, model: dict) -> list[str]:
    errors = []
    for s in set(g.subjects(RDF.type, OWL.NamedIndividual)):
        classes = set()
        for c in g.objects(s, RDF.type):
            if c != OWL.NamedIndividual:
                if c not in model["supers"]:
                    errors.append(f"{s}: unknown class {c}")
                    continue
                classes |= model["supers"][c]
        for c in classes:
            for p, lo, hi in model["restrictions"].get(c, []):
                n = len(list(g.objects(s, p)))
                if (lo is not None and n < lo) or (hi is not None and n > hi):
                    errors.append(f"{s}: {p} has {n} values, {c} wants [{lo}, {hi}]")
        for p, o in g.predicate_objects(s):
            if p == RDF.type:
                continue
            dom = model["domains"].get(p)
            if dom is None:
                errors.append(f"{s}: property {p} not in the model")
            elif dom not in classes:
                errors.append(f"{s}: {p} outside its domain {dom}")
            rng = model["ranges"].get(p)
            if isinstance(o, Literal):
                if rng in (XSD.decimal, KTW.positiveDecimal) and o.datatype != XSD.decimal:
                    errors.append(f"{s}: {p} {o!r} is not an xsd:decimal")
                if rng == KTW.positiveDecimal and not float(o) > 0:
                    errors.append(f"{s}: {p} {o} is not positive")
                if rng in (XSD.positiveInteger, XSD.nonNegativeInteger, XSD.NMTOKEN, XSD.boolean) and o.datatype != rng:
                    errors.append(f"{s}: {p} {o!r} should be typed {rng}")
                if rng in (KTW.angleUnit, KTW.lengthUnit, KTW.weightUnit) and o.datatype not in (None, XSD.string):
                    errors.append(f"{s}: {p} {o!r} should be a plain string")
            elif rng is not None and rng in model["supers"]:
                if not any(rng in model["supers"].get(c, ()) for c in g.objects(o, RDF.type)):
                    errors.append(f"{s}: {p} value {o} is not a {rng}")
    return errors


def test_files_meet_the_model_restrictions(shipped, generated, model):
    for key, g in _all_graphs(shipped, generated):
        assert _check_against_model(g, model) == [], key


def test_model_check_can_fail(shipped, model):
    g = Graph() + shipped["small-kit", "init"]
    g.remove((None, KTW.hasKitTray_SerialNumber, None))
    robot = URIRef("https://w3id.org/kitkb/scenario/small-kit#robot_1")
    g.add((robot, KTW.hasPoint_X, Literal("1.0", datatype=XSD.decimal)))
    errors = _check_against_model(g, model)
    tray = URIRef("https://w3id.org/kitkb/scenario/small-kit#kit_tray_1")  # the one kit tray
    assert sorted(errors) == sorted([
        f"{robot}: {KTW.hasPoint_X} outside its domain {KTW.Point}",
        f"{tray}: {KTW.hasKitTray_SerialNumber} has 0 values, {KTW.KitTray} wants [1, 1]"])


# ------------------------------------------------------------------ generator


def test_same_seed_same_bytes_different_seed_different_poses(tmp_path):
    for run in ("a", "b"):
        write_scenario(tmp_path / run, parts=120, kits=3, seed=42)
    write_scenario(tmp_path / "c", parts=120, kits=3, seed=43)
    for state in STATES:
        assert (tmp_path / "a" / f"{state}.ttl").read_bytes() == (tmp_path / "b" / f"{state}.ttl").read_bytes()
    a, c = _load(tmp_path / "a" / "init.ttl"), _load(tmp_path / "c" / "init.ttl")

    def tray_axes(g):
        return sorted(tuple(_pose(g, t)[2][:, 0].round(12)) for t in _ind(g, "PartsTray"))

    assert tray_axes(a) != tray_axes(c)


@pytest.mark.parametrize(
    "parts,kits", [(1, 1), (5, 5), (30, 1), (61, 4), pytest.param(500, 7, marks=pytest.mark.slow)]
)
def test_parts_and_kits_honoured(tmp_path, parts, kits):
    write_scenario(tmp_path, parts=parts, kits=kits, seed=parts + kits)
    init, goal = _load(tmp_path / "init.ttl"), _load(tmp_path / "goal.ttl")
    assert len(_ind(goal, "Kit")) == kits
    assert len(_ind(goal, "Slot")) == parts
    assert len(list(goal.subject_objects(KTW.hasKit_Part))) == parts
    assert len(_ind(init, "KitTray")) == kits
    spec = random_spec(parts, kits, parts + kits)
    assert len(_ind(init, "Part")) == parts + spec.spare * len(spec.part_types)  # the spares of each type
    for kit in _ind(goal, "Kit"):
        design = goal.value(kit, KTW.hasKit_Design)
        prps = set(goal.objects(design, KTW.hasKitDesign_PartRefAndPose))
        slots = list(goal.objects(kit, KTW.hasKit_Slot))
        assert {goal.value(s, KTW.hasSlot_PartRefAndPose) for s in slots} == prps
        for s in slots:
            part = goal.value(s, KTW.hasSlot_Part)
            assert goal.value(part, KTW.hasSkuObject_Sku) == goal.value(
                goal.value(s, KTW.hasSlot_PartRefAndPose), KTW.hasPartRefAndPose_Sku
            )
    # one design per kit size and kit number modulo 3 (random_spec): kits of equal size share
    # at most three designs
    sizes = [parts // kits + (1 if k < parts % kits else 0) for k in range(kits)]
    assert len(_ind(goal, "KitDesign")) == len({(size, k % min(kits, 3)) for k, size in enumerate(sizes)})


def test_many_part_types_get_letter_pairs():
    sc = build_scenario(1000, 2, 0)
    keys = [t.key for t in sc.spec.part_types]
    # ceil(sqrt(1000)) = 32 part types: a..z, then aa..af
    assert keys == list("abcdefghijklmnopqrstuvwxyz") + ["aa", "ab", "ac", "ad", "ae", "af"]


def test_parallel_write_gives_the_same_bytes(tmp_path, monkeypatch):
    write_scenario(tmp_path / "seq", parts=200, kits=2, seed=9)
    monkeypatch.setattr(scenario, "PARALLEL_FROM_PARTS", 1)
    write_scenario(tmp_path / "par", parts=200, kits=2, seed=9)
    for state in STATES:
        assert (tmp_path / "seq" / f"{state}.ttl").read_bytes() == (tmp_path / "par" / f"{state}.ttl").read_bytes()


@pytest.mark.parametrize("parts,kits", [(0, 1), (5, 0), (-3, 1), (3, 4)])
def test_bad_arguments(tmp_path, parts, kits):
    with pytest.raises(InputError) as err:
        write_scenario(tmp_path / "x", parts=parts, kits=kits, seed=0)
    assert "\n" not in str(err.value)
    assert not (tmp_path / "x").exists()


def test_output_path_is_a_file(tmp_path):
    f = tmp_path / "taken"
    f.write_text("keep me")
    with pytest.raises(InputError, match="not a folder"):
        write_scenario(f, parts=3, kits=1, seed=0)
    assert f.read_text() == "keep me"


def test_rewrite_replaces_files_and_leaves_no_temporaries(tmp_path):
    write_scenario(tmp_path, parts=10, kits=1, seed=1)
    write_scenario(tmp_path, parts=12, kits=2, seed=1)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["goal.ttl", "init.ttl"]
    assert len(_ind(_load(tmp_path / "goal.ttl"), "Kit")) == 2


def test_cli_generate_and_bad_input(tmp_path):
    out = tmp_path / "cli"
    ok = subprocess.run(
        [sys.executable, "-m", "kb.cli", "scenario", "generate", "--parts", "8", "--kits", "2", "--seed", "4",
         "-o", str(out)],
        capture_output=True, text=True, cwd=REPO,
    )
    assert ok.returncode == 0, ok.stderr
    write_scenario(tmp_path / "lib", parts=8, kits=2, seed=4)
    for state in STATES:  # what the library writes for the same arguments
        assert (out / f"{state}.ttl").read_bytes() == (tmp_path / "lib" / f"{state}.ttl").read_bytes()
    bad = subprocess.run(
        [sys.executable, "-m", "kb.cli", "scenario", "generate", "--parts", "2", "--kits", "3", "-o", str(out)],
        capture_output=True, text=True, cwd=REPO,
    )
    assert bad.returncode == 2
    assert len(bad.stderr.strip().splitlines()) == 1 and "kits" in bad.stderr


def test_boxy_shapes_have_length_at_least_width(shipped, generated):
    for key, g in _all_graphs(shipped, generated):
        shapes = _ind(g, "BoxyShape")
        # every shape the file uses is a boxy one
        used = {o for p in (KTW.hasStockKeepingUnit_InternalShape, KTW.hasNoSkuObject_InternalShape,
                            KTW.hasStockKeepingUnit_ExternalShape, KTW.hasNoSkuObject_ExternalShape)
                for o in g.objects(None, p)}
        assert set(shapes) == used, key
        for s in shapes:
            assert float(g.value(s, KTW.hasBoxyShape_Length)) >= float(g.value(s, KTW.hasBoxyShape_Width)), (key, s)


def test_goal_keeps_every_object_of_init(shipped, generated):
    pairs = [(shipped[n, "init"], shipped[n, "goal"]) for n in SHIPPED_NAMES] + [(generated["init"], generated["goal"])]
    for init, goal in pairs:
        before = set(init.subjects(RDF.type, OWL.NamedIndividual))
        after = set(goal.subjects(RDF.type, OWL.NamedIndividual))
        assert before <= after
        new_classes = {c for s in after - before for c in goal.objects(s, RDF.type)} - {OWL.NamedIndividual}
        # the kits, their slots, and the kits' poses in their boxes
        assert new_classes == {KTW.Kit, KTW.Slot, KTW.PoseLocationIn, KTW.Point, KTW.Vector}
