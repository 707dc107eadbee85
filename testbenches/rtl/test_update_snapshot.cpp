// The results of one odometry update (the update count, the pose and the
// increments and steering of that update) change on one clock edge, so an SPI
// snapshot can never pair the pose of one update with the count or the
// increments of another. The test snapshots the block through the chip's pins
// at every clock of the update period (so also in the clocks around each
// update's completion) and checks every read against the one set of results
// the fabric ever showed for that update count.
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <map>
#include <set>
#include <vector>

#include "odoloc/board/encoder_pins.hpp"
#include "odoloc/regs.hpp"
#include "odoloc/rtl/odoloc_chip.hpp"
#include "odoloc/world/quadrature_source.hpp"
#include "spi_master_bfm.hpp"

namespace {

using odoloc::rtl::ChipPins;
using odoloc::rtl::OdolocChip;
using odoloc::rtl::UInt;
namespace regs = odoloc::regs;
namespace o = regs::odometry;

constexpr unsigned kPeriod = 64;  // update_clocks: every phase of it is snapshot once
// odometry.updates .. odometry.steer_position: the count, the pose, the
// increments, steering.
constexpr unsigned kFirst = o::updates::kAddress;
constexpr unsigned kWords = o::steer_position::kAddress - kFirst + 1;

using Results = std::vector<std::uint64_t>;

// What the fabric shows of its last update now, read from its registers.
Results fabric_results(const OdolocChip& chip) {
  const auto& f = chip.fabric();
  const auto& r = f.report();
  return {f.sequencer().updates.value(),
          odoloc::rtl::pose_coordinate(f.pose().x).raw_bits(),
          odoloc::rtl::pose_coordinate(f.pose().y).raw_bits(),
          f.pose().theta.value(),
          r.rear_ds.raw_bits(),
          r.rear_dtheta.raw_bits(),
          r.front_ds.raw_bits(),
          r.front_dtheta.raw_bits(),
          r.ds.raw_bits(),
          r.dtheta.raw_bits(),
          r.steer_phi.raw_bits(),
          r.steer_position.raw_bits()};
}

// The same, decoded from the words of one read burst with the map's fields.
Results read_results(const std::vector<std::uint32_t>& w) {
  const auto word = [&](unsigned address) { return w[address - kFirst]; };
  const auto wide = [&](unsigned lo, unsigned hi, unsigned width) {
    const std::uint64_t bits = (std::uint64_t{word(hi)} << 32) | word(lo);
    return width == 64 ? bits : bits & ((std::uint64_t{1} << width) - 1);
  };
  return {word(o::updates::kAddress),
          wide(o::pose_x_lo::kAddress, o::pose_x_hi::kAddress, 64),
          wide(o::pose_y_lo::kAddress, o::pose_y_hi::kAddress, 64),
          wide(o::pose_theta_lo::kAddress, o::pose_theta_hi::kAddress, 40),
          wide(o::rear_ds_lo::kAddress, o::rear_ds_hi::kAddress, 48),
          wide(o::rear_dtheta_lo::kAddress, o::rear_dtheta_hi::kAddress, 56),
          wide(o::front_ds_lo::kAddress, o::front_ds_hi::kAddress, 48),
          wide(o::front_dtheta_lo::kAddress, o::front_dtheta_hi::kAddress, 56),
          wide(o::ds_lo::kAddress, o::ds_hi::kAddress, 48),
          wide(o::dtheta_lo::kAddress, o::dtheta_hi::kAddress, 56),
          wide(o::steer_phi_lo::kAddress, o::steer_phi_hi::kAddress, 40),
          o::steer_position::counts.get(word(o::steer_position::kAddress))};
}

TEST(UpdateSnapshot, AnUpdatesResultsChangeTogetherAndAReadNeverMixesUpdates) {
  OdolocChip chip;
  ChipPins pins;
  std::array<odoloc::world::QuadratureSource, 4> sources{
      odoloc::world::QuadratureSource{0.011}, odoloc::world::QuadratureSource{0.013},
      odoloc::world::QuadratureSource{0.007}, odoloc::world::QuadratureSource{0.002}};
  std::map<std::uint64_t, Results> shown;  // per update count, what the fabric showed
  std::set<std::uint64_t> snapshot_phases;
  odoloc::tb::SpiMasterBfm master({.half_period = 4, .mode3 = false});

  const auto step = [&](UInt<1> sclk, UInt<1> cs_n, UInt<1> mosi) {
    for (std::size_t w = 0; w < sources.size(); ++w) {
      pins.encoders[w] = odoloc::board::encoder_pins(sources[w].tick());
    }
    pins.sclk = sclk;
    pins.cs_n = cs_n;
    pins.mosi = mosi;
    if (chip.spi().engine().snapshot)  // this clock's registers are what the bank captures
      snapshot_phases.insert(chip.fabric().sequencer().period_count.value());
    chip.step(pins);
    const Results now = fabric_results(chip);
    const auto [it, first] = shown.emplace(now[0], now);
    if (!first && it->second != now)
      ADD_FAILURE() << "update " << now[0] << ": its results changed in another clock";
    return chip.miso();
  };
  const auto write = [&](unsigned address, std::vector<std::uint32_t> words) {
    master.transfer(odoloc::tb::spi_frame(odoloc::tb::SpiOp::kWrite, address, words, false), step);
  };
  // Short periods, scales that make every increment non-zero, a steering limit.
  write(o::cfg::kAddress, {o::cfg::update_clocks.set(0, kPeriod), 0x12345678, 0x00ABCDEF, 0x2345678,
                           0x0123456, 0x0003456, 477'218'588});

  std::vector<std::uint32_t> words(kWords, 0);
  for (unsigned phase = 0; phase < kPeriod; ++phase) {
    // Start the frame so the slave sees cs_n fall at this phase of the period.
    while ((chip.fabric().sequencer().period_count.value() + 4) % kPeriod != phase)
      step(UInt<1>{}, UInt<1>{1}, UInt<1>{});
    const std::vector<std::uint8_t> miso = master.transfer(
        odoloc::tb::spi_frame(odoloc::tb::SpiOp::kRead, kFirst, words, false), step);
    const auto reply = odoloc::sw::decode_reply(miso, kWords, false);
    const Results read = read_results(reply.words);
    ASSERT_TRUE(shown.contains(read[0]));
    EXPECT_EQ(read, shown.at(read[0])) << "snapshot at phase " << phase;
  }
  EXPECT_EQ(snapshot_phases.size(), kPeriod);  // every clock of the period was snapshot
  EXPECT_GT(shown.size(), 50U);
}

}  // namespace
