#!/usr/bin/env bash
# Set up (idempotent), check the import contracts, start a throwaway PostgreSQL on loopback,
# run the whole test suite. Arguments go to pytest (e.g. ./test.sh -m "not slow and not postgres").
set -euo pipefail
cd "$(dirname "$0")"
bash scripts/setup.sh --postgres
.venv/bin/lint-imports --no-cache --no-logo  # the architecture contracts of pyproject.toml
source scripts/postgres.sh
pg_start
trap pg_stop EXIT
# two workers (one per core of the CI machines), each with a PostgreSQL database of its own (tests/conftest.py)
.venv/bin/python -m pytest -m "slow or not slow" -n "${KITKB_TEST_WORKERS:-2}" "$@"
