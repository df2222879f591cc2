#!/usr/bin/env bash
# Configures and builds one variant into build/<variant>.
#   scripts/build.sh release|asan|tsan [target ...]
set -euo pipefail
cd "$(dirname "$0")/.."
variant=${1:-release}
shift || true
targets=()
for t in "$@"; do targets+=(--target "$t"); done
case "$variant" in
  release) args=(-DCMAKE_BUILD_TYPE=Release) ;;
  asan)    args=(-DCMAKE_BUILD_TYPE=RelWithDebInfo -DWIREDEM_SANITIZE=address,undefined -DWIREDEM_BUILD_BENCH=OFF) ;;
  tsan)    args=(-DCMAKE_BUILD_TYPE=RelWithDebInfo -DWIREDEM_SANITIZE=thread -DWIREDEM_BUILD_BENCH=OFF) ;;
  *) echo "build.sh: unknown variant '$variant' (release, asan, tsan)" >&2; exit 2 ;;
esac
cmake -S . -B "build/$variant" -G Ninja "${args[@]}" >/dev/null
cmake --build "build/$variant" --parallel "$(nproc)" "${targets[@]}"
