#!/usr/bin/env bash
# A throwaway PostgreSQL for tests: Debian's postgresql 15 binaries run a cluster in a folder of the
# caller's, listening on 127.0.0.1 only (no Unix socket), on a free port, with a random password.
#
#   postgres.sh start FOLDER [--watch PID]   creates FOLDER/data, starts the server, and prints
#                                            one line: a postgresql:// connection string for the
#                                            database "postgres" (its superuser is "caustic").
#                                            With --watch, the cluster is stopped and FOLDER removed
#                                            once process PID is gone (a test binary killed before
#                                            it could say stop).
#   postgres.sh restart FOLDER [immediate]   restarts it on the same port (immediate: as a crash);
#                                            starts it again after down.
#   postgres.sh down FOLDER                  stops it (fast), keeping FOLDER: an outage.
#   postgres.sh stop FOLDER                  stops it (if it runs) and removes FOLDER.
#
# Run as root (CI), the server runs as an unprivileged user, $CAUSTIC_PG_USER or Debian's
# "postgres" (PostgreSQL refuses to run as root), and FOLDER is given to that user (its parent
# folders must let that user through, as /tmp does). Every step is
# bounded in time. The cluster trades durability for speed (fsync off): it only outlives crashes of
# its own processes, which is all a test does to it.
set -euo pipefail

bin=${CAUSTIC_PG_BIN:-/usr/lib/postgresql/15/bin}
timeout_s=60

die() {
    echo "postgres.sh: $*" >&2
    exit 1
}

[ $# -ge 2 ] || die "usage: postgres.sh start|restart|down|stop FOLDER [...]"
command=$1
folder=$2
shift 2

# Runs a command as the cluster's owner.
as_owner=()
if [ "$(id -u)" -eq 0 ]; then
    user=${CAUSTIC_PG_USER:-postgres}
    id "$user" >/dev/null 2>&1 || die "no user $user to run PostgreSQL as (set CAUSTIC_PG_USER)"
    as_owner=(setpriv --reuid="$user" --regid="$(id -g "$user")" --clear-groups --)
fi
run() { timeout "$timeout_s" "${as_owner[@]}" env -u PGDATA -u PGPORT "$@"; }

start() {
    [ -x "$bin/initdb" ] && [ -x "$bin/pg_ctl" ] || die "no PostgreSQL binaries in $bin"
    mkdir -p "$folder"
    folder=$(cd "$folder" && pwd)
    [ ${#as_owner[@]} -eq 0 ] || chown "$user:" "$folder"
    run test -w "$folder" || die "$folder is out of reach of user ${user:-$(id -un)} (its parents too)"
    chmod 700 "$folder"
    local password
    password=$(head -c 18 /dev/urandom | od -An -tx1 | tr -d ' \n')
    (umask 077 && printf '%s\n' "$password" >"$folder/password")
    [ ${#as_owner[@]} -eq 0 ] || chown "$user:" "$folder/password"
    run "$bin/initdb" -D "$folder/data" -U caustic --auth=scram-sha-256 \
        --pwfile="$folder/password" -E UTF8 --locale=C.UTF-8 >"$folder/initdb.log" 2>&1 ||
        die "initdb failed: $(tail -5 "$folder/initdb.log")"
    # fsync off: only a crash of the machine could lose what is committed. synchronous_commit
    # stays on: an immediate restart (as a crash) loses asynchronous commits already acknowledged.
    cat >>"$folder/data/postgresql.conf" <<EOF
listen_addresses = '127.0.0.1'
unix_socket_directories = ''
fsync = off
full_page_writes = off
max_connections = 300
EOF
    # A port the kernel says is free; another process may take it before the server binds, so
    # try a few.
    local port
    for _ in 1 2 3 4 5; do
        port=$(python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
        echo "$port" >"$folder/port"
        if run "$bin/pg_ctl" -D "$folder/data" -l "$folder/server.log" -o "-p $port" -w \
            -t "$timeout_s" start >/dev/null 2>&1; then
            if [ -n "$watch" ]; then
                # Detached from the caller's stdout, so that a reader of this script's output
                # sees its end.
                setsid bash "$0" watch "$folder" "$watch" </dev/null >/dev/null 2>&1 &
            fi
            echo "postgresql://caustic:$password@127.0.0.1:$port/postgres"
            return 0
        fi
    done
    die "the server did not start: $(tail -5 "$folder/server.log" 2>/dev/null)"
}

stop() {
    if [ -f "$folder/data/postmaster.pid" ]; then
        run "$bin/pg_ctl" -D "$folder/data" -m fast -w -t "$timeout_s" stop >/dev/null 2>&1 ||
            run "$bin/pg_ctl" -D "$folder/data" -m immediate -w -t "$timeout_s" stop \
                >/dev/null 2>&1 || true
    fi
    rm -rf "$folder"
}

case $command in
    start)
        watch=
        if [ "${1:-}" = --watch ]; then watch=${2:?--watch needs a process id}; fi
        start
        ;;
    restart)
        mode=${1:-fast}
        run "$bin/pg_ctl" -D "$folder/data" -l "$folder/server.log" -o "-p $(cat "$folder/port")" \
            -m "$mode" -w -t "$timeout_s" restart >/dev/null
        ;;
    down)
        run "$bin/pg_ctl" -D "$folder/data" -m fast -w -t "$timeout_s" stop >/dev/null
        ;;
    stop)
        stop
        ;;
    watch)
        pid=$1
        while kill -0 "$pid" 2>/dev/null && [ -d "$folder" ]; do sleep 1; done
        [ -d "$folder" ] && stop
        ;;
    *)
        die "unknown command $command (start, restart, down, stop)"
        ;;
esac
