#!/usr/bin/env bash
# Quick start 2: builds and runs every test (ctest fails when no test ran):
# the default preset's suite, then the fuzz preset's libFuzzer runs (clang,
# every library the fuzzers link instrumented; docs/fuzzing.md). With a
# preset name, that preset's suite alone.   scripts/test.sh [PRESET]
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup-debian.sh --tests  # the outside tools the tests compare against
if [ $# -ge 1 ]; then
  scripts/build.sh "$1"
  ctest --preset "$1"
  exit
fi
scripts/build.sh default
ctest --preset default
scripts/build.sh fuzz
ctest --preset fuzz
