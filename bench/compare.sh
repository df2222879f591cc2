#!/usr/bin/env bash
# Before/after comparison of wiredem-bench binaries on one saved packing.
#
# On a shared machine one run says little: the same binary varies by ±20 %
# from run to run. This runs the binaries alternately (A B A B …), each run
# timing 1 and 2 threads of every integrator, and prints per binary and
# integrator the minimum and median one-thread CPU time, their ratio to the
# first binary's, and the median of the per-run 2-thread speed-ups (one-thread
# wall time / two-thread wall time of the same run).
#
# usage: bench/compare.sh (--packing FILE | --specimen FILE) [--reps N] [--steps N] [--integrators gear5,verlet]
#                         [--wire-membrane] [--quiet] BIN...
#   --packing FILE  a data file written by `wiredem-bench --liggghts-data FILE` (settling a packing
#                   per run would take minutes)
#   --specimen FILE a snapshot (a prepared specimen.h5 or a test's checkpoint): the study's column
#                   with wire and membrane (`wiredem-bench --specimen`); one of the two is required
#   --wire-membrane with --packing: also time the `wire_membrane` case (the paper-size cell: grains,
#                   wire and membrane), reported as wm-gear5 and wm-verlet
#   --reps N        alternations (default 5)
#   --steps N       timed steps per case (default 1000)
#   --quiet         before each run, wait (up to 10 min) until the CPUs are ≥ 85 % idle over 2 s
set -euo pipefail

reps=5
steps=1000
packing=
specimen=
integrators=gear5,verlet
quiet=0
wire_membrane=0
bins=()
while [ $# -gt 0 ]; do
    case $1 in
        --reps) reps=$2; shift 2 ;;
        --steps) steps=$2; shift 2 ;;
        --packing) packing=$2; shift 2 ;;
        --specimen) specimen=$2; shift 2 ;;
        --integrators) integrators=$2; shift 2 ;;
        --quiet) quiet=1; shift ;;
        --wire-membrane) wire_membrane=1; shift ;;
        -h|--help) awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "$0"; exit 0 ;;
        -*) echo "unknown option: $1 (try --help)" >&2; exit 2 ;;
        *) bins+=("$1"); shift ;;
    esac
done
if [ -n "$packing" ] && [ -z "$specimen" ]; then
    input=(--packing "$packing")
    [ "$wire_membrane" = 1 ] || input+=(--no-wire-membrane)
elif [ -n "$specimen" ] && [ -z "$packing" ]; then input=(--specimen "$specimen")
else echo "give one of --packing FILE and --specimen FILE (try --help)" >&2; exit 2; fi
[ ${#bins[@]} -gt 0 ] || { echo "no binaries given (try --help)" >&2; exit 2; }

wait_for_quiet() { # idle share of all CPUs over 2 s, from /proc/stat
    for _ in $(seq 300); do
        read -r -a a < <(head -n1 /proc/stat); sleep 2; read -r -a b < <(head -n1 /proc/stat)
        local idle=$((b[4] - a[4])) total=0 i
        for i in 1 2 3 4 5 6 7 8; do total=$((total + b[i] - a[i])); done
        [ $((100 * idle)) -ge $((85 * total)) ] && return 0
    done
    echo "note: the machine never got quiet; running anyway" >&2
}

out=$(mktemp)
trap 'rm -f "$out"' EXIT
for r in $(seq "$reps"); do
    for i in "${!bins[@]}"; do
        [ "$quiet" = 1 ] && wait_for_quiet
        "${bins[$i]}" --json "${input[@]}" --steps "$steps" --threads 1,2 \
            --integrators "$integrators" | sed "s/^/$i $r /" >> "$out"
    done
    echo "run $r of $reps done" >&2
done

echo "$(date -u '+%Y-%m-%d %H:%M UTC'); load average $(cut -d' ' -f1-3 /proc/loadavg); $reps alternated runs of $steps steps"
for i in "${!bins[@]}"; do echo "[$i] ${bins[$i]}"; done
# Lines: "<bin> <run> {json}". Fields taken from the JSON by name.
awk '
    function field(name,   s) { s = $0; sub(".*\"" name "\":\"?", "", s); sub("[\",}].*", "", s); return s }
    function median(list,   n, v, i, j, t) {
        n = split(list, v, " ")
        for (i = 2; i <= n; ++i) for (j = i; j > 1 && v[j - 1] + 0 > v[j] + 0; --j) { t = v[j]; v[j] = v[j - 1]; v[j - 1] = t }
        return n % 2 ? v[(n + 1) / 2] : (v[n / 2] + v[n / 2 + 1]) / 2
    }
    {
        key = $1 " " (field("case") == "wire_membrane" ? "wm-" : "") field("integrator"); run = key " " $2
        if (field("threads") == 1) { cpu1[key] = cpu1[key] " " field("cpu_time_s"); wall1[run] = field("wall_time_s") }
        else if (field("threads") == 2) wall2[run] = field("wall_time_s")
        keys[key] = 1; runs[run] = key
    }
    END {
        for (run in runs) if ((run in wall1) && (run in wall2)) speedup[runs[run]] = speedup[runs[run]] " " wall1[run] / wall2[run]
        for (key in keys) { mn = 1e30; n = split(cpu1[key], v, " ")
            for (i = 1; i <= n; ++i) if (v[i] + 0 < mn) mn = v[i] + 0
            cmin[key] = mn; cmed[key] = median(cpu1[key]) }
        for (key in keys) { split(key, k, " "); ref = "0 " k[2]
            printf "%s %-4s %-9s %14.3f %14.3f %11.2fx %11.2fx %18.2f\n", k[2] " " k[1], "[" k[1] "]", k[2],
                   cmin[key], cmed[key], cmin[ref] / cmin[key], cmed[ref] / cmed[key], median(speedup[key]) }
    }' "$out" | sort -k1,1 -k2,2n | cut -d" " -f3- |
    { printf "%-4s %-9s %14s %14s %12s %12s %18s\n" bin method "1T cpu min [s]" "1T cpu med [s]" \
          "min vs [0]" "med vs [0]" "2T speed-up (med)"; cat; }
