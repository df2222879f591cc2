#!/usr/bin/env bash
# Configures and builds one variant into build/<variant>.
#   scripts/build.sh release|asan|tsan|clang [target ...]
# release: GCC with -Werror, the programs, tests, benchmarks and web page.
# asan: Debian's clang (14) with AddressSanitizer + UndefinedBehaviorSanitizer
#   and libFuzzer's coverage: the tests and the fuzz targets (tests/fuzz,
#   scripts/fuzz.sh) in one tree, and with -Werror and without precompiled
#   headers, the check that every file (benchmarks and demo included) compiles
#   -Wall -Wextra clean with clang as with GCC and includes what it uses (a
#   precompiled header would hide a missing include). One build instead of
#   three (GCC ASan, clang -fsyntax-only over every file, clang fuzz build):
#   621 s instead of about 1340 s on 2 cores.
# tsan: GCC with ThreadSanitizer, for the threaded code.
# clang: a Release build with clang and -Werror, into build/clang.
set -euo pipefail
cd "$(dirname "$0")/.."
variant=${1:-release}
shift || true
targets=()
for t in "$@"; do targets+=(--target "$t"); done
# The sanitizer builds compile at -O1 with line tables only (-g1,
# clang's -gline-tables-only): about half the compile time of -O2 -g
# (measured on server/session.cpp under ASan: 143 s → 75 s of CPU), still
# with file:line in every sanitizer report. The engine library itself stays
# at -O2 (engine/CMakeLists.txt): the tests run in it; the server and the
# client's network side go down to -O0 (CMakeLists.txt,
# wiredem_compile_fast_under_sanitizers): they wait on sockets. Neither
# builds the web page (its browser test runs against the Release server);
# the TSan build neither the benchmarks nor the demo, which no test runs.
# -DNDEBUG keeps the standard library's and Eigen's own checks out, but
# WIREDEM_ASSERTIONS keeps the engine's WIREDEM_ASSERT in (engine/core/
# assert.hpp): the tests run with the engine's contracts checked.
sanitizer_flags=(-DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1 -DNDEBUG -DWIREDEM_ASSERTIONS"
  -DWIREDEM_BUILD_BENCH=OFF -DWIREDEM_BUILD_APPS=OFF -DWIREDEM_BUILD_WEB=OFF)
case "$variant" in
  release) args=(-DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS=-Werror) ;;
  asan)    args=(-DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -gline-tables-only -DNDEBUG -DWIREDEM_ASSERTIONS"
                 -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_CXX_FLAGS=-Werror -DWIREDEM_PCH=OFF
                 -DWIREDEM_SANITIZE=address,undefined -DWIREDEM_FUZZ=ON -DWIREDEM_BUILD_WEB=OFF) ;;
  tsan)    args=("${sanitizer_flags[@]}" -DWIREDEM_SANITIZE=thread) ;;
  clang)   args=(-DCMAKE_BUILD_TYPE=Release -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_CXX_FLAGS=-Werror) ;;
  *) echo "build.sh: unknown variant '$variant' (release, asan, tsan, clang)" >&2; exit 2 ;;
esac
# A tree configured with another compiler (build/asan was GCC's until
# 2026-12-03) is configured afresh: CMake cannot switch a cache's compiler.
want=c++
case " ${args[*]} " in *" -DCMAKE_CXX_COMPILER=clang++ "*) want=clang++ ;; esac
cache="build/$variant/CMakeCache.txt"
if [ -f "$cache" ] && ! grep -q "^CMAKE_CXX_COMPILER:[A-Z]*=.*/$want\$" "$cache"; then
  echo "build.sh: build/$variant was configured with another compiler: configuring it afresh"
  rm -rf "build/$variant"
fi
cmake -S . -B "build/$variant" -G Ninja "${args[@]}" >/dev/null
cmake --build "build/$variant" --parallel "$(nproc)" "${targets[@]}"
