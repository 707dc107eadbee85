// VCD (IEEE 1364 value change dump) writer for clocked blocks.
//
// Why: a waveform in GTKWave is the quickest way to see what a block did cycle
// by cycle, and VCD is the format every waveform viewer reads.
//
// How: declare() walks the block's trace() once to learn scopes, names and
// widths and writes the header plus every initial value. sample() runs after
// each commit and writes only the signals that changed, comparing against the
// last values kept by visit order, so a trace() must visit the same signals in
// the same order every time. Time: one fabric clock is kFabricClockPeriodNs;
// clk rises at cycle * period (the commit) and falls half a period later.
//
//   VcdWriter vcd(file);
//   vcd.declare(block);
//   for (std::uint64_t c = 0; ...; ++c) { block.commit(block.eval(...)); vcd.sample(block, c); }
#pragma once

#include <cstdint>
#include <optional>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "odoloc/rtl/bits.hpp"
#include "odoloc/rtl/clocked.hpp"

namespace odoloc::rtl {

class VcdWriter {
 public:
  explicit VcdWriter(std::ostream& out, std::string top_scope = "odoloc");

  // Once, before any sample(): writes the header and the initial values.
  template <class Block>
  void declare(const Block& block) {
    begin_declarations();
    Declarer declarer{*this};
    block.trace(declarer);
    end_declarations();
  }

  // After the commit of fabric clock `cycle`; cycles must increase.
  template <class Block>
  void sample(const Block& block, std::uint64_t cycle) {
    begin_sample(cycle);
    Sampler sampler{*this};
    block.trace(sampler);
    end_sample(sampler.visited);
  }

  [[nodiscard]] std::size_t signal_count() const { return last_values_.size(); }

 private:
  struct Declarer {
    VcdWriter& writer;
    void enter(std::string_view name) { writer.declare_scope(name); }
    void leave() { writer.declare_upscope(); }
    template <int W>
    void signal(std::string_view name, UInt<W> value) {
      writer.declare_var(name, W, value.value());
    }
    template <int W>
    void signal(std::string_view name, SInt<W> value) {
      writer.declare_var(name, W, value.raw_bits());
    }
  };

  // The hot path: one compare per signal; only changes leave the header.
  struct Sampler {
    VcdWriter& writer;
    std::size_t visited = 0;
    void enter(std::string_view /*name*/) {}
    void leave() {}
    template <int W>
    void signal(std::string_view /*name*/, UInt<W> value) {
      observe(value.value());
    }
    template <int W>
    void signal(std::string_view /*name*/, SInt<W> value) {
      observe(value.raw_bits());
    }
    void observe(std::uint64_t bits) {
      if (visited >= writer.last_values_.size() || writer.last_values_[visited] != bits) {
        writer.record_change(visited, bits);
      }
      ++visited;
    }
  };
  static_assert(TraceVisitor<Declarer> && TraceVisitor<Sampler>);

  void begin_declarations();
  void declare_scope(std::string_view name);
  void declare_upscope();
  void declare_var(std::string_view name, int width, std::uint64_t initial);
  void end_declarations();
  void begin_sample(std::uint64_t cycle);
  void record_change(std::size_t index, std::uint64_t bits);
  void end_sample(std::size_t visited);
  void write_value(std::size_t index, std::uint64_t bits);

  std::ostream& out_;
  std::string top_scope_;
  bool declaring_ = false;
  bool declared_ = false;
  int open_scopes_ = 0;
  std::string definitions_;       // scopes and vars, written once the trace walk is done
  std::vector<std::string> ids_;  // per signal, in visit order; clk has its own
  std::vector<int> widths_;
  std::vector<std::uint64_t> last_values_;
  std::optional<std::uint64_t> last_cycle_;
};

}  // namespace odoloc::rtl
