#!/usr/bin/env bash
# Installs what is missing, lints the container files, builds and runs the
# whole test suite: Release,
# then AddressSanitizer + UndefinedBehaviorSanitizer, then ThreadSanitizer on
# the threaded tests.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh

jobs=$(nproc)
echo "== lint: container files"
bash scripts/lint-docker.sh
for variant in release asan; do
  echo "== $variant"
  bash scripts/build.sh "$variant"
done
# ThreadSanitizer only for the threaded code: the engine's thread pool and
# determinism tests, and the server with the client it is driven through.
echo "== tsan"
bash scripts/build.sh tsan wiredem_engine_tests wiredem_server_tests wiredem_client_display_tests wiredem-server wiredem

echo "== tests (release)"
ctest --test-dir build/release --output-on-failure -j "$jobs" -LE threaded
echo "== tests (address + undefined behaviour sanitizers)"
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --test-dir build/asan --output-on-failure -j "$jobs" -LE threaded
echo "== tests (thread sanitizer: the threaded engine code and the server)"
TSAN_OPTIONS=halt_on_error=1 ctest --test-dir build/tsan --output-on-failure -j "$jobs" -L "threaded|server"
