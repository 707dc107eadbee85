// The odometry datapath as an HLS kernel: one call = one fabric clock of
// rtl::OdometryDatapath, the odometry fabric without its four EPPMs
// (rtl/odometry.hpp, docs/odometry.md), in odoloc::hls integer types. C++14.
//
// Boundary. The fabric is four EPPMs plus this datapath: the sequencer, the
// shared sequential CORDIC, the rear unit, the front unit, min-select, the pose
// integrator and the report of the last update. The EPPMs are a kernel of
// their own (one per encoder), and what crosses from them into the datapath is
// one register per encoder, the count latched by the last latch-and-clear; what
// goes back is the latch-and-clear strobe. So the latched counts are input
// ports, `latch` is an output port, and the odometry.* configuration registers
// (wires from the register file) are input ports. The outputs are the
// odometry.* status the register file reads, i.e. everything this block drives
// to the rest of the fabric. The CORDIC is the cordic kernel's logic
// (logic/cordic.hpp), one CORDIC, two runs per update.
//
// Inputs (per call; all read in this clock):
//   n_left, n_right, n_front, n_steer   SInt<20>  the four EPPMs' latched counts
//                      (x4 edges; eppm[left_rear, right_rear, front_drive,
//                      steering].latched). Read only in the GATHER clock.
//   update_clocks      UInt<16>  control period in clocks, 0 stops updates
//   policy             UInt<2>   min-select: 0 per component, 1 whole set,
//                                2 rear only, 3 front only
//   select_shift       UInt<4>   min-select memory, 2^shift updates
//   rear_ds_scale, rear_dtheta_scale, front_ds_scale, front_dtheta_scale,
//   steer_scale        UInt<32>  2^-40 m or 2^-40 turn per count
//   steer_limit        UInt<32>  |phi| limit, 2^-32 turn
//   select_ds_threshold UInt<32> 2^-32 m;  select_dtheta_threshold UInt<32> 2^-40 turn
//   set_x_hi, set_y_hi SInt<32>, set_x_lo, set_y_lo UInt<32>: set_x, set_y
//                      (SInt<64>, 2^-46 m) as their high and low words
//   set_theta          UInt<40>  2^-40 turn
//   clear_overrun      UInt<1>   odometry.status.overrun write-1-to-clear
//   clear_steer_clamped UInt<1>  odometry.status.steer_clamped write-1-to-clear
//   set_pose           UInt<1>   command.set_pose: pose <- set_*; wins over an
//                                update on the same edge
//   clear_flags        UInt<1>   command.clear_flags: clears every sticky flag
//   reset              UInt<1>   synchronous reset of the whole datapath
// Outputs (the registers after this clock's edge):
//   latch              UInt<1>   the EPPMs latch-and-clear on the next edge
//                                (phase = LATCH): the EPPMs' latch_clear wire
//   phase              UInt<4>   sequencer phase (0 idle, 1 latch, 2 gather,
//                                3 phi_load, 4 phi_wait, 5 front, 6 select,
//                                7 theta_load, 8 theta_wait)
//   overrun, steer_clamped UInt<1> sticky flags
//   ds_from_front, dtheta_from_front UInt<1> min-select's choice, last update
//   updates            UInt<32>  completed pose updates (wraps)
//   pose_x_hi, pose_y_hi SInt<32>, pose_x_lo, pose_y_lo UInt<32>: x, y
//                      (SInt<64>, 2^-46 m, wrap) as their high and low words
//   pose_theta         UInt<40>  2^-40 turn (wraps at one turn)
//   rear_ds, front_ds, ds   SInt<48>  2^-32 m, the last update's increments
//   rear_dtheta, front_dtheta, dtheta  SInt<56>  2^-40 turn
//   steer_phi          SInt<40>  clamped steering angle of the last update
//   steer_position     SInt<24>  steering counts since reset (saturating)
//
// Latency: `latch` = 1 after call k means call k+1 is the LATCH clock, whose
// edge latches the EPPMs; the pose, the update count and every increment
// output then change together on the edge of call k+1+39
// (rtl::OdometrySequencer::kUpdateLatencyClocks). An update holds the
// sequencer for 40 calls, so with update_clocks <= 40 a period ends before
// its update finished: `overrun` is set and that period is skipped.
// Reset: every register to 0 (the model's reset values), CORDIC included.
//
// x and y are 64 bits: the logic keeps and adds them as two 32-bit words
// (logic::Words), so that every intermediate fits in 63 bits (docs/hls.md),
// and the ports are the register map's own _hi/_lo words.
//
// The logic is the model's own (logic/odometry.hpp, which the cycle model's
// rtl::OdometryDatapath runs): this file maps the kernel's flat ports onto
// the register map's port structs (odoloc/logic/ports.hpp) and back, nothing
// else. test_hls_odometry_* checks every output and register against the
// model per type family.
#pragma once

#include "odoloc/hls/types.hpp"
#include "odoloc/logic/odometry.hpp"
#include "odoloc/logic/ports.hpp"

namespace odoloc {
namespace hls {
namespace odometry {

namespace oc = rtl::odometry;

using Count = sint<oc::kCountBits>;
using Scale = uint<oc::kScaleBits>;
using Distance = sint<oc::kDistanceBits>;
using Heading = sint<oc::kHeadingBits>;
using Steer = sint<oc::kSteerBits>;
using SteerPosition = sint<oc::kSteerPositionBits>;
using Theta = uint<oc::kThetaBits>;
using HiWord = sint<32>;
using LoWord = uint<32>;

// Every field starts at 0: ap_int's default constructor leaves the value
// undefined (docs/hls.md).
struct Inputs {
  Count n_left = 0, n_right = 0, n_front = 0, n_steer = 0;
  uint<oc::kPeriodBits> update_clocks = 0;
  uint<oc::kPolicyBits> policy = 0;
  uint<oc::kShiftBits> select_shift = 0;
  Scale rear_ds_scale = 0, rear_dtheta_scale = 0, front_ds_scale = 0, front_dtheta_scale = 0;
  Scale steer_scale = 0, steer_limit = 0, select_ds_threshold = 0, select_dtheta_threshold = 0;
  HiWord set_x_hi = 0;
  LoWord set_x_lo = 0;
  HiWord set_y_hi = 0;
  LoWord set_y_lo = 0;
  Theta set_theta = 0;
  uint<1> clear_overrun = 0, clear_steer_clamped = 0, set_pose = 0, clear_flags = 0, reset = 0;
};

struct Outputs {
  uint<1> latch = 0;
  uint<oc::kPhaseBits> phase = 0;
  uint<1> overrun = 0, steer_clamped = 0, ds_from_front = 0, dtheta_from_front = 0;
  uint<oc::kUpdatesBits> updates = 0;
  HiWord pose_x_hi = 0;
  LoWord pose_x_lo = 0;
  HiWord pose_y_hi = 0;
  LoWord pose_y_lo = 0;
  Theta pose_theta = 0;
  Distance rear_ds = 0;
  Heading rear_dtheta = 0;
  Distance front_ds = 0;
  Heading front_dtheta = 0;
  Distance ds = 0;
  Heading dtheta = 0;
  Steer steer_phi = 0;
  SteerPosition steer_position = 0;
};

using Logic = logic::odometry::Datapath<Family>;
using Registers = logic::odometry::Regs<Family>;  // the model's blocks, register for register
using Config = logic::ports::odometry::Config<Family>;
using Pulses = logic::ports::odometry::Pulses<Family>;
using Status = logic::ports::odometry::Status<Family>;

// The ports by name, in the golden vectors' column order (testbenches only).
template <class Visit>
void visit_fields(Inputs& s, Visit&& v) {
  v("n_left", s.n_left);
  v("n_right", s.n_right);
  v("n_front", s.n_front);
  v("n_steer", s.n_steer);
  v("update_clocks", s.update_clocks);
  v("policy", s.policy);
  v("select_shift", s.select_shift);
  v("rear_ds_scale", s.rear_ds_scale);
  v("rear_dtheta_scale", s.rear_dtheta_scale);
  v("front_ds_scale", s.front_ds_scale);
  v("front_dtheta_scale", s.front_dtheta_scale);
  v("steer_scale", s.steer_scale);
  v("steer_limit", s.steer_limit);
  v("select_ds_threshold", s.select_ds_threshold);
  v("select_dtheta_threshold", s.select_dtheta_threshold);
  v("set_x_hi", s.set_x_hi);
  v("set_x_lo", s.set_x_lo);
  v("set_y_hi", s.set_y_hi);
  v("set_y_lo", s.set_y_lo);
  v("set_theta", s.set_theta);
  v("clear_overrun", s.clear_overrun);
  v("clear_steer_clamped", s.clear_steer_clamped);
  v("set_pose", s.set_pose);
  v("clear_flags", s.clear_flags);
  v("reset", s.reset);
}
template <class Visit>
void visit_fields(Outputs& s, Visit&& v) {
  v("latch", s.latch);
  v("phase", s.phase);
  v("overrun", s.overrun);
  v("steer_clamped", s.steer_clamped);
  v("ds_from_front", s.ds_from_front);
  v("dtheta_from_front", s.dtheta_from_front);
  v("updates", s.updates);
  v("pose_x_hi", s.pose_x_hi);
  v("pose_x_lo", s.pose_x_lo);
  v("pose_y_hi", s.pose_y_hi);
  v("pose_y_lo", s.pose_y_lo);
  v("pose_theta", s.pose_theta);
  v("rear_ds", s.rear_ds);
  v("rear_dtheta", s.rear_dtheta);
  v("front_ds", s.front_ds);
  v("front_dtheta", s.front_dtheta);
  v("ds", s.ds);
  v("dtheta", s.dtheta);
  v("steer_phi", s.steer_phi);
  v("steer_position", s.steer_position);
}

// The flat ports as the register map's port structs.
inline logic::odometry::LatchedCounts<Family> latched_counts(const Inputs& in) {
  logic::odometry::LatchedCounts<Family> c;
  c.left_rear = in.n_left;
  c.right_rear = in.n_right;
  c.front_drive = in.n_front;
  c.steering = in.n_steer;
  return c;
}
inline Config config(const Inputs& in) {
  Config c;
  c.cfg.update_clocks = in.update_clocks;
  c.cfg.policy = in.policy;
  c.cfg.select_shift = in.select_shift;
  c.rear_ds_scale.value = in.rear_ds_scale;
  c.rear_dtheta_scale.value = in.rear_dtheta_scale;
  c.front_ds_scale.value = in.front_ds_scale;
  c.front_dtheta_scale.value = in.front_dtheta_scale;
  c.steer_scale.value = in.steer_scale;
  c.steer_limit.value = in.steer_limit;
  c.select_ds_threshold.value = in.select_ds_threshold;
  c.select_dtheta_threshold.value = in.select_dtheta_threshold;
  c.set_x.bits.hi = in.set_x_hi;
  c.set_x.bits.lo = in.set_x_lo;
  c.set_y.bits.hi = in.set_y_hi;
  c.set_y.bits.lo = in.set_y_lo;
  c.set_theta.bits = in.set_theta;
  return c;
}
inline Pulses pulses(const Inputs& in) {
  Pulses p;
  p.status.overrun = in.clear_overrun;
  p.status.steer_clamped = in.clear_steer_clamped;
  p.command.set_pose = in.set_pose;
  p.command.clear_flags = in.clear_flags;
  return p;
}
inline void drive(Outputs& out, const uint<1>& latch, const Status& s) {
  out.latch = latch;
  out.phase = s.status.phase;
  out.overrun = s.status.overrun;
  out.steer_clamped = s.status.steer_clamped;
  out.ds_from_front = s.status.ds_from_front;
  out.dtheta_from_front = s.status.dtheta_from_front;
  out.updates = s.updates.count;
  out.pose_x_hi = s.pose_x.bits.hi;
  out.pose_x_lo = s.pose_x.bits.lo;
  out.pose_y_hi = s.pose_y.bits.hi;
  out.pose_y_lo = s.pose_y.bits.lo;
  out.pose_theta = s.pose_theta.bits;
  out.rear_ds = s.rear_ds.bits;
  out.rear_dtheta = s.rear_dtheta.bits;
  out.front_ds = s.front_ds.bits;
  out.front_dtheta = s.front_dtheta.bits;
  out.ds = s.ds.bits;
  out.dtheta = s.dtheta.bits;
  out.steer_phi = s.steer_phi.bits;
  out.steer_position = s.steer_position.counts;
}

// One fabric clock: the registers after this clock's edge (`regs` is the
// register bank), then the outputs of those registers.
inline void step(Registers& regs, const Inputs& in, Outputs& out) {
#pragma HLS inline
  regs = Logic::next(regs, latched_counts(in), config(in), pulses(in), in.reset);
  drive(out, Logic::latch(regs.sequencer), Logic::status<Status>(regs));
}

}  // namespace odometry
}  // namespace hls
}  // namespace odoloc

// The top function (hls/src/odometry_top.cpp): one call = one clock, the
// registers held in the function's static state.
void odoloc_odometry(const odoloc::hls::odometry::Inputs& in, odoloc::hls::odometry::Outputs& out);
