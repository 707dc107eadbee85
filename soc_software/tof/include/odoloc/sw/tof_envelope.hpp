// Rise-time compensation: the receiver envelope model and its inversion from
// the comparator's pulse width to the threshold-crossing delay
// (docs/tof-measurements.md#rise-time-compensation).
//
// Model (first order, per receiver): a burst of length T_p arriving at t = 0
// gives the envelope
//     e(t) = A (1 - exp(-t/tau_r))              0 <= t <= T_p
//     e(t) = A_end exp(-(t - T_p)/tau_f)         t > T_p,  A_end = A (1 - exp(-T_p/tau_r))
// A comparator at threshold V (x = A/V) rises at
//     t_up = tau_r ln(x/(x-1))                   (the crossing delay to subtract)
// and falls at t_dn = T_p + tau_f ln(x (1 - exp(-T_p/tau_r))), so the width
//     w(x) = T_p + tau_f ln(x (1 - exp(-T_p/tau_r))) - tau_r ln(x/(x-1))
// exists for x > x_min = 1/(1 - exp(-T_p/tau_r)) (the envelope must reach V
// before the burst ends) and grows strictly from 0 (x -> x_min, t_up -> T_p)
// to infinity:  dw/dx = tau_f/x + tau_r/(x(x-1)) > 0. Inverting w(x) gives x,
// then t_up(x).
#pragma once

#include <string>

namespace odoloc::sw::tof {

// The parameters the acoustic world will calibrate, in one place.
struct EnvelopeModel {
  // Envelope time constants. Kleeman: the transmitter's envelope rises in
  // "about 1 ms" and the received envelope falls in "2 ms"; read as three
  // time constants each (95 %): tau_r = 1/3 ms, tau_f = 2/3 ms.
  double rise_s = 1e-3 / 3;
  double fall_s = 2e-3 / 3;
  // Burst length T_p (Kleeman's t_pulse).
  double burst_s = 2.5e-3;
  // Largest plausible A/V (60 dB). A longer width than w(max_ratio) is not a
  // single burst (overlapping echoes, a stuck input): compensated as
  // max_ratio and flagged kMergedPulse.
  double max_ratio = 1000;

  // Throws std::invalid_argument naming `owner` and the bad field.
  void validate(const std::string& owner = "EnvelopeModel") const;

  // x_min = 1/(1 - exp(-T_p/tau_r)): the smallest A/V that crosses at all.
  [[nodiscard]] double min_ratio() const;
  // t_up(x) = tau_r ln(x/(x-1)), for x > x_min.
  [[nodiscard]] double crossing_delay_s(double ratio) const;
  // w(x), for x > x_min.
  [[nodiscard]] double width_s(double ratio) const;
  // The longest single-burst width, w(max_ratio).
  [[nodiscard]] double max_width_s() const { return width_s(max_ratio); }

  struct Inverse {
    double ratio = 0;           // A/V
    double delay_s = 0;         // t_up to subtract from the rise
    double ddelay_dwidth = 0;   // sensitivity, in [-1, 0]: width noise -> delay noise
    bool clamped_high = false;  // width beyond w(max_ratio): ratio = max_ratio
  };
  // Inverts w(x) by bisection on ln(x - x_min) to double precision; a width
  // <= 0 gives x -> x_min (delay T_p). Monotone in width.
  [[nodiscard]] Inverse invert_width(double width_s) const;
};

// One envelope pulse as an arrival time at its receiver: the rise minus
// the crossing delay its width gives, and the arrival's standard deviation
// from the rise's and the width's quantisation (tick_s: each stamp's
// uniform error spreads the width by tick/sqrt(6)) and timing_sd_s.
struct CompensatedPulse {
  double time_s = 0;
  double sd_s = 0;
  EnvelopeModel::Inverse compensation;
};
[[nodiscard]] CompensatedPulse compensate_pulse(const EnvelopeModel& model, double rise_s,
                                                double width_s, double tick_s, double timing_sd_s);

}  // namespace odoloc::sw::tof
