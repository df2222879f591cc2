#!/usr/bin/env bash
# wiredem, LIGGGHTS and LAMMPS side by side on one packing (issues 3, 15).
#
# 1. wiredem-bench settles the grains, writes the packing as a LIGGGHTS data
#    file and times N steps on it at 1 and 2 threads;
# 2. each peer reads that packing and runs the same N steps with the same δt,
#    on 1 process and, if it is built with MPI and mpirun exists, on 2:
#    LIGGGHTS (bench/liggghts/in.bench) and LAMMPS (bench/liggghts/in.lammps,
#    pair_style granular; skipped with a note when no LAMMPS binary is found);
# 3. one table: wall time, body-steps/s, body-steps/s per core, and
#    wiredem (and LAMMPS) per core relative to each peer.
#
# Builds nothing: it needs build/release (bash scripts/build.sh release).
#
# usage: bench/liggghts/side_by_side.sh [--steps N] [--settle-time S] [--grains G] [--packing FILE] [--no-mpi]
#   defaults: 2000 steps, 8000 grains, 0.2 s settling. The bench's own default
#   (0.03 s) leaves most grains still falling (~500 contacts instead of ~20000),
#   which is not the static packing the comparison is about; 0.2 s gives a
#   packing at rest (kinetic energy ~1e-5 J) but takes minutes to settle.
#   --packing FILE times a packing saved earlier (the data file that
#   `wiredem-bench --liggghts-data FILE` writes; KEEP=1 leaves one in the work
#   directory) instead of settling a new one: both codes then start it at rest.
#
# Both wall time and CPU time are reported. On a machine that is busy with
# other work, wall times mostly measure the waiting; the CPU time of a
# one-thread run does not (LIGGGHTS' CPU time is that of an N-step run minus
# that of a 0-step run, i.e. without reading the file and setting up).
# environment: as peers.sh (WIREDEM_BENCH, LIGGGHTS, LAMMPS, KEEP=1; NICE is
#              0 here), and MPIRUN (default: mpirun on PATH).
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)

steps=2000
settle=0.2
grains=
packing=
use_mpi=1
while [ $# -gt 0 ]; do
    case $1 in
        --steps) steps=$2; shift 2 ;;
        --settle-time) settle=$2; shift 2 ;;
        --grains) grains=$2; shift 2 ;;
        --packing) packing=$(realpath "$2"); shift 2 ;;
        --no-mpi) use_mpi=0; shift ;;
        -h|--help) awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "$0"; exit 0 ;;
        *) echo "unknown argument: $1 (try --help)" >&2; exit 2 ;;
    esac
done

use_lammps=1
NICE=${NICE:-0} # timings: at normal priority unless asked
. "$here/peers.sh" # bench, liggghts, lammps, use_lammps, work, field
[ "$use_lammps" = 1 ] || lammps=
mpirun=${MPIRUN:-$(command -v mpirun || true)}
# mpi_procs BINARY: the process counts to run it on (2 only with mpirun and an MPI build).
# (not `ldd | grep -q`: grep -q quits early, ldd gets SIGPIPE, pipefail fails it)
mpi_procs() {
    if [ "$use_mpi" = 1 ] && [ -n "$mpirun" ] && [ "$(ldd "$1" 2>/dev/null | grep -c libmpi)" != 0 ]; then
        echo 1 2
    else
        [ "$use_mpi" = 1 ] && echo "note: $1 runs on 1 process only (no mpirun, or not built with MPI)" >&2
        echo 1
    fi
}

# --- wiredem ---------------------------------------------------------------
bench_args=(--json --threads 1,2 --steps "$steps" --no-wire-membrane --liggghts-data "$work/packing.data")
[ -n "$settle" ] && bench_args+=(--settle-time "$settle")
[ -n "$grains" ] && bench_args+=(--grains "$grains")
[ -n "$packing" ] && bench_args+=(--packing "$packing")
echo "running: $bench ${bench_args[*]}" >&2
"$bench" "${bench_args[@]}" > "$work/wiredem.json"

dt=$(head -n1 "$work/wiredem.json" | field time_step_s)
bodies=$(head -n1 "$work/wiredem.json" | field bodies)
contacts=$(head -n1 "$work/wiredem.json" | field contacts)

# --- the peers ------------------------------------------------------------
# The bench writes "2 atom types": type 2 is the walls' own material.
cp "$work/packing.data" "$work/packing2.data"
grep -q '^2 atom types$' "$work/packing2.data" || { echo "unexpected data file header" >&2; exit 1; }

run_peer() { # run_peer NAME BINARY DECK PROCS [STEPS]: prints "loop_wall procs steps atoms cpu"
    local name=$1 binary=$2 deck=$3 procs=$4 n=${5:-$steps}
    local log=$work/$name.$procs.$n.log
    local cmd=(/usr/bin/time -f "%U %S" -o "$work/time.$name.$procs.$n" "$binary" -in "$deck" -var datafile "$work/packing2.data" -var dt "$dt" -var steps "$n" -log "$log")
    if [ "$procs" -gt 1 ]; then
        # OMPI_ALLOW_RUN_AS_ROOT*: Open MPI refuses root otherwise (containers); harmless elsewhere.
        cmd=(env OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 "$mpirun" -np "$procs" "${cmd[@]}")
    fi
    echo "running: ${cmd[*]}" >&2
    (cd "$work" && "${cmd[@]}" > "$work/$name.$procs.out" 2>&1) || {
        echo "$name failed on $procs process(es); its output:" >&2
        tail -n 30 "$work/$name.$procs.out" >&2
        exit 1
    }
    # "Loop time of X on P procs for N steps with M atoms[, finish time ...]"
    local cpu
    cpu=$(awk '{ print $1 + $2 }' "$work/time.$name.$procs.$n")
    grep -m1 '^Loop time of' "$log" |
        sed -n "s/^Loop time of \([0-9.eE+-]*\) on \([0-9]*\) procs for \([0-9]*\) steps with \([0-9]*\) atoms.*/\1 \2 \3 \4 $cpu/p"
}

rows=()
while read -r line; do
    rows+=("wiredem/$(echo "$line" | field integrator) $(echo "$line" | field threads) $(echo "$line" | field steps) $(echo "$line" | field wall_time_s) $(echo "$line" | field cpu_time_s) $(echo "$line" | field bodies)")
done < <(grep '"case":"settled_packing"' "$work/wiredem.json")
time_peer() { # time_peer NAME BINARY DECK: appends its rows (CPU time without reading and set-up)
    local name=$1 binary=$2 deck=$3 p wall np nsteps atoms cpu cpu0
    for p in $(mpi_procs "$binary"); do
        read -r _ _ _ _ cpu0 < <(run_peer "$name" "$binary" "$deck" "$p" 0)
        read -r wall np nsteps atoms cpu < <(run_peer "$name" "$binary" "$deck" "$p")
        [ -n "${wall:-}" ] || { echo "no 'Loop time' line in the $name log" >&2; exit 1; }
        [ "$atoms" = "$bodies" ] || echo "warning: $name has $atoms atoms, wiredem $bodies bodies" >&2
        rows+=("$name $np $nsteps $wall $(awk -v a="$cpu" -v b="$cpu0" 'BEGIN { print a - b }') $atoms")
    done
}
time_peer LIGGGHTS "$liggghts" "$here/in.bench"
[ -n "$lammps" ] && time_peer LAMMPS "$lammps" "$here/in.lammps"

# --- table -----------------------------------------------------------------
echo
echo "$(date -u '+%Y-%m-%d %H:%M UTC'); $(nproc) cores; load average $(cut -d' ' -f1-3 /proc/loadavg)"
simd=$(grep -m1 '"case":"settled_packing"' "$work/wiredem.json" | field simd)
echo "$bodies grains, ${packing:-${settle:-default} s settling}, $contacts contacts, δt = $dt s, $steps steps on the packing; $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//'), wiredem's SIMD paths: ${simd:-unknown}"
# per core: body-steps per second of wall time / cores; per CPU-s: body-steps per second of CPU time.
# vs PEER: per core (wall) and per CPU-s, relative to the peer on as many
# cores (or on 1 if it ran on fewer).
printf '%s\n' "${rows[@]}" | awk '
    { engine[NR] = $1; cores[NR] = $2; steps[NR] = $3; wall[NR] = $4; cpu[NR] = $5; bodies[NR] = $6
      rate[NR] = $6 * $3 / $4; per_core[NR] = rate[NR] / $2; per_cpu[NR] = $6 * $3 / $5
      if ($1 == "LIGGGHTS" || $1 == "LAMMPS") { peer[$1, $2] = per_core[NR]; peer_cpu[$1, $2] = per_cpu[NR]; has[$1] = 1 } }
    function vs(i, name, cpu_based,   key) {
      if (engine[i] == name || !(name in has)) return "-"
      key = ((name, cores[i]) in peer) ? cores[i] : 1
      return sprintf("%.2fx", cpu_based ? per_cpu[i] / peer_cpu[name, key] : per_core[i] / peer[name, key])
    }
    END {
      printf "%-15s %7s %6s %9s %8s %13s %13s %13s %11s %11s %11s %11s\n", "engine", "cores", "steps", "wall [s]", "cpu [s]",
             "body-steps/s", "per core", "per CPU-s", "vs LIG wall", "vs LIG cpu", "vs LMP wall", "vs LMP cpu"
      for (i = 1; i <= NR; ++i)
        printf "%-15s %7s %6d %9.3f %8.3f %13.4g %13.4g %13.4g %11s %11s %11s %11s\n", engine[i],
               cores[i] (engine[i] ~ /^wiredem/ ? " thr" : " proc"), steps[i], wall[i], cpu[i], rate[i], per_core[i],
               per_cpu[i], vs(i, "LIGGGHTS", 0), vs(i, "LIGGGHTS", 1), vs(i, "LAMMPS", 0), vs(i, "LAMMPS", 1)
    }'
