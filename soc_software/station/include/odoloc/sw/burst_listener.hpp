// Liu's ranging burst as the robot hears it (Liu eq. 14.8; docs/fusion.md,
// "Liu's base station"): the burst leaves the station t0 after its RF
// packet; its direct wavefront is the first one heard by min_receivers
// receivers after that, within the station's range (later ones are
// echoes). Only the ranging packet's time is needed, so it works with or
// without a beacon cycle around it (a lawn with the station alone).
//
// From the capture driver's envelope events: each pulse's rise minus the
// rise-time compensation from its width (tof_envelope.hpp) is its arrival
// at its receiver; the first pulse that min_receivers receivers' pulses
// follow within the array's aperture / c plus group_margin_s starts the
// wavefront, and the plane-wave fit over the first pulse of each of them
// (tof_doa.hpp) gives its time at the robot origin.
#pragma once

#include <cstdint>
#include <vector>

#include "odoloc/sw/tof_doa.hpp"
#include "odoloc/sw/tof_envelope.hpp"
#include "odoloc/sw/tof_measurement.hpp"

namespace odoloc::sw::station {

struct BurstListenerConfig {
  tof::ReceiverArray array = tof::ReceiverArray::polygon(8, 0.05);
  tof::EnvelopeModel envelope;
  double speed_of_sound_mps = 343.2;
  double max_range_m = 15;       // StationConfig::max_range_m
  double min_width_s = 0.25e-3;  // narrower pulses are noise
  double timing_sd_s = 1e-6;     // per receiver, besides the ticks' quantisation
  double group_margin_s = 60e-6;
  int min_receivers = 2;

  // Throws std::invalid_argument naming the first bad field.
  void validate() const;
};

struct HeardBurst {
  double arrival_s = 0;         // the wavefront at the robot origin, robot clock
  double sd_s = 0;              // its timing noise
  std::uint32_t receivers = 0;  // bit i: channel i heard it
};

enum class BurstStatus : std::uint8_t {
  kPending,  // the window has not been read out yet
  kHeard,
  kNotHeard,  // no wavefront with enough receivers in the window
  kLost,      // the capture driver lost or could not unwrap events in the window
};

struct BurstResult {
  BurstStatus status = BurstStatus::kPending;
  HeardBurst burst;  // kHeard only
};

class BurstListener {
 public:
  // Validates the configuration (std::invalid_argument).
  explicit BurstListener(BurstListenerConfig config);

  // Takes the capture driver's next batch (read order; times on the robot
  // clock, tof::Timebase::edge_time_s from tick 0, as the sync edges').
  void push(const tof::CaptureBatch& batch);
  // The burst that left the station at sent_s (robot clock): its direct
  // wavefront in (sent_s, sent_s + max_range / c]. Pending until every
  // pulse that could belong to it has been read.
  [[nodiscard]] BurstResult listen(double sent_s) const;
  // Forgets the pulses and incidents before t_s (bursts sent before
  // t_s - max_range / c are no longer listened for).
  void drop_before(double t_s);

 private:
  struct Pulse {
    int channel = 0;
    double time_s = 0;  // compensated arrival at its receiver
    double sd_s = 0;
  };
  struct Span {
    double from_s, until_s;
  };
  BurstListenerConfig config_;
  double aperture_s_ = 0;
  std::vector<Pulse> pulses_;  // sorted by time
  std::vector<Span> incidents_;
  double complete_s_ = -1e300;  // every pulse arriving before this has been read
};

}  // namespace odoloc::sw::station
