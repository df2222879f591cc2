#!/usr/bin/env bash
# Configures and builds one variant into build/<variant>.
#   scripts/build.sh release|asan|tsan|clang [target ...]
# clang: a Release build with Debian's clang (/usr/bin/clang++) instead of
# GCC, into build/clang, with -Werror: both compilers must build the project
# -Wall -Wextra clean, and this variant is there to keep it so (the fuzz
# targets, scripts/fuzz.sh, need clang's libFuzzer).
set -euo pipefail
cd "$(dirname "$0")/.."
variant=${1:-release}
shift || true
targets=()
for t in "$@"; do targets+=(--target "$t"); done
# The sanitizer builds compile at -O1 with line tables only (-g1): about half
# the compile time of -O2 -g (measured on server/session.cpp under ASan:
# 143 s → 75 s of CPU), still with file:line in every sanitizer report. They
# build neither the benchmarks nor the demo, which no test runs, nor the web
# page (its browser test runs against the Release server). The engine
# library itself stays at -O2 (engine/CMakeLists.txt): the tests run in it;
# the server and the client's network side go down to -O0 (CMakeLists.txt,
# wiredem_compile_fast_under_sanitizers): they wait on sockets.
sanitizer_flags=(-DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1 -DNDEBUG"
  -DWIREDEM_BUILD_BENCH=OFF -DWIREDEM_BUILD_APPS=OFF -DWIREDEM_BUILD_WEB=OFF)
case "$variant" in
  release) args=(-DCMAKE_BUILD_TYPE=Release) ;;
  asan)    args=("${sanitizer_flags[@]}" -DWIREDEM_SANITIZE=address,undefined) ;;
  tsan)    args=("${sanitizer_flags[@]}" -DWIREDEM_SANITIZE=thread) ;;
  clang)   args=(-DCMAKE_BUILD_TYPE=Release -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_CXX_FLAGS=-Werror) ;;
  *) echo "build.sh: unknown variant '$variant' (release, asan, tsan, clang)" >&2; exit 2 ;;
esac
cmake -S . -B "build/$variant" -G Ninja "${args[@]}" >/dev/null
cmake --build "build/$variant" --parallel "$(nproc)" "${targets[@]}"
