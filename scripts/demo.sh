#!/usr/bin/env bash
# Quick start 1: the main job on its embedded default scenario.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh default
exec build/default/host_tools/demo/odoloc_demo "$@"
