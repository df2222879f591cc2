#!/usr/bin/env bash
# Builds the libFuzzer targets (tests/fuzz: clang, ASan + UBSan) in
# build/asan and runs each for a fixed time, or a fixed number of inputs;
# fails when any target finds a crash or a property violation (the input is
# then in build/asan/fuzz/artifacts/, reproduce with `build/asan/tests/fuzz/TARGET FILE`).
# docs/fuzzing.md describes the targets.
#
#   scripts/fuzz.sh [-t SECONDS] [-n RUNS] [-j PARALLEL] [TARGET ...]
#     -t SECONDS   time per target (default 30)
#     -n RUNS      inputs per target instead of a time (e.g. 1000000)
#     -j PARALLEL  targets run at once (default: the number of cores)
#     TARGET       some of the targets (default: all)
#
# Each target keeps its working corpus in build/asan/fuzz/corpus/TARGET (it grows
# from run to run) and starts from its seeds (examples/*.json, tests/fuzz/seeds/)
# with its dictionary (tests/fuzz/*.dict).
set -euo pipefail
cd "$(dirname "$0")/.."

seconds=30
runs=""
parallel=$(nproc)
while getopts "t:n:j:" opt; do
  case "$opt" in
    t) seconds=$OPTARG ;;
    n) runs=$OPTARG ;;
    j) parallel=$OPTARG ;;
    *) echo "usage: scripts/fuzz.sh [-t SECONDS] [-n RUNS] [-j PARALLEL] [TARGET ...]" >&2; exit 2 ;;
  esac
done
shift $((OPTIND - 1))
all=(fuzz_job_spec_text fuzz_job_spec_values fuzz_http_request fuzz_request_parsers fuzz_progress_line fuzz_result_file)
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=("${all[@]}")

# The fuzz targets live in the ASan + UBSan build (scripts/build.sh asan:
# clang, libFuzzer's coverage on every library), beside the tests; only they
# and the libraries they link are built here.
bash scripts/build.sh asan "${targets[@]}"
bin=build/asan/tests/fuzz
work=build/asan/fuzz

seeds_of() {  # the read-only seed folders of a target
  case "$1" in
    fuzz_job_spec_text) echo examples tests/fuzz/seeds/job_spec ;;
    fuzz_progress_line) echo tests/fuzz/seeds/progress_line ;;
    fuzz_http_request) echo tests/fuzz/seeds/http_request ;;
    fuzz_request_parsers) echo tests/fuzz/seeds/request_parsers ;;
    *) ;;  # the value and result-file targets build their documents from the input's choices
  esac
}
dict_of() {
  case "$1" in
    fuzz_job_spec_text|fuzz_progress_line) echo -dict=tests/fuzz/json.dict ;;
    fuzz_http_request|fuzz_request_parsers) echo -dict=tests/fuzz/http.dict ;;
    *) ;;
  esac
}

options_of() {
  case "$1" in
    # The job store keeps what each accepted job allocates: libFuzzer's
    # per-input leak check then scans the whole heap after nearly every
    # input (27 inputs/s instead of ~600). LeakSanitizer still checks the
    # process at exit.
    fuzz_http_request) echo -detect_leaks=0 ;;
    # Its input is a list of changes (a few bytes each, up to 8 per
    # document): full-length inputs from the start, for combinations.
    fuzz_job_spec_values) echo -detect_leaks=0 -max_len=256 -len_control=0 ;;
    *) ;;
  esac
}

limit=(-max_total_time="$seconds")
[ -z "$runs" ] || limit=(-runs="$runs")
mkdir -p "$work/artifacts" "$work/logs"
run_one() {
  local t=$1
  mkdir -p "$work/corpus/$t"
  # -timeout: an input that takes this long is a hang (the validation bound is
  # far below it); -rss_limit_mb: the default 2 GB, stated.
  if "$bin/$t" "${limit[@]}" -timeout=60 -rss_limit_mb=2048 -print_final_stats=1 \
      -artifact_prefix="$work/artifacts/$t-" $(dict_of "$t") $(options_of "$t") "$work/corpus/$t" $(seeds_of "$t") \
      >"$work/logs/$t.log" 2>&1; then
    echo "fuzz: $t: ok, $(grep -o 'Done [0-9]* runs in [0-9]* second(s)' "$work/logs/$t.log" | tail -1)" \
      "$(grep -o 'slowest validation.*' "$work/logs/$t.log" | tail -1)"
  else
    echo "fuzz: $t: FAILED ($work/logs/$t.log; input in $work/artifacts/$t-*)"
    grep -m1 -A12 -E 'ERROR|property violated|runtime error' "$work/logs/$t.log" | head -30
    return 1
  fi
}

failed=0
pids=()
names=()
for t in "${targets[@]}"; do
  while [ "$(jobs -rp | wc -l)" -ge "$parallel" ]; do sleep 1; done
  run_one "$t" &
  pids+=($!)
  names+=("$t")
done
for i in "${!pids[@]}"; do
  wait "${pids[$i]}" || failed=1
done
exit $failed
