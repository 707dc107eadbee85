#!/usr/bin/env bash
# Checks that a built tree is up to date: configuring it again and then
# building the named targets (default: all, package) compiles, links and
# generates nothing. Ninja's explanations name the cause when it does.
#   scripts/check-up-to-date.sh PRESET [TARGET...]
# The preset's tree must have been built. Only the glob re-check and CPack's
# own step (the package target always runs it) may run.
set -euo pipefail
cd "$(dirname "$0")/.."
preset=${1:?usage: scripts/check-up-to-date.sh PRESET [TARGET...]}
targets=("${@:2}")
[ ${#targets[@]} -ne 0 ] || targets=(all package)
cmake --preset "$preset" >/dev/null
log=$(cmake --build --preset "$preset" --target "${targets[@]}" -- -d explain 2>&1)
steps=$(grep -E '^\[[0-9]+/[0-9]+\] ' <<<"$log" |
        grep -vE '\] (Re-checking globbed directories|Run CPack packaging tool)\.\.\.$' || true)
if [ -n "$steps" ]; then
  echo "check-up-to-date: preset '$preset': an up-to-date tree ran build steps:" >&2
  echo "$steps" | head -20 >&2
  echo "why (ninja -d explain):" >&2
  grep -E '^ninja explain: ' <<<"$log" | grep -vE 'is dirty$|phony edge' | head -20 >&2
  exit 1
fi
echo "check-up-to-date: preset '$preset': ${targets[*]} up to date after a configure"
