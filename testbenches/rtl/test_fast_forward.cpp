// Fast-forward (rtl/clocked.hpp) is bit-identical to cycle stepping. Two
// chips see the same pins: one is stepped clock by clock, the other is
// advanced over every run of identical pins (OdolocChip::advance: skipped up
// to each event, stepped through it). The stimulus moves four encoders at
// random rates (stops long enough to saturate the period meters, reversals,
// glitches shorter than the filter), pulses the ultrasonic comparators and
// the sync input (pulses spanning timestamp epochs among them), sends random
// SPI frames that reconfigure every block (windows, prescalers, filters,
// update periods including 0, arming, reads) and resets the chip now and
// then. Every register of every block is compared at the end of every frame
// and every 2^20 clocks. CMakeLists.txt builds this test against mutants of
// every skip rule too, and expects each of them to fail.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "odoloc/board/chip_link.hpp"
#include "odoloc/board/encoder_pins.hpp"
#include "odoloc/regs.hpp"
#include "odoloc/rtl/odoloc_chip.hpp"
#include "odoloc/world/quadrature_source.hpp"
#include "random_frames.hpp"
#include "register_dump.hpp"
#include "spi_master_bfm.hpp"
#include "test_scale.hpp"

namespace {

using odoloc::rtl::ChipPins;
using odoloc::rtl::OdolocChip;
using odoloc::rtl::UInt;

bool same_pins(const ChipPins& a, const ChipPins& b) {
  return a.encoders == b.encoders && a.comparators == b.comparators && a.tof_sync == b.tof_sync &&
         a.sclk == b.sclk && a.cs_n == b.cs_n && a.mosi == b.mosi && a.reset == b.reset;
}

bool same_sensor_pins(const ChipPins& a, const ChipPins& b) {
  return a.encoders == b.encoders && a.comparators == b.comparators && a.tof_sync == b.tof_sync;
}

// `stepped` takes every clock; `forwarded` takes each run of identical pins
// in one advance(). Inside a frame (cs_n low) `forwarded` clocks its slave
// alone while its register file is quiet (step_bus) and brings its sensor
// side up, run by run of the sensor pins it fell behind by
// (sensors().advance), before the first clock that is not.
class TwinChips {
 public:
  void clock(const ChipPins& pins) {
    stepped_.step(pins);
    ++clocks_;
    if (pins.cs_n.is_zero()) {
      ++frame_clocks_;
      flush();
      if (forwarded_.bus_quiet(pins)) {
        forwarded_.step_bus(pins);
        if (behind_.empty() || !same_sensor_pins(pins, behind_.back().pins))
          behind_.push_back({pins, 0});
        ++behind_.back().clocks;
        ++lagged_;
        return;
      }
      catch_up();
      forwarded_.step(pins);
      return;
    }
    catch_up();
    if (run_ != 0 && !same_pins(pins, run_pins_))
      flush();
    run_pins_ = pins;
    ++run_;
  }
  // "" when every register agrees, else the first difference.
  std::string difference() {
    flush();
    catch_up();
    return odoloc::tb::first_difference(stepped_, forwarded_);
  }
  [[nodiscard]] const OdolocChip& stepped() const { return stepped_; }
  [[nodiscard]] std::uint64_t clocks() const { return clocks_; }
  [[nodiscard]] std::uint64_t skipped() const { return skipped_; }
  [[nodiscard]] std::uint64_t lagged() const { return lagged_; }
  [[nodiscard]] std::uint64_t frame_clocks() const { return frame_clocks_; }

 private:
  struct Behind {
    ChipPins pins;
    std::uint64_t clocks;
  };
  void flush() {
    if (run_ != 0)
      skipped_ += forwarded_.advance(run_, run_pins_);
    run_ = 0;
  }
  void catch_up() {
    for (const Behind& b : behind_)
      forwarded_.sensors().advance(b.clocks, b.pins);
    behind_.clear();
  }
  OdolocChip stepped_, forwarded_;
  ChipPins run_pins_;
  std::uint64_t run_ = 0;
  std::uint64_t clocks_ = 0;
  std::uint64_t skipped_ = 0;
  std::uint64_t lagged_ = 0;
  std::uint64_t frame_clocks_ = 0;
  std::vector<Behind> behind_;
};

// One line of pulses: low for an exponential time, then high for a short
// (filtered out), medium or, rarely, very long time (past several epochs of
// the capture unit's timestamp at prescale 0).
class PulseLine {
 public:
  PulseLine(std::uint64_t seed, double mean_gap) : rng_(seed), gap_(1.0 / mean_gap) {}
  bool tick() {
    if (remaining_ == 0) {
      high_ = !high_;
      if (high_) {
        const auto kind = rng_() % 100;
        remaining_ = kind < 30   ? 1 + rng_() % 5
                     : kind < 99 ? 10 + rng_() % 20'000
                                 : 9'000'000 + rng_() % 9'000'000;
      } else {
        remaining_ = 1 + static_cast<std::uint64_t>(gap_(rng_));
      }
    }
    --remaining_;
    return high_;
  }

 private:
  std::mt19937_64 rng_;
  std::exponential_distribution<double> gap_;
  std::uint64_t remaining_ = 0;
  bool high_ = true;
};

// An encoder: a quadrature source whose rate is redrawn at random times
// (stopped for millions of clocks, slow, fast, either direction), with rare
// glitches of one to four clocks on one line.
class EncoderLine {
 public:
  explicit EncoderLine(std::uint64_t seed) : rng_(seed) {}
  UInt<2> tick() {
    if (hold_ == 0)
      redraw();
    --hold_;
    UInt<2> ab = odoloc::board::encoder_pins(source_.tick());
    if (glitch_ == 0 && rng_() % 200'000 == 0) {
      glitch_ = 1 + rng_() % 4;
      glitch_line_ = UInt<2>::truncate(1U << (rng_() % 2));
    }
    if (glitch_ != 0) {
      --glitch_;
      ab = ab ^ glitch_line_;
    }
    return ab;
  }

 private:
  void redraw() {
    const double sign = rng_() % 2 ? 1.0 : -1.0;
    switch (rng_() % 4) {
      case 0:
        source_.set_rate(0.0);
        hold_ = 5'000'000 + rng_() % 10'000'000;
        return;
      case 1:
        source_.set_rate(sign * std::uniform_real_distribution<double>(1e-6, 1e-4)(rng_));
        break;
      default:
        source_.set_rate(sign * std::uniform_real_distribution<double>(1e-4, 0.05)(rng_));
        break;
    }
    hold_ = 1 + rng_() % 3'000'000;
  }
  std::mt19937_64 rng_;
  odoloc::world::QuadratureSource source_;
  std::uint64_t hold_ = 0;
  std::uint64_t glitch_ = 0;
  UInt<2> glitch_line_;
};

void run_scenario(std::uint64_t seed, std::uint64_t clocks) {
  std::mt19937_64 rng(seed);
  TwinChips chips;
  std::array<EncoderLine, 4> encoders{EncoderLine(seed * 10 + 1), EncoderLine(seed * 10 + 2),
                                      EncoderLine(seed * 10 + 3), EncoderLine(seed * 10 + 4)};
  std::array<PulseLine, 9> lines{
      PulseLine(seed * 20 + 1, 3e5), PulseLine(seed * 20 + 2, 3e5), PulseLine(seed * 20 + 3, 1e6),
      PulseLine(seed * 20 + 4, 1e6), PulseLine(seed * 20 + 5, 3e6), PulseLine(seed * 20 + 6, 3e6),
      PulseLine(seed * 20 + 7, 1e7), PulseLine(seed * 20 + 8, 1e7), PulseLine(seed * 20 + 9, 2e6)};
  std::exponential_distribution<double> frame_gap(1.0 / 1e6);
  ChipPins pins;
  const auto clock = [&](UInt<1> sclk, UInt<1> cs_n, UInt<1> mosi) {
    for (std::size_t w = 0; w < encoders.size(); ++w)
      pins.encoders[w] = encoders[w].tick();
    std::uint64_t comparators = 0;
    for (std::size_t i = 0; i < 8; ++i)
      comparators |= std::uint64_t{lines[i].tick()} << i;
    pins.comparators = UInt<8>::truncate(comparators);
    pins.tof_sync = UInt<1>::truncate(lines[8].tick());
    pins.sclk = sclk;
    pins.cs_n = cs_n;
    pins.mosi = mosi;
    pins.reset = UInt<1>::truncate(rng() % 20'000'000 == 0);
    chips.clock(pins);
    if (chips.clocks() % (1U << 20) == 0) {
      const std::string diff = chips.difference();
      if (!diff.empty())
        ADD_FAILURE() << "seed " << seed << ", clock " << chips.clocks() << ": " << diff;
    }
    return chips.stepped().miso();
  };
  odoloc::tb::SpiMasterBfm master({.half_period = 4, .mode3 = false});
  while (chips.clocks() < clocks && !testing::Test::HasFailure()) {
    const auto gap = static_cast<std::uint64_t>(frame_gap(rng));
    for (std::uint64_t k = 0; k < gap; ++k)
      clock(UInt<1>{}, UInt<1>{1}, UInt<1>{});
    master.transfer(odoloc::tb::random_frame(rng), clock);
    const std::string diff = chips.difference();
    if (!diff.empty())
      ADD_FAILURE() << "seed " << seed << ", frame end at clock " << chips.clocks() << ": " << diff;
  }
  // Many clocks were skipped, not stepped (about 40 %: the encoders run up to
  // 0.05 edges per clock), so the comparison is of the fast path.
  EXPECT_GT(chips.skipped(), chips.clocks() / 4) << "seed " << seed;
  // And the sensor side lagged behind the slave through most frame clocks.
  EXPECT_GT(chips.lagged(), chips.frame_clocks() / 2) << "seed " << seed;
}

TEST(FastForward, BitIdenticalToCycleSteppingOverRandomScenarios) {
  const std::uint64_t clocks = odoloc::tb::scaled(30'000'000);
  for (std::uint64_t seed = 1; seed <= 3 && !HasFailure(); ++seed)
    run_scenario(seed, clocks);
}

// Directed: the boundaries a random run may pass between two comparisons.
// One copy of `block` is stepped, another fast-forwarded, with `in` held, to
// each checkpoint (clocks from now, ascending); "" or the first difference.
template <class Block, class... Config>
std::string difference_at(const Block& start, const typename Block::In& in,
                          const std::vector<std::uint64_t>& checkpoints, const Config&... config) {
  Block stepped = start;
  Block forwarded = start;  // one jump per segment between checkpoints
  std::uint64_t now = 0;
  for (const std::uint64_t checkpoint : checkpoints) {
    odoloc::rtl::fast_forward(forwarded, checkpoint - now, in, config...);
    for (; now < checkpoint; ++now)
      stepped.step(in, config...);
    Block jumped = start;  // and one jump from the start
    odoloc::rtl::fast_forward(jumped, checkpoint, in, config...);
    for (const Block* other : {&forwarded, &jumped})
      if (std::string diff = odoloc::tb::first_difference(stepped, *other); !diff.empty())
        return "at clock " + std::to_string(checkpoint) + ": " + diff;
  }
  return {};
}

std::vector<std::uint64_t> around(std::initializer_list<std::uint64_t> boundaries) {
  std::vector<std::uint64_t> clocks;
  for (const std::uint64_t b : boundaries)
    for (std::uint64_t c = b - 2; c <= b + 2; ++c)
      clocks.push_back(c);
  return clocks;
}

// A stopped wheel, a tick every clock: the period count saturates at 2^23 - 1
// and the next tick sets overflow.
TEST(FastForward, PeriodMeterSaturatesAsStepping) {
  odoloc::rtl::Eppm eppm;
  odoloc::rtl::EppmConfig cfg;
  cfg.prescale.divider = UInt<16>{0};
  cfg.window.clocks = UInt<23>{1'000'000};
  const odoloc::rtl::EppmInputs in{};
  for (int k = 0; k < 8; ++k)  // settle the pipeline
    eppm.step(in, cfg);
  const std::uint64_t saturation =
      odoloc::rtl::PeriodTicks::max_value - eppm.period().count.value();
  EXPECT_EQ(difference_at(eppm, in, around({saturation, saturation + 1'000'000}), cfg), "");
}

// A settled EPPM (a nonzero count, a sticky phase error) given a control
// and held there, its pins unchanged or new: a latch-and-clear, a flag's
// clear and a reset each make every clock an event, which fast-forward
// steps (the EPPM's horizon asks for calm before anything else).
TEST(FastForward, HeldControlsOnASettledEppmAsStepping) {
  odoloc::rtl::EppmConfig cfg;
  cfg.prescale.divider = UInt<16>{3};
  cfg.window.clocks = UInt<23>{500};
  odoloc::rtl::Eppm settled;
  odoloc::rtl::EppmInputs in{};
  // Four forward steps, then both lines at once (illegal), then settling.
  for (const unsigned ab : {0U, 1U, 3U, 2U, 0U, 3U, 3U, 3U}) {
    in.a = UInt<1>::truncate(ab >> 1);
    in.b = UInt<1>::truncate(ab);
    for (int k = 0; k < 10; ++k)
      settled.step(in, cfg);
  }
  ASSERT_NE(settled.count().value(), 0);
  ASSERT_EQ(settled.decoder().phase_error.value(), 1U);
  std::array<odoloc::rtl::EppmInputs, 6> controls{in, in, in, in, in, in};
  controls[0].latch_clear = UInt<1>{1};
  controls[1].clear.status.phase_error = UInt<1>{1};
  controls[2].clear.status.carry = UInt<1>{1};
  controls[3].clear.status.borrow = UInt<1>{1};
  controls[4].clear.status.period_overflow = UInt<1>{1};
  controls[5].reset = UInt<1>{1};
  for (std::size_t c = 0; c < controls.size(); ++c)
    for (const unsigned a : {1U, 0U}) {  // A held (pins unchanged), then A new
      odoloc::rtl::EppmInputs held = controls[c];
      held.a = UInt<1>::truncate(a);
      EXPECT_EQ(difference_at(settled, held, {1, 2, 3, 7, 40, 600}, cfg), "")
          << "control " << c << ", A " << a;
    }
}

// An update period of 0 stops updates; the period counter still wraps at 2^16.
TEST(FastForward, StoppedUpdatesWrapThePeriodCounterAsStepping) {
  odoloc::rtl::OdometryFabric fabric;
  odoloc::rtl::OdometryFabric::Config cfg;
  cfg.odometry.cfg.update_clocks = UInt<16>{};
  const odoloc::rtl::OdometryFabric::In in{};
  EXPECT_EQ(difference_at(fabric, in, around({65'536, 3 * 65'536}), cfg), "");
}

// A pulse in progress counts the timestamp's epochs (its width saturates
// after three); at prescale 0 and 3 an epoch is every 2^23 ticks.
TEST(FastForward, EpochsDuringALongPulseAsStepping) {
  for (const unsigned prescale : {0U, 3U}) {
    odoloc::rtl::ChipTofCapture tof;
    odoloc::rtl::ChipTofCapture::Config cfg;
    cfg.tof.cfg.prescale = UInt<16>{prescale};
    odoloc::rtl::ChipTofCapture::In arm{};
    arm.tof.command.arm = UInt<8>{1};
    tof.step(arm, cfg);
    odoloc::rtl::ChipTofCapture::In high{};
    high.comparators = UInt<8>{1};
    for (int k = 0; k < 8; ++k)  // the rise reaches channel 0
      tof.step(high, cfg);
    ASSERT_EQ(tof.channel(0).in_progress.value(), 1U);
    const std::uint64_t epoch = std::uint64_t{1} << odoloc::rtl::TofTimebase::kEpochBits;
    const std::uint64_t ticks = epoch - tof.timebase().timestamp.value();
    const std::uint64_t first = tof.timebase().prescale_count.value() <= prescale
                                    ? prescale - tof.timebase().prescale_count.value()
                                    : 0;
    const auto epoch_clock = [&](std::uint64_t k) {
      return first + (ticks + k * epoch - 1) * (prescale + 1);
    };
    EXPECT_EQ(
        difference_at(tof, high, around({epoch_clock(0), epoch_clock(1), epoch_clock(3)}), cfg), "")
        << "prescale " << prescale;
  }
}

// The sim target's link fast-forwards while no stimulus drives the pins:
// against a cycle-stepped link, the same register reads (timestamps, the
// odometry period counter, EPPM status) return the same words, and every
// register agrees, after idle stretches of up to 0.1 s.
TEST(FastForward, ChipLinkAdvanceReadsTheSameRegisters) {
  odoloc::board::ChipLink stepped({.half_period = 4});
  odoloc::board::ChipLink forwarded({.half_period = 4});
  stepped.set_cycle_step(true);
  odoloc::sw::SpiRegisterBus stepped_bus(stepped, {.crc = false, .confirm_writes = true});
  odoloc::sw::SpiRegisterBus forwarded_bus(forwarded, {.crc = false, .confirm_writes = true});
  namespace regs = odoloc::regs;
  for (auto* bus : {&stepped_bus, &forwarded_bus}) {
    bus->write(regs::tof::cfg::kAddress, regs::tof::cfg::prescale.set(0, 2));
    bus->write(regs::eppm::prescale::address(0), 0);
    bus->write(regs::tof::command::kAddress, regs::tof::command::arm.set(0, 0xFF));
  }
  std::mt19937_64 rng(5);
  // The stepped link clocks the whole chip every clock: ODOLOC_TEST_SCALE
  // shortens the idle stretches (the sanitizers' build runs it at 0.3).
  const auto most_idle = std::max<std::uint64_t>(odoloc::tb::scaled(5'000'000), 1);
  for (int k = 0; k < 40; ++k) {
    const std::uint64_t idle = rng() % most_idle;
    stepped.advance(idle);
    forwarded.advance(idle);
    std::array<std::uint32_t, 8> a{}, b{};
    const auto address =
        static_cast<std::uint16_t>(rng() % 2 ? regs::tof::kBase : regs::eppm::kBase);
    stepped_bus.read(address, a);
    forwarded_bus.read(address, b);
    ASSERT_EQ(a, b) << "read " << k;
    ASSERT_EQ(odoloc::tb::first_difference(stepped.chip(), forwarded.chip()), "") << "read " << k;
  }
  EXPECT_EQ(stepped.clocks(), forwarded.clocks());
  EXPECT_EQ(stepped.skipped_clocks(), 0U);
  EXPECT_GT(forwarded.skipped_clocks(), forwarded.clocks() * 9 / 10);
}

}  // namespace
