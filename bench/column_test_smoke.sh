#!/usr/bin/env bash
# CI's smoke run of the benchmark case users' work is made of: a column test
# with wire, membrane and moving plate (wiredem-bench --column-test), on a
# small wired column (examples/tiny.json with a helix) prepared by the real
# `wiredem prepare`. Checks that the case runs through the triaxial driver
# into its loading, on one and two threads, to the same state hash, and
# reports its body-steps per second and per-stage times (JSON lines).
# The paper's column: `wiredem prepare examples/paper-helix.json -o DIR`,
# then `wiredem-bench --column-test DIR --test-index 3 --column-phase loading`
# (bench/README.md).
#
# usage: bench/column_test_smoke.sh WIREDEM WIREDEM_BENCH SOURCE_DIR
set -euo pipefail
wiredem=$1 bench=$2 source=$3
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
python3 - "$source/examples/tiny.json" "$scratch/job.json" <<'PY'
import json, sys
job = json.load(open(sys.argv[1]))
job["specimen"]["wire"] = {"pattern": "helix", "helix_radius_m": 4e-3}
json.dump(job, open(sys.argv[2], "w"))
PY
"$wiredem" prepare "$scratch/job.json" -o "$scratch/dir" > "$scratch/prepare.log" 2>&1 || { cat "$scratch/prepare.log"; exit 1; }
"$bench" --column-test "$scratch/dir" --column-phase loading --steps 200 --threads 1,2 --json > "$scratch/cases.jsonl"
cat "$scratch/cases.jsonl"
python3 - "$scratch/cases.jsonl" <<'PY'
import json, sys
cases = [json.loads(line) for line in open(sys.argv[1])]
assert [c["threads"] for c in cases] == [1, 2], cases
assert all(c["case"] == "column_loading" and c["steps"] == 200 for c in cases), cases
assert len({c["state_hash"] for c in cases}) == 1, "the thread counts' states differ"
for c in cases:
    assert c["body_steps_per_second"] > 0 and c["contacts"] > 0, c
    assert c["stage_s"]["membrane"] > 0 and c["stage_s"]["wire"] > 0, "membrane and wire must be in the timed steps"
print("column test: %d bodies, %.3g body-steps/s on 1 thread, %.3g on 2; same state hash"
      % (cases[0]["bodies"], cases[0]["body_steps_per_second"], cases[1]["body_steps_per_second"]))
PY
