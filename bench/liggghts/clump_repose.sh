#!/usr/bin/env bash
# A column of clumps settled in a tube on a rough base, the tube lifted
# slowly, in wiredem and in LIGGGHTS' fix multisphere: the packing fraction
# of the settled column and the angle of the cone it leaves, read the same way
# from the positions of each (issue 40 §5; docs/validation.md, "Across codes:
# clumps"). The sphere version is repose_physics.sh.
#
# For each seed:
# 1. wiredem-bench --clumps SHAPE --heap --rough-base --tube --settle-time 0
#    writes the start: N clumps of SHAPE (volume-equivalent radius 1.23 mm,
#    turned at random) on the heap's loose lattice (gaps 0.2 of the clump's
#    bounding diameter) in a cylinder of --lattice-radius, lifted above the
#    rough base of repose_physics.sh (fixed spheres of 1.23 mm to
#    --rough-base from the axis), inside a tube of fixed spheres of 1.23 mm
#    (repose_physics.sh's rings, here up to the lattice's top), and the
#    template (--clump-template: the first clump's spheres in its body frame);
# 2. the clumps are left out of that file for LIGGGHTS, which cannot start a
#    multisphere body from a data file: it reads the base and the tube, and
#    inserts N clumps of the same template at random orientations in the
#    lattice's region (the cylinder, from the lattice's lowest to its highest
#    sphere; in.clump_repose). So both codes fill the same tube with the same
#    clumps in the same region, each at its own random places: two samples
#    of one column, not one packing;
# 3. each code (two processes at a time) lets them settle for --settle-time
#    in the tube, writes the column, holds the tube still for --hold, lifts it
#    at --lift m/s (wiredem: Motion::kinematic spheres; LIGGGHTS: fix move
#    linear) for --lift-time in all (the hold included), and writes the cone;
#    laws: the paper's (wiredem) and Hertz + Mindlin (LIGGGHTS), both without
#    rolling resistance, as repose_physics.sh's at μ_r = 0;
# 4. clump_repose.py reads the packing fraction of the settled column's core
#    and the cone's angles; --out DIR keeps them as clump_repose.csv with a
#    figure clump_repose.png.
#
# Builds nothing (bash scripts/build.sh release wiredem-bench first).
#
# usage: bench/liggghts/clump_repose.sh [--shape SHAPE] [--grains N] [--lattice-radius R] [--rough-base R]
#                                       [--settle-time S] [--hold S] [--lift V] [--lift-time S]
#                                       [--seeds "1 2"] [--out DIR]
#   defaults: 600 tetrahedral clumps in a 10 mm tube (a lattice 0.18 m tall,
#   a settled column ~27 mm), a 35 mm base (436 spheres), settled 0.35 s, held
#   0.02 s and lifted at 0.05 m/s for 0.8 s in all (the tube's foot 39 mm up at
#   the end); seed 1. A seed is 2.5 min of CPU for wiredem and about twice its
#   time for LIGGGHTS.
# environment: see peers.sh (WIREDEM_BENCH, LIGGGHTS, NICE, KEEP).
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)
shape=tetrahedral
grains=600
lattice_radius=0.010
rough_base=0.035
settle_s=0.35
hold_s=0.02
lift=0.05
lift_s=0.8
seeds=1
out=
while [ $# -gt 0 ]; do
    case $1 in
        --shape) shape=$2; shift 2 ;;
        --grains) grains=$2; shift 2 ;;
        --lattice-radius) lattice_radius=$2; shift 2 ;;
        --rough-base) rough_base=$2; shift 2 ;;
        --settle-time) settle_s=$2; shift 2 ;;
        --hold) hold_s=$2; shift 2 ;;
        --lift) lift=$2; shift 2 ;;
        --lift-time) lift_s=$2; shift 2 ;;
        --seeds) seeds=$2; shift 2 ;;
        --out) out=$(realpath -m "$2"); shift 2 ;;
        -h|--help) awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "$0"; exit 0 ;;
        *) echo "unknown argument: $1 (try --help)" >&2; exit 2 ;;
    esac
done
use_lammps=0
source "$here/peers.sh"
d_eq=0.00246  # wiredem-bench's r_p = 1.23 mm: the base's and the tube's spheres, the clumps' volume-equivalent size
skin=0.000246 # 0.2 r_p, as in.repose
# LIGGGHTS' insertion seeds (primes above 10000), one per wiredem seed.
primes=(32452867 32452883 32452909 32452919 32452921)

geometry=(--clumps "$shape" --heap --grains "$grains" --lattice-radius "$lattice_radius" --rough-base "$rough_base"
          --tube --steps 1 --threads 1 --integrators verlet --no-wire-membrane --json)
# The start of each seed; then two chains of runs, two processes at a time: LIGGGHTS' first
# seed, and wiredem's seeds followed by LIGGGHTS' others (LIGGGHTS takes about twice
# wiredem's time here).
wiredem_chain=()
liggghts_chain=()
for seed in $seeds; do
    nice -n "$nice_level" "$bench" "${geometry[@]}" --seed "$seed" --settle-time 0 --liggghts-data "$work/start.s$seed.data" \
        --clump-template "$work/clump.spheres" > "$work/start.s$seed.json" 2> "$work/start.s$seed.err"
    dt=$(field time_step_s < "$work/start.s$seed.json" | head -n1)
    read -r poured base < <(sed -n 's/^tube: \([0-9]*\) poured spheres ([0-9]* clumps), \([0-9]*\) base grains.*/\1 \2/p' \
        "$work/start.s$seed.err")
    nsph=$(wc -l < "$work/clump.spheres")
    # The base and the tube, renumbered from 1, for LIGGGHTS.
    awk -v p="$poured" 'f && NF == 7 { if ($1 > p) { $1 -= p; rows[++n] = $0 } next }
        /^Atoms/ { f = 1; next } / atoms$/ { next } !f { head = head $0 "\n" }
        END { printf "wiredem base and tube\n\n%d atoms\n", n; sub(/^[^\n]*\n\n/, "", head); printf "%s", head
              print "Atoms\n"; for (i = 1; i <= n; ++i) print rows[i] }' "$work/start.s$seed.data" > "$work/walls.s$seed.data"
    # The lattice's region: its lowest and highest sphere; the clump's bounding radius off the cylinder.
    read -r zlo zhi < <(awk -v p="$poured" 'f && NF == 7 && $1 <= p { lo = (n++ == 0 || $7 - $3 / 2 < lo) ? $7 - $3 / 2 : lo
        hi = ($7 + $3 / 2 > hi) ? $7 + $3 / 2 : hi } /^Atoms/ { f = 1 } END { print lo, hi }' "$work/start.s$seed.data")
    bound=$(awk '{ d = sqrt($1 * $1 + $2 * $2 + $3 * $3) + $4; if (d > m) m = d } END { print m }' "$work/clump.spheres")
    region=$(awk -v R="$lattice_radius" -v b="$bound" 'BEGIN { print R - 0.2 * b }') # wiredem's reach + b: R - gap/2
    settle_steps=$(awk -v t="$settle_s" -v dt="$dt" 'BEGIN { printf "%d", t / dt }')
    hold_steps=$(awk -v t="$hold_s" -v dt="$dt" 'BEGIN { printf "%d", t / dt }')
    lift_steps=$(awk -v t="$lift_s" -v dt="$dt" 'BEGIN { printf "%d", t / dt }')
    echo "seed $seed: δt = $dt s, $poured clump spheres, $base base spheres; LIGGGHTS inserts in r < $region m," \
         "z $zlo-$zhi m; $settle_steps steps settling, $lift_steps lifting (the hold $hold_steps)" >&2
    tag=s$seed
    wiredem_chain+=("$seed")
    liggghts_chain+=("$tag -var datafile walls.s$seed.data -var clumpfile clump.spheres -var nspheres $nsph
        -var clumps $grains -var radius $region -var zlo $zlo -var zhi $zhi -var skin $skin -var dt $dt
        -var settle $settle_steps -var hold $hold_steps -var lift $lift_steps -var speed $lift -var base $base
        -var seed ${primes[$(( (seed - 1) % ${#primes[@]} ))]} -var settled liggghts.$tag.settled.dump
        -var dumpfile liggghts.$tag.lifted.dump")
done
liggghts_run() { # liggghts_run "TAG -var NAME VALUE ...": one LIGGGHTS run of the chain
    # shellcheck disable=SC2086 # the deck's variables, split on purpose
    set -- $1
    local tag=$1
    shift
    run_peer "$liggghts" "$here/in.clump_repose" "liggghts.$tag" "$@"
}
liggghts_run "${liggghts_chain[0]}" &
lpid=$!
(
    for seed in "${wiredem_chain[@]}"; do
        nice -n "$nice_level" "$bench" "${geometry[@]}" --seed "$seed" --settle-time "$settle_s" --lift-tube "$lift" \
            --tube-hold "$hold_s" --lift-time "$lift_s" --liggghts-data "$work/wiredem.s$seed.settled.data" \
            --lifted-data "$work/wiredem.s$seed.lifted.data" > /dev/null 2> "$work/wiredem.s$seed.err" ||
            { tail "$work/wiredem.s$seed.err" >&2; exit 1; }
    done
    for args in "${liggghts_chain[@]:1}"; do liggghts_run "$args"; done
) &
wpid=$!
wait "$wpid" || { echo "a run failed (work directory $work; KEEP=1 keeps it)" >&2; exit 1; }
wait "$lpid" || { echo "LIGGGHTS failed (work directory $work; KEEP=1 keeps it)" >&2; exit 1; }

runs=()
energies=()
for seed in $seeds; do
    tag=s$seed
    poured=$(sed -n 's/^tube: \([0-9]*\) poured spheres.*/\1/p' "$work/start.s$seed.err")
    for f in settled lifted; do # the clumps' spheres only
        awk -v p="$poured" 'f && NF == 7 { if ($1 <= p) print; next } /^Atoms/ { f = 1 } { print }' \
            "$work/wiredem.$tag.$f.data" > "$work/wiredem.$tag.$f.poured.data"
    done
    runs+=("wiredem/$tag=$work/wiredem.$tag.settled.poured.data,$work/wiredem.$tag.lifted.poured.data")
    runs+=("LIGGGHTS/$tag=$work/liggghts.$tag.settled.dump,$work/liggghts.$tag.lifted.dump")
    energies+=(--energy "wiredem/$tag=$(sed -n 's/^lifted: kinetic energy \([^ ]*\) J.*/\1/p' "$work/wiredem.$tag.err")")
    energies+=(--energy "LIGGGHTS/$tag=$(last_kinetic_energy "$work/liggghts.$tag.log")")
    echo "seed $seed: LIGGGHTS kept $(last_atoms "$work/liggghts.$tag.log") atoms; the clumps' kinetic energy settled:" \
         "wiredem $(sed -n 's/^heap: .*kinetic energy \([^ ]*\) J.*/\1/p' "$work/wiredem.$tag.err") J, LIGGGHTS" \
         "$(sed -n 's/^settled: kinetic energy \([^ ]*\) J.*/\1/p' "$work/liggghts.$tag.log" | head -n1) J" >&2
done

echo "$(date -u '+%Y-%m-%d %H:%M UTC'); $grains $shape clumps settled $settle_s s in a $lattice_radius m tube on a" \
     "$rough_base m base, the tube lifted at $lift m/s for $lift_s s; kinetic energy of the clumps at the end" \
     "(both: the bodies' translation and rotation)"
extra=()
if [ -n "$out" ]; then
    mkdir -p "$out"
    extra=(--csv "$out/clump_repose.csv" --png "$out/clump_repose.png")
fi
/usr/bin/python3 "$here/clump_repose.py" --tube-radius "$lattice_radius" --base-top "$d_eq" --d-eq "$d_eq" \
    "${runs[@]}" "${energies[@]}" "${extra[@]}"
