"""Fixtures the database tests share, and a PostgreSQL database per pytest-xdist worker."""

from __future__ import annotations

import os
from typing import Iterator

import pytest

from kb import world



def _worker_database() -> None:
    """Under pytest-xdist (``./test.sh -n 2``) each worker gets a PostgreSQL database of its own
    on the server of ``KITKB_PG_URL`` (``<database>_gw0`` ...: tests wipe and lock theirs), set in
    ``KITKB_PG_URL`` before any test module reads it, so subprocesses inherit it too."""
    worker, url = os.environ.get("PYTEST_XDIST_WORKER"), os.environ.get("KITKB_PG_URL")
    if not worker or not url:
        return
    import psycopg2
    from sqlalchemy.engine import make_url

    u = make_url(url)
    name = f"{u.database}_{worker}"
    conn = psycopg2.connect(host=u.host, port=u.port, user=u.username, password=u.password, dbname=u.database)
    conn.autocommit = True
    try:
        with conn.cursor() as cur:
            cur.execute("SELECT 1 FROM pg_database WHERE datname = %s", (name,))
            if cur.fetchone() is None:
                cur.execute(f'CREATE DATABASE "{name}"')
    finally:
        conn.close()
    os.environ["KITKB_PG_URL"] = u.set(database=name).render_as_string(hide_password=False)


_worker_database()
PG_URL = os.environ.get("KITKB_PG_URL")


@pytest.fixture(params=["sqlite", pytest.param("postgresql", marks=pytest.mark.postgres)])
def url(request, tmp_path):
    """A world-model database URL: a new SQLite file, and the test PostgreSQL server (wiped
    before and after) when ``KITKB_PG_URL`` is set."""
    if request.param == "sqlite":
        yield world.normalize_url(tmp_path / "world.sqlite")
        return
    if not PG_URL:
        pytest.skip("KITKB_PG_URL is not set")
    world.drop_all(PG_URL)
    yield PG_URL
    world.drop_all(PG_URL)


@pytest.fixture(scope="module")
def own_directory(tmp_path_factory: pytest.TempPathFactory) -> Iterator[None]:
    """Fast Downward's driver writes output.sas in the working directory: a module's tests
    plan in one of their own (``pytestmark = pytest.mark.usefixtures("own_directory")``)."""
    with pytest.MonkeyPatch.context() as mp:
        mp.chdir(tmp_path_factory.mktemp("cwd"))
        yield


@pytest.fixture
def fork_ready(monkeypatch: pytest.MonkeyPatch) -> None:
    """Threads that earlier tests of this worker left running (Dask's offload and IO-loop
    threads after a campaign, which live as long as the process) are not counted by
    ``kb.core.jobs.fork_is_safe`` during the test, so a test that asserts kitkb forks does not
    depend on which tests its pytest-xdist worker happened to run before it. Threads the test
    itself starts still count (``kitkb`` never runs beside such leftovers: each command is a
    process of its own)."""
    import threading

    from kb.core import jobs

    leftovers = [t for t in threading.enumerate() if t is not threading.main_thread()]
    counted = jobs.pausable_threads
    monkeypatch.setattr(jobs, "pausable_threads", lambda: counted() + sum(t.is_alive() for t in leftovers))
