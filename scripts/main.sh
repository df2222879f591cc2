#!/usr/bin/env bash
# The main job: installs what is missing, builds, starts wiredem-server on
# loopback, submits examples/main.json (a small triaxial campaign at three
# confining pressures) with the wiredem client, follows its progress, prints
# the results table (Mohr–Coulomb φ and c), downloads summary.json and
# result.h5 into results/main/, and stops the server.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh release

bin=build/release/bin
data=$(mktemp -d /tmp/wiredem-main.XXXXXX)
"$bin/wiredem-server" --listen 127.0.0.1:0 --port-file "$data/port" --data-dir "$data/store" \
  > "$data/server.log" 2>&1 &
server=$!
trap 'kill -TERM $server 2>/dev/null; wait $server 2>/dev/null || true' EXIT
for _ in $(seq 100); do [ -s "$data/port" ] && break; sleep 0.1; done
[ -s "$data/port" ] || { echo "main: the server did not start (see $data/server.log)" >&2; exit 1; }
export WIREDEM_SERVER="http://127.0.0.1:$(cat "$data/port")"
echo "wiredem-server listening on $WIREDEM_SERVER (data in $data)"

id=$("$bin/wiredem" submit examples/main.json)
echo "submitted job $id"
"$bin/wiredem" wait "$id"
"$bin/wiredem" summary "$id"
"$bin/wiredem" fetch "$id" -o results/main
echo "results: results/main/summary.json, results/main/result.h5"
