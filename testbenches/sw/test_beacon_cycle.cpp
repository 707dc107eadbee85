// Kleeman beacon-cycle decoding (soc_software beacon_cycle) against an
// independent synthetic world built here in long double: a 10 m room with six
// beacons at its edges firing on Kleeman's schedule (beacon 0's double
// pulse), first-order wall echoes (image sources), piston directivity,
// spreading and air absorption, the first-order receiver envelope and its
// comparator, an octagon of receivers on a robot that may move, the robot's
// own clock, the capture unit's clock-and-tick quantisation and input
// latency, and a driver that reads the FIFOs every 40 ms. Distances are
// checked against the true path lengths plus the common offset the decoder
// documents (c (beacon 0's firing time - anchor)), bearings against the
// true directions; every bad input must give a flag, never a silent wrong
// distance, and the next cycle must work.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "odoloc/sw/beacon_cycle.hpp"

namespace {

namespace tof = odoloc::sw::tof;
using tof::Flag;
using LD = long double;
constexpr LD kPiL = std::numbers::pi_v<LD>;

struct P2 {
  LD x = 0, y = 0;
};
struct Pose {
  LD x = 0, y = 0, theta = 0;
};

LD norm(P2 a) {
  return std::hypot(a.x, a.y);
}
LD wrap(LD a) {
  a = std::remainder(a, 2 * kPiL);
  return a <= -kPiL ? a + 2 * kPiL : a;
}

// Baffled piston: |2 J1(ka sin th) / (ka sin th)|.
LD piston(LD ka, LD theta) {
  const LD s = ka * std::sin(std::abs(theta));
  if (s < 1e-9L)
    return 1;
  return std::abs(2 * std::cyl_bessel_j(1.0L, s) / s);
}

struct Interval {
  LD up, down;
  int beacon, cycle, path, burst;
};

struct Truth {
  LD fire_s = 0;    // robot time the (first) burst left the beacon
  LD distance = 0;  // beacon to robot origin when the direct wavefront passes it
  LD bearing = 0;   // robot frame, toward the beacon
  bool fired = false;
  bool heard = false;   // at least two receivers over threshold on the direct path
  bool merged = false;  // a receiver's direct pulse overlapped another arrival
};

// Raw comparator pulses of one channel, in capture ticks.
struct RawEvent {
  std::uint64_t rise, fall;
};

struct World {
  LD width = 10, height = 10;
  std::vector<P2> beacons{{0.05L, 0.05L}, {5.0L, 0.05L}, {9.95L, 0.05L},
                          {9.95L, 9.95L}, {5.0L, 9.95L}, {0.05L, 9.95L}};
  LD c = 343.2L;
  LD t_fire = 0.150L, t_double = 5.5e-3L, burst = 2.5e-3L;
  LD tau_r = 1e-3L / 3, tau_f = 2e-3L / 3;
  LD x_1m = 62.5L;                // Kleeman: 12.5 V at 1 m over a 0.2 V threshold
  LD absorption_db_per_m = 1.3L;  // 40 kHz, 20 C, 50 % RH
  LD ka_tx = 1.5L;                // beacons: wide (Kleeman pairs two transmitters)
  LD ka_rx = 3.7L;                // receivers: a = 5 mm at 40 kHz
  LD reflection = 0.7L;
  bool echoes = true;
  LD clock_offset_s = 0.0371L;  // robot time = beacon time (1 + skew) + offset
  LD skew = 0;
  LD common_jitter_s = 1e-6L, receiver_jitter_s = 0.5e-6L;
  LD amplitude_jitter = 0.05L;  // per burst and path
  unsigned seed = 1;
  std::uint32_t prescale = 124, latency = 5;
  LD f_clk = 50e6L;
  std::uint64_t epoch_ticks = 1000;  // the driver's count at robot time 0
  std::function<Pose(LD)> pose = [](LD) { return Pose{3.2L, 4.1L, 0.3L}; };
  std::function<bool(int, int)> fires = [](int, int) { return true; };     // (beacon, cycle)
  std::function<bool(int, int)> blocked = [](int, int) { return false; };  // (beacon, path)
  std::function<LD(int)> schedule_shift = [](int) { return 0.0L; };        // per cycle, s
  // Slots after the beacons' with no beacon; a station transmitter at
  // `station` (facing the room's centre) fires in the first one when
  // station_fires(cycle): emitter index n(), in `truth` as beacon n().
  int reserved = 0;
  P2 station{0.05L, 5.0L};
  std::function<bool(int)> station_fires = [](int) { return true; };

  std::map<std::pair<int, int>, Truth> truth;  // (cycle, beacon)
  std::vector<std::vector<RawEvent>> events;   // per channel

  [[nodiscard]] int n() const { return static_cast<int>(beacons.size()); }
  [[nodiscard]] int slots() const { return n() + reserved; }
  [[nodiscard]] P2 emitter(int k) const {
    return k < n() ? beacons[static_cast<std::size_t>(k)] : station;
  }
  [[nodiscard]] LD tick_s() const { return (prescale + 1.0L) / f_clk; }

  // The octagon: faces of 50 mm, receivers at the face centres facing out.
  [[nodiscard]] static std::vector<std::pair<P2, LD>> receivers() {
    std::vector<std::pair<P2, LD>> r;
    const LD apothem = 0.025L / std::tan(kPiL / 8);
    for (int i = 0; i < 8; ++i) {
      const LD a = kPiL * i / 4;
      r.push_back({{apothem * std::cos(a), apothem * std::sin(a)}, a});
    }
    return r;
  }
  [[nodiscard]] P2 to_world(const Pose& p, P2 r) const {
    return {p.x + r.x * std::cos(p.theta) - r.y * std::sin(p.theta),
            p.y + r.x * std::sin(p.theta) + r.y * std::cos(p.theta)};
  }
  // Beacons face the room's centre.
  [[nodiscard]] LD beacon_axis(int k) const {
    const P2 b = emitter(k);
    return std::atan2(height / 2 - b.y, width / 2 - b.x);
  }
  // Path 0: the beacon; 1..4: its images in x = 0, x = W, y = 0, y = H,
  // except in the walls it is mounted on (their reflection is part of its
  // beam). Returns false when the path does not exist.
  bool source(int k, int path, P2& pos, LD& axis) const {
    const P2 b = emitter(k);
    axis = beacon_axis(k);
    pos = b;
    switch (path) {
      case 0:
        return true;
      case 1:
        pos.x = -b.x, axis = kPiL - axis;
        return b.x > 0.3L;
      case 2:
        pos.x = 2 * width - b.x, axis = kPiL - axis;
        return b.x < width - 0.3L;
      case 3:
        pos.y = -b.y, axis = -axis;
        return b.y > 0.3L;
      case 4:
        pos.y = 2 * height - b.y, axis = -axis;
        return b.y < height - 0.3L;
      default:
        return false;
    }
  }
  // Robot time a wavefront from `src` emitted at `t_emit` reaches the point
  // `r` (robot frame) of the moving robot.
  [[nodiscard]] LD arrival(P2 src, LD t_emit, P2 r, LD* length = nullptr) const {
    LD t = t_emit;
    LD len = 0;
    for (int i = 0; i < 6; ++i) {
      const P2 w = to_world(pose(t), r);
      len = norm({w.x - src.x, w.y - src.y});
      t = t_emit + len / c;
    }
    if (length != nullptr)
      *length = len;
    return t;
  }

  [[nodiscard]] std::uint64_t tick_at_clock(LD clock) const {
    return epoch_ticks + static_cast<std::uint64_t>(std::floor(clock / (prescale + 1.0L)));
  }
  // The capture unit's timestamp of an edge at robot time t: the first clock
  // edge sampling it, plus the input latency, in ticks.
  [[nodiscard]] std::uint64_t edge_tick(LD t) const {
    return tick_at_clock(std::ceil(t * f_clk) + latency);
  }
  [[nodiscard]] std::uint64_t counter_tick(LD t) const {
    return tick_at_clock(std::floor(t * f_clk));
  }
  // Robot time of a decoder time (seconds after the driver's tick 0).
  [[nodiscard]] LD robot_time(double decoder_s) const {
    return decoder_s - static_cast<LD>(epoch_ticks) * tick_s();
  }

  void generate(int cycles) {
    std::mt19937_64 rng(seed);
    std::normal_distribution<LD> gauss(0, 1);
    const auto rx = receivers();
    const LD reach = 1 - std::exp(-burst / tau_r);
    const LD x_min = 1 / reach;
    std::vector<std::vector<Interval>> iv(rx.size());
    for (int cyc = 0; cyc < cycles; ++cyc) {
      for (int k = 0; k < n() + (reserved > 0 ? 1 : 0); ++k) {
        const LD fire_b = (cyc * slots() + k) * t_fire + schedule_shift(cyc);
        const LD fire_r = fire_b * (1 + skew) + clock_offset_s;
        Truth& tr = truth[{cyc, k}];
        tr.fire_s = fire_r;
        tr.fired = k < n() ? fires(k, cyc) : station_fires(cyc);
        {
          P2 src;
          LD axis;
          source(k, 0, src, axis);
          const LD t = arrival(src, fire_r, {0, 0}, &tr.distance);
          const Pose p = pose(t);
          tr.bearing = wrap(std::atan2(src.y - p.y, src.x - p.x) - p.theta);
        }
        if (!tr.fired)
          continue;
        int direct_heard = 0;
        for (int b = 0; b < (k == 0 ? 2 : 1); ++b) {
          const LD emit = fire_r + b * t_double;
          for (int path = 0; path <= (echoes ? 4 : 0); ++path) {
            P2 src;
            LD axis;
            if (!source(k, path, src, axis) || blocked(k, path))
              continue;
            const LD common = common_jitter_s * gauss(rng);
            const LD gain = std::max(0.05L, 1 + amplitude_jitter * gauss(rng));
            for (std::size_t i = 0; i < rx.size(); ++i) {
              LD len = 0;
              const LD t = arrival(src, emit, rx[i].first, &len);
              const Pose p = pose(t);
              const P2 w = to_world(p, rx[i].first);
              const LD depart = std::atan2(w.y - src.y, w.x - src.x) - axis;
              const LD incoming =
                  wrap(std::atan2(src.y - w.y, src.x - w.x) - p.theta - rx[i].second);
              if (std::abs(incoming) > 80 * kPiL / 180)
                continue;  // the robot's own shadow
              LD x = x_1m / len * piston(ka_tx, depart) * piston(ka_rx, incoming) *
                     std::pow(10.0L, -absorption_db_per_m * len / 20) * gain;
              if (path > 0)
                x *= reflection;
              if (x <= x_min * 1.000001L)
                continue;
              const LD t_true = t + common + receiver_jitter_s * gauss(rng);
              const LD up = t_true + tau_r * std::log(x / (x - 1));
              const LD down = t_true + burst + tau_f * std::log(x * reach);
              iv[i].push_back({up, down, k, cyc, path, b});
              if (path == 0 && b == 0)
                ++direct_heard;
            }
          }
        }
        tr.heard = direct_heard >= 2;
      }
    }
    // The comparator: overlapping arrivals make one pulse.
    events.assign(rx.size(), {});
    for (std::size_t i = 0; i < rx.size(); ++i) {
      auto& list = iv[i];
      std::sort(list.begin(), list.end(),
                [](const Interval& a, const Interval& b) { return a.up < b.up; });
      for (std::size_t j = 0; j < list.size();) {
        LD up = list[j].up, down = list[j].down;
        std::size_t e = j + 1;
        while (e < list.size() && list[e].up <= down)
          down = std::max(down, list[e++].down);
        if (e - j > 1)
          for (std::size_t m = j; m < e; ++m)
            if (list[m].path == 0 && list[m].burst == 0)
              truth[{list[m].cycle, list[m].beacon}].merged = true;
        events[i].push_back({edge_tick(up), edge_tick(down)});
        j = e;
      }
    }
  }
};

// The driver: reads every `period` of robot time; an entry exists from its
// falling edge on. A FIFO holds `depth` entries between reads; what does
// not fit is dropped and reported (the fabric keeps the oldest).
struct Driver {
  LD period = 0.040L;
  std::size_t depth = 16;
  std::function<LD(int)> read_delay = [](int) { return 0.0L; };  // extra delay of read i
  std::function<void(tof::CaptureBatch&, int)> tamper = [](tof::CaptureBatch&, int) {};

  std::vector<tof::CaptureBatch> batches(const World& w, LD until) const {
    std::vector<tof::CaptureBatch> out;
    std::vector<std::size_t> next(w.events.size(), 0);
    std::uint64_t previous = w.counter_tick(0);
    int index = 0;
    for (LD t = period; t < until; t += period, ++index) {
      const LD delay = read_delay(index);
      if (delay < 0)
        continue;  // this read is skipped
      tof::CaptureBatch b;
      b.timebase.prescale = w.prescale;
      b.timebase.input_latency_clocks = w.latency;
      b.read_tick = w.counter_tick(t + delay);
      for (std::size_t ch = 0; ch < w.events.size(); ++ch) {
        tof::ChannelEvents ev;
        std::size_t kept = 0, dropped = 0;
        std::uint64_t last_kept = previous;
        while (next[ch] < w.events[ch].size() && w.events[ch][next[ch]].fall < b.read_tick) {
          const RawEvent& e = w.events[ch][next[ch]++];
          if (kept < depth) {
            const std::uint64_t width =
                std::min<std::uint64_t>(e.fall - e.rise, tof::kWidthSaturated);
            ev.envelope.push_back({e.rise, static_cast<std::uint32_t>(width)});
            ++kept;
            last_kept = e.rise;
          } else {
            ++dropped;
          }
        }
        if (dropped > 0)
          b.incidents.push_back({tof::IncidentKind::kOverflow, static_cast<int>(ch), last_kept,
                                 b.read_tick, static_cast<std::uint32_t>(dropped)});
        b.channels.push_back(std::move(ev));
      }
      previous = b.read_tick;
      tamper(b, index);
      out.push_back(std::move(b));
    }
    return out;
  }
};

tof::KleemanConfig config_for(const World& w, bool with_positions = false) {
  tof::KleemanConfig cfg;
  cfg.schedule.beacons = w.n();
  cfg.schedule.reserved_slots = w.reserved;
  cfg.schedule.fire_period_s = static_cast<double>(w.t_fire);
  cfg.schedule.pulse_s = static_cast<double>(w.burst);
  cfg.schedule.double_spacing_s = static_cast<double>(w.t_double);
  cfg.envelope.rise_s = static_cast<double>(w.tau_r);
  cfg.envelope.fall_s = static_cast<double>(w.tau_f);
  cfg.envelope.burst_s = static_cast<double>(w.burst);
  cfg.timebase.prescale = w.prescale;
  cfg.timebase.input_latency_clocks = w.latency;
  cfg.speed_of_sound_mps = static_cast<double>(w.c);
  if (with_positions)
    for (const P2& b : w.beacons)
      cfg.beacon_positions.push_back({static_cast<double>(b.x), static_cast<double>(b.y)});
  return cfg;
}

std::vector<tof::CycleMeasurement> run(const World& w, tof::BeaconCycleDecoder& decoder,
                                       const Driver& driver, int cycles) {
  std::vector<tof::CycleMeasurement> out;
  const LD until = (cycles * w.slots() + 0.5L) * w.t_fire + w.clock_offset_s;
  for (const tof::CaptureBatch& b : driver.batches(w, until))
    for (tof::CycleMeasurement& m : decoder.push(b))
      out.push_back(std::move(m));
  return out;
}

// The cycle a record belongs to: the one whose beacon 0 fired last before
// its anchor.
int cycle_of(const World& w, const tof::CycleMeasurement& m) {
  const LD anchor = w.robot_time(m.anchor_s);
  int best = -1;
  LD gap = 1e9L;
  for (const auto& [key, tr] : w.truth) {
    if (key.second != 0)
      continue;
    const LD d = anchor - tr.fire_s;
    if (d > -0.01L && d < gap)
      gap = d, best = key.first;
  }
  return best;
}

// The offset the decoder documents: c (beacon 0's firing - anchor).
LD offset_m(const World& w, const tof::CycleMeasurement& m, int cycle) {
  return w.c * (w.truth.at({cycle, 0}).fire_s - w.robot_time(m.anchor_s));
}

// Flags that announce that a distance may be wrong.
bool warned(tof::Flags f) {
  for (const Flag x : {Flag::kMissing, Flag::kEchoSuspect, Flag::kOccludedSuspect, Flag::kOverflow,
                       Flag::kLostEvents, Flag::kStuckChannel, Flag::kUnwrapAmbiguous,
                       Flag::kOutOfOrder, Flag::kSingleReceiver, Flag::kDoaInconsistent,
                       Flag::kReferenceSuspect, Flag::kSaturated, Flag::kMergedPulse, Flag::kWeak})
    if (f.has(x))
      return true;
  return false;
}

struct Errors {
  int checked = 0, wrong_unflagged = 0;
  double max_distance_error = 0, max_bearing_z = 0;
  std::vector<double> bearing_error;
  std::string first_wrong;
};

// Every beacon of every locked record: a primary without warning flags
// must be within 3 mm + 4 sd of the truth, its bearing within
// 4 sd + 0.5 degree (plane wave on a curved front).
Errors check(const World& w, const std::vector<tof::CycleMeasurement>& records) {
  Errors e;
  for (const auto& m : records) {
    if (!m.locked())
      continue;
    const int cyc = cycle_of(w, m);
    if (cyc < 0)
      continue;
    const LD offset = offset_m(w, m, cyc);
    for (const auto& b : m.beacons) {
      const Truth& tr = w.truth.at({cyc, b.beacon});
      const tof::Arrival* p = b.direct();
      if (p == nullptr || warned(b.flags))
        continue;
      ++e.checked;
      const double err = static_cast<double>(p->distance_m - (tr.distance + offset));
      const double bearing_err =
          static_cast<double>(wrap(static_cast<LD>(p->doa.bearing_rad) - tr.bearing));
      e.max_distance_error = std::max(e.max_distance_error, std::abs(err));
      if (p->doa.valid) {
        e.bearing_error.push_back(bearing_err);
        e.max_bearing_z = std::max(e.max_bearing_z, std::abs(bearing_err) / p->doa.sd_rad);
      }
      const bool distance_bad = std::abs(err) > 0.003 + 4 * p->sd_m;
      const bool bearing_bad =
          p->doa.valid && std::abs(bearing_err) > 4 * p->doa.sd_rad + 0.5 * std::numbers::pi / 180;
      if (distance_bad || bearing_bad) {
        if (e.wrong_unflagged++ == 0)
          e.first_wrong = "cycle " + std::to_string(cyc) + " beacon " + std::to_string(b.beacon) +
                          ": distance error " + std::to_string(err) + " m (sd " +
                          std::to_string(p->sd_m) + "), bearing error " +
                          std::to_string(bearing_err * 180 / std::numbers::pi) + " deg (sd " +
                          std::to_string(p->doa.sd_rad * 180 / std::numbers::pi) + "), flags " +
                          tof::to_string(b.flags);
      }
    }
  }
  return e;
}

int count_flag(const std::vector<tof::CycleMeasurement>& records, Flag f) {
  int n = 0;
  for (const auto& m : records)
    n += m.flags.has(f) ? 1 : 0;
  return n;
}

// ------------------------------------------------------------------ tests

TEST(BeaconCycle, LocksOnTheDoublePulseAndMeasuresEveryBeacon) {
  for (const Pose pose :
       {Pose{3.2L, 4.1L, 0.3L}, Pose{7.5L, 2.0L, -2.0L}, Pose{5.0L, 8.0L, 1.7L}}) {
    World w;
    w.pose = [pose](LD) { return pose; };
    w.generate(8);
    tof::BeaconCycleDecoder decoder(config_for(w));
    const auto records = run(w, decoder, Driver{}, 8);
    ASSERT_GE(records.size(), 6U);
    EXPECT_TRUE(records.front().flags.has(Flag::kResynchronised));
    for (std::size_t i = 0; i < records.size(); ++i) {
      const auto& m = records[i];
      ASSERT_TRUE(m.locked()) << i << " " << tof::to_string(m.flags);
      EXPECT_EQ(m.flags.has(Flag::kResynchronised), i == 0) << i;
      EXPECT_FALSE(m.flags.has(Flag::kCoasted));
      EXPECT_EQ(m.lock_epoch, 1U);
      EXPECT_EQ(m.sequence, i);
      if (i > 0) {
        EXPECT_NEAR(m.cycle_period_s, 6 * 0.150, 20e-6);  // static robot
      }
      ASSERT_NE(m.beacons[0].direct(), nullptr);
      // Anchor = beacon 0's first arrival (the first candidate) at the robot
      // origin.
      const int cyc = cycle_of(w, m);
      const Truth& t0 = w.truth.at({cyc, 0});
      const tof::Arrival& first = m.beacons[0].candidates.front();
      EXPECT_NEAR(first.distance_m, 0, 1e-9);
      EXPECT_NEAR(static_cast<double>(w.robot_time(m.anchor_s) - t0.fire_s - t0.distance / w.c), 0,
                  (0.003 + 4 * first.sd_m) / 343.2);
      for (const auto& b : m.beacons) {
        if (w.truth.at({cyc, b.beacon}).heard) {
          EXPECT_FALSE(b.flags.has(Flag::kMissing));
        }
      }
    }
    const Errors e = check(w, records);
    // Far beacons may be heard by one receiver only (flagged): at least half
    // the beacons are clean at every pose.
    EXPECT_GE(e.checked, static_cast<int>(records.size()) * 3);
    EXPECT_EQ(e.wrong_unflagged, 0) << e.first_wrong;
    std::printf(
        "pose (%.1f, %.1f, %.1f): %d clean beacons, max distance error %.2f mm, max |z| "
        "bearing %.2f\n",
        static_cast<double>(pose.x), static_cast<double>(pose.y), static_cast<double>(pose.theta),
        e.checked, e.max_distance_error * 1e3, e.max_bearing_z);
  }
}

// A base station's ranging burst in a reserved slot after the beacons'
// (docs/fusion.md): reported in CycleMeasurement::reserved at its true
// arrival, never taken for a beacon; the cycle is N + 1 slots long.
TEST(BeaconCycle, ReservedSlotCarriesTheStationPulse) {
  World w;
  w.reserved = 1;
  w.station_fires = [](int cycle) { return cycle % 3 != 1; };
  w.pose = [](LD t) { return Pose{3 + 0.5L * t, 4.1L, 0.1L}; };  // 0.5 m/s
  w.generate(8);
  tof::BeaconCycleDecoder decoder(config_for(w, true));
  const auto records = run(w, decoder, Driver{}, 8);
  ASSERT_GE(records.size(), 6U);
  int heard = 0, silent = 0;
  for (std::size_t i = 0; i < records.size(); ++i) {
    const auto& m = records[i];
    ASSERT_TRUE(m.locked()) << i << " " << tof::to_string(m.flags);
    if (i > 0) {
      EXPECT_NEAR(m.cycle_period_s, 7 * 0.150, 2e-3);  // 0.5 m/s changes the range to beacon 0
    }
    const int cyc = cycle_of(w, m);
    const Truth& st = w.truth.at({cyc, w.n()});
    if (!st.fired) {
      EXPECT_TRUE(m.reserved.empty()) << i;
      ++silent;
      continue;
    }
    ASSERT_FALSE(m.reserved.empty()) << i;
    const tof::Arrival& first = m.reserved.front();
    const LD slot_start = w.robot_time(m.anchor_s) + w.n() * w.t_fire;
    EXPECT_NEAR(first.time_s, static_cast<double>(st.fire_s + st.distance / w.c - slot_start),
                (0.003 + 4 * first.sd_m) / 343.2)
        << i;
    EXPECT_NEAR(first.distance_m, static_cast<double>(w.c) * first.time_s, 1e-9);
    ++heard;
  }
  EXPECT_GE(heard, 4);
  EXPECT_GE(silent, 2);
  // The beacons are measured as without the station: nothing wrong unflagged.
  const Errors e = check(w, records);
  EXPECT_GE(e.checked, static_cast<int>(records.size()) * 3);
  EXPECT_EQ(e.wrong_unflagged, 0) << e.first_wrong;
}

TEST(BeaconCycle, DistanceDifferencesAgainstBeaconZero) {
  World w;
  w.generate(5);
  tof::BeaconCycleDecoder decoder(config_for(w));
  const auto records = run(w, decoder, Driver{}, 5);
  ASSERT_FALSE(records.empty());
  for (const auto& m : records) {
    const int cyc = cycle_of(w, m);
    const auto* d0 = m.beacons[0].direct();
    ASSERT_NE(d0, nullptr);
    for (const auto& b : m.beacons) {
      const auto* p = b.direct();
      if (p == nullptr || warned(b.flags))
        continue;
      const LD truth = w.truth.at({cyc, b.beacon}).distance - w.truth.at({cyc, 0}).distance;
      EXPECT_NEAR(p->distance_m - d0->distance_m, static_cast<double>(truth), 0.004)
          << "beacon " << b.beacon;
    }
  }
}

// Near a wall an echo can overlap the direct pulse in the comparator: the
// width then overstates the amplitude. Such pulses must be flagged or still
// right; the world's truth knows which ones merged.
TEST(BeaconCycle, EchoesOverlappingTheDirectPulseNearWalls) {
  int merged = 0, checked = 0;
  // In this room that happens next to beacon 0's corner.
  for (const Pose pose : {Pose{0.3L, 0.3L, 0.3L}, Pose{0.3L, 0.6L, 2.0L}, Pose{0.6L, 0.3L, -1.0L},
                          Pose{1.5L, 1.0L, 0.3L}}) {
    World w;
    w.reflection = 0.95L;
    w.pose = [pose](LD) { return pose; };
    w.generate(4);
    tof::BeaconCycleDecoder decoder(config_for(w));
    const auto records = run(w, decoder, Driver{}, 4);
    for (const auto& m : records) {
      const int cyc = cycle_of(w, m);
      for (const auto& b : m.beacons)
        merged += w.truth.at({cyc, b.beacon}).merged ? 1 : 0;
    }
    const Errors e = check(w, records);
    EXPECT_EQ(e.wrong_unflagged, 0) << e.first_wrong;
    checked += e.checked;
  }
  EXPECT_GE(merged, 8);  // the poses do produce overlaps
  EXPECT_GE(checked, 15);
}

TEST(BeaconCycle, MovingRobotKeepsTheLock) {
  World w;
  // 1 m/s along a curve, heading along the path.
  w.pose = [](LD t) {
    const LD s = t * 1.0L;
    const LD a = s / 3.0L;
    return Pose{5 + 3 * std::cos(a) * 0.8L, 5 + 3 * std::sin(a) * 0.8L, a + kPiL / 2};
  };
  w.generate(12);
  tof::BeaconCycleDecoder decoder(config_for(w, true));
  const auto records = run(w, decoder, Driver{}, 12);
  ASSERT_GE(records.size(), 10U);
  for (const auto& m : records) {
    EXPECT_TRUE(m.locked()) << tof::to_string(m.flags);
    EXPECT_FALSE(m.flags.has(Flag::kLockLost));
    EXPECT_FALSE(m.flags.has(Flag::kCoasted));
  }
  EXPECT_EQ(count_flag(records, Flag::kResynchronised), 1);
  const Errors e = check(w, records);
  EXPECT_GE(e.checked, 30);
  EXPECT_EQ(e.wrong_unflagged, 0) << e.first_wrong;
}

// Direction of arrival over many random poses with every error source of the
// world: the figure docs/tof-measurements.md quotes.
TEST(BeaconCycle, DirectionOfArrivalResolutionOnSyntheticData) {
  for (const std::uint32_t prescale : {124U, 0U}) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> xy(1.2, 8.8), heading(-3.14159, 3.14159);
    std::vector<double> errors;
    double z2 = 0;
    for (int trial = 0; trial < 12; ++trial) {
      World w;
      w.prescale = prescale;
      w.seed = 100 + static_cast<unsigned>(trial);
      const Pose pose{xy(rng), xy(rng), heading(rng)};
      w.pose = [pose](LD) { return pose; };
      w.generate(3);
      tof::BeaconCycleDecoder decoder(config_for(w));
      const auto records = run(w, decoder, Driver{}, 3);
      for (const auto& m : records) {
        const int cyc = cycle_of(w, m);
        for (const auto& b : m.beacons) {
          const auto* p = b.direct();
          if (p == nullptr || !p->doa.valid || warned(b.flags))
            continue;
          const double err = static_cast<double>(
              wrap(static_cast<LD>(p->doa.bearing_rad) - w.truth.at({cyc, b.beacon}).bearing));
          errors.push_back(err);
          z2 += (err / p->doa.sd_rad) * (err / p->doa.sd_rad);
        }
      }
    }
    ASSERT_GE(errors.size(), 100U);
    double ss = 0, worst = 0;
    for (const double e : errors)
      ss += e * e, worst = std::max(worst, std::abs(e));
    const auto n = static_cast<double>(errors.size());
    const double rms_deg = std::sqrt(ss / n) * 180 / std::numbers::pi;
    std::printf(
        "DOA on the synthetic world (tick %.2f us, 1 us common + 0.5 us per receiver "
        "jitter, near field, echoes): %zu arrivals, rms %.3f deg, worst %.3f deg, z rms "
        "%.2f\n",
        (prescale + 1) * 0.02, errors.size(), rms_deg, worst * 180 / std::numbers::pi,
        std::sqrt(z2 / n));
    // Theory: 0.5 us per receiver and the tick over a 60 mm radius: about
    // 0.25 degree at 2.5 us ticks; allow the near field and the
    // compensation's width quantisation four times that.
    EXPECT_LT(rms_deg, 1.0);
    EXPECT_LT(std::sqrt(z2 / n), 2.0);  // the reported deviation is not optimistic
  }
}

TEST(BeaconCycle, EarlyWavefrontsInASlotAreRejected) {
  World w;
  w.generate(5);
  // A wavefront from the direction of beacon 3 on three receivers, in slot 3
  // of cycle 2, 16 m (46.6 ms) before the anchor's slot start: earlier than
  // any arrival beacon 3 could produce (|b0 b3| = 14.1 m; max_range 15 m),
  // 32 ms before beacon 3 even fires. As if beacon 2's sound had not died out.
  const Truth& t3 = w.truth.at({2, 3});
  const LD at = t3.fire_s + (w.truth.at({2, 0}).distance - 16) / w.c;
  const auto rx = World::receivers();
  const Pose p = w.pose(at);
  for (int ch = 0; ch < 8; ++ch) {
    const LD incoming = wrap(t3.bearing - rx[static_cast<std::size_t>(ch)].second);
    if (std::abs(incoming) > 50 * kPiL / 180)
      continue;
    const P2 r = rx[static_cast<std::size_t>(ch)].first;
    const LD lead = (r.x * std::cos(t3.bearing) + r.y * std::sin(t3.bearing)) / w.c;
    const LD up = at - lead;
    auto& ev = w.events[static_cast<std::size_t>(ch)];
    ev.push_back({w.edge_tick(up), w.edge_tick(up + 2.0e-3L)});
    std::sort(ev.begin(), ev.end(),
              [](const RawEvent& a, const RawEvent& b) { return a.rise < b.rise; });
  }
  (void)p;
  for (const bool positions : {true, false}) {
    tof::BeaconCycleDecoder decoder(config_for(w, positions));
    const auto records = run(w, decoder, Driver{}, 5);
    bool seen = false;
    for (const auto& m : records) {
      const int cyc = cycle_of(w, m);
      const auto& b = m.beacons[3];
      if (cyc == 2) {
        seen = true;
        EXPECT_TRUE(b.flags.has(Flag::kEarlyRejected)) << positions << tof::to_string(b.flags);
        ASSERT_FALSE(b.rejected.empty());
        EXPECT_TRUE(b.rejected.front().flags.has(Flag::kEarlyRejected));
      } else {
        EXPECT_FALSE(b.flags.has(Flag::kEarlyRejected)) << cyc;
      }
    }
    EXPECT_TRUE(seen);
    const Errors e = check(w, records);
    EXPECT_EQ(e.wrong_unflagged, 0) << e.first_wrong;
  }
}

// Beacon 0's direct path is hidden and its double pulse arrives 25 ms
// (8.6 m) late, as from a long echo path: the anchor is late, so every other
// beacon seems earlier than the triangle inequality allows. Kleeman: then it
// is beacon 0's measurement that is too long. With the positions the decoder
// keeps the early wavefronts (before_bound) and says reference_suspect; the
// distances still hold with the documented offset c (F - anchor). Without
// positions the wavefronts beyond max_range are rejected and their beacons
// flagged.
TEST(BeaconCycle, LateReferenceFromBeaconZero) {
  World w;
  w.pose = [](LD) { return Pose{7.0L, 8.0L, 0.4L}; };
  w.fires = [](int k, int) { return k != 0; };
  w.generate(5);
  World late = w;
  late.fires = [](int k, int) { return k == 0; };
  late.echoes = false;
  late.x_1m = 250;  // loud enough from the far corner
  late.clock_offset_s += 0.025L;
  late.generate(5);
  for (std::size_t ch = 0; ch < 8; ++ch) {
    for (const RawEvent& e : late.events[ch])
      w.events[ch].push_back(e);
    std::sort(w.events[ch].begin(), w.events[ch].end(),
              [](const RawEvent& a, const RawEvent& b) { return a.rise < b.rise; });
  }
  {
    tof::BeaconCycleDecoder decoder(config_for(w, true));
    const auto records = run(w, decoder, Driver{}, 5);
    ASSERT_GE(records.size(), 3U);
    for (const auto& m : records) {
      EXPECT_TRUE(m.flags.has(Flag::kReferenceSuspect)) << tof::to_string(m.flags);
      EXPECT_TRUE(m.beacons[0].flags.has(Flag::kEchoSuspect));
      const int cyc = cycle_of(w, m);
      const LD offset = w.c * (w.truth.at({cyc, 0}).fire_s - w.robot_time(m.anchor_s));
      EXPECT_NEAR(static_cast<double>(offset),
                  static_cast<double>(-w.truth.at({cyc, 0}).distance - 0.025L * w.c), 0.01);
      int before = 0;
      for (int k = 1; k < 6; ++k) {
        const auto& b = m.beacons[static_cast<std::size_t>(k)];
        EXPECT_TRUE(b.flags.has(Flag::kReferenceSuspect));
        EXPECT_TRUE(b.rejected.empty());
        const auto* p = b.direct();
        if (p == nullptr)
          continue;
        before += p->flags.has(Flag::kBeforeBound) ? 1 : 0;
        if (!p->flags.has(Flag::kSingleReceiver)) {
          EXPECT_NEAR(p->distance_m, static_cast<double>(w.truth.at({cyc, k}).distance + offset),
                      0.005)
              << "beacon " << k;
        }
      }
      EXPECT_GE(before, 2);
    }
  }
  {
    tof::BeaconCycleDecoder decoder(config_for(w, false));
    const auto records = run(w, decoder, Driver{}, 5);
    ASSERT_GE(records.size(), 3U);
    const Errors e = check(w, records);
    EXPECT_EQ(e.wrong_unflagged, 0) << e.first_wrong;
  }
}

TEST(BeaconCycle, ABeaconFiringInTheWrongSlotIsFlaggedNotTaken) {
  // The controller glitches in cycle 2: beacon 4 fires a whole slot early,
  // in beacon 3's slot, and not in its own. With the beacons' positions
  // the pulse is later than beacon 3's direct arrival, so it is an extra
  // candidate of beacon 3 and beacon 4 is missing; neither gives a wrong
  // unflagged distance.
  World w;
  w.fires = [](int k, int cyc) { return !(k == 4 && cyc == 2); };
  w.generate(5);
  LD misfire_distance = 0;  // beacon 4's direct path when it misfired
  {
    // Beacon 4's burst in slot 3, 40 ms after beacon 3 fired: copy its
    // direct pulses from cycle 3, moved back by one cycle and one slot.
    World shifted = w;
    shifted.fires = [](int, int) { return true; };
    shifted.schedule_shift = [&w](int) { return -(w.n() + 1) * w.t_fire + 0.040L; };
    shifted.echoes = false;
    shifted.generate(4);
    const auto& t4 = shifted.truth.at({3, 4});
    misfire_distance = t4.distance;
    for (std::size_t ch = 0; ch < 8; ++ch)
      for (const RawEvent& e : shifted.events[ch]) {
        const LD t = static_cast<LD>(e.rise - w.epoch_ticks) * w.tick_s();
        if (t > t4.fire_s && t < t4.fire_s + 0.05L)
          w.events[ch].push_back(e);
      }
    for (auto& ev : w.events)
      std::sort(ev.begin(), ev.end(),
                [](const RawEvent& a, const RawEvent& b) { return a.rise < b.rise; });
  }
  tof::BeaconCycleDecoder decoder(config_for(w, true));
  const auto records = run(w, decoder, Driver{}, 5);
  bool seen = false;
  for (const auto& m : records) {
    if (cycle_of(w, m) != 2)
      continue;
    seen = true;
    EXPECT_TRUE(m.beacons[4].flags.has(Flag::kMissing)) << tof::to_string(m.beacons[4].flags);
    const auto& b3 = m.beacons[3];
    EXPECT_TRUE(b3.flags.has(Flag::kEchoes)) << tof::to_string(b3.flags);
    // The misfired burst is one of beacon 3's later candidates, where a
    // burst 40 ms after beacon 3's slot start would be; not the primary.
    const LD expected = w.c * 0.040L + misfire_distance + offset_m(w, m, 2);
    int found = -1;
    for (std::size_t i = 0; i < b3.candidates.size(); ++i)
      if (std::abs(b3.candidates[i].distance_m - static_cast<double>(expected)) < 0.01)
        found = static_cast<int>(i);
    EXPECT_GT(found, b3.primary);
  }
  EXPECT_TRUE(seen);
  const Errors e = check(w, records);
  EXPECT_EQ(e.wrong_unflagged, 0) << e.first_wrong;
}

TEST(BeaconCycle, MissingDoublePulseCoastsThenResynchronises) {
  World w;
  // Beacon 0 silent in cycle 2 (one cycle: coast) and in cycles 4-6 (lock
  // lost, then found again).
  w.fires = [](int k, int cyc) { return !(k == 0 && (cyc == 2 || (cyc >= 4 && cyc <= 6))); };
  w.generate(11);
  tof::BeaconCycleDecoder decoder(config_for(w));
  const auto records = run(w, decoder, Driver{}, 11);
  int coasted = 0, lost = 0, resync = 0;
  for (const auto& m : records) {
    if (m.flags.has(Flag::kLockLost)) {
      ++lost;
      EXPECT_FALSE(m.locked());
      EXPECT_TRUE(m.flags.has(Flag::kDoublePulseMissing));
      continue;
    }
    const int cyc = cycle_of(w, m);
    if (m.flags.has(Flag::kResynchronised))
      ++resync;
    if (m.flags.has(Flag::kCoasted)) {
      ++coasted;
      EXPECT_TRUE(m.flags.has(Flag::kDoublePulseMissing));
      EXPECT_TRUE(m.beacons[0].flags.has(Flag::kMissing));
      EXPECT_TRUE(m.beacons[2].flags.has(Flag::kCoasted));  // every beacon says so
      EXPECT_TRUE(std::isnan(m.cycle_period_s));
      // The distances still hold with the documented offset: the predicted
      // anchor's.
      const LD offset = w.c * (w.truth.at({cyc, 0}).fire_s - w.robot_time(m.anchor_s));
      for (int k = 1; k < 6; ++k) {
        const auto* p = m.beacons[static_cast<std::size_t>(k)].direct();
        if (p == nullptr || warned(m.beacons[static_cast<std::size_t>(k)].flags))
          continue;
        EXPECT_NEAR(p->distance_m, static_cast<double>(w.truth.at({cyc, k}).distance + offset),
                    0.004);
      }
    }
  }
  EXPECT_EQ(coasted, 2);  // cycle 2, and cycle 4 before the lock goes
  EXPECT_EQ(lost, 1);
  EXPECT_EQ(resync, 2);  // the first lock and the relock
  // After the relock every cycle is clean again.
  ASSERT_FALSE(records.empty());
  EXPECT_FALSE(records.back().flags.has(Flag::kCoasted));
  EXPECT_TRUE(records.back().locked());
  EXPECT_EQ(records.back().lock_epoch, 2U);
  const Errors e = check(w, records);
  EXPECT_EQ(e.wrong_unflagged, 0) << e.first_wrong;
}

TEST(BeaconCycle, DoublePulseInTheWrongPlaceResynchronises) {
  World w;
  // The beacon controller restarts during cycle 3: from then on the schedule
  // is 2.4 slots later.
  w.schedule_shift = [&w](int cyc) { return cyc >= 3 ? 2.4L * w.t_fire : 0.0L; };
  w.fires = [](int, int cyc) { return cyc != 2; };  // and is silent while restarting
  w.generate(10);
  tof::BeaconCycleDecoder decoder(config_for(w));
  const auto records = run(w, decoder, Driver{}, 10);
  int lost = 0, resync = 0;
  std::uint64_t last_epoch = 0;
  for (const auto& m : records) {
    if (m.flags.has(Flag::kLockLost))
      ++lost;
    if (m.flags.has(Flag::kResynchronised))
      ++resync;
    last_epoch = m.lock_epoch;
  }
  EXPECT_GE(lost, 1);
  EXPECT_EQ(resync, 2);
  EXPECT_EQ(last_epoch, 2U);
  // The last records are on the new schedule, clean, with right distances.
  ASSERT_GE(records.size(), 3U);
  for (std::size_t i = records.size() - 3; i < records.size(); ++i) {
    EXPECT_TRUE(records[i].locked());
    EXPECT_EQ(cycle_of(w, records[i]) >= 4, true);
  }
  const Errors e = check(w, records);
  EXPECT_EQ(e.wrong_unflagged, 0) << e.first_wrong;
  EXPECT_GE(e.checked, 20);
}

TEST(BeaconCycle, ADoublePulseMovedWhileLockedIsReportedMisplaced) {
  World w;
  w.schedule_shift = [&w](int cyc) { return cyc >= 3 ? 2.4L * w.t_fire : 0.0L; };
  w.generate(9);
  tof::BeaconCycleDecoder decoder(config_for(w));
  const auto records = run(w, decoder, Driver{}, 9);
  EXPECT_GE(count_flag(records, Flag::kDoublePulseMisplaced), 1);
  EXPECT_EQ(count_flag(records, Flag::kResynchronised), 2);
  const Errors e = check(w, records);
  EXPECT_EQ(e.wrong_unflagged, 0) << e.first_wrong;
}

TEST(BeaconCycle, FifoOverflowFlagsTheSlotsItTouches) {
  World w;
  w.generate(6);
  Driver d;
  d.depth = 4;
  // The reads from 1.84 s to 3.00 s (cycle 2, cycle 3's double pulse) do not
  // happen: at the next one the first four entries of each FIFO survive,
  // the rest was dropped by the fabric.
  d.read_delay = [](int i) { return i >= 45 && i < 75 ? -1.0L : 0.0L; };
  tof::BeaconCycleDecoder decoder(config_for(w));
  const auto records = run(w, decoder, d, 6);
  int overflowed = 0;
  for (const auto& m : records)
    for (const auto& b : m.beacons)
      overflowed += b.flags.has(Flag::kOverflow) ? 1 : 0;
  EXPECT_GE(overflowed, 1);
  // Records after the overflow are clean again.
  ASSERT_FALSE(records.empty());
  for (const auto& b : records.back().beacons)
    EXPECT_FALSE(b.flags.has(Flag::kOverflow));
  const Errors e = check(w, records);
  EXPECT_EQ(e.wrong_unflagged, 0) << e.first_wrong;
}

TEST(BeaconCycle, LostEventsAreFlagged) {
  World w;
  w.generate(5);
  Driver d;
  // Read 40 (1.6 s: cycle 1, slot 4) fails for channels 0-7: the driver
  // reports the loss, and the events are gone.
  d.tamper = [](tof::CaptureBatch& b, int i) {
    if (i != 40)
      return;
    for (std::size_t ch = 0; ch < b.channels.size(); ++ch) {
      b.incidents.push_back({tof::IncidentKind::kLostEvents, static_cast<int>(ch),
                             b.read_tick - 16000, b.read_tick,
                             static_cast<std::uint32_t>(b.channels[ch].envelope.size())});
      b.channels[ch].envelope.clear();
    }
  };
  tof::BeaconCycleDecoder decoder(config_for(w));
  const auto records = run(w, decoder, d, 5);
  int lost = 0;
  for (const auto& m : records)
    for (const auto& b : m.beacons)
      lost += b.flags.has(Flag::kLostEvents) ? 1 : 0;
  EXPECT_GE(lost, 1);
  EXPECT_LE(lost, 2);
  const Errors e = check(w, records);
  EXPECT_EQ(e.wrong_unflagged, 0) << e.first_wrong;
}

TEST(BeaconCycle, DeadChannelIsReported) {
  World w;
  // Receiver 0 faces beacon 1 (5.0, 0.05) from (5, 2.5): strong.
  w.pose = [](LD) { return Pose{5.0L, 2.5L, -kPiL / 2}; };
  w.generate(5);
  w.events[0].clear();
  tof::BeaconCycleDecoder decoder(config_for(w));
  const auto records = run(w, decoder, Driver{}, 5);
  ASSERT_FALSE(records.empty());
  for (const auto& m : records) {
    EXPECT_TRUE(m.channels[0].silent);
    EXPECT_TRUE(m.beacons[1].flags.has(Flag::kDeadChannel)) << tof::to_string(m.beacons[1].flags);
    for (std::size_t ch = 1; ch < 8; ++ch)
      EXPECT_FALSE(m.channels[ch].silent) << ch;
    // Beacon 1 is still measured from the neighbours of receiver 0.
    const auto* p = m.beacons[1].direct();
    ASSERT_NE(p, nullptr);
    const int cyc = cycle_of(w, m);
    EXPECT_NEAR(p->distance_m,
                static_cast<double>(w.truth.at({cyc, 1}).distance + offset_m(w, m, cyc)), 0.005);
  }
}

TEST(BeaconCycle, StuckHighComparator) {
  World w;
  w.generate(6);
  // Channel 2 sticks high from 1.30 s to 2.10 s (cycle 1 slot 2 to cycle 2
  // slot 1): no pulses, then one entry whose width saturates... at 2.5 us
  // ticks 0.8 s is 320000 ticks: the driver sees in_progress and reports it.
  const std::uint64_t from = w.edge_tick(1.30L), to = w.edge_tick(2.10L);
  auto& ev = w.events[2];
  std::erase_if(ev, [&](const RawEvent& e) { return e.fall >= from && e.rise < to; });
  ev.push_back({from, to});
  std::sort(ev.begin(), ev.end(),
            [](const RawEvent& a, const RawEvent& b) { return a.rise < b.rise; });
  Driver d;
  d.tamper = [from, to](tof::CaptureBatch& b, int) {
    if (b.read_tick > from + 4000 && b.read_tick <= to + 4000)
      b.incidents.push_back({tof::IncidentKind::kStuckHigh, 2, from, std::min(b.read_tick, to), 0});
  };
  tof::BeaconCycleDecoder decoder(config_for(w));
  const auto records = run(w, decoder, d, 6);
  int stuck_beacons = 0;
  bool channel_stuck = false;
  for (const auto& m : records) {
    for (const auto& b : m.beacons)
      stuck_beacons += b.flags.has(Flag::kStuckChannel) ? 1 : 0;
    channel_stuck = channel_stuck || m.channels[2].stuck;
  }
  EXPECT_GE(stuck_beacons, 5);
  EXPECT_TRUE(channel_stuck);
  ASSERT_FALSE(records.empty());
  EXPECT_FALSE(records.back().channels[2].stuck);
  for (const auto& b : records.back().beacons)
    EXPECT_FALSE(b.flags.has(Flag::kStuckChannel));
  const Errors e = check(w, records);
  EXPECT_EQ(e.wrong_unflagged, 0) << e.first_wrong;
}

TEST(BeaconCycle, SaturatedWidthIsAStuckChannel) {
  World w;
  w.prescale = 0;  // 20 ns ticks: 2^24 ticks = 335 ms
  w.generate(5);
  const std::uint64_t from = w.edge_tick(1.95L), to = w.edge_tick(2.40L);
  auto& ev = w.events[5];
  std::erase_if(ev, [&](const RawEvent& e) { return e.fall >= from && e.rise < to; });
  ev.push_back({from, to});
  std::sort(ev.begin(), ev.end(),
            [](const RawEvent& a, const RawEvent& b) { return a.rise < b.rise; });
  tof::BeaconCycleDecoder decoder(config_for(w));
  const auto records = run(w, decoder, Driver{}, 5);
  int saturated = 0;
  for (const auto& m : records)
    for (const auto& b : m.beacons)
      saturated += b.flags.has(Flag::kSaturated) ? 1 : 0;
  EXPECT_GE(saturated, 1);
  const Errors e = check(w, records);
  EXPECT_EQ(e.wrong_unflagged, 0) << e.first_wrong;
  EXPECT_GE(e.checked, 15);
}

TEST(BeaconCycle, ACycleAcrossTheCounterWrap) {
  for (const std::uint32_t prescale : {124U, 0U}) {
    World w;
    w.prescale = prescale;
    // The 32-bit counter wraps in the middle of cycle 2 (the driver's
    // unwrapped count goes on past 2^32).
    const LD wrap_at = 2.5L * 6 * 0.150L;
    w.epoch_ticks = (1ULL << 32) - static_cast<std::uint64_t>(wrap_at / w.tick_s());
    w.generate(5);
    tof::BeaconCycleDecoder decoder(config_for(w));
    const auto records = run(w, decoder, Driver{}, 5);
    ASSERT_GE(records.size(), 3U);
    bool spans = false;
    for (const auto& m : records) {
      EXPECT_TRUE(m.locked());
      EXPECT_FALSE(warned(m.flags)) << tof::to_string(m.flags);
      const LD start = w.robot_time(m.anchor_s), end = start + 6 * w.t_fire;
      spans = spans || (start < wrap_at && end > wrap_at);
    }
    EXPECT_TRUE(spans);
    const Errors e = check(w, records);
    EXPECT_EQ(e.wrong_unflagged, 0) << e.first_wrong;
    EXPECT_GE(e.checked, 15);
  }
}

TEST(BeaconCycle, NoisePulsesAreDroppedOrLeftAsFlaggedCandidates) {
  World w;
  w.generate(6);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> when(0.0, 6 * 0.9), spike(2e-6, 150e-6),
      longer(0.4e-3, 2e-3);
  std::uniform_int_distribution<int> channel(0, 7);
  for (int i = 0; i < 300; ++i) {  // spikes: electrical noise
    const LD t = when(rng);
    w.events[static_cast<std::size_t>(channel(rng))].push_back(
        {w.edge_tick(t), w.edge_tick(t + spike(rng))});
  }
  for (int i = 0; i < 20; ++i) {  // longer single-receiver pulses: acoustic noise
    const LD t = when(rng);
    w.events[static_cast<std::size_t>(channel(rng))].push_back(
        {w.edge_tick(t), w.edge_tick(t + longer(rng))});
  }
  // The comparator cannot rise again while high: merge what overlaps.
  for (auto& ev : w.events) {
    std::sort(ev.begin(), ev.end(),
              [](const RawEvent& a, const RawEvent& b) { return a.rise < b.rise; });
    std::vector<RawEvent> merged;
    for (const RawEvent& e : ev) {
      if (!merged.empty() && e.rise <= merged.back().fall)
        merged.back().fall = std::max(merged.back().fall, e.fall);
      else
        merged.push_back(e);
    }
    ev = merged;
  }
  tof::BeaconCycleDecoder decoder(config_for(w));
  const auto records = run(w, decoder, Driver{}, 6);
  ASSERT_GE(records.size(), 4U);
  int noise = 0, flagged = 0;
  for (const auto& m : records) {
    EXPECT_TRUE(m.locked());
    noise += m.noise_pulses;
    for (const auto& b : m.beacons)
      flagged += b.flags.has(Flag::kNoise) ? 1 : 0;
  }
  EXPECT_GT(noise, 100);
  EXPECT_GT(flagged, 10);
  const Errors e = check(w, records);
  EXPECT_EQ(e.wrong_unflagged, 0) << e.first_wrong;
  EXPECT_GE(e.checked, 15);
}

TEST(BeaconCycle, EmptyCycleIsCoastedAndTheNextCycleWorks) {
  World w;
  w.fires = [](int, int cyc) { return cyc != 2; };
  w.generate(6);
  tof::BeaconCycleDecoder decoder(config_for(w));
  const auto records = run(w, decoder, Driver{}, 6);
  int empty = 0;
  for (const auto& m : records) {
    EXPECT_TRUE(m.locked());
    if (cycle_of(w, m) == 2 || m.flags.has(Flag::kCoasted)) {
      ++empty;
      EXPECT_TRUE(m.flags.has(Flag::kCoasted));
      for (const auto& b : m.beacons)
        EXPECT_TRUE(b.flags.has(Flag::kMissing)) << b.beacon;
    }
  }
  EXPECT_EQ(empty, 1);
  EXPECT_EQ(count_flag(records, Flag::kResynchronised), 1);  // the lock held
  ASSERT_FALSE(records.empty());
  EXPECT_FALSE(records.back().flags.has(Flag::kCoasted));
  const Errors e = check(w, records);
  EXPECT_EQ(e.wrong_unflagged, 0) << e.first_wrong;
}

TEST(BeaconCycle, OutOfOrderAndLateEventsAreDroppedAndFlagged) {
  World w;
  w.generate(5);
  Driver d;
  d.tamper = [](tof::CaptureBatch& b, int i) {
    if (i == 50)  // an event from 1 s ago, out of order
      b.channels[1].envelope.push_back({b.read_tick - 400000, 1000});
  };
  tof::BeaconCycleDecoder decoder(config_for(w));
  const auto records = run(w, decoder, d, 5);
  EXPECT_EQ(count_flag(records, Flag::kOutOfOrder), 1);
  int dropped = 0;
  for (const auto& m : records)
    dropped += m.dropped_events;
  EXPECT_EQ(dropped, 1);
  const Errors e = check(w, records);
  EXPECT_EQ(e.wrong_unflagged, 0) << e.first_wrong;
}

TEST(BeaconCycle, UnwrapAmbiguousEventsAreDropped) {
  World w;
  w.generate(5);
  Driver d;
  const std::uint64_t from = w.edge_tick(2.0L), until = w.edge_tick(2.2L);
  d.tamper = [from, until](tof::CaptureBatch& b, int i) {
    if (i == 56)
      for (int ch = 0; ch < 8; ++ch)
        b.incidents.push_back({tof::IncidentKind::kUnwrapAmbiguous, ch, from, until, 0});
  };
  tof::BeaconCycleDecoder decoder(config_for(w));
  const auto records = run(w, decoder, d, 5);
  int flagged = 0;
  for (const auto& m : records)
    for (const auto& b : m.beacons)
      flagged += b.flags.has(Flag::kUnwrapAmbiguous) ? 1 : 0;
  EXPECT_GE(flagged, 1);
  const Errors e = check(w, records);
  EXPECT_EQ(e.wrong_unflagged, 0) << e.first_wrong;
}

TEST(BeaconCycle, BlockedDirectPathIsFlaggedNotTakenSilently) {
  // An obstacle hides beacon 4 from cycle 3 on: only its echo off the wall
  // x = 0 arrives (hard walls, reflection 0.95), 3.2 m later.
  World w;
  w.reflection = 0.95L;
  w.pose = [](LD) { return Pose{2.0L, 6.5L, 0.5L}; };
  const LD cut = 3 * 6 * w.t_fire + w.clock_offset_s - 0.01L;
  World open = w;
  open.generate(7);
  w.blocked = [](int k, int path) { return k == 4 && path == 0; };
  w.generate(7);
  for (std::size_t ch = 0; ch < 8; ++ch) {  // cycles 0-2 from the open world
    std::erase_if(w.events[ch], [&](const RawEvent& e) { return e.rise < w.edge_tick(cut); });
    for (const RawEvent& e : open.events[ch])
      if (e.rise < w.edge_tick(cut))
        w.events[ch].push_back(e);
    std::sort(w.events[ch].begin(), w.events[ch].end(),
              [](const RawEvent& a, const RawEvent& b) { return a.rise < b.rise; });
  }
  for (const bool positions : {true, false}) {
    tof::BeaconCycleDecoder decoder(config_for(w, positions));
    const auto records = run(w, decoder, Driver{}, 7);
    int occluded = 0;
    for (const auto& m : records) {
      const int cyc = cycle_of(w, m);
      const auto& b = m.beacons[4];
      const auto* p = b.direct();
      if (cyc < 3) {
        EXPECT_FALSE(b.flags.has(Flag::kOccludedSuspect)) << cyc;
        continue;
      }
      ASSERT_NE(p, nullptr) << "the echo is heard";
      const double err = static_cast<double>(p->distance_m -
                                             (w.truth.at({cyc, 4}).distance + offset_m(w, m, cyc)));
      EXPECT_GT(err, 1.0) << "the first arrival is the echo";
      EXPECT_TRUE(b.flags.has(Flag::kOccludedSuspect))
          << "cycle " << cyc << " error " << err << " flags " << tof::to_string(b.flags);
      ++occluded;
    }
    EXPECT_GE(occluded, 3) << positions;
    const Errors e = check(w, records);
    EXPECT_EQ(e.wrong_unflagged, 0) << e.first_wrong;
  }
}

TEST(BeaconCycle, InvalidConfigurationIsRejectedWithAMessage) {
  const auto expect_invalid = [](const tof::KleemanConfig& cfg, const std::string& word) {
    try {
      tof::BeaconCycleDecoder decoder(cfg);
      ADD_FAILURE() << "accepted; expected a complaint about " << word;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(word), std::string::npos) << e.what();
    }
  };
  const World w;
  tof::KleemanConfig cfg = config_for(w);
  EXPECT_NO_THROW(tof::BeaconCycleDecoder{cfg});
  auto bad = cfg;
  bad.speed_of_sound_mps = std::nan("");
  expect_invalid(bad, "speed_of_sound_mps");
  bad = cfg;
  bad.schedule.fire_period_s = -0.15;
  expect_invalid(bad, "fire_period_s");
  bad = cfg;
  bad.schedule.fire_period_s = 0.05;  // shorter than two room crossings
  expect_invalid(bad, "fire_period_s");
  bad = cfg;
  bad.schedule.double_spacing_s = 2e-3;  // overlaps its own first burst
  expect_invalid(bad, "double_spacing_s");
  bad = cfg;
  bad.schedule.beacons = 1;
  expect_invalid(bad, "beacons");
  bad = cfg;
  bad.envelope.fall_s = std::nan("");
  expect_invalid(bad, "fall_s");
  bad = cfg;
  bad.beacon_positions = {{0, 0}, {1, 1}};
  expect_invalid(bad, "beacon_positions");
  bad = cfg;
  bad.array.receivers[3].position_m = bad.array.receivers[2].position_m;
  expect_invalid(bad, "same place");
  bad = cfg;
  bad.timebase.fabric_clock_hz = 0;
  expect_invalid(bad, "fabric_clock_hz");
  bad = cfg;
  bad.max_speed_mps = 50;  // the double pulse could move half a slot per cycle
  expect_invalid(bad, "half a slot");
  bad = cfg;
  bad.min_receivers = 9;
  expect_invalid(bad, "min_receivers");
  // A batch from another timebase, or with more channels than receivers.
  tof::BeaconCycleDecoder decoder(cfg);
  tof::CaptureBatch batch;
  batch.timebase.prescale = 3;
  EXPECT_THROW(decoder.push(batch), std::invalid_argument);
  batch.timebase = cfg.timebase;
  batch.channels.resize(9);
  EXPECT_THROW(decoder.push(batch), std::invalid_argument);
}

// The beacons' clock runs 100 ppm fast against the robot's: t_fire on the
// robot clock is 15 us shorter than configured, and beacon k's distance
// carries -c k t_fire 1e-4 on top of the common offset (26 mm for beacon 5),
// as docs/tof-measurements.md says. The measured cycle period gives the
// real t_fire; set_fire_period removes the error from the next cycle on.
TEST(BeaconCycle, BeaconClockRateErrorAndItsCorrection) {
  World w;
  w.skew = -100e-6L;
  w.generate(10);
  tof::BeaconCycleDecoder decoder(config_for(w));
  const auto batches = Driver{}.batches(w, (10 * 6 + 0.5L) * w.t_fire + w.clock_offset_s);
  std::vector<tof::CycleMeasurement> before, after;
  std::size_t i = 0;
  for (; i < batches.size() / 2; ++i)
    for (auto& m : decoder.push(batches[i]))
      before.push_back(std::move(m));
  ASSERT_GE(before.size(), 3U);
  double period = 0;
  int periods = 0;
  for (const auto& m : before) {
    const int cyc = cycle_of(w, m);
    if (std::isfinite(m.cycle_period_s))
      period += m.cycle_period_s, ++periods;
    const LD offset = offset_m(w, m, cyc);
    for (const auto& b : m.beacons) {
      const auto* p = b.direct();
      if (p == nullptr || warned(b.flags))
        continue;
      const double expected = static_cast<double>(w.c * b.beacon * w.t_fire * w.skew);
      EXPECT_NEAR(
          p->distance_m - static_cast<double>(w.truth.at({cyc, b.beacon}).distance + offset),
          expected, 0.003)
          << "beacon " << b.beacon;
    }
  }
  ASSERT_GE(periods, 2);
  const double t_fire = period / periods / 6;
  EXPECT_NEAR(t_fire, static_cast<double>(w.t_fire * (1 + w.skew)), 2e-7);
  decoder.set_fire_period(t_fire);
  for (; i < batches.size(); ++i)
    for (auto& m : decoder.push(batches[i]))
      after.push_back(std::move(m));
  ASSERT_GE(after.size(), 3U);
  EXPECT_EQ(count_flag(after, Flag::kLockLost), 0);
  const Errors e = check(w, after);
  EXPECT_EQ(e.wrong_unflagged, 0) << e.first_wrong;
  EXPECT_GE(e.checked, 10);
  EXPECT_THROW(decoder.set_fire_period(std::nan("")), std::invalid_argument);
}

// Garbage from a broken driver: a real stream with events corrupted at
// random (zero, short, saturated widths, rises moved by up to 50 ms so that
// they come out of order), events invented, batches lost, incidents with
// reversed intervals on any channel. The decoder must neither throw nor
// emit non-finite values, and must keep decoding.
TEST(BeaconCycle, GarbageInputNeverBreaksTheDecoder) {
  World w;
  w.generate(20);
  std::mt19937_64 rng(99);
  std::uniform_int_distribution<int> coin(0, 99);
  std::uniform_int_distribution<std::int64_t> shift(-20000, 20000);  // +-50 ms in ticks
  std::uniform_int_distribution<std::uint32_t> width(0, 4000);
  Driver d;
  d.tamper = [&](tof::CaptureBatch& b, int) {
    for (auto& ch : b.channels) {
      for (auto& e : ch.envelope) {
        const int r = coin(rng);
        if (r < 5)
          e.width = width(rng);
        else if (r < 7)
          e.width = tof::kWidthSaturated;
        else if (r < 10)
          e.rise = static_cast<std::uint64_t>(static_cast<std::int64_t>(e.rise) + shift(rng));
      }
      if (coin(rng) < 5)
        ch.envelope.push_back({b.read_tick - 1000, width(rng)});
    }
    if (coin(rng) < 5) {
      b.incidents.push_back({static_cast<tof::IncidentKind>(coin(rng) % 4), coin(rng) % 10 - 1,
                             b.read_tick, b.read_tick - 30000, 1});
    }
    if (coin(rng) < 3)
      b.channels.clear();  // a batch that lost everything
  };
  tof::BeaconCycleDecoder decoder(config_for(w));
  std::vector<tof::CycleMeasurement> records;
  ASSERT_NO_THROW(records = run(w, decoder, d, 20));
  int locked = 0;
  for (const auto& m : records) {
    locked += m.locked() ? 1 : 0;
    EXPECT_TRUE(std::isfinite(m.anchor_s));
    for (const auto& be : m.beacons)
      for (const auto* list : {&be.candidates, &be.rejected})
        for (const auto& a : *list) {
          EXPECT_TRUE(std::isfinite(a.distance_m));
          EXPECT_TRUE(std::isfinite(a.sd_m) && a.sd_m > 0);
          EXPECT_TRUE(std::isfinite(a.doa.bearing_rad));
        }
  }
  EXPECT_GE(locked, 10);
  std::printf("garbage: %zu records, %d locked\n", records.size(), locked);
}

TEST(BeaconCycle, BatchesOfAnySizeGiveTheSameRecords) {
  World w;
  w.generate(5);
  Driver often, rarely;
  often.period = 0.013L;
  rarely.period = 0.31L;
  rarely.depth = 64;
  tof::BeaconCycleDecoder a(config_for(w)), b(config_for(w));
  const auto ra = run(w, a, often, 5), rb = run(w, b, rarely, 5);
  // The last cycle may not be complete at the last rare read.
  const std::size_t common = std::min(ra.size(), rb.size());
  ASSERT_GE(common, 3U);
  for (std::size_t i = 0; i < common; ++i) {
    // The same up to rounding (the decoders' time origins differ).
    EXPECT_EQ(ra[i].flags, rb[i].flags);
    EXPECT_NEAR(ra[i].anchor_s, rb[i].anchor_s, 1e-12);
    ASSERT_EQ(ra[i].beacons.size(), rb[i].beacons.size());
    for (std::size_t k = 0; k < ra[i].beacons.size(); ++k) {
      ASSERT_EQ(ra[i].beacons[k].candidates.size(), rb[i].beacons[k].candidates.size());
      for (std::size_t j = 0; j < ra[i].beacons[k].candidates.size(); ++j)
        EXPECT_NEAR(ra[i].beacons[k].candidates[j].distance_m,
                    rb[i].beacons[k].candidates[j].distance_m, 1e-9);
    }
  }
}

}  // namespace
