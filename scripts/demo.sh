#!/usr/bin/env bash
# Quick start 1: the main job on its embedded default scenario: the whole
# localisation system (docs/simulator.md), writing odoloc-sim/. Builds only
# the host tool `odoloc` and what it links (docs/development.md).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh default odoloc
exec build/default/host_tools/tools/cli/odoloc sim --out odoloc-sim "$@"
