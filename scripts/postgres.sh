# Sourced by test.sh: a throwaway PostgreSQL cluster on 127.0.0.1 for the server tests.
# Exports KITKB_PG_URL; pg_stop removes the cluster.
PG_PORT=${PG_PORT:-54329}
PG_DIR=${PG_DIR:-/tmp/kitkb-pg-$$}

pg_start() {
    local bin
    bin=$(ls -d /usr/lib/postgresql/*/bin 2>/dev/null | sort -V | tail -n 1)
    if [ -z "$bin" ]; then
        echo "test: PostgreSQL is not installed; PostgreSQL tests will be skipped" >&2
        return 0
    fi
    local run=""
    if [ "$(id -u)" = 0 ]; then
        run="runuser -u postgres --"
        mkdir -p "$PG_DIR" && chown postgres "$PG_DIR"
    else
        mkdir -p "$PG_DIR"
    fi
    $run "$bin/initdb" -D "$PG_DIR/data" -U kitkb --auth=trust >/dev/null
    $run "$bin/pg_ctl" -D "$PG_DIR/data" -l "$PG_DIR/log" -w \
        -o "-c listen_addresses=127.0.0.1 -p $PG_PORT -k $PG_DIR" start >/dev/null
    $run "$bin/createdb" -h 127.0.0.1 -p "$PG_PORT" -U kitkb kitkb
    export KITKB_PG_URL="postgresql+psycopg2://kitkb@127.0.0.1:$PG_PORT/kitkb"
    PG_BIN=$bin PG_RUN=$run
}

pg_stop() {
    if [ -n "${PG_BIN:-}" ]; then
        $PG_RUN "$PG_BIN/pg_ctl" -D "$PG_DIR/data" -m fast stop >/dev/null 2>&1 || true
        rm -rf "$PG_DIR"
    fi
}
