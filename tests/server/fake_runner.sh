#!/usr/bin/env bash
# A stand-in for `wiredem run` that follows the runner contract (docs/api.md)
# without the engine, so the server tests exercise queue, progress, cancel,
# durability and downloads for real and in seconds:
#   fake_runner.sh run JOB.json -o OUTDIR --threads N --progress json --checkpoint-interval S
# prints progress lines, writes OUTDIR/summary.json and OUTDIR/result.h5
# (temp names, then rename), exits 0; stops within a second on SIGTERM (143).
# The job's "name" steers it: fail* exits 3 with a reason on stderr, slow*
# takes three times longer, *burn* keeps N cores busy while it runs; a
# "comment" containing fail-this-point fails it like fail* (a study's points
# differ in their fields, not their names).
# WIREDEM_FAKE_STEP_S (default 0.2) is the pause between progress lines;
# WIREDEM_FAKE_RESULT_DIR (below) a folder whose result files it hands over.
set -u
if [ "${1:-}" != run ]; then echo "fake runner: usage: run JOB.json -o OUTDIR --threads N --progress json" >&2; exit 2; fi
job=$2
shift 2
out=""
threads=1
while [ $# -gt 0 ]; do
  case $1 in
    -o) out=$2; shift 2 ;;
    --threads) threads=$2; shift 2 ;;
    --progress) shift 2 ;;
    --checkpoint-interval) shift 2 ;;
    *) echo "fake runner: unknown argument $1" >&2; exit 2 ;;
  esac
done
[ -n "$out" ] && [ -r "$job" ] || { echo "fake runner: need JOB.json and -o OUTDIR" >&2; exit 2; }
mkdir -p "$out"
name=$(sed -n 's/.*"name":"\([^"]*\)".*/\1/p' "$job")
comment=$(sed -n 's/.*"comment":"\([^"]*\)".*/\1/p' "$job")
case $comment in *fail-this-point*) name="fail: $name" ;; esac
step=${WIREDEM_FAKE_STEP_S:-0.2}
steps=8
case $name in slow*) steps=24 ;; esac

sleeper=""
burners=()
stop() {
  [ -n "$sleeper" ] && kill "$sleeper" 2>/dev/null
  for b in "${burners[@]}"; do kill "$b" 2>/dev/null; done
}
trap 'stop; echo "fake runner: stopped by SIGTERM" >&2; exit 143' TERM INT
nap() { sleep "$1" & sleeper=$!; wait "$sleeper"; sleeper=""; }
emit() { printf '{"stage":"%s","progress":%s,"eta_s":%s,"message":"%s"}\n' "$1" "$2" "$3" "$4"; }

case $name in
  *burn*) for ((t = 0; t < threads; t++)); do (while :; do :; done) & burners+=($!); done ;;
esac

emit preparing 0 null "pouring grains"
nap "$step"
case $name in
  fail*) echo "fake runner: the specimen collapsed while pouring (job name asks for a failure)" >&2; exit 3 ;;
esac
for ((i = 1; i <= steps; i++)); do
  if ((i <= steps / 2)); then stage=preparing; else stage=testing; fi
  p=$(awk -v i="$i" -v n="$steps" 'BEGIN { printf "%.3f", i / (n + 2) }')
  eta=$(awk -v i="$i" -v n="$steps" -v s="$step" 'BEGIN { printf "%.2f", (n + 2 - i) * s }')
  emit "$stage" "$p" "$eta" "step $i of $steps"
  # The free-standing test's file (WIREDEM_FAKE_RESULT_DIR/free_standing.h5)
  # appears three quarters through, as the runner's tests/free_standing.h5,
  # and stays there for twenty steps of the job's running.
  if ((i == 3 * steps / 4)) && [ -n "${WIREDEM_FAKE_RESULT_DIR:-}" ] && [ -f "$WIREDEM_FAKE_RESULT_DIR/free_standing.h5" ]; then
    mkdir -p "$out/tests"
    cp "$WIREDEM_FAKE_RESULT_DIR/free_standing.h5" "$out/tests/free_standing.h5.tmp"
    mv "$out/tests/free_standing.h5.tmp" "$out/tests/free_standing.h5"
    nap "$(awk -v s="$step" 'BEGIN { print 20 * s }')"  # long enough for a poll to see it while the job runs
  fi
  nap "$step"
done
emit analysing 0.9 0.4 "fitting Mohr-Coulomb"
nap "$step"
emit writing 0.95 0.2 "writing result.h5"
stop

# WIREDEM_FAKE_RESULT_DIR: copy its result.h5 (and result.xdmf) instead of
# writing a stand-in, so the result data routes read a real HDF5 file.
if [ -n "${WIREDEM_FAKE_RESULT_DIR:-}" ]; then
  cp "$WIREDEM_FAKE_RESULT_DIR/result.h5" "$out/result.h5.tmp"
  [ -f "$WIREDEM_FAKE_RESULT_DIR/result.xdmf" ] && cp "$WIREDEM_FAKE_RESULT_DIR/result.xdmf" "$out/result.xdmf"
else
  seq 1 50000 > "$out/result.h5.tmp"
fi
cat > "$out/summary.json.tmp" <<JSON
{"job": "${name//[\\\"]/}",
 "tests": [
  {"confining_pressure_pa": 20000, "peak_deviatoric_stress_pa": 81234.5, "peak_axial_strain": 0.0412, "sigma1_pa": 101234.5, "sigma3_effective_pa": 20000},
  {"confining_pressure_pa": 40000, "peak_deviatoric_stress_pa": 152000.25, "peak_axial_strain": 0.0533, "sigma1_pa": 192000.25, "sigma3_effective_pa": 40000},
  {"confining_pressure_pa": 60000, "peak_deviatoric_stress_pa": 219876, "peak_axial_strain": 0.0611, "sigma1_pa": 279876, "sigma3_effective_pa": 60000}
 ],
 "mohr_coulomb": {"friction_angle_deg": 41.25, "cohesion_pa": 3150.5, "r_squared": 0.9987},
 "specimen": {"grain_volume_fraction": 0.6123, "wire_volume_fraction": 0.0084, "sample_volume_m3": 0.000150796, "grains": 8000, "wire_nodes": 3210},
 "wire": {"autocorrelation_lag_m": 0.0123},
 "warnings": ["fake runner: numbers are made up"],
 "engine": {"time_step_s": 1.2e-06, "steps": 123456, "wall_time_s": 12.5, "body_steps_per_second": 2500000.0}}
JSON
mv "$out/result.h5.tmp" "$out/result.h5"
mv "$out/summary.json.tmp" "$out/summary.json"
exit 0
