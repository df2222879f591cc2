#!/usr/bin/env bash
# Runs the Slurm suite (tests/slurm/test_slurm_cluster.cpp) against a
# single-node cluster of its own (scripts/slurm-cluster.sh, in a temporary
# directory on a port of its own), which is stopped however the suite ends.
#   tests/slurm/run.sh WIREDEM_SLURM_TESTS_BINARY [gtest options]
set -euo pipefail
# The cluster needs root (munged runs as user munge, slurmd runs jobs as
# their user); elsewhere the suite is skipped, said so (ctest: SKIP_RETURN_CODE).
if [[ $(id -u) != 0 ]]; then
  echo "skipped: a Slurm cluster on this machine needs root (CI runs as root)" >&2
  exit 77
fi
here=$(cd "$(dirname "$0")" && pwd)
cluster=$here/../../scripts/slurm-cluster.sh
export WIREDEM_SLURM_DIR
WIREDEM_SLURM_DIR=$(mktemp -d "${TMPDIR:-/tmp}/wiredem-slurm-test.XXXXXX")
# Away from a cluster a user started with the script's default port (6817).
export WIREDEM_SLURM_PORT=${WIREDEM_SLURM_TEST_PORT:-16817}
cleanup() {
  bash "$cluster" stop || true
  rm -rf "$WIREDEM_SLURM_DIR"
}
trap cleanup EXIT
trap 'exit 130' INT TERM
eval "$(bash "$cluster" start)"   # export SLURM_CONF=…
"$@"
