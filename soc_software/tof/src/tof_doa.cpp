#include "odoloc/sw/tof_doa.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace odoloc::sw::tof {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr int kGrid = 720;  // 0.5 degree

// Upper 99.9 % point of chi^2 with `dof` degrees of freedom (Wilson-Hilferty).
double chi2_limit(int dof) {
  const double k = dof;
  const double a = 2.0 / (9.0 * k);
  const double z = 3.090;
  const double v = 1.0 - a + z * std::sqrt(a);
  return k * v * v * v;
}

struct Problem {
  std::vector<Vec2> r;       // receiver positions / c  (seconds per unit direction)
  std::vector<double> t, w;  // times, weights 1/sd^2
  std::vector<double> axis;
  double sum_w = 0;

  // Profile cost: sum w_i (tau_i - mean_w tau)^2 with tau_i = t_i + r_i.u/c.
  [[nodiscard]] double cost(double beta, double* t0 = nullptr) const {
    const double cx = std::cos(beta), sy = std::sin(beta);
    double mean = 0;
    for (std::size_t i = 0; i < t.size(); ++i)
      mean += w[i] * (t[i] + r[i].x * cx + r[i].y * sy);
    mean /= sum_w;
    double ss = 0;
    for (std::size_t i = 0; i < t.size(); ++i) {
      const double d = t[i] + r[i].x * cx + r[i].y * sy - mean;
      ss += w[i] * d * d;
    }
    if (t0 != nullptr)
      *t0 = mean;
    return ss;
  }
  // How squarely the receivers face beta (tie-break between mirror minima).
  [[nodiscard]] double facing(double beta) const {
    double f = 0;
    for (const double a : axis)
      f += std::cos(beta - a);
    return f;
  }
};

double refine(const Problem& p, double lo, double hi) {
  const double g = (std::sqrt(5.0) - 1) / 2;
  double a = lo, b = hi;
  double c = b - g * (b - a), d = a + g * (b - a);
  double fc = p.cost(c), fd = p.cost(d);
  for (int i = 0; i < 80 && b - a > 1e-12; ++i) {
    if (fc < fd) {
      b = d, d = c, fd = fc;
      c = b - g * (b - a), fc = p.cost(c);
    } else {
      a = c, c = d, fc = fd;
      d = a + g * (b - a), fd = p.cost(d);
    }
  }
  return 0.5 * (a + b);
}

// Fit over the hits with used[i]; fills doa, t0, residuals, chi2.
void fit_used(const ReceiverArray& array, std::span<const TimedHit> hits, const PlaneWaveOptions& o,
              PlaneWaveFit& fit) {
  Problem p;
  std::vector<std::size_t> index;
  for (std::size_t i = 0; i < hits.size(); ++i) {
    if (!fit.hits[i].used)
      continue;
    const Receiver& rx = array.receivers[static_cast<std::size_t>(hits[i].channel)];
    p.r.push_back({rx.position_m.x / o.speed_of_sound_mps, rx.position_m.y / o.speed_of_sound_mps});
    p.t.push_back(hits[i].time_s);
    p.w.push_back(1.0 / (hits[i].sd_s * hits[i].sd_s));
    p.axis.push_back(rx.axis_rad);
    p.sum_w += p.w.back();
    index.push_back(i);
  }
  const std::size_t n = p.t.size();
  for (PlaneWaveFit::Hit& h : fit.hits)
    h.residual_s = 0;
  if (n == 1) {
    // No direction: assume the source within single_half_angle of the axis.
    const Receiver& rx = array.receivers[static_cast<std::size_t>(hits[index[0]].channel)];
    const double h = o.single_half_angle_rad;
    const double along =
        (rx.position_m.x * std::cos(rx.axis_rad) + rx.position_m.y * std::sin(rx.axis_rad)) /
        o.speed_of_sound_mps;
    const double radius = std::hypot(rx.position_m.x, rx.position_m.y) / o.speed_of_sound_mps;
    // r.u ranges over about [along - radius (1 - cos h), along]: take its middle.
    const double spread = radius * (1 - std::cos(h));
    fit.t0_s = p.t[0] + along - spread / 2;
    fit.t0_sd_s = std::sqrt(1.0 / p.w[0] + spread * spread / 12.0);
    fit.doa = Doa{false, angle_difference(rx.axis_rad, 0), h / std::sqrt(3.0), 0, 1};
    fit.chi2 = 0;
    fit.dof = -1;
    return;
  }
  // Grid, then every local minimum within one unit of chi^2 of the best
  // competes on facing.
  std::vector<double> c(kGrid);
  for (int k = 0; k < kGrid; ++k)
    c[static_cast<std::size_t>(k)] = p.cost(2 * kPi * k / kGrid);
  double best_cost = INFINITY;
  for (const double v : c)
    best_cost = std::min(best_cost, v);
  double beta = 0;
  double best_facing = -INFINITY;
  double chosen_cost = INFINITY;
  for (int k = 0; k < kGrid; ++k) {
    const double prev = c[static_cast<std::size_t>((k + kGrid - 1) % kGrid)];
    const double next = c[static_cast<std::size_t>((k + 1) % kGrid)];
    const double here = c[static_cast<std::size_t>(k)];
    if (here > prev || here > next)
      continue;
    const double b = refine(p, 2 * kPi * (k - 1) / kGrid, 2 * kPi * (k + 1) / kGrid);
    const double cb = p.cost(b);
    if (cb > best_cost + 1.0)
      continue;
    const double f = p.facing(b);
    if (f > best_facing + 1e-12 || (std::abs(f - best_facing) <= 1e-12 && cb < chosen_cost)) {
      best_facing = f, beta = b, chosen_cost = cb;
    }
  }
  double t0 = 0;
  const double ss = p.cost(beta, &t0);
  // Fisher information in beta with t0 profiled: centred derivatives.
  const double cx = std::cos(beta), sy = std::sin(beta);
  std::vector<double> g(n);
  double g_mean = 0;
  for (std::size_t i = 0; i < n; ++i) {
    g[i] = -p.r[i].x * sy + p.r[i].y * cx;  // d(tau_i)/d beta
    g_mean += p.w[i] * g[i];
  }
  g_mean /= p.sum_w;
  double info = 0;
  for (std::size_t i = 0; i < n; ++i)
    info += p.w[i] * (g[i] - g_mean) * (g[i] - g_mean);
  const int dof = static_cast<int>(n) - 2;
  const double scale = dof > 0 ? std::max(1.0, ss / dof) : 1.0;
  const double var_beta = info > 0 ? scale / info : INFINITY;
  fit.t0_s = t0;
  fit.t0_sd_s = std::sqrt(scale / p.sum_w + g_mean * g_mean * var_beta);
  fit.chi2 = ss;
  fit.dof = dof;
  double rss = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double res = p.t[i] - (t0 - p.r[i].x * cx - p.r[i].y * sy);
    fit.hits[index[i]].residual_s = res;
    rss += res * res;
  }
  for (std::size_t i = 0; i < hits.size(); ++i) {
    if (fit.hits[i].used)
      continue;
    const Receiver& rx = array.receivers[static_cast<std::size_t>(hits[i].channel)];
    fit.hits[i].residual_s = hits[i].time_s - (t0 - (rx.position_m.x * cx + rx.position_m.y * sy) /
                                                        o.speed_of_sound_mps);
  }
  fit.doa = Doa{std::isfinite(var_beta), angle_difference(beta, 0), std::sqrt(var_beta),
                std::sqrt(rss / static_cast<double>(n)), static_cast<int>(n)};
  if (dof >= 1) {
    fit.inconsistent = ss > chi2_limit(dof);
  } else {
    // Two receivers: |t_i - t_j| may not exceed |r_i - r_j|/c (3 sigma slack).
    const double dt = std::abs(p.t[0] - p.t[1]);
    const double dr = std::hypot(p.r[0].x - p.r[1].x, p.r[0].y - p.r[1].y);
    fit.inconsistent = dt > dr + 3 * std::sqrt(1 / p.w[0] + 1 / p.w[1]);
  }
}

}  // namespace

double angle_difference(double a, double b) {
  double d = std::remainder(a - b, 2 * kPi);
  if (d <= -kPi)
    d += 2 * kPi;
  return d;
}

PlaneWaveFit fit_plane_wave(const ReceiverArray& array, std::span<const TimedHit> hits,
                            const PlaneWaveOptions& options) {
  if (!(std::isfinite(options.speed_of_sound_mps) && options.speed_of_sound_mps > 0))
    throw std::invalid_argument("fit_plane_wave: speed of sound must be finite and positive");
  for (const TimedHit& h : hits) {
    if (h.channel < 0 || static_cast<std::size_t>(h.channel) >= array.receivers.size())
      throw std::invalid_argument("fit_plane_wave: channel " + std::to_string(h.channel) +
                                  " is not in the receiver array");
    if (!std::isfinite(h.time_s) || !(std::isfinite(h.sd_s) && h.sd_s > 0))
      throw std::invalid_argument("fit_plane_wave: channel " + std::to_string(h.channel) +
                                  ": time and deviation must be finite, deviation positive");
  }
  PlaneWaveFit fit;
  fit.hits.assign(hits.size(), PlaneWaveFit::Hit{});
  if (hits.empty())
    return fit;
  fit_used(array, hits, options, fit);
  while (options.reject_outliers && fit.inconsistent && fit.dof >= 2) {
    std::size_t worst = 0;
    double worst_z = -1;
    for (std::size_t i = 0; i < hits.size(); ++i) {
      if (!fit.hits[i].used)
        continue;
      const double z = std::abs(fit.hits[i].residual_s) / hits[i].sd_s;
      if (z > worst_z)
        worst_z = z, worst = i;
    }
    fit.hits[worst].used = false;
    fit.inconsistent = false;
    fit_used(array, hits, options, fit);
  }
  return fit;
}

}  // namespace odoloc::sw::tof
