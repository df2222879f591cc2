#!/usr/bin/env bash
# ctest's entry to the browser test (pages.test.mjs): Debian's chromium
# (installed here when it is missing and we are root, as on CI), puppeteer-core
# from web/package-lock.json (installed by the build's `npm ci`, again here if
# it is gone), then node's test runner. Needs WIREDEM_SERVER_BIN (with the
# `wiredem` runner beside it and the page in BIN/../share/wiredem/web),
# WIREDEM_WEB_NODE_MODULES and WIREDEM_SOURCE_DIR, which ctest sets.
set -euo pipefail
chromium=${CHROMIUM:-/usr/bin/chromium}
if [ ! -x "$chromium" ]; then
  if [ "$(id -u)" = 0 ]; then
    echo "web test: installing Debian's chromium" >&2
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -qq && apt-get install -y -qq --no-install-recommends chromium >/dev/null
  else
    echo "web test: $chromium is missing: apt-get install chromium (scripts/setup.sh does)" >&2
    exit 1
  fi
fi
if [ ! -d "$WIREDEM_WEB_NODE_MODULES/puppeteer-core" ]; then
  (cd "$(dirname "$WIREDEM_WEB_NODE_MODULES")" && npm ci --ignore-scripts --no-audit --no-fund --loglevel=error)
fi
export CHROMIUM=$chromium
exec node --test --test-reporter=spec "$(dirname "$0")/pages.test.mjs"
