"""``python -m kb.cli``: the kitkb command."""

from kb.cli import run

run()
