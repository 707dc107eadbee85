// Liu's scanning-laser + ultrasonic base station, the world side; the model
// and its reading of the paper in docs/acoustic-world.md.
#include "odoloc/world/base_station.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>

namespace odoloc::world {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kTwoPi = 2 * kPi;
// The hit search's grid: the station laser turns 2 width / period (1.3 rad/s
// for Liu's half turn in 2.5 s), 1.3 mrad a sample, so a target's bearing
// never crosses the laser twice between samples away from the turnarounds
// (which are samples themselves).
constexpr double kSampleS = 1e-3;
constexpr double kBisectS = 1e-9;  // 1.3 nrad of laser travel: far below a count
// An angle this many steps below an edge counts as on it (count()).
constexpr double kEdgeSlack = 1e-9;

void require(bool ok, const std::string& what) {
  if (!ok)
    throw std::invalid_argument("plan_base_station: " + what);
}

// Wrapped to (-pi, pi].
double wrap(double a) {
  double r = std::remainder(a, kTwoPi);
  if (r <= -kPi)
    r += kTwoPi;
  return r;
}

// Where the sweep is at time_s: 0 at its start, 1 at its far end.
double sweep_fraction(const ScanningLaser& laser, double time_s) {
  double u = std::fmod(time_s + laser.phase_s, laser.period_s);
  if (u < 0)
    u += laser.period_s;
  const double half = laser.period_s / 2;
  return u < half ? u / half : (laser.period_s - u) / half;
}

void check_laser(const ScanningLaser& l, const char* which) {
  const std::string w = which;
  require(std::isfinite(l.sweep_start_rad) && std::isfinite(l.phase_s),
          w + ": non-finite angle or phase");
  require(l.sweep_width_rad > 0 && l.sweep_width_rad <= kTwoPi,
          w + ": sweep width outside (0, 2 pi]");
  require(l.period_s > 0 && std::isfinite(l.period_s), w + ": period must be positive and finite");
  require(l.counts_per_rev > 0, w + ": no encoder counts");
}

struct Hit {
  StationReportKind kind;
  double hit_s;
};

// Every time in [0, end_s] at which laser.angle_rad(t) crosses bearing(t):
// f = wrap(angle - bearing) changes sign between two samples of the grid
// (plus the turnarounds, where the angle turns back), both |f| < pi/2 (not
// the jump of the wrap at +-pi), refined by bisection.
std::vector<double> crossings(const ScanningLaser& laser,
                              const std::function<double(double)>& bearing, double end_s) {
  const auto f = [&](double t) { return wrap(laser.angle_rad(t) - bearing(t)); };
  std::vector<double> out;
  double a = 0;
  double fa = f(a);
  const auto interval_to = [&](double b) {
    const double fb = f(b);
    // fb == 0 ends this interval's crossing; the next interval then starts
    // at 0 and does not count it again.
    const bool sign_change = (fa < 0 && fb >= 0) || (fa > 0 && fb <= 0);
    if (sign_change && std::abs(fa) < kPi / 2 && std::abs(fb) < kPi / 2) {
      double lo = a;
      double hi = b;
      while (hi - lo > kBisectS) {
        const double mid = 0.5 * (lo + hi);
        const double fm = f(mid);
        if (fm != 0 && (fm < 0) == (fa < 0))
          lo = mid;
        else
          hi = mid;
      }
      out.push_back(0.5 * (lo + hi));
    }
    a = b;
    fa = fb;
  };
  // The grid's samples, end_s, and the turnarounds (at -phase + k period / 2)
  // between them, in time order, generated as they go (an hour's run is
  // 3.6 M samples).
  const double half = laser.period_s / 2;
  double turn = std::ceil(laser.phase_s / half);  // the next turnaround's k
  const auto grid = static_cast<std::size_t>(std::floor(end_s / kSampleS));
  for (std::size_t j = 1;; ++j) {
    const double g = j <= grid ? static_cast<double>(j) * kSampleS : end_s;
    for (; turn * half - laser.phase_s < g; ++turn)
      if (turn * half - laser.phase_s > a)
        interval_to(turn * half - laser.phase_s);
    if (g > a)
      interval_to(g);
    if (j > grid)
      break;
  }
  return out;
}

}  // namespace

double ScanningLaser::step_rad() const {
  return kTwoPi / static_cast<double>(counts_per_rev);
}

double ScanningLaser::angle_rad(double time_s) const {
  return sweep_start_rad + sweep_width_rad * sweep_fraction(*this, time_s);
}

std::uint32_t ScanningLaser::count(double time_s) const {
  // From the sweep's fraction, not angle - start: no rounding of the start.
  // The fraction is in [0, 1], so the count in [0, floor(width / step)].
  const double steps = sweep_width_rad / step_rad();
  return static_cast<std::uint32_t>(std::floor(sweep_fraction(*this, time_s) * steps + kEdgeSlack));
}

StationPlan plan_base_station(const BaseStation& station, const AcousticWorld& world,
                              const KleemanTiming& timing, const Trajectory& robot,
                              double first_burst_s, double end_s) {
  require(std::isfinite(station.position.x_m) && std::isfinite(station.position.y_m),
          "non-finite station position");
  require(station.transmitter < world.beacons.size(), "transmitter not in the world's beacons");
  const Beacon& tx = world.beacons[station.transmitter];
  require(!tx.mount, "the transmitter must be fixed in the world");
  require(std::hypot(tx.position.x_m - station.position.x_m,
                     tx.position.y_m - station.position.y_m) <= 1e-3,
          "the transmitter is not at the station");
  const double t0 = tx.electronics_delay_s;
  require(t0 >= 0 && std::isfinite(t0), "transmitter delay must be finite and >= 0");
  check_laser(station.station_laser, "station laser");
  check_laser(station.robot_laser, "robot laser");
  require(station.rf_pulse_s > 0 && std::isfinite(station.rf_spacing_s) &&
              station.rf_spacing_s > station.rf_pulse_s,
          "RF pulses must be positive and spaced wider than they last");
  require(station.request_margin_s >= 0 && std::isfinite(station.request_margin_s),
          "request margin must be finite and >= 0");
  require(timing.reserved_slots > 0, "the timing has no reserved slot");
  const double fire = timing.fire_s();
  const double cycle = timing.cycle_s();
  require(fire > 0 && std::isfinite(cycle), "the timing's slots must be positive and finite");
  require(station.pulse_s > 0 && station.pulse_s <= fire, "the burst does not fit in a slot");
  require(std::isfinite(first_burst_s) && std::isfinite(end_s) && end_s >= 0,
          "first burst and end must be finite, end >= 0");
  require(static_cast<bool>(robot), "no robot trajectory");

  const Vec2 s = station.position;
  const auto alpha = [&](double t) {
    const Pose p = robot(t);
    return std::atan2(p.y_m - s.y_m, p.x_m - s.x_m);
  };
  const auto beta = [&](double t) {
    const Pose p = robot(t);
    return wrap(std::atan2(s.y_m - p.y_m, s.x_m - p.x_m) - p.theta_rad);
  };

  std::vector<Hit> hits;
  for (const double t : crossings(station.station_laser, alpha, end_s))
    hits.push_back({StationReportKind::kStationSawRobot, t});
  for (const double t : crossings(station.robot_laser, beta, end_s))
    hits.push_back({StationReportKind::kRobotSawStation, t});
  std::sort(hits.begin(), hits.end(), [](const Hit& a, const Hit& b) { return a.hit_s < b.hit_s; });

  // The first reserved slot of cycle k starts N t_fire after the cycle's
  // start, computed as kleeman_schedule computes its slots (same grid).
  const auto slot_start = [&](std::size_t k) {
    const double cycle_start = first_burst_s + static_cast<double>(k) * cycle;
    return cycle_start + static_cast<double>(timing.beacon_count) * fire;
  };
  // Liu fires at once; here the burst waits for the reserved slot, whose
  // start must be t0 after the trigger, which must clear the margin.
  std::set<std::size_t> ranging_slots;
  for (const Hit& h : hits) {
    if (h.kind != StationReportKind::kStationSawRobot)
      continue;
    const double earliest = h.hit_s + station.request_margin_s;
    const double guess = std::ceil((earliest + t0 - slot_start(0)) / cycle);
    auto k = static_cast<std::size_t>(std::max(0.0, guess));
    while (k > 0 && slot_start(k - 1) - t0 >= earliest)
      --k;
    while (slot_start(k) - t0 < earliest)
      ++k;
    if (slot_start(k) - t0 <= end_s)
      ranging_slots.insert(k);
  }

  std::vector<StationReport> reports;
  std::set<double> strobes;  // every strobe placed so far
  for (const std::size_t k : ranging_slots) {
    const double start = slot_start(k);
    reports.push_back({StationReportKind::kRanging, 0, start - t0, start,
                       std::numeric_limits<double>::quiet_NaN()});
    strobes.insert(start - t0);
  }
  const double spacing = station.rf_spacing_s;
  const auto too_close = [&](double t) -> std::optional<double> {
    for (auto it = strobes.lower_bound(t - 2 * spacing);
         it != strobes.end() && *it < t + 2 * spacing; ++it)
      if (std::abs(t - *it) < spacing)
        return *it;
    return std::nullopt;
  };
  // In hit order, each at the first clear time from its hit: a later hit
  // meets every strobe an earlier one met, so the order stays the hits'.
  for (const Hit& h : hits) {
    double t = h.hit_s;
    while (const std::optional<double> other = too_close(t)) {
      double next = *other + spacing;
      while (next - *other < spacing)  // clear by the test's own subtraction
        next = std::nextafter(next, std::numeric_limits<double>::infinity());
      t = next;
    }
    if (t > end_s)
      continue;
    strobes.insert(t);
    const bool by_station = h.kind == StationReportKind::kStationSawRobot;
    const ScanningLaser& laser = by_station ? station.station_laser : station.robot_laser;
    reports.push_back(
        {h.kind, laser.count(h.hit_s), t, h.hit_s, by_station ? alpha(h.hit_s) : beta(h.hit_s)});
  }
  std::stable_sort(
      reports.begin(), reports.end(),
      [](const StationReport& a, const StationReport& b) { return a.strobe_s < b.strobe_s; });

  StationPlan plan;
  for (const StationReport& r : reports) {
    plan.schedule.sync.push_back({station.transmitter, r.strobe_s, station.rf_pulse_s});
    if (r.kind == StationReportKind::kRanging)
      plan.schedule.emissions.push_back({station.transmitter, r.strobe_s, station.pulse_s});
  }
  plan.reports = std::move(reports);
  return plan;
}

}  // namespace odoloc::world
