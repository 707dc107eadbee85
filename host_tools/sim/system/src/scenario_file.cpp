#include "odoloc/sim/scenario_file.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include "odoloc/output/printable.hpp"
#include "odoloc/sw/pose_ekf.hpp"

namespace odoloc::sim {

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

using world::Vec2;
using world::Wheel;
using YAML::Node;

// How long a path takes: each segment's distance over its speed, its
// duration, or its steering move at the path's rate (the steering starts
// straight and carries over).
double path_seconds(const world::Path& path) {
  double seconds = 0;
  double steer = 0;
  for (const world::Segment& s : path.segments) {
    switch (s.end) {
      case world::Segment::End::kDistance:
        seconds += s.amount / std::abs(s.speed_mps);
        break;
      case world::Segment::End::kDuration:
        seconds += s.amount;
        break;
      case world::Segment::End::kSteered:
        seconds += std::abs(s.steer_rad - steer) / path.steer_rate_radps;
        break;
    }
    if (s.end == world::Segment::End::kSteered)
      steer = s.steer_rad;
  }
  return seconds;
}

// The rear-midpoint odometer of a path's segments (m).
double path_metres(const world::Path& path) {
  double metres = 0;
  for (const world::Segment& s : path.segments) {
    if (s.end == world::Segment::End::kDistance)
      metres += s.amount;
    else if (s.end == world::Segment::End::kDuration)
      metres += std::abs(s.speed_mps) * s.amount;
  }
  return metres;
}

// The whole file at `path`; nullopt when it cannot be read.
std::optional<std::string> read_text(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  if (in)
    text << in.rdbuf();
  if (!in || in.bad())
    return std::nullopt;
  return std::move(text).str();
}

// A recorded trajectory (docs/scenarios.md, path.trajectory): the rear
// midpoint's pose over time, one CSV row per sample.
constexpr std::string_view kTrajectoryHeader = "time_s,x_m,y_m,heading_deg";
constexpr std::array<std::string_view, 4> kTrajectoryColumns = {"time_s", "x_m", "y_m",
                                                                "heading_deg"};
// Bigger files would not be recordings: 64 MiB is a day of samples at 20 Hz.
constexpr std::uintmax_t kMaxTrajectoryBytes = 64U << 20;
// What the tricycle cannot do within a sample interval: drive faster than a
// segment may (path.segments), or move sideways to its heading (its rear
// wheels cannot slide) by more than this, which allows for the recording's
// rounding.
constexpr double kMaxTrajectorySpeedMps = 1.5;
constexpr double kMaxSidewaysM = 1e-3;
// path.start, when given, must be the first sample to within these.
constexpr double kStartToleranceM = 1e-3;
constexpr double kStartToleranceRad = 0.1 * kDeg;

struct TrajectorySample {
  double time_s = 0;
  world::Pose pose;
  std::size_t line = 0;  // in the CSV, for its errors
};

[[noreturn]] void fail_at(std::string_view csv, std::size_t line, std::string_view what) {
  throw yaml::InputError(fmt::format("{}:{}: {}", csv, line, what));
}

// The samples of the CSV text `text`, named `csv` in its errors: the
// header, then rows of four finite numbers with the time strictly
// increasing. Blank lines are skipped.
std::vector<TrajectorySample> read_trajectory_samples(std::string_view text, std::string_view csv) {
  if (text.starts_with("\xEF\xBB\xBF"))  // a UTF-8 byte-order mark, as spreadsheets write
    text.remove_prefix(3);
  const std::vector<std::string_view> lines = yaml::split_fields(text, '\n');
  std::vector<TrajectorySample> samples;
  std::size_t header = 0;  // its line
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const std::size_t line = i + 1;
    if (lines[i].empty())
      continue;
    const std::vector<std::string_view> fields = yaml::split_fields(lines[i]);
    if (header == 0) {
      if (!std::ranges::equal(fields, kTrajectoryColumns))
        fail_at(csv, line,
                fmt::format("the header is '{}' (these columns, no others), not '{}'",
                            kTrajectoryHeader, output::printable_excerpt(lines[i], 80)));
      header = line;
      continue;
    }
    if (fields.size() != kTrajectoryColumns.size())
      fail_at(csv, line,
              fmt::format("{} values; the header names {} ({})", fields.size(),
                          kTrajectoryColumns.size(), kTrajectoryHeader));
    std::array<double, 4> v{};
    for (std::size_t c = 0; c < v.size(); ++c) {
      const std::optional<double> value = yaml::finite_number(fields[c]);
      if (!value)
        fail_at(csv, line,
                fmt::format("{} must be a finite number, not '{}'", kTrajectoryColumns[c],
                            output::printable_excerpt(fields[c])));
      v[c] = *value;
    }
    if (!samples.empty() && !(v[0] > samples.back().time_s))
      fail_at(csv, line,
              fmt::format("time_s {} is not after the previous sample's {} (line {})", v[0],
                          samples.back().time_s, samples.back().line));
    samples.push_back({v[0], {v[1], v[2], v[3] * kDeg}, line});
  }
  if (header == 0)
    fail_at(
        csv, 1,
        fmt::format("an empty file: a trajectory starts with the header '{}'", kTrajectoryHeader));
  if (samples.size() < 2)
    fail_at(csv, samples.empty() ? header : samples.back().line,
            fmt::format("{} sample{}: a trajectory needs two at least", samples.size(),
                        samples.size() == 1 ? "" : "s"));
  return samples;
}

// The tricycle's segments that drive the samples back, one per sample
// interval: the arc through both poses (chord and heading change,
// sw::fuse::arc_length), at ds/dt with the steering atan(L dtheta / ds).
// Each interval must be one the tricycle can drive. A recording cannot
// show how a standing robot steers: a standing interval steers toward the
// motion that follows it (and holds the steering after the last one), so
// a robot recorded standing before a turn starts it without a lag.
world::Path trajectory_path(const std::vector<TrajectorySample>& samples,
                            const world::Geometry& geometry, const std::optional<world::Room>& room,
                            std::string_view csv) {
  const auto fuse_pose = [](const world::Pose& p) {
    sw::fuse::Pose out;
    out.x = {p.x_m, p.y_m, p.theta_rad};
    return out;
  };
  world::Path path;
  double steer = 0;
  for (std::size_t k = 0; k < samples.size(); ++k) {
    const TrajectorySample& to = samples[k];
    if (room && !(to.pose.x_m >= 0 && to.pose.x_m <= room->width_m && to.pose.y_m >= 0 &&
                  to.pose.y_m <= room->depth_m))
      fail_at(csv, to.line,
              fmt::format("({}, {}) m is outside the {} x {} m room", to.pose.x_m, to.pose.y_m,
                          room->width_m, room->depth_m));
    if (k == 0)
      continue;
    const TrajectorySample& from = samples[k - 1];
    const double dt = to.time_s - from.time_s;
    // In the frame of `from`; the turn is the shorter way round.
    const sw::fuse::Vector3 d =
        sw::fuse::increment_between(fuse_pose(from.pose), fuse_pose(to.pose));
    // An arc's chord lies along the heading halfway through the turn.
    const double sideways = d.y() * std::cos(d.z() / 2) - d.x() * std::sin(d.z() / 2);
    if (std::abs(sideways) > kMaxSidewaysM)
      fail_at(csv, to.line,
              fmt::format("{:.1f} mm sideways to the heading since line {}: a tricycle cannot "
                          "slide ({:.0f} mm at most)",
                          sideways * 1e3, from.line, kMaxSidewaysM * 1e3));
    const double ds = sw::fuse::arc_length(d);
    if (ds == 0 && d.z() != 0)
      fail_at(csv, to.line,
              fmt::format("turns {:.3f} degrees on the spot since line {}: a tricycle cannot",
                          d.z() / kDeg, from.line));
    const double speed = ds / dt;
    if (std::abs(speed) > kMaxTrajectorySpeedMps)
      fail_at(csv, to.line,
              fmt::format("{:.3f} m/s since line {}: faster than {} m/s", speed, from.line,
                          kMaxTrajectorySpeedMps));
    if (ds != 0)
      steer = std::atan(geometry.wheelbase_m * d.z() / ds);
    if (std::abs(steer) > geometry.steering.limit_rad)
      fail_at(csv, to.line,
              fmt::format("the turn since line {} needs {:.2f} degrees of steering, beyond "
                          "robot.steering.limit_deg {:.2f}",
                          from.line, steer / kDeg, geometry.steering.limit_rad / kDeg));
    path.segments.push_back(world::Segment::duration(speed, steer, dt));
  }
  std::optional<double> next;
  for (auto s = path.segments.rbegin(); s != path.segments.rend(); ++s) {
    if (s->speed_mps != 0)
      next = s->steer_rad;
    else if (next)
      s->steer_rad = *next;
  }
  return path;
}

class ScenarioReader {
 public:
  ScenarioReader(std::string_view file, const ScenarioOverrides& overrides,
                 std::optional<std::filesystem::path> directory)
      : r_(file), overrides_(overrides), directory_(std::move(directory)) {}

  Scenario read(const std::string& text) {
    const Node root = r_.load(text);
    if (!root.IsMap())
      r_.fail(root, "a scenario is a YAML mapping (docs/scenarios.md)");
    r_.check_keys(root, "scenario",
                  {"name", "seed", "room", "air", "noise", "beacons", "station", "robot", "path",
                   "stationary", "disturbances", "survey", "liu_filter", "thamma"});
    Scenario s;
    world::RoomTour& tour = s.tour;
    const std::string name = r_.scalar(r_.required(root, "name", "scenario"), "name");
    if (const Node seed = root["seed"])
      s.seed = r_.whole(seed, "seed");
    world::AcousticWorld& w = tour.acoustics;
    if (const Node room = root["room"])
      read_room(room, w);
    if (const Node air = root["air"])
      read_air(air, w.air);
    if (const Node noise = root["noise"])
      read_noise(noise, w.noise);
    if (const Node beacons = root["beacons"])
      read_beacons(beacons, tour);
    else
      tour.timing.beacon_count = 0;
    read_robot(r_.required(root, "robot", "scenario"), tour);
    if (const Node station = root["station"])
      read_station(station, tour);
    if (const Node thamma = root["thamma"]) {
      if (root["beacons"] || root["station"])
        r_.fail(thamma,
                "thamma: Thamma's stations exclude 'beacons' and 'station' (the sync "
                "input and the receivers are theirs)");
      read_thamma(thamma, tour);
    }
    if (!root["beacons"] && !root["station"] && !root["thamma"])
      r_.fail(root, "scenario: no 'beacons', 'station' or 'thamma': nothing to localise with");
    if (root["stationary"] && !root["beacons"])
      r_.fail(root["stationary"], "stationary: Kleeman's experiment needs 'beacons'");
    if (root["stationary"] && (overrides_.laps || overrides_.speed_mps))
      r_.fail(root["stationary"], overrides_.laps ? "--laps: a stationary scenario has no path"
                                                  : "--speed: a stationary scenario has no path");
    if (root["path"] && root["stationary"])
      r_.fail(root["stationary"], "scenario: a path or stationary points, not both");
    Laps laps;
    if (const Node points = root["stationary"])
      s.stationary = read_stationary(points, tour);
    else
      laps = read_path(r_.required(root, "path", "scenario"), tour);
    tour.name = laps.count == 0
                    ? name
                    : fmt::format("{} lap{} of {}", laps.count, laps.count == 1 ? "" : "s", name);
    tour.drive.name = tour.name;
    if (const Node d = root["disturbances"])
      read_disturbances(d, laps, tour.drive);
    read_survey(r_.required(root, "survey", "scenario"), tour, s.survey);
    if (const Node liu = root["liu_filter"])
      read_liu_filter(liu, tour, s.survey);
    check_inside(root, tour);
    return s;
  }

 private:
  // What the world's own constructors refuse (std::invalid_argument) is an
  // error at `node`, the section that made it.
  template <class Build>
  auto world_checked(const Node& node, Build&& build) const {
    try {
      return build();
    } catch (const std::invalid_argument& e) {
      r_.fail(node, e.what());
    }
  }

  Vec2 point(const Node& node, std::string_view where) const {
    const std::vector<double> xy = r_.numbers(node, where, 2);
    return {xy[0], xy[1]};
  }

  void read_room(const Node& node, world::AcousticWorld& w) const {
    r_.check_keys(node, "room", {"width_m", "depth_m", "reflection", "obstacles"});
    world::Room& room = w.room.emplace();
    room.width_m = r_.number(r_.required(node, "width_m", "room"), "room.width_m", 0.5, 1000);
    room.depth_m = r_.number(r_.required(node, "depth_m", "room"), "room.depth_m", 0.5, 1000);
    if (const Node reflection = node["reflection"]) {
      const std::vector<double> k = r_.numbers(reflection, "room.reflection", world::kWallCount);
      for (std::size_t i = 0; i < world::kWallCount; ++i) {
        if (!(k[i] >= 0 && k[i] <= 1))
          r_.fail(reflection, "room.reflection: each coefficient is in [0, 1]");
        room.reflection[i] = k[i];
      }
    }
    if (const Node obstacles = node["obstacles"]) {
      r_.sequence(obstacles, "room.obstacles");
      for (const Node& o : obstacles) {
        r_.check_keys(o, "room.obstacles[]", {"from", "to", "radius_m"});
        w.obstacles.push_back({point(r_.required(o, "from", "obstacle"), "obstacle.from"),
                               point(r_.required(o, "to", "obstacle"), "obstacle.to"),
                               r_.number_or(o, "radius_m", "obstacle", 0, 0, 100)});
      }
    }
  }

  void read_air(const Node& node, world::Air& air) const {
    r_.check_keys(node, "air", {"temperature_c", "relative_humidity", "pressure_kpa"});
    air.temperature_c = r_.number_or(node, "temperature_c", "air", air.temperature_c, -40, 60);
    air.relative_humidity =
        r_.number_or(node, "relative_humidity", "air", air.relative_humidity, 0, 1);
    air.pressure_kpa = r_.number_or(node, "pressure_kpa", "air", air.pressure_kpa, 50, 120);
  }

  void read_noise(const Node& node, world::AcousticNoise& n) const {
    r_.check_keys(node, "noise",
                  {"path_jitter_s", "receiver_jitter_s", "amplitude_sd", "pulses_per_s",
                   "pulse_min_width_s", "pulse_max_width_s"});
    n.path_jitter_sd_s = r_.number_or(node, "path_jitter_s", "noise", 0, 0, 1e-3);
    n.receiver_jitter_sd_s = r_.number_or(node, "receiver_jitter_s", "noise", 0, 0, 1e-3);
    n.amplitude_sd = r_.number_or(node, "amplitude_sd", "noise", 0, 0, 1);
    n.noise_rate_hz = r_.number_or(node, "pulses_per_s", "noise", 0, 0, 1000);
    n.noise_min_width_s =
        r_.number_or(node, "pulse_min_width_s", "noise", n.noise_min_width_s, 1e-6, 1);
    n.noise_max_width_s =
        r_.number_or(node, "pulse_max_width_s", "noise", n.noise_max_width_s, 1e-6, 1);
    if (n.noise_max_width_s < n.noise_min_width_s)
      r_.fail(node, "noise: pulse_max_width_s is below pulse_min_width_s");
  }

  // Every transmitter's acoustics; `base` holds the defaults.
  world::Beacon transmitter(const Node& node, std::string_view where, world::Beacon base) const {
    base.carrier_hz = r_.number_or(node, "carrier_hz", where, base.carrier_hz, 1e3, 1e6);
    base.amplitude_1m_v =
        r_.number_or(node, "amplitude_1m_v", where, base.amplitude_1m_v, 1e-3, 1e4);
    base.piston_radius_m =
        r_.number_or(node, "piston_radius_m", where, base.piston_radius_m, 1e-4, 0.5);
    base.envelope_tau_s =
        r_.number_or(node, "envelope_tau_s", where, base.envelope_tau_s, 1e-6, 0.1);
    return base;
  }
  std::vector<double> axes(const Node& node, std::string_view where) const {
    std::vector<double> out;
    for (const double deg : r_.numbers(node, where))
      out.push_back(deg * kDeg);
    return out;
  }

  void read_beacons(const Node& node, world::RoomTour& tour) const {
    r_.check_keys(node, "beacons",
                  {"height_m", "fire_s", "fire_ticks", "pulse_s", "double_pulse_s", "first_burst_s",
                   "transmitter", "list"});
    world::AcousticWorld& w = tour.acoustics;
    world::KleemanTiming& t = tour.timing;
    w.height_m = r_.number_or(node, "height_m", "beacons", 0, 0, 100);
    t.fire_ticks = static_cast<std::uint32_t>(
        node["fire_ticks"] ? r_.whole(node["fire_ticks"], "beacons.fire_ticks", 1, 1U << 24)
                           : t.fire_ticks);
    if (const Node fire = node["fire_s"])
      t.timer_tick_s = r_.number(fire, "beacons.fire_s", 1e-3, 10) / t.fire_ticks;
    t.pulse_s = r_.number_or(node, "pulse_s", "beacons", t.pulse_s, 1e-5, 1);
    t.double_pulse_s = r_.number_or(node, "double_pulse_s", "beacons", t.double_pulse_s, 1e-5, 1);
    tour.first_burst_s = r_.number_or(node, "first_burst_s", "beacons", tour.first_burst_s, 0, 60);
    world::Beacon base;
    if (const Node tx = node["transmitter"]) {
      r_.check_keys(tx, "beacons.transmitter",
                    {"carrier_hz", "amplitude_1m_v", "piston_radius_m", "envelope_tau_s"});
      base = transmitter(tx, "beacons.transmitter", base);
    }
    const Node list = r_.required(node, "list", "beacons");
    r_.sequence(list, "beacons.list");
    for (const Node& b : list) {
      r_.check_keys(b, "beacons.list[]",
                    {"position", "axes_deg", "carrier_hz", "amplitude_1m_v", "piston_radius_m",
                     "envelope_tau_s"});
      world::Beacon beacon = transmitter(b, "beacon", base);
      beacon.position = point(r_.required(b, "position", "beacon"), "beacon.position");
      beacon.axes_rad = axes(r_.required(b, "axes_deg", "beacon"), "beacon.axes_deg");
      w.beacons.push_back(beacon);
    }
    if (w.beacons.size() < 3 || w.beacons.size() > 16)
      r_.fail(list, fmt::format("beacons.list: {} beacons; Kleeman's system needs 3 to 16",
                                w.beacons.size()));
    t.beacon_count = w.beacons.size();
    world_checked(node, [&] { return world::kleeman_schedule(t, 1); });
  }

  void read_station(const Node& node, world::RoomTour& tour) const {
    r_.check_keys(node, "station",
                  {"position", "axes_deg", "t0_s", "station_laser", "robot_laser", "carrier_hz",
                   "amplitude_1m_v", "piston_radius_m", "envelope_tau_s"});
    world::AcousticWorld& w = tour.acoustics;
    world::BaseStation& station = tour.station.emplace();
    station.position = point(r_.required(node, "position", "station"), "station.position");
    station.transmitter = w.beacons.size();
    // The beacons' transmitter unless the station says otherwise.
    world::Beacon tx =
        transmitter(node, "station", w.beacons.empty() ? world::Beacon{} : w.beacons.front());
    tx.position = station.position;
    tx.axes_rad = axes(r_.required(node, "axes_deg", "station"), "station.axes_deg");
    tx.electronics_delay_s = r_.number_or(node, "t0_s", "station", 0, 0, 1);
    w.beacons.push_back(tx);
    tour.timing.reserved_slots = 1;
    read_laser(r_.required(node, "station_laser", "station"), "station.station_laser",
               station.station_laser);
    read_laser(r_.required(node, "robot_laser", "station"), "station.robot_laser",
               station.robot_laser);
  }
  // Thamma's stations: every acoustics beacon, fired in the list's order.
  void read_thamma(const Node& node, world::RoomTour& tour) const {
    r_.check_keys(node, "thamma",
                  {"repeats", "period_s", "pulse_s", "cycle_gap_s", "first_trigger_s", "delay_s",
                   "transmitter", "stations"});
    world::ThammaStations& th = tour.thamma.emplace();
    world::TriggeredTiming& t = th.timing;
    t.repeats = node["repeats"] ? r_.whole(node["repeats"], "thamma.repeats", 1, 16) : t.repeats;
    t.period_s = r_.number_or(node, "period_s", "thamma", t.period_s, 1e-3, 10);
    t.pulse_s = r_.number_or(node, "pulse_s", "thamma", t.pulse_s, 1e-5, 1);
    t.cycle_gap_s = r_.number_or(node, "cycle_gap_s", "thamma", t.period_s, 0, 100);
    th.first_trigger_s = r_.number_or(node, "first_trigger_s", "thamma", th.first_trigger_s, 0, 60);
    world::Beacon base;
    base.electronics_delay_s = r_.number_or(node, "delay_s", "thamma", 100e-6, 0, 0.1);
    if (const Node tx = node["transmitter"]) {
      r_.check_keys(tx, "thamma.transmitter",
                    {"amplitude_1m_v", "piston_radius_m", "envelope_tau_s"});
      base = transmitter(tx, "thamma.transmitter", base);
    }
    const Node list = r_.required(node, "stations", "thamma");
    r_.sequence(list, "thamma.stations");
    for (const Node& st : list) {
      r_.check_keys(st, "thamma.stations[]",
                    {"position", "axes_deg", "carrier_hz", "amplitude_1m_v", "piston_radius_m",
                     "envelope_tau_s"});
      world::Beacon b = transmitter(st, "station", base);
      b.position = point(r_.required(st, "position", "station"), "station.position");
      b.axes_rad = axes(r_.required(st, "axes_deg", "station"), "station.axes_deg");
      tour.acoustics.beacons.push_back(b);
    }
    if (list.size() < 2 || list.size() > 16)
      r_.fail(list, "thamma.stations: 2 to 16 stations");
    if (t.period_s <= t.pulse_s)
      r_.fail(node, "thamma: period_s must exceed pulse_s");
    if (t.cycle_gap_s < t.period_s / 2)
      r_.fail(node,
              "thamma: cycle_gap_s must be at least half period_s (the robot frames the "
              "cycles on it)");
  }

  void read_laser(const Node& node, std::string_view where, world::ScanningLaser& laser) const {
    r_.check_keys(node, where,
                  {"sweep_start_deg", "sweep_width_deg", "period_s", "phase_s", "counts_per_rev"});
    laser.sweep_start_rad =
        r_.number(r_.required(node, "sweep_start_deg", where), "sweep_start_deg", -360, 360) * kDeg;
    laser.sweep_width_rad =
        r_.number(r_.required(node, "sweep_width_deg", where), "sweep_width_deg", 1, 360) * kDeg;
    laser.period_s = r_.number_or(node, "period_s", where, laser.period_s, 0.01, 1000);
    laser.phase_s = r_.number_or(node, "phase_s", where, laser.phase_s, -1000, 1000);
    if (const Node counts = node["counts_per_rev"])
      laser.counts_per_rev = static_cast<std::uint32_t>(
          r_.whole(counts, fmt::format("{}.counts_per_rev", where), 4, 1U << 24));
  }

  void read_wheel(const Node& node, std::string_view where, world::WheelEncoder& wheel) const {
    r_.check_keys(node, where,
                  {"nominal_radius_m", "true_radius_m", "radius_error", "lines", "gear"});
    wheel.nominal_radius_m =
        r_.number_or(node, "nominal_radius_m", where, wheel.nominal_radius_m, 0.005, 2);
    if (node["true_radius_m"] && node["radius_error"])
      r_.fail(node, fmt::format("{}: true_radius_m or radius_error, not both", where));
    if (const Node error = node["radius_error"])
      wheel.true_radius_m =
          wheel.nominal_radius_m *
          (1 + r_.number(error, fmt::format("{}.radius_error", where), -0.5, 0.5));
    else
      wheel.true_radius_m =
          r_.number_or(node, "true_radius_m", where, wheel.nominal_radius_m, 0.005, 2);
    if (const Node lines = node["lines"])
      wheel.lines =
          static_cast<std::uint32_t>(r_.whole(lines, fmt::format("{}.lines", where), 1, 1U << 20));
    wheel.gear = r_.number_or(node, "gear", where, wheel.gear, 0.01, 1000);
  }

  void read_robot(const Node& node, world::RoomTour& tour) const {
    r_.check_keys(node, "robot", {"track_m", "wheelbase_m", "wheels", "steering", "receivers"});
    world::Geometry& g = tour.drive.geometry;
    g.track_m = r_.number_or(node, "track_m", "robot", g.track_m, 0.05, 5);
    g.wheelbase_m = r_.number_or(node, "wheelbase_m", "robot", g.wheelbase_m, 0.05, 5);
    if (const Node wheels = node["wheels"]) {
      r_.check_keys(wheels, "robot.wheels", {"left_rear", "right_rear", "front"});
      if (const Node w = wheels["left_rear"])
        read_wheel(w, "robot.wheels.left_rear", g.left_rear);
      if (const Node w = wheels["right_rear"])
        read_wheel(w, "robot.wheels.right_rear", g.right_rear);
      if (const Node w = wheels["front"])
        read_wheel(w, "robot.wheels.front", g.front);
    }
    if (const Node s = node["steering"]) {
      r_.check_keys(s, "robot.steering", {"lines", "gear", "limit_deg"});
      if (const Node lines = s["lines"])
        g.steering.lines =
            static_cast<std::uint32_t>(r_.whole(lines, "robot.steering.lines", 1, 1U << 20));
      g.steering.gear = r_.number_or(s, "gear", "robot.steering", g.steering.gear, 0.01, 1000);
      if (const Node limit = s["limit_deg"])
        g.steering.limit_rad = r_.number(limit, "robot.steering.limit_deg", 1, 89) * kDeg;
    }
    read_receivers(r_.required(node, "receivers", "robot"), tour.acoustics.receivers);
  }

  void read_receivers(const Node& node, std::vector<world::Receiver>& out) const {
    r_.check_keys(node, "robot.receivers", {"octagon", "list", "boxes"});
    if ((node["octagon"] ? 1 : 0) + (node["list"] ? 1 : 0) + (node["boxes"] ? 1 : 0) > 1)
      r_.fail(node, "robot.receivers: one of octagon, list or boxes");
    if (const Node b = node["boxes"]) {
      r_.check_keys(b, "robot.receivers.boxes", {"head", "tail"});
      out = world::thamma_boxes(point(r_.required(b, "head", "boxes"), "boxes.head"),
                                point(r_.required(b, "tail", "boxes"), "boxes.tail"));
      return;
    }
    if (const Node o = node["octagon"]) {
      r_.check_keys(o, "robot.receivers.octagon", {"side_m", "centre"});
      const Vec2 centre = o["centre"] ? point(o["centre"], "octagon.centre") : Vec2{};
      out = world::kleeman_octagon(centre, r_.number_or(o, "side_m", "octagon", 0.05, 0.005, 1));
      return;
    }
    const Node list = r_.required(node, "list", "robot.receivers");
    r_.sequence(list, "robot.receivers.list");
    for (const Node& item : list) {
      r_.check_keys(
          item, "robot.receivers.list[]",
          {"position", "axis_deg", "resonance_hz", "quality", "piston_radius_m", "threshold_v"});
      world::Receiver rx;
      rx.position = point(r_.required(item, "position", "receiver"), "receiver.position");
      rx.axis_rad =
          r_.number(r_.required(item, "axis_deg", "receiver"), "receiver.axis_deg", -360, 360) *
          kDeg;
      rx.resonance_hz = r_.number_or(item, "resonance_hz", "receiver", rx.resonance_hz, 1e3, 1e6);
      rx.quality = r_.number_or(item, "quality", "receiver", rx.quality, 0.5, 1000);
      rx.piston_radius_m =
          r_.number_or(item, "piston_radius_m", "receiver", rx.piston_radius_m, 1e-4, 0.5);
      rx.threshold_v = r_.number_or(item, "threshold_v", "receiver", rx.threshold_v, 1e-4, 100);
      out.push_back(rx);
    }
    if (out.empty() || out.size() > 8)
      r_.fail(list, "robot.receivers.list: 1 to 8 receivers (the capture unit's channels)");
  }

  // A path's laps: how many (0: a path without laps) and the odometer of one.
  struct Laps {
    std::size_t count = 0;
    double metres = 0;
  };
  Laps read_path(const Node& node, world::RoomTour& tour) const {
    r_.check_keys(node, "path",
                  {"start", "wait_s", "laps", "lap_wait_s", "square", "segments", "trajectory",
                   "steer_rate_degps"});
    world::Scenario& drive = tour.drive;
    // A trajectory's first sample is its start.
    const Node start = node["trajectory"] ? node["start"] : r_.required(node, "start", "path");
    if (start) {
      r_.check_keys(start, "path.start", {"x_m", "y_m", "heading_deg"});
      drive.start = {r_.number(r_.required(start, "x_m", "path.start"), "path.start.x_m"),
                     r_.number(r_.required(start, "y_m", "path.start"), "path.start.y_m"),
                     r_.number_or(start, "heading_deg", "path.start", 0, -360, 360) * kDeg};
    }
    const double wait_s = r_.number_or(node, "wait_s", "path", 0, 0, 3600);
    const double lap_wait_s = r_.number_or(node, "lap_wait_s", "path", 0, 0, 3600);
    std::size_t laps = node["laps"] ? r_.whole(node["laps"], "path.laps", 1, 100) : 0;
    if (overrides_.laps) {
      if (laps == 0)
        r_.fail(node, "--laps: this scenario's path has no laps");
      laps = *overrides_.laps;
    }
    if ((node["square"] ? 1 : 0) + (node["segments"] ? 1 : 0) + (node["trajectory"] ? 1 : 0) > 1)
      r_.fail(node, "path: one of square, segments and trajectory");
    if (overrides_.speed_mps && !node["square"])
      r_.fail(node, "--speed: only a square path has one speed");
    world::Path lap;
    double lap_m = 0;
    if (const Node sq = node["square"]) {
      r_.check_keys(sq, "path.square", {"side_m", "speed_mps", "steer_deg"});
      const double side = r_.number(r_.required(sq, "side_m", "path.square"), "side_m", 0.5, 1000);
      double speed = r_.number(r_.required(sq, "speed_mps", "path.square"), "speed_mps", 0.01, 1.5);
      if (overrides_.speed_mps)
        speed = *overrides_.speed_mps;
      const double steer =
          r_.number(r_.required(sq, "steer_deg", "path.square"), "steer_deg", 1, 40) * kDeg;
      lap =
          world_checked(sq, [&] { return world::square_path(drive.geometry, side, speed, steer); });
      // The odometer of one lap: four straights and four quarter turns.
      const double radius = drive.geometry.wheelbase_m / std::tan(steer);
      lap_m = 4 * (side - 2 * radius) + 2 * std::numbers::pi * radius;
    } else {
      if (const Node trajectory = node["trajectory"])
        lap = read_trajectory(trajectory, start, tour);
      else
        read_segments(r_.required(node, "segments", "path"), lap);
      lap_m = path_metres(lap);
    }
    if (const Node rate = node["steer_rate_degps"])
      lap.steer_rate_radps = r_.number(rate, "path.steer_rate_degps", 1, 3600) * kDeg;
    drive.path.steer_rate_radps = lap.steer_rate_radps;
    drive.path.segments.push_back(world::Segment::duration(0, 0, wait_s));
    for (std::size_t l = 0; l < std::max<std::size_t>(laps, 1); ++l) {
      if (l > 0 && lap_wait_s > 0)  // standing at the start between laps
        drive.path.segments.push_back(world::Segment::duration(0, 0, lap_wait_s));
      drive.path.segments.insert(drive.path.segments.end(), lap.segments.begin(),
                                 lap.segments.end());
    }
    drive.path.segments.push_back(world::Segment::duration(0, 0, wait_s));
    tour.duration_s = path_seconds(drive.path);
    // The tricycle's own checks (a steering angle beyond the limit, ...).
    world_checked(node,
                  [&] { return world::TricycleSimulator(drive.geometry, drive.path, {}, {}); });
    return {laps, lap_m};
  }
  // path.trajectory: the CSV file's samples, read from the scenario's
  // directory, set the start (or agree with path.start) and become the lap.
  world::Path read_trajectory(const Node& node, const Node& start, world::RoomTour& tour) const {
    r_.check_keys(node, "path.trajectory", {"file"});
    const Node file = r_.required(node, "file", "path.trajectory");
    const std::string name = r_.scalar(file, "path.trajectory.file");
    if (!directory_)
      r_.fail(file,
              "path.trajectory.file: a trajectory file needs a scenario file on disk (this "
              "scenario is a text without a directory: built in, or the fuzzer's)");
    if (name.empty() || name.find('\0') != std::string::npos)
      r_.fail(file, "path.trajectory.file: expected a file name");
    // Only ever opened to be read; a name from the scenario is shown printable.
    const std::filesystem::path path = *directory_ / name;
    const std::string csv = output::printable_excerpt(path.string(), 200);
    std::error_code ec;
    const std::filesystem::file_status status = std::filesystem::status(path, ec);
    if (!std::filesystem::exists(status))
      r_.fail(file, fmt::format("path.trajectory.file: no such file '{}'", csv));
    if (!std::filesystem::is_regular_file(status))  // a FIFO or a device could never end
      r_.fail(file, fmt::format("path.trajectory.file: '{}' is not a regular file", csv));
    if (std::filesystem::file_size(path, ec) > kMaxTrajectoryBytes)
      r_.fail(file, fmt::format("path.trajectory.file: '{}' is over {} MiB", csv,
                                kMaxTrajectoryBytes >> 20));
    const std::optional<std::string> text = read_text(path);
    if (!text)
      r_.fail(file, fmt::format("path.trajectory.file: cannot read '{}'", csv));
    const std::vector<TrajectorySample> samples = read_trajectory_samples(*text, csv);
    const world::Pose first = samples.front().pose;
    world::Pose& set_down = tour.drive.start;
    if (start &&
        (std::hypot(set_down.x_m - first.x_m, set_down.y_m - first.y_m) > kStartToleranceM ||
         std::abs(sw::fuse::wrap_angle(set_down.theta_rad - first.theta_rad)) > kStartToleranceRad))
      r_.fail(start, fmt::format("path.start ({:.6g}, {:.6g}) m, {:.6g} deg is not the "
                                 "trajectory's first sample ({:.6g}, {:.6g}) m, {:.6g} deg "
                                 "({}:{}) within 1 mm and 0.1 degree "
                                 "(leave 'start' out to start there)",
                                 set_down.x_m, set_down.y_m, set_down.theta_rad / kDeg, first.x_m,
                                 first.y_m, first.theta_rad / kDeg, csv, samples.front().line));
    set_down = first;
    return trajectory_path(samples, tour.drive.geometry, tour.acoustics.room, csv);
  }

  void read_segments(const Node& node, world::Path& path) const {
    r_.sequence(node, "path.segments");
    for (const Node& s : node) {
      r_.check_keys(s, "path.segments[]",
                    {"speed_mps", "steer_deg", "distance_m", "duration_s", "steer_to_deg"});
      const int ends =
          (s["distance_m"] ? 1 : 0) + (s["duration_s"] ? 1 : 0) + (s["steer_to_deg"] ? 1 : 0);
      if (ends != 1)
        r_.fail(s, "path.segments[]: exactly one of distance_m, duration_s, steer_to_deg");
      if (const Node to = s["steer_to_deg"]) {
        path.segments.push_back(
            world::Segment::steer_to(r_.number(to, "segment.steer_to_deg", -89, 89) * kDeg));
        continue;
      }
      const double speed = r_.number_or(s, "speed_mps", "segment", 0, -1.5, 1.5);
      const double steer = r_.number_or(s, "steer_deg", "segment", 0, -89, 89) * kDeg;
      if (const Node d = s["distance_m"]) {
        if (speed == 0)
          r_.fail(s, "path.segments[]: a distance needs a speed");
        path.segments.push_back(
            world::Segment::distance(speed, steer, r_.number(d, "segment.distance_m", 0, 1e5)));
      } else {
        path.segments.push_back(world::Segment::duration(
            speed, steer, r_.number(s["duration_s"], "segment.duration_s", 0, 1e5)));
      }
    }
    if (path.segments.empty())
      r_.fail(node, "path.segments: at least one segment");
  }

  Stationary read_stationary(const Node& node, const world::RoomTour& tour) const {
    r_.check_keys(node, "stationary", {"points", "grid"});
    if (!tour.acoustics.room)
      r_.fail(node, "stationary: the points stand in a room (give 'room')");
    const world::Room& room = *tour.acoustics.room;
    Stationary out;
    if (const Node points = node["points"]) {
      r_.sequence(points, "stationary.points");
      for (const Node& p : points) {
        r_.check_keys(p, "stationary.points[]", {"position", "fixes", "paper_sd_mm"});
        StandingPoint standing;
        standing.position = point(r_.required(p, "position", "point"), "point.position");
        if (!(standing.position.x_m > 0 && standing.position.x_m < room.width_m &&
              standing.position.y_m > 0 && standing.position.y_m < room.depth_m))
          r_.fail(p, fmt::format("stationary point ({}, {}) m is outside the room",
                                 standing.position.x_m, standing.position.y_m));
        standing.fixes = r_.whole(r_.required(p, "fixes", "point"), "point.fixes", 2, 100000);
        if (const Node sd = p["paper_sd_mm"]) {
          const std::vector<double> mm = r_.numbers(sd, "point.paper_sd_mm", 2);
          standing.paper_sd_m = world::Vec2{mm[0] / 1000, mm[1] / 1000};
        }
        out.points.push_back(standing);
      }
    }
    if (const Node g = node["grid"]) {
      r_.check_keys(g, "stationary.grid", {"step_m", "margin_m", "fixes", "paper_worst_mm"});
      StandingGrid& grid = out.grid.emplace();
      grid.step_m = r_.number(r_.required(g, "step_m", "stationary.grid"), "grid.step_m", 0.1, 100);
      grid.margin_m = r_.number_or(g, "margin_m", "stationary.grid", 1, 0.05, 100);
      grid.fixes = r_.whole(r_.required(g, "fixes", "stationary.grid"), "grid.fixes", 1, 10000);
      if (const Node w = g["paper_worst_mm"])
        grid.paper_worst_m = r_.number(w, "grid.paper_worst_mm", 0, 1e6) / 1000;
      if (2 * grid.margin_m >= std::min(room.width_m, room.depth_m))
        r_.fail(g, "stationary.grid: the margins leave no floor");
    }
    if (out.points.empty() && !out.grid)
      r_.fail(node, "stationary: at least one point or a grid");
    return out;
  }

  Wheel wheel(const Node& node, std::string_view where, bool both_rear_allowed,
              bool* both_rear) const {
    const std::string w = r_.scalar(node, where);
    if (w == "left_rear")
      return Wheel::kLeftRear;
    if (w == "right_rear")
      return Wheel::kRightRear;
    if (w == "front")
      return Wheel::kFront;
    if (both_rear_allowed && w == "both_rear") {
      *both_rear = true;
      return Wheel::kLeftRear;
    }
    r_.fail(node,
            fmt::format("{}: unknown wheel '{}' (known: left_rear, right_rear, front{})", where,
                        output::printable_excerpt(w), both_rear_allowed ? ", both_rear" : ""));
  }

  void read_disturbances(const Node& node, Laps laps, world::Scenario& drive) const {
    r_.check_keys(node, "disturbances", {"each_lap", "bumps", "slips"});
    const bool each_lap = node["each_lap"] && r_.scalar(node["each_lap"], "each_lap") == "true";
    if (each_lap && laps.count == 0)
      r_.fail(node, "disturbances.each_lap: the path has no laps");
    for (std::size_t l = 0; l < (each_lap ? laps.count : 1); ++l) {
      const double at = static_cast<double>(l) * laps.metres;
      if (const Node bumps = node["bumps"]) {
        r_.sequence(bumps, "disturbances.bumps");
        for (const Node& b : bumps) {
          r_.check_keys(b, "disturbances.bumps[]", {"wheel", "at_m", "height_m", "length_m"});
          bool both = false;
          const Wheel w = wheel(r_.required(b, "wheel", "bump"), "bump.wheel", true, &both);
          const double start = at + r_.number(r_.required(b, "at_m", "bump"), "bump.at_m", 0, 1e5);
          const double height =
              r_.number(r_.required(b, "height_m", "bump"), "bump.height_m", 1e-4, 0.2);
          const double length =
              r_.number(r_.required(b, "length_m", "bump"), "bump.length_m", 0.01, 5);
          const world::Disturbances d = both ? world::bump_under_both_rear(start, height, length)
                                        : w == Wheel::kFront
                                            ? world::bump_under_front(start, height, length)
                                            : world::bump_under_one_rear(w, start, height, length);
          drive.disturbances.bumps.insert(drive.disturbances.bumps.end(), d.bumps.begin(),
                                          d.bumps.end());
        }
      }
      if (const Node slips = node["slips"]) {
        r_.sequence(slips, "disturbances.slips");
        for (const Node& s : slips) {
          r_.check_keys(s, "disturbances.slips[]", {"wheel", "from_m", "to_m", "ratio"});
          world::Slip slip;
          slip.wheel = wheel(r_.required(s, "wheel", "slip"), "slip.wheel", false, nullptr);
          slip.start_m = at + r_.number(r_.required(s, "from_m", "slip"), "slip.from_m", 0, 1e5);
          slip.end_m = at + r_.number(r_.required(s, "to_m", "slip"), "slip.to_m", 0, 1e5);
          slip.ratio = r_.number(r_.required(s, "ratio", "slip"), "slip.ratio", -0.9, 10);
          if (slip.end_m <= slip.start_m)
            r_.fail(s, "disturbances.slips[]: to_m must be beyond from_m");
          drive.disturbances.slips.push_back(slip);
        }
      }
    }
    // The tricycle's own checks (a bump too sharp for its wheel, ...).
    world_checked(node, [&] {
      return world::TricycleSimulator(drive.geometry, drive.path, drive.disturbances, {});
    });
  }

  void read_survey(const Node& node, const world::RoomTour& tour, Survey& survey) const {
    r_.check_keys(node, "survey",
                  {"beacons", "beacon_height_m", "temperature_c", "envelope_tau_s", "path_jitter_s",
                   "receiver_jitter_s", "station", "start", "thamma"});
    if (tour.timing.beacon_count > 0 || node["beacons"]) {
      const Node beacons = r_.required(node, "beacons", "survey");
      r_.sequence(beacons, "survey.beacons");
      for (const Node& b : beacons)
        survey.beacons.push_back(point(b, "survey.beacons[]"));
      if (survey.beacons.size() != tour.timing.beacon_count)
        r_.fail(beacons, fmt::format("survey.beacons: {} positions for {} beacons",
                                     survey.beacons.size(), tour.timing.beacon_count));
    }
    if (const Node start = node["start"]) {
      r_.check_keys(start, "survey.start", {"sd_m", "heading_sd_deg"});
      survey.start = SurveyedStart{
          .sd_m = r_.number(r_.required(start, "sd_m", "survey.start"), "sd_m", 1e-6, 10),
          .heading_sd_rad = r_.number(r_.required(start, "heading_sd_deg", "survey.start"),
                                      "heading_sd_deg", 1e-6, 180) *
                            kDeg};
    } else if (tour.timing.beacon_count == 0 && !tour.thamma) {
      r_.fail(node,
              "survey: missing 'start' (without beacons the filter starts on the start mark)");
    }
    const Node thamma = node["thamma"];
    if (static_cast<bool>(thamma) != tour.thamma.has_value())
      r_.fail(thamma ? thamma : node,
              tour.thamma ? "survey: missing 'thamma' (the scenario has Thamma's stations)"
                          : "survey.thamma: the scenario has no Thamma stations");
    if (thamma) {
      r_.check_keys(thamma, "survey.thamma", {"stations", "delay_s", "head", "tail"});
      SurveyedThamma& s = survey.thamma.emplace();
      const Node stations = r_.required(thamma, "stations", "survey.thamma");
      r_.sequence(stations, "survey.thamma.stations");
      for (const Node& p : stations)
        s.stations.push_back(point(p, "survey.thamma.stations[]"));
      if (s.stations.size() != tour.acoustics.beacons.size())
        r_.fail(stations, fmt::format("survey.thamma.stations: {} positions for {} stations",
                                      s.stations.size(), tour.acoustics.beacons.size()));
      s.delay_s = r_.number_or(thamma, "delay_s", "survey.thamma", 100e-6, 0, 0.1);
      s.head = point(r_.required(thamma, "head", "survey.thamma"), "survey.thamma.head");
      s.tail = point(r_.required(thamma, "tail", "survey.thamma"), "survey.thamma.tail");
    }
    survey.beacon_height_m = r_.number_or(node, "beacon_height_m", "survey", 0, 0, 100);
    survey.temperature_c = r_.number_or(node, "temperature_c", "survey", 20, -40, 60);
    survey.envelope_tau_s = r_.number_or(node, "envelope_tau_s", "survey", 0.5e-3, 1e-6, 0.1);
    survey.path_jitter_s = r_.number_or(node, "path_jitter_s", "survey", 0, 0, 1e-3);
    survey.receiver_jitter_s = r_.number_or(node, "receiver_jitter_s", "survey", 0, 0, 1e-3);
    const Node station = node["station"];
    if (static_cast<bool>(station) != tour.station.has_value())
      r_.fail(station ? station : node, tour.station
                                            ? "survey: missing 'station' (the scenario has one)"
                                            : "survey.station: the scenario has no station");
    if (station) {
      r_.check_keys(
          station, "survey.station",
          {"position", "t0_s", "station_laser_start_deg", "robot_laser_start_deg", "max_range_m"});
      SurveyedStation& s = survey.station.emplace();
      s.position =
          point(r_.required(station, "position", "survey.station"), "survey.station.position");
      s.t0_s = r_.number_or(station, "t0_s", "survey.station", 0, 0, 1);
      s.station_laser_start_rad =
          r_.number(r_.required(station, "station_laser_start_deg", "survey.station"),
                    "station_laser_start_deg", -360, 360) *
          kDeg;
      s.robot_laser_start_rad =
          r_.number(r_.required(station, "robot_laser_start_deg", "survey.station"),
                    "robot_laser_start_deg", -360, 360) *
          kDeg;
      s.max_range_m =
          r_.number_or(station, "max_range_m", "survey.station", s.max_range_m, 1, 1000);
    }
  }

  // Liu et al.'s settings (mm^2 and degrees, as the paper prints them).
  void read_liu_filter(const Node& node, const world::RoomTour& tour, Survey& survey) const {
    if (!tour.station)
      r_.fail(node, "liu_filter: Liu's filter needs the 'station'");
    r_.check_keys(node, "liu_filter",
                  {"q_mm2", "r_mm2", "p0_mm2", "fix_gate_mm", "heading_gate_deg",
                   "odometry_heading_var_deg2", "laser_heading_var_deg2"});
    sw::fuse::LiuFilterOptions& o = survey.liu_filter.emplace();
    const auto mm2 = [&](const char* key, double& m2) {
      m2 = r_.number_or(node, key, "liu_filter", m2 * 1e6, 1e-6, 1e9) * 1e-6;
    };
    const auto deg2 = [&](const char* key, double& rad2) {
      rad2 = r_.number_or(node, key, "liu_filter", rad2 / (kDeg * kDeg), 1e-9, 1e4) * kDeg * kDeg;
    };
    mm2("q_mm2", o.process_var_m2);
    mm2("r_mm2", o.fix_var_m2);
    mm2("p0_mm2", o.initial_var_m2);
    o.fix_gate_m =
        r_.number_or(node, "fix_gate_mm", "liu_filter", o.fix_gate_m * 1e3, 1e-3, 1e6) * 1e-3;
    o.heading_gate_rad =
        r_.number_or(node, "heading_gate_deg", "liu_filter", o.heading_gate_rad / kDeg, 1e-6, 180) *
        kDeg;
    deg2("odometry_heading_var_deg2", o.odometry_heading_var_rad2);
    deg2("laser_heading_var_deg2", o.laser_heading_var_rad2);
  }

  // Everything that stands in the room stands inside it.
  void check_inside(const Node& root, const world::RoomTour& tour) const {
    const std::optional<world::Room>& room = tour.acoustics.room;
    if (!room)
      return;
    const auto inside = [&](Vec2 p) {
      return p.x_m >= 0 && p.x_m <= room->width_m && p.y_m >= 0 && p.y_m <= room->depth_m;
    };
    for (std::size_t i = 0; i < tour.acoustics.beacons.size(); ++i)
      if (!inside(tour.acoustics.beacons[i].position))
        r_.fail(tour.thamma                    ? root["thamma"]["stations"][i]
                : i < tour.timing.beacon_count ? root["beacons"]["list"][i]
                                               : root["station"],
                fmt::format("{} at ({}, {}) m is outside the {} x {} m room",
                            tour.thamma                    ? fmt::format("station {}", i)
                            : i < tour.timing.beacon_count ? fmt::format("beacon {}", i)
                                                           : std::string("the station"),
                            tour.acoustics.beacons[i].position.x_m,
                            tour.acoustics.beacons[i].position.y_m, room->width_m, room->depth_m));
    if (root["stationary"])
      return;  // read_stationary checked its points
    const world::Pose& start = tour.drive.start;
    if (!inside({start.x_m, start.y_m}))
      r_.fail(root["path"]["start"],
              fmt::format("path.start ({}, {}) m is outside the room", start.x_m, start.y_m));
  }

  yaml::Reader r_;
  ScenarioOverrides overrides_;
  // Where the files a scenario names are read from; none for a text.
  std::optional<std::filesystem::path> directory_;
};

}  // namespace

std::vector<world::Vec2> grid_points(const world::Room& room, const StandingGrid& grid) {
  // Counted, not accumulated: no point lost to a rounding of the step.
  const auto count = [&](double side_m) {
    return static_cast<int>(std::floor((side_m - 2 * grid.margin_m) / grid.step_m + 1e-9)) + 1;
  };
  std::vector<world::Vec2> points;
  for (int j = 0; j < count(room.depth_m); ++j)
    for (int i = 0; i < count(room.width_m); ++i)
      points.push_back({grid.margin_m + i * grid.step_m, grid.margin_m + j * grid.step_m});
  return points;
}

Scenario parse_scenario(const std::string& text, std::string_view file,
                        const ScenarioOverrides& overrides,
                        const std::optional<std::filesystem::path>& directory) {
  if (overrides.laps && (*overrides.laps < 1 || *overrides.laps > 100))
    throw yaml::InputError("--laps must be 1 to 100");
  if (overrides.speed_mps && !(*overrides.speed_mps > 0 && *overrides.speed_mps <= 1.5))
    throw yaml::InputError("--speed must be in (0, 1.5] m/s");
  return ScenarioReader(file, overrides, directory).read(text);
}

Scenario load_scenario(const std::filesystem::path& path, const ScenarioOverrides& overrides) {
  const std::optional<std::string> text = read_text(path);
  if (!text)
    throw yaml::InputError(
        fmt::format("{}: cannot read the scenario", output::printable_excerpt(path.string(), 200)),
        false);
  return parse_scenario(*text, path.string(), overrides, path.parent_path());
}

const BuiltinScenario* find_builtin_scenario(std::string_view key) {
  for (const BuiltinScenario& s : builtin_scenarios())
    if (s.key == key)
      return &s;
  return nullptr;
}

Scenario default_scenario(const ScenarioOverrides& overrides) {
  const BuiltinScenario* s = find_builtin_scenario(kDefaultScenario);
  return parse_scenario(std::string(s->text), fmt::format("{} (built in)", s->key), overrides);
}

}  // namespace odoloc::sim
