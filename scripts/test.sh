#!/usr/bin/env bash
# Installs what is missing, lints the container files, builds and runs the
# test suite: every test in Release (the Slurm executor's among them, on a
# single-node cluster the test starts: label slurm) but the study-scale run
# (label study_scale: tests/CMakeLists.txt says how to run it); then, built
# with clang under AddressSanitizer + UndefinedBehaviorSanitizer with -Werror
# and without precompiled headers (scripts/build.sh asan: that build is also
# the check that every file compiles clang-clean and includes what it uses),
# every test but the Python ones (label scripts: the report script's, and the
# package's, python/, which also has the label python), the benchmark's
# smoke run (label bench: a timing case, run in Release), the Slurm
# cluster's (label slurm: its pieces run there in the server's unit tests) and
# the long physical runs (label physics_long: whole column preparations and
# the end-to-end triaxial runs, a minute or two each under ASan, whose code
# the sanitizer run still goes through in the determinism and campaign
# tests); then under ThreadSanitizer the threaded engine tests, the server and
# the campaign's scheduler (a `wiredem run` of three tests on two threads);
# then the fuzz targets of the same ASan build, each for 30 s (scripts/fuzz.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh

jobs=$(nproc)
# Each phase is announced with the seconds since the start, so a CI log shows
# where the run's time goes (CI allows 90 min; the run should stay near 30).
phase() { echo "== $* (at $SECONDS s)"; }
phase "lint: container files"
bash scripts/lint-docker.sh
for variant in release asan; do
  phase "build: $variant"
  bash scripts/build.sh "$variant"
done
# The README's plain build uses CMake's default generator (Makefiles), whose
# custom commands differ from Ninja's (a working directory is not made for
# them): configured that way and its custom-command target built, the npm
# step (seconds; a whole second build would cost a Release build's time).
phase "build: default generator (configure, and the web page's custom commands)"
cmake -S . -B build/makefiles -G "Unix Makefiles" -DCMAKE_BUILD_TYPE=Release > build/makefiles.log 2>&1 \
  || { cat build/makefiles.log; exit 1; }
if grep -q '^wiredem_web:' build/makefiles/Makefile; then
  cmake --build build/makefiles --target wiredem_web >> build/makefiles.log 2>&1 || { cat build/makefiles.log; exit 1; }
fi
# ThreadSanitizer only for the threaded code: the engine's thread pool and
# determinism tests, and the server with the client it is driven through.
phase "tsan"
bash scripts/build.sh tsan wiredem_threaded_tests wiredem_server_tests wiredem_client_display_tests wiredem-server wiredem \
  wiredem_stages_tests

# The SIMD paths this CPU has, read here from /proc/cpuinfo rather than by
# the engine: a path the CPU has that the engine does not take fails the
# determinism tests (Simd.EveryPathTheCpuHasIsTested) instead of skipping.
required_simd=""
if grep -qw avx2 /proc/cpuinfo; then required_simd=avx2; fi
if grep -qw avx512f /proc/cpuinfo && grep -qw avx512vl /proc/cpuinfo && grep -qw avx512bw /proc/cpuinfo; then
  required_simd="$required_simd,avx512"
fi
export WIREDEM_REQUIRE_SIMD=${required_simd#,}

phase "tests (release)"
ctest --test-dir build/release --output-on-failure -j "$jobs" -LE study_scale
phase "tests (address + undefined behaviour sanitizers)"
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --test-dir build/asan --output-on-failure -j "$jobs" -LE "physics_long|study_scale|scripts|slurm|bench"
phase "tests (thread sanitizer: the threaded engine code and the server)"
TSAN_OPTIONS=halt_on_error=1 ctest --test-dir build/tsan --output-on-failure -j "$jobs" -L "threaded|server"
# The campaign's own scheduler (campaign/stages.cpp: tests at once, threads
# handed over as tests end, a test continued on more threads): the TSan
# `wiredem run` of three tests on two threads, which fails on any report.
phase "tests (thread sanitizer: the campaign's scheduler)"
TSAN_OPTIONS=halt_on_error=1 build/tsan/tests/campaign/wiredem_stages_tests \
  --gtest_filter=Stages.ATestTakesTheThreadsOfTheTestsThatEnded
phase "fuzzing (libFuzzer, ASan + UBSan: each target 30 s, docs/fuzzing.md)"
bash scripts/fuzz.sh
echo "== done in $SECONDS s"
