// Ground-truth tricycle simulator. Equations and error budget:
// docs/tricycle-simulator.md.
#include "odoloc/world/tricycle.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <stdexcept>
#include <utility>

namespace odoloc::world {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kForever = std::numeric_limits<double>::infinity();

void require(bool ok, const char* what) {
  if (!ok)
    throw std::invalid_argument(what);
}

bool is_wheel(Wheel w) {
  return index(w) < kWheelCount;
}

// sin(x)/x without the 0/0.
double sinc(double x) {
  return x == 0 ? 1.0 : std::sin(x) / x;
}

// Means of tan(phi) and sec(phi) over a steering ramp from a to b, from the
// closed forms int tan = -ln cos and int sec = atanh(sin), rearranged so that
// a short ramp does not cancel: cos a - cos b = 2 sin(m) sin(d) and
// sin b - sin a = 2 cos(m) sin(d), with m the mid angle and d the half ramp.
double mean_tan(double a, double b) {
  if (a == b)
    return std::tan(a);
  const double m = (a + b) / 2;
  const double d = (b - a) / 2;
  return std::log1p(2 * std::sin(m) * std::sin(d) / std::cos(b)) / (b - a);
}
double mean_sec(double a, double b) {
  if (a == b)
    return 1 / std::cos(a);
  const double m = (a + b) / 2;
  const double d = (b - a) / 2;
  return std::atanh(2 * std::cos(m) * std::sin(d) / (1 - std::sin(a) * std::sin(b))) / (b - a);
}

// Three-point Gauss-Legendre rule on [0, 1]: exact for degree-5 polynomials.
struct GaussNode {
  double at;
  double weight;
};
constexpr double kGaussOffset = 0.38729833462074168852;  // sqrt(15) / 10
constexpr std::array<GaussNode, 3> kGauss3 = {{
    {0.5 - kGaussOffset, 5.0 / 18},
    {0.5, 8.0 / 18},
    {0.5 + kGaussOffset, 5.0 / 18},
}};

// Arc length minus horizontal length of the raised-cosine profile over
// [0, u]. With slope amplitude a = pi h / l and k^2 = a^2 / (1 + a^2):
//   int_0^u sqrt(1 + a^2 sin^2(2 pi v / l)) dv
//     = l / (2 pi) sqrt(1 + a^2) [E(pi/2 | k) - E(pi/2 - 2 pi u / l | k)].
double profile_extra(const Bump& bump, double u) {
  const double l = bump.length_m;
  u = std::clamp(u, 0.0, l);
  const double a = kPi * bump.height_m / l;
  const double scale = std::sqrt(1 + a * a);
  const double k = a / scale;
  const double arc =
      l / (2 * kPi) * scale * (std::comp_ellint_2(k) - std::ellint_2(k, kPi / 2 - 2 * kPi * u / l));
  return arc - u;
}

void validate(const WheelEncoder& w) {
  require(w.nominal_radius_m > 0 && w.true_radius_m > 0, "wheel radius must be positive");
  require(w.lines > 0 && w.gear > 0, "encoder lines and gear must be positive");
}

void validate(const Geometry& g) {
  require(g.track_m > 0 && g.wheelbase_m > 0, "track and wheelbase must be positive");
  validate(g.left_rear);
  validate(g.right_rear);
  validate(g.front);
  require(g.steering.lines > 0 && g.steering.gear > 0,
          "steering encoder lines and gear must be positive");
  require(g.steering.limit_rad > 0 && g.steering.limit_rad < kPi / 2,
          "steering limit must be in (0, 90) degrees");
}

void validate(const Path& path, const Geometry& g) {
  require(path.steer_rate_radps > 0, "steering rate limit must be positive");
  for (const Segment& s : path.segments) {
    require(std::isfinite(s.speed_mps) && std::isfinite(s.amount) && s.amount >= 0,
            "segment speed must be finite and its amount finite and non-negative");
    require(std::abs(s.steer_rad) <= g.steering.limit_rad, "segment steers beyond the limit");
    require(s.end != Segment::End::kDistance || s.amount == 0 || s.speed_mps != 0,
            "a distance segment needs a speed");
  }
}

void validate(const Disturbances& d, const Geometry& g) {
  for (const Bump& b : d.bumps) {
    require(is_wheel(b.wheel), "a bump needs a rolling wheel");
    require(b.height_m > 0 && b.length_m > 0, "bump height and length must be positive");
    // The feet of the profile are concave with radius l^2 / (2 pi^2 h); a
    // wheel larger than that bridges them and stops following the profile.
    const double foot_radius = b.length_m * b.length_m / (2 * kPi * kPi * b.height_m);
    require(g.wheel(b.wheel).true_radius_m <= foot_radius,
            "bump too sharp for the wheel: needs l^2 >= 2 pi^2 h R");
  }
  for (const Slip& s : d.slips) {
    require(is_wheel(s.wheel), "slip needs a rolling wheel");
    require(s.start_m <= s.end_m && s.ratio > -1, "slip needs start <= end and ratio > -1");
  }
}

}  // namespace

const WheelEncoder& Geometry::wheel(Wheel w) const {
  switch (w) {
    case Wheel::kLeftRear:
      return left_rear;
    case Wheel::kRightRear:
      return right_rear;
    case Wheel::kFront:
      return front;
  }
  throw std::invalid_argument("no such wheel");
}

Path straight_path(double distance_m, double speed_mps) {
  return {{Segment::distance(speed_mps, 0, distance_m)}};
}

Path square_path(const Geometry& geometry, double side_m, double speed_mps, double steer_rad) {
  require(steer_rad != 0, "square_path: the corners need a steering angle");
  const double radius = geometry.wheelbase_m / std::tan(std::abs(steer_rad));
  const double straight = side_m - 2 * radius;
  require(straight >= 0, "square_path: the turn radius exceeds half the side");
  Path path;
  for (int side = 0; side < 4; ++side) {
    path.segments.insert(
        path.segments.end(),
        {Segment::distance(speed_mps, 0, straight), Segment::steer_to(steer_rad),
         Segment::distance(speed_mps, steer_rad, radius * kPi / 2), Segment::steer_to(0)});
  }
  return path;
}

double bump_extra_length(double height_m, double length_m) {
  const double a = kPi * height_m / length_m;
  const double scale = std::sqrt(1 + a * a);
  return 2 * length_m / kPi * scale * std::comp_ellint_2(a / scale) - length_m;
}

Disturbances bump_under_both_rear(double start_m, double height_m, double length_m) {
  return {.bumps = {{Wheel::kLeftRear, start_m, height_m, length_m},
                    {Wheel::kRightRear, start_m, height_m, length_m}},
          .slips = {}};
}
Disturbances bump_under_one_rear(Wheel rear, double start_m, double height_m, double length_m) {
  require(rear == Wheel::kLeftRear || rear == Wheel::kRightRear, "not a rear wheel");
  return {.bumps = {{rear, start_m, height_m, length_m}}, .slips = {}};
}
Disturbances bump_under_front(double start_m, double height_m, double length_m) {
  return {.bumps = {{Wheel::kFront, start_m, height_m, length_m}}, .slips = {}};
}

TricycleSimulator::TricycleSimulator(Geometry geometry, Path path, Disturbances disturbances,
                                     Options options)
    : geometry_(geometry), path_(std::move(path)), options_(options) {
  validate(geometry_);
  validate(path_, geometry_);
  validate(disturbances, geometry_);
  require(options_.clock_hz > 0 && options_.clocks_per_step > 0,
          "clock rate and clocks per step must be positive");
  step_s_ = options_.clocks_per_step / options_.clock_hz;
  for (const Wheel w : {Wheel::kLeftRear, Wheel::kRightRear, Wheel::kFront})
    edges_per_metre_[index(w)] = geometry_.wheel(w).true_edges_per_metre();
  for (const Bump& b : disturbances.bumps) {
    bumps_.push_back({.bump = b});
    boundaries_.push_back(b.start_m);
  }
  slips_ = std::move(disturbances.slips);
  for (const Slip& s : slips_)
    boundaries_.insert(boundaries_.end(), {s.start_m, s.end_m});
  std::sort(boundaries_.begin(), boundaries_.end());
  state_.pose = options_.start;
  step_start_ = state_;
  if (options_.record_every_steps != 0)
    trajectory_.push_back({.truth = {.pose = options_.start}});
}

TruePose TricycleSimulator::pose() const {
  State s = state_;
  if (clock_in_step_ != 0) {
    s = step_start_;
    drive(s, clock_in_step_ / options_.clock_hz, [](double, const Travel&) {});
  }
  return {s.pose, s.steer_rad, s.odometer_m, static_cast<double>(clock_) / options_.clock_hz};
}

// Integrates one step, then sets each source's rate so that its phase lands on
// the exact encoder position at the end of the step (to 2^-30 edge times half
// the clocks per step); the residual carries into the next step, so rounding
// never accumulates.
void TricycleSimulator::begin_step() {
  const bool was_driving = state_.segment < path_.segments.size();
  step_start_ = state_;
  drive(state_, step_s_, [this](double odometer, const Travel& ground) { roll(odometer, ground); });
  exact_edges_[index(Encoder::kSteering)] = state_.steer_rad * geometry_.steering.edges_per_rad();

  constexpr int kBits = QuadratureSource::kFractionBits;
  const auto clocks = static_cast<std::int64_t>(options_.clocks_per_step);
  for (std::size_t e = 0; e < kEncoderCount; ++e) {
    const std::int64_t target = std::llround(std::ldexp(exact_edges_[e], kBits));
    const std::int64_t increment =
        std::llround(static_cast<double>(target - phase_[e]) / static_cast<double>(clocks));
    if (std::abs(increment) > (std::int64_t{1} << kBits))
      throw std::range_error("TricycleSimulator: an encoder needs more than one edge per clock");
    sources_[e].set_rate(std::ldexp(static_cast<double>(increment), -kBits));
    phase_[e] += increment * clocks;
  }

  ++steps_;
  const bool finished_now = was_driving && state_.segment == path_.segments.size();
  if (options_.record_every_steps != 0 &&
      (steps_ % options_.record_every_steps == 0 || finished_now))
    record();
}

void TricycleSimulator::record() {
  const auto clocks = steps_ * options_.clocks_per_step;
  trajectory_.push_back({.truth = {state_.pose, state_.steer_rad, state_.odometer_m,
                                   static_cast<double>(clocks) / options_.clock_hz},
                         .edges = exact_edges_});
}

// Advances s by `seconds`, in sub-intervals over which the speed is constant
// and the steering is constant or ramps linearly: split where a segment ends,
// where the steering reaches its target and where the odometer crosses a
// disturbance boundary. Each sub-interval's ground travel goes to on_travel
// with the odometer at its start.
template <class OnTravel>
void TricycleSimulator::drive(State& s, double seconds, OnTravel&& on_travel) const {
  double left = seconds;
  while (left > 0) {
    const bool driving = s.segment < path_.segments.size();
    const Segment seg = driving ? path_.segments[s.segment] : Segment::steer_to(s.steer_rad);
    const double speed = std::abs(seg.speed_mps);

    // h is the first of the limits; each limit hit is detected by equality.
    double h = left;
    const double steer_gap = seg.steer_rad - s.steer_rad;
    const double steer_time =
        steer_gap != 0 ? std::abs(steer_gap) / path_.steer_rate_radps : kForever;
    h = std::min(h, steer_time);
    double end_time = kForever;
    if (driving) {
      switch (seg.end) {
        case Segment::End::kDistance:
          end_time = std::max(seg.amount - s.segment_distance_m, 0.0);
          end_time = end_time > 0 ? end_time / speed : 0.0;
          break;
        case Segment::End::kDuration:
          end_time = std::max(seg.amount - s.segment_time_s, 0.0);
          break;
        case Segment::End::kSteered:
          end_time = steer_gap == 0 ? 0.0 : kForever;
          break;
      }
    }
    h = std::min(h, end_time);
    const double boundary_time = speed > 0 && s.next_boundary < boundaries_.size()
                                     ? (boundaries_[s.next_boundary] - s.odometer_m) / speed
                                     : kForever;
    h = std::min(h, boundary_time);

    double steer_end = s.steer_rad;
    if (steer_gap != 0) {
      steer_end = h == steer_time
                      ? seg.steer_rad
                      : s.steer_rad + std::copysign(path_.steer_rate_radps * h, steer_gap);
    }
    const double odometer = s.odometer_m;
    on_travel(odometer, move(s, seg.speed_mps, steer_end, h));

    s.odometer_m = h == boundary_time ? boundaries_[s.next_boundary] : odometer + speed * h;
    while (s.next_boundary < boundaries_.size() && boundaries_[s.next_boundary] <= s.odometer_m)
      ++s.next_boundary;
    if (driving) {
      s.segment_time_s += h;
      s.segment_distance_m += speed * h;
      if (h == end_time || (seg.end == Segment::End::kSteered && s.steer_rad == seg.steer_rad)) {
        ++s.segment;
        s.segment_time_s = s.segment_distance_m = 0;
      }
    }
    left -= h;
  }
}

// One sub-interval of h seconds at rear-midpoint speed v, the steering going
// linearly from s.steer_rad to steer_end (no lateral slip):
//   theta' = v tan(phi) / L,  x' = v cos(theta),  y' = v sin(theta),
//   left/right rear wheel: v -/+ theta' D / 2,  front wheel: v / cos(phi).
// Constant steering: an exact arc. Ramping steering: heading and front-wheel
// distance in closed form, position by Gauss-Legendre on the exact heading.
TricycleSimulator::Travel TricycleSimulator::move(State& s, double v, double steer_end,
                                                  double h) const {
  const double wheelbase = geometry_.wheelbase_m;
  const double steer = s.steer_rad;
  const double ds = v * h;
  const double tan_mean = mean_tan(steer, steer_end);
  const double dtheta = ds * tan_mean / wheelbase;
  Pose& p = s.pose;
  if (steer_end == steer) {
    // The chord of the arc: length ds sinc(dtheta/2), along the mid heading.
    const double chord = ds * sinc(dtheta / 2);
    const double mid = p.theta_rad + dtheta / 2;
    p.x_m += chord * std::cos(mid);
    p.y_m += chord * std::sin(mid);
  } else {
    double cos_sum = 0;
    double sin_sum = 0;
    for (const GaussNode& node : kGauss3) {
      const double steer_at = steer + node.at * (steer_end - steer);
      const double theta = p.theta_rad + node.at * ds * mean_tan(steer, steer_at) / wheelbase;
      cos_sum += node.weight * std::cos(theta);
      sin_sum += node.weight * std::sin(theta);
    }
    p.x_m += ds * cos_sum;
    p.y_m += ds * sin_sum;
  }
  p.theta_rad += dtheta;
  s.steer_rad = steer_end;
  const double half_track = geometry_.track_m / 2;
  return {ds - dtheta * half_track, ds + dtheta * half_track, ds * mean_sec(steer, steer_end)};
}

// Turns ground travel into rolled distance (bumps, then slip) and encoder
// position.
void TricycleSimulator::roll(double odometer_m, const Travel& ground) {
  Travel rolled = ground;
  for (BumpTrack& track : bumps_) {
    const std::size_t w = index(track.bump.wheel);
    const double ds = ground[w];
    if (!track.met) {
      if (odometer_m < track.bump.start_m || ds == 0)
        continue;
      track.met = true;
      track.direction = ds > 0 ? 1.0 : -1.0;
    }
    // The bump is fixed on the ground: u follows the wheel both ways.
    const double u0 = track.position_m;
    const double u1 = u0 + track.direction * ds;
    track.position_m = u1;
    const double l = track.bump.length_m;
    if ((u0 <= 0 && u1 <= 0) || (u0 >= l && u1 >= l))
      continue;
    rolled[w] += track.direction * (profile_extra(track.bump, u1) - profile_extra(track.bump, u0));
  }
  for (const Slip& slip : slips_) {
    if (odometer_m >= slip.start_m && odometer_m < slip.end_m)
      rolled[index(slip.wheel)] *= 1 + slip.ratio;
  }
  for (const Wheel w : {Wheel::kLeftRear, Wheel::kRightRear, Wheel::kFront})
    exact_edges_[index(encoder(w))] += rolled[index(w)] * edges_per_metre_[index(w)];
}

}  // namespace odoloc::world
