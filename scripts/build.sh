#!/usr/bin/env bash
# Configures and builds one preset (default: "default"). Used by the two
# quick-start commands and by CI.
set -euo pipefail
cd "$(dirname "$0")/.."
preset=${1:-default}
scripts/setup-debian.sh
cmake --preset "$preset" >/dev/null
cmake --build --preset "$preset"
