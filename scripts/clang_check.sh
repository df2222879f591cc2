#!/usr/bin/env bash
# Every C++ file of the project through Debian's clang (14), front end only
# (-fsyntax-only), with the build's own flags and -Werror: the project must
# compile -Wall -Wextra clean with clang as with GCC (the GCC builds compile
# and run the code; clang's warnings are its front end's, which this runs in
# full). Without precompiled headers (WIREDEM_PCH=OFF), so a file that uses a
# header it does not include fails here even where a precompiled header hides
# it in the builds. Every file the build knows: libraries, programs, tests,
# benchmarks.
#   scripts/clang_check.sh [REGEX]    only the files whose path matches REGEX
# A quick check to run before a commit (nothing is optimised or written): CI
# gets the same from its clang ASan build (scripts/build.sh asan: -Werror, no
# precompiled headers), which compiles every one of these files anyway.
set -euo pipefail
cd "$(dirname "$0")/.."
filter=${1:-.}
cmake -S . -B build/clang-check -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_CXX_FLAGS=-Werror \
  -DWIREDEM_PCH=OFF -DWIREDEM_BUILD_WEB=OFF -DCMAKE_EXPORT_COMPILE_COMMANDS=ON >/dev/null
exec /usr/bin/python3 - build/clang-check/compile_commands.json "$filter" "$(nproc)" <<'EOF'
"""Runs each C++ compile command of a compile_commands.json with -fsyntax-only
instead of writing an object; prints the failures and exits 1 if any."""
import json
import re
import shlex
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor

database, pattern, jobs = sys.argv[1], re.compile(sys.argv[2]), int(sys.argv[3])
entries = [e for e in json.load(open(database))
           if e["file"].endswith(".cpp") and pattern.search(e["file"])]


def syntax_only(entry):
    args = shlex.split(entry["command"]) if "command" in entry else list(entry["arguments"])
    kept, skip = [], False
    for a in args:
        if skip:
            skip = False
        elif a == "-o":
            skip = True
        elif a != "-c":
            kept.append(a)
    kept.insert(1, "-fsyntax-only")
    proc = subprocess.run(kept, cwd=entry["directory"], capture_output=True, text=True)
    return entry["file"], proc.returncode, proc.stderr


failed = 0
with ThreadPoolExecutor(max_workers=max(1, jobs)) as pool:
    for path, code, err in pool.map(syntax_only, entries):
        if code != 0 or err.strip():
            failed += 1
            print(f"clang_check: {path}\n{err}", file=sys.stderr)
print(f"clang_check: {len(entries)} files, {failed} with errors or warnings")
sys.exit(1 if failed or not entries else 0)
EOF
