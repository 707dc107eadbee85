// Rise-time compensation and direction of arrival (soc_software tof_envelope,
// tof_doa) against independent references: the envelope's threshold
// crossings found numerically on the piecewise envelope in long double, and
// plane waves computed from receiver positions.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <stdexcept>
#include <vector>

#include "odoloc/sw/tof_doa.hpp"
#include "odoloc/sw/tof_envelope.hpp"

namespace {

using odoloc::sw::tof::EnvelopeModel;
using odoloc::sw::tof::fit_plane_wave;
using odoloc::sw::tof::PlaneWaveOptions;
using odoloc::sw::tof::ReceiverArray;
using odoloc::sw::tof::TimedHit;
using LD = long double;
constexpr double kPi = std::numbers::pi;

// The envelope of docs/tof-measurements.md, evaluated directly, and its
// threshold crossings (threshold 1, amplitude x) found by bisection.
struct NumericEnvelope {
  LD tau_r, tau_f, burst;
  [[nodiscard]] LD level(LD x, LD t) const {
    if (t <= burst)
      return x * (1 - std::exp(-t / tau_r));
    return x * (1 - std::exp(-burst / tau_r)) * std::exp(-(t - burst) / tau_f);
  }
  // First crossing of 1 in [lo, hi], rising (up) or falling.
  [[nodiscard]] LD crossing(LD x, LD lo, LD hi, bool up) const {
    for (int i = 0; i < 200; ++i) {
      const LD mid = (lo + hi) / 2;
      const bool above = level(x, mid) >= 1;
      ((above == up) ? hi : lo) = mid;
    }
    return (lo + hi) / 2;
  }
  struct Pulse {
    LD up, width;
  };
  [[nodiscard]] Pulse pulse(LD x) const {
    const LD up = crossing(x, 0, burst, true);
    const LD down = crossing(x, burst, burst + 80 * tau_f, false);
    return {up, down - up};
  }
};

TEST(TofEnvelope, InversionRecoversTheCrossingDelayOfTheNumericEnvelope) {
  const EnvelopeModel model;  // defaults: tau_r 1/3 ms, tau_f 2/3 ms, T_p 2.5 ms
  const NumericEnvelope env{1e-3L / 3, 2e-3L / 3, 2.5e-3L};
  const LD x_min = 1 / (1 - std::exp(-env.burst / env.tau_r));
  EXPECT_NEAR(model.min_ratio(), static_cast<double>(x_min), 1e-12);
  for (const LD x : {x_min * 1.0000001L, x_min * 1.0001L, 1.01L, 1.1L, 1.5L, 2.0L, 3.0L, 6.0L,
                     20.0L, 100.0L, 900.0L}) {
    const NumericEnvelope::Pulse p = env.pulse(x);
    const EnvelopeModel::Inverse inv = model.invert_width(static_cast<double>(p.width));
    EXPECT_FALSE(inv.clamped_high) << static_cast<double>(x);
    EXPECT_NEAR(inv.delay_s, static_cast<double>(p.up), 1e-12) << "x = " << static_cast<double>(x);
    EXPECT_NEAR(inv.ratio / static_cast<double>(x), 1.0, 1e-6) << static_cast<double>(x);
    // The sensitivity against a numeric derivative of the reference.
    const LD h = 1e-5L * (x - x_min);
    const NumericEnvelope::Pulse a = env.pulse(x - h), b = env.pulse(x + h);
    const LD slope = (b.up - a.up) / (b.width - a.width);
    EXPECT_NEAR(inv.ddelay_dwidth, static_cast<double>(slope), 1e-4) << static_cast<double>(x);
  }
}

TEST(TofEnvelope, InversionIsMonotoneAndClamps) {
  const EnvelopeModel model;
  double last_delay = INFINITY;
  for (double w = 1e-7; w < model.max_width_s(); w *= 1.05) {
    const auto inv = model.invert_width(w);
    ASSERT_LE(inv.delay_s, last_delay) << w;
    last_delay = inv.delay_s;
  }
  const auto longest = model.invert_width(model.max_width_s() * 1.5);
  EXPECT_TRUE(longest.clamped_high);
  EXPECT_NEAR(longest.ratio, model.max_ratio, 1e-6 * model.max_ratio);
  const auto none = model.invert_width(0.0);  // touching the threshold: crossing at the burst's end
  EXPECT_NEAR(none.delay_s, model.burst_s, 1e-9);
  EXPECT_TRUE(model.invert_width(std::nan("")).clamped_high);
}

TEST(TofEnvelope, InvalidParametersAreRejectedWithTheirName) {
  EnvelopeModel m;
  m.rise_s = std::nan("");
  try {
    m.validate();
    FAIL() << "NaN rise accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("rise_s"), std::string::npos) << e.what();
  }
  m = EnvelopeModel{};
  m.burst_s = -1;
  EXPECT_THROW(m.validate(), std::invalid_argument);
  m = EnvelopeModel{};
  m.max_ratio = 1.5;
  EXPECT_THROW(m.validate(), std::invalid_argument);
}

// ------------------------------------------------------------------- DOA

// Kleeman's octagon computed here: faces of 50 mm, receivers at the face
// centres facing outward.
std::vector<std::pair<LD, LD>> octagon_positions() {
  std::vector<std::pair<LD, LD>> p;
  const LD apothem = 0.025L / std::tan(std::numbers::pi_v<LD> / 8);
  for (int i = 0; i < 8; ++i) {
    const LD a = std::numbers::pi_v<LD> * i / 4;
    p.emplace_back(apothem * std::cos(a), apothem * std::sin(a));
  }
  return p;
}

// Arrival times at receivers `channels` of a plane wave from `bearing`
// passing the origin at t0.
std::vector<TimedHit> plane_wave(LD bearing, LD t0, LD c, const std::vector<int>& channels,
                                 double sd) {
  const auto pos = octagon_positions();
  std::vector<TimedHit> hits;
  for (const int ch : channels) {
    const auto [x, y] = pos[static_cast<std::size_t>(ch)];
    const LD t = t0 - (x * std::cos(bearing) + y * std::sin(bearing)) / c;
    hits.push_back({ch, static_cast<double>(t), sd});
  }
  return hits;
}

// The receivers facing within 67.5 degrees of the bearing (3 or 4 of them).
std::vector<int> facing(LD bearing) {
  std::vector<int> ch;
  for (int i = 0; i < 8; ++i) {
    LD d = std::remainder(bearing - std::numbers::pi_v<LD> * i / 4, 2 * std::numbers::pi_v<LD>);
    if (std::abs(d) <= 67.5L * std::numbers::pi_v<LD> / 180 + 1e-9L)
      ch.push_back(i);
  }
  return ch;
}

TEST(TofDoa, ExactPlaneWavesFromEveryDirection) {
  const ReceiverArray array = ReceiverArray::polygon(8, 0.05);
  const PlaneWaveOptions options{343.2, kPi / 4, true};
  for (int deg = -180; deg < 180; deg += 7) {
    const LD b = deg * std::numbers::pi_v<LD> / 180;
    const auto hits = plane_wave(b, 1.25L, 343.2L, facing(b), 1e-6);
    const auto fit = fit_plane_wave(array, hits, options);
    ASSERT_TRUE(fit.doa.valid) << deg;
    EXPECT_NEAR(odoloc::sw::tof::angle_difference(fit.doa.bearing_rad, static_cast<double>(b)), 0,
                1e-7)
        << deg;
    EXPECT_NEAR(fit.t0_s, 1.25, 1e-12) << deg;
    EXPECT_FALSE(fit.inconsistent);
  }
}

TEST(TofDoa, TwoReceiversPickTheMirrorSolutionTheyFace) {
  const ReceiverArray array = ReceiverArray::polygon(8, 0.05);
  const PlaneWaveOptions options{343.2, kPi / 4, true};
  for (const int ch : {0, 3, 6}) {
    // A source between receivers ch and ch+1, nearer ch.
    const LD b = std::numbers::pi_v<LD> / 4 * ch + 0.25L;
    const auto hits = plane_wave(b, 0.5L, 343.2L, {ch, (ch + 1) % 8}, 1e-6);
    const auto fit = fit_plane_wave(array, hits, options);
    ASSERT_TRUE(fit.doa.valid);
    EXPECT_NEAR(odoloc::sw::tof::angle_difference(fit.doa.bearing_rad, static_cast<double>(b)), 0,
                1e-6)
        << ch;
  }
}

TEST(TofDoa, OneWrongReceiverIsDroppedAsAnOutlier) {
  const ReceiverArray array = ReceiverArray::polygon(8, 0.05);
  const PlaneWaveOptions options{343.2, kPi / 4, true};
  const LD b = 1.0L;
  auto hits = plane_wave(b, 0.5L, 343.2L, {7, 0, 1, 2, 3}, 1e-6);
  hits[2].time_s += 60e-6;  // receiver 1 late by 60 us (20 mm)
  const auto fit = fit_plane_wave(array, hits, options);
  EXPECT_FALSE(fit.hits[2].used);
  EXPECT_NEAR(fit.doa.bearing_rad, 1.0, 1e-5);
  EXPECT_EQ(fit.doa.receivers, 4);
}

TEST(TofDoa, BadHitsThrow) {
  const ReceiverArray array = ReceiverArray::polygon(8, 0.05);
  const PlaneWaveOptions options;
  const std::vector<TimedHit> outside{{9, 0.0, 1e-6}};
  EXPECT_THROW((void)fit_plane_wave(array, outside, options), std::invalid_argument);
  const std::vector<TimedHit> nan{{1, std::nan(""), 1e-6}};
  EXPECT_THROW((void)fit_plane_wave(array, nan, options), std::invalid_argument);
  EXPECT_FALSE(fit_plane_wave(array, {}, options).doa.valid);
}

// Resolution: timing noise sigma over the array's aperture. For a plane wave
// the bearing's Fisher information is sum_i (p_i - mean p)^2 / (c sigma)^2,
// p_i = r_i . u'(beta) the receivers' spread across the wavefront. Measured
// on random bearings with the tick quantisation plus Gaussian jitter, and
// the reported deviation checked against the observed error.
struct Resolution {
  double rms_deg, theory_deg, z_rms;
};
Resolution measure_resolution(double tick_s, double jitter_s, unsigned seed) {
  const ReceiverArray array = ReceiverArray::polygon(8, 0.05);
  const PlaneWaveOptions options{343.2, kPi / 4, true};
  const auto pos = octagon_positions();
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> angle(-kPi, kPi), phase(0, 1);
  std::normal_distribution<double> gauss(0, 1);
  const double sigma = std::sqrt(tick_s * tick_s / 12 + jitter_s * jitter_s);
  double se = 0, sz = 0, st = 0;
  const int trials = 4000;
  for (int i = 0; i < trials; ++i) {
    const double b = angle(rng);
    const std::vector<int> channels = facing(b);
    auto hits = plane_wave(b, 0.01L, 343.2L, channels, sigma);
    const double start = phase(rng) * tick_s;  // the tick grid's phase
    for (auto& h : hits) {
      const double noisy = h.time_s + jitter_s * gauss(rng) + start;
      h.time_s = (std::floor(noisy / tick_s) + 0.5) * tick_s - start;  // quantised: mid-tick
    }
    const auto fit = fit_plane_wave(array, hits, options);
    const double err = odoloc::sw::tof::angle_difference(fit.doa.bearing_rad, b);
    se += err * err;
    sz += (err / fit.doa.sd_rad) * (err / fit.doa.sd_rad);
    // Theory for this geometry.
    double mean = 0, ss = 0;
    std::vector<double> p;
    for (const int ch : channels) {
      const auto [x, y] = pos[static_cast<std::size_t>(ch)];
      p.push_back(static_cast<double>(-x * std::sin(b) + y * std::cos(b)));
      mean += p.back();
    }
    mean /= static_cast<double>(p.size());
    for (const double v : p)
      ss += (v - mean) * (v - mean);
    st += sigma * sigma * 343.2 * 343.2 / ss;
  }
  return {std::sqrt(se / trials) * 180 / kPi, std::sqrt(st / trials) * 180 / kPi,
          std::sqrt(sz / trials)};
}

TEST(TofDoa, ResolutionMatchesTheQuantisationOverTheAperture) {
  // Kleeman's 2.5 us tick (prescale 124), no other noise.
  const Resolution kleeman = measure_resolution(2.5e-6, 0, 11);
  // 20 ns ticks with 1 us of jitter (turbulence, threshold noise).
  const Resolution fine = measure_resolution(20e-9, 1e-6, 12);
  std::printf("DOA resolution, 2.5 us ticks: rms %.3f deg (theory %.3f deg), z rms %.2f\n",
              kleeman.rms_deg, kleeman.theory_deg, kleeman.z_rms);
  std::printf(
      "DOA resolution, 20 ns ticks + 1 us jitter: rms %.3f deg (theory %.3f deg), z rms %.2f\n",
      fine.rms_deg, fine.theory_deg, fine.z_rms);
  EXPECT_NEAR(kleeman.rms_deg / kleeman.theory_deg, 1.0, 0.25);
  EXPECT_NEAR(fine.rms_deg / fine.theory_deg, 1.0, 0.25);
  EXPECT_LT(kleeman.rms_deg, 0.5);  // against the paper's 45-degree sectors
  EXPECT_GT(kleeman.z_rms, 0.6);    // the reported deviation is honest
  EXPECT_LT(kleeman.z_rms, 1.6);
  EXPECT_GT(fine.z_rms, 0.6);
  EXPECT_LT(fine.z_rms, 1.6);
}

}  // namespace
