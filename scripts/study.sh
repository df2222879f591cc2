#!/usr/bin/env bash
# The full-size study (docs/study.md): the paper's column with each wire
# pattern, several seeds, every campaign run with `wiredem run`, and each
# campaign's summary.json gathered into docs/study/ (small files, kept in git
# so the report can be checked and re-plotted; the result.h5 files stay in the
# run folder).
#
#   bash scripts/study.sh [--jobs N] [--threads T] [--runs DIR] [--wiredem PATH]
#                         [--patterns "none helix ..."] [--seeds "1 2 3"]
#                         [--base JOB.json] [--summaries DIR] [--prepare-only]
#                         [--specimens-from DIR]
#
# Each campaign is examples/paper-<pattern>.json with its seed replaced (or,
# with --base, that job file with its pattern and seed replaced); it runs in
# DIR/<pattern>-seed<k>/ (default build/study), and its summary is copied to
# --summaries (default docs/study). A campaign whose
# summary.json already exists, in its folder or gathered into --summaries, is
# not run again (to rerun one, move its gathered summary away: the first
# seed-1 campaigns, from superseded job files, are in
# docs/study/plate-5mm-per-s/), and one that was stopped
# continues where it was (`wiredem run` resumes its directory: the specimen,
# the finished tests, each running test's last checkpoint), so the command
# can be stopped and started again; a failed one is reported and the others
# go on. --jobs
# campaigns run at once (default 1), each on --threads threads (default: the
# cores divided among the jobs). --prepare-only prepares the specimens
# (`wiredem prepare`, docs/studies.md) and stops: the specimen table of the
# report, and the campaigns continue from them later. --specimens-from DIR
# takes each campaign's specimen from DIR/<pattern>-seed<k>/ when that is
# prepared (`wiredem run --specimen-from`: its job must prepare the same
# specimen, i.e. differ in `triaxial`, `name` or `comment` only), so a
# study of other test settings on the same columns pours nothing. The figures: /usr/bin/python3
# scripts/study_report.py (reads DIR).
set -euo pipefail
cd "$(dirname "$0")/.."

jobs=1
threads=0
runs=build/study
wiredem=build/release/bin/wiredem
patterns="none helix spiral_helix radial_helix"
seeds="1 2 3"
base=""
summaries=docs/study
prepare_only=0
specimens_from=""
while [[ $# -gt 0 ]]; do
    case "$1" in
        --jobs) jobs="$2"; shift ;;
        --threads) threads="$2"; shift ;;
        --runs) runs="$2"; shift ;;
        --wiredem) wiredem="$2"; shift ;;
        --patterns) patterns="$2"; shift ;;
        --seeds) seeds="$2"; shift ;;
        --base) base="$2"; shift ;;
        --summaries) summaries="$2"; shift ;;
        --prepare-only) prepare_only=1; shift; continue ;;
        --specimens-from) specimens_from="$2"; shift ;;
        *) echo "usage: $0 [--jobs N] [--threads T] [--runs DIR] [--wiredem PATH] [--patterns LIST] [--seeds LIST]" \
                "[--base JOB.json] [--summaries DIR] [--prepare-only] [--specimens-from DIR]" >&2
           exit 2 ;;
    esac
    shift
done
[[ "$jobs" =~ ^[1-9][0-9]*$ ]] || { echo "study: --jobs must be a positive integer, got '$jobs'" >&2; exit 2; }
[[ "$threads" =~ ^[0-9]+$ ]] || { echo "study: --threads must be a whole number, got '$threads'" >&2; exit 2; }
[[ -x "$wiredem" ]] || { echo "study: $wiredem not found; build it first (bash scripts/build.sh release)" >&2; exit 2; }
if [[ "$threads" -eq 0 ]]; then threads=$(( $(nproc) / jobs )); [[ $threads -ge 1 ]] || threads=1; fi
for p in $patterns; do
    case "$p" in none|helix|spiral_helix|radial_helix) ;;
        *) echo "study: unknown pattern '$p' (none, helix, spiral_helix, radial_helix)" >&2; exit 2 ;; esac
done
for s in $seeds; do [[ "$s" =~ ^[0-9]+$ ]] || { echo "study: a seed must be a whole number, got '$s'" >&2; exit 2; }; done
[[ -z "$base" || -f "$base" ]] || { echo "study: --base $base not found" >&2; exit 2; }
[[ -z "$specimens_from" || -d "$specimens_from" ]] || { echo "study: --specimens-from $specimens_from is not a directory" >&2; exit 2; }
mkdir -p "$runs" "$summaries"

# One campaign: job file with the seed, run, copy the summary.
campaign() {
    local pattern=$1 seed=$2
    local name="${pattern}-seed${seed}" job="${base:-examples/paper-${pattern//_/-}.json}"
    local dir="$runs/$name"
    [[ -f "$job" ]] || { echo "study: $job is missing" >&2; return 1; }
    if [[ -f "$dir/summary.json" ]]; then
        echo "study: $name done already"
    elif [[ -f "$summaries/$name.json" ]]; then
        echo "study: $name done already (its summary is $summaries/$name.json)"
        return 0
    else
        mkdir -p "$dir"
        # The campaign's input sits beside its directory: the directory's own
        # job.json is the runner's (campaign/files.hpp), compared on resume.
        /usr/bin/python3 - "$job" "$seed" "$pattern" "$runs/$name.json" <<'EOF'
import json, sys
job_file, seed, pattern, out = sys.argv[1:]
job = json.load(open(job_file))
job["seed"] = int(seed)
job.setdefault("specimen", {}).setdefault("wire", {})["pattern"] = pattern
job["name"] = f'{job.get("name", job_file)} ({pattern}, seed {seed})'
json.dump(job, open(out, "w"), indent=1)
EOF
        local t0=$SECONDS
        local from=()
        if [[ -n "$specimens_from" && -f "$specimens_from/$name/specimen.h5" && ! -f "$dir/specimen.h5" ]]; then
            from=(--specimen-from "$specimens_from/$name")
        fi
        if [[ $prepare_only -eq 1 ]]; then
            echo "study: $name preparing $(date -u +%H:%M:%S), $threads threads, load $(cut -d' ' -f1-3 /proc/loadavg)"
            if ! "$wiredem" prepare "$runs/$name.json" -o "$dir" --threads "$threads" "${from[@]}" >> "$dir/run.log" 2>&1; then
                echo "study: $name preparation FAILED after $((SECONDS - t0)) s (see $dir/run.log)" >&2
                return 1
            fi
            echo "study: $name prepared in $((SECONDS - t0)) s"
            return 0
        fi
        echo "study: $name started $(date -u +%H:%M:%S), $threads threads, load $(cut -d' ' -f1-3 /proc/loadavg)"
        if ! "$wiredem" run "$runs/$name.json" -o "$dir" --threads "$threads" "${from[@]}" >> "$dir/run.log" 2>&1; then
            echo "study: $name FAILED after $((SECONDS - t0)) s (see $dir/run.log)" >&2
            return 1
        fi
        echo "study: $name finished in $((SECONDS - t0)) s"
    fi
    cp "$dir/summary.json" "$summaries/$name.json"
}

failed=0
running=0
for pattern in $patterns; do
    for seed in $seeds; do
        campaign "$pattern" "$seed" &
        running=$((running + 1))
        if [[ $running -ge $jobs ]]; then
            wait -n || failed=$((failed + 1))
            running=$((running - 1))
        fi
    done
done
while [[ $running -gt 0 ]]; do
    wait -n || failed=$((failed + 1))
    running=$((running - 1))
done
echo "study: $failed campaign(s) failed; summaries in $summaries/"
[[ $failed -eq 0 ]]
