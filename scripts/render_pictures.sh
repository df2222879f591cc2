#!/usr/bin/env bash
# Renders docs/pictures/<pattern>.png for the four wire patterns (docs/pictures.md):
# runs each job file docs/pictures/<pattern>.json with `wiredem run` (which also
# writes the XDMF sidecar), then draws the specimen from result.xdmf with ParaView.
#
#   bash scripts/render_pictures.sh [--reuse] [--wiredem PATH] [PATTERN ...]
#
# PATTERN: none, helix, spiral_helix, radial_helix (default: all four). --wiredem:
# the client binary (default build/release/bin/wiredem). --reuse keeps a result
# already in build/pictures/<pattern>/ and only renders it.
# Needs Debian's paraview and xvfb (apt-get install paraview xvfb): for the docs
# only, deliberately not in scripts/setup.sh or CI.
set -euo pipefail
cd "$(dirname "$0")/.."

reuse=0
wiredem=build/release/bin/wiredem
patterns=()
while [[ $# -gt 0 ]]; do
    case "$1" in
        --reuse) reuse=1 ;;
        --wiredem) wiredem="$2"; shift ;;
        none|helix|spiral_helix|radial_helix) patterns+=("$1") ;;
        *) echo "usage: $0 [--reuse] [--wiredem PATH] [none|helix|spiral_helix|radial_helix ...]" >&2; exit 2 ;;
    esac
    shift
done
[[ ${#patterns[@]} -gt 0 ]] || patterns=(none helix spiral_helix radial_helix)
runs=build/pictures

for tool in pvbatch xvfb-run; do
    command -v "$tool" >/dev/null || { echo "render_pictures: $tool not found (apt-get install paraview xvfb)" >&2; exit 1; }
done

for pattern in "${patterns[@]}"; do
    job="docs/pictures/$pattern.json"
    out="$runs/$pattern"
    if [[ $reuse == 0 || ! -f "$out/result.xdmf" ]]; then
        [[ -x "$wiredem" ]] || { echo "render_pictures: no wiredem binary at $wiredem" >&2; exit 1; }
        echo "== $pattern: wiredem run $job"
        "$wiredem" run "$job" -o "$out" --threads 0
    fi
    # the wire's contact radius from the job file (default 0.5 mm), for the tube
    radius=$(/usr/bin/python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["specimen"]["wire"].get("radius_m", 5e-4))' "$job")
    echo "== $pattern: rendering docs/pictures/$pattern.png"
    xvfb-run -a pvbatch scripts/render_pictures.py "$out/result.xdmf" "docs/pictures/$pattern.png" \
        "wire pattern: $pattern" "$radius"
done
