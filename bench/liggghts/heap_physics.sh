#!/usr/bin/env bash
# A poured heap in wiredem, LIGGGHTS and LAMMPS, and its angle of repose read
# the same way from the positions of each (issue 43 §4; docs/validation.md,
# "Across codes: a poured heap").
#
# For each rolling friction μ_r and seed:
# 1. wiredem-bench --heap writes a column of the paper's grains on a loose
#    lattice (gap 0.02 d, the seed's jitter) in a cylinder of --lattice-radius,
#    at rest, without the cylinder, above a rough base (a layer of fixed
#    grains of the same size on a square lattice, to --rough-base from the
#    axis; the ids after the poured grains'): a data file every code starts from;
# 2. each code lets the column fall onto the base (the floor beyond it flat;
#    μ = 0.3 everywhere) for --time under gravity: the column's foot lands
#    first and the rest pours onto it, from up to its height; the positions
#    at the end are written (wiredem: Gear-5 and the paper's laws with the rolling law of
#    docs/model.md, η_r = 0; LIGGGHTS: in.heap, Hertz + Mindlin + epsd2;
#    LAMMPS: in.heap.lammps, Hertz + Mindlin + sds);
# 3. heap_physics.py reads every heap's angle the same way (the surface and
#    the radius-profile readings of scripts/gravel_calibration.py, tried there
#    on synthetic heaps of known angle) and prints one table; --out DIR keeps
#    it as CSV with a figure of the heaps' profiles.
#
# Builds nothing (bash scripts/build.sh release wiredem-bench first).
#
# usage: bench/liggghts/heap_physics.sh [--grains N] [--lattice-radius R] [--rough-base R] [--time S]
#                                       [--mu-r "0.3 0"] [--seeds "1 2"] [--also-kt K] [--out DIR] [--no-lammps]
#   defaults: 1500 grains, a 12 mm lattice column (37 grains a layer, 0.12 m
#   tall), a 45 mm base (1005 grains; 0: none, the flat floor), 0.5 s,
#   μ_r = 0.3, seed 1. --also-kt K: also wiredem with the
#   tangential law's k_t = K [1/m] (its rolling stiffness is k_t F_n R*²: both
#   then of the peers' order). A run is a few minutes of CPU per code.
# environment: see peers.sh (WIREDEM_BENCH, LIGGGHTS, LAMMPS, NICE, KEEP).
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)
grains=1500
lattice_radius=0.012
rough_base=0.045
time_s=0.5
mu_rs=0.3
seeds=1
out=
use_lammps=1
also_kt=
while [ $# -gt 0 ]; do
    case $1 in
        --grains) grains=$2; shift 2 ;;
        --lattice-radius) lattice_radius=$2; shift 2 ;;
        --rough-base) rough_base=$2; shift 2 ;;
        --time) time_s=$2; shift 2 ;;
        --mu-r) mu_rs=$2; shift 2 ;;
        --seeds) seeds=$2; shift 2 ;;
        --out) out=$(realpath -m "$2"); shift 2 ;;
        --no-lammps) use_lammps=0; shift ;;
        --also-kt) also_kt=$2; shift 2 ;;
        -h|--help) awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "$0"; exit 0 ;;
        *) echo "unknown argument: $1 (try --help)" >&2; exit 2 ;;
    esac
done
source "$here/peers.sh"

runs=()
energies=()
for mu_r in $mu_rs; do
    for seed in $seeds; do
        tag="r$mu_r.s$seed"
        common=(--heap --grains "$grains" --lattice-radius "$lattice_radius" --rough-base "$rough_base"
                --rolling-friction "$mu_r" --seed "$seed"
                --steps 1 --threads 1 --integrators verlet --no-wire-membrane --json)
        nice -n "$nice_level" "$bench" "${common[@]}" --settle-time 0 --liggghts-data "$work/lattice.$tag.data" \
            > "$work/lattice.$tag.json" 2> /dev/null
        dt=$(sed -n 's/.*"time_step_s":\([^,}]*\).*/\1/p' "$work/lattice.$tag.json" | head -n1)
        steps=$(awk -v s="$time_s" -v dt="$dt" 'BEGIN { printf "%d", s / dt }')
        echo "mu_r $mu_r, seed $seed: δt = $dt s, $steps steps" >&2
        # The codes run side by side (each one thread, at the nice level): only the heaps are compared.
        echo "  wiredem, LIGGGHTS$([ "$use_lammps" = 1 ] && echo ", LAMMPS")$([ -n "$also_kt" ] && echo ", wiredem with k_t = $also_kt")" >&2
        pids=()
        nice -n "$nice_level" "$bench" "${common[@]}" --settle-time "$time_s" --liggghts-data "$work/wiredem.$tag.data" \
            > /dev/null 2> "$work/wiredem.$tag.err" &
        pids+=($!)
        if [ -n "$also_kt" ]; then
            nice -n "$nice_level" "$bench" "${common[@]}" --settle-time "$time_s" --tangential-stiffness "$also_kt" \
                --liggghts-data "$work/wiredem-kt.$tag.data" > /dev/null 2> "$work/wiredem-kt.$tag.err" &
            pids+=($!)
        fi
        run_peer "$liggghts" "$here/in.heap" "liggghts.$tag" -var datafile "lattice.$tag.data" -var dt "$dt" \
            -var steps "$steps" -var dumpfile "liggghts.$tag.dump" -var mur "$mu_r" -var poured "$grains" &
        pids+=($!)
        if [ "$use_lammps" = 1 ]; then
            run_peer "$lammps" "$here/in.heap.lammps" "lammps.$tag" -var datafile "lattice.$tag.data" -var dt "$dt" \
                -var steps "$steps" -var dumpfile "lammps.$tag.dump" -var mur "$mu_r" -var poured "$grains" &
            pids+=($!)
        fi
        for pid in "${pids[@]}"; do wait "$pid" || { echo "a run of mu_r $mu_r, seed $seed failed" >&2; exit 1; }; done
        runs+=("wiredem/r$mu_r/s$seed=$work/wiredem.$tag.data")
        energies+=("wiredem/r$mu_r/s$seed $(sed -n 's/.*kinetic energy \([^ ]*\) J.*/\1/p' "$work/wiredem.$tag.err" | tail -n1) $grains")
        if [ -n "$also_kt" ]; then
            runs+=("wiredem-kt$also_kt/r$mu_r/s$seed=$work/wiredem-kt.$tag.data")
            energies+=("wiredem-kt$also_kt/r$mu_r/s$seed $(sed -n 's/.*kinetic energy \([^ ]*\) J.*/\1/p' "$work/wiredem-kt.$tag.err" | tail -n1) $grains")
        fi
        runs+=("LIGGGHTS/r$mu_r/s$seed=$work/liggghts.$tag.dump")
        energies+=("LIGGGHTS/r$mu_r/s$seed $(last_kinetic_energy "$work/liggghts.$tag.log") $(last_atoms "$work/liggghts.$tag.log")")
        if [ "$use_lammps" = 1 ]; then
            runs+=("LAMMPS/r$mu_r/s$seed=$work/lammps.$tag.dump")
            energies+=("LAMMPS/r$mu_r/s$seed $(last_kinetic_energy "$work/lammps.$tag.log") $(last_atoms "$work/lammps.$tag.log")")
        fi
    done
done

echo "$(date -u '+%Y-%m-%d %H:%M UTC'); $grains grains from a $lattice_radius m lattice column onto a $rough_base m base, $time_s s;" \
     "kinetic energy at the end [J] and grains left (a peer loses those beyond its 0.2 m box):"
printf '  %s\n' "${energies[@]}"
extra=()
if [ -n "$out" ]; then
    mkdir -p "$out"
    extra=(--csv "$out/heap_physics.csv" --png "$out/heap_physics.png")
fi
/usr/bin/python3 "$here/heap_physics.py" --poured "$grains" "${runs[@]}" "${extra[@]}"
