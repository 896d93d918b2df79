"""The execution world model: objects, poses and stable states in the kitkb database.

Typical use by an executor::

    with WorldModel("world.sqlite") as wm:          # or a postgresql:// URL
        tray = wm.object("part_a_tray")
        G = wm.global_pose("part_a_1")               # 4x4 numpy, workstation frame
        result = wm.commit_stable_state({"part_a_1": G_sensed}, predicates={"part-in-tray": True})

Poses: an object's primary location is a ``PoseLocation`` (point, x axis, z axis) relative
to its reference object; :meth:`WorldModel.pose` is that relative transform ``L``, and
:meth:`WorldModel.global_pose` composes ``L`` up the transformation tree. A sensed global
pose ``G'`` is stored with equation (1), ``L' = L G^-1 G'``, keeping the reference object.
A ``RelativeLocation`` (no numbers) counts as the identity relative to its reference.

Stable states: :meth:`WorldModel.step` collects updates and applies them in one transaction
only if the caller confirms that all predicates of the step hold; otherwise nothing changes.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path
from types import TracebackType
from typing import Any, Iterable, Mapping

from numpy.typing import ArrayLike
from sqlalchemy import Connection, bindparam, literal, or_, select, update

from kb.core.errors import InputError
from kb.core.namespaces import local_name
from kb.world import database as db
from kb.world.generated import accessors as gen
from kb.world.schema import model
from kb.spatial.transforms import Matrix, axes_of, check_matrix, identity, pose_matrix, updated_relative

_thing = gen.Thing.__table__
_solid = gen.SolidObject.__table__
_loc = gen.PhysicalLocation.__table__
_pose = gen.PoseLocation.__table__
_point = gen.Point.__table__
_vector = gen.Vector.__table__


@dataclass(frozen=True)
class WorldObject:
    """An individual of the world model: database id, IRI, local name and most specific class IRI."""

    id: int
    iri: str
    name: str
    cls: str

    @property
    def class_name(self) -> str:
        """Local name of the most specific class (``Part``, ``KitTray``...)."""
        return local_name(self.cls)


@dataclass(frozen=True)
class StepResult:
    """Outcome of a stable-state step: committed or not, and the predicates that failed."""

    committed: bool
    failed: tuple[str, ...] = ()
    state: int = 0  # number of the stable state now in the database


@dataclass
class _Location:
    """One solid object's primary location as stored."""

    ref: int | None
    point: int | None
    x_axis: int | None
    z_axis: int | None
    matrix: Matrix | None  # None: a location without numbers (RelativeLocation)


def _pose_query() -> Any:
    pt, xa, za = _point.alias("pt"), _vector.alias("xa"), _vector.alias("za")
    return (select(_solid.c.id, _loc.c.ref_object_id, _pose.c.point_id, _pose.c.x_axis_id, _pose.c.z_axis_id,
                   pt.c.x, pt.c.y, pt.c.z, xa.c.i, xa.c.j, xa.c.k, za.c.i, za.c.j, za.c.k)
            .join(_loc, _loc.c.id == _solid.c.primary_location_id)
            .outerjoin(_pose, _pose.c.id == _loc.c.id)
            .outerjoin(pt, pt.c.id == _pose.c.point_id)
            .outerjoin(xa, xa.c.id == _pose.c.x_axis_id)
            .outerjoin(za, za.c.id == _pose.c.z_axis_id))


_MAX_DEPTH = 1000  # longer reference chains are taken for cycles
_VECTOR_UPDATE = (update(_vector).where(_vector.c.id == bindparam("vid"))
                  .values(i=bindparam("vi"), j=bindparam("vj"), k=bindparam("vk")))


@lru_cache(maxsize=1)
def _chain_query() -> Any:
    """Pose rows of an object and of its reference objects up to the root, nearest first."""
    start = (select(_solid.c.id.label("obj"), _loc.c.id.label("loc"), _loc.c.ref_object_id.label("ref"),
                    literal(0).label("depth"))
             .join(_loc, _loc.c.id == _solid.c.primary_location_id)
             .where(_solid.c.id == bindparam("start"))
             .cte("chain", recursive=True))
    s2, l2 = _solid.alias("s2"), _loc.alias("l2")
    step = (select(s2.c.id, l2.c.id, l2.c.ref_object_id, start.c.depth + 1)
            .join(l2, l2.c.id == s2.c.primary_location_id)
            .join(start, s2.c.id == start.c.ref)
            .where(start.c.ref != start.c.obj, start.c.depth < _MAX_DEPTH))
    chain = start.union_all(step)
    pt, xa, za = _point.alias("pt"), _vector.alias("xa"), _vector.alias("za")
    # Starts from the few chain rows and follows primary keys (no scan of the object table).
    return (select(chain.c.obj, chain.c.ref, _pose.c.point_id, _pose.c.x_axis_id, _pose.c.z_axis_id,
                   pt.c.x, pt.c.y, pt.c.z, xa.c.i, xa.c.j, xa.c.k, za.c.i, za.c.j, za.c.k, chain.c.depth)
            .select_from(chain)
            .outerjoin(_pose, _pose.c.id == chain.c.loc)
            .outerjoin(pt, pt.c.id == _pose.c.point_id)
            .outerjoin(xa, xa.c.id == _pose.c.x_axis_id)
            .outerjoin(za, za.c.id == _pose.c.z_axis_id)
            .order_by(chain.c.depth))


def _location(row: Any) -> tuple[int, _Location]:
    (obj, ref, p, x, z, *nums) = row
    matrix = None
    if p is not None and None not in nums:
        v = [float(n) for n in nums]
        matrix = pose_matrix(v[0:3], v[3:6], v[6:9])
    return obj, _Location(ref, p, x, z, matrix)


class WorldModel:
    """Read and update the world model kept in database ``url`` (SQLite path or SQLAlchemy URL)."""

    def __init__(self, url: str | Path = db.DEFAULT_DB):
        self.url = db.normalize_url(url)
        self.engine = db.open_engine(self.url, must_exist=True)
        with self.engine.connect() as conn:
            db.check_version(conn, self.url)

    # --- lifecycle ---------------------------------------------------------------------------
    def close(self) -> None:
        """Release the database connections."""
        self.engine.dispose()

    def __enter__(self) -> "WorldModel":
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    # --- objects ---------------------------------------------------------------------------------
    def object(self, name: str) -> WorldObject:
        """The individual called ``name`` (local name or full IRI)."""
        with self.engine.connect() as conn:
            return self._resolve(conn, name)

    def objects(self, cls: str | type | None = None) -> list[WorldObject]:
        """All individuals, or those of class ``cls`` and its subclasses (local name, IRI or generated class)."""
        query = select(_thing.c.id, _thing.c.iri, _thing.c.name, _thing.c.kind)
        if cls is not None:
            table = self._class_table(cls)
            query = query.join(table, table.c.id == _thing.c.id)
        with self.engine.connect() as conn:
            return [WorldObject(*row) for row in conn.execute(query.order_by(_thing.c.name, _thing.c.iri))]

    def _class_table(self, cls: str | type) -> Any:
        if isinstance(cls, type) and hasattr(cls, "__table__"):
            return cls.__table__
        m = model()
        text = str(cls)
        if text in m.class_table:
            return m.class_table[text]
        matches = sorted(iri for iri in m.class_table if local_name(iri) == text)
        if not matches:
            raise InputError(f"unknown class {text!r}")
        return m.class_table[matches[0]]

    @staticmethod
    def _resolve(conn: Connection, name: str) -> WorldObject:
        cols = (_thing.c.id, _thing.c.iri, _thing.c.name, _thing.c.kind)
        rows = conn.execute(select(*cols).where(or_(_thing.c.iri == name, _thing.c.name == name)).limit(4)).all()
        exact = [r for r in rows if r[1] == name]
        if exact:
            return WorldObject(*exact[0])
        if not rows:
            raise InputError(f"no object named {name!r} in the world model")
        if len(rows) > 1:
            raise InputError(f"the name {name!r} is ambiguous: " + ", ".join(r[1] for r in rows[:3]) + " ...")
        return WorldObject(*rows[0])

    # --- poses -------------------------------------------------------------------------------------
    def _loc(self, conn: Connection, obj: WorldObject) -> _Location:
        row = conn.execute(_pose_query().where(_solid.c.id == obj.id)).first()
        if row is None:
            raise InputError(f"{obj.name} is not a solid object with a location")
        return _location(row)[1]

    def reference_of(self, name: str) -> str | None:
        """Name of the reference object of ``name``'s primary location (None at the root)."""
        with self.engine.connect() as conn:
            obj = self._resolve(conn, name)
            ref = self._loc(conn, obj).ref
            if ref is None or ref == obj.id:
                return None
            return conn.execute(select(_thing.c.name).where(_thing.c.id == ref)).scalar_one()

    def pose(self, name: str) -> Matrix:
        """The relative pose ``L`` of ``name`` in its reference object's frame (4x4)."""
        with self.engine.connect() as conn:
            loc = self._loc(conn, self._resolve(conn, name))
            return identity() if loc.matrix is None else loc.matrix

    def global_pose(self, name: str) -> Matrix:
        """The pose of ``name`` in the root frame: the product of relative poses up the tree."""
        with self.engine.connect() as conn:
            return self._global(conn, self._resolve(conn, name))

    def _chain(self, conn: Connection, obj: WorldObject) -> list[_Location]:
        """The locations from ``obj`` up to the root of its tree (one recursive query)."""
        rows = [_location(row[:-1]) for row in conn.execute(_chain_query(), {"start": obj.id})]
        if not rows:
            raise InputError(f"{obj.name} is not a solid object with a location")
        last_id, last = rows[-1]
        if last.ref is not None and last.ref != last_id:
            raise InputError(f"{obj.name}: its reference objects form a cycle")
        return [loc for _, loc in rows]

    def _global(self, conn: Connection, obj: WorldObject, chain: list[_Location] | None = None) -> Matrix:
        out = identity()
        for loc in reversed(chain or self._chain(conn, obj)):
            out = out @ (identity() if loc.matrix is None else loc.matrix)
        return out

    def global_poses(self, names: Iterable[str] | None = None) -> dict[str, Matrix]:
        """Global poses of all solid objects (or of ``names``), keyed by name, from one query."""
        with self.engine.connect() as conn:
            locs = dict(_location(r) for r in conn.execute(_pose_query()))
            ids = _solid_names(conn)
        done: dict[int, Matrix] = {}
        wanted = list(ids) if names is None else [self.object(n).id for n in names]
        for obj in wanted:
            _compose(obj, locs, done, ids)
        return {ids[o]: done[o] for o in wanted}

    def transformation_tree(self) -> dict[str, str | None]:
        """Each solid object's name mapped to its reference object's name (None for the root)."""
        with self.engine.connect() as conn:
            ids = _solid_names(conn)
            refs = conn.execute(select(_solid.c.id, _loc.c.ref_object_id)
                                .join(_loc, _loc.c.id == _solid.c.primary_location_id)).all()
        return {ids[o]: (ids.get(r) if r is not None and r != o else None) for o, r in refs}

    def set_pose(self, name: str, matrix: ArrayLike) -> None:
        """Store ``matrix`` as the relative pose of ``name`` (same reference object); one transaction."""
        with db.writing(self.engine.connect()) as conn, conn.begin():
            self._write_pose(conn, self._resolve(conn, name), _rigid(matrix, name))

    def set_global_pose(self, name: str, matrix: ArrayLike) -> Matrix:
        """Store a sensed global pose with equation (1), ``L' = L G^-1 G'``; returns ``L'``."""
        with db.writing(self.engine.connect()) as conn, conn.begin():
            return self._apply_global(conn, self._resolve(conn, name), _rigid(matrix, name))

    def _apply_global(self, conn: Connection, obj: WorldObject, new_global: Matrix) -> Matrix:
        chain = self._chain(conn, obj)
        loc = chain[0]
        relative = identity() if loc.matrix is None else loc.matrix
        new = updated_relative(relative, self._global(conn, obj, chain), new_global)
        self._write_pose(conn, obj, new, loc)
        return new

    def _write_pose(self, conn: Connection, obj: WorldObject, matrix: Matrix, loc: _Location | None = None) -> None:
        loc = loc or self._loc(conn, obj)
        if loc.point is None or loc.x_axis is None or loc.z_axis is None:
            raise InputError(f"{obj.name} has no pose location (point and axes) to update")
        point, x_axis, z_axis = axes_of(matrix)
        conn.execute(update(_point).where(_point.c.id == loc.point).values(x=point[0], y=point[1], z=point[2]))
        conn.execute(_VECTOR_UPDATE, [{"vid": vid, "vi": v[0], "vj": v[1], "vk": v[2]}
                                      for vid, v in ((loc.x_axis, x_axis), (loc.z_axis, z_axis))])

    # --- stable states -----------------------------------------------------------------------------
    def step(self) -> "Step":
        """A batch of updates applied together when confirmed (use as a context manager)."""
        return Step(self)

    def commit_stable_state(self, global_poses: Mapping[str, ArrayLike],
                            predicates: Mapping[str, bool] | Iterable[bool] | bool,
                            relative_poses: Mapping[str, ArrayLike] | None = None) -> StepResult:
        """Apply sensed poses in one transaction if every predicate holds; otherwise change nothing."""
        with self.step() as s:
            for name, m in (relative_poses or {}).items():
                s.set_pose(name, m)
            for name, m in global_poses.items():
                s.set_global_pose(name, m)
            s.confirm(predicates)
        assert s.result is not None
        return s.result

    def stable_state(self) -> int:
        """Number of stable states committed since the data was loaded."""
        with self.engine.connect() as conn:
            return int(db.read_meta(conn).get("stable_state", "0"))

    def _commit(self, relative: list[tuple[str, Matrix]], global_: list[tuple[str, Matrix]]) -> int:
        with db.writing(self.engine.connect()) as conn, conn.begin():
            objs = {n: self._resolve(conn, n) for n, _ in relative + global_}
            for name, m in relative:
                self._write_pose(conn, objs[name], m)
            depth = {n: len(self._chain(conn, objs[n])) for n, _ in global_}
            for name, m in sorted(global_, key=lambda item: depth[item[0]]):  # parents before children
                self._apply_global(conn, objs[name], m)
            return _bump(conn, "stable_state")


class Step:
    """Updates of one plan step; applied on leaving the ``with`` block only if confirmed.

    ``step.confirm(all_hold)`` takes a bool, an iterable of bools or a mapping from predicate
    name to bool. Leaving the block by an exception, or without a true confirmation, discards
    the updates. ``step.result`` tells what happened.
    """

    def __init__(self, wm: WorldModel):
        self.wm = wm
        self.relative: list[tuple[str, Matrix]] = []
        self.global_: list[tuple[str, Matrix]] = []
        self.failed: tuple[str, ...] | None = None
        self.result: StepResult | None = None

    def set_pose(self, name: str, matrix: ArrayLike) -> None:
        """Queue a relative pose."""
        self.relative.append((name, _rigid(matrix, name)))

    def set_global_pose(self, name: str, matrix: ArrayLike) -> None:
        """Queue a sensed global pose (stored with equation (1))."""
        self.global_.append((name, _rigid(matrix, name)))

    def confirm(self, predicates: Mapping[str, bool] | Iterable[bool] | bool) -> bool:
        """Record whether all predicates of the step hold; returns that verdict."""
        if isinstance(predicates, bool):
            failed = () if predicates else ("<step>",)
        elif isinstance(predicates, Mapping):
            failed = tuple(sorted(str(k) for k, v in predicates.items() if not v))
        else:
            failed = tuple(f"#{i}" for i, v in enumerate(predicates) if not v)
        self.failed = failed
        return not failed

    def __enter__(self) -> "Step":
        return self

    def __exit__(self, exc_type: type[BaseException] | None, exc: BaseException | None,
                 tb: TracebackType | None) -> None:
        if exc_type is not None or self.failed is None or self.failed:
            self.result = StepResult(False, self.failed or ("<not confirmed>",), self.wm.stable_state())
            return
        state = self.wm._commit(self.relative, self.global_)
        self.result = StepResult(True, (), state)


def _rigid(matrix: ArrayLike, name: str) -> Matrix:
    try:
        return check_matrix(matrix)
    except ValueError as exc:
        raise InputError(f"pose of {name}: {exc}") from None


def _compose(obj: int, locs: dict[int, _Location], done: dict[int, Matrix], names: dict[int, str]) -> Matrix:
    """Global pose of ``obj`` with memoisation (iterative: deep trees do not hit the recursion limit)."""
    path, current = [], obj
    while current not in done:
        loc = locs.get(current)
        if loc is None:
            raise InputError(f"{names.get(obj, obj)}: an object in its reference chain has no location")
        if current in path:
            raise InputError(f"{names.get(obj, obj)}: its reference objects form a cycle")
        path.append(current)
        if loc.ref is None or loc.ref == current:
            done[current] = identity() if loc.matrix is None else loc.matrix
            path.pop()
            break
        current = loc.ref
    for o in reversed(path):
        loc = locs[o]
        done[o] = done[loc.ref] @ (identity() if loc.matrix is None else loc.matrix)  # type: ignore[index]
    return done[obj]


def _solid_names(conn: Connection) -> dict[int, str]:
    """Names of all solid objects by id."""
    query = select(_thing.c.id, _thing.c.name).join(_solid, _solid.c.id == _thing.c.id)
    return {i: n for i, n in conn.execute(query)}


def _bump(conn: Connection, key: str) -> int:
    """Increment counter ``key`` in kitkb_meta and return its new value."""
    meta = model().table("kitkb_meta")
    value = conn.execute(select(meta.c.value).where(meta.c.key == key).with_for_update()).scalar()
    new = int(value or 0) + 1
    if value is None:
        conn.execute(meta.insert().values(key=key, value=str(new)))
    else:
        conn.execute(update(meta).where(meta.c.key == key).values(value=str(new)))
    return new
