#!/usr/bin/env bash
# Runs a command with the study's running campaign stopped (SIGSTOP), and
# resumes the campaign when the command ends, however it ends. For timing on
# a machine whose cores a study (scripts/study.sh) keeps busy.
#
# usage: bench/with_study_paused.sh CMD [ARG...]
#   WIREDEM_PAUSE_PATTERN  pgrep -f pattern of the process to stop
#                          (default: a `wiredem run` started by scripts/study.sh)
set -uo pipefail
pattern=${WIREDEM_PAUSE_PATTERN:-'^build/study/bin/wiredem-[0-9a-f]+ run '}
pids=$(pgrep -f "$pattern" || true)
resume() { [ -n "$pids" ] && kill -CONT $pids 2>/dev/null; }
trap resume EXIT
trap 'exit 130' INT TERM
if [ -n "$pids" ]; then
    kill -STOP $pids
    echo "with_study_paused: stopped $pids" >&2
fi
sleep 1
echo "with_study_paused: $(uptime)" >&2
"$@"
