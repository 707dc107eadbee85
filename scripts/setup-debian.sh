#!/usr/bin/env bash
# Installs the Debian 12 packages odoloc builds with; with --tests also the
# outside tools the tests check the project against (the main job does not
# need them). Idempotent: asks apt only for what is missing. Needs root (or
# sudo) when something is.
set -euo pipefail

packages=(
  build-essential cmake ninja-build git
  ccache  # the compiler cache the build uses when present (docs/development.md)
  libgtest-dev libgmock-dev libbenchmark-dev libcli11-dev libyaml-cpp-dev nlohmann-json3-dev libfmt-dev
  libeigen3-dev  # the beacon solvers and the fusion filter
  clang libclang-rt-14-dev  # libFuzzer for the bounded fuzz runs (ctest label fuzz)
  clang-tidy python3  # the HLS synthesizability lint, with clang (ctest label lint)
  gnuplot-nox  # the demo's trajectory plot, odoloc plot, locate --plot, sweep merge
  liblcm-dev liblcm-bin libglib2.0-dev  # LCM messages, lcm-gen, lcm-logger/-logplayer (lcm.pc needs glib)
  help2man  # the man page odoloc.1, made from the built odoloc's --help (without it: no man page)
)
if [ "${1:-}" = "--tests" ]; then
  packages+=(
    gtkwave      # vcd2fst: the waveform test cross-checks our VCD with GTKWave's own reader
    verilator    # test_rdl lints the SystemVerilog PeakRDL-regblock makes from odoloc.rdl
    sigrok-cli   # test_cli_e2e decodes the host tool's --vcd-pins waveform with sigrok's SPI decoder
    parallel     # test_sweep_e2e runs a sweep's shards through GNU parallel
    gcc-avr avr-libc                          # test_regmap_corpus: odoloc_regs.h with a 16-bit int
    gcc-arm-none-eabi libnewlib-arm-none-eabi  # ... and on a Cortex-M compiler
    lintian groff-base  # cli_package lints the Debian package and renders its man page
    # test_lcm_user_tools: a real lcm-spy on Xvfb with the generated Java
    # types (the build makes the jar when a JDK and liblcm-java are there)
    liblcm-java libjchart2d-java default-jdk-headless xvfb
  )
fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0

echo "setup: installing ${missing[*]}"
sudo_cmd=()
[ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -q
"${sudo_cmd[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}"
