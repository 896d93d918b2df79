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

Each row of kitkb's run tables holds its record's dict form (:mod:`kb.execution.codec`) as
JSON text in its ``record`` column, which :func:`read_run` reads back equal to the record in
memory; the other columns are derived from that dict for SQL queries (``mode``, ``idx``,
``seconds``, ...). Rows of older kitkb versions (no ``record``) are read from their columns.

Objects the database does not know (a kit that appears during the run) keep their poses in
the run records only.

A run holds its database's writer lock (:mod:`kb.world.lock`) from :func:`prepare` to
:meth:`RunStore.close`: a second run or a load into the same database is refused while it
works, and a killed run leaves the lock to the system, which gives it back.
"""

from __future__ import annotations

import datetime as dt
import hashlib
import itertools
import json
import logging
import math
import tempfile
import time
from pathlib import Path
from typing import Any, Mapping, Sequence

import numpy as np
from sqlalchemy import (BigInteger, Boolean, Column, DateTime, Float, ForeignKey, Integer, MetaData, String, Table, Text,
                        bindparam, func, insert, inspect, select, text, update)

from kb.core.errors import InputError
from kb.io import load_file
from kb.io.loader import domain_paths
from kb.io.turtle import Names
from kb.core.units import SI, Units
from kb.execution.codec import dumps, encode, loads
from kb.execution.records import ActionRecord, FailureRecord, RunRecord
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
    Column("scenario", Text, nullable=False),
    Column("seed", BigInteger),
    Column("started_at", DateTime(timezone=True), nullable=False),
    Column("ended_at", DateTime(timezone=True)),
    Column("goal_holds", Boolean),
    Column("stopped", Text),
    Column("replans", BigInteger, nullable=False, default=0),
    Column("report", Text),
    Column("record", Text),  # JSON: the run's dict form, without its actions and failures (their rows')
    comment="One execution of a plan: kitkb's run history (kb.execution.store).",
)
ACTIONS = Table(
    "kitkb_run_action", META,
    Column("run_id", Integer, ForeignKey("kitkb_run.id"), primary_key=True),
    Column("idx", BigInteger, primary_key=True),
    Column("action", Text, nullable=False),
    Column("args", Text, nullable=False),
    Column("status", Text, nullable=False),
    Column("commands", Text, nullable=False),
    Column("seconds", Float),
    Column("crcl", Text),  # JSON: the CRCL programs sent, each a list of statements (CRCL text)
    Column("record", Text),  # JSON: the action's dict form
    comment="Each action of a run as executed (arguments after late binding, CRCL commands sent).",
)
KITS = Table(
    "kitkb_run_kit", META,
    Column("run_id", Integer, ForeignKey("kitkb_run.id"), primary_key=True),
    Column("kit", Text, primary_key=True),
    Column("design", Text),
    Column("score", BigInteger, nullable=False),
    Column("max_score", BigInteger, nullable=False),
    Column("lost", Text, nullable=False),  # JSON: [{points, reason, predicate, objects, holds}]
    comment="Each goal kit's score at the end of a run, and why every point was lost (kb.metrics.kits).",
)
#: an action's row inserted, and updated by (run, index): statements made once, the values bound
#: as parameters (a statement built with ``.values()`` per row was built and keyed again for each
#: of a 160-part run's 357 rows, 0.05 s)
_ACTION_ROW = (insert(ACTIONS), update(ACTIONS).where((ACTIONS.c.run_id == bindparam("key_run"))
                                                      & (ACTIONS.c.idx == bindparam("key_idx"))))
#: columns added to kitkb's run tables since they were first made: (table, column, SQL type)
_ADDED = (("kitkb_run_action", "crcl", "TEXT"), ("kitkb_run", "record", "TEXT"),
          ("kitkb_run_action", "record", "TEXT"), ("kitkb_run_failure", "record", "TEXT"))
FAILURES = Table(
    "kitkb_run_failure", META,
    Column("id", Integer, primary_key=True, autoincrement=True),
    Column("run_id", Integer, ForeignKey("kitkb_run.id"), nullable=False, index=True),
    Column("action_failure", String(400), index=True),  # IRI of the soap:ActionFailure row
    Column("idx", BigInteger, nullable=False),
    Column("action", Text, nullable=False),
    Column("args", Text, nullable=False),
    Column("phase", Text, nullable=False),
    Column("mode", Text, nullable=False, index=True),
    Column("kit", Text),
    Column("consequence", Text),
    Column("severity", BigInteger),
    Column("recovery", Text),
    Column("outcome", Text),
    Column("violated", Text, nullable=False),
    Column("sightings", Text, nullable=False),
    Column("seconds", Float),
    Column("record", Text),  # JSON: the failure's dict form
    comment="A diagnosed action failure with what the soap:ActionFailure row does not hold.",
)

INPUTS = Table(
    "kitkb_run_input", META,
    Column("run_id", Integer, ForeignKey("kitkb_run.id"), primary_key=True),
    Column("inputs", Text, nullable=False),  # JSON: the files (path, sha256) and the options
    comment="What a run was started from: its state and domain files and its options (kitkb run --resume).",
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
        domain = domain_paths(domain_files)  # the shipped domain and the extensions
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
        #: what each row holds: action index -> its record's JSON; id(failure) -> (failure, row id, JSON)
        self._actions: dict[int, str] = {}
        self._failures: dict[int, tuple[FailureRecord, int, str]] = {}
        self._known: set[str] | None = None
        self._started = dt.datetime.now(dt.timezone.utc)
        self._t0 = time.perf_counter()
        #: what the run was started from (files and options, :func:`run_inputs`), written with its
        #: row by :meth:`begin_run` when set (a run that can be resumed: kb.execution.resume)
        self.inputs: dict[str, Any] | None = None

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
            self.run_id = conn.execute(insert(RUNS).values(started_at=self._started, **_run_columns(
                _run_dict(record)))).inserted_primary_key[0]
            if self.inputs is not None:
                conn.execute(insert(INPUTS).values(run_id=self.run_id, inputs=dumps(self.inputs)))
        record.run_id = self.run_id
        self._actions, self._failures = {}, {}

    def continue_run(self, record: RunRecord) -> None:
        """Go on writing the run ``record`` read back from this database (:func:`read_run`, its
        ``run_id`` set): the same run's row, its actions' and failures' rows updated where they
        change, new ones added after them (kb.execution.resume)."""
        self.run_id = record.run_id
        self._t0 = record.started
        with self.engine.connect() as conn:
            self._actions = {int(r.idx): r.record for r in conn.execute(
                select(ACTIONS.c.idx, ACTIONS.c.record).where(ACTIONS.c.run_id == self.run_id))}
            rows = conn.execute(select(FAILURES.c.id, FAILURES.c.record).where(
                FAILURES.c.run_id == self.run_id).order_by(FAILURES.c.id)).all()
        if len(rows) != len(record.failures):
            raise InputError(f"run {self.run_id}: {len(record.failures)} failure(s) read back, {len(rows)} row(s)")
        self._failures = {id(f): (f, row.id, row.record) for f, row in zip(record.failures, rows)}
        self.failures = len(rows)

    def end_run(self, record: RunRecord) -> None:
        """The run's row, its kits' rows, and the rows of every action and failure as they are
        now (a failure's outcome decided after it was recorded, one never recorded)."""
        d = _run_dict(record)
        with self.engine.begin() as conn:
            conn.execute(update(RUNS).where(RUNS.c.id == self.run_id).values(
                ended_at=dt.datetime.now(dt.timezone.utc), report=json.dumps(record.report()), **_run_columns(d)))
            conn.execute(KITS.delete().where(KITS.c.run_id == self.run_id))
            kits = {k["kit"]: k for k in reversed(d["kits"])}  # a row per kit name (the record holds them all)
            if kits:
                conn.execute(insert(KITS), [dict(_kit_columns(k), run_id=self.run_id) for k in reversed(kits.values())])
        for action in record.actions:
            self.record_action(action)  # written again only where it changed
        for failure in record.failures:
            self.record_failure(failure)

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
        """The action's row (its index is its key in the run: recorded again, the row is
        updated)."""
        d = action.to_dict()
        text_ = dumps(d)
        if self._actions.get(action.index) == text_:
            return
        values = _action_columns(d, text_)
        with self.engine.begin() as conn:  # the statements made once, the row's values bound (_ACTION_ROW)
            if action.index in self._actions:
                conn.execute(_ACTION_ROW[1], {"key_run": self.run_id, "key_idx": action.index, **values})
            else:
                conn.execute(_ACTION_ROW[0], {"run_id": self.run_id, **values})
        self._actions[action.index] = text_

    def record_failure(self, failure: FailureRecord) -> None:
        """The failure as a soap:ActionFailure row (by key) and a kitkb_run_failure row (the
        same failure recorded again: its row updated)."""
        d = failure.to_dict()
        text_ = dumps(d)
        known = self._failures.get(id(failure))
        if known is not None and known[0] is failure:
            if known[2] != text_:
                with self.engine.begin() as conn:
                    conn.execute(update(FAILURES).where(FAILURES.c.id == known[1]).values(
                        **_failure_columns(d, text_, self._t0)))
                self._failures[id(failure)] = (failure, known[1], text_)
            return
        self.failures += 1
        iri = f"urn:kitkb:run:{self.run_id}:failure:{self.failures}"
        soap_row = self._action_failure(iri, failure)
        with self.engine.begin() as conn:
            row = conn.execute(insert(FAILURES).values(
                run_id=self.run_id, action_failure=iri if soap_row else None,
                **_failure_columns(d, text_, self._t0))).inserted_primary_key[0]
        self._failures[id(failure)] = (failure, row, text_)

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


def _run_dict(record: RunRecord) -> dict[str, Any]:
    """The run's dict form without its actions and failures (which have rows of their own)."""
    return encode(record, skip=("actions", "failures"))


def _run_columns(d: dict[str, Any]) -> dict[str, Any]:
    """The queried columns of a run's row, from its dict form."""
    return {"scenario": d["scenario"], "seed": d["seed"], "goal_holds": d["goal_holds"], "stopped": d["stopped"],
            "replans": d["replans"], "record": dumps(d)}


def _action_columns(d: dict[str, Any], record: str) -> dict[str, Any]:
    """The columns of an action's row, from its dict form (and that form's JSON text)."""
    return {"idx": d["index"], "action": d["action"], "args": dumps(d["args"]), "status": d["status"],
            "commands": dumps(d["commands"]), "seconds": _finite(max(0.0, d["ended"] - d["started"])),
            "crcl": dumps(d["programs"]), "record": record}


def _failure_columns(d: dict[str, Any], record: str, t0: float) -> dict[str, Any]:
    """The columns of a failure's row, from its dict form (``seconds``: since ``t0``)."""
    return {"idx": d["action_index"], "action": d["action"], "args": dumps(d["args"]), "phase": d["phase"],
            "mode": d["mode"], "kit": d["kit"], "consequence": d["consequence"], "severity": d["severity"],
            "recovery": d["recovery"], "outcome": d["outcome"], "violated": dumps(d["violated"]),
            "sightings": dumps(d["sightings"]), "seconds": _finite(d["time"] - t0), "record": record}


def _finite(seconds: float) -> float | None:
    """A duration for a Float column (None where a difference of extreme times overflows)."""
    return seconds if math.isfinite(seconds) else None


def _kit_columns(d: dict[str, Any]) -> dict[str, Any]:
    """The columns of a kit's row, from its score's dict form."""
    return {"kit": d["kit"], "design": d["design"], "score": d["score"], "max_score": d["max_score"],
            "lost": dumps(d["lost"])}


def read_run(url: str | Path, run_id: int | None = None) -> RunRecord:
    """A run back from the database (the latest one by default), as a :class:`RunRecord`
    equal to the one that was recorded (rows of older kitkb versions: what their columns hold)."""
    url = normalize_url(url)
    engine = open_engine(url, must_exist=True)
    try:
        with engine.connect() as conn:
            if not inspect(conn).has_table(RUNS.name):
                raise InputError(f"no run is recorded in {safe_url(url)} (it has no kitkb_run table)")
            q = select(*_columns(conn, RUNS)).order_by(RUNS.c.id.desc())
            row = conn.execute(q.where(RUNS.c.id == run_id) if run_id is not None else q).first()
            if row is None:
                raise InputError(f"no run {run_id if run_id is not None else ''} in {safe_url(url)}".replace("  ", " "))
            try:
                return _read(conn, row, f"{safe_url(url)}: run {row.id}")
            except ValueError as exc:  # a row that is not what kitkb writes: the message names it
                raise InputError(str(exc)) from None
    finally:
        engine.dispose()


def _read(conn: Any, row: Any, where: str) -> RunRecord:
    """Run ``row`` and its actions' and failures' rows, each from its dict form (``where``: how
    an error names the run)."""
    report = _json(row.report, f"{where}: report") if row.report else {}
    record = getattr(row, "record", None)
    d = _json(record, f"{where}: record") if record else _legacy_run(conn, row, report, where)
    d["run_id"] = row.id
    run: RunRecord = RunRecord.from_dict(d, where)
    for a in conn.execute(select(*_columns(conn, ACTIONS)).where(ACTIONS.c.run_id == row.id).order_by(ACTIONS.c.idx)):
        at = f"{where}: action {a.idx}"
        run.actions.append(ActionRecord.from_dict(_json(a.record, at) if getattr(a, "record", None)
                                                  else _legacy_action(a, at), at))
    failures = conn.execute(select(*_columns(conn, FAILURES)).where(FAILURES.c.run_id == row.id).order_by(FAILURES.c.id)).all()
    told = report.get("failures") if isinstance(report.get("failures"), list) else []
    for i, f in enumerate(failures):
        at = f"{where}: failure row {f.id}"
        run.failures.append(FailureRecord.from_dict(_json(f.record, at) if getattr(f, "record", None) else
                                                    _legacy_failure(f, told[i] if len(told) == len(failures)
                                                                    and isinstance(told[i], dict) else {}, at), at))
    return run


def recorded_inputs(init: str | Path, goal: str | Path, options: Any) -> dict[str, Any]:
    """What a run needs to be resumed, as JSON data: its state files and domain extensions
    (absolute path and SHA-256 each) and the options that decide what it does."""
    faults = options.faults
    return {"init": _file(init), "goal": _file(goal),
            "domain": [_file(p) for p in options.domain_files or ()],
            "seed": options.seed, "faults": None if faults is None else str(faults),
            "partial_kits": options.partial_kits, "planner": options.planner,
            "sensor_noise": None if options.sensor_noise is None else str(options.sensor_noise),
            "match_names": options.match_names, "cell": options.cell if isinstance(options.cell, str) else None,
            "name": options.name}


def _file(path: str | Path) -> dict[str, str]:
    p = Path(path).resolve()
    return {"path": str(p), "sha256": hashlib.sha256(p.read_bytes()).hexdigest()}


def run_inputs(url: str | Path, run_id: int) -> dict[str, Any]:
    """What run ``run_id`` was started from (:attr:`RunStore.inputs`); an InputError in one line
    for a run recorded without them (by a kitkb before ``--resume``, or through the Python API
    with a store of its own)."""
    url = normalize_url(url)
    engine = open_engine(url, must_exist=True)
    try:
        with engine.connect() as conn:
            row = conn.execute(select(INPUTS.c.inputs).where(INPUTS.c.run_id == run_id)).first() \
                if inspect(conn).has_table(INPUTS.name) else None
    finally:
        engine.dispose()
    if row is None:
        raise InputError(f"run {run_id} in {safe_url(url)} was recorded without its state files and options "
                         "(a kitkb before kitkb run --resume): it cannot be resumed")
    try:
        return dict(loads(row.inputs))
    except (ValueError, TypeError) as exc:
        raise InputError(f"{safe_url(url)}: run {run_id}: its recorded inputs are not JSON ({exc})") from None


def latest_run(url: str | Path) -> int | None:
    """The id of the last run recorded in ``url`` (None: no run table or no run)."""
    url = normalize_url(url)
    engine = open_engine(url, must_exist=True)
    try:
        with engine.connect() as conn:
            if not inspect(conn).has_table(RUNS.name):
                return None
            return conn.execute(select(func.max(RUNS.c.id))).scalar()
    finally:
        engine.dispose()


def _columns(conn: Any, table: Table) -> list[Column]:
    """The columns of ``table`` that the database's table has (an older version's lacks some)."""
    have = {c["name"] for c in inspect(conn).get_columns(table.name)}
    return [c for c in table.columns if c.name in have]


def _json(text_: str, where: str) -> Any:
    try:
        return loads(text_)
    except ValueError as exc:
        raise ValueError(f"{where}: not JSON ({exc})") from None


def _legacy_run(conn: Any, row: Any, report: dict[str, Any], where: str) -> dict[str, Any]:
    """The dict form of a run row without a record: its columns and its JSON report (times
    relative to its start, the report's rounded plan times; no checks)."""
    metrics = report.get("metrics") or {}
    d = {"scenario": row.scenario, "seed": row.seed, "goal_holds": row.goal_holds, "stopped": row.stopped,
         "replans": row.replans, "started": 0.0,
         "ended": (row.ended_at - row.started_at).total_seconds() if row.ended_at else 0.0,
         "injected": report.get("injected", []), "plan_time": metrics.get("plan_time_s"),
         "replan_time": metrics.get("replan_time_s") or 0.0}
    d.update({k: report.get(k) for k in ("violations", "tip_start", "scene", "sensor", "sensor_errors")})
    kits = conn.execute(select(KITS).where(KITS.c.run_id == row.id).order_by(KITS.c.kit)) \
        if inspect(conn).has_table(KITS.name) else ()
    d["kits"] = [{"kit": k.kit, "design": k.design, "score": k.score, "max_score": k.max_score,
                  "lost": _json(k.lost, f"{where}: kit {k.kit}")} for k in kits]
    return d


def _legacy_action(a: Any, where: str) -> dict[str, Any]:
    """The dict form of an action row without a record (no times)."""
    return {"index": a.idx, "action": a.action, "args": _json(a.args, where), "status": a.status,
            "commands": _json(a.commands, where), "programs": _json(a.crcl or "[]", where)}


def _legacy_failure(f: Any, told: dict[str, Any], where: str) -> dict[str, Any]:
    """The dict form of a failure row without a record (its certainty from the run's report,
    its witnesses the objects sighted that are not the violated atoms' arguments)."""
    violated = _json(f.violated, where)
    sightings = _json(f.sightings, where)
    args = {x for a in violated if isinstance(a, dict) for x in a.get("args", ())}
    return {"action_index": f.idx, "action": f.action, "args": _json(f.args, where),
            "phase": f.phase, "violated": violated, "sightings": sightings, "mode": f.mode,
            "consequence": f.consequence or "", "severity": f.severity or 0, "recovery": f.recovery or "",
            "outcome": f.outcome or "", "time": f.seconds or 0.0, "kit": f.kit,
            "certainty": told.get("certainty"), "witnesses": [s["name"] for s in sightings if isinstance(s, dict) and s.get("name") not in args]}


def _add_columns(engine: Any) -> None:
    """Columns kitkb's run tables gained since a database's tables were made (:data:`_ADDED`),
    and, in PostgreSQL, the columns widened since (text of any length, 64-bit integers)."""
    with engine.begin() as conn:
        insp = inspect(conn)
        for table, column, kind in _ADDED:
            if insp.has_table(table) and column not in {c["name"] for c in insp.get_columns(table)}:
                conn.execute(text(f"ALTER TABLE {table} ADD COLUMN {column} {kind}"))
        if conn.dialect.name != "postgresql":
            return  # SQLite: any integer column holds 64 bits, no text column has a length
        for table in (RUNS, ACTIONS, KITS, FAILURES):
            have = {c["name"]: c["type"] for c in insp.get_columns(table.name)}
            for col in table.columns:
                old = have.get(col.name)
                if isinstance(col.type, BigInteger) and isinstance(old, Integer) and not isinstance(old, BigInteger):
                    conn.execute(text(f"ALTER TABLE {table.name} ALTER COLUMN {col.name} TYPE BIGINT"))
                elif type(col.type) is Text and isinstance(old, String) and not isinstance(old, Text):
                    conn.execute(text(f"ALTER TABLE {table.name} ALTER COLUMN {col.name} TYPE TEXT"))


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
