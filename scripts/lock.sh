#!/usr/bin/env bash
# Write constraints.txt: the exact versions of every Python package scripts/setup.sh installs.
# Run after changing dependencies in pyproject.toml (in a venv made by setup.sh), then run
# ./test.sh: the differential tests of kb/patches compare kitkb's changes to library
# internals with the stock code on exactly these versions.
set -euo pipefail
cd "$(dirname "$0")/.."
{
    echo "# Exact versions of the Python packages scripts/setup.sh installs (pip -c constraints.txt)."
    echo "# Regenerate with scripts/lock.sh; the ranges kitkb accepts are in pyproject.toml."
    .venv/bin/python -m pip freeze --exclude-editable --all | grep -v -E '^(pip|setuptools|wheel)=='
} > constraints.txt
echo "wrote constraints.txt ($(grep -vc '^#' constraints.txt) packages)"
