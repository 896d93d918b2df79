"""A run in the world-model database: stable states, and the records executives query.

The database (SQLite file or PostgreSQL URL) holds the workstation and the SOAP individuals of
the domain (actions, their predicate atoms, failure modes, remediations: loaded together,
:func:`prepare`). During a run, :class:`RunStore`

* takes the poses the sensor reported and, when an action's effects hold, commits them as one
  stable state with eq. (1) (:meth:`kb.world.WorldModel.commit_stable_state`): a run that is
  killed leaves the last stable state;
* records each failure as a ``soap:ActionFailure`` row of the generated tables (its action,
  phase, violated predicate atoms and failure mode by key, so it can be queried in SQL) and,
  in kitkb's run tables, everything else: the run, its actions, the failure's arguments,
  objects, expected and seen positions, consequence, severity, recovery and outcome.

Objects the database does not know (a kit that appears during the run) keep their poses in
the run records only.

A run holds its database's writer lock (:mod:`kb.world.lock`) from :func:`prepare` to
:meth:`RunStore.close`: a second run or a load into the same database is refused while it
works, and a killed run leaves the lock to the system, which gives it back.
"""

from __future__ import annotations

import datetime as dt
import itertools
import json
import logging
import tempfile
import time
from dataclasses import asdict
from pathlib import Path
from typing import Any, Mapping, Sequence

import numpy as np
from sqlalchemy import (Boolean, Column, DateTime, Float, ForeignKey, Integer, MetaData, String, Table, Text,
                        func, insert, inspect, select, text, update)

from kb.core.errors import InputError
from kb.core.resources import ontology_path
from kb.io import load_file
from kb.io.turtle import Names
from kb.core.units import SI, Units
from kb.execution.records import ActionRecord, AtomCheck, FailureRecord, RunRecord, Sighting
from kb.metrics.kits import KitScore, LostPoint
from kb.world import LoadReport, load, normalize_url, open_engine
from kb.world.database import safe_url
from kb.world.lock import Held, acquire

#: What a run's lock says it is held by.
RUN = "a run"
#: Locks taken by :func:`prepare`, handed to the :class:`RunStore` that follows it on that URL.
_PREPARED: dict[str, Held] = {}

log = logging.getLogger("kitkb.execution")
META = MetaData()

RUNS = Table(
    "kitkb_run", META,
    Column("id", Integer, primary_key=True, autoincrement=True),
    Column("scenario", String(200), nullable=False),
    Column("seed", Integer),
    Column("started_at", DateTime(timezone=True), nullable=False),
    Column("ended_at", DateTime(timezone=True)),
    Column("goal_holds", Boolean),
    Column("stopped", Text),
    Column("replans", Integer, nullable=False, default=0),
    Column("report", Text),
    comment="One execution of a plan: kitkb's run history (kb.execution.store).",
)
ACTIONS = Table(
    "kitkb_run_action", META,
    Column("run_id", Integer, ForeignKey("kitkb_run.id"), primary_key=True),
    Column("idx", Integer, primary_key=True),
    Column("action", String(200), nullable=False),
    Column("args", Text, nullable=False),
    Column("status", String(40), nullable=False),
    Column("commands", Text, nullable=False),
    Column("seconds", Float),
    Column("crcl", Text),  # JSON: the CRCL programs sent, each a list of statements (CRCL text)
    comment="Each action of a run as executed (arguments after late binding, CRCL commands sent).",
)
KITS = Table(
    "kitkb_run_kit", META,
    Column("run_id", Integer, ForeignKey("kitkb_run.id"), primary_key=True),
    Column("kit", String(400), primary_key=True),
    Column("design", String(400)),
    Column("score", Integer, nullable=False),
    Column("max_score", Integer, nullable=False),
    Column("lost", Text, nullable=False),  # JSON: [{points, reason, predicate, objects, holds}]
    comment="Each goal kit's score at the end of a run, and why every point was lost (kb.metrics.kits).",
)
#: columns added to kitkb's run tables since they were first made: (table, column, SQL type)
_ADDED = (("kitkb_run_action", "crcl", "TEXT"),)
FAILURES = Table(
    "kitkb_run_failure", META,
    Column("id", Integer, primary_key=True, autoincrement=True),
    Column("run_id", Integer, ForeignKey("kitkb_run.id"), nullable=False, index=True),
    Column("action_failure", String(400), index=True),  # IRI of the soap:ActionFailure row
    Column("idx", Integer, nullable=False),
    Column("action", String(200), nullable=False),
    Column("args", Text, nullable=False),
    Column("phase", String(20), nullable=False),
    Column("mode", String(200), nullable=False, index=True),
    Column("kit", String(400)),
    Column("consequence", Text),
    Column("severity", Integer),
    Column("recovery", String(40)),
    Column("outcome", Text),
    Column("violated", Text, nullable=False),
    Column("sightings", Text, nullable=False),
    Column("seconds", Float),
    comment="A diagnosed action failure with what the soap:ActionFailure row does not hold.",
)

_SOAP = "https://w3id.org/kitkb/soap#"
_KD = "https://w3id.org/kitkb/kitting-domain#"


def prepare(url: str | Path, init: str | Path, domain_files: Sequence[str | Path] | None = None,
            replace: bool = False, loaded: Mapping[Path, Any] | None = None) -> LoadReport:
    """Load the initial state and the domain's SOAP individuals into ``url`` (one transaction;
    a database that holds a world model or run history only with ``replace``). ``loaded``: the
    files already read (resolved path -> :class:`kb.io.loader.Source`), not parsed again."""
    url = normalize_url(url)
    held = acquire(url, RUN)  # before anything is read: a busy database is refused at once
    try:
        domain = _domain_sources(domain_files) if domain_files else [ontology_path("kitting-domain.ttl")]
        with tempfile.TemporaryDirectory(prefix="kitkb-run-") as tmp:
            both = Path(tmp) / f"{Path(init).stem}+domain.nt"
            # N-Triples spellings: <iri>, _:label, "escaped"^^<dt> (rdflib's n3() writes a string with
            # a line break as """...""", which is Turtle, not N-Triples: NIST's STL file names are such)
            spell = Names({}).term
            starts: list[tuple[int, Any]] = []  # (first line in `both`, source) of each file's statements
            with open(both, "w", encoding="utf-8") as out:
                line = 1
                for path in [init, *domain]:
                    src = (loaded or {}).get(Path(path).resolve()) or load_file(path)
                    starts.append((line, src))
                    for s, p, o in src.triples():
                        out.write(f"{spell(s)} {spell(p)} {spell(o)} .\n")
                        line += 1
            try:
                report = load(both, url, replace=replace)
            except InputError as exc:
                raise _in_source(exc, both, starts, init) from None
    except BaseException:
        held.release()
        raise
    old = _PREPARED.pop(url, None)
    if old is not None:  # prepared twice without a run between: one hold is enough
        old.release()
    _PREPARED[url] = held
    return report


def _in_source(exc: InputError, both: Path, starts: list[tuple[int, Any]], init: str | Path) -> InputError:
    """An error of the load at a line of kitkb's own N-Triples file ``both``, told at the file
    and line of the statement it was written from (the temporary file is gone when it is read)."""
    if exc.file is None or Path(exc.file) != both:
        return exc
    if exc.line is None:
        return InputError(exc.message, init)
    first, src = next((start for start in reversed(starts) if start[0] <= exc.line), starts[0])
    statement = next(itertools.islice(src.triples(), exc.line - first, None), None)
    line = src.line_of(*statement) if statement is not None else None
    return InputError(exc.message, src.path, line)


def _domain_sources(domain_files: Sequence[str | Path]) -> list[Path]:
    """The domain files and the domain ontologies they import (an extension imports
    kitting-domain), without the model ontologies (soap.ttl, kitting.ttl) they import."""
    from kb.io import load as load_ontologies
    model = {ontology_path(name).resolve() for name in ("soap.ttl", "kitting.ttl")}
    return [s.path for s in load_ontologies(list(domain_files)).sources if Path(s.path).resolve() not in model]


class RunStore:
    """Writes one run into the database at ``url`` (which :func:`prepare` filled)."""

    def __init__(self, url: str | Path):
        from kb.world import WorldModel
        self.url = normalize_url(url)
        self._lock: Held | None = _PREPARED.pop(self.url, None) or acquire(self.url, RUN)
        try:
            self.engine = open_engine(self.url)
            META.create_all(self.engine, checkfirst=True)
            _add_columns(self.engine)
            self.world = WorldModel(self.url)
        except BaseException:
            self._release()
            raise
        self.run_id: int | None = None
        self.pending: dict[str, np.ndarray] = {}
        self.units = _units(self.engine)  # poses are sensed in metres; the database keeps its file's units
        self.metres = self.units.metres
        self.failures = 0
        self._known: set[str] | None = None
        self._started = dt.datetime.now(dt.timezone.utc)
        self._t0 = time.perf_counter()

    def close(self) -> None:
        """Close the database and give its writer lock back."""
        try:
            self.world.close()
            self.engine.dispose()
        finally:
            self._release()

    def _release(self) -> None:
        if self._lock is not None:
            self._lock.release()
            self._lock = None

    # --- the run ------------------------------------------------------------------------
    def begin_run(self, record: RunRecord, init: Any = None, goal: Any = None) -> None:
        self._t0 = time.perf_counter()
        with self.engine.begin() as conn:
            self.run_id = conn.execute(insert(RUNS).values(
                scenario=record.scenario, seed=record.seed, started_at=self._started, replans=0)).inserted_primary_key[0]
        record.run_id = self.run_id

    def end_run(self, record: RunRecord) -> None:
        with self.engine.begin() as conn:
            conn.execute(update(RUNS).where(RUNS.c.id == self.run_id).values(
                ended_at=dt.datetime.now(dt.timezone.utc), goal_holds=record.goal_holds, stopped=record.stopped,
                replans=record.replans, report=json.dumps(record.report())))
            conn.execute(KITS.delete().where(KITS.c.run_id == self.run_id))
            if record.kits:
                conn.execute(insert(KITS), [
                    {"run_id": self.run_id, "kit": k.kit, "design": k.design, "score": k.score,
                     "max_score": k.max_score, "lost": json.dumps([dict(x.as_dict(), objects=list(x.objects)) for x in k.lost])}
                    for k in record.kits])

    # --- stable states ------------------------------------------------------------------
    def poses_changed(self, poses: dict[str, np.ndarray]) -> None:
        """Sensed global poses, kept (copied: the caller's arrays are its belief, which changes,
        e.g. to NaN when the object is gone) until the next stable state."""
        known = self._names()
        self.pending.update({n: _in_units(np.array(m, float), self.metres) for n, m in poses.items() if n in known})

    def commit_stable(self, action_index: int) -> None:
        """The action's effects hold: its sensed poses become the database's stable state."""
        self.world.commit_stable_state(self.pending, True)  # one stable state per action, moved or not
        self.pending = {}

    def _names(self) -> set[str]:
        if self._known is None:
            self._known = {o.iri for o in self.world.objects()}
        return self._known

    # --- records ------------------------------------------------------------------------
    def record_action(self, action: ActionRecord) -> None:
        with self.engine.begin() as conn:
            conn.execute(insert(ACTIONS).values(
                run_id=self.run_id, idx=action.index, action=action.action, args=json.dumps(list(action.args)),
                status=action.status, commands=json.dumps(action.commands),
                seconds=max(0.0, action.ended - action.started), crcl=json.dumps(action.programs)))

    def record_failure(self, failure: FailureRecord) -> None:
        """The failure as a soap:ActionFailure row (by key) and a kitkb_run_failure row."""
        self.failures += 1
        iri = f"urn:kitkb:run:{self.run_id}:failure:{self.failures}"
        soap_row = self._action_failure(iri, failure)
        with self.engine.begin() as conn:
            conn.execute(insert(FAILURES).values(
                run_id=self.run_id, action_failure=iri if soap_row else None, idx=failure.action_index,
                action=failure.action, args=json.dumps(list(failure.args)), phase=failure.phase, mode=failure.mode,
                kit=failure.kit, consequence=failure.consequence, severity=failure.severity,
                recovery=failure.recovery, outcome=failure.outcome,
                violated=json.dumps([asdict(a) for a in failure.violated]),
                sightings=json.dumps([asdict(s) for s in failure.sightings]), seconds=failure.time - self._t0))

    def _action_failure(self, iri: str, failure: FailureRecord) -> bool:
        """Insert the soap:ActionFailure individual; False when the domain is not in the database."""
        from kb.world.generated.accessors import ActionFailure, Thing, soap_has_action_failure_violated_atom
        thing = Thing.__table__
        action_iri = f"{_KD}{failure.action}"
        phase_iri = f"{_SOAP}{'PreconditionCheck' if failure.phase == 'precondition' else 'EffectCheck'}"
        mode_iri = f"{_KD}{failure.mode}"
        atom_iris = [f"{_KD}{failure.action}_{'pre' if failure.phase == 'precondition' else 'eff'}"
                     f"{'_not' if a.negated else ''}_{a.predicate}" for a in failure.violated]
        with self.engine.begin() as conn:
            ids = dict(conn.execute(select(thing.c.iri, thing.c.id).where(
                thing.c.iri.in_([action_iri, phase_iri, mode_iri, *atom_iris]))).all())
            if action_iri not in ids or phase_iri not in ids:
                return False
            # explicit id: a bulk load (PostgreSQL COPY) writes ids without moving the serial sequence
            new_id = (conn.execute(select(func.max(thing.c.id))).scalar() or 0) + 1
            conn.execute(insert(thing).values(id=new_id, iri=iri, name=f"failure_{self.failures}",
                                              kind=f"{_SOAP}ActionFailure"))
            conn.execute(insert(ActionFailure.__table__).values(
                id=new_id, action_id=ids[action_iri], phase_id=ids[phase_iri], failure_mode_id=ids.get(mode_iri),
                timestamp=dt.datetime.now(dt.timezone.utc)))
            atoms = [{"subject_id": new_id, "value_id": ids[a]} for a in dict.fromkeys(atom_iris) if a in ids]
            if atoms:
                conn.execute(insert(soap_has_action_failure_violated_atom), atoms)
        return True


def read_run(url: str | Path, run_id: int | None = None) -> RunRecord:
    """A run back from the database (the latest one by default), as a :class:`RunRecord`."""
    engine = open_engine(normalize_url(url), must_exist=True)
    try:
        with engine.connect() as conn:
            if not inspect(conn).has_table(RUNS.name):
                from kb.core.errors import InputError
                raise InputError(f"no run is recorded in {safe_url(normalize_url(url))} (it has no kitkb_run table)")
            q = select(RUNS).order_by(RUNS.c.id.desc())
            row = conn.execute(q.where(RUNS.c.id == run_id) if run_id is not None else q).first()
            if row is None:
                from kb.core.errors import InputError
                raise InputError(f"no run {run_id if run_id is not None else ''} in {safe_url(normalize_url(url))}"
                                 .replace("  ", " "))
            rec = RunRecord(row.scenario, row.seed, goal_holds=row.goal_holds, stopped=row.stopped,
                            replans=row.replans, run_id=row.id)
            rec.started, rec.ended = 0.0, (row.ended_at - row.started_at).total_seconds() if row.ended_at else 0.0
            report = json.loads(row.report) if row.report else {}
            rec.injected = report.get("injected", [])
            metrics = report.get("metrics") or {}
            rec.plan_time, rec.replan_time = metrics.get("plan_time_s"), metrics.get("replan_time_s") or 0.0
            rec.violations = report.get("violations")
            rec.tip_start = tuple(report["tip_start"]) if report.get("tip_start") else None
            rec.scene = report.get("scene")
            for a in conn.execute(select(ACTIONS).where(ACTIONS.c.run_id == row.id).order_by(ACTIONS.c.idx)):
                rec.actions.append(ActionRecord(a.idx, a.action, tuple(json.loads(a.args)), a.status,
                                                json.loads(a.commands), programs=json.loads(a.crcl or "[]")))
            has_kits = inspect(conn).has_table(KITS.name)
            for k in conn.execute(select(KITS).where(KITS.c.run_id == row.id).order_by(KITS.c.kit)) if has_kits else ():
                rec.kits.append(KitScore(k.kit, k.design, k.score, k.max_score, tuple(
                    LostPoint(int(x["points"]), x["reason"], x["predicate"], tuple(x["objects"]), bool(x.get("holds")))
                    for x in json.loads(k.lost))))
            for f in conn.execute(select(FAILURES).where(FAILURES.c.run_id == row.id).order_by(FAILURES.c.id)):
                violated = [AtomCheck(d["predicate"], tuple(d["args"]), d["negated"], d["holds"])
                            for d in json.loads(f.violated)]
                sightings = [Sighting(d["name"], tuple(d["expected"]) if d["expected"] else None,
                                      tuple(d["seen"]) if d["seen"] else None) for d in json.loads(f.sightings)]
                args = {x for a in violated for x in a.args}  # the other objects sighted are its witnesses
                rec.failures.append(FailureRecord(
                    f.idx, f.action, tuple(json.loads(f.args)), f.phase, violated, sightings,
                    f.mode, f.consequence or "", f.severity or 0, f.recovery or "", f.outcome or "", f.seconds or 0.0,
                    kit=f.kit, witnesses=[s.name for s in sightings if s.name not in args]))
            return rec
    finally:
        engine.dispose()


def _add_columns(engine: Any) -> None:
    """Columns kitkb's run tables gained since a database's tables were made (:data:`_ADDED`)."""
    with engine.begin() as conn:
        insp = inspect(conn)
        for table, column, kind in _ADDED:
            if insp.has_table(table) and column not in {c["name"] for c in insp.get_columns(table)}:
                conn.execute(text(f"ALTER TABLE {table} ADD COLUMN {column} {kind}"))


def _units(engine: Any) -> Units:
    """The units of the world model in the database (its workstation's; SI where it has none)."""
    with engine.connect() as conn:
        row = conn.execute(text("SELECT length_unit, angle_unit, weight_unit FROM ktw_kitting_workstation")).first()
    return Units(*row) if row is not None else SI


def _in_units(pose: np.ndarray, metres: float) -> np.ndarray:
    """A global pose sensed in metres, with its translation in the database's length unit."""
    if metres == 1.0:
        return pose
    out = np.array(pose, float)
    out[:3, 3] /= metres
    return out
