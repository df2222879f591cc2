#!/usr/bin/env bash
# Lints the container files offline (no Docker engine needed):
# docker/Dockerfile with dockerfilelint (npm), docker/compose.yaml as YAML.
set -euo pipefail
cd "$(dirname "$0")/.."
if ! command -v npx >/dev/null; then
  echo "lint-docker: npx not found (Debian: apt-get install npm)" >&2
  exit 1
fi
npx --yes dockerfilelint docker/Dockerfile
# Debian's Python, where scripts/setup.sh installs python3-yaml.
/usr/bin/python3 - <<'PY'
import sys
try:
    import yaml
except ImportError:
    print("lint-docker: python3-yaml missing (scripts/setup.sh installs it)", file=sys.stderr)
    sys.exit(1)
doc = yaml.safe_load(open("docker/compose.yaml"))
assert "server" in doc["services"], "compose.yaml: no server service"
svc = doc["services"]["server"]
assert svc["build"]["dockerfile"] == "docker/Dockerfile"
assert all(p.startswith("127.0.0.1:") for p in svc["ports"]), "compose.yaml: publish on loopback only"
print("docker/compose.yaml: ok")
PY
