// The register interface as an HLS kernel: one call = one 50 MHz fabric
// clock of the SPI slave and the register file together (docs/spi.md,
// docs/register-map.md), in odoloc::hls integer types (types.hpp). C++14.
//
// The logic is the model's own (logic/register_interface.hpp over
// logic/spi_slave.hpp and logic/register_file.hpp, which the cycle model's
// rtl::RegisterInterface runs inside rtl::OdolocChip): this file maps the
// kernel's flat ports onto it, nothing else. Every address, mask, reset
// value and the CRC come from the register map (odoloc/logic/
// regfile_map.hpp, generated from regmap/odoloc.yaml).
//
// Inputs, per call:
//   sclk, cs_n, mosi [1 each]  SPI pins, asynchronous to the fabric clock
//                      (two synchroniser flops inside; every SCLK level must
//                      last >= spi.min_level_clocks calls)
//   reset [1]          synchronous reset of every register
//   <register> [32]    the fabric's status: per register with bits the hardware
//                      drives (hw w, set, count) except the register file's own
//                      top.spi_status and top.frame_errors, the word those
//                      bits make (ports.hpp encode_status; other bits ignored),
//                      named after the register (eppm_left_rear_count, ...).
//                      Read in the call a snapshot is taken (the clock the
//                      frame's cs_n fall is seen: snapshot registers) and in
//                      the call a word is fetched for MISO (live registers).
//
// Outputs, the registers after this call's clock edge:
//   miso [1]           the MISO pin
//   snapshot [1]       one call: the snapshot is taken (the TOF capture unit
//                      freezes its FIFO levels for the frame)
//   config_<register> [32]  the stored rw bits of every rw register: the
//                      configuration ports are their fields
//   pulse_<register> [32]  per register with w1c or w1p bits: the bits a
//                      committed write set, for one call (w1c clears, w1p
//                      commands)
//   pops_<fifo> [4]    per rpop FIFO, for one call: the whole entries a
//                      completed read frame read in order from its first word
//                      (the FIFO pops them)
// The blocks take the pulses and pops in the next clock, as in the model.
//
// Latency: the slave sees a pin edge in the third call after it changes;
// a write's configuration and pulses show in the outputs of the call after
// the one in which the slave saw cs_n rise. The top (hls/src/regfile_top.cpp)
// is free-running (ap_ctrl_none) with II=1, like the fabric's other blocks.
// Reset: the `reset` port, and the registers' initialisers (stored words:
// the map's reset values).
// No heap, no containers, no floating point, static loop bounds.
#pragma once

#include "odoloc/hls/types.hpp"
#include "odoloc/logic/register_interface.hpp"

namespace odoloc {
namespace hls {
namespace regfile {

namespace map = logic::regfile_map;
namespace rf = logic::regfile;

using Logic = logic::register_interface::RegisterInterface<Family>;
using Registers = logic::register_interface::Regs<Family>;  // the model's, register for register
using Word = rf::BufferWord<Family>;
using Status = rf::StatusWords<Family>;
using Pops = rf::Cell<Family, rf::kPopBits>;

// Every field starts at 0 (the arrays' elements by their initialisers):
// ap_int's default constructor leaves the value undefined.
struct Inputs {
  uint<1> sclk = 0, cs_n = 1, mosi = 0;
  uint<1> reset = 0;
  Status status;  // bank kStatus, in address order
};

struct Outputs {
  uint<1> miso = 0;
  uint<1> snapshot = 0;
  Word config[rf::kStoredWords];  // bank kStored
  Word pulse[rf::kPulseWords];    // bank kPulse
  Pops pops[rf::kPopWindows];
};

// ---- port names (testbenches only: never synthesised) ------------------------------
// Column names built at compile time: "config_eppm_left_rear_cfg".
constexpr int kNameChars = 48;
struct Name {
  char text[kNameChars];
};
template <int N>
struct Names {
  Name of[N];
};

// prefix + stem. Longer names are cut, which the testbenches' name check reports.
constexpr Name port_name(const char* prefix, const char* stem) {
  Name name = {};
  int n = 0;
  for (const char* s = prefix; *s != '\0' && n < kNameChars - 1; ++s)
    name.text[n++] = *s;
  for (const char* s = stem; *s != '\0' && n < kNameChars - 1; ++s)
    name.text[n++] = *s;
  return name;
}
// prefix + the register's name, for every word of a bank.
template <int N>
constexpr Names<N> bank_names(const char* prefix, int bank) {
  Names<N> names = {};
  for (int k = 0; k < N; ++k)
    names.of[k] = port_name(prefix, map::kRegisterNames[rf::kLayout.member[bank][k]]);
  return names;
}
constexpr Names<rf::kPopWindows> pop_names() {
  Names<rf::kPopWindows> names = {};
  for (int w = 0; w < rf::kPopWindows; ++w)
    names.of[w] = port_name("pops_", map::kPopWindowNames[w]);
  return names;
}

// The ports by name, in the golden vectors' column order (testbenches only).
template <class Visit>
void visit_fields(Inputs& s, Visit&& v) {
  v("sclk", s.sclk);
  v("cs_n", s.cs_n);
  v("mosi", s.mosi);
  v("reset", s.reset);
  for (int k = 0; k < rf::kStatusWords; ++k)
    v(map::kRegisterNames[rf::kLayout.member[rf::kStatus][k]], s.status.bank[k].value);
}
template <class Visit>
void visit_fields(Outputs& s, Visit&& v) {
  static constexpr Names<rf::kStoredWords> kConfig =
      bank_names<rf::kStoredWords>("config_", rf::kStored);
  static constexpr Names<rf::kPulseWords> kPulses =
      bank_names<rf::kPulseWords>("pulse_", rf::kPulse);
  static constexpr Names<rf::kPopWindows> kPops = pop_names();
  v("miso", s.miso);
  v("snapshot", s.snapshot);
  for (int k = 0; k < rf::kStoredWords; ++k)
    v(kConfig.of[k].text, s.config[k].value);
  for (int k = 0; k < rf::kPulseWords; ++k)
    v(kPulses.of[k].text, s.pulse[k].value);
  for (int w = 0; w < rf::kPopWindows; ++w)
    v(kPops.of[w].text, s.pops[w].value);
}

// One fabric clock: the registers after this clock's edge (`regs` is the
// register bank), then the outputs those registers drive.
inline void step(Registers& regs, const Inputs& in, Outputs& out) {
#pragma HLS inline
  logic::register_interface::Pins<Family> pins;
  pins.sclk = in.sclk;
  pins.cs_n = in.cs_n;
  pins.mosi = in.mosi;
  pins.reset = in.reset;
  regs = Logic::next(regs, pins, in.status);
  out.miso = regs.slave.engine.miso;
  out.snapshot = regs.slave.engine.snapshot;
  for (int k = 0; k < rf::kStoredWords; ++k)
    out.config[k] = regs.registers.stored.word[k];
  for (int k = 0; k < rf::kPulseWords; ++k)
    out.pulse[k] = regs.registers.pulse[k];
  for (int w = 0; w < rf::kPopWindows; ++w)
    out.pops[w] = regs.registers.pops[w];
}

}  // namespace regfile
}  // namespace hls
}  // namespace odoloc

// The top function (hls/src/regfile_top.cpp): one call = one clock, the
// registers held in the function's static state.
void odoloc_regfile(const odoloc::hls::regfile::Inputs& in, odoloc::hls::regfile::Outputs& out);
