// The whole chip through its pins: the SoC-side bus (sw::SpiRegisterBus)
// drives the pin-level master, the fabric answers through its register file.
// Expected values come from odoloc/regs.hpp and from the fabric's own
// registers, never from a previous run.
#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "odoloc/board/chip_link.hpp"
#include "odoloc/board/encoder_pins.hpp"
#include "odoloc/regs.hpp"
#include "odoloc/sw/spi_frame.hpp"
#include "odoloc/world/quadrature_source.hpp"
#include "register_by_path.hpp"

namespace {

namespace regs = odoloc::regs;
using odoloc::board::ChipLink;
using odoloc::board::SpiPinMaster;
using odoloc::rtl::Encoder;
using odoloc::rtl::UInt;
using odoloc::sw::BusError;
using odoloc::sw::SpiOp;
using odoloc::sw::SpiRegisterBus;
using odoloc::world::QuadratureSource;
using Words = std::vector<std::uint32_t>;

constexpr std::uint32_t kRefused = regs::top::spi_status::write_refused.mask();
constexpr std::uint32_t kCrcError = regs::top::spi_status::crc_error.mask();
constexpr std::uint32_t kBadLength = regs::top::spi_status::bad_length.mask();
constexpr std::uint32_t kOverrun = regs::top::spi_status::overrun.mask();

using odoloc::tb::reg;
bool writable(const regs::Register& r) {
  return (r.rw_mask | r.w1c_mask | r.w1p_mask) != 0;
}

// Encoder stimulus: one NCO per wheel, rates set by the test.
struct Encoders {
  std::array<QuadratureSource, 4> sources;
  void operator()(std::array<UInt<2>, 4>& pins) {
    for (std::size_t w = 0; w < 4; ++w)
      pins[w] = odoloc::board::encoder_pins(sources[w].tick());
  }
};

struct ChipBench {
  Encoders encoders;
  ChipLink link{{.half_period = 4}, [this](auto& pins) { encoders(pins.encoders); }};
  SpiRegisterBus bus{link, {.crc = false, .confirm_writes = false}};

  std::uint32_t read(std::string_view path) { return bus.read(reg(path).address); }
  void write(std::string_view path, std::uint32_t value) { bus.write(reg(path).address, value); }
  void stop_odometry() {
    write("odometry.cfg", regs::odometry::cfg::update_clocks.set(regs::odometry::cfg::kReset, 0));
  }
  // Clears top.spi_status and returns what it held.
  std::uint32_t take_spi_status() {
    const std::uint32_t s = read("top.spi_status");
    write("top.spi_status", s);
    return s;
  }
  // Runs a frame whose bytes the test has built, cut after `bits` SCLK edges.
  void raw_frame(const std::vector<std::uint8_t>& mosi, std::size_t bits = SpiPinMaster::kNoAbort) {
    link.transfer_bits(mosi, bits);
  }
};

// Every mapped register reads its documented reset value: the model, the
// generated header (and through test_regmap the YAML and the docs) agree.
TEST(OdolocChip, EveryRegisterReadsItsResetValue) {
  ChipBench b;
  for (const regs::Register& r : regs::kRegisters) {
    const std::uint64_t updates_before = b.link.chip().fabric().sequencer().updates.value();
    const std::uint64_t clocks_before = b.link.clocks();
    const std::uint32_t value = b.bus.read(r.address);
    if (r.address == regs::odometry::updates::kAddress) {  // free-running from reset
      EXPECT_GE(value, updates_before);
      EXPECT_LE(value, b.link.chip().fabric().sequencer().updates.value());
      continue;
    }
    if (r.address == regs::tof::timestamp::kAddress) {  // counts clocks from reset (prescale 0)
      EXPECT_GT(value, clocks_before);
      EXPECT_LT(value, b.link.clocks());
      continue;
    }
    EXPECT_EQ(value, r.reset) << r.path;
  }
  EXPECT_EQ(b.read("top.spi_status"), 0U);
}

TEST(OdolocChip, UnmappedAndReservedAddressesReadZeroAndRefuseWrites) {
  ChipBench b;
  for (const std::uint16_t a : {std::uint16_t{0x005}, std::uint16_t{0x00F}, std::uint16_t{0x04D},
                                std::uint16_t{0x087}, std::uint16_t{0x105}, std::uint16_t{0x115},
                                std::uint16_t{0x1D0}, std::uint16_t{0x1FF}, std::uint16_t{0x3FF}}) {
    ASSERT_EQ(regs::find(a), nullptr);
    EXPECT_EQ(b.bus.read(a), 0U) << a;
    b.bus.write(a, 0xFFFFFFFFU);
    EXPECT_EQ(b.take_spi_status(), kRefused) << a;
    EXPECT_EQ(b.bus.read(a), 0U) << a;
  }
}

// Random words into every writable register: rw bits read back, the fabric's
// configuration ports see the decoded fields.
TEST(OdolocChip, RwRegistersStoreTheirBitsAndDriveTheFabric) {
  ChipBench b;
  std::mt19937 rng(7);  // 32-bit words
  for (int round = 0; round < 3; ++round) {
    std::vector<std::pair<const regs::Register*, std::uint32_t>> written;
    for (const regs::Register& r : regs::kRegisters) {
      if (r.rw_mask == 0)
        continue;
      // Keep the SPI settings: they change the framing of the next frame.
      const auto v = static_cast<std::uint32_t>(r.address == regs::top::ctrl::kAddress ? 0 : rng());
      b.bus.write(r.address, v);
      written.emplace_back(&r, v);
    }
    EXPECT_EQ(b.take_spi_status(), 0U);
    for (const auto& [r, v] : written)
      EXPECT_EQ(b.bus.read(r->address), v & r->rw_mask) << r->path;

    const odoloc::ports::Config& c = b.link.chip().config();
    for (unsigned i = 0; i < 4; ++i) {
      namespace e = regs::eppm;
      const std::uint32_t cfg = b.bus.read(e::cfg::address(i));
      EXPECT_EQ(c.eppm[i].cfg.filter_clocks.value(), e::cfg::filter_clocks.get(cfg));
      EXPECT_EQ(c.eppm[i].cfg.decode_mode.value(), e::cfg::decode_mode.get(cfg));
      EXPECT_EQ(c.eppm[i].cfg.speed_mode_select.value(), e::cfg::speed_mode_select.get(cfg));
      EXPECT_EQ(c.eppm[i].window.clocks.value(), b.bus.read(e::window::address(i)));
      EXPECT_EQ(c.eppm[i].prescale.divider.value(), b.bus.read(e::prescale::address(i)));
      EXPECT_EQ(c.eppm[i].to_period_below.edges.value(),
                b.bus.read(e::to_period_below::address(i)));
      EXPECT_EQ(c.eppm[i].to_pulse_at.edges.value(), b.bus.read(e::to_pulse_at::address(i)));
      EXPECT_EQ(c.eppm[i].stall_ticks.ticks.value(), b.bus.read(e::stall_ticks::address(i)));
    }
    namespace o = regs::odometry;
    const std::uint32_t cfg = b.read("odometry.cfg");
    EXPECT_EQ(c.odometry.cfg.update_clocks.value(), o::cfg::update_clocks.get(cfg));
    EXPECT_EQ(c.odometry.cfg.policy.value(), o::cfg::policy.get(cfg));
    EXPECT_EQ(c.odometry.cfg.select_shift.value(), o::cfg::select_shift.get(cfg));
    EXPECT_EQ(c.odometry.rear_ds_scale.value.value(), b.read("odometry.rear_ds_scale"));
    EXPECT_EQ(c.odometry.rear_dtheta_scale.value.value(), b.read("odometry.rear_dtheta_scale"));
    EXPECT_EQ(c.odometry.front_ds_scale.value.value(), b.read("odometry.front_ds_scale"));
    EXPECT_EQ(c.odometry.front_dtheta_scale.value.value(), b.read("odometry.front_dtheta_scale"));
    EXPECT_EQ(c.odometry.steer_scale.value.value(), b.read("odometry.steer_scale"));
    EXPECT_EQ(c.odometry.steer_limit.value.value(), b.read("odometry.steer_limit"));
    EXPECT_EQ(c.odometry.select_ds_threshold.value.value(), b.read("odometry.select_ds_threshold"));
    EXPECT_EQ(c.odometry.select_dtheta_threshold.value.value(),
              b.read("odometry.select_dtheta_threshold"));
  }
}

// A write to a read-only register is refused, flagged and changes nothing,
// while the encoders keep the fabric busy.
TEST(OdolocChip, ReadOnlyRegistersRefuseWrites) {
  ChipBench b;
  b.stop_odometry();  // updates and the sequencer phase would move
  b.link.advance(1000);
  std::vector<std::pair<const regs::Register*, std::uint32_t>> before;
  for (const regs::Register& r : regs::kRegisters)
    if (!writable(r))
      before.emplace_back(&r, b.bus.read(r.address));
  for (const auto& [r, v] : before) {
    b.bus.write(r->address, ~v);
    const std::uint32_t status = b.read("top.spi_status");
    EXPECT_EQ(status & kRefused, kRefused) << r->path;
    b.write("top.spi_status", status);
  }
  for (const auto& [r, v] : before) {
    if (r->address == regs::top::frame_errors::kAddress || r->address == regs::top::id::kAddress ||
        r->address == regs::tof::timestamp::kAddress)
      continue;  // frame_errors counted the refusals; id is checked below; the timestamp runs
    EXPECT_EQ(b.bus.read(r->address), v) << r->path;
  }
  EXPECT_EQ(b.read("top.id"), regs::top::id::kReset);
  // One error per refused frame, and reading returns and clears them.
  EXPECT_EQ(b.read("top.frame_errors"), before.size());
  EXPECT_EQ(b.read("top.frame_errors"), 0U);
}

// A burst from frame_errors (rc, not writable) over scratch (rw): the
// writable word lands, the refused one is dropped and flagged.
TEST(OdolocChip, MixedBurstWritesTheWritableWords) {
  ChipBench b;
  const Words words{0x1234U, 0xCAFEF00DU};
  b.bus.write(regs::top::frame_errors::kAddress, words);
  EXPECT_EQ(b.take_spi_status(), kRefused);
  EXPECT_EQ(b.read("top.scratch"), 0xCAFEF00DU);
  EXPECT_EQ(b.read("top.frame_errors"), 1U);
}

// Sticky EPPM flags: each w1c bit clears its own flag only.
TEST(OdolocChip, EppmStatusClearsExactlyTheBitsWritten) {
  namespace e = regs::eppm;
  ChipBench b;
  b.stop_odometry();  // its latch-and-clear would restart the count
  const unsigned left = static_cast<unsigned>(Encoder::kLeftRear);
  // carry: 2^19 forward edges; phase error: both channels change at once.
  b.encoders.sources[left].set_rate(0.25);
  b.link.advance((1U << 19) * 4 + 200);
  b.encoders.sources[left].set_rate(0.0);
  b.link.advance(100);
  const auto status = [&] { return b.bus.read(e::status::address(left)); };
  ASSERT_EQ(e::status::carry.get(status()), 1U);
  ASSERT_EQ(e::status::phase_error.get(status()), 0U);
  // Two quarter steps in one clock is an illegal transition.
  b.encoders.sources[left].set_rate(2.0);
  b.link.advance(1);
  b.encoders.sources[left].set_rate(0.0);
  b.link.advance(100);
  ASSERT_EQ(e::status::phase_error.get(status()), 1U);
  const std::uint32_t errors = b.bus.read(e::error_count::address(left));
  ASSERT_GE(errors, 1U);
  EXPECT_EQ(e::status::forward.get(status()), 1U);

  b.bus.write(e::status::address(left), e::status::carry.mask());
  EXPECT_EQ(e::status::carry.get(status()), 0U);
  EXPECT_EQ(e::status::phase_error.get(status()), 1U);
  EXPECT_EQ(b.bus.read(e::error_count::address(left)), errors);
  // Writing 0s and the ro direction bit clears nothing.
  b.bus.write(e::status::address(left), e::status::forward.mask());
  EXPECT_EQ(e::status::phase_error.get(status()), 1U);
  b.bus.write(e::status::address(left), e::status::phase_error.mask());
  EXPECT_EQ(status(), e::status::forward.mask());
  EXPECT_EQ(b.bus.read(e::error_count::address(left)), 0U);
  EXPECT_EQ(b.take_spi_status(), 0U);
}

// Period overflow (prescale 0: a tick per clock, 2^23 clocks without an
// edge), cleared by the fabric-wide clear_flags command.
TEST(OdolocChip, ClearFlagsCommandClearsEveryStickyFlag) {
  namespace e = regs::eppm;
  ChipBench b;
  const unsigned right = static_cast<unsigned>(Encoder::kRightRear);
  b.bus.write(e::prescale::address(right), 0);
  b.link.advance((std::uint64_t{1} << 23) + 100);
  ASSERT_EQ(e::status::period_overflow.get(b.bus.read(e::status::address(right))), 1U);
  // While the counter stays saturated the flag sets again at once; an edge
  // restarts the count.
  b.encoders.sources[right].set_rate(0.5);
  b.link.advance(2);
  b.encoders.sources[right].set_rate(0.0);
  b.link.advance(100);
  ASSERT_EQ(e::status::period_overflow.get(b.bus.read(e::status::address(right))), 1U);
  b.bus.write(0x3FF, 0);  // a refused write sets spi_status
  ASSERT_NE(b.read("top.spi_status"), 0U);
  b.write("odometry.command", regs::odometry::command::clear_flags.mask());
  EXPECT_EQ(b.bus.read(e::status::address(right)), e::status::forward.mask());
  EXPECT_EQ(b.read("top.spi_status"), 0U);
  EXPECT_EQ(b.read("odometry.command"), 0U);  // w1p reads 0
}

// set_pose loads the set_* words; the snapshot pose words read them back.
TEST(OdolocChip, SetPoseLoadsThePoseWords) {
  namespace o = regs::odometry;
  ChipBench b;
  b.write("odometry.cfg", o::cfg::update_clocks.set(o::cfg::kReset, 0));  // no updates
  const std::int64_t x = -123'456'789'012'345, y = 987'654'321'098;
  const std::uint64_t theta = 0xAB'1234'5678;
  const auto lo = [](std::int64_t v) { return static_cast<std::uint32_t>(v); };
  const auto hi = [](std::int64_t v) { return static_cast<std::uint32_t>(v >> 32); };
  b.bus.write(o::set_x_lo::kAddress,
              Words{lo(x), hi(x), lo(y), hi(y), static_cast<std::uint32_t>(theta),
                    static_cast<std::uint32_t>(theta >> 32)});
  b.write("odometry.command", o::command::set_pose.mask());
  Words pose(6);
  b.bus.read(o::pose_x_lo::kAddress, pose);
  EXPECT_EQ(pose, (Words{lo(x), hi(x), lo(y), hi(y), static_cast<std::uint32_t>(theta),
                         static_cast<std::uint32_t>(theta >> 32)}));
  EXPECT_EQ(odoloc::rtl::pose_coordinate(b.link.chip().fabric().pose().x).value(), x);
  EXPECT_EQ(odoloc::rtl::pose_coordinate(b.link.chip().fabric().pose().y).value(), y);
  EXPECT_EQ(b.link.chip().fabric().pose().theta.value(), theta);
}

// The increments of the last update and the steering, against the fabric's
// own registers, after a drive with programmed scales.
TEST(OdolocChip, OdometryIncrementWordsAreTheFabricsValues) {
  namespace o = regs::odometry;
  ChipBench b;
  b.write("odometry.rear_ds_scale", 1U << 28);
  b.write("odometry.rear_dtheta_scale", 1U << 26);
  b.write("odometry.front_ds_scale", 3U << 27);
  b.write("odometry.front_dtheta_scale", 1U << 25);
  b.write("odometry.steer_scale", 1U << 24);
  b.encoders.sources[0].set_rate(0.02);
  b.encoders.sources[1].set_rate(0.03);
  b.encoders.sources[2].set_rate(0.025);
  b.encoders.sources[3].set_rate(-0.0004);
  b.link.advance(40'000);  // 8 updates
  b.stop_odometry();       // freezes the values
  Words w(o::steer_position::kAddress - o::rear_ds_lo::kAddress + 1);
  b.bus.read(o::rear_ds_lo::kAddress, w);
  const auto& f = b.link.chip().fabric();
  const auto wide = [&](std::uint16_t lo) {
    const auto i = static_cast<std::size_t>(lo - o::rear_ds_lo::kAddress);
    return static_cast<std::uint64_t>(w[i + 1]) << 32U | w[i];
  };
  const auto raw = [](auto v) { return v.as_uint().value(); };
  EXPECT_NE(f.rear().ds.value(), 0);
  EXPECT_NE(f.front().phi.value(), 0);
  EXPECT_EQ(wide(o::rear_ds_lo::kAddress), raw(f.rear().ds));
  EXPECT_EQ(wide(o::rear_dtheta_lo::kAddress), raw(f.rear().dtheta));
  EXPECT_EQ(wide(o::front_ds_lo::kAddress), raw(f.front().ds));
  EXPECT_EQ(wide(o::front_dtheta_lo::kAddress), raw(f.front().dtheta));
  EXPECT_EQ(wide(o::ds_lo::kAddress), raw(f.select().ds));
  EXPECT_EQ(wide(o::dtheta_lo::kAddress), raw(f.select().dtheta));
  EXPECT_EQ(wide(o::steer_phi_lo::kAddress), raw(f.front().phi));
  EXPECT_EQ(o::steer_position::counts.get_signed(w.back()), f.front().steer_position.value());
  // Signed high words read back as the value's sign.
  EXPECT_EQ(
      o::steer_phi_hi::bits.get_signed(w[o::steer_phi_hi::kAddress - o::rear_ds_lo::kAddress]),
      f.front().phi.value() >> 32);
}

// A burst over both rear counts, with identical encoder signals on both
// wheels: without the snapshot the second count would be read ~4000 clocks
// later, thousands of edges apart.
TEST(OdolocChip, BurstReadsOneInstant) {
  namespace e = regs::eppm;
  ChipBench b;
  b.stop_odometry();  // its latch-and-clear would restart the counts
  b.encoders.sources[0].set_rate(0.45);
  b.encoders.sources[1].set_rate(0.45);
  b.link.advance(1000);
  const unsigned left = e::count::address(0), right = e::count::address(1);
  const auto span = static_cast<std::size_t>(right - left + 1);
  std::int64_t previous = 0;
  for (int i = 0; i < 20; ++i) {
    Words words(span);
    const std::int64_t before =
        b.link.chip().fabric().encoders().eppm(Encoder::kLeftRear).count().value();
    b.bus.read(static_cast<std::uint16_t>(left), words);
    const std::int64_t after =
        b.link.chip().fabric().encoders().eppm(Encoder::kLeftRear).count().value();
    const std::int64_t l = e::count::value.get_signed(words.front());
    EXPECT_EQ(words.front(), words.back()) << i;
    EXPECT_GT(l, previous);
    EXPECT_GE(l, before);
    EXPECT_LT(l, before + 40);   // captured as the frame starts...
    EXPECT_LT(l, after - 1000);  // ...not while it shifts
    previous = l;
  }
}

// top.frame_errors counts frames with errors; a completed read returns and
// clears it, an aborted one clears nothing (and counts).
TEST(OdolocChip, FrameErrorsIsReadToClear) {
  ChipBench b;
  const auto frame =
      odoloc::sw::encode_frame(SpiOp::kWrite, regs::top::scratch::kAddress, 1, Words{5}, false);
  b.raw_frame(frame, 20);  // aborted
  b.raw_frame(frame, 47);  // one bit short
  const auto read_errors =
      odoloc::sw::encode_frame(SpiOp::kRead, regs::top::frame_errors::kAddress, 1, Words{}, false);
  b.raw_frame(read_errors, 40);  // a read cut inside the data counts and clears nothing
  EXPECT_EQ(b.read("top.frame_errors"), 3U);
  EXPECT_EQ(b.read("top.frame_errors"), 0U);
  EXPECT_EQ(b.read("top.scratch"), 0U);
  EXPECT_EQ(b.take_spi_status(), kBadLength);
}

// Writes cut after every bit count leave the register as it was.
TEST(OdolocChip, AbortedWritesCommitNothing) {
  namespace o = regs::odometry;
  ChipBench b;
  const Words old{0x11111111U, 0x22222222U}, fresh{0xAAAAAAAAU, 0x55555555U};
  b.bus.write(o::set_x_lo::kAddress, old);
  const auto frame =
      odoloc::sw::encode_frame(SpiOp::kWrite, o::set_x_lo::kAddress, 2, fresh, false);
  Words now(2);
  for (std::size_t bits = 0; bits < frame.size() * 8; ++bits) {
    b.raw_frame(frame, bits);
    b.bus.read(o::set_x_lo::kAddress, now);
    ASSERT_EQ(now, old) << bits;
    ASSERT_EQ(b.take_spi_status(), kBadLength) << bits;
  }
  b.raw_frame(frame);
  b.bus.read(o::set_x_lo::kAddress, now);
  EXPECT_EQ(now, fresh);
  EXPECT_EQ(b.read("top.frame_errors"), frame.size() * 8);
}

// CRC on through top.ctrl: the bus follows, a corrupted write is discarded
// and flagged, and the next frame works.
TEST(OdolocChip, CrcFramesAndCorruptedWrites) {
  ChipBench b;
  b.write("top.ctrl", regs::top::ctrl::crc_enable.mask());
  ASSERT_TRUE(b.bus.crc());
  b.write("top.scratch", 0x600DF00DU);
  EXPECT_EQ(b.read("top.scratch"), 0x600DF00DU);
  for (std::size_t flip = 0; flip < 7 * 8; ++flip) {
    auto frame = odoloc::sw::encode_frame(SpiOp::kWrite, regs::top::scratch::kAddress, 1,
                                          Words{0xBADU}, true);
    frame[flip / 8] = static_cast<std::uint8_t>(frame[flip / 8] ^ (0x80U >> (flip % 8)));
    b.raw_frame(frame);
    // A flip in the command may make it a read, another length or another
    // address; scratch keeps its value and the frame is flagged either way.
    ASSERT_EQ(b.read("top.scratch"), 0x600DF00DU) << flip;
    const std::uint32_t status = b.take_spi_status();
    ASSERT_NE(status & (kCrcError | kBadLength), 0U) << flip;
  }
  b.write("top.ctrl", 0);
  EXPECT_FALSE(b.bus.crc());
  EXPECT_EQ(b.read("top.ctrl"), 0U);
}

// A new bus on a board left with CRC on adopts it from top.ctrl.
TEST(OdolocChip, NewBusAdoptsTheSlavesCrcSetting) {
  ChipBench b;
  b.write("top.ctrl", regs::top::ctrl::crc_enable.mask());
  SpiRegisterBus later(b.link, {.crc = false, .confirm_writes = true});
  EXPECT_TRUE(later.crc());
  later.write(regs::top::scratch::kAddress, 0xC0FFEEU);
  EXPECT_EQ(later.read(regs::top::scratch::kAddress), 0xC0FFEEU);
}

TEST(OdolocChip, Mode3ThroughCtrl) {
  ChipBench b;
  b.write("top.ctrl", regs::top::ctrl::spi_mode3.mask());
  ASSERT_TRUE(b.link.master().config().mode3);
  b.write("top.scratch", 0x3333CCCCU);
  EXPECT_EQ(b.read("top.scratch"), 0x3333CCCCU);
  EXPECT_EQ(b.read("top.ctrl"), regs::top::ctrl::spi_mode3.mask());
  EXPECT_EQ(b.take_spi_status(), 0U);
}

// SCLK faster than the synchronisers allow: flagged, nothing written, and
// the next frame at a legal speed works.
TEST(OdolocChip, SclkTooFastIsFlaggedAndRecovers) {
  ChipBench b;
  b.write("top.scratch", 1);
  for (const unsigned half_period : {1U, 2U, 3U}) {
    b.link.master() = SpiPinMaster({.half_period = half_period});
    b.raw_frame(
        odoloc::sw::encode_frame(SpiOp::kWrite, regs::top::scratch::kAddress, 1, Words{2}, false));
    b.link.master() = SpiPinMaster({.half_period = 4});
    EXPECT_EQ(b.read("top.scratch"), 1U) << half_period;
    EXPECT_NE(b.take_spi_status() & (kOverrun | kBadLength), 0U) << half_period;
  }
}

// The confirming bus reports a refused write as an error naming the flag.
TEST(OdolocChip, ConfirmingBusThrowsOnRefusedWrite) {
  ChipBench b;
  SpiRegisterBus confirming(b.link, {.crc = true, .confirm_writes = true});
  confirming.write(regs::top::scratch::kAddress, 77);
  EXPECT_EQ(confirming.read(regs::top::scratch::kAddress), 77U);
  try {
    confirming.write(regs::top::id::kAddress, 0);
    FAIL() << "no error";
  } catch (const BusError& e) {
    EXPECT_NE(std::string{e.what()}.find("write_refused"), std::string::npos) << e.what();
  }
}

// Activity gating of the whole chip: a gated chip, one switching between
// gated and ungated runs (the gating's bookkeeping survives them) and an
// ungated chip see the same pins (random frames, moving encoders) and must
// agree on every register-file and slave register and on every readable
// register, every clock (the mixed chip's readable registers every 8th:
// a divergence persists).
TEST(OdolocChip, GatedAndUngatedChipsAgree) {
  odoloc::rtl::OdolocChip gated, mixed, full;
  odoloc::rtl::ChipPins pins;
  std::array<QuadratureSource, 4> sources{QuadratureSource(0.01), QuadratureSource(-0.2),
                                          QuadratureSource(0.0003), QuadratureSource(0.05)};
  std::uint64_t clocks = 0;
  const auto agrees = [&](const odoloc::rtl::OdolocChip& chip, const char* which, bool readable) {
    EXPECT_TRUE(chip.spi() == full.spi()) << which << ", clock " << clocks;
    EXPECT_EQ(chip.registers().regs(), full.registers().regs()) << which << ", clock " << clocks;
    if (!readable)
      return;
    // The status words once per clock, not once per register (the read
    // itself is what is compared).
    const odoloc::rtl::EncodedStatus chip_status{chip.fabric().status(chip.config())};
    const odoloc::rtl::EncodedStatus full_status{full.fabric().status(full.config())};
    for (const regs::Register& r : regs::kRegisters) {
      const auto a = UInt<10>::truncate(r.address);
      if (chip.registers().read(a, chip_status) != full.registers().read(a, full_status)) {
        ADD_FAILURE() << r.path << " differs at clock " << clocks << ", " << which;
        return;
      }
    }
  };
  const auto step = [&](UInt<1> sclk, UInt<1> cs_n, UInt<1> mosi) {
    for (std::size_t w = 0; w < 4; ++w)
      pins.encoders[w] = odoloc::board::encoder_pins(sources[w].tick());
    pins.sclk = sclk;
    pins.cs_n = cs_n;
    pins.mosi = mosi;
    gated.step<odoloc::rtl::Gating::kOn>(pins);
    full.step<odoloc::rtl::Gating::kOff>(pins);
    if ((clocks / 997) % 2 == 0)  // runs of 997 clocks, out of step with the frames
      mixed.step<odoloc::rtl::Gating::kOn>(pins);
    else
      mixed.step<odoloc::rtl::Gating::kOff>(pins);
    ++clocks;
    agrees(gated, "gated", true);
    agrees(mixed, "mixed gating", clocks % 8 == 0);
    return full.miso();
  };
  std::mt19937 rng(11);
  SpiPinMaster master({.half_period = 4});
  for (int frame = 0; frame < 300 && !HasFailure(); ++frame) {
    const bool read = rng() % 2 == 0;
    const regs::Register& r = regs::kRegisters[rng() % std::size(regs::kRegisters)];
    // Writes avoid top.ctrl (it would change the framing) and reset-like
    // commands, but hit every other writable register, w1c and w1p included.
    const unsigned n = 1 + static_cast<unsigned>(rng() % 4);
    Words words(n);
    for (auto& w : words)
      w = static_cast<std::uint32_t>(rng());
    const auto address = static_cast<std::uint16_t>(
        r.address == regs::top::ctrl::kAddress ? regs::top::scratch::kAddress : r.address);
    master.transfer(
        odoloc::sw::encode_frame(read ? SpiOp::kRead : SpiOp::kWrite, address, n, words, false),
        step, rng() % 10 == 0 ? rng() % 80 : SpiPinMaster::kNoAbort);
    for (auto idle = rng() % 3000; idle > 0; --idle)
      step(UInt<1>{}, UInt<1>{1}, UInt<1>{});
  }
  EXPECT_GT(clocks, 300'000U);
}

}  // namespace
