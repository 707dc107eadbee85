#include "odoloc/sim/system.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>
#include <vector>

#include "odoloc/board/beacon_ranges.hpp"
#include "odoloc/board/chip_link.hpp"
#include "odoloc/board/world_stimulus.hpp"
#include "odoloc/process/run_program.hpp"
#include "odoloc/regs.hpp"
#include "odoloc/sw/spi_frame.hpp"

namespace odoloc::sim {

namespace {

constexpr double kClockHz = regs::kFabricClockHz;

// The tricycle's trajectory for the acoustic world, every 1 ms; the
// physics steps 100 us at a time (the chip's truth steps 10 us: both
// integrate the same arcs, docs/tricycle-simulator.md).
// A signal while the system is built ends the construction too: the
// pre-pass and the chip's world take seconds (more under the sanitizers).
void check_stop(const std::atomic<bool>* stop) {
  if (stop != nullptr && stop->load())
    throw process::Interrupted();
}

world::Trajectory prepass(const world::Scenario& drive, double end_s,
                          const std::atomic<bool>* stop) {
  world::Options options;
  options.start = drive.start;
  options.clocks_per_step = 5000;
  options.record_every_steps = 10;
  world::TricycleSimulator truth(drive.geometry, drive.path, drive.disturbances, options);
  const auto end_clock = static_cast<std::uint64_t>(std::ceil(end_s * kClockHz));
  while (!truth.done() && truth.clock() < end_clock) {
    check_stop(stop);
    truth.tick();
    truth.skip(truth.hold_ticks());
  }
  std::vector<world::TrajectorySample> samples = truth.trajectory();
  if (samples.back().truth.time_s < truth.pose().time_s)  // the last, cut short
    samples.push_back({truth.pose(), {}});
  return world::interpolate(std::move(samples));
}

// Thamma's stations and boxes as the SoC is told them: the surveyed
// places, the controller's protocol (repeats, period, gap: the stations'
// data), the calibrated delay t and envelope, the boxes' drawing (120 x 80
// mm, a receiver on each side: head channels 0-3 at 40 kHz, tail 4-7 at
// 32.5 kHz).
sw::LocaliserConfig::Thamma thamma_config(const world::ThammaStations& stations,
                                          const SurveyedThamma& surveyed, const Survey& survey,
                                          double speed_of_sound_mps) {
  sw::LocaliserConfig::Thamma t;
  t.measure.fixed_delay_s = surveyed.delay_s;
  t.measure.repeats = stations.timing.repeats;
  t.measure.envelope.rise_s = survey.envelope_tau_s;
  t.measure.envelope.fall_s = survey.envelope_tau_s;
  t.measure.envelope.burst_s = stations.timing.pulse_s;
  t.measure.speed_of_sound_mps = speed_of_sound_mps;
  t.measure.timing_sd_s = std::hypot(survey.path_jitter_s, survey.receiver_jitter_s);
  t.schedule.stations = static_cast<int>(surveyed.stations.size());
  t.schedule.repeats = static_cast<int>(stations.timing.repeats);
  t.schedule.period_s = stations.timing.period_s;
  t.schedule.cycle_gap_s = stations.timing.cycle_gap_s;
  for (const world::Vec2& s : surveyed.stations)
    t.stations.beacons.push_back({{s.x_m, s.y_m}, 0});
  t.body.head_m = {surveyed.head.x_m, surveyed.head.y_m};
  t.body.tail_m = {surveyed.tail.x_m, surveyed.tail.y_m};
  for (const world::Receiver& r : world::thamma_boxes(surveyed.head, surveyed.tail))
    t.body.receivers.receivers.push_back({{r.position.x_m, r.position.y_m}, r.axis_rad});
  return t;
}

// What the SoC software is told about the world (the scenario's survey,
// docs/scenarios.md): the vehicle's nominal geometry, the start mark, the
// capture channels wired, the beacons' surveyed positions and the
// controller's timing, the air's speed of sound (a thermometer's), and the
// capture chain's residual error with the turbulence as calibrated (path
// jitter x c, added to 1 mm).
sw::LocaliserConfig soc_config(const world::RoomTour& tour, const Survey& survey,
                               const SystemOptions& options) {
  sw::LocaliserConfig c;
  c.fuse_beacon_ranges = options.fuse_beacon_ranges;
  c.vehicle = board::nominal_geometry(tour.drive.geometry);
  c.min_select = sw::min_select_setup(c.vehicle);
  c.start_pose = {tour.drive.start.x_m, tour.drive.start.y_m, tour.drive.start.theta_rad};
  if (survey.start)
    c.start_covariance =
        sw::fuse::Vector3(survey.start->sd_m * survey.start->sd_m,
                          survey.start->sd_m * survey.start->sd_m,
                          survey.start->heading_sd_rad * survey.start->heading_sd_rad)
            .asDiagonal();
  c.liu_filter = survey.liu_filter;
  for (std::size_t i = 0; i < tour.acoustics.receivers.size(); ++i)
    c.capture.channels.at(i).enabled = true;
  const double speed_of_sound_mps =
      world::Air{.temperature_c = survey.temperature_c}.speed_of_sound_mps();
  c.kleeman =
      board::kleeman_config(tour.timing, survey.beacons, survey.envelope_tau_s, speed_of_sound_mps);
  c.kleeman.timing_sd_s = std::hypot(survey.path_jitter_s, survey.receiver_jitter_s);
  for (const world::Vec2& b : survey.beacons)
    c.layout.beacons.push_back({{b.x_m, b.y_m}, survey.beacon_height_m});
  c.ekf.history_s = 3.0;
  c.ekf.odometry.along_sd_per_sqrt_m = 0.003;
  c.ekf.odometry.across_sd_per_sqrt_m = 0.001;
  c.ekf.odometry.heading_sd_per_sqrt_m = 0.001;
  c.ekf.odometry.heading_sd_per_sqrt_rad = 0.005;
  const double turbulence_m = survey.path_jitter_s * speed_of_sound_mps;
  c.chain_sd_m = std::hypot(0.001, turbulence_m);
  if (survey.station && tour.station) {
    // Surveyed and calibrated: the station's place, its t0, the lasers'
    // encoder indices (and their encoders' counts, the devices' data).
    const SurveyedStation& st = *survey.station;
    sw::station::StationConfig& sc = c.station.emplace();
    sc.position_m = {st.position.x_m, st.position.y_m};
    sc.height_m = survey.beacon_height_m;
    sc.t0_s = st.t0_s;
    sc.station_laser = {st.station_laser_start_rad, tour.station->station_laser.counts_per_rev};
    sc.robot_laser = {st.robot_laser_start_rad, tour.station->robot_laser.counts_per_rev};
    sc.chain_sd_m = c.chain_sd_m;
    sc.max_range_m = st.max_range_m;
    // The station's protocol: its next slot after its turnaround.
    sc.ranging_after_alpha_s =
        tour.timing.cycle_s() + tour.station->request_margin_s + tour.station->rf_spacing_s;
    c.capture.sync_enable = true;
  }
  if (survey.thamma && tour.thamma) {
    c.thamma = thamma_config(*tour.thamma, *survey.thamma, survey, speed_of_sound_mps);
    // A range is no better than the capture chain (as the beacons' ranges).
    c.thamma->pose.fix.min_sd_m = c.chain_sd_m;
    // Thamma averages four repeats; a range heard in fewer than half of
    // them is noise or an echo more often than the burst.
    c.thamma->pose.min_repeats = static_cast<int>((tour.thamma->timing.repeats + 1) / 2);
  }
  if (c.thamma) {
    c.capture.sync_enable = true;
    // Thamma counts at 20 MHz; the capture unit divides the fabric's 50 MHz
    // by an integer: 25 MHz (40 ns) is the nearest at least as fine.
    c.capture.timebase.prescale = 1;
  }
  return c;
}

sw::station::ReportKind kind_of(world::StationReportKind kind) {
  switch (kind) {
    case world::StationReportKind::kStationSawRobot:
      return sw::station::ReportKind::kStationSawRobot;
    case world::StationReportKind::kRobotSawStation:
      return sw::station::ReportKind::kRobotSawStation;
    case world::StationReportKind::kRanging:
      break;
  }
  return sw::station::ReportKind::kRanging;
}

// The base station's RF packets as the robot's radio hands them over: each
// one once simulated time has reached its strobe.
class StationRadio final : public sw::station::Link {
 public:
  explicit StationRadio(std::vector<world::StationReport> reports) : reports_(std::move(reports)) {}
  void advance_to(double time_s) { now_s_ = time_s; }
  std::optional<sw::station::Report> receive() override {
    if (next_ >= reports_.size() || reports_[next_].strobe_s > now_s_)
      return std::nullopt;
    const world::StationReport& r = reports_[next_++];
    return sw::station::Report{kind_of(r.kind), r.count};
  }

 private:
  std::vector<world::StationReport> reports_;
  std::size_t next_ = 0;
  double now_s_ = 0;
};

}  // namespace

// The chip and everything on its pins, in construction order.
class LocalisationSystem::Chip {
 public:
  Chip(const world::RoomTour& tour, const Survey& survey, const world::Trajectory& trajectory,
       const world::StationPlan& plan, const SystemOptions& options)
      : acoustic_run_(world::simulate(tour.acoustics, tour.schedule(plan), trajectory,
                                      tour.duration_s, options.seed)),
        truth_(tour.drive.geometry, tour.drive.path, tour.drive.disturbances,
               world::Options{.start = tour.drive.start}),
        pins_(acoustic_run_, world::ComparatorKind::kEnvelope, kClockHz),
        stimulus_(&truth_, &pins_),
        link_({.half_period = 4}, stimulus_),
        bus_(link_, {.crc = true, .confirm_writes = true}),
        radio_(plan.reports),
        localiser_((link_.set_cycle_step(options.cycle_step), bus_),
                   soc_config(tour, survey, options), &radio_) {}

  world::AcousticRun acoustic_run_;
  world::TricycleSimulator truth_;
  world::AcousticPins pins_;
  board::WorldStimulus stimulus_;
  board::ChipLink link_;
  sw::SpiRegisterBus bus_;
  StationRadio radio_;
  sw::Localiser localiser_;
};

LocalisationSystem::LocalisationSystem(Scenario scenario, const SystemOptions& options)
    : tour_(std::move(scenario.tour)), survey_(std::move(scenario.survey)), options_(options) {
  if (options_.until_s < 0 || !std::isfinite(options_.until_s))
    throw std::invalid_argument("until_s must be >= 0 s");
  if (options_.until_s > 0 && options_.until_s < tour_.duration_s) {
    tour_.duration_s = options_.until_s;
    cut_short_ = true;
  }
  if (!(options_.step_s >= 1e-3 && options_.step_s <= 0.1))
    throw std::invalid_argument("the SoC loop's period must be in [1 ms, 100 ms]");
  if (!(options_.encoder_period_s >= options_.step_s && options_.encoder_period_s <= 10))
    throw std::invalid_argument("the encoder read period must be in [the step, 10 s]");
  const auto reference_run = [drive = tour_.drive, end = tour_.duration_s,
                              stop = options_.stop](rtl::MinSelectPolicy policy) {
    return board::run_scenario(drive, {.policy = policy,
                                       .tuning = board::MinSelectTuning::kVehicle,
                                       .record_every_clocks = 500'000,
                                       .cycle_step = false,
                                       .max_seconds = end,
                                       .stop = stop});
  };
  rear_future_ = std::async(std::launch::async, reference_run, rtl::MinSelectPolicy::kRearOnly);
  front_future_ = std::async(std::launch::async, reference_run, rtl::MinSelectPolicy::kFrontOnly);
  trajectory_ = prepass(tour_.drive, tour_.duration_s, options_.stop);
  check_stop(options_.stop);
  const auto plan = tour_.station_plan(trajectory_);
  check_stop(options_.stop);
  chip_ = std::make_unique<Chip>(tour_, survey_, trajectory_, plan, options_);
}

LocalisationSystem::~LocalisationSystem() = default;

bool LocalisationSystem::done() const {
  return time_s() >= tour_.duration_s;
}

Frame LocalisationSystem::step() {
  ++steps_;
  const auto target = static_cast<std::uint64_t>(
      std::llround(static_cast<double>(steps_) * options_.step_s * kClockHz));
  board::ChipLink& link = chip_->link_;
  if (target > link.clocks())
    link.advance(target - link.clocks());
  chip_->radio_.advance_to(static_cast<double>(link.clocks()) / kClockHz);
  Frame f;
  f.soc = chip_->localiser_.step();
  f.clocks = link.clocks();
  f.time_s = static_cast<double>(f.clocks) / kClockHz;
  f.truth = chip_->truth_.pose().pose;
  if (steps_ == 1)
    soc_offset_s_ = f.time_s - f.soc.time_s;
  const auto encoder_steps = std::max<std::uint64_t>(
      1, static_cast<std::uint64_t>(std::llround(options_.encoder_period_s / options_.step_s)));
  if (steps_ % encoder_steps == 0)
    f.encoders = read_encoders(chip_->bus_);
  return f;
}

std::array<EncoderRead, 4> LocalisationSystem::read_encoders(sw::RegisterBus& bus) {
  std::array<EncoderRead, 4> encoders{};
  // Per encoder module one burst from count to status (six words).
  namespace eppm = regs::eppm;
  for (unsigned i = 0; i < eppm::kInstances; ++i) {
    const std::uint16_t first = eppm::count::address(i);
    std::array<std::uint32_t, eppm::status::kOffset - eppm::count::kOffset + 1> words{};
    bus.read(first, words);
    const auto word = [&](std::uint16_t address) { return words[address - first]; };
    const std::uint32_t speed = word(eppm::speed::address(i));
    encoders[i] = {.count = eppm::count::value.get_signed(word(first)),
                   .speed = eppm::speed::value.get_signed(speed),
                   .pulse_mode = eppm::speed::mode.get(speed) != 0,
                   .valid = eppm::speed::valid.get(speed) != 0,
                   .stalled = eppm::speed::stalled.get(speed) != 0,
                   .forward = eppm::status::forward.get(word(eppm::status::address(i))) != 0};
  }
  return encoders;
}

sw::RegisterBus& LocalisationSystem::bus() {
  return chip_->bus_;
}
const sw::Localiser& LocalisationSystem::localiser() const {
  return chip_->localiser_;
}
std::uint64_t LocalisationSystem::clocks() const {
  return chip_->link_.clocks();
}
std::uint64_t LocalisationSystem::skipped_clocks() const {
  return chip_->link_.skipped_clocks();
}
double LocalisationSystem::time_s() const {
  return static_cast<double>(clocks()) / kClockHz;
}

world::Pose LocalisationSystem::truth_at(double time_s) const {
  return trajectory_(time_s);
}

double LocalisationSystem::to_sim_time(double soc_time_s) const {
  return soc_time_s + soc_offset_s_;
}

const board::RunResult& LocalisationSystem::reference(rtl::MinSelectPolicy policy) {
  std::unique_ptr<board::RunResult>& result =
      policy == rtl::MinSelectPolicy::kRearOnly ? rear_ : front_;
  std::future<board::RunResult>& future =
      policy == rtl::MinSelectPolicy::kRearOnly ? rear_future_ : front_future_;
  if (policy != rtl::MinSelectPolicy::kRearOnly && policy != rtl::MinSelectPolicy::kFrontOnly)
    throw std::invalid_argument("reference runs are rear-only and front-only");
  if (!result)
    result = std::make_unique<board::RunResult>(future.get());
  return *result;
}

}  // namespace odoloc::sim
