// rtl::OdometryDatapath (the odometry fabric without its four EPPMs, the
// block rtl::OdometryFabric composes) behind the odometry kernel's ports: one
// call = one model step(in, cfg), then its latch wire and status().
//
// Stimulus (the model's state steers it, so the rare cases come often):
// - Configuration: a profile drawn at start and redrawn one call in 8192:
//   62 % a random vehicle (rear/front metres per count, track, wheelbase, the
//   steering gear) with the scales sw::odometry_scales would compute, the 40
//   degree limit (or 1/4 turn, or less) and thresholds of 3 quantisations (or
//   0 with shift 0: the paper's rule); 19 % every scale, limit and threshold
//   random 32-bit (limits past 1/4 turn wrap phi); 6 % all at 0xFFFFFFFF
//   (pose wrap within a few updates); 13 % zeros mixed in. Policy per
//   component half the time. update_clocks (redrawn one call in 512 as well,
//   mid-period): 40..64 (back to back), 1..39 (update strobes while busy:
//   overrun), 39..41 exactly, 0 (stopped), 65..400, rarely 5000 or random.
// - Counts: new ones in each GATHER clock (when the EPPMs' latched values
//   change). A rear-midpoint speed with reversals (1 update in 128), speed
//   changes (0, slow, fast, up to 2^18 counts), and wheel counts that agree
//   with the vehicle and the current steering angle plus quantisation;
//   over-count episodes (slip, bumps) on one rear wheel, both, or the front
//   wheel that min-select must drop; steering that sweeps slowly, jumps by up
//   to 2^19 (saturating the 24-bit position) and returns; one update in 64
//   full-range or boundary counts (+-2^19). Outside GATHER, one call in 16
//   carries garbage counts, which the datapath must ignore.
// - Strobes: the two flag clears one call in 64 each, clear_flags one in
//   1024; set_pose one call in 4096 and one in 16 of the clocks the pose
//   integrates (set_pose wins); set_x/set_y/set_theta redrawn one call in 32,
//   often within 2^40 of the 64-bit wrap or near one turn; reset about one
//   call in 20000, half of them during an update.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <random>

#include "odoloc/rtl/encoder_fabric.hpp"  // the encoders' names and count format
#include "odoloc/rtl/odometry.hpp"
#include "odoloc/verification/reference.hpp"

namespace odoloc::verification {

namespace {

using rtl::OdometryPhase;
using rtl::SInt;
using rtl::UInt;

// The kernel's input columns (odometry_kernel.hpp, visit_fields order).
enum Column : std::size_t {
  kNLeft,
  kNRight,
  kNFront,
  kNSteer,
  kUpdateClocks,
  kPolicy,
  kSelectShift,
  kRearDsScale,
  kRearDthetaScale,
  kFrontDsScale,
  kFrontDthetaScale,
  kSteerScale,
  kSteerLimit,
  kSelectDsThreshold,
  kSelectDthetaThreshold,
  kSetXHi,
  kSetXLo,
  kSetYHi,
  kSetYLo,
  kSetTheta,
  kClearOverrun,
  kClearSteerClamped,
  kSetPose,
  kClearFlags,
  kReset,
  kInputCount
};

constexpr std::array<std::string_view, kInputCount> kIn = {  // the kernel's Inputs
    "n_left",
    "n_right",
    "n_front",
    "n_steer",
    "update_clocks",
    "policy",
    "select_shift",
    "rear_ds_scale",
    "rear_dtheta_scale",
    "front_ds_scale",
    "front_dtheta_scale",
    "steer_scale",
    "steer_limit",
    "select_ds_threshold",
    "select_dtheta_threshold",
    "set_x_hi",
    "set_x_lo",
    "set_y_hi",
    "set_y_lo",
    "set_theta",
    "clear_overrun",
    "clear_steer_clamped",
    "set_pose",
    "clear_flags",
    "reset"};
constexpr std::array<std::string_view, 20> kOut = {  // the kernel's Outputs
    "latch",
    "phase",
    "overrun",
    "steer_clamped",
    "ds_from_front",
    "dtheta_from_front",
    "updates",
    "pose_x_hi",
    "pose_x_lo",
    "pose_y_hi",
    "pose_y_lo",
    "pose_theta",
    "rear_ds",
    "rear_dtheta",
    "front_ds",
    "front_dtheta",
    "ds",
    "dtheta",
    "steer_phi",
    "steer_position"};

template <int W>
UInt<W> unsigned_port(std::int64_t v) {
  return UInt<W>::truncate(static_cast<std::uint64_t>(v));
}
template <int W>
SInt<W> signed_port(std::int64_t v) {
  return SInt<W>::truncate(v);
}
// A 64-bit register from its high (signed) and low (unsigned) word ports.
SInt<64> from_words(std::int64_t hi, std::int64_t lo) {
  return SInt<64>::truncate(static_cast<std::int64_t>(
      static_cast<std::uint64_t>(hi) << 32 | (static_cast<std::uint64_t>(lo) & 0xFFFFFFFFU)));
}
std::int64_t high_word(SInt<64> v) {
  return v.value() >> 32;
}
std::int64_t low_word(SInt<64> v) {
  return static_cast<std::int64_t>(v.raw_bits() & 0xFFFFFFFFU);
}

// The datapath's ports in the model's types.
struct Ports {
  rtl::OdometryDatapath::In in;
  rtl::OdometryConfig cfg;
};

Ports decode(std::span<const std::int64_t> in) {
  Ports p;
  rtl::LatchedCounts& n = p.in.latched;
  n.left_rear = signed_port<rtl::PositionCount::width>(in[kNLeft]);
  n.right_rear = signed_port<rtl::PositionCount::width>(in[kNRight]);
  n.front_drive = signed_port<rtl::PositionCount::width>(in[kNFront]);
  n.steering = signed_port<rtl::PositionCount::width>(in[kNSteer]);
  rtl::OdometryConfig& c = p.cfg;
  c.cfg.update_clocks = unsigned_port<16>(in[kUpdateClocks]);
  c.cfg.policy = unsigned_port<2>(in[kPolicy]);
  c.cfg.select_shift = unsigned_port<4>(in[kSelectShift]);
  c.rear_ds_scale.value = unsigned_port<32>(in[kRearDsScale]);
  c.rear_dtheta_scale.value = unsigned_port<32>(in[kRearDthetaScale]);
  c.front_ds_scale.value = unsigned_port<32>(in[kFrontDsScale]);
  c.front_dtheta_scale.value = unsigned_port<32>(in[kFrontDthetaScale]);
  c.steer_scale.value = unsigned_port<32>(in[kSteerScale]);
  c.steer_limit.value = unsigned_port<32>(in[kSteerLimit]);
  c.select_ds_threshold.value = unsigned_port<32>(in[kSelectDsThreshold]);
  c.select_dtheta_threshold.value = unsigned_port<32>(in[kSelectDthetaThreshold]);
  c.set_x.bits = from_words(in[kSetXHi], in[kSetXLo]);
  c.set_y.bits = from_words(in[kSetYHi], in[kSetYLo]);
  c.set_theta.bits = unsigned_port<40>(in[kSetTheta]);
  rtl::OdometryPulses& pulses = p.in.odometry;
  pulses.status.overrun = unsigned_port<1>(in[kClearOverrun]);
  pulses.status.steer_clamped = unsigned_port<1>(in[kClearSteerClamped]);
  pulses.command.set_pose = unsigned_port<1>(in[kSetPose]);
  pulses.command.clear_flags = unsigned_port<1>(in[kClearFlags]);
  p.in.reset = unsigned_port<1>(in[kReset]);
  return p;
}

// The kernel's outputs, from the datapath's registers after the edge.
void encode(const rtl::OdometryDatapath& d, std::span<std::int64_t> out) {
  const rtl::OdometryStatus s = d.status();
  const auto u = [](auto v) { return static_cast<std::int64_t>(v.value()); };
  const std::array<std::int64_t, kOut.size()> values{u(d.latch()),
                                                     u(s.status.phase),
                                                     u(s.status.overrun),
                                                     u(s.status.steer_clamped),
                                                     u(s.status.ds_from_front),
                                                     u(s.status.dtheta_from_front),
                                                     u(s.updates.count),
                                                     high_word(s.pose_x.bits),
                                                     low_word(s.pose_x.bits),
                                                     high_word(s.pose_y.bits),
                                                     low_word(s.pose_y.bits),
                                                     u(s.pose_theta.bits),
                                                     s.rear_ds.bits.value(),
                                                     s.rear_dtheta.bits.value(),
                                                     s.front_ds.bits.value(),
                                                     s.front_dtheta.bits.value(),
                                                     s.ds.bits.value(),
                                                     s.dtheta.bits.value(),
                                                     s.steer_phi.bits.value(),
                                                     s.steer_position.counts.value()};
  std::copy(values.begin(), values.end(), out.begin());
}

class OdometryReference final : public Reference {
 public:
  explicit OdometryReference(std::uint64_t seed) : rng_(seed) {
    draw_profile();
    draw_update_clocks();
    draw_set_pose_values();
  }

  [[nodiscard]] std::span<const std::string_view> input_names() const override { return kIn; }
  [[nodiscard]] std::span<const std::string_view> output_names() const override { return kOut; }

  void stimulus(std::span<std::int64_t> in) override {
    if (one_in(8192))
      draw_profile();
    if (one_in(512))
      draw_update_clocks();
    if (one_in(32))
      draw_set_pose_values();
    const bool gather = model_.phase() == OdometryPhase::kGather;
    if (gather)
      draw_counts();
    std::copy(held_.begin(), held_.end(), in.begin());
    if (!gather && one_in(16)) {
      for (std::size_t w = 0; w < rtl::kEncoderCount; ++w)
        in[kNLeft + w] = wrap20(static_cast<std::int64_t>(rng_()));
    }
    const bool integrates =
        model_.phase() == OdometryPhase::kThetaWait && model_.cordic().ready.value() == 1;
    const bool busy = model_.phase() != OdometryPhase::kIdle;
    in[kClearOverrun] = one_in(64) ? 1 : 0;
    in[kClearSteerClamped] = one_in(64) ? 1 : 0;
    in[kClearFlags] = one_in(1024) ? 1 : 0;
    in[kSetPose] = one_in(4096) || (integrates && one_in(16)) ? 1 : 0;
    in[kReset] = one_in(40000) || (busy && one_in(25000)) ? 1 : 0;
  }

  void step(std::span<const std::int64_t> in, std::span<std::int64_t> out) override {
    const Ports p = decode(in);
    model_.step(p.in, p.cfg);
    encode(model_, out);
  }

 private:
  static constexpr double kUnits40 = 1099511627776.0;  // 2^40
  static constexpr double kUnits32 = 4294967296.0;     // 2^32
  static constexpr std::int64_t kCountMax = (std::int64_t{1} << 19) - 1;

  bool one_in(std::uint64_t n) { return rng_() % n == 0; }
  double uniform(double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(rng_);
  }
  std::int64_t random32() { return static_cast<std::int64_t>(rng_() & 0xFFFFFFFFU); }
  static std::int64_t wrap20(std::int64_t v) {
    return SInt<rtl::PositionCount::width>::truncate(v).value();
  }
  static std::int64_t scale(double v) {
    return static_cast<std::int64_t>(std::llround(std::min(v, 4294967295.0)));
  }

  // A configuration: mostly a plausible vehicle, sometimes arbitrary words.
  void draw_profile() {
    const std::uint64_t kind = rng_() % 16;
    kappa_rear_ = uniform(2e-5, 4e-4);  // metres per x4 edge
    kappa_front_ = uniform(2e-5, 4e-4);
    track_ = uniform(0.2, 0.6);
    wheelbase_ = uniform(0.25, 0.8);
    if (kind < 10) {
      constexpr double kTwoPi = 6.283185307179586;
      held_[kRearDsScale] = scale(kappa_rear_ / 2 * kUnits40);
      held_[kRearDthetaScale] = scale(kappa_rear_ / (kTwoPi * track_) * kUnits40);
      held_[kFrontDsScale] = scale(kappa_front_ * kUnits40);
      held_[kFrontDthetaScale] = scale(kappa_front_ / (kTwoPi * wheelbase_) * kUnits40);
      held_[kSteerScale] = scale(kUnits40 / (4 * uniform(500, 20000)));
      const std::uint64_t limit = rng_() % 4;
      held_[kSteerLimit] = limit == 0   ? std::int64_t{1} << 30
                           : limit == 1 ? random32() >> 2
                                        : 477218588;  // 40 degrees
      const bool paper = one_in(4);
      held_[kSelectDsThreshold] = paper ? 0 : scale(3 * (kappa_rear_ + kappa_front_) * kUnits32);
      held_[kSelectDthetaThreshold] =
          paper ? 0
                : scale(3 * (2 * kappa_rear_ / track_ + kappa_front_ / wheelbase_) / kTwoPi *
                        kUnits40);
      held_[kSelectShift] = paper ? 0 : one_in(2) ? 12 : static_cast<std::int64_t>(rng_() % 16);
    } else if (kind < 13) {
      for (const Column c : {kRearDsScale, kRearDthetaScale, kFrontDsScale, kFrontDthetaScale,
                             kSteerScale, kSteerLimit, kSelectDsThreshold, kSelectDthetaThreshold})
        held_[c] = random32();
      held_[kSelectShift] = static_cast<std::int64_t>(rng_() % 16);
    } else if (kind < 14) {
      for (const Column c : {kRearDsScale, kRearDthetaScale, kFrontDsScale, kFrontDthetaScale,
                             kSteerScale, kSteerLimit})
        held_[c] = 0xFFFFFFFF;
      held_[kSelectDsThreshold] = one_in(2) ? 0 : 0xFFFFFFFF;
      held_[kSelectDthetaThreshold] = one_in(2) ? 0 : 0xFFFFFFFF;
      held_[kSelectShift] = one_in(2) ? 0 : 15;
    } else {
      for (const Column c : {kRearDsScale, kRearDthetaScale, kFrontDsScale, kFrontDthetaScale,
                             kSteerScale, kSteerLimit, kSelectDsThreshold, kSelectDthetaThreshold})
        held_[c] = one_in(2) ? 0 : random32();
      held_[kSelectShift] = static_cast<std::int64_t>(rng_() % 16);
    }
    held_[kPolicy] = one_in(2) ? 0 : static_cast<std::int64_t>(rng_() % 4);
  }

  // The control period: mostly short, so that updates come every ~50 calls.
  void draw_update_clocks() {
    const std::uint64_t r = rng_() % 100;
    held_[kUpdateClocks] =
        r < 45   ? 40 + static_cast<std::int64_t>(rng_() % 25)  // back to back
        : r < 60 ? 1 + static_cast<std::int64_t>(rng_() % 39)   // strobes while busy: overrun
        : r < 70 ? 39 + static_cast<std::int64_t>(rng_() % 3)   // the boundary
        : r < 73 ? 0                                            // stopped
        : r < 95 ? 65 + static_cast<std::int64_t>(rng_() % 336)
        : r < 98 ? 5000
                 : static_cast<std::int64_t>(rng_() & 0xFFFFU);
  }

  // set_x, set_y, set_theta: often near the wraps of the pose registers.
  void draw_set_pose_values() {
    const auto wide = [this]() -> std::uint64_t {
      const std::uint64_t r = rng_() % 4;
      const std::uint64_t near = rng_() >> 24;               // < 2^40
      return r == 0   ? (std::uint64_t{1} << 63) - 1 - near  // just below +2^63
             : r == 1 ? (std::uint64_t{1} << 63) + near      // just above -2^63
             : r == 2 ? 0
                      : rng_();
    };
    const std::uint64_t x = wide(), y = wide();
    held_[kSetXHi] = static_cast<std::int64_t>(x) >> 32;
    held_[kSetXLo] = static_cast<std::int64_t>(x & 0xFFFFFFFFU);
    held_[kSetYHi] = static_cast<std::int64_t>(y) >> 32;
    held_[kSetYLo] = static_cast<std::int64_t>(y & 0xFFFFFFFFU);
    const std::uint64_t near_turn = rng_() >> 40;  // < 2^24
    held_[kSetTheta] =
        static_cast<std::int64_t>((one_in(2) ? (std::uint64_t{1} << 40) - near_turn : rng_()) &
                                  ((std::uint64_t{1} << 40) - 1));
  }

  // The latched counts of one control period.
  void draw_counts() {
    if (one_in(64)) {  // full range or the 20-bit boundaries
      for (std::size_t w = 0; w < rtl::kEncoderCount; ++w) {
        const std::uint64_t r = rng_() % 4;
        held_[kNLeft + w] = r == 0   ? kCountMax
                            : r == 1 ? -kCountMax - 1
                                     : wrap20(static_cast<std::int64_t>(rng_()));
      }
      return;
    }
    if (one_in(128))
      speed_ = -speed_;  // reversal
    if (one_in(32)) {
      const std::uint64_t r = rng_() % 8;
      const double top = r < 2 ? 0.0 : r < 5 ? 64.0 : r < 7 ? 4096.0 : 262144.0;
      speed_ = uniform(-top, top + 1e-9);
    }
    speed_ += uniform(-0.5, 0.5);
    if (one_in(64)) {
      const std::uint64_t r = rng_() % 8;
      steer_rate_ = r < 3 ? 0.0 : r < 6 ? uniform(-50, 50) : uniform(-524288, 524287);
    }
    if (std::abs(steer_rate_) > 1000 && one_in(32))
      steer_rate_ = -steer_rate_;  // back from the stop
    // The vehicle's own kinematics at the current steering angle.
    const double phi =
        6.283185307179586 * static_cast<double>(model_.front().phi.value()) / kUnits40;
    const double tan_phi = std::clamp(std::tan(phi), -4.0, 4.0);
    const double cos_phi = std::max(std::abs(std::cos(phi)), 0.25);
    const double differential = track_ / 2 * tan_phi / wheelbase_;
    std::array<double, rtl::kEncoderCount> counts{
        speed_ * (1 - differential), speed_ * (1 + differential),
        speed_ * kappa_rear_ / (kappa_front_ * cos_phi), steer_rate_};
    if (episode_left_ == 0 && one_in(256)) {  // slip or a bump: one source over-counts
      episode_left_ = 1 + rng_() % 200;
      episode_wheel_ = rng_() % 4;  // left, right, both rear, front
      episode_extra_ = uniform(0.02, 0.4);
    }
    if (episode_left_ > 0) {
      --episode_left_;
      const double sign = speed_ < 0 ? -1.0 : 1.0;
      const auto over = [&](std::size_t w) {
        counts[w] +=
            sign * (std::abs(counts[w]) * episode_extra_ + 1 + static_cast<double>(rng_() % 8));
      };
      if (episode_wheel_ == 0 || episode_wheel_ == 2)
        over(0);
      if (episode_wheel_ == 1 || episode_wheel_ == 2)
        over(1);
      if (episode_wheel_ == 3)
        over(2);
    }
    for (std::size_t w = 0; w < rtl::kEncoderCount; ++w) {
      const double quantised = std::floor(counts[w] + uniform(0, 1));  // edge quantisation
      held_[kNLeft + w] = wrap20(static_cast<std::int64_t>(std::clamp(
          quantised, -static_cast<double>(kCountMax) - 1, static_cast<double>(kCountMax))));
    }
  }

  std::mt19937_64 rng_;
  rtl::OdometryDatapath model_;
  std::array<std::int64_t, kInputCount> held_{};  // the inputs that persist between calls
  double kappa_rear_ = 1e-4, kappa_front_ = 1e-4, track_ = 0.3, wheelbase_ = 0.4;
  double speed_ = 0, steer_rate_ = 0;  // counts per control period
  std::uint64_t episode_left_ = 0, episode_wheel_ = 0;
  double episode_extra_ = 0;
};

}  // namespace

std::unique_ptr<Reference> make_odometry_reference(std::uint64_t seed) {
  return std::make_unique<OdometryReference>(seed);
}

}  // namespace odoloc::verification
