// Thamma's ranging cycle on the SoC
// (soc_software/tof/include/odoloc/sw/thamma_cycle.hpp): synthetic capture
// batches of the stations' triggers and the boxes' envelope pulses, stamped
// as the capture unit stamps them. Each station's time of flight comes back
// within the ticks' quantisation, framed on the cycle gap, whatever the
// batches' boundaries; lost edges leave their places empty.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "odoloc/sw/thamma_cycle.hpp"

namespace {

using namespace odoloc::sw::tof;

constexpr double kDelay = 100e-6;  // t: trigger to sound
constexpr double kFirst = 1.0;     // the first cycle's first trigger

ThammaConfig measure_config() {
  ThammaConfig c;
  c.fixed_delay_s = kDelay;
  c.envelope.burst_s = 1e-3;
  return c;
}

// Station s, repeat r of cycle k: its trigger, and the flight to the box
// tuned to its carrier (stations 0, 1: the head, channels 0-3; 2, 3: the
// tail, 4-7), a little longer each cycle (the robot drives away).
struct World {
  ThammaSchedule schedule;
  ThammaConfig measure = measure_config();
  Timebase timebase{.prescale = 1};  // 25 MHz
  std::vector<double> flight_s = {0.004, 0.011, 0.017, 0.023};

  [[nodiscard]] double trigger_s(int cycle, int station, int repeat) const {
    return kFirst + cycle * schedule.cycle_s() +
           (station * schedule.repeats + repeat) * schedule.period_s;
  }
  [[nodiscard]] double flight(int cycle, int station) const {
    return flight_s[static_cast<std::size_t>(station)] + 1e-4 * cycle;
  }
  [[nodiscard]] Tick tick_of(double t) const {  // Timebase::edge_time_s inverted
    return static_cast<Tick>(
        std::llround((t * timebase.fabric_clock_hz + 0.5 + timebase.input_latency_clocks) /
                         (timebase.prescale + 1.0) -
                     0.5));
  }
  // Every edge and pulse of `cycles` cycles, cut into batches read every
  // read_every_s from read_from_s on.
  [[nodiscard]] std::vector<CaptureBatch> batches(int cycles, double read_every_s,
                                                  const std::vector<double>& lost = {}) const {
    struct Edge {
      double t;
      int channel;  // -1: sync
      std::uint32_t width = 0;
    };
    std::vector<Edge> edges;
    const EnvelopeModel& e = measure.envelope;
    const double ratio = 20;
    for (int k = 0; k < cycles; ++k)
      for (int s = 0; s < schedule.stations; ++s)
        for (int r = 0; r < schedule.repeats; ++r) {
          const double t = trigger_s(k, s, r);
          bool gone = false;
          for (const double l : lost)
            gone = gone || std::abs(l - t) < 1e-9;
          if (!gone)
            edges.push_back({t, -1});
          const int first = s < 2 ? 0 : 4;
          const auto width = static_cast<std::uint32_t>(
              std::llround(e.width_s(ratio) * timebase.fabric_clock_hz / (timebase.prescale + 1)));
          for (int c = first; c < first + 2; ++c)  // two receivers face it, 0.1 mm apart
            edges.push_back(
                {t + kDelay + flight(k, s) + 1e-4 / 343.2 * (c - first) + e.crossing_delay_s(ratio),
                 c, width});
        }
    std::vector<CaptureBatch> out;
    const double end = kFirst + cycles * schedule.cycle_s() + 0.2;
    for (double read = 0.5; read < end + read_every_s; read += read_every_s) {
      CaptureBatch b;
      b.timebase = timebase;
      b.read_tick = tick_of(read);
      b.channels.resize(8);
      for (const Edge& x : edges) {
        // An envelope entry exists from its fall on.
        const double ready = x.t + x.width * timebase.tick_s();
        if (ready > read || ready <= read - read_every_s)
          continue;
        if (x.channel < 0)
          b.sync.push_back(tick_of(x.t));
        else
          b.channels[static_cast<std::size_t>(x.channel)].envelope.push_back(
              {tick_of(x.t), x.width});
      }
      out.push_back(std::move(b));
    }
    return out;
  }
};

std::vector<ThammaCycle> run(const World& w, const std::vector<CaptureBatch>& batches) {
  ThammaCycleDecoder decoder(w.measure, w.schedule);
  std::vector<ThammaCycle> cycles;
  for (const CaptureBatch& b : batches)
    for (ThammaCycle& c : decoder.push(b))
      cycles.push_back(std::move(c));
  return cycles;
}

void expect_flights(const World& w, const std::vector<ThammaCycle>& cycles, int count) {
  ASSERT_EQ(static_cast<int>(cycles.size()), count);
  for (int k = 0; k < count; ++k) {
    const ThammaCycle& c = cycles[static_cast<std::size_t>(k)];
    EXPECT_NEAR(c.time_s, w.trigger_s(k, 0, 0), 1e-6) << k;
    for (int s = 0; s < w.schedule.stations; ++s) {
      const std::size_t box = s < 2 ? 0 : 1;
      const ThammaBoxResult& r = c.per_station[static_cast<std::size_t>(s)].boxes[box];
      // Two ticks of 40 ns (the rise and the width) at most.
      EXPECT_NEAR(r.tof_s, w.flight(k, s), 80e-9) << k << " " << s;
      EXPECT_NEAR(c.station_time_s[static_cast<std::size_t>(s)],
                  (w.trigger_s(k, s, 0) + w.trigger_s(k, s, w.schedule.repeats - 1)) / 2, 1e-6);
    }
  }
}

TEST(ThammaCycle, EachStationsFlightFramedOnTheGap) {
  const World w;
  expect_flights(w, run(w, w.batches(3, 0.05)), 3);
}

TEST(ThammaCycle, TheBatchesBoundariesDoNotMatter) {
  const World w;
  for (const double every : {0.013, 0.05, 0.3, 0.9})
    expect_flights(w, run(w, w.batches(3, every)), 3);
}

// A lost edge leaves its place empty: the station's burst is measured from
// the other three (kSyncMissing); a lost first edge of a later cycle is
// where the schedule puts it.
TEST(ThammaCycle, LostEdgesLeaveTheirPlacesEmpty) {
  const World w;
  const std::vector<ThammaCycle> cycles =
      run(w, w.batches(3, 0.05, {w.trigger_s(0, 1, 2), w.trigger_s(1, 0, 0)}));
  ASSERT_EQ(cycles.size(), 3U);
  const ThammaMeasurement& m = cycles[0].per_station[1];
  EXPECT_TRUE(m.flags.has(Flag::kSyncMissing));
  EXPECT_EQ(m.boxes[0].used, 3);
  EXPECT_NEAR(m.boxes[0].tof_s, w.flight(0, 1), 80e-9);
  EXPECT_TRUE(cycles[1].per_station[0].flags.has(Flag::kSyncMissing));
  EXPECT_NEAR(cycles[1].time_s, w.trigger_s(1, 0, 0), 1e-6);
  EXPECT_NEAR(cycles[1].per_station[3].boxes[1].tof_s, w.flight(1, 3), 80e-9);
  EXPECT_NEAR(cycles[2].time_s, w.trigger_s(2, 0, 0), 1e-6);
}

// Edges without a gap before them (the decoder started mid-cycle) frame
// nothing: the first full cycle is the one after the next gap.
TEST(ThammaCycle, StartedMidCycleItWaitsForTheGap) {
  World w;
  std::vector<CaptureBatch> batches = w.batches(3, 0.05);
  // The driver's first read is in the middle of the first cycle.
  std::erase_if(batches, [&](const CaptureBatch& b) {
    return w.timebase.edge_time_s(b.read_tick, 0) < kFirst + 0.6;
  });
  const std::vector<ThammaCycle> cycles = run(w, batches);
  ASSERT_EQ(cycles.size(), 2U);
  EXPECT_NEAR(cycles[0].time_s, w.trigger_s(1, 0, 0), 1e-6);
}

TEST(ThammaCycle, BadSchedulesAreRefused) {
  const auto refused = [](auto edit) {
    World w;
    edit(w);
    EXPECT_THROW(ThammaCycleDecoder(w.measure, w.schedule), std::invalid_argument);
  };
  refused([](World& w) { w.schedule.cycle_gap_s = 0.04; });  // no frame
  refused([](World& w) { w.schedule.repeats = 3; });         // measure.repeats is 4
  refused([](World& w) { w.measure.max_tof_s = 0.2; });      // past the next trigger
  refused([](World& w) { w.schedule.stations = 0; });
  refused([](World& w) { w.schedule.place_tolerance_s = 0.05; });
}

}  // namespace
