#!/usr/bin/env bash
# Installs what wiredem needs to build and test, from Debian 12 packages.
# Idempotent: installs only what is missing. Run as root.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config
  libeigen3-dev libhdf5-dev hdf5-tools
  libboost1.81-dev libboost-json1.81-dev libboost-url1.81-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libcli11-dev libspdlog-dev libfmt-dev libsqlite3-dev
  sqlite3                                         # the server tests forge a damaged store with it
  python3-numpy python3-h5py python3-matplotlib   # scripts/study_report.py and its test
  python3-pandas python3-pytest python3-mypy python3-setuptools python3-pip python3-venv  # the Python package (python/) and its tests
  python3-yaml                                    # scripts/lint-docker.sh checks compose.yaml
  chromium                                        # the web page's browser test (tests/web/), headless
  # scripts/build.sh asan and clang, scripts/fuzz.sh: clang, and its libFuzzer and
  # sanitizer runtimes (libclang_rt.fuzzer, .asan, .ubsan_standalone), which
  # are only recommended by clang-14, and apt-get here skips recommendations.
  clang libclang-rt-14-dev
)
# scripts/lint-docker.sh runs dockerfilelint with npx, and the build installs
# the web page's libraries with npm ci (web/package-lock.json): Debian's npm
# where no npx is on the PATH (a machine may bring its own Node.js).
command -v npx >/dev/null || packages+=(npm)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
