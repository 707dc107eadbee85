// Sync-referenced time of flight (soc_software tof_sync_modes): Thamma's RF
// trigger with four repeats per base station and receiver boxes per carrier,
// and the binaural pair's coarse TOF plus carrier phase. Events come from
// geometry computed here in long double (envelope comparator for Thamma, the
// carrier's threshold crossings for the binaural pair) and the capture
// unit's quantisation; results are checked against the true path lengths.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>
#include <vector>

#include "odoloc/sw/tof_sync_modes.hpp"

namespace {

namespace tof = odoloc::sw::tof;
using tof::Flag;
using LD = long double;
constexpr LD kPiL = std::numbers::pi_v<LD>;

struct P2 {
  LD x, y;
};

// The capture unit at 20 ns ticks (prescale 0), latency 5 clocks.
struct Capture {
  std::uint32_t prescale = 0, latency = 5;
  LD f_clk = 50e6L;
  std::uint64_t epoch = (1ULL << 32) - 20'000'000;  // wraps 0.4 s in: unwrapped by the driver
  [[nodiscard]] std::uint64_t tick(LD t) const {
    return epoch + static_cast<std::uint64_t>(
                       std::floor((std::ceil(t * f_clk) + latency) / (prescale + 1.0L)));
  }
  [[nodiscard]] tof::Timebase timebase() const {
    tof::Timebase tb;
    tb.prescale = prescale;
    tb.input_latency_clocks = latency;
    return tb;
  }
};

// ------------------------------------------------------------------ Thamma

// Robot at the origin facing +x: head box (40 kHz) at (0.3, 0), tail box
// (32.5 kHz) at (-0.3, 0); each a 100 mm square box with a receiver facing
// out of each side (channels 0-3 head: +x, +y, -x, -y; 4-7 tail).
struct ThammaWorld {
  P2 station{3.0L, 1.5L};
  LD c = 343.2L;
  LD tau_r = 1e-3L / 3, tau_f = 2e-3L / 3, burst = 2.5e-3L;
  LD x_1m = 40;
  LD emit_delay = 150e-6L;  // sync edge to emission (the fixed delay t)
  LD jitter = 2e-6L;
  int box = 0;  // which box the station's frequency reaches
  Capture cap;

  [[nodiscard]] static P2 receiver(int ch, LD& axis) {
    const P2 centre{ch < 4 ? 0.3L : -0.3L, 0};
    axis = kPiL / 2 * (ch % 4);
    return {centre.x + 0.05L * std::cos(axis), centre.y + 0.05L * std::sin(axis)};
  }
  [[nodiscard]] LD path(int ch) const {
    LD axis;
    const P2 r = receiver(ch, axis);
    return std::hypot(station.x - r.x, station.y - r.y);
  }
  // Envelope events of one burst emitted at `sync` + emit_delay.
  void burst_events(LD sync, std::vector<tof::ChannelEvents>& ch, std::mt19937_64& rng,
                    LD extra_path = 0) const {
    std::normal_distribution<LD> g(0, 1);
    for (int i = box * 4; i < box * 4 + 4; ++i) {
      LD axis;
      const P2 r = receiver(i, axis);
      const LD len = path(i) + extra_path;
      const LD incoming =
          std::remainder(std::atan2(station.y - r.y, station.x - r.x) - axis, 2 * kPiL);
      const LD gain = std::cos(incoming) > 0.2L ? std::cos(incoming) : 0;  // a cosine receiver
      const LD x = x_1m / len * gain;
      const LD reach = 1 - std::exp(-burst / tau_r);
      if (x * reach <= 1.000001L)
        continue;
      const LD t = sync + emit_delay + len / c + jitter * g(rng);
      const LD up = t + tau_r * std::log(x / (x - 1));
      const LD down = t + burst + tau_f * std::log(x * reach);
      const std::uint64_t rise = cap.tick(up);
      ch[static_cast<std::size_t>(i)].envelope.push_back(
          {rise, static_cast<std::uint32_t>(cap.tick(down) - rise)});
    }
  }
  [[nodiscard]] LD nearest_path() const {
    LD best = 1e9L;
    for (int i = box * 4; i < box * 4 + 4; ++i) {
      LD axis;
      const P2 r = receiver(i, axis);
      const LD incoming =
          std::remainder(std::atan2(station.y - r.y, station.x - r.x) - axis, 2 * kPiL);
      if (std::cos(incoming) > 0.2L)
        best = std::min(best, path(i));
    }
    return best;
  }
};

tof::ThammaConfig thamma_config(const ThammaWorld& w) {
  tof::ThammaConfig cfg;
  cfg.fixed_delay_s = static_cast<double>(w.emit_delay);
  cfg.speed_of_sound_mps = static_cast<double>(w.c);
  return cfg;
}

struct Burst {
  std::vector<std::uint64_t> sync;
  std::vector<tof::ChannelEvents> channels = std::vector<tof::ChannelEvents>(8);
};

// Four pings 50 ms apart starting at t0.
Burst four_pings(const ThammaWorld& w, LD t0, unsigned seed, int late_echo_only = -1) {
  Burst b;
  std::mt19937_64 rng(seed);
  for (int r = 0; r < 4; ++r) {
    const LD s = t0 + 0.05L * r;
    b.sync.push_back(w.cap.tick(s));
    w.burst_events(s, b.channels, rng, r == late_echo_only ? 0.9L : 0.0L);
  }
  return b;
}

TEST(Thamma, FourRepeatsAveragedPerBox) {
  for (const P2 station : {P2{3.0L, 1.5L}, P2{-2.0L, 4.0L}, P2{6.0L, -0.5L}}) {
    ThammaWorld w;
    w.station = station;
    const Burst b = four_pings(w, 0.3L, 5);
    const auto m = tof::measure_thamma(thamma_config(w), w.cap.timebase(), b.sync, b.channels);
    EXPECT_FALSE(m.flags.any()) << tof::to_string(m.flags);
    ASSERT_EQ(m.boxes.size(), 2U);
    const auto& head = m.boxes[0];
    EXPECT_EQ(head.used, 4);
    EXPECT_EQ(head.repeats.size(), 4U);
    EXPECT_NEAR(head.distance_m, static_cast<double>(w.nearest_path()),
                0.002 + 4 * head.distance_sd_m);
    EXPECT_LT(head.spread_s, 10e-6);  // 2 us of jitter
    EXPECT_GT(head.spread_s, 0.0);
    EXPECT_FALSE(head.flags.any()) << tof::to_string(head.flags);
    EXPECT_TRUE(m.boxes[1].flags.has(Flag::kMissing));  // 32.5 kHz box: not its frequency
    EXPECT_EQ(m.boxes[1].used, 0);
    EXPECT_TRUE(std::isnan(m.boxes[1].distance_m));
  }
}

TEST(Thamma, AnEchoInOneRepeatIsAnOutlier) {
  ThammaWorld w;
  const Burst b = four_pings(w, 0.3L, 6, 2);  // repeat 2 took a 0.9 m longer path
  const auto m = tof::measure_thamma(thamma_config(w), w.cap.timebase(), b.sync, b.channels);
  const auto& head = m.boxes[0];
  EXPECT_TRUE(head.flags.has(Flag::kOutlier));
  EXPECT_TRUE(head.repeats[2].flags.has(Flag::kOutlier));
  EXPECT_EQ(head.used, 3);
  EXPECT_NEAR(head.distance_m, static_cast<double>(w.nearest_path()), 0.003);
}

TEST(Thamma, SyncEdgesMissingOrExtra) {
  ThammaWorld w;
  Burst b = four_pings(w, 0.3L, 7);
  auto three = b.sync;
  three.pop_back();
  const auto m3 = tof::measure_thamma(thamma_config(w), w.cap.timebase(), three, b.channels);
  EXPECT_TRUE(m3.flags.has(Flag::kSyncMissing));
  EXPECT_TRUE(m3.boxes[0].flags.has(Flag::kSyncMissing));
  EXPECT_EQ(m3.boxes[0].used, 3);
  EXPECT_NEAR(m3.boxes[0].distance_m, static_cast<double>(w.nearest_path()), 0.003);
  auto five = b.sync;
  five.push_back(five.back() + 2'500'000);  // a fifth edge, 50 ms later, nothing heard
  const auto m5 = tof::measure_thamma(thamma_config(w), w.cap.timebase(), five, b.channels);
  EXPECT_TRUE(m5.flags.has(Flag::kExtraSync));
  EXPECT_TRUE(m5.boxes[0].repeats[4].flags.has(Flag::kMissing));
  EXPECT_EQ(m5.boxes[0].used, 4);
  const auto m0 = tof::measure_thamma(thamma_config(w), w.cap.timebase(), {}, b.channels);
  EXPECT_TRUE(m0.flags.has(Flag::kInvalid));
  EXPECT_TRUE(m0.boxes[0].flags.has(Flag::kMissing));
}

TEST(Thamma, IncidentsNoiseAndCarrierMode) {
  ThammaWorld w;
  Burst b = four_pings(w, 0.3L, 8);
  // A noise spike before the arrival of repeat 1 on channel 0.
  b.channels[0].envelope.insert(b.channels[0].envelope.begin() + 1,
                                {b.sync[1] + 10000, 500});  // 10 us wide
  const std::vector<tof::Incident> incidents{
      {tof::IncidentKind::kOverflow, 1, b.sync[3], b.sync[3] + 1'000'000, 3}};
  const auto m =
      tof::measure_thamma(thamma_config(w), w.cap.timebase(), b.sync, b.channels, incidents);
  const auto& head = m.boxes[0];
  EXPECT_TRUE(head.repeats[1].flags.has(Flag::kNoise));
  EXPECT_TRUE(head.repeats[3].flags.has(Flag::kOverflow));
  EXPECT_FALSE(head.repeats[0].flags.has(Flag::kOverflow));
  EXPECT_EQ(head.used, 4);
  EXPECT_NEAR(head.distance_m, static_cast<double>(w.nearest_path()), 0.003);
  // Carrier mode: the first edge, not compensated (its threshold delay
  // belongs in the fixed delay).
  Burst c;
  for (int r = 0; r < 4; ++r) {
    const LD s = 0.3L + 0.05L * r;
    c.sync.push_back(w.cap.tick(s));
    c.channels[0].mode = tof::ChannelMode::kCarrier;
    c.channels[0].carrier.push_back({w.cap.tick(s + w.emit_delay + 40e-6L + w.path(0) / w.c), 0});
  }
  auto cfg = thamma_config(w);
  cfg.fixed_delay_s += 40e-6;
  const auto mc = tof::measure_thamma(cfg, w.cap.timebase(), c.sync, c.channels);
  EXPECT_NEAR(mc.boxes[0].distance_m, static_cast<double>(w.path(0)), 0.0002);
}

TEST(Thamma, InvalidConfigurationAndChannels) {
  ThammaWorld w;
  const Burst b = four_pings(w, 0.3L, 9);
  auto cfg = thamma_config(w);
  cfg.fixed_delay_s = std::nan("");
  EXPECT_THROW((void)tof::measure_thamma(cfg, w.cap.timebase(), b.sync, b.channels),
               std::invalid_argument);
  cfg = thamma_config(w);
  cfg.max_tof_s = 0;
  EXPECT_THROW((void)tof::measure_thamma(cfg, w.cap.timebase(), b.sync, b.channels),
               std::invalid_argument);
  cfg = thamma_config(w);
  cfg.boxes.clear();
  EXPECT_THROW((void)tof::measure_thamma(cfg, w.cap.timebase(), b.sync, b.channels),
               std::invalid_argument);
  cfg = thamma_config(w);
  const std::vector<tof::ChannelEvents> four(4);  // the tail box's channels are absent
  try {
    (void)tof::measure_thamma(cfg, w.cap.timebase(), b.sync, four);
    ADD_FAILURE() << "accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("channel 4"), std::string::npos) << e.what();
  }
}

// --------------------------------------------------------------- binaural

// Two receivers at (0, +-b/2) facing +x; a 40 kHz transmitter at `tx`. The
// received carrier A(t) sin(2 pi f (t - tau)), A(t) = A (1 - exp(-(t-tau)/tau_r)),
// makes the comparator (threshold v) rise once per cycle where
// A(t) sin(...) crosses v upwards; found per cycle by bisection.
struct BinauralWorld {
  P2 tx{1.5L, 0.2L};
  LD baseline = 0.35L;
  LD c = 343.2L, f = 40e3L;
  LD tau_r = 1e-3L / 3;
  LD amplitude_left = 8, amplitude_right = 8;  // over the comparator threshold
  LD emit_delay = 100e-6L;
  Capture cap;

  [[nodiscard]] LD path(int side) const {
    const LD y = side == 0 ? baseline / 2 : -baseline / 2;
    return std::hypot(tx.x, tx.y - y);
  }
  [[nodiscard]] std::vector<tof::CarrierEvent> edges(LD ref, int side, int k) const {
    const LD tau = ref + emit_delay + path(side) / c;
    const LD a = side == 0 ? amplitude_left : amplitude_right;
    const auto level = [&](LD t) {
      return a * (1 - std::exp(-(t - tau) / tau_r)) * std::sin(2 * kPiL * f * (t - tau));
    };
    std::vector<tof::CarrierEvent> out;
    for (int cycle = 0; cycle < 400 && static_cast<int>(out.size()) < k; ++cycle) {
      LD lo = tau + cycle / f, hi = lo + 0.25L / f;  // the rising quarter
      if (level(hi) < 1)
        continue;  // below threshold this cycle
      for (int i = 0; i < 100; ++i) {
        const LD mid = (lo + hi) / 2;
        (level(mid) >= 1 ? hi : lo) = mid;
      }
      out.push_back({cap.tick(hi), static_cast<std::uint32_t>(out.size())});
    }
    return out;
  }
  [[nodiscard]] std::vector<tof::ChannelEvents> channels(LD ref, int k) const {
    std::vector<tof::ChannelEvents> ch(2);
    for (int s = 0; s < 2; ++s) {
      ch[static_cast<std::size_t>(s)].mode = tof::ChannelMode::kCarrier;
      ch[static_cast<std::size_t>(s)].carrier = edges(ref, s, k);
    }
    return ch;
  }
};

tof::BinauralConfig binaural_config(const BinauralWorld& w) {
  tof::BinauralConfig cfg;
  cfg.pairs = {{0, 1, static_cast<double>(w.baseline), static_cast<double>(w.f)}};
  cfg.speed_of_sound_mps = static_cast<double>(w.c);
  // Calibrated: emission delay plus the onset cycles below threshold at this
  // amplitude (the first edge whose peak exceeds 1/A of full scale).
  return cfg;
}

TEST(Binaural, PhaseDifferenceResolvedByTheCoarseTime) {
  for (const P2 tx : {P2{1.5L, 0.2L}, P2{2.0L, -0.6L}, P2{0.8L, 0.05L}, P2{3.0L, 1.0L}}) {
    BinauralWorld w;
    w.tx = tx;
    const LD ref = 0.2L;
    const auto ch = w.channels(ref, 8);
    const auto m = tof::measure_binaural(binaural_config(w), w.cap.timebase(), w.cap.tick(ref), ch);
    ASSERT_EQ(m.pairs.size(), 1U);
    const auto& p = m.pairs[0];
    // Carrier edges only: right here (the synthetic onsets are exact), but
    // nothing proved the whole periods.
    EXPECT_EQ(p.flags, tof::Flags{tof::Flag::kCycleUnverified}) << tof::to_string(p.flags);
    EXPECT_EQ(p.edges_used, 8);
    const LD truth = w.path(0) - w.path(1);
    EXPECT_NEAR(p.path_difference_m, static_cast<double>(truth), 20e-6);  // 20 um
    EXPECT_LT(p.phase_sd_rad, 0.05);
    EXPECT_LT(p.ambiguity, 0.2);
    // The coarse times are the arrivals plus the same onset delay.
    EXPECT_NEAR(p.tof_left_s - p.tof_right_s, static_cast<double>(truth / w.c), 3e-6);
    EXPECT_NEAR(p.tof_left_s, static_cast<double>(w.emit_delay + w.path(0) / w.c), 100e-6);
  }
}

TEST(Binaural, DroppedAndNoisyEdges) {
  BinauralWorld w;
  const LD ref = 0.2L;
  auto ch = w.channels(ref, 8);
  // Edges 0 and 1 of the left receiver dropped: the coarse time steps back
  // by their index; the phase uses the edges both have.
  ch[0].carrier.erase(ch[0].carrier.begin(), ch[0].carrier.begin() + 2);
  // A noise edge between two carrier edges on the right.
  ch[1].carrier.insert(ch[1].carrier.begin() + 4,
                       {ch[1].carrier[3].rise + 300, ch[1].carrier[3].edge + 1});
  for (std::size_t i = 5; i < ch[1].carrier.size(); ++i)
    ++ch[1].carrier[i].edge;
  const auto m = tof::measure_binaural(binaural_config(w), w.cap.timebase(), w.cap.tick(ref), ch);
  const auto& p = m.pairs[0];
  EXPECT_TRUE(p.flags.has(Flag::kEdgesMissing));
  EXPECT_TRUE(p.flags.has(Flag::kCarrierIrregular));
  EXPECT_NEAR(p.path_difference_m, static_cast<double>(w.path(0) - w.path(1)), 20e-6);
}

TEST(Binaural, SilentReceiverOrIncidentIsFlagged) {
  BinauralWorld w;
  const LD ref = 0.2L;
  auto ch = w.channels(ref, 8);
  ch[1].carrier.clear();
  const auto m = tof::measure_binaural(binaural_config(w), w.cap.timebase(), w.cap.tick(ref), ch);
  EXPECT_TRUE(m.pairs[0].flags.has(Flag::kMissing));
  EXPECT_TRUE(m.pairs[0].flags.has(Flag::kInvalid));
  EXPECT_TRUE(std::isnan(m.pairs[0].path_difference_m));
  auto ok = w.channels(ref, 8);
  const std::vector<tof::Incident> lost{
      {tof::IncidentKind::kLostEvents, 0, w.cap.tick(ref), w.cap.tick(ref + 0.01L), 2}};
  const auto ml =
      tof::measure_binaural(binaural_config(w), w.cap.timebase(), w.cap.tick(ref), ok, lost);
  EXPECT_TRUE(ml.pairs[0].flags.has(Flag::kLostEvents));
  ok[0].mode = tof::ChannelMode::kEnvelope;  // a channel in the wrong mode
  const auto mw = tof::measure_binaural(binaural_config(w), w.cap.timebase(), w.cap.tick(ref), ok);
  EXPECT_TRUE(mw.pairs[0].flags.has(Flag::kInvalid));
}

TEST(Binaural, CoarseTimeNearHalfAPeriodOffIsAmbiguous) {
  BinauralWorld w;
  const LD ref = 0.2L;
  auto ch = w.channels(ref, 8);
  auto cfg = binaural_config(w);
  cfg.period_tolerance = 0.45;  // keep the lagging first edges on the grid
  ASSERT_FALSE(tof::measure_binaural(cfg, w.cap.timebase(), w.cap.tick(ref), ch)
                   .pairs[0]
                   .flags.has(Flag::kAmbiguous));
  // Onsets that differ: the left receiver's first edge lags its carrier by
  // 0.19 period more than now, the right one's less (both on the grid).
  // The coarse difference is then 0.38 period off the phase: no longer a
  // safe choice of the whole number of periods.
  ch[0].carrier.front().rise += 237;  // 0.19 x 1250 ticks of 20 ns
  ch[1].carrier.front().rise -= 237;
  const auto m = tof::measure_binaural(cfg, w.cap.timebase(), w.cap.tick(ref), ch);
  EXPECT_TRUE(m.pairs[0].flags.has(Flag::kAmbiguous)) << m.pairs[0].ambiguity;
  EXPECT_FALSE(m.pairs[0].flags.has(Flag::kCarrierIrregular));
}

TEST(Binaural, PathDifferenceBeyondTheBaselineIsOutOfRange) {
  BinauralWorld w;
  const LD ref = 0.2L;
  auto ch = w.channels(ref, 8);
  for (auto& e : ch[0].carrier)
    e.rise += 75'000;  // 1.5 ms: 0.5 m, more than 0.35 m
  const auto m = tof::measure_binaural(binaural_config(w), w.cap.timebase(), w.cap.tick(ref), ch);
  EXPECT_TRUE(m.pairs[0].flags.has(Flag::kOutOfRange));
}

TEST(Binaural, InvalidConfiguration) {
  BinauralWorld w;
  const auto ch = w.channels(0.2L, 8);
  auto cfg = binaural_config(w);
  cfg.pairs[0].right = 0;
  EXPECT_THROW((void)tof::measure_binaural(cfg, w.cap.timebase(), 0, ch), std::invalid_argument);
  cfg = binaural_config(w);
  cfg.pairs[0].carrier_hz = std::nan("");
  EXPECT_THROW((void)tof::measure_binaural(cfg, w.cap.timebase(), 0, ch), std::invalid_argument);
  cfg = binaural_config(w);
  cfg.edges = 0;
  EXPECT_THROW((void)tof::measure_binaural(cfg, w.cap.timebase(), 0, ch), std::invalid_argument);
  cfg = binaural_config(w);
  cfg.pairs[0].right = 5;  // not among the channels given
  EXPECT_THROW((void)tof::measure_binaural(cfg, w.cap.timebase(), 0, ch), std::invalid_argument);
}

}  // namespace
