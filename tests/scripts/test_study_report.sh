#!/usr/bin/env bash
# Tests of scripts/study_report.py (tests/scripts/test_study_report.py) on a
# synthetic RUNS tree, with Debian's python3 and its numpy, pandas, h5py and
# matplotlib (the report's only dependencies, with the wiredem package of
# python/) and the wiredem binary for the wire's R ($WIREDEM_BIN: ctest passes
# the build's). A few seconds; exit status non-zero on failure.
#
#   bash tests/scripts/test_study_report.sh
set -euo pipefail
cd "$(dirname "$0")"
exec /usr/bin/python3 -m unittest -v test_study_report
