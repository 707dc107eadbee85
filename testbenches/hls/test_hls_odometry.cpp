// The odometry datapath kernel (hls/odometry_kernel.hpp) against the cycle
// model, compiled once per type family. Both run logic/odometry.hpp, so these
// check the type families and the kernel's port mapping:
// - under the reference's seeded random stimulus (odometry_reference.cpp)
//   every output equals the model's after every call, and the stimulus
//   reaches the rare cases it claims (overrun, clamp, saturation, wraps,
//   min-select switching both ways, set_pose over an update, resets);
// - beside the whole rtl::OdometryFabric (four EPPMs on quadrature pins),
//   fed the EPPMs' latched counts, every register of the kernel equals the
//   fabric's and every output the fabric's status, every clock: the kernel's
//   boundary is the fabric's own, internal registers included;
// - directed: the update latency and the overrun boundary, min-select
//   dropping a one-wheel over-count, and the pose's 64-bit and one-turn wraps.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "hls_kernel_check.hpp"
#include "odoloc/hls/odometry_kernel.hpp"
#include "odoloc/hls_export/kernels.hpp"
#include "odoloc/rtl/cordic.hpp"
#include "odoloc/rtl/odometry_fabric.hpp"

namespace {

namespace hk = odoloc::hls::odometry;
namespace rtl = odoloc::rtl;
using odoloc::hls::to_s64;

namespace oc = rtl::odometry;

constexpr std::int64_t kTwo40 = std::int64_t{1} << 40;

// x and y from their two words.
std::int64_t wide(const hk::HiWord& hi, const hk::LoWord& lo) {
  return static_cast<std::int64_t>(static_cast<std::uint64_t>(to_s64(hi)) << 32 |
                                   static_cast<std::uint64_t>(to_s64(lo)));
}

template <int W>
long long model_value(rtl::UInt<W> v) {
  return static_cast<long long>(v.value());
}
template <int W>
long long model_value(rtl::SInt<W> v) {
  return v.value();
}

// The first register (or port) where kernel and model differ, or "".
class Compare {
 public:
  template <class Kernel, class Model>
  void operator()(const char* name, const Kernel& kernel, const Model& model) {
    equal(name, to_s64(kernel), model_value(model));
  }
  void equal(const char* name, long long kernel, long long model) {
    if (first_.empty() && kernel != model)
      first_ = std::string(name) + ": kernel " + std::to_string(kernel) + ", model " +
               std::to_string(model);
  }
  [[nodiscard]] const std::string& first() const { return first_; }

 private:
  std::string first_;
};

// Every register of the kernel against the fabric's blocks (the EPPMs aside).
std::string register_difference(const hk::Registers& k, const rtl::OdometryFabric& f) {
  Compare c;
  const auto& s = f.sequencer();
  c("sequencer.phase", k.sequencer.phase, s.phase);
  c("sequencer.period_count", k.sequencer.period_count, s.period_count);
  c("sequencer.updates", k.sequencer.updates, s.updates);
  c("sequencer.overrun", k.sequencer.overrun, s.overrun);
  const auto& q = f.cordic();
  c("cordic.x", k.cordic.state.x, q.state.x);
  c("cordic.y", k.cordic.state.y, q.state.y);
  c("cordic.z", k.cordic.state.z, q.state.z);
  c("cordic.quadrant", k.cordic.state.quadrant, q.state.quadrant);
  c("cordic.iteration", k.cordic.iteration, q.iteration);
  c("cordic.busy", k.cordic.busy, q.busy);
  c("cordic.ready", k.cordic.ready, q.ready);
  c("cordic.load_ignored", k.cordic.load_ignored, q.load_ignored);
  c("cordic.sin", k.cordic.result.sin, q.result.sin);
  c("cordic.cos", k.cordic.result.cos, q.result.cos);
  c("rear.ds", k.rear.ds, f.rear().ds);
  c("rear.dtheta", k.rear.dtheta, f.rear().dtheta);
  const auto& fr = f.front();
  c("front.steer_position", k.front.steer_position, fr.steer_position);
  c("front.phi", k.front.phi, fr.phi);
  c("front.phi_prev", k.front.phi_prev, fr.phi_prev);
  c("front.clamped", k.front.clamped, fr.clamped);
  c("front.clamp_flag", k.front.clamp_flag, fr.clamp_flag);
  c("front.drive", k.front.drive, fr.drive);
  c("front.turn_per_sin", k.front.turn_per_sin, fr.turn_per_sin);
  c("front.ds", k.front.ds, fr.ds);
  c("front.dtheta", k.front.dtheta, fr.dtheta);
  const auto& se = f.select();
  c("select.ds", k.select.ds, se.ds);
  c("select.dtheta", k.select.dtheta, se.dtheta);
  c("select.ds_from_front", k.select.ds_from_front, se.ds_from_front);
  c("select.dtheta_from_front", k.select.dtheta_from_front, se.dtheta_from_front);
  c("select.rear_ds_sum", k.select.rear_ds_sum, se.rear_ds_sum);
  c("select.front_ds_sum", k.select.front_ds_sum, se.front_ds_sum);
  c("select.rear_dtheta_sum", k.select.rear_dtheta_sum, se.rear_dtheta_sum);
  c("select.front_dtheta_sum", k.select.front_dtheta_sum, se.front_dtheta_sum);
  c.equal("pose.x", wide(k.pose.x.hi, k.pose.x.lo), rtl::pose_coordinate(f.pose().x).value());
  c.equal("pose.y", wide(k.pose.y.hi, k.pose.y.lo), rtl::pose_coordinate(f.pose().y).value());
  c("pose.theta", k.pose.theta, f.pose().theta);
  const auto& r = f.report();
  c("report.rear_ds", k.report.rear_ds, r.rear_ds);
  c("report.front_ds", k.report.front_ds, r.front_ds);
  c("report.ds", k.report.ds, r.ds);
  c("report.rear_dtheta", k.report.rear_dtheta, r.rear_dtheta);
  c("report.front_dtheta", k.report.front_dtheta, r.front_dtheta);
  c("report.dtheta", k.report.dtheta, r.dtheta);
  c("report.steer_phi", k.report.steer_phi, r.steer_phi);
  c("report.steer_position", k.report.steer_position, r.steer_position);
  c("report.ds_from_front", k.report.ds_from_front, r.ds_from_front);
  c("report.dtheta_from_front", k.report.dtheta_from_front, r.dtheta_from_front);
  return c.first();
}

// Every output port against the status the fabric shows the register file.
std::string output_difference(const hk::Outputs& o, const rtl::OdometryFabric& f,
                              const rtl::OdometryFabric::Config& cfg) {
  const rtl::OdometryStatus s = f.status(cfg).odometry;
  Compare c;
  c.equal("latch", to_s64(o.latch), f.phase() == rtl::OdometryPhase::kLatch ? 1 : 0);
  c("phase", o.phase, s.status.phase);
  c("overrun", o.overrun, s.status.overrun);
  c("steer_clamped", o.steer_clamped, s.status.steer_clamped);
  c("ds_from_front", o.ds_from_front, s.status.ds_from_front);
  c("dtheta_from_front", o.dtheta_from_front, s.status.dtheta_from_front);
  c("updates", o.updates, s.updates.count);
  c.equal("pose_x", wide(o.pose_x_hi, o.pose_x_lo), s.pose_x.bits.value());
  c.equal("pose_y", wide(o.pose_y_hi, o.pose_y_lo), s.pose_y.bits.value());
  c("pose_theta", o.pose_theta, s.pose_theta.bits);
  c("rear_ds", o.rear_ds, s.rear_ds.bits);
  c("rear_dtheta", o.rear_dtheta, s.rear_dtheta.bits);
  c("front_ds", o.front_ds, s.front_ds.bits);
  c("front_dtheta", o.front_dtheta, s.front_dtheta.bits);
  c("ds", o.ds, s.ds.bits);
  c("dtheta", o.dtheta, s.dtheta.bits);
  c("steer_phi", o.steer_phi, s.steer_phi.bits);
  c("steer_position", o.steer_position, s.steer_position.counts);
  return c.first();
}

// The kernel's input ports from the fabric's configuration, strobes and the
// EPPMs' latched counts (the wires rtl::OdometryFabric::wires reads).
hk::Inputs kernel_inputs(const rtl::OdometryFabric& f, const rtl::OdometryFabric::In& in,
                         const rtl::OdometryFabric::Config& cfg) {
  const auto latched = [&](rtl::Encoder w) {
    return f.encoders().eppm(w).counter().latched.value();
  };
  const rtl::OdometryConfig& oc = cfg.odometry;
  hk::Inputs k;
  k.n_left = latched(rtl::Encoder::kLeftRear);
  k.n_right = latched(rtl::Encoder::kRightRear);
  k.n_front = latched(rtl::Encoder::kFrontDrive);
  k.n_steer = latched(rtl::Encoder::kSteering);
  k.update_clocks = oc.cfg.update_clocks.value();
  k.policy = oc.cfg.policy.value();
  k.select_shift = oc.cfg.select_shift.value();
  k.rear_ds_scale = oc.rear_ds_scale.value.value();
  k.rear_dtheta_scale = oc.rear_dtheta_scale.value.value();
  k.front_ds_scale = oc.front_ds_scale.value.value();
  k.front_dtheta_scale = oc.front_dtheta_scale.value.value();
  k.steer_scale = oc.steer_scale.value.value();
  k.steer_limit = oc.steer_limit.value.value();
  k.select_ds_threshold = oc.select_ds_threshold.value.value();
  k.select_dtheta_threshold = oc.select_dtheta_threshold.value.value();
  const auto bits = [](rtl::SInt<64> v) { return v.raw_bits(); };
  k.set_x_hi = static_cast<std::int64_t>(bits(oc.set_x.bits) >> 32);
  k.set_x_lo = static_cast<std::int64_t>(bits(oc.set_x.bits) & 0xFFFFFFFFU);
  k.set_y_hi = static_cast<std::int64_t>(bits(oc.set_y.bits) >> 32);
  k.set_y_lo = static_cast<std::int64_t>(bits(oc.set_y.bits) & 0xFFFFFFFFU);
  k.set_theta = static_cast<std::int64_t>(oc.set_theta.bits.value());
  k.clear_overrun = in.odometry.status.overrun.value();
  k.clear_steer_clamped = in.odometry.status.steer_clamped.value();
  k.set_pose = in.odometry.command.set_pose.value();
  k.clear_flags = in.odometry.command.clear_flags.value();
  k.reset = in.reset.value();
  return k;
}

// An ideal quadrature encoder: `rate` edges per clock, A leading B forward.
struct Quadrature {
  double position = 0.5, rate = 0;
  rtl::UInt<2> tick() {
    position += rate;
    constexpr std::array<std::uint64_t, 4> kGray{0b00, 0b10, 0b11, 0b01};
    return rtl::UInt<2>::truncate(
        kGray[static_cast<std::uint64_t>(static_cast<std::int64_t>(std::floor(position))) & 3U]);
  }
};

TEST(HlsOdometry, EveryOutputEqualsTheModelEveryClock) {
  const auto check = odoloc::tb::check_kernel<hk::Inputs, hk::Outputs, hk::Registers>(
      "odometry", 5, odoloc::tb::hls_calls(1000000), hk::step);
  EXPECT_EQ(check.names_error, "");
  EXPECT_GT(check.calls, 0U);
  EXPECT_EQ(check.mismatches, 0U) << check.first_mismatch;
}

// The reference's stimulus, replayed through the kernel: equal outputs, and
// the rare cases the stimulus promises actually happen.
TEST(HlsOdometry, TheStimulusReachesTheRareCases) {
  const auto* kernel = odoloc::hls_export::find_kernel("odometry");
  ASSERT_NE(kernel, nullptr);
  const auto reference = kernel->make_reference(11);
  std::vector<std::int64_t> in_row(reference->input_names().size());
  std::vector<std::int64_t> want(reference->output_names().size());
  hk::Registers regs;
  hk::Outputs out;
  hk::Outputs last;
  struct {
    int updates = 0, overrun = 0, clamp = 0, to_front = 0, to_rear = 0, x_wrap = 0, theta_wrap = 0,
        steer_saturated = 0, resets = 0, set_pose_over_update = 0;
  } seen;
  std::uint64_t mismatches = 0;
  constexpr std::int64_t kSteerMax = (std::int64_t{1} << 23) - 1;
  for (std::uint64_t call = 0; call < odoloc::tb::scaled(300000); ++call) {
    reference->stimulus(in_row);
    reference->step(in_row, want);
    hk::Inputs in;
    std::size_t i = 0;
    visit_fields(in, [&](const char*, auto& field) { field = in_row[i++]; });
    const bool integrating =
        to_s64(regs.sequencer.phase) == oc::kPhaseThetaWait && to_s64(regs.cordic.ready) == 1;
    hk::step(regs, in, out);
    std::size_t o = 0;
    visit_fields(out, [&](const char*, auto& field) { mismatches += to_s64(field) != want[o++]; });
    seen.resets += to_s64(in.reset) == 1;
    seen.set_pose_over_update += integrating && to_s64(in.set_pose) == 1;
    if (to_s64(out.updates) != to_s64(last.updates) && to_s64(in.reset) == 0 &&
        to_s64(in.set_pose) == 0) {
      ++seen.updates;
      seen.to_front += to_s64(out.dtheta_from_front) > to_s64(last.dtheta_from_front);
      seen.to_rear += to_s64(out.dtheta_from_front) < to_s64(last.dtheta_from_front);
      // The high word jumps from one end to the other: x wrapped at 2^63.
      seen.x_wrap += std::abs(to_s64(out.pose_x_hi) - to_s64(last.pose_x_hi)) > (1LL << 31);
      seen.theta_wrap += std::abs(to_s64(out.pose_theta) - to_s64(last.pose_theta)) > kTwo40 / 2;
      seen.steer_saturated += std::abs(to_s64(out.steer_position)) >= kSteerMax;
    }
    seen.overrun += to_s64(out.overrun) > to_s64(last.overrun);
    seen.clamp += to_s64(out.steer_clamped) > to_s64(last.steer_clamped);
    last = out;
  }
  EXPECT_EQ(mismatches, 0U);
  std::printf(
      "%d updates, %d overruns, %d clamps, dtheta to front %d / back %d, x wraps %d, theta wraps "
      "%d, saturated steering %d, resets %d, set_pose over an update %d\n",
      seen.updates, seen.overrun, seen.clamp, seen.to_front, seen.to_rear, seen.x_wrap,
      seen.theta_wrap, seen.steer_saturated, seen.resets, seen.set_pose_over_update);
  EXPECT_GT(seen.updates, 1000);
  EXPECT_GT(seen.overrun, 10);
  EXPECT_GT(seen.clamp, 10);
  EXPECT_GT(seen.to_front, 10);
  EXPECT_GT(seen.to_rear, 10);
  EXPECT_GT(seen.x_wrap, 0);
  EXPECT_GT(seen.theta_wrap, 0);
  EXPECT_GT(seen.steer_saturated, 0);
  EXPECT_GT(seen.resets, 0);
  EXPECT_GT(seen.set_pose_over_update, 0);
}

// The kernel beside the whole fabric: its input ports are the fabric's
// configuration, strobes and EPPM latched counts, and every register and
// output must equal the fabric's, every clock.
TEST(HlsOdometry, EqualsTheWholeFabricEveryRegisterEveryClock) {
  std::mt19937_64 rng(2027);
  rtl::OdometryFabric fabric;
  rtl::OdometryFabric::Config cfg;
  rtl::OdometryFabric::In in{};
  std::array<Quadrature, rtl::kEncoderCount> wheels{};
  hk::Registers regs;
  hk::Outputs out;
  const auto one_in = [&](std::uint64_t n) { return rng() % n == 0; };
  const auto strobe = [&](std::uint64_t n) { return rtl::UInt<1>::truncate(one_in(n)); };
  std::uniform_real_distribution<double> rate(-0.06, 0.06);
  const std::uint64_t clocks = odoloc::tb::scaled(400000);
  std::uint64_t updates = 0;
  rtl::UInt<32> last_updates;
  for (std::uint64_t clock = 0; clock < clocks; ++clock) {
    if (clock % 30000 == 0) {  // a new configuration, within and beyond the physical range
      rtl::OdometryConfig& oc = cfg.odometry;
      constexpr std::array<std::uint16_t, 7> kPeriods{41, 50, 64, 120, 300, 30, 0};
      oc.cfg.update_clocks = rtl::UInt<16>{kPeriods[(clock / 30000) % kPeriods.size()]};
      oc.cfg.policy = rtl::UInt<2>::truncate(rng());
      oc.cfg.select_shift = rtl::UInt<4>::truncate(one_in(3) ? 0 : one_in(2) ? 12 : rng());
      const bool wild = one_in(3);
      const auto word = [&](std::uint64_t typical) {
        return rtl::UInt<32>::truncate(wild ? rng() : typical + rng() % (typical / 4 + 1));
      };
      oc.rear_ds_scale.value = word(54975581);  // 1e-4 m per edge
      oc.rear_dtheta_scale.value = word(58333000);
      oc.front_ds_scale.value = word(109951163);
      oc.front_dtheta_scale.value = word(43750000);
      oc.steer_scale.value = word(std::uint64_t{1} << 32);  // 1/256 turn per count
      oc.steer_limit.value = rtl::UInt<32>::truncate(one_in(2)   ? 477218588
                                                     : one_in(2) ? 1U << 30
                                                                 : rng());
      oc.select_ds_threshold.value = rtl::UInt<32>::truncate(one_in(2) ? 0 : rng() % 2000000);
      oc.select_dtheta_threshold.value = rtl::UInt<32>::truncate(one_in(2) ? 0 : rng() % 100000000);
    }
    if (clock % 4000 == 0) {
      for (auto& w : wheels)
        w.rate = one_in(5) ? 0.0 : rate(rng);
      if (one_in(3))  // a one-wheel over-count: the left rear wheel runs fast
        wheels[0].rate = wheels[1].rate * 1.3;
    }
    for (std::size_t w = 0; w < rtl::kEncoderCount; ++w)
      in.pins[w] = wheels[w].tick();
    in.odometry.status = {.overrun = strobe(500), .steer_clamped = strobe(500)};
    in.odometry.command = {.set_pose = strobe(3000), .clear_flags = strobe(5000)};
    if (one_in(100)) {
      cfg.odometry.set_x.bits = rtl::SInt<64>::truncate(static_cast<std::int64_t>(rng()));
      cfg.odometry.set_y.bits = rtl::SInt<64>::truncate(static_cast<std::int64_t>(rng()));
      cfg.odometry.set_theta.bits = rtl::UInt<40>::truncate(rng());
    }
    in.reset = strobe(50000);
    const hk::Inputs k = kernel_inputs(fabric, in, cfg);  // this clock's wires
    fabric.step(in, cfg);
    hk::step(regs, k, out);
    const std::string reg_diff = register_difference(regs, fabric);
    ASSERT_EQ(reg_diff, "") << "clock " << clock;
    const std::string out_diff = output_difference(out, fabric, cfg);
    ASSERT_EQ(out_diff, "") << "clock " << clock;
    updates += fabric.sequencer().updates != last_updates;
    last_updates = fabric.sequencer().updates;
  }
  EXPECT_GT(updates, odoloc::tb::scaled(400000) / 400);  // many complete updates compared
}

// A kernel run from reset with one configuration; counts held per call.
struct Bench {
  hk::Registers regs;
  hk::Inputs in;
  hk::Outputs out;
  void step() {
    hk::step(regs, in, out);
    in.set_pose = 0;
    in.reset = 0;
  }
  // Runs to the next LATCH clock, then through the update it starts; returns
  // the calls from the LATCH call (its edge latches the EPPMs) to the call
  // whose edge updates the pose, both included.
  int update() {
    while (to_s64(out.latch) == 0)
      step();
    const long long before = to_s64(out.updates);
    int calls = 0;
    do {
      step();
      ++calls;
    } while (to_s64(out.updates) == before && calls < 1000);
    return calls;
  }
};

TEST(HlsOdometry, UpdateLatencyAndTheOverrunBoundary) {
  for (int period = 38; period <= 43; ++period) {
    Bench b;
    b.in.update_clocks = period;
    int latency = 0;
    for (int u = 0; u < 5; ++u)
      latency = b.update();
    // docs/odometry.md: the pose edge is kUpdateLatencyClocks after the LATCH edge.
    EXPECT_EQ(latency - 1, static_cast<int>(rtl::OdometrySequencer::kUpdateLatencyClocks))
        << "update_clocks " << period;
    // An update holds the sequencer for latency + 1 clocks (LATCH included).
    const bool overrun =
        period < static_cast<int>(rtl::OdometrySequencer::kUpdateLatencyClocks) + 2;
    EXPECT_EQ(to_s64(b.out.overrun), overrun ? 1 : 0) << "update_clocks " << period;
  }
}

// The paper's memoryless rule (shift 0, thresholds 0) keeps the smaller of
// each increment, so a one-wheel over-count never reaches the pose when the
// front unit reads true; the leaky rule lets at most about its threshold through.
TEST(HlsOdometry, MinSelectDropsAOneWheelOverCount) {
  for (const bool paper : {true, false}) {
    Bench clean, bumped;
    for (Bench* b : {&clean, &bumped}) {
      b->in.update_clocks = 50;
      b->in.rear_ds_scale = 1U << 27;   // 2^-13 m per count of nL + nR
      b->in.front_ds_scale = 1U << 28;  // so nF = (nL + nR) / 2 agrees
      b->in.rear_dtheta_scale = 1U << 24;
      b->in.front_dtheta_scale = 1U << 24;
      b->in.steer_scale = 1U << 20;
      b->in.steer_limit = 477218588;
      b->in.select_shift = paper ? 0 : 12;
      b->in.select_ds_threshold = paper ? 0 : 1U << 20;
      b->in.select_dtheta_threshold = paper ? 0 : 1U << 28;
      b->in.n_left = 200;
      b->in.n_right = 200;
      b->in.n_front = 200;
    }
    int front_picked = 0;
    for (int u = 0; u < 60; ++u) {
      const bool bump = u >= 20 && u < 40;
      bumped.in.n_left = bump ? 260 : 200;  // slip or a bump: the left wheel over-counts
      clean.update();
      bumped.update();
      if (bump) {
        front_picked +=
            to_s64(bumped.out.dtheta_from_front) == 1 && to_s64(bumped.out.ds_from_front) == 1;
      } else if (paper) {
        EXPECT_EQ(to_s64(bumped.out.ds_from_front), 0) << "ties go to the rear, update " << u;
      }
    }
    const long long dtheta_error =
        std::abs(to_s64(bumped.out.pose_theta) - to_s64(clean.out.pose_theta));
    const long long x_error = std::abs(wide(bumped.out.pose_x_hi, bumped.out.pose_x_lo) -
                                       wide(clean.out.pose_x_hi, clean.out.pose_x_lo));
    if (paper) {
      EXPECT_EQ(front_picked, 20);
      EXPECT_EQ(dtheta_error, 0);
      EXPECT_EQ(x_error, 0);
    } else {
      // One over-count update is 60 * 2^24 turn units and 30 * 2^20 m units:
      // the hysteresis lets through about one threshold and one update's worth.
      EXPECT_GE(front_picked, 15);
      EXPECT_LE(dtheta_error, (1LL << 28) + 2 * 60 * (1LL << 24));
      EXPECT_LE(x_error, ((1LL << 20) + 2 * 30 * (1LL << 20)) << 14);
    }
  }
}

// x and y wrap at 2^63 like the model's 64-bit add_wrap; theta at one turn;
// and set_pose wins over an update on the same edge.
TEST(HlsOdometry, PoseWrapsAndSetPoseWins) {
  Bench b;
  b.in.update_clocks = 41;
  b.in.rear_ds_scale = 0xFFFFFFFFU;  // ds near 2^47 per update at the count limit
  b.in.rear_dtheta_scale = 1U << 20;
  b.in.n_left = (1 << 19) - 1;
  b.in.n_right = (1 << 19) - 2;  // turns right a little: theta goes down through 0
  b.in.policy = oc::kPolicyRearOnly;
  b.in.set_x_hi = 0x7FFFFFFF;
  b.in.set_x_lo = 0xFFFFF000U;  // 2^63 - 4096: the next update wraps x
  b.in.set_theta = 0;
  b.in.set_pose = 1;
  b.step();
  b.update();
  const std::int64_t ds = to_s64(b.out.ds);
  const std::int64_t dtheta = to_s64(b.out.dtheta);
  ASSERT_GT(ds, 0);
  ASSERT_LT(dtheta, 0);
  // The heading CORDIC ran at theta + dtheta / 2, just below one turn.
  const auto angle = odoloc::logic::odometry::to_cordic_angle<rtl::Family>(
      rtl::Heading::truncate(dtheta).shr<1>());
  const rtl::cordic::SinCos sc = rtl::cordic::sincos(angle);
  const std::uint64_t x =
      (std::uint64_t{1} << 63) - 4096 + static_cast<std::uint64_t>(ds * sc.cos.value());
  EXPECT_EQ(wide(b.out.pose_x_hi, b.out.pose_x_lo), static_cast<std::int64_t>(x));
  EXPECT_LT(wide(b.out.pose_x_hi, b.out.pose_x_lo), 0);  // wrapped
  EXPECT_EQ(to_s64(b.out.pose_theta), kTwo40 + dtheta);  // wrapped below one turn
  // set_pose in the very clock the pose would integrate: the set values win.
  while (
      !(to_s64(b.regs.sequencer.phase) == oc::kPhaseThetaWait && to_s64(b.regs.cordic.ready) == 1))
    b.step();
  b.in.set_x_hi = 0;
  b.in.set_x_lo = 7;
  b.in.set_theta = 5;
  const long long updates = to_s64(b.out.updates);
  b.in.set_pose = 1;
  b.step();
  EXPECT_EQ(to_s64(b.out.updates), updates + 1);         // the update completed...
  EXPECT_EQ(wide(b.out.pose_x_hi, b.out.pose_x_lo), 7);  // ...but the pose is the set one
  EXPECT_EQ(to_s64(b.out.pose_theta), 5);
}

}  // namespace
