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
An object located by a ``RelativeLocation`` (no numbers), or relative to such an object, has no
pose: ``global_pose`` says so (an InputError) and ``global_poses()`` leaves it out.

Stable states: :meth:`WorldModel.step` collects updates and applies them in one transaction
only if the caller confirms that all predicates of the step hold; otherwise nothing changes.

Speed: the shape of the transformation tree (who is located relative to whom, and the ids of
the rows holding the numbers) is read once and kept (:class:`kb.world.poses.PoseTree`); a
pose read is then one query for the numbers of the object's chain, and a stable-state batch
reads the chains of all its objects in one query, computes every new ``L'`` at once with
numpy and writes each table with one statement (``executemany`` of one prepared statement on
SQLite, one ``UPDATE ... FROM (VALUES ...)`` on PostgreSQL). The tree is read again when the
database was reloaded meanwhile (its ``load_id`` changed) or after :meth:`WorldModel.refresh`.
A ``WorldModel`` keeps one connection and belongs to one thread.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from types import TracebackType
from typing import Any, Iterable, Mapping, Sequence

import numpy as np
from numpy.typing import ArrayLike
from sqlalchemy import Connection, or_, select

from kb.core.errors import InputError
from kb.core.namespaces import local_name
from kb.world import database as db
from kb.world import poses as P
from kb.world.schema import model

Matrix = np.ndarray

_TREE = ("SELECT s.id, t.name, t.iri, l.id, l.ref_object_id, p.point_id, p.x_axis_id, p.z_axis_id "
         "FROM ktw_solid_object s JOIN kitkb_thing t ON t.id = s.id "
         "JOIN ktw_physical_location l ON l.id = s.primary_location_id "
         "LEFT JOIN ktw_pose_location p ON p.id = l.id")
_NUMBERS = ("SELECT p.id, pt.x, pt.y, pt.z, xa.i, xa.j, xa.k, za.i, za.j, za.k, "
            "(SELECT value FROM kitkb_meta WHERE key = 'load_id') "
            "FROM ktw_pose_location p JOIN ktw_point pt ON pt.id = p.point_id "
            "JOIN ktw_vector xa ON xa.id = p.x_axis_id JOIN ktw_vector za ON za.id = p.z_axis_id")
_TOKEN = "SELECT value FROM kitkb_meta WHERE key = 'load_id'"


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


class _Stale(Exception):
    """The database was reloaded since the tree was read."""


class WorldModel:
    """Read and update the world model kept in database ``url`` (SQLite path or SQLAlchemy URL)."""

    def __init__(self, url: str | Path = db.DEFAULT_DB):
        self.url = db.normalize_url(url)
        self.engine = db.open_engine(self.url, must_exist=True)
        with self.engine.connect() as conn:
            db.check_version(conn, self.url)
        self._pg = self.engine.dialect.name == "postgresql"
        self._raw: Any = None
        self._tree: P.PoseTree | None = None

    # --- lifecycle ---------------------------------------------------------------------------
    def close(self) -> None:
        """Release the database connections."""
        if self._raw is not None:
            self._raw.close()
            self._raw = None
        self.engine.dispose()

    def __enter__(self) -> "WorldModel":
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def refresh(self) -> None:
        """Forget the transformation tree read so far (read again on the next pose operation)."""
        self._tree = None

    # --- the connection of the pose operations ---------------------------------------------------------
    def _cursor(self) -> Any:
        if self._raw is None:
            self._raw = self.engine.raw_connection()
            driver = self._raw.driver_connection
            if self._pg:
                import psycopg2.extensions as ext

                driver.autocommit = True  # transactions are begun explicitly (below)
                ext.register_type(ext.new_type((1700,), "KITKB_NUMERIC", _float), driver)
                driver.cursor().execute(f"PREPARE kitkb_numbers(int[]) AS {_NUMBERS} WHERE p.id = ANY($1)")
        return self._raw.driver_connection.cursor()

    def _begin(self, cur: Any) -> None:
        """Begin a write transaction (on PostgreSQL sent with the next statement: one round trip less)."""
        if self._pg:
            self._prefix = "BEGIN; "
        else:
            cur.execute("BEGIN IMMEDIATE")  # the write lock now: two writers queue, never deadlock

    _prefix = ""

    def _execute(self, cur: Any, sql: str, params: Any = ()) -> None:
        prefix, self._prefix = self._prefix, ""
        cur.execute(prefix + sql, params)

    def _numbers(self, cur: Any, locations: Sequence[int] | None) -> dict[int, list[float]]:
        """Numbers ``(point, x axis, z axis)`` of pose locations (all if None), by location id."""
        if locations is None:
            self._execute(cur, _NUMBERS)
        elif self._pg:
            self._execute(cur, "EXECUTE kitkb_numbers(%s)", (list(locations),))
        else:
            self._execute(cur, f"{_NUMBERS} WHERE p.id IN ({', '.join('?' * len(locations))})", tuple(locations))
        rows = cur.fetchall()
        if rows and self._tree is not None and rows[0][10] != self._tree.token:
            raise _Stale()
        return {r[0]: r[1:10] for r in rows}

    def _tree_of(self, cur: Any) -> P.PoseTree:
        if self._tree is None:
            cur.execute(_TOKEN)
            token = cur.fetchone()
            cur.execute(_TREE)
            self._tree = P.PoseTree.from_rows(cur.fetchall(), token[0] if token else None)
        return self._tree

    @staticmethod
    def _local(tree: P.PoseTree, numbers: dict[int, Any], members: Sequence[int]) -> Matrix:
        """Relative poses of ``members`` (rows in their order; identity where there are no numbers)."""
        local = np.empty((len(members), 4, 4))
        local[:] = np.eye(4)
        have = [k for k, i in enumerate(members) if tree.loc[i] in numbers]
        if have:
            try:
                local[have] = P.matrices(np.array([numbers[tree.loc[members[k]]] for k in have], dtype=float))
            except P.BadPose as exc:
                raise InputError(f"{tree.names[members[have[exc.row]]]}: {exc.reason}") from None
        return local

    def _read(self, fn: Any) -> Any:
        """Run ``fn(cursor, tree)``; read the tree again and retry once if the database was reloaded."""
        cur = self._cursor()
        for attempt in (0, 1):
            try:
                return fn(cur, self._tree_of(cur))
            except _Stale:
                self._tree = None
                if attempt:
                    raise InputError("the world model keeps being reloaded; try again") from None
        return None  # pragma: no cover

    # --- objects ---------------------------------------------------------------------------------
    def object(self, name: str) -> WorldObject:
        """The individual called ``name`` (local name or full IRI)."""
        with self.engine.connect() as conn:
            return self._resolve(conn, name)

    def objects(self, cls: str | type | None = None) -> list[WorldObject]:
        """All individuals, or those of class ``cls`` and its subclasses (local name, IRI or generated class)."""
        thing = model().table("kitkb_thing")
        query = select(thing.c.id, thing.c.iri, thing.c.name, thing.c.kind)
        if cls is not None:
            table = self._class_table(cls)
            query = query.join(table, table.c.id == thing.c.id)
        with self.engine.connect() as conn:
            return [WorldObject(*row) for row in conn.execute(query.order_by(thing.c.name, thing.c.iri))]

    @staticmethod
    def _class_table(cls: str | type) -> Any:
        m = model()
        if isinstance(cls, type) and hasattr(cls, "__table__"):
            return m.table(cls.__table__.name)  # a class of kb.world.generated.accessors
        text = str(cls)
        if text in m.class_table:
            return m.class_table[text]
        matches = sorted(iri for iri in m.class_table if local_name(iri) == text)
        if not matches:
            raise InputError(f"unknown class {text!r}")
        return m.class_table[matches[0]]

    @staticmethod
    def _resolve(conn: Connection, name: str) -> WorldObject:
        thing = model().table("kitkb_thing")
        cols = (thing.c.id, thing.c.iri, thing.c.name, thing.c.kind)
        rows = conn.execute(select(*cols).where(or_(thing.c.iri == name, thing.c.name == name)).limit(4)).all()
        exact = [r for r in rows if r[1] == name]
        if exact:
            return WorldObject(*exact[0])
        if not rows:
            raise InputError(f"no object named {name!r} in the world model")
        if len(rows) > 1:
            raise InputError(f"the name {name!r} is ambiguous: " + ", ".join(r[1] for r in rows[:3]) + " ...")
        return WorldObject(*rows[0])

    def _find(self, tree: P.PoseTree, name: str) -> int:
        try:
            return tree.find(name)
        except InputError:
            with self.engine.connect() as conn:
                obj = self._resolve(conn, name)  # the message for a name that is not a solid object
            raise InputError(f"{obj.name} is not a solid object with a location") from None

    # --- poses -------------------------------------------------------------------------------------
    def reference_of(self, name: str) -> str | None:
        """Name of the reference object of ``name``'s primary location (None at the root)."""
        def run(cur: Any, tree: P.PoseTree) -> str | None:
            self._check_token(cur, tree)
            ref = int(tree.ref[self._find(tree, name)])
            return tree.names[ref] if ref >= 0 else None
        return self._read(run)  # type: ignore[no-any-return]

    def pose(self, name: str) -> Matrix:
        """The relative pose ``L`` of ``name`` in its reference object's frame (4x4)."""
        def run(cur: Any, tree: P.PoseTree) -> Matrix:
            i = self._find(tree, name)
            return self._local(tree, self._numbers(cur, [tree.loc[i]]), [i])[0]
        return self._read(run)  # type: ignore[no-any-return]

    def global_pose(self, name: str) -> Matrix:
        """The pose of ``name`` in the root frame: the product of relative poses up the tree
        (one query for the numbers of the object's chain)."""
        def run(cur: Any, tree: P.PoseTree) -> Matrix:
            chain = tree.chain(self._find(tree, name))
            local = self._local(tree, self._numbers(cur, [tree.loc[i] for i in chain]), chain)
            out = local[-1]
            for k in range(len(chain) - 2, -1, -1):
                out = out @ local[k]
            return out
        return self._read(run)  # type: ignore[no-any-return]

    def global_poses(self, names: Iterable[str] | None = None) -> dict[str, Matrix]:
        """Global poses of all solid objects that have one (or of ``names``), keyed by name: one query, numpy."""
        def run(cur: Any, tree: P.PoseTree) -> dict[str, Matrix]:
            wanted = None if names is None else [self._find(tree, n) for n in names]
            if wanted is None:
                bad = np.nonzero(tree.depth < 0)[0]
                if len(bad):
                    tree.chain(int(bad[0]))  # names the cycle
                members = P.Members(tree, [int(i) for i in np.concatenate(tree.levels or [np.zeros(0, int)])
                                           if tree.posed[i]])  # objects with no pose are left out
                numbers = self._numbers(cur, None)
            else:
                members = P.Members(tree, tree.closure(wanted))
                numbers = self._numbers(cur, [tree.loc[i] for i in members.indexes])
            glob = P.compose(members, self._local(tree, numbers, members.indexes))
            keys = sorted(members.indexes) if wanted is None else wanted
            return {tree.names[i]: glob[members.row[i]] for i in keys}
        return self._read(run)  # type: ignore[no-any-return]

    def transformation_tree(self) -> dict[str, str | None]:
        """Each solid object's name mapped to its reference object's name (None for the root)."""
        def run(cur: Any, tree: P.PoseTree) -> dict[str, str | None]:
            self._check_token(cur, tree)
            return {n: (tree.names[r] if r >= 0 else None) for n, r in zip(tree.names, tree.ref.tolist())}
        return self._read(run)  # type: ignore[no-any-return]

    def _check_token(self, cur: Any, tree: P.PoseTree) -> None:
        cur.execute(_TOKEN)
        row = cur.fetchone()
        if (row[0] if row else None) != tree.token:
            raise _Stale()

    def set_pose(self, name: str, matrix: ArrayLike) -> None:
        """Store ``matrix`` as the relative pose of ``name`` (same reference object); one transaction."""
        self._apply([(name, P.rigid(matrix, [name])[0])], [], bump=False)

    def set_global_pose(self, name: str, matrix: ArrayLike) -> Matrix:
        """Store a sensed global pose with equation (1), ``L' = L G^-1 G'``; returns ``L'``."""
        return self._apply([], [(name, P.rigid(matrix, [name])[0])], bump=False)[0][name]

    # --- stable states -----------------------------------------------------------------------------
    def step(self) -> "Step":
        """A batch of updates applied together when confirmed (use as a context manager)."""
        return Step(self)

    def commit_stable_state(self, global_poses: Mapping[str, ArrayLike],
                            predicates: Mapping[str, bool] | Iterable[bool] | bool,
                            relative_poses: Mapping[str, ArrayLike] | None = None) -> StepResult:
        """Apply sensed global poses (eq. (1)) and relative poses in one transaction if every
        predicate holds; otherwise change nothing. Parents are updated before their children,
        so a tray and the part in it both reach their sensed poses. Returns the stable state's
        number (the counter in ``kitkb_meta``) when committed."""
        with self.step() as s:
            s.set_poses(relative_poses or {})
            s.set_global_poses(global_poses)
            s.confirm(predicates)
        assert s.result is not None
        return s.result

    def stable_state(self) -> int:
        """Number of stable states committed since the data was loaded."""
        cur = self._cursor()
        cur.execute("SELECT value FROM kitkb_meta WHERE key = 'stable_state'")
        row = cur.fetchone()
        return int(row[0]) if row else 0

    def _commit(self, relative: list[tuple[str, Matrix]], global_: list[tuple[str, Matrix]]) -> int:
        return self._apply(relative, global_, bump=True)[1]

    def _apply(self, relative: list[tuple[str, Matrix]], global_: list[tuple[str, Matrix]],
               bump: bool) -> tuple[dict[str, Matrix], int]:
        """One transaction: the updates of a batch (see :func:`kb.world.poses.update_batch`);
        the new relative pose of each object by name, and the stable state (if ``bump``)."""
        cur = self._cursor()
        for attempt in (0, 1):
            self._begin(cur)
            try:
                out, points, vectors = self._write(cur, self._tree_of(cur), relative, global_)
                state = self._store(cur, points, vectors, bump)
                cur.execute("COMMIT")
                return out, state
            except _Stale:
                self._rollback(cur)
                self._tree = None
                if attempt:
                    raise InputError("the world model keeps being reloaded; try again") from None
            except BaseException:
                self._rollback(cur)
                raise
        return {}, 0  # pragma: no cover

    def _rollback(self, cur: Any) -> None:
        if self._prefix:  # nothing was sent yet
            self._prefix = ""
        else:
            cur.execute("ROLLBACK")

    def _write(self, cur: Any, tree: P.PoseTree, relative: list[tuple[str, Matrix]], global_: list[tuple[str, Matrix]]
               ) -> tuple[dict[str, Matrix], list[tuple[Any, ...]], list[tuple[Any, ...]]]:
        """The new relative poses (eq. (1) for the global ones) and the point and vector rows
        ``(id, a, b, c)`` that store them."""
        rel = {self._find(tree, n): m for n, m in relative}
        glob = {self._find(tree, n): m for n, m in global_}
        changed = sorted(rel.keys() | glob.keys())
        for i in changed:
            if not tree.point[i] or not tree.x_axis[i] or not tree.z_axis[i]:
                raise InputError(f"{tree.names[i]} has no pose location (point and axes) to update")
        members = P.Members(tree, tree.closure(changed) if glob else changed)
        local = self._local(tree, self._numbers(cur, [tree.loc[i] for i in members.indexes]), members.indexes) \
            if glob else np.zeros((len(changed), 4, 4))
        row = members.row
        new = P.update_batch(members, local, {row[i]: m for i, m in rel.items()}, {row[i]: m for i, m in glob.items()})
        new = new[[row[i] for i in changed]]
        points, xs, zs = P.axes(new)
        point_rows = [(tree.point[i], *v) for i, v in zip(changed, points.tolist())]
        vector_rows = [(tree.x_axis[i], *v) for i, v in zip(changed, xs.tolist())] + \
            [(tree.z_axis[i], *v) for i, v in zip(changed, zs.tolist())]
        return {tree.names[i]: new[k] for k, i in enumerate(changed)}, point_rows, vector_rows

    def _store(self, cur: Any, points: list[tuple[Any, ...]], vectors: list[tuple[Any, ...]], bump: bool) -> int:
        """Write the rows, one statement per table (on PostgreSQL one statement for all, the
        stable-state counter included); the new stable state if ``bump``."""
        if not self._pg:
            cur.executemany("UPDATE ktw_point SET x = ?, y = ?, z = ? WHERE id = ?", [(*r[1:], r[0]) for r in points])
            cur.executemany("UPDATE ktw_vector SET i = ?, j = ?, k = ? WHERE id = ?", [(*r[1:], r[0]) for r in vectors])
            return _bump(cur, False) if bump else 0
        row = "(%s, %s::numeric, %s::numeric, %s::numeric)"
        values = [",".join(cur.mogrify(row, r).decode() for r in rows) for rows in (points, vectors)]
        parts = []  # a stable state with no pose to change only counts (VALUES () is not SQL)
        if values[0]:
            parts.append(f"p AS (UPDATE ktw_point AS t SET x = v.x, y = v.y, z = v.z FROM (VALUES {values[0]}) "
                         f"AS v(id, x, y, z) WHERE t.id = v.id)")
        if values[1]:
            parts.append(f"a AS (UPDATE ktw_vector AS t SET i = v.i, j = v.j, k = v.k FROM (VALUES {values[1]}) "
                         f"AS v(id, i, j, k) WHERE t.id = v.id)")
        sql = f"WITH {', '.join(parts)} " if parts else ""
        if not bump:
            self._execute(cur, sql + "SELECT 0")
            return 0
        self._execute(cur, sql + "UPDATE kitkb_meta SET value = CAST(CAST(value AS INTEGER) + 1 AS TEXT) "
                                 "WHERE key = 'stable_state' RETURNING value")
        found = cur.fetchone()
        return int(found[0]) if found else _bump(cur, True)


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
        self.relative.append((name, P.rigid(matrix, [name])[0]))

    def set_global_pose(self, name: str, matrix: ArrayLike) -> None:
        """Queue a sensed global pose (stored with equation (1))."""
        self.global_.append((name, P.rigid(matrix, [name])[0]))

    def set_poses(self, poses: Mapping[str, ArrayLike]) -> None:
        """Queue relative poses (checked all at once)."""
        self.relative += _checked(poses)

    def set_global_poses(self, poses: Mapping[str, ArrayLike]) -> None:
        """Queue sensed global poses (checked all at once)."""
        self.global_ += _checked(poses)

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


def _checked(poses: Mapping[str, ArrayLike]) -> list[tuple[str, Matrix]]:
    if not poses:
        return []
    names = list(poses)
    try:
        stacked = np.stack([np.asarray(poses[n], dtype=float) for n in names])
    except ValueError:
        return [(n, P.rigid(poses[n], [n])[0]) for n in names]  # says which one is malformed
    return list(zip(names, P.rigid(stacked, names)))


def _bump(cur: Any, pg: bool) -> int:
    """Increment the stable-state counter in kitkb_meta (in the caller's transaction); its new value."""
    p = "%s" if pg else "?"
    cur.execute("UPDATE kitkb_meta SET value = CAST(CAST(value AS INTEGER) + 1 AS TEXT) WHERE key = 'stable_state'")
    if cur.rowcount == 0:
        cur.execute(f"INSERT INTO kitkb_meta (key, value) VALUES ({p}, {p})", ("stable_state", "1"))
    cur.execute("SELECT value FROM kitkb_meta WHERE key = 'stable_state'")
    return int(cur.fetchone()[0])


def _float(value: str | None, _cur: Any) -> float | None:
    return None if value is None else float(value)
