// SPI slave protocol engine: pins in, narrow wires to the register side out.
// The register file is not part of this block (docs/spi.md). The logic, the
// frame format, the timing and the register-side interface:
// logic/spi_slave.hpp (the one source, also the HLS kernel's). Here: what
// only a simulator needs around it (field lists, the waveform's ports, idle
// conditions and activity gating, the quiet fast path).
#pragma once

#include <cstdint>
#include <span>

#include "odoloc/logic/register_file.hpp"
#include "odoloc/logic/spi_slave.hpp"
#include "odoloc/regs.hpp"
#include "odoloc/rtl/bits.hpp"
#include "odoloc/rtl/clocked.hpp"
#include "odoloc/rtl/family.hpp"

namespace odoloc::rtl {

// CRC-8 as in SAE J1850 (regmap/odoloc.yaml, spi.crc): polynomial 0x1D,
// init 0xFF, no reflection, final XOR 0xFF.
inline constexpr std::uint8_t kCrc8Poly = regs::spi::kCrcPolynomial;
inline constexpr std::uint8_t kCrc8Init = regs::spi::kCrcInit;
inline constexpr std::uint8_t kCrc8XorOut = regs::spi::kCrcXorOut;

// The CRC of a whole message, bit by bit as the slave computes it.
inline std::uint8_t crc8_j1850(std::span<const std::uint8_t> bytes) {
  UInt<8> crc{kCrc8Init};
  for (const std::uint8_t b : bytes)
    for (int i = 7; i >= 0; --i)
      crc =
          logic::spi::crc8_step<Family>(crc, UInt<1>::truncate(static_cast<std::uint64_t>(b >> i)));
  return static_cast<std::uint8_t>(crc.value() ^ kCrc8XorOut);
}

inline constexpr unsigned kSpiMaxBurst = regs::spi::kMaxBurst;
static_assert(kSpiMaxBurst == logic::spi::kMaxBurst &&
              regs::spi::kMinLevelClocks == logic::spi::kMinLevelClocks);

// ---- the leaves (logic/spi_slave.hpp) -------------------------------------------
ODOLOC_LOGIC_FIELDS(logic::spi::SynchroniserRegs, sclk_meta, sclk_sync, sclk_prev, cs_meta, cs_sync,
                    cs_prev, mosi_meta, mosi_sync, level_clocks)
ODOLOC_LOGIC_FIELDS(logic::spi::EngineRegs, active, crc_on, fall_armed, frame_overrun, rx_count,
                    rx_shift, rx_crc, command, tx_count, tx_shift, tx_crc, read_word, miso,
                    snapshot, read_strobe, read_address, commit, commit_write, frame_end,
                    commit_address, commit_count, status)
ODOLOC_LOGIC_FIELDS(logic::spi::BufferWord, value)
ODOLOC_LOGIC_FIELDS(logic::spi::WriteBufferRegs, words)

using SpiSynchroniserRegs = logic::spi::SynchroniserRegs<Family>;
using SpiEngineRegs = logic::spi::EngineRegs<Family>;
using SpiWriteBufferRegs = logic::spi::WriteBufferRegs<Family>;

// The two synchroniser flops of each pin, edge detection and the level
// count: clocked every clock; the engine sees its edges (Seen).
class SpiSynchroniser : public Registers<SpiSynchroniserRegs> {
  using Logic = logic::spi::Synchroniser<Family>;

 public:
  using In = logic::spi::SynchroniserIn<Family>;
  using Seen = logic::spi::Seen<Family>;
  // What the engine sees in this clock, from the current registers.
  [[nodiscard]] Seen seen() const { return Logic::seen(r_); }
  [[nodiscard]] Regs eval(const In& in) const { return Logic::next(r_, in); }
  // Every pin held through both flops, no edge pending, the level count saturated.
  [[nodiscard]] bool idle(const In& in) const {
    const auto held = [](UInt<1> pin, UInt<1> meta, UInt<1> sync) {
      return pin == meta && meta == sync;
    };
    return in.reset.is_zero() && held(in.sclk, r_.sclk_meta, r_.sclk_sync) &&
           r_.sclk_sync == r_.sclk_prev && held(in.cs_n, r_.cs_meta, r_.cs_sync) &&
           r_.cs_sync == r_.cs_prev && held(in.mosi, r_.mosi_meta, r_.mosi_sync) &&
           r_.level_clocks.value() == UInt<logic::spi::kLevelBits>::max_value;
  }
};

// The words of a write frame, one write port.
class SpiWriteBuffer : public Registers<SpiWriteBufferRegs> {
 public:
  using In = logic::spi::WriteBufferIn<Family>;
  [[nodiscard]] Regs eval(const In& in) const {
    return logic::spi::WriteBuffer<Family>::next(r_, in);
  }
  [[nodiscard]] bool idle(const In& in) const { return (in.write | in.reset).is_zero(); }
};

// The frame state, the shift registers, the CRCs and every output to the
// register side. Moves only on a seen edge, a strobe to clear, a read word to
// latch or a refused write: between SCLK edges it is idle.
class SpiEngine : public Registers<SpiEngineRegs> {
  using Logic = logic::spi::Engine<Family>;

 public:
  static constexpr unsigned kMinLevelClocks = regs::spi::kMinLevelClocks;
  // status bits: the top.spi_status fields
  static constexpr std::uint8_t kStatusCrcError = logic::spi::kCrcError;
  static constexpr std::uint8_t kStatusBadLength = logic::spi::kBadLength;
  static constexpr std::uint8_t kStatusWriteRefused = logic::spi::kWriteRefused;
  static constexpr std::uint8_t kStatusOverrun = logic::spi::kOverrun;

  using In = logic::spi::EngineIn<Family>;
  [[nodiscard]] Regs eval(const In& in) const { return Logic::next(r_, in); }
  [[nodiscard]] bool idle(const In& in) const {
    const SpiSynchroniser::Seen& s = in.seen;
    return !(s.cs_fall || s.cs_rise || s.rise || s.fall) &&
           (in.reset | in.write_refused | r_.read_strobe).is_zero() && !strobing();
  }
  // The write buffer's port in this clock.
  [[nodiscard]] SpiWriteBuffer::In word_write(const In& in) const {
    return Logic::word_write(r_, in);
  }
  // Any strobe the register side acts on.
  [[nodiscard]] bool strobing() const { return Logic::strobing(r_); }
};

// The register side's wires from the slave (logic/register_file.hpp).
using SpiRegisterPort = logic::regfile::Port<Family>;

// ---- the slave ----------------------------------------------------------------------
// Three blocks, so that a clock between SCLK edges costs the synchroniser
// alone: the engine and the write buffer are idle then (activity gating).
class SpiSlave {
  using Logic = logic::spi::Slave<Family>;

 public:
  static constexpr unsigned kMinLevelClocks = SpiEngine::kMinLevelClocks;
  static constexpr std::uint8_t kStatusCrcError = SpiEngine::kStatusCrcError;
  static constexpr std::uint8_t kStatusBadLength = SpiEngine::kStatusBadLength;
  static constexpr std::uint8_t kStatusWriteRefused = SpiEngine::kStatusWriteRefused;
  static constexpr std::uint8_t kStatusOverrun = SpiEngine::kStatusOverrun;

  // Pins, top.ctrl's bits, and the register file's read_data (the clock
  // after read_strobe) and write_refused (the commit clock).
  using In = logic::spi::SlaveIn<Family>;

  // The wires into every child, from the current registers only.
  struct Wires {
    SpiSynchroniser::In synchroniser;
    SpiEngine::In engine;
    SpiWriteBuffer::In buffer;
  };
  [[nodiscard]] Wires wires(const In& in) const {
    const SpiEngine::In engine = engine_in(in);
    return {.synchroniser = synchroniser_in(in),
            .engine = engine,
            .buffer = engine_.word_write(engine)};
  }
  [[nodiscard]] SpiSynchroniser::In synchroniser_in(const In& in) const {
    return Logic::synchroniser_in(engine_.regs(), in);
  }
  [[nodiscard]] SpiEngine::In engine_in(const In& in) const {
    return Logic::engine_in(synchroniser_.regs(), in);
  }

  template <Gating G = Gating::kOn, class Order = DeclarationOrder>
  void step(const In& in, const Order& order = {}) {
    if (G == Gating::kOn && quiet(in))
      return;
    step_blocks<G>(in, order);
  }
  [[nodiscard]] bool idle(const In& in) const {
    const Wires w = wires(in);
    return synchroniser_.idle(w.synchroniser) && engine_.idle(w.engine) && buffer_.idle(w.buffer);
  }
  void reset_now() {
    synchroniser_.reset_now();
    engine_.reset_now();
    buffer_.reset_now();
    settled_ = false;
  }

  // Settled on the pins it last took, these pins and no reset: a clock with
  // them and no refused write changes nothing (the gated step's fast path).
  [[nodiscard]] bool settled_on(UInt<1> sclk, UInt<1> cs_n, UInt<1> mosi, UInt<1> reset) const {
    const SpiSynchroniserRegs& s = synchroniser_.regs();
    return settled_ && sclk == s.sclk_meta && cs_n == s.cs_meta && mosi == s.mosi_meta &&
           reset.is_zero();
  }
  // Any strobe the register side acts on (port()'s strobes, without the copy).
  [[nodiscard]] bool strobing() const { return engine_.strobing(); }
  [[nodiscard]] SpiRegisterPort port() const {
    return logic::regfile::port(engine_.regs(), buffer_.regs());
  }
  [[nodiscard]] UInt<1> miso() const { return engine_.regs().miso; }

  [[nodiscard]] const SpiSynchroniserRegs& synchroniser() const { return synchroniser_.regs(); }
  [[nodiscard]] const SpiEngineRegs& engine() const { return engine_.regs(); }
  [[nodiscard]] const SpiWriteBufferRegs& buffer() const { return buffer_.regs(); }
  bool operator==(const SpiSlave& o) const {
    return synchroniser() == o.synchroniser() && engine() == o.engine() && buffer() == o.buffer();
  }

  template <class V>
  void trace(V& v) const {
    trace_scope(v, "synchroniser", synchroniser_);
    trace_scope(v, "engine", engine_);
    trace_scope(v, "buffer", buffer_);
  }

 private:
  // Out of line: a bus at rest (the common case) costs quiet() alone.
  template <Gating G, class Order>
  [[gnu::noinline]] void step_blocks(const In& in, const Order& order) {
    // Between SCLK edges the engine is idle, and with it the write buffer
    // (written only on an edge): only the synchroniser moves.
    if (G == Gating::kOn && engine_.idle(engine_in(in))) {
      clock_block<G>(synchroniser_, synchroniser_in(in));
    } else {
      const Wires w = wires(in);
      order([&] { clock_block<G>(synchroniser_, w.synchroniser); },
            [&] { clock_block<G>(engine_, w.engine); }, [&] { clock_block<G>(buffer_, w.buffer); });
    }
    settled_ = G == Gating::kOn && settled();  // only the gated step reads it
  }
  // The synchroniser idle on the pins it last took and no strobe out: then
  // the whole slave is idle for the same pins, no reset and no refused write.
  [[nodiscard]] bool settled() const {
    const SpiSynchroniserRegs& s = synchroniser_.regs();
    return synchroniser_.idle({.sclk = s.sclk_meta,
                               .cs_n = s.cs_meta,
                               .mosi = s.mosi_meta,
                               .active = engine_.regs().active,
                               .reset = {}}) &&
           !engine_.strobing();
  }
  [[nodiscard]] bool quiet(const In& in) const {
    return settled_on(in.sclk, in.cs_n, in.mosi, in.reset) && in.write_refused.is_zero();
  }

  SpiSynchroniser synchroniser_;
  SpiEngine engine_;
  SpiWriteBuffer buffer_;
  bool settled_ = false;  // simulator bookkeeping, not a register: settled() after the last clock
};

}  // namespace odoloc::rtl
