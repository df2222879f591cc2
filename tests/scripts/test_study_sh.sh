#!/usr/bin/env bash
# Tests of scripts/study.sh on examples/small.json cut to 1 % axial strain (a
# few seconds): a campaign run with its tests two at a time (--tests-at-once 2,
# one thread each) gives the summary of the same campaign run by `wiredem run`
# on two threads, every value but the timings; a campaign whose summary exists
# is not run again; bad options are refused with the option's name.
#
#   bash tests/scripts/test_study_sh.sh WIREDEM_BINARY
set -euo pipefail
wiredem=$(realpath "$1")
cd "$(dirname "$0")/../.."
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

/usr/bin/python3 - examples/small.json "$work/base.json" <<'PY'
import json, sys
job = json.load(open(sys.argv[1]))
job["triaxial"]["target_axial_strain"] = 0.01
job["triaxial"]["snapshot_strains"] = []
json.dump(job, open(sys.argv[2], "w"))
PY
study() { bash scripts/study.sh --base "$work/base.json" --wiredem "$wiredem" --patterns helix --seeds 4 "$@"; }

study --runs "$work/staged" --summaries "$work/s1" --threads 2 --tests-at-once 2 > "$work/staged.out"
study --runs "$work/plain" --summaries "$work/s2" --threads 2 > "$work/plain.out"
for k in 0 1; do
    grep -q "done in" "$work/staged/helix-seed4/test-$k.log" || fail "test $k of the staged campaign left no log of its end"
done
/usr/bin/python3 - "$work/s1/helix-seed4.json" "$work/s2/helix-seed4.json" <<'PY'
import json, sys
timing = ("wall_time_s", "body_steps_per_second", "elapsed_s", "threads")
def strip(d):
    if isinstance(d, dict):
        return {k: strip(v) for k, v in d.items() if not any(t in k for t in timing)}
    if isinstance(d, list):
        return [strip(x) for x in d]
    return d
a, b = (strip(json.load(open(f))) for f in sys.argv[1:])
assert a["tests"] and len(a["tests"]) == 2, "the staged campaign's summary has not its two tests"
assert a == b, "the staged campaign's summary differs from wiredem run's"
PY

# Done already: not run again (its folder is not touched).
before=$(stat -c %Y "$work/staged/helix-seed4/summary.json")
out=$(study --runs "$work/staged" --summaries "$work/s1" --tests-at-once 2)
grep -q "helix-seed4 done already" <<< "$out" || fail "a finished campaign was not recognised: $out"
[[ $(stat -c %Y "$work/staged/helix-seed4/summary.json") == "$before" ]] || fail "a finished campaign was run again"

# Bad options name themselves.
for bad in 0 -1 two; do
    if out=$(study --runs "$work/bad" --tests-at-once "$bad" 2>&1); then fail "--tests-at-once $bad was accepted"; fi
    grep -q -- "--tests-at-once must be a positive integer" <<< "$out" || fail "--tests-at-once $bad: unclear error: $out"
done
echo "study.sh: all cases pass"
