#!/usr/bin/env bash
# A repose heap in wiredem, LIGGGHTS and LAMMPS: a column of grains settled in
# a tube on a rough base, the tube lifted slowly, the cone left read the same
# way from the positions of each (issue 43 §4; docs/validation.md, "Across
# codes: the angle of repose of a lifted tube").
#
# For each seed, then each rolling friction μ_r:
# 1. wiredem-bench --heap --tube writes the start every code and μ_r reads: a column
#    of the paper's grains (the heap's loose lattice, gaps 0.2 d, in a cylinder
#    of --lattice-radius) settled for --settle-time with μ_r = --settle-mu-r inside that cylinder, on
#    the rough base of heap_physics.sh (to --rough-base from the axis), with
#    the cylinder replaced by a tube of spheres of the grains' size and
#    material around it (closed rings, √3 r apart, to the column's top): ids
#    1…N the poured grains, then the base's, then the tube's;
# 2. each code holds the tube still for --hold (the contacts form under its
#    own laws: every code starts at rest with fresh springs), then lifts it at
#    --lift m/s until its bottom has passed the column's top, and runs --rest
#    more; the positions at the end are written (wiredem: --lift-tube, Gear-5
#    and the paper's laws with the rolling law η_r = 0; LIGGGHTS: in.repose,
#    Hertz + Mindlin + epsd2, fix move linear; LAMMPS: in.repose.lammps,
#    Hertz + Mindlin + rolling sds, fix move linear);
# 3. heap_physics.py reads every cone's angle as it reads the poured heaps
#    (the surface and the radius-profile readings) and prints one table;
#    --out DIR keeps it as repose_physics.csv with a figure repose_physics.png.
#
# Builds nothing (bash scripts/build.sh release wiredem-bench first).
#
# usage: bench/liggghts/repose_physics.sh [--grains N] [--lattice-radius R] [--rough-base R] [--settle-time S] [--settle-mu-r M]
#                                         [--hold S] [--lift V] [--rest S] [--mu-r "0.3 0"] [--seeds "1 2"]
#                                         [--wiredem-kt K] [--out DIR] [--no-lammps]
#   defaults: 600 grains in a 10 mm tube (a column ~27 mm high), a 35 mm base
#   (436 grains), settled 0.25 s with μ_r = 0.3; held 0.02 s, lifted at 0.05 m/s (0.32 √(g d)),
#   0.15 s of rest after; μ_r = 0.3, seed 1. A run is a few minutes of CPU per code.
#   --wiredem-kt K: wiredem's lift runs with k_t = K [1/m] (its rolling spring
#   k_r = f_r k_t F_n R*² with it; the start is settled with the paper's k_t as
#   always); its rows are then named wiredem-ktK. The step follows the springs:
#   K = 1e7 takes 8.5 times the steps of the paper's 1e5.
# environment: see peers.sh (WIREDEM_BENCH, LIGGGHTS, LAMMPS, NICE, KEEP).
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)
grains=600
lattice_radius=0.010
rough_base=0.035
settle_s=0.25
settle_mu_r=0.3
hold_s=0.02
lift=0.05
rest_s=0.15
mu_rs=0.3
seeds=1
out=
use_lammps=1
wiredem_kt=
while [ $# -gt 0 ]; do
    case $1 in
        --grains) grains=$2; shift 2 ;;
        --lattice-radius) lattice_radius=$2; shift 2 ;;
        --rough-base) rough_base=$2; shift 2 ;;
        --settle-time) settle_s=$2; shift 2 ;;
        --settle-mu-r) settle_mu_r=$2; shift 2 ;;
        --hold) hold_s=$2; shift 2 ;;
        --lift) lift=$2; shift 2 ;;
        --rest) rest_s=$2; shift 2 ;;
        --mu-r) mu_rs=$2; shift 2 ;;
        --seeds) seeds=$2; shift 2 ;;
        --wiredem-kt) wiredem_kt=$2; shift 2 ;;
        --out) out=$(realpath -m "$2"); shift 2 ;;
        --no-lammps) use_lammps=0; shift ;;
        -h|--help) awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "$0"; exit 0 ;;
        *) echo "unknown argument: $1 (try --help)" >&2; exit 2 ;;
    esac
done
source "$here/peers.sh"
wiredem_name=wiredem
wiredem_stiffness=()
if [ -n "$wiredem_kt" ]; then
    wiredem_name=wiredem-kt$wiredem_kt
    wiredem_stiffness=(--tangential-stiffness "$wiredem_kt")
fi

geometry=(--heap --grains "$grains" --lattice-radius "$lattice_radius" --rough-base "$rough_base"
          --steps 1 --threads 1 --integrators verlet --no-wire-membrane --json)
runs=()
energies=()
pids=()
tags=()
# Every case runs at once (each code one thread, at the nice level): only the cones are compared.
for seed in $seeds; do
    # One start per seed, for every code and μ_r: the column settled in its cylinder with μ_r = --settle-mu-r.
    start="start.s$seed.data"
    nice -n "$nice_level" "$bench" "${geometry[@]}" --rolling-friction "$settle_mu_r" --seed "$seed" --tube \
        --settle-time "$settle_s" --liggghts-data "$work/$start" > "$work/start.s$seed.json" 2> "$work/start.s$seed.err"
    dt=$(field time_step_s < "$work/start.s$seed.json" | head -n1)
    base=$(sed -n 's/^tube: [0-9]* poured grains, \([0-9]*\) base grains.*/\1/p' "$work/start.s$seed.err")
    # The tube rises until its lowest ring's bottom (2.03 r above the floor)
    # has passed the top of the column, then the rest.
    read -r time_s steps hold < <(awk -v n="$grains" -v dt="$dt" -v hold="$hold_s" -v v="$lift" -v rest="$rest_s" '
        f && NF == 7 && $1 <= n { top = $7 + 0.5 * $3 > top ? $7 + 0.5 * $3 : top; r = 0.5 * $3 }
        /^Atoms/ { f = 1 }
        END { t = hold + (top - 2.03 * r) / v + rest; printf "%.6g %d %d\n", t, t / dt, hold / dt }' "$work/$start")
    echo "seed $seed: δt = $dt s, $base base grains, $time_s s ($steps steps, the lift from step $hold)" >&2
    for mu_r in $mu_rs; do
        tag="r$mu_r.s$seed"
        nice -n "$nice_level" "$bench" "${geometry[@]}" --rolling-friction "$mu_r" --seed "$seed" "${wiredem_stiffness[@]}" \
            --packing "$work/$start" --lift-tube "$lift" --tube-hold "$hold_s" --settle-time "$time_s" \
            --liggghts-data "$work/wiredem.$tag.data" > /dev/null 2> "$work/wiredem.$tag.err" &
        pids+=($!)
        peer=(-var datafile "$start" -var dt "$dt" -var hold "$hold" -var steps "$steps" -var lift "$lift"
              -var mur "$mu_r" -var poured "$grains" -var base "$base")
        run_peer "$liggghts" "$here/in.repose" "liggghts.$tag" "${peer[@]}" -var dumpfile "liggghts.$tag.dump" &
        pids+=($!)
        if [ "$use_lammps" = 1 ]; then
            run_peer "$lammps" "$here/in.repose.lammps" "lammps.$tag" "${peer[@]}" -var dumpfile "lammps.$tag.dump" &
            pids+=($!)
        fi
        tags+=("$mu_r $seed $tag")
    done
done
for pid in "${pids[@]}"; do wait "$pid" || { echo "a run failed (work directory $work; KEEP=1 keeps it)" >&2; exit 1; }; done
for t in "${tags[@]}"; do
    read -r mu_r seed tag <<< "$t"
    runs+=("$wiredem_name/r$mu_r/s$seed=$work/wiredem.$tag.data")
    energies+=("$wiredem_name/r$mu_r/s$seed $(sed -n 's/.*kinetic energy \([^ ]*\) J.*/\1/p' "$work/wiredem.$tag.err" | tail -n1) $grains")
    runs+=("LIGGGHTS/r$mu_r/s$seed=$work/liggghts.$tag.dump")
    energies+=("LIGGGHTS/r$mu_r/s$seed $(last_kinetic_energy "$work/liggghts.$tag.log") $(last_atoms "$work/liggghts.$tag.log")")
    if [ "$use_lammps" = 1 ]; then
        runs+=("LAMMPS/r$mu_r/s$seed=$work/lammps.$tag.dump")
        energies+=("LAMMPS/r$mu_r/s$seed $(last_kinetic_energy "$work/lammps.$tag.log") $(last_atoms "$work/lammps.$tag.log")")
    fi
done

echo "$(date -u '+%Y-%m-%d %H:%M UTC'); $grains grains settled in a $lattice_radius m tube on a $rough_base m base," \
     "the tube lifted at $lift m/s; kinetic energy of the poured grains at the end [J] and atoms left (all):"
printf '  %s\n' "${energies[@]}"
extra=()
if [ -n "$out" ]; then
    mkdir -p "$out"
    extra=(--csv "$out/repose_physics.csv" --png "$out/repose_physics.png" --title "lifted tube: radius profile (surface / profile angle)")
fi
/usr/bin/python3 "$here/heap_physics.py" --poured "$grains" "${runs[@]}" "${extra[@]}"
