#!/usr/bin/env bash
# Configures and builds one preset (default: "default"), all of it or only
# the targets named after it:  scripts/build.sh [PRESET [TARGET...]]
# Used by the two quick-start commands and by CI.
set -euo pipefail
cd "$(dirname "$0")/.."
preset=${1:-default}
targets=("${@:2}")
scripts/setup-debian.sh
cmake --preset "$preset" >/dev/null
if [ ${#targets[@]} -eq 0 ]; then
  cmake --build --preset "$preset"
else
  cmake --build --preset "$preset" --target "${targets[@]}"
fi
