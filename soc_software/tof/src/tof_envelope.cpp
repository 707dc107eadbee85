#include "odoloc/sw/tof_envelope.hpp"

#include <cmath>
#include <stdexcept>

namespace odoloc::sw::tof {
namespace {

void require_positive(double v, const std::string& owner, const char* field) {
  if (!(std::isfinite(v) && v > 0))
    throw std::invalid_argument(owner + ": " + field + " must be finite and positive, got " +
                                std::to_string(v));
}

}  // namespace

void EnvelopeModel::validate(const std::string& owner) const {
  require_positive(rise_s, owner, "rise_s (tau_r)");
  require_positive(fall_s, owner, "fall_s (tau_f)");
  require_positive(burst_s, owner, "burst_s (T_p)");
  if (!(std::isfinite(max_ratio) && max_ratio > 2 * min_ratio()))
    throw std::invalid_argument(owner + ": max_ratio must be finite and above 2 x_min = " +
                                std::to_string(2 * min_ratio()));
}

double EnvelopeModel::min_ratio() const {
  return -1.0 / std::expm1(-burst_s / rise_s);
}

double EnvelopeModel::crossing_delay_s(double ratio) const {
  return -rise_s * std::log1p(-1.0 / ratio);
}

double EnvelopeModel::width_s(double ratio) const {
  const double reach = -std::expm1(-burst_s / rise_s);  // 1 - exp(-T_p/tau_r)
  return burst_s + fall_s * std::log(ratio * reach) - crossing_delay_s(ratio);
}

EnvelopeModel::Inverse EnvelopeModel::invert_width(double width) const {
  // x = x_min + exp(s); x - 1 = q/(1-q) + exp(s) with q = exp(-T_p/tau_r),
  // kept apart so that x close to x_min (x_min - 1 ~ 5e-4 by default) loses
  // nothing to cancellation.
  const double q = std::exp(-burst_s / rise_s);
  const double reach = -std::expm1(-burst_s / rise_s);
  const double x_min_minus_1 = q / reach;
  const auto eval = [&](double log_u, double& ratio, double& ratio_m1) {
    ratio_m1 = x_min_minus_1 + std::exp(log_u);
    ratio = 1.0 + ratio_m1;
    const double delay = rise_s * (std::log(ratio) - std::log(ratio_m1));
    return burst_s + fall_s * std::log(ratio * reach) - delay;
  };
  Inverse out;
  double x = 0, xm1 = 0;
  const double s_max = std::log(max_ratio - (1.0 + x_min_minus_1));
  double s = s_max;
  if (!(width < eval(s_max, x, xm1))) {  // also catches a NaN width
    out.clamped_high = true;
  } else {
    double lo = -60.0;  // exp(-60) ~ 1e-26: x indistinguishable from x_min
    if (eval(lo, x, xm1) >= width) {
      s = lo;
    } else {
      for (int i = 0; i < 200 && s - lo > 1e-13; ++i) {
        const double mid = 0.5 * (lo + s);
        (eval(mid, x, xm1) < width ? lo : s) = mid;
      }
    }
  }
  eval(s, x, xm1);
  out.ratio = x;
  out.delay_s = rise_s * (std::log(x) - std::log(xm1));
  // d t_up/dw = (d t_up/dx)/(dw/dx) = -tau_r / (tau_f (x-1) + tau_r)
  out.ddelay_dwidth = -rise_s / (fall_s * xm1 + rise_s);
  return out;
}

CompensatedPulse compensate_pulse(const EnvelopeModel& model, double rise_s, double width_s,
                                  double tick_s, double timing_sd_s) {
  CompensatedPulse p;
  p.compensation = model.invert_width(width_s);
  p.time_s = rise_s - p.compensation.delay_s;
  const double quantisation = tick_s / std::sqrt(12.0);
  const double width_noise = p.compensation.ddelay_dwidth * tick_s / std::sqrt(6.0);
  p.sd_s = std::sqrt(quantisation * quantisation + timing_sd_s * timing_sd_s +
                     width_noise * width_noise);
  return p;
}

}  // namespace odoloc::sw::tof
