"""The runnable examples of the docs run and give what the docs say."""

from __future__ import annotations

import doctest
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parent.parent


@pytest.mark.parametrize("doc", ["docs/execution.md"])
def test_doc_examples_run(doc: str, monkeypatch) -> None:
    monkeypatch.chdir(REPO)  # the examples name files relative to the checkout
    result = doctest.testfile(str(REPO / doc), module_relative=False, optionflags=doctest.ELLIPSIS, verbose=False)
    assert result.attempted >= 8 and result.failed == 0
