#!/usr/bin/env bash
# Installs what is missing, builds and runs the whole test suite: Release,
# then AddressSanitizer + UndefinedBehaviorSanitizer, then ThreadSanitizer on
# the threaded tests.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh

jobs=$(nproc)
for variant in release asan tsan; do
  echo "== $variant"
  bash scripts/build.sh "$variant"
done

echo "== tests (release)"
ctest --test-dir build/release --output-on-failure -j "$jobs" -LE threaded
echo "== tests (address + undefined behaviour sanitizers)"
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --test-dir build/asan --output-on-failure -j "$jobs" -LE threaded
echo "== tests (thread sanitizer: the threaded code)"
TSAN_OPTIONS=halt_on_error=1 ctest --test-dir build/tsan --output-on-failure -j "$jobs" -L threaded
