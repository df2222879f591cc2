#!/usr/bin/env bash
# Steps per CPU-second of wiredem binaries continuing one test of a real job
# directory from the same checkpoint: the study's own workload (wire,
# membrane, moving plate), engine against engine, or one test against another.
#
# usage: bench/test_stage_speed.sh [--index K | --free-standing] [--from-start] [--seconds S] [--reps N] [--threads T] [--copies C] JOBDIR BIN...
#   JOBDIR   a job directory with job.json, specimen.h5 and tests/test_K.checkpoint.h5
#            (a test that `wiredem run`/`wiredem test` left running, e.g. build/study/helix-seed1)
#            or, with --free-standing, tests/free_standing.checkpoint.h5
#   BIN...   wiredem binaries (each must read the checkpoint's snapshot version)
#   --from-start  no checkpoint: each run starts the test from the specimen (its
#                 first S seconds: for the free-standing test the formwork's removal
#                 and the settling, for a triaxial test the pressure ramp and hold)
# Each binary runs `wiredem test COPY --index K --threads T --checkpoint-interval 0` (or
# `--free-standing`) in a scratch copy of the folder, alternated N times (default 3); from
# its first progress line (the checkpoint restored, or the test's first steps) it is timed
# for S seconds of wall time (default 120): the steps
# from its progress lines (every 500 steps, so ±500), the CPU time from /proc/PID/stat.
# With --copies C, C such runs at once (each in its own copy), timed together: the
# throughput of a machine whose cores run C tests side by side, as a campaign runs its
# tests (`--copies 2 --threads 1`) against one test on every core (`--copies 1 --threads 2`);
# the line then gives the copies' steps summed, per second of wall time as well.
set -euo pipefail
index=0 seconds=120 reps=3 threads=1 copies=1 free_standing=0 from_start=0
while [[ $# -gt 0 ]]; do
    case "$1" in
        --index) index=$2; shift 2 ;;
        --free-standing) free_standing=1; shift ;;
        --from-start) from_start=1; shift ;;
        --seconds) seconds=$2; shift 2 ;;
        --reps) reps=$2; shift 2 ;;
        --threads) threads=$2; shift 2 ;;
        --copies) copies=$2; shift 2 ;;
        -h|--help) awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "$0"; exit 0 ;;
        -*) echo "unknown option: $1 (try --help)" >&2; exit 2 ;;
        *) break ;;
    esac
done
[[ $# -ge 2 ]] || { echo "usage: $0 [--index K | --free-standing] [--from-start] [--seconds S] [--reps N] [--threads T] [--copies C] JOBDIR BIN... (try --help)" >&2; exit 2; }
dir=$(realpath "$1"); shift
if [[ $free_standing == 1 ]]; then
    which=(--free-standing) name="the free-standing test" checkpoint="$dir/tests/free_standing.checkpoint.h5"
else
    which=(--index "$index") name="test $index" checkpoint="$dir/tests/test_$index.checkpoint.h5"
fi
[[ -f "$dir/job.json" && -f "$dir/specimen.h5" ]] || { echo "$dir needs job.json and specimen.h5" >&2; exit 2; }
[[ $from_start == 1 || -f "$checkpoint" ]] ||
    { echo "$dir needs $checkpoint (or --from-start)" >&2; exit 2; }
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
tick=$(getconf CLK_TCK)
echo "$(date -u '+%Y-%m-%d %H:%M UTC'); $dir $name$([[ $from_start == 1 ]] && echo ' from its start'); $seconds s per run; $copies cop(y/ies) at once on $threads thread(s) each"
for r in $(seq "$reps"); do
    for b in "$@"; do
        pids=()
        for k in $(seq "$copies"); do
            copy="$scratch/job$k"
            rm -rf "$copy"; mkdir -p "$copy/tests"
            cp "$dir/job.json" "$copy/"; ln -s "$dir/specimen.h5" "$copy/specimen.h5"
            [[ $from_start == 1 ]] || cp "$checkpoint" "$copy/tests/"
            "$b" test "$copy" "${which[@]}" --threads "$threads" --checkpoint-interval 0 > "$scratch/out$k" 2>&1 &
            pids+=($!)
        done
        # From the first progress line with a step of every copy (the
        # checkpoint restored) to the last ones S seconds later: steps and CPU
        # time of stepping alone, summed over the copies.
        at() { grep -o "step [0-9]*" "$scratch/out$1" | tail -1 | cut -d' ' -f2; }
        steps() { local sum=0 k v; for k in $(seq "$copies"); do v=$(at "$k"); sum=$((sum + ${v:-0})); done; echo "$sum"; }
        started() { local k; for k in $(seq "$copies"); do [[ -n "$(at "$k")" ]] || return 1; done; }
        cpu() { local p; for p in "${pids[@]}"; do awk -v t="$tick" '{ print ($14 + $15) / t }' "/proc/$p/stat"; done | awk '{ s += $1 } END { print s }'; }
        for _ in $(seq 600); do started && break; sleep 0.1; done
        if ! started; then
            echo "$b: no progress line (does it read this checkpoint?)"; tail -2 "$scratch/out1"
            kill -9 "${pids[@]}" 2>/dev/null || true; wait 2>/dev/null || true
            continue
        fi
        first=$(steps); cpu0=$(cpu); t0=$(date +%s.%N)
        sleep "$seconds"
        last=$(steps); cpu1=$(cpu); t1=$(date +%s.%N)
        kill -9 "${pids[@]}" 2>/dev/null || true; wait 2>/dev/null || true
        awk -v b="$b" -v r="$r" -v n=$((last - first)) -v c0="$cpu0" -v c1="$cpu1" -v t0="$t0" -v t1="$t1" \
            -v l="$(cut -d' ' -f1-3 /proc/loadavg)" \
            'BEGIN { printf "run %s %-50s %7d steps %7.2f s CPU %8.1f steps/CPU-s %8.1f steps/s  load %s\n", r, b, n, c1 - c0, n / (c1 - c0), n / (t1 - t0), l }'
    done
done
