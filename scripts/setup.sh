#!/usr/bin/env bash
# Idempotent set-up on a fresh clone: Java (HermiT, ENHSP), Chromium (headless, for the report's
# browser tests), xmllint (the CRCL XML tests), a venv with kitkb and its
# dependencies at the versions of constraints.txt. With --postgres also the PostgreSQL server
# package (started by test.sh).
set -euo pipefail
cd "$(dirname "$0")/.."

want_pg=0
[ "${1:-}" = "--postgres" ] && want_pg=1

apt_install() {
    if [ "$(id -u)" = 0 ]; then
        (apt-get update -qq || true) >/dev/null
        DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "$@" >/dev/null
    else
        sudo DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "$@" >/dev/null
    fi
}

if ! command -v java >/dev/null 2>&1; then
    echo "setup: installing a Java runtime (HermiT, ENHSP)"
    apt_install default-jre-headless
fi
if ! command -v chromium >/dev/null 2>&1; then
    echo "setup: installing Chromium (the report's browser tests, headless)"
    apt_install chromium
fi
if ! command -v xmllint >/dev/null 2>&1; then
    echo "setup: installing libxml2-utils (xmllint: the CRCL XML tests check kitkb's documents with it)"
    apt_install libxml2-utils
fi
if [ "$want_pg" = 1 ] && ! ls /usr/lib/postgresql/*/bin/initdb >/dev/null 2>&1; then
    echo "setup: installing PostgreSQL"
    apt_install postgresql
fi

PY=${PYTHON:-python3}
if [ ! -x .venv/bin/python ]; then
    "$PY" -m venv .venv
fi
stamp=.venv/.kitkb-installed
if [ ! -f "$stamp" ] || [ pyproject.toml -nt "$stamp" ] || [ constraints.txt -nt "$stamp" ]; then
    .venv/bin/python -m pip install -q --upgrade pip
    # exact versions from constraints.txt (the ones kitkb's tests and patches were checked on)
    .venv/bin/python -m pip install -q -c constraints.txt -e ".[test,postgres]"
    touch "$stamp"
fi
# byte-compile kitkb's own modules (PYTHONDONTWRITEBYTECODE=1 environments never cache
# them, and every command would compile them again: 0.15 s of each kitkb run)
.venv/bin/python -m compileall -q kb generators >/dev/null || true
