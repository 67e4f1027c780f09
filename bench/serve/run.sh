#!/usr/bin/env bash
# Usage: bench/serve/run.sh [BUILD_DIR]
#
# The benchmark of issue 34, all on this machine, the same sites (datasets/weather_stations.csv)
# and the same query points for every service:
#   - geovor serve: GET /nearest under wrk (keep-alive);
#   - PostGIS 15, a geography(Point) column with a GiST index, the lookup
#     SELECT id FROM stations ORDER BY geog <-> point LIMIT 1 through pgbench;
#   - a FastAPI + uvicorn + scipy cKDTree service (fastapi_service.py) under wrk;
#   - a correctness check: the three services' nearest stations against each other and brute force;
#   - batch: POST /nearest of 10^6 points (CSV) against geovor nearest on the same file.
# Prints a markdown table at the end. BUILD_DIR (default: build/ of this repository) holds
# tools/geovor (scripts/build.sh release geovor_cli; the target geovor is the library). Binds
# 127.0.0.1 only (PostGIS: a unix socket), needs no internet, writes only under a mktemp -d
# directory and stops everything it starts.
#
# Settings (environment): THREADS (geovor serve's --threads and geovor nearest's, default: nproc),
# CONNECTIONS (wrk -c, default 64), WRK_THREADS (wrk -t and pgbench -j, default 2), DURATION
# (seconds per measurement, default 10), WARMUP (seconds before each, default 2), POINTS (query
# points, default 10000), CHECK_POINTS (default 1000), BATCH_POINTS (default 1000000), PG_CLIENTS
# (pgbench -c, default CONNECTIONS), PG_EXTRA_CLIENTS (more pgbench -c values at the listed points,
# extra rows, default 8: PostgreSQL's best on 2 cores), FASTAPI_WORKERS (uvicorn --workers, default:
# nproc), GEOVOR_EXTRA_THREADS (more geovor serve --threads values, extra rows; default none),
# KEEP_TMP=1 (keep the temporary directory), PIN=1 (servers on CPU 0, clients on CPU 1; see above).
# The targets are checked against the best PostGIS figure at the listed points, for each geovor row.
#
# Packages (Debian): wrk postgresql-15-postgis-3 python3-fastapi python3-uvicorn python3-scipy curl;
# python3-uvloop and python3-httptools make uvicorn faster when installed (it picks them itself).
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
repo=$(cd "$here/../.." && pwd)
if (($# > 1)) || [[ ${1:-} == -h || ${1:-} == --help ]]; then
  sed -n '2p' "${BASH_SOURCE[0]}" | sed 's/^# //' >&2
  exit 2
fi
build=${1:-$repo/build}
geovor=$(cd "$build" && pwd)/tools/geovor
sites=$repo/datasets/weather_stations.csv
py=/usr/bin/python3  # Debian's Python, with Debian's scipy, fastapi and uvicorn
pgbin=/usr/lib/postgresql/15/bin

ncpu=$(nproc)
# PIN=1: every server (geovor, uvicorn, PostgreSQL) on CPU 0 and every client (wrk, pgbench, curl)
# on CPU 1, so that a server's latency is not the client's turn on a shared core; one thread or
# worker per server by default then.
PIN=${PIN:-0}
on_server=() on_client=()
if [[ $PIN == 1 ]]; then
  ((ncpu >= 2)) || { echo "run.sh: PIN=1 needs two CPUs" >&2; exit 2; }
  on_server=(taskset -c 0) on_client=(taskset -c 1) ncpu=1
fi
THREADS=${THREADS:-$ncpu}
CONNECTIONS=${CONNECTIONS:-64}
WRK_THREADS=${WRK_THREADS:-2}
DURATION=${DURATION:-10}
WARMUP=${WARMUP:-2}
POINTS=${POINTS:-10000}
CHECK_POINTS=${CHECK_POINTS:-1000}
BATCH_POINTS=${BATCH_POINTS:-1000000}
PG_CLIENTS=${PG_CLIENTS:-$CONNECTIONS}
FASTAPI_WORKERS=${FASTAPI_WORKERS:-$ncpu}
PG_EXTRA_CLIENTS=${PG_EXTRA_CLIENTS-8}
GEOVOR_EXTRA_THREADS=${GEOVOR_EXTRA_THREADS-}
[[ $GEOVOR_EXTRA_THREADS == "$THREADS" ]] && GEOVOR_EXTRA_THREADS=
SEED=34

die() {
  echo "run.sh: $*" >&2
  exit 1
}

# --- prerequisites -------------------------------------------------------------------------------
[[ -x $geovor ]] || die "$geovor: not built (scripts/build.sh release geovor_cli)"
missing=()
for c in wrk curl psql pgbench; do command -v "$c" >/dev/null || missing+=("$c"); done
[[ -x $pgbin/initdb && -x $pgbin/pg_ctl ]] || missing+=("$pgbin/initdb")
[[ -f /usr/share/postgresql/15/extension/postgis.control ]] || missing+=(postgis)
"$py" -c 'import numpy, scipy, fastapi, uvicorn' 2>/dev/null || missing+=("python modules")
if ((${#missing[@]})); then
  die "missing: ${missing[*]}; install with: apt-get install wrk curl postgresql-15-postgis-3 python3-fastapi python3-uvicorn python3-scipy"
fi

# --- cleanup: every process started here, the cluster, the temporary directory ------------------
tmp=$(mktemp -d)
pids=()
pg_data=
as_pg=()
cleanup() {
  set +e
  local pid i
  for pid in "${pids[@]}"; do kill -TERM "$pid" 2>/dev/null; done
  for pid in "${pids[@]}"; do
    for ((i = 0; i < 100; i++)); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
    kill -KILL "$pid" 2>/dev/null
    wait "$pid" 2>/dev/null
  done
  if [[ -n $pg_data && -f $pg_data/postmaster.pid ]]; then
    "${as_pg[@]}" "$pgbin/pg_ctl" -D "$pg_data" -m immediate -w stop >/dev/null 2>&1
  fi
  if [[ ${KEEP_TMP:-0} == 1 ]]; then
    echo "run.sh: logs kept in $tmp" >&2
  else
    rm -rf "$tmp"
  fi
}
trap cleanup EXIT
trap 'exit 130' INT TERM

results=$tmp/results.tsv  # kind, service, requests/s, p99 ms, note
: >"$results"

wait_http() {  # URL PID: until URL answers 200, or the process is gone
  local i
  for ((i = 0; i < 600; i++)); do
    curl -fsS -o /dev/null "$1" 2>/dev/null && return 0
    kill -0 "$2" 2>/dev/null || return 1
    sleep 0.1
  done
  return 1
}

free_port() {
  "$py" -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'
}

# wrk KIND NAME URL: a warm-up, then the measurement; appends to results. --timeout 10s: a slow
# answer counts in the latencies (wrk's default, 2 s, drops it from them as a "timeout").
run_wrk() {
  local kind=$1 name=$2 url=$3 out=$tmp/wrk-${2//[^A-Za-z0-9]/_}.txt
  sync  # the writes before (data, logs, a previous run's cleanup) not flushed during the measurement
  timeout $((WARMUP + 30)) "${on_client[@]}" wrk -t"$WRK_THREADS" -c"$CONNECTIONS" -d"${WARMUP}s" -s "$here/nearest.lua" \
    "$url" -- "$tmp/points.csv" "$SEED" >/dev/null
  timeout $((DURATION + 60)) "${on_client[@]}" wrk -t"$WRK_THREADS" -c"$CONNECTIONS" -d"${DURATION}s" --latency --timeout 10s \
    -s "$here/nearest.lua" "$url" -- "$tmp/points.csv" "$SEED" >"$out"
  sed 's/^/    /' "$out"
  "$py" - "$kind" "$name" "$out" >>"$results" <<'EOF'
import re, sys
kind, name, path = sys.argv[1:4]
text = open(path).read()
rps = float(re.search(r"Requests/sec:\s*([0-9.]+)", text).group(1))
m = re.search(r"^\s*99%\s+([0-9.]+)(us|ms|s|m)\s*$", text, re.M)
scale = {"us": 1e-3, "ms": 1.0, "s": 1e3, "m": 6e4}[m.group(2)]
notes = []
bad = re.search(r"Non-2xx or 3xx responses:\s*(\d+)", text)
if bad:
    notes.append(f"{bad.group(1)} non-2xx answers")
err = re.search(r"Socket errors: (.*)", text)
if err:
    notes.append("socket errors: " + err.group(1).strip())
print(f"{kind}\t{name}\t{rps:.0f}\t{float(m.group(1)) * scale:.2f}\t{'; '.join(notes)}")
EOF
}

echo "bench/serve: $(date -u '+%Y-%m-%d %H:%M UTC'), $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg)"
echo "geovor: $geovor; sites: $sites ($(($(wc -l <"$sites") - 1)) rows)"
echo "wrk -t$WRK_THREADS -c$CONNECTIONS -d${DURATION}s (keep-alive); pgbench -c$PG_CLIENTS -j$WRK_THREADS -T$DURATION -M prepared; geovor serve --threads $THREADS; uvicorn --workers $FASTAPI_WORKERS"

# --- query points: the same for every service ---------------------------------------------------
"$py" "$here/make_points.py" "$POINTS" "$SEED" "$tmp/points.csv"
echo "query points: $POINTS uniform on the sphere (seed $SEED)"

# --- geovor serve -------------------------------------------------------------------------------
start_geovor() {  # THREADS: starts geovor serve, sets geovor_pid and geovor_url
  local out=$tmp/geovor-$1.out
  : >"$out"
  "${on_server[@]}" "$geovor" serve "$sites" --port 0 --threads "$1" >"$out" 2>"$tmp/geovor-$1.err" &
  geovor_pid=$!
  pids+=("$geovor_pid")
  local i port=
  for ((i = 0; i < 600; i++)); do
    port=$(sed -n 's|^geovor serve: http://127\.0\.0\.1:\([0-9][0-9]*\)/.*|\1|p' "$out")
    [[ -n $port ]] && break
    kill -0 "$geovor_pid" 2>/dev/null || die "geovor serve exited: $(cat "$tmp/geovor-$1.err")"
    sleep 0.1
  done
  [[ -n $port ]] || die "geovor serve printed no address"
  geovor_url=http://127.0.0.1:$port
  wait_http "$geovor_url/healthz" "$geovor_pid" || die "geovor serve does not answer /healthz"
}
stop_pid() {
  kill -TERM "$1" 2>/dev/null || true
  wait "$1" 2>/dev/null || true
}

start_geovor "$THREADS"
echo
echo "== geovor serve --threads $THREADS: $geovor_url"
run_wrk geovor "geovor serve --threads $THREADS" "$geovor_url"

# --- FastAPI + uvicorn + cKDTree ----------------------------------------------------------------
fastapi_port=$(free_port)
fastapi_url=http://127.0.0.1:$fastapi_port
loop=$("$py" -c 'import importlib.util as u; print("uvloop" if u.find_spec("uvloop") else "asyncio", "+", "httptools" if u.find_spec("httptools") else "h11")')
(cd "$here" && GEOVOR_BENCH_SITES=$sites exec "${on_server[@]}" "$py" -m uvicorn fastapi_service:app --host 127.0.0.1 \
  --port "$fastapi_port" --workers "$FASTAPI_WORKERS" --log-level warning --no-access-log \
  >"$tmp/fastapi.out" 2>&1) &
fastapi_pid=$!
pids+=("$fastapi_pid")
wait_http "$fastapi_url/healthz" "$fastapi_pid" || die "the FastAPI service did not start: $(tail -5 "$tmp/fastapi.out")"
echo
echo "== FastAPI + uvicorn ($loop, $FASTAPI_WORKERS workers) + cKDTree: $fastapi_url"
run_wrk fastapi "FastAPI + uvicorn + cKDTree ($FASTAPI_WORKERS workers)" "$fastapi_url"

# --- PostGIS ------------------------------------------------------------------------------------
pg_root=$tmp/pg
pg_max=$PG_CLIENTS
for c in $PG_EXTRA_CLIENTS; do ((c > pg_max)) && pg_max=$c; done
mkdir -p "$pg_root/sock"
if ((EUID == 0)); then  # initdb refuses root: the cluster belongs to postgres
  id postgres >/dev/null 2>&1 || die "running as root and there is no user postgres for the cluster"
  chmod 711 "$tmp"
  chown -R postgres: "$pg_root"
  as_pg=(runuser -u postgres --)
fi
"${as_pg[@]}" "$pgbin/initdb" -D "$pg_root/data" -U bench -A trust -E UTF8 --no-locale >"$tmp/initdb.log" 2>&1 ||
  die "initdb failed: $(tail -5 "$tmp/initdb.log")"
pg_data=$pg_root/data
"${on_server[@]}" "${as_pg[@]}" "$pgbin/pg_ctl" -D "$pg_data" -l "$pg_root/server.log" -w -o \
  "-c listen_addresses='' -c unix_socket_directories='$pg_root/sock' -c port=5432 -c max_connections=$((pg_max + 20)) -c fsync=off -c synchronous_commit=off -c jit=off" \
  start >/dev/null || die "the PostgreSQL cluster did not start: $(tail -5 "$pg_root/server.log")"
pg=(-h "$pg_root/sock" -p 5432 -U bench)
psql_do() { psql "${pg[@]}" -d postgres -X -q -v ON_ERROR_STOP=1 "$@"; }
psql_do -c 'CREATE EXTENSION postgis' \
  -c 'CREATE TABLE stations_raw (icao text, name text, lat_deg float8, lon_deg float8)' \
  -c 'CREATE TABLE qpts (i serial PRIMARY KEY, lat float8, lon float8)'
psql_do -c '\copy stations_raw FROM STDIN WITH (FORMAT csv, HEADER true)' <"$sites"
psql_do -c '\copy qpts (lat, lon) FROM STDIN WITH (FORMAT csv, HEADER true)' <"$tmp/points.csv"
psql_do <<'EOF'
CREATE TABLE stations AS
  SELECT icao AS id, name, ST_MakePoint(lon_deg, lat_deg)::geography(Point, 4326) AS geog FROM stations_raw;
CREATE INDEX stations_geog ON stations USING gist (geog);
ALTER TABLE qpts ADD COLUMN g geography(Point, 4326);
UPDATE qpts SET g = ST_MakePoint(lon, lat)::geography;
VACUUM ANALYZE stations;
VACUUM ANALYZE qpts;
EOF
echo
echo "== PostGIS $(psql_do -At -c 'SELECT postgis_lib_version()') on PostgreSQL $(psql_do -At -c 'SHOW server_version'): $(psql_do -At -c 'SELECT count(*) FROM stations') stations, GiST on geography"
cat >"$tmp/pg_list.sql" <<EOF
\\set i random(1, $POINTS)
SELECT id FROM stations ORDER BY geog <-> (SELECT g FROM qpts WHERE i = :i) LIMIT 1;
EOF
cat >"$tmp/pg_fixed.sql" <<'EOF'
SELECT id FROM stations ORDER BY geog <-> ST_MakePoint(2.35, 48.85)::geography LIMIT 1;
EOF
cat >"$tmp/pg_formula.sql" <<'EOF'
\set z random(-1000000000, 1000000000) / 1000000000.0
\set lon random(-1800000000, 1800000000) / 10000000.0
SELECT id FROM stations ORDER BY geog <-> ST_MakePoint(:lon, asind(:z))::geography LIMIT 1;
EOF
echo "plan of the lookup at the listed points (the index's KNN order):"
psql_do -At -c 'EXPLAIN SELECT id FROM stations ORDER BY geog <-> (SELECT g FROM qpts WHERE i = 1) LIMIT 1' | sed 's/^/    /'

# pgbench KIND NAME SCRIPT CLIENTS: a warm-up, then the measurement with a per-transaction log
# for the p99.
run_pgbench() {
  local kind=$1 name=$2 script=$3 clients=$4 tag=${3##*/}
  tag=${tag%.sql}-c$clients
  sync
  timeout $((WARMUP + 30)) "${on_client[@]}" pgbench "${pg[@]}" -n -M prepared -c "$clients" -j "$WRK_THREADS" -T "$WARMUP" \
    -f "$script" postgres >/dev/null 2>&1
  mkdir -p "$tmp/pglog-$tag"
  timeout $((DURATION + 60)) "${on_client[@]}" pgbench "${pg[@]}" -n -M prepared -c "$clients" -j "$WRK_THREADS" -T "$DURATION" \
    -f "$script" -l --log-prefix="$tmp/pglog-$tag/log" postgres >"$tmp/pgbench-$tag.txt" 2>&1 ||
    die "pgbench failed: $(tail -5 "$tmp/pgbench-$tag.txt")"
  grep -E '^(number of (transactions actually processed|failed)|latency average|tps)' "$tmp/pgbench-$tag.txt" | sed 's/^/    /'
  "$py" - "$kind" "$name" "$tmp/pgbench-$tag.txt" "$tmp/pglog-$tag" >>"$results" <<'EOF'
import glob, re, sys
import numpy as np
kind, name, summary, logs = sys.argv[1:5]
text = open(summary).read()
tps = float(re.search(r"^tps = ([0-9.]+)", text, re.M).group(1))
lat = np.concatenate([np.loadtxt(f, usecols=2, ndmin=1) for f in glob.glob(logs + "/log*")])
print(f"{kind}\t{name}\t{tps:.0f}\t{np.percentile(lat, 99) / 1000:.2f}\tpgbench; p99 from its -l log")
EOF
  echo "    p99: $(tail -1 "$results" | cut -f4) ms"
}
echo "-- $PG_CLIENTS clients, random points of the list (the same as geovor's and FastAPI's):"
run_pgbench postgis "PostGIS, $PG_CLIENTS clients" "$tmp/pg_list.sql" "$PG_CLIENTS"
for c in $PG_EXTRA_CLIENTS; do
  echo "-- $c clients, random points of the list:"
  run_pgbench postgis "PostGIS, $c clients" "$tmp/pg_list.sql" "$c"
done
echo "-- $PG_CLIENTS clients, random points uniform on the sphere drawn by pgbench (no lookup of the point):"
run_pgbench postgis-other "PostGIS, $PG_CLIENTS clients, pgbench's own random points" "$tmp/pg_formula.sql" "$PG_CLIENTS"
echo "-- $PG_CLIENTS clients, one fixed point (48.85, 2.35):"
run_pgbench postgis-other "PostGIS, $PG_CLIENTS clients, one fixed point" "$tmp/pg_fixed.sql" "$PG_CLIENTS"

# --- correctness --------------------------------------------------------------------------------
echo
echo "== correctness: the nearest station of the first $CHECK_POINTS query points"
psql_do -At -F, -c "SELECT q.i, s.id FROM qpts q CROSS JOIN LATERAL
  (SELECT id FROM stations ORDER BY geog <-> q.g LIMIT 1) s WHERE q.i <= $CHECK_POINTS ORDER BY q.i" >"$tmp/postgis_check.csv"
if "$py" "$here/check.py" "$sites" "$tmp/points.csv" "$CHECK_POINTS" "$geovor_url" "$fastapi_url" "$tmp/postgis_check.csv"; then
  correct="every service exact on its own sphere"
else
  correct="SOME ANSWERS WRONG (see above)"
fi

# PostgreSQL and FastAPI are done: stop them before the batch and the extra geovor rows.
"${as_pg[@]}" "$pgbin/pg_ctl" -D "$pg_data" -m fast -w stop >/dev/null 2>&1 || true
stop_pid "$fastapi_pid"

# --- batch: POST /nearest against geovor nearest on the file -----------------------------------
echo
echo "== batch: $BATCH_POINTS points (seed $((SEED + 1)))"
"$py" "$here/make_points.py" "$BATCH_POINTS" $((SEED + 1)) "$tmp/batch.csv"
now() { date +%s.%N; }
best_of() {  # OUTPUT COMMAND...: seconds of the fastest of 3 runs of COMMAND (OUTPUT removed before each)
  local out=$1 best='' t0 t1 i
  shift
  for i in 1 2 3; do
    rm -f "$out"
    t0=$(now)
    "$@" >/dev/null
    t1=$(now)
    best=$("$py" -c "import sys; t = $t1 - $t0; b = sys.argv[1]; print(t if not b else min(t, float(b)))" "$best")
  done
  echo "$best"
}
file_s=$(best_of "$tmp/batch-file.csv" "${on_server[@]}" "$geovor" nearest --sites "$sites" --queries "$tmp/batch.csv" -o "$tmp/batch-file.csv" \
  --threads "$THREADS" -q)
printf '    geovor nearest --threads %s on the file: %.3f s (best of 3)\n' "$THREADS" "$file_s"
batch_ratio=
code=$(curl -sS -o "$tmp/batch-post.csv" -w '%{http_code}' -H 'Content-Type: text/csv' -H 'Expect:' \
  --data-binary @"$tmp/batch.csv" "$geovor_url/nearest" || echo 000)
if [[ $code == 404 || $code == 405 ]]; then
  echo "batch: POST /nearest not available"
elif [[ $code != 200 ]]; then
  echo "batch: POST /nearest answered HTTP $code: $(head -c 300 "$tmp/batch-post.csv")"
else
  post_s=$(best_of "$tmp/batch-post.csv" "${on_client[@]}" curl -sS -f -o "$tmp/batch-post.csv" -H 'Content-Type: text/csv' -H 'Expect:' \
    --data-binary @"$tmp/batch.csv" "$geovor_url/nearest")
  printf '    POST /nearest (curl --data-binary): %.3f s (best of 3)\n' "$post_s"
  if cmp -s "$tmp/batch-file.csv" "$tmp/batch-post.csv"; then
    echo "    outputs identical (cmp)"
  else
    echo "    OUTPUTS DIFFER: $(cmp "$tmp/batch-file.csv" "$tmp/batch-post.csv" 2>&1 | head -1)"
    diff <(head -5 "$tmp/batch-file.csv") <(head -5 "$tmp/batch-post.csv") | sed 's/^/    /' || true
  fi
  batch_ratio=$("$py" -c "print(f'{$post_s / $file_s:.2f}')")
  echo "    POST / file: ${batch_ratio}x (target: within 1.5x)"
fi

# --- extra geovor rows (other --threads) --------------------------------------------------------
stop_pid "$geovor_pid"
for t in $GEOVOR_EXTRA_THREADS; do
  start_geovor "$t"
  echo
  echo "== geovor serve --threads $t: $geovor_url"
  run_wrk geovor "geovor serve --threads $t" "$geovor_url"
  stop_pid "$geovor_pid"
done

# --- the table ----------------------------------------------------------------------------------
echo
pinned="servers and clients sharing the cores"
[[ $PIN == 1 ]] && pinned="servers on CPU 0, clients on CPU 1"
echo "## bench/serve: GET /nearest, $CONNECTIONS connections ($(date -u +%Y-%m-%d), $(nproc) cores, $pinned, load average at the end $(cut -d' ' -f1-3 /proc/loadavg))"
echo
"$py" - "$results" "$correct" "${batch_ratio:-}" <<'EOF'
import sys
rows = [line.rstrip("\n").split("\t") for line in open(sys.argv[1]) if line.strip()]
correct, batch = sys.argv[2], sys.argv[3]
geovor = [r for r in rows if r[0] == "geovor"]
g = float(geovor[0][2])

def ratio(x):
    return f"{x:.2f}x" if x >= 0.1 else f"{x:.2g}x"

print(f"| service | requests/s | p99 ms | {geovor[0][1]} / other | notes |")
print("|---|---:|---:|---:|---|")
for kind, name, rps, p99, note in rows:
    print(f"| {name} | {float(rps):,.0f} | {float(p99):,.2f} | {'' if name == geovor[0][1] else ratio(g / float(rps))} | {note} |")
pg = max(float(r[2]) for r in rows if r[0] == "postgis")
fa = float(next(r for r in rows if r[0] == "fastapi")[2])
met = lambda ok: "met" if ok else "NOT met"
print()
for _, name, rps, p99, _ in geovor:
    rps, p99 = float(rps), float(p99)
    print(f"targets, {name}: >= 5x PostGIS (its best, {pg:,.0f}/s): {ratio(rps / pg)}, {met(rps >= 5 * pg)}; "
          f">= 10x FastAPI: {ratio(rps / fa)}, {met(rps >= 10 * fa)}; p99 < 2 ms: {p99:,.2f} ms, {met(p99 < 2)}")
print(f"batch within 1.5x of geovor nearest on the file: {batch}x, {met(float(batch) <= 1.5)}" if batch
      else "batch: not measured (POST /nearest not available)")
print(f"correctness: {correct}")
EOF
