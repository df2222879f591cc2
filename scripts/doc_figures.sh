#!/usr/bin/env bash
# The docs' figures of the main job, remade from a run of it
# (scripts/doc_figures.py says how a doc marks them).
#   bash scripts/doc_figures.sh            run examples/main.json, record its
#                                          summary in docs/figures/main-summary.json
#                                          and rewrite the marked figures of the docs
#   bash scripts/doc_figures.sh --check    run it and change nothing: exit 1 when
#                                          a figure of the docs is not the run's
# The run is `wiredem run` (WIREDEM_BIN, default build/release/bin/wiredem;
# about a minute on 2 quiet cores); its results are the same bit for bit on
# any number of threads, so the check is exact at the printed precision.
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${WIREDEM_BIN:-build/release/bin/wiredem}
docs=(README.md docs/results.md)
out=$(mktemp -d /tmp/wiredem-doc-figures.XXXXXX)
trap 'rm -rf "$out"' EXIT
if ! "$bin" run examples/main.json -o "$out/main" --checkpoint-interval 0 > "$out/run.log" 2>&1; then
  cat "$out/run.log" >&2
  exit 1
fi
if [ "${1:-}" = --check ]; then
  python3 scripts/doc_figures.py --check --summary "$out/main/summary.json" "${docs[@]}"
else
  mkdir -p docs/figures
  cp "$out/main/summary.json" docs/figures/main-summary.json
  python3 scripts/doc_figures.py --summary docs/figures/main-summary.json "${docs[@]}"
fi
