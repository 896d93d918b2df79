"""World model API: objects, poses, the transformation tree, equation (1), stable-state commits,
concurrent writers. SQLite always; PostgreSQL when KITKB_PG_URL is set."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np
import pytest
from rdflib import RDF, RDFS, Namespace, URIRef

from kb import world
from kb.core.errors import InputError
from kb.io.loader import load_file
from kb.core.resources import scenario_dirs
from kb.spatial.transforms import axes_of, from_xyz_rpy, invert, pose_matrix, updated_relative
from kb.world.worldmodel import WorldModel

from shared_data import NIST_DIR

KTW = Namespace("https://w3id.org/kitkb/kitting#")
PG_URL = os.environ.get("KITKB_PG_URL")
SCENARIO = next((d / "init.ttl" for d in scenario_dirs() if d.name == "small-kit"), None) or \
    next(d / "init.ttl" for d in scenario_dirs())
REPO = Path(__file__).resolve().parent.parent


@pytest.fixture(params=["sqlite", pytest.param("postgresql", marks=pytest.mark.postgres)])
def url(request, tmp_path):
    if request.param == "sqlite":
        u = world.normalize_url(tmp_path / "world.sqlite")
    elif not PG_URL:
        pytest.skip("KITKB_PG_URL is not set")
    else:
        u = PG_URL
        world.drop_all(u)
    world.load(SCENARIO, u)
    yield u
    if request.param == "postgresql":
        world.drop_all(u)


@pytest.fixture
def wm(url):
    with WorldModel(url) as w:
        yield w


# --- transforms --------------------------------------------------------------------------------

def test_pose_matrix_and_back():
    m = from_xyz_rpy(0.3, -1.0, 2.0, 0.2, -0.4, 1.1)
    p, x, z = axes_of(m)
    assert np.allclose(pose_matrix(p, x, z), m)
    assert np.allclose(invert(m) @ m, np.eye(4))
    skew = pose_matrix((0, 0, 0), (2, 0, 0.5), (0, 0, 3))  # not unit, not orthogonal
    assert np.allclose(skew[:3, :3], np.eye(3))


def test_equation_1_keeps_the_reference_frame():
    parent = from_xyz_rpy(1, 2, 0, 0, 0, 0.5)
    local = from_xyz_rpy(0.1, 0.2, 0.3, 0, 0, -0.2)
    sensed = from_xyz_rpy(1.5, 2.5, 0.1, 0.01, 0.02, 0.9)
    new_local = updated_relative(local, parent @ local, sensed)
    assert np.allclose(parent @ new_local, sensed)
    assert np.allclose(new_local, invert(parent) @ sensed)


# --- objects and poses ----------------------------------------------------------------------------

def _rdf_global(graph, node):
    """Global pose computed straight from the data file (independent of the database)."""
    m = np.eye(4)
    seen = set()
    while node not in seen:
        seen.add(node)
        loc = graph.value(node, KTW.hasSolidObject_PrimaryLocation)
        pt = graph.value(loc, KTW.hasPoseLocation_Point)
        local = np.eye(4)
        if pt is not None:
            xa, za = graph.value(loc, KTW.hasPoseLocation_XAxis), graph.value(loc, KTW.hasPoseLocation_ZAxis)
            x = np.array([float(graph.value(xa, KTW["hasVector_" + c])) for c in "IJK"])
            z = np.array([float(graph.value(za, KTW["hasVector_" + c])) for c in "IJK"])
            x, z = x / np.linalg.norm(x), z / np.linalg.norm(z)
            local[:3, 0], local[:3, 1], local[:3, 2] = x, np.cross(z, x), z
            local[:3, 3] = [float(graph.value(pt, KTW["hasPoint_" + c])) for c in "XYZ"]
        m = local @ m
        ref = graph.value(loc, KTW.hasPhysicalLocation_RefObject)
        if ref is None or ref == node:
            break
        node = ref
    return m


def _solid_objects(graph) -> set[str]:
    """IRIs of the individuals of SolidObject and its subclasses in ``graph`` (rdflib)."""
    model = load_file(REPO / "ontologies" / "kitting.ttl").graph
    classes, todo = set(), [KTW.SolidObject]
    while todo:
        c = todo.pop()
        classes.add(c)
        todo += [s for s in model.subjects(RDFS.subClassOf, c) if s not in classes]
    return {str(s) for s, c in graph.subject_objects(RDF.type) if c in classes}


def test_objects_by_class_and_name(wm):
    graph = load_file(SCENARIO).graph
    parts = wm.objects("Part")
    assert {p.iri for p in parts} == {str(s) for s in graph.subjects(RDF.type, KTW.Part)}
    assert len(parts) == 7 and all(p.class_name == "Part" for p in parts)  # small-kit: 3 in the kit, 4 spares
    assert {o.iri for o in wm.objects("SolidObject")} == _solid_objects(graph)  # subclasses included
    first = parts[0]
    assert wm.object(first.name) == wm.object(first.iri) == first
    with pytest.raises(InputError, match="no object named 'nothing_here'"):
        wm.object("nothing_here")
    with pytest.raises(InputError, match="unknown class"):
        wm.objects("Unicorn")


def test_global_poses_match_the_data_file(wm):
    graph = load_file(SCENARIO).graph
    all_poses = wm.global_poses()
    solids = wm.objects("SolidObject")
    assert len(all_poses) == len(solids)
    for obj in solids:
        expected = _rdf_global(graph, URIRef(obj.iri))
        assert np.allclose(wm.global_pose(obj.name), expected, atol=1e-9), obj.name
        assert np.allclose(all_poses[obj.name], expected, atol=1e-9), obj.name


def test_transformation_tree(wm):
    tree = wm.transformation_tree()
    roots = [name for name, ref in tree.items() if ref is None]
    assert roots == ["kitting_workstation_1"]
    part = wm.objects("Part")[0].name
    assert tree[part] == wm.reference_of(part) is not None
    chain, node = [], part
    while node is not None:
        chain.append(node)
        node = tree[node]
    assert chain[-1] == "kitting_workstation_1"
    product = np.eye(4)
    for name in reversed(chain):
        product = product @ wm.pose(name)
    assert np.allclose(product, wm.global_pose(part))


def test_sensed_pose_update_keeps_reference_and_moves_children(wm):
    tree = wm.transformation_tree()
    parent = next(n for n in tree.values() if n and n != "kitting_workstation_1" and list(tree.values()).count(n) > 1)
    child = next(c for c, r in tree.items() if r == parent)
    others = {n: g for n, g in wm.global_poses().items() if n not in (parent, child)}
    child_local = wm.pose(child)
    sensed = wm.global_pose(parent) @ from_xyz_rpy(0.05, -0.02, 0.01, 0, 0, 0.3)
    wm.set_global_pose(parent, sensed)
    assert wm.reference_of(parent) == tree[parent]
    assert np.allclose(wm.global_pose(parent), sensed)
    assert np.allclose(wm.pose(child), child_local)  # the child rides along
    assert np.allclose(wm.global_pose(child), sensed @ child_local)
    after = wm.global_poses()
    moved = {n for n in others if not np.allclose(after[n], others[n])}
    # exactly what hangs below the parent moved with it
    assert moved == {n for n in others if _under(tree, n, parent)}


def _under(tree, node, ancestor):
    while node is not None:
        if node == ancestor:
            return True
        node = tree[node]
    return False


def test_set_pose_rejects_non_rigid(wm):
    part = wm.objects("Part")[0].name
    with pytest.raises(InputError, match="rigid"):
        wm.set_pose(part, np.diag([2.0, 1, 1, 1]))


# --- stable states --------------------------------------------------------------------------------

def test_step_commits_only_when_all_predicates_hold(wm):
    a, b = [o.name for o in wm.objects("Part")[:2]]
    before = wm.global_poses()
    ga = from_xyz_rpy(0.4, 0.4, 0.9, 0, 0, 0.1)
    gb = from_xyz_rpy(0.5, 0.4, 0.9, 0, 0, -0.1)
    result = wm.commit_stable_state({a: ga, b: gb}, {"part-in-kit-tray(a)": True, "robot-empty(r)": False})
    assert not result.committed and result.failed == ("robot-empty(r)",) and result.state == 0
    after = wm.global_poses()
    assert all(np.allclose(after[n], before[n]) for n in before)
    result = wm.commit_stable_state({a: ga, b: gb}, [True, True])
    assert result.committed and result.state == 1 == wm.stable_state()
    assert np.allclose(wm.global_pose(a), ga) and np.allclose(wm.global_pose(b), gb)


def test_step_discards_on_error_and_without_confirmation(wm):
    part = wm.objects("Part")[0].name
    before = wm.global_pose(part)
    with wm.step() as s:
        s.set_global_pose(part, from_xyz_rpy(1, 1, 1, 0, 0, 0))
    assert not s.result.committed and s.result.failed == ("<not confirmed>",)
    with pytest.raises(InputError):
        with wm.step() as s:
            s.set_global_pose(part, from_xyz_rpy(1, 1, 1, 0, 0, 0))
            s.set_global_pose("no_such_object", np.eye(4))
            s.confirm(True)
    assert np.allclose(wm.global_pose(part), before) and wm.stable_state() == 0


def test_batch_with_parent_and_child_reaches_both_targets(wm):
    tree = wm.transformation_tree()
    child = wm.objects("Part")[0].name
    parent = tree[child]
    g_parent = wm.global_pose(parent) @ from_xyz_rpy(0.1, 0, 0, 0, 0, 0.2)
    g_child = wm.global_pose(child) @ from_xyz_rpy(0, 0.05, 0, 0, 0, -0.3)
    assert wm.commit_stable_state({child: g_child, parent: g_parent}, True).committed  # child listed first
    assert np.allclose(wm.global_pose(parent), g_parent) and np.allclose(wm.global_pose(child), g_child)


# --- two processes ------------------------------------------------------------------------------------

_WORKER = textwrap.dedent("""
    import sys, numpy as np
    from kb.world.worldmodel import WorldModel
    from kb.spatial.transforms import from_xyz_rpy
    import os, time
    url, names, rounds, seed = sys.argv[1], sys.argv[2].split(","), int(sys.argv[3]), int(sys.argv[4])
    go = sys.argv[5]
    with WorldModel(url) as wm:
        open(go + "." + str(seed), "w").close()  # ready
        while not os.path.exists(go):  # both start writing together
            time.sleep(0.01)
        for r in range(rounds):
            for i, name in enumerate(names):
                wm.set_global_pose(name, from_xyz_rpy(seed + r * 0.001, i * 0.01, 1.0, 0, 0, r * 0.01))
""")


def test_two_processes_updating_different_objects_lose_nothing(wm, url, tmp_path):
    names = [o.name for o in wm.objects("Part")][:6]
    assert len(names) == 6
    mine, theirs = names[:3], names[3:]
    others = {n: g for n, g in wm.global_poses().items() if n not in names}
    rounds = 15
    env = {**os.environ, "PYTHONPATH": str(REPO)}
    go = tmp_path / "go"
    procs = [subprocess.Popen([sys.executable, "-c", _WORKER, url, ",".join(group), str(rounds), str(seed), str(go)],
                              env=env, stderr=subprocess.PIPE, text=True)
             for group, seed in ((mine, 1), (theirs, 2))]
    deadline = time.monotonic() + 120
    while not all(Path(f"{go}.{seed}").exists() for seed in (1, 2)) and time.monotonic() < deadline:
        time.sleep(0.02)
    go.touch()
    for p in procs:
        _, err = p.communicate(timeout=300)
        assert p.returncode == 0, err
    last = rounds - 1
    for group, seed in ((mine, 1), (theirs, 2)):
        for i, name in enumerate(group):
            expected = from_xyz_rpy(seed + last * 0.001, i * 0.01, 1.0, 0, 0, last * 0.01)
            assert np.allclose(wm.global_pose(name), expected, atol=1e-9), name
    after = wm.global_poses()
    assert all(np.allclose(after[n], g) for n, g in others.items())


def test_nist_init_file_global_poses(tmp_path):
    nist = NIST_DIR / "kittingInstancesInit1.owl"
    if not nist.is_file():
        pytest.skip("NIST files not present")
    url = world.normalize_url(tmp_path / "nist.sqlite")
    world.load(nist, url)
    graph = load_file(nist).graph
    with WorldModel(url) as wm:
        poses = wm.global_poses()
        assert set(poses) == {o.name for o in wm.objects("SolidObject")}
        assert {o.iri for o in wm.objects("SolidObject")} == _solid_objects(graph)
        for obj in wm.objects("SolidObject"):
            assert np.allclose(poses[obj.name], _rdf_global(graph, URIRef(obj.iri)), atol=1e-9), obj.name
        assert wm.transformation_tree()["kitting_workstation_1"] is None


# --- batches: numpy arithmetic, one statement per table ----------------------------------------------

def test_batch_of_parents_and_children_reaches_every_target(wm):
    """A tray, the parts in it and parts elsewhere in one stable state: each object in the batch
    reaches its sensed pose; every other object keeps its relative pose (and rides along)."""
    tree = wm.transformation_tree()
    before_local = {n: wm.pose(n) for n in tree}
    tray = next(r for r in tree.values() if r and list(tree.values()).count(r) > 1 and tree[r] is not None)
    inside = [c for c, r in tree.items() if r == tray][:2]
    others = [o.name for o in wm.objects("Part") if tree[o.name] != tray][:3]
    batch = [tray, *inside, *others]
    rng = np.random.default_rng(7)
    targets = {n: wm.global_pose(n) @ from_xyz_rpy(*rng.uniform(-0.05, 0.05, 3), 0, 0, rng.uniform(-1, 1))
               for n in batch}
    result = wm.commit_stable_state(dict(reversed(list(targets.items()))), True)  # children listed first
    assert result.committed and result.state == 1
    after = wm.global_poses()
    for name, target in targets.items():
        assert np.allclose(after[name], target, atol=1e-9), name
    for name in tree:
        if name not in targets:
            assert np.allclose(wm.pose(name), before_local[name], atol=1e-12), name
            ref = tree[name]
            expected = before_local[name] if ref is None else after[ref] @ before_local[name]
            assert np.allclose(after[name], expected, atol=1e-9), name


def test_global_poses_of_some_objects_equal_those_of_all(wm):
    everything = wm.global_poses()
    names = [o.name for o in wm.objects("Part")][:4] + ["kitting_workstation_1"]
    some = wm.global_poses(names)
    assert list(some) == names
    assert all(np.allclose(some[n], everything[n]) for n in names)


def test_a_bad_pose_in_a_batch_names_it_and_writes_nothing(wm):
    a, b = [o.name for o in wm.objects("Part")[:2]]
    before = wm.global_poses()
    with pytest.raises(InputError, match=f"pose of {b}: a pose must be a rigid transform"):
        wm.commit_stable_state({a: from_xyz_rpy(0.1, 0.1, 1, 0, 0, 0), b: np.diag([1.0, 2, 1, 1])}, True)
    after = wm.global_poses()
    assert all(np.allclose(after[n], before[n]) for n in before) and wm.stable_state() == 0


def test_poses_are_read_fresh_while_the_tree_is_kept(wm, url):
    part = wm.objects("Part")[0].name
    wm.global_pose(part)  # reads the tree
    target = from_xyz_rpy(0.7, 0.2, 1.1, 0, 0, 0.3)
    with WorldModel(url) as other:  # another writer
        other.set_global_pose(part, target)
    assert np.allclose(wm.global_pose(part), target)
    assert np.allclose(wm.global_poses([part])[part], target)


def test_an_object_located_by_a_relative_location_has_no_pose(tmp_path):
    """A tray located "in" the workstation by a relative location (no numbers), and the parts
    posed in its frame, have no global pose: refused by name, left out of global_poses(), never
    read as the identity (the tray at its reference's origin, its parts around it)."""
    data = Path(__file__).parent / "data" / "unknown_reference" / "kittingInstancesRelativeTray.owl"
    db = tmp_path / "w.sqlite"
    world.load(data, world.normalize_url(db))
    with WorldModel(world.normalize_url(db)) as w:
        with pytest.raises(InputError, match="part_a_tray has no pose in the world model: its location has no point"):
            w.global_pose("part_a_tray")
        with pytest.raises(InputError, match="part_a_1 has no pose .* its reference object part_a_tray's location"):
            w.global_pose("part_a_1")
        poses = w.global_poses()
        assert "part_b_1" in poses and not {"part_a_tray", "part_a_1", "part_a_2"} & set(poses)
        assert np.allclose(poses["part_b_1"], w.global_pose("part_b_1"))
        with pytest.raises(InputError, match="part_a_1 has no pose"):
            w.global_poses(["part_a_1"])
