#!/usr/bin/env bash
# Quick start 2: builds and runs every test (ctest fails when no test ran).
set -euo pipefail
cd "$(dirname "$0")/.."
preset=${1:-default}
scripts/setup-debian.sh --tests  # the outside tools the tests compare against
scripts/build.sh "$preset"
ctest --preset "$preset"
