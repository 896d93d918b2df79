"""A campaign on Dask distributed: its trials as independent jobs, their rows in a folder.

:func:`run_campaign` maps :func:`kb.testmethod.trial.run_trial` over the campaign's jobs
(:func:`kb.testmethod.methods.jobs`) with ``Client.map``: on a ``LocalCluster`` of one worker
process per core (``workers``), or on the scheduler of a real cluster (``scheduler``). The
scheduling, the retries (``retries=``: a trial that raised is run again) and the recovery from
a worker that died (the scheduler gives its trial to another worker; a trial that has been
on more than :data:`ALLOWED_FAILURES` workers that died is given up as lost) are Dask's. A trial's row depends on its
job alone, so 1 worker, N workers and a cluster give the same rows.

The campaign folder (the contract with ``kitkb report``)::

    DIR/campaign.json        {"method", "seed", "trials", "options", "summary"}
    DIR/trials/00000.json    one trial's row: a run report plus "trial": {index, seed, method,
                             design, layout, time_s, error; noise, sweep}

A noise sweep (``Options.noise_sweep``) runs every trial at every level: row ``k`` (its file
``k``) is trial ``k // L`` at level ``k % L`` of ``L``, with the trial's seed.

Each trial file is written atomically by the client as its result arrives. A campaign run
again into the same folder with the same method, seed and options resumes: the trials whose
files are there are read, not run (more ``--trials`` extend it). campaign.json gets its summary
when the campaign ends (``null`` until then).
"""

from __future__ import annotations

import json
import logging
import os
import time
import uuid
from contextlib import contextmanager, nullcontext
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Iterator

from kb.core.errors import InputError
from kb.core.files import write_atomic
from kb.core.progress import SILENT, Progress
from kb.model.faults import domain_fault_kinds
from kb.testmethod.methods import Job, Options, jobs, not_executed, trial_seed
from kb.testmethod.summary import summarize

#: times Dask runs a trial again after it raised
RETRIES = 2
#: worker deaths a trial may be part of before it is given up as lost (Dask's allowed-failures)
ALLOWED_FAILURES = 3
CAMPAIGN_FILE = "campaign.json"
TRIALS = "trials"


@dataclass
class Campaign:
    """A finished (or resumed and finished) campaign: its rows in trial order and summary."""

    options: Options
    out_dir: Path
    rows: list[dict[str, Any]]
    summary: dict[str, Any]
    ran: int = 0  # trials run now
    resumed: int = 0  # trials read from the folder
    lost: list[int] = field(default_factory=list)  # trials whose workers kept dying
    wall_s: float = 0.0
    workers: int = 0


def trial_path(out_dir: Path, index: int) -> Path:
    return Path(out_dir) / TRIALS / f"{index:05d}.json"


def header(options: Options, summary: dict[str, Any] | None = None) -> dict[str, Any]:
    """campaign.json's content."""
    return {"method": options.method, "seed": options.seed, "trials": options.trials,
            "options": options.as_dict(), "summary": summary}


def done_rows(options: Options, out_dir: Path) -> dict[int, dict[str, Any]]:
    """The rows of this campaign already in ``out_dir``; an InputError when the folder holds a
    campaign of another method, seed or options (or is no campaign folder)."""
    out_dir = Path(out_dir)
    if out_dir.exists() and not out_dir.is_dir():
        raise InputError("--out exists and is not a folder", file=out_dir)
    meta = out_dir / CAMPAIGN_FILE
    if not meta.exists():
        if (out_dir / TRIALS).exists():
            raise InputError(f"{out_dir / TRIALS} exists without {CAMPAIGN_FILE}: not a campaign folder kitkb wrote",
                             file=out_dir)
        return {}
    try:
        old = json.loads(meta.read_text(encoding="utf-8"))
        same = (old["method"], old["seed"], old["options"]) == (options.method, options.seed, options.as_dict())
    except (OSError, ValueError, KeyError, TypeError) as e:
        raise InputError(f"not a campaign file kitkb wrote ({e})", file=meta) from None
    if not same:
        raise InputError(f"holds the campaign {old['method']} --seed {old['seed']} {old['options']}, not this one: "
                         "give another --out, or the same options to resume it", file=meta)
    rows = {}
    for index in range(options.rows):
        row = _read_row(trial_path(out_dir, index))
        trial = (row or {}).get("trial") or {}
        number, level = options.locate(index)
        if trial.get("index") == index and trial.get("seed") == trial_seed(options.seed, number) \
                and trial.get("method") == options.method \
                and trial.get("sweep") == (None if level is None else {"trial": number, "level": level}):
            rows[index] = row
    return rows


def _check_folder(out_dir: Path) -> None:
    """An InputError, before any work, for a campaign folder that cannot be made or written."""
    place = out_dir
    while not place.exists() and place != place.parent:
        place = place.parent
    if not place.is_dir():
        raise InputError(f"{place} is a file: the campaign folder cannot be made under it", file=out_dir)
    if not os.access(place, os.W_OK | os.X_OK):
        raise InputError(f"{place} is not writable: the campaign folder cannot be made there", file=out_dir)


def _read_row(path: Path) -> dict[str, Any] | None:
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):  # missing, or not JSON: run the trial (again)
        return None
    return data if isinstance(data, dict) else None


def run_campaign(options: Options, out_dir: str | Path, *, workers: int | None = None, scheduler: str | None = None,
                 client: Any = None, progress: Progress = SILENT) -> Campaign:
    """Run the campaign's trials not yet in ``out_dir`` on Dask and write their rows; the
    campaign with every row and its summary. ``workers``: processes of the LocalCluster
    (default one per core); ``scheduler``: the address of a running Dask scheduler instead;
    ``client``: a ``distributed.Client`` to use as it is (left open)."""
    out_dir = Path(out_dir)
    if workers is not None and workers < 1:
        raise InputError(f"--workers must be at least 1 (got {workers})")
    rows = done_rows(options, out_dir)
    _check_folder(out_dir)
    todo = [i for i in range(options.rows) if i not in rows]
    t = time.perf_counter()
    lost: list[int] = []
    n_workers = 0
    with _client(workers, scheduler, client) if todo else nullcontext() as client:
        try:
            (out_dir / TRIALS).mkdir(parents=True, exist_ok=True)  # once the scheduler answered
        except OSError as e:
            raise InputError(f"cannot make the campaign folder: {e.strerror}", file=out_dir) from None
        write_atomic(out_dir / CAMPAIGN_FILE, json.dumps(header(options), indent=1) + "\n")
        if todo:
            n_workers = len(client.scheduler_info().get("workers", {})) or (workers or 0)
            with progress.task(f"{options.method}: trials on {n_workers} Dask worker(s)", total=len(todo),
                               unit="trials") as task:
                for index, row in _results(client, jobs(options, todo)):
                    if row is None:
                        lost.append(index)
                    else:
                        write_atomic(trial_path(out_dir, index), json.dumps(row, separators=(",", ":")) + "\n")
                        rows[index] = row
                    task.advance()
    wall = time.perf_counter() - t
    ordered = [rows[i] for i in sorted(rows)]
    summary = summarize(ordered, sweep=options.noise_sweep, base=options.sensor_noise,
                        kinds=domain_fault_kinds(options.domain) if options.domain else None)
    summary["run"] = {"ran": len(todo) - len(lost), "resumed": options.rows - len(todo), "lost": sorted(lost),
                      "workers": n_workers, "wall_s": round(wall, 3),
                      "trials_per_s": round((len(todo) - len(lost)) / wall, 4) if todo and wall > 0 else None}
    write_atomic(out_dir / CAMPAIGN_FILE, json.dumps(header(options, summary), indent=1) + "\n")
    return Campaign(options, out_dir, ordered, summary, len(todo) - len(lost), options.rows - len(todo),
                    sorted(lost), wall, n_workers)


def _results(client: Any, batch: list[Job]) -> Iterator[tuple[int, dict[str, Any] | None]]:
    """(index, row) of each job as it finishes; a job whose trial raised after its retries gets
    an error row; one Dask gave up on (its workers died) gets None."""
    from distributed import as_completed
    from distributed.scheduler import KilledWorker
    from kb.testmethod.trial import run_trial

    token = uuid.uuid4().hex[:8]
    futures = client.map(run_trial, batch, key=[f"kitkb-trial-{job.method}-{job.index}-{token}" for job in batch],
                         retries=RETRIES, pure=False)
    by_key = {f.key: job for f, job in zip(futures, batch)}
    try:
        for future in as_completed(futures, raise_errors=False):
            job = by_key[future.key]
            if future.status == "finished":
                yield job.index, future.result()
                continue
            exc = future.exception()
            yield job.index, None if isinstance(exc, KilledWorker) else _error_row(job, exc)
            future.release()
    finally:
        client.cancel(futures)


def _error_row(job: Job, exc: BaseException) -> dict[str, Any]:
    """The row of a trial that raised each time it ran (a fault of kitkb's: it says which)."""
    message = f"internal error: {type(exc).__name__}: {exc}"
    return {**not_executed(job, message), "trial": {**job.facts(), "layout": None, "time_s": None, "error": message}}


@contextmanager
def _client(workers: int | None, scheduler: str | None, given: Any = None) -> Iterator[Any]:
    """A Dask client: ``given``, or of the scheduler at ``scheduler``, or of a new LocalCluster
    of ``workers`` single-threaded worker processes (default: one per core)."""
    import dask
    from distributed import Client, LocalCluster

    quiet = logging.getLogger("distributed")
    level = quiet.level
    quiet.setLevel(logging.CRITICAL)  # a killed worker is retried and reported, not logged at us
    try:
        if given is not None:
            yield given
            return
        with dask.config.set({"distributed.scheduler.allowed-failures": ALLOWED_FAILURES}):
            if scheduler:
                try:
                    client = Client(scheduler, timeout="10s")
                except (OSError, TimeoutError, ValueError) as e:
                    raise InputError(f"--scheduler {scheduler}: no Dask scheduler answers there ({e})") from None
                with client:
                    yield client
                return
            n = workers or os.cpu_count() or 1
            with LocalCluster(n_workers=n, threads_per_worker=1, processes=True, dashboard_address="127.0.0.1:0",
                              silence_logs=logging.CRITICAL) as cluster, Client(cluster) as client:
                yield client
    finally:
        quiet.setLevel(level)
