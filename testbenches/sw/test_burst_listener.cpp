// Liu's ranging burst heard from capture batches
// (soc_software/station/include/odoloc/sw/burst_listener.hpp): synthetic
// envelope pulses of a plane wave on Kleeman's octagon, stamped as the
// capture unit stamps them; the wavefront's time at the robot origin comes
// back within the ticks' quantisation, whatever noise, echoes, batches and
// incidents surround it.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "odoloc/sw/burst_listener.hpp"

namespace {

using namespace odoloc::sw;
using station::BurstListener;
using station::BurstListenerConfig;
using station::BurstStatus;

constexpr double kC = 343.2;

struct Scene {
  BurstListenerConfig config;
  tof::Timebase timebase;  // 20 ns ticks
  std::vector<std::vector<tof::EnvelopeEvent>> events =
      std::vector<std::vector<tof::EnvelopeEvent>>(8);

  // The tick the capture unit stamps for an edge at the pin at t_s
  // (tof::Timebase::edge_time_s inverted).
  [[nodiscard]] tof::Tick tick_of(double t_s) const {
    return static_cast<tof::Tick>(
        std::llround(t_s * timebase.fabric_clock_hz + timebase.input_latency_clocks));
  }
  // A pulse of amplitude ratio A/V arriving at channel's receiver at t_s:
  // the comparator rises the crossing delay later and stays high w(A/V).
  void pulse(int channel, double t_s, double ratio = 20) {
    const tof::EnvelopeModel& e = config.envelope;
    events[static_cast<std::size_t>(channel)].push_back(
        {tick_of(t_s + e.crossing_delay_s(ratio)),
         static_cast<std::uint32_t>(std::llround(e.width_s(ratio) * timebase.fabric_clock_hz))});
  }
  // A plane wave from bearing_rad (robot frame) passing the origin at t0_s,
  // heard by the receivers facing within 60 degrees of it.
  void wavefront(double t0_s, double bearing_rad) {
    const tof::Vec2 u{std::cos(bearing_rad), std::sin(bearing_rad)};
    for (int i = 0; i < 8; ++i) {
      const tof::Receiver& r = config.array.receivers[static_cast<std::size_t>(i)];
      if (std::cos(r.axis_rad - bearing_rad) < std::cos(std::numbers::pi / 3))
        continue;
      pulse(i, t0_s - (r.position_m.x * u.x + r.position_m.y * u.y) / kC);
    }
  }
  // The events so far as one batch read at read_s; cleared.
  tof::CaptureBatch batch(double read_s) {
    tof::CaptureBatch b;
    b.timebase = timebase;
    b.read_tick = tick_of(read_s);
    for (auto& ev : events) {
      b.channels.push_back({.mode = tof::ChannelMode::kEnvelope, .envelope = ev, .carrier = {}});
      ev.clear();
    }
    return b;
  }
};

constexpr double kSent = 1.0;
const double kT0 = kSent + 10.0 / kC;  // 10 m away

TEST(BurstListener, HearsTheWavefrontAtTheRobotOrigin) {
  for (const double bearing : {0.0, 0.4, 2.0, -2.9}) {
    Scene s;
    s.config.speed_of_sound_mps = kC;
    s.wavefront(kT0, bearing);
    BurstListener l(s.config);
    l.push(s.batch(1.1));
    const station::BurstResult r = l.listen(kSent);
    ASSERT_EQ(r.status, BurstStatus::kHeard) << bearing;
    // Each stamp is within 10 ns (half a tick); the fit averages them.
    EXPECT_NEAR(r.burst.arrival_s, kT0, 30e-9) << bearing;
    EXPECT_GT(r.burst.sd_s, 0);
    EXPECT_GE(std::popcount(r.burst.receivers), 2);
  }
}

TEST(BurstListener, PendingUntilTheWindowHasBeenRead) {
  Scene s;
  s.config.speed_of_sound_mps = kC;
  s.wavefront(kT0, 0.3);
  BurstListener l(s.config);
  // The window ends 15 m / c after the burst left; a pulse may still be
  // high for the longest burst width after it.
  l.push(s.batch(kSent + 0.045));
  EXPECT_EQ(l.listen(kSent).status, BurstStatus::kPending);
  l.push(s.batch(kSent + 0.045 + s.config.envelope.max_width_s() + s.config.envelope.burst_s));
  EXPECT_EQ(l.listen(kSent).status, BurstStatus::kHeard);
}

// A noise pulse on one receiver before the burst and an echo after it: the
// direct wavefront is the first one that two receivers hear. Pulses before
// the burst left, and a wavefront beyond the range, are not it.
TEST(BurstListener, TakesTheFirstWavefrontOfEnoughReceivers) {
  Scene s;
  s.config.speed_of_sound_mps = kC;
  s.pulse(3, kSent + 0.004);        // noise: one receiver
  s.wavefront(kSent - 0.001, 1.0);  // before the burst left
  s.wavefront(kT0, 1.0);            // direct
  s.wavefront(kT0 + 0.006, 2.5);    // an echo
  BurstListener l(s.config);
  l.push(s.batch(1.2));
  const station::BurstResult r = l.listen(kSent);
  ASSERT_EQ(r.status, BurstStatus::kHeard);
  EXPECT_NEAR(r.burst.arrival_s, kT0, 30e-9);

  Scene far;
  far.config.speed_of_sound_mps = kC;
  far.wavefront(kSent + 15.5 / kC, 1.0);
  BurstListener lf(far.config);
  lf.push(far.batch(1.2));
  EXPECT_EQ(lf.listen(kSent).status, BurstStatus::kNotHeard);
}

TEST(BurstListener, AWavefrontSplitAcrossBatches) {
  Scene s;
  s.config.speed_of_sound_mps = kC;
  s.wavefront(kT0, 0.0);  // receivers 7, 0, 1
  std::vector<tof::EnvelopeEvent> first = s.events[7];
  s.events[7].clear();
  BurstListener l(s.config);
  tof::CaptureBatch later = s.batch(1.1);
  s.events[7] = first;
  l.push(s.batch(kT0 + 0.001));
  l.push(later);
  const station::BurstResult r = l.listen(kSent);
  ASSERT_EQ(r.status, BurstStatus::kHeard);
  EXPECT_EQ(r.burst.receivers, 0b1000'0011U);
  EXPECT_NEAR(r.burst.arrival_s, kT0, 30e-9);
}

// Events lost in the window (an overflow) spoil it; a comparator stuck high
// only takes its own channel out.
TEST(BurstListener, IncidentsInTheWindow) {
  for (const tof::IncidentKind kind :
       {tof::IncidentKind::kOverflow, tof::IncidentKind::kLostEvents,
        tof::IncidentKind::kUnwrapAmbiguous, tof::IncidentKind::kStuckHigh}) {
    Scene s;
    s.config.speed_of_sound_mps = kC;
    s.wavefront(kT0, 0.0);
    tof::CaptureBatch b = s.batch(1.1);
    b.incidents.push_back({.kind = kind,
                           .channel = 4,
                           .from = s.tick_of(kSent + 0.01),
                           .until = s.tick_of(kSent + 0.02),
                           .count = 1});
    BurstListener l(s.config);
    l.push(b);
    EXPECT_EQ(l.listen(kSent).status,
              kind == tof::IncidentKind::kStuckHigh ? BurstStatus::kHeard : BurstStatus::kLost)
        << static_cast<int>(kind);
  }
}

TEST(BurstListener, ForgetsWhatItDrops) {
  Scene s;
  s.config.speed_of_sound_mps = kC;
  s.wavefront(kT0, 0.0);
  BurstListener l(s.config);
  l.push(s.batch(1.1));
  l.drop_before(kT0 + 0.001);
  EXPECT_EQ(l.listen(kSent).status, BurstStatus::kNotHeard);
}

TEST(BurstListener, BadConfigurationsAreRefused) {
  const auto refused = [](auto edit) {
    BurstListenerConfig c;
    edit(c);
    EXPECT_THROW(BurstListener{c}, std::invalid_argument);
  };
  refused([](BurstListenerConfig& c) { c.min_receivers = 0; });
  refused([](BurstListenerConfig& c) { c.min_receivers = 9; });
  refused([](BurstListenerConfig& c) { c.max_range_m = NAN; });
  refused([](BurstListenerConfig& c) { c.speed_of_sound_mps = 0; });
  refused([](BurstListenerConfig& c) { c.envelope.rise_s = -1; });
}

}  // namespace
