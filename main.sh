#!/usr/bin/env bash
# Set up (idempotent) and run the main job on the shipped scenarios: validate, plan, check the
# geometry, load the world model, and execute every plan in the simulated cell with two faults
# injected (a missed grasp, then a missing part), which are diagnosed and recovered.
set -euo pipefail
cd "$(dirname "$0")"
bash scripts/setup.sh
if [ $# -eq 0 ]; then
    set -- --faults "missed-grasp@6,part-missing@9" --seed 1 --report out/report.json
fi
exec .venv/bin/kitkb run "$@"
