// Random well-formed SPI frames for the whole-chip testbenches: writes that
// configure every block (short odometry periods, EPPM windows, prescalers and
// filters, the capture unit's timebase, channels and commands), w1c clears,
// the commands, the pose to set, and reads of random ranges (snapshots, rc
// and rpop registers).
#pragma once

#include <cstdint>
#include <random>
#include <vector>

#include "odoloc/regs.hpp"
#include "spi_master_bfm.hpp"

namespace odoloc::tb {

inline std::vector<std::uint8_t> random_frame(std::mt19937_64& rng) {
  std::vector<std::uint32_t> words;
  unsigned address = 0;
  switch (rng() % 8) {
    case 0: {  // odometry configuration: short periods so updates happen often; 0 stops them
      address = regs::odometry::cfg::kAddress;
      const auto update_clocks = rng() % 4 == 0 ? 0U : static_cast<std::uint32_t>(60 + rng() % 200);
      std::uint32_t cfg = regs::odometry::cfg::update_clocks.set(0, update_clocks);
      cfg = regs::odometry::cfg::policy.set(cfg, static_cast<std::uint32_t>(rng() % 4));
      cfg = regs::odometry::cfg::select_shift.set(cfg, static_cast<std::uint32_t>(rng() % 6));
      words = {cfg};
      for (int k = 0; k < 8; ++k)  // scales, steering limit and thresholds
        words.push_back(static_cast<std::uint32_t>(rng() >> 34));
      break;
    }
    case 1:  // w1c clears anywhere, or the commands
      address = rng() % 2 ? regs::odometry::command::kAddress
                          : regs::eppm::status::address(static_cast<unsigned>(rng() % 4));
      words = {static_cast<std::uint32_t>(rng() % 16)};
      break;
    case 2: {  // an EPPM's configuration: cfg, window, prescale, switch points, stall
      const auto i = static_cast<unsigned>(rng() % regs::eppm::kInstances);
      address = regs::eppm::cfg::address(i);
      words = {
          static_cast<std::uint32_t>(rng() % 4096),    static_cast<std::uint32_t>(rng() % 3000),
          static_cast<std::uint32_t>(rng() % 100),     static_cast<std::uint32_t>(rng() % 50),
          static_cast<std::uint32_t>(50 + rng() % 50), static_cast<std::uint32_t>(rng() % 5000)};
      break;
    }
    case 3:  // the pose to set
      address = regs::odometry::set_x_lo::kAddress;
      for (int k = 0; k < 6; ++k)
        words.push_back(static_cast<std::uint32_t>(rng()));
      break;
    case 4: {  // the capture unit's timebase and filter
      address = regs::tof::cfg::kAddress;
      std::uint32_t cfg = regs::tof::cfg::prescale.set(
          0, static_cast<std::uint32_t>(rng() % 2 ? rng() % 4 : rng() % 300));
      cfg = regs::tof::cfg::filter_clocks.set(cfg, static_cast<std::uint32_t>(rng() % 6));
      words = {regs::tof::cfg::sync_enable.set(cfg, static_cast<std::uint32_t>(rng() % 2))};
      break;
    }
    case 5:  // arm, disarm, flush
      address = regs::tof::command::kAddress;
      words = {static_cast<std::uint32_t>(rng() % 2 ? 0xFF : rng())};
      break;
    case 6: {  // a channel's mode and edge limit
      address = regs::tof_channel::cfg::address(static_cast<unsigned>(rng() % 8));
      std::uint32_t cfg =
          regs::tof_channel::cfg::mode.set(0, static_cast<std::uint32_t>(rng() % 2));
      words = {regs::tof_channel::cfg::edges.set(cfg, static_cast<std::uint32_t>(rng() % 16))};
      break;
    }
    default: {  // a read of a random range (snapshot, live, rc, rpop)
      address = static_cast<unsigned>(rng() % 0x190);  // through the capture unit
      words.assign(1 + rng() % 8, 0);
      return spi_frame(SpiOp::kRead, address, words, false);
    }
  }
  return spi_frame(SpiOp::kWrite, address, words, false);
}

}  // namespace odoloc::tb
