"""Fixtures the database tests share, and how the suite splits over pytest-xdist workers."""

from __future__ import annotations

import os
from typing import Iterator

import pytest

from kb import world

PG_URL = os.environ.get("KITKB_PG_URL")


@pytest.hookimpl(tryfirst=True)  # before xdist's own hook reads the groups
def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """Under ``-n N --dist loadgroup`` (./test.sh) the tests that use the one PostgreSQL
    database of ``KITKB_PG_URL`` (each wipes it) run on one worker, one after another."""
    for item in items:
        if item.get_closest_marker("postgres"):
            item.add_marker(pytest.mark.xdist_group("postgres"))


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
