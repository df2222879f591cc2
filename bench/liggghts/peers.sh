# Shared by the cross-code scripts: packing_physics.sh and heap_physics.sh
# (issue 43 §4), side_by_side.sh and clumps_side_by_side.sh (the timings)
# source it after parsing their arguments. It finds the three
# codes and makes the work directory; its functions run a peer's deck and read
# its log.
#
# on entry: here (this directory), root (the repository), use_lammps (1 to use LAMMPS if found)
# sets:     bench, liggghts, lammps, use_lammps (0 with a note when LAMMPS is missing),
#           nice_level, work (removed at exit unless KEEP=1)
# environment: WIREDEM_BENCH, LIGGGHTS, LAMMPS (binaries; default
#              build/release/bench/wiredem-bench, liggghts and lmp on PATH),
#              NICE (default 19), KEEP=1 keeps the work directory.
# functions: run_peer, last_kinetic_energy, last_atoms, field (below)

bench=${WIREDEM_BENCH:-$root/build/release/bench/wiredem-bench}
[ -x "$bench" ] || { echo "no $bench: build it first with 'bash scripts/build.sh release wiredem-bench'" >&2; exit 1; }
liggghts=${LIGGGHTS:-$(command -v liggghts || true)}
[ -n "$liggghts" ] || { echo "no LIGGGHTS binary: apt-get install liggghts, or set LIGGGHTS=" >&2; exit 1; }
lammps=${LAMMPS:-$(command -v lmp || true)}
if [ "$use_lammps" = 1 ] && [ -z "$lammps" ]; then
    echo "note: no LAMMPS binary (apt-get install lammps, or set LAMMPS=): left out" >&2
    use_lammps=0
fi
nice_level=${NICE:-19}

work=$(mktemp -d /tmp/wiredem-peers.XXXXXX)
if [ "${KEEP:-0}" = 1 ]; then echo "work directory: $work" >&2; else trap 'rm -rf "$work"' EXIT; fi

# run_peer BINARY DECK TAG [-var NAME VALUE ...]: runs the deck in the work
# directory at the nice level, log TAG.log, screen TAG.out; on failure shows
# the screen's end and exits.
run_peer() {
    local binary=$1 deck=$2 tag=$3
    shift 3
    (cd "$work" && nice -n "$nice_level" "$binary" -in "$deck" "$@" -log "$tag.log" > "$tag.out" 2>&1) ||
        { tail -n 20 "$work/$tag.out" >&2; exit 1; }
}

# last_kinetic_energy LOG: the kinetic energy of the thermo output's last row
# (thermo_style custom step atoms ke) [J].
last_kinetic_energy() {
    awk '/^ *Step/ { on = 1; next } on && NF == 3 && $1 ~ /^[0-9]+$/ { ke = $3 } END { print ke }' "$1"
}

# last_atoms LOG: the atoms left at the thermo output's last row (a peer drops
# a grain that leaves its box).
last_atoms() {
    awk '/^ *Step/ { on = 1; next } on && NF == 3 && $1 ~ /^[0-9]+$/ { n = $2 } END { print n }' "$1"
}

# field NAME < one JSON line (wiredem-bench --json): the value of a top-level
# number or string field. The stage_s object goes first: its stage
# "contacts" would match.
field() {
    sed 's/,"stage_s":{[^}]*}//' | sed -n "s/.*\"$1\":\"\{0,1\}\([^\",}]*\).*/\1/p"
}
