// The acoustic world: propagation, amplitudes, threshold crossings,
// comparator outputs and their pins. Model and sources:
// docs/acoustic-world.md.
#include "odoloc/world/acoustics.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>

#include "odoloc/world/random.hpp"

namespace odoloc::world {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kInfinity = std::numeric_limits<double>::infinity();

void require(bool ok, const std::string& what) {
  if (!ok)
    throw std::invalid_argument("acoustic world: " + what);
}

Vec2 operator+(Vec2 a, Vec2 b) {
  return {a.x_m + b.x_m, a.y_m + b.y_m};
}
Vec2 operator-(Vec2 a, Vec2 b) {
  return {a.x_m - b.x_m, a.y_m - b.y_m};
}
Vec2 operator*(double s, Vec2 v) {
  return {s * v.x_m, s * v.y_m};
}
double dot(Vec2 a, Vec2 b) {
  return a.x_m * b.x_m + a.y_m * b.y_m;
}
double cross(Vec2 a, Vec2 b) {
  return a.x_m * b.y_m - a.y_m * b.x_m;
}
Vec2 unit(double angle_rad) {
  return {std::cos(angle_rad), std::sin(angle_rad)};
}
// Path length between two points of the plane whose heights differ by h.
double distance(Vec2 a, Vec2 b, double h) {
  return std::hypot(b.x_m - a.x_m, b.y_m - a.y_m, h);
}

// Mirror images in the room's walls.
Vec2 mirror(const Room& room, Wall wall, Vec2 p) {
  switch (wall) {
    case Wall::kXMin:
      return {-p.x_m, p.y_m};
    case Wall::kXMax:
      return {2 * room.width_m - p.x_m, p.y_m};
    case Wall::kYMin:
      return {p.x_m, -p.y_m};
    case Wall::kYMax:
      return {p.x_m, 2 * room.depth_m - p.y_m};
  }
  throw std::invalid_argument("acoustic world: not a wall");
}
double mirror_angle(Wall wall, double angle_rad) {
  return wall == Wall::kXMin || wall == Wall::kXMax ? kPi - angle_rad : -angle_rad;
}

// Where the ray from an image source to the receiver meets its wall, if the
// meeting point lies on the wall.
std::optional<Vec2> reflection_point(const Room& room, Wall wall, Vec2 image, Vec2 receiver) {
  const bool x_wall = wall == Wall::kXMin || wall == Wall::kXMax;
  const double plane = wall == Wall::kXMax   ? room.width_m
                       : wall == Wall::kYMax ? room.depth_m
                                             : 0.0;
  const double from = x_wall ? image.x_m : image.y_m;
  const double to = x_wall ? receiver.x_m : receiver.y_m;
  if ((from - plane) * (to - plane) > 0 || from == to)
    return std::nullopt;  // the receiver is behind the wall
  const Vec2 p = image + ((plane - from) / (to - from)) * (receiver - image);
  const double along = x_wall ? p.y_m : p.x_m;
  const double extent = x_wall ? room.depth_m : room.width_m;
  if (along < 0 || along > extent)
    return std::nullopt;
  return p;
}

// Distance from point p to segment a-b.
double point_segment_distance(Vec2 p, Vec2 a, Vec2 b) {
  const Vec2 ab = b - a;
  const double length2 = dot(ab, ab);
  const double s = length2 > 0 ? std::clamp(dot(p - a, ab) / length2, 0.0, 1.0) : 0.0;
  const Vec2 d = p - (a + s * ab);
  return std::hypot(d.x_m, d.y_m);
}
bool segments_intersect(Vec2 p, Vec2 q, Vec2 a, Vec2 b) {
  const double d1 = cross(q - p, a - p);
  const double d2 = cross(q - p, b - p);
  const double d3 = cross(b - a, p - a);
  const double d4 = cross(b - a, q - a);
  return ((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0));
}
// The ray p-q passes within the obstacle's radius of its segment.
bool blocks(const Obstacle& o, Vec2 p, Vec2 q) {
  if (segments_intersect(p, q, o.a, o.b))
    return true;
  const double d =
      std::min({point_segment_distance(p, o.a, o.b), point_segment_distance(q, o.a, o.b),
                point_segment_distance(o.a, p, q), point_segment_distance(o.b, p, q)});
  return d <= o.radius_m;
}
bool occluded(const std::vector<Obstacle>& obstacles, Vec2 p, Vec2 q) {
  return std::any_of(obstacles.begin(), obstacles.end(),
                     [&](const Obstacle& o) { return blocks(o, p, q); });
}

// Baffled circular piston: 2 J1(x)/x, x = ka sin(theta); nothing behind the
// baffle (cos theta <= 0). Signed: the side lobes invert the carrier.
double piston(double ka, double cos_theta) {
  if (cos_theta <= 0)
    return 0;
  const double x = ka * std::sqrt(std::max(0.0, 1 - cos_theta * cos_theta));
  if (x < 1e-6)
    return 1 - x * x / 8;
  return 2 * std::cyl_bessel_j(1.0, x) / x;
}

// Relative amplitude of a carrier f at a resonance f0 of quality Q.
double resonance(double f, double f0, double q) {
  const double detune = q * (f / f0 - f0 / f);
  return 1 / std::sqrt(1 + detune * detune);
}

// The arrival time of a wavefront that leaves `source` at t_emit at the body
// point `body` of the robot: t = t_emit + |p(t) - source| / c. Fixed-point
// iteration, a contraction with factor |v|/c (0.003 at 1 m/s).
double solve_arrival(Vec2 source, double t_emit, Vec2 body, const Trajectory& robot, double c,
                     double h) {
  double t = t_emit;
  for (int i = 0; i < 64; ++i) {
    const double next = t_emit + distance(source, to_world(robot(t), body), h) / c;
    if (std::abs(next - t) <= 1e-13 + 4 * std::numeric_limits<double>::epsilon() * std::abs(t))
      return next;
    t = next;
  }
  throw std::runtime_error("acoustic world: no arrival (a receiver near the speed of sound?)");
}

// A transmitter or its image in a wall at one time: position and the world
// axes of its transducers.
struct Source {
  Vec2 position;
  double heading = 0;  // added to the beacon's axes (mount heading)
  std::optional<Wall> wall;
};
Source source_at(const Beacon& b, const std::optional<Wall>& wall, const Room* room, double t) {
  Source s;
  if (b.mount) {
    const Pose pose = b.mount(t);
    s.position = to_world(pose, b.position);
    s.heading = pose.theta_rad;
  } else {
    s.position = b.position;
  }
  if (wall) {
    s.position = mirror(*room, *wall, s.position);
    s.wall = wall;
  }
  return s;
}
double transducer_axis(const Source& s, double axis_rad) {
  const double world = s.heading + axis_rad;
  return s.wall ? mirror_angle(*s.wall, world) : world;
}

// One arrival's contribution to its channel's comparators.
struct Contribution {
  Pulse above;                     // envelope above threshold
  std::vector<Pulse> half_cycles;  // positive carrier half-cycles begun inside `above`
};

std::vector<Pulse> union_of(std::vector<Pulse> pulses) {
  std::sort(pulses.begin(), pulses.end(),
            [](const Pulse& a, const Pulse& b) { return a.rise_s < b.rise_s; });
  std::vector<Pulse> out;
  for (const Pulse& p : pulses) {
    if (!(p.fall_s > p.rise_s))
      continue;
    if (!out.empty() && p.rise_s <= out.back().fall_s)
      out.back().fall_s = std::max(out.back().fall_s, p.fall_s);
    else
      out.push_back(p);
  }
  return out;
}

// The carrier comparator: at each instant it belongs to the arrival that rose
// first among those above threshold; arrival i owns [max(rise_i, M_i), fall_i)
// with M_i the latest fall of the arrivals that rose before it.
std::vector<Pulse> carrier_output(std::vector<Contribution>& contributions) {
  std::stable_sort(
      contributions.begin(), contributions.end(),
      [](const Contribution& a, const Contribution& b) { return a.above.rise_s < b.above.rise_s; });
  std::vector<Pulse> kept;
  double latest_fall = -kInfinity;
  for (const Contribution& c : contributions) {
    const double begin = std::max(c.above.rise_s, latest_fall);
    for (const Pulse& h : c.half_cycles)
      if (h.rise_s >= begin && h.rise_s < c.above.fall_s)
        kept.push_back(h);
    latest_fall = std::max(latest_fall, c.above.fall_s);
  }
  return union_of(std::move(kept));
}

void validate(const AcousticWorld& w, const Schedule& schedule, const Trajectory& robot,
              double end_s) {
  require(w.air.temperature_c > -273.15, "temperature below absolute zero");
  require(w.air.relative_humidity >= 0 && w.air.relative_humidity <= 1,
          "relative humidity outside [0, 1]");
  require(w.air.pressure_kpa > 0, "pressure must be positive");
  if (w.room) {
    require(w.room->width_m > 0 && w.room->depth_m > 0, "room size must be positive");
    for (const double r : w.room->reflection)
      require(r >= 0 && r <= 1, "wall reflection outside [0, 1]");
  }
  for (const Obstacle& o : w.obstacles)
    require(o.radius_m >= 0, "negative obstacle radius");
  for (const Beacon& b : w.beacons) {
    require(!b.axes_rad.empty(), "a beacon without transducer axes");
    require(b.carrier_hz > 0 && b.amplitude_1m_v >= 0 && b.piston_radius_m >= 0 &&
                b.envelope_tau_s > 0 && b.electronics_delay_s >= 0,
            "beacon parameters out of range");
  }
  for (const Receiver& r : w.receivers)
    require(r.resonance_hz > 0 && r.quality > 0 && r.piston_radius_m >= 0 && r.threshold_v > 0,
            "receiver parameters out of range");
  const AcousticNoise& n = w.noise;
  require(n.path_jitter_sd_s >= 0 && n.receiver_jitter_sd_s >= 0 && n.amplitude_sd >= 0 &&
              n.noise_rate_hz >= 0 && n.noise_min_width_s > 0 &&
              n.noise_max_width_s >= n.noise_min_width_s,
          "noise parameters out of range");
  require(w.height_m >= 0 && std::isfinite(w.height_m), "height must be finite and >= 0");
  require(std::isfinite(end_s), "end_s must be finite");
  require(w.receivers.empty() || static_cast<bool>(robot), "no robot trajectory");
  for (const Emission& e : schedule.emissions)
    require(e.beacon < w.beacons.size() && e.duration_s > 0 && std::isfinite(e.trigger_s),
            "emission of an unknown beacon or without duration");
  for (const SyncPulse& s : schedule.sync)
    require(s.beacon < w.beacons.size() && s.duration_s > 0 && std::isfinite(s.start_s),
            "sync pulse of an unknown beacon or without duration");
}

class Simulator {
 public:
  Simulator(const AcousticWorld& world, const Trajectory& robot, double end_s, std::uint64_t seed)
      : w_(world),
        robot_(robot),
        end_s_(end_s),
        seed_(seed),
        c_(world.air.speed_of_sound_mps()),
        contributions_(world.receivers.size()) {}

  AcousticRun run(const Schedule& schedule) {
    AcousticRun out;
    out.noise.resize(w_.receivers.size());
    for (std::size_t ch = 0; ch < w_.receivers.size(); ++ch)
      out.noise[ch] = noise_pulses(ch);

    std::vector<Emission> emissions;
    for (const Emission& e : schedule.emissions)
      if (e.trigger_s < end_s_)
        emissions.push_back(e);
    std::stable_sort(emissions.begin(), emissions.end(),
                     [this](const Emission& a, const Emission& b) {
                       return emission_time(a) < emission_time(b);
                     });
    Random random(seed_, 0);
    for (std::size_t i = 0; i < emissions.size(); ++i) {
      const double slot_end = i + 1 < emissions.size() ? emission_time(emissions[i + 1]) : end_s_;
      out.emissions.push_back(emit(emissions[i], random, out.noise, slot_end));
    }

    out.channels.resize(w_.receivers.size());
    for (std::size_t ch = 0; ch < w_.receivers.size(); ++ch) {
      std::vector<Pulse> above;
      for (const Contribution& c : contributions_[ch])
        above.push_back(c.above);
      out.channels[ch].envelope = union_of(std::move(above));
      out.channels[ch].carrier = carrier_output(contributions_[ch]);
    }

    std::vector<Pulse> sync;
    for (const SyncPulse& s : schedule.sync) {
      if (s.start_s >= end_s_)
        continue;
      const Vec2 from = source_at(w_.beacons[s.beacon], std::nullopt, nullptr, s.start_s).position;
      const Vec2 to = robot_ ? to_world(robot_(s.start_s), {}) : from;
      const double rise = s.start_s + distance(from, to, w_.height_m) / kSpeedOfLightMps;
      sync.push_back({rise, rise + s.duration_s});
    }
    out.sync = union_of(std::move(sync));
    return out;
  }

 private:
  [[nodiscard]] double emission_time(const Emission& e) const {
    return e.trigger_s + w_.beacons[e.beacon].electronics_delay_s;
  }

  // Spurious pulses of one channel over [0, end_s): its own random stream.
  [[nodiscard]] std::vector<NoisePulse> noise_pulses(std::size_t ch) {
    const AcousticNoise& n = w_.noise;
    std::vector<NoisePulse> pulses;
    if (n.noise_rate_hz <= 0)
      return pulses;
    Random random(seed_, static_cast<std::uint32_t>(ch + 1));
    const double f0 = w_.receivers[ch].resonance_hz;
    double t = 0;
    while (true) {
      t += random.exponential(n.noise_rate_hz);
      if (t >= end_s_)
        break;
      const double width =
          n.noise_min_width_s + (n.noise_max_width_s - n.noise_min_width_s) * random.uniform();
      const double phase = 2 * kPi * random.uniform();
      pulses.push_back({{t, t + width}, phase});
      // Rising zero crossings of sin(2 pi f0 (t' - t) + phase) inside the pulse.
      Contribution c{{t, t + width}, {}};
      for (double k = std::ceil(phase / (2 * kPi));; ++k) {
        const double rise = t + (k - phase / (2 * kPi)) / f0;
        if (rise >= t + width)
          break;
        if (rise >= t)
          c.half_cycles.push_back({rise, rise + 0.5 / f0});
      }
      contributions_[ch].push_back(std::move(c));
    }
    return pulses;
  }

  EmissionRecord emit(const Emission& e, Random& random,
                      const std::vector<std::vector<NoisePulse>>& noise, double slot_end) {
    const Beacon& b = w_.beacons[e.beacon];
    EmissionRecord record{e, emission_time(e), {}};
    record.receivers.resize(w_.receivers.size());
    std::vector<std::optional<Wall>> paths{std::nullopt};
    if (w_.room)
      for (const Wall wall : {Wall::kXMin, Wall::kXMax, Wall::kYMin, Wall::kYMax})
        if (w_.room->reflection[index(wall)] > 0)
          paths.emplace_back(wall);
    for (const std::optional<Wall>& wall : paths) {
      const double path_jitter = w_.noise.path_jitter_sd_s * random.normal();
      for (std::size_t ch = 0; ch < w_.receivers.size(); ++ch) {
        const double jitter = path_jitter + w_.noise.receiver_jitter_sd_s * random.normal();
        const double fluctuation = std::max(0.0, 1 + w_.noise.amplitude_sd * random.normal());
        std::optional<Arrival> a =
            arrive(b, record.emission_s, e.duration_s, wall, ch, jitter, fluctuation);
        if (!a)
          continue;
        Reception& reception = record.receivers[ch];
        if (wall)
          reception.echoes.push_back(*a);
        else
          reception.direct = *a;
      }
    }
    for (std::size_t ch = 0; ch < w_.receivers.size(); ++ch) {
      const auto& pulses = noise[ch];
      const auto rises_before = [&](double t) {
        return std::partition_point(pulses.begin(), pulses.end(),
                                    [t](const NoisePulse& p) { return p.pulse.rise_s < t; });
      };
      record.receivers[ch].noise_pulses = static_cast<std::size_t>(
          std::max<std::ptrdiff_t>(0, rises_before(slot_end) - rises_before(record.emission_s)));
    }
    return record;
  }

  // One path of one emission to channel ch; empty when the echo's reflection
  // point is not on its wall.
  std::optional<Arrival> arrive(const Beacon& b, double t_emit, double duration_s,
                                const std::optional<Wall>& wall, std::size_t ch, double jitter,
                                double fluctuation) {
    const Receiver& rx = w_.receivers[ch];
    const Room* room = w_.room ? &*w_.room : nullptr;
    const double h = w_.height_m;
    // The arrival of the wavefront that leaves the transducer `delay` after
    // the emission time.
    const auto wavefront = [&](double delay) {
      const Source s = source_at(b, wall, room, t_emit + delay);
      return solve_arrival(s.position, t_emit + delay, rx.position, robot_, c_, h) + jitter;
    };

    const Source source = source_at(b, wall, room, t_emit);
    Arrival a;
    a.wall = wall;
    a.source = source.position;
    a.true_time_s = solve_arrival(source.position, t_emit, rx.position, robot_, c_, h);
    a.time_s = a.true_time_s + jitter;
    const Pose pose = robot_(a.true_time_s);
    const Vec2 at = to_world(pose, rx.position);
    a.path_m = distance(source.position, at, h);

    if (wall) {
      const std::optional<Vec2> p = reflection_point(*room, *wall, source.position, at);
      if (!p)
        return std::nullopt;
      const Vec2 real = source_at(b, std::nullopt, room, t_emit).position;
      a.occluded = occluded(w_.obstacles, real, *p) || occluded(w_.obstacles, *p, at);
    } else {
      a.occluded = occluded(w_.obstacles, source.position, at);
    }

    // Amplitude: A_1m R H D_tx D_rx (1 m / r) 10^(-alpha (r - 1 m) / 20).
    const double f = b.carrier_hz;
    const double k = 2 * kPi * f / c_;
    const Vec2 toward = at - source.position;  // transmitter to receiver, planar
    double d_tx = 0;
    for (const double axis : b.axes_rad)
      d_tx += piston(k * b.piston_radius_m,
                     dot(unit(transducer_axis(source, axis)), toward) / a.path_m);
    const double d_rx =
        piston(k * rx.piston_radius_m, -dot(unit(pose.theta_rad + rx.axis_rad), toward) / a.path_m);
    const double reflection = wall ? room->reflection[index(*wall)] : 1.0;
    const double loss_db = w_.air.absorption_db_per_m(f) * (a.path_m - 1.0);
    a.amplitude_v = b.amplitude_1m_v * reflection * resonance(f, rx.resonance_hz, rx.quality) *
                    std::abs(d_tx * d_rx) / a.path_m * std::pow(10.0, -loss_db / 20) * fluctuation;
    a.inverted = d_tx * d_rx < 0;

    // Envelope A (1 - e^(-t/tau)) during the burst, its end value decaying
    // e^(-(t - T)/tau) after it; crossings as wavefront delays.
    const double tau = b.envelope_tau_s;
    const double v = rx.threshold_v;
    const double at_end = -a.amplitude_v * std::expm1(-duration_s / tau);
    if (a.occluded || !(at_end > v))
      return a;
    const double rise_delay = -tau * std::log1p(-v / a.amplitude_v);
    const double fall_delay = duration_s + tau * std::log(at_end / v);
    Contribution c{{wavefront(rise_delay), wavefront(fall_delay)}, {}};
    a.above_threshold = c.above;
    // Positive half-cycles: wavefronts at carrier phase 0 (pi when inverted).
    const double offset = a.inverted ? 0.5 : 0.0;
    for (double n = std::ceil(rise_delay * f - offset);; ++n) {
      const double delay = (n + offset) / f;
      if (delay >= fall_delay)
        break;
      if (delay >= rise_delay)
        c.half_cycles.push_back({wavefront(delay), wavefront(delay + 0.5 / f)});
    }
    contributions_[ch].push_back(std::move(c));
    return a;
  }

  const AcousticWorld& w_;
  const Trajectory& robot_;
  double end_s_;
  std::uint64_t seed_;
  double c_;
  std::vector<std::vector<Contribution>> contributions_;  // per channel
};

}  // namespace

Vec2 to_world(const Pose& pose, Vec2 body) {
  const double c = std::cos(pose.theta_rad);
  const double s = std::sin(pose.theta_rad);
  return {pose.x_m + c * body.x_m - s * body.y_m, pose.y_m + s * body.x_m + c * body.y_m};
}

Trajectory stationary(Pose pose) {
  return [pose](double) { return pose; };
}

Trajectory interpolate(std::vector<TrajectorySample> samples) {
  require(!samples.empty(), "no trajectory samples");
  for (std::size_t i = 1; i < samples.size(); ++i)
    require(samples[i].truth.time_s >= samples[i - 1].truth.time_s,
            "trajectory samples not sorted by time");
  auto shared = std::make_shared<const std::vector<TrajectorySample>>(std::move(samples));
  return [shared](double t) {
    const std::vector<TrajectorySample>& s = *shared;
    if (t <= s.front().truth.time_s)
      return s.front().truth.pose;
    if (t >= s.back().truth.time_s)
      return s.back().truth.pose;
    const auto after =
        std::upper_bound(s.begin(), s.end(), t,
                         [](double x, const TrajectorySample& y) { return x < y.truth.time_s; });
    const TruePose& p1 = after->truth;
    const TruePose& p0 = std::prev(after)->truth;
    const double u = (t - p0.time_s) / (p1.time_s - p0.time_s);
    return Pose{p0.pose.x_m + u * (p1.pose.x_m - p0.pose.x_m),
                p0.pose.y_m + u * (p1.pose.y_m - p0.pose.y_m),
                p0.pose.theta_rad + u * (p1.pose.theta_rad - p0.pose.theta_rad)};
  };
}

double Air::speed_of_sound_mps() const {
  return 331.3 * std::sqrt(1 + temperature_c / 273.15);
}

double Air::absorption_db_per_m(double frequency_hz) const {
  // ISO 9613-1:1993, equations (3)-(5) and annex B (saturation pressure).
  const double t = temperature_c + 273.15;
  const double t_ref = 293.15;  // K
  const double t01 = 273.16;    // triple point, K
  const double p_rel = pressure_kpa / 101.325;
  const double p_sat_rel = std::pow(10.0, -6.8346 * std::pow(t01 / t, 1.261) + 4.6151);
  const double h = 100 * relative_humidity * p_sat_rel / p_rel;  // molar % of water vapour
  const double fr_o = p_rel * (24 + 4.04e4 * h * (0.02 + h) / (0.391 + h));
  const double fr_n = p_rel * std::pow(t / t_ref, -0.5) *
                      (9 + 280 * h * std::exp(-4.170 * (std::pow(t / t_ref, -1.0 / 3) - 1)));
  const double f2 = frequency_hz * frequency_hz;
  return 8.686 * f2 *
         (1.84e-11 / p_rel * std::sqrt(t / t_ref) +
          std::pow(t / t_ref, -2.5) * (0.01275 * std::exp(-2239.1 / t) / (fr_o + f2 / fr_o) +
                                       0.1068 * std::exp(-3352.0 / t) / (fr_n + f2 / fr_n)));
}

AcousticRun simulate(const AcousticWorld& world, const Schedule& schedule, const Trajectory& robot,
                     double end_s, std::uint64_t seed) {
  validate(world, schedule, robot, end_s);
  return Simulator(world, robot, end_s, seed).run(schedule);
}

PinSource::PinSource(const std::vector<Pulse>& waveform, double clock_hz) {
  if (!(clock_hz > 0))
    throw std::invalid_argument("PinSource: clock_hz must be positive");
  constexpr double kLimit = 0x1p63;
  for (const Pulse& p : union_of(waveform)) {
    const double rise = std::max(0.0, std::ceil(p.rise_s * clock_hz));
    const double fall = std::max(0.0, std::ceil(p.fall_s * clock_hz));
    if (!(fall < kLimit))
      throw std::out_of_range("PinSource: a transition beyond 2^63 clocks");
    if (fall <= rise)
      continue;  // shorter than a clock and containing no clock start
    const auto r = static_cast<std::uint64_t>(rise);
    const auto f = static_cast<std::uint64_t>(fall);
    if (!transitions_.empty() && r <= transitions_.back())
      transitions_.back() = std::max(transitions_.back(), f);  // touching: one pulse
    else
      transitions_.insert(transitions_.end(), {r, f});
  }
}

void PinSource::skip_to(std::uint64_t clock) {
  if (clock >= clock_) {
    while (next_ < transitions_.size() && transitions_[next_] < clock)
      ++next_;
  } else {
    next_ = static_cast<std::size_t>(
        std::lower_bound(transitions_.begin(), transitions_.end(), clock) - transitions_.begin());
  }
  clock_ = clock;
}

AcousticPins::AcousticPins(const AcousticRun& run, ComparatorKind kind, double clock_hz)
    : AcousticPins(run, std::vector<ComparatorKind>(run.channels.size(), kind), clock_hz) {}

AcousticPins::AcousticPins(const AcousticRun& run, const std::vector<ComparatorKind>& kinds,
                           double clock_hz)
    : sync_(run.sync, clock_hz) {
  if (run.channels.size() > 32)
    throw std::invalid_argument("AcousticPins: more than 32 channels");
  if (kinds.size() != run.channels.size())
    throw std::invalid_argument("AcousticPins: one comparator kind per channel");
  for (std::size_t i = 0; i < run.channels.size(); ++i)
    channels_.emplace_back(run.channels[i](kinds[i]), clock_hz);
  skip_to(0);
}

PinLevels AcousticPins::tick() {
  if (clock_ >= next_change_) {
    PinLevels levels;
    std::uint64_t next = PinSource::kNever;
    for (std::size_t i = 0; i < channels_.size(); ++i) {
      channels_[i].skip_to(clock_);
      if (channels_[i].tick())
        levels.channels |= 1U << i;
      next = std::min(next, channels_[i].next_transition_clock());
    }
    sync_.skip_to(clock_);
    levels.sync = sync_.tick();
    levels_ = levels;
    next_change_ = std::min(next, sync_.next_transition_clock());
  }
  ++clock_;
  return levels_;
}

void AcousticPins::skip_to(std::uint64_t clock) {
  clock_ = clock;
  PinLevels levels;
  for (std::size_t i = 0; i < channels_.size(); ++i) {
    channels_[i].skip_to(clock);
    if (channels_[i].level())
      levels.channels |= 1U << i;
  }
  sync_.skip_to(clock);
  levels.sync = sync_.level();
  levels_ = levels;
  next_change_ = sync_.next_transition_clock();
  for (const PinSource& s : channels_)
    next_change_ = std::min(next_change_, s.next_transition_clock());
}

}  // namespace odoloc::world
