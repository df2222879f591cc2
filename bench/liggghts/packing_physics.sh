#!/usr/bin/env bash
# The same settling in wiredem, LIGGGHTS and LAMMPS, and the physics of the
# three packings side by side (issue 43 §4; docs/validation.md, "Across codes").
#
# For each seed:
# 1. wiredem-bench writes the bench's container at its start (the grains on a
#    loose lattice with the seed's jitter, at rest: --settle-time 0), then
#    settles the same lattice for --settle-time and writes the settled
#    positions (Gear-5, the engine's reference; the paper's laws);
# 2. LIGGGHTS (in.settle) and LAMMPS (in.settle.lammps) read the lattice and
#    settle it for as many steps of the same δt with their laws closest to
#    wiredem's (in.bench, in.lammps say where they differ), and dump the
#    settled positions with 17 digits;
# 3. packing_physics.py measures every packing the same way (packing
#    fraction, coordination, normal-force distribution from the overlaps,
#    the floor's load) and prints one table, the seed-to-seed spread per
#    code and the KS distances; --out DIR keeps the table (CSV) and the
#    figure (PNG).
#
# Builds nothing (bash scripts/build.sh release wiredem-bench first).
#
# usage: bench/liggghts/packing_physics.sh [--grains N] [--settle-time S] [--seeds "1 2"] [--out DIR] [--no-lammps]
#                                          [--also-kt K]
#   --also-kt K: also settle each lattice in wiredem with the tangential
#   law's k_t = K [1/m] (wiredem-bench --tangential-stiffness), labelled
#   wiredem-ktK: the paper's 1e5 against a spring as stiff as the peers'.
#   defaults: 2000 grains, 0.2 s, seeds 1 and 2 (a few minutes of CPU per
#   run on a quiet machine: wiredem ~30 s, LIGGGHTS and LAMMPS longer).
# environment: LIGGGHTS, LAMMPS (binaries; default liggghts and lmp on PATH),
#              WIREDEM_BENCH, NICE (default 19), KEEP=1 keeps the work directory.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)
grains=2000
settle=0.2
seeds="1 2"
out=
use_lammps=1
also_kt=
while [ $# -gt 0 ]; do
    case $1 in
        --grains) grains=$2; shift 2 ;;
        --settle-time) settle=$2; shift 2 ;;
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
for seed in $seeds; do
    common=(--grains "$grains" --seed "$seed" --steps 1 --threads 1 --integrators verlet --no-wire-membrane --json)
    nice -n "$nice_level" "$bench" "${common[@]}" --settle-time 0 --liggghts-data "$work/lattice.$seed.data" > "$work/lattice.$seed.json"
    dt=$(sed -n 's/.*"time_step_s":\([^,}]*\).*/\1/p' "$work/lattice.$seed.json" | head -n1)
    steps=$(awk -v s="$settle" -v dt="$dt" 'BEGIN { printf "%d", s / dt }')
    echo "seed $seed: δt = $dt s, $steps steps" >&2
    echo "  wiredem" >&2
    nice -n "$nice_level" "$bench" "${common[@]}" --settle-time "$settle" --liggghts-data "$work/wiredem.$seed.data" > /dev/null
    runs+=("wiredem/s$seed=$work/wiredem.$seed.data")
    if [ -n "$also_kt" ]; then
        echo "  wiredem, k_t = $also_kt" >&2
        nice -n "$nice_level" "$bench" "${common[@]}" --settle-time "$settle" --tangential-stiffness "$also_kt" \
            --liggghts-data "$work/wiredem-kt.$seed.data" > /dev/null
        runs+=("wiredem-kt$also_kt/s$seed=$work/wiredem-kt.$seed.data")
    fi
    echo "  LIGGGHTS" >&2
    run_peer "$liggghts" "$here/in.settle" "liggghts.$seed" -var datafile "lattice.$seed.data" -var dt "$dt" \
        -var steps "$steps" -var dumpfile "liggghts.$seed.dump"
    runs+=("LIGGGHTS/s$seed=$work/liggghts.$seed.dump")
    if [ "$use_lammps" = 1 ]; then
        echo "  LAMMPS" >&2
        run_peer "$lammps" "$here/in.settle.lammps" "lammps.$seed" -var datafile "lattice.$seed.data" -var dt "$dt" \
            -var steps "$steps" -var dumpfile "lammps.$seed.dump"
        runs+=("LAMMPS/s$seed=$work/lammps.$seed.dump")
    fi
done

echo "$(date -u '+%Y-%m-%d %H:%M UTC'); $grains grains, $settle s of settling; kinetic energy at the end [J]:"
for seed in $seeds; do
    echo "  seed $seed: LIGGGHTS $(last_kinetic_energy "$work/liggghts.$seed.log")" \
         "$([ "$use_lammps" = 1 ] && echo "LAMMPS $(last_kinetic_energy "$work/lammps.$seed.log")")"
done
extra=()
if [ -n "$out" ]; then
    mkdir -p "$out"
    extra=(--csv "$out/packing_physics.csv" --png "$out/packing_physics.png")
fi
/usr/bin/python3 "$here/packing_physics.py" "${runs[@]}" "${extra[@]}"
