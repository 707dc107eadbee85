// Waveforms name what the registers name. Every register struct has one
// field list (ODOLOC_FIELDS), which cannot miss a member: it does not compile
// then (fields.hpp). These tests check the rest: each block's trace() is
// exactly the walk of its register struct (the same names, in order, with
// the same values), every listed member is a distinct member in declaration
// order, and the whole chip's waveform declares one signal per register.
#include <gtest/gtest.h>

#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

#include "odoloc/logic/register_file.hpp"
#include "odoloc/rtl/odoloc_chip.hpp"
#include "odoloc/rtl/vcd.hpp"
#include "register_dump.hpp"

namespace {

using namespace odoloc::rtl;  // NOLINT(google-build-using-namespace): the blocks under test

// Every scalar of a struct with a field list: dotted paths (array elements
// by index), found by walking the field lists directly.
struct FieldWalk {
  std::vector<std::string> paths;
  template <class T>
  void walk(const std::string& path, const T& value) {
    if constexpr (HasFields<T>) {
      visit_fields(value, [&](std::string_view name, const auto& member) {
        walk(path + std::string(name) + (HasFields<std::decay_t<decltype(member)>> ? "." : ""),
             member);
      });
    } else if constexpr (odoloc::rtl::detail::is_bank<T>) {  // std::array or C array
      for (std::size_t i = 0; i < odoloc::rtl::detail::bank_size<T>; ++i)
        walk(path + "." + std::to_string(i) +
                 (HasFields<std::decay_t<decltype(value[0])>> ? "." : ""),
             value[i]);
    } else {
      paths.push_back(path);
    }
  }
};

template <class Block>
void expect_trace_is_field_list(const Block& block, const char* what) {
  FieldWalk walk;
  walk.walk("", block.regs());
  const odoloc::tb::RegisterDump dump = odoloc::tb::dump_registers(block, true);
  EXPECT_EQ(dump.names, walk.paths) << what;
  EXPECT_FALSE(dump.names.empty()) << what;
}

// The listed members are distinct and in declaration order.
template <class Regs>
void expect_members_in_order(const char* what) {
  const Regs r{};
  std::vector<const void*> addresses;
  visit_fields(r, [&](std::string_view, const auto& member) { addresses.push_back(&member); });
  if constexpr (HasMemberFields<Regs>) {
    EXPECT_EQ(addresses.size(), Regs::kFieldCount) << what;
  }
  for (std::size_t i = 1; i < addresses.size(); ++i)
    EXPECT_LT(addresses[i - 1], addresses[i]) << what << " member " << i;
}

TEST(TraceFields, EveryLeafTracesExactlyItsRegisterStruct) {
  expect_trace_is_field_list(InputConditioner<2>{}, "InputConditioner<2>");
  expect_trace_is_field_list(QuadratureDecoder{}, "QuadratureDecoder");
  expect_trace_is_field_list(PositionCounter{}, "PositionCounter");
  expect_trace_is_field_list(SpeedTimebase{}, "SpeedTimebase");
  expect_trace_is_field_list(PulseMeter{}, "PulseMeter");
  expect_trace_is_field_list(PeriodMeter{}, "PeriodMeter");
  expect_trace_is_field_list(SequentialCordic{}, "SequentialCordic");
  expect_trace_is_field_list(RearOdometryUnit{}, "RearOdometryUnit");
  expect_trace_is_field_list(FrontOdometryUnit{}, "FrontOdometryUnit");
  expect_trace_is_field_list(MinSelect{}, "MinSelect");
  expect_trace_is_field_list(PoseIntegrator{}, "PoseIntegrator");
  expect_trace_is_field_list(OdometryReport{}, "OdometryReport");
  expect_trace_is_field_list(OdometrySequencer{}, "OdometrySequencer");
  expect_trace_is_field_list(odoloc::rtl::SpiSynchroniser{}, "SpiSynchroniser");
  expect_trace_is_field_list(odoloc::rtl::SpiEngine{}, "SpiEngine");
  expect_trace_is_field_list(odoloc::rtl::SpiWriteBuffer{}, "SpiWriteBuffer");
  expect_trace_is_field_list(FabricRegisters{}, "FabricRegisters");
  expect_trace_is_field_list(InputConditioner<9>{}, "InputConditioner<9>");
  expect_trace_is_field_list(odoloc::rtl::TofTimebase{}, "TofTimebase");
  expect_trace_is_field_list(odoloc::rtl::TofChannel<16>{}, "TofChannel<16>");
  expect_trace_is_field_list(odoloc::rtl::TofSync<16>{}, "TofSync<16>");
}

TEST(TraceFields, ListedMembersAreDistinctAndInDeclarationOrder) {
  expect_members_in_order<InputConditionerRegs<2>>("InputConditionerRegs<2>");
  expect_members_in_order<QuadratureDecoderRegs>("QuadratureDecoderRegs");
  expect_members_in_order<PositionCounterRegs>("PositionCounterRegs");
  expect_members_in_order<SpeedTimebaseRegs>("SpeedTimebaseRegs");
  expect_members_in_order<PulseMeterRegs>("PulseMeterRegs");
  expect_members_in_order<PeriodMeterRegs>("PeriodMeterRegs");
  expect_members_in_order<SequentialCordicRegs>("SequentialCordicRegs");
  expect_members_in_order<RearOdometryUnitRegs>("RearOdometryUnitRegs");
  expect_members_in_order<FrontOdometryUnitRegs>("FrontOdometryUnitRegs");
  expect_members_in_order<MinSelectRegs>("MinSelectRegs");
  expect_members_in_order<PoseIntegratorRegs>("PoseIntegratorRegs");
  expect_members_in_order<OdometryReportRegs>("OdometryReportRegs");
  expect_members_in_order<OdometrySequencerRegs>("OdometrySequencerRegs");
  expect_members_in_order<odoloc::rtl::SpiSynchroniserRegs>("SpiSynchroniserRegs");
  expect_members_in_order<odoloc::rtl::SpiEngineRegs>("SpiEngineRegs");
  expect_members_in_order<odoloc::rtl::SpiWriteBufferRegs>("SpiWriteBufferRegs");
  expect_members_in_order<FabricRegistersRegs>("FabricRegistersRegs");
  expect_members_in_order<odoloc::rtl::TofTimebaseRegs>("TofTimebaseRegs");
  expect_members_in_order<odoloc::rtl::TofChannelRegs<16>>("TofChannelRegs<16>");
  expect_members_in_order<odoloc::rtl::TofSyncRegs<16>>("TofSyncRegs<16>");
}

// The chip's waveform: the pins, MISO, and every register of every block;
// the register file's stored words, snapshot bank and pulses included.
TEST(TraceFields, ChipWaveformDeclaresEveryRegister) {
  const OdolocChip chip;
  std::ostringstream vcd_text;
  VcdWriter vcd(vcd_text);
  vcd.declare(chip);
  const odoloc::tb::RegisterDump dump = odoloc::tb::dump_registers(chip, true);
  EXPECT_EQ(vcd.signal_count(), dump.names.size());

  // encoders, comparators, tof_sync, sclk, cs_n, mosi, reset; miso
  std::size_t expected = ChipPins{}.encoders.size() + 6 + 1;
  FieldWalk walk;
  walk.walk("", chip.spi().synchroniser());
  walk.walk("", chip.spi().engine());
  walk.walk("", chip.spi().buffer());
  walk.walk("", chip.registers().regs());
  expected += walk.paths.size();
  for (std::size_t w = 0; w < kEncoderCount; ++w) {
    const Eppm& e = chip.fabric().encoders().eppm(static_cast<Encoder>(w));
    FieldWalk eppm;
    eppm.walk("", EppmInputs{});
    eppm.walk("", e.conditioner());
    eppm.walk("", e.decoder());
    eppm.walk("", e.counter());
    eppm.walk("", e.timebase());
    eppm.walk("", e.pulse());
    eppm.walk("", e.period());
    expected += eppm.paths.size();
  }
  const OdometryFabric& f = chip.fabric();
  FieldWalk odometry;
  odometry.walk("", f.sequencer());
  odometry.walk("", f.cordic());
  odometry.walk("", f.rear());
  odometry.walk("", f.front());
  odometry.walk("", f.select());
  odometry.walk("", f.pose());
  odometry.walk("", f.report());
  expected += odometry.paths.size();
  const auto& t = chip.tof();
  FieldWalk tof;
  tof.walk("", odoloc::rtl::ChipTofCapture::In{});
  tof.walk("", t.conditioner());
  tof.walk("", t.timebase());
  tof.walk("", t.sync());
  for (std::size_t c = 0; c < odoloc::rtl::ChipTofCapture::kChannels; ++c)
    tof.walk("", t.channel(c));
  expected += tof.paths.size();
  EXPECT_EQ(dump.names.size(), expected);
  // The SPI slave's write-data words and the register file's banks are there.
  const auto has = [&](const std::string& name) {
    return std::find(dump.names.begin(), dump.names.end(), name) != dump.names.end();
  };
  // (A struct per word, as in the logic: `= {}` leaves ap_int elements undefined.)
  EXPECT_TRUE(has("spi.buffer.words.31.value"));
  EXPECT_TRUE(has("spi.engine.frame_end"));
  EXPECT_TRUE(has("registers.stored.word.0.value"));
  EXPECT_TRUE(has("registers.snapshot.0.value"));
  EXPECT_TRUE(
      has("registers.pulse." + std::to_string(odoloc::logic::regfile::kPulseWords - 1) + ".value"));
  EXPECT_TRUE(has("registers.pops.0.value"));
  EXPECT_TRUE(has("fabric.report.steer_position"));
}

}  // namespace
