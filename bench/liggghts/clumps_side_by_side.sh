#!/usr/bin/env bash
# wiredem's clumps against LIGGGHTS' fix multisphere on a settled packing of
# clumps (issue 40, part 5: "wiredem stays at least 3x LIGGGHTS' multisphere
# per core"; bench/README.md, "Clumps against LIGGGHTS' multisphere").
#
# 1. wiredem-bench --clumps SHAPE --grains N settles N clumps of a built-in
#    shape (volume-equivalent radius 1.23 mm, turned at random) in the
#    bench's container (floor z = 0, cylinder r = 20 mm) for 0.2 s, times
#    STEPS steps on one thread with each integrator, and writes the settled
#    spheres (--liggghts-data) and the first clump's spheres in its body
#    frame (--clump-template): the template, as the engine holds it;
# 2. LIGGGHTS pours N clumps of the same template (particletemplate/
#    multisphere, reading that template) at random orientations into the same
#    container, lets them settle for the same simulated time with the same
#    δt (in.multisphere_settle) and writes a restart; then it times STEPS steps
#    on that packing from the restart (in.multisphere_time), and 0 steps: the
#    CPU time of the difference, without reading and set-up;
# 3. one table: CPU time, sphere-steps per CPU second, and wiredem's per core
#    against LIGGGHTS'.
#
# Both beds are settled from each code's own start (wiredem: a jittered
# lattice; LIGGGHTS: random insertion between 2 and 50 mm), so they are two
# samples of the same bed, not one packing: the contacts per sphere are
# printed for both. Laws as in in.bench (Hertz, Coulomb μ = 0.3, e = 0.5,
# walls E = 1 GPa); the tangential laws differ as in.bench states.
#
# usage: bench/liggghts/clumps_side_by_side.sh [--shape SHAPE] [--grains N] [--steps STEPS] [--reps R]
#   defaults: tetrahedral, 500 clumps, 2000 steps, 3 timed repetitions each
# environment: as peers.sh: WIREDEM_BENCH, LIGGGHTS, NICE (default 19: both codes
# run at it; CPU times hardly depend on it), KEEP=1.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)
shape=tetrahedral grains=500 steps=2000 reps=3
while [ $# -gt 0 ]; do
    case $1 in
        --shape) shape=$2; shift 2 ;;
        --grains) grains=$2; shift 2 ;;
        --steps) steps=$2; shift 2 ;;
        --reps) reps=$2; shift 2 ;;
        -h|--help) awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "$0"; exit 0 ;;
        *) echo "unknown argument: $1 (try --help)" >&2; exit 2 ;;
    esac
done
use_lammps=0
. "$here/peers.sh" # bench, liggghts, nice_level, work, run_peer, field
settle_s=0.2

# --- wiredem ---------------------------------------------------------------
threads=$(seq -s, "$reps" | sed 's/[0-9][0-9]*/1/g') # "1,1,1": each run from the same settled packing
echo "running: $bench --clumps $shape --grains $grains --threads $threads (settling $settle_s s, then $steps steps per run)" >&2
nice -n "$nice_level" "$bench" --clumps "$shape" --grains "$grains" --settle-time "$settle_s" --threads "$threads" --steps "$steps" \
    --no-wire-membrane --json --liggghts-data "$work/wiredem.data" --clump-template "$work/clump.spheres" > "$work/wiredem.json"
dt=$(head -n1 "$work/wiredem.json" | field time_step_s)
spheres=$(head -n1 "$work/wiredem.json" | field bodies)
nsph=$(wc -l < "$work/clump.spheres")
radius=$(awk '{ if ($4 > r) r = $4 } END { print r }' "$work/clump.spheres") # the largest sphere's

# --- LIGGGHTS --------------------------------------------------------------
settle_steps=$(awk -v t="$settle_s" -v dt="$dt" 'BEGIN { printf "%d", t / dt }')
# wiredem's skin (engine/step.cpp, effective_skin_m): 0.2 x the largest sphere's radius.
common=(-var skin "$(awk -v r="$radius" 'BEGIN { print 0.2 * r }')" -var dt "$dt")
echo "running: $liggghts -in in.multisphere_settle ($grains clumps, $settle_steps steps)" >&2
run_peer "$liggghts" "$here/in.multisphere_settle" settle "${common[@]}" -var clumpfile clump.spheres \
    -var nspheres "$nsph" -var clumps "$grains" -var steps "$settle_steps" -var restart settled.restart
ligg_cpu() { # ligg_cpu STEPS: CPU seconds of a run of STEPS steps from the restart
    (cd "$work" && /usr/bin/time -f "%U %S" -o time.$1 nice -n "$nice_level" "$liggghts" -in "$here/in.multisphere_time" "${common[@]}" \
        -var restart settled.restart -var steps "$1" -log time.$1.log > time.$1.out 2>&1) ||
        { tail -n 30 "$work/time.$1.out" >&2; exit 1; }
    awk '{ print $1 + $2 }' "$work/time.$1"
}
ligg_rows=()
for r in $(seq "$reps"); do
    c0=$(ligg_cpu 0)
    c1=$(ligg_cpu "$steps")
    ligg_rows+=("$(awk -v a="$c1" -v b="$c0" 'BEGIN { print a - b }')")
done
ligg_atoms=$(sed -n 's/^Loop time of .* with \([0-9]*\) atoms.*/\1/p' "$work/time.$steps.log" | head -n1)
ligg_neighs=$(sed -n 's/^Ave neighs\/atom = //p' "$work/time.$steps.log" | tail -n1)

# --- table -----------------------------------------------------------------
echo
echo "$(date -u '+%Y-%m-%d %H:%M UTC'); load average $(cut -d' ' -f1-3 /proc/loadavg); $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//')"
echo "$grains $shape clumps ($nsph spheres of $radius m each; wiredem $spheres spheres, LIGGGHTS ${ligg_atoms:-?} atoms), settled $settle_s s, δt = $dt s, $steps steps timed on one core"
echo "contacts per sphere: wiredem $(head -n1 "$work/wiredem.json" | field contacts) / $spheres; LIGGGHTS neighbours per atom ${ligg_neighs:-?} (its list, skin included)"
{
    while read -r line; do
        echo "wiredem/$(echo "$line" | field integrator) $(echo "$line" | field cpu_time_s)"
    done < "$work/wiredem.json"
    for c in "${ligg_rows[@]}"; do echo "LIGGGHTS/multisphere $c"; done
} | awk -v n="$spheres" -v s="$steps" '
    { name[NR] = $1; cpu[NR] = $2; if (!($1 in best) || $2 < best[$1]) best[$1] = $2 }
    END {
      printf "%-22s %10s %20s\n", "engine", "cpu [s]", "sphere-steps/CPU-s"
      for (i = 1; i <= NR; ++i) printf "%-22s %10.3f %20.4g\n", name[i], cpu[i], n * s / cpu[i]
      l = best["LIGGGHTS/multisphere"]
      for (e in best) if (e != "LIGGGHTS/multisphere" && l > 0)
        printf "best of %s against best of LIGGGHTS/multisphere: %.2fx per core\n", e, l / best[e]
    }'
