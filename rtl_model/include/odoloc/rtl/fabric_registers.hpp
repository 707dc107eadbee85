// The register file of the odometry fabric: regmap/odoloc.yaml made logic.
// Every address, mask and reset comes from the generated odoloc/regs.hpp.
//
// Address map (32-bit words; docs/register-map.md lists every field):
//   0x000-0x004  top        id, ctrl, spi_status, frame_errors, scratch
//   0x010-0x04C  eppm[4]    stride 0x010: cfg..stall_ticks (rw), count..period_last
//                           (snapshot), status (w1c), error_count
//   0x060-0x086  odometry   cfg and scales (rw), status (w1c), updates and pose
//                           (snapshot), set_* (rw), command (w1p)
//   0x100-0x1FF  reserved   ultrasonic time-of-flight capture
//
// Access kinds:
//   rw   stored here; the fabric's configuration ports decode the stored words.
//   ro   live from the fabric; `snapshot` registers come from the bank
//        captured in the clock the frame's cs_n fall is seen, so one burst
//        reads one instant and never tears.
//   w1c  a 1 pulses that flag's clear input for one clock (an event in the
//        same clock wins, so nothing is lost).
//   w1p  a 1 pulses the command for one clock; reads 0.
//   rc   frame_errors: a completed read frame subtracts the value it
//        returned, so errors counted while the frame ran are kept.
// A write word to an ro or unmapped address is dropped and flags
// write_refused; the other words of its burst are written.
//
// Timing: the SPI slave's strobes are registers; this block decodes them in
// the clock they are high, and its own one-clock outputs (flag clears,
// set_pose) reach the fabric in the clock after. The slave latches read_data
// in the clock read_strobe is high; write_refused goes back to it in the
// commit clock.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>

#include "odoloc/regs.hpp"
#include "odoloc/rtl/bits.hpp"
#include "odoloc/rtl/clocked.hpp"
#include "odoloc/rtl/odometry_fabric.hpp"
#include "odoloc/rtl/spi_slave.hpp"

namespace odoloc::rtl {

namespace regfile {

inline constexpr std::size_t kAddressSpace = std::size_t{1} << regs::kAddressBits;
static_assert(regs::kDataBits == 32);

constexpr bool is_stored(const regs::Register& r) {
  return r.rw_mask != 0;
}
constexpr bool is_snapshot(const regs::Register& r) {
  return r.snapshot;
}

template <auto Pred>
constexpr std::size_t slot_count() {
  std::size_t n = 0;
  for (const regs::Register& r : regs::kRegisters)
    n += Pred(r) ? 1 : 0;
  return n;
}

// Address -> slot of the registers Pred selects, -1 elsewhere.
template <auto Pred>
constexpr std::array<std::int16_t, kAddressSpace> slot_table() {
  std::array<std::int16_t, kAddressSpace> table{};
  table.fill(-1);
  std::int16_t next = 0;
  for (const regs::Register& r : regs::kRegisters)
    if (Pred(r))
      table[r.address] = next++;
  return table;
}

inline constexpr std::size_t kStoredWords = slot_count<is_stored>();
inline constexpr std::size_t kSnapshotWords = slot_count<is_snapshot>();
inline constexpr auto kStoredSlot = slot_table<is_stored>();
inline constexpr auto kSnapshotSlot = slot_table<is_snapshot>();

constexpr std::array<UInt<32>, kStoredWords> stored_resets() {
  std::array<UInt<32>, kStoredWords> words{};
  for (const regs::Register& r : regs::kRegisters)
    if (is_stored(r))
      words[static_cast<std::size_t>(kStoredSlot[r.address])] = UInt<32>{r.reset & r.rw_mask};
  return words;
}

// A field as a typed wire: its width is the type's, so a field that does not
// fit its port does not compile.
template <const regs::Field& F>
constexpr UInt<F.width> field(UInt<32> word) {
  return UInt<F.width>::truncate(F.get(static_cast<std::uint32_t>(word.value())));
}
template <const regs::Field& F, int W>
constexpr std::uint32_t put(std::uint32_t word, UInt<W> value) {
  static_assert(W == F.width, "port and field widths differ");
  return F.set(word, static_cast<std::uint32_t>(value.value()));
}
template <const regs::Field& F, int W>
constexpr std::uint32_t put(std::uint32_t word, SInt<W> value) {
  return put<F>(word, value.as_uint());
}

}  // namespace regfile

struct FabricRegistersRegs {
  std::array<UInt<32>, regfile::kStoredWords> stored = regfile::stored_resets();  // rw bits
  std::array<UInt<32>, regfile::kSnapshotWords> snapshot{};
  UInt<4> spi_status;              // sticky top.spi_status
  UInt<16> frame_errors;           // top.frame_errors, saturating
  UInt<16> frame_errors_returned;  // what this frame's read of frame_errors returned
  // one-clock outputs to the fabric
  std::array<EppmFlagClear, kWheelCount> eppm_clear{};
  OdometryFlagClear odometry_clear;
  UInt<1> set_pose;
  bool operator==(const FabricRegistersRegs&) const = default;
};

class FabricRegisters : public Registers<FabricRegistersRegs> {
 public:
  struct In {
    const SpiSlave::Regs& spi;
    UInt<32> read_data;  // read(spi.read_address) while spi.read_strobe is high
    const OdometryFabric& fabric;
    const OdometryFabricConfig& config;
    UInt<1> reset;
  };

  [[nodiscard]] Regs eval(const In& in) const {
    if (in.reset)
      return Regs{};
    Regs n = r_;
    n.eppm_clear = {};
    n.odometry_clear = {};
    n.set_pose = UInt<1>{};
    const SpiSlave::Regs& spi = in.spi;
    if (spi.snapshot) {
      for (const regs::Register& r : regs::kRegisters)
        if (r.snapshot)
          n.snapshot[snapshot_slot(r.address)] = live(r.address, in.fabric, in.config);
      n.frame_errors_returned = UInt<16>{};
    }
    if (spi.read_strobe && spi.read_address.value() == regs::top::frame_errors::kAddress)
      n.frame_errors_returned = regfile::field<regs::top::frame_errors::count>(in.read_data);
    bool refused = false;
    if (spi.commit && spi.commit_write) {
      for (unsigned k = 0; k < spi.commit_count.value(); ++k)
        refused |= !write_word(n, word_address(spi.commit_address, k), spi.words[k]);
    } else if (spi.commit) {
      n.frame_errors =
          UInt<16>::truncate(n.frame_errors.value() - r_.frame_errors_returned.value());
    }
    if (spi.frame_end) {
      const UInt<4> errors = spi.status | (refused ? kRefused : UInt<4>{});
      n.spi_status = n.spi_status | errors;
      if (!errors.is_zero())
        n.frame_errors = (n.frame_errors + UInt<1>{1}).sat<16>();
    }
    return n;
  }

  [[nodiscard]] bool idle(const In& in) const {
    const SpiSlave::Regs& spi = in.spi;
    return (in.reset | spi.snapshot | spi.read_strobe | spi.commit | spi.frame_end | r_.set_pose |
            r_.odometry_clear.any())
               .is_zero() &&
           std::ranges::all_of(r_.eppm_clear, [](const EppmFlagClear& c) { return !c.any(); });
  }

  // The write_refused wire of the commit clock.
  [[nodiscard]] static UInt<1> write_refused(const SpiSlave::Regs& spi) {
    bool refused = false;
    if (spi.commit && spi.commit_write)
      for (unsigned k = 0; k < spi.commit_count.value(); ++k)
        refused |= !writable(word_address(spi.commit_address, k));
    return UInt<1>::truncate(refused);
  }

  // What a read frame returns for `address`.
  [[nodiscard]] UInt<32> read(UInt<10> address, const OdometryFabric& fabric,
                              const OdometryFabricConfig& config) const {
    const auto a = static_cast<std::size_t>(address.value());
    if (regfile::kSnapshotSlot[a] >= 0)
      return r_.snapshot[static_cast<std::size_t>(regfile::kSnapshotSlot[a])];
    if (regfile::kStoredSlot[a] >= 0)
      return r_.stored[static_cast<std::size_t>(regfile::kStoredSlot[a])];
    return live(a, fabric, config);
  }

  // The fabric's configuration ports: the stored words, decoded.
  [[nodiscard]] OdometryFabricConfig config() const {
    OdometryFabricConfig c;
    for (unsigned i = 0; i < kWheelCount; ++i)
      c.eppm[i] = eppm_config(i);
    namespace o = regs::odometry;
    const UInt<32> cfg = stored(o::cfg::kAddress);
    OdometryConfig& oc = c.odometry;
    oc.update_clocks = regfile::field<o::cfg::update_clocks>(cfg);
    oc.policy = regfile::field<o::cfg::policy>(cfg);
    oc.select_shift = regfile::field<o::cfg::select_shift>(cfg);
    oc.rear_ds_scale = regfile::field<o::rear_ds_scale::value>(stored(o::rear_ds_scale::kAddress));
    oc.rear_dtheta_scale =
        regfile::field<o::rear_dtheta_scale::value>(stored(o::rear_dtheta_scale::kAddress));
    oc.front_ds_scale =
        regfile::field<o::front_ds_scale::value>(stored(o::front_ds_scale::kAddress));
    oc.front_dtheta_scale =
        regfile::field<o::front_dtheta_scale::value>(stored(o::front_dtheta_scale::kAddress));
    oc.steer_scale = regfile::field<o::steer_scale::value>(stored(o::steer_scale::kAddress));
    oc.steer_limit = regfile::field<o::steer_limit::value>(stored(o::steer_limit::kAddress));
    oc.select_ds_threshold =
        regfile::field<o::select_ds_threshold::value>(stored(o::select_ds_threshold::kAddress));
    oc.select_dtheta_threshold = regfile::field<o::select_dtheta_threshold::value>(
        stored(o::select_dtheta_threshold::kAddress));
    return c;
  }

  // The pose set_pose loads: the set_* words.
  [[nodiscard]] PoseIntegrator::Regs pose_to_set() const {
    namespace o = regs::odometry;
    const auto wide = [&](std::uint16_t hi, std::uint16_t lo) {
      return cat(stored(hi), stored(lo));
    };
    return {wide(o::set_x_hi::kAddress, o::set_x_lo::kAddress).as_sint(),
            wide(o::set_y_hi::kAddress, o::set_y_lo::kAddress).as_sint(),
            cat(regfile::field<o::set_theta_hi::bits>(stored(o::set_theta_hi::kAddress)),
                stored(o::set_theta_lo::kAddress))};
  }

  // The fabric inputs this block drives: flag clears and set_pose.
  void drive(OdometryFabric::Inputs& in) const {
    in.eppm_clear = r_.eppm_clear;
    in.odometry_clear = r_.odometry_clear;
    in.set_pose = r_.set_pose;
    in.pose = pose_to_set();
  }

  [[nodiscard]] UInt<1> crc_enable() const {
    return regfile::field<regs::top::ctrl::crc_enable>(stored(regs::top::ctrl::kAddress));
  }
  [[nodiscard]] UInt<1> spi_mode3() const {
    return regfile::field<regs::top::ctrl::spi_mode3>(stored(regs::top::ctrl::kAddress));
  }

  template <class V>
  void trace(V& v) const {
    v.signal("spi_status", r_.spi_status);
    v.signal("frame_errors", r_.frame_errors);
    v.signal("frame_errors_returned", r_.frame_errors_returned);
    v.signal("set_pose", r_.set_pose);
    v.signal("clear_overrun", r_.odometry_clear.overrun);
    v.signal("clear_steer_clamped", r_.odometry_clear.steer_clamped);
  }

 private:
  static constexpr UInt<4> kRefused{SpiSlave::kStatusWriteRefused};
  static_assert(SpiSlave::kStatusCrcError == regs::top::spi_status::crc_error.mask());
  static_assert(SpiSlave::kStatusBadLength == regs::top::spi_status::bad_length.mask());
  static_assert(SpiSlave::kStatusWriteRefused == regs::top::spi_status::write_refused.mask());
  static_assert(SpiSlave::kStatusOverrun == regs::top::spi_status::overrun.mask());

  static std::size_t word_address(UInt<10> start, unsigned k) {
    return static_cast<std::size_t>((start.value() + k) % regfile::kAddressSpace);
  }
  static std::size_t snapshot_slot(std::size_t address) {
    return static_cast<std::size_t>(regfile::kSnapshotSlot[address]);
  }
  static bool writable(std::size_t address) {
    const regs::Register* r = regs::find(static_cast<std::uint32_t>(address));
    return r != nullptr && (r->rw_mask | r->w1c_mask | r->w1p_mask) != 0;
  }
  [[nodiscard]] UInt<32> stored(std::uint16_t address) const {
    return r_.stored[static_cast<std::size_t>(regfile::kStoredSlot[address])];
  }

  [[nodiscard]] EppmConfig eppm_config(unsigned i) const {
    namespace e = regs::eppm;
    const UInt<32> cfg = stored(e::cfg::address(i));
    return {regfile::field<e::cfg::filter_clocks>(cfg),
            regfile::field<e::cfg::decode_mode>(cfg),
            regfile::field<e::cfg::speed_mode_select>(cfg),
            regfile::field<e::window::clocks>(stored(e::window::address(i))),
            regfile::field<e::prescale::divider>(stored(e::prescale::address(i))),
            regfile::field<e::to_period_below::edges>(stored(e::to_period_below::address(i))),
            regfile::field<e::to_pulse_at::edges>(stored(e::to_pulse_at::address(i))),
            regfile::field<e::stall_ticks::ticks>(stored(e::stall_ticks::address(i)))};
  }

  // Applies one written word; false when the address takes no write.
  static bool write_word(Regs& n, std::size_t address, UInt<32> word) {
    const regs::Register* r = regs::find(static_cast<std::uint32_t>(address));
    if (r == nullptr || (r->rw_mask | r->w1c_mask | r->w1p_mask) == 0)
      return false;
    const auto data = static_cast<std::uint32_t>(word.value());
    if (r->rw_mask != 0) {
      UInt<32>& s = n.stored[static_cast<std::size_t>(regfile::kStoredSlot[address])];
      s = UInt<32>{(static_cast<std::uint32_t>(s.value()) & ~r->rw_mask) | (data & r->rw_mask)};
    }
    if ((data & (r->w1c_mask | r->w1p_mask)) != 0)
      pulse(n, address, UInt<32>{data & (r->w1c_mask | r->w1p_mask)});
    return true;
  }

  // The clears and commands of a w1c / w1p write.
  static void pulse(Regs& n, std::size_t address, UInt<32> ones) {
    namespace e = regs::eppm;
    namespace o = regs::odometry;
    if (address == regs::top::spi_status::kAddress) {
      n.spi_status = n.spi_status & ~UInt<4>::truncate(ones.value());
      return;
    }
    if (address == o::status::kAddress) {
      n.odometry_clear = {regfile::field<o::status::overrun>(ones),
                          regfile::field<o::status::steer_clamped>(ones)};
      return;
    }
    if (address == o::command::kAddress) {
      n.set_pose = regfile::field<o::command::set_pose>(ones);
      if (regfile::field<o::command::clear_flags>(ones)) {
        n.eppm_clear.fill(EppmFlagClear::all(UInt<1>{1}));
        n.odometry_clear = OdometryFlagClear::all(UInt<1>{1});
        n.spi_status = UInt<4>{};
      }
      return;
    }
    for (unsigned i = 0; i < kWheelCount; ++i)
      if (address == e::status::address(i))
        n.eppm_clear[i] = {regfile::field<e::status::phase_error>(ones),
                           regfile::field<e::status::carry>(ones),
                           regfile::field<e::status::borrow>(ones),
                           regfile::field<e::status::period_overflow>(ones)};
  }

  // The value of a register that is not stored here, straight from the fabric.
  [[nodiscard]] UInt<32> live(std::size_t address, const OdometryFabric& fabric,
                              const OdometryFabricConfig& config) const {
    using regfile::put;
    namespace t = regs::top;
    namespace o = regs::odometry;
    std::uint32_t w = 0;
    switch (address) {
      case t::id::kAddress:
        w = t::id::kReset;
        break;
      case t::spi_status::kAddress:
        w = static_cast<std::uint32_t>(r_.spi_status.value());
        break;
      case t::frame_errors::kAddress:
        w = put<t::frame_errors::count>(w, r_.frame_errors);
        break;
      case o::status::kAddress: {
        w = put<o::status::overrun>(w, fabric.sequencer().overrun);
        w = put<o::status::steer_clamped>(w, fabric.front().clamp_flag);
        w = put<o::status::ds_from_front>(w, fabric.select().ds_from_front);
        w = put<o::status::dtheta_from_front>(w, fabric.select().dtheta_from_front);
        w = put<o::status::phase>(w, fabric.sequencer().phase);
        break;
      }
      case o::updates::kAddress:
        w = put<o::updates::count>(w, fabric.sequencer().updates);
        break;
      default:
        if (const auto word = live_wide(address, fabric))
          return UInt<32>{*word};
        w = live_eppm(address, fabric, config);
    }
    return UInt<32>{w};
  }

  // The low or the high word of a value wider than 32 bits.
  template <const regs::Field& Lo, const regs::Field& Hi, int W>
  static std::uint32_t word_of(std::size_t address, std::uint16_t high_address, UInt<W> value) {
    static_assert(Lo.width == 32 && Lo.width + Hi.width == W, "words and value widths differ");
    return address == high_address ? Hi.set(0, static_cast<std::uint32_t>(value.value() >> 32U))
                                   : Lo.set(0, static_cast<std::uint32_t>(value.value()));
  }
  template <const regs::Field& Lo, const regs::Field& Hi, int W>
  static std::uint32_t word_of(std::size_t address, std::uint16_t high_address, SInt<W> value) {
    return word_of<Lo, Hi>(address, high_address, value.as_uint());
  }

  // The odometry's wide values, split into lo/hi words.
  [[nodiscard]] static std::optional<std::uint32_t> live_wide(std::size_t address,
                                                              const OdometryFabric& fabric) {
    namespace o = regs::odometry;
#define ODOLOC_WIDE(reg, value) \
  case o::reg##_lo::kAddress:   \
  case o::reg##_hi::kAddress:   \
    return word_of<o::reg##_lo::bits, o::reg##_hi::bits>(address, o::reg##_hi::kAddress, value)
    switch (address) {
      ODOLOC_WIDE(pose_x, fabric.pose().x);
      ODOLOC_WIDE(pose_y, fabric.pose().y);
      ODOLOC_WIDE(pose_theta, fabric.pose().theta);
      ODOLOC_WIDE(rear_ds, fabric.rear().ds);
      ODOLOC_WIDE(rear_dtheta, fabric.rear().dtheta);
      ODOLOC_WIDE(front_ds, fabric.front().ds);
      ODOLOC_WIDE(front_dtheta, fabric.front().dtheta);
      ODOLOC_WIDE(ds, fabric.select().ds);
      ODOLOC_WIDE(dtheta, fabric.select().dtheta);
      ODOLOC_WIDE(steer_phi, fabric.front().phi);
      case o::steer_position::kAddress:
        return regfile::put<o::steer_position::counts>(0, fabric.front().steer_position);
      default:
        return std::nullopt;
    }
#undef ODOLOC_WIDE
  }

  [[nodiscard]] static std::uint32_t live_eppm(std::size_t address, const OdometryFabric& fabric,
                                               const OdometryFabricConfig& config) {
    using regfile::put;
    namespace e = regs::eppm;
    if (address < e::kBase || address >= e::kBase + e::kInstances * e::kStride)
      return 0;  // unmapped or reserved: reads 0
    const auto i = static_cast<unsigned>((address - e::kBase) / e::kStride);
    const Eppm& m = fabric.encoders().eppm(static_cast<Wheel>(i));
    std::uint32_t w = 0;
    switch ((address - e::kBase) % e::kStride) {
      case e::count::kOffset:
        return put<e::count::value>(w, m.counter().count);
      case e::latched::kOffset:
        return put<e::latched::value>(w, m.counter().latched);
      case e::speed::kOffset: {
        const EppmSpeed s = m.speed(config.eppm[i]);
        w = put<e::speed::value>(w, s.value);
        w = put<e::speed::mode>(w, s.mode);
        w = put<e::speed::valid>(w, s.valid);
        return put<e::speed::stalled>(w, s.stalled);
      }
      case e::pulse_last::kOffset:
        return put<e::pulse_last::edges>(w, m.pulse().last);
      case e::period_last::kOffset:
        w = put<e::period_last::ticks>(w, m.period().last);
        w = put<e::period_last::valid>(w, m.period().valid);
        return put<e::period_last::forward>(w, m.period().last_dir);
      case e::status::kOffset:
        w = put<e::status::phase_error>(w, m.decoder().phase_error);
        w = put<e::status::carry>(w, m.counter().carry);
        w = put<e::status::borrow>(w, m.counter().borrow);
        w = put<e::status::period_overflow>(w, m.period().overflow);
        return put<e::status::forward>(w, m.decoder().direction);
      case e::error_count::kOffset:
        return put<e::error_count::count>(w, m.decoder().error_count);
      default:
        return 0;
    }
  }
};

}  // namespace odoloc::rtl
