#!/usr/bin/env bash
# Set up (idempotent), start a throwaway PostgreSQL on loopback, run the whole test suite.
set -euo pipefail
cd "$(dirname "$0")"
bash scripts/setup.sh --postgres
source scripts/postgres.sh
pg_start
trap pg_stop EXIT
.venv/bin/python -m pytest -m "slow or not slow" "$@"
